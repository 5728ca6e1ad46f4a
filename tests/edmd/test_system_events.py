"""Tests of running the event loop (collisionkit.edmd._system_events): runs that cannot go on, interrupts, and the
contacts that once made the loop spin.

Every hang here used to keep one kernel call busy for ever, where no signal can land. The systems are compiled
before the deadline (a cold numba cache takes tens of seconds), so the deadline times only the run.
"""

import math
import time
import warnings
from fractions import Fraction

import numpy as np
import pytest

from collisionkit import edmd
from collisionkit._kernels import edmd as kernels
from collisionkit._kernels.edmd.crossings import CROSSING_BASE
from collisionkit.edmd import _system_events
from collisionkit.edmd._cell_crossings import run_crossing_kernel
from tests.edmd.systems import fcc_system
from tests.sweep.helpers import deadline


def _compiled(system):
    system.compile_event_loop()
    return system


def parallel_discs(engine="auto"):
    """Two discs on parallel lines in a periodic box, at the same velocity: no pair can ever collide."""
    return _compiled(edmd.HardSphereSystem([[1.0, 1.0], [1.0, 5.0]], [[1.0, 0.0], [1.0, 0.0]], 0.5, 10.0,
                                           engine=engine))


def test_a_run_for_collisions_no_pair_can_make_stops_with_the_cause():
    # spun for ever: list rebuilds without end inside one kernel call, run(collisions=100) never returned
    system = parallel_discs()
    with deadline(30.0), pytest.raises(RuntimeError, match="no pair collision in .* no pair can collide"):
        system.run(collisions=100)
    # a stretch of time is still theirs to run
    assert parallel_discs().run(time=50.0) == 0


def test_a_dilute_gas_is_not_mistaken_for_one_that_cannot_collide():
    # a collision every ~4000 events: far from the QUIET_EVENTS without a collision the run would give up at
    system = _compiled(fcc_system(cells=3, eta=0.001))
    assert system.run(collisions=300) == 300


def _dropped_balls(**elastic_below):
    """Two balls dropped at rest in separate columns onto an inelastic floor (e = 0.5) under gravity."""
    return _compiled(edmd.HardSphereSystem([[2.0, 3.0], [7.0, 5.0]], np.zeros((2, 2)), 0.5, 10.0,
                                           periodic=[True, False], gravity=[0.0, -1.0], wall_restitution=0.5,
                                           **elastic_below))


def test_a_ball_on_an_inelastic_floor_without_an_elastic_floor_is_reported_as_a_wall_collapse():
    # each ball bounces ever lower, infinitely many bounces in finite time; spun for ever at the instant they rested
    system = _dropped_balls(elastic_below=0.0)
    with deadline(30.0), pytest.raises(RuntimeError, match="wall collapse: .* bounces off a wall: .* raise elastic_below"):
        system.run(collisions=100)
    assert system.elapsed + system.time == pytest.approx(math.sqrt(2 * 2.5) * 3, rel=1e-9)  # 2.5 high, e = 0.5


def test_the_elastic_floor_guards_wall_bounces_too():
    # issue 16, item 9: elastic_below guarded pair contacts only, so a ball on an inelastic floor always collapsed
    system = _dropped_balls()
    assert system.elastic_below == pytest.approx(1e-6 * math.sqrt(10.0))  # sqrt(<v^2> + |g| L), balls at rest
    with deadline(30.0):
        system.run(time=10.0)  # past the collapse instant sqrt(5) * 3 of the lower ball
    heights = system.positions()[:, 1] - 0.5
    speeds = np.abs(system.velocities()[:, 1])
    # each ball now bounces elastically at (about) the floor speed: its energy per mass stays at that scale
    energy = heights + 0.5 * speeds**2
    assert np.all(energy < 0.5 * (1.01 * system.elastic_below) ** 2 + 1e-12)
    assert np.all(energy > 0.5 * (0.5 * system.elastic_below) ** 2)  # e = 0.5 above the floor, elastic below it


def test_inelastic_collapse_without_an_elastic_floor_is_an_error_naming_it():
    # restitution 0.3, elastic_below 0: a cluster collides without end at one instant
    system = _compiled(edmd.random_fluid(2, 300, 0.6, seed=0, restitution=0.3, elastic_below=0.0))
    with deadline(30.0), pytest.raises(RuntimeError, match="inelastic collapse: 65536 events in a row .* elastic"):
        system.run(collisions=300_000)


def test_a_collapse_that_round_off_ended_is_warned_of():
    system = _compiled(edmd.random_fluid(3, 300, 0.4, seed=0, restitution=0.3, elastic_below=0.0))
    with deadline(30.0), pytest.warns(RuntimeWarning, match="inelastic collapse: .* events in a row at one instant"):
        system.run(collisions=300_000)


def test_an_interrupt_lands_within_a_second_of_a_run_without_collisions():
    # the alarm stands in for Ctrl-C: Python handles signals between kernel calls only, and a run of these two
    # discs for a long time was one kernel call (no collision ever ends it)
    system = parallel_discs()
    start = time.perf_counter()
    with pytest.raises(TimeoutError), deadline(0.3):
        system.run(time=1e15)
    assert time.perf_counter() - start < 1.3


def test_a_kernel_call_stops_at_its_event_allowance_and_at_a_stalled_instant():
    crossing = parallel_discs()  # dilute: the cell-crossing engine, whose events here are all crossings
    assert crossing.engine == "cells"
    t, _, _, stop, target = run_crossing_kernel(crossing, 0.0, 0, 100, 1000, math.inf, kernels.STALLED_EVENTS)
    assert stop == kernels.STOP_EVENTS and crossing.acc[kernels.ACC_EVENTS] == 1000 and t > 0.0
    assert target <= CROSSING_BASE and crossing.acc[kernels.ACC_PAIR_COLLISIONS] == 0
    system = parallel_discs("lists")
    arrays = (system.p, system.book, system.anchor_time, system._image, system.cell_of, system.neighbours, system.neighbour_count,
              system.cell_members, system.cell_count, system.cell_points, system.ncell, system.geom, system.dim,
              system.restitution, system.params, system.queue, system.tree, system.leaves, system.acc, system.spin)
    t, still, longest, stop, target = kernels.run_events(0.0, 0, 100, 1000, math.inf, kernels.STALLED_EVENTS, *arrays)
    assert stop == kernels.STOP_EVENTS and system.acc[kernels.ACC_EVENTS] == 1000 and t > 0.0
    # a ball resting on the floor under gravity: a bounce at once, that changes nothing, for ever
    resting = edmd.HardSphereSystem([[2.0, 0.5], [7.0, 5.0]], np.zeros((2, 2)), 0.5, 10.0, periodic=[True, False],
                                    gravity=[0.0, -1.0])
    arrays = (resting.p, resting.book, resting.anchor_time, resting._image, resting.cell_of, resting.neighbours, resting.neighbour_count,
              resting.cell_members, resting.cell_count, resting.cell_points, resting.ncell, resting.geom,
              resting.dim, resting.restitution, resting.params, resting.queue, resting.tree, resting.leaves,
              resting.acc, resting.spin)
    t, still, longest, stop, target = kernels.run_events(0.0, 0, 100, 1 << 20, math.inf, kernels.STALLED_EVENTS, *arrays)
    assert (t, stop, target) == (0.0, kernels.STOP_STALLED, kernels.wall_target(2))
    assert still == longest == kernels.STALLED_EVENTS


def test_events_in_a_row_at_one_instant_are_counted_across_calls():
    # a collapse split over calls of fewer events than STALLED_EVENTS is still caught
    resting = edmd.HardSphereSystem([[2.0, 0.5], [7.0, 5.0]], np.zeros((2, 2)), 0.5, 10.0, periodic=[True, False],
                                    gravity=[0.0, -1.0])
    arrays = (resting.p, resting.book, resting.anchor_time, resting._image, resting.cell_of, resting.neighbours, resting.neighbour_count,
              resting.cell_members, resting.cell_count, resting.cell_points, resting.ncell, resting.geom,
              resting.dim, resting.restitution, resting.params, resting.queue, resting.tree, resting.leaves,
              resting.acc, resting.spin)
    still, calls = 0, 0
    while True:
        _, still, _, stop, _ = kernels.run_events(0.0, still, 100, 1000, math.inf, kernels.STALLED_EVENTS, *arrays)
        calls += 1
        if stop != kernels.STOP_EVENTS:
            break
    assert stop == kernels.STOP_STALLED and calls == kernels.STALLED_EVENTS // 1000 + 1


def _lockstep_lattice(cells, restitution=1.0):
    """A square lattice whose columns move in step, +x and -x in turn: all its pairs collide at one instant."""
    positions, box = edmd.lattice("square", cells, 0.3)
    column = np.round(positions[:, 0] / (box[0] / cells) - 0.5).astype(int)
    velocities = np.zeros_like(positions)
    velocities[:, 0] = np.where(column % 2 == 0, 1.0, -1.0)
    return edmd.HardSphereSystem(positions, velocities, 0.5, box, restitution=restitution)


def test_a_symmetric_start_with_many_simultaneous_events_is_not_a_collapse():
    # issue 16, item 10: fixed limits (2^12 to warn, 2^16 to stop) called N/2 pairs colliding at one instant
    # an "inelastic collapse" of an elastic system (N = 136900 warned 4 times); the limits now grow with N
    system = _compiled(_lockstep_lattice(370))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with deadline(60.0):
            assert system.run(collisions=3 * system.count) == 3 * system.count
    assert system.kinetic_energy() == pytest.approx(0.5 * system.count, rel=1e-12)
    assert _system_events.stall_limit(system.count) == 8 * system.count
    assert not _system_events.loses_energy(system) and _system_events.loses_energy(_lockstep_lattice(4, 0.9))


def test_restitution_zero_is_a_sticky_contact():
    # head-on, equal masses: both stop (the normal approach ends); was a ZeroDivisionError or "stopped colliding"
    system = edmd.HardSphereSystem([[3.0, 5.0], [6.0, 5.0]], [[1.0, 0.0], [-1.0, 0.0]], 0.5, 10.0, restitution=0.0)
    assert system.run(collisions=1) == 1
    np.testing.assert_array_equal(system.velocities(), np.zeros((2, 2)))
    assert system.energy_lost == pytest.approx(1.0, rel=1e-15)
    # an oblique contact keeps the tangential motion: the pair slides apart along its tangent
    system = edmd.HardSphereSystem([[3.0, 5.0], [4.0, 5.6]], [[1.0, 0.0], [0.0, 0.0]], 0.5, 10.0, restitution=0.0)
    assert system.run(collisions=1) == 1
    positions, velocities = system.positions(), system.velocities()
    normal = (positions[1] - positions[0]) / np.linalg.norm(positions[1] - positions[0])
    assert (velocities[1] - velocities[0]) @ normal == pytest.approx(0.0, abs=1e-15)
    np.testing.assert_allclose(velocities.sum(axis=0), [1.0, 0.0], rtol=1e-15)


def test_a_gas_with_restitution_zero_runs_and_is_measured():
    # the collision step found receding some pairs the prediction sent to collide at once (a sticky contact
    # leaves b = r.u at round-off): the same pair again and again at one instant, each time "collided"
    positions, box = edmd.lattice("square", 20, 0.3)
    system = _compiled(edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(400), 2, seed=1), 0.5, box,
                                             restitution=0.0))
    with deadline(30.0):
        assert system.run(collisions=400_000) == 400_000
    assert system.temperature() < 0.1  # was 0.89: most "collisions" changed nothing
    run = edmd.EdmdRun(edmd.EdmdParameters(dim=2, particles=100, initial="square", restitution=0.0, seed=1,
                                           collisions=4000, blocks=2))
    with deadline(60.0):
        assert run.run().measurement().collisions == 4000


def test_a_grazing_touch_is_judged_alike_by_the_prediction_and_the_collision_step():
    # in contact, |r| = 1; the plain r.u rounds to -5.6e-17, while exactly it is +1.6e-17: receding. The collision
    # step judged it receding and the prediction approaching: collide at once, for ever (e = 0.1)
    r = [0.32149425662228026, -0.8636488644210076, -0.38826805423984007]
    u = [1.5252817078295342, 0.2758589414822427, 0.6493556307131993]
    assert r[0] * u[0] + r[1] * u[1] + r[2] * u[2] < 0.0 < sum(Fraction(a) * Fraction(b) for a, b in zip(r, u))
    assert kernels.pair_contact_time(*r, *u, 1.0, 1.0, 0.0, math.inf) == math.inf
    positions = np.array([[5.0, 5.0, 5.0], np.add([5.0, 5.0, 5.0], r)])
    system = _compiled(edmd.HardSphereSystem(positions, np.array([[0.0, 0.0, 0.0], u]), 0.5, 10.0,
                                             restitution=0.1))
    with deadline(30.0):
        system.run(time=0.1)
    assert system.collisions == 0


def test_elastic_collisions_keep_the_energy_without_drift():
    # each collision raised the energy by ~5e-17 of the pair's (a normal rounded to unit length has
    # |n|^2 - 1 = +8e-17 on average): +3.6e-13 of the total here, always up; now the round-off floor, ~1e-15
    system = _compiled(fcc_system(cells=3, eta=0.45))

    def energy():
        return sum(Fraction(float(v)) ** 2 for v in system.velocities().ravel())

    before = energy()
    system.run(collisions=200_000)
    assert abs(float((energy() - before) / before)) < 2e-14


def test_the_stall_messages_name_their_causes():
    system = parallel_discs()
    assert _system_events.stall_message(system, kernels.wall_target(0)).startswith("wall collapse")
    assert _system_events.stall_message(system, kernels.LIST_TARGET).startswith("the event loop stalled")
    assert "locked in contact" in _system_events.stall_message(system, 1)
    assert _system_events.mean_free_time(parallel_discs()) == pytest.approx(1 / (2 * math.sqrt(2) * 0.02), rel=1e-12)


def test_a_fixed_seed_trajectory_keeps_momentum_and_energy_to_round_off():
    """500 spheres at eta = 0.45 (the dense shell; 5 cells an axis, so rebuilds take each cell's image once).

    A collision changes two velocities by opposite impulses, each rounded to
    half a unit in the last place: the total momentum takes a random walk
    of at most eps max|v| a step and axis, so after n collisions it stays
    within 4 sqrt(n) eps max|v|; the energy within the floor of the test
    above.
    """
    system = _compiled(fcc_system(cells=5, eta=0.45, seed=7))
    assert system.ncell.min() >= 3 and system.neighbour_shell_width == pytest.approx(edmd.DENSE_SHELL)
    start = system.velocities()
    system.run(collisions=100_000)
    velocities = system.velocities()
    bound = 4.0 * math.sqrt(system.collisions) * np.finfo(float).eps * np.abs(velocities).max()
    assert np.all(np.abs(velocities.sum(axis=0) - start.sum(axis=0)) < bound)
    assert abs((velocities**2).sum() / (start**2).sum() - 1.0) < 2e-14
    system.check()


def test_a_granular_gas_cooled_to_rest_is_not_said_to_be_unable_to_collide():
    # restitution 0.8 and elastic_below 0: the gas cooled to kT ~ 1e-34, and the message blamed parallel paths
    positions, box = edmd.lattice("square", 4, 0.3)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(16), 2, seed=1), 0.5, box,
                                   restitution=0.8, elastic_below=0.0)
    with pytest.raises(RuntimeError, match=r"the inelastic gas has cooled almost to rest \(kT now .*raise elastic_below"):
        system.run(collisions=200_000)
