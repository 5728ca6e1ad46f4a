"""Flights about the particular solution (:mod:`collisionkit._kernels.transport.particular`) against the ODE."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from collisionkit._kernels.transport.flight import derived_field
from collisionkit._kernels.transport.oscillating import flight_with_phases, oscillating_field
from collisionkit._kernels.transport.particular import (
    PARTICULAR_DETUNING, particular_flight, particular_position, particular_terms,
)


def _record(static_acceleration, omega_vector, amplitude, omega):
    return oscillating_field(derived_field(np.asarray(static_acceleration, float), np.asarray(omega_vector, float)),
                             np.asarray(amplitude, float), omega)


def _ode(record, x0, v0, t0, tau):
    a_s, b, w = record[0:3], record[3:6], record[12]
    a_c, omega = record[14:17], record[13]

    def rhs(t, y):
        v = y[3:]
        return np.concatenate([v, a_s + a_c * math.cos(omega * t) + np.cross(v, w * b)])

    solution = solve_ivp(rhs, (t0, t0 + tau), np.concatenate([x0, v0]), method="DOP853", rtol=1e-13, atol=1e-14)
    return solution.y[:3, -1], solution.y[3:, -1]


def _fly(record, x0, v0, t0, tau):
    use, k_s, k_c = particular_terms(record)
    assert use
    c0, s0 = math.cos(record[13] * t0), math.sin(record[13] * t0)
    u0 = np.asarray(v0) - (s0 * np.asarray(k_s) + c0 * np.asarray(k_c))
    out = particular_flight(*u0, c0, s0, tau, k_s, k_c, record)
    position = particular_position(*x0, *u0, c0, s0, tau, *out[5:9], k_s, k_c, record)
    return np.array(position), np.array(out[:3]), out[3:5]


@pytest.mark.parametrize("angle", [90.0, 60.0, 20.0])
@pytest.mark.parametrize("ratio", [0.3, 0.57, 0.98, 1.5, 4.0])  # |Omega| / omega, incl. 2 % off resonance
@pytest.mark.parametrize("gravity", [False, True])
def test_flights_about_the_particular_solution_solve_the_equation_of_motion(angle, ratio, gravity):
    """dv/dt = a_s + a_c cos(omega t) + v x Omega integrated by DOP853 (rtol 1e-13): velocity, position and the
    phase at the end agree for short and long flights at any phase, 2 % off resonance included."""
    rng = np.random.default_rng(int(angle * 100 + ratio * 10 + gravity))
    omega = 1.3
    psi = math.radians(angle)
    record = _record([0.2, -0.1, 0.3] if gravity else [0.0, 0.0, 0.0],
                     ratio * omega * np.array([0.0, math.sin(psi), math.cos(psi)]), [0.0, 0.0, 2.0], omega)
    for tau in (1e-7, 0.05, 0.9, 3.0, 17.0):
        x0, v0, t0 = rng.normal(size=3), rng.normal(size=3), rng.uniform(0.0, 10.0)
        position, velocity, (c1, s1) = _fly(record, x0, v0, t0, tau)
        ode_position, ode_velocity = _ode(record, x0, v0, t0, tau)
        scale = 1.0 + tau
        np.testing.assert_allclose(velocity, ode_velocity, rtol=0, atol=2e-10 * scale)
        np.testing.assert_allclose(position, ode_position, rtol=0, atol=2e-10 * scale * scale)
        assert c1 == pytest.approx(math.cos(omega * (t0 + tau)), abs=1e-12)
        assert s1 == pytest.approx(math.sin(omega * (t0 + tau)), abs=1e-12)


def test_short_flights_agree_with_the_complex_response_to_round_off():
    """omega tau 1e-9 to 1: the particular form and :func:`flight_with_phases` (the response from rest) agree to
    1e-14 of the speeds involved, and the displacement keeps its first order (no cancellation)."""
    omega = 1.0
    record = _record([0.0, 0.0, 0.0], 0.57 * omega * np.array([0.0, math.sin(1.0), math.cos(1.0)]),
                     [0.0, 0.0, 2.0], omega)
    use, k_s, k_c = particular_terms(record)
    v0 = np.array([0.3, -0.2, 0.5])
    for tau in (1e-9, 1e-6, 1e-3, 0.1, 1.0):
        c0, s0 = math.cos(0.4), math.sin(0.4)
        u0 = v0 - (s0 * np.asarray(k_s) + c0 * np.asarray(k_c))
        out = particular_flight(*u0, c0, s0, tau, k_s, k_c, record)
        reference = flight_with_phases(*v0, c0, s0, tau, record)
        speeds = np.abs(v0).max() + np.abs(k_s).max() + np.abs(k_c).max()
        np.testing.assert_allclose(out[:3], reference[:3], rtol=0, atol=1e-14 * speeds)
        moved = np.array(particular_position(0.0, 0.0, 0.0, *u0, c0, s0, tau, *out[5:9], k_s, k_c, record))
        # to first order the displacement is v0 tau: a cancelling form would lose it for tau 1e-9
        np.testing.assert_allclose(moved, v0 * tau, rtol=0, atol=2.0 * tau * tau * speeds + 1e-16 * tau)


def test_the_particular_form_is_off_near_resonance_and_without_b():
    omega = 2.0
    near = _record([0.0, 0.0, 0.0], [0.0, (1.0 + 0.5 * PARTICULAR_DETUNING) * omega, 0.0], [0.0, 0.0, 1.0], omega)
    assert not particular_terms(near)[0]
    assert particular_terms(_record([0.0, 0.0, 0.0], [0.0, (1.0 + 2 * PARTICULAR_DETUNING) * omega, 0.0],
                                    [0.0, 0.0, 1.0], omega))[0]
    assert not particular_terms(_record([0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0], omega))[0]
    assert not particular_terms(derived_field(np.zeros(3), np.array([0.0, 1.0, 0.0])))[0]
