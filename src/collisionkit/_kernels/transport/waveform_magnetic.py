"""Exact free flight in a periodic electric field given as samples, with a static B at any angle.

The field is that of :mod:`.waveform`, E(t) = E0 f(t / T) with f piecewise
linear, now with ``Omega = (q/m) B``. The equation of motion dv/dt = g + a
f(t/T) + v x Omega is linear, so a flight is the static flight of
:func:`.flight.flown_velocity` (the initial velocity, gravity g and B) plus
the response from rest to ``a f``. With b = Omega/|Omega| (W = |Omega|):

* along b, ``a_par = a . b`` is integrated as without B: ``a_par T J1`` and
  ``a_par T^2 J2`` (:func:`.waveform.waveform_integrals`);
* across b, the part of size A along e1 (e2 = b x e1) drives zeta = w . e1
  + i w . e2, which obeys ``d zeta/dt = -i W zeta + A f``.

On a piece where f = f_k + sigma' s (s the time from the piece's start),
from rest, after d (``phi_j`` the phi functions of exponential
integrators, ``phi_j(z) = integral_0^1 e^{(1 - r) z} r^{j-1}/(j-1)! dr``,
z = -i W d: :func:`phi_functions`):

* ``zeta(d) = d (f_k phi1 + sigma' d phi2)``, and its time integral
  ``Z(d) = d^2 (f_k phi2 + sigma' d phi3)``;

a state zeta_k at the piece's start adds ``e^z zeta_k`` and ``d phi1
zeta_k``. Chained from rest at the period's start, they give the response
``R(t)`` and its integral ``P(t)`` at every knot (tabulated in the record);
between knots, the same formulas from the last knot. Over whole periods
(R, P) -> (q R + R(T), P + c R + P(T)), ``q = e^{-i W T}``, ``c = T
phi1(-i W T)``: m periods are that affine map to the power m, by repeated
squaring. A flight from t0 (t0' = t0 mod T) to t0' + tau then gets, from
rest, ``zeta = R(t0' + tau) - e^{-i W tau} R(t0')`` and ``Z = P(t0' + tau) -
P(t0') - R(t0') tau phi1(-i W tau)`` (the responses from the period's start
minus that of the state they had at t0'); a flight inside one piece takes
the piece's formulas directly (no difference, no cancellation). The
differences carry a rounding error of about 1e-16 of max |R| (at most
about min(T, 2/W) max|f|), as the antiderivatives without B do.

The record is the waveform record (:func:`.waveform.waveform_record`) with
the oscillating record's decomposition along and across b (17: a . b;
18:21 e1; 21:24 e2; 24: A; 26:29 b; :func:`.oscillating.oscillating_field`),
then ``|a . b| max|f|`` (29) and ``A max|f|`` (30); after the waveform's
tables, R and P at the knots (real and imaginary parts, 4 n entries) and
q, c (4 entries); then the periodic solution's tables of the window bound
(:mod:`.waveform_window`, :func:`periodic_tables`: 3 n + 1 entries); then
the trials' tables (:mod:`.waveform_periodic`, :func:`trial_tables`: 5 n +
1 entries, ending where the next tables start); last, with B or without,
the tables that find a phase's piece and G1's extremes over a window
(:func:`.waveform.with_window_tables`, their start in 33). Entry 32 holds
a . b T.
"""

from __future__ import annotations

import math

import numpy as np

from ..._jit import borrowing_kernel, kernel
from .flight import flown_velocity
from .oscillating import oscillating_field, sincos
from .waveform import WAVE_START, _piece, piece_integrals, waveform_integrals, waveform_record, with_window_tables

# below this |1 - q| the periodic solution is not tabulated (cyclotron resonance): the window bound then grows with
# the flight (:mod:`.waveform_window`)
RESONANCE = 1e-9
# below this |x| the phi functions come from the series of phi3 (17 terms: truncation below 1e-17)
PHI_SERIES = 1.0
# the trials take the periodic solution (:func:`trial_tables`) if |1 - q| is at least PERIODIC_GAP (away from
# cyclotron resonance, where the periodic solution grows as 1/|1 - q| and its rounding with it) and the pieces'
# particular solutions are at most PERIODIC_LOSS times its size
PERIODIC_GAP = 0.05
PERIODIC_LOSS = 16.0


@kernel
def phi_functions(x):
    """``(e^{ix}, phi1(ix), phi2(ix), phi3(ix))`` for real x: ``phi1 = (e^z - 1)/z``, ``phi2 = (phi1 - 1)/z``,
    ``phi3 = (phi2 - 1/2)/z`` (z = ix; 1, 1/2, 1/6 at 0).

    For |x| < ``PHI_SERIES`` phi3 from its series sum_n (ix)^n/(n + 3)! (to n = 16, by Horner's rule),
    then phi2, phi1 and e^z upwards (``phi_{j-1} = 1/(j-1)! + z phi_j``:
    no cancellation); above, the recurrence downwards from e^z, which loses
    at most a few ulps there.

    Examples
    --------
    >>> import cmath
    >>> from collisionkit._kernels.transport.waveform_magnetic import phi_functions
    >>> e, p1, p2, p3 = phi_functions(2.0)
    >>> abs(p3 - (cmath.exp(2j) - 1 - 2j - (2j) ** 2 / 2) / (2j) ** 3) < 1e-15, phi_functions(0.0)[3] == 1 / 6
    (True, True)
    """
    z = complex(0.0, x)
    if abs(x) < PHI_SERIES:
        x2 = x * x  # the even terms are the real part, the odd ones the imaginary part (Horner in x^2)
        real = 1.0 / 6.0 - x2 * (1.0 / 120.0 - x2 * (1.0 / 5040.0 - x2 * (1.0 / 362880.0 - x2 * (
            1.0 / 39916800.0 - x2 * (1.0 / 6227020800.0 - x2 * (1.0 / 1307674368000.0 - x2 * (
                1.0 / 355687428096000.0 - x2 / 121645100408832000.0)))))))
        imag = x * (1.0 / 24.0 - x2 * (1.0 / 720.0 - x2 * (1.0 / 40320.0 - x2 * (1.0 / 3628800.0 - x2 * (
            1.0 / 479001600.0 - x2 * (1.0 / 87178291200.0 - x2 * (1.0 / 20922789888000.0
                                                                  - x2 / 6402373705728000.0)))))))
        p3 = complex(real, imag)
        p2 = 0.5 + z * p3
        p1 = 1.0 + z * p2
        return 1.0 + z * p1, p1, p2, p3
    s, c = sincos(x)
    inverse = 1.0 / x  # w / z = (Im w - i Re w) / x: one real division for the three (numba's complex one is dear)
    p1 = complex(s * inverse, (1.0 - c) * inverse)
    p2 = complex(p1.imag * inverse, (1.0 - p1.real) * inverse)
    return complex(c, s), p1, p2, complex(p2.imag * inverse, (0.5 - p2.real) * inverse)


@kernel
def _response_tables(knots, values, slopes, period, w):
    """R and P (module docstring, per unit A) at the knots, and the period map's q and c."""
    n = knots.shape[0]
    big_r = np.zeros(n, np.complex128)
    big_p = np.zeros(n, np.complex128)
    for k in range(n - 1):
        length = (knots[k + 1] - knots[k]) * period
        e, p1, p2, p3 = phi_functions(-w * length)
        f_k, rise = values[k], slopes[k] / period * length  # f's change over the piece
        big_r[k + 1] = e * big_r[k] + length * (f_k * p1 + rise * p2)
        big_p[k + 1] = big_p[k] + big_r[k] * length * p1 + length * length * (f_k * p2 + rise * p3)
    q, c, _, _ = phi_functions(-w * period)
    return big_r, big_p, q, period * c


def periodic_tables(knots, values, slopes, period, w, big_r, q):
    """The periodic solution's tables (module docstring of :mod:`.waveform_window`): P at the knots, the pieces'
    bounds of |P|, their largest, from the knots, f and its slopes, the period, W, R at the knots and q = e^{-i W
    T}.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.waveform_magnetic import periodic_tables
    >>> w = 1.0  # f = 1: P = 1 / (i W) = -i at every time
    >>> r = np.array([0.0, (1.0 - np.exp(-2j)) / 1j])
    >>> tables = periodic_tables(np.array([0.0, 1.0]), np.array([1.0, 1.0]), np.zeros(2), 2.0, w, r, np.exp(-2j))
    >>> [round(float(value), 12) for value in tables]  # Re P, Im P at both knots, the bound (1 + 1 + 2) / 2, top
    [0.0, 0.0, -1.0, -1.0, 2.0, 0.0, 2.0]
    """
    n = knots.size
    gap = 1.0 - q
    pieces = np.zeros(n)
    if abs(gap) < RESONANCE:  # no periodic solution: P = 0 and no bound of it
        return np.concatenate([np.zeros(2 * n), np.full(n, math.inf), [math.inf]])
    start = big_r[-1] / gap
    big_p = big_r + np.exp(-1j * w * knots * period) * start
    size = np.abs(big_p)
    for k in range(n - 1):
        length = knots[k + 1] - knots[k]
        f_a, f_b = values[k], values[k] + slopes[k] * length
        if f_a * f_b >= 0.0:
            integral = 0.5 * length * (abs(f_a) + abs(f_b))
        else:  # f changes sign inside the piece: two triangles
            integral = 0.5 * length * (f_a * f_a + f_b * f_b) / (abs(f_a) + abs(f_b))
        pieces[k] = 0.5 * (size[k] + size[k + 1] + integral * period)
    return np.concatenate([big_p.real, big_p.imag, pieces, [pieces[:-1].max() if n > 1 else 0.0]])


def trial_tables(knots, values, slopes, period, w, periodic, q, largest):
    """The tables of the trials' flights from the periodic solution (:mod:`.waveform_periodic`), per unit A: a flag
    (1.0 if they may be used), then per piece k (padded to n): the gyration ``K_k = P_k - L_k(t_k)`` about the
    piece's particular solution (real and imaginary parts), the turn ``e^{i W (t_{k+1} - t_k)}`` over the piece
    (real and imaginary parts) and ``sigma_k / W^2``.

    On piece k, where f = f_k + sigma_k (t - t_k), ``L_k(t) = -i f(t)/W +
    sigma_k/W^2`` solves dL/dt = -i W L + f, so the periodic solution there
    is ``P(t) = L_k(t) + e^{-i W (t - t_k)} K_k``. The flag is 0 near
    cyclotron resonance (``|1 - q| < PERIODIC_GAP``) or where L and K are
    more than ``PERIODIC_LOSS`` times the periodic solution's size (slopes
    steep beside W: their difference would lose that many ulps), and the
    trials then take the phi functions (:func:`piece_response`).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.waveform_magnetic import trial_tables
    >>> tables = trial_tables(np.array([0.0, 1.0]), np.array([1.0, 1.0]), np.zeros(2), 2.0, 1.0,
    ...                       np.array([-1j, -1j]), np.exp(-2j), 1.0)  # f = 1: P = L = -i, K = 0
    >>> [round(float(value), 12) + 0.0 for value in tables]  # flag, Re K, Im K, Re turn, Im turn, sigma/W^2
    [1.0, 0.0, 0.0, 0.0, 0.0, -0.416146836547, 1.0, 0.909297426826, 0.0, 0.0, 0.0]
    """
    n = knots.size
    sigma = slopes / period
    start = -1j * values / w + sigma / w**2  # L_k at the piece's start
    gyration = periodic - start
    turns = np.exp(1j * w * np.append(np.diff(knots) * period, 0.0))
    size = float(max(np.abs(start[:-1]).max(), np.abs(gyration[:-1]).max())) if n > 1 else 0.0
    reference = max(float(np.abs(periodic).max()), largest * min(period, 1.0 / w))
    usable = abs(1.0 - q) >= PERIODIC_GAP and math.isfinite(size) and size <= PERIODIC_LOSS * reference
    return np.concatenate([[1.0 if usable else 0.0], gyration.real, gyration.imag, turns.real, turns.imag,
                           sigma / w**2])


def shaped_field_record(static_field, amplitude, period, knots, values):
    """The flight record of a waveform (:func:`.waveform.waveform_record`) in the static field ``static_field``,
    with the entries and tables of the module docstring if it has a magnetic field.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform_magnetic import shaped_field_record
    >>> square = np.array([0.0, 0.5, 0.5, 1.0]), np.array([1.0, 1.0, -1.0, -1.0])
    >>> record = shaped_field_record(derived_field(np.zeros(3), np.array([0.0, 1.0, 0.0])), np.array([0.0, 0.0, 2.0]),
    ...                              1.0, *square)
    >>> int(record[33]) - (34 + 2 + 5 * 4), float(record[24]), float(record[30])  # 12 n + 6 more; A = 2, A max|f| = 2
    (54, 2.0, 2.0)
    """
    record = waveform_record(static_field, amplitude, period, knots, values)
    w = float(static_field[12])
    if w == 0.0:
        return with_window_tables(record)
    largest = record[25] / float(np.linalg.norm(amplitude))
    decomposed = oscillating_field(np.asarray(static_field, dtype=float), np.asarray(amplitude, dtype=float), 1.0)
    record[17:25] = decomposed[17:25]
    record[26:29] = decomposed[26:29]
    record[29] = abs(decomposed[17]) * largest
    record[30] = decomposed[24] * largest
    record[32] = decomposed[17] * period  # the window bound's parallel scale: a . b T
    n = len(knots)
    big_r, big_p, q, c = _response_tables(np.asarray(knots, dtype=float), np.asarray(values, dtype=float),
                                          record[WAVE_START + 2 + 2 * n:WAVE_START + 2 + 3 * n].copy(), period, w)
    slopes = record[WAVE_START + 2 + 2 * n:WAVE_START + 2 + 3 * n].copy()
    periodic = periodic_tables(np.asarray(knots, dtype=float), np.asarray(values, dtype=float), slopes, period, w,
                               big_r, q)
    trials = trial_tables(np.asarray(knots, dtype=float), np.asarray(values, dtype=float), slopes, period, w,
                          periodic[:n] + 1j * periodic[n:2 * n], q, largest)
    tables = np.concatenate([big_r.real, big_r.imag, big_p.real, big_p.imag, [q.real, q.imag, c.real, c.imag],
                             periodic, trials])
    return with_window_tables(np.concatenate([record, tables]))


@borrowing_kernel
def _within_period(time, field, n, w):
    """``(R, P)`` at ``time`` in [0, T] from the knot before it (module docstring)."""
    period = field[WAVE_START]
    k = _piece(min(time / period, 1.0), field, n)
    knots, values, slopes = WAVE_START + 2, WAVE_START + 2 + n, WAVE_START + 2 + 2 * n
    tables = WAVE_START + 2 + 5 * n
    r_k = complex(field[tables + k], field[tables + n + k])
    p_k = complex(field[tables + 2 * n + k], field[tables + 3 * n + k])
    d = max(time - field[knots + k] * period, 0.0)
    e, p1, p2, p3 = phi_functions(-w * d)
    f_k, rise = field[values + k], field[slopes + k] / period * d
    return e * r_k + d * (f_k * p1 + rise * p2), p_k + r_k * d * p1 + d * d * (f_k * p2 + rise * p3)


@borrowing_kernel
def _responses_at(time, field, n, w):
    """``(R, P)`` at any ``time`` >= 0 from the period's start: m whole periods by the affine map's powers."""
    period = field[WAVE_START]
    m = math.floor(time / period)
    rest = time - m * period
    if rest >= period:  # rounding of a time just below a whole period
        m, rest = m + 1.0, 0.0
    if m == 0.0:
        return _within_period(rest, field, n, w)
    tables = WAVE_START + 2 + 5 * n
    end = tables + 4 * n
    # the map over one period: (R, P) -> (q R + a, P + c R + b)
    q, c = complex(field[end], field[end + 1]), complex(field[end + 2], field[end + 3])
    a = complex(field[tables + n - 1], field[tables + 2 * n - 1])
    b = complex(field[tables + 3 * n - 1], field[tables + 4 * n - 1])
    big_r, big_p = 0.0j, 0.0j  # from rest: the powers applied to (0, 0)
    power = int(m)
    while power > 0:
        if power & 1:
            big_r, big_p = q * big_r + a, big_p + c * big_r + b
        # the map composed with itself
        q, c, a, b = q * q, c + c * q, q * a + a, b + c * a + b
        power >>= 1
    r_rest, p_rest = _within_period(rest, field, n, w)
    e, p1, _, _ = phi_functions(-w * rest)
    return e * big_r + r_rest, big_p + big_r * rest * p1 + p_rest


@borrowing_kernel
def magnetic_response(t0, tau, field):
    """``(zeta, Z)``: the perpendicular velocity (as e1 + i e2 components) and displacement gained from rest in a
    flight of ``tau`` from time ``t0``, per unit A (module docstring).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform_magnetic import magnetic_response, shaped_field_record
    >>> record = shaped_field_record(derived_field(np.zeros(3), np.array([0.0, 1.0, 0.0])), np.array([0.0, 0.0, 1.0]),
    ...                              2.0, np.array([0.0, 1.0]), np.array([1.0, 1.0]))  # a constant field, W = 1
    >>> zeta, _ = magnetic_response(0.3, np.pi, record)  # (1 - e^{-i pi}) / i = -2i
    >>> round(zeta.real, 12), round(zeta.imag, 12)
    (0.0, -2.0)
    """
    period = field[WAVE_START]
    n = int(field[WAVE_START + 1])
    w = field[12]
    phase = t0 / period
    u0 = phase - math.floor(phase)
    if u0 >= 1.0:
        u0 = 0.0
    k = _piece(u0, field, n)
    knots, values, slopes = WAVE_START + 2, WAVE_START + 2 + n, WAVE_START + 2 + 2 * n
    start = u0 * period
    e, p1, p2, p3 = phi_functions(-w * tau)
    if start + tau <= field[knots + k + 1] * period:  # within the piece
        sigma = field[slopes + k] / period
        f0 = field[values + k] + field[slopes + k] * (u0 - field[knots + k])
        return tau * (f0 * p1 + sigma * tau * p2), tau * tau * (f0 * p2 + sigma * tau * p3)
    r0, q0 = _within_period(start, field, n, w)
    r1, q1 = _responses_at(start + tau, field, n, w)
    return r1 - e * r0, q1 - q0 - r0 * tau * p1


@borrowing_kernel
def piece_response(u0, k, tau, field):
    """``(zeta, Z)`` of :func:`magnetic_response` for a flight from the phase ``u0`` in [0, 1), which piece ``k``
    holds: the pieces' formulas chained piece by piece from rest (no search, no difference of responses); a
    flight of a period or more takes :func:`magnetic_response`.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform_magnetic import piece_response, shaped_field_record
    >>> record = shaped_field_record(derived_field(np.zeros(3), np.array([0.0, 1.0, 0.0])), np.array([0.0, 0.0, 1.0]),
    ...                              8.0, np.array([0.0, 0.5, 1.0]), np.array([1.0, 1.0, 1.0]))  # constant, W = 1
    >>> zeta, _ = piece_response(0.25, 0, np.pi, record)  # across the knot at 4: (1 - e^{-i pi}) / i = -2i
    >>> round(zeta.real, 12), round(zeta.imag, 12)
    (0.0, -2.0)
    """
    period = field[WAVE_START]
    if tau >= period:
        return magnetic_response(u0 * period, tau, field)
    n = int(field[WAVE_START + 1])
    w = field[12]
    knots, values, slopes = WAVE_START + 2, WAVE_START + 2 + n, WAVE_START + 2 + 2 * n
    rate = field[slopes + k] / period  # f's slope in time
    f = field[values + k] + field[slopes + k] * (u0 - field[knots + k])
    now, end = u0 * period, field[knots + k + 1] * period
    target = now + tau
    if target <= end:  # within the piece
        _, p1, p2, p3 = phi_functions(-w * tau)
        return tau * (f * p1 + rate * tau * p2), tau * tau * (f * p2 + rate * tau * p3)
    zeta, big_z = 0.0j, 0.0j
    while True:
        d = min(end, target) - now
        e, p1, p2, p3 = phi_functions(-w * d)
        big_z = big_z + zeta * (d * p1) + d * d * (f * p2 + rate * d * p3)
        zeta = e * zeta + d * (f * p1 + rate * d * p2)
        if target <= end:
            return zeta, big_z
        k += 1
        if k >= n - 1:  # the next period
            k, target = 0, target - period
        now, end = field[knots + k] * period, field[knots + k + 1] * period
        f, rate = field[values + k], field[slopes + k] / period


@borrowing_kernel
def shaped_flight(vx, vy, vz, u0, k, tau, field):
    """``(vx', vy', vz', dx, dy, dz)``: :func:`shaped_velocity` and :func:`shaped_displacement` together, for a
    flight from the phase ``u0`` in [0, 1) (piece ``k``) of the field: from :func:`.waveform.piece_integrals`
    and :func:`piece_response` (the swarm's trials: a real collision's displacement comes with its velocity).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform_magnetic import shaped_field_record, shaped_flight
    >>> record = shaped_field_record(derived_field(np.zeros(3), np.array([0.0, 1.0, 0.0])), np.array([0.0, 0.0, 1.0]),
    ...                              20.0, np.array([0.0, 1.0]), np.array([1.0, 1.0]))  # E along z, B along y
    >>> [round(value, 12) + 0.0 for value in shaped_flight(0.0, 0.0, 0.0, 0.0, 0, 2.0 * np.pi, record)]  # one turn
    [0.0, 0.0, 0.0, -6.28318530718, 0.0, 0.0]
    """
    j1, j2 = piece_integrals(u0, k, tau, field)
    if field[12] == 0.0:
        return (vx + field[0] * tau + field[14] * j1, vy + field[1] * tau + field[15] * j1,
                vz + field[2] * tau + field[16] * j1, field[14] * j2, field[15] * j2, field[16] * j2)
    ox, oy, oz = flown_velocity(vx, vy, vz, tau, field)
    along, moved = field[17] * j1, field[17] * j2
    ox, oy, oz = ox + along * field[26], oy + along * field[27], oz + along * field[28]
    dx, dy, dz = moved * field[26], moved * field[27], moved * field[28]
    if field[24] > 0.0:
        zeta, big_z = piece_response(u0, k, tau, field)
        zeta, big_z = zeta * field[24], big_z * field[24]
        ox += zeta.real * field[18] + zeta.imag * field[21]
        oy += zeta.real * field[19] + zeta.imag * field[22]
        oz += zeta.real * field[20] + zeta.imag * field[23]
        dx += big_z.real * field[18] + big_z.imag * field[21]
        dy += big_z.real * field[19] + big_z.imag * field[22]
        dz += big_z.real * field[20] + big_z.imag * field[23]
    return ox, oy, oz, dx, dy, dz


@borrowing_kernel
def shaped_velocity(vx, vy, vz, t0, tau, field):
    """Velocity after an exact flight of ``tau`` from (vx, vy, vz) at time ``t0`` in the waveform (and B), as a
    tuple: the static flight plus the response from rest (module docstring; without B ``v0 + g tau + a T J1``).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform_magnetic import shaped_field_record, shaped_velocity
    >>> record = shaped_field_record(derived_field(np.zeros(3), np.array([0.0, 1.0, 0.0])), np.array([0.0, 0.0, 1.0]),
    ...                              2.0, np.array([0.0, 1.0]), np.array([1.0, 1.0]))  # E along z, B along y
    >>> [round(value, 12) for value in shaped_velocity(0.0, 0.0, 0.0, 0.0, np.pi, record)]  # twice the drift a x Omega
    [-2.0, 0.0, 0.0]
    """
    j1, _ = waveform_integrals(t0, tau, field)
    if field[12] == 0.0:
        return (vx + field[0] * tau + field[14] * j1, vy + field[1] * tau + field[15] * j1,
                vz + field[2] * tau + field[16] * j1)
    ox, oy, oz = flown_velocity(vx, vy, vz, tau, field)
    along = field[17] * j1
    ox, oy, oz = ox + along * field[26], oy + along * field[27], oz + along * field[28]
    if field[24] > 0.0:
        zeta, _ = magnetic_response(t0, tau, field)
        zeta = zeta * field[24]
        ox += zeta.real * field[18] + zeta.imag * field[21]
        oy += zeta.real * field[19] + zeta.imag * field[22]
        oz += zeta.real * field[20] + zeta.imag * field[23]
    return ox, oy, oz


@borrowing_kernel
def shaped_displacement(t0, tau, field):
    """Displacement from rest in a flight of ``tau`` from ``t0`` under the waveform's force, as a tuple (to add
    to the static flight's :func:`.flight.flown_position`): ``a T^2 J2`` without B, the module docstring's with.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform_magnetic import shaped_displacement, shaped_field_record
    >>> record = shaped_field_record(derived_field(np.zeros(3), np.array([0.0, 1.0, 0.0])), np.array([0.0, 0.0, 1.0]),
    ...                              2.0, np.array([0.0, 1.0]), np.array([1.0, 1.0]))
    >>> round(shaped_displacement(0.0, 2.0 * np.pi, record)[0], 12)  # a whole gyration: the drift a x Omega / W^2
    -6.28318530718
    """
    _, moved = waveform_integrals(t0, tau, field)
    if field[12] == 0.0:
        return field[14] * moved, field[15] * moved, field[16] * moved
    along = field[17] * moved
    dx, dy, dz = along * field[26], along * field[27], along * field[28]
    if field[24] > 0.0:
        _, z = magnetic_response(t0, tau, field)
        z = z * field[24]
        dx += z.real * field[18] + z.imag * field[21]
        dy += z.real * field[19] + z.imag * field[22]
        dz += z.real * field[20] + z.imag * field[23]
    return dx, dy, dz


@borrowing_kernel
def shaped_window(vx, vy, vz, t0, start, h, field, accel_mag):
    """An upper bound of the speed over the window [start, start + h] of a flight from (vx, vy, vz) at ``t0``.

    From the exact velocity at the window's start: ``|v| + (|g| + |a|
    max|f|) h`` (``accel_mag``; the magnetic force does no work), and
    without static acceleration the smaller ``sqrt((|v . p| + |a . p|
    max|f| h)^2 + (|w| + A max|f| h)^2)``, p the direction of a (without B:
    then A = 0) or b, w the part of v across p (d|w|/dt <= A |f|: the
    gyration keeps |w|). Padded by 1e-10.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform_magnetic import shaped_field_record, shaped_window
    >>> record = shaped_field_record(derived_field(np.zeros(3), np.array([0.0, 1.0, 0.0])), np.array([0.0, 0.0, 1.0]),
    ...                              1.0, np.array([0.0, 1.0]), np.array([-1.0, 1.0]))
    >>> round(shaped_window(0.0, 3.0, 0.0, 0.0, 0.0, 4.0, record, 1.0), 6)  # v along B: sqrt(3^2 + 4^2)
    5.0
    """
    if start > 0.0:
        vx, vy, vz = shaped_velocity(vx, vy, vz, t0, start, field)
    speed = math.sqrt(vx * vx + vy * vy + vz * vz)
    bound = speed + accel_mag * h
    if field[0] == 0.0 and field[1] == 0.0 and field[2] == 0.0:
        px, py, pz = field[26], field[27], field[28]
        v_par = vx * px + vy * py + vz * pz
        wx, wy, wz = vx - v_par * px, vy - v_par * py, vz - v_par * pz
        if field[12] == 0.0:
            along, across = abs(v_par) + field[25] * h, math.sqrt(wx * wx + wy * wy + wz * wz)
        else:
            along, across = abs(v_par) + field[29] * h, math.sqrt(wx * wx + wy * wy + wz * wz) + field[30] * h
        bound = min(bound, math.sqrt(along * along + across * across))
    return bound * (1.0 + 1e-10)
