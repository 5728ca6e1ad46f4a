"""StarCrash set-up (user manual, J. Faber 2003, "Hyperbolic Collisions", eqs. 34-39).

Independent route: the seed's equations written out literally; the oriented
orbit must start at the initial conditions; the grid warning's threshold is
found by root finding.
"""

from __future__ import annotations

import json
import math
import re
import warnings

import numpy as np
import pytest
from hypothesis import given
from scipy.optimize import brentq

from collisionkit import encounters
from collisionkit.encounters import GridExitWarning, Hyperbolic, starcrash_initial_conditions, unit_system
from tests.encounters.reference import distances, log_uniform, masses, speeds


def test_starcrash_worked_example():
    """m1 = m2 = 1, rp = 1, v_inf = 0.5, r0 = 10, G = 1, eqs. 34-39 by hand."""
    ic = starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, 10.0, G=1.0)
    assert ic.energy == pytest.approx(0.5 * 0.5 * 0.25, rel=1e-15, abs=0)  # eq. 34
    assert ic.v0 == pytest.approx(math.sqrt(0.65), rel=1e-15, abs=0)  # eq. 35
    assert ic.vp == pytest.approx(math.sqrt(4.25), rel=1e-15, abs=0)  # eq. 36
    assert ic.angular_momentum == pytest.approx(0.5 * math.sqrt(4.25), rel=1e-15, abs=0)  # eq. 37
    assert ic.impact_parameter == pytest.approx(math.sqrt(17.0), rel=1e-15, abs=0)  # eq. 38
    assert ic.vt == pytest.approx(0.5 * math.sqrt(17.0) / 10.0, rel=1e-15, abs=0)  # eq. 39
    assert ic.vr == pytest.approx(math.sqrt(0.65 - 0.0425), rel=1e-14, abs=0)
    assert ic.orbit.eccentricity == pytest.approx(1.125, rel=1e-15, abs=0)


@given(m1=masses, m2=masses, rp=distances, v_inf=speeds, stretch=log_uniform(-6, 3))
def test_starcrash_equations_over_wide_ranges(m1, m2, rp, v_inf, stretch):
    G = 1.0
    r0 = rp * (1.0 + stretch)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GridExitWarning)
        ic = starcrash_initial_conditions(m1, m2, rp, v_inf, r0, G=G)
    M, mu = m1 + m2, m1 * m2 / (m1 + m2)
    # the seed's equations, written out literally
    v0 = math.sqrt(v_inf**2 + 2 * G * M / r0)
    vp = math.sqrt(v_inf**2 + 2 * G * M / rp)
    J = mu * math.sqrt(rp**2 * v_inf**2 + 2 * G * M * rp)
    b = J / (mu * v_inf)
    vt = math.sqrt(rp**2 * v_inf**2 + 2 * G * M * rp) / r0
    assert ic.energy == pytest.approx(0.5 * mu * v_inf**2, rel=1e-14, abs=0)
    assert ic.v0 == pytest.approx(v0, rel=1e-14, abs=0)
    assert ic.vp == pytest.approx(vp, rel=1e-14, abs=0)
    assert ic.angular_momentum == pytest.approx(mu * vp * rp, rel=1e-14, abs=0)
    assert ic.angular_momentum == pytest.approx(J, rel=1e-14, abs=0)
    assert ic.impact_parameter == pytest.approx(b, rel=1e-14, abs=0)
    assert ic.impact_parameter == pytest.approx(math.sqrt(rp**2 + 2 * G * M * rp / v_inf**2), rel=1e-14, abs=0)
    assert ic.vt == pytest.approx(vt, rel=1e-14, abs=0)
    assert ic.vt == pytest.approx(v_inf * b / r0, rel=1e-14, abs=0)
    # v_r = sqrt(v0^2 - v_t^2): compare squares (the literal difference cancels near periastron)
    assert ic.vr**2 + ic.vt**2 == pytest.approx(v0**2, rel=1e-13, abs=0)
    # the arrays: centre of mass at rest at the origin, separation r0, speeds v_t and v_r
    x, v = ic.positions, ic.velocities
    assert x.shape == v.shape == (2, 3)
    assert np.allclose(m1 * x[0] + m2 * x[1], 0.0, atol=1e-14 * M * r0)
    assert np.allclose(m1 * v[0] + m2 * v[1], 0.0, atol=1e-14 * M * v0)
    separation, relative = x[1] - x[0], v[1] - v[0]
    assert np.linalg.norm(separation) == pytest.approx(r0, rel=1e-14, abs=0)
    unit = separation / np.linalg.norm(separation)
    assert np.allclose(unit, np.ones(3) / math.sqrt(3.0), rtol=0, atol=1e-15)
    assert relative @ unit == pytest.approx(-ic.vr, rel=1e-12, abs=1e-14 * v0)
    transverse = relative - (relative @ unit) * unit
    assert np.linalg.norm(transverse) == pytest.approx(ic.vt, rel=1e-12, abs=1e-14 * v0)
    assert v[0, 0] == v[0, 1] and v[1, 0] == v[1, 1]  # v_x = v_y for both stars
    # the oriented orbit starts at the initial conditions
    start_x, start_v = ic.orbit.state_at_time(-ic.time_to_periastron)
    assert np.allclose(start_x, x, rtol=0, atol=1e-11 * r0)
    assert np.allclose(start_v, v, rtol=0, atol=1e-11 * v0)


def test_stars_in_opposite_corners_and_plain_layout():
    diagonal = starcrash_initial_conditions(2.0, 1.0, 1.0, 0.5, 12.0)
    x = diagonal.positions
    assert np.all(x[1] > 0) and np.all(x[0] < 0)  # opposite corners (+,+,+) and (-,-,-)
    assert x[1][0] == x[1][1] == x[1][2]
    assert np.dot(diagonal.velocities[1] - diagonal.velocities[0], np.ones(3)) < 0  # approaching
    plain = starcrash_initial_conditions(2.0, 1.0, 1.0, 0.5, 12.0, layout="x")
    separation = plain.positions[1] - plain.positions[0]
    assert separation == pytest.approx([12.0, 0.0, 0.0], abs=1e-14)
    relative = plain.velocities[1] - plain.velocities[0]
    assert relative == pytest.approx([-diagonal.vr, diagonal.vt, 0.0], rel=1e-14, abs=0)
    assert plain.time_to_periastron == pytest.approx(diagonal.time_to_periastron, rel=1e-14, abs=0)
    assert plain.orbit.time_since_periastron(separation, relative) == pytest.approx(-plain.time_to_periastron, rel=1e-12, abs=0)


def _ratio(sep0):
    return starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, sep0, layout="x").speed_ratio


def test_grid_warning_threshold_is_where_a_star_leaves_its_corner():
    """The seed's sqrt(1/3): above it, the star in the (+,+,+) corner gets v_z > 0 (outwards)."""
    threshold_sep0 = brentq(lambda s: _ratio(s) - math.sqrt(1.0 / 3.0), 1.0 + 1e-9, 100.0, xtol=1e-14)
    with pytest.warns(GridExitWarning, match=r"sqrt\(1/3\)"):
        above = starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, threshold_sep0 * 0.99)
    assert above.speed_ratio > math.sqrt(1.0 / 3.0)
    assert above.velocities[1, 2] > 0 and above.velocities[0, 2] < 0  # both head out of the grid
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        below = starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, threshold_sep0 * 1.01)
        plain = starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, threshold_sep0 * 0.5, layout="x")
    assert below.speed_ratio < math.sqrt(1.0 / 3.0)
    assert np.all(below.velocities[1] < 0) and np.all(below.velocities[0] > 0)
    assert plain.speed_ratio > math.sqrt(1.0 / 3.0)  # no grid, no warning


def test_grid_warning_is_a_user_warning_subclass():
    assert issubclass(GridExitWarning, UserWarning)
    with pytest.warns(GridExitWarning):
        starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, 1.0)  # r0 = rp: all transverse


def test_write_initial_conditions(tmp_path):
    ic = starcrash_initial_conditions(1.0, 3.0, 2.0, 0.3, 20.0)
    json_path, text_path = ic.write(tmp_path / "ic", units=unit_system("nbody"))
    data = json.loads(json_path.read_text())
    assert data["impact_parameter"] == ic.impact_parameter
    assert data["units"]["name"] == "nbody"
    assert np.array_equal(np.array(data["positions"]), ic.positions)
    assert np.array_equal(np.array(data["velocities"]), ic.velocities)
    table = np.loadtxt(text_path)
    assert table.shape == (2, 8)
    assert np.array_equal(table[:, 0], [1, 2]) and np.array_equal(table[:, 1], [1.0, 3.0])
    assert np.array_equal(table[:, 2:5], ic.positions) and np.array_equal(table[:, 5:], ic.velocities)
    assert sorted(p.name for p in (tmp_path / "ic").iterdir()) == ["initial_conditions.json", "initial_conditions.txt"]


def test_tiny_speeds_and_unit_names(tmp_path):
    # v_inf^2 rounding to 0 was a ZeroDivisionError; a unit system given by name an AttributeError
    with pytest.raises(ValueError, match=re.escape("v_inf must lie in (1.49e-154, 1.34e+154)")):
        Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1e-200)
    with pytest.raises(ValueError, match="v_inf"):
        Hyperbolic.from_impact_parameter(1.0, 1.0, 1.0, 1e-160)
    ic = encounters.starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, 10.0)
    json_path, _ = ic.write(tmp_path, units="cgs")
    assert json.loads(json_path.read_text())["units"]["name"] == encounters.unit_system("cgs").name
    with pytest.raises(TypeError, match="units"):
        ic.write(tmp_path, units=3)


# ------------------------------------------------------------------ bad input


def test_starcrash_rejects_bad_input():
    with pytest.raises(ValueError, match="sep0 must be >= rp"):
        starcrash_initial_conditions(1.0, 1.0, 2.0, 0.5, 1.0)
    with pytest.raises(ValueError, match="v_inf"):
        starcrash_initial_conditions(1.0, 1.0, 1.0, 0.0, 10.0)
    with pytest.raises(ValueError, match="m2"):
        starcrash_initial_conditions(1.0, 0.0, 1.0, 0.5, 10.0)
    with pytest.raises(ValueError, match="sep0"):
        starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, float("nan"))
    with pytest.raises(ValueError, match="G"):
        starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, 10.0, G=0.0)
    with pytest.raises(ValueError, match="layout"):
        starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, 10.0, layout="y")


@pytest.mark.parametrize(("masses", "v_inf", "scale"), [
    ((1e300, 1e300), 0.5, "G m1 m2 / rp = inf"),
    ((1e-300, 1e-300), 0.5, "G m1 m2 / rp = 0"),
    ((1.0, 1.0), 1e-160, "v_inf must lie in"),
    ((1.0, 1.0), 1e160, "v_inf must lie in"),
    ((1e150, 1e150), 1e150, "mu v_inf^2 = inf"),
])
def test_a_set_up_beyond_the_float_range_is_a_named_value_error(masses, v_inf, scale):
    """Scales that overflow or vanish in double precision are refused by name, never an OverflowError or a 0."""
    with pytest.raises(ValueError, match=re.escape(scale)):
        starcrash_initial_conditions(*masses, 1.0, v_inf, 10.0)


def test_tiny_masses_keep_their_reduced_mass_and_energy():
    """m1 m2 underflows for masses of 1e-160; mu = (m1 / M) m2 does not (the exact value is m / 2)."""
    ic = starcrash_initial_conditions(1e-160, 1e-160, 1e-160, 1e-40, 1e-159)
    assert ic.orbit.reduced_mass == pytest.approx(0.5e-160, rel=1e-15)
    assert ic.energy == pytest.approx(0.5 * 0.5e-160 * 1e-80, rel=1e-12)
