"""The gas's collisions as the discrete operators of the two-term equation (:mod:`collisionkit.transport.two_term`).

:func:`gas_collisions` turns every process into what the equation needs on
any grid: its share of the gas, its momentum-transfer cross section and
:class:`~._two_term_operators.CrossSectionIntegral`; the levels of reversible
excitations are populated at the gas temperature as the swarm does it, and
their superelastic inverses added. :func:`collision_operator` assembles, on
one grid, the inelastic operator (gains minus losses per cell) and the net
production of electrons (ionization minus attachment).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse

from ._tables import _unique
from ._two_term_operators import GAMMA, CrossSectionIntegral, ShiftedIntegral, transfer_matrix
from .angular import screened_coulomb_momentum_ratio
from .gases import ELECTRON_MASS
from .superelastic import BOLTZMANN_EV, level_populations


@dataclass
class Collisions:
    """The gas's processes as energy integrals and transfer matrices, on one grid."""

    mass_ratios: list  # (fraction x, 2 m / M, momentum-transfer sigma(eps) callable) of each elastic process
    momentum: list  # (x, sigma_m(eps) callable) of every process (the inelastic ones isotropic)
    channels: list  # (label, kind, share of the gas (x times the level's population), integral, threshold, g_k/g_0)


def _populations(gas, kT):
    """Per species: (ground fraction, excited fraction of each process)."""
    temperature = kT / BOLTZMANN_EV
    return [level_populations(species, temperature) for species in gas.species]


def _momentum_sigma(process):
    """sigma_m(eps) of one process: the table (elastic: momentum transfer, or the screened Coulomb integral cross
    section times its ratio) plus k / (gamma sqrt(eps))."""
    def sigma(energy):
        energy = np.asarray(energy, float)
        value = process.cross_section_at(energy) if process.energy.size else np.zeros_like(energy)
        if process.kind == "elastic" and process.scattering == "screened_coulomb":
            value = value * screened_coulomb_momentum_ratio(energy, process.screening_energy)
        if process.rate_coefficient:
            with np.errstate(divide="ignore"):
                value = value + process.rate_coefficient / (GAMMA * np.sqrt(energy))
        return value
    return sigma


def gas_collisions(gas, kT) -> Collisions:
    """The gas's processes, with the level populations at kT."""
    populations = _populations(gas, kT)
    mass_ratios, momentum, channels = [], [], []
    for s, (species, x) in enumerate(zip(gas.species, gas.fractions)):
        ground, levels = populations[s]
        for j, process in enumerate(species.processes):
            sigma_m = _momentum_sigma(process)
            if process.kind == "elastic":
                mass_ratios.append((x, 2.0 * ELECTRON_MASS / species.mass, sigma_m))
                momentum.append((x, sigma_m))
                continue
            share = x * (ground if process.reversible else 1.0)
            momentum.append((share, sigma_m))
            points = np.concatenate([[0.0, process.threshold], process.energy])
            integral = CrossSectionIntegral(process.cross_section_at, points, process.rate_coefficient)
            label = f"{species.name}:{process.label}"
            channels.append((label, process.kind, share, integral, process.threshold, process.weight_ratio))
            if process.reversible and levels[j] > 0.0:
                channels.append((f"{label} (superelastic)", "superelastic", x * levels[j], integral,
                                 process.threshold, process.weight_ratio))
                momentum.append((x * levels[j], _superelastic_sigma(process)))
    labels = _unique([channel[0] for channel in channels])
    channels = [(label, *channel[1:]) for label, channel in zip(labels, channels)]
    return Collisions(mass_ratios, momentum, channels)


def _superelastic_sigma(process):
    def sigma(energy):
        energy = np.asarray(energy, float)
        with np.errstate(divide="ignore", invalid="ignore"):
            value = (energy + process.threshold) / energy * process.cross_section_at(energy + process.threshold)
        return np.where(energy > 0, value / process.weight_ratio, 0.0)
    return sigma


def collision_operator(collisions, edges, sharing):
    """The inelastic operator (gains minus losses per cell, per unit F0 of each cell) and the row vector of net
    electron production per unit F0 (ionization minus attachment)."""
    n = edges.size - 1
    low, high = edges[:-1], edges[1:]
    operator = sparse.csr_matrix((n, n))
    production = np.zeros(n)
    for _, kind, share, integral, threshold, weight_ratio in collisions.channels:
        scale = GAMMA * share
        if kind == "superelastic":
            # from eps to eps + u at the rate gamma (eps + u) sigma_ex(eps + u) / (g_k/g_0) F0(eps)
            shifted = ShiftedIntegral(integral, threshold)
            loss = scale / weight_ratio * shifted(low, high)
            gain = transfer_matrix(shifted, edges, low - threshold, high - threshold, scale / weight_ratio)
            operator = operator + gain - sparse.diags(loss)
            continue
        loss = scale * integral(low, high)
        operator = operator - sparse.diags(loss)
        if kind == "excitation":
            operator = operator + transfer_matrix(integral, edges, low + threshold, high + threshold, scale)
        elif kind == "ionization":
            operator = operator + _ionization_gain(integral, edges, threshold, scale, sharing)
            production += loss
        else:  # attachment: the electron is lost
            production -= loss
    return operator.tocsr(), production


def _ionization_gain(integral, edges, threshold, scale, sharing):
    """Gains of an ionization: both electrons, (eps' - u) shared equally or uniformly."""
    low, high = edges[:-1], edges[1:]
    if sharing == "equal":  # each gets (eps' - u) / 2: cell i is fed by eps' in [2 low + u, 2 high + u], twice
        return transfer_matrix(integral, edges, 2.0 * low + threshold, 2.0 * high + threshold, scale, 2.0)
    return _uniform_sharing_gain(integral, edges, threshold, scale)


def _uniform_sharing_gain(integral, edges, threshold, scale):
    """Gains when each electron gets a uniform share of eps' - u: from source cell j, cell i receives
    2 (length of cell i below eps' - u) / (eps' - u) per collision (Gauss-Legendre over each source cell's part
    above the threshold, each column scaled to give exactly twice the source's collisions)."""
    width = edges[1] - edges[0]
    start = np.maximum(edges[:-1], threshold)
    length = edges[1:] - start
    sources = np.nonzero(length > 1e-9 * width)[0]
    nodes, weights = np.polynomial.legendre.leggauss(8)
    gain = np.zeros((edges.size - 1, sources.size))
    for node, weight in zip(nodes, weights):
        points = start[sources] + length[sources] * (node + 1.0) / 2.0
        available = points - threshold
        share = np.clip(available[None, :] - edges[:-1, None], 0.0, width) / available[None, :]
        gain += share * (0.5 * length[sources] * weight * integral.integrand(points))[None, :]
    exact = integral(start[sources], edges[1:][sources])
    totals = gain.sum(axis=0)
    gain *= 2.0 * scale * np.where(totals > 0, exact / np.where(totals > 0, totals, 1.0), 0.0)[None, :]
    rows, columns = np.nonzero(gain)
    return sparse.csr_matrix((gain[rows, columns], (rows, sources[columns])), shape=(edges.size - 1,) * 2)
