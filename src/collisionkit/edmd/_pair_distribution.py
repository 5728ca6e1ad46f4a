"""Pair distances of an EDMD snapshot: the histogram behind g(r), and g at contact.

Counts are of ordered pairs (each pair twice), from a cell-list kernel.
"""

from __future__ import annotations

import math

import numpy as np

from .._kernels import edmd as _k

# the most species whose partial g(r) a sampler records (their pair histograms cost S (S + 1) / 2 a block)
PARTIAL_RDF_SPECIES = 4

def pair_histogram(system, r_max, bins):
    """Counts of pairs (each counted twice) per distance bin up to r_max, in one snapshot.

    The snapshot is taken half-way to the next event, not at the last one:
    there the pair that just collided sits exactly at contact, one extra
    contact pair a snapshot (12 % of the contact bin for 400 discs).
    """
    points, offset = _snapshot(system)
    return _histogram(points, system, offset, r_max, bins)


def partial_histograms(system, r_max, bins, kinds):
    r"""The ordered pairs (a, b) of species a and b per distance bin, shape (kinds, kinds, bins), in one snapshot.

    ``[a, b]`` counts each particle of a with each of b (a pair of one
    species twice, as :func:`pair_histogram`); the cross counts are what
    the histogram of a and b together holds beyond those of a and b alone,
    halved: :math:`H_{ab} = (C_{a \cup b} - C_a - C_b) / 2`.
    """
    points, offset = _snapshot(system)
    species = np.asarray(system._species)  # in the engine's order, as the snapshot's points
    members = [species == kind for kind in range(kinds)]
    single = [_histogram(points[member], system, offset, r_max, bins) for member in members]
    counts = np.zeros((kinds, kinds, bins))
    for a in range(kinds):
        counts[a, a] = single[a]
        for b in range(a + 1, kinds):
            both = _histogram(points[members[a] | members[b]], system, offset, r_max, bins)
            counts[a, b] = counts[b, a] = 0.5 * (both - single[a] - single[b])
    return counts


def _snapshot(system):
    """The particles' folded positions half-way to the next event (see :func:`pair_histogram`), and the
    Lees-Edwards image offset then (None without shear)."""
    system.synchronise()
    gap = system._time_to_next_event()
    ahead = 0.5 * gap if 0.0 < gap < math.inf else 0.0
    points = system._folded(ahead=ahead)[0][:, : system.dim]
    offset = system._offset_at(system.time + ahead) if system.shear_rate != 0.0 else None
    return points, offset


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


def contact_value(r, g, counts, diameter):
    """g at contact and its standard error: a weighted quadratic fit to the bins
    within 0.1 diameter of contact (5 bins at least), extrapolated to contact (Poisson errors per bin,
    of the pairs: ``counts`` counts each pair twice). Only whole bins beyond contact count: a bin that
    straddles contact is partly inside the core, so partly empty."""
    half_width = 0.5 * (r[1] - r[0]) if len(r) > 1 else 0.0
    # a small species' contact (a tenth of it narrower than 5 bins) is fitted over 5 bins
    reach = max(1.1 * diameter, diameter + 10.0 * half_width)
    near = (r - half_width >= diameter * (1.0 - 1e-12)) & (r < reach) & (counts > 0)
    if near.sum() < 4:
        return math.nan, math.nan
    sigma = g[near] / np.sqrt(0.5 * counts[near])
    x = r[near] - diameter
    coefficients, covariance = np.polyfit(x, g[near], 2, w=1.0 / sigma, cov="unscaled")
    return float(coefficients[-1]), float(math.sqrt(covariance[-1, -1]))
