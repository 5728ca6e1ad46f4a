r"""Is a cooling granular gas still homogeneous? The energy of its box-scale shear flows against a homogeneous gas's.

A granular gas cools homogeneously (Haff's law, the cooling state's
theories) only while it stays homogeneous. A large enough one is not: its
transverse (shear) velocity modes of the longest wavelengths cool more
slowly than the heat and grow, relative to it, into vortices, and density
clusters follow (Goldhirsch & Zanetti 1993, PRL 70, 1619; McNamara & Young
1996, PRE 53, 5089; Brey, Ruiz-Montero & Cubero 1998, PRE 60, 3150). The
box sets the longest wavelength, so the box decides.

:func:`shear_mode_energy` measures it: for each periodic axis a with
:math:`k = 2\pi / L_a` and each velocity component b across it, the mode

.. math::

    j_b(k) = \sum_i m_i u_{i,b}\, e^{-i k x_{i,a}}

(u the velocity relative to the centre of mass), its energy over a
homogeneous gas's share, :math:`|j_b(k)|^2 / \sum_i m_i^2 u_{i,b}^2`,
averaged over the :math:`M = d(d - 1)` modes. In equilibrium the velocities
are independent of each other and of the positions (the canonical
distribution factorises), so at any density each mode's ratio has mean 1
and, its real and imaginary parts being sums of many independent terms,
an exponential distribution: the average of M is Gamma(M, 1/M)
distributed (mean 1, standard deviation :math:`1/\sqrt{M}`).
:func:`homogeneity_threshold` is the value a homogeneous gas exceeds at one
block end of a run of ``blocks`` with probability ``false_alarm / blocks``.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import stats

__all__ = ["FALSE_ALARM", "homogeneity_threshold", "shear_mode_count", "shear_mode_energy"]

FALSE_ALARM = 1e-3  # a homogeneous gas's probability of crossing the threshold anywhere in a run


def shear_mode_count(dim: int) -> int:
    """The transverse modes at the box's longest wavelengths, d (d - 1): 6 in 3D, 2 in 2D.

    Examples
    --------
    >>> shear_mode_count(3), shear_mode_count(2)
    (6, 2)
    """
    if dim not in (2, 3):
        raise ValueError(f"dim must be 2 or 3; got {dim!r}")
    return dim * (dim - 1)


def shear_mode_energy(positions, velocities, box, masses=None) -> float:
    r"""The energy of the box-scale shear flows over a homogeneous gas's share: about 1 if homogeneous.

    :math:`\frac{1}{M} \sum_{a} \sum_{b \ne a} |\sum_i m_i u_{i,b} e^{-2\pi i
    x_{i,a} / L_a}|^2 / \sum_i m_i^2 u_{i,b}^2` over the M = d (d - 1)
    transverse modes (module notes), u the velocities relative to the
    centre of mass.

    Parameters
    ----------
    positions, velocities : array_like, shape (N, d)
        d = 2 or 3, every axis periodic with the box's lengths.
    box : array_like, shape (d,)
        The periodic box's lengths.
    masses : array_like, shape (N,), optional
        Default: equal masses.

    Returns
    -------
    float
        1 on average in equilibrium (standard deviation 1/sqrt(M)); a shear
        flow u_b = A sin(2 pi x_a / L_a) across the box raises its mode's
        ratio by about N m A^2 / (4 kT) (the average by 1/M of it), kT >> m A^2.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(1)
    >>> draws = [shear_mode_energy(rng.uniform(0, 10, (1000, 3)), rng.normal(size=(1000, 3)), [10, 10, 10])
    ...          for _ in range(400)]
    >>> round(float(np.mean(draws)), 1), round(float(np.std(draws)), 1)  # homogeneous: 1 and 1 / sqrt(6)
    (1.0, 0.4)
    >>> x, v = rng.uniform(0, 10, (100000, 2)), rng.normal(size=(100000, 2))
    >>> v[:, 1] += 0.1 * np.sin(2 * np.pi * x[:, 0] / 10)  # a shear flow: N A^2 / 4 = 250 in one mode of two
    >>> 100 < shear_mode_energy(x, v, [10, 10]) < 150
    True
    """
    positions = np.asarray(positions, dtype=float)
    velocities = np.asarray(velocities, dtype=float)
    box = np.asarray(box, dtype=float)
    if positions.ndim != 2 or positions.shape != velocities.shape or positions.shape[1] not in (2, 3):
        raise ValueError(f"positions and velocities must both have shape (N, 2) or (N, 3); got {positions.shape} and "
                         f"{velocities.shape}")
    dim = positions.shape[1]
    if box.shape != (dim,) or not np.all(np.isfinite(box) & (box > 0)):
        raise ValueError(f"box must be {dim} positive finite lengths; got {box.tolist()}")
    masses = np.ones(len(positions)) if masses is None else np.broadcast_to(np.asarray(masses, dtype=float),
                                                                           (len(positions),))
    relative = velocities - masses @ velocities / np.sum(masses)
    momenta = masses[:, None] * relative
    ratios = []
    for axis in range(dim):
        phase = np.exp(-2j * np.pi * positions[:, axis] / box[axis])
        for component in range(dim):
            if component != axis:
                share = float(np.sum(momenta[:, component] ** 2))
                ratios.append(abs(phase @ momenta[:, component]) ** 2 / share if share > 0 else math.nan)
    return float(np.mean(ratios))


def homogeneity_threshold(dim: int, blocks: int, false_alarm: float = FALSE_ALARM) -> float:
    """The :func:`shear_mode_energy` a homogeneous gas exceeds at one of ``blocks`` block ends with probability
    ``false_alarm`` or less (the Gamma(M, 1/M) quantile of ``false_alarm / blocks``).

    Examples
    --------
    >>> round(homogeneity_threshold(3, 10), 2), round(homogeneity_threshold(2, 10), 2)
    (3.26, 5.88)
    """
    if not 0.0 < false_alarm < 1.0:
        raise ValueError(f"false_alarm must lie in (0, 1); got {false_alarm!r}")
    if blocks < 1:
        raise ValueError(f"blocks must be >= 1; got {blocks!r}")
    modes = shear_mode_count(dim)
    return float(stats.gamma.isf(false_alarm / blocks, modes, scale=1.0 / modes))


def homogeneity_summary(block_values, dim: int, collisions_per_block: float) -> dict:
    """The summary keys of a cooling run's homogeneity from :func:`shear_mode_energy` at its block ends.

    ``shear_mode_energy`` at the last block end, its maximum, the threshold
    for the blocks measured (NaN values: blocks of a checkpoint written
    before it was recorded, left out), ``homogeneous`` and
    ``homogeneity_lost_after``: the collisions per particle to the first
    block end above the threshold (None if none), ``collisions_per_block``
    per particle. Empty if no block has a value.

    Examples
    --------
    >>> summary = homogeneity_summary([1.2, 0.7, 9.0, 40.0], 3, 10.0)
    >>> summary["homogeneous"], summary["homogeneity_lost_after"], summary["shear_mode_energy_max"]
    (False, 30.0, 40.0)
    """
    values = np.asarray(block_values, dtype=float)
    known = np.flatnonzero(np.isfinite(values))
    if known.size == 0:
        return {}
    threshold = homogeneity_threshold(dim, known.size)
    above = known[values[known] > threshold]
    return {"shear_mode_energy": float(values[known[-1]]), "shear_mode_energy_max": float(np.max(values[known])),
            "shear_mode_energy_threshold": threshold, "homogeneous": bool(above.size == 0),
            "homogeneity_lost_after": None if above.size == 0 else float((above[0] + 1) * collisions_per_block)}
