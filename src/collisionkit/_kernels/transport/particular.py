"""A flight in an oscillating field with a static B, taken about the particular solution (off cyclotron resonance).

The motion dv/dt = a_s + a_c cos(theta) + v x Omega (theta = omega t, the
record of :mod:`.oscillating`) is linear, and off resonance it has the
periodic particular solution ``v_p(theta) = sin(theta) K_s + cos(theta)
K_c``: along b = Omega/|Omega| the integral ``(a_c . b / omega) sin(theta)``,
across it ``P(theta) = (A/2i)(alpha e^{i theta} + beta e^{-i theta}) = (A/2)
((alpha - beta) sin(theta) - i (alpha + beta) cos(theta))`` in zeta = w . e1
+ i w . e2 (alpha = 1/(|Omega| + omega), beta = 1/(|Omega| - omega); module
docstring of :mod:`.ac_window`), so

* ``K_s = (a_c . b / omega) b + (A/2)(alpha - beta) e1``, ``K_c = -(A/2)(alpha + beta) e2``.

The rest, ``v - v_p``, obeys the static equation dv/dt = a_s + v x Omega.
A flight of tau from phase theta0 is then the static flight of ``u0 = v0 -
v_p(theta0)`` (:func:`.flight.gyrated_velocity`, :func:`.flight.gyrated_position`)
plus ``v_p(theta1)``, and its displacement the static one of u0 plus
``integral v_p dt = (K_s (cos theta0 - cos theta1) + K_c (sin theta1 - sin
theta0)) / omega``, those differences taken free of cancellation from the
half angle, ``cos theta0 - cos theta1 = c0 vers + s0 sin(omega tau)`` and
``sin theta1 - sin theta0 = c0 sin(omega tau) - s0 vers`` (vers = 1 -
cos(omega tau) = 2 sin^2(omega tau/2)). A trial costs the two half-angle
sines of :func:`.oscillating.flight_with_phases` and a few products, with no
complex arithmetic; a real collision's displacement reuses them.

The subtraction ``v0 - v_p`` rounds at about 1e-16 of |v_p|, which grows
as 1/| |Omega| - omega | near resonance: :data:`PARTICULAR_DETUNING` keeps
|v_p| within 50 times the quiver amplitude |a_c|/omega, and closer to
resonance (and without B) the flights of :mod:`.oscillating` are used.
"""

from __future__ import annotations

from ..._jit import inline_kernel, kernel
from .flight import gyrated_position, gyrated_velocity
from .oscillating import sincos, sincos_spread

# the particular solution is used when | |Omega| - omega | >= this fraction of omega: its size is then at most
# (A/2)(alpha + |beta|) <= (1/2 + 1/(2 x 0.01)) |a_c|/omega, about 50 quiver amplitudes
PARTICULAR_DETUNING = 0.01


@kernel
def particular_terms(field):
    """``(use, K_s, K_c)`` of an oscillating record (module docstring), K_s and K_c as 3-tuples; ``use`` is False
    (and the vectors zero) without B, without oscillation, or within :data:`PARTICULAR_DETUNING` of resonance.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.flight import derived_field
    >>> from collisionkit._kernels.transport.oscillating import oscillating_field
    >>> from collisionkit._kernels.transport.particular import particular_terms
    >>> record = oscillating_field(derived_field(np.zeros(3), np.array([0.0, 3.0, 0.0])), np.array([0.0, 0.0, 2.0]),
    ...                            1.0)  # E perpendicular to B, |Omega| = 3, omega = 1
    >>> use, k_s, k_c = particular_terms(record)
    >>> use, [round(value, 12) + 0.0 for value in k_s], [round(value, 12) + 0.0 for value in k_c]
    (True, [0.0, 0.0, -0.25], [-0.75, 0.0, 0.0])
    """
    zero = (0.0, 0.0, 0.0)
    if field.shape[0] <= 13 or field[13] <= 0.0 or field[12] == 0.0:
        return False, zero, zero
    omega, w = field[13], field[12]
    if abs(w - omega) < PARTICULAR_DETUNING * omega:
        return False, zero, zero
    half_a = 0.5 * field[24]
    along = half_a * (field[31] - field[32])
    across = -half_a * (field[31] + field[32])
    k_s = (field[30] * field[26] + along * field[18], field[30] * field[27] + along * field[19],
           field[30] * field[28] + along * field[20])
    k_c = (across * field[21], across * field[22], across * field[23])
    return True, k_s, k_c


@inline_kernel
def particular_flight(ux, uy, uz, c0, s0, tau, k_s, k_c, field):
    """The velocity after a flight of ``tau`` from phase (c0, s0) = (cos, sin)(theta0), given ``u0 = v0 -
    v_p(theta0)`` (module docstring), with the phase at its end and the half-angle sines it took: ``(vx, vy, vz,
    cos theta1, sin theta1, sin(omega tau/2), cos(omega tau/2), sin(|Omega| tau/2), cos(|Omega| tau/2))``, as
    :func:`.oscillating.flight_with_phases` returns them. ``field`` is the record's tuple or array.
    """
    sh, ch = sincos(0.5 * field[13] * tau)
    sin_w = 2.0 * sh * ch
    vers = 2.0 * sh * sh
    c1 = c0 * (1.0 - vers) - s0 * sin_w
    s1 = s0 * (1.0 - vers) + c0 * sin_w
    gs, gc = sincos_spread(0.5 * field[12] * tau)
    ox, oy, oz = gyrated_velocity(ux, uy, uz, tau, gs, gc, field)
    return (ox + s1 * k_s[0] + c1 * k_c[0], oy + s1 * k_s[1] + c1 * k_c[1], oz + s1 * k_s[2] + c1 * k_c[2],
            c1, s1, sh, ch, gs, gc)


@inline_kernel
def particular_position(x, y, z, ux, uy, uz, c0, s0, tau, sh, ch, gs, gc, k_s, k_c, field):
    """The position after the flight of :func:`particular_flight` from (x, y, z), from its half-angle sines: the
    static flight of u0 plus the integral of v_p (module docstring)."""
    px, py, pz = gyrated_position(x, y, z, ux, uy, uz, tau, gs, gc, field)
    sin_w = 2.0 * sh * ch
    vers = 2.0 * sh * sh
    cos_drop = (c0 * vers + s0 * sin_w) * field[29]  # (cos theta0 - cos theta1) / omega
    sin_rise = (c0 * sin_w - s0 * vers) * field[29]  # (sin theta1 - sin theta0) / omega
    return (px + cos_drop * k_s[0] + sin_rise * k_c[0], py + cos_drop * k_s[1] + sin_rise * k_c[1],
            pz + cos_drop * k_s[2] + sin_rise * k_c[2])
