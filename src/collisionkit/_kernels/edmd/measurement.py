"""Measurements on a synchronised system: moving all to one time, overlaps, anchor drift, pair distances, moments."""

from __future__ import annotations

import math

# no EDMD kernel allocates or returns an array: all of them borrow, without reference counting
from ..._jit import borrowing_inline_kernel as inline_kernel
from ..._jit import borrowing_kernel as kernel
from .cells import cell_coordinates, cell_index, cell_offsets, neighbour_coordinate
from .layout import ANCHOR, G_BOX, G_PERIODIC, MASS, P_SHEAR_FRAME, P_SHEAR_RATE, P_SHEAR_REACH, R, T, V, X
from .motion import advance, streaming_velocity


@kernel
def largest_anchor_drift(p, b, anchor_time, geom, dim, params):
    """Largest distance of a particle (synchronised) from its anchor: at most shell / 2 while its list holds.

    Under Lees-Edwards shear the distance from the anchor carried by the
    flow, plus |G| R / 4 times the list's age (the budget its expiry
    spends, see :func:`.prediction.sheared_list_expiry`).
    """
    sheared = params[P_SHEAR_RATE] != 0.0
    lx = geom[G_BOX, 0]
    ageing = 0.25 * abs(params[P_SHEAR_RATE]) * params[P_SHEAR_REACH]
    worst = 0.0
    for i in range(p.shape[0]):
        norm2 = 0.0
        for k in range(dim):
            d = p[i, X + k] - b[i, ANCHOR + k]
            if sheared and k == 0:
                d -= streaming_velocity(params, geom, b[i, ANCHOR + 1]) * (p[i, T] - params[P_SHEAR_FRAME])
                d -= lx * math.floor(d / lx + 0.5)
            norm2 += d * d
        spent = math.sqrt(norm2)
        if sheared:
            spent += ageing * (p[i, T] - anchor_time[i])
        worst = max(worst, spent)
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
        zl, zh = cell_offsets(ncell[2], geom[G_PERIODIC, 2] != 0.0) if dim == 3 else (0, 0)
        yl, yh = cell_offsets(ncell[1], geom[G_PERIODIC, 1] != 0.0)
        xl, xh = cell_offsets(ncell[0], geom[G_PERIODIC, 0] != 0.0)
        for oz in range(zl, zh + 1):
            nz, _ = neighbour_coordinate(cz, oz, ncell[2], geom[G_PERIODIC, 2] != 0.0, 0.0)
            if nz < 0:
                continue
            for oy in range(yl, yh + 1):
                ny, _ = neighbour_coordinate(cy, oy, ncell[1], geom[G_PERIODIC, 1] != 0.0, 0.0)
                if ny < 0:
                    continue
                for ox in range(xl, xh + 1):
                    nx, _ = neighbour_coordinate(cx, ox, ncell[0], geom[G_PERIODIC, 0] != 0.0, 0.0)
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
        zl, zh = cell_offsets(ncell[2], periodic[2])
        yl, yh = cell_offsets(ncell[1], periodic[1])
        xl, xh = cell_offsets(ncell[0], periodic[0])
        for oz in range(zl, zh + 1):
            nz, sz = neighbour_coordinate(cz, oz, ncell[2], periodic[2], box[2])
            if nz < 0:
                continue
            for oy in range(yl, yh + 1):
                ny, sy = neighbour_coordinate(cy, oy, ncell[1], periodic[1], box[1])
                if ny < 0:
                    continue
                for ox in range(xl, xh + 1):
                    nx, sx = neighbour_coordinate(cx, ox, ncell[0], periodic[0], box[0])
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


@kernel
def stored_helfand_moments(p, b, t, out):
    """The Helfand moments of the stored positions x at time t into ``out`` (12 entries), particles in free flight.

    ``out[3 a + b] = sum_i m_i v_ia x_ib`` (momentum) and
    ``out[9 + a] = sum_i (m_i v_i^2 / 2) x_ia`` (energy), each x moved
    from the particle's own time to t along its straight flight (no
    gravity; the records are not changed). Plus the image slots of the
    accumulator they are the moments whose time derivatives are the
    momentum and energy fluxes (see :mod:`.layout`).
    """
    for k in range(12):
        out[k] = 0.0
    for i in range(p.shape[0]):
        mass = b[i, MASS]
        ahead = t - p[i, T]
        energy = 0.0
        for a in range(3):
            momentum = mass * p[i, V + a]
            energy += 0.5 * momentum * p[i, V + a]
            for c in range(3):
                out[3 * a + c] += momentum * (p[i, X + c] + p[i, V + c] * ahead)
        for a in range(3):
            out[9 + a] += energy * (p[i, X + a] + p[i, V + a] * ahead)
