"""Small systems the EDMD tests start from: lattices melted with Maxwell-Boltzmann velocities."""

import numpy as np

from collisionkit import edmd


def fcc_system(cells=4, eta=0.4, seed=1, **options):
    positions, box = edmd.lattice("fcc", cells, eta)
    velocities = edmd.maxwell_boltzmann(np.ones(len(positions)), 3, seed=seed)
    return edmd.HardSphereSystem(positions, velocities, 0.5, box, **options)


def hexagonal_system(cells=12, eta=0.3, seed=1, **options):
    positions, box = edmd.lattice("hexagonal", cells, eta)
    velocities = edmd.maxwell_boltzmann(np.ones(len(positions)), 2, seed=seed)
    return edmd.HardSphereSystem(positions, velocities, 0.5, box, **options)


def square_system(velocities=None):
    positions, box = edmd.lattice("square", 4, 0.3)
    if velocities is None:
        velocities = edmd.maxwell_boltzmann(np.ones(16), 2, seed=1)
    return edmd.HardSphereSystem(positions, velocities, 0.5, box)
