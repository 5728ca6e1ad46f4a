"""Event prediction: contact times of pairs, list expiry and wall hits, a particle's next event.

Every prediction starts from the particle at its own time (``p[i, T]``);
times returned are from that time, except :func:`predict`'s, which is
absolute.
"""

from __future__ import annotations

import math

# no EDMD kernel allocates or returns an array: all of them borrow, without reference counting
from ..._jit import borrowing_inline_kernel as inline_kernel
from ..._jit import borrowing_kernel as kernel
from .layout import (
    ANCHOR, G_BOX, G_GRAVITY, G_PERIODIC, LIST_TARGET, P_GROWTH, P_SCALE0, P_SHEAR_FRAME, P_SHEAR_RATE, P_SHEAR_REACH,
    P_SHELL, PREDICTED_AT, R, SHEAR_X_EXCURSION, T, TARGET, V, X, wall_target,
)
from .exact import sure_approach
from .motion import half_box, minimum_image, pair_image, shear_offset, sheared_image, streaming_velocity

# box lengths (in diameters) below which the pair tests take periodic images without a branch. With this and
# layout.PREFETCH_FROM the engine is 3-6 % faster at N = 864, eta 0.45 (box 10 diameters; benchmarks/bench_edmd_ab.py,
# two runs: 5.6 % and 3.3 %, quartiles 1.5-8.5 %); always branch-free was 2.5-3.3 % slower at N = 4000 and 32000
# (20 and 31 diameters) (issue 21)
SMALL_BOX_DIAMETERS = 12.0


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
    Whether the pair approaches is the collision step's test
    (:func:`.exact.sure_approach`).
    """
    rr = rx * rx + ry * ry + rz * rz
    ru = rx * ux + ry * uy + rz * uz
    sigma = contact * scale
    rate = contact * growth
    c = rr - sigma * sigma
    shift = sigma * rate
    # the collision step's approach test, bit for bit (see .exact)
    b = sure_approach(ru - shift, rx, ry, rz, ux, uy, uz, shift)
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
def contact_before(rx, ry, rz, ux, uy, uz, sigma, best):
    """Time until |r + u tau| = sigma (straight flights, fixed radii) if it comes before ``best``, else inf.

    r is the separation (partner minus particle), u the relative velocity.
    The root is tau = c / (-b + sqrt(D)) with b = r.u, c = |r|^2 - sigma^2
    and D = sigma^2 |u|^2 - |r x u|^2 (= b^2 - |u|^2 c by Lagrange's
    identity, without its cancellation), taken when the pair approaches
    (b < 0) and D >= 0; an overlap by round-off (c <= 0) while approaching
    collides at once. Since sqrt(D) <= -b when c >= 0, tau >= c / (-2 b):
    one cheap test, c < -2 b best, rejects the receding pairs and those that
    cannot beat ``best`` before the square root and the division.
    """
    b = rx * ux + ry * uy + rz * uz
    c = rx * rx + ry * ry + rz * rz - sigma * sigma
    # b < 0 and c + 2 b best < 0 in one comparison, so one (rarely taken, well predicted) branch;
    # then b's sign made sure, as the collision step makes it (see .exact)
    if max(b, c + 2.0 * b * best) < 0.0 and sure_approach(b, rx, ry, rz, ux, uy, uz, 0.0) < 0.0:
        cx = ry * uz - rz * uy
        cy = rz * ux - rx * uz
        cz = rx * uy - ry * ux
        discriminant = sigma * sigma * (ux * ux + uy * uy + uz * uz) - (cx * cx + cy * cy + cz * cz)
        if discriminant >= 0.0 or c <= 0.0:
            return max(c, 0.0) / (math.sqrt(max(discriminant, 0.0)) - b)
    return math.inf


@inline_kernel
def _first_contact_ballistic(p, i, neighbours, neighbour_count, geom, scale, horizon):
    """Earliest contact of i (at its own time) with its list before ``horizon``: fixed radii, straight flights.

    Returns (time from i's time, partner), or (inf, -1) if no contact comes
    before ``horizon``. Each pair's root and filter: :func:`contact_before`,
    whose one rarely taken branch is well predicted (a branch on b < 0 alone
    would be a coin toss, and a mispredicted branch costs more than the
    arithmetic it saves). For the same reason the periodic images are taken
    without a branch in a box shorter than ``SMALL_BOX_DIAMETERS`` of i's
    diameters, where about one pair in five lies across a face
    (:func:`.motion.pair_image`); in a larger box the branch is cheaper.
    """
    t = p[i, T]
    xi, yi, zi = p[i, X], p[i, X + 1], p[i, X + 2]
    vxi, vyi, vzi = p[i, V], p[i, V + 1], p[i, V + 2]
    ri = p[i, R]
    lx, ly, lz = geom[G_BOX, 0], geom[G_BOX, 1], geom[G_BOX, 2]
    hx, hy, hz = half_box(geom, 0), half_box(geom, 1), half_box(geom, 2)
    # in a small box many pairs lie across a face: take their images without a branch to mispredict
    across_often = min(hx, hy, hz) < SMALL_BOX_DIAMETERS * ri * scale  # half the shortest periodic length
    best = horizon
    partner = -1
    for m in range(neighbour_count[i]):
        j = neighbours[i, m]
        dt = t - p[j, T]
        rx = p[j, X] + p[j, V] * dt - xi
        ry = p[j, X + 1] + p[j, V + 1] * dt - yi
        rz = p[j, X + 2] + p[j, V + 2] * dt - zi
        if across_often:
            rx, ry, rz = pair_image(rx, lx, hx), pair_image(ry, ly, hy), pair_image(rz, lz, hz)
        else:
            rx, ry, rz = minimum_image(rx, lx, hx), minimum_image(ry, ly, hy), minimum_image(rz, lz, hz)
        ux = p[j, V] - vxi
        uy = p[j, V + 1] - vyi
        uz = p[j, V + 2] - vzi
        tau = contact_before(rx, ry, rz, ux, uy, uz, (ri + p[j, R]) * scale, best)
        if tau < best:
            best = tau
            partner = j
    if partner < 0:
        return math.inf, -1
    return best, partner


@inline_kernel
def _first_contact_sheared(p, i, neighbours, neighbour_count, geom, params, horizon):
    """:func:`_first_contact_ballistic` under Lees-Edwards shear: each partner's nearest image, with its velocity.

    The image across a y face is shifted by the box offset at i's time and
    moves at -+ G L_y along x relative to the partner, so the pair's
    relative motion is again a straight line and its contact time the same
    root (exact, as in a periodic box).
    """
    t = p[i, T]
    xi, yi, zi = p[i, X], p[i, X + 1], p[i, X + 2]
    vxi, vyi, vzi = p[i, V], p[i, V + 1], p[i, V + 2]
    ri = p[i, R]
    lz = geom[G_BOX, 2]
    hz = half_box(geom, 2)
    offset = shear_offset(params, geom, t)
    slide = params[P_SHEAR_RATE] * geom[G_BOX, 1]
    scale = params[P_SCALE0]
    best = horizon
    partner = -1
    for m in range(neighbour_count[i]):
        j = neighbours[i, m]
        dt = t - p[j, T]
        rx, ry, n = sheared_image(p[j, X] + p[j, V] * dt - xi, p[j, X + 1] + p[j, V + 1] * dt - yi, geom, offset)
        rz = minimum_image(p[j, X + 2] + p[j, V + 2] * dt - zi, lz, hz)
        ux = p[j, V] - n * slide - vxi
        uy = p[j, V + 1] - vyi
        uz = p[j, V + 2] - vzi
        tau = contact_before(rx, ry, rz, ux, uy, uz, (ri + p[j, R]) * scale, best)
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
    hx, hy, hz = half_box(geom, 0), half_box(geom, 1), half_box(geom, 2)
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
def sheared_list_expiry(p, i, b, anchor_time, geom, dim, params):
    """Time (from i's own time) until particle i's list expires under Lees-Edwards shear.

    The anchor moves with the flow at its height, x_a(t) = xi + u_x(y_a)
    (t - t_f) (:func:`.motion.frame_x`), and the list holds while
    |x - x_a| + k (t - t_a) <= shell / 2, with k = |G| R / 4 and t_a the
    anchor's time (why: :func:`.neighbour_lists._gather_sheared`). With
    d = x - x_a now, w = v - u_x(y_a) e_x its rate and H = shell / 2 - k
    (t - t_a) the budget left, the first tau with |d + w tau| = H - k tau
    is the first root of (|w|^2 - k^2) tau^2 + 2 (d.w + k H) tau + |d|^2 -
    H^2 (tau <= H / k keeps the right side >= 0, and the budget is spent
    by then anyway). The list also expires when x strays
    ``SHEAR_X_EXCURSION`` L_x outside [0, L_x) (the anchor no longer bounds
    it; the minimum image of :func:`.motion.sheared_image` needs it).
    """
    t = p[i, T]
    lx = geom[G_BOX, 0]
    drift = streaming_velocity(params, geom, b[i, ANCHOR + 1])
    d = p[i, X] - b[i, ANCHOR] - drift * (t - params[P_SHEAR_FRAME])
    d -= lx * math.floor(d / lx + 0.5)  # the anchor's frame x is kept in [0, L_x), the position is not
    w = p[i, V] - drift
    ageing = 0.25 * abs(params[P_SHEAR_RATE]) * params[P_SHEAR_REACH]
    budget = 0.5 * params[P_SHELL] - ageing * (t - anchor_time[i])
    if budget <= 0.0:
        return 0.0
    quadratic = w * w - ageing * ageing
    linear = 2.0 * (d * w + ageing * budget)
    constant = d * d - budget * budget
    for k in range(1, dim):
        d = p[i, X + k] - b[i, ANCHOR + k]
        v = p[i, V + k]
        quadratic += v * v
        linear += 2.0 * d * v
        constant += d * d
    vx = p[i, V]
    stray = SHEAR_X_EXCURSION * lx
    excursion = math.inf
    if vx > 0.0:
        excursion = max(lx + stray - p[i, X], 0.0) / vx
    elif vx < 0.0:
        excursion = max(p[i, X] + stray, 0.0) / -vx
    spent = budget / ageing if ageing > 0.0 else math.inf
    return min(first_root_from_below(quadratic, linear, constant), spent, excursion)


@inline_kernel
def predict_boundary(p, i, b, anchor_time, geom, dim, params):
    """When particle i (at its own time) must next rebuild its list or hits a wall.

    Returns (time from i's time, target: LIST_TARGET or the wall's target).
    """
    growth = params[P_GROWTH]
    scale = params[P_SCALE0] + growth * p[i, T]
    if params[P_SHEAR_RATE] != 0.0:
        best = sheared_list_expiry(p, i, b, anchor_time, geom, dim, params)
    else:
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
def predict(p, i, b, anchor_time, neighbours, neighbour_count, geom, dim, params, event):
    """Predict particle i's next event (i at its own time): its boundary event, then the collisions before it.

    Records the event's target in ``b`` and returns its absolute time.
    """
    boundary, target = predict_boundary(p, i, b, anchor_time, geom, dim, params)
    if params[P_SHEAR_RATE] != 0.0:
        pair, partner = _first_contact_sheared(p, i, neighbours, neighbour_count, geom, params, boundary)
    else:
        pair, partner = predict_pairs(p, i, neighbours, neighbour_count, geom, params[P_SCALE0], params[P_GROWTH],
                                      boundary)
    b[i, PREDICTED_AT] = event
    if partner >= 0:
        b[i, TARGET] = partner
        return p[i, T] + pair
    b[i, TARGET] = target
    return p[i, T] + boundary
