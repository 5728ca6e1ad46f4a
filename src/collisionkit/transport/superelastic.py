r"""Superelastic collisions (of the second kind) by detailed balance, and the populations of excited levels.

An excitation :math:`0 \to k` of threshold :math:`\Delta` whose statistical
weights have the ratio :math:`g_k/g_0` (``Process.weight_ratio``) has the
inverse :math:`k \to 0`, in which the electron gains :math:`\Delta`. Detailed
balance (Klein & Rosseland, Z. Phys. 4, 46 (1921)) gives its cross section:

.. math::

    \sigma_{sup}(\epsilon) = \frac{g_0}{g_k}\,\frac{\epsilon + \Delta}{\epsilon}\,
    \sigma_{ex}(\epsilon + \Delta).

The swarm collides with the excited level's density :math:`N_k`. By default
the levels are populated as a Boltzmann distribution at the gas temperature
:math:`T_g`, and a species' density :math:`N_s` is split between its ground
level and the upper levels of its reversible excitations (the convention of
LoKI-B and BOLSIG+ for the states of a gas):

.. math::

    \frac{N_k}{N_0} = \frac{g_k}{g_0} e^{-\Delta_k/kT_g}, \qquad
    \frac{N_0}{N_s} = \Bigl(1 + \sum_k \frac{g_k}{g_0} e^{-\Delta_k/kT_g}\Bigr)^{-1},

so a reversible excitation happens on the ground level :math:`N_0` and its
inverse on :math:`N_k`. Every other process (elastic, ionization,
attachment, one-way excitations) is taken to act on the whole species
:math:`N_s` (cross sections that do not depend on the level). A population
set by hand (``Process.population``, :meth:`~collisionkit.transport.Gas.with_populations`)
replaces the Boltzmann value of its level; the ground level keeps what the
set levels leave. At :math:`T_g = 0` the Boltzmann populations vanish and so
do the superelastic collisions (unless populations are set).

At equilibrium (no field) these rates make the Maxwellian at :math:`T_g`
stationary: the test suite checks it.
"""

from __future__ import annotations

import math

from scipy import constants

from .. import _arrays
from .gases import Process, Species

__all__ = ["superelastic_cross_section", "level_populations"]

BOLTZMANN_EV = constants.k / constants.e  # eV/K


def superelastic_cross_section(process: Process, energy):
    r"""The detailed-balance cross section (m^2) of the inverse of a reversible excitation at ``energy`` (eV, > 0).

    :math:`\sigma_{sup}(\epsilon) = (g_0/g_k)\,((\epsilon + \Delta)/\epsilon)\,\sigma_{ex}(\epsilon + \Delta)`
    (Klein-Rosseland), with :math:`\sigma_{ex}` the process's table
    (:meth:`~collisionkit.transport.Process.cross_section_at`).

    Examples
    --------
    >>> from collisionkit.transport import Process
    >>> from collisionkit.transport.superelastic import superelastic_cross_section
    >>> p = Process("excitation", [1.0, 2.0, 5.0], [0.0, 4e-20, 1e-20], threshold=1.0, weight_ratio=3.0)
    >>> float(superelastic_cross_section(p, 0.5))  # (1/3) (1.5/0.5) sigma_ex(1.5) = 2e-20
    2e-20
    """
    if not isinstance(process, Process) or not process.reversible:
        raise ValueError("process must be a reversible excitation (a Process with weight_ratio > 0)")
    energy = _arrays.as_finite_in_range(energy, "energy (eV)", 0.0, inclusive=(False, False))
    return (energy + process.threshold) / energy * process.cross_section_at(energy + process.threshold) \
        / process.weight_ratio


def level_populations(species: Species, gas_temperature: float) -> tuple[float, tuple[float, ...]]:
    r"""The fractions of a species in its ground level and in the upper level of each of its processes.

    Returns ``(ground, levels)``: ``levels[j]`` is the fraction :math:`N_k/N_s`
    in the excited level of process ``j`` (0 for a process that is not a
    reversible excitation), ``ground`` is :math:`N_0/N_s`; together they sum
    to 1 (see the module docstring for the Boltzmann split).

    Examples
    --------
    >>> import math
    >>> from collisionkit.transport import Process, Species
    >>> from collisionkit.transport.superelastic import level_populations, BOLTZMANN_EV
    >>> x = Species("x", 6.6e-27, (Process("elastic", [0, 10], [1e-20, 1e-20]),
    ...             Process("excitation", [0.1, 10], [0, 1e-20], threshold=0.1, weight_ratio=3.0)))
    >>> ground, levels = level_populations(x, 1000.0)
    >>> b = 3.0 * math.exp(-0.1 / (BOLTZMANN_EV * 1000.0))
    >>> math.isclose(ground, 1 / (1 + b)), math.isclose(levels[1], b / (1 + b)), levels[0]
    (True, True, 0.0)
    """
    temperature = float(gas_temperature)
    if not (math.isfinite(temperature) and temperature >= 0.0):
        raise ValueError(f"gas_temperature must be finite and >= 0 (K); got {gas_temperature}")
    boltzmann = [0.0] * len(species.processes)
    fixed = [None] * len(species.processes)
    for j, p in enumerate(species.processes):
        if not p.reversible:
            continue
        if p.population is not None:
            fixed[j] = p.population
        elif temperature > 0.0:
            boltzmann[j] = p.weight_ratio * math.exp(-p.threshold / (BOLTZMANN_EV * temperature))
    set_total = sum(value for value in fixed if value is not None)
    if set_total >= 1.0:
        raise ValueError(f"the populations set for the excited levels of {species.name} sum to {set_total:g}: "
                         "they must leave the ground level a share (sum < 1)")
    ground = (1.0 - set_total) / (1.0 + sum(boltzmann))
    levels = tuple(fixed[j] if fixed[j] is not None else ground * boltzmann[j] for j in range(len(boltzmann)))
    return ground, levels
