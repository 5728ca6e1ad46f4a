"""The cell grid: cell coordinates and indices, neighbouring cells, cell membership of the anchors."""

from __future__ import annotations

import math

# no EDMD kernel allocates or returns an array: all of them borrow, without reference counting
from ..._jit import borrowing_inline_kernel as inline_kernel
from ..._jit import borrowing_kernel as kernel
from .layout import ANCHOR, G_CELL


@inline_kernel
def cell_coordinates(cell, ncell):
    """(x, y, z) coordinates of cell number ``cell`` (x fastest)."""
    cx = cell % ncell[0]
    rest = cell // ncell[0]
    return cx, rest % ncell[1], rest // ncell[1]


@inline_kernel
def cell_index(cx, cy, cz, ncell):
    """Number of the cell at coordinates (cx, cy, cz): the inverse of :func:`cell_coordinates`."""
    return cx + ncell[0] * (cy + ncell[1] * cz)


@kernel
def neighbour_coordinate(c, offset, n, periodic, length):
    """Neighbour cell coordinate along one axis and the image shift; -1 if outside."""
    c += offset
    if c < 0:
        if not periodic:
            return -1, 0.0
        return c + n, -length
    if c >= n:
        if not periodic:
            return -1, 0.0
        return c - n, length
    return c, 0.0


@kernel
def cell_offsets(n, periodic):
    """Cell offsets to visit along one axis: each neighbouring cell once, also when n < 3."""
    if periodic and n < 3:
        return 0, n - 1
    return -1, 1


@inline_kernel
def cell_remove(i, cell_of, cell_members, cell_count, cell_points):
    """Take particle i out of its cell (the last member moves into its slot).

    i's slot is found by a scan of the cell (a few members, in cache lines
    the rebuild reads anyway) rather than kept per particle, which would
    cost a write to the moved particle's record, a cache miss.
    """
    cell = cell_of[i]
    last = cell_count[cell] - 1
    slot = last
    while cell_members[cell, slot] != i:
        slot -= 1
    cell_members[cell, slot] = cell_members[cell, last]
    for k in range(4):
        cell_points[cell, slot, k] = cell_points[cell, last, k]
    cell_count[cell] = last


@inline_kernel
def cell_insert(i, cell, b, radius, cell_of, cell_members, cell_count, cell_points):
    """Append particle i (anchor and radius) to ``cell``; False if the cell is full."""
    slot = cell_count[cell]
    if slot >= cell_members.shape[1]:
        return False
    cell_members[cell, slot] = i
    for k in range(3):
        cell_points[cell, slot, k] = b[i, ANCHOR + k]
    cell_points[cell, slot, 3] = radius
    cell_count[cell] = slot + 1
    cell_of[i] = cell
    return True


@inline_kernel
def cell_of_anchor(b, i, ncell, geom, dim):
    """Number of the cell holding particle i's anchor (clamped into the grid)."""
    c0 = c1 = c2 = 0
    for k in range(dim):
        c = int(math.floor(b[i, ANCHOR + k] / geom[G_CELL, k]))
        c = min(max(c, 0), ncell[k] - 1)
        if k == 0:
            c0 = c
        elif k == 1:
            c1 = c
        else:
            c2 = c
    return cell_index(c0, c1, c2, ncell)
