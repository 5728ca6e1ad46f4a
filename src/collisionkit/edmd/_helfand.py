"""Transport coefficients from a time series of Einstein-Helfand moments: fits, their window, Green-Kubo.

An EDMD run with ``transport=True`` samples the Helfand moments (see
:meth:`~collisionkit.edmd.HardSphereSystem.helfand_moments`) on a uniform
time grid; each measurement block is an independent Einstein measurement:
for every lag its mean squared change over every time origin in the block
(pairs of samples both in the block, so blocks share no origin), and a
straight line fitted to it over the fit window. The coefficient is the
mean of the blocks' slopes, its error their standard error.

Einstein-Helfand relations (Helfand, Phys. Rev. 119, 1 (1960); Hansen &
McDonald, Theory of Simple Liquids, 4th ed., sec. 8.4; for hard spheres
Alder, Gass & Wainwright, J. Chem. Phys. 53, 3813 (1970)), d dimensions,
volume V, t the lag::

    shear viscosity       eta    = <dG°_ab dG°_ab> / ((d - 1)(d + 2) 2 V kT t)
    bulk viscosity        zeta   = var(tr dG / d) / (2 V kT t)
    thermal conductivity  lambda = <|dG_E|^2> / (d 2 V kT^2 t)
    interdiffusion        D_12   = <|dM|^2> / (d 2 N x_1 x_2 t)

G° is the symmetric traceless part of the momentum moment's change: its
(d - 1)(d + 2) / 2 independent components (the off-diagonal ones and the
normal-stress differences) all give eta in an isotropic fluid, so the sum
over all of them is used (Daivis & Evans, J. Chem. Phys. 100, 541
(1994)). M = x_2 sum_{i in 1} r_i - x_1 sum_{i in 2} r_i (unwrapped
positions) is the moment of the interdiffusion flux; D_12 here is Fick's
interdiffusion coefficient divided by the thermodynamic factor (equal to
it in an ideal mixture; Hansen & McDonald, sec. 8.2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ._msd import block_error

__all__ = ["FIT_END", "FIT_NOISE", "FIT_START", "EinsteinFit", "einstein_fit", "fit_window", "green_kubo_viscosity"]

FIT_START = 8.0  # the fit window opens this many mean free times after the origin (the fluxes have relaxed)
FIT_END = 32.0  # and closes this many mean free times after it, or earlier where the noise sets in:
FIT_NOISE = 0.25  # the relative standard error of the mean squared change beyond which a lag is too noisy
# the fit window never closes before this many times its opening (a line needs a stretch of lags)
FIT_MIN_SPAN = 2.0


@dataclass
class EinsteinFit:
    """One transport coefficient from its Einstein-Helfand curve: value, error and the curve with its fit.

    ``time`` are the lags, ``curve`` the block mean of the normalised mean
    squared change (whose slope is the coefficient), ``curve_error`` its
    standard error; the fitted line is ``intercept + value * time`` over
    ``window``; ``blocks`` the slope of each block.

    Examples
    --------
    >>> import numpy as np
    >>> time = np.arange(1.0, 5.0)
    >>> einstein_fit(time, np.array([2.0 * time, 4.0 * time]), (1.0, 4.0)).blocks.round(12)
    array([2., 4.])
    """

    value: float
    error: float
    intercept: float
    window: tuple[float, float]
    time: np.ndarray = field(repr=False)
    curve: np.ndarray = field(repr=False)
    curve_error: np.ndarray = field(repr=False)
    blocks: np.ndarray = field(repr=False)


def block_slices(block_of):
    """The (start, stop) sample ranges of each block, from the block number of each sample (non-decreasing).

    Examples
    --------
    >>> block_slices([0, 0, 1, 1, 1])
    [(0, 2), (2, 5)]
    """
    block_of = np.asarray(block_of)
    if block_of.size == 0:
        return []
    edges = np.flatnonzero(np.diff(block_of)) + 1
    starts = np.concatenate([[0], edges])
    stops = np.concatenate([edges, [block_of.size]])
    return list(zip(starts.tolist(), stops.tolist()))


def block_curves(values, slices, lags, reduce):
    """Per block and lag: the mean over the block's time origins of ``reduce(values[k + lag] - values[k])``.

    ``values`` (n, ...) are samples on a uniform grid, ``slices`` the
    blocks' sample ranges, ``lags`` positive integers; ``reduce`` maps an
    array of changes (pairs, ...) to one number a pair. NaN where a block
    has no pair at a lag.

    Examples
    --------
    >>> import numpy as np
    >>> walk = np.arange(10.0)[:, None]  # moves by 1 a step
    >>> block_curves(walk, [(0, 5), (5, 10)], [1, 2], lambda d: d[:, 0] ** 2)
    array([[1., 4.],
           [1., 4.]])
    """
    curves = np.full((len(slices), len(lags)), math.nan)
    for b, (start, stop) in enumerate(slices):
        block = values[start:stop]
        for k, lag in enumerate(lags):
            if lag < len(block):
                curves[b, k] = float(np.mean(reduce(block[lag:] - block[:-lag])))
    return curves


def column_statistics(curves, width):
    """Per column (lag) of ``curves`` (blocks, width): the mean of the finite entries and its standard error.

    Examples
    --------
    >>> import numpy as np
    >>> means, errors = column_statistics(np.array([[1.0, np.nan], [3.0, 2.0]]), 2)
    >>> means.tolist(), float(errors[0])
    ([2.0, 2.0], 1.0)
    """
    columns = [column[np.isfinite(column)] for column in np.asarray(curves).reshape(-1, width).T]
    means = np.array([float(np.mean(column)) if column.size else math.nan for column in columns])
    return means, np.array([block_error(column) for column in columns])


def fit_window(time, curve, curve_error, free_time, start=FIT_START, end=FIT_END, noise=FIT_NOISE):
    """The fit window (t_min, t_max): from ``start`` to ``end`` mean free times, closed earlier by the noise.

    The Einstein curves turn linear once the fluxes' correlations have
    decayed (Alder, Gass & Wainwright 1970; Erpenbeck & Wood, J. Stat. Phys.
    24, 455 (1981)). The slowest is the heat flux of the dilute gas, which
    relaxes in about 2 mean free times (the Prandtl number 2/3 of Chapman-
    Enskog makes it 3/2 of the momentum flux's time eta / (n kT)): a fit
    from 5 free times on found the conductivity 3 % low, from 8 on the rest
    of the relaxation is below 1 %. So the window opens at ``start`` free
    times and closes at ``end``, or before the first lag whose relative
    standard error exceeds ``noise``, but never before ``FIT_MIN_SPAN``
    times its opening; both ends are capped by the lags measured (the
    window then shrinks in proportion: the blocks are too short for it).

    Examples
    --------
    >>> import numpy as np
    >>> time = np.arange(1, 201) * 0.25
    >>> fit_window(time, time, 0.01 * time, 1.0)
    (8.0, 32.0)
    >>> fit_window(time, time, 0.01 * time**2, 1.0)  # noisy beyond t = 25
    (8.0, 25.0)
    """
    t_min, t_max = start * free_time, end * free_time
    measured = time[np.isfinite(curve) & np.isfinite(curve_error)]
    longest = float(measured.max()) if measured.size else 0.0
    if longest < t_max:  # blocks too short: the window shrinks with them
        t_min, t_max = t_min * longest / t_max, longest
    with np.errstate(divide="ignore", invalid="ignore"):
        noisy = (time >= t_min) & ~(np.abs(curve_error) <= noise * np.abs(curve))
    if np.any(noisy):
        t_max = min(t_max, max(float(time[noisy].min()) - _step(time), FIT_MIN_SPAN * t_min))
    inside = time[(time >= t_min * (1 - 1e-12)) & (time <= t_max * (1 + 1e-12))]
    if inside.size < 2:
        return math.nan, math.nan
    return float(inside.min()), float(inside.max())


def _step(time):
    return float(time[1] - time[0]) if time.size > 1 else 0.0


def einstein_fit(time, curves, window):
    """Fit a line to each block's curve over ``window``: the mean slope, its standard error, the mean intercept.

    Examples
    --------
    >>> import numpy as np
    >>> time = np.arange(1.0, 11.0)
    >>> curves = np.array([1.0 + 2.0 * time, 3.0 + 4.0 * time])
    >>> fit = einstein_fit(time, curves, (2.0, 8.0))
    >>> round(fit.value, 12), round(fit.error, 12), round(fit.intercept, 12)
    (3.0, 1.0, 2.0)
    """
    curve, errors = column_statistics(curves, time.size)
    inside = (time >= window[0]) & (time <= window[1])
    usable = [row for row in curves if np.all(np.isfinite(row[inside]))]
    if not math.isfinite(window[0]) or inside.sum() < 2 or not usable:
        return EinsteinFit(math.nan, math.nan, math.nan, window, time, curve, errors, np.array([]))
    fits = np.polyfit(time[inside], np.array(usable)[:, inside].T, 1)
    slopes, intercepts = fits[0], fits[1]
    return EinsteinFit(float(np.mean(slopes)), block_error(slopes), float(np.mean(intercepts)), window, time, curve,
                       errors, slopes)


def green_kubo_viscosity(stress, interval, volume, kT, slices, cutoff):
    r"""Shear viscosity from the Green-Kubo integral of a pressure-tensor series, with its block error.

    :math:`\eta = \frac{V}{kT} \int_0^{t_c} \langle P^\circ_{ab}(0) P^\circ_{ab}(t)\rangle\,dt
    \,/\, ((d-1)(d+2))`, summed over a and b (Hansen & McDonald, sec. 8.4;
    the average over the traceless components as in :mod:`._helfand`): ``stress`` (n, d, d)
    holds the pressure tensor averaged over each interval of the grid (the
    change of the momentum moment divided by V and the interval), whose
    correlation at lag k is summed as
    :math:`\Delta t\,[C_0 / 2 + \sum_{k=1}^{K} C_k]` up to ``cutoff``
    (K intervals): the discrete form of which the Einstein relation is the
    time integral. Each block (``slices`` of the series) gives a value;
    returns their mean and standard error.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(1)
    >>> # white noise of variance s2 per traceless component: eta = V s2 dt / (2 kT)
    >>> a = rng.normal(size=(20000, 3, 3))
    >>> stress = 0.5 * (a + a.transpose(0, 2, 1))
    >>> value, error = green_kubo_viscosity(stress, 0.1, 1.0, 1.0, [(0, 10000), (10000, 20000)], 0.0)
    >>> abs(value - 0.5 * 0.5 * 0.1) < 4 * error + 0.002
    True
    """
    dim = stress.shape[1]
    traceless = stress - np.trace(stress, axis1=1, axis2=2)[:, None, None] / dim * np.eye(dim)
    lags = int(round(cutoff / interval))
    values = []
    for start, stop in slices:
        block = traceless[start:stop]
        if len(block) <= lags:
            continue
        correlation = [np.mean(np.sum(block[k:] * block[: len(block) - k], axis=(1, 2))) for k in range(lags + 1)]
        integral = interval * (0.5 * correlation[0] + sum(correlation[1:]))
        values.append(volume / kT * integral / ((dim - 1) * (dim + 2)))
    if not values:
        return math.nan, math.nan
    return float(np.mean(values)), block_error(values)
