"""A periodic electric field of any shape, given as samples: E(t) = E0 f(omega t / 2 pi).

The samples are pairs (u, f): u the fraction of the period (0 to 1,
non-decreasing; the same u twice makes a jump) and f = E/E0 there. f is
linear between consecutive samples and periodic: the last sample joins the
first one period later, so a sample at u = 1 with another value than the
one at u = 0 is a jump at the period's start. The motion in it, with a
static B at any angle or without, is exact
(:mod:`collisionkit._kernels.transport.waveform_magnetic`).
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np

from .._kernels.transport.waveform_magnetic import shaped_field_record

MAX_SAMPLES = 100_000
# |E/E0| of a sample at most: a waveform is a shape (of order 1) scaled by the amplitude E0/N; a value a million
# times the amplitude is a slip (and 1e300 overflowed its r.m.s.); the peak E/N is bounded as E/N itself
MAX_RATIO = 1e6


def waveform_knots(samples) -> tuple[np.ndarray, np.ndarray]:
    """The knots of f over one period, from 0 to 1, and f at them (the value right of a jump).

    ValueError (naming ``waveform`` and the rule) unless ``samples`` is a
    sequence of at least two (u, f) pairs of finite numbers, u in [0, 1]
    non-decreasing, no u three times, |f| <= :data:`MAX_RATIO`, not all f zero.

    Examples
    --------
    >>> from collisionkit.transport._waveform import waveform_knots
    >>> knots, values = waveform_knots([(0.25, 1.0), (0.75, -1.0)])  # a triangle, peaks at 1/4 and 3/4
    >>> knots.tolist(), values.tolist()
    ([0.0, 0.25, 0.75, 1.0], [0.0, 1.0, -1.0, 0.0])
    """
    try:
        table = np.array(samples, dtype=float)
    except (TypeError, ValueError):
        raise ValueError("waveform must be a list of (phase fraction, E/E0) pairs of numbers") from None
    if table.ndim != 2 or table.shape[1] != 2 or not 2 <= table.shape[0] <= MAX_SAMPLES:
        raise ValueError(f"waveform must hold 2 to {MAX_SAMPLES} (phase fraction, E/E0) pairs; got an array of shape "
                         f"{table.shape}")
    if not np.isfinite(table).all():
        raise ValueError("waveform must hold finite numbers")
    u, f = table[:, 0], table[:, 1]
    if u[0] < 0.0 or u[-1] > 1.0 or np.any(np.diff(u) < 0.0):
        raise ValueError("waveform phase fractions must be non-decreasing from 0 to 1")
    if np.any((np.diff(u)[:-1] == 0.0) & (np.diff(u)[1:] == 0.0)):
        raise ValueError("waveform phase fractions may repeat once (a jump), not three times")
    if np.any(np.abs(f) > MAX_RATIO):
        raise ValueError(f"waveform E/E0 values must lie in [-{MAX_RATIO:g}, {MAX_RATIO:g}] (a shape, scaled by "
                         f"the amplitude E/N); got {f[np.abs(f) > MAX_RATIO][0]:g}")
    if not np.any(f != 0.0):
        raise ValueError("waveform E/E0 values must not all be zero")
    # the piece that wraps from the last sample to the first, one period later: its value at u = 0 (= 1)
    gap = u[0] + 1.0 - u[-1]
    wrap = f[-1] + (f[0] - f[-1]) * (1.0 - u[-1]) / gap if gap > 0.0 else f[0]
    knots, values = list(u), list(f)
    if u[0] > 0.0:
        knots.insert(0, 0.0)
        values.insert(0, wrap)
    if u[-1] < 1.0:
        knots.append(1.0)
        values.append(wrap)
    return np.array(knots), np.array(values)


def waveform_peak(samples) -> float:
    """The largest |f| = |E/E0| over a period (f is linear between samples: a sample holds it).

    Examples
    --------
    >>> from collisionkit.transport._waveform import waveform_peak
    >>> waveform_peak([(0.0, 0.5), (0.5, -2.0)])
    2.0
    """
    return float(np.abs(waveform_knots(samples)[1]).max())


def waveform_rms(samples) -> float:
    """The r.m.s. of f over a period (exact for the linear pieces: (f_a^2 + f_a f_b + f_b^2)/3 each).

    Examples
    --------
    >>> from collisionkit.transport._waveform import waveform_rms
    >>> waveform_rms([(0.0, 1.0), (0.5, 1.0), (0.5, -1.0), (1.0, -1.0)])  # a square wave
    1.0
    """
    knots, values = waveform_knots(samples)
    lengths = np.diff(knots)
    left, right = values[:-1], _left_limits(knots, values)
    return math.sqrt(float(np.sum(lengths * (left**2 + left * right + right**2) / 3.0)))


def _left_limits(knots, values):
    """f at the end of each piece (the value left of the next knot)."""
    right = values[1:].copy()
    # a jump is a zero-length piece: the piece before it ends at the jump's first value
    for k in range(len(knots) - 2, 0, -1):
        if knots[k + 1] == knots[k]:
            right[k - 1] = values[k]
    return right


def half_wave_antisymmetric(samples) -> bool:
    """True if f(u + 1/2) = -f(u) (to 1e-12 of max |f|): the cycle-averaged drift is then zero by symmetry.

    Examples
    --------
    >>> from collisionkit.transport._waveform import half_wave_antisymmetric
    >>> half_wave_antisymmetric([(0.0, 1.0), (0.5, 1.0), (0.5, -1.0), (1.0, -1.0)])  # a square wave
    True
    >>> half_wave_antisymmetric([(0.0, -1.0), (1.0, 1.0)])  # a sawtooth
    False
    """
    knots, values = waveform_knots(samples)
    right = _left_limits(knots, values)
    # between consecutive edges neither f(u) nor f(u + 1/2) has a knot: both are linear, two points decide
    edges = np.unique(np.concatenate([knots, (knots + 0.5) % 1.0, [0.0, 1.0]]))
    steps = np.diff(edges)
    points = np.concatenate([edges[:-1] + steps / 3.0, edges[:-1] + 2.0 * steps / 3.0])

    def at(u):
        k = np.clip(np.searchsorted(knots, u, side="right") - 1, 0, len(knots) - 2)
        return values[k] + (right[k] - values[k]) * (u - knots[k]) / (knots[k + 1] - knots[k])

    scale = float(np.abs(values).max())
    return bool(np.all(np.abs(at(points) + at((points + 0.5) % 1.0)) <= 1e-12 * scale))


def read_waveform(path) -> list[list[float]]:
    r"""The samples of a waveform file: two columns, the fraction of the period (0 to 1) and E/E0 (``#`` comments).

    ValueError (one line, naming the file) if it cannot be read or is not two columns of numbers.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from collisionkit.transport import read_waveform
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = Path(folder) / "square.txt"
    ...     _ = path.write_text("# u  E/E0\n0 1\n0.5 1\n0.5 -1\n1 -1\n")
    ...     read_waveform(path)
    [[0.0, 1.0], [0.5, 1.0], [0.5, -1.0], [1.0, -1.0]]
    """
    path = Path(path)
    if path.is_dir():
        raise ValueError(f"{path} is a folder, not a waveform file")
    try:
        with warnings.catch_warnings():  # numpy warns of a file without data: said below in one line instead
            warnings.simplefilter("ignore", UserWarning)
            table = np.loadtxt(path, comments="#", ndmin=2)
    except FileNotFoundError:
        raise ValueError(f"waveform file not found: {path}") from None
    except (OSError, ValueError) as failure:
        raise ValueError(f"waveform file {path} is not two columns of numbers: {failure}") from None
    if table.size == 0:
        raise ValueError(f"waveform file {path} holds no samples (two columns: phase fraction, E/E0)")
    if table.shape[1] != 2:
        raise ValueError(f"waveform file {path} must have two columns (phase fraction, E/E0); it has {table.shape[1]}")
    return table.tolist()


def shaped_record(static_record, amplitude, period, samples) -> np.ndarray:
    """The kernel's record of the waveform in the static field of ``static_record`` (gravity, B at any angle):
    :func:`collisionkit._kernels.transport.waveform_magnetic.shaped_field_record`."""
    knots, values = waveform_knots(samples)
    return shaped_field_record(static_record, amplitude, period, knots, values)
