"""The cell-crossing engine in HardSphereSystem (collisionkit.edmd._cell_crossings): its choice, runs, checkpoints."""

import numpy as np
import pytest

from collisionkit import edmd
from collisionkit._kernels import edmd as _k
from collisionkit._kernels.edmd.layout import CELLS_PREFETCH_FROM, PREFETCH_FROM, PREFETCH_REBUILDS_FROM
from collisionkit.edmd._cell_crossings import (
    CELLS_BELOW_PACKING, CELLS_BELOW_PACKING_AT, ENGINE_CELLS, ENGINE_LISTS, cells_below_packing, engine_code,
)
from tests.edmd.systems import fcc_system, hexagonal_system


def _disc_system(eta, seed=2, side=16, **options):
    positions, box = edmd.lattice("square", side, eta)
    velocities = edmd.maxwell_boltzmann(np.ones(len(positions)), 2, seed=seed)
    return edmd.HardSphereSystem(positions, velocities, 0.5, box, **options)


def test_auto_takes_cells_for_dilute_straight_flights_and_lists_otherwise():
    below, above = cells_below_packing(3, 256) * 0.5, cells_below_packing(3, 256) * 1.5
    assert fcc_system(cells=4, eta=below).engine == "cells"
    assert fcc_system(cells=4, eta=above).engine == "lists"
    assert _disc_system(cells_below_packing(2, 256) * 0.5).engine == "cells"
    assert _disc_system(cells_below_packing(2, 256) * 1.25).engine == "lists"
    assert fcc_system(cells=4, eta=below, gravity=[0, 0, -1.0], periodic=[True, True, False]).engine == "lists"
    assert fcc_system(cells=4, eta=below, shear_rate=0.5).engine == "lists"
    assert edmd.random_fluid(3, 64, 0.1, seed=1).engine == "cells"  # compressed on lists, then its own engine
    assert edmd.random_fluid(3, 64, 0.1, seed=1, engine="lists").engine == "lists"
    assert fcc_system(cells=4, eta=above, engine="cells").engine == "cells"
    assert fcc_system(cells=4, eta=below, engine="lists").engine == "lists"
    # a periodic axis of exactly 3 diameters (walls on the others): 3 cells wider than a diameter do not fit
    tight = {"positions": [[0.5, 5.0, 5.0], [2.0, 20.0, 20.0]], "velocities": [[1.0, 0.5, 0.0], [-1.0, 0.0, 0.3]],
             "radii": 0.5, "box": [3.0, 30.0, 30.0], "periodic": [True, False, False]}
    assert edmd.HardSphereSystem(**tight).engine == "lists"
    with pytest.raises(ValueError, match=r"box\[0\] = 3 is too small: a periodic axis needs at least 3 times"):
        edmd.HardSphereSystem(**tight, engine="cells")


@pytest.mark.parametrize("dim", [2, 3])
def test_auto_takes_the_cells_just_below_the_threshold_and_the_lists_at_it(dim):
    """At the threshold itself the lists, also where a lattice's packing fraction rounds to just below it (a
    lattice's packing fraction can come out an ulp below the one asked for)."""
    threshold = CELLS_BELOW_PACKING[dim][0]  # a small system's
    make = (lambda eta: fcc_system(cells=4, eta=eta)) if dim == 3 else (lambda eta: hexagonal_system(eta=eta))
    assert make(threshold - 0.01).engine == "cells"
    assert make(threshold).engine == "lists"
    assert engine_code("auto", dim, threshold, 500, True) == ENGINE_LISTS
    assert engine_code("auto", dim, threshold * (1 - 1e-6), 500, True) == ENGINE_CELLS
    assert edmd.random_fluid(dim, 64, threshold - 0.01, seed=1).engine == "cells"


@pytest.mark.parametrize("dim", [2, 3])
def test_the_threshold_falls_with_n_as_measured_linear_in_log_n_between_the_measured_sizes(dim):
    """Held below the first size and beyond the last; between two sizes at their geometric mean the mean of theirs."""
    counts, thresholds = CELLS_BELOW_PACKING_AT, CELLS_BELOW_PACKING[dim]
    assert cells_below_packing(dim, 2) == cells_below_packing(dim, counts[0]) == thresholds[0]
    assert cells_below_packing(dim, 10**9) == thresholds[-1]
    for (n0, t0), (n1, t1) in zip(zip(counts, thresholds), zip(counts[1:], thresholds[1:])):
        assert cells_below_packing(dim, n1) == pytest.approx(t1, abs=1e-12)
        assert cells_below_packing(dim, (n0 * n1) ** 0.5) == pytest.approx((t0 + t1) / 2, abs=1e-12)
        assert t1 <= t0  # the lists win sooner in a larger system
    # the same packing fraction: the cells for a small system, the lists for a large one
    eta = (thresholds[0] + thresholds[-1]) / 2
    assert engine_code("auto", dim, eta, 1000, True) == ENGINE_CELLS
    assert engine_code("auto", dim, eta, 2 * counts[-1], True) == ENGINE_LISTS


@pytest.mark.parametrize(("options", "message"), [
    ({"engine": "fast"}, "engine must be 'auto', 'lists' or 'cells'; got 'fast'"),
    ({"engine": "cells", "gravity": [0, 0, -1.0], "periodic": [True, True, False]}, "no gravity, compression"),
    ({"engine": "cells", "shear_rate": 0.3}, "no gravity, compression or shear"),
])
def test_an_engine_the_system_cannot_run_is_refused_naming_it(options, message):
    with pytest.raises(ValueError, match=message):
        fcc_system(cells=4, eta=0.1, **options)


def _same_start(make, **options):
    """Two systems of one state, one per engine (the state taken after 2 collisions a particle)."""
    first = make(engine="lists", **options)
    first.run(collisions=2 * first.count)
    second = edmd.HardSphereSystem(first.positions(), first.velocities(), first.radius, first.box[: first.dim],
                                   periodic=first.periodic[: first.dim], engine="cells")
    lists = edmd.HardSphereSystem(first.positions(), first.velocities(), first.radius, first.box[: first.dim],
                                  periodic=first.periodic[: first.dim], engine="lists")
    return lists, second


@pytest.mark.parametrize("make", [
    lambda **options: fcc_system(cells=5, eta=0.12, **options),
    lambda **options: fcc_system(cells=5, eta=0.08, periodic=[False, True, False], **options),
    lambda **options: _disc_system(0.25, **options),
    # from PREFETCH_FROM particles the lists' loop prefetches (the guesses must not change what happens)
    lambda **options: fcc_system(cells=8, eta=0.12, **options),
    lambda **options: _disc_system(0.3, side=46, **options),
    # from PREFETCH_REBUILDS_FROM the lists' loop also prefetches for the next list rebuild (and from
    # CELLS_PREFETCH_FROM the cells' loop prefetches)
    lambda **options: fcc_system(cells=26, eta=0.12, **options),
    lambda **options: _disc_system(0.3, side=257, **options),
])
def test_both_engines_make_one_trajectory_over_many_runs(make):
    """Run in pieces (the clock restarts at 0 after each): the same collisions at the same times, the same sums.

    The engines differ by round-off only (where positions are wrapped, the
    clock's origin), which the chaos amplifies by a factor of a few per
    collision of a particle: after one collision a particle the positions
    agree far below 1e-6 diameters; a missed collision would move
    particles by a good part of a free path.
    """
    lists, cells = _same_start(make)
    for _ in range(4):
        assert lists.run(collisions=lists.count // 4) == cells.run(collisions=cells.count // 4)
    np.testing.assert_allclose(cells.positions(unwrapped=True), lists.positions(unwrapped=True), rtol=0, atol=1e-6)
    np.testing.assert_allclose(cells.velocities(), lists.velocities(), rtol=0, atol=1e-6)
    assert cells.elapsed == pytest.approx(lists.elapsed, rel=1e-9)
    assert cells.acc[_k.ACC_VIRIAL] == pytest.approx(lists.acc[_k.ACC_VIRIAL], rel=1e-9)
    assert cells.acc[_k.ACC_WALL_COLLISIONS] == lists.acc[_k.ACC_WALL_COLLISIONS]
    assert cells.check() > -1e-9


def test_the_largest_systems_of_the_trajectory_test_reach_the_prefetching_loops():
    assert 4 * 8**3 >= PREFETCH_FROM and 46**2 >= PREFETCH_FROM
    assert 4 * 26**3 >= PREFETCH_REBUILDS_FROM and 257**2 >= PREFETCH_REBUILDS_FROM
    assert 4 * 26**3 >= CELLS_PREFETCH_FROM and 257**2 >= CELLS_PREFETCH_FROM


def test_a_long_cells_run_conserves_energy_and_momentum_across_memory_sorts():
    system = fcc_system(cells=4, eta=0.1)
    assert system.engine == "cells"
    momentum, energy = system.velocities().sum(axis=0), (system.velocities() ** 2).sum()
    for _ in range(25):  # past a re-sort (every 20 collisions a particle, checked between runs and chunks)
        system.run(collisions=system.count)
    assert system.last_sort > 0
    np.testing.assert_allclose(system.velocities().sum(axis=0), momentum, atol=1e-11)
    assert (system.velocities() ** 2).sum() == pytest.approx(energy, rel=1e-12)
    assert system.check() > -1e-9


def test_a_cells_checkpoint_resumes_bit_for_bit(tmp_path):
    straight = fcc_system(cells=4, eta=0.1)
    straight.run(collisions=3_000)
    straight.run(collisions=3_000)
    interrupted = fcc_system(cells=4, eta=0.1)
    interrupted.run(collisions=3_000)
    interrupted.save(tmp_path / "state.npz")
    resumed = edmd.HardSphereSystem.load(tmp_path / "state.npz")
    assert resumed.engine == "cells"
    resumed.run(collisions=3_000)
    np.testing.assert_array_equal(resumed.positions(), straight.positions())
    np.testing.assert_array_equal(resumed.velocities(), straight.velocities())
    np.testing.assert_array_equal(resumed.acc, straight.acc)


def test_a_cell_outgrowing_its_slots_grows_them_and_the_run_goes_on():
    system = fcc_system(cells=4, eta=0.1)
    fullest = int(system.cell_count.max())
    system.cell_members = system.cell_members[:, :fullest].copy()  # the first crossing into a full cell outgrows it
    energy = (system.velocities() ** 2).sum()
    assert system.run(collisions=3_000) == 3_000
    assert system.cell_members.shape[1] > fullest
    assert (system.velocities() ** 2).sum() == pytest.approx(energy, rel=1e-12)
    assert system.check() > -1e-9


def test_the_drift_check_catches_a_particle_outside_its_cell():
    """check() guards the cell engine's invariant (each particle within round-off of its cell)."""
    system = fcc_system(cells=4, eta=0.1)
    system.check()
    system.p[0, _k.X] += 1.5 * system.geom[_k.G_CELL, 0]
    with pytest.raises(RuntimeError, match="outside its cell"):
        system._check_cell_drift(1e-9)


def test_a_particle_at_rest_keeps_a_valid_event_and_its_checkpoint_loads():
    """A resting particle's event is at inf; its target must still be a code the checkpoint check accepts."""
    system = edmd.HardSphereSystem([[1.0, 1.0], [5.0, 5.0], [8.0, 2.0]], [[0.0, 0.0], [1.0, 0.3], [-0.4, 0.7]], 0.5,
                                   10.0)
    assert system.engine == "cells"
    assert system.book[0, _k.TARGET] != 0.0 and system.queue[0] == np.inf
    restored = edmd.HardSphereSystem.from_state_dict(system.state_dict())
    assert restored.run(time=50.0) == system.run(time=50.0)
    np.testing.assert_array_equal(restored.positions(), system.positions())
