"""Tests of the cooling of inelastic mixtures (collisionkit.edmd.mixture_theory): rates and the cooling state.

The rates are checked against a direct Monte Carlo of the collision rule
(Maxwellian pairs, random contact normals: nothing of the closed form) and
against Haff's law of one species; the cooling state by its definition
(equal rates), equipartition and the symmetries of the species.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from collisionkit import edmd

ETA = st.floats(0.0, 0.45, allow_subnormal=False)
ALPHA = st.floats(0.0, 1.0)


def _unit_vectors(rng, samples, dim):
    normals = rng.normal(size=(samples, dim))
    return normals / np.linalg.norm(normals, axis=1, keepdims=True)


def _monte_carlo_rates(rng, eta, fractions, diameters, masses, alpha, temperatures, dim, samples):
    """zeta_i = -(2 / (d T_i)) sum_j n_j g_ij sigma_ij^(d-1) Omega_d E[max(g.n, 0) dE_i], by sampling the collisions.

    v_i, v_j Maxwellian at T_i, T_j, n uniform on the unit sphere (Omega_d its area), g = v_i - v_j towards j along
    n; the collision rule v_i' = v_i - mu_ji (1 + alpha_ij) (g.n) n. Returns the rates and their standard errors.
    """
    g = edmd.mixture_contact_values(eta, fractions, diameters, dim)
    volume = (math.pi / 6.0 if dim == 3 else math.pi / 4.0) * float(np.sum(fractions * diameters**dim))
    density = eta / volume
    sphere = 2.0 * math.pi ** (dim / 2.0) / math.gamma(dim / 2.0)
    rates, errors = np.zeros(len(fractions)), np.zeros(len(fractions))
    for i, j in np.ndindex(len(fractions), len(fractions)):
        vi = rng.normal(0.0, math.sqrt(temperatures[i] / masses[i]), size=(samples, dim))
        vj = rng.normal(0.0, math.sqrt(temperatures[j] / masses[j]), size=(samples, dim))
        normal = _unit_vectors(rng, samples, dim)
        approach = np.einsum("ij,ij->i", vi - vj, normal)
        kick = (masses[j] / (masses[i] + masses[j])) * (1.0 + alpha[i, j]) * approach
        after = vi - kick[:, None] * normal
        gain = 0.5 * masses[i] * (np.sum(after**2, axis=1) - np.sum(vi**2, axis=1))
        weighted = np.where(approach > 0.0, approach * gain, 0.0)
        factor = -2.0 / (dim * temperatures[i]) * density * fractions[j] * g[i, j] * sphere
        factor *= (0.5 * (diameters[i] + diameters[j])) ** (dim - 1)
        rates[i] += factor * weighted.mean()
        errors[i] = math.hypot(errors[i], factor * weighted.std() / math.sqrt(samples))
    return rates, errors


@pytest.mark.parametrize("dim", [2, 3])
def test_the_cooling_rates_are_those_of_the_collision_rule_sampled(dim):
    """Three species of unlike sizes, masses, temperatures and restitutions: the closed form within 5 of the Monte
    Carlo's standard errors (0.2 to 2.1 % of the rates), and a light hot species cooling fastest."""
    rng = np.random.default_rng(11)
    fractions, diameters = np.array([0.2, 0.3, 0.5]), np.array([1.0, 0.7, 0.5])
    masses, temperatures = np.array([2.0, 1.0, 0.3]), np.array([0.8, 1.0, 1.3])
    alpha = np.array([[0.9, 0.8, 0.6], [0.8, 0.95, 0.7], [0.6, 0.7, 0.5]])
    expected, errors = _monte_carlo_rates(rng, 0.2, fractions, diameters, masses, alpha, temperatures, dim, 2_000_000)
    rates = edmd.mixture_cooling_rates(0.2, fractions, diameters, masses, alpha, temperatures, dim)
    assert np.all(np.abs(rates - expected) < 5 * errors), (rates, expected, errors)
    assert np.all(errors < 0.03 * np.abs(expected))  # the test can tell a 15 % error in any rate
    assert np.argmax(rates) == 2


@pytest.mark.parametrize("dim", [2, 3])
@given(eta=ETA, alpha=ALPHA, fraction=st.floats(0.05, 0.95), kT=st.floats(0.01, 100.0), mass=st.floats(0.01, 100.0))
@settings(max_examples=30, deadline=None)
def test_alike_species_cool_by_haffs_law(dim, eta, alpha, fraction, kT, mass):
    """Two labels of one species: zeta = (1 - alpha^2) omega / d, omega Enskog's collision frequency (Haff's law,
    T = T0 exp(-2 (1 - e^2) C / (d N)) in collisions C), whatever the split."""
    fractions, diameters = [fraction, 1.0 - fraction], [1.0, 1.0]
    rates = edmd.mixture_cooling_rates(eta, fractions, diameters, mass, alpha, kT, dim)
    omega = edmd.mixture_collision_frequency(eta, fractions, diameters, mass, dim, kT)
    np.testing.assert_allclose(rates, (1.0 - alpha**2) * omega / dim, rtol=1e-12, atol=1e-14 * omega)


def test_elastic_pairs_neither_cool_nor_heat_at_equal_temperatures_and_share_heat_otherwise():
    """alpha = 1: no rate at equal temperatures; a hotter species gives heat to a colder one (opposite signs)."""
    arguments = (0.1, [0.4, 0.6], [1.0, 0.5], [1.0, 0.1], 1.0)
    np.testing.assert_allclose(edmd.mixture_cooling_rates(*arguments, [1.0, 1.0]), 0.0, atol=1e-14)
    hot_first = edmd.mixture_cooling_rates(*arguments, [2.0, 1.0])
    assert hot_first[0] > 0.0 > hot_first[1]


@pytest.mark.parametrize("dim", [2, 3])
@given(eta=ETA, alphas=st.lists(ALPHA, min_size=3, max_size=3), masses=st.lists(st.floats(0.01, 100.0), min_size=2,
                                                                                 max_size=2),
       diameters=st.lists(st.floats(0.1, 1.0), min_size=2, max_size=2), fraction=st.floats(0.05, 0.95))
@settings(max_examples=40, deadline=None)
def test_the_cooling_state_is_where_every_species_cools_at_one_rate(dim, eta, alphas, masses, diameters, fraction):
    """Any binary mixture: the rates are equal at the state's temperatures, whose mean over the fractions is 1; the
    species swapped, so are the temperatures."""
    fractions = [fraction, 1.0 - fraction]
    alpha = [[alphas[0], alphas[1]], [alphas[1], alphas[2]]]
    theta = edmd.homogeneous_cooling_temperatures(eta, fractions, diameters, masses, alpha, dim)
    assert np.sum(np.asarray(fractions) * theta) == pytest.approx(1.0, rel=1e-12)
    rates = edmd.mixture_cooling_rates(eta, fractions, diameters, masses, alpha, theta, dim)
    assert np.ptp(rates) <= 1e-8 * np.max(np.abs(rates)) + 1e-12
    swapped = edmd.homogeneous_cooling_temperatures(eta, fractions[::-1], diameters[::-1], masses[::-1],
                                                    [row[::-1] for row in alpha[::-1]], dim)
    np.testing.assert_allclose(swapped, theta[::-1], rtol=1e-7)


def test_the_cooling_state_of_three_species_and_its_limits():
    """Three species: equal rates; all pairs elastic is equipartition; alike species share one temperature; the
    heavier of two species otherwise alike is the hotter (Garzo & Dufty 1999, Fig. 1)."""
    fractions, diameters, masses = [0.2, 0.3, 0.5], [1.0, 0.7, 0.5], [2.0, 1.0, 0.3]
    alpha = [[0.9, 0.8, 0.6], [0.8, 0.95, 0.7], [0.6, 0.7, 0.5]]
    theta = edmd.homogeneous_cooling_temperatures(0.2, fractions, diameters, masses, alpha)
    rates = edmd.mixture_cooling_rates(0.2, fractions, diameters, masses, alpha, theta)
    assert np.ptp(rates) < 1e-9 * rates.max()
    np.testing.assert_array_equal(edmd.homogeneous_cooling_temperatures(0.2, fractions, diameters, masses, 1.0),
                                  np.ones(3))
    np.testing.assert_allclose(edmd.homogeneous_cooling_temperatures(0.3, [0.3, 0.7], [1.0, 1.0], 2.0, 0.7), 1.0,
                               rtol=1e-10)
    heavy, light = edmd.homogeneous_cooling_temperatures(0.02, [0.5, 0.5], [1.0, 1.0], [1.0, 0.25], 0.8)
    assert heavy > 1.1 > 0.9 > light


@pytest.mark.parametrize("dim", [2, 3])
@given(eta=ETA, alpha=ALPHA, fraction=st.floats(0.05, 0.95), mass=st.floats(0.01, 100.0))
@settings(max_examples=30, deadline=None)
def test_one_species_cools_per_collision_by_haffs_law_at_any_density(dim, eta, alpha, fraction, mass):
    """-d ln T / dC = (1 - alpha^2) / d, alone or as two labels of one species."""
    expected = (1.0 - alpha**2) / dim
    assert edmd.homogeneous_cooling_rate(eta, [1.0], [1.0], mass, alpha, dim) == pytest.approx(expected, abs=1e-12)
    two = edmd.homogeneous_cooling_rate(eta, [fraction, 1.0 - fraction], [0.7, 0.7], mass, alpha, dim)
    assert two == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize("dim", [2, 3])
def test_the_collision_frequency_of_species_at_their_own_temperatures_is_that_of_maxwellian_pairs(dim):
    """kT per species: x_i n_j g_ij S_ij <|v_i - v_j|> summed, by sampling each pair's velocities at T_i and T_j."""
    rng = np.random.default_rng(3)
    fractions, diameters, masses, temperatures = [0.3, 0.7], np.array([1.0, 0.4]), np.array([1.0, 0.05]), [2.0, 0.5]
    g = edmd.mixture_contact_values(0.2, fractions, diameters, dim)
    density = 0.2 / ((math.pi / 6.0 if dim == 3 else math.pi / 4.0) * float(np.dot(fractions, diameters**dim)))
    expected = 0.0
    for i, j in np.ndindex(2, 2):
        vi = rng.normal(0.0, math.sqrt(temperatures[i] / masses[i]), size=(1_000_000, dim))
        vj = rng.normal(0.0, math.sqrt(temperatures[j] / masses[j]), size=(1_000_000, dim))
        contact = 0.5 * (diameters[i] + diameters[j])
        cross_section = math.pi * contact**2 if dim == 3 else 2.0 * contact
        expected += fractions[i] * fractions[j] * density * g[i, j] * cross_section * np.linalg.norm(vi - vj,
                                                                                                      axis=1).mean()
    rate = edmd.mixture_collision_frequency(0.2, fractions, diameters, masses, dim, temperatures)
    assert rate == pytest.approx(expected, rel=3e-3)  # sd / mean of |v_rel| / sqrt(1e6): ~5e-4
    assert rate != pytest.approx(edmd.mixture_collision_frequency(0.2, fractions, diameters, masses, dim, 1.25),
                                 rel=0.02)  # not the rate at the mean temperature


def test_the_cooling_rate_per_collision_is_the_cooling_state_s_rate_over_its_collision_frequency():
    """zeta / omega, both at the cooling state's temperatures (alpha = 1: no cooling)."""
    assert edmd.homogeneous_cooling_rate(0.1, [0.5, 0.5], [1.0, 0.5], [1.0, 0.2], 1.0) == 0.0
    arguments = (0.2, [0.3, 0.7], [1.0, 0.6], [1.0, 0.25])
    alpha = [[0.9, 0.7], [0.7, 0.8]]
    theta = edmd.homogeneous_cooling_temperatures(*arguments, alpha)
    zeta = edmd.mixture_cooling_rates(*arguments, alpha, theta)
    omega = edmd.mixture_collision_frequency(*arguments, 3, theta)
    assert edmd.homogeneous_cooling_rate(*arguments, alpha) == pytest.approx(zeta[0] / omega, rel=1e-9)


@pytest.mark.parametrize(
    ("arguments", "match"),
    [
        (dict(restitution=[[0.9, 0.8], [0.7, 0.9]]), "symmetric"),
        (dict(restitution=[0.9, 0.8]), "symmetric 2 x 2"),
        (dict(restitution=1.2), r"restitution must lie in \[0, 1\]"),
        (dict(restitution=math.nan), r"restitution must lie in \[0, 1\]"),
        (dict(masses=[1.0, 2.0, 3.0]), "masses"),
        (dict(temperatures=[1.0, 0.0]), "temperatures"),
        (dict(packing_fraction=1.0), "packing_fraction"),
        (dict(dim=1), "dim"),
    ],
)
def test_the_cooling_functions_check_their_arguments(arguments, match):
    values = dict(packing_fraction=0.1, fractions=[0.5, 0.5], diameters=[1.0, 0.5], masses=1.0, restitution=0.9,
                  dim=3) | arguments
    temperatures = values.pop("temperatures", 1.0)
    with pytest.raises(ValueError, match=match):
        edmd.mixture_cooling_rates(**values, temperatures=temperatures)
    if "temperatures" not in arguments:
        with pytest.raises(ValueError, match=match):
            edmd.homogeneous_cooling_temperatures(**values)
