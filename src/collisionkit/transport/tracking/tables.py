"""The gas tables of a tracking run: the swarm's kernel tables plus each species' total collision rate.

The null-collision method uses the swarm tables as they are
(:func:`collisionkit.transport._tables.build_tables`). The path-length
method integrates the total collision frequency nu(v) of the projectile's
lab speed along the trajectory:

* for a projectile much lighter than every target (m/M < ``THERMAL_MASS_RATIO``,
  electrons), the targets' thermal motion is left out of the *rate*,
  nu = N (sigma_s(eps) v + k_s) with eps = m v^2 / 2 (its relative effect is
  of order (kT/M) / v^2, below 1e-5 for electrons above 0.01 eV in a gas at
  300 K); the target velocity of a collision is still drawn from the gas
  Maxwellian, in proportion to sigma(g) g (rejection), so the kinematics are
  exact;
* otherwise the rate averaged over the Maxwellian of each species,
  <sigma(g) g> + k = integral of p(g|v) sigma(g) g dg with
  p(g|v) = (g / (sqrt(2 pi) s v)) [exp(-(g - v)^2 / 2s^2) - exp(-(g + v)^2 / 2s^2)]
  (the speed of a Gaussian of variance s^2 = kT/M per axis shifted by v),
  tabulated on ``THERMAL_BINS`` uniform speed bins.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._tables import KernelTables, build_tables
from ..gases import Gas

__all__ = ["TrackingTables", "tracking_tables", "thermal_rates"]

THERMAL_MASS_RATIO = 1e-2
THERMAL_BINS = 4096
QUADRATURE_POINTS = 96
GAS_SPEED_SIGMAS = 10.0


@dataclass(frozen=True)
class TrackingTables:
    """The swarm tables of a projectile in a gas, with per-species totals (and thermal rates) for the path method.

    Examples
    --------
    >>> from collisionkit.transport import reid_ramp
    >>> from collisionkit.transport.tracking.tables import tracking_tables
    >>> tables = tracking_tables(reid_ramp(), 9.1093837e-31, 0.0)
    >>> tables.species_sigma.shape[1], tables.thermal.shape
    (1, (1, 1))
    """

    tables: KernelTables
    species_sigma: np.ndarray
    species_const: np.ndarray
    thermal: np.ndarray
    thermal_step: float

    def arrays(self) -> tuple:
        """The gas arguments of :func:`collisionkit._kernels.transport.tracking.track_particles`, in order.

        Examples
        --------
        >>> from collisionkit.transport import reid_ramp
        >>> len(tracking_tables(reid_ramp(), 9.1093837e-31, 0.0).arrays())
        19
        """
        t = self.tables
        return (t.gas, t.kind, t.species_of, t.threshold, t.const_rate, t.angular, t.screening, t.nodes, t.sigma,
                t.accelerator, t.accelerator_step, t.bound, t.bound_step, t.sigma_max, t.const_max,
                self.species_sigma, self.species_const, self.thermal, self.thermal_step)


def tracking_tables(gas: Gas, mass: float, gas_temperature: float) -> TrackingTables:
    """The tables for a projectile of ``mass`` (kg) in ``gas`` at ``gas_temperature`` (K).

    Examples
    --------
    >>> from collisionkit.transport import maxwell_model
    >>> tables = tracking_tables(maxwell_model(1e-13), 9.1093837e-31, 300.0)
    >>> float(tables.species_const[0])
    1e-13
    """
    tables = build_tables(gas, mass, gas_temperature)
    n_species = tables.gas.shape[0]
    species_sigma = tables.sigma_total  # each species' summed cross section at the nodes
    species_const = np.array([tables.const_rate[tables.species_of == s].sum() for s in range(n_species)])
    thermal, step = np.zeros((1, n_species)), 1.0
    warm = gas_temperature > 0.0 and any(mass / member.mass >= THERMAL_MASS_RATIO for member in gas.species)
    if warm:
        thermal, step = thermal_rates(tables, species_sigma, species_const, mass)
    return TrackingTables(tables, np.ascontiguousarray(species_sigma), species_const, np.ascontiguousarray(thermal),
                          float(step))


def _cold_rate(speeds, tables, species_sigma, species_const, mass, s):
    energy = 0.5 * mass * speeds**2
    sigma = np.interp(energy, tables.nodes, species_sigma[:, s])
    return sigma * speeds + species_const[s]


def thermal_rates(tables: KernelTables, species_sigma, species_const, mass: float) -> tuple[np.ndarray, float]:
    """Each species' collision frequency per unit density averaged over its Maxwellian, on uniform speed bins.

    Returns ``(rates, step)``: ``rates[i, s]`` at the lab speed ``i * step``
    (m^3/s), by Gauss-Legendre quadrature of p(g|v) sigma(g) g over
    |g - v| <= 10 s (see the module docstring).

    Examples
    --------
    A constant rate coefficient is its own average:

    >>> from collisionkit.transport import maxwell_model
    >>> from collisionkit.transport._tables import build_tables
    >>> import numpy as np
    >>> tables = build_tables(maxwell_model(1e-13), 6.6e-27, 300.0)
    >>> rates, step = thermal_rates(tables, np.zeros((tables.nodes.size, 1)), np.array([1e-13]), 6.6e-27)
    >>> bool(np.allclose(rates, 1e-13, rtol=1e-9))
    True
    """
    n_species = species_sigma.shape[1]
    thermal = tables.gas[:, 1]
    top = math.sqrt(2.0 * tables.nodes[-1] / mass) + GAS_SPEED_SIGMAS * float(thermal.max())
    step = top / (THERMAL_BINS - 1)
    speeds = np.arange(THERMAL_BINS) * step
    x, w = np.polynomial.legendre.leggauss(QUADRATURE_POINTS)
    rates = np.zeros((THERMAL_BINS, n_species))
    for s in range(n_species):
        sigma_gas = float(thermal[s])
        if sigma_gas == 0.0:
            rates[:, s] = _cold_rate(speeds, tables, species_sigma, species_const, mass, s)
            continue
        low = np.maximum(speeds - GAS_SPEED_SIGMAS * sigma_gas, 0.0)
        high = speeds + GAS_SPEED_SIGMAS * sigma_gas
        g = 0.5 * (high - low)[:, None] * (x[None, :] + 1.0) + low[:, None]  # (bins, points)
        v = np.maximum(speeds, 1e-300)[:, None]
        a = g * v / sigma_gas**2
        # p(g|v) = g / (sqrt(2 pi) s v) [exp(-(g - v)^2 / 2 s^2) - exp(-(g + v)^2 / 2 s^2)], written without
        # cancellation for small g v / s^2 as 2 exp(-(g^2 + v^2) / 2 s^2) sinh(a) with sinh(a)/a -> 1
        small = a < 1e-3
        difference = np.where(small, 2.0 * a * (1.0 + a * a / 6.0) * np.exp(-(g * g + v * v) / (2 * sigma_gas**2)),
                              np.exp(-(g - v) ** 2 / (2 * sigma_gas**2)) - np.exp(-(g + v) ** 2 / (2 * sigma_gas**2)))
        density = g / (math.sqrt(2.0 * math.pi) * sigma_gas * v) * difference
        values = _cold_rate(g, tables, species_sigma, species_const, mass, s)
        rates[:, s] = 0.5 * (high - low) * ((density * values) @ w)
        norm = 0.5 * (high - low) * (density @ w)  # the quadrature of the density itself: 1 up to its error
        rates[:, s] /= norm
    return rates, step
