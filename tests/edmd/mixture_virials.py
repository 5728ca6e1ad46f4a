"""Exact low-density results of additive hard-sphere and hard-disc mixtures, from Mayer's overlap integrals.

Independent of :mod:`collisionkit.edmd.mixture_theory`: the second and third
virial coefficients and the first-order contact values follow from the
volume (area) two spheres (discs) share, the lens of :func:`lens`
(the cavity function at first order in the density is that overlap:
g_ij(sigma_ij) = 1 + n sum_k x_k |B(sigma_ik) & B(sigma_jk)| at distance sigma_ij).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import integrate


def lens(distance, r1, r2, dim):
    """Volume (dim 3) or area (dim 2) common to balls of radii r1, r2 whose centres are ``distance`` apart."""
    if distance >= r1 + r2:
        return 0.0
    if distance <= abs(r1 - r2):
        return 4.0 / 3.0 * math.pi * min(r1, r2) ** 3 if dim == 3 else math.pi * min(r1, r2) ** 2
    if dim == 3:
        return (math.pi * (r1 + r2 - distance) ** 2 * (distance**2 + 2 * distance * (r1 + r2) - 3 * (r1 - r2) ** 2)
                / (12.0 * distance))
    d = distance
    segments = (r1**2 * math.acos((d * d + r1 * r1 - r2 * r2) / (2 * d * r1))
                + r2**2 * math.acos((d * d + r2 * r2 - r1 * r1) / (2 * d * r2)))
    return segments - 0.5 * math.sqrt((-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2))


def contacts(diameters):
    """sigma_ij = (sigma_i + sigma_j) / 2."""
    diameters = np.asarray(diameters, dtype=float)
    return 0.5 * np.add.outer(diameters, diameters)


def volume_per_particle(fractions, diameters, dim):
    """sum_i x_i v_i: eta / n."""
    fractions, diameters = np.asarray(fractions), np.asarray(diameters)
    return (math.pi / 6.0 if dim == 3 else math.pi / 4.0) * float(np.sum(fractions * diameters**dim))


def second_virial(fractions, diameters, dim):
    """B2 = (2 pi / 3) sum x_i x_j sigma_ij^3 (spheres), (pi / 2) sum x_i x_j sigma_ij^2 (discs)."""
    prefactor = 2.0 * math.pi / 3.0 if dim == 3 else math.pi / 2.0
    return prefactor * float(np.sum(np.outer(fractions, fractions) * contacts(diameters) ** dim))


def third_virial(fractions, diameters, dim):
    """B3 = sum x_i x_j x_k B_ijk, B_ijk = (1/3) int_{r < sigma_ij} lens(r; sigma_ik, sigma_jk) d^d r: the three
    Mayer bonds are all -1 when k overlaps both i and j and j overlaps i."""
    sigma = contacts(diameters)
    surface = (lambda r: 4.0 * math.pi * r**2) if dim == 3 else (lambda r: 2.0 * math.pi * r)
    total = 0.0
    for i, j, k in np.ndindex(len(fractions), len(fractions), len(fractions)):
        shell = integrate.quad(lambda r: surface(r) * lens(r, sigma[i, k], sigma[j, k], dim), 0.0, sigma[i, j],
                               epsabs=0, epsrel=1e-12, limit=200)[0]
        total += fractions[i] * fractions[j] * fractions[k] * shell / 3.0
    return total


def first_order_contacts(fractions, diameters, dim):
    """The (S, S) slopes c_ij of g_ij(sigma_ij) = 1 + c_ij n + O(n^2)."""
    sigma = contacts(diameters)
    size = len(fractions)
    return np.array([[sum(fractions[k] * lens(sigma[i, j], sigma[i, k], sigma[j, k], dim) for k in range(size))
                      for j in range(size)] for i in range(size)])
