"""The speed bound of a flight window in an oscillating field E0 cos(omega t) with a static B at any angle.

The trial frequency of a window is the rate bound at the largest speed the
particle can reach in it (:mod:`.flight`). Here the motion is that of
:mod:`.oscillating`: along the direction p of the record (b, or without B
the field's direction) ``v . p = v_par(t1) + (a_par/omega)(sin theta - sin
theta1)`` (theta = omega t; with no static acceleration), exact and cheap
to bound over a window; across p, the part zeta = w . e1 + i w . e2 obeys
d zeta/dt = -i |Omega| zeta + A cos(omega t), whose solution is a gyration
of fixed radius about the particular solution ``P(t) = (A/2)(e^{i omega
t}/(i(|Omega| + omega)) + e^{-i omega t}/(i(|Omega| - omega)))``: so
``|zeta(t)| <= |zeta(t0) - P(t0)| + max |P|`` over the whole flight (off
cyclotron resonance), and always ``|zeta(t)| <= |zeta(t0)| + A (t - t0)``.
Without B, A = 0 and |zeta| is constant.

Window by window the gyration is followed instead of bounded: with D =
zeta(t0) - P(t0), ``zeta(t) e^{i theta} = D e^{i theta0} e^{-i (|Omega| -
omega) s} + (A/2i) beta + (A/2i) alpha e^{2 i theta}`` (s = t - t0, alpha =
1/(|Omega| + omega), beta = 1/(|Omega| - omega)). The first term turns
slowly near resonance (where beta is large) and the second is fixed, so
``|zeta| <= |X(s) + Y| + (A/2)|alpha|`` with X the turning term and Y =
(A/2i) beta, and the largest |X + Y| over a window is that of its ends,
or |D| + |Y| if X lines up with Y inside it: the bound R above, reached
only where the two line up. X is carried as ``U = X conj(Y)/|Y|`` (Y along
the positive real axis), taken at each window's end from its value at the
flight's start (no error builds up over the windows).

:func:`flight_envelope_ac` takes those constants once per flight and
:func:`parallel_window` bounds each window from the parallel velocity and
the phase at its start alone (one sine and cosine, of omega h / 2): the
windows chain the parallel velocity and the phase, not the whole state;
:func:`stepped_window` takes those sines from its caller (the swarm's
windows of a flight are all of one length: one sine a flight).
With a static acceleration (gravity) :func:`oscillating_window` bounds a
window from the exact state at its start.
"""

from __future__ import annotations

import math

from ..._jit import inline_kernel, kernel
from .oscillating import oscillating_flown_velocity, sincos


@inline_kernel
def _gyration_offset(wx, wy, wz, c1, s1, field):
    """D = zeta - P at phase (c1, s1) of the perpendicular velocity (wx, wy, wz) (module docstring)."""
    rotor = complex(c1, s1)
    z = rotor * field[31] + rotor.conjugate() * field[32]
    p = 0.5 * field[24] * complex(z.imag, -z.real)  # (A/2) z / i
    zeta = complex(wx * field[18] + wy * field[19] + wz * field[20], wx * field[21] + wy * field[22] + wz * field[23])
    return zeta - p


@inline_kernel
def _gyration_radius(wx, wy, wz, c1, s1, field):
    """|zeta - P| at phase (c1, s1) of the perpendicular velocity (wx, wy, wz) (module docstring)."""
    d = _gyration_offset(wx, wy, wz, c1, s1, field)
    return math.sqrt(d.real * d.real + d.imag * d.imag)  # not abs(): the library hypot took 5 % of a run (perf)


@inline_kernel
def flight_envelope_ac(vx, vy, vz, c0, s0, field):
    """The constants of a flight's speed bound without static acceleration: ``(v . p, R, |zeta(t0)|, U0)`` with R
    the bound of |zeta| over the flight (module docstring; inf at cyclotron resonance, |zeta(t0)| if A = 0) and
    U0 the turning term at the flight's start, ``i sign(beta) D e^{i theta0}`` (0 at resonance or if A = 0).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.oscillating import oscillating_field
    >>> from collisionkit._kernels.transport.ac_window import flight_envelope_ac
    >>> record = oscillating_field(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 2.0]), 1.0)
    >>> [complex(value) for value in flight_envelope_ac(3.0, 0.0, 4.0, 1.0, 0.0, record)]  # no B: |zeta| stays 3
    [(4+0j), (3+0j), (3+0j), 0j]
    """
    px, py, pz = field[26], field[27], field[28]
    v_par = vx * px + vy * py + vz * pz
    wx, wy, wz = vx - v_par * px, vy - v_par * py, vz - v_par * pz
    w_speed = math.sqrt(wx * wx + wy * wy + wz * wz)
    if field[24] == 0.0:
        return v_par, w_speed, w_speed, 0.0j
    if field[12] == field[13]:
        return v_par, math.inf, w_speed, 0.0j
    d = _gyration_offset(wx, wy, wz, c0, s0, field)
    turning = d * complex(c0, s0) * complex(0.0, math.copysign(1.0, field[32]))
    return v_par, math.sqrt(d.real * d.real + d.imag * d.imag) + field[33], w_speed, turning


@inline_kernel
def _tracked_perpendicular(turning, first, reach, h, field):
    """The largest |X + Y| + (A/2)|alpha| over the window [reach - h, reach] of the flight (module docstring),
    padded by 1e-14 of the sizes it adds (the rounding of D and of the ends), and U at the window's end:
    ``turning`` is U0, ``first`` U at the window's start."""
    delta = field[12] - field[13]
    y = 0.5 * field[24] * abs(field[32])
    size = math.sqrt(turning.real * turning.real + turning.imag * turning.imag)
    hs, hc = sincos(-0.5 * delta * reach)
    last = turning * complex(1.0 - 2.0 * hs * hs, 2.0 * hs * hc)  # U0 e^{-i delta reach}
    turn = delta * h  # U turns by -delta h: clockwise for delta > 0
    if abs(turn) >= math.pi or (turn >= 0.0 and first.imag >= 0.0 and last.imag <= 0.0) or (
            turn <= 0.0 and first.imag <= 0.0 and last.imag >= 0.0):
        top = size + y  # X lines up with Y inside the window
    else:
        top = max(math.sqrt((first.real + y) ** 2 + first.imag ** 2), math.sqrt((last.real + y) ** 2 + last.imag ** 2))
    return top + 0.5 * field[24] * field[31] + 1e-14 * (size + y), last


@inline_kernel
def parallel_window(v_par, c1, s1, theta1, h, reach, radius, w_speed, turning, turned, speed0, accel_mag,
                    field):
    """An upper bound of the speed over a window [t1, t1 + h] of a flight without static acceleration, and the
    parallel velocity, phase and turning term U at its end: ``(bound, v_par, cos theta2, sin theta2, U)``.

    ``v_par`` and ``(c1, s1)`` are v . p and the phase (cos, sin of
    ``theta1 = omega t1``) at the window's start, ``reach`` the flight time
    at its end; ``radius``, ``w_speed``, ``turning`` (:func:`flight_envelope_ac`)
    and ``speed0`` the flight's constants, ``turned`` U at the window's start (``turning`` in the first window). The parallel speed's range is
    exact over the window (its ends, and an extremum of the sine inside);
    across, the smallest of R, |zeta(t0)| + A reach and, off resonance, the
    gyration followed over the window (module docstring); with ``|v(t0)| +
    |a| reach`` as a cap (the magnetic force does no work). Padded by 1e-10 of the speeds (and 1e-12
    of the oscillation amplitude a_par/omega) against rounding.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.oscillating import oscillating_field
    >>> from collisionkit._kernels.transport.ac_window import parallel_window
    >>> record = oscillating_field(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 2.0]), 1.0)
    >>> [round(value, 6) for value in parallel_window(0.0, 1.0, 0.0, 0.0, 10.0, 10.0, 0.0, 0.0, 0j, 0j, 0.0, 2.0, record)[:4]]
    [2.0, -1.088042, -0.839072, -0.544021]
    """
    sh, ch = sincos(0.5 * field[13] * h)
    return stepped_window(v_par, c1, s1, theta1, sh, ch, h, reach, radius, w_speed, turning, turned, speed0,
                          accel_mag, field)


@inline_kernel
def stepped_window(v_par, c1, s1, theta1, sh, ch, h, reach, radius, w_speed, turning, turned, speed0, accel_mag,
                   field):
    """:func:`parallel_window` given ``(sin, cos)(omega h / 2)``: the windows of a flight, all of one length,
    take the sines once.

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.oscillating import oscillating_field
    >>> from collisionkit._kernels.transport.ac_window import stepped_window
    >>> record = oscillating_field(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 2.0]), 1.0)
    >>> arguments = (0.0, 1.0, 0.0, 0.0, 10.0, 10.0, 0.0, 0.0, 0j, 0j, 0.0, 2.0, record)  # as parallel_window's
    >>> [round(value, 6) for value in stepped_window(*arguments[:4], math.sin(5.0), math.cos(5.0), *arguments[4:])[:4]]
    [2.0, -1.088042, -0.839072, -0.544021]
    """
    omega = field[13]
    sin_w = 2.0 * sh * ch
    vers = 2.0 * sh * sh  # 1 - cos(omega h)
    c2 = c1 * (1.0 - vers) - s1 * sin_w
    s2 = s1 * (1.0 - vers) + c1 * sin_w
    a_over_omega = field[30]
    v_end = v_par + a_over_omega * (c1 * sin_w - s1 * vers)
    low, high = _sine_range(theta1, theta1 + omega * h, s1, s2, c1, c2)
    extremes = max(abs(v_par + a_over_omega * (low - s1)), abs(v_par + a_over_omega * (high - s1)))
    parallel = max(abs(v_par), abs(v_end), extremes) + abs(a_over_omega) * 1e-12
    perpendicular = min(radius, w_speed + field[24] * reach)
    if field[24] > 0.0 and field[12] != omega:
        tracked, turned = _tracked_perpendicular(turning, turned, reach, h, field)
        perpendicular = min(perpendicular, tracked)
    bound = min(speed0 + accel_mag * reach, math.sqrt(parallel * parallel + perpendicular * perpendicular))
    return bound * (1.0 + 1e-10), v_end, c2, s2, turned


@kernel
def _sine_range(theta1, theta2, s1, s2, c1, c2):
    """The smallest and largest sin(theta) for theta in [theta1, theta2] (theta2 >= theta1; s1, s2 their sines,
    c1, c2 their cosines).

    Over less than pi the sine has at most one extremum inside, a maximum
    where the cosine goes from + to -, a minimum where it goes from - to +:
    the signs of c1 and c2 tell (no floor, no division); over more, the
    first maximum and minimum at or after theta1 are placed on the line.
    """
    low, high = min(s1, s2), max(s1, s2)
    if theta2 - theta1 < math.pi:
        if c1 >= 0.0 and c2 <= 0.0:
            high = 1.0
        if c1 <= 0.0 and c2 >= 0.0:
            low = -1.0
        return low, high
    quarter = 0.5 * math.pi
    # the first maximum (pi/2 + 2 pi n) and minimum (-pi/2 + 2 pi n) at or after theta1
    peak = quarter + 2.0 * math.pi * math.ceil((theta1 - quarter) / (2.0 * math.pi))
    trough = -quarter + 2.0 * math.pi * math.ceil((theta1 + quarter) / (2.0 * math.pi))
    if peak <= theta2:
        high = 1.0
    if trough <= theta2:
        low = -1.0
    return low, high


@inline_kernel
def oscillating_window(vx, vy, vz, c1, s1, theta1, h, field, accel_mag):
    """An upper bound of the speed over [t1, t1 + h] of a particle with velocity (vx, vy, vz) at time t1, and its
    exact state at t1 + h: ``(bound, vx, vy, vz, cos theta2, sin theta2)``.

    ``(c1, s1)`` are cos and sin of ``theta1 = omega t1``; the end state is
    :func:`oscillating_flown_velocity` over h, so a flight's windows chain
    from one to the next. Always ``|v| + integral |a| <= |v| + (|a_s| +
    |a_c|) h`` (``accel_mag``; the magnetic force does no work). Without
    static acceleration the smaller of that and the exact range along b,
    where v . b + a_par (sin theta - sin theta1)/omega over theta = omega t
    in the window (its ends, and an extremum of the sine inside), combined in
    quadrature with a bound of the perpendicular speed: |w(t1)| + A h, or,
    away from resonance, |w(t1) - P(t1)| + max |P| (the particular solution
    P, of size at most (A/2)(1/(Omega+omega) + 1/|Omega-omega|), plus the
    gyration about it). Padded by 1e-10 of the speeds (and 1e-12 of the
    oscillation amplitude a_par/omega) against rounding.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.oscillating import oscillating_field
    >>> from collisionkit._kernels.transport.ac_window import oscillating_window
    >>> record = oscillating_field(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 2.0]), 1.0)
    >>> [round(value, 6) for value in oscillating_window(0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 10.0, record, 2.0)]  # 2 sin(10)
    [2.0, 0.0, 0.0, -1.088042, -0.839072, -0.544021]
    """
    ex, ey, ez, c2, s2 = oscillating_flown_velocity(vx, vy, vz, c1, s1, h, field)
    speed = math.sqrt(vx * vx + vy * vy + vz * vz)
    growth = (speed + accel_mag * h) * (1.0 + 1e-10)
    if field[0] != 0.0 or field[1] != 0.0 or field[2] != 0.0:
        return growth, ex, ey, ez, c2, s2
    omega = field[13]
    px, py, pz = field[26], field[27], field[28]
    v_par = vx * px + vy * py + vz * pz
    low, high = _sine_range(theta1, theta1 + omega * h, s1, s2, c1, c2)
    a_over_omega = field[30]
    ends = max(abs(v_par), abs(ex * px + ey * py + ez * pz))
    extremes = max(abs(v_par + a_over_omega * (low - s1)), abs(v_par + a_over_omega * (high - s1)))
    parallel = max(ends, extremes) + abs(a_over_omega) * 1e-12
    wx, wy, wz = vx - v_par * px, vy - v_par * py, vz - v_par * pz
    w_speed = math.sqrt(wx * wx + wy * wy + wz * wz)
    a_perp = field[24]
    perpendicular = w_speed + a_perp * h
    w = field[12]
    if a_perp > 0.0 and w != omega:
        # the particular solution P(t) = (A/2) (e^{i omega t}/(i(w + omega)) + e^{-i omega t}/(i(w - omega)))
        perpendicular = min(perpendicular, _gyration_radius(wx, wy, wz, c1, s1, field) + field[33])
    bound = min(growth, math.sqrt(parallel * parallel + perpendicular * perpendicular) * (1.0 + 1e-10))
    return bound, ex, ey, ez, c2, s2
