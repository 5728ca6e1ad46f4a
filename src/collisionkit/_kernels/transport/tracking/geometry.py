"""Surfaces that bound the tracking volume: planes, cylinders and spheres, with their signed distances.

A surface row (``SURFACE_COLUMNS`` floats): kind, action, then

* plane: a point (2:5) and the unit normal pointing into the volume (5:8):
  f = (r - p) . n;
* cylinder: a point of the axis (2:5), the unit axis (5:8), the radius (8)
  and the side (9: +1 the volume is inside, -1 outside):
  f = side (R - rho), rho the distance from the axis;
* sphere: the centre (2:5), the radius (8), the side (9): f = side (R - |r - c|).

The volume is where every f >= 0; f is a signed distance (exact for planes,
cylinders and spheres), so a step that ends with some f < 0 crossed that
surface.
"""

from __future__ import annotations

import math

from ...._jit import inline_kernel
from .codes import CYLINDER, PLANE


@inline_kernel
def surface_value(surfaces, k, x, y, z):
    """Signed distance of (x, y, z) from surface ``k``: >= 0 inside the volume."""
    row = surfaces[k]
    dx = x - row[2]
    dy = y - row[3]
    dz = z - row[4]
    if row[0] == PLANE:
        return dx * row[5] + dy * row[6] + dz * row[7]
    if row[0] == CYLINDER:
        along = dx * row[5] + dy * row[6] + dz * row[7]
        px = dx - along * row[5]
        py = dy - along * row[6]
        pz = dz - along * row[7]
        return row[9] * (row[8] - math.sqrt(px * px + py * py + pz * pz))
    return row[9] * (row[8] - math.sqrt(dx * dx + dy * dy + dz * dz))


@inline_kernel
def lowest_surface(surfaces, x, y, z):
    """(smallest signed distance, its surface) over all surfaces; (inf, -1) without any."""
    lowest = math.inf
    which = -1
    for k in range(surfaces.shape[0]):
        f = surface_value(surfaces, k, x, y, z)
        if f < lowest:
            lowest = f
            which = k
    return lowest, which


@inline_kernel
def surface_normal(surfaces, k, x, y, z):
    """A unit normal of surface ``k`` at (x, y, z) (its sign does not matter for a reflection), a tuple."""
    row = surfaces[k]
    if row[0] == PLANE:
        return row[5], row[6], row[7]
    dx = x - row[2]
    dy = y - row[3]
    dz = z - row[4]
    if row[0] == CYLINDER:
        along = dx * row[5] + dy * row[6] + dz * row[7]
        dx -= along * row[5]
        dy -= along * row[6]
        dz -= along * row[7]
    norm = math.sqrt(dx * dx + dy * dy + dz * dz)
    if norm == 0.0:
        return 0.0, 0.0, 1.0
    return dx / norm, dy / norm, dz / norm
