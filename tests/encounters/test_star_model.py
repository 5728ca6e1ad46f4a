"""Particle stars: sums over the particles, rigid moves, smoothing lengths and exact unit conversions."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.constants as const

from collisionkit.encounters import (
    GM_SUN,
    R_SUN,
    StarModel,
    conversion_factors,
    neighbour_smoothing_lengths,
    unit_system,
    unit_system_from_cgs,
)

EPS = np.finfo(float).eps


def random_star(count=200, seed=1, units="cgs", scale=1.0):
    rng = np.random.default_rng(seed)
    return StarModel(
        positions=scale * rng.normal(size=(count, 3)) + [3.0 * scale, -1.0 * scale, 0.5 * scale],
        velocities=rng.normal(size=(count, 3)),
        masses=rng.uniform(0.5, 1.5, count),
        smoothing_lengths=scale * rng.uniform(0.1, 0.2, count),
        internal_energies=rng.uniform(0.0, 2.0, count),
        ids=rng.permutation(count) + 10,
        units=units,
    )


def test_mass_centre_of_mass_and_its_velocity_are_the_mass_weighted_sums():
    star = random_star()
    m = star.masses
    assert star.mass == pytest.approx(math.fsum(m), rel=4 * EPS, abs=0)
    for axis in range(3):
        assert star.centre_of_mass[axis] == pytest.approx(math.fsum(m * star.positions[:, axis]) / math.fsum(m),
                                                          rel=1e-14, abs=1e-15)
        assert star.centre_of_mass_velocity[axis] == pytest.approx(
            math.fsum(m * star.velocities[:, axis]) / math.fsum(m), rel=1e-13, abs=1e-15)


def test_the_radius_holds_the_fraction_of_the_mass_about_the_centre_of_mass():
    star = random_star(1000)
    distance = np.linalg.norm(star.positions - star.centre_of_mass, axis=1)
    for fraction in (0.5, 0.9, 0.99, 1.0):
        radius = star.radius(fraction)
        inside = star.masses[distance <= radius].sum()
        just_inside = star.masses[distance < radius].sum()  # without the particle at the radius
        assert inside >= fraction * star.mass * (1 - 1e-14) and just_inside < fraction * star.mass
    assert star.radius(1.0) == distance.max()
    with pytest.raises(ValueError, match="fraction must be in"):
        star.radius(0.0)


def test_potential_energy_is_the_sum_over_pairs():
    star = random_star(150)
    x, m = star.positions, star.masses
    expected = -star.G * math.fsum(m[i] * m[j] / np.linalg.norm(x[i] - x[j]) for i in range(len(star))
                                   for j in range(i + 1, len(star)))
    assert star.potential_energy() == pytest.approx(expected, rel=1e-12, abs=0)
    softened = -star.G * math.fsum(m[i] * m[j] / math.sqrt(np.sum((x[i] - x[j]) ** 2) + 0.3**2)
                                   for i in range(len(star)) for j in range(i + 1, len(star)))
    assert star.potential_energy(softening=0.3) == pytest.approx(softened, rel=1e-12, abs=0)


def test_a_rigid_move_keeps_the_distances_and_relative_velocities_and_moves_the_centre():
    star = random_star()
    moved = star.moved(shift=[1e3, -2e3, 5.0], boost=[0.5, 0.0, -7.0])
    # the mass-weighted sum of 200 shifted coordinates rounds by ~ eps |shift| at each of its log2(200) levels
    assert np.allclose(moved.centre_of_mass, star.centre_of_mass + [1e3, -2e3, 5.0], rtol=0, atol=64 * EPS * 2e3)
    assert np.allclose(moved.centre_of_mass_velocity, star.centre_of_mass_velocity + [0.5, 0, -7], rtol=0,
                       atol=64 * EPS * 7)
    pairs = np.random.default_rng(3).integers(0, len(star), size=(500, 2))
    before = np.linalg.norm(star.positions[pairs[:, 0]] - star.positions[pairs[:, 1]], axis=1)
    after = np.linalg.norm(moved.positions[pairs[:, 0]] - moved.positions[pairs[:, 1]], axis=1)
    assert np.max(np.abs(after - before)) <= 8 * EPS * 2e3  # a shift of 2e3 rounds each coordinate by <= 1 ulp
    for name in ("masses", "smoothing_lengths", "internal_energies", "ids"):
        assert np.array_equal(getattr(moved, name), getattr(star, name))


def test_conversions_are_the_ratios_of_the_unit_sizes():
    """cgs -> solar against scipy's constants: AU, Julian year, and Msun = GM_sun / G."""
    star = random_star(units="cgs", scale=1e13)
    solar = star.in_units("solar")
    msun_g = GM_SUN / const.G * 1e3
    au_cm, year_s = const.au * 1e2, const.Julian_year
    np.testing.assert_allclose(solar.positions, star.positions / au_cm, rtol=4 * EPS, atol=0)
    np.testing.assert_allclose(solar.smoothing_lengths, star.smoothing_lengths / au_cm, rtol=4 * EPS, atol=0)
    np.testing.assert_allclose(solar.velocities, star.velocities * year_s / au_cm, rtol=4 * EPS, atol=0)
    np.testing.assert_allclose(solar.internal_energies, star.internal_energies * (year_s / au_cm) ** 2, rtol=6 * EPS,
                               atol=0)
    np.testing.assert_allclose(solar.masses, star.masses / msun_g, rtol=4 * EPS, atol=0)
    assert solar.units.name == "solar" and np.array_equal(solar.ids, star.ids)


@pytest.mark.parametrize(("first", "second"), [("cgs", "solar"), ("si", "stellar"), ("stellar", "cgs")])
def test_a_round_trip_between_two_systems_returns_every_number_to_round_off(first, second):
    star = random_star(units=first)
    back = star.in_units(second).in_units(first)
    for name in ("positions", "velocities", "masses", "smoothing_lengths", "internal_energies"):
        np.testing.assert_allclose(getattr(back, name), getattr(star, name), rtol=6 * EPS, atol=0, err_msg=name)
    factors, inverse = conversion_factors(first, second), conversion_factors(second, first)
    for name in factors:
        assert factors[name] * inverse[name] == pytest.approx(1.0, rel=4 * EPS, abs=0)


def test_the_physics_does_not_depend_on_the_units():
    """G M / R and G M / (R u) are pure numbers: the same in stellar units and in cgs."""
    star = random_star(units="stellar")
    cgs = star.in_units("cgs")
    for model in (star, cgs):
        assert model.G == model.units.G
    ratio = star.G * star.mass / (star.radius() * star.centre_of_mass_velocity @ star.centre_of_mass_velocity)
    ratio_cgs = cgs.G * cgs.mass / (cgs.radius() * cgs.centre_of_mass_velocity @ cgs.centre_of_mass_velocity)
    assert ratio_cgs == pytest.approx(ratio, rel=1e-13, abs=0)
    assert cgs.potential_energy() / (cgs.mass * cgs.internal_energies.mean()) == pytest.approx(
        star.potential_energy() / (star.mass * star.internal_energies.mean()), rel=1e-12, abs=0)
    # the stellar unit of speed is km/s, its length Rsun (IAU 2015 nominal)
    assert conversion_factors("stellar", "cgs")["velocity"] == pytest.approx(1e5, rel=2 * EPS, abs=0)
    assert conversion_factors("stellar", "si")["length"] == R_SUN


def test_n_body_units_convert_to_no_other_system_but_to_themselves():
    star = random_star(units="nbody")
    assert star.in_units("nbody").positions is not None
    assert conversion_factors("nbody", "nbody")["mass"] == 1.0
    with pytest.raises(ValueError, match="no size in SI"):
        star.in_units("cgs")


def test_units_from_cgs_sizes_match_a_named_system_or_make_an_exact_custom_one():
    for name in ("si", "cgs", "solar", "stellar"):
        system = unit_system(name)
        assert unit_system_from_cgs(system.mass_si * 1e3, system.length_si * 1e2, system.time_si) is system
    custom = unit_system_from_cgs(1.98841e33, 6.957e10, 1e3)
    assert custom.name == "custom" and (custom.mass_si, custom.length_si, custom.time_si) == (1.98841e30, 6.957e8, 1e3)
    assert custom.G == pytest.approx(const.G * 1.98841e30 * 1e6 / 6.957e8**3, rel=4 * EPS, abs=0)
    with pytest.raises(ValueError, match="finite and > 0"):
        unit_system_from_cgs(0.0, 1.0, 1.0)


def test_smoothing_lengths_hold_the_neighbour_number():
    positions = np.random.default_rng(5).normal(size=(400, 3))
    for neighbours in (1, 10, 50):
        h = neighbour_smoothing_lengths(positions, neighbours)
        distances = np.linalg.norm(positions[:, None] - positions[None], axis=2)
        inside = np.count_nonzero(distances <= h[:, None], axis=1) - 1  # less the particle itself
        assert np.all(inside == neighbours)
    with pytest.raises(ValueError, match="neighbours must be <"):
        neighbour_smoothing_lengths(positions[:5], 5)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"masses": [1.0, 0.0]}, "masses"),
        ({"ids": [3, 3]}, "distinct"),
        ({"ids": [1.0, 2.0]}, "integers"),
        ({"ids": [-1, 2]}, "ids must be integers >= 0"),
        ({"positions": [[0, 0, 0]]}, "velocities must have shape"),
        ({"internal_energies": [-1.0, 1.0]}, "internal_energies"),
        ({"smoothing_lengths": [np.nan, 1.0]}, "smoothing_lengths"),
        ({"star_ids": [0, 1]}, "star_ids"),
        ({"units": "furlongs"}, "units must be one of"),
    ],
)
def test_a_bad_star_is_a_named_error(change, message):
    arrays = dict(positions=np.zeros((2, 3)), velocities=np.zeros((2, 3)), masses=[1.0, 1.0],
                  smoothing_lengths=[1.0, 1.0], internal_energies=[0.0, 0.0], ids=[1, 2])
    with pytest.raises((ValueError, TypeError), match=message):
        StarModel(**(arrays | change))


def test_a_star_model_is_read_only():
    star = random_star(10)
    with pytest.raises(ValueError, match="read-only"):
        star.positions[0, 0] = 1.0
