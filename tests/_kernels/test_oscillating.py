"""Exact flight in E0 cos(omega t) with a static B at any angle, and the speed bound of a flight window.

Independent check: the equation of motion dv/dt = a_s + a_c cos(omega t) + v x Omega integrated numerically
(scipy solve_ivp, DOP853 at rtol 1e-12).
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from collisionkit._kernels.transport.flight import derived_field, flown_position, flown_velocity
from collisionkit._kernels.transport.ac_window import oscillating_window
from collisionkit._kernels.transport.oscillating import (
    SERIES_GAP, divided_difference, oscillating_displacement, oscillating_field, oscillating_flown_velocity,
)


def _velocity(v0, t0, tau, record):
    """The velocity after tau from v0 at time t0 (and the phase omega (t0 + tau) as cos, sin)."""
    omega = record[13]
    vx, vy, vz, c1, s1 = oscillating_flown_velocity(*v0, math.cos(omega * t0), math.sin(omega * t0), tau, record)
    return np.array([vx, vy, vz]), (c1, s1)


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
        velocity, (c1, s1) = _velocity(v0, t0, tau, record)
        assert (c1, s1) == pytest.approx((math.cos(omega * (t0 + tau)), math.sin(omega * (t0 + tau))), abs=1e-12)
        position = (np.array(flown_position(*x0, *v0, tau, static))
                    + np.array(oscillating_displacement(math.cos(omega * t0), math.sin(omega * t0), tau, record)))
        np.testing.assert_allclose(velocity, solution.y[3:, -1], rtol=0, atol=1e-9 * (1 + tau))
        np.testing.assert_allclose(position, solution.y[:3, -1], rtol=0, atol=1e-9 * (1 + tau) ** 2)


def test_at_resonance_the_perpendicular_response_grows_linearly():
    """omega = Omega, E perpendicular to B, from rest at t0 = 0: |w| = (A/2) t for t >> 1/omega (secular growth)."""
    record = oscillating_field(derived_field(np.zeros(3), np.array([0.0, 2.0, 0.0])), np.array([0.0, 0.0, 1.0]), 2.0)
    tau = 200 * math.pi  # 200 periods
    speed = np.linalg.norm(_velocity(np.zeros(3), 0.0, tau, record)[0])
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
        _, record, gravity, amplitude, omega, omega_vector, _, v0, t0, tau = _case(rng, kind)
        accel = np.linalg.norm(gravity) + np.linalg.norm(amplitude)
        grid = np.linspace(0.0, tau, 1201)
        speeds = [np.linalg.norm(_velocity(v0, t0, s, record)[0]) for s in grid]
        bound, *end = oscillating_window(*v0, math.cos(omega * t0), math.sin(omega * t0), omega * t0, tau, record,
                                         accel)
        velocity, rotor = _velocity(v0, t0, tau, record)
        np.testing.assert_allclose(end, [*velocity, *rotor], rtol=0, atol=1e-15 * (1 + np.abs(velocity).max()))
        assert bound >= max(speeds) * (1 - 1e-12)
        assert bound <= (np.linalg.norm(v0) + accel * tau) * (1 + 1e-9)  # never above the work bound


def test_the_window_bound_is_exact_for_a_window_holding_a_peak_of_the_field_without_b():
    """No B, no gravity: the speed's largest value over a window is reached (the bound is tight)."""
    record = oscillating_field(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 3.0]), 2.0)
    grid = np.linspace(0.0, 2.5, 20001)
    speeds = [np.linalg.norm(_velocity(np.array([0.3, 0.0, 1.0]), 0.4, s, record)[0]) for s in grid]
    bound = oscillating_window(0.3, 0.0, 1.0, math.cos(0.8), math.sin(0.8), 0.8, 2.5, record, 3.0)[0]
    assert bound == pytest.approx(max(speeds), rel=1e-6)


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


@pytest.mark.parametrize("name", ["sincos", "sincos_spread"])
def test_sincos_agrees_with_the_library_to_a_few_ulp(name):
    from collisionkit._kernels.transport import oscillating

    sincos = getattr(oscillating, name)
    rng = np.random.default_rng(7)
    for x in np.concatenate([rng.uniform(-10, 10, 2000), rng.uniform(-1e5, 1e5, 2000), [0.0, -0.0, math.pi / 4, -math.pi / 4, 1e-300, -1e-300]]):
        s, c = sincos(x)
        assert abs(s - math.sin(x)) <= 4e-16 * max(1.0, abs(x) * 1e-5) + 2e-16 * abs(math.sin(x))
        assert abs(c - math.cos(x)) <= 4e-16 * max(1.0, abs(x) * 1e-5) + 2e-16 * abs(math.cos(x))


def test_the_parallel_displacement_is_free_of_cancellation_for_short_flights():
    """omega tau from 1e-9 to 10, no B: the closed form against the double integral of cos by quadrature."""
    from scipy.integrate import quad

    record = oscillating_field(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 1.0]), 1.0)
    for tau in (1e-9, 1e-4, 0.3, 0.49, 0.51, 2.0, 10.0):
        for t0 in (0.0, 1.0, 2.5):
            # sin(t0 + u) - sin(t0) = 2 cos(t0 + u/2) sin(u/2): an integrand free of cancellation
            exact = quad(lambda u: 2 * math.cos(t0 + u / 2) * math.sin(u / 2), 0.0, tau, epsabs=0, epsrel=1e-13)[0]
            value = oscillating_displacement(math.cos(t0), math.sin(t0), tau, record)[2]
            assert value == pytest.approx(exact, rel=1e-11, abs=1e-13 * tau * tau)


def test_the_series_of_phi1_agrees_with_its_closed_form():
    """Against sin(x)/x + i 2 sin(x/2)^2/x from the library's sine (no cancellation, a few ulp)."""
    from collisionkit._kernels.transport.oscillating import PHI1_SERIES, _phi1_series, phi1

    for x in np.linspace(-PHI1_SERIES, PHI1_SERIES, 101):
        exact = 1.0 if x == 0 else complex(math.sin(x) / x, 2 * math.sin(x / 2) ** 2 / x)
        assert abs(_phi1_series(x) - exact) < 4e-16
        assert abs(phi1(x) - exact) < 4e-16
