"""The two-term equation in a high-frequency field E0 cos(omega t): the effective field of the Maxwell model, the
static limit, and the Monte Carlo swarm in the same oscillating field."""

import math

import pytest

from collisionkit.transport import hard_sphere_gas, maxwell_model, simulate_swarm, two_term_boltzmann

from .test_two_term import maxwell_exact


@pytest.mark.parametrize("omega_N", [1e-14, 1e-13, 1e-12])
def test_the_maxwell_model_heats_as_its_effective_field(omega_N):
    """A constant collision frequency nu = N k: a fast field of amplitude E0 heats as the DC field
    E_eff = (E0 / sqrt 2) nu / sqrt(nu^2 + omega^2) (Margenau, Phys. Rev. 69, 508 (1946)), so the distribution
    is the Maxwellian of kT_e = kT + (M/3)(e E_eff/(m nu))^2 / e (written out in test_two_term): to 1e-5 at
    1000 cells, as the DC case."""
    k = 1e-13
    effective = 10.0 / math.sqrt(2.0) * k / math.sqrt(k * k + omega_N * omega_N)
    result = two_term_boltzmann(maxwell_model(k), 10.0, 300.0, omega_N=omega_N)
    assert result.mean_energy == pytest.approx(maxwell_exact(k, effective, 300.0)[0], rel=1e-5)
    assert result.omega_N == omega_N and abs(result.power_balance) < 3e-4


def test_a_slow_oscillation_heats_as_the_rms_field():
    """omega -> 0: the mean square of E0 cos(omega t) is E0^2 / 2, so the result is the DC one at E0 / sqrt 2."""
    slow = two_term_boltzmann(hard_sphere_gas(), 10.0, 0.0, omega_N=1e-20)
    static = two_term_boltzmann(hard_sphere_gas(), 10.0 / math.sqrt(2.0), 0.0)
    assert slow.mean_energy == pytest.approx(static.mean_energy, rel=1e-9)
    assert slow.mobility_N == pytest.approx(static.mobility_N, rel=1e-9)


@pytest.mark.slow
def test_the_monte_carlo_swarm_in_the_same_oscillating_field_agrees():
    """Helium-mass hard spheres (6e-20 m^2) at 10 Td amplitude, omega/N = 1e-14 rad m^3/s, gas at 0 K: omega is
    comparable to the momentum-transfer frequency (about 6e-14 N) and 600 times the energy relaxation frequency
    (2 m/M of it), so the distribution is steady over a period (the swarm's mean energy by phase varies by
    0.25 %) and the two-term equation is exact to O(m/M) = 1.4e-4. The swarm's cycle-averaged mean energy must
    agree within 4 standard errors plus 2e-4. Measured 4.2818 +- 0.0085 eV against 4.2657 eV (1.9 sigma; DC at
    the amplitude: 6.08 eV); ~25 s."""
    gas = hard_sphere_gas()
    swarm = simulate_swarm(gas, 10.0, reduced_frequency=1e-14, gas_temperature=0.0, particles=4000, seed=3,
                           threads=2, tolerances={"mean_energy": 2e-3})
    result = two_term_boltzmann(gas, 10.0, 0.0, omega_N=1e-14)
    assert abs(swarm.mean_energy - result.mean_energy) < 4.0 * swarm.mean_energy_error + 2e-4 * result.mean_energy
    assert result.mean_energy < 0.75 * two_term_boltzmann(gas, 10.0, 0.0).mean_energy


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"omega_N": -1e-14}, "omega_N"),
    ({"omega_N": 1e-3}, "omega_N"),
    ({"omega_N": 1e-14, "growth": "spatial"}, "growth='spatial'"),
])
def test_bad_high_frequency_inputs_are_named(kwargs, message):
    with pytest.raises(ValueError, match=message):
        two_term_boltzmann(hard_sphere_gas(), 10.0, 0.0, **kwargs)
