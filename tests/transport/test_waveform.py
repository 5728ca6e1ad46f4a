"""Swarms in a periodic field of any shape given as samples (transport/_waveform.py and simulate_swarm(waveform=)).

Exact references for the Maxwell model (constant collision frequency nu, nu' = mu nu / m): the mean velocity obeys
m dW/dt = q E0 f(t/T) - m nu' W exactly. Its periodic solution for
* a square wave (f = +1 on the first half period, -1 on the second): W = W_inf + (W0 - W_inf) e^{-nu' t} on the first
  half, W_inf = q E0/(m nu'), W0 = -W_inf tanh(nu' T / 4), and W(t + T/2) = -W(t);
* a sawtooth f = 2 t/T - 1 on [0, T): W = W_p(t) + C e^{-nu' t}, W_p = (q E0/(m nu'))(2 t/T - 1) - 2 q E0/(m T nu'^2),
  C = (2 q E0/(m nu')) / (1 - e^{-nu' T}) (W(T) = W(0)).
A cosine sampled at 256 points reproduces the E0 cos(omega t) swarm (test_periodic.py) within the errors.
"""

import math
import warnings

import numpy as np
import pytest

from collisionkit.transport import maxwell_model, read_waveform, simulate_swarm
from collisionkit.transport._waveform import half_wave_antisymmetric, waveform_knots, waveform_rms
from collisionkit.transport.swarm import REFERENCE_DENSITY, TOWNSEND

from .test_periodic import LIGHT_GAS, ME, NU_PRIME, RATE, E, _agree, _maxwell_ac

KAPPA = -E * 10.0 * TOWNSEND * REFERENCE_DENSITY / ME  # q E0 / m at 10 Td
SQUARE = [(0.0, 1.0), (0.5, 1.0), (0.5, -1.0), (1.0, -1.0)]
SAWTOOTH = [(0.0, -1.0), (1.0, 1.0)]


def _run(waveform, omega, seed, monkeypatch):
    from collisionkit.transport import swarm

    monkeypatch.setattr(swarm, "CHECK_BOUND", True)
    r = simulate_swarm(maxwell_model(RATE, mass=LIGHT_GAS), 10.0, reduced_frequency=omega / REFERENCE_DENSITY,
                       waveform=waveform, gas_temperature=0.0, particles=2000, seed=seed, threads=2,
                       tolerances={"mean_energy": 6e-3})
    assert r.converged and r.extras["bound_violations"] == 0
    return r


def _square(t, period):
    w_inf = KAPPA / NU_PRIME
    w0 = -w_inf * math.tanh(NU_PRIME * period / 4)
    half = np.mod(t, period) >= period / 2
    s = np.mod(t, period / 2)
    return np.where(half, -1.0, 1.0) * (w_inf + (w0 - w_inf) * np.exp(-NU_PRIME * s))


def _sawtooth(t, period):
    s = np.mod(t, period)
    particular = KAPPA / NU_PRIME * (2 * s / period - 1) - 2 * KAPPA / (period * NU_PRIME**2)
    return particular + 2 * KAPPA / NU_PRIME / (1 - math.exp(-NU_PRIME * period)) * np.exp(-NU_PRIME * s)


def test_the_analytic_solutions_solve_the_momentum_balance():
    """Against a direct numerical integration of dW/dt = kappa f - nu' W over ten periods (periodic state)."""
    from scipy.integrate import solve_ivp

    period = 2 * math.pi / NU_PRIME
    for shape, exact in ((SQUARE, _square), (SAWTOOTH, _sawtooth)):
        knots, values = waveform_knots(shape)
        f = lambda t: np.interp(np.mod(t / period, 1.0), knots, values)  # noqa: E731 (no jump inside np.interp's pieces)
        w0 = exact(np.array([1e-9 * period]), period)[0]
        t = np.linspace(0.0, period, 7)[1:-1] + 10 * period
        solution = solve_ivp(lambda s, w: KAPPA * f(s) - NU_PRIME * w, (0.0, t[-1]), [w0], t_eval=t, rtol=1e-10,
                             atol=1e-6, max_step=period / 400)
        np.testing.assert_allclose(solution.y[0], exact(t, period), rtol=1e-5, atol=1e-5 * abs(KAPPA / NU_PRIME))


@pytest.mark.parametrize("shape, exact, seed", [(SQUARE, _square, 11), (SAWTOOTH, _sawtooth, 12)])
def test_maxwell_model_velocity_follows_the_exact_cycle_of_a_square_and_a_sawtooth_wave(shape, exact, seed,
                                                                                         monkeypatch):
    omega = NU_PRIME
    r = _run(shape, omega, seed, monkeypatch)
    period = 2 * math.pi / omega
    expected = exact(r.phases / omega, period)
    assert np.abs(expected).max() > 30 * r.drift_velocity_flux_by_phase_error[:, 2].max()  # a resolved cycle
    assert _agree(r.drift_velocity_flux_by_phase[:, 2], r.drift_velocity_flux_by_phase_error[:, 2], expected)
    assert _agree(r.drift_velocity_flux_by_phase[:, :2], r.drift_velocity_flux_by_phase_error[:, :2], 0.0)
    assert r.extras["waveform"] == [list(pair) for pair in shape]


def test_a_sampled_cosine_reproduces_the_cosine_field(monkeypatch):
    """256 samples of cos(2 pi u): the linear pieces differ from the cosine by at most (2 pi/256)^2/8 = 8e-5."""
    omega = NU_PRIME
    samples = [(k / 256, math.cos(2 * math.pi * k / 256)) for k in range(256)]
    r = _run(samples, omega, 13, monkeypatch)
    amplitude, energy = _maxwell_ac(10.0, omega)
    expected = np.real(amplitude[None, :] * np.exp(1j * r.phases)[:, None])
    assert _agree(r.drift_velocity_flux_by_phase, r.drift_velocity_flux_by_phase_error, expected)
    assert _agree(r.mean_energy_by_phase, r.mean_energy_by_phase_error, energy(r.phases))


def test_the_samples_are_checked_and_described():
    gas = maxwell_model(RATE, mass=LIGHT_GAS)
    for bad, match in (([(0.0, 1.0)], "2 to"), ([(0.5, 1.0), (0.2, 0.0)], "non-decreasing"),
                       ([(0.0, 0.0), (1.0, 0.0)], "all be zero"), ([(0.0, 1.0), (1.5, 0.0)], "from 0 to 1"),
                       ([(0.0, 1.0), (0.5, 1.0), (0.5, 0.0), (0.5, 2.0)], "three times"),
                       ([(0.0, float("nan")), (1.0, 1.0)], "finite"), ("square", "pairs")):
        with pytest.raises(ValueError, match=match):
            simulate_swarm(gas, 10.0, reduced_frequency=1e-13, waveform=bad)
    with pytest.raises(ValueError, match="reduced_frequency > 0"):
        simulate_swarm(gas, 10.0, waveform=SQUARE)
    assert waveform_rms(SQUARE) == 1.0 and waveform_rms(SAWTOOTH) == pytest.approx(1 / math.sqrt(3), rel=1e-15)
    assert waveform_rms([(k / 4, math.cos(math.pi * k / 2)) for k in range(4)]) == pytest.approx(math.sqrt(1 / 3))
    assert half_wave_antisymmetric(SQUARE) and not half_wave_antisymmetric(SAWTOOTH)
    assert half_wave_antisymmetric([(k / 8, math.cos(math.pi * k / 4)) for k in range(8)])
    assert not half_wave_antisymmetric([(k / 8, abs(math.cos(math.pi * k / 4))) for k in range(8)])


@pytest.mark.parametrize("text", ["", "# u  E/E0\n", "\n\n"])
def test_a_waveform_file_without_samples_is_refused_in_one_line_without_a_warning(text, tmp_path):
    path = tmp_path / "empty.txt"
    path.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match="empty.txt holds no samples"):
            read_waveform(path)
