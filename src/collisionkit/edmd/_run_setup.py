"""An EDMD run's set-up: its starting state from the parameters, and the files a new run does not replace."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from ._rotation import UNIFORM_INERTIA, random_spins
from .initial import lattice, lattice_cells, maxwell_boltzmann, random_fluid
from .system import HardSphereSystem

# the random stream of the initial spins, apart from the positions' and velocities' (drawn from the seed itself)
SPIN_STREAM = 1

def initial_system(parameters, progress: Callable[[float], Any] | None = None) -> HardSphereSystem:
    """The starting state of an :class:`~collisionkit.edmd.EdmdRun` of ``parameters``: a compressed random fluid
    or a lattice with Maxwell-Boltzmann velocities (and rough spheres' spins at the rotational kT asked for)."""
    p = parameters
    species = np.repeat(np.arange(len(p.species_counts)), p.species_counts)
    diameters = np.asarray(p.diameters or (1.0,) * len(p.species_counts))[species]
    masses = np.asarray(p.masses or (1.0,) * len(p.species_counts))[species]
    if p.initial == "random":
        fluid = random_fluid(p.dim, p.particles, p.packing_fraction, seed=p.seed, diameters=diameters, masses=masses,
                             progress=progress)
        positions, velocities, box = fluid.positions(), fluid.velocities(), fluid.box[: p.dim]
    else:  # one species (the checks): unit diameters and masses
        positions, box = lattice(p.initial, lattice_cells(p.initial, p.dim, p.particles), p.packing_fraction)
        velocities = maxwell_boltzmann(masses, p.dim, kT=1.0, seed=p.seed)
    spins = None
    if p.tangential_restitution is not None:  # (drawn from a stream of their own: the velocities stay the same)
        kappa = p.inertia_factor if p.inertia_factor is not None else UNIFORM_INERTIA[p.dim]
        moments = kappa * masses * (diameters / 2.0) ** 2
        spins = random_spins(moments, p.dim, kT=1.0, seed=np.random.SeedSequence([p.seed, SPIN_STREAM]))
        # scaled to the rotational kT asked for exactly, as the velocities are to kT = 1
        drawn = np.sum(moments * (spins**2 if p.dim == 2 else np.sum(spins**2, axis=1))) / (3 if p.dim == 3 else 1)
        spins *= np.sqrt(p.initial_rotational_temperature * p.particles / drawn)
    return HardSphereSystem(positions, velocities, diameters / 2.0, box, masses, species=species,
                            restitution=p.restitution, restitution_law=p.restitution_law, law_speed=p.law_speed,
                            law_exponent=p.law_exponent, elastic_below=p.elastic_below, shear_rate=p.shear_rate,
                            thermostat=1.0 if p.thermostat else None, engine=p.engine, well_width=p.well_width,
                            well_depth=p.well_depth, tangential_restitution=p.tangential_restitution,
                            inertia_factor=p.inertia_factor, angular_velocities=spins, friction=p.friction)


def refuse_existing(**files) -> None:
    """FileExistsError naming the first of ``files`` (name: path or None) that exists: a new run does not replace it."""
    for name, path in files.items():
        if path is not None and Path(path).exists():
            raise FileExistsError(f"{name} {path} exists (another run's file): resume that run "
                                  "(EdmdRun.resume), choose another file or pass overwrite=True")
