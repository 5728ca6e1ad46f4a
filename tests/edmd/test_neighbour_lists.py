"""Tests of the neighbour lists and cells (collisionkit.edmd._neighbour_lists): complete, grown, narrowed, checked."""

import numpy as np
import pytest

from collisionkit import edmd
from tests.edmd.systems import fcc_system, hexagonal_system


@pytest.mark.parametrize("lattice_cells", [4, 2])
def test_neighbour_lists_are_symmetric_and_complete(lattice_cells):
    """Every pair whose anchors are within the list radius is listed, both ways, and no pair beyond it.

    The cells hold float32 anchors, so a pair within their round-off of the
    radius may be listed too (harmless: the list is a superset). Four FCC
    cells make 4 list cells a side (each neighbouring cell seen through one
    periodic shift), two make 2 (a cell its own neighbour on both sides:
    minimum images per anchor). The lists are named: the mixture's packing
    fraction (0.23-0.25) lies below CELLS_BELOW_PACKING, where "auto" takes
    the cells.
    """
    rng = np.random.default_rng(3)
    positions, box = edmd.lattice("fcc", lattice_cells, 0.35)
    radii = np.where(rng.random(len(positions)) < 0.5, 0.5, 0.35)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(len(radii)), 3, seed=rng), radii, box,
                                   engine="lists")
    system.run(collisions=20 * system.count)  # lists rebuilt one particle at a time
    shell, scale = system.neighbour_shell_width, system.neighbour_list_scale
    length = system.box[:3]
    slack = system.neighbour_list_slack
    slot_radii = system.radius[system.ids]  # in memory order, as the lists and anchors
    listed = {(i, int(j)) for i in range(system.count) for j in system.neighbours[i, : system.neighbour_count[i]]}
    within, allowed = set(), set()
    for i in range(system.count):
        separation = system.anchor - system.anchor[i]
        separation -= length * np.round(separation / length)
        distance = np.sqrt(np.sum(separation**2, axis=1))
        reach = (slot_radii + slot_radii[i]) * scale + shell
        within |= {(i, int(j)) for j in np.flatnonzero(distance <= reach) if j != i}
        allowed |= {(i, int(j)) for j in np.flatnonzero(distance <= reach + 2 * slack) if j != i}
    assert within <= listed <= allowed
    assert len(within) > 8 * system.count
    assert all((j, i) in listed for i, j in listed)
    assert (system.ncell[:3] >= 3).all() == (lattice_cells == 4)


def test_lists_grow_when_they_overflow_mid_run():
    """Rows cut to the longest list of the lattice: the melting fluid outgrows them at once."""
    system = fcc_system(cells=4, eta=0.45)
    width = int(system.neighbour_count.max())
    system.neighbours = np.ascontiguousarray(system.neighbours[:, :width])
    energy = system.kinetic_energy()
    system.run(collisions=40 * system.count)
    assert system.neighbours.shape[1] > width
    assert system.check() > -1e-9
    assert system.kinetic_energy() == pytest.approx(energy, rel=1e-12)


def test_cells_grow_for_a_mixture_of_small_and_large_spheres():
    rng = np.random.default_rng(8)
    diameters = np.where(rng.random(400) < 0.8, 0.2, 1.0)
    system = edmd.random_fluid(3, 400, 0.3, seed=rng, diameters=diameters, masses=diameters**3)
    assert system.cell_members.shape[1] > 12  # more small spheres per cell than the default slots
    energy = system.kinetic_energy()
    system.run(collisions=20 * system.count)
    assert system.check() > -1e-9
    assert system.kinetic_energy() == pytest.approx(energy, rel=1e-11)


def test_smallest_periodic_box_narrows_the_shell():
    """A box of 3 diameters leaves room for a shell below half a diameter; runs stay exact."""
    positions = np.array([[0.5, 0.5, 0.5], [2.0, 1.5, 1.0], [1.0, 2.2, 2.4]])
    velocities = edmd.maxwell_boltzmann(np.ones(3), 3, seed=2)
    system = edmd.HardSphereSystem(positions, velocities, 0.5, 3.0)
    assert 0 < system.neighbour_shell_width < 0.5
    energy = system.kinetic_energy()
    system.run(collisions=5000)
    assert system.check() > -1e-9
    assert system.kinetic_energy() == pytest.approx(energy, rel=1e-12)


def test_neighbour_shell_is_validated():
    positions, box = edmd.lattice("sc", 4, 0.3)
    with pytest.raises(ValueError, match="neighbour_shell"):
        edmd.HardSphereSystem(positions, np.zeros_like(positions), 0.5, box, neighbour_shell=0.0)


def test_the_anchor_drift_check_catches_a_particle_beyond_half_the_shell():
    """check() guards the neighbour-list invariant |x - anchor| <= shell / 2; a particle 0.6 shell away must
    raise. Kills: allowed = 0.5 shell -> 5 shell."""
    system = edmd.HardSphereSystem(*_square_lattice_with_velocities(), engine="lists")
    system.check()
    system.anchor[0, 0] -= 0.6 * system.neighbour_shell_width
    with pytest.raises(RuntimeError, match="drifted"):
        system.check()


def _square_lattice_with_velocities():
    positions, box = edmd.lattice("square", 6, 0.3)
    return positions, edmd.maxwell_boltzmann(np.ones(36), 2, seed=4), 0.5, box


def test_the_shell_is_the_requested_fraction_of_the_largest_diameter():
    system = fcc_system(cells=3, eta=0.3)  # a box of 5.7 diameters: wide enough not to narrow the shell
    assert system.neighbour_list_scale == 1.0
    assert system.neighbour_shell_width == pytest.approx(edmd.DEFAULT_SHELL, rel=1e-12)
    wider = fcc_system(cells=3, eta=0.3, neighbour_shell=0.9)
    assert wider.neighbour_shell_width == pytest.approx(0.9, rel=1e-12)


@pytest.mark.parametrize("eta", [0.02, 0.3])
def test_cells_are_sized_by_the_grid_they_hold_not_by_every_grid_before(eta):
    # issue 16, item 6: each grid change of a compression took 1.25 times the old grid's slots, and the small
    # starting radii asked for many empty cells: 65 kB of cells a particle at eta = 0.02 (1.4 kB at 0.3)
    system = edmd.random_fluid(3, 4000, eta, seed=1, engine="lists")
    cells = int(np.prod(system.ncell))
    assert cells <= 2 * system.count
    occupancy = np.bincount(system.cell_of.astype(np.int64), minlength=cells).max()
    slots = system.cell_members.shape[1]
    assert occupancy <= slots <= max(12, 2 * occupancy)
    assert system.cell_points.nbytes / system.count < 1_000
    energy = system.kinetic_energy()
    assert system.run(collisions=4 * system.count) == 4 * system.count  # the capped grid runs as before
    assert system.kinetic_energy() == pytest.approx(energy, rel=1e-12)


def test_dense_spheres_get_the_dense_shell_by_default():
    """The default shell is DENSE_SHELL from a packing fraction of DENSE_PACKING in 3D, DEFAULT_SHELL below and in 2D."""
    assert fcc_system(cells=3, eta=0.45).neighbour_shell_width == pytest.approx(edmd.DENSE_SHELL, rel=1e-12)
    assert fcc_system(cells=3, eta=edmd.DENSE_PACKING * 0.99).neighbour_shell_width == pytest.approx(
        edmd.DEFAULT_SHELL, rel=1e-12)
    positions, box = edmd.lattice("hexagonal", 12, 0.6)
    discs = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(len(positions)), 2, seed=1), 0.5, box)
    assert discs.neighbour_shell_width == pytest.approx(edmd.DEFAULT_SHELL, rel=1e-12)


@pytest.mark.parametrize(("dim", "eta"), [(2, 0.01), (2, 0.3), (3, 0.005), (3, 0.1)])
def test_dilute_systems_get_a_shell_whose_ball_holds_list_neighbours_particles(dim, eta):
    """Below DILUTE_PACKING a homogeneous system's default shell s makes n V_1 ((1 + s) sigma)^d = LIST_NEIGHBOURS
    (or stays DEFAULT_SHELL where that is wider)."""
    positions, box = edmd.lattice("fcc" if dim == 3 else "square", 6 if dim == 3 else 20, eta)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(len(positions)), dim, seed=1), 0.5, box)
    density = len(positions) / np.prod(box)
    unit_ball = np.pi if dim == 2 else 4 * np.pi / 3
    expected = max(edmd.DEFAULT_SHELL, (edmd.LIST_NEIGHBOURS / (density * unit_ball)) ** (1 / dim) - 1)
    assert edmd.default_shell(np.full(len(positions), 0.5), box) == pytest.approx(expected, rel=1e-12)
    assert system.neighbour_shell_width == pytest.approx(min(expected, 0.98 * (0.5 * box.min() - 1)), rel=1e-12)
    if eta < 0.05:
        assert system.neighbour_shell_width > 3 * edmd.DEFAULT_SHELL


def test_no_widening_under_gravity_or_compression_or_for_dense_discs():
    """The mean density says little about the local one when particles settle or are compressed; dense discs ran
    faster with the narrow shell."""
    radii = np.full(200, 0.5)
    assert edmd.default_shell(radii, np.full(3, 40.0), homogeneous=False) == edmd.DEFAULT_SHELL
    assert edmd.default_shell(np.full(400, 0.5), np.full(2, 20.0 * np.sqrt(np.pi / 4 / 0.55))) == edmd.DEFAULT_SHELL
    positions, box = edmd.lattice("fcc", 4, 0.01)
    walled = edmd.HardSphereSystem(positions, np.zeros_like(positions), 0.5, box, periodic=[True, True, False],
                                   gravity=[0.0, 0.0, -1.0])
    assert walled.neighbour_shell_width == pytest.approx(edmd.DEFAULT_SHELL, rel=1e-12)
    assert edmd.random_fluid(3, 200, 0.3, seed=1).neighbour_shell_width <= edmd.DEFAULT_SHELL


@pytest.mark.parametrize("dim", [2, 3])
def test_a_wide_dilute_shell_gives_the_trajectory_of_the_narrow_one(dim):
    """Only speed depends on the shell: 100 collisions of a dilute gas with the widened default shell and with
    DEFAULT_SHELL end at the same time, positions and velocities. (The two synchronise positions at different
    instants, so they differ by round-off, which every collision multiplies by about 2 l / sigma ~ 50 in a dilute
    gas: after a few collisions per particle the trajectories part, as any two exact ones do. Here they agree to
    1e-4, while a missed or extra collision would move two particles by order 1.)"""
    eta = 0.01
    positions, box = edmd.lattice("fcc" if dim == 3 else "square", 4 if dim == 3 else 10, eta)
    velocities = edmd.maxwell_boltzmann(np.ones(len(positions)), dim, seed=3)
    wide = edmd.HardSphereSystem(positions, velocities, 0.5, box)
    narrow = edmd.HardSphereSystem(positions, velocities, 0.5, box, neighbour_shell=edmd.DEFAULT_SHELL)
    assert wide.neighbour_shell_width > 2 * narrow.neighbour_shell_width
    for system in (wide, narrow):
        system.run(collisions=100)
    assert wide.elapsed + wide.time == pytest.approx(narrow.elapsed + narrow.time, rel=1e-6)
    np.testing.assert_allclose(wide.positions(), narrow.positions(), rtol=0, atol=1e-4)
    np.testing.assert_allclose(wide.velocities(), narrow.velocities(), rtol=0, atol=1e-4)


def test_a_dilute_random_fluid_ends_its_compression_with_the_dilute_shell():
    """The compression runs with the narrow shell (the density changes); the finished dilute fluid gets
    default_shell's, unless a shell was asked for, and runs on it without overlaps, conserving energy."""
    system = edmd.random_fluid(2, 400, 0.01, seed=1)
    side = np.sqrt(400 * np.pi / 4 / 0.01)
    expected = edmd.default_shell(np.full(400, 0.5), np.full(2, side))
    assert expected > 3 * edmd.DEFAULT_SHELL
    assert system.neighbour_shell_width == pytest.approx(min(expected, 0.98 * (0.5 * side - 1)), rel=1e-9)
    energy = system.kinetic_energy()
    system.run(collisions=20 * 400)
    assert system.check() > -1e-9 and system.kinetic_energy() == pytest.approx(energy, rel=1e-12)
    asked = edmd.random_fluid(2, 400, 0.01, seed=1, neighbour_shell=0.5)
    assert asked.neighbour_shell_width == pytest.approx(0.5, rel=1e-12)


def test_sorting_by_cell_builds_the_lists_once_and_keeps_every_particle(monkeypatch):
    """The renumbering follows the cells of the positions at the sort: one list build; particles and momentum kept."""
    from collisionkit._kernels import edmd as kernels

    system = fcc_system(3, 0.45, seed=5)
    system.run(collisions=5 * system.count)
    system._refresh_lists()  # rows grown to the fluid's lists: a build now needs no second try
    before = system.p[np.argsort(system.ids)].copy()
    unwrapped = system.positions(unwrapped=True)
    builds = []
    build_all_lists = kernels.build_all_lists
    monkeypatch.setattr(kernels, "build_all_lists", lambda *args: builds.append(1) or build_all_lists(*args))
    system._sort_by_cell()
    assert len(builds) == 1
    assert np.all(np.diff(system.cell_of) >= 0)  # memory in the order of the cells of the (new) anchors
    assert np.array_equal(np.sort(system.ids), np.arange(system.count))
    after = system.p[np.argsort(system.ids)]
    # positions wrapped into the box at the sort: the same points of the periodic box
    shift = (after[:, :3] - before[:, :3]) / system.box[:3]
    assert np.allclose(shift, np.round(shift), atol=1e-12)
    assert np.array_equal(after[:, 3:6], before[:, 3:6])
    # the image counts move with their particles (permuted in place, column by column)
    assert np.allclose(system.positions(unwrapped=True), unwrapped, rtol=0, atol=1e-12 * float(system.box.max()))
    momentum = system.p[:, 3:6].sum(axis=0)
    system.run(collisions=5 * system.count)
    assert np.allclose(system.p[:, 3:6].sum(axis=0), momentum, atol=1e-12 * system.count)
    system.check()


@pytest.mark.parametrize("make", [lambda: fcc_system(5, 0.45, seed=5), lambda: hexagonal_system(16, 0.6, seed=4)])
def test_the_memory_order_changes_no_trajectory(make):
    """Runs sorted in cell order and in a random order follow the same trajectory, bit for bit.

    The slots only change where a particle's records sit: each particle (by
    identity) has the same positions, velocities and time after 45 N
    collisions, two sorts included; energy and momentum (sums over the
    slots, in another order) agree to round-off.
    """
    runs = []
    for shuffled in (False, True):
        system = make()
        system.run(collisions=5 * system.count)
        if shuffled:
            system._slot_order = lambda s=system, rng=np.random.default_rng(3): rng.permutation(s.count)
        energy, momentum = system.kinetic_energy(), system.momentum()
        system._sort_by_cell()
        order = system.ids.copy()
        system.run(collisions=40 * system.count)
        assert system.check() > -1e-9
        assert system.kinetic_energy() == pytest.approx(energy, rel=1e-12)
        assert np.allclose(system.momentum(), momentum, rtol=0, atol=1e-12 * system.count)
        runs.append((order, system.positions(), system.velocities(), system.elapsed, system.collisions))
    (cell_order, *sorted_run), (random_order, *shuffled_run) = runs
    assert np.mean(cell_order != random_order) > 0.9  # the two orders differ
    for a, b in zip(sorted_run, shuffled_run):
        assert np.array_equal(a, b)
