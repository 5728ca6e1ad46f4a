"""The cell-crossing engine's kernels against the neighbour-list engine: the same trajectory, conserved sums."""

import math

import numpy as np
import pytest

from collisionkit._kernels import edmd as kernels
from collisionkit._kernels.edmd import crossings
from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann


def _dilute_system(dim, eta, walls=False, seed=3, radii=None):
    positions, box = lattice("fcc" if dim == 3 else "square", 6 if dim == 3 else 24, eta)
    count = len(positions)
    radius = 0.5 if radii is None else radii(count)
    system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(count), dim, seed=seed), radius, box,
                              periodic=not walls, engine="lists")
    system.run(collisions=3 * count)  # away from the lattice: no simultaneous events
    return system


class CrossingEngine:
    """The crossing engine's arrays beside a system (a copy of its particles and queue), run by the kernels."""

    def __init__(self, system):
        self.system = system
        dim = system.dim
        geom = system.geom.copy()
        contact = 2.0 * system.p[:, kernels.R].max() * system.params[kernels.P_SCALE0]
        ncell = np.ones(3, dtype=np.int64)
        for k in range(dim):
            ncell[k] = int(math.floor(geom[kernels.G_BOX, k] / contact * (1 - 1e-12)))
        geom[kernels.G_CELL] = geom[kernels.G_BOX] / ncell
        self.geom, self.ncell, self.dim = geom, ncell, dim
        count = system.count
        for k in range(dim):
            if geom[kernels.G_PERIODIC, k] != 0.0:
                turns = np.floor(system.p[:, kernels.X + k] / geom[kernels.G_BOX, k]).astype(np.int64)
                system.p[:, kernels.X + k] -= turns * geom[kernels.G_BOX, k]
                system._image[:, k] += turns
        self.cell_of = np.zeros(count, dtype=np.int32)
        self.cell_members = np.zeros((int(ncell.prod()), 8), dtype=np.int32)
        self.cell_count = np.zeros(int(ncell.prod()), dtype=np.int32)
        assert crossings.bin_into_cells(system.p, self.cell_of, self.cell_members, self.cell_count, ncell, geom,
                                        dim) == 0
        self.pending = np.zeros((count, 3))
        self.offsets = crossings.offset_table(dim)
        self.gathered = np.zeros(3**dim * self.cell_members.shape[1] + 2, dtype=np.int64)
        self.steps = crossings.linear_offsets(self.offsets, ncell)
        crossings.predict_all_crossings(system.p, system.book, self.pending, self.offsets, self.steps, self.cell_of,
                                        self.cell_members, self.cell_count, ncell, geom, dim, system.params,
                                        system.queue, system.tree, system.leaves, system.acc, self.gathered)
        self.time = system.time

    def run(self, collisions):
        s = self.system
        before = s.acc[kernels.ACC_PAIR_COLLISIONS]
        self.time, _, _, stop, _ = crossings.run_crossing_events(
            self.time, 0, collisions, 10**9, math.inf, 10**6, s.p, s.book, self.pending, s._image, self.offsets,
            self.steps, self.cell_of, self.cell_members, self.cell_count, self.ncell, self.geom, self.dim,
            s.restitution, s.params, s.queue, s.tree, s.leaves, s.acc, self.gathered)
        assert stop == kernels.STOP_COLLISIONS
        assert s.acc[kernels.ACC_PAIR_COLLISIONS] - before == collisions

    def unwrapped(self):
        return _unwrapped_by_id(self.system, self.time)


def _unwrapped_by_id(system, time):
    """Unwrapped positions at ``time`` (every particle flown there from its own time), in the order of the ids."""
    flown = system.p[:, kernels.X:kernels.X + system.dim] + system.p[:, kernels.V:kernels.V + system.dim] * (
        time - system.p[:, kernels.T:kernels.T + 1])
    unwrapped = flown + system._image * system.geom[kernels.G_BOX, : system.dim]
    return unwrapped[np.argsort(system.ids)]


@pytest.mark.parametrize(("dim", "eta", "walls"), [(3, 0.1, False), (3, 0.05, True), (2, 0.2, False),
                                                    (2, 0.15, True)])
def test_crossing_engine_follows_the_list_engines_trajectory(dim, eta, walls):
    """Both engines resolve the same collisions at the same times: positions agree but for chaos-grown round-off.

    Exact dynamics from one state: two correct engines differ only by
    round-off (here: where a position is wrapped, the clock's origin),
    which the chaos amplifies by a factor of a few per collision of a
    particle; after ~2 collisions a particle it is far below 1e-6 of a
    diameter, while a missed or spurious collision moves particles by a
    good part of a free path (a diameter or more at these densities).
    """
    lists = _dilute_system(dim, eta, walls)
    engine = CrossingEngine(HardSphereSystem.from_state_dict(lists.state_dict()))
    start = lists.elapsed
    collisions = lists.count
    lists.run(collisions=collisions)
    engine.run(collisions)
    assert engine.time == pytest.approx(lists.elapsed - start, rel=0, abs=1e-9)  # elapsed: a sum over calls
    np.testing.assert_allclose(engine.unwrapped(), _unwrapped_by_id(lists, lists.time), rtol=0, atol=1e-6)
    if walls:
        assert engine.system.acc[kernels.ACC_WALL_COLLISIONS] == lists.acc[kernels.ACC_WALL_COLLISIONS]
    assert engine.system.acc[kernels.ACC_LIST_REBUILDS] > 0  # cells were crossed


def test_crossing_engine_conserves_energy_and_momentum_of_a_polydisperse_gas():
    rng = np.random.default_rng(4)
    system = _dilute_system(3, 0.12, radii=lambda count: rng.uniform(0.3, 0.5, count))
    engine = CrossingEngine(system)
    velocities = system.p[:, kernels.V:kernels.V + 3].copy()
    engine.run(20000)
    after = system.p[:, kernels.V:kernels.V + 3]
    np.testing.assert_allclose(after.sum(axis=0), velocities.sum(axis=0), atol=1e-11)
    assert (after**2).sum() == pytest.approx((velocities**2).sum(), rel=1e-12)
    positions = system.p[:, kernels.X:kernels.X + 3]
    # every particle sits in the cell its position says (within round-off of a face)
    width = engine.geom[kernels.G_CELL]
    coordinates = np.stack(np.unravel_index(engine.cell_of, engine.ncell[::-1])[::-1], axis=1)
    assert (positions >= coordinates * width - 1e-9).all() and (positions <= (coordinates + 1) * width + 1e-9).all()


def test_offset_table_rows_bring_in_the_new_cells_nearest_first():
    table = crossings.offset_table(3)
    every = table[crossings.ALL_NEIGHBOURS]
    assert len({tuple(row) for row in every}) == 27 and tuple(every[0]) == (0, 0, 0)
    assert np.all(np.diff(np.abs(every).sum(axis=1)) >= 0)
    for face in range(6):
        axis, step = face // 2, 1 if face % 2 else -1
        rows = table[face][table[face, :, 0] != crossings.ROW_END]
        assert len(rows) == 9 and (rows[:, axis] == step).all()
    flat = crossings.offset_table(2)
    assert (flat[crossings.ALL_NEIGHBOURS, :, 2] == 0).all() and flat.shape[1] == 9
    assert ((flat[:4] != crossings.ROW_END).all(axis=2).sum(axis=1) == 3).all()


def _earliest_neighbour_contacts(positions, velocities, sigma, box, cells, ncell):
    """Each particle's earliest contact time and partner among the particles of its own and the adjacent cells.

    The quadratic formula over every pair (minimum images), kept where the
    periodic cell coordinates differ by at most one on every axis.
    """
    r = positions[None, :, :] - positions[:, None, :]
    r -= box * np.round(r / box)
    u = velocities[None, :, :] - velocities[:, None, :]
    a = (u * u).sum(axis=2)
    b = (r * u).sum(axis=2)
    c = (r * r).sum(axis=2) - sigma**2
    discriminant = b * b - a * c
    with np.errstate(invalid="ignore", divide="ignore"):
        tau = np.where((b < 0) & (discriminant >= 0), (-b - np.sqrt(np.maximum(discriminant, 0))) / a, np.inf)
    steps = np.abs(cells[None, :, :] - cells[:, None, :])
    adjacent = (np.minimum(steps, ncell - steps) <= 1).all(axis=2)
    tau[~adjacent] = np.inf
    np.fill_diagonal(tau, np.inf)
    earliest = tau.min(axis=1)
    return earliest, np.where(np.isfinite(earliest), tau.argmin(axis=1), -1)


def _random_packing(rng, count, sigma, box):
    """``count`` non-overlapping spheres (discs) placed one at a time in a periodic box."""
    placed = []
    while len(placed) < count:
        trial = rng.uniform(0, box)
        if placed:
            r = np.array(placed) - trial
            r -= box * np.round(r / box)
            if ((r * r).sum(axis=1) < sigma**2).any():
                continue
        placed.append(trial)
    return np.array(placed)


@pytest.mark.parametrize("dim", [3, 2])
def test_full_cell_search_finds_the_earliest_contact_among_the_adjacent_cells(dim):
    """The 27 (9) cell search from inner cells and from cells on a periodic face, against every adjacent pair."""
    rng = np.random.default_rng(11)
    count, sigma, side = (150, 1.0, 5) if dim == 3 else (50, 1.0, 8)
    ncell = np.array([side] * dim, dtype=np.int64)
    box = ncell * 1.25 * sigma
    positions = _random_packing(rng, count, sigma, box)
    velocities = rng.normal(size=(count, dim))
    p = np.zeros((count, 8))
    p[:, kernels.X:kernels.X + dim] = positions
    p[:, kernels.V:kernels.V + dim] = velocities
    p[:, kernels.R] = sigma / 2
    geom = np.zeros((4, 3))
    geom[kernels.G_BOX] = 1.0
    geom[kernels.G_BOX, :dim] = box
    geom[kernels.G_PERIODIC, :dim] = 1.0
    grid = np.ones(3, dtype=np.int64)
    grid[:dim] = ncell
    geom[kernels.G_CELL] = geom[kernels.G_BOX] / grid
    cell_of = np.zeros(count, dtype=np.int32)
    cell_members = np.zeros((int(grid.prod()), count), dtype=np.int32)
    cell_count = np.zeros(int(grid.prod()), dtype=np.int32)
    assert crossings.bin_into_cells(p, cell_of, cell_members, cell_count, grid, geom, dim) == 0
    cells = np.stack(np.unravel_index(cell_of, tuple(grid[::-1]))[::-1], axis=1)
    expected_tau, expected_partner = _earliest_neighbour_contacts(positions, velocities, sigma, box, cells[:, :dim],
                                                                  ncell)
    offsets = crossings.offset_table(dim)
    gathered = np.zeros(3**dim * cell_members.shape[1] + 2, dtype=np.int64)
    steps = crossings.linear_offsets(offsets, grid)
    for i in range(count):
        tau, partner = crossings.search_cells(p, i, *cells[i], offsets, steps, crossings.ALL_NEIGHBOURS,
                                              cell_members, cell_count, grid, geom, 1.0, gathered)
        assert partner == expected_partner[i]
        assert tau == (pytest.approx(expected_tau[i], rel=1e-9) if partner >= 0 else math.inf)
    inner = ((cells[:, :dim] > 0) & (cells[:, :dim] < side - 1)).all(axis=1)
    assert inner.any() and not inner.all() and np.isfinite(expected_tau).sum() > count // 4
