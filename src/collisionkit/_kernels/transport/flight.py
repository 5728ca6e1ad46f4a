"""Exact free flight in uniform fields, and the speed bounds of a flight window.

The field record (float64, 13 entries, from :func:`derived_field`): the
acceleration ``a`` (0:3); the unit vector ``b`` of ``Omega = (q/m) B``
(3:6); the acceleration along it (6:9); the E x B drift (9:12); ``|Omega|``
(12, 0 without a magnetic field).

The trial frequency of a window of a flight is the rate bound at the
largest speed the particle can reach in it. Without a magnetic field the
speed is ``|v + a t|``, whose square is convex in t: the largest speed is
at an end of the window (exact, :func:`window_top_speed`). With one, the
smaller of two bounds: the convex bound of :func:`window_top_speed` at the
ends of the window, and ``|v| + |a| t`` at its end
(:func:`window_growth_speed`).
"""

from __future__ import annotations

import math

import numpy as np

from ..._jit import borrowing_inline_kernel, borrowing_kernel, kernel
from .oscillating import sincos_spread


@kernel
def derived_field(acceleration, omega_vector):
    """The field record (see the module docstring) of a uniform acceleration and ``Omega = (q/m) B``."""
    field = np.zeros(13)
    field[0:3] = acceleration
    field[3:6] = omega_vector
    w = math.sqrt(omega_vector[0] ** 2 + omega_vector[1] ** 2 + omega_vector[2] ** 2)
    field[12] = w
    if w > 0.0:
        b = omega_vector / w
        a_par = (acceleration[0] * b[0] + acceleration[1] * b[1] + acceleration[2] * b[2]) * b
        a_perp = acceleration - a_par
        field[6:9] = a_par
        # drift u = (a_perp x Omega) / omega^2 makes a_perp + u x Omega vanish
        field[9] = (a_perp[1] * omega_vector[2] - a_perp[2] * omega_vector[1]) / w**2
        field[10] = (a_perp[2] * omega_vector[0] - a_perp[0] * omega_vector[2]) / w**2
        field[11] = (a_perp[0] * omega_vector[1] - a_perp[1] * omega_vector[0]) / w**2
        # store the unit vector in place of Omega (Omega = w * b)
        field[3:6] = b
    return field


@borrowing_kernel
def flown_velocity(vx, vy, vz, dt, field):
    """Velocity after an exact free flight of ``dt`` from (vx, vy, vz), as a tuple.

    Constant acceleration, or gyration about B plus the E x B drift: the
    closed-form solution of dv/dt = a + v x Omega. The gyration's sine and
    cosine come from one :func:`.oscillating.sincos` of the half angle (sin =
    2 s c, cos = 1 - 2 s^2; a tenth of the cost of the library's sin and cos).
    """
    w = field[12]
    if w == 0.0:
        return vx + field[0] * dt, vy + field[1] * dt, vz + field[2] * dt
    half_sin, half_cos = sincos_spread(0.5 * w * dt)
    return gyrated_velocity(vx, vy, vz, dt, half_sin, half_cos, field)


@borrowing_inline_kernel
def gyrated_velocity(vx, vy, vz, dt, half_sin, half_cos, field):
    """:func:`flown_velocity` in a magnetic field given ``(sin, cos)(|Omega| dt / 2)``: a trial that becomes a
    real collision hands its sines on to :func:`gyrated_position` (one sine series a collision, not two).

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field, gyrated_velocity
    >>> field = derived_field(np.zeros(3), np.array([0.0, 0.0, 2.0]))  # |Omega| = 2 along z
    >>> [round(value, 12) for value in gyrated_velocity(1.0, 0.0, 0.0, math.pi / 4, math.sin(math.pi / 4),
    ...                                                  math.cos(math.pi / 4), field)]  # a quarter turn
    [0.0, -1.0, 0.0]
    """
    bx, by, bz = field[3], field[4], field[5]
    vb = vx * bx + vy * by + vz * bz
    wx = vx - vb * bx - field[9]
    wy = vy - vb * by - field[10]
    wz = vz - vb * bz - field[11]
    cx = wy * bz - wz * by
    cy = wz * bx - wx * bz
    cz = wx * by - wy * bx
    s = 2.0 * half_sin * half_cos
    c = 1.0 - 2.0 * half_sin * half_sin
    return (vb * bx + field[6] * dt + field[9] + wx * c + cx * s,
            vb * by + field[7] * dt + field[10] + wy * c + cy * s,
            vb * bz + field[8] * dt + field[11] + wz * c + cz * s)


@borrowing_kernel
def flown_position(x, y, z, vx, vy, vz, dt, field):
    """Position after an exact free flight of ``dt`` from (x, y, z) with velocity (vx, vy, vz), as a tuple.

    The time integral of :func:`flown_velocity` (its sines from the half angle too).
    """
    w = field[12]
    if w == 0.0:
        half = 0.5 * dt * dt
        return x + vx * dt + field[0] * half, y + vy * dt + field[1] * half, z + vz * dt + field[2] * half
    half_sin, half_cos = sincos_spread(0.5 * w * dt)
    return gyrated_position(x, y, z, vx, vy, vz, dt, half_sin, half_cos, field)


@borrowing_inline_kernel
def gyrated_position(x, y, z, vx, vy, vz, dt, half_sin, half_cos, field):
    """:func:`flown_position` in a magnetic field given ``(sin, cos)(|Omega| dt / 2)`` (see :func:`gyrated_velocity`).

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field, gyrated_position
    >>> field = derived_field(np.zeros(3), np.array([0.0, 0.0, 2.0]))  # a circle of radius 1/2 about (0, -1/2)
    >>> [round(value, 12) for value in gyrated_position(0.0, 0.0, 0.0, 1.0, 0.0, 0.0, math.pi / 2, 1.0, 0.0, field)]
    [0.0, -1.0, 0.0]
    """
    w = field[12]
    bx, by, bz = field[3], field[4], field[5]
    vb = vx * bx + vy * by + vz * bz
    wx = vx - vb * bx - field[9]
    wy = vy - vb * by - field[10]
    wz = vz - vb * bz - field[11]
    cx = wy * bz - wz * by
    cy = wz * bx - wx * bz
    cz = wx * by - wy * bx
    s = 2.0 * half_sin * half_cos
    one_minus_c = 2.0 * half_sin * half_sin
    return (x + (vb * bx + field[9]) * dt + 0.5 * field[6] * dt * dt + (wx * s + cx * one_minus_c) / w,
            y + (vb * by + field[10]) * dt + 0.5 * field[7] * dt * dt + (wy * s + cy * one_minus_c) / w,
            z + (vb * bz + field[11]) * dt + 0.5 * field[8] * dt * dt + (wz * s + cz * one_minus_c) / w)


@kernel
def flight_envelope(vx, vy, vz, bx, by, bz, ux, uy, uz, a_par):
    """Constants of a flight's speed bound in a magnetic field: (v . b, |u| + |w|, a . b).

    The exact motion (:func:`flown_velocity`) is v(t) = (v.b + (a.b) t) b
    + u + w(t), with the E x B drift u and the gyrating part w(t) both
    perpendicular to b = Omega/|Omega| and |w(t)| = |w(0)|, so
    |v(t)|^2 <= (v.b + (a.b) t)^2 + (|u| + |w|)^2. Takes the field record's
    unit vector b, drift u and ``a_par`` = a . b as scalars: no array, so no
    reference counting.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field, flight_envelope
    >>> field = derived_field(np.array([0.0, 0.0, 1.0]), np.array([0.0, 2.0, 0.0]))
    >>> a_par = float(field[6:9] @ field[3:6])
    >>> envelope = flight_envelope(0.0, 3.0, 0.0, *field[3:6], *field[9:12], a_par)
    >>> [float(round(value, 12)) for value in envelope]  # drift speed 0.5
    [3.0, 1.0, 0.0]
    """
    vb = vx * bx + vy * by + vz * bz
    wx = vx - vb * bx - ux
    wy = vy - vb * by - uy
    wz = vz - vb * bz - uz
    return vb, math.sqrt(ux * ux + uy * uy + uz * uz) + math.sqrt(wx * wx + wy * wy + wz * wz), a_par


@kernel
def window_top_speed(vx, vy, vz, ax, ay, az, t, exact, vb, radius, a_par):
    """A convex-in-time bound f(t) of the speed at flight time ``t``: its largest value on a window is at an end.

    Without B it is |v + a t| itself, from the components (the arithmetic
    of the flown velocity, free of the cancellation of |v|^2 + 2 a.v t +
    a^2 t^2 near a stop). With B it is sqrt((v.b + a_par t)^2 + radius^2)
    (:func:`flight_envelope`), padded by 1e-10 against the rounding of the
    gyration formula.

    Examples
    --------
    >>> from collisionkit._kernels.transport.flight import window_top_speed
    >>> [window_top_speed(0.0, 0.0, 3.0, 0.0, 0.0, -2.0, t, True, 0.0, 0.0, 0.0) for t in (0.5, 1.0)]  # |3 - 2 t|
    [2.0, 1.0]
    """
    if exact:
        x = vx + ax * t
        y = vy + ay * t
        z = vz + az * t
        return math.sqrt(x * x + y * y + z * z)
    along = vb + a_par * t
    return math.sqrt(along * along + radius * radius) * (1.0 + 1e-10)


@kernel
def window_growth_speed(speed0, accel_mag, t, exact, radius):
    """The bound |v| + |a| t of the speed at flight time ``t`` in a magnetic field (inf without one).

    d|v|/dt = a . v/|v| <= |a|: the magnetic force does no work. Padded by
    1e-10 of the speeds involved against the rounding of the gyration formula.
    """
    if exact:
        return math.inf
    return (speed0 + accel_mag * t + radius) * (1.0 + 1e-10) - radius
