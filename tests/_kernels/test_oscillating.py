"""Exact flight in E0 cos(omega t) with a static B at any angle, and the speed bound of a flight window.

Independent check: the equation of motion dv/dt = a_s + a_c cos(omega t) + v x Omega integrated numerically
(scipy solve_ivp, DOP853 at rtol 1e-12).
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from collisionkit._kernels.transport.flight import derived_field, flown_position, flown_velocity
from collisionkit._kernels.transport.oscillating import (
    SERIES_GAP, divided_difference, oscillating_displacement, oscillating_field, oscillating_velocity,
    oscillating_window_speed,
)


def _case(rng, kind):
    """A random flight: angle psi of B to E, |Omega|, omega, amplitude along z, gravity, start state and length."""
    psi = rng.uniform(0.0, math.pi)
    gyro = 0.0 if kind == "no B" else rng.uniform(0.1, 3.0)
    omega = gyro if kind == "resonance" else rng.uniform(0.05, 3.0)
    gravity = rng.normal(size=3) if kind == "gravity" else np.zeros(3)
    b = np.array([0.0, math.sin(psi), math.cos(psi)])
    amplitude = np.array([0.0, 0.0, rng.uniform(-2.0, 2.0)])
    static = derived_field(gravity, gyro * b)
    record = oscillating_field(static, amplitude, omega)
    return (static, record, gravity, amplitude, omega, gyro * b, rng.normal(size=3), rng.normal(size=3),
            rng.uniform(0.0, 20.0), rng.uniform(0.01, 6.0))


def _ode(gravity, amplitude, omega, omega_vector):
    def rhs(t, y):
        v = y[3:]
        return np.concatenate([v, gravity + amplitude * math.cos(omega * t) + np.cross(v, omega_vector)])
    return rhs


KINDS = ["no B", "oblique B", "resonance", "gravity"]


@pytest.mark.parametrize("kind", KINDS)
def test_the_flight_is_the_solution_of_the_equation_of_motion(kind):
    """Random angles, phases (start times) and lengths, at and off cyclotron resonance: the closed form agrees
    with the numerical integration to 1e-9 of the velocities and lengths involved (the integrator's tolerance)."""
    rng = np.random.default_rng(KINDS.index(kind))
    for _ in range(12):
        static, record, gravity, amplitude, omega, omega_vector, x0, v0, t0, tau = _case(rng, kind)
        solution = solve_ivp(_ode(gravity, amplitude, omega, omega_vector), (t0, t0 + tau), np.concatenate([x0, v0]),
                             method="DOP853", rtol=1e-12, atol=1e-13)
        velocity = np.array(flown_velocity(*v0, tau, static)) + np.array(oscillating_velocity(t0, tau, record))
        position = (np.array(flown_position(*x0, *v0, tau, static))
                    + np.array(oscillating_displacement(t0, tau, record)))
        np.testing.assert_allclose(velocity, solution.y[3:, -1], rtol=0, atol=1e-9 * (1 + tau))
        np.testing.assert_allclose(position, solution.y[:3, -1], rtol=0, atol=1e-9 * (1 + tau) ** 2)


def test_at_resonance_the_perpendicular_response_grows_linearly():
    """omega = Omega, E perpendicular to B, from rest at t0 = 0: |w| = (A/2) t for t >> 1/omega (secular growth)."""
    record = oscillating_field(derived_field(np.zeros(3), np.array([0.0, 2.0, 0.0])), np.array([0.0, 0.0, 1.0]), 2.0)
    tau = 200 * math.pi  # 200 periods
    speed = np.linalg.norm(oscillating_velocity(0.0, tau, record))
    assert speed == pytest.approx(0.5 * tau, rel=1e-3)


def test_the_divided_difference_is_continuous_across_the_switch_to_its_series():
    for x in (0.0, 0.7, 3.0, 40.0):
        inside = divided_difference(x, x + 0.999 * SERIES_GAP)
        outside = divided_difference(x, x + 1.001 * SERIES_GAP)
        slope = abs(divided_difference(x, x + 0.5 * SERIES_GAP) - divided_difference(x, x))
        assert abs(inside - outside) < 1e-12 + 2 * slope * 0.002 / 0.5


@pytest.mark.parametrize("kind", KINDS)
def test_the_window_bound_is_never_below_the_speed_reached(kind):
    """The bound over [t1, t1 + h] from the exact velocity at t1 covers the largest speed on a fine grid."""
    rng = np.random.default_rng(10 + KINDS.index(kind))
    for _ in range(30):
        static, record, gravity, amplitude, omega, omega_vector, _, v0, t0, tau = _case(rng, kind)
        accel = np.linalg.norm(gravity) + np.linalg.norm(amplitude)
        grid = np.linspace(0.0, tau, 1201)
        speeds = [np.linalg.norm(np.array(flown_velocity(*v0, s, static))
                                 + np.array(oscillating_velocity(t0, s, record))) for s in grid]
        bound = oscillating_window_speed(*v0, t0, tau, record, accel)
        assert bound >= max(speeds) * (1 - 1e-12)
        assert bound <= (np.linalg.norm(v0) + accel * tau) * (1 + 1e-9)  # never above the work bound


def test_the_window_bound_is_exact_for_a_window_holding_a_peak_of_the_field_without_b():
    """No B, no gravity: the speed's largest value over a window is reached (the bound is tight)."""
    record = oscillating_field(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 3.0]), 2.0)
    grid = np.linspace(0.0, 2.5, 20001)
    speeds = [np.linalg.norm(np.array([0.3, 0.0, 1.0]) + np.array(oscillating_velocity(0.4, s, record))) for s in grid]
    assert oscillating_window_speed(0.3, 0.0, 1.0, 0.4, 2.5, record, 3.0) == pytest.approx(max(speeds), rel=1e-6)


def test_the_static_flight_at_any_angle_solves_the_equation_of_motion():
    """The static record at an oblique angle (E along z, B in the y-z plane): exact gyration plus drift."""
    rng = np.random.default_rng(3)
    for _ in range(10):
        psi = rng.uniform(0.0, math.pi)
        omega_vector = rng.uniform(0.2, 3.0) * np.array([0.0, math.sin(psi), math.cos(psi)])
        acceleration = np.array([0.0, 0.0, rng.uniform(-2.0, 2.0)])
        field = derived_field(acceleration, omega_vector)
        x0, v0, tau = rng.normal(size=3), rng.normal(size=3), rng.uniform(0.1, 5.0)
        solution = solve_ivp(_ode(acceleration, np.zeros(3), 1.0, omega_vector), (0.0, tau),
                             np.concatenate([x0, v0]), method="DOP853", rtol=1e-12, atol=1e-13)
        np.testing.assert_allclose(flown_velocity(*v0, tau, field), solution.y[3:, -1], atol=1e-9 * (1 + tau))
        np.testing.assert_allclose(flown_position(*x0, *v0, tau, field), solution.y[:3, -1], atol=1e-9 * (1 + tau) ** 2)
