"""The speed bound of a flight window in a periodic waveform (:mod:`.waveform`), with or without a static B.

Without static acceleration the motion of :mod:`.waveform_magnetic` splits
along the record's direction p (b, or without B the unit vector of a) and
across it. Along p, ``v . p = v0 . p + a_p T (G1(u) - G1(u0))`` exactly (a_p
= a . b, or |a| without B; u = t / T the phase, u0 the flight's start, G1
the antiderivative of f): its extremes over a window are those of G1, found
at the window's ends, the knots inside it and the zeros of f inside a piece
(f linear there, so G1 is a parabola with its vertex where f = 0):
:func:`window_extremes`, exact, walks over the pieces (with B, where it
also gathers the pieces' bounds of |P|); :func:`window_range` (without B)
takes the same extremes in a fixed number of steps from tables of the
record (:func:`.waveform.window_tables`: the pieces' extremes in a sparse
table, the piece of a phase from cells). The exact window bound
(:func:`shaped_tight_window`) takes 1/T and a_p T from the record (31,
32): products, no division or root of its own but the bound's. The
swarm's windows take the looser :func:`stepped_shaped_window` (G1 at the
window's ends and the slope bound max|f|: no walk, no tables; measured
0.91 times the waveform's cost per real collision with the exact bound,
although it leaves 0.19 null trials a real collision instead of 0.11);
the exact one is the reference its tests compare it with.

Across p, without B the velocity is constant. With B its complex
components zeta (as in :mod:`.waveform_magnetic`) obey ``d zeta/dt = -i W
zeta + A f(t/T)``, whose periodic solution (per unit A) is ``P(t) = R(t) +
e^{-i W t} P(0)``, ``P(0) = R(T) / (1 - q)`` (R the response from rest at
the period's start, q = e^{-i W T}). Then ``zeta - A P`` only turns, so
``|zeta(t)| <= |D| + A max |P|`` over the window, D = zeta(t0) - A P(t0)
fixed over the flight. On a piece |P| changes at most as fast as |f|
(``d|P|/dt <= |f|``), so over piece k ``|P| <= (|P_k| + |P_{k+1}| +
integral_k |f| dt) / 2`` (the smaller of the bounds from its two ends,
at its largest where they meet): a table of the record, with its largest
value over the period. Near cyclotron resonance (|1 - q| small) P is
large and the bound ``|zeta(t)| <= |zeta(t0)| + A max|f| (t - t0)`` (d|zeta|/dt
<= A |f|) is the smaller one: the window takes the smaller of the two.

The tables follow those of :mod:`.waveform_magnetic` in the record (after
q and c, from :func:`periodic_start` on): P at the knots (real and
imaginary parts, 2 n entries), the pieces' bounds of |P| (n - 1 entries,
padded to n) and their largest (1 entry).
"""

from __future__ import annotations

import math

from ..._jit import borrowing_inline_kernel, borrowing_kernel, inline_kernel
from .waveform import WAVE_START, at, cell_piece
from .waveform_magnetic import phi_functions

@inline_kernel
def periodic_start(n):
    """The record index at which the periodic solution's tables start, for n knots (module docstring).

    Examples
    --------
    >>> from collisionkit._kernels.transport.waveform_window import periodic_start
    >>> periodic_start(4)  # 34 + 2 + 5 n + 4 n + 4
    76
    """
    return WAVE_START + 2 + 9 * n + 4


def window_extremes(u_start, u_end, field, n, table, hint_period, hint):
    """``(min G1, max G1, max_k table[k], period, piece)`` over the phases [u_start, u_end] (0 <= u_start <=
    u_end), k the pieces the window touches (``table`` a record index; 0 for none: the third value is then 0),
    and a hint for the window that starts at u_end. ``(hint_period, hint)``: a period (a whole number) and a
    piece of it at or before u_start's if u_start is in that period (then the walk from it replaces the search),
    else anything: the flight's start (0, its piece), then the previous window's (u_end's period and piece), so
    that a flight's windows walk the pieces once.

    G1 at the window's ends, the knots inside and the vertices of its
    parabolas inside (module docstring). A window of a period or more takes
    the period's extremes, shifted by the whole periods' integrals.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform_magnetic import shaped_field_record
    >>> from collisionkit._kernels.transport.waveform_window import window_extremes
    >>> record = shaped_field_record(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 1.0]), 1.0,
    ...                              np.array([0.0, 1.0]), np.array([1.0, -1.0]))  # f = 1 - 2u: G1 = u - u^2
    >>> [round(value, 12) for value in window_extremes(0.1, 0.8, record, 2, 0, 0.0, 0)]  # min at 0.1, max at vertex
    [0.09, 0.25, 0.0, 0.0, 0]
    """
    knots, values, slopes, g1 = WAVE_START + 2, WAVE_START + 2 + n, WAVE_START + 2 + 2 * n, WAVE_START + 2 + 3 * n
    period_integral = field[g1 + n - 1]
    m = math.floor(u_start)
    r = u_start - m
    if r >= 1.0:
        m, r = m + 1.0, 0.0
    top = 0.0
    if u_end - u_start >= 1.0:  # every piece: the period's extremes in the periods the window meets
        low = high = 0.0
        for k in range(n - 1):
            low, high = min(low, field[g1 + k + 1]), max(high, field[g1 + k + 1])
            f_a, sigma = field[values + k], field[slopes + k]
            if sigma != 0.0:
                d = -f_a / sigma
                if 0.0 < d < field[knots + k + 1] - field[knots + k]:
                    vertex = field[g1 + k] + 0.5 * f_a * d
                    low, high = min(low, vertex), max(high, vertex)
            if table > 0:
                top = max(top, field[table + k])
        shifts = (m * period_integral, math.floor(u_end) * period_integral)
        return low + min(shifts), high + max(shifts), top, hint_period, hint
    if m == hint_period and field[knots + hint] <= r:
        k = hint
        while k < n - 2 and field[knots + k + 1] <= r:
            k += 1
    else:
        k = cell_piece(r, field, n)
    base = m * period_integral
    d = r - field[knots + k]
    low = high = base + field[g1 + k] + d * (field[values + k] + 0.5 * field[slopes + k] * d)
    left = r  # the window's part in period m starts here
    while True:
        f_a, sigma, knot, end = field[values + k], field[slopes + k], field[knots + k], field[knots + k + 1]
        if table > 0:
            top = max(top, field[table + k])
        right = u_end - m
        # the parabola's vertex, if inside the window's part of the piece: where f (linear) changes sign there
        # (the division only then: f crosses zero about twice a period)
        if (f_a + sigma * (left - knot)) * (f_a + sigma * (min(end, right) - knot)) < 0.0:
            d = -f_a / sigma
            vertex = base + field[g1 + k] + 0.5 * f_a * d
            low, high = min(low, vertex), max(high, vertex)
        if right <= end:
            d = right - knot
            value = base + field[g1 + k] + d * (f_a + 0.5 * sigma * d)
            return min(low, value), max(high, value), top, m, k
        value = base + field[g1 + k + 1]
        low, high = min(low, value), max(high, value)
        k += 1
        left = end
        if k >= n - 1:
            k, m, left = 0, m + 1.0, 0.0
            base = m * period_integral


def window_range(u_start, u_end, field, n, hint_period, hint):
    """``(min G1, max G1, period, piece)`` over the phases [u_start, u_end] (0 <= u_start <= u_end), as
    :func:`window_extremes` gives them (with its hint), in a fixed number of steps from the record's window tables
    (:func:`.waveform.window_tables`): no walk over the pieces.

    Below a period the window meets the pieces from that of u_start (k_s:
    the hint's, or from its cell) to that of u_end (k_e, from its cell,
    counted on into the next period if u_end is there: the tables hold two
    periods). On k_s and k_e, the parabola of G1 at the window's end in it
    and at its vertex clamped into the window's part (an end of it if the
    vertex is outside), and G1 at the knot after k_s if the window passes
    it; the pieces between lie wholly inside the window, and their extremes
    come from the sparse table: two entries per extreme. A window of a
    period or more takes the period's extremes, shifted by the whole
    periods' integrals.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform_magnetic import shaped_field_record
    >>> from collisionkit._kernels.transport.waveform_window import window_range
    >>> record = shaped_field_record(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 1.0]), 1.0,
    ...                              np.array([0.0, 0.25, 0.5, 1.0]), np.array([1.0, 0.5, 0.0, -1.0]))
    >>> [round(value, 12) for value in window_range(0.1, 0.8, record, 4, 0.0, 0)]  # f = 1 - 2u, G1 = u - u^2
    [0.09, 0.25, 0.0, 2]
    """
    tables = int(at(field, 33))
    pieces, levels = int(at(field, tables + 1)), int(at(field, tables + 2))
    knots, values, slopes, g1 = WAVE_START + 2, WAVE_START + 2 + n, WAVE_START + 2 + 2 * n, WAVE_START + 2 + 3 * n
    vertices = tables + 5 + 3 * int(at(field, tables))
    logs = vertices + n - 1
    period_integral = at(field, g1 + n - 1)
    m = math.floor(u_start)
    r = u_start - m
    if r >= 1.0:
        m, r = m + 1.0, 0.0
    if u_end - u_start >= 1.0:
        shifts = (m * period_integral, math.floor(u_end) * period_integral)
        return at(field, tables + 3) + min(shifts), at(field, tables + 4) + max(shifts), hint_period, hint
    right = u_end - m  # below r + 1 < 2: in this period or the next
    wrap = right >= 1.0
    rest = right - 1.0 if wrap else right  # right's phase in its period
    if m == hint_period and at(field, knots + hint) <= r:
        first = hint
        while first < n - 2 and at(field, knots + first + 1) <= r:
            first += 1
    else:
        first = cell_piece(r, field, n)
    last = cell_piece(rest, field, n)
    # the first piece, from r to the piece's end or the window's
    knot, f, sigma = at(field, knots + first), at(field, values + first), at(field, slopes + first)
    g = at(field, g1 + first)
    low_end, high_end = r - knot, min(right, at(field, knots + first + 1)) - knot
    d = min(max(at(field, vertices + first), low_end), high_end)
    value = g + low_end * (f + 0.5 * sigma * low_end)
    vertex = g + d * (f + 0.5 * sigma * d)
    end = last + n - 1 if wrap else last  # the last piece among the two periods'
    joint = at(field, g1 + first + 1) if end > first else value  # the first piece's end, if inside the window
    low, high = min(value, vertex, joint), max(value, vertex, joint)
    # the last piece, from its start or r to right (in its own period: G1 shifted by a period's integral there)
    knot, f, sigma = at(field, knots + last), at(field, values + last), at(field, slopes + last)
    g = at(field, g1 + last) + (period_integral if wrap else 0.0)
    low_end, high_end = max(r - 1.0 if wrap else r, knot) - knot, rest - knot
    d = min(max(at(field, vertices + last), low_end), high_end)
    value = g + high_end * (f + 0.5 * sigma * high_end)
    vertex = g + d * (f + 0.5 * sigma * d)
    low, high = min(low, value, vertex), max(high, value, vertex)
    if end - first >= 2:  # the pieces between: two entries of the sparse table
        level = int(at(field, logs + end - first - 1))
        lows = logs + pieces + 1 + level * pieces
        highs = lows + levels * pieces
        other = end - (1 << level)
        low = min(low, at(field, lows + first + 1), at(field, lows + other))
        high = max(high, at(field, highs + first + 1), at(field, highs + other))
    base = m * period_integral
    return base + low, base + high, m + 1.0 if wrap else m, last


# inlined into the window bound (no call per window), and kernels of their own for the tests
_inline_range = borrowing_inline_kernel(window_range)
window_range = borrowing_kernel(window_range)
_inline_extremes = borrowing_inline_kernel(window_extremes)
window_extremes = borrowing_kernel(window_extremes)


@borrowing_kernel
def shaped_flight_constants(vx, vy, vz, t0, field):
    """``(u0, k, G1(u0), v . p, |v across p|, |D|)`` of a flight from (vx, vy, vz) at time ``t0`` (module
    docstring; u0 the phase in [0, 1), k its piece; |D| = |v across p| without B or A = 0).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform_magnetic import shaped_field_record
    >>> from collisionkit._kernels.transport.waveform_window import shaped_flight_constants
    >>> record = shaped_field_record(derived_field(np.zeros(3), np.array([0.0, 1.0, 0.0])), np.array([0.0, 0.0, 1.0]),
    ...                              2.0, np.array([0.0, 1.0]), np.array([1.0, 1.0]))  # f = 1, W = 1: P = -i
    >>> [round(value, 12) for value in shaped_flight_constants(0.0, 0.0, 0.0, 5.0, record)]  # at rest: |D| = 1
    [0.5, 0, 0.5, 0.0, 0.0, 1.0]
    """
    period = field[WAVE_START]
    n = int(field[WAVE_START + 1])
    phase = t0 * field[31]
    u0 = phase - math.floor(phase)
    if u0 >= 1.0:
        u0 = 0.0
    px, py, pz = field[26], field[27], field[28]
    along = vx * px + vy * py + vz * pz
    wx, wy, wz = vx - along * px, vy - along * py, vz - along * pz
    across = math.sqrt(wx * wx + wy * wy + wz * wz)
    offset = across
    w = field[12]
    k = cell_piece(u0, field, n)
    d = u0 - at(field, WAVE_START + 2 + k)
    g0 = at(field, WAVE_START + 2 + 3 * n + k) + d * (at(field, WAVE_START + 2 + n + k)
                                                      + 0.5 * at(field, WAVE_START + 2 + 2 * n + k) * d)
    if w != 0.0 and field[24] > 0.0:
        tables = periodic_start(n)
        d = (u0 - field[WAVE_START + 2 + k]) * period
        e, p1, p2, _ = phi_functions(-w * d)
        rise = field[WAVE_START + 2 + 2 * n + k] / period * d
        start = complex(field[tables + k], field[tables + n + k])
        big_p = e * start + d * (field[WAVE_START + 2 + n + k] * p1 + rise * p2)
        zeta = complex(vx * field[18] + vy * field[19] + vz * field[20], vx * field[21] + vy * field[22]
                       + vz * field[23])
        gap = zeta - field[24] * big_p
        offset = math.sqrt(gap.real * gap.real + gap.imag * gap.imag)
    return u0, k, g0, along, across, offset


@borrowing_kernel
def shaped_tight_window(u0, k0, g0, along, across, offset, start, h, field, hint_period, hint):
    """An upper bound of the speed over the window [start, start + h] of a flight with the constants of
    :func:`shaped_flight_constants`, without static acceleration (module docstring), padded by 1e-10, and the
    hint of :func:`window_extremes` for the flight's next window: ``(bound, period, piece)``. ``(hint_period,
    hint)``: (0, k0) for the flight's first window, then what the previous window returned.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform_magnetic import shaped_field_record
    >>> from collisionkit._kernels.transport.waveform_window import shaped_tight_window
    >>> record = shaped_field_record(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 2.0]), 1.0,
    ...                              np.array([0.0, 1.0]), np.array([1.0, -1.0]))  # v_z = 2 (u - u^2) from rest at 0
    >>> round(shaped_tight_window(0.0, 0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.9, record, 0.0, 0)[0], 9)  # at u = 1/2
    0.5
    """
    inverse = field[31]  # 1/T
    n = int(field[WAVE_START + 1])
    magnetic = field[12] != 0.0 and field[24] > 0.0
    if magnetic:
        low, high, top, end_period, end_piece = _inline_extremes(u0 + start * inverse, u0 + (start + h) * inverse,
                                                                 field, n, periodic_start(n) + 2 * n, hint_period,
                                                                 hint)
    else:  # G1's extremes alone: from the tables, in a fixed number of steps
        top = 0.0
        low, high, end_period, end_piece = _inline_range(u0 + start * inverse, u0 + (start + h) * inverse, field, n,
                                                         hint_period, hint)
    scale = field[32]  # a_p T
    parallel = max(abs(along + scale * (low - g0)), abs(along + scale * (high - g0)))
    if magnetic:
        across = min(offset + field[24] * top, across + field[30] * (start + h))
    return math.sqrt(parallel * parallel + across * across) * (1.0 + 1e-10), end_period, end_piece


@borrowing_kernel
def stepped_shaped_window(u0, g0, along, across, offset, start, h, field, g_start, periods, piece):
    """An upper bound of the speed over the window [start, start + h] of a flight with the constants of
    :func:`shaped_flight_constants` (without static acceleration), from G1 at the window's ends alone: ``(bound,
    G1 at the end, periods, piece)`` for the next window. ``g_start``, ``periods`` and ``piece``: G1 at the
    window's start (u0's G1 for the flight's first window, ``g0``), the whole periods and the piece of a phase at
    or before the start (0 and u0's piece for the first window), as the previous window returned them.

    G1 has slope f, |f| <= max|f|, so over a window of phases [u1, u2] it
    stays within ``(G1(u1) + G1(u2))/2 +- max|f| (u2 - u1)/2`` (each end
    bounds it by a cone; the cones meet there): the velocity along p within
    ``|a_p| max|f| h / 2`` of its value at G1's midpoint, a looser range
    than the exact extremes of :func:`shaped_tight_window` by at most that
    padding (a few per cent of the speed on a window of about one collision
    time), but without a walk over the window's pieces or tables: one piece
    step at most, usually none. Across p, with B, |D| + A max |P| over the
    period (or the growth bound). Padded by 1e-10.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform_magnetic import shaped_field_record
    >>> from collisionkit._kernels.transport.waveform_window import stepped_shaped_window
    >>> record = shaped_field_record(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 2.0]), 1.0,
    ...                              np.array([0.0, 1.0]), np.array([1.0, -1.0]))  # v_z = 2 (u - u^2) from rest at 0
    >>> bound, g_end, periods, piece = stepped_shaped_window(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.5, record, 0.0, 0.0, 0)
    >>> round(bound, 9), round(g_end, 12), periods, piece  # 2 (0 + 1/4)/2 + 2 (1/2)/2 (the exact largest: 1/2)
    (0.75, 0.25, 0.0, 0)
    """
    n = int(field[WAVE_START + 1])
    knots, values, slopes, g1 = WAVE_START + 2, WAVE_START + 2 + n, WAVE_START + 2 + 2 * n, WAVE_START + 2 + 3 * n
    u = u0 + (start + h) * field[31] - periods  # the window's end in the walk's period
    while at(field, knots + piece + 1) <= u:
        piece += 1
        if piece >= n - 1:  # the next period
            piece, periods, u = 0, periods + 1.0, u - 1.0
    d = u - at(field, knots + piece)
    g_end = periods * field[g1 + n - 1] + at(field, g1 + piece) + d * (at(field, values + piece)
                                                                        + 0.5 * at(field, slopes + piece) * d)
    magnetic = field[12] != 0.0 and field[24] > 0.0
    padding = 0.5 * h * (field[29] if field[12] != 0.0 else field[25])  # |a_p| max|f| h / 2
    middle = along + field[32] * (0.5 * (g_start + g_end) - g0)
    parallel = abs(middle) + padding
    if magnetic:
        across = min(offset + field[24] * field[periodic_start(n) + 3 * n], across + field[30] * (start + h))
    return math.sqrt(parallel * parallel + across * across) * (1.0 + 1e-10), g_end, periods, piece
