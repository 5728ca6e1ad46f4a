"""Numba kernels of the event-driven engine for hard spheres and discs.

Algorithm (Rapaport; Isobe, Int. J. Mod. Phys. C 10, 1281 (1999)):

* particles move ballistically (parabolas under uniform gravity) and are
  updated lazily: ``pos[i]`` and ``vel[i]`` hold the state at the
  particle's own time ``tloc[i]``;
* a cell list with cells no smaller than the largest contact distance;
  every particle has exactly one scheduled event, the earliest of: a
  collision with a particle in the 3^d surrounding cells, leaving its cell,
  or hitting a wall;
* a complete binary tree over the particles' event times gives the next
  event in O(1) and updates in O(log N);
* an event with partner j is stale if j has changed velocity since it was
  predicted (``counter[j]`` moved on); stale events are re-predicted.

Growing particles (Lubachevsky-Stillinger compression) use radii
``radius * (scale0 + growth * t)``; with growth 0 the contact quadratic is the
one of :mod:`collisionkit._kernels.collisions`.

Boxes span [0, L) on every axis; an axis is periodic or closed by hard walls
at 0 and L. Periodic images are fixed by which neighbour cell a partner sits
in, so boxes of only 3 cells per axis are handled exactly.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import kernel

# event kinds
NO_EVENT = 0
PAIR = 1
CELL = 2
WALL = 3

# accumulator slots (acc array)
ACC_VIRIAL = 0  # sum over pair collisions of impulse * contact distance
ACC_PAIR_COLLISIONS = 1
ACC_WALL_COLLISIONS = 2
ACC_CELL_CROSSINGS = 3
ACC_STALE_EVENTS = 4
ACC_ENERGY_LOST = 5
ACC_WALL_IMPULSE = 6  # sum of |momentum| transferred to walls
ACC_SIZE = 7

# restitution laws
LAW_CONSTANT = 0
LAW_BRIDGES = 1  # e = min(1, (u_n / u_c)^-exponent), Bridges, Hatzes & Lin, Nature 309, 333 (1984)


@kernel
def first_root_from_below(a, b, c):
    """Smallest tau >= 0 where a tau^2 + b tau + c reaches 0, given c <= 0 now.

    Used for leaving a cell or reaching a wall: the function is a (negative)
    distance to the boundary. Returns inf if it never gets there.
    """
    if c >= 0.0:
        # at or (by round-off) just past the boundary
        if b > 0.0 or (b == 0.0 and a > 0.0):
            return 0.0
        if a <= 0.0:
            return math.inf
        discriminant = b * b - 4.0 * a * c
        if discriminant <= 0.0:
            return 0.0
        return (-b + math.sqrt(discriminant)) / (2.0 * a)
    if a == 0.0:
        return -c / b if b > 0.0 else math.inf
    discriminant = b * b - 4.0 * a * c
    if a > 0.0:
        # c < 0 < a: exactly one positive root, (-b + root) / 2a
        root = math.sqrt(discriminant)
        return (-2.0 * c) / (b + root) if b >= 0.0 else (-b + root) / (2.0 * a)
    # a < 0: a hump, reached only when moving towards the boundary
    if b <= 0.0 or discriminant < 0.0:
        return math.inf
    return (-2.0 * c) / (b + math.sqrt(discriminant))


@kernel
def pair_contact_time(rx, ry, rz, ux, uy, uz, contact, scale, growth, beat):
    """Time until |r + u tau| = contact * (scale + growth * tau), first touch only.

    r is the separation (partner minus particle), u the relative velocity
    (partner minus particle). Returns 0 for an overlapping approaching pair
    (round-off), inf if they never touch or cannot touch before ``beat``.
    """
    rr = rx * rx + ry * ry + rz * rz
    ru = rx * ux + ry * uy + rz * uz
    sigma = contact * scale
    rate = contact * growth
    c = rr - sigma * sigma
    b = ru - sigma * rate
    if c <= 0.0:
        return 0.0 if b < 0.0 else math.inf
    if rate == 0.0:
        # fixed sizes: only approaching pairs meet, and never before c / (-2 b)
        if b >= 0.0 or c >= -2.0 * b * beat:
            return math.inf
    uu = ux * ux + uy * uy + uz * uz
    a = uu - rate * rate
    cx = ry * uz - rz * uy
    cy = rz * ux - rx * uz
    cz = rx * uy - ry * ux
    wx = scale * ux - growth * rx
    wy = scale * uy - growth * ry
    wz = scale * uz - growth * rz
    # b^2 - a c == contact^2 |scale u - growth r|^2 - |r x u|^2 (Lagrange's identity)
    discriminant = contact * contact * (wx * wx + wy * wy + wz * wz) - (cx * cx + cy * cy + cz * cz)
    if b < 0.0:
        if discriminant < 0.0:
            return math.inf
        return c / (-b + math.sqrt(discriminant))
    if a < 0.0:
        return (b + math.sqrt(max(discriminant, 0.0))) / (-a)
    return math.inf


@kernel
def advance(i, t, pos, vel, tloc, gravity):
    """Move particle i along its flight to time t (exact parabola)."""
    dt = t - tloc[i]
    if dt != 0.0:
        for k in range(pos.shape[1]):
            pos[i, k] += (vel[i, k] + 0.5 * gravity[k] * dt) * dt
            vel[i, k] += gravity[k] * dt
        tloc[i] = t


@kernel
def cell_coordinates(cell, ncell):
    cx = cell % ncell[0]
    rest = cell // ncell[0]
    cy = rest % ncell[1]
    cz = rest // ncell[1]
    return cx, cy, cz


@kernel
def cell_index(cx, cy, cz, ncell):
    return cx + ncell[0] * (cy + ncell[1] * cz)


@kernel
def tree_update(leaf, tree_index, tree_time, ev_time, leaves):
    """Propagate leaf's new event time up the tournament tree."""
    node = leaves + leaf
    tree_time[node] = ev_time[leaf]
    node >>= 1
    while node >= 1:
        left = 2 * node
        right = left + 1
        if tree_time[left] <= tree_time[right]:
            tree_index[node] = tree_index[left]
            tree_time[node] = tree_time[left]
        else:
            tree_index[node] = tree_index[right]
            tree_time[node] = tree_time[right]
        node >>= 1


@kernel
def tree_build(tree_index, tree_time, ev_time, n, leaves):
    for leaf in range(leaves):
        tree_index[leaves + leaf] = leaf
        tree_time[leaves + leaf] = ev_time[leaf] if leaf < n else math.inf
    for node in range(leaves - 1, 0, -1):
        left = 2 * node
        right = left + 1
        if tree_time[left] <= tree_time[right]:
            tree_index[node] = tree_index[left]
            tree_time[node] = tree_time[left]
        else:
            tree_index[node] = tree_index[right]
            tree_time[node] = tree_time[right]


@kernel
def boundary_event(i, pos, vel, radius, cell_of, ncell, cell_size, box, periodic, gravity, scale, growth):
    """Earliest time (from particle i's own time) it leaves its cell or hits a wall.

    Returns (tau, kind, code) with code = 2 * axis + (1 if upward else 0).
    """
    d = pos.shape[1]
    best = math.inf
    kind = NO_EVENT
    code = -1
    cx, cy, cz = cell_coordinates(cell_of[i], ncell)
    cells = (cx, cy, cz)
    r = radius[i]
    for k in range(d):
        c = cells[k]
        x = pos[i, k]
        v = vel[i, k]
        g = 0.5 * gravity[k]
        # upper side
        if periodic[k] or c < ncell[k] - 1:
            tau = first_root_from_below(g, v, x - (c + 1) * cell_size[k])
            this_kind = CELL
        else:
            tau = first_root_from_below(g, v + r * growth, x + r * scale - box[k])
            this_kind = WALL
        if tau < best:
            best = tau
            kind = this_kind
            code = 2 * k + 1
        # lower side
        if periodic[k] or c > 0:
            tau = first_root_from_below(-g, -v, c * cell_size[k] - x)
            this_kind = CELL
        else:
            tau = first_root_from_below(-g, -v + r * growth, r * scale - x)
            this_kind = WALL
        if tau < best:
            best = tau
            kind = this_kind
            code = 2 * k
    return best, kind, code


@kernel
def predict(
    i, t, pos, vel, tloc, radius, cell_of, head, next_in_cell, ncell, cell_size, box, periodic,
    gravity, scale0, growth, counter, ev_time, ev_kind, ev_partner, ev_count,
):
    """Schedule particle i's next event (i must be at time t)."""
    d = pos.shape[1]
    scale = scale0 + growth * t
    tau, kind, code = boundary_event(i, pos, vel, radius, cell_of, ncell, cell_size, box, periodic, gravity, scale, growth)
    best = tau
    best_kind = kind
    best_partner = code
    cx, cy, cz = cell_coordinates(cell_of[i], ncell)
    pix = pos[i, 0]
    piy = pos[i, 1]
    piz = pos[i, 2] if d == 3 else 0.0
    vix = vel[i, 0]
    viy = vel[i, 1]
    viz = vel[i, 2] if d == 3 else 0.0
    zrange = 1 if d == 3 else 0
    for oz in range(-zrange, zrange + 1):
        nz = cz + oz
        shift_z = 0.0
        if d == 3:
            if nz < 0:
                if not periodic[2]:
                    continue
                nz += ncell[2]
                shift_z = -box[2]
            elif nz >= ncell[2]:
                if not periodic[2]:
                    continue
                nz -= ncell[2]
                shift_z = box[2]
        for oy in range(-1, 2):
            ny = cy + oy
            shift_y = 0.0
            if ny < 0:
                if not periodic[1]:
                    continue
                ny += ncell[1]
                shift_y = -box[1]
            elif ny >= ncell[1]:
                if not periodic[1]:
                    continue
                ny -= ncell[1]
                shift_y = box[1]
            for ox in range(-1, 2):
                nx = cx + ox
                shift_x = 0.0
                if nx < 0:
                    if not periodic[0]:
                        continue
                    nx += ncell[0]
                    shift_x = -box[0]
                elif nx >= ncell[0]:
                    if not periodic[0]:
                        continue
                    nx -= ncell[0]
                    shift_x = box[0]
                j = head[cell_index(nx, ny, nz, ncell)]
                while j >= 0:
                    if j != i:
                        dt = t - tloc[j]
                        # relative velocity is unchanged by gravity (both fall alike)
                        rx = pos[j, 0] + vel[j, 0] * dt + 0.5 * gravity[0] * dt * dt + shift_x - pix
                        ry = pos[j, 1] + vel[j, 1] * dt + 0.5 * gravity[1] * dt * dt + shift_y - piy
                        ux = vel[j, 0] + gravity[0] * dt - vix
                        uy = vel[j, 1] + gravity[1] * dt - viy
                        if d == 3:
                            rz = pos[j, 2] + vel[j, 2] * dt + 0.5 * gravity[2] * dt * dt + shift_z - piz
                            uz = vel[j, 2] + gravity[2] * dt - viz
                        else:
                            rz = 0.0
                            uz = 0.0
                        tau = pair_contact_time(rx, ry, rz, ux, uy, uz, radius[i] + radius[j], scale, growth, best)
                        if tau < best:
                            best = tau
                            best_kind = PAIR
                            best_partner = j
                    j = next_in_cell[j]
    ev_time[i] = t + best
    ev_kind[i] = best_kind
    ev_partner[i] = best_partner
    ev_count[i] = counter[best_partner] if best_kind == PAIR else 0


@kernel
def cell_remove(i, cell, head, next_in_cell, prev_in_cell):
    p = prev_in_cell[i]
    n = next_in_cell[i]
    if p >= 0:
        next_in_cell[p] = n
    else:
        head[cell] = n
    if n >= 0:
        prev_in_cell[n] = p


@kernel
def cell_insert(i, cell, head, next_in_cell, prev_in_cell):
    first = head[cell]
    next_in_cell[i] = first
    prev_in_cell[i] = -1
    if first >= 0:
        prev_in_cell[first] = i
    head[cell] = i


@kernel
def build_cells(pos, ncell, cell_size, cell_of, head, next_in_cell, prev_in_cell):
    head[:] = -1
    d = pos.shape[1]
    for i in range(pos.shape[0]):
        c = [0, 0, 0]
        for k in range(d):
            ck = int(math.floor(pos[i, k] / cell_size[k]))
            c[k] = min(max(ck, 0), ncell[k] - 1)
        cell = cell_index(c[0], c[1], c[2], ncell)
        cell_of[i] = cell
        cell_insert(i, cell, head, next_in_cell, prev_in_cell)


@kernel
def restitution_for(i, j, approach, species, restitution, law, law_speed, law_exponent, elastic_below):
    """Coefficient of normal restitution of one contact."""
    if approach < elastic_below:
        return 1.0
    e = restitution[species[i], species[j]]
    if law == LAW_BRIDGES and approach > law_speed:
        e = min(e, (approach / law_speed) ** (-law_exponent))
    return e


@kernel
def collide_pair(
    i, j, pos, vel, mass, radius, box, periodic, scale, growth, species, restitution, law, law_speed,
    law_exponent, elastic_below, acc,
):
    """Resolve the contact of i and j (both at the current time)."""
    d = pos.shape[1]
    r = np.empty(3)
    norm2 = 0.0
    for k in range(d):
        x = pos[j, k] - pos[i, k]
        if periodic[k]:
            x -= box[k] * round(x / box[k])
        r[k] = x
        norm2 += x * x
    distance = math.sqrt(norm2)
    approach = 0.0
    for k in range(d):
        r[k] /= distance
        approach += (vel[i, k] - vel[j, k]) * r[k]
    # the contact distance grows at rate (r_i + r_j) * growth during compression
    surface_rate = (radius[i] + radius[j]) * growth
    effective = approach + surface_rate
    if effective <= 0.0:
        return
    e = restitution_for(i, j, approach, species, restitution, law, law_speed, law_exponent, elastic_below)
    mi = mass[i]
    mj = mass[j]
    reduced = mi * mj / (mi + mj)
    impulse = reduced * ((1.0 + e) * approach + 2.0 * surface_rate) if growth != 0.0 else reduced * (1.0 + e) * approach
    for k in range(d):
        vel[i, k] -= impulse / mi * r[k]
        vel[j, k] += impulse / mj * r[k]
    acc[ACC_VIRIAL] += impulse * distance
    acc[ACC_PAIR_COLLISIONS] += 1.0
    acc[ACC_ENERGY_LOST] += 0.5 * reduced * (1.0 - e * e) * approach * approach if growth == 0.0 else 0.0


@kernel
def cross_cell(i, code, pos, cell_of, ncell, box, image, head, next_in_cell, prev_in_cell):
    """Move particle i into the neighbouring cell across face ``code``."""
    axis = code // 2
    upward = code % 2 == 1
    cx, cy, cz = cell_coordinates(cell_of[i], ncell)
    cells = [cx, cy, cz]
    c = cells[axis] + (1 if upward else -1)
    if c >= ncell[axis]:
        c = 0
        pos[i, axis] -= box[axis]
        image[i, axis] += 1
    elif c < 0:
        c = ncell[axis] - 1
        pos[i, axis] += box[axis]
        image[i, axis] -= 1
    cells[axis] = c
    new_cell = cell_index(cells[0], cells[1], cells[2], ncell)
    cell_remove(i, cell_of[i], head, next_in_cell, prev_in_cell)
    cell_insert(i, new_cell, head, next_in_cell, prev_in_cell)
    cell_of[i] = new_cell


@kernel
def bounce_off_wall(i, code, vel, mass, wall_restitution, acc):
    axis = code // 2
    upward = code % 2 == 1
    v = vel[i, axis]
    if (upward and v > 0.0) or ((not upward) and v < 0.0):
        vel[i, axis] = -wall_restitution * v
        acc[ACC_WALL_IMPULSE] += mass[i] * (1.0 + wall_restitution) * abs(v)
        acc[ACC_WALL_COLLISIONS] += 1.0


@kernel
def run_events(
    t, max_pair_collisions, t_stop, pos, vel, tloc, mass, radius, species, image, counter,
    cell_of, head, next_in_cell, prev_in_cell, ncell, cell_size, box, periodic, gravity,
    scale0, growth, restitution, law, law_speed, law_exponent, elastic_below, wall_restitution,
    ev_time, ev_kind, ev_partner, ev_count, tree_index, tree_time, leaves, acc,
):
    """Process events until ``max_pair_collisions`` collisions or time ``t_stop``.

    Returns the current time: the last event's time, or ``t_stop`` if that
    came first (no particle is moved to it: call ``synchronise``).
    """
    done = 0
    while done < max_pair_collisions:
        i = tree_index[1]
        event_time = tree_time[1]
        if event_time > t_stop:
            return t_stop
        if event_time == math.inf:
            return t
        t = event_time
        kind = ev_kind[i]
        if kind == PAIR:
            j = ev_partner[i]
            if counter[j] != ev_count[i]:
                acc[ACC_STALE_EVENTS] += 1.0
                advance(i, t, pos, vel, tloc, gravity)
            else:
                advance(i, t, pos, vel, tloc, gravity)
                advance(j, t, pos, vel, tloc, gravity)
                collide_pair(
                    i, j, pos, vel, mass, radius, box, periodic, scale0 + growth * t, growth, species,
                    restitution, law, law_speed, law_exponent, elastic_below, acc,
                )
                counter[i] += 1
                counter[j] += 1
                done += 1
                predict(
                    j, t, pos, vel, tloc, radius, cell_of, head, next_in_cell, ncell, cell_size, box,
                    periodic, gravity, scale0, growth, counter, ev_time, ev_kind, ev_partner, ev_count,
                )
                tree_update(j, tree_index, tree_time, ev_time, leaves)
        elif kind == CELL:
            advance(i, t, pos, vel, tloc, gravity)
            cross_cell(i, ev_partner[i], pos, cell_of, ncell, box, image, head, next_in_cell, prev_in_cell)
            acc[ACC_CELL_CROSSINGS] += 1.0
        elif kind == WALL:
            advance(i, t, pos, vel, tloc, gravity)
            bounce_off_wall(i, ev_partner[i], vel, mass, wall_restitution, acc)
            counter[i] += 1
        predict(
            i, t, pos, vel, tloc, radius, cell_of, head, next_in_cell, ncell, cell_size, box,
            periodic, gravity, scale0, growth, counter, ev_time, ev_kind, ev_partner, ev_count,
        )
        tree_update(i, tree_index, tree_time, ev_time, leaves)
    return t


@kernel
def predict_all(
    t, pos, vel, tloc, radius, cell_of, head, next_in_cell, ncell, cell_size, box, periodic,
    gravity, scale0, growth, counter, ev_time, ev_kind, ev_partner, ev_count, tree_index, tree_time, leaves,
):
    n = pos.shape[0]
    for i in range(n):
        predict(
            i, t, pos, vel, tloc, radius, cell_of, head, next_in_cell, ncell, cell_size, box,
            periodic, gravity, scale0, growth, counter, ev_time, ev_kind, ev_partner, ev_count,
        )
    tree_build(tree_index, tree_time, ev_time, n, leaves)


@kernel
def synchronise(t, pos, vel, tloc, gravity):
    """Move every particle to time t."""
    for i in range(pos.shape[0]):
        advance(i, t, pos, vel, tloc, gravity)


@kernel
def min_gap(pos, radius, scale, cell_of, head, next_in_cell, ncell, box, periodic):
    """Smallest (distance - contact distance) over all pairs in neighbouring cells.

    Positions must be synchronised. Negative means an overlap.
    """
    d = pos.shape[1]
    worst = math.inf
    for i in range(pos.shape[0]):
        cx, cy, cz = cell_coordinates(cell_of[i], ncell)
        zrange = 1 if d == 3 else 0
        for oz in range(-zrange, zrange + 1):
            nz = cz + oz
            if d == 3 and (nz < 0 or nz >= ncell[2]):
                if not periodic[2]:
                    continue
                nz %= ncell[2]
            for oy in range(-1, 2):
                ny = cy + oy
                if ny < 0 or ny >= ncell[1]:
                    if not periodic[1]:
                        continue
                    ny %= ncell[1]
                for ox in range(-1, 2):
                    nx = cx + ox
                    if nx < 0 or nx >= ncell[0]:
                        if not periodic[0]:
                            continue
                        nx %= ncell[0]
                    j = head[cell_index(nx, ny, nz, ncell)]
                    while j >= 0:
                        if j > i:
                            norm2 = 0.0
                            for k in range(d):
                                x = pos[j, k] - pos[i, k]
                                if periodic[k]:
                                    x -= box[k] * round(x / box[k])
                                norm2 += x * x
                            gap = math.sqrt(norm2) - (radius[i] + radius[j]) * scale
                            worst = min(worst, gap)
                        j = next_in_cell[j]
    return worst


@kernel
def wall_gap(pos, radius, scale, box, periodic):
    """Smallest distance between a sphere's surface and a wall (negative: overlap)."""
    worst = math.inf
    for i in range(pos.shape[0]):
        for k in range(pos.shape[1]):
            if not periodic[k]:
                r = radius[i] * scale
                worst = min(worst, pos[i, k] - r, box[k] - r - pos[i, k])
    return worst
