"""Stars from stellar-structure profiles: a Lane-Emden polytrope written as a profile (and as a MESA file) is the
independent reference: its mass, potential energy and virial theorem in closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from collisionkit.encounters import (
    StellarProfile, conversion_factors, lane_emden, profile_star, read_mesa_profile, unit_system,
)
from collisionkit.encounters.profile_star import G_CGS, M_SUN_G, R_SUN_CM

MASS, RADIUS = M_SUN_G, R_SUN_CM


def polytrope_profile(n: float, zones: int = 4000, with_mass: bool = False) -> StellarProfile:
    """A polytrope of index n, one solar mass and radius, in cgs: rho = rho_c theta^n, P/rho = (G M / R) xi1 theta /
    ((n + 1) omega_n), m = M x mass fraction (Chandrasekhar ch. IV), out to 0.9999 of the surface."""
    solution = lane_emden(n)
    xi = np.linspace(0.0, 0.9999 * solution.xi1, zones)
    alpha = RADIUS / solution.xi1
    central = MASS / (4.0 * math.pi * alpha**3 * solution.omega)
    theta = solution.theta(xi)
    density = central * theta**n
    pressure = density * G_CGS * MASS / RADIUS * solution.xi1 * theta / ((n + 1.0) * solution.omega)
    mass = None
    if with_mass:  # as a MESA model: no zone at the centre
        xi, density, pressure, mass = xi[1:], density[1:], pressure[1:], MASS * solution.mass_fraction(xi[1:])
    return StellarProfile(alpha * xi, density, pressure, mass=mass)


def polytrope_cells(n: float, zones: int = 2000) -> StellarProfile:
    """The polytrope as MESA writes a model: cells between faces at xi_k (to 0.995 xi1), the exact enclosed mass
    at each face, each cell's mean density (its mass over its volume) and the pressure at its mid-mass radius."""
    solution = lane_emden(n)
    faces = np.linspace(0.0, 0.995 * solution.xi1, zones + 1)[1:]  # (beyond, a cell's mass is lost to round-off)
    alpha = RADIUS / solution.xi1
    mass = MASS * solution.mass_fraction(faces)
    volumes = 4.0 / 3.0 * math.pi * np.diff((alpha * faces) ** 3, prepend=0.0)
    density = np.diff(mass, prepend=0.0) / volumes
    middle = solution.radius_of_mass_fraction(0.5 * (mass + np.concatenate(([0.0], mass[:-1]))) / MASS)
    theta = solution.theta(middle)
    central = MASS / (4.0 * math.pi * alpha**3 * solution.omega)
    pressure = central * theta ** (n + 1) * G_CGS * MASS / RADIUS * solution.xi1 / ((n + 1.0) * solution.omega)
    return StellarProfile(alpha * faces, density, pressure, mass=mass, cells=True)


@pytest.mark.parametrize("n", [1.5, 3.0])
def test_a_polytrope_as_cells_holds_its_mass_exactly_and_its_virial_balance(n):
    """Cells: the integrated mass is the mass column to round-off (each cell's density times its volume), the
    virial ratio 1 within 1e-4, and the energy at a radius is its cell's. Kills: cells integrated as points
    (a 1e-3 mismatch), the cell below taken for a radius."""
    profile = polytrope_cells(n)
    assert abs(profile.mass_mismatch()) < 1e-12
    assert profile.virial_ratio() == pytest.approx(1.0, abs=1e-4)
    between = 0.5 * (profile.radius[10] + profile.radius[11])
    assert profile.specific_energy(between) == pytest.approx(1.5 * profile.pressure[11] / profile.density[11],
                                                             rel=1e-14)
    points = StellarProfile(profile.radius, profile.density, profile.pressure, mass=profile.mass)
    assert abs(points.mass_mismatch()) > 1e-4


@pytest.mark.parametrize("n", [1.5, 3.0])
def test_a_polytrope_profile_has_its_mass_potential_energy_and_virial_balance(n):
    """The integrated mass is M (to the 1e-4 beyond 0.9999 xi1 and the trapezoids), W = -3/(5-n) G M^2 / R, and
    3 int P dV / -W = 1 (hydrostatic equilibrium), each within 5e-4. A radius read in the wrong unit (x 100)
    breaks the virial balance by orders of magnitude. Kills: 4 pi r^2 rho without r^2, a virial ratio missing
    its 3."""
    profile = polytrope_profile(n)
    assert profile.total_mass == pytest.approx(MASS, rel=5e-4)
    assert profile.potential_energy() == pytest.approx(-3.0 / (5.0 - n) * G_CGS * MASS**2 / RADIUS, rel=5e-4)
    assert profile.virial_ratio() == pytest.approx(1.0, abs=5e-4)
    wrong = StellarProfile(profile.radius * 100.0, profile.density, profile.pressure)
    assert not 0.01 < wrong.virial_ratio() < 100.0


def test_the_mass_column_is_used_and_checked_against_the_density():
    """With the model's mass column: the enclosed mass is it, and the integral of the density agrees within 1e-5
    (4000 zones); a column off by 2 % shows as a 2 % mismatch."""
    profile = polytrope_profile(1.5, with_mass=True)
    np.testing.assert_array_equal(profile.enclosed_mass(), profile.mass)
    assert abs(profile.mass_mismatch()) < 1e-5
    heavier = StellarProfile(profile.radius, profile.density, profile.pressure, mass=profile.mass * 1.02)
    assert heavier.mass_mismatch() == pytest.approx(1 / 1.02 - 1.0, rel=1e-4)


@pytest.mark.parametrize("n", [1.5, 3.0])
def test_sampled_radii_follow_the_lane_emden_mass_and_energies_the_closed_form(n):
    """Kolmogorov-Smirnov distance of 20000 sampled radii from the Lane-Emden mass fraction below its 99.9 %
    bound 1.95 / sqrt(K); u = P / ((gamma - 1) rho) = (G M / R) xi1 theta / ((n + 1) omega (gamma - 1)) at each
    particle within 1e-3 inside 0.99 R (log-linear between zones). Kills: gamma - 1 dropped, radii from the
    density instead of the mass."""
    profile, solution = polytrope_profile(n), lane_emden(n)
    star = profile_star(profile, 20000, units="cgs", neighbours=10, gamma=1.0 + 1.0 / n, seed=4)
    r = np.linalg.norm(star.positions, axis=1)
    statistic = stats.kstest(r / RADIUS * solution.xi1, solution.mass_fraction).statistic
    assert statistic < 1.95 / math.sqrt(20000)
    inside = r < 0.99 * RADIUS
    theta = solution.theta(r[inside] / RADIUS * solution.xi1)
    expected = G_CGS * MASS / RADIUS * solution.xi1 * theta / ((n + 1.0) * solution.omega * (1.0 + 1.0 / n - 1.0))
    np.testing.assert_allclose(star.internal_energies[inside], expected, rtol=1e-3)
    assert star.mass == pytest.approx(profile.total_mass, rel=1e-12)


def test_units_convert_through_the_factors_and_nbody_is_refused():
    """Stellar and solar units are the cgs star times the conversion factors (lengths, and u by the velocity factor
    squared); N-body units, which have no size, are refused (two stars would both get M = 1, R = 1). Kills: a
    velocity factor not squared, masses left in grams."""
    profile = polytrope_profile(3.0)
    cgs = profile_star(profile, 500, units="cgs", neighbours=10, seed=1)
    for name in ("stellar", "solar"):
        star = profile_star(profile, 500, units=name, neighbours=10, seed=1)
        factors = conversion_factors("cgs", unit_system(name))
        np.testing.assert_allclose(star.internal_energies, cgs.internal_energies * factors["specific_energy"],
                                   rtol=1e-12)
        np.testing.assert_allclose(star.positions, cgs.positions * factors["length"], rtol=1e-12)
        assert star.mass == pytest.approx(cgs.mass * factors["mass"], rel=1e-12) and star.units.name == name
    with pytest.raises(ValueError, match="units nbody .* would lose the star's mass and radius"):
        profile_star(profile, 500, units="nbody", neighbours=10)


def _write_mesa(path, profile: StellarProfile, names=("zone", "logR", "logRho", "logP", "mass"), energy=None):
    """``profile`` in the layout of a MESA profile file: 6 header lines, zones from the surface to the centre."""
    with np.errstate(divide="ignore"):  # a zone at the centre: log R = -inf, written as such
        log_radius = np.log10(profile.radius / R_SUN_CM)
    columns = {"zone": np.arange(1, len(profile) + 1)[::-1], "logR": log_radius,
               "radius_cm": profile.radius, "logRho": np.log10(profile.density), "rho": profile.density,
               "logP": np.log10(profile.pressure), "mass": profile.enclosed_mass() / M_SUN_G, "energy": energy}
    header = "1 2 3\nmodel_number star_age star_mass\n1 4.6e9 1.0\n\n"
    rows = [" ".join(f"{columns[name][k]:.17g}" for name in names) for k in range(len(profile) - 1, -1, -1)]
    path.write_text(header + " ".join(str(k) for k in range(1, len(names) + 1)) + "\n" + " ".join(names) + "\n"
                    + "\n".join(rows) + "\n")
    return path


def test_a_mesa_profile_reads_back_in_cgs_from_its_log_and_solar_columns(tmp_path):
    """logR (Rsun), logRho, logP and mass (Msun), surface first: the arrays come back to round-off, sorted from
    the centre; radius_cm and rho are taken as well. Kills: Rsun not applied, the order not reversed."""
    profile = polytrope_cells(1.5, zones=300)
    read = read_mesa_profile(_write_mesa(tmp_path / "profile1.data", profile))
    for name in ("radius", "density", "pressure", "mass"):
        np.testing.assert_allclose(getattr(read, name), getattr(profile, name), rtol=1e-12)
    assert read.source == "profile1.data" and read.cells
    plain = read_mesa_profile(_write_mesa(tmp_path / "profile2.data", profile, ("radius_cm", "rho", "logP")))
    np.testing.assert_allclose(plain.radius, profile.radius, rtol=1e-15)
    assert plain.mass is None and plain.total_mass == pytest.approx(profile.total_mass, rel=1e-12)


def test_the_model_s_own_internal_energy_is_used_unless_a_gamma_is_given(tmp_path):
    profile = polytrope_cells(1.5, zones=300)
    energy = 3.0 * profile.pressure / profile.density  # some other equation of state
    read = read_mesa_profile(_write_mesa(tmp_path / "p.data", profile, ("radius_cm", "rho", "logP", "energy"),
                                         energy=energy))
    np.testing.assert_allclose(read.specific_energy(read.radius[5:8]), energy[5:8], rtol=1e-12)
    np.testing.assert_allclose(read.specific_energy(read.radius[5:8], gamma=5.0 / 3.0),
                               1.5 * profile.pressure[5:8] / profile.density[5:8], rtol=1e-12)


def test_files_and_profiles_that_are_no_star_are_refused(tmp_path):
    profile = polytrope_profile(1.5, zones=20)
    no_pressure = _write_mesa(tmp_path / "a.data", profile, ("zone", "logR", "logRho"))
    with pytest.raises(ValueError, match="no pressure column among the names on line 6"):
        read_mesa_profile(no_pressure)
    broken = _write_mesa(tmp_path / "b.data", profile)
    lines = broken.read_text().splitlines()
    broken.write_text("\n".join([*lines[:6], "1 2", *lines[6:]]) + "\n")
    with pytest.raises(ValueError, match="line 7: 2 values for 5 column names"):
        read_mesa_profile(broken)
    (tmp_path / "binary.data").write_bytes(b"\x80\xff" * 100)
    with pytest.raises(ValueError, match="binary.data is not a MESA profile: it is not text"):
        read_mesa_profile(tmp_path / "binary.data")
    holed = _write_mesa(tmp_path / "nan.data", profile)
    lines = holed.read_text().splitlines()
    lines[10] = lines[10].replace(lines[10].split()[3], "nan", 1)  # logP of a zone (the file's line 11)
    holed.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match="nan.data line 11: the pressure column holds nan"):
        read_mesa_profile(holed)
    assert repr(profile).startswith("StellarProfile(20 points, mass=") and len(repr(profile)) < 120
    (tmp_path / "c.data").write_text("1 2\n")
    with pytest.raises(ValueError, match="not a MESA profile"):
        read_mesa_profile(tmp_path / "c.data")
    r = np.array([1.0, 2.0, 3.0])
    refusals = [((r[:2], r[:2], r[:2]), "at least 3 zones"), ((r, -r, r), "density must be > 0"),
                ((r, r, [1.0, np.nan, 1.0]), "pressure must be finite"), (([1.0, 1.0, 2.0], r, r), "distinct"),
                ((r, r, r, [3.0, 2.0, 1.0]), "mass .* must be >= 0 and never fall")]
    for arguments, message in refusals:
        with pytest.raises(ValueError, match=message):
            StellarProfile(*arguments)
    with pytest.raises(ValueError, match="particles"):
        profile_star(profile, 5, neighbours=10)


def test_the_summary_gives_the_profile_checks_and_energies_in_the_star_s_units(tmp_path):
    """The star command's library call: the profile's virial ratio and mass check, no warning for a polytrope;
    the thermal energy of the particles against the virial theorem's -W / (3 (gamma - 1)) within 4 of its
    sampling errors; a profile whose radius is in other units than its name says is flagged."""
    from collisionkit.encounters import ProfileStarParameters, profile_star_summary

    profile = polytrope_cells(1.5, zones=2000)
    path = _write_mesa(tmp_path / "profile1.data", profile)
    summary, star = profile_star_summary(ProfileStarParameters(profile=str(path), particles=4000, neighbours=20,
                                                               units="stellar", seed=3))
    assert summary["warnings"] == [] and abs(summary["profile"]["virial_ratio"] - 1.0) < 1e-4
    assert summary["profile"]["mass_g"] == pytest.approx(MASS, rel=1e-3) and summary["star"]["particles"] == 4000
    assert summary["internal_energy"].startswith("P / ((gamma - 1) rho), gamma 1.666")
    thermal_expected = -summary["potential_energy_profile"] / (3.0 * (5.0 / 3.0 - 1.0))
    u = star.internal_energies  # sum m u estimates int u dm with the relative error std(u) / mean(u) / sqrt(K)
    noise = float(u.std() / u.mean()) / math.sqrt(len(u))
    assert abs(summary["thermal_energy"] / thermal_expected - 1.0) < 4.0 * noise + 1e-3
    assert summary["potential_energy_profile"] == pytest.approx(-3.0 / 3.5 * star.G * 1.0**2 / 1.0, rel=1e-3)
    wrong = _write_mesa(tmp_path / "profile2.data", profile, ("radius_cm", "logRho", "logP", "mass"))
    wrong.write_text(wrong.read_text().replace("radius_cm", "radius"))  # cm values read as Rsun
    flagged, _ = profile_star_summary(ProfileStarParameters(profile=str(wrong), particles=100, neighbours=10))
    assert any("not in hydrostatic equilibrium" in text for text in flagged["warnings"])


def test_a_coarse_uniform_sphere_needs_its_core_and_r_cubed_in_the_mass():
    """A uniform sphere (rho = 1, R = 1) given by points from r = 1/2 and by 3 cells: the mass inside the first
    zone (1/8 of it) enters W as a uniform core, -(3/5) G m0^2 / r0, so W = -(3/5) G M^2 / R within the
    trapezoids' error (5e-4 with 2000 points); and radii sampled in 3 cells follow r^3 = m / M (KS bound at
    99.9 % for 20000). Kills: W without its core (3 % off), r linear in m within a cell."""
    r = np.linspace(0.5, 1.0, 2000)
    points = StellarProfile(r, np.ones_like(r), 1.0 - r**2 + 1e-3)
    mass = 4.0 / 3.0 * math.pi
    assert points.potential_energy() == pytest.approx(-0.6 * G_CGS * mass**2, rel=5e-4)
    cells = StellarProfile([1.0 / 3.0, 2.0 / 3.0, 1.0], [1.0, 1.0, 1.0], [1.0, 1.0, 1.0], cells=True)
    rng = np.random.default_rng(7)
    sampled = cells.radius_of_mass(rng.random(20000) * cells.total_mass)
    assert stats.kstest(sampled**3, "uniform").statistic < 1.95 / math.sqrt(20000)
