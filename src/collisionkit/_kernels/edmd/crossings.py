"""The cell-crossing engine: events are collisions, wall hits and cell crossings; no neighbour lists.

For dilute systems, where a neighbour list expires after a fraction of a
free path. The cells are no smaller than the largest contact distance, so
a particle can touch only particles in its own and the adjacent cells
(Rapaport, The Art of Molecular Dynamics Simulation, 2nd ed., ch. 14;
the "Cell" variant of Smallenburg, arXiv:2201.01100). Each particle keeps
one queued event, the earliest of

* its best pair collision found so far (``pending``: absolute time,
  partner, number of the event that predicted it), kept across its cell
  crossings: a crossing searches only the cells that came into its
  neighbourhood (9 of 27 in 3D, 3 of 9 in 2D) and keeps the earlier of the
  old and the new best;
* its next cell crossing (TARGET ``crossing_target(face)``);
* its next wall hit (TARGET ``wall_target(face)``).

A pair event is stale when the partner changed velocity after the
prediction (its CHANGED_AT is later than the pending PREDICTED_AT); a stale
or resolved event makes the particle search all its neighbouring cells
again. A particle's cell (``cell_of``) is state, not recomputed from its
position: a crossing moves it to the next cell whatever round-off did to
the position, and a crossing of a periodic face moves the position by a
box length (with the image counter and the Helfand image sums, as
:func:`.motion.wrap_into_box`). Positions therefore stay within round-off
of their cells, and each neighbouring cell is seen through one periodic
shift, taken once per cell.

Straight flights and fixed radii only (no gravity, compression or shear:
those systems use the neighbour lists).
"""

from __future__ import annotations

import math

# no EDMD kernel allocates or returns an array: all of them borrow, without reference counting
from ..._jit import borrowing_inline_kernel as inline_kernel
from ..._jit import borrowing_kernel as kernel
from .._memory import prefetch
from .cell_search import ALL_NEIGHBOURS, search_cells
from .cells import cell_coordinates, cell_index
from .contacts import bounce_off_wall, collide_pair
from .layout import (
    ACC_CELL_OVERFLOW, ACC_EVENTS, ACC_LIST_REBUILDS, ACC_STALE_EVENTS, CELLS_PREFETCH_FROM, CHANGED_AT, G_BOX, G_CELL,
    G_PERIODIC, P_SCALE0, PREDICTED_AT, R, STOP_COLLISIONS, STOP_EVENTS, STOP_NO_EVENT,
    STOP_OVERFLOW, STOP_STALLED, STOP_TIME, T, TARGET, V, X, wall_target,
)
from .motion import shift_by_box, wrap_into_box
from .prediction import first_root_from_below
from .queue import likely_next, prefetch_queue_entry, queue_update, tree_build

# columns of the pending-collision records (float64, N x 3)
PENDING_TIME = 0  # absolute time of the particle's best pair collision found so far (inf: none)
PENDING_PARTNER = 1
PENDING_AT = 2  # number of the event that predicted it

# TARGET codes of cell crossings: crossing_target(face), face = 2 * axis + 1 (upper) or 2 * axis (lower),
# below the wall codes (-2 ... -7)
CROSSING_BASE = -8
# relative widening of the horizon of a crossing's search (the time left to the pending collision)
HORIZON_MARGIN = 1e-12


@kernel
def crossing_target(face):
    """TARGET code of a crossing of face ``face`` of the particle's cell; its own inverse."""
    return CROSSING_BASE - face


@inline_kernel
def _axis_crossing(c, n, x, v, width, periodic):
    """Time until a flight at x with speed v along one axis leaves cell c of n there (inf if never), without a branch.

    Towards the upper face (c + 1) w when v > 0, the lower c w when v < 0;
    a face on a wall is never crossed; a position past the face by
    round-off crosses at once (the time is held at 0). The velocity's sign
    is a coin toss, so a branch on it would be mispredicted half the time.
    """
    up = v > 0.0
    face_at = (c + 1 if up else c) * width
    can_leave = v != 0.0 and (periodic or (c < n - 1 if up else c > 0))
    return max((face_at - x) / v, 0.0) if can_leave else math.inf


@inline_kernel
def next_crossing(p, i, c0, c1, c2, ncell, geom, dim):
    """Time (from i's time) until i leaves its cell (c0, c1, c2), and the face; (inf, -1) if it never does.

    A face on a wall is never crossed (the wall hit comes first). A
    position past the face by round-off crosses at once. The axes are
    taken in order, an earlier one winning a tie.
    """
    best = math.inf
    face = -1
    for k in range(3):
        c = c0 if k == 0 else (c1 if k == 1 else c2)
        v = p[i, V + k] if k < dim else 0.0
        tau = _axis_crossing(c, ncell[k], p[i, X + k], v, geom[G_CELL, k], geom[G_PERIODIC, k] != 0.0)
        face = 2 * k + (1 if v > 0.0 else 0) if tau < best else face
        best = min(tau, best)
    return best, face


@inline_kernel
def next_wall_hit(p, i, geom, dim, scale):
    """Time (from i's time) until i touches a wall, and the wall's TARGET; (inf, 0) in a periodic box.

    The roots of :func:`.prediction.predict_boundary` without gravity or
    growth (the same arithmetic, so the same times).
    """
    best = math.inf
    target = 0
    r = p[i, R]
    for k in range(dim):
        if geom[G_PERIODIC, k] != 0.0:
            continue
        x = p[i, X + k]
        v = p[i, V + k]
        tau = first_root_from_below(0.0, v, x + r * scale - geom[G_BOX, k])
        if tau < best:
            best, target = tau, wall_target(2 * k + 1)
        tau = first_root_from_below(0.0, -v, r * scale - x)
        if tau < best:
            best, target = tau, wall_target(2 * k)
    return best, target


@inline_kernel
def _queue_earliest(p, i, b, pending, boundary, boundary_target, queue, tree, leaves):
    """Queue i's earlier of its pending collision and its boundary event (from i's time)."""
    boundary_time = p[i, T] + boundary
    if pending[i, PENDING_TIME] < boundary_time:
        b[i, TARGET] = pending[i, PENDING_PARTNER]
        queue_update(i, pending[i, PENDING_TIME], queue, tree, leaves)
    else:
        b[i, TARGET] = boundary_target
        queue_update(i, boundary_time, queue, tree, leaves)


@inline_kernel
def _boundary(p, i, c0, c1, c2, ncell, geom, dim, scale):
    """i's next boundary event: (time from i's time, TARGET), a wall hit or a crossing of cell (c0, c1, c2)."""
    crossing, face = next_crossing(p, i, c0, c1, c2, ncell, geom, dim)
    wall, wall_code = next_wall_hit(p, i, geom, dim, scale)
    if wall < crossing:
        return wall, wall_code
    # a particle at rest never leaves its cell: an event at inf, still a crossing code (a TARGET of 0 would name
    # particle 0 as its partner)
    return crossing, crossing_target(max(face, 0))


@inline_kernel
def predict_fully(p, i, b, pending, offsets, steps, cell_of, cell_members, cell_count, ncell, geom, dim, scale,
                  event, queue, tree, leaves, gathered):
    """Search all of i's neighbouring cells, record its best collision as pending and queue its next event."""
    c0, c1, c2 = cell_coordinates(cell_of[i], ncell)
    tau, partner = search_cells(p, i, c0, c1, c2, offsets, steps, ALL_NEIGHBOURS, cell_members, cell_count, ncell,
                                geom, scale, math.inf, gathered)
    pending[i, PENDING_TIME] = p[i, T] + tau if partner >= 0 else math.inf
    pending[i, PENDING_PARTNER] = partner
    pending[i, PENDING_AT] = event
    b[i, PREDICTED_AT] = event
    boundary, target = _boundary(p, i, c0, c1, c2, ncell, geom, dim, scale)
    _queue_earliest(p, i, b, pending, boundary, target, queue, tree, leaves)


@inline_kernel
def _cross(p, i, face, b, pending, image, offsets, steps, cell_of, cell_members, cell_count, ncell, geom, dim, scale,
           event, acc, queue, tree, leaves, gathered):
    """Move i (at the crossing) into the next cell, search the cells it brings in, queue i's next event.

    False if the new cell is full (``acc[ACC_CELL_OVERFLOW]`` set).
    """
    old = cell_of[i]
    last = cell_count[old] - 1
    slot = last
    while cell_members[old, slot] != i:
        slot -= 1
    cell_members[old, slot] = cell_members[old, last]
    cell_count[old] = last
    axis = face // 2
    step = 1 if face % 2 == 1 else -1
    c0, c1, c2 = cell_coordinates(old, ncell)
    c = (c0 if axis == 0 else (c1 if axis == 1 else c2)) + step
    if c < 0 or c >= ncell[axis]:  # across a periodic face: the position moves by a box length with the cell
        c = c + ncell[axis] if c < 0 else c - ncell[axis]
        shift_by_box(p, i, axis, -step, geom, image, b, acc)
    if axis == 0:
        c0 = c
    elif axis == 1:
        c1 = c
    else:
        c2 = c
    new = cell_index(c0, c1, c2, ncell)
    if cell_count[new] >= cell_members.shape[1]:
        acc[ACC_CELL_OVERFLOW] = cell_count[new] + 1
        cell_members[old, cell_count[old]] = i  # back where it was, so the state stays whole
        cell_count[old] += 1
        return False
    cell_members[new, cell_count[new]] = i
    cell_count[new] += 1
    cell_of[i] = new
    # only a contact before the pending one can replace it: that bound rejects most pairs by the cheap filter
    # (a hair wider than the difference of times, so that round-off cannot drop one the comparison below keeps)
    horizon = pending[i, PENDING_TIME] - p[i, T]
    tau, partner = search_cells(p, i, c0, c1, c2, offsets, steps, face, cell_members, cell_count, ncell, geom,
                                scale, horizon + horizon * HORIZON_MARGIN, gathered)
    if partner >= 0 and p[i, T] + tau < pending[i, PENDING_TIME]:
        pending[i, PENDING_TIME] = p[i, T] + tau
        pending[i, PENDING_PARTNER] = partner
        pending[i, PENDING_AT] = event
    boundary, target = _boundary(p, i, c0, c1, c2, ncell, geom, dim, scale)
    _queue_earliest(p, i, b, pending, boundary, target, queue, tree, leaves)
    return True


@inline_kernel
def _prefetch_particle(i, p, b, pending, cell_of, queue, tree, leaves):
    """Start loading the records an event of particle i reads, so that the misses overlap."""
    prefetch(p, i)
    prefetch(b, i)
    prefetch(pending, i)
    prefetch(cell_of, i)
    prefetch_queue_entry(i, queue, tree, leaves)


@inline_kernel
def _prefetch_neighbourhood(cell, cell_members, cell_count, ncell):
    """Start loading the counts and member rows of the cells around ``cell`` if it is off the grid's faces.

    Along x the 3 cells of a row are adjacent in memory: their ends are
    prefetched, one line each for the counts, every member row.
    """
    n0, n1, n2 = ncell[0], ncell[1], ncell[2]
    c0, c1, c2 = cell_coordinates(cell, ncell)
    if not (0 < c0 < n0 - 1 and 0 < c1 < n1 - 1 and (n2 == 1 or 0 < c2 < n2 - 1)):
        return
    layers = 3 if n2 > 1 else 1
    for dz in range(layers):
        for dy in range(3):
            centre = cell + n0 * ((dy - 1) + n1 * (dz - (1 if n2 > 1 else 0)))
            prefetch(cell_count, centre - 1)
            prefetch(cell_count, centre + 1)
            prefetch(cell_members, centre - 1)
            prefetch(cell_members, centre)
            prefetch(cell_members, centre + 1)


@inline_kernel
def _fly(p, i, t, dim):
    """Move particle i along its straight flight to time t."""
    dt = t - p[i, T]
    if dt != 0.0:
        for k in range(dim):
            p[i, X + k] += p[i, V + k] * dt
        p[i, T] = t


@kernel
def run_crossing_events(t, still, max_pair_collisions, max_events, t_stop, stall_limit, p, b, pending, image,
                        offsets, steps, cell_of, cell_members, cell_count, ncell, geom, dim, restitution, params, queue,
                        tree, leaves, acc, gathered, spin):
    """:func:`.loop.run_events` for the cell-crossing engine: same arguments' meaning, same results.

    Cell crossings are counted in ``acc[ACC_LIST_REBUILDS]`` (the
    boundary events of this engine). ``gathered`` is scratch for the cell
    searches: int64, 3^dim times the slots a cell, plus 2; ``spin`` the
    angular velocities of rough spheres. It stops with ``STOP_OVERFLOW`` and
    ``acc[ACC_CELL_OVERFLOW]`` set if a cell outgrows its row.
    """
    done = 0
    events = 0
    longest = still
    stop = STOP_COLLISIONS
    target = -1
    scale = params[P_SCALE0]
    event = int(acc[ACC_EVENTS])
    prefetching = p.shape[0] >= CELLS_PREFETCH_FROM
    while done < max_pair_collisions:
        if events >= max_events:
            stop = STOP_EVENTS
            break
        event_time = tree[1, 0]
        i = int(tree[1, 1])
        if event_time > t_stop:
            if t_stop > t:
                still = 0
            t = t_stop
            stop = STOP_TIME
            break
        if event_time == math.inf:
            stop = STOP_NO_EVENT
            break
        still = still + 1 if event_time == t else 0
        longest = max(longest, still)
        if still >= stall_limit:
            stop = STOP_STALLED
            break
        t = event_time
        event += 1
        events += 1
        target = int(b[i, TARGET])
        upcoming = -1
        if prefetching:  # memory latency dominates: start every load whose address is known
            _prefetch_particle(i, p, b, pending, cell_of, queue, tree, leaves)
            upcoming = likely_next(i, tree, leaves)
            if upcoming >= 0:
                _prefetch_particle(upcoming, p, b, pending, cell_of, queue, tree, leaves)
            if target >= 0:
                _prefetch_particle(target, p, b, pending, cell_of, queue, tree, leaves)
        _fly(p, i, t, dim)
        if upcoming >= 0:  # its records have arrived by now: fetch the cells around it and its partner's records
            _prefetch_neighbourhood(cell_of[upcoming], cell_members, cell_count, ncell)
            upcoming_target = int(b[upcoming, TARGET])
            if upcoming_target >= 0:
                _prefetch_particle(upcoming_target, p, b, pending, cell_of, queue, tree, leaves)
        if target >= 0:
            j = target
            if b[j, CHANGED_AT] > pending[i, PENDING_AT]:
                acc[ACC_STALE_EVENTS] += 1.0
            else:
                _fly(p, j, t, dim)
                if collide_pair(p, i, j, b, geom, scale, 0.0, restitution, params, acc, spin):
                    b[i, CHANGED_AT] = event
                    b[j, CHANGED_AT] = event
                    done += 1
                predict_fully(p, j, b, pending, offsets, steps, cell_of, cell_members, cell_count, ncell, geom, dim,
                              scale, event, queue, tree, leaves, gathered)
        elif target <= CROSSING_BASE:
            acc[ACC_LIST_REBUILDS] += 1.0
            if not _cross(p, i, crossing_target(target), b, pending, image, offsets, steps, cell_of, cell_members,
                          cell_count, ncell, geom, dim, scale, event, acc, queue, tree, leaves, gathered):
                stop = STOP_OVERFLOW
                break
            continue
        else:
            bounce_off_wall(p, i, wall_target(target), b, params, acc)
            b[i, CHANGED_AT] = event
        predict_fully(p, i, b, pending, offsets, steps, cell_of, cell_members, cell_count, ncell, geom, dim, scale,
                      event, queue, tree, leaves, gathered)
    acc[ACC_EVENTS] = event
    return t, still, longest, stop, target


@kernel
def predict_all_crossings(p, b, pending, offsets, steps, cell_of, cell_members, cell_count, ncell, geom, dim, params,
                          queue, tree, leaves, acc, gathered):
    """Predict every particle's next event (all at their own times) and rebuild the tree (``gathered``: scratch)."""
    event = int(acc[ACC_EVENTS])
    scale = params[P_SCALE0]
    for i in range(p.shape[0]):
        predict_fully(p, i, b, pending, offsets, steps, cell_of, cell_members, cell_count, ncell, geom, dim, scale,
                      event, queue, tree, leaves, gathered)
    for padding in range(p.shape[0], queue.shape[0]):
        queue[padding] = math.inf
    tree_build(tree, queue, leaves)


@kernel
def wrap_all(p, geom, dim, image, b, acc, params):
    """Bring every particle into [0, L) on periodic axes (:func:`.motion.wrap_into_box`, image sums kept)."""
    for i in range(p.shape[0]):
        wrap_into_box(p, i, geom, dim, image, b, acc, params)


@kernel
def bin_into_cells(p, cell_of, cell_members, cell_count, ncell, geom, dim):
    """Put every particle into the cell holding its position (clamped into the grid); the fullest cell's count.

    Positions must lie in the box. Returns early with the count needed if
    a cell outgrows its row (the caller grows the rows and bins again).
    """
    cell_count[:] = 0
    for i in range(p.shape[0]):
        c0 = c1 = c2 = 0
        for k in range(dim):
            c = min(max(int(math.floor(p[i, X + k] / geom[G_CELL, k])), 0), ncell[k] - 1)
            if k == 0:
                c0 = c
            elif k == 1:
                c1 = c
            else:
                c2 = c
        cell = cell_index(c0, c1, c2, ncell)
        if cell_count[cell] >= cell_members.shape[1]:
            return cell_count[cell] + 1
        cell_members[cell, cell_count[cell]] = i
        cell_count[cell] += 1
        cell_of[i] = cell
    return 0


__all__ = [
    "CROSSING_BASE", "PENDING_AT", "PENDING_PARTNER", "PENDING_TIME", "bin_into_cells", "crossing_target",
    "next_crossing", "next_wall_hit", "predict_all_crossings", "run_crossing_events", "wrap_all",
]
