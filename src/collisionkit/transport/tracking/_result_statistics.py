"""Estimators behind :class:`~collisionkit.transport.tracking.TrackingResult`: the numbers derived from its arrays.

Means with their standard errors over independent units, the end records
at the collecting electrode and the per-primary sums of their arrival
times, the Polya parameter of the gain distribution
(with a jackknife error) and the swarm coefficients fitted to the moments
sampled in an unbounded gas. The functions take plain arrays, so this
module does not import the result's.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import constants

from ..._kernels.transport.tracking import codes as _c

EV = constants.e
JACKKNIFE_BLOCKS = 32  # blocks of primaries left out in turn for the error of the Polya parameter


def mean_and_error(values) -> tuple[float, float]:
    """The mean of independent values and its standard error (NaN where too few values define them).

    Parameters
    ----------
    values : array_like
        One value per independent unit (a primary, a group).

    Returns
    -------
    tuple of float
        ``(mean, standard error)``: both NaN for no values, the error NaN for one.

    Examples
    --------
    >>> mean_and_error([1.0, 3.0])
    (2.0, 1.0)
    """
    values = np.asarray(values, dtype=float)
    if values.size == 0:
        return math.nan, math.nan
    if values.size < 2:
        return float(values.mean()), math.nan
    return float(values.mean()), float(values.std(ddof=1) / math.sqrt(values.size))


def records_at_collector(records: np.ndarray, surfaces, collector: str | None) -> np.ndarray:
    """The end records of the electrons that reached the collecting electrode.

    Parameters
    ----------
    records : ndarray
        End records (:mod:`collisionkit._kernels.transport.tracking.codes`).
    surfaces : sequence of str
        The device's surface names, in the order of the records' surface index.
    collector : str or None
        The collecting electrode's name.

    Returns
    -------
    ndarray
        The rows of ``records`` that ended on ``collector``.

    Raises
    ------
    ValueError
        If ``collector`` is None (the device names none).

    Examples
    --------
    >>> records = np.zeros((2, _c.RECORD_COLUMNS))
    >>> records[:, _c.RECORD_STATUS] = _c.ENDED_SURFACE
    >>> records[:, _c.RECORD_SURFACE] = [0, 1]
    >>> records_at_collector(records, ("cathode", "anode"), "anode").shape
    (1, 11)
    """
    if collector is None:
        raise ValueError("this device names no collecting electrode (collector)")
    index = list(surfaces).index(collector)
    mask = (records[:, _c.RECORD_STATUS] == _c.ENDED_SURFACE) & (records[:, _c.RECORD_SURFACE] == index)
    return records[mask]


def arrival_sums(collected_records, primaries: int) -> tuple[np.ndarray, np.ndarray]:
    """Per primary, the sum of the arrival times of its collected electrons and their number.

    Parameters
    ----------
    collected_records : ndarray
        End records of the electrons at the collecting electrode.
    primaries : int
        Primaries of the run (the length of both results).

    Returns
    -------
    tuple of ndarray
        ``(sums of the times in s, counts)``: the numerators and
        denominators of the mean drift time.

    Examples
    --------
    >>> records = np.zeros((3, _c.RECORD_COLUMNS))
    >>> records[:, _c.RECORD_PRIMARY] = [0, 0, 2]
    >>> records[:, _c.RECORD_TIME] = [1.0, 2.0, 4.0]
    >>> [a.tolist() for a in arrival_sums(records, 3)]
    [[3.0, 0.0, 4.0], [2, 0, 1]]
    """
    primary = collected_records[:, _c.RECORD_PRIMARY].astype(np.int64)
    sums = np.bincount(primary, weights=collected_records[:, _c.RECORD_TIME], minlength=primaries)
    counts = np.bincount(primary, minlength=primaries)
    return sums, counts


def polya_theta(values) -> float:
    """The Polya parameter theta of gains from their moments, var/mean^2 = 1/(1 + theta) - 1/mean.

    Parameters
    ----------
    values : array_like
        The gain of each primary.

    Returns
    -------
    float
        theta (0 for the exponential Yule-Furry law); NaN if the mean or the
        variance is not positive.

    Examples
    --------
    >>> polya_theta([1.0, 1.0, 1.0])
    nan
    """
    values = np.asarray(values, dtype=float)
    mean = values.mean()
    variance = values.var(ddof=1)
    if mean <= 0 or variance <= 0:
        return math.nan
    return 1.0 / (variance / mean**2 + 1.0 / mean) - 1.0


def polya_theta_and_error(values: np.ndarray) -> tuple[float, float]:
    """:func:`polya_theta` of the gains with its standard error by the jackknife over blocks of primaries.

    Parameters
    ----------
    values : ndarray of float
        The gain of each primary.

    Returns
    -------
    tuple of float
        ``(theta, standard error)``; the error is NaN for fewer than 3 primaries.

    Examples
    --------
    >>> theta, error = polya_theta_and_error(np.array([1.0, 2.0]))
    >>> math.isnan(error)
    True
    """
    theta = polya_theta(values)
    if values.size < 3:
        return theta, math.nan
    blocks = np.array_split(np.arange(values.size), min(values.size, JACKKNIFE_BLOCKS))
    partial = np.array([polya_theta(np.delete(values, block)) for block in blocks])
    return theta, float(math.sqrt((len(blocks) - 1) * partial.var()))


def swarm_coefficients(sample_times: np.ndarray, moments: np.ndarray,
                       start: float) -> dict[str, tuple[float, float]]:
    """Bulk swarm coefficients from moments sampled per group, fitted over the samples from fraction ``start`` on.

    Parameters
    ----------
    sample_times : ndarray
        The sample times (s), at least 2.
    moments : ndarray
        Per group and sample time, sums of 1, r, r^2, v, kinetic energy, r_k v_k
        (:mod:`collisionkit._kernels.transport.tracking.codes`).
    start : float
        Fraction of the samples left out at the start (the transient).

    Returns
    -------
    dict
        ``drift_velocity`` (along z, m/s), ``diffusion_L`` and ``diffusion_T``
        (m^2/s, N-less) and ``mean_energy`` (eV), each ``(mean, standard
        error)`` over the groups.

    Examples
    --------
    >>> moments = np.zeros((2, 2, _c.MOMENT_COLUMNS))
    >>> moments[..., 0] = 1.0
    >>> moments[:, 1, 3] = [2.0, 4.0]  # z at the second sample
    >>> swarm_coefficients(np.array([0.0, 1.0]), moments, 0.0)["drift_velocity"]
    (3.0, 1.0)
    """
    first = int(start * (sample_times.size - 1))
    times = sample_times[first:]
    m = moments[:, first:, :]
    n = np.maximum(m[..., 0], 1.0)
    mean = m[..., 1:14] / n[..., None]
    centroid = mean[..., 0:3]
    variance = (mean[..., 3:6] - centroid**2) * (n / np.maximum(n - 1.0, 1.0))[..., None]
    tc = times - times.mean()

    def slope(y):
        return (y - y.mean(axis=1, keepdims=True)) @ tc / (tc @ tc)

    per_group = {
        "drift_velocity": slope(centroid[..., 2]),
        "diffusion_L": 0.5 * slope(variance[..., 2]),
        "diffusion_T": 0.25 * slope(variance[..., 0] + variance[..., 1]),
        "mean_energy": (mean[..., 9] / EV).mean(axis=1),
    }
    return {name: mean_and_error(values) for name, values in per_group.items()}
