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


def assert_errors_match_the_scatter(measurements, names):
    """The block errors of ``names`` agree with the scatter of independent ``measurements``.

    (n - 1) s^2 / sigma^2 follows chi^2(n - 1): the variance ratio s^2 / <error^2> must lie in its central 1 - 2e-4
    band (a factor of two wrong in the error fails it for 16 runs). Returns the ratios.
    """
    from scipy import stats

    dof = len(measurements) - 1
    low, high = stats.chi2.ppf([1e-4, 1 - 1e-4], dof) / dof
    ratios = {name: np.var([getattr(m, name) for m in measurements], ddof=1)
              / np.mean(np.square([getattr(m, f"{name}_error") for m in measurements])) for name in names}
    assert all(low < ratio < high for ratio in ratios.values()), ratios
    return ratios
