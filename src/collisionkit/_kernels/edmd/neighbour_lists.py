"""Neighbour lists: building every list, and rebuilding one particle's at its list event."""

from __future__ import annotations

import math

# no EDMD kernel allocates or returns an array: all of them borrow, without reference counting
from ..._jit import borrowing_inline_kernel as inline_kernel
from ..._jit import borrowing_kernel as kernel
from .._memory import prefetch, prefetch_at
from .cells import (
    cell_coordinates, cell_index, cell_insert, cell_of_anchor, cell_offsets, cell_remove, neighbour_coordinate,
)
from .layout import (
    ACC_CELL_OVERFLOW, ACC_LIST_OVERFLOW, ANCHOR, ANCHOR_ROUNDING, CELL_SLOTS_PER_LINE, G_BOX, G_CELL, G_PERIODIC,
    P_LIST_SCALE, P_SHEAR_FRAME, P_SHEAR_RATE, P_SHEAR_REACH, P_SHELL, R, T, X,
)
from .motion import frame_x, half_box, minimum_image, shear_offset, streaming_velocity, wrap_into_box, wrapped


@inline_kernel
def _append_within(i, j, dx, dy, dz, reach, neighbours, count):
    """Keep j in i's list if its anchor is within ``reach`` (separation dx, dy, dz) and not i's own; the new count.

    j is written at the end of the list whether kept or not (no branch on
    the distance to mispredict), only while the row has room: a full row's
    last entry stays (a list that outgrows its row is rebuilt anyway).
    """
    if count < neighbours.shape[1]:
        neighbours[i, count] = j
    return count + ((dx * dx + dy * dy + dz * dz <= reach * reach) & (j != i))


@inline_kernel
def _scan_cell(i, cell, shift_x, shift_y, shift_z, reach_i, list_scale, neighbours, count, cell_members, cell_count,
               cell_points):
    """Append to i's list the anchors of one cell within reach of i's anchor, the cell seen at a fixed shift.

    ``shift`` is i's anchor minus the cell's periodic shift (0 or a box
    length a side), so no anchor needs an image of its own. Returns the
    count so far.
    """
    for slot in range(cell_count[cell]):
        dx = cell_points[cell, slot, 0] - shift_x
        dy = cell_points[cell, slot, 1] - shift_y
        dz = cell_points[cell, slot, 2] - shift_z
        reach = reach_i + cell_points[cell, slot, 3] * list_scale
        count = _append_within(i, cell_members[cell, slot], dx, dy, dz, reach, neighbours, count)
    return count


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
                if per_cell:
                    count = _scan_cell(i, cell, ax - sx, ay - sy, az - sz, reach_i, list_scale, neighbours, count,
                                       cell_members, cell_count, cell_points)
                    continue
                for slot in range(cell_count[cell]):
                    dx = minimum_image(cell_points[cell, slot, 0] - ax, lx, hx)
                    dy = minimum_image(cell_points[cell, slot, 1] - ay, ly, hy)
                    dz = minimum_image(cell_points[cell, slot, 2] - az, lz, hz)
                    count = _append_within(i, cell_members[cell, slot], dx, dy, dz,
                                           reach_i + cell_points[cell, slot, 3] * list_scale, neighbours, count)
    neighbour_count[i] = min(count, width)
    return count


@inline_kernel
def _row_columns(centre, reach, ncell, geom):
    """Columns of cells to scan in a row for anchors within ``reach`` along x of ``centre``: (first, last, half).

    ``first`` and ``last`` are unwrapped column numbers, at most one row
    length outside it (``centre`` in [0, L_x), ``reach`` below L_x); if they
    would cover the row, every column once, seen through the minimum image
    (``half`` = L_x / 2; else inf, no image to take per anchor).
    """
    width = geom[G_CELL, 0]
    first = int(math.floor((centre - reach) / width))
    last = int(math.floor((centre + reach) / width))
    if last - first + 1 >= ncell[0]:
        return 0, ncell[0] - 1, 0.5 * geom[G_BOX, 0]
    return first, last, math.inf


@inline_kernel
def _scan_row(i, ny, nz, across, shift_y, shift_z, centre, strain, hz, reach_i, largest, list_scale, neighbours,
              count, cell_members, cell_count, cell_points, ncell, geom):
    """Append to i's list the anchors of one row of cells (y row ``ny``, z layer ``nz``) near i's (sheared frame).

    The cells hold the anchors' frame x (:func:`.motion.frame_x`); at a
    strain ``strain`` = G (t - t_f) from the frame time, two anchors' lab
    separation along x is their frame separation plus ``strain`` times
    their y separation. ``centre`` is i's frame x seen from the row (shifted
    back by the frame's offset if the row lies across a y face:
    ``across`` = -1 or 1, its anchors seen ``across`` box heights away), so
    the row's anchors within ``largest`` of i's lie within
    ``largest (1 + |strain|)`` of it along x (kept by
    :func:`_append_within`). Returns the count so far.
    """
    lx = geom[G_BOX, 0]
    lz = geom[G_BOX, 2]
    first, last, hx = _row_columns(centre, largest * (1.0 + abs(strain)), ncell, geom)
    for column in range(first, last + 1):
        # the column's cell, and the whole box lengths it is seen shifted by (none if every column is scanned once)
        nx, shift_x = column, centre
        if column < 0:
            nx, shift_x = column + ncell[0], centre + lx
        elif column >= ncell[0]:
            nx, shift_x = column - ncell[0], centre - lx
        cell = cell_index(nx, ny, nz, ncell)
        for slot in range(cell_count[cell]):
            dy = cell_points[cell, slot, 1] - shift_y
            dx = minimum_image(cell_points[cell, slot, 0] - shift_x, lx, hx) + strain * dy
            dz = minimum_image(cell_points[cell, slot, 2] - shift_z, lz, hz)
            count = _append_within(i, cell_members[cell, slot], dx, dy, dz,
                                   reach_i + cell_points[cell, slot, 3] * list_scale, neighbours, count)
    return count


@inline_kernel
def _gather_sheared(p, i, b, cell_of, neighbours, neighbour_count, cell_members, cell_count, cell_points, ncell, geom,
                    dim, params):
    """:func:`gather_neighbours` under Lees-Edwards shear (at least 3 rows of cells along y).

    The anchors move with the flow at their heights and the cells hold them
    in the flow's frame (:func:`.motion.frame_x`), where the sliding images
    stand still: across a y face the neighbouring row of cells is the one at
    the other face, shifted by the offset at the frame time t_f. The lab
    separation of two anchors now, at strain G (t - t_f), follows exactly
    from their frame separation (see :func:`_scan_row`), and i lists those
    within the list radius, as in a periodic box. Two anchors then move
    apart or together along x at G times their y separation: an unlisted
    pair's anchors, more than R = sigma + shell apart at the later of their
    rebuilds t_b, stay at least R (1 - |G| (t - t_b) / 2) apart (the
    smallest singular value of the shear map [[1, s], [0, 1]] is
    sqrt(1 + s^2 / 4) - |s| / 2 >= 1 - |s| / 2), so each particle's list
    stays valid while its distance from its moving anchor plus |G| R / 4
    times the list's age is below shell / 2 (:func:`.prediction.list_expiry`).
    """
    cx, cy, cz = cell_coordinates(cell_of[i], ncell)
    zl, zh = cell_offsets(ncell[2], geom[G_PERIODIC, 2] != 0.0) if dim == 3 else (0, 0)
    lx, ly, lz = geom[G_BOX, 0], geom[G_BOX, 1], geom[G_BOX, 2]
    # with fewer than 3 layers along z a layer is its own neighbour on both sides: minimum images per anchor
    hz = half_box(geom, 2) if ncell[2] < 3 else math.inf
    ax, ay, az = b[i, ANCHOR], b[i, ANCHOR + 1], b[i, ANCHOR + 2]
    slack = ANCHOR_ROUNDING * (max(lx, ly, lz) + 1.0)
    reach_i = p[i, R] * params[P_LIST_SCALE] + params[P_SHELL] + slack
    offset = shear_offset(params, geom, params[P_SHEAR_FRAME])
    strain = params[P_SHEAR_RATE] * (p[i, T] - params[P_SHEAR_FRAME])
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
            centre = wrapped(ax - across * offset, lx)
            count = _scan_row(i, ny, nz, across, ay - across * ly, shift_z, centre, strain, hz, reach_i,
                              params[P_SHEAR_REACH], params[P_LIST_SCALE], neighbours, count, cell_members, cell_count,
                              cell_points, ncell, geom)
    neighbour_count[i] = min(count, neighbours.shape[1])
    return count


@inline_kernel
def _anchor(p, i, b, geom, params, anchor_time):
    """Anchor particle i at its position (at its own time): in the flow's frame and timed under shear."""
    for k in range(3):
        b[i, ANCHOR + k] = p[i, X + k]
    if params[P_SHEAR_RATE] != 0.0:
        b[i, ANCHOR] = frame_x(params, geom, p[i, X], p[i, X + 1], p[i, T])
        anchor_time[i] = p[i, T]


@kernel
def sweep_frame(p, b, cell_of, cell_members, cell_count, cell_points, ncell, geom, dim, params, t):
    """Lees-Edwards sweep: the flow's frame is moved on to time t, every anchor's frame x with it, the cells refilled.

    A point carried by the flow at height y has frame x
    ``xi + u_x(y) (t - t_f)`` at the new frame time (:func:`.motion.frame_x`):
    the anchors stay where they are in the lab, and so do the lists and
    every predicted event; only the cells change, so that the strain of the
    frame (how far the cells must be scanned along x, :func:`_scan_row`)
    starts again from 0. Returns the fullest cell's count (more than its
    slots hold: the cells are incomplete, grow them and rebuild all).
    """
    lx = geom[G_BOX, 0]
    elapsed = t - params[P_SHEAR_FRAME]
    cell_count[:] = 0
    most = 0
    for i in range(p.shape[0]):
        b[i, ANCHOR] = wrapped(b[i, ANCHOR] + streaming_velocity(params, geom, b[i, ANCHOR + 1]) * elapsed, lx)
        cell = cell_of_anchor(b, i, ncell, geom, dim)
        if not cell_insert(i, cell, b, p[i, R], cell_of, cell_members, cell_count, cell_points):
            cell_count[cell] += 1  # count what would not fit, to report the size needed
        most = max(most, cell_count[cell])
    params[P_SHEAR_FRAME] = t
    return most


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
def _prefetch_cells(cell, cell_members, cell_count, cell_points, ncell, geom, dim, members):
    """Start loading the cells around ``cell``: their counts, first slots and, if ``members``, member rows."""
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
                if members:
                    prefetch(cell_members, neighbour_cell)


@inline_kernel
def prefetch_rebuild(i, b, cell_of, neighbours, neighbour_count, cell_members, cell_count, cell_points, ncell, geom,
                     dim):
    """Start loading what i's coming list rebuild reads: its neighbours' lists and the cells around its anchor.

    The new anchor lies within half a shell of the old one, so in the old
    anchor's cell or next to it: most of the cells the rebuild scans.
    """
    for m in range(neighbour_count[i]):
        prefetch(neighbours, neighbours[i, m])
        prefetch(neighbour_count, neighbours[i, m])
    prefetch(cell_of, i)
    _prefetch_cells(cell_of_anchor(b, i, ncell, geom, dim), cell_members, cell_count, cell_points, ncell, geom, dim,
                    True)


@inline_kernel
def drop_from_list(j, i, neighbours, neighbour_count):
    """Remove i from j's list (order not kept; also the square wells' record of pairs inside, :mod:`.wells`)."""
    last = neighbour_count[j] - 1
    for m in range(last + 1):
        if neighbours[j, m] == i:
            neighbours[j, m] = neighbours[j, last]
            neighbour_count[j] = last
            return


@inline_kernel
def rebuild_list(p, i, b, anchor_time, cell_of, neighbours, neighbour_count, cell_members, cell_count, cell_points,
                 ncell, geom, dim, params, image, acc):
    """Re-anchor particle i at its position (at its own time) and rebuild its list.

    Returns False, with ``acc[ACC_LIST_OVERFLOW]`` or ``acc[ACC_CELL_OVERFLOW]``
    set to the size needed, if a list or a cell outgrew its row; the lists
    are then incomplete and must all be rebuilt.
    """
    wrap_into_box(p, i, geom, dim, image, b, acc, params)
    _anchor(p, i, b, geom, params, anchor_time)
    cell = cell_of_anchor(b, i, ncell, geom, dim)
    _prefetch_cells(cell, cell_members, cell_count, cell_points, ncell, geom, dim, False)
    for m in range(neighbour_count[i]):
        prefetch(neighbours, neighbours[i, m])
        prefetch(neighbour_count, neighbours[i, m])
    for m in range(neighbour_count[i]):
        drop_from_list(neighbours[i, m], i, neighbours, neighbour_count)
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
def anchor_all(p, b, anchor_time, cell_of, cell_members, cell_count, cell_points, ncell, geom, dim, params, image, acc):
    """Anchor every particle at its position (all synchronised) and fill the cells with the anchors; no list built.

    Returns the fullest cell's count (more than its slots hold: the cells
    are incomplete, grow them and call again).
    """
    cell_count[:] = 0
    most = 0
    for i in range(p.shape[0]):
        wrap_into_box(p, i, geom, dim, image, b, acc, params)
        _anchor(p, i, b, geom, params, anchor_time)
        cell = cell_of_anchor(b, i, ncell, geom, dim)
        if not cell_insert(i, cell, b, p[i, R], cell_of, cell_members, cell_count, cell_points):
            cell_count[cell] += 1  # count what would not fit, to report the size needed
        most = max(most, cell_count[cell])
    return most


@kernel
def build_all_lists(p, b, anchor_time, cell_of, neighbours, neighbour_count, cell_members, cell_count, cell_points,
                    ncell, geom, dim, params, image, acc):
    """Anchor every particle at its position (all synchronised, :func:`anchor_all`) and build every list.

    Returns the longest list and the fullest cell needed; if either exceeds
    its row length the structures are incomplete and the caller must grow
    them and call again.
    """
    most = anchor_all(p, b, anchor_time, cell_of, cell_members, cell_count, cell_points, ncell, geom, dim, params, image,
                      acc)
    if most > cell_members.shape[1]:
        return 0, most
    needed = 0
    for i in range(p.shape[0]):
        count = _gather(p, i, b, cell_of, neighbours, neighbour_count, cell_members, cell_count, cell_points, ncell,
                        geom, dim, params)
        needed = max(needed, count)
    return needed, most
