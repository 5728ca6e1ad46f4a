"""The event loop: take the earliest event, resolve it, predict again; and the first prediction of all."""

from __future__ import annotations

import math

# no EDMD kernel allocates or returns an array: all of them borrow, without reference counting
from ..._jit import borrowing_inline_kernel as inline_kernel
from ..._jit import borrowing_kernel as kernel
from .._memory import prefetch
from .contacts import bounce_off_wall, collide_pair
from .layout import (
    ACC_CELL_OVERFLOW, ACC_EVENTS, ACC_LIST_REBUILDS, ACC_STALE_EVENTS, CHANGED_AT, LIST_TARGET, P_GROWTH, P_SCALE0,
    P_SHEAR_RATE, P_SHEAR_SWEEP, PREDICTED_AT, PREFETCH_FROM, PREFETCH_REBUILDS_FROM, SHEAR_SWEEP_STRAIN,
    STOP_COLLISIONS, STOP_EVENTS, STOP_NO_EVENT, STOP_OVERFLOW, STOP_STALLED, STOP_TIME, TARGET, WELL_TARGET_BASE,
    wall_target, well_target,
)
from .motion import advance
from .neighbour_lists import prefetch_rebuild, rebuild_list, sweep_frame
from .prediction import predict
from .queue import likely_next, prefetch_queue_entry, queue_update, tree_build
from .wells import cross_well_edge, predict_in_wells


@inline_kernel
def _prefetch_particle(i, p, b, queue, neighbours, neighbour_count, tree, leaves):
    """Start loading everything an event of particle i reads, so the misses overlap."""
    prefetch(p, i)
    prefetch(b, i)
    prefetch(neighbours, i)
    prefetch(neighbour_count, i)
    prefetch_queue_entry(i, queue, tree, leaves)


@inline_kernel
def _prefetch_neighbours(i, p, neighbours, neighbour_count):
    """Start loading the records of the particles in i's list."""
    for m in range(neighbour_count[i]):
        prefetch(p, neighbours[i, m])


@inline_kernel
def _repredict(p, i, b, anchor_time, neighbours, neighbour_count, geom, dim, params, queue, tree, leaves, event):
    """Predict i's next event (i at its own time) and queue it."""
    queue_update(i, predict(p, i, b, anchor_time, neighbours, neighbour_count, geom, dim, params, event), queue, tree,
                 leaves)


@inline_kernel
def _repredict_in_wells(p, i, b, anchor_time, neighbours, neighbour_count, bonds, bond_count, geom, dim, params,
                        queue, tree, leaves, event):
    """:func:`_repredict` with square wells (:func:`.wells.predict_in_wells`)."""
    queue_update(i, predict_in_wells(p, i, b, anchor_time, neighbours, neighbour_count, bonds, bond_count, geom, dim,
                                     params, event), queue, tree, leaves)


@kernel
def run_events(t, still, max_pair_collisions, max_events, t_stop, stall_limit, p, b, anchor_time, image, cell_of,
               neighbours, neighbour_count, cell_members, cell_count, cell_points, ncell, geom, dim, restitution,
               params, queue, tree, leaves, acc, spin, bonds=None, bond_count=None):
    """Process events until ``max_pair_collisions`` collisions, ``max_events`` events or time ``t_stop``.

    ``still`` is the number of events in a row at time ``t`` so far (the
    previous call's count). Returns ``(time, still, longest, stop,
    target)``: the current time (the last event's time, or ``t_stop`` if
    that came first; particles are not moved to it: call ``synchronise``),
    the events in a row at it, the most events in a row at one instant in
    this call (a collapse that round-off ended, if large), why it stopped
    (a ``STOP_*`` code of :mod:`.layout`) and the target of the last event
    (a partner >= 0, ``LIST_TARGET`` or a wall's code: what stalled, with
    ``STOP_STALLED``).
    It stops early with ``STOP_OVERFLOW``, ``acc[ACC_LIST_OVERFLOW]`` or
    ``acc[ACC_CELL_OVERFLOW]`` set to the size needed, if a neighbour list
    or a cell outgrows its row (grow the rows and rebuild every list); and
    with ``STOP_STALLED`` after ``stall_limit`` events in a row at one
    instant (the caller scales it with N: a symmetric lattice makes N
    events at one instant), a collapse (infinitely many events in finite
    time) whose clock has stopped in floating point and that would never end.
    ``max_events`` bounds the time of one call, so that a caller looping
    over calls can be interrupted in between.

    ``spin`` holds the angular velocities of rough spheres (any array for
    smooth ones: :func:`.contacts.collide_pair`).

    With square wells ``bonds`` and ``bond_count`` are the record of the
    pairs inside (:mod:`.wells`); hard spheres pass None, and numba compiles
    them a loop without the wells' code (its ``is None`` branches pruned
    before typing: the code had cost 5 % at N = 32000, and a loop compiled
    with both took 3 to 7 times as long to compile).
    """
    done = 0
    events = 0
    longest = still
    stop = STOP_COLLISIONS
    target = LIST_TARGET
    scale0 = params[P_SCALE0]
    growth = params[P_GROWTH]
    event = int(acc[ACC_EVENTS])
    prefetching = p.shape[0] >= PREFETCH_FROM
    prefetching_rebuilds = p.shape[0] >= PREFETCH_REBUILDS_FROM
    while done < max_pair_collisions:
        if events >= max_events:
            stop = STOP_EVENTS
            break
        event_time = tree[1, 0]
        i = int(tree[1, 1])
        if params[P_SHEAR_RATE] != 0.0 and event_time < math.inf and min(event_time, t_stop) >= params[P_SHEAR_SWEEP]:
            # Lees-Edwards: the flow's frame moves on before the cells would have to be scanned too far along x
            sweep = params[P_SHEAR_SWEEP]
            still = still + 1 if sweep == t else 0
            t = sweep
            events += 1
            fullest = sweep_frame(p, b, cell_of, cell_members, cell_count, cell_points, ncell, geom, dim, params, t)
            params[P_SHEAR_SWEEP] = sweep + SHEAR_SWEEP_STRAIN / abs(params[P_SHEAR_RATE])
            if fullest > cell_members.shape[1]:
                acc[ACC_CELL_OVERFLOW] = fullest
                stop = STOP_OVERFLOW
                break
            continue
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
        # memory latency dominates: start every load whose address is known, then compute;
        # also for the particle of the next event, most likely the runner-up now
        upcoming = -1
        target = int(b[i, TARGET])
        if prefetching:
            _prefetch_particle(i, p, b, queue, neighbours, neighbour_count, tree, leaves)
            upcoming = likely_next(i, tree, leaves)
            if upcoming >= 0:
                _prefetch_particle(upcoming, p, b, queue, neighbours, neighbour_count, tree, leaves)
            if target >= 0:
                _prefetch_particle(target, p, b, queue, neighbours, neighbour_count, tree, leaves)
            _prefetch_neighbours(i, p, neighbours, neighbour_count)
        advance(p, i, t, geom, dim)
        partner = -1  # the second particle to re-predict, if any
        if target >= 0:
            j = target
            if prefetching:
                _prefetch_neighbours(j, p, neighbours, neighbour_count)
            if b[j, CHANGED_AT] > b[i, PREDICTED_AT]:
                acc[ACC_STALE_EVENTS] += 1.0
            else:
                advance(p, j, t, geom, dim)
                if collide_pair(p, i, j, b, geom, scale0 + growth * t, growth, restitution, params, acc, spin):
                    b[i, CHANGED_AT] = event
                    b[j, CHANGED_AT] = event
                    done += 1
                partner = j
        elif target <= WELL_TARGET_BASE:
            if bonds is not None:
                j = well_target(target)
                if b[j, CHANGED_AT] > b[i, PREDICTED_AT]:
                    acc[ACC_STALE_EVENTS] += 1.0
                else:
                    advance(p, j, t, geom, dim)
                    if cross_well_edge(p, i, j, b, geom, params, bonds, bond_count, image, acc, t):
                        b[i, CHANGED_AT] = event
                        b[j, CHANGED_AT] = event
                    partner = j
        elif target == LIST_TARGET:
            acc[ACC_LIST_REBUILDS] += 1.0
            if not rebuild_list(p, i, b, anchor_time, cell_of, neighbours, neighbour_count, cell_members, cell_count,
                                cell_points, ncell, geom, dim, params, image, acc):
                stop = STOP_OVERFLOW
                break
        else:
            bounce_off_wall(p, i, wall_target(target), b, params, acc)
            b[i, CHANGED_AT] = event
        if upcoming >= 0:  # its rows have arrived by now: fetch what they point to
            _prefetch_neighbours(upcoming, p, neighbours, neighbour_count)
            upcoming_target = int(b[upcoming, TARGET])
            if upcoming_target >= 0:
                _prefetch_particle(upcoming_target, p, b, queue, neighbours, neighbour_count, tree, leaves)
            elif upcoming_target == LIST_TARGET and prefetching_rebuilds:
                prefetch_rebuild(upcoming, b, cell_of, neighbours, neighbour_count, cell_members, cell_count,
                                 cell_points, ncell, geom, dim)
        # one call site, so the inlined prediction is compiled once
        for q in range(1 if partner < 0 else 2):
            if bonds is None:
                _repredict(p, i if q == 0 else partner, b, anchor_time, neighbours, neighbour_count, geom, dim, params,
                           queue, tree, leaves, event)
            else:
                _repredict_in_wells(p, i if q == 0 else partner, b, anchor_time, neighbours, neighbour_count, bonds,
                                    bond_count, geom, dim, params, queue, tree, leaves, event)
    acc[ACC_EVENTS] = event
    return t, still, longest, stop, target


@kernel
def predict_all(p, b, anchor_time, neighbours, neighbour_count, geom, dim, params, queue, tree, leaves, acc, bonds=None,
                bond_count=None):
    """Predict every particle's next event (all at their own times) and rebuild the tree (wells: see run_events)."""
    event = int(acc[ACC_EVENTS])
    for i in range(p.shape[0]):
        if bonds is None:
            queue[i] = predict(p, i, b, anchor_time, neighbours, neighbour_count, geom, dim, params, event)
        else:
            queue[i] = predict_in_wells(p, i, b, anchor_time, neighbours, neighbour_count, bonds, bond_count, geom,
                                        dim, params, event)
    for padding in range(p.shape[0], queue.shape[0]):
        queue[padding] = math.inf
    tree_build(tree, queue, leaves)
