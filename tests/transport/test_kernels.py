"""Kernel-level checks: random streams, exact free flight, angular sampling, rate bounds."""

import math

import numpy as np
import pytest
from scipy import constants, stats
from scipy.integrate import solve_ivp

from collisionkit._kernels import transport as K
from collisionkit.transport import Gas, Process, Species, reid_ramp, screened_coulomb_momentum_ratio
from collisionkit.transport._tables import build_tables


def _state(seed=1):
    state = np.zeros(4, np.uint64)
    K.seed_state(np.uint64(seed), state)
    return state


def test_uniform_stream_has_the_right_moments_and_never_returns_zero():
    state = _state()
    values = np.array([K.uniform(state) for _ in range(200_000)])
    assert values.min() > 0.0 and values.max() < 1.0
    assert abs(values.mean() - 0.5) < 5 * math.sqrt(1 / 12 / values.size)
    assert abs(values.var() - 1 / 12) < 0.002


def test_exact_gyration_matches_numerical_integration():
    acceleration = np.array([1.0, -2.0, 3.0])
    omega = np.array([0.3, 1.1, -0.7])
    field = K.derived_field(acceleration, omega)
    pos, vel = np.array([0.1, 0.2, 0.3]), np.array([1.0, 0.5, -0.2])

    def rhs(_, y):
        return np.concatenate([y[3:], acceleration + np.cross(y[3:], omega)])

    solution = solve_ivp(rhs, (0, 7.3), np.concatenate([pos, vel]), rtol=1e-11, atol=1e-12)
    K.fly(pos, vel, 7.3, field)
    np.testing.assert_allclose(np.concatenate([pos, vel]), solution.y[:, -1], rtol=1e-8, atol=1e-8)


def test_screened_coulomb_sampling_has_the_analytic_mean_cosine():
    state = _state(3)
    energy, screening = 2.0, 1.0
    samples = np.array([K.scattering_cosine(K.SCREENED_COULOMB, energy, screening, state) for _ in range(200_000)])
    expected = screened_coulomb_momentum_ratio(energy, screening)
    error = samples.std() / math.sqrt(samples.size)
    assert abs(np.mean(1 - samples) - expected) < 5 * error


def test_rate_bound_is_never_below_the_true_rate():
    gas = Gas.mixture({reid_ramp(): 0.6, Gas((Species("x", 1e-26, (
        Process("elastic", [0, 1, 3, 50], [1e-19, 3e-19, 5e-20, 2e-20]),
        Process("excitation", [1.5, 4, 50], [2e-20, 1e-19, 0.0], threshold=1.5))),)): 0.4})
    tables = build_tables(gas, constants.m_e, 0.0)
    energies = np.concatenate([np.linspace(0, 120, 20001), [0.2, 1.5, 3.0]]) * constants.e
    for s in range(2):
        for energy in energies:
            speed = math.sqrt(2 * energy / constants.m_e)
            i = K.node_index(energy, tables.nodes, tables.accelerator, tables.accelerator_step)
            rate = sum(K.cross_section(j, energy, i, tables.nodes, tables.sigma) * speed + tables.const_rate[j]
                       for j in range(tables.kind.size)
                       if tables.species_of[j] == s and energy >= tables.threshold[j])
            bound = K.rate_bound(s, speed, tables.bound, tables.bound_step, tables.sigma_max, tables.const_max)
            assert bound >= rate * (1 - 1e-12)


def test_slab_elastic_energy_loss_matches_the_mass_ratio_law():
    state = _state(5)
    a = 12.0
    energies = np.array([K._elastic_lab(1.0, 1.0, a, state)[1] for _ in range(100_000)])
    alpha = ((a - 1) / (a + 1)) ** 2
    assert energies.min() >= alpha - 1e-12 and energies.max() <= 1 + 1e-12
    assert abs(energies.mean() - (1 + alpha) / 2) < 5 * energies.std() / math.sqrt(energies.size)


@pytest.mark.parametrize("bad", [-1.0, math.nan])
def test_tables_refuse_bad_cross_sections(bad):
    with pytest.raises(ValueError, match="cross_section"):
        Process("elastic", [0, 1], [1e-20, bad])


def _ionize_many(sharing, draws=20_000, energy_ev=40.0, threshold_ev=15.0):
    """Energies (eV) of the primary and the new electron after ionizing collisions on a target at rest."""
    mass = constants.m_e
    energy = energy_ev * constants.e
    kind = np.array([K.IONIZATION])
    threshold = np.array([threshold_ev * constants.e])
    angular = np.array([K.ISOTROPIC])
    screening = np.array([1.0])
    state = np.zeros(4, dtype=np.uint64)
    K.seed_state(np.uint64(12345), state)
    gas_v = np.zeros(3)
    speed = math.sqrt(2 * energy / mass)
    primary, secondary = np.empty(draws), np.empty(draws)
    for n in range(draws):
        vel = np.array([0.0, 0.0, speed])
        g = vel.copy()
        child = np.zeros(3)
        outcome = K._collide(0, vel, gas_v, g, speed, energy, mass, 1e3 * mass, kind, threshold, angular,
                             screening, sharing, state, child, np.zeros(16))
        assert outcome == 2
        primary[n] = 0.5 * mass * vel @ vel / constants.e
        secondary[n] = 0.5 * mass * child @ child / constants.e
    return primary, secondary


def test_ionization_shares_the_energy_left_above_the_threshold():
    primary, secondary = _ionize_many(K.SHARE_EQUAL, draws=200)
    np.testing.assert_allclose(primary, 12.5, rtol=1e-12)
    np.testing.assert_allclose(secondary, 12.5, rtol=1e-12)
    primary, secondary = _ionize_many(K.SHARE_UNIFORM)
    np.testing.assert_allclose(primary + secondary, 25.0, rtol=1e-12)  # energy conserved
    assert stats.kstest(primary / 25.0, "uniform").pvalue > 1e-3  # the primary's share is uniform
