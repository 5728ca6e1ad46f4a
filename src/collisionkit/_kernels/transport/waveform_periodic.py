"""The trials of a flight in a sampled waveform with a static B, from the periodic solution: one rotation a trial.

The motion is that of :mod:`.waveform_magnetic` without static acceleration:
along b, ``v . b = v0 . b + a_b T (G1(u) - G1(u0))`` (u = t/T the phase,
G1 the antiderivative of f, :mod:`.waveform`); across b, zeta = w . e1 + i
w . e2 obeys ``d zeta/dt = -i W zeta + A f(t/T)``. With P the periodic
solution per unit A (:mod:`.waveform_window`), ``zeta - A P`` only turns,
so a flight from t0 has, after tau,

    zeta(t0 + tau) = A P(t0 + tau) + e^{-i W tau} D,    D = zeta(t0) - A P(t0).

On piece j (f = f_j + sigma_j (t - t_j)), ``P(t) = L_j(t) + e^{-i W (t -
t_j)} K_j`` with the piece's particular solution ``L_j(t) = -i f(t)/W +
sigma_j/W^2`` and ``K_j = P_j - L_j(t_j)`` tabulated
(:func:`.waveform_magnetic.trial_tables`). Writing ``e^{-i W (t - t_j)} =
e^{-i W tau} e^{-i W (t0 - t_j)}``, the second factor (the *turn* of the
piece) is ``e^{-i W (t0 - t_k0)}`` on the flight's first piece (one sine a
flight) and gains the tabulated ``e^{i W (t_{j+1} - t_j)}`` at each knot
the flight passes, so that a trial takes

    zeta = A L_j(t) + e^{-i W tau} (A turn_j K_j + D),

the rotation ``e^{-i W tau}`` from the half-angle sines that the static
gyration takes anyway: no phi function, no sine of its own. The trials of
a flight come in time order, so each walks the pieces on from where the
last one stopped (the piece, the whole periods passed and the turn are
carried).

A real collision's displacement across b follows from the same equation
integrated, ``Z = integral zeta dt = i (zeta(t) - zeta(t0) - A T J1)/W``
(J1 the integral of f over the flight, :func:`.waveform.piece_integrals`);
along b it is ``(v0 . b) tau + a_b T^2 J2``. The division by W costs
digits when W tau is small: the rounding is about 1/(W tau) ulps of the
flight's scale (|v| plus the field's velocity, times tau), and below
``DISPLACEMENT_TURN`` the displacement is the phi functions' (the
gyration's phi1 from the trial's half-angle sines, the response from rest
of :func:`.waveform_magnetic.piece_response`: exact to ulps of itself).

Rounding: the terms carry about 1e-16 of max(|L|, |K|, |P|) A, which
:func:`.waveform_magnetic.trial_tables` keeps within ``PERIODIC_LOSS`` of
the periodic solution's size (otherwise the trials take the phi
functions): a few ulps of the velocity the field gives in a period.
"""

from __future__ import annotations

import math

from ..._jit import borrowing_kernel
from .oscillating import sincos
from .waveform import WAVE_START, at, cell_piece, piece_integrals
from .waveform_magnetic import piece_response

# below this W tau a real collision's displacement comes from the phi functions: the formula divides by W, so its
# rounding is about 1 / (W tau) ulps of (speed scale x tau), at most 4 here (within 64 ulps in the tests); 0.25
# against 0.5: 7 % faster on Reid's ramp at 200 Hx, where W tau < 0.5 in about a third of the flights
DISPLACEMENT_TURN = 0.25


@borrowing_kernel
def trial_table_start(n, field):
    """The record index of the trials' tables' flag (:func:`.waveform_magnetic.trial_tables`, the 5 n + 1 entries
    before the window tables, whose start is entry 33: :func:`.waveform.with_window_tables`), for n knots.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform_magnetic import shaped_field_record
    >>> from collisionkit._kernels.transport.waveform_periodic import trial_table_start
    >>> record = shaped_field_record(derived_field(np.zeros(3), np.array([0.0, 1.0, 0.0])), np.array([0.0, 0.0, 1.0]),
    ...                              2.0, np.array([0.0, 1.0]), np.array([1.0, 1.0]))
    >>> float(record[trial_table_start(2, record)])  # f = 1, W T = 2: the trials may use the periodic solution
    1.0
    """
    return int(field[33]) - (5 * n + 1)


@borrowing_kernel
def periodic_trials(field):
    """Whether the trials of a waveform record may take the periodic solution: a magnetic field with a perpendicular
    amplitude, and the flag of its tables (:func:`.waveform_magnetic.trial_tables`)."""
    if field[12] == 0.0 or field[24] == 0.0:
        return False
    return field[trial_table_start(int(field[WAVE_START + 1]), field)] > 0.0


@borrowing_kernel
def periodic_flight_constants(vx, vy, vz, t0, field):
    """``(u0, k, G1(u0), v . b, |v across b|, |D|, D, turn)`` of a flight from (vx, vy, vz) at time ``t0``
    (module docstring): the constants of :func:`.waveform_window.shaped_flight_constants`, then D = zeta(t0) - A
    P(t0) and the turn ``e^{-i W (t0 - t_k)}`` of the flight's first piece k. One sine and cosine; a flight that
    starts where a trial of the last one ended takes :func:`periodic_chained_constants` instead.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform_magnetic import shaped_field_record
    >>> from collisionkit._kernels.transport.waveform_periodic import periodic_flight_constants
    >>> record = shaped_field_record(derived_field(np.zeros(3), np.array([0.0, 1.0, 0.0])), np.array([0.0, 0.0, 1.0]),
    ...                              2.0, np.array([0.0, 1.0]), np.array([1.0, 1.0]))  # f = 1, W = 1: P = -i
    >>> constants = periodic_flight_constants(0.0, 0.0, 0.0, 5.0, record)  # at rest: D = i, |D| = 1
    >>> [round(value, 12) for value in constants[:6]], round(constants[6].imag, 12)
    ([0.5, 0, 0.5, 0.0, 0.0, 1.0], 1.0)
    """
    n = int(field[WAVE_START + 1])
    phase = t0 * field[31]  # t0 / T
    u0 = phase - math.floor(phase)
    if u0 >= 1.0:
        u0 = 0.0
    k = cell_piece(u0, field, n)
    s, c = sincos(field[12] * (u0 - field[WAVE_START + 2 + k]) * field[WAVE_START])
    return periodic_chained_constants(vx, vy, vz, u0, k, complex(c, -s), 1.0 / field[12], field)


@borrowing_kernel
def periodic_chained_constants(vx, vy, vz, u0, k, turn, inverse_w, field):
    """:func:`periodic_flight_constants` of a flight from phase ``u0`` in [0, 1) of piece ``k`` with the turn
    ``e^{-i W (t0 - t_k)}`` known: where a trial of the last flight became a real collision, its walk's piece, its
    phase and its rotation times its turn (no sine, no search). ``inverse_w`` is 1/W.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform_magnetic import shaped_field_record
    >>> from collisionkit._kernels.transport.waveform_periodic import (
    ...     periodic_chained_constants, periodic_flight_constants)
    >>> record = shaped_field_record(derived_field(np.zeros(3), np.array([0.0, 1.0, 0.0])), np.array([0.0, 0.0, 1.0]),
    ...                              4.0, np.array([0.0, 0.5, 1.0]), np.array([1.0, -1.0, 0.5]))
    >>> direct = periodic_flight_constants(0.3, 0.2, -0.1, 3.0, record)  # t0 = 3: phase 0.75, piece 1
    >>> chained = periodic_chained_constants(0.3, 0.2, -0.1, 0.75, 1, direct[7], 1.0, record)
    >>> chained == direct
    True
    """
    n = int(field[WAVE_START + 1])
    knots, values, slopes, g1 = WAVE_START + 2, WAVE_START + 2 + n, WAVE_START + 2 + 2 * n, WAVE_START + 2 + 3 * n
    d = u0 - field[knots + k]
    slope = field[slopes + k]
    g0 = field[g1 + k] + d * (field[values + k] + 0.5 * slope * d)
    px, py, pz = field[26], field[27], field[28]
    along = vx * px + vy * py + vz * pz
    wx, wy, wz = vx - along * px, vy - along * py, vz - along * pz
    across = math.sqrt(wx * wx + wy * wy + wz * wz)
    tables = trial_table_start(n, field) + 1
    f = field[values + k] + slope * d
    start = complex(field[tables + 4 * n + k], -f * inverse_w) + turn * complex(field[tables + k],
                                                                               field[tables + n + k])
    zeta = complex(vx * field[18] + vy * field[19] + vz * field[20], vx * field[21] + vy * field[22] + vz * field[23])
    gap = zeta - field[24] * start
    return u0, k, g0, along, across, math.sqrt(gap.real * gap.real + gap.imag * gap.imag), gap, turn


@borrowing_kernel
def periodic_velocity(along, g0, gap, u0, elapsed, half_sin, half_cos, piece, periods, turn, inverse_period,
                      inverse_w, field):
    """The velocity after ``elapsed`` of a flight with the constants of :func:`periodic_flight_constants`, given
    ``(sin, cos)(W elapsed / 2)``: ``(vx, vy, vz, zeta, piece, periods, turn)`` with zeta across b and the walk's
    state for the next trial (module docstring). ``(piece, periods, turn)``: the piece a trial of the flight
    reached, the whole periods before it and its turn (``(k, 0, turn)`` of the constants for the first trial);
    ``elapsed`` not before that trial's. ``inverse_period`` and ``inverse_w`` are 1/T and 1/W.

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform_magnetic import shaped_field_record
    >>> from collisionkit._kernels.transport.waveform_periodic import periodic_flight_constants, periodic_velocity
    >>> record = shaped_field_record(derived_field(np.zeros(3), np.array([0.0, 1.0, 0.0])), np.array([0.0, 0.0, 1.0]),
    ...                              20.0, np.array([0.0, 1.0]), np.array([1.0, 1.0]))  # E along z, B along y
    >>> u0, k, g0, along, _, _, gap, turn = periodic_flight_constants(0.0, 0.0, 0.0, 0.0, record)
    >>> tau = math.pi  # half a turn from rest: twice the drift a x Omega / W^2
    >>> velocity = periodic_velocity(along, g0, gap, u0, tau, math.sin(tau / 2), math.cos(tau / 2), k, 0.0, turn,
    ...                              1 / 20.0, 1.0, record)
    >>> [round(value, 12) + 0.0 for value in velocity[:3]]
    [-2.0, 0.0, 0.0]
    """
    n = int(field[WAVE_START + 1])
    knots, values, slopes, g1 = WAVE_START + 2, WAVE_START + 2 + n, WAVE_START + 2 + 2 * n, WAVE_START + 2 + 3 * n
    tables = trial_table_start(n, field) + 1
    u = u0 + elapsed * inverse_period - periods  # the phase in the walk's period
    while at(field, knots + piece + 1) <= u:  # the knots the flight passed since the last trial
        turn = turn * complex(at(field, tables + 2 * n + piece), at(field, tables + 3 * n + piece))
        piece += 1
        if piece >= n - 1:  # the next period
            piece, periods, u = 0, periods + 1.0, u - 1.0
    d = u - at(field, knots + piece)
    slope = at(field, slopes + piece)
    f = at(field, values + piece) + slope * d
    g = periods * field[g1 + n - 1] + at(field, g1 + piece) + d * (at(field, values + piece) + 0.5 * slope * d)
    v_par = along + field[32] * (g - g0)  # a . b T (G1(u) - G1(u0))
    rotation = complex(1.0 - 2.0 * half_sin * half_sin, -2.0 * half_sin * half_cos)  # e^{-i W elapsed}
    amplitude = field[24]
    local = complex(at(field, tables + 4 * n + piece), -f * inverse_w)
    zeta = amplitude * local + rotation * (amplitude * turn * complex(at(field, tables + piece),
                                                                      at(field, tables + n + piece)) + gap)
    return (v_par * field[26] + zeta.real * field[18] + zeta.imag * field[21],
            v_par * field[27] + zeta.real * field[19] + zeta.imag * field[22],
            v_par * field[28] + zeta.real * field[20] + zeta.imag * field[23], zeta, piece, periods, turn)


@borrowing_kernel
def periodic_displacement(vx, vy, vz, zeta, u0, k, elapsed, half_sin, half_cos, inverse_w, field):
    """The displacement of a flight of ``elapsed`` from (vx, vy, vz) at phase ``u0`` (piece ``k``) that ends with
    zeta across b (:func:`periodic_velocity`, given ``(sin, cos)(W elapsed / 2)`` too), as a tuple: ``(v0 . b) tau
    + a_b T^2 J2`` along b and ``i (zeta - zeta0 - A T J1)/W`` across (module docstring); for W tau below
    ``DISPLACEMENT_TURN``, across, the gyration's ``zeta0 tau phi1(-i W tau)`` (phi1 from the half-angle sines:
    ``(2 sin/(W tau)) (cos - i sin)``, no cancellation) and the response from rest of
    :func:`.waveform_magnetic.piece_response` (the phi functions' series: no sine).

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.waveform_magnetic import shaped_field_record
    >>> from collisionkit._kernels.transport.waveform_periodic import periodic_displacement
    >>> record = shaped_field_record(derived_field(np.zeros(3), np.array([0.0, 1.0, 0.0])), np.array([0.0, 0.0, 1.0]),
    ...                              20.0, np.array([0.0, 1.0]), np.array([1.0, 1.0]))  # E along z, B along y
    >>> moved = periodic_displacement(0.0, 0.0, 0.0, 0j, 0.0, 0, 2 * math.pi, 0.0, -1.0, 1.0, record)  # a turn
    >>> [round(value, 12) + 0.0 for value in moved]  # the drift a x Omega / W^2 times 2 pi
    [-6.28318530718, 0.0, 0.0]
    """
    integral, double = piece_integrals(u0, k, elapsed, field)
    along = (vx * field[26] + vy * field[27] + vz * field[28]) * elapsed + field[17] * double
    start = complex(vx * field[18] + vy * field[19] + vz * field[20], vx * field[21] + vy * field[22] + vz * field[23])
    theta = field[12] * elapsed
    if theta < DISPLACEMENT_TURN:
        _, response = piece_response(u0, k, elapsed, field)
        ratio = 2.0 * half_sin / theta if theta > 0.0 else 1.0
        moved = start * complex(ratio * half_cos, -ratio * half_sin) * elapsed + field[24] * response
        across_1, across_2 = moved.real, moved.imag
    else:
        change = zeta - start - field[24] * integral
        across_1, across_2 = -change.imag * inverse_w, change.real * inverse_w  # i change / W
    return (along * field[26] + across_1 * field[18] + across_2 * field[21],
            along * field[27] + across_1 * field[19] + across_2 * field[22],
            along * field[28] + across_1 * field[20] + across_2 * field[23])
