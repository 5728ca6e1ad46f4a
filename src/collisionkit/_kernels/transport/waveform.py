"""The record of a periodic electric field of any shape given as samples, and its exact integrals.

E(t) = E0 f(t / T) with f periodic of period 1 in the phase fraction u and
piecewise linear between knots ``u_0 = 0 <= u_1 <= ... <= u_n = 1`` (two
equal knots make a jump). With the acceleration ``a = q E0 / m`` and a
static one ``g``, a flight of ``tau`` from t0 (phase u0) gives exactly

* ``v = v0 + g tau + a T J1`` and ``x = x0 + v0 tau + g tau^2 / 2 + a T^2 J2``,
* ``J1 = integral_{u0}^{u0 + s} f``, ``J2 = integral_{u0}^{u0 + s} (integral_{u0}^{u} f) du``, s = tau / T.

Within one piece f = f_a + sigma (u - u_a), so J1 and J2 are the
polynomials ``f(u0) s + sigma s^2 / 2`` and ``f(u0) s^2 / 2 + sigma s^3 / 6``
(no cancellation: the common case of a flight short beside a piece). A
flight that leaves its piece takes the rest from the antiderivatives at
the knots, ``G1(U) = integral_0^U f = m M + g1(r)`` and ``G2(U) =
integral_0^U G1 = M m(m - 1)/2 + m g2(1) + m M r + g2(r)`` (U = m + r, M =
g1(1) the integral over a period, g1 and g2 tabulated at the knots and
polynomial between them): their differences carry a rounding error of
about 1e-16 of a period's integral, below 1e-16 (nu T) of the flight's own
(nu the collision frequency).

The record extends the oscillating one (:mod:`.oscillating`, with omega =
0 there, so the cosine is off): the acceleration ``a`` (14:17); ``|a|
max |f|`` (25); the unit vector of ``a`` (26:29); 1/T (31, a product
instead of a division per trial); the window bound's parallel scale (32,
:mod:`.waveform_window`: |a| T here); from :data:`WAVE_START`: T, the
number n + 1 of knots, then the knots, f at them (the value on the right of
a jump), the slopes of the pieces, g1 and g2 at the knots. The flights that
use it, with a static B or without, are in :mod:`.waveform_magnetic`, which
also appends, last, the tables of :func:`window_tables` (their start in
33): the piece of a phase in O(1) (:func:`cell_piece`, not by bisection)
and G1's extremes over a window (:mod:`.waveform_window`).
"""

from __future__ import annotations

import math

import numpy as np

from ..._jit import borrowing_inline_kernel, borrowing_kernel

WAVE_START = 34  # the oscillating record's size: the waveform's entries follow
# cells of the piece table per piece (:func:`window_tables`, rounded up to a power of two): evenly spaced knots
# then fall one at most in a cell
CELLS_PER_PIECE = 4


def waveform_record(static_field, amplitude, period, knots, values):
    """The record (module docstring) of a static record, the acceleration amplitude ``a`` (m/s^2), the period T
    (s) and f at the knots (``knots`` from 0 to 1, non-decreasing; ``values`` f there, right of a jump).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform import waveform_record
    >>> record = waveform_record(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 2.0]), 1.0,
    ...                          np.array([0.0, 0.5, 0.5, 1.0]), np.array([1.0, 1.0, -1.0, -1.0]))  # a square wave
    >>> float(record[25]), int(record[35]), float(record[36 + 3 * 4 + 3])  # |a| max|f|, knots, g1(1) = 0
    (2.0, 4, 0.0)
    """
    knots = np.asarray(knots, dtype=float)
    values = np.asarray(values, dtype=float)
    n = knots.size
    lengths = np.diff(knots)
    slopes = np.zeros(n)
    long = lengths > 0.0
    slopes[:-1][long] = (values[1:][long] - values[:-1][long]) / lengths[long]
    g1 = np.zeros(n)
    g2 = np.zeros(n)
    for k in range(n - 1):
        length = lengths[k]
        g1[k + 1] = g1[k] + values[k] * length + 0.5 * slopes[k] * length**2
        g2[k + 1] = g2[k] + g1[k] * length + 0.5 * values[k] * length**2 + slopes[k] * length**3 / 6.0
    record = np.zeros(WAVE_START + 2 + 5 * n)
    record[:static_field.size] = static_field
    size = float(np.linalg.norm(amplitude))
    record[14:17] = amplitude
    # f's largest size: at a knot (linear pieces; a jump's left value is the previous piece's end)
    ends = values[:-1] + slopes[:-1] * lengths
    record[25] = size * max(float(np.abs(values).max()), float(np.abs(ends).max()) if n > 1 else 0.0)
    record[26:29] = np.asarray(amplitude) / size if size > 0.0 else np.array([0.0, 0.0, 1.0])
    record[31] = 1.0 / period
    record[32] = size * period
    record[WAVE_START] = period
    record[WAVE_START + 1] = n
    start = WAVE_START + 2
    for table in (knots, values, slopes, g1, g2):
        record[start:start + n] = table
        start += n
    return record


def _piece_extremes(knots, values, slopes, g1):
    """Per piece, the smallest and largest G1 over it (at its ends or its parabola's vertex: module docstring), and
    the vertex's offset from the piece's start (-f/sigma; 0 without slope)."""
    n = knots.size
    low, high, vertex = np.minimum(g1[:-1], g1[1:]), np.maximum(g1[:-1], g1[1:]), np.zeros(max(n - 1, 0))
    for k in range(n - 1):
        if slopes[k] != 0.0:
            vertex[k] = -values[k] / slopes[k]
            if 0.0 < vertex[k] < knots[k + 1] - knots[k]:
                top = g1[k] + 0.5 * values[k] * vertex[k]
                low[k], high[k] = min(low[k], top), max(high[k], top)
    return low, high, vertex


def window_tables(knots, values, slopes, g1):
    """The tables that find a phase's piece and G1's extremes over a window in O(1) (layout in
    :func:`with_window_tables`), from the knots (0 to 1), f at them, the pieces' slopes and g1 at the knots.

    * C cells (a power of two, at least :data:`CELLS_PER_PIECE` per piece),
      each ``(x, k_lo, k_hi)``: the piece of the cell's start c / C, the
      first knot x strictly inside the cell (2 if none) and x's piece (the
      last k <= n - 2 with knot k <= x: the right side of a jump). With C a
      power of two, ``u C`` and c / C are exact: a phase u of cell floor(u C)
      below x is in piece k_lo, at or above x in k_hi or (only if the cell
      holds more than one knot) a later one.
    * per piece, the offset of its parabola's vertex from its start;
    * for the 2 (n - 1) pieces of two periods (the second's G1 shifted by
      the period's integral), a sparse table of the pieces' smallest and
      largest G1: level j holds the extremes over 2^j pieces from each piece,
      so any range of pieces takes two entries per extreme, at the level
      ``floor(log2(length))`` (tabulated for each length).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.waveform import window_tables
    >>> knots, values = np.array([0.0, 0.5, 0.5, 1.0]), np.array([1.0, 1.0, -1.0, -1.0])  # a square wave
    >>> tables = window_tables(knots, values, np.zeros(4), np.array([0.0, 0.5, 0.5, 0.0]))
    >>> tables[:5].tolist()  # 16 cells, 6 pieces over two periods, 3 levels; G1 from 0 to 1/2 over the period
    [16.0, 6.0, 3.0, 0.0, 0.5]
    >>> tables[5 + 3 * 7:5 + 3 * 9].tolist()  # cells 7 and 8: no knot inside, pieces 0 (before the jump) and 2
    [2.0, 0.0, 0.0, 2.0, 2.0, 2.0]
    """
    n = knots.size
    pieces = n - 1
    cells = 1 << max(int(math.ceil(math.log2(CELLS_PER_PIECE * max(pieces, 1)))), 0)
    starts = np.arange(cells) / cells
    cell_table = np.zeros((cells, 3))
    cell_table[:, 1] = np.minimum(np.searchsorted(knots, starts, side="right") - 1, n - 2)
    inside = np.searchsorted(knots, starts, side="right")  # the first knot after the cell's start
    for c in range(cells):
        x = knots[inside[c]] if inside[c] < n else 2.0
        if x >= (c + 1) / cells:
            x = 2.0
        cell_table[c, 0] = x
        cell_table[c, 2] = min(int(np.searchsorted(knots, x, side="right")) - 1, n - 2) if x < 2.0 else cell_table[c, 1]
    low, high, vertex = _piece_extremes(knots, values, slopes, g1)
    shift = g1[-1]
    low, high = np.concatenate([low, low + shift]), np.concatenate([high, high + shift])
    span = 2 * pieces
    levels = max(int(span).bit_length(), 1)
    logs = np.array([0.0] + [float(length.bit_length() - 1) for length in range(1, span + 1)])
    sparse_low, sparse_high = [low], [high]
    for j in range(1, levels):
        half = 1 << (j - 1)
        last_low, last_high = sparse_low[-1], sparse_high[-1]
        next_low, next_high = last_low.copy(), last_high.copy()
        next_low[:span - half] = np.minimum(last_low[:span - half], last_low[half:])
        next_high[:span - half] = np.maximum(last_high[:span - half], last_high[half:])
        sparse_low.append(next_low)
        sparse_high.append(next_high)
    head = [cells, span, levels, float(low[:pieces].min()), float(high[:pieces].max())]
    return np.concatenate([head, cell_table.ravel(), vertex, logs, *sparse_low, *sparse_high])


def with_window_tables(record):
    """A waveform record (module docstring), all its other tables in place, with :func:`window_tables` appended
    (last) and their start in entry 33. From that start S: C, the pieces of two periods P = 2 (n - 1), the levels L,
    G1's smallest and largest over a period; from S + 5 the 3 C entries of the cells, then n - 1 vertices, P + 1
    levels by length, L P smallest and L P largest G1 (level by level).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform import waveform_record, with_window_tables
    >>> record = with_window_tables(waveform_record(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 2.0]),
    ...                                             1.0, np.array([0.0, 0.25, 1.0]), np.array([1.0, 0.0, 1.0])))
    >>> start = int(record[33])
    >>> start == 34 + 2 + 5 * 3, record[start:start + 3].tolist()  # after the knots' tables: 8 cells, 4 pieces, 3 levels
    (True, [8.0, 4.0, 3.0])
    """
    n = int(record[WAVE_START + 1])
    tables = [record[WAVE_START + 2 + j * n:WAVE_START + 2 + (j + 1) * n] for j in range(4)]
    start = record.size
    record = np.concatenate([record, window_tables(*tables)])
    record[33] = start
    return record


@borrowing_inline_kernel
def at(field, index):
    """``field[index]`` for an index known to be >= 0: as an unsigned index, without numba's wraparound of negative
    ones (three instructions per load, on every load of the window tables).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.waveform import at
    >>> at(np.array([1.0, 2.0, 3.0]), 2)
    3.0
    """
    return field[np.uint64(index)]


@borrowing_inline_kernel
def cell_piece(u, field, n):
    """The piece k holding phase u in [0, 1) (as :func:`_piece`) from the record's cells
    (:func:`window_tables`): k_lo or k_hi of u's cell, then forward over the knots up to u (only in a cell that
    holds more than one knot: never for evenly spaced knots).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform import cell_piece, waveform_record, with_window_tables
    >>> record = with_window_tables(waveform_record(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 2.0]),
    ...                                             1.0, np.array([0.0, 0.3, 0.3, 1.0]), np.array([1.0, 0.0, 1.0, 1.0])))
    >>> cell_piece(0.29, record, 4), cell_piece(0.3, record, 4), cell_piece(0.999, record, 4)
    (0, 2, 2)
    """
    tables = int(at(field, 33))
    size = int(at(field, tables))
    cell = tables + 5 + 3 * min(int(u * size), size - 1)
    below, above = at(field, cell + 1), at(field, cell + 2)
    k = int(below if u < at(field, cell) else above)
    first = WAVE_START + 3
    while k < n - 2 and at(field, first + k) <= u:
        k += 1
    return k


@borrowing_kernel
def _piece(u, field, n):
    """The piece k holding phase u in [0, 1]: the last k <= n - 2 with knot k <= u (the right side of a jump)."""
    first = WAVE_START + 2
    low, high = 0, n - 2
    while low < high:
        middle = (low + high + 1) // 2
        if field[first + middle] <= u:
            low = middle
        else:
            high = middle - 1
    return low


@borrowing_kernel
def _antiderivatives(big_u, field, n):
    """``(G1(U), G2(U))`` for U >= 0 (module docstring)."""
    m = math.floor(big_u)
    r = big_u - m
    if r >= 1.0:  # rounding of a U just below a whole number
        m, r = m + 1.0, 0.0
    k = _piece(r, field, n)
    knots, values, slopes, g1, g2 = (WAVE_START + 2, WAVE_START + 2 + n, WAVE_START + 2 + 2 * n,
                                      WAVE_START + 2 + 3 * n, WAVE_START + 2 + 4 * n)
    d = r - field[knots + k]
    f_a, sigma = field[values + k], field[slopes + k]
    local1 = field[g1 + k] + f_a * d + 0.5 * sigma * d * d
    local2 = field[g2 + k] + field[g1 + k] * d + 0.5 * f_a * d * d + sigma * d * d * d / 6.0
    period_integral = field[g1 + n - 1]
    return (m * period_integral + local1,
            period_integral * m * (m - 1.0) / 2.0 + m * field[g2 + n - 1] + m * period_integral * r + local2)


@borrowing_kernel
def waveform_integrals(t0, tau, field):
    """``(T J1, T^2 J2)`` of a flight of ``tau`` from time ``t0`` (module docstring): the velocity gained is
    ``a T J1``, the displacement from rest ``a T^2 J2``.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform import waveform_integrals, waveform_record
    >>> record = waveform_record(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 1.0]), 2.0,
    ...                          np.array([0.0, 0.5, 0.5, 1.0]), np.array([1.0, 1.0, -1.0, -1.0]))
    >>> [round(value, 12) for value in waveform_integrals(0.5, 1.0, record)]  # +1 for 0.5 s, then -1 for 0.5 s
    [0.0, 0.25]
    """
    period = field[WAVE_START]
    n = int(field[WAVE_START + 1])
    phase = t0 / period
    u0 = phase - math.floor(phase)
    if u0 >= 1.0:
        u0 = 0.0
    s = tau / period
    k = _piece(u0, field, n)
    knots, values, slopes = WAVE_START + 2, WAVE_START + 2 + n, WAVE_START + 2 + 2 * n
    f0 = field[values + k] + field[slopes + k] * (u0 - field[knots + k])
    sigma = field[slopes + k]
    end = field[knots + k + 1]
    if u0 + s <= end:  # within the piece: the polynomials
        return period * (f0 * s + 0.5 * sigma * s * s), period * period * s * s * (0.5 * f0 + sigma * s / 6.0)
    length = end - u0
    first1 = f0 * length + 0.5 * sigma * length * length
    first2 = length * length * (0.5 * f0 + sigma * length / 6.0)
    rest = u0 + s - end
    a1, a2 = _antiderivatives(end, field, n)
    b1, b2 = _antiderivatives(u0 + s, field, n)
    j1 = first1 + (b1 - a1)
    j2 = first2 + first1 * rest + (b2 - a2 - a1 * rest)
    return period * j1, period * period * j2


@borrowing_inline_kernel
def piece_integrals(u0, k, tau, field):
    """``(T J1, T^2 J2)`` of a flight of ``tau`` from the phase ``u0`` in [0, 1), which piece ``k`` holds: as
    :func:`waveform_integrals`, without the phase's reduction and the search for its piece, and across knots
    piece by piece (each piece's polynomials, accumulated: no difference of antiderivatives). A flight of a
    period or more takes :func:`waveform_integrals`. Inlined into its callers (the swarm's trials: no call).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform import piece_integrals, waveform_record
    >>> record = waveform_record(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 1.0]), 2.0,
    ...                          np.array([0.0, 0.5, 0.5, 1.0]), np.array([1.0, 1.0, -1.0, -1.0]))
    >>> [round(value, 12) for value in piece_integrals(0.25, 1, 1.0, record)]  # +1 for 0.5 s, then -1 for 0.5 s
    [0.0, 0.25]
    """
    period = field[WAVE_START]
    s = tau * field[31]
    if s >= 1.0:
        return waveform_integrals(u0 * period, tau, field)
    n = int(field[WAVE_START + 1])
    knots, values, slopes = WAVE_START + 2, WAVE_START + 2 + n, WAVE_START + 2 + 2 * n
    sigma = at(field, slopes + k)
    f = at(field, values + k) + sigma * (u0 - at(field, knots + k))
    end = at(field, knots + k + 1)
    target = u0 + s
    if target <= end:  # within the piece: the polynomials
        return period * s * (f + 0.5 * sigma * s), period * period * s * s * (0.5 * f + sigma * s * (1.0 / 6.0))
    left, j1, j2 = u0, 0.0, 0.0
    while True:
        length = min(end, target) - left
        j2 += length * (j1 + length * (0.5 * f + sigma * length * (1.0 / 6.0)))
        j1 += length * (f + 0.5 * sigma * length)
        if target <= end:
            return period * j1, period * period * j2
        k += 1
        if k >= n - 1:  # the next period
            k, target = 0, target - 1.0
        left, f, sigma = at(field, knots + k), at(field, values + k), at(field, slopes + k)
        end = at(field, knots + k + 1)
