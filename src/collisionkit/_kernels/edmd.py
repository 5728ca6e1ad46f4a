"""Numba kernels of the event-driven engine for hard spheres and discs.

Algorithm (Rapaport; Isobe, Int. J. Mod. Phys. C 10, 1281 (1999)):

* particles move ballistically (parabolas under uniform gravity) and are
  updated lazily: row ``p[i]`` holds position, velocity, the particle's own
  time and its radius (one 64-byte record, so a neighbour costs one cache
  line);
* a cell list with cells no smaller than the largest contact distance;
  every particle keeps its best predicted collision (with a particle in the
  3^d surrounding cells) and its next boundary event (leaving its cell or
  hitting a wall); its event is the earlier of the two. After a cell
  crossing only the newly adjacent cells are searched;
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

# columns of the particle records p (float64, N x 8)
X = 0  # position x, y, z (z = 0 in 2D)
V = 3  # velocity
T = 6  # the particle's own time
R = 7  # radius at scale 1

# columns of the integer records info (int64, N x 8)
CELL_OF = 0
NEXT = 1  # next particle in the same cell (-1: none)
PREV = 2
COUNTER = 3  # velocity changes so far (stale-event detection)
PARTNER = 4  # partner of the best predicted collision
PARTNER_COUNT = 5  # the partner's counter when predicted
BOUNDARY_CODE = 6  # 2 * axis + (1 upward, 0 downward)
BOUNDARY_KIND = 7  # CELL or WALL

# columns of the event times (float64, N x 3)
EVENT_TIME = 0
PAIR_TIME = 1
BOUNDARY_TIME = 2

# rows of the geometry array (float64, 4 x 3)
G_BOX = 0
G_CELL = 1
G_GRAVITY = 2
G_PERIODIC = 3  # 1.0 periodic, 0.0 walls

# entries of the parameter array (float64)
P_SCALE0 = 0  # radius scale at time 0
P_GROWTH = 1  # d scale / dt (compression)
P_LAW = 2
P_LAW_SPEED = 3
P_LAW_EXPONENT = 4
P_ELASTIC_BELOW = 5
P_WALL_RESTITUTION = 6
P_SIZE = 7

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
def advance(p, i, t, geom, dim):
    """Move particle i along its flight to time t (exact parabola)."""
    dt = t - p[i, T]
    if dt != 0.0:
        for k in range(dim):
            g = geom[G_GRAVITY, k]
            p[i, X + k] += (p[i, V + k] + 0.5 * g * dt) * dt
            p[i, V + k] += g * dt
        p[i, T] = t


@kernel
def cell_coordinates(cell, ncell):
    cx = cell % ncell[0]
    rest = cell // ncell[0]
    return cx, rest % ncell[1], rest // ncell[1]


@kernel
def cell_index(cx, cy, cz, ncell):
    return cx + ncell[0] * (cy + ncell[1] * cz)


@kernel
def tree_update(leaf, tree, time, leaves):
    """Give ``leaf`` a new event time and replay its matches up the tournament tree.

    ``tree[node] = (time, particle)`` of the winner below ``node`` (the
    particle index stored as a float, exact below 2^53), so both sit in one
    cache line with the sibling's; the climb stops where nothing changes.
    """
    node = leaves + leaf
    tree[node, 0] = time
    node >>= 1
    while node >= 1:
        left = 2 * node
        winner = left if tree[left, 0] <= tree[left + 1, 0] else left + 1
        if tree[node, 0] == tree[winner, 0] and tree[node, 1] == tree[winner, 1]:
            return
        tree[node, 0] = tree[winner, 0]
        tree[node, 1] = tree[winner, 1]
        node >>= 1


@kernel
def tree_build(tree, times, leaves):
    n = times.shape[0]
    for leaf in range(leaves):
        tree[leaves + leaf, 0] = times[leaf, EVENT_TIME] if leaf < n else math.inf
        tree[leaves + leaf, 1] = leaf
    for node in range(leaves - 1, 0, -1):
        left = 2 * node
        winner = left if tree[left, 0] <= tree[left + 1, 0] else left + 1
        tree[node, 0] = tree[winner, 0]
        tree[node, 1] = tree[winner, 1]


@kernel
def predict_boundary(p, i, info, times, ncell, geom, dim, scale, growth):
    """Next time particle i (at its own time) leaves its cell or hits a wall."""
    best = math.inf
    kind = NO_EVENT
    code = -1
    cx, cy, cz = cell_coordinates(info[i, CELL_OF], ncell)
    cells = (cx, cy, cz)
    r = p[i, R]
    for k in range(dim):
        c = cells[k]
        x = p[i, X + k]
        v = p[i, V + k]
        g = 0.5 * geom[G_GRAVITY, k]
        periodic = geom[G_PERIODIC, k] != 0.0
        width = geom[G_CELL, k]
        if periodic or c < ncell[k] - 1:
            tau = first_root_from_below(g, v, x - (c + 1) * width)
            this_kind = CELL
        else:
            tau = first_root_from_below(g, v + r * growth, x + r * scale - geom[G_BOX, k])
            this_kind = WALL
        if tau < best:
            best, kind, code = tau, this_kind, 2 * k + 1
        if periodic or c > 0:
            tau = first_root_from_below(-g, -v, c * width - x)
            this_kind = CELL
        else:
            tau = first_root_from_below(-g, -v + r * growth, r * scale - x)
            this_kind = WALL
        if tau < best:
            best, kind, code = tau, this_kind, 2 * k
    times[i, BOUNDARY_TIME] = p[i, T] + best
    info[i, BOUNDARY_KIND] = kind
    info[i, BOUNDARY_CODE] = code


@kernel
def _neighbour(c, offset, n, periodic, length):
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
def scan_pairs(p, i, t, info, head, ncell, geom, dim, scale, growth, best, fixed_axis, fixed_offset):
    """Earliest collision of particle i (at time t) with particles in nearby cells.

    Searches the 3^d cells around i's cell, or, with ``fixed_axis`` >= 0,
    only the layer at ``fixed_offset`` along that axis. Returns
    (time from t, partner), partner -1 if nothing beats ``best``.
    """
    partner = -1
    cx, cy, cz = cell_coordinates(info[i, CELL_OF], ncell)
    xi = p[i, X]
    yi = p[i, X + 1]
    zi = p[i, X + 2]
    vxi = p[i, V]
    vyi = p[i, V + 1]
    vzi = p[i, V + 2]
    ri = p[i, R]
    gx = 0.5 * geom[G_GRAVITY, 0]
    gy = 0.5 * geom[G_GRAVITY, 1]
    gz = 0.5 * geom[G_GRAVITY, 2]
    falling = gx != 0.0 or gy != 0.0 or gz != 0.0
    z_low, z_high = (-1, 1) if dim == 3 else (0, 0)
    y_low, y_high = -1, 1
    x_low, x_high = -1, 1
    if fixed_axis == 0:
        x_low = x_high = fixed_offset
    elif fixed_axis == 1:
        y_low = y_high = fixed_offset
    elif fixed_axis == 2:
        z_low = z_high = fixed_offset
    for oz in range(z_low, z_high + 1):
        nz, shift_z = _neighbour(cz, oz, ncell[2], geom[G_PERIODIC, 2] != 0.0, geom[G_BOX, 2])
        if nz < 0:
            continue
        for oy in range(y_low, y_high + 1):
            ny, shift_y = _neighbour(cy, oy, ncell[1], geom[G_PERIODIC, 1] != 0.0, geom[G_BOX, 1])
            if ny < 0:
                continue
            for ox in range(x_low, x_high + 1):
                nx, shift_x = _neighbour(cx, ox, ncell[0], geom[G_PERIODIC, 0] != 0.0, geom[G_BOX, 0])
                if nx < 0:
                    continue
                j = head[cell_index(nx, ny, nz, ncell)]
                while j >= 0:
                    dt = t - p[j, T]
                    rx = p[j, X] + p[j, V] * dt + shift_x - xi
                    ry = p[j, X + 1] + p[j, V + 1] * dt + shift_y - yi
                    rz = p[j, X + 2] + p[j, V + 2] * dt + shift_z - zi
                    ux = p[j, V] - vxi
                    uy = p[j, V + 1] - vyi
                    uz = p[j, V + 2] - vzi
                    if falling:
                        # the relative velocity is unchanged by gravity (both fall alike)
                        rx += gx * dt * dt
                        ry += gy * dt * dt
                        rz += gz * dt * dt
                        ux += 2.0 * gx * dt
                        uy += 2.0 * gy * dt
                        uz += 2.0 * gz * dt
                    contact = ri + p[j, R]
                    if growth == 0.0:
                        # cheap filter first: approaching, and able to touch before ``best``
                        ru = rx * ux + ry * uy + rz * uz
                        sigma = contact * scale
                        c = rx * rx + ry * ry + rz * rz - sigma * sigma
                        if ru < 0.0 and c < -2.0 * ru * best and j != i:
                            # most approaching pairs pass by: discriminant < 0 (a miss by less
                            # than round-off of sigma changes nothing: it would not touch)
                            uu = ux * ux + uy * uy + uz * uz
                            if ru * ru >= uu * c or c <= 0.0:
                                tau = pair_contact_time(rx, ry, rz, ux, uy, uz, contact, scale, 0.0, best)
                                if tau < best:
                                    best = tau
                                    partner = j
                    elif j != i:
                        tau = pair_contact_time(rx, ry, rz, ux, uy, uz, contact, scale, growth, best)
                        if tau < best:
                            best = tau
                            partner = j
                    j = info[j, NEXT]
    return best, partner


@kernel
def predict_pairs(p, i, info, times, head, ncell, geom, dim, scale0, growth):
    """Best collision of particle i (at its own time) over all nearby cells."""
    t = p[i, T]
    tau, partner = scan_pairs(p, i, t, info, head, ncell, geom, dim, scale0 + growth * t, growth, math.inf, -1, 0)
    times[i, PAIR_TIME] = t + tau
    info[i, PARTNER] = partner
    info[i, PARTNER_COUNT] = info[partner, COUNTER] if partner >= 0 else 0


@kernel
def schedule(i, info, times, tree, leaves):
    """Make i's event the earlier of its collision and its boundary event."""
    time = min(times[i, PAIR_TIME], times[i, BOUNDARY_TIME])
    times[i, EVENT_TIME] = time
    tree_update(i, tree, time, leaves)


@kernel
def cell_remove(i, cell, head, info):
    before = info[i, PREV]
    after = info[i, NEXT]
    if before >= 0:
        info[before, NEXT] = after
    else:
        head[cell] = after
    if after >= 0:
        info[after, PREV] = before


@kernel
def cell_insert(i, cell, head, info):
    first = head[cell]
    info[i, NEXT] = first
    info[i, PREV] = -1
    if first >= 0:
        info[first, PREV] = i
    head[cell] = i
    info[i, CELL_OF] = cell


@kernel
def build_cells(p, ncell, geom, dim, info, head):
    head[:] = -1
    for i in range(p.shape[0]):
        c0 = c1 = c2 = 0
        for k in range(dim):
            c = int(math.floor(p[i, X + k] / geom[G_CELL, k]))
            c = min(max(c, 0), ncell[k] - 1)
            if k == 0:
                c0 = c
            elif k == 1:
                c1 = c
            else:
                c2 = c
        cell_insert(i, cell_index(c0, c1, c2, ncell), head, info)


@kernel
def restitution_for(i, j, approach, species, restitution, params):
    """Coefficient of normal restitution of one contact."""
    if approach < params[P_ELASTIC_BELOW]:
        return 1.0
    e = restitution[species[i], species[j]]
    speed = params[P_LAW_SPEED]
    if params[P_LAW] == LAW_BRIDGES and approach > speed:
        e = min(e, (approach / speed) ** (-params[P_LAW_EXPONENT]))
    return e


@kernel
def collide_pair(p, i, j, mass, geom, dim, scale, growth, species, restitution, params, acc):
    """Resolve the contact of i and j (both at the current time)."""
    rx = 0.0
    ry = 0.0
    rz = 0.0
    for k in range(dim):
        x = p[j, X + k] - p[i, X + k]
        if geom[G_PERIODIC, k] != 0.0:
            length = geom[G_BOX, k]
            x -= length * round(x / length)
        if k == 0:
            rx = x
        elif k == 1:
            ry = x
        else:
            rz = x
    distance = math.sqrt(rx * rx + ry * ry + rz * rz)
    nx = rx / distance
    ny = ry / distance
    nz = rz / distance
    approach = (p[i, V] - p[j, V]) * nx + (p[i, V + 1] - p[j, V + 1]) * ny + (p[i, V + 2] - p[j, V + 2]) * nz
    # while compressing, the contact distance grows at (r_i + r_j) * growth
    surface_rate = (p[i, R] + p[j, R]) * growth
    if approach + surface_rate <= 0.0:
        return
    mi = mass[i]
    mj = mass[j]
    reduced = mi * mj / (mi + mj)
    if growth != 0.0:
        impulse = reduced * 2.0 * (approach + surface_rate)
    else:
        e = restitution_for(i, j, approach, species, restitution, params)
        impulse = reduced * (1.0 + e) * approach
        acc[ACC_ENERGY_LOST] += 0.5 * reduced * (1.0 - e * e) * approach * approach
    p[i, V] -= impulse / mi * nx
    p[i, V + 1] -= impulse / mi * ny
    p[i, V + 2] -= impulse / mi * nz
    p[j, V] += impulse / mj * nx
    p[j, V + 1] += impulse / mj * ny
    p[j, V + 2] += impulse / mj * nz
    acc[ACC_VIRIAL] += impulse * distance
    acc[ACC_PAIR_COLLISIONS] += 1.0


@kernel
def cross_cell(p, i, code, info, head, ncell, geom, image):
    """Move particle i into the neighbouring cell across face ``code``."""
    axis = code // 2
    step = 1 if code % 2 == 1 else -1
    cx, cy, cz = cell_coordinates(info[i, CELL_OF], ncell)
    c = (cx, cy, cz)[axis] + step
    if c >= ncell[axis]:
        c = 0
        p[i, X + axis] -= geom[G_BOX, axis]
        image[i, axis] += 1
    elif c < 0:
        c = ncell[axis] - 1
        p[i, X + axis] += geom[G_BOX, axis]
        image[i, axis] -= 1
    if axis == 0:
        cx = c
    elif axis == 1:
        cy = c
    else:
        cz = c
    cell_remove(i, info[i, CELL_OF], head, info)
    cell_insert(i, cell_index(cx, cy, cz, ncell), head, info)
    return axis, step


@kernel
def bounce_off_wall(p, i, code, mass, params, acc):
    axis = code // 2
    upward = code % 2 == 1
    v = p[i, V + axis]
    if (upward and v > 0.0) or ((not upward) and v < 0.0):
        e = params[P_WALL_RESTITUTION]
        p[i, V + axis] = -e * v
        acc[ACC_WALL_IMPULSE] += mass[i] * (1.0 + e) * abs(v)
        acc[ACC_WALL_COLLISIONS] += 1.0


@kernel
def _repredict(p, i, info, times, head, ncell, geom, dim, params, tree, leaves):
    """Full prediction of i (at its own time): pairs, boundary, schedule."""
    scale0 = params[P_SCALE0]
    growth = params[P_GROWTH]
    predict_pairs(p, i, info, times, head, ncell, geom, dim, scale0, growth)
    predict_boundary(p, i, info, times, ncell, geom, dim, scale0 + growth * p[i, T], growth)
    schedule(i, info, times, tree, leaves)


@kernel
def _after_crossing(p, i, axis, step, info, times, head, ncell, geom, dim, params):
    """Update i's collision after it entered a new cell: search the new layer only,
    unless its stored collision went stale (then search everything)."""
    t = p[i, T]
    scale0 = params[P_SCALE0]
    growth = params[P_GROWTH]
    partner = info[i, PARTNER]
    if partner >= 0 and info[partner, COUNTER] != info[i, PARTNER_COUNT]:
        predict_pairs(p, i, info, times, head, ncell, geom, dim, scale0, growth)
        return
    best = times[i, PAIR_TIME] - t
    tau, found = scan_pairs(p, i, t, info, head, ncell, geom, dim, scale0 + growth * t, growth, best, axis, step)
    if found >= 0:
        times[i, PAIR_TIME] = t + tau
        info[i, PARTNER] = found
        info[i, PARTNER_COUNT] = info[found, COUNTER]


@kernel
def run_events(t, max_pair_collisions, t_stop, p, mass, species, image, info, times, head, ncell, geom, dim,
               restitution, params, tree, leaves, acc):
    """Process events until ``max_pair_collisions`` collisions or time ``t_stop``.

    Returns the current time: the last event's time, or ``t_stop`` if that
    came first (particles are not moved to it: call ``synchronise``).
    """
    done = 0
    scale0 = params[P_SCALE0]
    growth = params[P_GROWTH]
    while done < max_pair_collisions:
        event_time = tree[1, 0]
        i = int(tree[1, 1])
        if event_time > t_stop:
            return t_stop
        if event_time == math.inf:
            return t
        t = event_time
        advance(p, i, t, geom, dim)
        if times[i, PAIR_TIME] <= times[i, BOUNDARY_TIME]:
            j = info[i, PARTNER]
            if info[j, COUNTER] != info[i, PARTNER_COUNT]:
                acc[ACC_STALE_EVENTS] += 1.0
                predict_pairs(p, i, info, times, head, ncell, geom, dim, scale0, growth)
                schedule(i, info, times, tree, leaves)
                continue
            advance(p, j, t, geom, dim)
            collide_pair(p, i, j, mass, geom, dim, scale0 + growth * t, growth, species, restitution, params, acc)
            info[i, COUNTER] += 1
            info[j, COUNTER] += 1
            done += 1
            _repredict(p, j, info, times, head, ncell, geom, dim, params, tree, leaves)
            _repredict(p, i, info, times, head, ncell, geom, dim, params, tree, leaves)
        elif info[i, BOUNDARY_KIND] == CELL:
            axis, step = cross_cell(p, i, info[i, BOUNDARY_CODE], info, head, ncell, geom, image)
            acc[ACC_CELL_CROSSINGS] += 1.0
            predict_boundary(p, i, info, times, ncell, geom, dim, scale0 + growth * t, growth)
            _after_crossing(p, i, axis, step, info, times, head, ncell, geom, dim, params)
            schedule(i, info, times, tree, leaves)
        else:
            bounce_off_wall(p, i, info[i, BOUNDARY_CODE], mass, params, acc)
            info[i, COUNTER] += 1
            _repredict(p, i, info, times, head, ncell, geom, dim, params, tree, leaves)
    return t


@kernel
def predict_all(p, info, times, head, ncell, geom, dim, params, tree, leaves):
    """Predict every particle's events (all at their own times) and rebuild the tree."""
    scale0 = params[P_SCALE0]
    growth = params[P_GROWTH]
    for i in range(p.shape[0]):
        predict_pairs(p, i, info, times, head, ncell, geom, dim, scale0, growth)
        predict_boundary(p, i, info, times, ncell, geom, dim, scale0 + growth * p[i, T], growth)
        times[i, EVENT_TIME] = min(times[i, PAIR_TIME], times[i, BOUNDARY_TIME])
    tree_build(tree, times, leaves)


@kernel
def synchronise(p, t, geom, dim):
    """Move every particle to time t."""
    for i in range(p.shape[0]):
        advance(p, i, t, geom, dim)


@kernel
def min_gap(p, scale, info, head, ncell, geom, dim):
    """Smallest (distance - contact distance) over pairs in neighbouring cells.

    Particles must be synchronised. Negative means an overlap.
    """
    worst = math.inf
    for i in range(p.shape[0]):
        cx, cy, cz = cell_coordinates(info[i, CELL_OF], ncell)
        for oz in range(-1 if dim == 3 else 0, 2 if dim == 3 else 1):
            nz, _ = _neighbour(cz, oz, ncell[2], geom[G_PERIODIC, 2] != 0.0, 0.0)
            if nz < 0:
                continue
            for oy in range(-1, 2):
                ny, _ = _neighbour(cy, oy, ncell[1], geom[G_PERIODIC, 1] != 0.0, 0.0)
                if ny < 0:
                    continue
                for ox in range(-1, 2):
                    nx, _ = _neighbour(cx, ox, ncell[0], geom[G_PERIODIC, 0] != 0.0, 0.0)
                    if nx < 0:
                        continue
                    j = head[cell_index(nx, ny, nz, ncell)]
                    while j >= 0:
                        if j > i:
                            norm2 = 0.0
                            for k in range(dim):
                                x = p[j, X + k] - p[i, X + k]
                                if geom[G_PERIODIC, k] != 0.0:
                                    x -= geom[G_BOX, k] * round(x / geom[G_BOX, k])
                                norm2 += x * x
                            worst = min(worst, math.sqrt(norm2) - (p[i, R] + p[j, R]) * scale)
                        j = info[j, NEXT]
    return worst


@kernel
def wall_gap(p, scale, geom, dim):
    """Smallest distance between a surface and a wall (negative: overlap)."""
    worst = math.inf
    for i in range(p.shape[0]):
        for k in range(dim):
            if geom[G_PERIODIC, k] == 0.0:
                r = p[i, R] * scale
                worst = min(worst, p[i, X + k] - r, geom[G_BOX, k] - r - p[i, X + k])
    return worst
