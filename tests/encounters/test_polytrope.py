"""Polytropes: the Lane-Emden solutions against the analytic ones and Chandrasekhar's table, and the sampled stars."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy import stats
from scipy.integrate import quad

from collisionkit.encounters import PolytropeParameters, lane_emden, polytrope_star, polytrope_summary

XI = np.linspace(0.0, 2.4, 97)


def test_n_0_is_a_parabola():
    solution = lane_emden(0.0)
    assert solution.xi1 == pytest.approx(math.sqrt(6.0), rel=1e-12, abs=0)
    assert np.allclose(solution.theta(XI), 1 - XI**2 / 6, rtol=0, atol=1e-12)
    assert np.allclose(solution.slope(XI), -XI / 3, rtol=0, atol=1e-12)
    assert solution.omega == pytest.approx(2 * math.sqrt(6.0), rel=1e-12, abs=0)  # xi1^2 * xi1 / 3


def test_n_1_is_sin_xi_over_xi():
    solution = lane_emden(1.0)
    xi = np.linspace(0.0, math.pi, 97)
    assert solution.xi1 == pytest.approx(math.pi, rel=1e-12, abs=0)
    assert np.allclose(solution.theta(xi), np.sinc(xi / math.pi), rtol=0, atol=1e-11)
    slope = np.where(xi > 0, (xi * np.cos(xi) - np.sin(xi)) / np.where(xi > 0, xi, 1) ** 2, 0.0)
    assert np.allclose(solution.slope(xi), slope, rtol=0, atol=1e-11)
    assert solution.omega == pytest.approx(math.pi, rel=1e-11, abs=0)


def test_n_5_is_the_plummer_sphere_without_a_surface():
    solution = lane_emden(5.0, xi_max=100.0)
    xi = np.linspace(0.0, 100.0, 201)
    assert solution.xi1 == math.inf
    assert np.allclose(solution.theta(xi), (1 + xi**2 / 3) ** -0.5, rtol=1e-10, atol=0)
    assert np.allclose(solution.slope(xi), -xi / 3 * (1 + xi**2 / 3) ** -1.5, rtol=1e-9, atol=1e-15)
    with pytest.raises(ValueError, match="no surface: give xi_max"):
        lane_emden(5.0)


@pytest.mark.parametrize(("n", "xi1", "omega"), [(1.5, 3.65375, 2.71406), (3.0, 6.89685, 2.01824),
                                                 (4.0, 14.97155, 1.79723)])
def test_surfaces_agree_with_chandrasekhar_s_table(n, xi1, omega):
    """Chandrasekhar (1939), ch. IV, table 4: xi1 and -xi1^2 theta'(xi1), to the 6 figures printed."""
    solution = lane_emden(n)
    assert solution.xi1 == pytest.approx(xi1, rel=0, abs=6e-6)
    assert solution.omega == pytest.approx(omega, rel=0, abs=6e-6)


def test_the_mass_fraction_and_its_inverse():
    solution = lane_emden(3.0)
    xi = np.linspace(0.0, solution.xi1, 50)
    fraction = solution.mass_fraction(xi)
    assert fraction[0] == 0.0 and fraction[-1] == pytest.approx(1.0, rel=1e-15, abs=0)
    assert np.all(np.diff(fraction) > 0)
    inverse = solution.radius_of_mass_fraction(fraction)
    assert np.allclose(solution.mass_fraction(inverse), fraction, rtol=4 * np.finfo(float).eps, atol=0)
    # in xi to the resolution the mass fraction allows: 4 ulp of it over its slope xi^2 theta^n / omega
    slope = xi[1:-1] ** 2 * solution.theta(xi[1:-1]) ** 3 / solution.omega
    resolution = 4 * np.finfo(float).eps * (fraction[1:-1] / slope + xi[1:-1])
    assert np.all(np.abs(inverse[1:-1] - xi[1:-1]) <= resolution) and inverse[0] == 0.0
    # the mass fraction is the integral of the density, xi^2 theta^n / omega (quadrature of the solution)
    for point in xi[5::11]:
        integral, error = quad(lambda x: x**2 * solution.theta(x) ** 3 / solution.omega, 0.0, point, epsabs=1e-13)
        assert solution.mass_fraction(point) == pytest.approx(integral, rel=1e-9, abs=1e-12)


def radii_cdf(n, radius=1.0):
    solution = lane_emden(n)
    return lambda r: solution.mass_fraction(np.asarray(r) / radius * solution.xi1)


@pytest.mark.parametrize("n", [0.0, 1.5, 3.0, 4.5])
def test_the_sampled_enclosed_mass_is_the_lane_emden_profile(n):
    """K-S test of the particles' radii against M(<r)/M; the same sample fails against a polytrope of another n."""
    star = polytrope_star(n, 2000, mass=2.0, radius=3.0, gamma=5 / 3 if n == 0 else None, seed=20261126)
    r = np.linalg.norm(star.positions, axis=1)
    assert stats.kstest(r, radii_cdf(n, 3.0)).pvalue > 1e-3
    other = 1.0 if n >= 3 else n + 1.5
    assert stats.kstest(r, radii_cdf(other, 3.0)).pvalue < 1e-6
    # isotropic directions: cos(polar angle) and the azimuth are uniform
    assert stats.kstest(star.positions[:, 2] / r, "uniform", args=(-1, 2)).pvalue > 1e-3
    assert stats.kstest(np.arctan2(star.positions[:, 1], star.positions[:, 0]), "uniform",
                        args=(-math.pi, 2 * math.pi)).pvalue > 1e-3


@pytest.mark.parametrize("n", [1.5, 3.0])
def test_the_potential_energy_is_minus_3_over_5_minus_n_G_M2_over_R(n):
    """W = -3/(5-n) G M^2/R (Chandrasekhar, ch. IV, eq. 90), within the sampling noise of 8 stars of 2000 particles.

    The direct sum over the N(N-1)/2 pairs of N independent particles of mass M/N has the mean (1 - 1/N) W; its
    spread is measured from the 8 seeds, and the mean of the 8 must lie within 4 of its standard errors.
    """
    count, G, M, R = 2000, 1.0, 1.0, 1.0
    energies = np.array([polytrope_star(n, count, M, R, seed=seed).potential_energy(softening=1e-6 * R)
                         for seed in range(8)])
    expected = -3.0 / (5.0 - n) * G * M**2 / R * (1 - 1 / count)
    spread = energies.std(ddof=1)
    assert 0 < spread < 0.05 * abs(expected)  # the noise is that of a sample, neither nil nor wild
    assert abs(energies.mean() - expected) < 4 * spread / math.sqrt(len(energies))
    assert np.all(np.abs(energies - expected) < 5 * spread)


@pytest.mark.parametrize(("n", "gamma"), [(1.5, None), (3.0, None), (3.0, 5 / 3), (0.0, 5 / 3)])
def test_the_thermal_energy_satisfies_the_virial_theorem(n, gamma):
    """sum m u = -W / (3 (gamma - 1)) = G M^2 / ((5 - n)(gamma - 1) R): hydrostatic equilibrium, integrated.

    The particles are independent, so the sum's standard error is sqrt(N) times the spread of m u.
    """
    count, M, R = 4000, 2.0, 0.5
    star = polytrope_star(n, count, M, R, units="stellar", gamma=gamma, seed=7)
    used = 1 + 1 / n if gamma is None else gamma
    expected = star.G * M**2 / ((5 - n) * (used - 1) * R)
    energies = star.masses * star.internal_energies
    assert abs(energies.sum() - expected) < 4 * energies.std(ddof=1) * math.sqrt(count)
    # at the centre u = P_c / ((gamma - 1) rho_c) = G M xi1 / ((n + 1)(gamma - 1) R omega_n)
    solution = lane_emden(n)
    central = star.G * M * solution.xi1 / ((n + 1) * (used - 1) * R * solution.omega)
    assert star.internal_energies.max() <= central and star.internal_energies.max() > 0.9 * central
    assert star.internal_energies.min() >= 0


def test_the_sampled_star_is_at_rest_with_equal_masses_ids_and_neighbour_smoothing_lengths():
    star = polytrope_star(2.0, 600, mass=3.0, radius=2.0, neighbours=32, seed=4)
    assert np.all(star.velocities == 0) and np.allclose(star.masses, 3.0 / 600, rtol=1e-15, atol=0)
    assert star.ids.tolist() == list(range(1, 601)) and star.star_ids is None
    assert np.max(np.linalg.norm(star.positions, axis=1)) <= 2.0
    distances = np.linalg.norm(star.positions[:, None] - star.positions[None], axis=2)
    assert np.all(np.count_nonzero(distances <= star.smoothing_lengths[:, None], axis=1) == 33)  # 32 and itself


def test_a_seed_repeats_the_star():
    first, second = (polytrope_star(1.5, 300, neighbours=10, seed=9) for _ in range(2))
    assert np.array_equal(first.positions, second.positions)
    assert not np.array_equal(first.positions, polytrope_star(1.5, 300, neighbours=10, seed=10).positions)


def test_the_summary_of_the_star_command():
    summary, star = polytrope_summary(PolytropeParameters(polytrope=3.0, particles=500, mass=1.0, radius=1.0,
                                                          units="stellar", neighbours=20, seed=11))
    assert summary["lane_emden"]["xi1"] == pytest.approx(6.89685, abs=6e-6)
    assert summary["potential_energy_expected"] == pytest.approx(-1.5 * star.G, rel=1e-15, abs=0)
    assert summary["thermal_energy"] == pytest.approx(float(star.masses @ star.internal_energies), rel=1e-15, abs=0)
    assert summary["star"]["particles"] == 500 and summary["seed"] == 11 and summary["relaxed"] is False
    assert summary["parameters"]["polytrope"] == 3.0 and summary["gamma"] == pytest.approx(4 / 3, rel=1e-15, abs=0)


@pytest.mark.parametrize(
    ("values", "message"),
    [
        ({"polytrope": 5.0}, r"polytrope must be in \[0, 5\)"),
        ({"polytrope": -0.5}, "polytrope"),
        ({"polytrope": 0.0}, "n = 0 .* give gamma"),
        ({"particles": 50, "neighbours": 50}, "particles must be in"),
        ({"neighbours": 0}, "neighbours must be >= 1"),
        ({"mass": 0.0}, "mass must be > 0"),
        ({"radius": -1.0}, "radius must be > 0"),
        ({"gamma": 1.0}, "gamma must be > 1"),
        ({"units": "furlongs"}, "units must be one of"),
        ({"seed": -1}, "seed must be >= 0"),
    ],
)
def test_bad_polytrope_parameters_are_named(values, message):
    with pytest.raises(ValueError, match=message):
        PolytropeParameters(**values)


@pytest.mark.parametrize(("mass", "radius", "scale"), [
    (1e160, 1.0, "G M^2 / R = inf"),
    (1.0, 1e-300, "M / R^3 = inf"),
    (1e-300, 1e300, "G M^2 / R = 0"),
])
def test_a_star_beyond_the_float_range_is_a_named_value_error(mass, radius, scale):
    """Refused when made (the command line stops before any work) and by polytrope_star itself."""
    with pytest.raises(ValueError, match=re.escape(scale)):
        PolytropeParameters(polytrope=1.0, particles=500, mass=mass, radius=radius)
    with pytest.raises(ValueError, match=re.escape(scale)):
        polytrope_star(1.0, 500, mass, radius, neighbours=10)
