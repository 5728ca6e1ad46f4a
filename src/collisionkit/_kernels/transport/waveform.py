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
also appends, last, the cell table of :func:`piece_cells` (its size C in
33): the piece of a phase in O(1) (:func:`cell_piece`), not by bisection.
"""

from __future__ import annotations

import math

import numpy as np

from ..._jit import borrowing_inline_kernel, borrowing_kernel

WAVE_START = 34  # the oscillating record's size: the waveform's entries follow
# cells of the piece table per piece (:func:`piece_cells`, rounded up to a power of two): a phase's cell then
# starts at most one knot (of evenly spaced ones) before the phase's piece
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


def piece_cells(knots):
    """The cell table of the knots (0 to 1, non-decreasing): C cells (a power of two, at least
    :data:`CELLS_PER_PIECE` per piece), cell c holding the piece of phase c / C (:func:`_piece`'s: the last k <= n -
    2 with knot k <= c / C). With C a power of two, ``u C`` and ``c / C`` are exact in floating point: the cell
    ``floor(u C)`` of a phase u starts at or before it, so its piece is at or before u's.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.waveform import piece_cells
    >>> cells = piece_cells(np.array([0.0, 0.5, 0.5, 1.0]))  # 3 pieces: 16 cells; a jump at 1/2, piece 2 right of it
    >>> cells.size, float(cells[7]), float(cells[8])
    (16, 0.0, 2.0)
    """
    knots = np.asarray(knots, dtype=float)
    n = knots.size
    cells = 1 << max(int(math.ceil(math.log2(CELLS_PER_PIECE * max(n - 1, 1)))), 0)
    pieces = np.searchsorted(knots, np.arange(cells) / cells, side="right") - 1
    return np.minimum(pieces, n - 2).astype(float)


def with_piece_cells(record):
    """A waveform record (module docstring), its tables complete, with :func:`piece_cells` of its knots appended
    (last: :func:`cell_piece` finds it from the record's end) and their number C in entry 33.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform import waveform_record, with_piece_cells
    >>> record = with_piece_cells(waveform_record(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 2.0]),
    ...                                           1.0, np.array([0.0, 0.25, 1.0]), np.array([1.0, 0.0, 1.0])))
    >>> int(record[33]), record[-8:].tolist()  # 8 cells: piece 0 below 1/4, then piece 1
    (8, [0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0])
    """
    n = int(record[WAVE_START + 1])
    cells = piece_cells(record[WAVE_START + 2:WAVE_START + 2 + n])
    record = np.concatenate([record, cells])
    record[33] = cells.size
    return record


@borrowing_inline_kernel
def cell_piece(u, field, n):
    """The piece k holding phase u in [0, 1) (as :func:`_piece`) from the record's cell table
    (:func:`with_piece_cells`): the piece of u's cell, then forward over the knots up to u (none or one for evenly
    spaced knots).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform import cell_piece, waveform_record, with_piece_cells
    >>> record = with_piece_cells(waveform_record(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 2.0]),
    ...                                           1.0, np.array([0.0, 0.3, 0.3, 1.0]), np.array([1.0, 0.0, 1.0, 1.0])))
    >>> cell_piece(0.29, record, 4), cell_piece(0.3, record, 4), cell_piece(0.999, record, 4)
    (0, 2, 2)
    """
    size = int(field[33])
    k = int(field[field.shape[0] - size + min(int(u * size), size - 1)])
    first = WAVE_START + 3
    while k < n - 2 and field[first + k] <= u:
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


@borrowing_kernel
def piece_integrals(u0, k, tau, field):
    """``(T J1, T^2 J2)`` of a flight of ``tau`` from the phase ``u0`` in [0, 1), which piece ``k`` holds: as
    :func:`waveform_integrals`, without the phase's reduction and the search for its piece, and across knots
    piece by piece (each piece's polynomials, accumulated: no difference of antiderivatives). A flight of a
    period or more takes :func:`waveform_integrals`.

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
    sigma = field[slopes + k]
    f = field[values + k] + sigma * (u0 - field[knots + k])
    end = field[knots + k + 1]
    target = u0 + s
    if target <= end:  # within the piece: the polynomials
        return period * s * (f + 0.5 * sigma * s), period * period * s * s * (0.5 * f + sigma * s / 6.0)
    left, j1, j2 = u0, 0.0, 0.0
    while True:
        length = min(end, target) - left
        j2 += length * (j1 + length * (0.5 * f + sigma * length / 6.0))
        j1 += length * (f + 0.5 * sigma * length)
        if target <= end:
            return period * j1, period * period * j2
        k += 1
        if k >= n - 1:  # the next period
            k, target = 0, target - 1.0
        left, f, sigma, end = field[knots + k], field[values + k], field[slopes + k], field[knots + k + 1]
