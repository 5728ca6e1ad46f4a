"""The collision channels a swarm samples: the gas's processes, converted, and the superelastic inverses.

A :class:`Channel` is one column of the kernel's tables: a cross section
(m^2, already multiplied by the species' number fraction and by the share of
the species on the channel's initial level) as a function of the energy, a
constant rate coefficient, a threshold (negative: the energy a superelastic
collision gives), an angular law and the energies where the cross section
has kinks. Channels whose cross section is not piecewise linear between those
energies (a momentum-transfer table under an anisotropic law, a
superelastic inverse) are marked ``curved``; the tables refine their nodes
until linear interpolation meets a tolerance.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy import constants

from .angular import mean_scattering_cosine
from .gases import Gas, Process
from .superelastic import level_populations

EV = constants.e
# below this fraction of the threshold the superelastic cross section of an excitation whose table jumps at its
# threshold (sigma_ex(Delta) > 0, so sigma_sup ~ Delta sigma_ex(Delta) / eps and the rate ~ 1 / sqrt(eps)) is held
# at its value there: the rate stays bounded, and a thermal swarm has a fraction (0.01 Delta / kT)^(3/2) below it
JUMP_FLOOR = 1e-2
# a continuous table (sigma_ex(Delta) = 0): sigma_sup has the finite limit (g0/gk) Delta sigma_ex'(Delta); the
# formula is evaluated this far above zero instead (relative error 1e-9)
LIMIT_FLOOR = 1e-9
MIN_WIDTH = 1e-7  # eV: the narrowest interval the refinement of a curved cross section makes
# anisotropic laws whose momentum-transfer conversion the tables do (screened_coulomb takes integral tables)
CONVERTED_LAWS = ("okhrimovskyy", "vahedi-surendra")


@dataclass(frozen=True)
class Channel:
    """One column of the kernel's tables (energies in eV, cross sections in m^2)."""

    label: str
    kind: str
    species: int
    threshold: float
    const_rate: float
    angular: str
    screening: float
    column: Callable[[np.ndarray], np.ndarray]
    breakpoints: np.ndarray
    curved: bool


def _breakpoints(p: Process) -> np.ndarray:
    """The energies where a table's linear interpolation has a kink or a jump (a node just below a jump)."""
    points = [np.zeros(1)]
    if p.energy.size:
        points.append(p.energy)
        if p.kind != "elastic" and p.energy[0] > 0 and p.cross_section[0] > 0:
            points.append(np.array([np.nextafter(p.energy[0], 0.0)]))
    if p.threshold > 0:
        points.append(np.array([p.threshold]))
    return np.unique(np.concatenate(points))


def _plain(p: Process, scale: float):
    return lambda energy: scale * p.cross_section_at(energy)


def _converted_elastic(p: Process, scale: float, mass: float):
    """sigma_m / (1 - <cos chi>) and, for a rate coefficient k, the cross section k <cos>/((1 - <cos>) g) that makes
    the rate k / (1 - <cos chi>): finite at zero energy, where <cos chi> vanishes like the energy."""
    def column(energy):
        cosine = mean_scattering_cosine(p.scattering, energy)
        speed = np.sqrt(2.0 * np.maximum(energy, 1e-300) * EV / mass)
        extra = np.where(energy > 0.0, p.rate_coefficient * cosine / speed, 0.0)
        return scale * (p.cross_section_at(energy) + extra) / (1.0 - cosine)

    return column


def _superelastic(p: Process, scale: float):
    """(g0/gk) ((e + D)/e) sigma_ex(e + D), held below a floor (see JUMP_FLOOR, LIMIT_FLOOR)."""
    jump = float(p.cross_section_at(p.threshold)) > 0.0
    floor = (JUMP_FLOOR if jump else LIMIT_FLOOR) * p.threshold

    def column(energy):
        e = np.maximum(energy, floor)
        return scale * (e + p.threshold) / e * p.cross_section_at(e + p.threshold) / p.weight_ratio

    shifted = _breakpoints(p) - p.threshold
    return column, np.unique(np.concatenate([[0.0, floor], shifted[shifted > 0.0]]))


def gas_channels(gas: Gas, mass: float, gas_temperature: float) -> list[Channel]:
    """The channels of ``gas`` for a projectile of ``mass`` (kg) at ``gas_temperature`` (K), species by species.

    The gas's processes in order (a reversible excitation on its ground
    level's share), each species followed by the superelastic inverses whose
    level is populated.
    """
    channels = []
    for s, member in enumerate(gas.species):
        fraction = gas.fractions[s]
        ground, levels = level_populations(member, gas_temperature)
        inverses = []
        for p, level in zip(member.processes, levels):
            scale = fraction * (ground if p.reversible else 1.0)
            label = f"{member.name}:{p.label}"
            if p.kind == "elastic" and p.scattering in CONVERTED_LAWS:
                channels.append(Channel(label, p.kind, s, p.threshold, p.rate_coefficient * fraction, p.scattering,
                                        p.screening_energy, _converted_elastic(p, fraction, mass), _breakpoints(p),
                                        True))
            else:
                channels.append(Channel(label, p.kind, s, p.threshold, p.rate_coefficient * scale, p.scattering,
                                        p.screening_energy, _plain(p, scale), _breakpoints(p), False))
            if p.reversible and level > 0.0:
                column, points = _superelastic(p, fraction * level)
                inverses.append(Channel(f"{label} (superelastic)", "superelastic", s, -p.threshold, 0.0,
                                        p.superelastic_scattering, p.screening_energy, column, points, True))
        channels.extend(inverses)
    return channels


def refined_nodes(column, nodes: np.ndarray, top: float, rtol: float, constant_rate: float = 0.0,
                  mass: float = constants.m_e, rounds: int = 60) -> np.ndarray:
    """Nodes (eV) on [0, top] between which linear interpolation of the cross section ``column`` is within ``rtol``.

    The test is on the channel's rate ``sigma(e) g + k`` (``g`` the speed of
    a projectile of ``mass`` at the energy e, ``k`` the channel's
    ``constant_rate``): the midpoint of an interval is added while the
    interpolated cross section there, times ``g``, is further than ``rtol``
    of that rate from the exact one, until no interval fails or they are
    ``MIN_WIDTH`` eV (or 1e-12 of ``top``) wide. (A cross section like sqrt(e)
    near zero, whose relative interpolation error does not fall with the
    interval, is then refined only as far as it matters next to ``k``.)

    Examples
    --------
    >>> import numpy as np
    >>> nodes = refined_nodes(lambda e: 1.0 / (1.0 + e), np.array([0.0, 10.0]), 10.0, 1e-4)
    >>> grid = np.linspace(0, 10, 1001)
    >>> bool(np.max(np.abs(np.interp(grid, nodes, 1 / (1 + nodes)) * (1 + grid) - 1)) < 2e-4)
    True
    """
    nodes = np.unique(np.clip(np.append(nodes, [0.0, top]), 0.0, top))
    for _ in range(rounds):
        values = column(nodes)
        middle = 0.5 * (nodes[:-1] + nodes[1:])
        exact = column(middle)
        speed = np.sqrt(2.0 * middle * EV / mass)
        error = np.abs(exact - 0.5 * (values[:-1] + values[1:])) * speed
        bad = (error > rtol * (np.abs(exact) * speed + constant_rate)) & (np.diff(nodes) > max(MIN_WIDTH, 1e-12 * top))
        if not bad.any():
            break
        nodes = np.unique(np.concatenate([nodes, middle[bad]]))
    return nodes
