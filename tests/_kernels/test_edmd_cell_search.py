"""The cell engine's pair search: the offset table and the earliest contact among the adjacent cells."""

import math

import numpy as np
import pytest

from collisionkit._kernels import edmd as kernels
from collisionkit._kernels.edmd import cell_search, crossings


def test_offset_table_rows_bring_in_the_new_cells_nearest_first():
    table = cell_search.offset_table(3)
    every = table[cell_search.ALL_NEIGHBOURS]
    assert len({tuple(row) for row in every}) == 27 and tuple(every[0]) == (0, 0, 0)
    assert np.all(np.diff(np.abs(every).sum(axis=1)) >= 0)
    for face in range(6):
        axis, step = face // 2, 1 if face % 2 else -1
        rows = table[face][table[face, :, 0] != cell_search.ROW_END]
        assert len(rows) == 9 and (rows[:, axis] == step).all()
    flat = cell_search.offset_table(2)
    assert (flat[cell_search.ALL_NEIGHBOURS, :, 2] == 0).all() and flat.shape[1] == 9
    assert ((flat[:4] != cell_search.ROW_END).all(axis=2).sum(axis=1) == 3).all()


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
    offsets = cell_search.offset_table(dim)
    gathered = np.zeros(3**dim * cell_members.shape[1] + 2, dtype=np.int64)
    steps = cell_search.linear_offsets(offsets, grid)
    for i in range(count):
        tau, partner = cell_search.search_cells(p, i, *cells[i], offsets, steps, cell_search.ALL_NEIGHBOURS,
                                                cell_members, cell_count, grid, geom, 1.0, math.inf, gathered)
        assert partner == expected_partner[i]
        assert tau == (pytest.approx(expected_tau[i], rel=1e-9) if partner >= 0 else math.inf)
        if partner >= 0:  # a horizon past the contact keeps it, one before it finds none
            later = cell_search.search_cells(p, i, *cells[i], offsets, steps, cell_search.ALL_NEIGHBOURS,
                                             cell_members, cell_count, grid, geom, 1.0, 1.5 * tau, gathered)
            earlier = cell_search.search_cells(p, i, *cells[i], offsets, steps, cell_search.ALL_NEIGHBOURS,
                                               cell_members, cell_count, grid, geom, 1.0, 0.5 * tau, gathered)
            assert later == (tau, partner)
            assert earlier == (math.inf, -1)
    inner = ((cells[:, :dim] > 0) & (cells[:, :dim] < side - 1)).all(axis=1)
    assert inner.any() and not inner.all() and np.isfinite(expected_tau).sum() > count // 4
