"""The cell engine's pair search: the contacts of a particle with the members of its neighbouring cells.

The cells are no smaller than the largest contact distance, so a particle
can touch only members of its own and the adjacent cells
(:mod:`.crossings`). The offsets of those cells are kept in a table, the
nearest first (:func:`offset_table`; rows for the cells a crossing brings
in); from an inner cell they are cell-number differences
(:func:`linear_offsets`), from a cell on the grid's faces each neighbour is
seen through the periodic image it lies in. The members are copied into a
scratch row first and tested in one loop (:func:`search_cells`): a loop
over each cell's own members would end at a different trip each cell.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

# no EDMD kernel allocates or returns an array: all of them borrow, without reference counting
from ..._jit import borrowing_inline_kernel as inline_kernel
from .layout import G_BOX, G_PERIODIC, R, T, V, X
from .prediction import contact_before

# the whole neighbourhood's row of the offset table (rows 0-5: the cells a crossing of face f brings in)
ALL_NEIGHBOURS = 6
# the offset marking the end of a shorter row of the table
ROW_END = 2
# periodic images a neighbouring cell can be seen through (3 shifts an axis), in the gathered members' codes
IMAGES = 27


def offset_table(dim):
    """Cell offsets to search, nearest first: rows 0-5 after a crossing of face f, row ``ALL_NEIGHBOURS`` all.

    Returns an int64 array (7, 3^dim, 3); a row shorter than 3^dim ends
    with ``ROW_END``. After crossing face f = 2 axis + (1 upper, 0 lower)
    the new neighbours are the cells one step further along that axis:
    offset +1 (upper) or -1 (lower) on it, any on the others.
    """
    axes = [(-1, 0, 1) if k < dim else (0,) for k in range(3)]
    every = sorted(itertools.product(*axes), key=lambda offset: (sum(map(abs, offset)), offset))
    table = np.full((ALL_NEIGHBOURS + 1, len(every), 3), ROW_END, dtype=np.int64)
    table[ALL_NEIGHBOURS] = every
    for face in range(2 * dim):
        axis, step = face // 2, 1 if face % 2 else -1
        rows = [offset for offset in every if offset[axis] == step]
        table[face, : len(rows)] = rows
    return table


def linear_offsets(offsets, ncell):
    """:func:`offset_table` as cell-number differences in a grid of ``ncell`` cells: (rows, 1 + 3^dim) int64.

    Column 0 holds the row's length, columns 1... the differences, the
    nearest first; they hold from a cell off the grid's faces, where no
    neighbour wraps.
    """
    rows, width, _ = offsets.shape
    table = np.zeros((rows, width + 1), dtype=np.int64)
    for row in range(rows):
        used = offsets[row, :, 0] != ROW_END
        steps = offsets[row, used]
        table[row, 0] = used.sum()
        table[row, 1 : 1 + used.sum()] = steps[:, 0] + ncell[0] * (steps[:, 1] + ncell[1] * steps[:, 2])
    return table


@inline_kernel
def _neighbour_cell(c, offset, n, periodic, length):
    """Neighbour cell coordinate along one axis and the shift of its image; -1 outside a wall."""
    c += offset
    if c < 0:
        return (c + n, -length) if periodic else (-1, 0.0)
    if c >= n:
        return (c - n, length) if periodic else (-1, 0.0)
    return c, 0.0


@inline_kernel
def _test_pair(p, j, sx, sy, sz, xi, yi, zi, vxi, vyi, vzi, ri, t, scale, best, partner):
    """The earlier of (best, partner) and the contact of a particle at (xi, yi, zi) with j, seen shifted by s.

    The root and the cheap filter of the list engine
    (:func:`.prediction.contact_before`: the same contact times). The
    particle itself has r = u = 0, so b = 0 and the filter drops it.
    """
    dt = t - p[j, T]
    rx = p[j, X] + p[j, V] * dt - xi + sx
    ry = p[j, X + 1] + p[j, V + 1] * dt - yi + sy
    rz = p[j, X + 2] + p[j, V + 2] * dt - zi + sz
    ux = p[j, V] - vxi
    uy = p[j, V + 1] - vyi
    uz = p[j, V + 2] - vzi
    tau = contact_before(rx, ry, rz, ux, uy, uz, (ri + p[j, R]) * scale, best)
    if tau < best:
        return tau, j
    return best, partner


@inline_kernel
def _scan_members(p, cell, sx, sy, sz, cell_members, cell_count, xi, yi, zi, vxi, vyi, vzi, ri, t, scale, best,
                  partner):
    """Earliest contact of a particle at (xi, yi, zi) with the members of one cell, seen shifted by (sx, sy, sz)."""
    for m in range(cell_count[cell]):
        best, partner = _test_pair(p, cell_members[cell, m], sx, sy, sz, xi, yi, zi, vxi, vyi, vzi, ri, t, scale,
                                   best, partner)
    return best, partner


@inline_kernel
def _gather_members(here, steps, row, cell_members, cell_count, gathered):
    """Copy the members of the cells of row ``row`` around inner cell ``here`` into ``gathered``; how many.

    ``steps`` is :func:`linear_offsets`'s table.
    Without a branch per cell: the first two slots of every cell are copied
    whether in use or not and the count moves on by the cell's count (the
    next cell's copy overwrites what was not in use); only a cell of three
    or more (rare where the cells are as narrow as a diameter: 0.6 spheres a
    cell at eta = 0.26) takes a loop. A loop over each cell's own members
    would end at a different trip each cell, a mispredicted branch each.
    ``gathered`` holds 3^dim times the slots a cell, plus 2.
    """
    found = 0
    for q in range(1, 1 + steps[row, 0]):
        cell = here + steps[row, q]
        filled = cell_count[cell]
        gathered[found] = cell_members[cell, 0]
        gathered[found + 1] = cell_members[cell, 1]
        if filled > 2:
            for m in range(2, filled):
                gathered[found + m] = cell_members[cell, m]
        found += filled
    return found


@inline_kernel
def _gather_edge_members(c0, c1, c2, offsets, row, cell_members, cell_count, ncell, geom, gathered):
    """:func:`_gather_members` from a cell on the grid's faces: each member stored as ``j * IMAGES + image``.

    ``image`` = kx + 3 ky + 9 kz says through which periodic image its cell
    is seen, k = 0, 1, 2 for a shift of -1, 0, +1 box lengths along the
    axis; cells beyond a wall are skipped.
    """
    n0, n1, n2 = ncell[0], ncell[1], ncell[2]
    periodic0, periodic1, periodic2 = geom[G_PERIODIC, 0] != 0.0, geom[G_PERIODIC, 1] != 0.0, geom[G_PERIODIC, 2] != 0.0
    found = 0
    for q in range(offsets.shape[1]):
        if offsets[row, q, 0] == ROW_END:
            break
        x, sx = _neighbour_cell(c0, offsets[row, q, 0], n0, periodic0, 1.0)
        y, sy = _neighbour_cell(c1, offsets[row, q, 1], n1, periodic1, 1.0)
        z, sz = _neighbour_cell(c2, offsets[row, q, 2], n2, periodic2, 1.0)
        if x < 0 or y < 0 or z < 0:
            continue
        cell = x + n0 * (y + n1 * z)
        image = int(sx + 1.0) + 3 * int(sy + 1.0) + 9 * int(sz + 1.0)
        filled = cell_count[cell]
        gathered[found] = cell_members[cell, 0] * IMAGES + image
        gathered[found + 1] = cell_members[cell, 1] * IMAGES + image
        if filled > 2:
            for m in range(2, filled):
                gathered[found + m] = cell_members[cell, m] * IMAGES + image
        found += filled
    return found


@inline_kernel
def _found(best, partner):
    """A search's result: (inf, -1) when nothing beat the horizon."""
    return (best, partner) if partner >= 0 else (math.inf, -1)


@inline_kernel
def search_cells(p, i, c0, c1, c2, offsets, steps, row, cell_members, cell_count, ncell, geom, scale, horizon,
                 gathered):
    """Earliest contact (time from i's time, partner) of i, in cell (c0, c1, c2), with the cells of row ``row``.

    Only contacts before ``horizon`` count: (inf, -1) if none. The pair
    test's cheap filter rejects a pair that cannot touch before the best so
    far (:func:`.prediction.contact_before`), so a finite horizon saves
    most roots. Row ``row`` of :func:`offset_table` lists cell offsets, the
    nearest first, so that an early good contact tightens the filter for
    the rest. From a cell off the grid's faces (most cells), every
    neighbour is the cell number plus the offset's (``steps``, the table of
    :func:`linear_offsets`), seen without an image: no per-axis wrap
    (measured 1.15x on the whole run at N 4000, eta 0.1); their members are
    gathered first (:func:`_gather_members`, into ``gathered``) and tested
    in one loop, in the same order; from a cell on the faces each with the
    image its cell is seen through (:func:`_gather_edge_members`).
    """
    t = p[i, T]
    xi, yi, zi = p[i, X], p[i, X + 1], p[i, X + 2]
    vxi, vyi, vzi = p[i, V], p[i, V + 1], p[i, V + 2]
    ri = p[i, R]
    n0, n1, n2 = ncell[0], ncell[1], ncell[2]
    periodic0, periodic1, periodic2 = geom[G_PERIODIC, 0] != 0.0, geom[G_PERIODIC, 1] != 0.0, geom[G_PERIODIC, 2] != 0.0
    l0, l1, l2 = geom[G_BOX, 0], geom[G_BOX, 1], geom[G_BOX, 2]
    best = horizon
    partner = -1
    inner = 0 < c0 < n0 - 1 and 0 < c1 < n1 - 1 and (n2 == 1 or 0 < c2 < n2 - 1)
    if inner and cell_members.shape[1] >= 2:
        # an inner cell: every neighbour is in the grid, none seen through a periodic image
        found = _gather_members(c0 + n0 * (c1 + n1 * c2), steps, row, cell_members, cell_count, gathered)
        for m in range(found):
            best, partner = _test_pair(p, gathered[m], 0.0, 0.0, 0.0, xi, yi, zi, vxi, vyi, vzi, ri, t, scale, best,
                                       partner)
        return _found(best, partner)
    if cell_members.shape[1] < 2:
        for q in range(offsets.shape[1]):
            if offsets[row, q, 0] == ROW_END:
                break
            x, sx = _neighbour_cell(c0, offsets[row, q, 0], n0, periodic0, l0)
            y, sy = _neighbour_cell(c1, offsets[row, q, 1], n1, periodic1, l1)
            z, sz = _neighbour_cell(c2, offsets[row, q, 2], n2, periodic2, l2)
            if x < 0 or y < 0 or z < 0:
                continue
            best, partner = _scan_members(p, x + n0 * (y + n1 * z), sx, sy, sz, cell_members, cell_count, xi, yi,
                                          zi, vxi, vyi, vzi, ri, t, scale, best, partner)
        return _found(best, partner)
    # a cell on the grid's faces: each member gathered with the image its cell is seen through
    found = _gather_edge_members(c0, c1, c2, offsets, row, cell_members, cell_count, ncell, geom, gathered)
    for m in range(found):
        j, image = gathered[m] // IMAGES, gathered[m] % IMAGES
        best, partner = _test_pair(p, j, (image % 3 - 1) * l0, (image // 3 % 3 - 1) * l1, (image // 9 - 1) * l2, xi,
                                   yi, zi, vxi, vyi, vzi, ri, t, scale, best, partner)
    return _found(best, partner)


__all__ = ["ALL_NEIGHBOURS", "IMAGES", "ROW_END", "linear_offsets", "offset_table", "search_cells"]
