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

The three functions the swarm step calls with the record are inlined into
it (:func:`collisionkit._jit.inline_kernel`): a call that takes an array
costs two atomic reference-count operations, more than a trial's arithmetic.

The oscillating record (float64, :data:`RECORD_SIZE` entries) extends the
static one (0:13): omega (13); a_c (14:17); a_c . b (17); e1 (18:21); e2
(21:24); A (24); |a_c| (25); the direction of the "parallel" part (26:29):
b, or without B the direction of a_c (all of it is then "parallel"); 1/omega
(29); a_c . b / omega (30) (multiplications in the flights, not divisions);
1/(|Omega| + omega) (31), 1/(|Omega| - omega) (32) and the largest size of
the particular solution, (A/2)(|31| + |32|) (33): see :mod:`.ac_window`.

The speed bound of a flight window is in :mod:`.ac_window`.
"""

from __future__ import annotations

import math

import numpy as np

from ..._jit import inline_kernel, kernel

STATIC_SIZE = 13
RECORD_SIZE = 34
# below this |x - y| the divided difference is summed from its Taylor series about the midpoint (error below
# 1e-17 there); above it the difference quotient loses at most 2e-16 / 1e-3 of |phi1| <= 1
SERIES_GAP = 1e-3
# below this |x| the response's phi1(ix) is summed from its series, above it taken as a difference of phases
PHI1_SERIES = 0.5


# sincos: pi/2 in two parts (fdlibm's pio2_1 of 33 bits and its remainder), so n pi/2 is exact for |n| < 2^20
PIO2_HI = 1.57079632673412561417e+00
PIO2_LO = 6.07710050650619224932e-11
# (y + ROUNDER) - ROUNDER is y rounded to the nearest whole number for |y| < 2^51 (IEEE arithmetic, no fast-math)
ROUNDER = 6755399441055744.0


@inline_kernel
def _sincos_reduced(r):
    """``(sin r, cos r)`` for |r| <= pi/4: Taylor series of sin to r^15 and cos to r^16 (truncation below 5e-17),
    the corrections beyond r and 1 - r^2/2 summed by Estrin's scheme (products of r^2, r^4, r^8: a chain of
    dependent operations half as long as Horner's)."""
    r2 = r * r
    r4 = r2 * r2
    r8 = r4 * r4
    sin_tail = ((-1.0 / 6.0 + r2 * (1.0 / 120.0)) + r4 * (-1.0 / 5040.0 + r2 * (1.0 / 362880.0))
                + r8 * ((-1.0 / 39916800.0 + r2 * (1.0 / 6227020800.0)) + r4 * (-1.0 / 1307674368000.0)))
    cos_tail = ((1.0 / 24.0 + r2 * (-1.0 / 720.0)) + r4 * (1.0 / 40320.0 + r2 * (-1.0 / 3628800.0))
                + r8 * ((1.0 / 479001600.0 + r2 * (-1.0 / 87178291200.0)) + r4 * (1.0 / 20922789888000.0)))
    return r + (r * r2) * sin_tail, (1.0 - 0.5 * r2) + r4 * cos_tail


@inline_kernel
def sincos_spread(x):
    """:func:`sincos` without a branch on the size of x, for arguments spread over several quadrants (the
    gyration's |Omega| tau / 2), where that branch is a coin toss.

    The argument is reduced to r in [-pi/4, pi/4] by the nearest multiple n
    of pi/2 (Cody-Waite, two constants; exact, and r = x for |x| <= pi/4),
    the series of :func:`_sincos_reduced` taken at r and the quadrant n mod 4
    applied by selects (no branch to mispredict). Inlined
    into its callers: a call and its tuple in memory cost about as much as
    the arithmetic.

    Examples
    --------
    >>> import math
    >>> from collisionkit._kernels.transport.oscillating import sincos_spread
    >>> all(abs(sincos_spread(x)[0] - math.sin(x)) < 1e-15 and abs(sincos_spread(x)[1] - math.cos(x)) < 1e-15
    ...     for x in (-3.0, 0.0, 0.5, 2.0, 100.0, 3e5))
    True
    """
    if abs(x) > 1e5:  # beyond the exact reduction: the library's
        return math.sin(x), math.cos(x)
    n = (x * (2.0 / math.pi) + ROUNDER) - ROUNDER  # 0 for |x| <= pi/4, where the reduction leaves x as it is
    sin_r, cos_r = _sincos_reduced((x - n * PIO2_HI) - n * PIO2_LO)
    quadrant = int(n)
    # the quadrant by selects, not branches: whether |x| passes pi/4 is a coin toss in the flights (a mispredicted
    # branch made a call 1.7 times as long on arguments spread over 0-5 rad: 12.9 vs 7.4 ns, measured)
    odd = (quadrant & 1) != 0
    first = cos_r if odd else sin_r
    second = sin_r if odd else cos_r
    return (-first if (quadrant & 2) != 0 else first), (-second if ((quadrant + 1) & 2) != 0 else second)


@inline_kernel
def sincos(x):
    """``(sin x, cos x)`` at about 1 ulp, for a fraction of the cost of two library calls (|x| <= 1e5).

    For |x| <= pi/4 the series of :func:`_sincos_reduced` directly (the
    oscillating field's phase steps omega tau / 2 mostly are: a branch
    predicted right is cheaper than the reduction); otherwise
    :func:`sincos_spread`. Inlined into its callers: a call and its tuple in
    memory cost about as much as the arithmetic.

    Examples
    --------
    >>> import math
    >>> from collisionkit._kernels.transport.oscillating import sincos
    >>> all(abs(sincos(x)[0] - math.sin(x)) < 1e-15 and abs(sincos(x)[1] - math.cos(x)) < 1e-15
    ...     for x in (-3.0, 0.0, 0.5, 2.0, 100.0, 3e5))
    True
    """
    if abs(x) <= 0.25 * math.pi:
        return _sincos_reduced(x)
    return sincos_spread(x)


@kernel
def oscillating_field(static_field, amplitude, omega):
    """The oscillating record (module docstring) of a static record and the amplitude ``a_c`` (m/s^2) at ``omega``.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.oscillating import oscillating_field
    >>> static = derived_field(np.zeros(3), np.array([0.0, 1.0, 0.0]))
    >>> record = oscillating_field(static, np.array([0.0, 0.0, 2.0]), 3.0)
    >>> record.shape, float(record[13]), float(record[17]), float(record[24])  # E perpendicular to B: A = |a_c|
    ((34,), 3.0, 0.0, 2.0)
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
    record[26:29] = b
    record[29] = 1.0 / omega
    record[30] = along / omega
    w = static_field[12]
    record[31] = 1.0 / (w + omega)
    record[32] = 1.0 / (w - omega) if w != omega else math.inf
    record[33] = 0.5 * a_perp * (abs(record[31]) + abs(record[32])) if a_perp > 0.0 else 0.0
    return record


@kernel
def record_values(field):
    """The record's 34 entries as a tuple (a static record padded with zeros: omega = 0).

    The swarm step hands the tuple, not the array, to the inlined flight
    functions: an inlined function that takes an array still costs an atomic
    reference-count increment and decrement per call.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.oscillating import record_values
    >>> values = record_values(derived_field(np.array([0.0, 0.0, 1.0]), np.zeros(3)))
    >>> len(values), values[2], values[13]
    (34, 1.0, 0.0)
    """
    if field.shape[0] >= RECORD_SIZE:
        return (field[0], field[1], field[2], field[3], field[4], field[5], field[6], field[7], field[8], field[9],
                field[10], field[11], field[12], field[13], field[14], field[15], field[16], field[17], field[18],
                field[19], field[20], field[21], field[22], field[23], field[24], field[25], field[26], field[27],
                field[28], field[29], field[30], field[31], field[32], field[33])
    return (field[0], field[1], field[2], field[3], field[4], field[5], field[6], field[7], field[8], field[9],
            field[10], field[11], field[12], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
            0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


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
    half, half_cos = sincos(0.5 * x)
    return complex(2.0 * half * half_cos / x, 2.0 * half * half / x)


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
    if abs(x - y) >= SERIES_GAP:
        return _divided_difference_of(x, y, phi1(x), phi1(y))
    return _divided_difference_of(x, y, 0.0j, 0.0j)


@kernel
def _phi1_series(x):
    """``(e^{ix} - 1)/(ix)`` for |x| <= ``PHI1_SERIES``: the series sum_n (ix)^n/(n + 1)! to n = 13 in real
    arithmetic (real part: the even terms, sin(x)/x; imaginary: the odd ones, (1 - cos x)/x); error below 5e-17."""
    x2 = x * x
    real = 1.0 - x2 * (1.0 / 6.0 - x2 * (1.0 / 120.0 - x2 * (1.0 / 5040.0 - x2 * (1.0 / 362880.0 - x2 * (
        1.0 / 39916800.0 - x2 / 6227020800.0)))))
    imag = x * (0.5 - x2 * (1.0 / 24.0 - x2 * (1.0 / 720.0 - x2 * (1.0 / 40320.0 - x2 * (1.0 / 3628800.0 - x2 * (
        1.0 / 479001600.0 - x2 / 87178291200.0))))))
    return complex(real, imag)


@inline_kernel
def _response(c0, s0, ew, spin, tau, w, omega, inverse_plus, inverse_minus):
    """``e^{-i w tau} tau (e^{i theta0} phi1(i (w + omega) tau) + e^{-i theta0} phi1(i (w - omega) tau))``.

    (c0, s0) = e^{i theta0}, ``ew`` = e^{i omega tau}, ``spin`` = e^{-i w tau}; ``inverse_plus`` and
    ``inverse_minus`` are 1/(w + omega) and 1/(w - omega). Each term is
    ``(e^{i k tau} - e^{-i w tau}) / (i (w + k))``, or, for |(w + k) tau| <= ``PHI1_SERIES`` (near
    resonance, short flights), ``spin tau phi1`` from its series: no cancellation either way.
    """
    x = (w + omega) * tau
    if abs(x) > PHI1_SERIES:
        z = ew - spin
        plus = complex(z.imag * inverse_plus, -z.real * inverse_plus)  # z / (i (w + omega))
    else:
        plus = spin * tau * _phi1_series(x)
    x = (w - omega) * tau
    if abs(x) > PHI1_SERIES:
        z = ew.conjugate() - spin
        minus = complex(z.imag * inverse_minus, -z.real * inverse_minus)
    else:
        minus = spin * tau * _phi1_series(x)
    return complex(c0, s0) * plus + complex(c0, -s0) * minus


@inline_kernel
def flight_with_phases(vx, vy, vz, c0, s0, tau, field):
    """:func:`oscillating_flown_velocity` and the half-angle sines and cosines it took: ``(vx, vy, vz, cos theta1,
    sin theta1, sin(omega tau/2), cos(omega tau/2), sin(|Omega| tau/2), cos(|Omega| tau/2))``.

    The displacement of the same flight (:func:`displacement_with_phases`)
    and the phase of the next flight then take no sine of their own: a
    real collision costs the trial's sines alone. The gyration by |Omega|
    tau comes from its half angle (sin = 2 s c, cos = 1 - 2 s^2).
    """
    omega = field[13]
    sh, ch = sincos(0.5 * omega * tau)
    sin_w = 2.0 * sh * ch
    vers = 2.0 * sh * sh  # 1 - cos(omega tau)
    c1 = c0 * (1.0 - vers) - s0 * sin_w
    s1 = s0 * (1.0 - vers) + c0 * sin_w
    along = field[30] * (c0 * sin_w - s0 * vers)
    px, py, pz = field[26], field[27], field[28]
    w = field[12]
    if w == 0.0:
        return (vx + field[0] * tau + along * px, vy + field[1] * tau + along * py, vz + field[2] * tau + along * pz,
                c1, s1, sh, ch, 0.0, 1.0)
    bx, by, bz = field[3], field[4], field[5]
    vb = vx * bx + vy * by + vz * bz
    wx = vx - vb * bx - field[9]
    wy = vy - vb * by - field[10]
    wz = vz - vb * bz - field[11]
    cx = wy * bz - wz * by
    cy = wz * bx - wx * bz
    cz = wx * by - wy * bx
    gs, gc = sincos_spread(0.5 * w * tau)
    s = 2.0 * gs * gc
    c = 1.0 - 2.0 * gs * gs
    ox = vb * bx + field[6] * tau + field[9] + wx * c + cx * s + along * px
    oy = vb * by + field[7] * tau + field[10] + wy * c + cy * s + along * py
    oz = vb * bz + field[8] * tau + field[11] + wz * c + cz * s + along * pz
    a_perp = field[24]
    if a_perp > 0.0:
        zeta = 0.5 * a_perp * _response(c0, s0, complex(1.0 - vers, sin_w), complex(c, -s), tau, w, omega,
                                       field[31], field[32])
        ox += zeta.real * field[18] + zeta.imag * field[21]
        oy += zeta.real * field[19] + zeta.imag * field[22]
        oz += zeta.real * field[20] + zeta.imag * field[23]
    return ox, oy, oz, c1, s1, sh, ch, gs, gc


@inline_kernel
def oscillating_flown_velocity(vx, vy, vz, c0, s0, tau, field):
    """Velocity after an exact flight of ``tau`` from (vx, vy, vz) in the static and oscillating fields, and the
    phase at its end: ``(vx, vy, vz, cos theta1, sin theta1)``, theta1 = omega (t0 + tau).

    ``(c0, s0) = (cos, sin)(omega t0)`` of the flight's start (computed once per flight). Costs one sine and
    cosine of omega tau / 2, and of |Omega| tau / 2 with B: the static flight of :func:`.flight.flown_velocity`
    plus the response from rest of the module docstring, along b ``a_par (sin theta1 - sin theta0)/omega``
    in the cancellation-free form ``a_par (c0 sin(omega tau) - s0 (1 - cos(omega tau)))/omega``.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.oscillating import oscillating_field, oscillating_flown_velocity
    >>> record = oscillating_field(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 2.0]), 1.0)
    >>> [round(value, 12) for value in oscillating_flown_velocity(0.0, 0.0, 0.0, 1.0, 0.0, np.pi / 2, record)]
    [0.0, 0.0, 2.0, 0.0, 1.0]
    """
    ox, oy, oz, c1, s1, _, _, _, _ = flight_with_phases(vx, vy, vz, c0, s0, tau, field)
    return ox, oy, oz, c1, s1


@kernel
def _sine_minus_argument(x, sin_x):
    """``sin x - x`` without cancellation (``sin_x`` given; its series for |x| < 0.5, to x^17: error below 1e-22
    there)."""
    if abs(x) >= 0.5:
        return sin_x - x
    x2 = x * x
    return -x * x2 * (1.0 / 6.0 - x2 * (1.0 / 120.0 - x2 * (1.0 / 5040.0 - x2 * (1.0 / 362880.0 - x2 * (
        1.0 / 39916800.0 - x2 * (1.0 / 6227020800.0 - x2 / 1307674368000.0 + x2 * x2 / 355687428096000.0))))))


@kernel
def _phi1_of_half(x, half_sin, half_cos):
    """:func:`phi1` of x from sin(x/2) and cos(x/2)."""
    if x == 0.0:
        return complex(1.0, 0.0)
    twice = 2.0 * half_sin / x
    return complex(twice * half_cos, twice * half_sin)


@kernel
def _divided_difference_of(x, y, phi1_x, phi1_y):
    """:func:`divided_difference` with phi1(ix) and phi1(iy) given."""
    d = x - y
    if abs(d) >= SERIES_GAP:
        z = phi1_x - phi1_y
        inverse = 1.0 / d
        return complex(z.imag * inverse, -z.real * inverse)  # z / (i d)
    m = 0.5 * (x + y)
    h = 0.5 * d
    return exp_moment(1, m) - exp_moment(3, m) * (h * h / 6.0)


@inline_kernel
def displacement_with_phases(c0, s0, tau, sh, ch, gs, gc, field):
    """:func:`oscillating_displacement` from the half-angle sines and cosines of :func:`flight_with_phases`:
    ``(sh, ch) = (sin, cos)(omega tau/2)``, ``(gs, gc) = (sin, cos)(|Omega| tau/2)``; phi1(+-i omega tau) are
    complex conjugates, so both divided differences take the same two values of phi1."""
    omega = field[13]
    x = omega * tau
    along = field[30] * field[29] * (c0 * 2.0 * sh * sh + s0 * _sine_minus_argument(x, 2.0 * sh * ch))
    dx, dy, dz = along * field[26], along * field[27], along * field[28]
    a_perp = field[24]
    if a_perp > 0.0:
        u = -field[12] * tau
        phi_u = _phi1_of_half(u, -gs, gc)
        phi_x = _phi1_of_half(x, sh, ch)
        rotor = complex(c0, s0)
        z = 0.5 * a_perp * tau * tau * (rotor * _divided_difference_of(u, x, phi_u, phi_x)
                                         + rotor.conjugate() * _divided_difference_of(u, -x, phi_u, phi_x.conjugate()))
        dx += z.real * field[18] + z.imag * field[21]
        dy += z.real * field[19] + z.imag * field[22]
        dz += z.real * field[20] + z.imag * field[23]
    return dx, dy, dz


@inline_kernel
def oscillating_displacement(c0, s0, tau, field):
    """Displacement from rest in a flight of ``tau`` under the oscillating force, as a tuple; ``(c0, s0) =
    (cos, sin)(omega t0)`` of the flight's start.

    The time integral of the oscillating part of :func:`oscillating_flown_velocity`: along b
    ``a_par (c0 (1 - cos(omega tau)) + s0 (sin(omega tau) - omega tau)) / omega^2`` (the double integral of
    cos(omega t0 + omega s), free of cancellation), across it the divided differences of the module
    docstring (:func:`displacement_with_phases`).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.oscillating import oscillating_field, oscillating_displacement
    >>> record = oscillating_field(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 2.0]), 1.0)
    >>> round(oscillating_displacement(1.0, 0.0, np.pi, record)[2], 12)  # 2 (1 - cos(pi))
    4.0
    """
    sh, ch = sincos(0.5 * field[13] * tau)
    gs, gc = sincos_spread(0.5 * field[12] * tau)
    return displacement_with_phases(c0, s0, tau, sh, ch, gs, gc, field)
