"""Square wells: the edge events against energy and momentum conservation, the record of pairs inside, checkpoints."""

import math

import numpy as np
import pytest

from collisionkit import edmd
from collisionkit._io import CheckpointError
from collisionkit._kernels import edmd as kernels

from .systems import fcc_system, hexagonal_system

MASSES = np.array([1.0, 3.0])
REDUCED = MASSES.prod() / MASSES.sum()


def head_on_pair(separation, relative_speed, depth=1.0):
    """Two discs of diameter 1 (masses 1 and 3) on a line along x, relative velocity ``relative_speed`` (> 0 apart)."""
    positions = [[5.0, 10.0], [5.0 + separation, 10.0]]
    # velocities with zero total momentum: v1 = -m2 u / M, v2 = m1 u / M
    velocities = [[-MASSES[1] * relative_speed / MASSES.sum(), 0.0], [MASSES[0] * relative_speed / MASSES.sum(), 0.0]]
    return edmd.HardSphereSystem(positions, velocities, 0.5, 20.0, masses=MASSES, well_width=1.5, well_depth=depth)


def relative_speed(system):
    velocities = system.velocities()
    return float(velocities[1, 0] - velocities[0, 0])


def test_capture_speeds_the_pair_up_by_the_well_depth():
    # approaching at 1.5 from 4 apart: the edge (1.5) at t = 2.5 / 1.5, the core 0.5 further on
    system = head_on_pair(4.0, -1.5)
    system.run(time=1.7)
    assert system.well_pairs == 1 and system.well_events["captures"] == 1
    # mu u'^2 / 2 = mu u^2 / 2 + epsilon
    assert relative_speed(system) == pytest.approx(-math.sqrt(1.5**2 + 2.0 / REDUCED), rel=1e-14)
    assert system.potential_energy() == -1.0
    np.testing.assert_allclose(system.momentum(), 0.0, atol=1e-15)
    # the virial: the impulse on the second disc along r times r, mu (u_n' - u_n) |r| with |r| = lambda sigma
    assert system.virial == pytest.approx(REDUCED * (-math.sqrt(1.5**2 + 2.0 / REDUCED) + 1.5) * 1.5, rel=1e-12)


def test_a_pair_that_collided_inside_escapes_at_its_first_speed():
    system = head_on_pair(4.0, -1.5)
    system.run(time=1.0)
    system.synchronise()  # the clock restarts: the pairs' time integral must carry over
    system.run(time=3.0)
    # inside from the capture at 2.5 / 1.5 to the escape 2 * 0.5 / |u'| later (core at sigma, back out at 1.5 sigma)
    assert system.well_pair_time() == pytest.approx(1.0 / math.sqrt(1.5**2 + 2.0 / REDUCED), rel=1e-12)
    assert system.collisions == 1 and system.well_events == {"captures": 1, "escapes": 1, "bounces": 0}
    assert relative_speed(system) == pytest.approx(1.5, rel=1e-14)
    assert system.well_pairs == 0 and system.potential_energy() == 0.0


def test_a_fast_pair_inside_escapes_losing_the_well_depth():
    system = head_on_pair(1.2, 2.0)
    system.run(time=1.0)
    assert system.well_events == {"captures": 0, "escapes": 1, "bounces": 0}
    assert relative_speed(system) == pytest.approx(math.sqrt(4.0 - 2.0 / REDUCED), rel=1e-14)


def test_a_slow_pair_stays_bound_bouncing_between_core_and_edge():
    # mu u^2 / 2 = 0.09375 < epsilon: trapped for ever, |u| kept
    system = head_on_pair(1.2, 0.5)
    before = system.total_energy()
    system.run(time=200.0)
    events = system.well_events
    assert events["escapes"] == 0 and events["bounces"] > 50 and abs(events["bounces"] - system.collisions) <= 1
    assert system.well_pairs == 1
    assert abs(relative_speed(system)) == pytest.approx(0.5, rel=1e-12)
    assert system.total_energy() == pytest.approx(before, rel=1e-13)


def test_a_bound_pair_never_colliding_is_not_taken_for_a_stall():
    # a pair bound in its well orbits without touching the core: a run by collisions would wait for ever, a run by
    # time goes on, events at the edge counting as progress
    positions = [[5.0, 5.0], [6.3, 5.0]]
    velocities = [[0.0, -0.05], [0.0, 0.05]]
    system = edmd.HardSphereSystem(positions, velocities, 0.5, 20.0, well_width=1.5, well_depth=1.0)
    system.run(time=2000.0)
    assert system.well_pairs == 1 and system.well_events["bounces"] > 0


@pytest.mark.parametrize("make", [fcc_system, hexagonal_system])
def test_dense_fluid_conserves_energy_and_momentum_to_round_off(make):
    system = make(eta=0.3, seed=4, well_width=1.5, well_depth=1.0)
    energy, momentum = system.total_energy(), system.momentum()
    system.run(collisions=25 * system.count)
    system.run(collisions=system.count)  # starts by renumbering the particles in cell order (after 20 N collisions)
    events = system.well_events
    assert min(events.values()) > system.count  # every kind of edge event happened, many times
    assert system.total_energy() == pytest.approx(energy, rel=1e-12)
    np.testing.assert_allclose(system.momentum(), momentum, atol=1e-12 * system.count)
    system.check()  # no overlap, and the record agrees with the distances (also after the renumbering sorts)
    assert system.last_sort > 0


def test_the_record_follows_a_checkpoint_bit_for_bit(tmp_path):
    system = fcc_system(cells=3, eta=0.3, well_width=1.7, well_depth=0.5)
    system.run(collisions=2000)
    path = tmp_path / "wells.npz"
    system.save(path)
    restored = edmd.HardSphereSystem.load(path)
    system.run(collisions=3000)
    restored.run(collisions=3000)
    assert (restored.velocities() == system.velocities()).all()
    assert restored.well_pairs == system.well_pairs and restored.well_events == system.well_events
    assert restored.well_pair_time() == system.well_pair_time()


def test_a_checkpoint_with_a_one_sided_record_is_refused():
    system = fcc_system(cells=3, eta=0.3, well_width=1.5)
    state = system.state_dict()
    i = int(np.flatnonzero(state["bond_count"])[0])
    state["bond_count"] = state["bond_count"].copy()
    state["bond_count"][i] -= 1
    with pytest.raises(CheckpointError, match="bonds"):
        edmd.HardSphereSystem.from_state_dict(state)


def test_hard_sphere_checkpoints_carry_no_record():
    state = fcc_system(cells=3).state_dict()
    assert not state["bond_count"].any()
    state["bond_count"] = state["bond_count"].copy()
    state["bond_count"][0] = 1
    with pytest.raises(CheckpointError, match="bond_count"):
        edmd.HardSphereSystem.from_state_dict(state)


def test_well_pair_time_integrates_across_clock_restarts():
    positions = [[1.0, 1.0], [2.2, 1.0], [5.0, 5.0]]
    system = edmd.HardSphereSystem(positions, np.zeros((3, 2)), 0.5, 10.0, well_width=1.5)
    system.run(time=1.5)
    system.synchronise()
    system.run(time=1.0)
    assert system.well_pair_time() == pytest.approx(2.5, rel=1e-15)


@pytest.mark.parametrize(("options", "message"), [
    ({"well_width": 1.0}, "well_width must be"),
    ({"well_width": 6.0}, "well_width must be"),
    ({"well_width": math.nan}, "well_width must be"),
    ({"well_width": 1.5, "well_depth": 0.0}, "well_depth must be"),
    ({"well_width": 1.5, "well_depth": -1.0}, "well_depth must be"),
    ({"well_width": 1.5, "shear_rate": 0.1}, "without shear_rate"),
    ({"well_width": 1.5, "engine": "cells"}, 'without engine="cells"'),
    ({"well_width": 1.5, "restitution": 0.9}, "without restitution or wall_restitution below 1"),
    ({"well_width": 1.5, "wall_restitution": 0.9, "periodic": False}, "without restitution or wall_restitution"),
])
def test_bad_well_arguments_are_refused_by_name(options, message):
    with pytest.raises(ValueError, match=message):
        hexagonal_system(cells=6, **options)


def test_hard_spheres_report_no_potential_energy():
    system = hexagonal_system(cells=6)
    measurement = edmd.measure(system, collisions=2000, blocks=2)
    assert system.well_width is None and system.potential_energy() == 0.0
    assert measurement.potential_energy == 0.0 and "potential_energy" not in measurement.summary()


def test_a_checkpoint_with_a_record_narrower_than_the_lists_is_refused():
    state = fcc_system(cells=3, eta=0.3, well_width=1.5).state_dict()
    state["bonds"] = np.ascontiguousarray(state["bonds"][:, :1])
    with pytest.raises(CheckpointError, match="as wide as the neighbour lists"):
        edmd.HardSphereSystem.from_state_dict(state)


def test_the_system_shows_its_wells():
    system = hexagonal_system(cells=6, well_width=1.5, well_depth=2.0)
    assert "well_width=1.5, well_depth=2" in repr(system)
    assert "square wells: width, depth, pairs inside" in system._repr_html_()
    assert "well" not in repr(hexagonal_system(cells=6))


def test_sticky_spheres_settling_under_gravity_conserve_energy_with_their_fall():
    # walls below and above, gravity down: kinetic + wells' - sum m g . x is conserved; pairs fall into wells
    positions, box = edmd.lattice("hexagonal", 10, 0.2)
    box = box + 1.0
    system = edmd.HardSphereSystem(positions + 0.5, edmd.maxwell_boltzmann(np.ones(len(positions)), 2, seed=5), 0.5,
                                   box, periodic=[True, False], gravity=[0.0, -0.5], well_width=1.5, well_depth=0.5)
    energy = system.total_energy()
    height = system.positions()[:, 1].mean()
    system.run(collisions=30 * system.count)
    assert system.total_energy() == pytest.approx(energy, rel=1e-12)
    assert system.wall_collisions > 0 and system.well_events["captures"] > system.count
    assert system.positions()[:, 1].mean() < height  # it settled
    system.check()


def test_a_pair_gliding_along_the_edge_of_its_well_bounces_along_it():
    # inside (by 1e-12), moving along the edge: chords shorter than round-off, the edge outside by round-off at the
    # next event, r.u = 0 exactly at the first; it leaves at the chord's far end and bounces back in, again and again
    # (a whispering-gallery orbit: about 3e5 bounces a unit of time here), never stalling
    system = edmd.HardSphereSystem([[5.0, 5.0], [6.5 - 1e-12, 5.0]], [[0.0, 0.0], [0.0, 1.0]], 0.5, 20.0,
                                   well_width=1.5)
    assert system.well_pairs == 1
    energy = system.total_energy()
    system.run(time=1e-3)
    assert system.well_pairs == 1 and system.well_events["escapes"] == 0 and system.well_events["bounces"] > 100
    assert system.total_energy() == pytest.approx(energy, rel=1e-12)
    exactly = edmd.HardSphereSystem([[5.0, 5.0], [6.5, 5.0]], [[0.0, 0.0], [0.0, 1.0]], 0.5, 20.0, well_width=1.5)
    assert exactly.well_pairs == 0  # r = lambda sigma exactly is outside (r < lambda sigma is inside)


def test_time_to_leave_takes_the_later_root_and_the_edge_cases():
    from collisionkit._kernels.edmd.wells import time_to_leave
    # |r + u t|^2 = w^2 with r = (0.5, 0), u = (1, 0), w = 1.5: t = 1 (and -2)
    assert time_to_leave(1.0, 0.5, 0.25 - 2.25) == pytest.approx(1.0, rel=1e-15)
    assert time_to_leave(1.0, -0.5, 0.25 - 2.25) == pytest.approx(2.0, rel=1e-15)
    assert time_to_leave(1.0, 1e-9, 1e-16) == 0.0  # at the edge, receding: now
    assert time_to_leave(1.0, -1e-8, 1e-15) == pytest.approx(2e-8, rel=1e-6)  # grazing chord despite round-off
    assert time_to_leave(0.0, 0.0, -1.0) == math.inf


def test_a_checkpoint_recording_pairs_that_are_not_neighbours_is_refused():
    system = fcc_system(cells=3, eta=0.3, well_width=1.5)
    state = system.state_dict()
    state["bonds"], state["bond_count"] = state["bonds"].copy(), state["bond_count"].copy()
    listed = set(state["neighbours"][0, : state["neighbour_count"][0]].tolist())
    far = next(j for j in range(1, system.count) if j not in listed)  # a phantom pair, symmetric and counted
    for owner, partner in ((0, far), (far, 0)):
        state["bonds"][owner, state["bond_count"][owner]] = partner
        state["bond_count"][owner] += 1
    state["acc"] = state["acc"].copy()
    state["acc"][kernels.ACC_WELL_PAIRS] += 1
    with pytest.raises(CheckpointError, match="neighbour lists"):
        edmd.HardSphereSystem.from_state_dict(state)


def test_a_restored_record_has_its_unused_slots_cleared():
    system = fcc_system(cells=3, eta=0.3, well_width=1.5)
    state = system.state_dict()
    state["bonds"] = state["bonds"].copy()
    state["bonds"][state["bond_count"] == 0, -1] = 10**6  # garbage beyond the counts (a re-sort would index it)
    restored = edmd.HardSphereSystem.from_state_dict(state)
    assert restored.bonds.max() < restored.count
