r"""Numba kernels of the two-body (Kepler/Coulomb) propagation.

The relative orbit obeys :math:`\ddot{\mathbf r} = -\mu\,\mathbf r / r^3` with
``mu`` of either sign (``mu < 0``: repulsion). It is described from its
periastron by three numbers, none of which cancels for any eccentricity:

* ``rp``: periastron distance;
* ``beta = 2 mu / rp - vp^2``: minus twice the specific energy
  (> 0 elliptic, 0 parabolic, < 0 hyperbolic);
* ``q = mu - beta rp = rp vp^2 - mu = |mu| e`` (> 0).

With the universal anomaly ``s`` (``ds = dt / r``) and the functions
``G_n(s) = s^n c_n(beta s^2)`` built from Stumpff's ``c_n`` (Danby,
*Fundamentals of Celestial Mechanics*, 2nd ed., sec. 6.9), the orbit measured
from periastron is, with ``h = rp vp`` (an input: ``h^2 = rp (mu + q)``
cancels for a repulsive near head-on orbit, ``mu + q = |mu| (e - 1)``, so the
callers take h from ``b v_inf`` or ``|r x v|`` when they have them),

.. math::
    t = r_p s + q G_3, \quad r = r_p + q G_2, \quad
    x_P = r_p - \mu G_2, \quad x_Q = h G_1, \quad
    v_P = -\mu G_1 / r, \quad v_Q = h G_0 / r,

in the perifocal basis (``P`` towards periastron, ``Q`` along the velocity
there). Both terms of ``t`` and of ``r`` are non-negative for ``s >= 0``, so
Kepler's equation ``t(s) = t`` is increasing (slope ``r``) and convex, and
Newton's method started above the root descends monotonically onto it.
"""

from __future__ import annotations

import math

from .._jit import kernel

_SERIES_LIMIT = 2.0
_MAX_ITERATIONS = 200
_EPSILON = 2.220446049250313e-16


@kernel
def stumpff(z):
    """Stumpff functions (c0, c1, c2, c3) of z, series for |z| < 2, closed forms beyond."""
    if abs(z) < _SERIES_LIMIT:
        # c_n(z) = sum_k (-z)^k / (2k + n)!
        c2 = 0.0
        c3 = 0.0
        term2 = 0.5
        term3 = 1.0 / 6.0
        for k in range(40):
            c2 += term2
            c3 += term3
            if abs(term2) < 1e-18 * abs(c2) and abs(term3) < 1e-18 * abs(c3):
                break
            term2 *= -z / ((2 * k + 3) * (2 * k + 4))
            term3 *= -z / ((2 * k + 4) * (2 * k + 5))
        return 1.0 - z * c2, 1.0 - z * c3, c2, c3
    if z > 0.0:
        y = math.sqrt(z)
        sin_y = math.sin(y)
        cos_y = math.cos(y)
        # 1 - cos y = 2 sin^2(y / 2) avoids the cancellation near y = 2 pi k
        return cos_y, sin_y / y, 2.0 * math.sin(0.5 * y) ** 2 / z, (y - sin_y) / (z * y)
    y = math.sqrt(-z)
    sinh_y = math.sinh(y)
    return math.cosh(y), sinh_y / y, 2.0 * math.sinh(0.5 * y) ** 2 / -z, (sinh_y - y) / (-z * y)


@kernel
def g_functions(beta, s):
    """Universal functions G0..G3 at anomaly s: G_n = s^n c_n(beta s^2)."""
    c0, c1, c2, c3 = stumpff(beta * s * s)
    s2 = s * s
    return c0, s * c1, s2 * c2, s2 * s * c3


@kernel
def time_of_anomaly(s, rp, beta, q):
    """Time from periastron at universal anomaly s: rp s + q G3(s)."""
    g3 = g_functions(beta, s)[3]
    return rp * s + q * g3


@kernel
def _hyperbolic_bound(t, mu, rp, beta, q):
    """Upper bound on s for beta < 0 from t w^3 = q sinh H - mu H, H = w s."""
    w = math.sqrt(-beta)
    scaled = t * w**3
    if mu > 0.0:
        # q sinh H - mu H >= (q - mu) sinh H = rp w^2 sinh H
        upper = math.asinh(t * w / rp)
        for _ in range(3):  # asinh-based refinement: stays an upper bound
            upper = min(upper, math.asinh((scaled + mu * upper) / q))
    else:
        upper = math.asinh(scaled / q)  # q sinh H + |mu| H >= q sinh H
    return upper / w


@kernel
def _upper_bound(t, mu, rp, beta, q):
    """A rigorous upper bound on the anomaly s with t(s) = t >= 0."""
    bound = t / rp  # t(s) >= rp s since r >= rp
    if beta > 0.0:
        root = math.sqrt(beta)
        bound = min(bound, math.pi / root)  # apoastron (t is at most half a period)
        # E - sin E >= E^3 / pi^2 on [0, pi]
        bound = min(bound, (math.pi**2 * t / q) ** (1.0 / 3.0))
    else:
        bound = min(bound, (6.0 * t / q) ** (1.0 / 3.0))  # G3 >= s^3 / 6
        if beta < 0.0:
            bound = min(bound, _hyperbolic_bound(t, mu, rp, beta, q))
    return bound


@kernel
def solve_anomaly(t, mu, rp, beta, q):
    """Universal anomaly s >= 0 with rp s + q G3(s) = t >= 0 (safeguarded Newton).

    Starts at a rigorous upper bound, where convexity makes Newton's iterates
    decrease monotonically; a step leaving the bracket [low, high] is replaced
    by bisection, so round-off can never make it diverge.
    """
    if t == 0.0:
        return 0.0
    low = 0.0
    high = _upper_bound(t, mu, rp, beta, q)
    s = high
    for _ in range(_MAX_ITERATIONS):
        g0, g1, g2, g3 = g_functions(beta, s)
        residual = rp * s + q * g3 - t
        if residual > 0.0:
            high = s
        elif residual < 0.0:
            low = s
        else:
            return s
        candidate = s - residual / (rp + q * g2)
        if abs(candidate - s) <= 4.0 * _EPSILON * s:
            return candidate
        if not (low < candidate < high):
            candidate = 0.5 * (low + high)
            if candidate == low or candidate == high:  # bracket down to adjacent numbers
                return candidate
        s = candidate
    return s


@kernel
def perifocal_position(s, mu, rp, beta, q, h):
    """Perifocal position (x_P, x_Q) = (rp - mu G2, h G1) at anomaly s (any sign)."""
    g0, g1, g2, g3 = g_functions(beta, s)
    return rp - mu * g2, h * g1


@kernel
def _perifocal_state(s, mu, rp, beta, q, h):
    g0, g1, g2, g3 = g_functions(beta, s)
    r = rp + q * g2
    return rp - mu * g2, h * g1, -mu * g1 / r, h * g0 / r


@kernel
def anomaly_of_state(r, sigma, rp, beta, q):
    """Signed anomaly s of a state with separation r and r.v = sigma.

    sigma = r dr/dt = q G1(s) gives s through an asinh (hyperbolic) or
    directly (parabolic); for an ellipse sin E = sqrt(beta) G1 and
    cos E = G0 = 1 - beta (r - rp) / q fix E = sqrt(beta) s in (-pi, pi].
    """
    if q == 0.0:  # circular orbit: take the state itself as periastron
        return 0.0
    g1 = sigma / q
    if beta > 0.0:
        root = math.sqrt(beta)
        return math.atan2(root * g1, 1.0 - beta * (r - rp) / q) / root
    if beta < 0.0:
        w = math.sqrt(-beta)
        return math.asinh(w * g1) / w
    return g1


@kernel
def perifocal_states(times, mu, rp, beta, q, h, out):
    """Perifocal state (x_P, x_Q, v_P, v_Q) at each time from periastron, in place.

    Elliptic orbits are first reduced to the period around the nearest
    periastron passage; negative times use the mirror symmetry of the orbit
    about its apse line: (x_P, -x_Q, -v_P, v_Q).
    """
    period = 2.0 * math.pi * mu / beta**1.5 if beta > 0.0 else math.inf
    for i in range(times.shape[0]):
        t = times[i]
        if beta > 0.0:
            t = t - period * math.floor(t / period + 0.5)
        sign = 1.0 if t >= 0.0 else -1.0
        s = solve_anomaly(abs(t), mu, rp, beta, q)
        x_p, x_q, v_p, v_q = _perifocal_state(s, mu, rp, beta, q, h)
        out[i, 0] = x_p
        out[i, 1] = sign * x_q
        out[i, 2] = sign * v_p
        out[i, 3] = v_q


@kernel
def anomaly_at_separation(r, rp, beta, q):
    """Anomaly s >= 0 where the separation first reaches r (NaN if never).

    Inverts r = rp + q G2(s) through G2 = 2 sinh^2(w s / 2) / w^2 (hyperbolic),
    2 sin^2(sqrt(beta) s / 2) / beta (elliptic) or s^2 / 2 (parabolic).
    """
    if not (r >= rp):
        return math.nan
    if r == rp:
        return 0.0
    half = math.sqrt(0.5 * (r - rp) / q)  # sqrt(G2 / 2)
    if beta > 0.0:
        root = math.sqrt(beta)
        argument = root * half
        if argument > 1.0:
            # beyond apoastron (allow the last bit of round-off at apoastron)
            if argument > 1.0 + 8.0 * _EPSILON:
                return math.nan
            argument = 1.0
        return 2.0 * math.asin(argument) / root
    if beta < 0.0:
        w = math.sqrt(-beta)
        return 2.0 * math.asinh(w * half) / w
    return 2.0 * half


@kernel
def times_at_separations(separations, rp, beta, q, out):
    """Time from periastron (>= 0, outbound) at which each separation is reached, in place."""
    for i in range(separations.shape[0]):
        s = anomaly_at_separation(separations[i], rp, beta, q)
        out[i] = time_of_anomaly(s, rp, beta, q) if s == s else math.nan
