"""The cell-crossing engine's kernels against the neighbour-list engine: the same trajectory, conserved sums."""

import math

import numpy as np
import pytest

from collisionkit._kernels import edmd as kernels
from collisionkit._kernels.edmd import cell_search, crossings
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
        self.offsets = cell_search.offset_table(dim)
        self.gathered = np.zeros(3**dim * self.cell_members.shape[1] + 2, dtype=np.int64)
        self.steps = cell_search.linear_offsets(self.offsets, ncell)
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
            s.restitution, s.params, s.queue, s.tree, s.leaves, s.acc, self.gathered, s.spin)
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




@pytest.mark.parametrize("dim", [3, 2])
def test_next_crossing_is_the_first_face_the_flight_reaches_but_never_one_on_a_wall(dim):
    """Against the faces' times one by one: distance / |v| along each axis that can be left; the flight ends there."""
    rng = np.random.default_rng(5)
    ncell = np.array([5, 4, 3 if dim == 3 else 1], dtype=np.int64)
    geom = np.zeros((4, 3))
    geom[kernels.G_BOX] = [5.0, 6.0, 4.5 if dim == 3 else 1.0]
    geom[kernels.G_CELL] = geom[kernels.G_BOX] / ncell
    geom[kernels.G_PERIODIC] = [1.0, 0.0, 1.0]  # y between walls
    width = geom[kernels.G_CELL]
    p = np.zeros((1, 8))
    never = 0
    for _ in range(500):
        cell = np.zeros(3, dtype=np.int64)
        cell[:dim] = rng.integers(0, ncell[:dim])
        velocity = np.zeros(3)
        velocity[:dim] = rng.normal(size=dim) * (rng.uniform(size=dim) > 0.2)  # some axes at rest
        p[0, kernels.X:kernels.X + dim] = (cell[:dim] + rng.uniform(0, 1, dim)) * width[:dim]
        p[0, kernels.V:kernels.V + 3] = velocity
        times = np.full(dim, math.inf)
        for k in range(dim):
            ahead = cell[k] + (1 if velocity[k] > 0 else -1)
            if velocity[k] != 0.0 and (k != 1 or 0 <= ahead < ncell[k]):  # y's outer faces lie on the walls
                face_at = (cell[k] + (velocity[k] > 0)) * width[k]
                times[k] = abs(face_at - p[0, kernels.X + k]) / abs(velocity[k])
        tau, face = crossings.next_crossing(p, 0, *cell, ncell, geom, dim)
        if np.isinf(times).all():
            assert (tau, face) == (math.inf, -1)
            never += 1
            continue
        axis = int(np.argmin(times))
        assert face == 2 * axis + (velocity[axis] > 0) and tau == pytest.approx(times[axis], rel=1e-12)
        # the flight stays in the cell until then along every axis it could leave by (a wall's hit comes first)
        end = p[0, kernels.X:kernels.X + dim] + velocity[:dim] * tau
        within = (end >= cell[:dim] * width[:dim] - 1e-12) & (end <= (cell[:dim] + 1) * width[:dim] + 1e-12)
        assert within[np.isfinite(times)].all()
    assert 0 < never < 100
