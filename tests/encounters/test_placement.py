"""Two particle stars placed on the StarCrash orbit: rigid moves, the two-body solution, eqs. 34-39 from the file."""

from __future__ import annotations

import dataclasses
import math
import warnings

import h5py
import numpy as np
import pytest

from collisionkit.encounters import (
    GridExitWarning,
    StarEncounterParameters,
    TidalWarning,
    place_stars,
    polytrope_star,
    star_encounter_summary,
    unit_system,
    write_star,
)

EPS = np.finfo(float).eps


def spinning(star, seed):
    """A star off the origin, drifting and spinning: placement must move it rigidly whatever it does."""
    rng = np.random.default_rng(seed)
    omega = rng.normal(size=3) * 1e-3
    return dataclasses.replace(star, positions=star.positions + rng.normal(size=3),
                               velocities=np.cross(omega, star.positions) + rng.normal(size=3) * 1e-2)


@pytest.fixture(scope="module")
def stars():
    """A 1 Msun, 1 Rsun n = 1.5 star and a 0.6 Msun, 0.5 Rsun n = 3 star in stellar units (Msun, Rsun, km/s)."""
    first = spinning(polytrope_star(1.5, 700, 1.0, 1.0, units="stellar", neighbours=20, seed=1), 2)
    second = spinning(polytrope_star(3.0, 400, 0.6, 0.5, units="stellar", neighbours=20, seed=3), 4)
    return first, dataclasses.replace(second, ids=second.ids + 5)  # IDs 6 ... 405: they overlap star 1's


PARAMETERS = StarEncounterParameters(rp=1.2, v_inf=100.0, sep0=12.0, units="stellar")


def pairs_of(count, seed=5, size=3000):
    pairs = np.random.default_rng(seed).integers(0, count, size=(size, 2))
    return pairs[pairs[:, 0] != pairs[:, 1]]


@pytest.mark.parametrize("layout", ["diagonal", "x"])
def test_placement_is_rigid_and_puts_each_centre_of_mass_on_the_two_body_orbit(stars, layout):
    parameters = PARAMETERS.replace(layout=layout)
    summary, ic, pair = star_encounter_summary(*stars, parameters)
    reach = np.max(np.abs(pair.positions))  # the largest coordinate: the round-off of a shift is ~ eps of it
    speed = np.max(np.abs(pair.velocities))
    for number, star in enumerate(stars, start=1):
        mine = pair.star_ids == number
        assert np.count_nonzero(mine) == len(star)
        moved_x, moved_v = pair.positions[mine], pair.velocities[mine]
        pairs = pairs_of(len(star))
        for before, after, scale in ((star.positions, moved_x, reach), (star.velocities, moved_v, speed)):
            d_before = np.linalg.norm(before[pairs[:, 0]] - before[pairs[:, 1]], axis=1)
            d_after = np.linalg.norm(after[pairs[:, 0]] - after[pairs[:, 1]], axis=1)
            assert np.max(np.abs(d_after - d_before)) <= 8 * EPS * scale
        masses = pair.masses[mine]
        assert np.array_equal(masses, star.masses)
        centre, velocity = masses @ moved_x / masses.sum(), masses @ moved_v / masses.sum()
        assert np.allclose(centre, ic.positions[number - 1], rtol=0, atol=64 * EPS * reach)
        assert np.allclose(velocity, ic.velocities[number - 1], rtol=0, atol=64 * EPS * speed)
        for name in ("smoothing_lengths", "internal_energies"):
            assert np.array_equal(getattr(pair, name)[mine], getattr(star, name))
    momentum = pair.masses @ pair.velocities
    assert np.all(np.abs(momentum) <= 64 * EPS * pair.mass * speed)  # total momentum zero
    assert np.all(np.abs(pair.centre_of_mass) <= 64 * EPS * reach)  # centre of mass at the origin
    assert summary["initial_conditions"]["layout"] == layout


def test_the_ids_are_star_1_s_then_star_2_s_following_them(stars):
    pair = place_stars(*stars, PARAMETERS)
    first, second = stars
    assert np.array_equal(pair.ids[: len(first)], first.ids)
    assert np.array_equal(pair.ids[len(first):], second.ids - second.ids.min() + first.ids.max() + 1)
    assert np.unique(pair.ids).size == len(pair)
    assert pair.star_ids.tolist() == [1] * len(first) + [2] * len(second)


def test_eqs_34_to_39_recomputed_from_the_particle_file(stars, tmp_path):
    """Read the HDF5 file back with h5py alone, group by StarID, and find the StarCrash quantities in it."""
    pair = place_stars(*stars, PARAMETERS)
    path = write_star(pair, tmp_path / "initial_conditions.hdf5")
    with h5py.File(path, "r") as file:
        gas = file["PartType0"]
        x, v, m, star_id = gas["Coordinates"][()], gas["Velocities"][()], gas["Masses"][()], gas["StarID"][()]
        units = file["Units"].attrs
        G = 6.67430e-8 * units["Unit mass in cgs (U_M)"] * units["Unit time in cgs (U_t)"] ** 2 \
            / units["Unit length in cgs (U_L)"] ** 3  # CODATA 2018, in the file's units
    assert G == pytest.approx(unit_system("stellar").G, rel=1e-15, abs=0)
    (M1, X1, V1), (M2, X2, V2) = ((m[star_id == k].sum(), m[star_id == k] @ x[star_id == k] / m[star_id == k].sum(),
                                   m[star_id == k] @ v[star_id == k] / m[star_id == k].sum()) for k in (1, 2))
    rp, v_inf, r0 = PARAMETERS.rp, PARAMETERS.v_inf, PARAMETERS.sep0
    assert (M1, M2) == (pytest.approx(1.0, rel=1e-14), pytest.approx(0.6, rel=1e-14))
    M, mu = M1 + M2, M1 * M2 / (M1 + M2)
    r, u = X2 - X1, V2 - V1
    assert np.linalg.norm(r) == pytest.approx(r0, rel=1e-13, abs=0)
    energy = 0.5 * mu * u @ u - G * M1 * M2 / np.linalg.norm(r)
    assert energy == pytest.approx(0.5 * mu * v_inf**2, rel=1e-12, abs=0)  # eq. 34
    assert np.linalg.norm(u) == pytest.approx(math.sqrt(v_inf**2 + 2 * G * M / r0), rel=1e-13, abs=0)  # eq. 35
    J = mu * np.linalg.norm(np.cross(r, u))
    vp = math.sqrt(v_inf**2 + 2 * G * M / rp)  # eq. 36
    assert J == pytest.approx(mu * vp * rp, rel=1e-12, abs=0)  # eq. 37
    b = math.sqrt(rp**2 + 2 * G * M * rp / v_inf**2)  # eq. 38
    assert J / (mu * v_inf) == pytest.approx(b, rel=1e-12, abs=0)
    vt = np.linalg.norm(np.cross(r, u)) / r0
    assert vt == pytest.approx(v_inf * b / r0, rel=1e-12, abs=0)  # eq. 39
    vr = -(r @ u) / r0
    assert vr == pytest.approx(math.sqrt(u @ u - vt**2), rel=1e-12, abs=0) and vr > 0  # inbound
    # the grid-corner layout: star 2 towards (1, 1, 1), the transverse velocity with v_x = v_y
    assert r / r0 == pytest.approx(np.ones(3) / math.sqrt(3), rel=1e-13, abs=0)
    transverse = u + vr * r / r0
    assert transverse[0] == pytest.approx(transverse[1], rel=1e-12, abs=0)


def test_the_stars_are_converted_to_the_encounter_s_units(stars):
    first, second = stars
    in_cgs = StarEncounterParameters(rp=1.2 * 6.957e10, v_inf=100e5, sep0=12 * 6.957e10, units="cgs")
    summary, ic, pair = star_encounter_summary(first.in_units("cgs"), second, in_cgs)
    _, ic_stellar, pair_stellar = star_encounter_summary(first, second, PARAMETERS)
    assert pair.units.name == "cgs"
    assert ic.impact_parameter / 6.957e10 == pytest.approx(ic_stellar.impact_parameter, rel=1e-10, abs=0)
    assert np.allclose(pair.in_units("stellar").positions, pair_stellar.positions, rtol=1e-10, atol=1e-10)
    with pytest.raises(ValueError, match="star1 is in nbody units and the encounter in cgs"):
        place_stars(polytrope_star(1.5, 100, neighbours=10, seed=1), second, in_cgs)


def test_the_summary_has_both_stars_their_radii_and_the_overlap(stars):
    summary, ic, pair = star_encounter_summary(*stars, PARAMETERS)
    for key, star in zip(("star1", "star2"), stars):
        entry = summary["stars"][key]
        assert entry["particles"] == len(star) and entry["mass"] == star.mass
        assert entry["radius_99"] == star.radius(0.99) and entry["centre_of_mass"] == star.centre_of_mass.tolist()
    r1, r2 = summary["stars"]["star1"]["radius_99"], summary["stars"]["star2"]["radius_99"]
    assert 0.8 < r1 < 1.0 and 0.3 < r2 < 0.5  # 99 % of the mass of an n = 1.5 and an n = 3 star
    assert summary["overlap_at_sep0"] is False and summary["sep0_over_radii"] == pytest.approx(12 / (r1 + r2))
    assert summary["contact"]["radius1"] == r1 and summary["contact"]["touches"] is (1.2 < r1 + r2)
    assert summary["parameters"] == PARAMETERS.to_dict() and summary["point_masses"]["m1"] == stars[0].mass
    assert summary["warnings"] == []


def test_stars_too_close_for_tides_or_overlapping_are_warned(stars):
    r1, r2 = stars[0].radius(0.99), stars[1].radius(0.99)
    near = PARAMETERS.replace(sep0=4 * (r1 + r2), layout="x")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        place_stars(*stars, near)
    assert [item.category for item in caught] == [TidalWarning]
    summary, _, _ = star_encounter_summary(*stars, near)
    assert summary["overlap_at_sep0"] is False and any("tidal effects" in text for text in summary["warnings"])
    touching = PARAMETERS.replace(rp=0.5, sep0=0.9 * (r1 + r2), layout="x")
    summary, _, _ = star_encounter_summary(*stars, touching)
    assert summary["overlap_at_sep0"] is True
    assert any("overlap" in text for text in summary["warnings"]) and any("tidal" in text for text in summary["warnings"])


def test_the_orbit_may_be_a_mapping_but_not_point_masses(stars):
    from collisionkit.encounters import EncounterParameters

    pair = place_stars(*stars, {"rp": 1.2, "vinf": 100.0, "sep0": 12.0, "units": "stellar"})
    assert np.array_equal(pair.positions, place_stars(*stars, PARAMETERS).positions)
    with pytest.raises(TypeError, match="the masses come from the particles"):
        place_stars(*stars, EncounterParameters(m1=3.0))
    with pytest.raises(ValueError, match="unknown parameter 'm1'"):
        place_stars(*stars, {"m1": 3.0})


def test_the_grid_exit_warning_is_kept(stars):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        place_stars(*stars, PARAMETERS.replace(v_inf=800.0, rp=10.0, sep0=12.0))
    assert GridExitWarning in [item.category for item in caught]
    with pytest.raises(ValueError, match="sep0 must be >= rp"):
        place_stars(*stars, PARAMETERS.replace(rp=20.0))


def test_outer_envelopes_within_periastron_are_warned_when_the_99_percent_radii_miss(stars):
    """The outermost particles' distances from each centre of mass are in the summary; an rp between the sum of the
    99 %-mass radii and the sum of the outer radii warns that the envelopes graze (a real star's envelope holds
    little mass far out); below both, the stars touch and no separate warning is given."""
    r1, r2 = stars[0].radius(0.99), stars[1].radius(0.99)
    outer1, outer2 = stars[0].radius(1.0), stars[1].radius(1.0)
    assert outer1 + outer2 > r1 + r2
    grazing = PARAMETERS.replace(rp=0.5 * (r1 + r2 + outer1 + outer2))
    summary, _, _ = star_encounter_summary(*stars, grazing)
    assert summary["outer_radii"] == [outer1, outer2] and summary["envelopes_touch"] is True
    assert summary["contact"]["touches"] is False
    assert any("outer envelopes reach within periastron" in text for text in summary["warnings"])
    head_on = PARAMETERS.replace(rp=0.5 * (r1 + r2))
    summary, _, _ = star_encounter_summary(*stars, head_on)
    assert summary["envelopes_touch"] is True and not any("outer envelopes" in text for text in summary["warnings"])
    far = PARAMETERS.replace(rp=1.01 * (outer1 + outer2), sep0=12.0)
    assert star_encounter_summary(*stars, far)[0]["envelopes_touch"] is False
