"""Exact flight in a periodic field given as samples (piecewise linear) with a static B at any angle.

Independent check: the equation of motion dv/dt = g + a f(t/T) + v x Omega, dx/dt = v integrated numerically
(scipy solve_ivp, DOP853 at rtol 1e-13, restarted at every knot so that each step sees a smooth field), for flights
inside one piece, across pieces and over many periods, at several angles and |Omega| (cyclotron resonance
|Omega| T = 2 pi included), against the closed form; the window bound against the exact speed on a fine grid.
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from collisionkit._kernels.transport.flight import derived_field, flown_position
from collisionkit._kernels.transport.waveform_magnetic import (
    phi_functions, shaped_displacement, shaped_velocity, shaped_window,
)
from collisionkit.transport._waveform import shaped_record, waveform_knots

SHAPES = {
    "square": [(0.0, 1.0), (0.5, 1.0), (0.5, -1.0), (1.0, -1.0)],
    "irregular": [(0.1, 0.3), (0.2, -2.0), (0.2, 1.5), (0.65, 0.4), (0.9, 2.5)],
    "cosine": [(k / 32, math.cos(2 * math.pi * k / 32)) for k in range(32)],
}
PERIOD = 0.7
AMPLITUDE = np.array([0.0, 0.0, 1.3])


def _integrated(samples, gravity, omega, t0, tau, v0):
    """Position and velocity after tau from (0, v0) at t0, by solve_ivp restarted at each knot."""
    knots, values = waveform_knots(samples)
    edges = [t0, *sorted(PERIOD * (k + n) for n in range(math.floor(t0 / PERIOD), math.ceil((t0 + tau) / PERIOD) + 1)
                         for k in knots if t0 < PERIOD * (k + n) < t0 + tau), t0 + tau]
    state = np.concatenate([np.zeros(3), v0])
    for start, end in zip(edges, edges[1:]):
        if end <= start:
            continue
        u = (0.5 * (start + end)) / PERIOD
        k = min(int(np.searchsorted(knots, u - math.floor(u), side="right")) - 1, len(knots) - 2)
        slope = (values[k + 1] - values[k]) / (knots[k + 1] - knots[k]) / PERIOD
        origin = PERIOD * (math.floor(u) + knots[k])  # f = values[k] + slope (t - origin) on this piece

        def rhs(t, y):
            f = values[k] + slope * (t - origin)
            return np.concatenate([y[3:], gravity + AMPLITUDE * f + np.cross(y[3:], omega)])

        state = solve_ivp(rhs, (start, end), state, method="DOP853", rtol=1e-13, atol=1e-15).y[:, -1]
    return state[:3], state[3:]


@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize("angle, w", [(90.0, 3.0), (30.0, 40.0), (0.0, 2 * math.pi / PERIOD), (60.0, 0.05)])
def test_the_flight_solves_the_equation_of_motion(shape, angle, w):
    """Velocity and position, across 0 to about 10 pieces and up to 7 periods (the period map's powers)."""
    rng = np.random.default_rng(int(angle) + int(10 * w))
    theta = math.radians(angle)
    omega = w * np.array([0.0, math.sin(theta), math.cos(theta)])
    for gravity in (np.zeros(3), np.array([0.1, -0.2, 0.05])):
        record = shaped_record(derived_field(gravity, omega), AMPLITUDE, PERIOD, SHAPES[shape])
        for tau in (1e-3, 0.05, 0.4, 1.1, 4.9):
            t0 = rng.uniform(0.0, 5.0)
            v0 = rng.normal(size=3)
            x, v = _integrated(SHAPES[shape], gravity, omega, t0, tau, v0)
            scale = np.linalg.norm(v0) + 3.0 * np.linalg.norm(AMPLITUDE) * tau
            np.testing.assert_allclose(shaped_velocity(*v0, t0, tau, record), v, rtol=0, atol=2e-11 * scale)
            flown = np.array(flown_position(0.0, 0.0, 0.0, *v0, tau, record))
            np.testing.assert_allclose(flown + shaped_displacement(t0, tau, record), x, rtol=0,
                                       atol=2e-11 * scale * tau)


def test_the_phi_functions_are_continuous_at_the_series_switch_and_match_their_definition():
    for x in (1e-8, 0.3, 0.999999, 1.000001, 7.0, -2.5):
        e, p1, p2, p3 = phi_functions(x)
        z = 1j * x
        assert e == pytest.approx(np.exp(z), abs=1e-15)
        # definitions by quadrature-free closed forms at moderate |x|, the series near 0
        exact = [(np.exp(z) - 1) / z, (np.exp(z) - 1 - z) / z**2, (np.exp(z) - 1 - z - z**2 / 2) / z**3] \
            if abs(x) > 0.1 else [sum(z**n / math.factorial(n + j) for n in range(25)) for j in (1, 2, 3)]
        assert [p1, p2, p3] == pytest.approx(exact, rel=2e-14 if abs(x) > 0.1 else 1e-15)


def test_the_window_bound_covers_the_exact_speed():
    """On a grid of 401 points over random windows, with and without gravity, E at 0, 45 and 90 degrees to B."""
    rng = np.random.default_rng(4)
    for angle in (0.0, 45.0, 90.0):
        theta = math.radians(angle)
        omega = 25.0 * np.array([0.0, math.sin(theta), math.cos(theta)])
        for gravity in (np.zeros(3), np.array([0.3, -0.2, 0.5])):
            record = shaped_record(derived_field(gravity, omega), AMPLITUDE, PERIOD, SHAPES["irregular"])
            accel = np.linalg.norm(gravity) + record[25]
            for _ in range(20):
                v0, t0, start, h = rng.normal(size=3), rng.uniform(0, 5), rng.uniform(0, 1), rng.uniform(0.01, 1)
                bound = shaped_window(*v0, t0, start, h, record, accel)
                speeds = [np.linalg.norm(shaped_velocity(*v0, t0, start + u, record)) for u in np.linspace(0, h, 401)]
                assert bound >= max(speeds) * (1 - 1e-12)
                if not gravity.any():  # tighter than |v| + |a| max|f| h across B
                    assert angle == 0.0 or bound < np.linalg.norm(speeds[0]) + accel * h


@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize("angle, w", [(90.0, 3.0), (60.0, 40.0), (0.0, 2 * math.pi / PERIOD), (30.0, 0.05)])
def test_the_flight_from_a_known_piece_solves_the_equation_of_motion(shape, angle, w):
    """shaped_flight (piece by piece from the phase's piece) against solve_ivp: inside a piece, across knots and
    jumps, over a period's end and longer than a period; without B too."""
    from collisionkit._kernels.transport.waveform import _piece
    from collisionkit._kernels.transport.waveform_magnetic import shaped_flight

    rng = np.random.default_rng(int(angle) + int(10 * w) + 1)
    theta = math.radians(angle)
    for omega in (w * np.array([0.0, math.sin(theta), math.cos(theta)]), np.zeros(3)):
        for gravity in (np.zeros(3), np.array([0.1, -0.2, 0.05])):
            record = shaped_record(derived_field(gravity, omega), AMPLITUDE, PERIOD, SHAPES[shape])
            for tau in (1e-3, 0.05, 0.4, 0.69, 2.3):
                t0 = rng.uniform(0.0, 5.0)
                v0 = rng.normal(size=3)
                u0 = t0 / PERIOD - math.floor(t0 / PERIOD)
                x, v = _integrated(SHAPES[shape], gravity, omega, t0, tau, v0)
                scale = np.linalg.norm(v0) + 3.0 * np.linalg.norm(AMPLITUDE) * tau
                flight = shaped_flight(*v0, u0, _piece(u0, record, int(record[35])), tau, record)
                np.testing.assert_allclose(flight[:3], v, rtol=0, atol=2e-11 * scale)
                flown = np.array(flown_position(0.0, 0.0, 0.0, *v0, tau, record))
                np.testing.assert_allclose(flown + flight[3:], x, rtol=0, atol=2e-11 * scale * tau)
