"""Kernels of bench_edmd_pair_test.py: the pair-test variants, the copies and their upkeep (issue 21)."""

from __future__ import annotations

import math

import numba
import numpy as np

from collisionkit._jit import BORROWING_OPTIONS
from collisionkit._kernels.edmd.exact import sure_approach
from collisionkit._kernels.edmd.layout import G_BOX, R, T, V, X
from collisionkit._kernels.edmd.motion import half_box, minimum_image
from collisionkit._kernels.edmd.prediction import _first_contact_ballistic, predict_boundary

# components of a list's copies: x, y, z, vx, vy, vz, t, radius (x0 copies: x - v t, y.., z.., vx, vy, vz, -, radius)
COPY_WIDTH = 8
# the float32 filter's margin on c + 2 b best < 0 and b < 0, relative to the terms' sizes (float32 rounding is 6e-8)
F32_MARGIN = 1e-5
# lists padded to whole zmm vectors of doubles (the padding copies are NaN: never a contact)
PAD = 8

jit = numba.njit(**BORROWING_OPTIONS)
inline_jit = numba.njit(inline="always", **BORROWING_OPTIONS)


@jit
def _horizons(p, b, anchor_time, geom, dim, params, out):
    for i in range(p.shape[0]):
        out[i] = predict_boundary(p, i, b, anchor_time, geom, dim, params)[0]


@jit
def run_gather(p, order, neighbours, count, geom, scale, horizon, found, taus):
    for i in order:
        taus[i], found[i] = _first_contact_ballistic(p, i, neighbours, count, geom, scale, horizon[i])


@inline_jit
def _exact_pair(rx, ry, rz, ux, uy, uz, sigma, best):
    """The engine's filter and root for one pair (``_first_contact_ballistic``'s body): tau, or inf."""
    b = rx * ux + ry * uy + rz * uz
    c = rx * rx + ry * ry + rz * rz - sigma * sigma
    if max(b, c + 2.0 * b * best) < 0.0 and sure_approach(b, rx, ry, rz, ux, uy, uz, 0.0) < 0.0:
        cx = ry * uz - rz * uy
        cy = rz * ux - rx * uz
        cz = rx * uy - ry * ux
        discriminant = sigma * sigma * (ux * ux + uy * uy + uz * uz) - (cx * cx + cy * cy + cz * cz)
        if discriminant >= 0.0 or c <= 0.0:
            return max(c, 0.0) / (math.sqrt(max(discriminant, 0.0)) - b)
    return math.inf


@inline_jit
def _exact_from_p(p, i, j, geom, scale, best):
    """The exact test of pair (i, j) from the particle records, as the engine makes it."""
    lx, ly, lz = geom[G_BOX, 0], geom[G_BOX, 1], geom[G_BOX, 2]
    hx, hy, hz = half_box(geom, 0), half_box(geom, 1), half_box(geom, 2)
    dt = p[i, T] - p[j, T]
    rx = minimum_image(p[j, X] + p[j, V] * dt - p[i, X], lx, hx)
    ry = minimum_image(p[j, X + 1] + p[j, V + 1] * dt - p[i, X + 1], ly, hy)
    rz = minimum_image(p[j, X + 2] + p[j, V + 2] * dt - p[i, X + 2], lz, hz)
    return _exact_pair(rx, ry, rz, p[j, V] - p[i, V], p[j, V + 1] - p[i, V + 1], p[j, V + 2] - p[i, V + 2],
                       (p[i, R] + p[j, R]) * scale, best)


@jit
def run_gather_2pass(p, order, neighbours, count, geom, scale, horizon, found, taus, mark):
    lx, ly, lz = geom[G_BOX, 0], geom[G_BOX, 1], geom[G_BOX, 2]
    hx, hy, hz = half_box(geom, 0), half_box(geom, 1), half_box(geom, 2)
    for i in order:
        t = p[i, T]
        best = horizon[i]
        n = count[i]
        for m in range(n):
            j = neighbours[i, m]
            dt = t - p[j, T]
            rx = minimum_image(p[j, X] + p[j, V] * dt - p[i, X], lx, hx)
            ry = minimum_image(p[j, X + 1] + p[j, V + 1] * dt - p[i, X + 1], ly, hy)
            rz = minimum_image(p[j, X + 2] + p[j, V + 2] * dt - p[i, X + 2], lz, hz)
            ux = p[j, V] - p[i, V]
            uy = p[j, V + 1] - p[i, V + 1]
            uz = p[j, V + 2] - p[i, V + 2]
            sigma = (p[i, R] + p[j, R]) * scale
            b = rx * ux + ry * uy + rz * uz
            c = rx * rx + ry * ry + rz * rz - sigma * sigma
            mark[m] = max(b, c + 2.0 * b * best) < 0.0
        partner = -1
        for m in range(n):
            if mark[m]:
                j = neighbours[i, m]
                tau = _exact_from_p(p, i, j, geom, scale, best)
                if tau < best:
                    best, partner = tau, j
        taus[i], found[i] = (best, partner) if partner >= 0 else (math.inf, -1)


@inline_jit
def _image(d, length, half):
    """Branch-free minimum image (a select, no jump) of a separation within 1.5 box lengths."""
    d = d - length if d > half else d
    return d + length if d < -half else d


@jit
def run_gather_select(p, order, neighbours, count, geom, scale, horizon, found, taus):
    """The engine's loop with the minimum image as selects (the same results: d - L > -L / 2 when d > L / 2)."""
    lx, ly, lz = geom[G_BOX, 0], geom[G_BOX, 1], geom[G_BOX, 2]
    hx, hy, hz = half_box(geom, 0), half_box(geom, 1), half_box(geom, 2)
    for i in order:
        t = p[i, T]
        xi, yi, zi = p[i, X], p[i, X + 1], p[i, X + 2]
        vxi, vyi, vzi = p[i, V], p[i, V + 1], p[i, V + 2]
        ri = p[i, R]
        best = horizon[i]
        partner = -1
        for m in range(count[i]):
            j = neighbours[i, m]
            dt = t - p[j, T]
            rx = _image(p[j, X] + p[j, V] * dt - xi, lx, hx)
            ry = _image(p[j, X + 1] + p[j, V + 1] * dt - yi, ly, hy)
            rz = _image(p[j, X + 2] + p[j, V + 2] * dt - zi, lz, hz)
            tau = _exact_pair(rx, ry, rz, p[j, V] - vxi, p[j, V + 1] - vyi, p[j, V + 2] - vzi, (ri + p[j, R]) * scale,
                              best)
            if tau < best:
                best, partner = tau, j
        taus[i], found[i] = (best, partner) if partner >= 0 else (math.inf, -1)


@jit
def run_copies(p, order, neighbours, count, copies, geom, scale, horizon, found, taus):
    lx, ly, lz = geom[G_BOX, 0], geom[G_BOX, 1], geom[G_BOX, 2]
    hx, hy, hz = half_box(geom, 0), half_box(geom, 1), half_box(geom, 2)
    for i in order:
        t = p[i, T]
        best = horizon[i]
        partner = -1
        row = copies[i]
        for m in range(count[i]):
            dt = t - row[6, m]
            rx = minimum_image(row[0, m] + row[3, m] * dt - p[i, X], lx, hx)
            ry = minimum_image(row[1, m] + row[4, m] * dt - p[i, X + 1], ly, hy)
            rz = minimum_image(row[2, m] + row[5, m] * dt - p[i, X + 2], lz, hz)
            tau = _exact_pair(rx, ry, rz, row[3, m] - p[i, V], row[4, m] - p[i, V + 1], row[5, m] - p[i, V + 2],
                              (p[i, R] + row[7, m]) * scale, best)
            if tau < best:
                best, partner = tau, neighbours[i, m]
        taus[i], found[i] = (best, partner) if partner >= 0 else (math.inf, -1)


@jit
def run_copies_2pass(p, order, neighbours, count, copies, geom, scale, horizon, found, taus, mark):
    lx, ly, lz = geom[G_BOX, 0], geom[G_BOX, 1], geom[G_BOX, 2]
    hx, hy, hz = half_box(geom, 0), half_box(geom, 1), half_box(geom, 2)
    for i in order:
        t = p[i, T]
        xi, yi, zi = p[i, X], p[i, X + 1], p[i, X + 2]
        vxi, vyi, vzi = p[i, V], p[i, V + 1], p[i, V + 2]
        ri = p[i, R]
        best = horizon[i]
        n = count[i]
        row = copies[i]
        _mark_copies(row, n, t, xi, yi, zi, vxi, vyi, vzi, ri, scale, best, lx, ly, lz, hx, hy, hz, mark)
        partner = -1
        for m in range(n):
            if mark[m]:
                dt = t - row[6, m]
                rx = minimum_image(row[0, m] + row[3, m] * dt - xi, lx, hx)
                ry = minimum_image(row[1, m] + row[4, m] * dt - yi, ly, hy)
                rz = minimum_image(row[2, m] + row[5, m] * dt - zi, lz, hz)
                tau = _exact_pair(rx, ry, rz, row[3, m] - vxi, row[4, m] - vyi, row[5, m] - vzi,
                                  (ri + row[7, m]) * scale, best)
                if tau < best:
                    best, partner = tau, neighbours[i, m]
        taus[i], found[i] = (best, partner) if partner >= 0 else (math.inf, -1)


@inline_jit
def _mark_inline(row, n, t, xi, yi, zi, vxi, vyi, vzi, ri, scale, best, lx, ly, lz, hx, hy, hz, mark):
    """:func:`_mark_copies`, inlined."""
    _mark_copies(row, n, t, xi, yi, zi, vxi, vyi, vzi, ri, scale, best, lx, ly, lz, hx, hy, hz, mark)


@jit
def _mark_copies(row, n, t, xi, yi, zi, vxi, vyi, vzi, ri, scale, best, lx, ly, lz, hx, hy, hz, mark):
    """The branch-free marking pass over exact copies (a separate function, to read its machine code)."""
    for m in range(n):
        dt = t - row[6, m]
        rx = _image(row[0, m] + row[3, m] * dt - xi, lx, hx)
        ry = _image(row[1, m] + row[4, m] * dt - yi, ly, hy)
        rz = _image(row[2, m] + row[5, m] * dt - zi, lz, hz)
        ux = row[3, m] - vxi
        uy = row[4, m] - vyi
        uz = row[5, m] - vzi
        sigma = (ri + row[7, m]) * scale
        b = rx * ux + ry * uy + rz * uz
        c = rx * rx + ry * ry + rz * rz - sigma * sigma
        mark[m] = max(b, c + 2.0 * b * best) < 0.0


@jit
def _mark_x0(row, n, t, xi, yi, zi, vxi, vyi, vzi, ri, scale, best, lx, ly, lz, hx, hy, hz, mark):
    """The marking pass over time-0 copies: r = (x0_j - x0_i) + (v_j - v_i) t, no per-pair time."""
    for m in range(n):
        ux = row[3, m] - vxi
        uy = row[4, m] - vyi
        uz = row[5, m] - vzi
        rx = _image(row[0, m] - xi + ux * t, lx, hx)
        ry = _image(row[1, m] - yi + uy * t, ly, hy)
        rz = _image(row[2, m] - zi + uz * t, lz, hz)
        sigma = (ri + row[7, m]) * scale
        b = rx * ux + ry * uy + rz * uz
        c = rx * rx + ry * ry + rz * rz - sigma * sigma
        mark[m] = max(b, c + 2.0 * b * best) < 0.0


@jit
def _mark_x0_f32(row, n, t, xi, yi, zi, vxi, vyi, vzi, ri, scale, best, lx, ly, lz, hx, hy, hz, margin, mark):
    """:func:`_mark_x0` in float32, the test widened by ``margin`` times the terms' sizes."""
    for m in range(n):
        ux = row[3, m] - vxi
        uy = row[4, m] - vyi
        uz = row[5, m] - vzi
        rx = _image(row[0, m] - xi + ux * t, lx, hx)
        ry = _image(row[1, m] - yi + uy * t, ly, hy)
        rz = _image(row[2, m] - zi + uz * t, lz, hz)
        sigma = (ri + row[7, m]) * scale
        rr = rx * rx + ry * ry + rz * rz
        b = rx * ux + ry * uy + rz * uz
        size = rr + sigma * sigma + np.float32(2.0) * abs(b) * best
        c = rr - sigma * sigma
        mark[m] = max(b - margin * abs(b), c + np.float32(2.0) * b * best - margin * size) < np.float32(0.0)


@jit
def run_x0(p, order, neighbours, count, copies, geom, scale, horizon, found, taus, mark, single):
    lx, ly, lz = geom[G_BOX, 0], geom[G_BOX, 1], geom[G_BOX, 2]
    hx, hy, hz = half_box(geom, 0), half_box(geom, 1), half_box(geom, 2)
    for i in order:
        t = p[i, T]
        # i's own time-0 position
        x0, y0, z0 = p[i, X] - p[i, V] * t, p[i, X + 1] - p[i, V + 1] * t, p[i, X + 2] - p[i, V + 2] * t
        best = horizon[i]
        n = count[i]
        if single:
            f = np.float32
            _mark_x0_f32(copies[i], n, f(t), f(x0), f(y0), f(z0), f(p[i, V]), f(p[i, V + 1]), f(p[i, V + 2]),
                         f(p[i, R]), f(scale), f(best), f(lx), f(ly), f(lz), f(hx), f(hy), f(hz), f(F32_MARGIN), mark)
        else:
            _mark_x0(copies[i], n, t, x0, y0, z0, p[i, V], p[i, V + 1], p[i, V + 2], p[i, R], scale, best, lx, ly, lz,
                     hx, hy, hz, mark)
        partner = -1
        for m in range(n):
            if mark[m]:
                j = neighbours[i, m]
                tau = _exact_from_p(p, i, j, geom, scale, best)
                if tau < best:
                    best, partner = tau, j
        taus[i], found[i] = (best, partner) if partner >= 0 else (math.inf, -1)


@inline_jit
def _tau_copies(row, n, t, xi, yi, zi, vxi, vyi, vzi, ri, scale, lx, ly, lz, hx, hy, hz, tau):
    """Branch-free pass: every partner's contact time from the plain sums (inf if it recedes or misses)."""
    for m in range(n):
        dt = t - row[6, m]
        rx = _image(row[0, m] + row[3, m] * dt - xi, lx, hx)
        ry = _image(row[1, m] + row[4, m] * dt - yi, ly, hy)
        rz = _image(row[2, m] + row[5, m] * dt - zi, lz, hz)
        ux = row[3, m] - vxi
        uy = row[4, m] - vyi
        uz = row[5, m] - vzi
        sigma = (ri + row[7, m]) * scale
        b = rx * ux + ry * uy + rz * uz
        c = rx * rx + ry * ry + rz * rz - sigma * sigma
        cx = ry * uz - rz * uy
        cy = rz * ux - rx * uz
        cz = rx * uy - ry * ux
        discriminant = sigma * sigma * (ux * ux + uy * uy + uz * uz) - (cx * cx + cy * cy + cz * cz)
        root = max(c, 0.0) / (math.sqrt(max(discriminant, 0.0)) - b)
        tau[m] = root if b < 0.0 and (discriminant >= 0.0 or c <= 0.0) else math.inf


@jit
def tau_pass_only(p, order, count, copies, geom, scale, tau):
    """The branch-free pass alone (its cost), over lists padded to whole vectors."""
    lx, ly, lz = geom[G_BOX, 0], geom[G_BOX, 1], geom[G_BOX, 2]
    hx, hy, hz = half_box(geom, 0), half_box(geom, 1), half_box(geom, 2)
    for i in order:
        _tau_copies(copies[i], (count[i] + PAD - 1) // PAD * PAD, p[i, T], p[i, X], p[i, X + 1], p[i, X + 2], p[i, V],
                    p[i, V + 1], p[i, V + 2], p[i, R], scale, lx, ly, lz, hx, hy, hz, tau)


@jit
def run_copies_tau(p, order, neighbours, count, copies, geom, scale, horizon, found, taus, tau):
    """Branch-free contact times of the whole (padded) list, then the engine's exact test for each new best."""
    lx, ly, lz = geom[G_BOX, 0], geom[G_BOX, 1], geom[G_BOX, 2]
    hx, hy, hz = half_box(geom, 0), half_box(geom, 1), half_box(geom, 2)
    for i in order:
        t = p[i, T]
        xi, yi, zi = p[i, X], p[i, X + 1], p[i, X + 2]
        vxi, vyi, vzi = p[i, V], p[i, V + 1], p[i, V + 2]
        ri = p[i, R]
        n = count[i]
        row = copies[i]
        _tau_copies(row, (n + PAD - 1) // PAD * PAD, t, xi, yi, zi, vxi, vyi, vzi, ri, scale, lx, ly, lz, hx, hy, hz,
                    tau)
        best = horizon[i]
        partner = -1
        for m in range(n):
            if tau[m] < best:
                # the engine's own test (its sure sign of b): the same time, or inf
                dt = t - row[6, m]
                rx = minimum_image(row[0, m] + row[3, m] * dt - xi, lx, hx)
                ry = minimum_image(row[1, m] + row[4, m] * dt - yi, ly, hy)
                rz = minimum_image(row[2, m] + row[5, m] * dt - zi, lz, hz)
                exact = _exact_pair(rx, ry, rz, row[3, m] - vxi, row[4, m] - vyi, row[5, m] - vzi,
                                    (ri + row[7, m]) * scale, best)
                if exact < best:
                    best, partner = exact, neighbours[i, m]
        taus[i], found[i] = (best, partner) if partner >= 0 else (math.inf, -1)


@inline_jit
def _gather_rows(p, i, neighbours, n, padded, buffer):
    """Copy i's partners' records (x, v, t, r) into a contiguous buffer, one row a component (NaN padding)."""
    for m in range(n):
        j = neighbours[i, m]
        for k in range(COPY_WIDTH):
            buffer[k, m] = p[j, k]
    for m in range(n, padded):
        buffer[0, m] = math.nan


@jit
def run_buffer_tau(p, order, neighbours, count, geom, scale, horizon, found, taus, buffer, tau):
    """No copies kept: each prediction gathers its partners into a buffer, the branch-free pass, the exact test."""
    lx, ly, lz = geom[G_BOX, 0], geom[G_BOX, 1], geom[G_BOX, 2]
    hx, hy, hz = half_box(geom, 0), half_box(geom, 1), half_box(geom, 2)
    for i in order:
        t = p[i, T]
        xi, yi, zi = p[i, X], p[i, X + 1], p[i, X + 2]
        vxi, vyi, vzi = p[i, V], p[i, V + 1], p[i, V + 2]
        ri = p[i, R]
        n = count[i]
        padded = (n + PAD - 1) // PAD * PAD
        _gather_rows(p, i, neighbours, n, padded, buffer)
        _tau_copies(buffer, padded, t, xi, yi, zi, vxi, vyi, vzi, ri, scale, lx, ly, lz, hx, hy, hz, tau)
        best = horizon[i]
        partner = -1
        for m in range(n):
            if tau[m] < best:
                j = neighbours[i, m]
                exact = _exact_from_p(p, i, j, geom, scale, best)
                if exact < best:
                    best, partner = exact, j
        taus[i], found[i] = (best, partner) if partner >= 0 else (math.inf, -1)


@jit
def run_buffer_compact(p, order, neighbours, count, geom, scale, horizon, found, taus, buffer, mark, picked):
    """Gathered buffer, the branch-free marking pass, the marked slots compacted without a branch, the exact test."""
    lx, ly, lz = geom[G_BOX, 0], geom[G_BOX, 1], geom[G_BOX, 2]
    hx, hy, hz = half_box(geom, 0), half_box(geom, 1), half_box(geom, 2)
    for i in order:
        t = p[i, T]
        xi, yi, zi = p[i, X], p[i, X + 1], p[i, X + 2]
        vxi, vyi, vzi = p[i, V], p[i, V + 1], p[i, V + 2]
        ri = p[i, R]
        n = count[i]
        padded = (n + PAD - 1) // PAD * PAD
        best = horizon[i]
        _gather_rows(p, i, neighbours, n, padded, buffer)
        _mark_inline(buffer, padded, t, xi, yi, zi, vxi, vyi, vzi, ri, scale, best, lx, ly, lz, hx, hy, hz, mark)
        kept = 0
        for m in range(n):
            picked[kept] = m
            kept += mark[m]
        partner = -1
        for s in range(kept):
            j = neighbours[i, picked[s]]
            exact = _exact_from_p(p, i, j, geom, scale, best)
            if exact < best:
                best, partner = exact, j
        taus[i], found[i] = (best, partner) if partner >= 0 else (math.inf, -1)


@jit
def _marked(p, order, neighbours, count, geom, scale, horizon, mark):
    """How many pairs pass the cheap filter against the horizon (the marking passes' output)."""
    lx, ly, lz = geom[G_BOX, 0], geom[G_BOX, 1], geom[G_BOX, 2]
    hx, hy, hz = half_box(geom, 0), half_box(geom, 1), half_box(geom, 2)
    total = 0
    for i in order:
        for m in range(count[i]):
            j = neighbours[i, m]
            dt = p[i, T] - p[j, T]
            rx = minimum_image(p[j, X] + p[j, V] * dt - p[i, X], lx, hx)
            ry = minimum_image(p[j, X + 1] + p[j, V + 1] * dt - p[i, X + 1], ly, hy)
            rz = minimum_image(p[j, X + 2] + p[j, V + 2] * dt - p[i, X + 2], lz, hz)
            ux = p[j, V] - p[i, V]
            uy = p[j, V + 1] - p[i, V + 1]
            uz = p[j, V + 2] - p[i, V + 2]
            sigma = (p[i, R] + p[j, R]) * scale
            b = rx * ux + ry * uy + rz * uz
            c = rx * rx + ry * ry + rz * rz - sigma * sigma
            total += max(b, c + 2.0 * b * horizon[i]) < 0.0
    return total


@jit
def fill_copies(p, neighbours, count, copies, at_zero, back):
    """Write every list's copies of its partners (x, v, t, r; or x - v t, v, -, r) and the back index."""
    for i in range(p.shape[0]):
        for m in range(count[i]):
            j = neighbours[i, m]
            for k in range(3):
                copies[i, k, m] = p[j, X + k] - p[j, V + k] * p[j, T] if at_zero else p[j, X + k]
                copies[i, 3 + k, m] = p[j, V + k]
            copies[i, 6, m] = p[j, T]
            copies[i, 7, m] = p[j, R]
            for s in range(count[j]):
                if neighbours[j, s] == i:
                    back[i, m] = s


@jit
def run_refresh(p, pairs, neighbours, count, copies, back):
    """Rewrite the copies of both particles of each collision in their partners' lists (2 x ~19 scattered rows)."""
    for e in range(pairs.shape[0]):
        for side in range(2):
            i = pairs[e, side]
            for m in range(count[i]):
                row = copies[neighbours[i, m]]
                s = back[i, m]
                for k in range(6):
                    row[k, s] = p[i, k]
                row[6, s] = p[i, T]


@jit
def run_refresh_records(p, pairs, neighbours, count, records, back):
    """:func:`run_refresh` for copies kept as whole records (list slot-major, one cache line a copy): its floor."""
    for e in range(pairs.shape[0]):
        for side in range(2):
            i = pairs[e, side]
            for m in range(count[i]):
                s = back[i, m]
                k = neighbours[i, m]
                for c in range(COPY_WIDTH):
                    records[k, s, c] = p[i, c]
