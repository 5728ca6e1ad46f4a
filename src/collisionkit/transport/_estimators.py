"""Transport coefficients from a swarm's per-step sums: per-group estimates and their standard errors."""

from __future__ import annotations

import math

import numpy as np
from scipy import constants

from .._kernels import transport as _k
from .townsend import townsend_coefficients

EV = constants.e


def slope(t, y):
    """Least-squares slope of y(t) along axis 0."""
    tc = t - t.mean()
    return np.tensordot(tc, y - y.mean(axis=0), axes=(0, 0)) / np.dot(tc, tc)


def spatial_moments(moments):
    """Per group (last axis of ``moments`` the 14 sums of :func:`~collisionkit._kernels.transport.group_moments`):
    the centroid and the (unbiased) spatial variance per axis, 6 columns."""
    n = moments[..., 0]
    centroid = moments[..., 1:4] / np.maximum(n, 1.0)[..., None]
    variance = (moments[..., 4:7] / np.maximum(n, 1.0)[..., None] - centroid**2) * (n / np.maximum(n - 1, 1))[..., None]
    return np.concatenate([centroid, variance], axis=-1)


def estimates(times, moments, tallies, kinds, density, shifts=None):
    """Per-group estimates (groups on the first axis) from the steady window.

    ``moments`` are per-sample snapshots (mean energy, positions, the flux
    diffusion's <r v>); ``tallies`` are sums over every flight of the
    interval before each sample (collisions, particle time, displacement).
    ``shifts`` (samples, groups, 6) are population control's cumulative jumps
    of the centroid and variance, taken out of the bulk coefficients' series.
    """
    n = moments[..., 0]
    mean = moments[..., 1:14] / n[..., None]
    centroid = mean[..., 0:3]
    spatial = spatial_moments(moments)
    if shifts is not None:
        spatial = spatial - shifts
    variance = spatial[..., 3:6]
    velocity = mean[..., 6:9]
    energy = mean[..., 9] / EV
    cross = mean[..., 10:13] - centroid * velocity
    rates_time = tallies.sum(axis=0)
    n_proc = len(kinds)
    particle_time = rates_time[:, n_proc + _k.TIME_COLUMN_OFFSET]
    counts = rates_time[:, :n_proc]
    moved = rates_time[:, n_proc + _k.DISPLACEMENT_COLUMN_OFFSET:n_proc + _k.DISPLACEMENT_COLUMN_OFFSET + 3]
    est = {
        "mean_energy": energy.mean(axis=0),
        # the flux drift <v> as the time average over every flight (displacement / particle time), not over the
        # samples: a sample sees each velocity once, a flight integrates it, so the error falls by the ratio of
        # the sampling interval to the velocity's correlation time (~20 collisions a sample: 10-15x in variance)
        "drift_velocity_flux": moved / particle_time[:, None],
        "drift_velocity_bulk": slope(times, spatial[..., 0:3]),
        "diffusion_L_N_flux": density * cross[..., 2].mean(axis=0),
        "diffusion_T_N_flux": density * 0.5 * (cross[..., 0] + cross[..., 1]).mean(axis=0),
        "diffusion_L_N": density * 0.5 * slope(times, variance[..., 2]),
        "diffusion_T_N": density * 0.25 * slope(times, variance[..., 0] + variance[..., 1]),
        "rates": counts / (particle_time[:, None] * density),
    }
    ionization = np.array([kind == "ionization" for kind in kinds])
    attachment = np.array([kind == "attachment" for kind in kinds])
    est["ionization_frequency_N"] = counts[:, ionization].sum(axis=1) / (particle_time * density)
    est["attachment_frequency_N"] = counts[:, attachment].sum(axis=1) / (particle_time * density)
    return est


def mean_and_error(values):
    """Mean over the groups (axis 0) and its standard error."""
    values = np.asarray(values, dtype=float)
    return values.mean(axis=0), values.std(axis=0, ddof=1) / math.sqrt(values.shape[0])


def drift_diffusion_correlations(est) -> tuple[float, float]:
    """The correlations over the groups of |W_bulk,z| with N D_L and with N D_T (NaN where a column is constant).

    Examples
    --------
    >>> est = {"drift_velocity_bulk": np.array([[0, 0, 1.0], [0, 0, 2.0], [0, 0, 3.0]]),
    ...        "diffusion_L_N": np.array([2.0, 4.0, 6.1]), "diffusion_T_N": np.array([3.0, 1.0, 2.0])}
    >>> [round(value, 3) for value in drift_diffusion_correlations(est)]
    [1.0, -0.5]
    """
    drift = np.abs(np.asarray(est["drift_velocity_bulk"])[:, 2])
    result = []
    for name in ("diffusion_L_N", "diffusion_T_N"):
        column = np.asarray(est[name], dtype=float)
        spread = drift.std() * column.std()
        result.append(float(np.mean((drift - drift.mean()) * (column - column.mean())) / spread) if spread > 0
                      else math.nan)
    return result[0], result[1]


def townsend_estimates(est) -> dict[str, tuple[float, float]]:
    """SST ``alpha_N`` and ``eta_N`` (m^2) with their errors from the per-group estimates of :func:`estimates`.

    The values come from the group means of |W_bulk,z|, N D_L, k_i and k_a
    (:func:`~collisionkit.transport.townsend_coefficients`); the errors
    propagate the groups' scatter through the formula to first order (the
    delta method with the groups' covariance: the standard error of
    ``f(mean) + grad f . (x_g - mean)`` over the groups g).
    """
    columns = np.column_stack([np.abs(est["drift_velocity_bulk"][:, 2]), est["diffusion_L_N"],
                               est["ionization_frequency_N"], est["attachment_frequency_N"]])
    mean = columns.mean(axis=0)
    values = np.array(townsend_coefficients(*mean))
    gradient = np.zeros((2, 4))
    for k in range(4):
        step = 1e-6 * max(abs(mean[k]), 1e-300)
        up, down = mean.copy(), mean.copy()
        up[k] += step
        down[k] -= step
        gradient[:, k] = (np.array(townsend_coefficients(*up)) - np.array(townsend_coefficients(*down))) / (2 * step)
    linear = (columns - mean) @ gradient.T  # (groups, 2)
    errors = linear.std(axis=0, ddof=1) / math.sqrt(columns.shape[0])
    return {"alpha_N": (float(values[0]), float(errors[0])), "eta_N": (float(values[1]), float(errors[1]))}
