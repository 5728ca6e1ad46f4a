"""Square-well fluid theory: virial coefficients, and the dilute gas's transport (Chapman-Enskog).

The pair potential is u(r) = inf for r < sigma, -epsilon for sigma <= r <
lambda sigma and 0 beyond (``width`` lambda, ``depth`` epsilon,
``diameter`` sigma); the references a square-well EDMD run is checked
against (see :class:`~collisionkit.edmd.HardSphereSystem`'s
``well_width``).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import integrate

from . import _checks

__all__ = [
    "square_well_collision_integral",
    "square_well_deflection",
    "square_well_dilute_transport",
    "square_well_low_density",
    "square_well_mixture_second_virial",
    "square_well_second_virial",
    "square_well_third_virial",
]


def _well_excess(width, kT, depth):
    """(lambda, x = exp(epsilon / kT) - 1) of square wells, checked: lambda > 1, kT > 0, epsilon > 0."""
    width = _checks.bounded(width, "width", 1.0, closed=(False, False))
    kT = _checks.positive(kT, "kT")
    depth = _checks.positive(depth, "depth")
    return width, math.expm1(depth / kT)


def square_well_second_virial(width, kT, dim=3, diameter=1.0, depth=1.0):
    r"""Second virial coefficient of square wells: :math:`B_2 = b_0 [1 - x (\lambda^d - 1)]`, exact.

    From :math:`B_2 = -\frac{1}{2} \int f(r)\, d^d r` with the Mayer function
    f = -1 inside the core and :math:`x = e^{\epsilon / kT} - 1` in the
    well; :math:`b_0 = 2 \pi \sigma^3 / 3` (spheres) or :math:`\pi \sigma^2 / 2`
    (discs). ``width`` is lambda (> 1), ``depth`` epsilon.

    Examples
    --------
    >>> round(square_well_second_virial(1.5, 2.0), 5)   # T* = 2: attraction wins, B2 < 0
    -1.13247
    """
    width, x = _well_excess(width, kT, depth)
    dim = _checks.integer_at_least(dim, "dim", 2)
    if dim not in (2, 3):
        raise ValueError(f"dim must be 2 or 3; got {dim}")
    diameter = _checks.positive(diameter, "diameter")
    b0 = 2.0 * math.pi * diameter**3 / 3.0 if dim == 3 else math.pi * diameter**2 / 2.0
    return b0 * (1.0 - x * (width**dim - 1.0))


def square_well_mixture_second_virial(fractions, kT, widths, depths, diameters=1.0, dim=3):
    r"""Second virial coefficient of a square-well mixture: :math:`B_2 = \sum_{ab} x_a x_b B_2^{ab}`, exact.

    :math:`B_2^{ab}` is :func:`square_well_second_virial` of the pair's
    contact distance sigma_ab (``diameters``, e.g. r_a + r_b), width
    lambda_ab and depth epsilon_ab (a depth of 0: hard cores only); each of
    ``widths``, ``depths``, ``diameters`` is a number or a symmetric (S, S)
    matrix, ``fractions`` the S mole fractions (normalised here). Then
    :math:`Z = 1 + B_2 \rho + O(\rho^2)` (McQuarrie, *Statistical
    Mechanics*, sec. 12-6).

    Examples
    --------
    >>> one = square_well_second_virial(1.5, 2.0)
    >>> bool(abs(square_well_mixture_second_virial([0.3, 0.7], 2.0, 1.5, 1.0) - one) < 1e-12)   # alike species
    True
    >>> round(square_well_mixture_second_virial([0.5, 0.5], 2.0, 1.5, [[1.0, 0.0], [0.0, 1.0]]), 5)  # no A-B well
    0.48096
    """
    fractions = np.asarray(fractions, dtype=float)
    if fractions.ndim != 1 or fractions.size < 1 or not np.all(np.isfinite(fractions) & (fractions >= 0)) \
            or not fractions.sum() > 0:
        raise ValueError(f"fractions must be a sequence of mole fractions >= 0, some > 0; got {fractions!r}")
    fractions = fractions / fractions.sum()
    size = fractions.size
    kT = _checks.positive(kT, "kT")
    if dim not in (2, 3):
        raise ValueError(f"dim must be 2 or 3; got {dim!r}")
    widths, depths, diameters = (_pair_table(value, name, size) for value, name in
                                 ((widths, "widths"), (depths, "depths"), (diameters, "diameters")))
    if not (np.all(diameters > 0.0) and np.all(depths >= 0.0) and np.all((widths > 1.0) | (depths == 0.0))):
        raise ValueError("diameters must be > 0, depths >= 0 and widths > 1 where a pair has a well")
    total = 0.0
    for a in range(size):
        for b in range(size):
            if depths[a, b] == 0.0:  # hard cores only: b0, whatever the well's width
                pair = (2.0 * math.pi * diameters[a, b] ** 3 / 3.0 if dim == 3 else math.pi * diameters[a, b] ** 2 / 2.0)
            else:
                pair = square_well_second_virial(widths[a, b], kT, dim, diameters[a, b], depths[a, b])
            total += fractions[a] * fractions[b] * pair
    return float(total)


def _pair_table(value, name, size):
    """A number or a symmetric (size, size) matrix of finite numbers as a (size, size) array."""
    array = np.asarray(value, dtype=float)
    if array.ndim not in (0, 2) or (array.ndim == 2 and array.shape != (size, size)):
        raise ValueError(f"{name} must be a number or a ({size}, {size}) matrix; got shape {array.shape}")
    table = np.broadcast_to(array, (size, size))
    if not (np.all(np.isfinite(table)) and np.array_equal(table, table.T)):
        raise ValueError(f"{name} must hold finite numbers, symmetric in the species")
    return table


def _kihara_polynomial(width):
    """Coefficients c0..c3 of 8 B3 / b0^2 = sum c_k x^k for spheres with wells of width lambda <= 2."""
    lam = width
    return (5.0, -(lam**6 - 18 * lam**4 + 32 * lam**3 - 15), -(2 * lam**6 - 36 * lam**4 + 32 * lam**3 + 18 * lam**2 - 16),
            -(6 * lam**6 - 18 * lam**4 + 18 * lam**2 - 6))


def square_well_third_virial(width, kT, diameter=1.0, depth=1.0):
    r"""Third virial coefficient of square-well spheres, 1 < lambda <= 2 (Kihara's polynomial).

    :math:`B_3 / b_0^2 = \frac{1}{8} [5 - c_1 x - c_2 x^2 - c_3 x^3]` with
    :math:`c_1 = \lambda^6 - 18 \lambda^4 + 32 \lambda^3 - 15`,
    :math:`c_2 = 2 \lambda^6 - 36 \lambda^4 + 32 \lambda^3 + 18 \lambda^2 - 16`,
    :math:`c_3 = 6 \lambda^6 - 18 \lambda^4 + 18 \lambda^2 - 6` and
    :math:`x = e^{\epsilon / kT} - 1` (T. Kihara, 1943; J. A. Barker and
    D. Henderson, J. Chem. Phys. 47, 4714 (1967); Hirschfelder, Curtiss &
    Bird, *Molecular Theory of Gases and Liquids*, 1954). Hard spheres (x = 0):
    :math:`5 b_0^2 / 8`.

    Examples
    --------
    >>> round(square_well_third_virial(1.5, 2.0), 5)
    2.49181
    """
    width, x = _well_excess(width, kT, depth)
    if width > 2.0:
        raise ValueError(f"width must be in (1, 2] (Kihara's polynomial holds there); got {width}")
    b0 = 2.0 * math.pi * _checks.positive(diameter, "diameter") ** 3 / 3.0
    return b0**2 * sum(c * x**k for k, c in enumerate(_kihara_polynomial(width))) / 8.0


def square_well_low_density(density, kT, width, diameter=1.0, depth=1.0):
    r"""Z and the potential energy per particle of square-well spheres to second order in the density.

    :math:`Z = 1 + B_2 \rho + B_3 \rho^2` and, from
    :math:`\beta A_{ex} / N = B_2 \rho + B_3 \rho^2 / 2` with
    :math:`dx / d\beta = \epsilon (1 + x)`,
    :math:`U / N = \epsilon (1 + x) [\rho\, dB_2/dx + \frac{\rho^2}{2} dB_3/dx]`
    (:func:`square_well_second_virial`, :func:`square_well_third_virial`;
    1 < lambda <= 2). The terms left out are :math:`O(\rho^3)`: about 1e-4 at
    :math:`\rho \sigma^3 = 0.05`.

    Returns
    -------
    (float, float)
        Z and U/N.

    Examples
    --------
    >>> z, energy = square_well_low_density(0.05, 2.0, 1.5)
    >>> round(z, 5), round(energy, 5)
    (0.94961, -0.40222)
    """
    density = _checks.bounded(density, "density", 0.0)
    width, x = _well_excess(width, kT, depth)
    b2 = square_well_second_virial(width, kT, 3, diameter, depth)
    b3 = square_well_third_virial(width, kT, diameter, depth)
    b0 = 2.0 * math.pi * diameter**3 / 3.0
    b2_slope = -b0 * (width**3 - 1.0)
    b3_slope = b0**2 * sum(k * c * x ** (k - 1) for k, c in enumerate(_kihara_polynomial(width)) if k) / 8.0
    z = 1.0 + b2 * density + b3 * density**2
    return z, depth * (1.0 + x) * (density * b2_slope + 0.5 * density**2 * b3_slope)


def square_well_deflection(impact, energy, width, diameter=1.0, depth=1.0):
    r"""Deflection angle chi of a pair scattered by square wells, at impact parameter b and relative energy E.

    Outside lambda sigma the path is straight; crossing the edge the relative
    speed grows by :math:`n = \sqrt{1 + \epsilon / E}` and the angular
    momentum is kept, so inside the path is straight with impact parameter
    b / n. With :math:`\theta_0 = \int_{r_{min}}^\infty b\, dr / (r^2
    \sqrt{1 - b^2/r^2 - u(r)/E})` and :math:`\chi = \pi - 2 \theta_0`
    (Hirschfelder, Curtiss & Bird, *Molecular Theory of Gases and Liquids*,
    sec. 1.5; Chapman & Cowling, sec. 3.44), R = lambda sigma:

    - b >= R: chi = 0;
    - b < n sigma (the cores touch):
      :math:`\chi = \pi - 2 [\arcsin(b/R) + \arcsin(b/(n\sigma)) - \arcsin(b/(nR))]`;
    - else (through the well only): :math:`\chi = 2 \arcsin(b/(nR)) - 2 \arcsin(b/R)` (< 0: attracted).

    Examples
    --------
    >>> square_well_deflection(0.0, 1.0, 1.5) == math.pi   # head on: straight back
    True
    >>> round(square_well_deflection(1.4, 1.0, 1.5), 5)    # grazes through the well, bent towards the partner
    -0.68183
    """
    impact = _checks.bounded(impact, "impact", 0.0)
    energy, diameter, depth = (_checks.positive(value, name) for value, name in
                               ((energy, "energy"), (diameter, "diameter"), (depth, "depth")))
    width = _checks.bounded(width, "width", 1.0, closed=(False, False))
    outer = width * diameter
    if impact >= outer:
        return 0.0
    n = math.sqrt(1.0 + depth / energy)
    entry, inner = math.asin(impact / outer), math.asin(impact / (n * outer))
    if impact < n * diameter:
        return math.pi - 2.0 * (entry + math.asin(impact / (n * diameter)) - inner)
    return 2.0 * (inner - entry)


def _cross_section(order, energy, width, diameter, depth):
    r""":math:`Q^{(l)}(E) = 2\pi \int_0^{\lambda\sigma} (1 - \cos^l \chi)\, b\, db`, split where chi has kinks."""
    outer = width * diameter
    touching = min(outer, math.sqrt(1.0 + depth / energy) * diameter)

    def integrand(b):
        return (1.0 - math.cos(square_well_deflection(b, energy, width, diameter, depth)) ** order) * b

    floor = 1e-13 * outer * outer  # absolute tolerance: the integrand vanishes as the wells stop mattering
    total = integrate.quad(integrand, 0.0, touching, epsabs=floor, epsrel=1e-10, limit=200)[0]
    if touching < outer:
        total += integrate.quad(integrand, touching, outer, epsabs=floor, epsrel=1e-10, limit=200)[0]
    return 2.0 * math.pi * total


def square_well_collision_integral(order, power, kT, width, diameter=1.0, depth=1.0, mass=1.0):
    r"""The Chapman-Enskog collision integral :math:`\Omega^{(l,s)}(T)` of square wells, equal masses m.

    :math:`\Omega^{(l,s)} = \sqrt{kT / (2 \pi \mu)} \int_0^\infty e^{-\gamma^2}
    \gamma^{2s+3} Q^{(l)}(\gamma^2 kT)\, d\gamma` with :math:`\mu = m / 2` and
    the cross-section :math:`Q^{(l)}` of :func:`square_well_deflection`,
    by adaptive quadrature (relative error about 1e-9) (Hirschfelder,
    Curtiss & Bird, eq. 7.4-34 to 7.4-36). Hard spheres (depth -> 0):
    :math:`\Omega^{(2,2)} = 2 \sigma^2 \sqrt{\pi kT / m}`.

    Examples
    --------
    >>> hard = 2.0 * math.sqrt(math.pi)
    >>> round(square_well_collision_integral(2, 2, 1.0, 1.5, depth=1e-9) / hard, 6)
    1.0
    >>> round(square_well_collision_integral(2, 2, 1.0, 1.5) / hard, 4)   # T* = 1: wells widen the collisions
    1.4748
    """
    order = _checks.integer_at_least(order, "order", 1)
    power = _checks.integer_at_least(power, "power", 1)
    kT, diameter, depth, mass = (_checks.positive(value, name) for value, name in
                                 ((kT, "kT"), (diameter, "diameter"), (depth, "depth"), (mass, "mass")))
    width = _checks.bounded(width, "width", 1.0, closed=(False, False))

    def integrand(gamma):
        if gamma == 0.0:
            return 0.0
        return math.exp(-gamma * gamma) * gamma ** (2 * power + 3) * _cross_section(
            order, gamma * gamma * kT, width, diameter, depth)

    # the weight is below 1e-300 of its peak beyond gamma = 27
    value = integrate.quad(integrand, 0.0, 27.0, epsabs=1e-13 * (width * diameter) ** 2, epsrel=1e-9, limit=200)[0]
    return math.sqrt(kT / (math.pi * mass)) * value


def square_well_dilute_transport(kT, width, diameter=1.0, depth=1.0, mass=1.0):
    r"""Shear viscosity and thermal conductivity of the dilute square-well gas (Chapman-Enskog), as a dict.

    Second Sonine approximations from :math:`\Omega^{(2,2)}, \Omega^{(2,3)},
    \Omega^{(2,4)}` (:func:`square_well_collision_integral`):
    :math:`\eta = \frac{5 kT}{8 \Omega^{(2,2)}} (1 + \frac{b_{12}^2}{b_{11}
    b_{22} - b_{12}^2})`, :math:`\lambda = \frac{15}{4} \frac{k}{m} \frac{5
    kT}{8 \Omega^{(2,2)}} (1 + \frac{a_{12}^2}{a_{11} a_{22} - a_{12}^2})` with
    :math:`a_{11} = b_{11} = 4 \Omega^{(2,2)}`, :math:`a_{12} = b_{12} = 7
    \Omega^{(2,2)} - 2 \Omega^{(2,3)}`, :math:`b_{22} = \frac{301}{12}
    \Omega^{(2,2)} - 7 \Omega^{(2,3)} + \Omega^{(2,4)}`, :math:`a_{22} =
    \frac{77}{4} \Omega^{(2,2)} - 7 \Omega^{(2,3)} + \Omega^{(2,4)}` (Chapman &
    Cowling, *The Mathematical Theory of Non-uniform Gases*, 3rd ed., sec.
    9.7 and 10.2; Hirschfelder, Curtiss & Bird, sec. 7.3). For hard spheres
    the factors are 1.0148 and 1.0227 (the limits 1.016 and 1.025). The
    gas is taken to scatter only: pairs bound in their wells (a fraction
    of order n B_2 of the pairs) are left out, as are the density's
    corrections (Enskog's for hard spheres: 0.4 % at n sigma^3 = 0.01).

    Examples
    --------
    >>> dilute = square_well_dilute_transport(1.0, 1.5)
    >>> round(dilute["shear_viscosity"], 4), round(dilute["thermal_conductivity"] / dilute["shear_viscosity"], 3)
    (0.12, 3.757)
    """
    omega = [square_well_collision_integral(2, power, kT, width, diameter, depth, mass) for power in (2, 3, 4)]
    first = 5.0 * kT / (8.0 * omega[0])
    off_diagonal = 7.0 * omega[0] - 2.0 * omega[1]
    viscosity_22 = 301.0 / 12.0 * omega[0] - 7.0 * omega[1] + omega[2]
    conductivity_22 = 77.0 / 4.0 * omega[0] - 7.0 * omega[1] + omega[2]
    diagonal = 4.0 * omega[0]
    square = off_diagonal * off_diagonal
    return {
        "shear_viscosity": first * (1.0 + square / (diagonal * viscosity_22 - square)),
        "thermal_conductivity": 3.75 / mass * first * (1.0 + square / (diagonal * conductivity_22 - square)),
    }
