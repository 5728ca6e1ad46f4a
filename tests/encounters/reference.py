"""Independent references for the encounter tests: strategies, DOP853, the classical Kepler equations.

Scipy's DOP853 integration of the relative two-body ODE at rtol = 1e-13; the
classical Kepler equations in eccentric/hyperbolic anomaly solved by
bisection; Barker's equation for the parabola; and the conserved energy,
angular momentum and Laplace-Runge-Lenz vector of a relative state.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import strategies as st
from scipy.integrate import solve_ivp


def log_uniform(low_exponent=-6.0, high_exponent=6.0):
    """Numbers spread evenly in log between 10**low and 10**high."""
    return st.floats(low_exponent, high_exponent).map(lambda x: 10.0**x)


masses = log_uniform()


distances = log_uniform()


speeds = log_uniform()


def relative_ode(_, y, mu):
    r = y[:3]
    return np.concatenate([y[3:], -mu * r / np.sqrt(r @ r) ** 3])


def dop853(mu, r0, v0, times):
    """DOP853 solution of r'' = -mu r / r^3 from (r0, v0) at t = 0, sampled at ``times`` (one sign)."""
    scale = float(np.linalg.norm(r0))
    solution = solve_ivp(
        relative_ode, (0.0, float(times[-1])), np.concatenate([r0, v0]), method="DOP853",
        rtol=1e-13, atol=1e-22 * scale, t_eval=times, args=(mu,),
    )  # fmt: skip
    assert solution.success
    return solution.y[:3].T, solution.y[3:].T


def dop853_disagreement(orbit, times):
    """Max pointwise relative difference (position and velocity) between DOP853 and the orbit.

    The integration starts at periastron from the state built from eq. 36
    (r_p on +x, v_p on +y) and runs outwards in time in each direction: the
    inbound leg integrated forwards from far away is ill-conditioned (an
    error of rtol |r0| in the far state becomes rtol |r0| / r_p at periastron).
    """
    r0 = np.array([orbit.periastron, 0.0, 0.0])
    mu_k = orbit.kepler_parameter
    vp = math.sqrt((mu_k + abs(mu_k) * orbit.eccentricity) / orbit.periastron)  # eq. 36: r_p v_p^2 = mu_K + q
    v0 = np.array([0.0, vp, 0.0])
    worst = 0.0
    for sign in (1.0, -1.0):
        part = np.sort(sign * times[sign * times > 0])
        if part.size == 0:
            continue
        signed = sign * part
        r_num, v_num = dop853(orbit.kepler_parameter, r0, v0, signed)
        r, v = orbit.relative_state_at_time(signed)
        worst = max(
            worst,
            float(np.max(np.linalg.norm(r_num - r, axis=1) / np.linalg.norm(r, axis=1))),
            float(np.max(np.linalg.norm(v_num - v, axis=1) / np.linalg.norm(v, axis=1))),
        )
    return worst


def bisect(function, low, high):
    """Root of an increasing function on [low, high] to the last bit."""
    for _ in range(2000):
        middle = 0.5 * (low + high)
        if middle in (low, high):
            break
        if function(middle) > 0:
            high = middle
        else:
            low = middle
    return 0.5 * (low + high)


def classical_elliptic(mu, rp, e, t):
    """Perifocal state from M = E - e sin E (bisection), x = a(cos E - e), y = b sin E."""
    a = rp / (1.0 - e)
    n = math.sqrt(mu / a**3)
    period = 2.0 * math.pi / n
    mean = n * (t - period * math.floor(t / period + 0.5))
    E = bisect(lambda x: x - e * math.sin(x) - mean, -math.pi, math.pi)
    root = math.sqrt(1.0 - e * e)
    rate = n / (1.0 - e * math.cos(E))
    return (
        np.array([a * (math.cos(E) - e), a * root * math.sin(E), 0.0]),
        np.array([-a * math.sin(E) * rate, a * root * math.cos(E) * rate, 0.0]),
    )


def classical_hyperbolic(mu, rp, e, t):
    """Perifocal state from M = e sinh H - H (bisection), x = |a|(e - cosh H), y = |a| sqrt(e^2-1) sinh H."""
    a = rp / (e - 1.0)
    n = math.sqrt(mu / a**3)
    mean = n * t
    span = math.asinh(abs(mean) / (e - 1.0)) + 1.0
    H = bisect(lambda x: e * math.sinh(x) - x - mean, -span, span)
    root = math.sqrt(e * e - 1.0)
    rate = n / (e * math.cosh(H) - 1.0)
    return (
        np.array([a * (e - math.cosh(H)), a * root * math.sinh(H), 0.0]),
        np.array([-a * math.sinh(H) * rate, a * root * math.cosh(H) * rate, 0.0]),
    )


def barker_parabola(mu, rp, t):
    """Parabolic state from Barker's equation D + D^3/3 = B = 2 t sqrt(mu/p^3), D = tan(theta/2).

    With D = 2 sinh(phi), D^3 + 3D = 2 sinh(3 phi), so D = 2 sinh(asinh(3B/2) / 3).
    """
    p = 2.0 * rp
    B = 2.0 * t * math.sqrt(mu / p**3)
    D = 2.0 * math.sinh(math.asinh(1.5 * B) / 3.0)
    position = np.array([p * (1.0 - D * D) / 2.0, p * D, 0.0])
    theta = 2.0 * math.atan(D)
    speed = math.sqrt(mu / p)
    velocity = np.array([-speed * math.sin(theta), speed * (1.0 + math.cos(theta)), 0.0])
    return position, velocity


def relative_error(a, b):
    return float(np.linalg.norm(np.asarray(a) - np.asarray(b)) / np.linalg.norm(b))


def specific_invariants(mu, r, v):
    """Energy v^2/2 - mu/r, angular momentum r x v, Laplace-Runge-Lenz e-vector, and the energy scale."""
    distance = np.linalg.norm(r, axis=-1)
    speed2 = np.sum(v * v, axis=-1)
    h = np.cross(r, v)
    lrl = np.cross(v, h) / mu - r / distance[..., None]
    return 0.5 * speed2 - mu / distance, h, lrl, 0.5 * speed2 + abs(mu) / distance
