"""Numba kernels of the event-driven engine for hard spheres and discs.

Algorithm (Rapaport; Isobe, Int. J. Mod. Phys. C 10, 1281 (1999); neighbour
lists after Donev, Torquato & Stillinger, J. Comput. Phys. 202, 737 (2005),
as used for speed by Smallenburg, arXiv:2201.01100):

* particles move ballistically (parabolas under uniform gravity) and are
  updated lazily: row ``p[i]`` holds position, velocity, the particle's own
  time and its radius (one 64-byte record, so a neighbour costs one cache
  line);
* every particle carries a neighbour list: the particles whose *anchors*
  (positions when their lists were last built) lie within
  ``(r_i + r_j) * list_scale + shell``. A particle's list is rebuilt (a list
  event) when it has moved ``shell / 2`` from its anchor, so two particles
  that are not neighbours cannot touch before one of them rebuilds. Lists are
  symmetric: a rebuild removes the particle from its old neighbours' lists
  and adds it to its new ones'. A cell list of the anchors (cells no smaller
  than the list radius, each a contiguous block of slots holding the anchors
  and radii, so a scan streams memory instead of chasing pointers) finds the
  new neighbours;
* every particle keeps its best predicted collision (over its list) and its
  next boundary event (list expiry or a wall); its event is the earlier;
* the particles' event times sit in blocks of 8 (one cache line); a
  complete binary tree over the blocks' earliest events gives the next event
  in O(1) and updates in O(log N). The tree is 16 times smaller than one over
  the particles, small enough to stay in the core's cache, and most updates
  end at the block (a particle that is not its block's first stays behind
  it);
* events are numbered; an event with partner j is stale if j has changed
  velocity since it was predicted (j's CHANGED_AT is later than i's
  PREDICTED_AT). Unlike per-particle counters, this needs no read of the
  partner's record when predicting, one memory round trip fewer. Stale
  events are re-predicted;
* what an event needs of a particle sits in two 64-byte records: ``p``
  (position, velocity, own time, radius: all a neighbour's prediction
  reads) and ``b`` (next event, event numbers, anchor, mass, species), so
  an event touches few cache lines: memory latency, not arithmetic, bounds
  the engine once the particles outgrow the caches.

Positions are not wrapped into a periodic box at every crossing, only when a
particle rebuilds its list, so they may lie up to ``shell / 2`` outside
[0, L); separations use the minimum image, valid because every periodic box
length exceeds twice the largest list radius.

Growing particles (Lubachevsky-Stillinger compression) use radii
``radius * (scale0 + growth * t)``; lists cover radii up to ``list_scale``
and the caller stops the run when the scale reaches it. With growth 0 the
contact quadratic is the one of :mod:`collisionkit._kernels.collisions`.
"""

from __future__ import annotations

import math

# no EDMD kernel allocates or returns an array: all of them borrow, without reference counting
from .._jit import borrowing_inline_kernel as inline_kernel
from .._jit import borrowing_kernel as kernel
from ._memory import prefetch, prefetch_at

# columns of the particle records p (float64, N x 8)
X = 0  # position x, y, z (z = 0 in 2D)
V = 3  # velocity
T = 6  # the particle's own time
R = 7  # radius at scale 1

# columns of the bookkeeping records b (float64, N x 8: one 64-byte cache line a particle, so an
# event reads and writes one line besides p; integers are stored as floats, exact below 2^53)
TARGET = 0  # the particle's next event: a collision with partner TARGET (>= 0), else LIST_TARGET or wall_target(face)
PREDICTED_AT = 1  # number of the event at which that event was predicted
CHANGED_AT = 2  # number of the event that last changed the velocity
ANCHOR = 3  # anchor x, y, z: the position where the neighbour list was last built
MASS = 6
SPECIES = 7

LIST_TARGET = -1  # next event: the particle moved shell / 2 from its anchor, rebuild its list

# particles per block of the event queue: their event times fill one 64-byte cache line
QUEUE_BLOCK = 8

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
P_SHELL = 7  # neighbour-list shell (skin) width
P_LIST_SCALE = 8  # largest radius scale the lists are valid for
P_SIZE = 9

# accumulator slots (acc array)
ACC_VIRIAL = 0  # sum over pair collisions of impulse * contact distance
ACC_PAIR_COLLISIONS = 1
ACC_WALL_COLLISIONS = 2
ACC_LIST_REBUILDS = 3
ACC_STALE_EVENTS = 4
ACC_ENERGY_LOST = 5
ACC_WALL_IMPULSE = 6  # sum of |momentum| transferred to walls
ACC_LIST_OVERFLOW = 7  # > 0: a neighbour list outgrew its row; the run stopped to grow the rows
ACC_EVENTS = 8  # events processed (pair, stale, list, wall): numbers them for stale detection
ACC_CELL_OVERFLOW = 9  # > 0: a cell outgrew its slots; the run stopped to grow them
ACC_SIZE = 10

# float32 anchor-and-radius slots of a cell in one 64-byte cache line
CELL_SLOTS_PER_LINE = 4

# relative round-off bound of the float32 anchors in the cell lists (8 float32 ulps), times the box size
ANCHOR_ROUNDING = 2.0**-21

# lowest levels of a block's path up the event tree to prefetch (the upper ones stay cached)
TREE_LEVELS_PREFETCHED = 6

@kernel
def wall_target(face):
    """TARGET code of a collision with wall ``face`` (2 * axis + 1 upper, 2 * axis lower); its own inverse."""
    return -2 - face


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


@inline_kernel
def advance(p, i, t, geom, dim):
    """Move particle i along its flight to time t (exact parabola)."""
    dt = t - p[i, T]
    if dt != 0.0:
        for k in range(dim):
            g = geom[G_GRAVITY, k]
            p[i, X + k] += (p[i, V + k] + 0.5 * g * dt) * dt
            p[i, V + k] += g * dt
        p[i, T] = t


@inline_kernel
def cell_coordinates(cell, ncell):
    cx = cell % ncell[0]
    rest = cell // ncell[0]
    return cx, rest % ncell[1], rest // ncell[1]


@inline_kernel
def cell_index(cx, cy, cz, ncell):
    return cx + ncell[0] * (cy + ncell[1] * cz)


@inline_kernel
def tree_update(leaf, tree, time, winner, leaves):
    """Give ``leaf`` (a block) a new earliest event and replay its matches up the tournament tree.

    ``tree[node] = (time, particle)`` of the winner below ``node`` (the
    particle index stored as a float, exact below 2^53), so both sit in one
    cache line with the sibling's; the climb stops where nothing changes.
    The winner so far rides up in registers and meets one sibling per level
    (the left one wins ties).
    """
    node = leaves + leaf
    tree[node, 0] = time
    tree[node, 1] = winner
    best_time = time
    best_id = winner
    while node > 1:
        # loads first, then selects (cmov): which side wins is a coin toss, a poor bet for a branch
        sibling_time = tree[node ^ 1, 0]
        sibling_id = tree[node ^ 1, 1]
        sibling_wins = (sibling_time < best_time) | ((sibling_time == best_time) & (node & 1 == 1))
        best_id = sibling_id if sibling_wins else best_id
        best_time = min(sibling_time, best_time)
        node >>= 1
        if tree[node, 0] == best_time and tree[node, 1] == best_id:
            return
        tree[node, 0] = best_time
        tree[node, 1] = best_id


@inline_kernel
def _block_first(block, queue):
    """Earliest event of a block of the queue: (time, particle); the lowest index wins ties."""
    first = block * QUEUE_BLOCK
    best_time = queue[first]
    best = first
    for k in range(first + 1, first + QUEUE_BLOCK):
        earlier = queue[k] < best_time
        best = k if earlier else best
        best_time = queue[k] if earlier else best_time
    return best_time, best


@inline_kernel
def queue_update(i, time, queue, tree, leaves):
    """Give particle i the event time ``time`` in the queue.

    The block's entry in the tree changes only if i was its first particle
    or now comes first; otherwise the update ends here, without a scan.
    """
    queue[i] = time
    block = i // QUEUE_BLOCK
    node = leaves + block
    block_time = tree[node, 0]
    block_first = int(tree[node, 1])
    if block_first != i:
        if time > block_time or (time == block_time and i > block_first):
            return
        tree_update(block, tree, time, float(i), leaves)
        return
    if time <= block_time:
        tree_update(block, tree, time, float(i), leaves)
        return
    best_time, best = _block_first(block, queue)
    tree_update(block, tree, best_time, float(best), leaves)


@kernel
def tree_build(tree, queue, leaves):
    """Fill the tree over the queue's blocks (queue padded with inf to whole blocks)."""
    blocks = queue.shape[0] // QUEUE_BLOCK
    for leaf in range(leaves):
        if leaf < blocks:
            best_time, best = _block_first(leaf, queue)
        else:
            best_time, best = math.inf, leaf * QUEUE_BLOCK
        tree[leaves + leaf, 0] = best_time
        tree[leaves + leaf, 1] = best
    for node in range(leaves - 1, 0, -1):
        left = 2 * node
        winner = left if tree[left, 0] <= tree[left + 1, 0] else left + 1
        tree[node, 0] = tree[winner, 0]
        tree[node, 1] = tree[winner, 1]


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
def restitution_for(i, j, approach, b, restitution, params):
    """Coefficient of normal restitution of one contact."""
    if approach < params[P_ELASTIC_BELOW]:
        return 1.0
    e = restitution[int(b[i, SPECIES]), int(b[j, SPECIES])]
    speed = params[P_LAW_SPEED]
    if params[P_LAW] == LAW_BRIDGES and approach > speed:
        e = min(e, (approach / speed) ** (-params[P_LAW_EXPONENT]))
    return e


@inline_kernel
def collide_pair(p, i, j, b, geom, dim, scale, growth, restitution, params, acc):
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
    mi = b[i, MASS]
    mj = b[j, MASS]
    reduced = mi * mj / (mi + mj)
    if growth != 0.0:
        impulse = reduced * 2.0 * (approach + surface_rate)
    else:
        e = restitution_for(i, j, approach, b, restitution, params)
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


@inline_kernel
def bounce_off_wall(p, i, code, b, params, acc):
    axis = code // 2
    upward = code % 2 == 1
    v = p[i, V + axis]
    if (upward and v > 0.0) or ((not upward) and v < 0.0):
        e = params[P_WALL_RESTITUTION]
        p[i, V + axis] = -e * v
        acc[ACC_WALL_IMPULSE] += b[i, MASS] * (1.0 + e) * abs(v)
        acc[ACC_WALL_COLLISIONS] += 1.0


@kernel
def minimum_image(dx, length, half):
    """Shortest periodic image of a separation no longer than 1.5 box lengths (half = inf: walls)."""
    if dx > half:
        return dx - length
    if dx < -half:
        return dx + length
    return dx


@inline_kernel
def _half_box(geom, k):
    return 0.5 * geom[G_BOX, k] if geom[G_PERIODIC, k] != 0.0 else math.inf


@inline_kernel
def _first_contact_ballistic(p, i, neighbours, neighbour_count, geom, scale, horizon):
    """Earliest contact of i (at its own time) with its list before ``horizon``: fixed radii, straight flights.

    Returns (time from i's time, partner), or (inf, -1) if no contact comes
    before ``horizon``. The root of |r + u tau| = sigma is
    tau = c / (-b + sqrt(D)) with b = r.u, c = |r|^2 - sigma^2 and
    D = sigma^2 |u|^2 - |r x u|^2 (= b^2 - |u|^2 c by Lagrange's identity,
    without its cancellation), taken when the pair approaches (b < 0) and
    D >= 0; an overlap by round-off (c <= 0) while approaching collides at
    once. Since sqrt(D) <= -b when c >= 0, tau >= c / (-2 b): one cheap
    test, c < -2 b best, rejects the receding pairs and those that cannot
    beat the best so far before the square root and the division. It rarely
    passes, so its branch is well predicted; a branch on b < 0 alone would
    be a coin toss, and a mispredicted branch costs more than the
    arithmetic it saves.
    """
    t = p[i, T]
    xi, yi, zi = p[i, X], p[i, X + 1], p[i, X + 2]
    vxi, vyi, vzi = p[i, V], p[i, V + 1], p[i, V + 2]
    ri = p[i, R]
    lx, ly, lz = geom[G_BOX, 0], geom[G_BOX, 1], geom[G_BOX, 2]
    hx, hy, hz = _half_box(geom, 0), _half_box(geom, 1), _half_box(geom, 2)
    best = horizon
    partner = -1
    for m in range(neighbour_count[i]):
        j = neighbours[i, m]
        dt = t - p[j, T]
        rx = minimum_image(p[j, X] + p[j, V] * dt - xi, lx, hx)
        ry = minimum_image(p[j, X + 1] + p[j, V + 1] * dt - yi, ly, hy)
        rz = minimum_image(p[j, X + 2] + p[j, V + 2] * dt - zi, lz, hz)
        ux = p[j, V] - vxi
        uy = p[j, V + 1] - vyi
        uz = p[j, V + 2] - vzi
        sigma = (ri + p[j, R]) * scale
        b = rx * ux + ry * uy + rz * uz
        c = rx * rx + ry * ry + rz * rz - sigma * sigma
        # b < 0 and c + 2 b best < 0 in one comparison, so one (rarely taken, well predicted) branch
        if max(b, c + 2.0 * b * best) < 0.0:
            cx = ry * uz - rz * uy
            cy = rz * ux - rx * uz
            cz = rx * uy - ry * ux
            discriminant = sigma * sigma * (ux * ux + uy * uy + uz * uz) - (cx * cx + cy * cy + cz * cz)
            if discriminant >= 0.0 or c <= 0.0:
                tau = max(c, 0.0) / (math.sqrt(max(discriminant, 0.0)) - b)
                if tau < best:
                    best = tau
                    partner = j
    if partner < 0:
        return math.inf, -1
    return best, partner


@inline_kernel
def predict_pairs(p, i, neighbours, neighbour_count, geom, scale0, growth, horizon):
    """Earliest collision of particle i (at its own time) with its list within ``horizon``.

    Returns (time from i's time, partner), or (inf, -1) if none comes
    before ``horizon``, i's boundary event: a later collision would be
    re-predicted at that event anyway.
    """
    t = p[i, T]
    scale = scale0 + growth * t
    xi = p[i, X]
    yi = p[i, X + 1]
    zi = p[i, X + 2]
    vxi = p[i, V]
    vyi = p[i, V + 1]
    vzi = p[i, V + 2]
    ri = p[i, R]
    lx, ly, lz = geom[G_BOX, 0], geom[G_BOX, 1], geom[G_BOX, 2]
    hx, hy, hz = _half_box(geom, 0), _half_box(geom, 1), _half_box(geom, 2)
    gx = 0.5 * geom[G_GRAVITY, 0]
    gy = 0.5 * geom[G_GRAVITY, 1]
    gz = 0.5 * geom[G_GRAVITY, 2]
    falling = gx != 0.0 or gy != 0.0 or gz != 0.0
    if growth == 0.0 and not falling:
        return _first_contact_ballistic(p, i, neighbours, neighbour_count, geom, scale, horizon)
    best = horizon
    partner = -1
    for m in range(neighbour_count[i]):
        j = neighbours[i, m]
        dt = t - p[j, T]
        rx = minimum_image(p[j, X] + p[j, V] * dt - xi, lx, hx)
        ry = minimum_image(p[j, X + 1] + p[j, V + 1] * dt - yi, ly, hy)
        rz = minimum_image(p[j, X + 2] + p[j, V + 2] * dt - zi, lz, hz)
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
            if ru < 0.0 and c < -2.0 * ru * best:
                # most approaching pairs pass by: discriminant < 0 (a miss by less
                # than round-off of sigma changes nothing: it would not touch)
                uu = ux * ux + uy * uy + uz * uz
                if ru * ru >= uu * c or c <= 0.0:
                    tau = pair_contact_time(rx, ry, rz, ux, uy, uz, contact, scale, 0.0, best)
                    if tau < best:
                        best = tau
                        partner = j
        else:
            tau = pair_contact_time(rx, ry, rz, ux, uy, uz, contact, scale, growth, best)
            if tau < best:
                best = tau
                partner = j
    if partner < 0:
        return math.inf, -1
    return best, partner


@inline_kernel
def list_expiry(p, i, b, geom, dim, reach):
    """Time (from i's own time) until particle i is ``reach`` away from its anchor.

    Without gravity the distance is measured in full (a quadratic); under
    gravity each axis is held within reach / sqrt(d), which keeps the
    distance within reach and leaves one quadratic per axis and direction.
    """
    falling = geom[G_GRAVITY, 0] != 0.0 or geom[G_GRAVITY, 1] != 0.0 or geom[G_GRAVITY, 2] != 0.0
    if not falling:
        quadratic = 0.0
        linear = 0.0
        constant = -reach * reach
        for k in range(dim):
            d = p[i, X + k] - b[i, ANCHOR + k]
            v = p[i, V + k]
            quadratic += v * v
            linear += 2.0 * d * v
            constant += d * d
        return first_root_from_below(quadratic, linear, constant)
    side = reach / math.sqrt(dim)
    best = math.inf
    for k in range(dim):
        d = p[i, X + k] - b[i, ANCHOR + k]
        v = p[i, V + k]
        g = 0.5 * geom[G_GRAVITY, k]
        best = min(best, first_root_from_below(g, v, d - side), first_root_from_below(-g, -v, -d - side))
    return best


@inline_kernel
def predict_boundary(p, i, b, geom, dim, params):
    """When particle i (at its own time) must next rebuild its list or hits a wall.

    Returns (time from i's time, target: LIST_TARGET or the wall's target).
    """
    growth = params[P_GROWTH]
    scale = params[P_SCALE0] + growth * p[i, T]
    best = list_expiry(p, i, b, geom, dim, 0.5 * params[P_SHELL])
    target = LIST_TARGET
    r = p[i, R]
    for k in range(dim):
        if geom[G_PERIODIC, k] != 0.0:
            continue
        x = p[i, X + k]
        v = p[i, V + k]
        g = 0.5 * geom[G_GRAVITY, k]
        tau = first_root_from_below(g, v + r * growth, x + r * scale - geom[G_BOX, k])
        if tau < best:
            best, target = tau, wall_target(2 * k + 1)
        tau = first_root_from_below(-g, -v + r * growth, r * scale - x)
        if tau < best:
            best, target = tau, wall_target(2 * k)
    return best, target


@inline_kernel
def predict(p, i, b, neighbours, neighbour_count, geom, dim, params, event):
    """Predict particle i's next event (i at its own time): its boundary event, then the collisions before it.

    Records the event's target in ``b`` and returns its absolute time.
    """
    boundary, target = predict_boundary(p, i, b, geom, dim, params)
    pair, partner = predict_pairs(p, i, neighbours, neighbour_count, geom, params[P_SCALE0], params[P_GROWTH],
                                  boundary)
    b[i, PREDICTED_AT] = event
    if partner >= 0:
        b[i, TARGET] = partner
        return p[i, T] + pair
    b[i, TARGET] = target
    return p[i, T] + boundary


@inline_kernel
def wrap_into_box(p, i, geom, dim, image):
    """Bring particle i back into [0, L) on periodic axes (it is at most a box length out)."""
    for k in range(dim):
        if geom[G_PERIODIC, k] != 0.0:
            length = geom[G_BOX, k]
            if p[i, X + k] >= length:
                p[i, X + k] -= length
                image[i, k] += 1
            elif p[i, X + k] < 0.0:
                p[i, X + k] += length
                image[i, k] -= 1
                if p[i, X + k] >= length:  # -tiny + L rounds to L
                    p[i, X + k] = 0.0


@inline_kernel
def cell_of_position(p, i, ncell, geom, dim):
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
    return cell_index(c0, c1, c2, ncell)


@kernel
def _offsets(n, periodic):
    """Cell offsets to visit along one axis: each neighbouring cell once, also when n < 3."""
    if periodic and n < 3:
        return 0, n - 1
    return -1, 1


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
    zl, zh = _offsets(ncell[2], geom[G_PERIODIC, 2] != 0.0) if dim == 3 else (0, 0)
    yl, yh = _offsets(ncell[1], geom[G_PERIODIC, 1] != 0.0)
    xl, xh = _offsets(ncell[0], geom[G_PERIODIC, 0] != 0.0)
    lx, ly, lz = geom[G_BOX, 0], geom[G_BOX, 1], geom[G_BOX, 2]
    hx, hy, hz = _half_box(geom, 0), _half_box(geom, 1), _half_box(geom, 2)
    ax, ay, az = b[i, ANCHOR], b[i, ANCHOR + 1], b[i, ANCHOR + 2]
    # anchors are stored in float32 in the cells: widen the test by their round-off
    slack = ANCHOR_ROUNDING * (max(lx, ly, lz) + 1.0)
    reach_i = p[i, R] * params[P_LIST_SCALE] + params[P_SHELL] + slack
    list_scale = params[P_LIST_SCALE]
    for oz in range(zl, zh + 1):
        nz, _ = _neighbour(cz, oz, ncell[2], geom[G_PERIODIC, 2] != 0.0, 0.0)
        if nz < 0:
            continue
        for oy in range(yl, yh + 1):
            ny, _ = _neighbour(cy, oy, ncell[1], geom[G_PERIODIC, 1] != 0.0, 0.0)
            if ny < 0:
                continue
            for ox in range(xl, xh + 1):
                nx, _ = _neighbour(cx, ox, ncell[0], geom[G_PERIODIC, 0] != 0.0, 0.0)
                if nx < 0:
                    continue
                cell = cell_index(nx, ny, nz, ncell)
                for slot in range(cell_count[cell]):
                    dx = minimum_image(cell_points[cell, slot, 0] - ax, lx, hx)
                    dy = minimum_image(cell_points[cell, slot, 1] - ay, ly, hy)
                    dz = minimum_image(cell_points[cell, slot, 2] - az, lz, hz)
                    reach = reach_i + cell_points[cell, slot, 3] * list_scale
                    if dx * dx + dy * dy + dz * dz <= reach * reach:
                        j = cell_members[cell, slot]
                        if j == i:
                            continue
                        if count < width:
                            neighbours[i, count] = j
                        count += 1
    neighbour_count[i] = min(count, width)
    return count


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
    zl, zh = _offsets(ncell[2], geom[G_PERIODIC, 2] != 0.0) if dim == 3 else (0, 0)
    yl, yh = _offsets(ncell[1], geom[G_PERIODIC, 1] != 0.0)
    for oz in range(zl, zh + 1):
        nz, _ = _neighbour(cz, oz, ncell[2], geom[G_PERIODIC, 2] != 0.0, 0.0)
        if nz < 0:
            continue
        for oy in range(yl, yh + 1):
            ny, _ = _neighbour(cy, oy, ncell[1], geom[G_PERIODIC, 1] != 0.0, 0.0)
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
    wrap_into_box(p, i, geom, dim, image)
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
    needed = gather_neighbours(p, i, b, cell_of, neighbours, neighbour_count, cell_members, cell_count, cell_points,
                               ncell, geom, dim, params)
    needed = max(needed, _join_neighbours(i, neighbours, neighbour_count))
    if needed > neighbours.shape[1]:
        acc[ACC_LIST_OVERFLOW] = needed
        return False
    return True


@kernel
def build_all_lists(p, b, cell_of, neighbours, neighbour_count, cell_members, cell_count, cell_points, ncell, geom,
                    dim, params, image):
    """Anchor every particle at its position (all synchronised) and build every list.

    Returns the longest list and the fullest cell needed; if either exceeds
    its row length the structures are incomplete and the caller must grow
    them and call again.
    """
    cell_count[:] = 0
    most = 0
    for i in range(p.shape[0]):
        wrap_into_box(p, i, geom, dim, image)
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
        count = gather_neighbours(p, i, b, cell_of, neighbours, neighbour_count, cell_members, cell_count,
                                  cell_points, ncell, geom, dim, params)
        needed = max(needed, count)
    return needed, most


@inline_kernel
def _prefetch_particle(i, p, b, queue, neighbours, neighbour_count, tree, leaves):
    """Start loading everything an event of particle i reads, so the misses overlap."""
    prefetch(p, i)
    prefetch(b, i)
    prefetch(neighbours, i)
    prefetch(neighbour_count, i)
    prefetch(queue, i)
    node = leaves + i // QUEUE_BLOCK
    for _ in range(TREE_LEVELS_PREFETCHED):
        prefetch(tree, node)
        node >>= 1


@inline_kernel
def _likely_next(i, tree, leaves):
    """The particle of the second-earliest event, a guess good enough for prefetching.

    The runner-up of the tournament is the best of the siblings along the
    winner i's path; the block and the lowest levels (cold in cache) are
    skipped, so the guess misses if the runner-up lies among i's nearest
    32 particles. Returns -1 if there is no guess.
    """
    node = (leaves + i // QUEUE_BLOCK) >> 2 if leaves >= 8 else leaves + i // QUEUE_BLOCK
    best_time = math.inf
    best = -1.0
    while node > 1:
        sibling_time = tree[node ^ 1, 0]
        sibling_id = tree[node ^ 1, 1]
        best = sibling_id if sibling_time < best_time else best
        best_time = min(sibling_time, best_time)
        node >>= 1
    return int(best)


@inline_kernel
def _prefetch_neighbours(i, p, neighbours, neighbour_count):
    for m in range(neighbour_count[i]):
        prefetch(p, neighbours[i, m])


@inline_kernel
def _repredict(p, i, b, neighbours, neighbour_count, geom, dim, params, queue, tree, leaves, event):
    """Predict i's next event (i at its own time) and queue it."""
    queue_update(i, predict(p, i, b, neighbours, neighbour_count, geom, dim, params, event), queue, tree, leaves)


@kernel
def run_events(t, max_pair_collisions, t_stop, p, b, image, cell_of, neighbours, neighbour_count, cell_members,
               cell_count, cell_points, ncell, geom, dim, restitution, params, queue, tree, leaves, acc):
    """Process events until ``max_pair_collisions`` collisions or time ``t_stop``.

    Returns the current time: the last event's time, or ``t_stop`` if that
    came first (particles are not moved to it: call ``synchronise``). Stops
    early, with ``acc[ACC_LIST_OVERFLOW]`` or ``acc[ACC_CELL_OVERFLOW]`` set
    to the size needed, if a neighbour list or a cell outgrows its row (grow
    the rows and rebuild every list).
    """
    done = 0
    scale0 = params[P_SCALE0]
    growth = params[P_GROWTH]
    event = int(acc[ACC_EVENTS])
    while done < max_pair_collisions:
        event_time = tree[1, 0]
        i = int(tree[1, 1])
        if event_time > t_stop:
            t = t_stop
            break
        if event_time == math.inf:
            break
        t = event_time
        event += 1
        # memory latency dominates: start every load whose address is known, then compute;
        # also for the particle of the next event, most likely the runner-up now
        _prefetch_particle(i, p, b, queue, neighbours, neighbour_count, tree, leaves)
        upcoming = _likely_next(i, tree, leaves)
        if upcoming >= 0:
            _prefetch_particle(upcoming, p, b, queue, neighbours, neighbour_count, tree, leaves)
        target = int(b[i, TARGET])
        if target >= 0:
            _prefetch_particle(target, p, b, queue, neighbours, neighbour_count, tree, leaves)
        _prefetch_neighbours(i, p, neighbours, neighbour_count)
        advance(p, i, t, geom, dim)
        partner = -1  # the second particle to re-predict, if any
        if target >= 0:
            j = target
            _prefetch_neighbours(j, p, neighbours, neighbour_count)
            if b[j, CHANGED_AT] > b[i, PREDICTED_AT]:
                acc[ACC_STALE_EVENTS] += 1.0
            else:
                advance(p, j, t, geom, dim)
                collide_pair(p, i, j, b, geom, dim, scale0 + growth * t, growth, restitution, params, acc)
                b[i, CHANGED_AT] = event
                b[j, CHANGED_AT] = event
                done += 1
                partner = j
        elif target == LIST_TARGET:
            acc[ACC_LIST_REBUILDS] += 1.0
            if not rebuild_list(p, i, b, cell_of, neighbours, neighbour_count, cell_members, cell_count, cell_points,
                                ncell, geom, dim, params, image, acc):
                break
        else:
            bounce_off_wall(p, i, wall_target(target), b, params, acc)
            b[i, CHANGED_AT] = event
        if upcoming >= 0:  # its rows have arrived by now: fetch what they point to
            _prefetch_neighbours(upcoming, p, neighbours, neighbour_count)
            upcoming_target = int(b[upcoming, TARGET])
            if upcoming_target >= 0:
                _prefetch_particle(upcoming_target, p, b, queue, neighbours, neighbour_count, tree, leaves)
        # one call site, so the inlined prediction is compiled once
        for q in range(1 if partner < 0 else 2):
            _repredict(p, i if q == 0 else partner, b, neighbours, neighbour_count, geom, dim, params, queue, tree,
                       leaves, event)
    acc[ACC_EVENTS] = event
    return t


@kernel
def predict_all(p, b, neighbours, neighbour_count, geom, dim, params, queue, tree, leaves, acc):
    """Predict every particle's next event (all at their own times) and rebuild the tree."""
    event = int(acc[ACC_EVENTS])
    for i in range(p.shape[0]):
        queue[i] = predict(p, i, b, neighbours, neighbour_count, geom, dim, params, event)
    for padding in range(p.shape[0], queue.shape[0]):
        queue[padding] = math.inf
    tree_build(tree, queue, leaves)


@kernel
def largest_anchor_drift(p, b, dim):
    """Largest distance of a particle (synchronised) from its anchor: at most shell / 2."""
    worst = 0.0
    for i in range(p.shape[0]):
        norm2 = 0.0
        for k in range(dim):
            d = p[i, X + k] - b[i, ANCHOR + k]
            norm2 += d * d
        worst = max(worst, math.sqrt(norm2))
    return worst



@kernel
def synchronise(p, t, geom, dim):
    """Move every particle to time t."""
    for i in range(p.shape[0]):
        advance(p, i, t, geom, dim)


@kernel
def min_gap(p, scale, cell_of, cell_members, cell_count, ncell, geom, dim):
    """Smallest (distance - contact distance) over pairs in neighbouring cells.

    Particles must be synchronised and within the list shell of their
    anchors (cells hold anchors). Negative means an overlap.
    """
    worst = math.inf
    for i in range(p.shape[0]):
        cx, cy, cz = cell_coordinates(cell_of[i], ncell)
        zl, zh = _offsets(ncell[2], geom[G_PERIODIC, 2] != 0.0) if dim == 3 else (0, 0)
        yl, yh = _offsets(ncell[1], geom[G_PERIODIC, 1] != 0.0)
        xl, xh = _offsets(ncell[0], geom[G_PERIODIC, 0] != 0.0)
        for oz in range(zl, zh + 1):
            nz, _ = _neighbour(cz, oz, ncell[2], geom[G_PERIODIC, 2] != 0.0, 0.0)
            if nz < 0:
                continue
            for oy in range(yl, yh + 1):
                ny, _ = _neighbour(cy, oy, ncell[1], geom[G_PERIODIC, 1] != 0.0, 0.0)
                if ny < 0:
                    continue
                for ox in range(xl, xh + 1):
                    nx, _ = _neighbour(cx, ox, ncell[0], geom[G_PERIODIC, 0] != 0.0, 0.0)
                    if nx < 0:
                        continue
                    cell = cell_index(nx, ny, nz, ncell)
                    for slot in range(cell_count[cell]):
                        j = cell_members[cell, slot]
                        if j > i:
                            norm2 = 0.0
                            for k in range(dim):
                                x = p[j, X + k] - p[i, X + k]
                                if geom[G_PERIODIC, k] != 0.0:
                                    x -= geom[G_BOX, k] * round(x / geom[G_BOX, k])
                                norm2 += x * x
                            worst = min(worst, math.sqrt(norm2) - (p[i, R] + p[j, R]) * scale)
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


@inline_kernel
def _nearest_image(x, length, wrap):
    """x, or its image nearest to 0 when ``wrap`` (a periodic axis of fewer than 3 cells)."""
    return x - length * round(x / length) if wrap else x


@kernel
def pair_distance_counts(points, cell_start, ncell, box, periodic, r_max, counts):
    """Add the ordered pairs (a, c), a != c, at distance in [b w, (b + 1) w) to ``counts[b]``.

    ``w = r_max / len(counts)``. The points (N, 3; z = 0 and one walled cell
    in 2D) lie in [0, L) per axis, sorted by cell: cells no smaller than
    ``r_max`` (x fastest, as :func:`cell_index`), ``cell_start`` (cells + 1
    entries) the first point of each, so every pair closer than ``r_max`` is
    in the same or a neighbouring cell. Across a periodic face the cell
    offset fixes the image (``r_max <= L / 2``); only a periodic axis of one
    or two cells needs the minimum image per pair.
    """
    bins = counts.shape[0]
    inverse_width = bins / r_max
    reach2 = r_max * r_max
    wrap_x = periodic[0] and ncell[0] < 3
    wrap_y = periodic[1] and ncell[1] < 3
    wrap_z = periodic[2] and ncell[2] < 3
    for cell in range(ncell[0] * ncell[1] * ncell[2]):
        cx, cy, cz = cell_coordinates(cell, ncell)
        zl, zh = _offsets(ncell[2], periodic[2])
        yl, yh = _offsets(ncell[1], periodic[1])
        xl, xh = _offsets(ncell[0], periodic[0])
        for oz in range(zl, zh + 1):
            nz, sz = _neighbour(cz, oz, ncell[2], periodic[2], box[2])
            if nz < 0:
                continue
            for oy in range(yl, yh + 1):
                ny, sy = _neighbour(cy, oy, ncell[1], periodic[1], box[1])
                if ny < 0:
                    continue
                for ox in range(xl, xh + 1):
                    nx, sx = _neighbour(cx, ox, ncell[0], periodic[0], box[0])
                    if nx < 0:
                        continue
                    other = cell_index(nx, ny, nz, ncell)
                    for a in range(cell_start[cell], cell_start[cell + 1]):
                        # the neighbour cell's image shift, moved onto the point of this cell
                        ax, ay, az = points[a, 0] - sx, points[a, 1] - sy, points[a, 2] - sz
                        for c in range(cell_start[other], cell_start[other + 1]):
                            x = _nearest_image(points[c, 0] - ax, box[0], wrap_x)
                            y = _nearest_image(points[c, 1] - ay, box[1], wrap_y)
                            z = _nearest_image(points[c, 2] - az, box[2], wrap_z)
                            norm2 = x * x + y * y + z * z
                            if norm2 < reach2 and c != a:
                                b = int(math.sqrt(norm2) * inverse_width)
                                if b < bins:
                                    counts[b] += 1.0
