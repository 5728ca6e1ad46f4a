"""Exact free flight in an oscillating electric field E0 cos(omega t) with a static B at any angle.

The equation of motion is dv/dt = a_s + a_c cos(omega t) + v x Omega:
``a_s`` the static acceleration (gravity) and ``Omega = (q/m) B`` of the
static field record (:mod:`.flight`), ``a_c = q E0 / m`` the amplitude of
the oscillating one. It is linear, so the flight is the static flight of
:func:`.flight.flown_velocity` (which carries the initial velocity) plus the
response to the oscillating force from rest, computed here.

With b = Omega/|Omega|, the part of ``a_c`` along b (``a_par``) is
integrated directly; the perpendicular part, of size A along the unit vector
e1 (e2 = b x e1), drives zeta = w . e1 + i w . e2, which obeys
d zeta/dt = -i |Omega| zeta + A cos(omega t). From rest at t0, after tau:

* ``zeta = (A/2) tau sum_k e^{i k t0} e^{-i |Omega| tau} phi1(i (|Omega| + k) tau)``
* ``Z = integral of zeta = (A/2) tau^2 sum_k e^{i k t0} exp[-i |Omega| tau, i k tau, 0]``

with k = +-omega, ``phi1(z) = (e^z - 1)/z`` and ``exp[x, y, 0]`` the second
divided difference of the exponential (:func:`divided_difference`), which
stays finite at cyclotron resonance (|Omega| = omega: the response grows
linearly in time) and at low frequency. Along b (and without B) the same
formulas with |Omega| = 0: ``v = a_par Re(e^{i omega t0} tau phi1(i omega tau))``
and ``z = a_par Re(e^{i omega t0} tau^2 exp[0, i omega tau, 0])``.

The oscillating record (float64, :data:`RECORD_SIZE` entries) extends the
static one (0:13): omega (13); a_c (14:17); a_c . b (17); e1 (18:21); e2
(21:24); A (24); |a_c| (25). Without B, b is taken as the direction of a_c
(all of it is "parallel").
"""

from __future__ import annotations

import math

import numpy as np

from ..._jit import kernel

STATIC_SIZE = 13
RECORD_SIZE = 26
# below this |x - y| the divided difference is summed from its Taylor series about the midpoint (error below
# 1e-17 there); above it the difference quotient loses at most 2e-16 / 1e-3 of |phi1| <= 1
SERIES_GAP = 1e-3


@kernel
def oscillating_field(static_field, amplitude, omega):
    """The oscillating record (module docstring) of a static record and the amplitude ``a_c`` (m/s^2) at ``omega``.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.oscillating import oscillating_field
    >>> record = oscillating_field(derived_field(np.zeros(3), np.array([0.0, 1.0, 0.0])), np.array([0.0, 0.0, 2.0]), 3.0)
    >>> record.shape, float(record[13]), float(record[17]), float(record[24])  # E perpendicular to B: A = |a_c|
    ((26,), 3.0, 0.0, 2.0)
    """
    record = np.zeros(RECORD_SIZE)
    record[:STATIC_SIZE] = static_field
    record[13] = omega
    record[14:17] = amplitude
    size = math.sqrt(amplitude[0] ** 2 + amplitude[1] ** 2 + amplitude[2] ** 2)
    record[25] = size
    if static_field[12] > 0.0:
        b = static_field[3:6]
    elif size > 0.0:
        b = amplitude / size
    else:
        b = np.array([0.0, 0.0, 1.0])
    along = amplitude[0] * b[0] + amplitude[1] * b[1] + amplitude[2] * b[2]
    record[17] = along
    perp = amplitude - along * b
    a_perp = math.sqrt(perp[0] ** 2 + perp[1] ** 2 + perp[2] ** 2)
    if static_field[12] == 0.0 or a_perp <= 1e-12 * size:
        a_perp = 0.0
        # any unit vector perpendicular to b (unused while A = 0)
        perp = np.array([1.0, 0.0, 0.0]) if abs(b[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        perp = perp - (perp[0] * b[0] + perp[1] * b[1] + perp[2] * b[2]) * b
    e1 = perp / math.sqrt(perp[0] ** 2 + perp[1] ** 2 + perp[2] ** 2)
    record[18:21] = e1
    record[21] = b[1] * e1[2] - b[2] * e1[1]
    record[22] = b[2] * e1[0] - b[0] * e1[2]
    record[23] = b[0] * e1[1] - b[1] * e1[0]
    record[24] = a_perp
    return record


@kernel
def phi1(x):
    """``(e^{ix} - 1)/(ix)`` for real x, free of cancellation (1 at x = 0).

    Examples
    --------
    >>> from collisionkit._kernels.transport.oscillating import phi1
    >>> import cmath
    >>> abs(phi1(0.3) - (cmath.exp(0.3j) - 1) / 0.3j) < 1e-15, phi1(0.0)
    (True, (1+0j))
    """
    if x == 0.0:
        return complex(1.0, 0.0)
    half = math.sin(0.5 * x)
    return complex(math.sin(x) / x, 2.0 * half * half / x)


@kernel
def exp_moment(n, x):
    """``integral_0^1 s^n e^{ixs} ds`` for real x and n = 0..3: a series for |x| < 1, else the upward recurrence.

    Examples
    --------
    >>> from collisionkit._kernels.transport.oscillating import exp_moment
    >>> exp_moment(1, 0.0), abs(exp_moment(3, 0.0) - 0.25) < 1e-15
    ((0.5+0j), True)
    """
    if abs(x) < 1.0:
        total = complex(0.0, 0.0)
        term = complex(1.0, 0.0)  # (ix)^k / k!
        for k in range(30):
            total += term / (n + k + 1)
            term = term * complex(0.0, x) / (k + 1)
        return total
    ix = complex(0.0, x)
    e = complex(math.cos(x), math.sin(x))
    value = (e - 1.0) / ix
    for j in range(1, n + 1):
        value = (e - j * value) / ix
    return value


@kernel
def divided_difference(x, y):
    """The second divided difference ``exp[ix, iy, 0]`` of the exponential for real x, y (1/2 at x = y = 0).

    ``(phi1(ix) - phi1(iy)) / (ix - iy)``; for |x - y| < ``SERIES_GAP`` the
    Taylor series of that quotient about the midpoint m, h = (x - y)/2:
    ``J1(m) - J3(m) h^2 / 6`` with ``J_n(m) = integral_0^1 s^n e^{ims} ds``
    (:func:`exp_moment`), the next term being below h^4/120.

    Examples
    --------
    >>> from collisionkit._kernels.transport.oscillating import divided_difference
    >>> divided_difference(0.0, 0.0), abs(divided_difference(2.0, 2.0 + 1e-9) - divided_difference(2.0, 2.0)) < 1e-9
    ((0.5+0j), True)
    """
    d = x - y
    if abs(d) >= SERIES_GAP:
        return (phi1(x) - phi1(y)) / complex(0.0, d)
    m = 0.5 * (x + y)
    h = 0.5 * d
    return exp_moment(1, m) - exp_moment(3, m) * (h * h / 6.0)


@kernel
def oscillating_velocity(t0, tau, field):
    """Velocity gained from rest in a flight of ``tau`` from time ``t0`` under the oscillating force, as a tuple.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.oscillating import oscillating_field, oscillating_velocity
    >>> record = oscillating_field(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 2.0]), 1.0)
    >>> round(oscillating_velocity(0.0, np.pi / 2, record)[2], 12)  # 2 sin(pi/2)
    2.0
    """
    omega = field[13]
    rotor = complex(math.cos(omega * t0), math.sin(omega * t0))
    along = field[17] * (rotor * tau * phi1(omega * tau)).real
    bx, by, bz = field[3], field[4], field[5]
    if field[12] == 0.0:
        bx, by, bz = field[14] / field[25], field[15] / field[25], field[16] / field[25]
    vx, vy, vz = along * bx, along * by, along * bz
    a_perp = field[24]
    if a_perp > 0.0:
        w = field[12]
        spin = complex(math.cos(w * tau), -math.sin(w * tau))
        zeta = 0.5 * a_perp * tau * spin * (rotor * phi1((w + omega) * tau)
                                            + rotor.conjugate() * phi1((w - omega) * tau))
        vx += zeta.real * field[18] + zeta.imag * field[21]
        vy += zeta.real * field[19] + zeta.imag * field[22]
        vz += zeta.real * field[20] + zeta.imag * field[23]
    return vx, vy, vz


@kernel
def oscillating_displacement(t0, tau, field):
    """Displacement from rest in a flight of ``tau`` from time ``t0`` under the oscillating force, as a tuple.

    The time integral of :func:`oscillating_velocity`.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.oscillating import oscillating_field, oscillating_displacement
    >>> record = oscillating_field(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 2.0]), 1.0)
    >>> round(oscillating_displacement(0.0, np.pi, record)[2], 12)  # 2 (1 - cos(pi))
    4.0
    """
    omega = field[13]
    rotor = complex(math.cos(omega * t0), math.sin(omega * t0))
    tau2 = tau * tau
    along = field[17] * (rotor * tau2 * divided_difference(0.0, omega * tau)).real
    bx, by, bz = field[3], field[4], field[5]
    if field[12] == 0.0:
        bx, by, bz = field[14] / field[25], field[15] / field[25], field[16] / field[25]
    dx, dy, dz = along * bx, along * by, along * bz
    a_perp = field[24]
    if a_perp > 0.0:
        w = field[12]
        z = 0.5 * a_perp * tau2 * (rotor * divided_difference(-w * tau, omega * tau)
                                   + rotor.conjugate() * divided_difference(-w * tau, -omega * tau))
        dx += z.real * field[18] + z.imag * field[21]
        dy += z.real * field[19] + z.imag * field[22]
        dz += z.real * field[20] + z.imag * field[23]
    return dx, dy, dz


@kernel
def _sine_range(theta1, theta2):
    """The smallest and largest sin(theta) for theta in [theta1, theta2] (theta2 >= theta1)."""
    s1, s2 = math.sin(theta1), math.sin(theta2)
    low, high = min(s1, s2), max(s1, s2)
    quarter = 0.5 * math.pi
    # the first maximum (pi/2 + 2 pi n) and minimum (-pi/2 + 2 pi n) at or after theta1
    peak = quarter + 2.0 * math.pi * math.ceil((theta1 - quarter) / (2.0 * math.pi))
    trough = -quarter + 2.0 * math.pi * math.ceil((theta1 + quarter) / (2.0 * math.pi))
    if peak <= theta2:
        high = 1.0
    if trough <= theta2:
        low = -1.0
    return low, high


@kernel
def oscillating_window_speed(vx, vy, vz, t1, h, field, accel_mag):
    """An upper bound of the speed over [t1, t1 + h] of a particle with velocity (vx, vy, vz) at time t1.

    Always ``|v| + integral |a| <= |v| + (|a_s| + |a_c|) h`` (``accel_mag``;
    the magnetic force does no work). Without static acceleration the
    smaller of that and the exact range along b, where v . b + a_par (sin
    theta - sin theta1)/omega over theta = omega t in the window (ends and
    extrema), combined in quadrature with a bound of the perpendicular
    speed: |w(t1)| + A h, or, away from resonance, |w(t1) - P(t1)| + max |P|
    (the particular solution P, of size at most (A/2)(1/(Omega+omega) +
    1/|Omega-omega|), plus the gyration about it). Padded by 1e-10 of the
    speeds against rounding.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.oscillating import oscillating_field, oscillating_window_speed
    >>> record = oscillating_field(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 2.0]), 1.0)
    >>> round(oscillating_window_speed(0.0, 0.0, 0.0, 0.0, 10.0, record, 2.0), 6)  # 2 |sin| <= 2
    2.0
    """
    speed = math.sqrt(vx * vx + vy * vy + vz * vz)
    growth = (speed + accel_mag * h) * (1.0 + 1e-10)
    if field[0] != 0.0 or field[1] != 0.0 or field[2] != 0.0 or field[13] == 0.0:
        return growth
    omega = field[13]
    bx, by, bz = field[3], field[4], field[5]
    if field[12] == 0.0:
        bx, by, bz = field[14] / field[25], field[15] / field[25], field[16] / field[25]
    v_par = vx * bx + vy * by + vz * bz
    theta1 = omega * t1
    low, high = _sine_range(theta1, theta1 + omega * h)
    s1 = math.sin(theta1)
    a_par = field[17]
    end = v_par + a_par * (complex(math.cos(theta1), s1) * h * phi1(omega * h)).real
    ends = max(abs(v_par), abs(end))
    extremes = max(abs(v_par + a_par * (low - s1) / omega), abs(v_par + a_par * (high - s1) / omega))
    parallel = max(ends, extremes) + abs(a_par) * 1e-15 / omega
    wx, wy, wz = vx - v_par * bx, vy - v_par * by, vz - v_par * bz
    w_speed = math.sqrt(wx * wx + wy * wy + wz * wz)
    a_perp = field[24]
    perpendicular = w_speed + a_perp * h
    w = field[12]
    if a_perp > 0.0 and w != omega:
        # the particular solution P(t) = (A/2) (e^{i omega t}/(i(w + omega)) + e^{-i omega t}/(i(w - omega)))
        rotor = complex(math.cos(theta1), s1)
        p = 0.5 * a_perp * (rotor / complex(0.0, w + omega) + rotor.conjugate() / complex(0.0, w - omega))
        zeta = complex(wx * field[18] + wy * field[19] + wz * field[20], wx * field[21] + wy * field[22] + wz * field[23])
        p_max = 0.5 * a_perp * (1.0 / (w + omega) + 1.0 / abs(w - omega))
        perpendicular = min(perpendicular, abs(zeta - p) + p_max)
    return min(growth, math.sqrt(parallel * parallel + perpendicular * perpendicular) * (1.0 + 1e-10))
