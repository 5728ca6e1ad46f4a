"""The full diffusion tensors of a swarm: per-step sums of r_i r_j and r_i v_j, and the flux and bulk estimates.

Robson, Ness, White and Dujko (e.g. Dujko et al., Phys. Rev. E 81, 046403
(2010), fields at any angle) define, in the frame of E along z and B in the
y-z plane:

* bulk ``D_ij = (1/2) d/dt (<r_i r_j> - <r_i><r_j>)`` (the time slope of the
  position covariance; symmetric by construction);
* flux ``D_ij = <r_i v_j> - <r_i><v_j>``; only its symmetric part enters the
  flux divergence (``D : grad grad n``), so the symmetrised tensor is
  reported. Without sources (no ionization, no attachment) it equals half
  the time derivative of the covariance, so flux and bulk agree.

:class:`TensorRun` is a :class:`~collisionkit.transport._swarm_run.SwarmRun`
that also keeps the tensor sums of every sample and adds the tensors (with
their standard errors over the groups) to its results.
"""

from __future__ import annotations

import numpy as np

from .._kernels import transport as _k
from ._estimators import mean_and_error, slope
from ._swarm_run import SwarmRun

TENSOR_COLUMNS = 18


def tensor_estimates(times, moments, tensor_moments, density, covariance_shifts=None):
    """Per-group N D flux and bulk tensors, each of shape (groups, 3, 3), from the samples of the steady window.

    ``moments`` (samples, groups, 14) are the sums of
    :func:`~collisionkit._kernels.transport.group_moments`, ``tensor_moments``
    (samples, groups, 18) those of :func:`~collisionkit._kernels.transport.group_tensor_moments`;
    ``covariance_shifts`` (samples, groups, 3, 3) population control's and the
    transient growth's cumulative jumps of the covariance, taken out of the
    bulk tensor's series as the scalar bulk coefficients take them out.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.transport._tensors import tensor_estimates
    >>> t = np.array([0.0, 1.0, 2.0])
    >>> moments = np.zeros((3, 1, 14)); moments[..., 0] = 2.0   # two walkers at +-sqrt(t) along x
    >>> tensor = np.zeros((3, 1, 18)); tensor[:, 0, 0] = 2.0 * t
    >>> flux, bulk = tensor_estimates(t, moments, tensor, 1.0)
    >>> float(bulk[0, 0, 0]), float(bulk[0, 1, 1])  # (1/2) d/dt of the variance 2t (n - 1 = 1)
    (1.0, 0.0)
    """
    n = moments[..., 0]
    centroid = moments[..., 1:4] / n[..., None]
    velocity = moments[..., 7:10] / n[..., None]
    second = tensor_moments[..., 0:9].reshape(*n.shape, 3, 3) / n[..., None, None]
    cross = tensor_moments[..., 9:18].reshape(*n.shape, 3, 3) / n[..., None, None]
    correction = (n / np.maximum(n - 1, 1))[..., None, None]
    covariance = (second - centroid[..., :, None] * centroid[..., None, :]) * correction
    if covariance_shifts is not None:
        covariance = covariance - covariance_shifts
    correlation = cross - centroid[..., :, None] * velocity[..., None, :]
    flux = density * 0.5 * (correlation + np.swapaxes(correlation, -1, -2)).mean(axis=0)
    bulk = density * 0.5 * slope(times, covariance)
    return flux, bulk


class TensorRun(SwarmRun):
    """A swarm run that also records the sums behind the full diffusion tensors and reports them."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.tensor_moments = []
        self.covariance_shift = np.zeros((self.groups, 3, 3))  # jumps of the covariance so far, per group
        self.covariance_shifts = []

    def step(self):
        """:meth:`SwarmRun.step`, then the tensor sums of the new sample."""
        super().step()
        self.tensor_moments.append(self._tensor_sums(self.swarm))
        self.covariance_shifts.append(self.covariance_shift.copy())

    def _tensor_sums(self, swarm):
        sums = np.zeros((self.groups, TENSOR_COLUMNS))
        _k.group_tensor_moments(swarm.pos, swarm.vel, swarm.alive, swarm.group, sums)
        return sums

    def _covariance(self, swarm):
        """Per group, the (unbiased) position covariance of the living particles."""
        moments = np.zeros((self.groups, 14))
        _k.group_moments(swarm.pos, swarm.vel, swarm.alive, swarm.group, self.groups, self.stepper.mass, moments)
        n = np.maximum(moments[:, 0], 1.0)
        centroid = moments[:, 1:4] / n[:, None]
        second = self._tensor_sums(swarm)[:, 0:9].reshape(-1, 3, 3) / n[:, None, None]
        correction = (n / np.maximum(n - 1, 1))[:, None, None]
        return (second - centroid[:, :, None] * centroid[:, None, :]) * correction

    def _record_jump(self, before, after):
        """:meth:`SwarmRun._record_jump`, and the jump of the whole covariance for the bulk tensor."""
        super()._record_jump(before, after)
        self.covariance_shift += self._covariance(after) - self._covariance(before)

    def calibrate(self, collisions_per_sample):
        """:meth:`SwarmRun.calibrate`; its probe sample is forgotten here too."""
        super().calibrate(collisions_per_sample)
        self.tensor_moments, self.covariance_shifts = [], []

    def _result(self, start, setup, converged):
        result = super()._result(start, setup, converged)
        flux, bulk = tensor_estimates(np.array(self.times[start:]), np.array(self.moments[start:]),
                                      np.array(self.tensor_moments[start:]), self.density,
                                      np.array(self.covariance_shifts[start:]))
        result.diffusion_N_flux, result.diffusion_N_flux_error = mean_and_error(flux)
        result.diffusion_N_bulk, result.diffusion_N_bulk_error = mean_and_error(bulk)
        return result
