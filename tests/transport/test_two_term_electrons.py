"""Electron-electron collisions in the two-term equation: the operator's conservation laws and limits, and the
solver's exact limits (a Maxwellian where they dominate, the gas's Maxwellian at E = 0)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy import constants

from collisionkit.transport import catalogue_gas, hard_sphere_gas, two_term_boltzmann
from collisionkit.transport._two_term_electrons import ElectronCollisions, coulomb_logarithm
from collisionkit.transport._two_term_operators import GAMMA, central_flux_matrix

ARGON_MASS = 6.64215627568e-27  # kg, hard_sphere_gas's default


def grid(top=40.0, cells=1000):
    edges = np.linspace(0.0, top, cells + 1)
    return edges, 0.5 * (edges[1:] + edges[:-1])


def normalised(eedf, collisions):
    return eedf / float(eedf @ collisions.density)


def test_the_coulomb_logarithm_counts_electrons_in_a_debye_sphere():
    """ln(12 pi n lambda_D^3) with lambda_D = sqrt(eps0 kT_e / (n e^2)) written out here, kT_e = 2/3 <e>."""
    for mean_energy, density in ((3.0, 1e18), (0.05, 1e12), (30.0, 1e22)):
        kT = 2.0 / 3.0 * mean_energy * constants.e
        debye = math.sqrt(constants.epsilon_0 * kT / (density * constants.e**2))
        assert coulomb_logarithm(mean_energy, density) == pytest.approx(
            math.log(12.0 * math.pi * density * debye**3), rel=1e-12)


def test_a_fast_electron_loses_energy_at_the_classical_rate_to_free_electrons():
    """Far above the distribution A1 = 1: the drift in energy, d eps/dt = N W_ee / eps^1/2 (from the flux
    G = eps^1/2 F0 (d eps/dt) / N), must be the energy loss of a fast charge to free electrons of its own mass,
    e^4 n_e ln(Lambda) / (4 pi eps0^2 m v) (Bohr; e.g. Jackson, Classical Electrodynamics, sec. 13.1), written
    out here from the constants: this checks the operator's overall factor a."""
    edges, middle = grid(top=200.0, cells=4000)
    degree, density = 1e-4, 1e18
    collisions = ElectronCollisions(degree, density, edges)
    drift, _ = collisions.coefficients(normalised(np.exp(-middle / 0.5), collisions))
    far = edges[1:-1] > 150.0
    gas_density = density / degree
    rate = gas_density * drift[far] / np.sqrt(edges[1:-1][far])  # eV/s
    speed = GAMMA * np.sqrt(edges[1:-1][far])
    classical = (constants.e**4 * density * collisions.coulomb_logarithm
                 / (4.0 * math.pi * constants.epsilon_0**2 * constants.m_e * speed)) / constants.e
    np.testing.assert_allclose(-rate, classical, rtol=1e-12)


@pytest.mark.parametrize("cells", [250, 500, 1000, 2000])
def test_a_maxwellian_is_left_alone_to_second_order(cells):
    """The flux of a Maxwellian (any temperature) vanishes in the exact operator; on the grid it is O(h^2): below
    0.1 h^2 of the drift's scale (measured 0.02-0.03 h^2, h in units of kT)."""
    edges, middle = grid(cells=cells)
    collisions = ElectronCollisions(1e-4, 1e18, edges)
    for kT in (1.0, 2.0, 3.0):
        eedf = normalised(np.exp(-middle / kT), collisions)
        drift, diffusion = collisions.coefficients(eedf)
        flux = drift * 0.5 * (eedf[1:] + eedf[:-1]) - diffusion * np.diff(eedf) / collisions.width
        scale = np.max(np.abs(drift * eedf[1:]))
        assert np.max(np.abs(flux)) < 0.1 * (collisions.width / kT) ** 2 * scale


@settings(max_examples=60, deadline=None)
@given(arrays(np.float64, 60, elements=st.floats(0.0, 1.0)), st.floats(1.0, 100.0))
def test_the_electrons_exchange_energy_without_creating_any(values, top):
    """For any distribution that vanishes in the top cell the central flux's energy sum_j h G_j is zero to
    round-off: the A2 weights make its terms cancel pair by pair (the discrete form of swapping the two energies
    of the double integral). Exact A2 weights (the cells' integrals of eps^3/2) leave O(h^2): checked to fail."""
    if not np.any(values[:-1] > 0.0):
        return
    values[-1] = 0.0
    edges = np.linspace(0.0, top, values.size + 1)
    collisions = ElectronCollisions(1e-3, 1e18, edges)
    eedf = normalised(values, collisions)
    drift, diffusion = collisions.coefficients(eedf)
    flux = drift * 0.5 * (eedf[1:] + eedf[:-1]) - diffusion * np.diff(eedf) / collisions.width
    moved = np.sum(np.abs(drift) * 0.5 * (eedf[1:] + eedf[:-1]) + np.abs(diffusion * np.diff(eedf)) / collisions.width)
    assert abs(np.sum(flux)) <= 1e-13 * moved


def test_the_operator_conserves_electrons():
    """A flux divergence: the columns of the matrix sum to zero, so the electrons are only moved in energy."""
    edges, middle = grid(cells=300)
    collisions = ElectronCollisions(1e-3, 1e18, edges)
    matrix = collisions.matrix(normalised(np.exp(-((middle / 5.0) ** 2)), collisions)).toarray()
    assert np.max(np.abs(matrix.sum(axis=0))) <= 1e-12 * np.max(np.abs(matrix))
    assert central_flux_matrix(np.ones(2), np.ones(2), 1.0).toarray().sum(axis=0) == pytest.approx(np.zeros(3))


def test_where_the_electrons_mostly_collide_with_each_other_the_distribution_is_maxwellian():
    """A hard-sphere gas (constant sigma, elastic only) at 0 K: with no electron-electron collisions F0 is
    Druyvesteyn's; where they dominate it is a Maxwellian whose kT_e the field and the gas's recoil balance,
    int G_elastic = 0: 2 kT^3 sigma_eps = (E/N)^2 kT / (3 sigma), kT = (E/N) / (sigma sqrt(12 m/M)) (derived
    here). Measured at n_e/N = 1e-2: <e> within 2e-7 of 1.5 kT, the slope of ln F0 across the bulk within 1.4e-4
    of -1/kT (the gas's recoil, ~4e-4 of the electrons' own flux here, still bends it)."""
    sigma, field = 6e-20, 10.0
    temperature = field * 1e-21 / (sigma * math.sqrt(12.0 * constants.m_e / ARGON_MASS))
    result = two_term_boltzmann(hard_sphere_gas(sigma), field, 0.0, ionization_degree=1e-2, electron_density=1e18)
    assert result.mean_energy == pytest.approx(1.5 * temperature, rel=2e-5)
    bulk = result.energy < 5.0 * temperature
    slope = np.polyfit(result.energy[bulk], np.log(result.eedf[bulk]), 1)[0]
    assert slope == pytest.approx(-1.0 / temperature, rel=5e-4)  # finite n_e/N: elastic/e-e flux ~ 4e-4 here
    druyvesteyn = two_term_boltzmann(hard_sphere_gas(sigma), field, 0.0)
    assert druyvesteyn.mean_energy < 0.99 * 1.5 * temperature  # the limit is not reached without them
    assert abs(result.power_balance) < 3e-4


def test_weak_electron_collisions_change_nothing():
    """At n_e/N = 1e-12 the solution is the one without them, to 1e-8."""
    gas = hard_sphere_gas(6e-20)
    plain = two_term_boltzmann(gas, 10.0, 0.0)
    weak = two_term_boltzmann(gas, 10.0, 0.0, ionization_degree=1e-12, electron_density=1e18)
    assert weak.mean_energy == pytest.approx(plain.mean_energy, rel=1e-8)
    assert weak.mobility_N == pytest.approx(plain.mobility_N, rel=1e-8)
    assert weak.coulomb_logarithm > 0.0 and plain.coulomb_logarithm == 0.0
    assert "ionization_degree=1e-12" in repr(weak) and "ionization_degree" not in repr(plain)  # shown when set


def test_without_a_field_the_electrons_take_the_gas_temperature():
    """E = 0: the gas's Maxwellian is a zero flux of both the recoil and the electron-electron terms, so it is the
    solution whatever n_e/N (to the grid's second order: 1.5 kT within 1e-4 at 1000 cells)."""
    result = two_term_boltzmann(hard_sphere_gas(6e-20), 0.0, 3000.0, ionization_degree=1e-3, electron_density=1e18)
    kT = constants.k * 3000.0 / constants.e
    assert result.mean_energy == pytest.approx(1.5 * kT, rel=1e-4)


@pytest.fixture(scope="module")
def argon_scan():
    gas = catalogue_gas("Ar")
    return {degree: two_term_boltzmann(gas, 50.0, 300.0, **({"ionization_degree": degree, "electron_density": 1e18}
                                                            if degree else {}))
            for degree in (0.0, 1e-6, 1e-4, 1e-3)}


def test_in_argon_electron_collisions_fill_the_tail_and_cool_the_bulk(argon_scan):
    """Argon at 50 Td (Hagelaar & Pitchford 2005, sec. 4, fig. 6: the EEDF turns Maxwellian as n_e/N rises): the
    electrons share energy, so the tail above the 11.5 eV threshold fills, the excitations rise and the mean
    energy falls, monotonically in n_e/N; energy still balances (the electrons' exchange is zero)."""
    degrees = sorted(argon_scan)
    means = [argon_scan[d].mean_energy for d in degrees]
    excitation = [sum(rate for label, rate in argon_scan[d].rate_coefficients.items() if "ioniz" not in label
                      and "lastic" not in label) for d in degrees]
    assert all(a > b for a, b in zip(means, means[1:])), means
    assert all(a < b for a, b in zip(excitation, excitation[1:])), excitation
    assert means[-1] < 0.95 * means[0]
    for result in argon_scan.values():
        assert abs(result.power_balance) < 1e-4


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"ionization_degree": -1e-3, "electron_density": 1e18}, "ionization_degree"),
    ({"ionization_degree": 0.5, "electron_density": 1e18}, "ionization_degree"),
    ({"ionization_degree": math.nan, "electron_density": 1e18}, "ionization_degree"),
    ({"ionization_degree": 1e-3}, "needs electron_density"),
    ({"electron_density": 1e18}, "only with ionization_degree"),
    ({"ionization_degree": 1e-3, "electron_density": 0.0}, "electron_density"),
    ({"ionization_degree": 1e-3, "electron_density": 1e40}, "electron_density"),
    ({"ionization_degree": 1e-3, "electron_density": 1e31}, "Coulomb logarithm"),
])
def test_bad_electron_collision_inputs_are_named(kwargs, message):
    with pytest.raises(ValueError, match=message):
        two_term_boltzmann(hard_sphere_gas(6e-20), 10.0, 0.0, **kwargs)
