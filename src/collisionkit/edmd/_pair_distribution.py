"""Pair distances of an EDMD snapshot: the histogram behind g(r), and g at contact.

Counts are of ordered pairs (each pair twice), from a cell-list kernel.
"""

from __future__ import annotations

import math

import numpy as np

from .._kernels import edmd as _k

# the most species whose partial g(r) a sampler records (their pair histograms cost S (S + 1) / 2 a block)
PARTIAL_RDF_SPECIES = 4
# the fewest pairs within 0.1 diameter of contact (over all snapshots) that give g at contact: a synthetic g of 1.3
# came out 1.39 +- 0.03 from 8 pairs, within a standard error from 14 up (errors 5-10 % small below 30)
MIN_CONTACT_PAIRS = 25

def pair_histogram(system, r_max, bins):
    """Counts of pairs (each counted twice) per distance bin up to r_max, in one snapshot.

    The snapshot is taken half-way to the next event, without the pair that
    collided last (:func:`_snapshot`).
    """
    points, offset, colliding = _snapshot(system)
    counts = _histogram(points, system, offset, r_max, bins)
    _remove_pairs(counts, points, system, colliding, offset, r_max)
    return counts


def partial_histograms(system, r_max, bins, kinds):
    r"""The ordered pairs (a, b) of species a and b per distance bin, shape (kinds, kinds, bins), in one snapshot.

    ``[a, b]`` counts each particle of a with each of b (a pair of one
    species twice, as :func:`pair_histogram`); the cross counts are what
    the histogram of a and b together holds beyond those of a and b alone,
    halved: :math:`H_{ab} = (C_{a \cup b} - C_a - C_b) / 2`.
    """
    points, offset, colliding = _snapshot(system)
    species = np.asarray(system._species)  # in the engine's order, as the snapshot's points
    members = [species == kind for kind in range(kinds)]
    single = [_histogram(points[member], system, offset, r_max, bins) for member in members]
    counts = np.zeros((kinds, kinds, bins))
    for a in range(kinds):
        counts[a, a] = single[a]
        for b in range(a + 1, kinds):
            both = _histogram(points[members[a] | members[b]], system, offset, r_max, bins)
            counts[a, b] = counts[b, a] = 0.5 * (both - single[a] - single[b])
    for i, j in colliding:  # each such pair counted twice in [a, a], once in [a, b] and [b, a] of unlike species
        pair = np.array([[i, j]])
        a, b = species[i], species[j]
        if a == b:
            _remove_pairs(counts[a, a], points, system, pair, offset, r_max)
        else:
            for first, second in ((a, b), (b, a)):
                _remove_pairs(counts[first, second], points, system, pair, offset, r_max, each=1.0)
    return counts


def _snapshot(system):
    """The particles' folded positions half-way to the next event, the Lees-Edwards image offset then (None
    without shear), and the pair (engine order; none, or one row) that collided at the last event.

    A run stops at a collision, so a snapshot then holds the pair that just
    collided at contact: one pair more than a snapshot at a random time, in
    the bins that give g at contact (300 discs at eta 0.05: g(contact) 1.57
    with it, 1.08 without, Henderson's 1.084). Half-way to the next event
    the pair has barely moved (crossing and list events come often), so it
    is left out: the last collision's partner (kept by the event loop) and
    the particle at contact with it (of several, as in an inelastic
    cluster, the one moving away fastest).
    """
    system.synchronise()
    colliding = _last_pair(system)
    gap = system._time_to_next_event()
    ahead = 0.5 * gap if 0.0 < gap < math.inf else 0.0
    points = system._folded(ahead=ahead)[0][:, : system.dim]
    offset = system._offset_at(system.time + ahead) if system.shear_rate != 0.0 else None
    return points, offset, colliding


def _separations(system, points, first, second, offset):
    """points[first] - points[second] by the minimum image: periodic axes, and under Lees-Edwards shear (``offset``
    not None) the images across y shifted by ``offset`` along x; also the images across y counted (n, y shifts)."""
    dim = system.dim
    box = np.asarray(system.box[:dim], dtype=float)
    separation = points[first] - points[second]
    across = np.zeros(len(separation))
    if offset is not None:  # the image n boxes up in y sits n offsets along x
        across = np.round(separation[:, 1] / box[1])
        separation[:, 0] -= across * offset
        separation[:, 1] -= across * box[1]
    periodic = np.asarray(system.periodic)
    separation[:, periodic] -= box[periodic] * np.round(separation[:, periodic] / box[periodic])
    return separation, across


def _last_pair(system) -> np.ndarray:
    """The pair (engine order, as a (1, 2) array) of the collision the last event call ended at, if its particles
    are still at contact (within 1e-9 of their contact distance); else an empty (0, 2) array."""
    partner = system._last_partner
    if partner < 0 or partner >= system.count:
        return np.empty((0, 2), dtype=np.int64)
    dim = system.dim
    now = system._folded()[0][:, :dim]
    offset = system._offset_at(system.time) if system.shear_rate != 0.0 else None
    others = np.arange(system.count)
    separation, across = _separations(system, now, others, np.full(system.count, partner), offset)
    radii = system.p[:, _k.R] * system.scale
    gap = np.linalg.norm(separation, axis=1) - (radii + radii[partner])
    touching = np.flatnonzero((np.abs(gap) <= 1e-9 * (radii + radii[partner])) & (others != partner))
    if touching.size == 0:
        return np.empty((0, 2), dtype=np.int64)
    relative = system.vel[touching] - system.vel[partner]
    relative[:, 0] -= across[touching] * system.shear_rate * system.box[1]  # (an image's flow)
    receding = np.sum(relative * separation[touching], axis=1)
    return np.array([[touching[np.argmax(receding)], partner]], dtype=np.int64)


def _remove_pairs(counts, points, system, pairs, offset, r_max, each=2.0) -> None:
    """Take ``pairs`` (engine order) out of ``counts`` at their distance in ``points``, ``each`` counts a pair."""
    if len(pairs) == 0:
        return
    separation, _ = _separations(system, points, pairs[:, 0], pairs[:, 1], offset)
    bins = (np.linalg.norm(separation, axis=1) * (counts.size / r_max)).astype(np.int64)
    for b in bins[bins < counts.size]:
        counts[b] = max(counts[b] - each, 0.0)


def _histogram(points, system, offset, r_max, bins):
    dim = system.dim
    if len(points) < 2:
        return np.zeros(bins)
    if offset is not None:
        return _sheared_histogram(points, system.box[:dim], offset, r_max, bins)
    return pair_distance_histogram(points, system.box[:dim], system.periodic[:dim], r_max, bins)


def _sheared_histogram(points, box, offset, r_max, bins):
    """:func:`pair_distance_histogram` under Lees-Edwards shear (points folded into the box, image offset ``offset``).

    Within r_max of a y face a particle's nearest partners may be images
    across it, shifted by -+ the offset: the points within r_max of a face
    get ghost copies beyond the other one, and y is counted open. The
    ordered pairs from the points to points and ghosts are then
    (C(points + ghosts) + C(points) - C(ghosts)) / 2, C counting ordered
    pairs within a set.
    """
    dim = points.shape[1]
    lx, ly = box[0], box[1]
    ghosts = []
    for side, near in ((1.0, points[:, 1] < r_max), (-1.0, points[:, 1] >= ly - r_max)):
        copy = points[near].copy()
        copy[:, 1] += side * ly
        copy[:, 0] = (copy[:, 0] + side * offset) % lx
        copy[copy[:, 0] >= lx, 0] = 0.0
        ghosts.append(copy)
    ghosts = np.concatenate(ghosts)
    tall = np.array(box, dtype=float)
    tall[1] = ly + 2.0 * r_max
    open_y = np.ones(dim, dtype=bool)
    open_y[1] = False
    lifted = [np.asarray(set_, dtype=float) + np.eye(dim)[1] * r_max for set_ in (points, ghosts)]
    both = pair_distance_histogram(np.concatenate(lifted), tall, open_y, r_max, bins)
    alone = pair_distance_histogram(lifted[0], tall, open_y, r_max, bins)
    among_ghosts = pair_distance_histogram(lifted[1], tall, open_y, r_max, bins) if len(ghosts) > 1 else 0.0
    return 0.5 * (both + alone - among_ghosts)


def pair_distance_histogram(points, box, periodic, r_max, bins):
    """Ordered pairs (i != j) per distance bin of width r_max / bins, points in [0, L) per axis.

    A cell-list kernel, O(N) for a fixed r_max (a k-d tree's
    ``count_neighbors`` over 500 radii took 3.6 s a snapshot for 4000
    spheres, most of an ``edmd`` run). Periodic axes use the minimum image
    (r_max <= L / 2 there), walled ones the plain distance.
    """
    count, dim = np.shape(points)
    padded = np.zeros((count, 3))  # 2D: z = 0 in one walled cell
    padded[:, :dim] = points
    cells_box = np.ones(3)
    cells_box[:dim] = box
    axes_periodic = np.zeros(3, dtype=np.bool_)
    axes_periodic[:dim] = periodic
    ncell = np.ones(3, dtype=np.int64)
    ncell[:dim] = np.maximum(np.floor(cells_box[:dim] / r_max), 1)
    coordinates = np.clip((padded / cells_box * ncell).astype(np.int64), 0, ncell - 1)
    cell = coordinates[:, 0] + ncell[0] * (coordinates[:, 1] + ncell[1] * coordinates[:, 2])
    in_cell_order = np.ascontiguousarray(padded[np.argsort(cell, kind="stable")])
    cell_start = np.concatenate([[0], np.cumsum(np.bincount(cell, minlength=int(np.prod(ncell))))])
    counts = np.zeros(bins)
    _k.pair_distance_counts(in_cell_order, cell_start, ncell, cells_box, axes_periodic, float(r_max), counts)
    return counts


def contact_value(r, g, counts, diameter, ideal=None):
    """g at contact and its standard error: a weighted quadratic fit to the bins within 0.1 diameter of contact
    (5 bins at least), extrapolated to contact; NaN with fewer than :data:`MIN_CONTACT_PAIRS` pairs there.

    Only whole bins beyond contact count (a bin that straddles contact is
    partly inside the core, so partly empty), empty ones included. Each
    bin's pairs (``counts`` counts each pair twice) are Poisson with the
    mean the fit gives, so its variance is the fit's g over half its
    ideal-gas count (``ideal``, in the units of ``counts``; by default
    ``counts / g``, interpolated over empty bins): weights from the counts
    seen instead favoured the bins that came out low, and leaving out empty
    ones biased g up, in a dilute or small system (300 discs at eta 0.05:
    1.94 against Henderson's 1.08).
    """
    half_width = 0.5 * (r[1] - r[0]) if len(r) > 1 else 0.0
    # a small species' contact (a tenth of it narrower than 5 bins) is fitted over 5 bins
    reach = max(1.1 * diameter, diameter + 10.0 * half_width)
    near = (r - half_width >= diameter * (1.0 - 1e-12)) & (r < reach)
    seen = near & (counts > 0)
    if near.sum() < 4 or 0.5 * np.sum(counts[near]) < MIN_CONTACT_PAIRS:
        return math.nan, math.nan
    if ideal is None:
        ideal = np.interp(r, r[seen], counts[seen] / g[seen])  # pairs counted twice per unit g
    ideal = np.asarray(ideal, dtype=float)[near]
    x, values = r[near] - diameter, g[near]
    fitted = np.full(x.size, np.sum(counts[near]) / np.sum(ideal))  # start from the mean g
    for _ in range(3):  # weights from the fit, refitted: they settle at once
        sigma = np.sqrt(np.maximum(fitted, 1e-3 * np.max(fitted)) / (0.5 * ideal))
        coefficients, covariance = np.polyfit(x, values, 2, w=1.0 / sigma, cov="unscaled")
        fitted = np.polyval(coefficients, x)
    return float(coefficients[-1]), float(math.sqrt(covariance[-1, -1]))
