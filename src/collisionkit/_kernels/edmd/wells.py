"""Square wells: a pair's events at the edge of its well, and the record of which pairs are inside.

The pair potential is a hard core at the contact distance sigma and a well
of depth epsilon out to lambda sigma (per species pair: the table after
the parameters, :func:`.layout.well_slot`): u(r) = inf for r < sigma, -epsilon for
sigma <= r < lambda sigma, 0 beyond (Alder & Wainwright, J. Chem. Phys. 31,
459 (1959); the events as in DynamO, Bannerman, Sargant & Lue, J. Comput.
Chem. 32, 3329 (2011)). At the well's edge only the normal relative
velocity u_n = r.u / |r| changes, by energy conservation with the reduced
mass mu:

* entering (u_n < 0): u_n' = -sqrt(u_n^2 + 2 epsilon / mu), kinetic energy +epsilon;
* leaving (u_n > 0) with mu u_n^2 / 2 > epsilon: u_n' = sqrt(u_n^2 - 2 epsilon / mu), -epsilon;
* else a bounce back into the well: u_n' = -u_n.

Which pairs are inside is a record, not a distance: after an event the pair
sits on the edge within round-off, where the distance cannot tell a pair
that just entered from one that just left (DynamO keeps the same record).
Each particle lists its partners inside (``bonds[i, :bond_count[i]]``,
symmetric); the prediction reads it only for pairs within ``WELL_BAND`` of
an edge, every other pair being plainly inside or outside by its distance.
"""

from __future__ import annotations

import math

# no EDMD kernel allocates or returns an array: all of them borrow, without reference counting
from ..._jit import borrowing_inline_kernel as inline_kernel
from ..._jit import borrowing_kernel as kernel
from .contacts import add_image_terms, add_transfer
from .exact import sure_approach
from .layout import (
    ACC_BOUNCES, ACC_CAPTURES, ACC_ENERGY_IMAGE, ACC_ESCAPES, ACC_VIRIAL, ACC_WELL_ENERGY, ACC_WELL_ENERGY_TIME,
    ACC_WELL_PAIR_TIME, ACC_WELL_PAIRS, ACC_WELL_SINCE, G_BOX, G_GRAVITY, MASS, P_SCALE0, P_SIZE, P_WELL_SPECIES,
    PREDICTED_AT, R, SPECIES, T, TARGET, V, X, well_slot, well_target,
)
from .motion import half_box, minimum_image, pair_image
from .neighbour_lists import drop_from_list
from .prediction import SMALL_BOX_DIAMETERS, contact_before, predict_boundary

# relative band of |r|^2 around the well's edge (lambda sigma)^2 within which a pair's side is read from the record:
# positions carry round-off of a few units in the last place of the box length, 1e-14 of |r|^2 at most
WELL_BAND = 1e-9
# the relative spacing of doubles
_LAST_PLACE = 2.0**-52


@inline_kernel
def bonded(i, j, bonds, bond_count):
    """True if i and j are inside their well (j in i's record)."""
    for m in range(bond_count[i]):
        if bonds[i, m] == j:
            return True
    return False


@inline_kernel
def pair_well(params, b, i, j):
    """(lambda, epsilon) of the pair i, j: the table's entry for their species (epsilon 0: no well).

    A table of one entry (S = 1) is every pair's well: the species are not
    read (their records are another cache line per partner).
    """
    species = int(params[P_WELL_SPECIES])
    slot = P_SIZE if species == 1 else well_slot(species, int(b[i, SPECIES]), int(b[j, SPECIES]))
    return params[slot], params[slot + 1]


@inline_kernel
def _count_change(acc, t, change, depth):
    """Add ``change`` (+-1) to the pairs inside and ``change * depth`` to their depths, first carrying both time
    integrals up to time t."""
    elapsed = t - acc[ACC_WELL_SINCE]
    acc[ACC_WELL_PAIR_TIME] += acc[ACC_WELL_PAIRS] * elapsed
    acc[ACC_WELL_ENERGY_TIME] += acc[ACC_WELL_ENERGY] * elapsed
    acc[ACC_WELL_SINCE] = t
    acc[ACC_WELL_PAIRS] += change
    acc[ACC_WELL_ENERGY] += change * depth


@inline_kernel
def time_to_leave(uu, ru, outside):
    """Time until a pair inside its well reaches the edge on its way out: the later root of uu t^2 + 2 ru t + outside.

    ``outside`` = |r|^2 - (lambda sigma)^2 is <= 0 for a pair inside, or
    round-off above 0 at the edge, where the record says inside: it is
    taken as 0 there (on the edge). A receding pair on the edge leaves at
    once (0); an approaching one crosses its chord, -2 ru / uu (a pair
    gliding along the edge: round-off would otherwise leave no chord at
    all, and its exit "now" would never happen, an approaching pair not
    leaving). Written without cancellation; infinite for a pair at rest
    relative to each other.
    """
    if uu == 0.0:
        return math.inf
    outside = min(outside, 0.0)
    root = math.sqrt(ru * ru - uu * outside)
    if ru > 0.0:
        return -outside / (ru + root)
    return (root - ru) / uu


@inline_kernel
def first_event_in_wells(p, i, b, neighbours, neighbour_count, bonds, bond_count, geom, params, horizon):
    """Earliest event of i (at its own time) with its list before ``horizon``: a core contact or a well's edge.

    Returns (time from i's time, partner, True for the edge of a well), or
    (inf, -1, False). A pair inside its well (``r < lambda sigma``, or by
    the record near the edge) meets either at the core, which comes first
    if it comes at all (:func:`.prediction.contact_before`), or at the
    edge on its way out: the later root of ``|r + u tau| = lambda sigma``
    (:func:`time_to_leave`). A pair outside can only
    enter: the contact time at lambda sigma. A pair whose species share no
    well (epsilon 0) only meets at the core.
    """
    t = p[i, T]
    scale = params[P_SCALE0]
    xi, yi, zi = p[i, X], p[i, X + 1], p[i, X + 2]
    vxi, vyi, vzi = p[i, V], p[i, V + 1], p[i, V + 2]
    ri = p[i, R]
    lx, ly, lz = geom[G_BOX, 0], geom[G_BOX, 1], geom[G_BOX, 2]
    hx, hy, hz = half_box(geom, 0), half_box(geom, 1), half_box(geom, 2)
    across_often = min(hx, hy, hz) < SMALL_BOX_DIAMETERS * ri * scale
    # under uniform gravity both partners fall alike: their relative motion is a straight line from i's time
    gx, gy, gz = 0.5 * geom[G_GRAVITY, 0], 0.5 * geom[G_GRAVITY, 1], 0.5 * geom[G_GRAVITY, 2]
    falling = gx != 0.0 or gy != 0.0 or gz != 0.0
    best = horizon
    partner = -1
    edge = False
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
        if falling:  # j's fall since its own time, as .prediction.predict_pairs takes it
            rx += gx * dt * dt
            ry += gy * dt * dt
            rz += gz * dt * dt
            ux += 2.0 * gx * dt
            uy += 2.0 * gy * dt
            uz += 2.0 * gz * dt
        sigma = (ri + p[j, R]) * scale
        width, depth = pair_well(params, b, i, j)
        if depth == 0.0:
            tau = contact_before(rx, ry, rz, ux, uy, uz, sigma, best)
            if tau < best:
                best, partner, edge = tau, j, False
            continue
        reach = sigma * width
        outside = rx * rx + ry * ry + rz * rz - reach * reach
        inside = outside < 0.0
        if abs(outside) <= WELL_BAND * reach * reach:
            inside = bonded(i, j, bonds, bond_count)
        if inside:
            tau = contact_before(rx, ry, rz, ux, uy, uz, sigma, best)
            if tau < best:
                best, partner, edge = tau, j, False
                continue
            # no core contact before best: the way out, if it comes first
            tau = time_to_leave(ux * ux + uy * uy + uz * uz, rx * ux + ry * uy + rz * uz, outside)
            if tau < best:
                best, partner, edge = tau, j, True
        else:
            tau = contact_before(rx, ry, rz, ux, uy, uz, reach, best)
            if tau < best:
                best, partner, edge = tau, j, True
    if partner < 0:
        return math.inf, -1, False
    return best, partner, edge


@inline_kernel
def cross_well_edge(p, i, j, b, geom, params, bonds, bond_count, image, acc, t):
    """Resolve the event of i and j (both at time t) at the edge of their well; False if nothing happens.

    A pair outside that does not approach, or inside that approaches, is
    left alone (a stale edge event). Otherwise only the normal relative
    velocity changes (see the module docstring), the record and the count
    of pairs inside follow, and the impulse joins the virial and the
    transport sums as a collision's does (:mod:`.contacts`).

    The energy transfer of the heat sums is j's whole energy change: its
    kinetic gain plus half the pair's change of potential energy (each
    partner carries half of its pairs' energies), -epsilon/2 entering and
    +epsilon/2 leaving, so that the energy's Helfand moment is that of
    kinetic plus potential energy (Bannerman & Lue, J. Chem. Phys. 133,
    124506 (2010)). Its potential part, -epsilon/2 sum_i n_i x_i over the
    unwrapped positions x + image L (n_i the pairs i is in), is added where
    the moment is read; it jumps by -epsilon/2 (x_i + x_j) at a capture,
    whose part outside the transfer times the minimum image, the partners'
    image counters times the box, is taken back in the image slots here.
    """
    dx = p[j, X] - p[i, X]
    dy = p[j, X + 1] - p[i, X + 1]
    dz = p[j, X + 2] - p[i, X + 2]
    rx = minimum_image(dx, geom[G_BOX, 0], half_box(geom, 0))
    ry = minimum_image(dy, geom[G_BOX, 1], half_box(geom, 1))
    rz = minimum_image(dz, geom[G_BOX, 2], half_box(geom, 2))
    ux = p[j, V] - p[i, V]
    uy = p[j, V + 1] - p[i, V + 1]
    uz = p[j, V + 2] - p[i, V + 2]
    approach = sure_approach(rx * ux + ry * uy + rz * uz, rx, ry, rz, ux, uy, uz, 0.0)
    inside = bonded(i, j, bonds, bond_count)
    # (a pair inside moving along the edge, r.u = 0 exactly, is leaving for the prediction: it bounces, turned in)
    if (inside and approach < 0.0) or ((not inside) and approach >= 0.0):
        return False
    mi = b[i, MASS]
    mj = b[j, MASS]
    reduced = mi * mj / (mi + mj)
    rr = rx * rx + ry * ry + rz * rz
    distance = math.sqrt(rr)
    normal_squared = approach * approach / rr  # u_n^2
    depth = pair_well(params, b, i, j)[1]
    barrier = 2.0 * depth / reduced  # u_n^2 a pair gains entering, or needs to leave
    # the change of u_n, written without the cancellation of sqrt(a) - sqrt(b)
    half_depth = 0.5 * depth
    if not inside:
        change = -barrier / (math.sqrt(normal_squared + barrier) + math.sqrt(normal_squared))
        bonds[i, bond_count[i]] = j
        bond_count[i] += 1
        bonds[j, bond_count[j]] = i
        bond_count[j] += 1
        _count_change(acc, t, 1.0, depth)
        acc[ACC_CAPTURES] += 1.0
        potential_gain = -half_depth  # j's half of the pair's potential energy change
    elif normal_squared > barrier:
        change = -barrier / (math.sqrt(normal_squared - barrier) + math.sqrt(normal_squared))
        drop_from_list(i, j, bonds, bond_count)
        drop_from_list(j, i, bonds, bond_count)
        _count_change(acc, t, -1.0, depth)
        acc[ACC_ESCAPES] += 1.0
        potential_gain = half_depth
    else:
        change = -2.0 * math.sqrt(normal_squared)
        acc[ACC_BOUNCES] += 1.0
        potential_gain = 0.0
    push = reduced * change / distance  # the impulse on j is push r (< 0: towards i)
    kinetic_gain = push * (rx * p[j, V] + ry * p[j, V + 1] + rz * p[j, V + 2]) + 0.5 * push * push * rr / mj
    gain = kinetic_gain + potential_gain
    add_transfer(acc, push, gain, rx, ry, rz)
    if rx != dx or ry != dy or rz != dz:
        add_image_terms(acc, push, gain, rx, ry, rz, dx, dy, dz, geom)
    if potential_gain != 0.0:
        for a in range(image.shape[1]):
            acc[ACC_ENERGY_IMAGE + a] -= potential_gain * (image[i, a] + image[j, a]) * geom[G_BOX, a]
    share_i = push / mi
    share_j = push / mj
    p[i, V] -= share_i * rx
    p[i, V + 1] -= share_i * ry
    p[i, V + 2] -= share_i * rz
    p[j, V] += share_j * rx
    p[j, V + 1] += share_j * ry
    p[j, V + 2] += share_j * rz
    if not inside or normal_squared <= barrier:  # the pair is inside now: it must approach
        _turn_inwards(p, i, j, rx, ry, rz, mj / (mi + mj), mi / (mi + mj), rr)
    acc[ACC_VIRIAL] += push * rr
    return True


@inline_kernel
def _turn_inwards(p, i, j, rx, ry, rz, share_i, share_j, rr):
    """Make sure a pair left inside its well at the edge approaches: else its next event would be leaving, at once.

    A bounce of a pair grazing the edge (u_n of round-off) can leave the
    sign of r.u unchanged; a kick along r from the velocities' last place,
    doubled until the approach test agrees, turns it in (as
    :func:`.contacts._separate` pushes a colliding pair apart). ``share_i``
    and ``share_j`` are m_j / M and m_i / M: the kick keeps the momentum.
    """
    kick = 0.0
    while True:
        ux = p[j, V] - p[i, V]
        uy = p[j, V + 1] - p[i, V + 1]
        uz = p[j, V + 2] - p[i, V + 2]
        if sure_approach(rx * ux + ry * uy + rz * uz, rx, ry, rz, ux, uy, uz, 0.0) < 0.0:
            return
        if kick == 0.0:
            speed = 0.0
            for k in range(3):
                speed = max(speed, abs(p[i, V + k]), abs(p[j, V + k]))
            kick = _LAST_PLACE * max(speed, _LAST_PLACE) / math.sqrt(rr)
        else:
            kick *= 2.0
        for k in range(3):
            x = rx if k == 0 else (ry if k == 1 else rz)
            p[i, V + k] += share_i * kick * x
            p[j, V + k] -= share_j * kick * x


@inline_kernel
def predict_in_wells(p, i, b, anchor_time, neighbours, neighbour_count, bonds, bond_count, geom, dim, params, event):
    """:func:`.prediction.predict` with square wells: the boundary event, then the pair events before it.

    Records the event's target in ``b`` (a partner, a well's edge
    :func:`.layout.well_target`, the list or a wall) and returns its
    absolute time. Wells go with fixed radii (no compression) and no
    shear; under gravity the pairs' relative motion is still straight.
    """
    boundary, target = predict_boundary(p, i, b, anchor_time, geom, dim, params)
    pair, partner, edge = first_event_in_wells(p, i, b, neighbours, neighbour_count, bonds, bond_count, geom, params,
                                               boundary)
    b[i, PREDICTED_AT] = event
    if partner >= 0:
        b[i, TARGET] = well_target(partner) if edge else partner
        return p[i, T] + pair
    b[i, TARGET] = target
    return p[i, T] + boundary


@kernel
def bound_energies(b, bonds, bond_count, params, out):
    """``out[i]``: the depths epsilon_ab of the wells particle i is inside (its record), summed; i in memory order."""
    for i in range(bond_count.shape[0]):
        total = 0.0
        for m in range(bond_count[i]):
            total += pair_well(params, b, i, bonds[i, m])[1]
        out[i] = total
