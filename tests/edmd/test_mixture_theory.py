"""Tests of collisionkit.edmd.mixture_theory against one species' equations, exact virial coefficients and kinetics."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from collisionkit import edmd

from . import mixture_virials as virials

ETA = st.floats(0.01, 0.6)
FRACTION = st.floats(0.05, 0.95)
DIAMETER = st.floats(0.1, 1.0)


def _volume_per_particle(fractions, diameters, dim):
    fractions, diameters = np.asarray(fractions), np.asarray(diameters)
    return (math.pi / 6.0 if dim == 3 else math.pi / 4.0) * float(np.sum(fractions * diameters**dim))


@pytest.mark.parametrize("dim", [2, 3])
@given(eta=ETA, fraction=FRACTION, diameter=DIAMETER)
@settings(max_examples=40, deadline=None)
def test_alike_species_are_one_species(dim, eta, fraction, diameter):
    """Two species of one diameter: Carnahan-Starling or Henderson, and Enskog's rate of one species."""
    fractions, diameters = [fraction, 1.0 - fraction], [diameter, diameter]
    one = edmd.carnahan_starling(eta) if dim == 3 else edmd.henderson(eta)
    Z = edmd.mixture_compressibility(eta, fractions, diameters, dim)
    assert Z == pytest.approx(one, rel=1e-12)
    contact = (one - 1.0) / (2 ** (dim - 1) * eta)  # Z = 1 + 2^(d-1) eta g(sigma)
    np.testing.assert_allclose(edmd.mixture_contact_values(eta, fractions, diameters, dim), contact, rtol=1e-12)
    rate = edmd.mixture_collision_frequency(eta, fractions, diameters, 2.0, dim, kT=1.5)
    assert rate == pytest.approx(edmd.enskog_collision_frequency(one, dim, diameter, kT=1.5, mass=2.0), rel=1e-12)


@pytest.mark.parametrize("dim", [2, 3])
@given(eta=ETA, fractions=st.lists(FRACTION, min_size=2, max_size=4), diameters=st.lists(DIAMETER, min_size=4,
                                                                                          max_size=4))
@settings(max_examples=60, deadline=None)
def test_the_contact_values_give_the_equation_of_state_by_the_virial_route(dim, eta, fractions, diameters):
    """Z = 1 + (2^(d-1) pi / (d (d-1))) n sum_ij x_i x_j sigma_ij^d g_ij: the closed form from the contacts."""
    fractions = np.asarray(fractions) / np.sum(fractions)
    diameters = np.asarray(diameters[: fractions.size])
    g = edmd.mixture_contact_values(eta, fractions, diameters, dim)
    contact = 0.5 * np.add.outer(diameters, diameters)
    density = eta / _volume_per_particle(fractions, diameters, dim)
    prefactor = 2.0 * math.pi / 3.0 if dim == 3 else math.pi / 2.0
    virial = 1.0 + prefactor * density * np.sum(np.outer(fractions, fractions) * contact**dim * g)
    assert edmd.mixture_compressibility(eta, fractions, diameters, dim) == pytest.approx(virial, rel=1e-12)
    np.testing.assert_array_equal(g, g.T)


def _series(fractions, diameters, dim):
    """The coefficients c1, c2 of Z = 1 + c1 eta + c2 eta^2 + ..., fitted to the closed form at small eta."""
    eta = np.linspace(1e-4, 2e-3, 40)
    Z = np.array([edmd.mixture_compressibility(value, fractions, diameters, dim) for value in eta])
    c1, c2 = np.polynomial.polynomial.polyfit(eta, (Z - 1.0) / eta, 3)[:2]
    return c1, c2


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize(("fractions", "diameters"), [([0.5, 0.5], [1.0, 0.5]), ([0.2, 0.3, 0.5], [1.0, 0.3, 0.7])])
def test_the_equation_of_state_holds_the_exact_second_virial_coefficient(dim, fractions, diameters):
    """B2 = (2 pi / 3) sum x_i x_j sigma_ij^3 (spheres), (pi / 2) sum x_i x_j sigma_ij^2 (discs): Z - 1 = B2 n."""
    contact = 0.5 * np.add.outer(diameters, diameters)
    prefactor = 2.0 * math.pi / 3.0 if dim == 3 else math.pi / 2.0
    b2 = prefactor * np.sum(np.outer(fractions, fractions) * contact**dim)
    c1, _ = _series(fractions, diameters, dim)
    assert c1 == pytest.approx(b2 / _volume_per_particle(fractions, diameters, dim), rel=1e-7)


@pytest.mark.parametrize("dim", [2, 3])
def test_the_lens_integral_gives_the_third_virial_coefficient_of_one_species(dim):
    """5 pi^2 / 18 sigma^6 (spheres); (4/3 - sqrt(3)/pi) (pi/2)^2 sigma^4 (discs)."""
    exact = 5.0 * math.pi**2 / 18.0 if dim == 3 else (4.0 / 3.0 - math.sqrt(3.0) / math.pi) * (math.pi / 2.0) ** 2
    assert virials.third_virial([1.0], [1.0], dim) == pytest.approx(exact, rel=1e-10)


@pytest.mark.parametrize(("fractions", "diameters"), [([0.5, 0.5], [1.0, 0.5]), ([0.3, 0.7], [1.0, 0.2]),
                                                      ([0.2, 0.3, 0.5], [1.0, 0.3, 0.7])])
def test_bmcsl_holds_the_exact_third_virial_coefficient_of_sphere_mixtures(fractions, diameters):
    """Z = 1 + B2 n + B3 n^2 + ...: BMCSL's eta^2 coefficient against B3 from the Mayer integral (Kihara's result)."""
    _, c2 = _series(fractions, diameters, 3)
    volume = _volume_per_particle(fractions, diameters, 3)
    assert c2 == pytest.approx(virials.third_virial(fractions, diameters, 3) / volume**2, rel=1e-5)


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize(("fractions", "diameters"), [([0.5, 0.5], [1.0, 0.6]), ([0.3, 0.7], [1.0, 0.2])])
def test_the_contact_values_at_first_order_in_the_density(dim, fractions, diameters):
    """g_ij = 1 + n sum_k x_k lens(sigma_ij; sigma_ik, sigma_jk): exact for BMCSL (spheres); the disc equation's
    slopes are those of an approximation: within 5 % (1.6 % at size ratio 0.6, 4.7 % at 0.2)."""
    eta = 1e-6
    density = eta / virials.volume_per_particle(fractions, diameters, dim)
    slopes = (edmd.mixture_contact_values(eta, fractions, diameters, dim) - 1.0) / density
    np.testing.assert_allclose(slopes, virials.first_order_contacts(fractions, diameters, dim),
                               rtol=1e-5 if dim == 3 else 0.05)


@pytest.mark.parametrize("dim", [2, 3])
def test_the_collision_frequency_is_the_collision_cylinder_times_the_mean_relative_speed(dim):
    """Enskog's rate against a Monte Carlo of Maxwell-Boltzmann pairs: x_i n_j g_ij S_ij <|v_i - v_j|>, summed."""
    rng = np.random.default_rng(7)
    fractions, diameters, masses, kT, eta = [0.3, 0.7], np.array([1.0, 0.4]), np.array([1.0, 0.05]), 1.7, 0.2
    g = edmd.mixture_contact_values(eta, fractions, diameters, dim)
    density = eta / _volume_per_particle(fractions, diameters, dim)
    samples = 2_000_000
    expected = 0.0
    for i, j in np.ndindex(2, 2):
        vi = rng.normal(0.0, math.sqrt(kT / masses[i]), size=(samples, dim))
        vj = rng.normal(0.0, math.sqrt(kT / masses[j]), size=(samples, dim))
        speed = np.linalg.norm(vi - vj, axis=1).mean()
        contact = 0.5 * (diameters[i] + diameters[j])
        cross_section = math.pi * contact**2 if dim == 3 else 2.0 * contact
        expected += fractions[i] * fractions[j] * density * g[i, j] * cross_section * speed
    rate = edmd.mixture_collision_frequency(eta, fractions, diameters, masses, dim, kT)
    # the sample mean's relative error: sd/mean of |v_rel| (~0.42 in 3D, 0.52 in 2D) / sqrt(samples) ~ 4e-4
    assert rate == pytest.approx(expected, rel=2e-3)


@pytest.mark.parametrize(
    ("arguments", "error", "match"),
    [
        (dict(fractions=[0.5, 0.6]), ValueError, "fractions must sum to 1"),
        (dict(fractions=[0.5, -0.5, 1.0], diameters=[1, 1, 1]), ValueError, "fractions"),
        (dict(diameters=[1.0]), ValueError, "one length"),
        (dict(diameters=[1.0, 0.0]), ValueError, "diameters"),
        (dict(packing_fraction=1.0), ValueError, "packing_fraction"),
        (dict(packing_fraction=math.nan), ValueError, "packing_fraction"),
        (dict(dim=4), ValueError, "dim"),
        (dict(masses=[1.0, 2.0, 3.0]), ValueError, "masses"),
        (dict(masses=[1.0, 0.0]), ValueError, "masses"),
        (dict(kT=0.0), ValueError, "kT"),
    ],
)
def test_the_mixture_functions_check_their_arguments(arguments, error, match):
    values = dict(packing_fraction=0.3, fractions=[0.5, 0.5], diameters=[1.0, 0.5], dim=3) | arguments
    masses, kT = values.pop("masses", 1.0), values.pop("kT", 1.0)
    with pytest.raises(error, match=match):
        edmd.mixture_collision_frequency(values["packing_fraction"], values["fractions"], values["diameters"], masses,
                                         values["dim"], kT)
    if "masses" not in arguments and "kT" not in arguments:
        for function in (edmd.mixture_compressibility, edmd.mixture_contact_values):
            with pytest.raises(error, match=match):
                function(**values)
