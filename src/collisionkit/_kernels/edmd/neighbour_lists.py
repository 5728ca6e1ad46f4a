"""Neighbour lists: building every list, and rebuilding one particle's at its list event."""

from __future__ import annotations

import math

# no EDMD kernel allocates or returns an array: all of them borrow, without reference counting
from ..._jit import borrowing_inline_kernel as inline_kernel
from ..._jit import borrowing_kernel as kernel
from .._memory import prefetch, prefetch_at
from .cells import (
    cell_coordinates, cell_index, cell_insert, cell_of_position, cell_offsets, cell_remove, neighbour_coordinate,
)
from .layout import (
    ACC_CELL_OVERFLOW, ACC_LIST_OVERFLOW, ANCHOR, ANCHOR_ROUNDING, CELL_SLOTS_PER_LINE, G_BOX, G_CELL, G_PERIODIC,
    P_LIST_SCALE, P_SHEAR_MARGIN, P_SHEAR_RATE, P_SHELL, R, T, X,
)
from .motion import half_box, minimum_image, shear_offset, wrap_into_box


@inline_kernel
def gather_neighbours(p, i, b, cell_of, neighbours, neighbour_count, cell_members, cell_count, cell_points, ncell,
                      geom, dim, params):
    """Fill i's list from the anchors in the cells around i's anchor.

    Returns the length the list would need (more than the row length:
    nothing beyond the row is written, the caller must grow it).
    """
    width = neighbours.shape[1]
    count = 0
    cx, cy, cz = cell_coordinates(cell_of[i], ncell)
    zl, zh = cell_offsets(ncell[2], geom[G_PERIODIC, 2] != 0.0) if dim == 3 else (0, 0)
    yl, yh = cell_offsets(ncell[1], geom[G_PERIODIC, 1] != 0.0)
    xl, xh = cell_offsets(ncell[0], geom[G_PERIODIC, 0] != 0.0)
    lx, ly, lz = geom[G_BOX, 0], geom[G_BOX, 1], geom[G_BOX, 2]
    # with 3 cells or more along every periodic axis each neighbouring cell is seen through one image, so its
    # periodic shift is taken once per cell; with fewer a cell is its own neighbour on both sides: minimum images
    per_cell = True
    for k in range(dim):
        per_cell = per_cell and (ncell[k] >= 3 or geom[G_PERIODIC, k] == 0.0)
    hx, hy, hz = half_box(geom, 0), half_box(geom, 1), half_box(geom, 2)
    if per_cell:
        hx, hy, hz = math.inf, math.inf, math.inf
    ax, ay, az = b[i, ANCHOR], b[i, ANCHOR + 1], b[i, ANCHOR + 2]
    # anchors are stored in float32 in the cells: widen the test by their round-off
    slack = ANCHOR_ROUNDING * (max(lx, ly, lz) + 1.0)
    reach_i = p[i, R] * params[P_LIST_SCALE] + params[P_SHELL] + slack
    list_scale = params[P_LIST_SCALE]
    for oz in range(zl, zh + 1):
        nz, sz = neighbour_coordinate(cz, oz, ncell[2], geom[G_PERIODIC, 2] != 0.0, lz)
        if nz < 0:
            continue
        for oy in range(yl, yh + 1):
            ny, sy = neighbour_coordinate(cy, oy, ncell[1], geom[G_PERIODIC, 1] != 0.0, ly)
            if ny < 0:
                continue
            for ox in range(xl, xh + 1):
                nx, sx = neighbour_coordinate(cx, ox, ncell[0], geom[G_PERIODIC, 0] != 0.0, lx)
                if nx < 0:
                    continue
                cell = cell_index(nx, ny, nz, ncell)
                # the anchors seen from i's: the periodic image of the cell (the shift is 0 or a box length)
                shift_x, shift_y, shift_z = ax - sx, ay - sy, az - sz
                if not per_cell:
                    shift_x, shift_y, shift_z = ax, ay, az
                for slot in range(cell_count[cell]):
                    dx = minimum_image(cell_points[cell, slot, 0] - shift_x, lx, hx)
                    dy = minimum_image(cell_points[cell, slot, 1] - shift_y, ly, hy)
                    dz = minimum_image(cell_points[cell, slot, 2] - shift_z, lz, hz)
                    reach = reach_i + cell_points[cell, slot, 3] * list_scale
                    j = cell_members[cell, slot]
                    # written at the end of the list whether kept or not (no branch on the distance to mispredict),
                    # only while the row has room: a full row's last entry stays (a list that outgrows its row is
                    # rebuilt anyway)
                    if count < width:
                        neighbours[i, count] = j
                    count += (dx * dx + dy * dy + dz * dz <= reach * reach) & (j != i)
    neighbour_count[i] = min(count, width)
    return count


@inline_kernel
def _row_columns(column, centre, across, reach, ncell, geom):
    """Columns of cells to scan in a row for anchors within ``reach`` along x of ``centre``: (first, last, half).

    ``first`` and ``last`` are unwrapped column numbers, at most one row
    length outside it (``centre`` in [0, L_x), ``reach`` below 1.5 cell
    widths); if they would cover the row, every column once, seen through
    the minimum image (``half`` = L_x / 2; else inf, no image to take per
    anchor). Rows within the box (``across`` = 0) scan the three columns
    around ``column``, the anchor's.
    """
    first, last = column - 1, column + 1
    if across != 0.0:
        width = geom[G_CELL, 0]
        first = int(math.floor((centre - reach) / width))
        last = int(math.floor((centre + reach) / width))
    if last - first + 1 >= ncell[0]:
        return 0, ncell[0] - 1, 0.5 * geom[G_BOX, 0]
    return first, last, math.inf


@inline_kernel
def _scan_row(i, cx, ny, nz, across, shift_y, shift_z, ax, offset, hz, reach_i, margin, list_scale, neighbours, count,
              cell_members, cell_count, cell_points, ncell, geom):
    """Append to i's list the anchors of one row of cells (y row ``ny``, z layer ``nz``) near i's anchor (column cx).

    The row lies across a y face if ``across`` is -1 or 1: its anchors are
    then seen as their sliding images, shifted by ``across`` box heights
    and ``across`` offsets along x, and kept within the list radius plus
    the shear margin along x only: (max(|dx| - margin, 0))^2 + dy^2 + dz^2
    <= reach^2, a capsule that holds every anchor the images bring within
    the list radius while the offset moves by less than the margin (the
    faces' y and z separations do not slide). Written at the end of the
    list whether kept or not while the row has room, as in
    :func:`gather_neighbours`. Returns the count so far.
    """
    width = neighbours.shape[1]
    lx = geom[G_BOX, 0]
    lz = geom[G_BOX, 2]
    centre = ax
    extra = 0.0
    if across != 0.0:
        centre = ax - across * offset
        centre -= lx * math.floor(centre / lx)
        extra = margin
    first, last, hx = _row_columns(cx, centre, across, geom[G_CELL, 0] + extra, ncell, geom)
    for column in range(first, last + 1):
        # the column's cell, and the whole box lengths it is seen shifted by (none if every column is scanned once)
        nx, shift_x = column, centre
        if column < 0:
            nx, shift_x = column + ncell[0], centre + lx
        elif column >= ncell[0]:
            nx, shift_x = column - ncell[0], centre - lx
        cell = cell_index(nx, ny, nz, ncell)
        for slot in range(cell_count[cell]):
            dx = minimum_image(cell_points[cell, slot, 0] - shift_x, lx, hx)
            dy = cell_points[cell, slot, 1] - shift_y
            dz = minimum_image(cell_points[cell, slot, 2] - shift_z, lz, hz)
            ex = max(abs(dx) - extra, 0.0)
            reach = reach_i + cell_points[cell, slot, 3] * list_scale
            j = cell_members[cell, slot]
            if count < width:
                neighbours[i, count] = j
            count += (ex * ex + dy * dy + dz * dz <= reach * reach) & (j != i)
    return count


@inline_kernel
def _gather_sheared(p, i, b, cell_of, neighbours, neighbour_count, cell_members, cell_count, cell_points, ncell, geom,
                    dim, params):
    """:func:`gather_neighbours` under Lees-Edwards shear (at least 3 rows of cells along y).

    Across a y face the neighbouring row of cells is the one at the other
    face, seen shifted by the box offset at i's time (see :func:`_scan_row`).
    Pairs whose anchors face each other across a y face are listed out to
    the list radius plus the shear margin along x: between two sweeps
    (every margin / (G L_y) in time) the images drift by less than the
    margin along x relative to the anchors, and every particle anchored in
    the first or last row of cells (all that could meet a partner across a
    face before rebuilding, the rows being as high as the list radius)
    renews its partners across the faces at each sweep
    (:func:`refresh_across_faces`).
    """
    cx, cy, cz = cell_coordinates(cell_of[i], ncell)
    zl, zh = cell_offsets(ncell[2], geom[G_PERIODIC, 2] != 0.0) if dim == 3 else (0, 0)
    ly, lz = geom[G_BOX, 1], geom[G_BOX, 2]
    # with fewer than 3 layers along z a layer is its own neighbour on both sides: minimum images per anchor
    hz = half_box(geom, 2) if ncell[2] < 3 else math.inf
    ax, ay, az = b[i, ANCHOR], b[i, ANCHOR + 1], b[i, ANCHOR + 2]
    slack = ANCHOR_ROUNDING * (max(geom[G_BOX, 0], ly, lz) + 1.0)
    reach_i = p[i, R] * params[P_LIST_SCALE] + params[P_SHELL] + slack
    margin = params[P_SHEAR_MARGIN]
    offset = shear_offset(params, geom, p[i, T])
    count = 0
    for oz in range(zl, zh + 1):
        nz, sz = neighbour_coordinate(cz, oz, ncell[2], geom[G_PERIODIC, 2] != 0.0, lz)
        if nz < 0:
            continue
        shift_z = az - sz if hz == math.inf else az
        for oy in range(-1, 2):
            row = cy + oy
            across = -1.0 if row < 0 else (1.0 if row >= ncell[1] else 0.0)
            ny = row - int(across) * ncell[1]
            count = _scan_row(i, cx, ny, nz, across, ay - across * ly, shift_z, ax, offset, hz, reach_i, margin,
                              params[P_LIST_SCALE], neighbours, count, cell_members, cell_count, cell_points, ncell,
                              geom)
    neighbour_count[i] = min(count, neighbours.shape[1])
    return count


@inline_kernel
def _row_of(i, cell_of, ncell):
    """Row of cells along y of particle i's anchor."""
    return (cell_of[i] // ncell[0]) % ncell[1]


@kernel
def refresh_across_faces(p, b, cell_of, neighbours, neighbour_count, cell_members, cell_count, cell_points, ncell,
                         geom, dim, params, t):
    """Lees-Edwards sweep at time t: renew the listed pairs across the y faces, from the anchors and the offset at t.

    Only particles anchored in the first and the last row of cells have
    partners across a face (a row is as high as the list radius), and a
    pair listed across a face is one of each: every such pair is dropped
    from both lists, then the first row's particles list their partners in
    the last row anew, both ways, as :func:`_gather_sheared` would at t
    (their anchors stay, so their other partners and list events stay as
    they are). Returns the length a list would need, more than the rows
    hold if one outgrew its row (the lists are then incomplete: grow the
    rows and rebuild them all).
    """
    top = ncell[1] - 1
    zl, zh = cell_offsets(ncell[2], geom[G_PERIODIC, 2] != 0.0) if dim == 3 else (0, 0)
    for row in (0, top):
        for cz in range(ncell[2]):
            for cx in range(ncell[0]):
                cell = cell_index(cx, row, cz, ncell)
                for slot in range(cell_count[cell]):
                    i = cell_members[cell, slot]
                    kept = 0
                    for m in range(neighbour_count[i]):
                        j = neighbours[i, m]
                        neighbours[i, kept] = j
                        kept += _row_of(j, cell_of, ncell) + row != top
                    neighbour_count[i] = kept
    ly, lz = geom[G_BOX, 1], geom[G_BOX, 2]
    hz = half_box(geom, 2) if ncell[2] < 3 else math.inf
    slack = ANCHOR_ROUNDING * (max(geom[G_BOX, 0], ly, lz) + 1.0)
    margin = params[P_SHEAR_MARGIN]
    offset = shear_offset(params, geom, t)
    width = neighbours.shape[1]
    needed = 0
    for cz in range(ncell[2]):
        for cx in range(ncell[0]):
            cell = cell_index(cx, 0, cz, ncell)
            for slot in range(cell_count[cell]):
                i = cell_members[cell, slot]
                ax, ay, az = b[i, ANCHOR], b[i, ANCHOR + 1], b[i, ANCHOR + 2]
                reach_i = p[i, R] * params[P_LIST_SCALE] + params[P_SHELL] + slack
                start = neighbour_count[i]
                count = start
                for oz in range(zl, zh + 1):
                    nz, sz = neighbour_coordinate(cz, oz, ncell[2], geom[G_PERIODIC, 2] != 0.0, lz)
                    if nz < 0:
                        continue
                    count = _scan_row(i, cx, top, nz, -1.0, ay + ly, az - sz if hz == math.inf else az, ax, offset, hz,
                                      reach_i, margin, params[P_LIST_SCALE], neighbours, count,
                                      cell_members, cell_count, cell_points, ncell, geom)
                neighbour_count[i] = min(count, width)
                needed = max(needed, count)
                for m in range(start, neighbour_count[i]):
                    j = neighbours[i, m]
                    other = neighbour_count[j]
                    if other < width:
                        neighbours[j, other] = i
                        neighbour_count[j] = other + 1
                    needed = max(needed, other + 1)
    return needed


@inline_kernel
def _gather(p, i, b, cell_of, neighbours, neighbour_count, cell_members, cell_count, cell_points, ncell, geom, dim,
            params):
    """Fill i's list: :func:`gather_neighbours`, or :func:`_gather_sheared` under shear."""
    if params[P_SHEAR_RATE] != 0.0:
        return _gather_sheared(p, i, b, cell_of, neighbours, neighbour_count, cell_members, cell_count, cell_points,
                               ncell, geom, dim, params)
    return gather_neighbours(p, i, b, cell_of, neighbours, neighbour_count, cell_members, cell_count, cell_points,
                             ncell, geom, dim, params)


@inline_kernel
def _join_neighbours(i, neighbours, neighbour_count):
    """Append i to the list of each particle in i's list; returns the longest length needed."""
    width = neighbours.shape[1]
    for m in range(neighbour_count[i]):
        prefetch(neighbours, neighbours[i, m])
        prefetch(neighbour_count, neighbours[i, m])
    needed = 0
    for m in range(neighbour_count[i]):
        j = neighbours[i, m]
        other = neighbour_count[j]
        if other < width:
            neighbours[j, other] = i
            neighbour_count[j] = other + 1
        needed = max(needed, other + 1)
    return needed


@inline_kernel
def _prefetch_cells(cell, cell_members, cell_count, cell_points, ncell, geom, dim):
    """Start loading the cells around ``cell`` (their counts and first slots)."""
    cx, cy, cz = cell_coordinates(cell, ncell)
    zl, zh = cell_offsets(ncell[2], geom[G_PERIODIC, 2] != 0.0) if dim == 3 else (0, 0)
    yl, yh = cell_offsets(ncell[1], geom[G_PERIODIC, 1] != 0.0)
    for oz in range(zl, zh + 1):
        nz, _ = neighbour_coordinate(cz, oz, ncell[2], geom[G_PERIODIC, 2] != 0.0, 0.0)
        if nz < 0:
            continue
        for oy in range(yl, yh + 1):
            ny, _ = neighbour_coordinate(cy, oy, ncell[1], geom[G_PERIODIC, 1] != 0.0, 0.0)
            if ny < 0:
                continue
            for ox in range(-1, 2):
                nx = (cx + ox) % ncell[0]  # a wrong guess at a walled edge costs nothing
                neighbour_cell = cell_index(nx, ny, nz, ncell)
                prefetch(cell_points, neighbour_cell)
                prefetch_at(cell_points, neighbour_cell, CELL_SLOTS_PER_LINE)  # a fifth sphere is common
                prefetch(cell_count, neighbour_cell)


@inline_kernel
def _drop_from_list(j, i, neighbours, neighbour_count):
    """Remove i from j's list (order not kept)."""
    last = neighbour_count[j] - 1
    for m in range(last + 1):
        if neighbours[j, m] == i:
            neighbours[j, m] = neighbours[j, last]
            neighbour_count[j] = last
            return


@inline_kernel
def rebuild_list(p, i, b, cell_of, neighbours, neighbour_count, cell_members, cell_count, cell_points, ncell, geom,
                 dim, params, image, acc):
    """Re-anchor particle i at its position (at its own time) and rebuild its list.

    Returns False, with ``acc[ACC_LIST_OVERFLOW]`` or ``acc[ACC_CELL_OVERFLOW]``
    set to the size needed, if a list or a cell outgrew its row; the lists
    are then incomplete and must all be rebuilt.
    """
    wrap_into_box(p, i, geom, dim, image, b, acc, params)
    cell = cell_of_position(p, i, ncell, geom, dim)
    _prefetch_cells(cell, cell_members, cell_count, cell_points, ncell, geom, dim)
    for m in range(neighbour_count[i]):
        prefetch(neighbours, neighbours[i, m])
        prefetch(neighbour_count, neighbours[i, m])
    for m in range(neighbour_count[i]):
        _drop_from_list(neighbours[i, m], i, neighbours, neighbour_count)
    for k in range(3):
        b[i, ANCHOR + k] = p[i, X + k]
    cell_remove(i, cell_of, cell_members, cell_count, cell_points)
    if not cell_insert(i, cell, b, p[i, R], cell_of, cell_members, cell_count, cell_points):
        acc[ACC_CELL_OVERFLOW] = cell_count[cell] + 1
        return False
    needed = _gather(p, i, b, cell_of, neighbours, neighbour_count, cell_members, cell_count, cell_points, ncell, geom,
                     dim, params)
    needed = max(needed, _join_neighbours(i, neighbours, neighbour_count))
    if needed > neighbours.shape[1]:
        acc[ACC_LIST_OVERFLOW] = needed
        return False
    return True


@kernel
def build_all_lists(p, b, cell_of, neighbours, neighbour_count, cell_members, cell_count, cell_points, ncell, geom,
                    dim, params, image, acc):
    """Anchor every particle at its position (all synchronised) and build every list.

    Returns the longest list and the fullest cell needed; if either exceeds
    its row length the structures are incomplete and the caller must grow
    them and call again.
    """
    cell_count[:] = 0
    most = 0
    for i in range(p.shape[0]):
        wrap_into_box(p, i, geom, dim, image, b, acc, params)
        for k in range(3):
            b[i, ANCHOR + k] = p[i, X + k]
        cell = cell_of_position(p, i, ncell, geom, dim)
        if not cell_insert(i, cell, b, p[i, R], cell_of, cell_members, cell_count, cell_points):
            cell_count[cell] += 1  # count what would not fit, to report the size needed
        most = max(most, cell_count[cell])
    if most > cell_members.shape[1]:
        return 0, most
    needed = 0
    for i in range(p.shape[0]):
        count = _gather(p, i, b, cell_of, neighbours, neighbour_count, cell_members, cell_count, cell_points, ncell,
                        geom, dim, params)
        needed = max(needed, count)
    return needed, most
