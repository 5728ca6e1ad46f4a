"""A swarm's starting energy: the mean energy at which the swarm's power balance closes.

The swarm relaxes from its initial Maxwellian to the steady state; the
closer the start, the shorter the transient (in argon the energy relaxes by
elastic collisions only below the first excitation, ~M/(2m) = 4e4
collisions). The guess takes the swarm Maxwellian at a mean energy eps
(k T_e = 2 eps / 3; averages <.> over it), with the momentum-transfer
frequency nu = <N sum_j (sigma_j(e) v + k_j)>, and finds the eps at which the
power the field gives equals the power the collisions take:

    F^2 nu / (m (nu^2 + omega_c^2)) = <sum_elastic (2 m / M_s) nu_j (e - 3/2 k T)>
                                      + <sum_inelastic nu_j e_j>,

with F = |q E + m g| (the drift W = F nu / (m (nu^2 + omega_c^2)) of the
momentum balance, the power F . W) and e_j the thresholds (negative for
superelastic processes): the momentum and energy balance equations of
swarm theory closed by a Maxwellian (e.g. Robson, White & Petrovic,
Fundamentals of Charged Particle Transport in Gases and Condensed Matter
(2017), ch. 5). Averaging over the Maxwellian's tail lets inelastic losses
act below their thresholds, as they do in a real swarm: on Reid's ramp, the
Lucas-Saelee model, argon and N2 the guess lands within about 35 % of the
steady mean energy, which is all a starting point needs. With no field the
answer is 3/2 k T.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import constants

from .._kernels import transport as _k

EV = constants.e
GRID_POINTS = 300  # mean energies tried between 3/2 kT (or 1 meV) and a tenth of the quadrature's top
TOP_ENERGY = 1e4  # eV: the quadrature reaches this or the tables' top, whichever is higher
QUADRATURE_POINTS = 2000  # energies of the Maxwellian averages
CHUNK = 20  # mean energies averaged at a time
FALLBACK = 1.0  # eV, when no energy balances (a runaway regime): the old fixed start


def balanced_energy(tables, density, force, magnetic, mass, gas_temperature) -> float:
    """The mean energy (eV) of the Maxwellian at which the swarm's power balance closes.

    Parameters
    ----------
    tables : KernelTables
        The gas's kernel tables (:func:`._tables.build_tables`).
    density : float
        Gas number density (m^-3).
    force : float
        Magnitude of the force on the particle, |q E + m g| (N).
    magnetic : float
        Cyclotron frequency |q B| / m (rad/s) of the magnetic field's
        component perpendicular to the force.
    mass : float
        Particle mass (kg).
    gas_temperature : float
        Gas temperature (K).

    Returns
    -------
    float
        The lowest mean energy where the losses catch up with the heating,
        in eV; 3/2 k T with no force; ``FALLBACK`` if the heating wins up to
        a tenth of the quadrature's top.

    Examples
    --------
    The Maxwell model (constant frequency nu, elastic only) closes the
    balance at eps - 3/2 kT = M F^2 / (2 m^2 nu^2) (Wannier's relation with
    mu ~ m):

    >>> from scipy import constants
    >>> from collisionkit.transport import maxwell_model
    >>> from collisionkit.transport._tables import build_tables
    >>> me, amu = constants.m_e, constants.atomic_mass
    >>> tables = build_tables(maxwell_model(1e-13, mass=4 * amu), me, 0.0)
    >>> force = constants.e * 10e-21 * 1e24  # 10 Td at N = 1e24 m^-3
    >>> eps = balanced_energy(tables, 1e24, force, 0.0, me, 0.0)
    >>> exact = 4 * amu * force**2 / (2 * me**2 * (1e-13 * 1e24) ** 2) / constants.e
    >>> abs(eps / exact - 1) < 0.02
    True
    """
    thermal = 1.5 * constants.k * gas_temperature
    if force == 0.0:
        return thermal / EV if thermal > 0.0 else FALLBACK
    # quadrature nodes of the energy (a fine log grid) and the per-process frequencies on them
    top = max(tables.nodes[-1], TOP_ENERGY * EV)  # tables hold their last value beyond their last node
    grid = np.geomspace(1e-4 * EV, top, QUADRATURE_POINTS)
    speed = np.sqrt(2.0 * grid / mass)
    frequencies = np.empty((grid.size, tables.kind.size))
    for j in range(tables.kind.size):
        sigma = np.interp(grid, tables.nodes, tables.sigma[:, j])
        frequencies[:, j] = density * (np.where(grid >= tables.threshold[j], sigma * speed, 0.0)
                                       + tables.const_rate[j])
    target_mass = tables.gas[tables.species_of, 0]
    elastic = tables.kind == _k.ELASTIC
    elastic_weight = (frequencies[:, elastic] * (2.0 * mass / target_mass[elastic])).sum(axis=1)
    inelastic_power = (frequencies[:, ~elastic] * tables.threshold[~elastic]).sum(axis=1)
    total = frequencies.sum(axis=1)
    # Maxwellians of mean energy eps (kT_e = 2 eps / 3): weights sqrt(e) exp(-e / kT_e) de on the grid
    means = np.geomspace(max(thermal, 1e-3 * EV), top / 10.0, GRID_POINTS)
    columns = np.column_stack([total, elastic_weight * (grid - thermal) + inelastic_power])
    averages = np.empty((means.size, 2))
    measure = np.sqrt(grid) * np.gradient(grid)
    for lo in range(0, means.size, CHUNK):  # a few rows at a time: the full table would be 5 MB of temporaries
        weights = measure * np.exp(-grid / (2.0 * means[lo:lo + CHUNK, None] / 3.0))
        averages[lo:lo + CHUNK] = (weights @ columns) / weights.sum(axis=1, keepdims=True)
    nu, loss = averages[:, 0], averages[:, 1]
    heating = force**2 * nu / (mass * (nu**2 + magnetic**2))
    cooling = np.nonzero(heating <= loss)[0]
    if cooling.size == 0:
        return FALLBACK
    k = int(cooling[0])
    if k == 0:
        return means[0] / EV
    # the crossing between grid points k - 1 and k, linear in the power difference
    before, after = heating[k - 1] - loss[k - 1], heating[k] - loss[k]
    share = before / (before - after)
    energies = means
    return float(math.exp(math.log(energies[k - 1]) + share * math.log(energies[k] / energies[k - 1])) / EV)
