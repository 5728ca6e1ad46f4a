"""Swarms in a periodic field given as samples with a static B at any angle (simulate_swarm(waveform=, B)).

Exact reference for the Maxwell model (constant collision frequency nu, nu' = mu nu / m): the mean velocity obeys
m dW/dt = q E0 f(t/T) z + q W x B - mu nu W exactly, a linear periodic equation whose periodic solution is found here
independently, by numerical integration (scipy solve_ivp, restarted at the jumps) over enough periods for the start
to be forgotten (e^{-nu' t} below 1e-12). A cosine sampled at 256 points in B at 60 degrees reproduces the exact AC
cycle of the Maxwell model (test_periodic.py) and, on Reid's ramp, the swarm of the cosine field itself.
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from collisionkit.transport import maxwell_model, reid_ramp, simulate_swarm
from collisionkit.transport.swarm import HUXLEY, REFERENCE_DENSITY, TOWNSEND, magnetic_direction

from .test_periodic import LIGHT_GAS, ME, NU_PRIME, RATE, E, _agree, _maxwell_ac
from .test_waveform import KAPPA, SQUARE

COSINE = [(k / 256, math.cos(2 * math.pi * k / 256)) for k in range(256)]


def _run(gas, waveform, omega, b_over_n, angle, seed, monkeypatch, tolerance=6e-3, particles=2000):
    from collisionkit.transport import swarm

    monkeypatch.setattr(swarm, "CHECK_BOUND", True)
    r = simulate_swarm(gas, 10.0, reduced_frequency=omega / REFERENCE_DENSITY, waveform=waveform,
                       reduced_magnetic_field=b_over_n, field_angle=angle, gas_temperature=0.0, particles=particles,
                       seed=seed, threads=2, tolerances={"mean_energy": tolerance})
    assert r.converged and r.extras["bound_violations"] == 0
    return r


def _square_with_b(times, period, b_over_n, angle):
    """The periodic W(t) of dW/dt = kappa f(t) z + W x Omega - nu' W for the square wave, by solve_ivp."""
    omega = -E * b_over_n * HUXLEY * REFERENCE_DENSITY / ME * magnetic_direction(angle)
    z = np.array([0.0, 0.0, 1.0])
    cycles = math.ceil(28.0 / (NU_PRIME * period))  # e^{-28} < 1e-12
    w = np.zeros(3)
    for n in range(cycles):
        for sign, start in ((1.0, 0.0), (-1.0, 0.5)):
            span = (n * period + start * period, n * period + (start + 0.5) * period)
            w = solve_ivp(lambda t, y: sign * KAPPA * z + np.cross(y, omega) - NU_PRIME * y, span, w,
                          method="DOP853", rtol=1e-11, atol=1e-9 * abs(KAPPA / NU_PRIME)).y[:, -1]
    values = []
    for t in np.mod(times, period):  # from the periodic state at the start of a period
        state = w
        for sign, start in ((1.0, 0.0), (-1.0, 0.5)):
            end = min(t, (start + 0.5) * period)
            if end > start * period:
                state = solve_ivp(lambda s, y: sign * KAPPA * z + np.cross(y, omega) - NU_PRIME * y,
                                  (start * period, end), state, method="DOP853", rtol=1e-11,
                                  atol=1e-9 * abs(KAPPA / NU_PRIME)).y[:, -1]
        values.append(state)
    return np.array(values)


def test_the_numerical_reference_is_periodic_and_reduces_to_the_closed_form_without_b():
    from .test_waveform import _square

    period = 2 * math.pi / NU_PRIME
    times = np.linspace(0.0, period, 9)[:-1] + 0.01 * period
    np.testing.assert_allclose(_square_with_b(times, period, 0.0, 90.0)[:, 2], _square(times, period),
                               rtol=1e-7, atol=1e-8 * abs(KAPPA / NU_PRIME))
    with_b = _square_with_b(times, period, 300.0, 60.0)
    np.testing.assert_allclose(_square_with_b(times + period / 2, period, 300.0, 60.0), -with_b,
                               rtol=1e-7, atol=1e-8 * abs(KAPPA / NU_PRIME))  # W(t + T/2) = -W(t)
    assert np.abs(with_b[:, 0]).max() > 0.1 * np.abs(with_b[:, 2]).max()  # B turns W out of the E direction


@pytest.mark.parametrize("b_over_n, angle, seed", [(300.0, 60.0, 21), (300.0, 90.0, 22)])
def test_maxwell_model_velocity_follows_the_momentum_balance_of_a_square_wave_with_b(b_over_n, angle, seed,
                                                                                     monkeypatch):
    omega = NU_PRIME
    r = _run(maxwell_model(RATE, mass=LIGHT_GAS), SQUARE, omega, b_over_n, angle, seed, monkeypatch)
    expected = _square_with_b(r.phases / omega, 2 * math.pi / omega, b_over_n, angle)
    assert np.abs(expected).max() > 30 * r.drift_velocity_flux_by_phase_error.max()  # a resolved cycle
    assert _agree(r.drift_velocity_flux_by_phase, r.drift_velocity_flux_by_phase_error, expected)
    assert r.field_angle == angle and r.extras["waveform"] == [list(pair) for pair in SQUARE]


def test_a_sampled_cosine_with_b_follows_the_exact_ac_cycle(monkeypatch):
    """B/N = 517 Hx at 60 degrees: |Omega| = 0.9996 omega, cyclotron resonance (secular terms of the flight)."""
    omega = NU_PRIME
    r = _run(maxwell_model(RATE, mass=LIGHT_GAS), COSINE, omega, 517.0, 60.0, 31, monkeypatch)
    amplitude, energy = _maxwell_ac(10.0, omega, 517.0, 60.0)
    expected = np.real(amplitude[None, :] * np.exp(1j * r.phases)[:, None])
    assert _agree(r.drift_velocity_flux_by_phase, r.drift_velocity_flux_by_phase_error, expected)
    assert _agree(r.mean_energy_by_phase, r.mean_energy_by_phase_error, energy(r.phases))


def test_a_sampled_cosine_with_oblique_b_reproduces_the_cosine_swarm_on_reids_ramp(monkeypatch):
    """Two independent runs, the cosine field and its 256 samples (B/N = 200 Hx at 30 degrees): the same cycle of
    <e> and W within their combined errors."""
    omega = 2e-14 * REFERENCE_DENSITY
    sampled = _run(reid_ramp(), COSINE, omega, 200.0, 30.0, 24, monkeypatch, tolerance=5e-3, particles=4000)
    cosine = _run(reid_ramp(), None, omega, 200.0, 30.0, 25, monkeypatch, tolerance=5e-3, particles=4000)
    for name in ("mean_energy_by_phase", "drift_velocity_flux_by_phase"):
        a, b = getattr(sampled, name), getattr(cosine, name)
        errors = np.hypot(getattr(sampled, name + "_error"), getattr(cosine, name + "_error"))
        assert _agree(a, errors, b), name
    assert abs(sampled.mean_energy - cosine.mean_energy) < 4 * math.hypot(sampled.mean_energy_error,
                                                                          cosine.mean_energy_error)


@pytest.mark.parametrize("b_over_n, angle", [(0.0, 90.0), (200.0, 60.0), (1000.0, 90.0)])
def test_the_window_bound_holds_on_reids_ramp_with_jumps(b_over_n, angle, monkeypatch):
    """A speed-dependent rate (Reid's ramp) in a waveform with jumps, without and with B (the windows' bound from the
    flight's constants, waveform_window): no trial finds the true rate above the trial frequency."""
    from collisionkit.transport import swarm

    shape = [(0.1, 0.3), (0.2, -2.0), (0.2, 1.5), (0.65, 0.4), (0.9, 2.5)]
    monkeypatch.setattr(swarm, "CHECK_BOUND", True)
    r = simulate_swarm(reid_ramp(), 12.0, reduced_frequency=2e-14, waveform=shape, reduced_magnetic_field=b_over_n,
                       field_angle=angle, gas_temperature=0.0, particles=1000, seed=5, threads=2, collision_budget=2e6,
                       tolerances={"mean_energy": 1e-9})
    assert r.collisions >= 2e6 and r.extras["bound_violations"] == 0
