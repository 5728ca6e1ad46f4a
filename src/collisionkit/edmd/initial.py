"""Initial states of an EDMD run: Maxwell-Boltzmann velocities, lattices and compressed random fluids."""

from __future__ import annotations

import math

import numpy as np

from . import _checks
from ._cell_crossings import cells_fit, engine_code
from .system import HardSphereSystem, default_shell
from .theory import MAX_PACKING_FRACTION, _ball_volume

__all__ = ["LATTICE_BASIS", "LATTICE_DIM", "lattice", "lattice_cells", "maxwell_boltzmann", "random_fluid"]

# per lattice: dimension, basis sites in the unit cell (fractions of it) and the unit cell's aspect
_LATTICE_BASES = {
    "square": (2, np.array([[0.5, 0.5]]), np.array([1.0, 1.0])),
    "hexagonal": (2, np.array([[0.25, 0.25], [0.75, 0.75]]), np.array([1.0, math.sqrt(3.0)])),
    "sc": (3, np.array([[0.5, 0.5, 0.5]]), np.array([1.0, 1.0, 1.0])),
    "fcc": (
        3,
        np.array([[0.25, 0.25, 0.25], [0.75, 0.75, 0.25], [0.75, 0.25, 0.75], [0.25, 0.75, 0.75]]),
        np.array([1.0, 1.0, 1.0]),
    ),
}
# nearest-neighbour distance of each lattice in units of its unit cell
_NEAREST_DISTANCE = {"square": 1.0, "hexagonal": 1.0, "sc": 1.0, "fcc": math.sqrt(0.5)}

#: Dimension of each lattice :func:`lattice` builds.
LATTICE_DIM = {kind: dim for kind, (dim, _, _) in _LATTICE_BASES.items()}
#: Particles per unit cell of each lattice.
LATTICE_BASIS = {kind: len(basis) for kind, (_, basis, _) in _LATTICE_BASES.items()}


def maxwell_boltzmann(masses, dim, kT=1.0, seed=None):
    """Maxwell-Boltzmann velocities with zero total momentum and exactly ``kT``.

    kT is defined by the kinetic energy, ``2 K / (d N)``.

    Parameters
    ----------
    masses : array_like, shape (N,)
        Finite and > 0; N >= 2 (zero total momentum would leave a single
        particle at rest).
    dim : {2, 3}
    kT : float
        Finite and > 0.
    seed : int, numpy.random.Generator or None, optional
        Seed of the random velocities (None: fresh entropy).

    Returns
    -------
    ndarray, shape (N, dim)

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.edmd import maxwell_boltzmann
    >>> v = maxwell_boltzmann(np.ones(100), 3, kT=2.0, seed=1)
    >>> bool(np.allclose(v.sum(axis=0), 0)), round(float((v**2).sum() / (3 * 100)), 12)
    (True, 2.0)
    """
    dim = _checks.dimension(dim)
    kT = _checks.positive(kT, "kT")
    masses = _checks.positive(masses, "masses", scalar=False)
    if masses.ndim != 1 or masses.size < 2:
        raise ValueError(
            f"masses must have shape (N,) with N >= 2 (zero total momentum leaves a single particle at rest, "
            f"so no temperature); got shape {masses.shape}"
        )
    generator = np.random.default_rng(seed)
    velocities = generator.normal(size=(masses.size, dim)) * np.sqrt(kT / masses)[:, None]
    velocities -= (masses[:, None] * velocities).sum(axis=0) / masses.sum()
    kinetic = 0.5 * np.sum(masses[:, None] * velocities**2)
    return velocities * math.sqrt(kT * dim * masses.size / (2.0 * kinetic))


def lattice(kind, cells, packing_fraction, diameter=1.0):
    """Particles on a lattice filling a periodic box at the given packing fraction.

    Parameters
    ----------
    kind : {"square", "hexagonal", "sc", "fcc"}
        2D square or hexagonal (triangular) lattice; 3D simple cubic or FCC.
    cells : int
        Unit cells per axis (N = cells^d times the basis size).
    packing_fraction : float
        Target eta, > 0; must leave the spheres apart on that lattice.
    diameter : float
        Finite and > 0.

    Returns
    -------
    positions : ndarray, shape (N, d)
    box : ndarray, shape (d,)

    Examples
    --------
    >>> from collisionkit.edmd import lattice
    >>> positions, box = lattice("fcc", 3, 0.4)
    >>> positions.shape
    (108, 3)
    """
    _lattice_kind(kind)
    cells = _checks.integer_at_least(cells, "cells", 1)
    packing_fraction = _checks.positive(packing_fraction, "packing_fraction")
    diameter = _checks.positive(diameter, "diameter")
    dim, basis, aspect = _LATTICE_BASES[kind]
    grid = np.stack(np.meshgrid(*[np.arange(cells)] * dim, indexing="ij"), axis=-1).reshape(-1, dim)
    unit = (grid[:, None, :] + basis[None, :, :]).reshape(-1, dim) * aspect
    count = unit.shape[0]
    cell_volume = float(np.prod(aspect)) * cells**dim
    particle_volume = _ball_volume(diameter / 2.0, dim)
    scale = (count * particle_volume / (packing_fraction * cell_volume)) ** (1.0 / dim)
    positions = unit * scale
    nearest = _NEAREST_DISTANCE[kind] * scale
    if nearest < diameter * (1 + 1e-12):
        raise ValueError(
            f"packing_fraction {packing_fraction} is above the close packing of the {kind} lattice"
        )
    return positions, aspect * cells * scale


def lattice_cells(kind, dim, particles) -> int:
    """Unit cells per axis of a lattice of ``particles`` sites in ``dim`` dimensions.

    Parameters
    ----------
    kind : {"square", "hexagonal", "sc", "fcc"}
        The lattice, as for :func:`lattice`; its dimension must be ``dim``.
    dim : {2, 3}
    particles : int
        Number of sites, >= 1: exactly ``LATTICE_BASIS[kind] * cells**dim``.

    Returns
    -------
    int
        ``cells``, to pass to :func:`lattice`.

    Raises
    ------
    ValueError
        If the lattice is of another dimension, or no whole number of cells
        gives ``particles`` sites (the message lists some that do).

    Examples
    --------
    >>> from collisionkit.edmd import lattice_cells
    >>> lattice_cells("fcc", 3, 500)
    5
    >>> lattice_cells("hexagonal", 2, 100)
    Traceback (most recent call last):
    ...
    ValueError: initial hexagonal needs particles = 2 * cells^2 (e.g. 18, 32, 50, 72); got 100
    """
    _lattice_kind(kind)
    dim = _checks.dimension(dim)
    particles = _checks.integer_at_least(particles, "particles", 1)
    if LATTICE_DIM[kind] != dim:
        raise ValueError(f"initial {kind} is a {LATTICE_DIM[kind]}D lattice; it cannot start a {dim}D run")
    basis = LATTICE_BASIS[kind]
    cells = max(1, round((particles / basis) ** (1.0 / dim)))
    if basis * cells**dim != particles:
        examples = ", ".join(str(basis * n**dim) for n in range(3, 7))
        raise ValueError(f"initial {kind} needs particles = {basis} * cells^{dim} (e.g. {examples}); got {particles}")
    return cells


def _lattice_kind(kind):
    """Refuse a lattice name :func:`lattice` does not know."""
    if not isinstance(kind, str) or kind not in _LATTICE_BASES:
        raise ValueError(f"kind must be one of {sorted(_LATTICE_BASES)}; got {kind!r}")


def random_fluid(
    dim,
    particles,
    packing_fraction,
    seed=None,
    diameters=1.0,
    masses=1.0,
    kT=1.0,
    growth_rate=0.05,
    progress=None,
    **system_options,
):
    """A random fluid grown by Lubachevsky-Stillinger compression.

    Points at random positions in a periodic box grow as spheres at a
    constant rate while the system runs event by event (J. Stat. Phys. 60,
    561 (1990)); velocities are rescaled to kT every time unit to remove the
    heat of compression, and growth stops exactly at the target packing
    fraction. Velocities finish Maxwell-Boltzmann at kT with zero momentum.

    Parameters
    ----------
    dim : {2, 3}
    particles : int
        N >= 2.
    packing_fraction : float
        Target eta, > 0 and at most ``MAX_PACKING_FRACTION[dim]`` (0.5 in
        3D, 0.7 in 2D: denser runs risk jamming before the target; the run
        fails clearly if so).
    seed : int, numpy.random.Generator or None, optional
        Seed of the random positions and velocities (None: fresh entropy).
    diameters, masses : float or array_like, shape (N,)
        Final diameters and masses (mixtures allowed), finite and > 0.
    kT : float
        Finite and > 0.
    growth_rate : float
        Relative growth of the diameters per unit time, finite and > 0.
    progress : callable, optional
        Called as ``progress(fraction)`` with the fraction of the compression
        done, in [0, 1].
    **system_options
        Passed to :class:`HardSphereSystem` (restitution, ...); the box is
        periodic. Without ``neighbour_shell`` the compressed fluid keeps the
        compression's shell or, where wider (dilute fluids),
        :func:`~collisionkit.edmd.default_shell`'s. The compression runs
        on neighbour lists; the fluid then runs the ``engine`` asked for
        (default "auto").

    Examples
    --------
    >>> from collisionkit.edmd import random_fluid
    >>> system = random_fluid(3, 200, 0.3, seed=1)
    >>> round(float(system.temperature()), 12), system.check() > -1e-9
    (1.0, True)
    """
    dim = _checks.dimension(dim)
    particles = _checks.integer_at_least(particles, "particles", 2)
    packing_fraction = _checks.bounded(
        packing_fraction, f"packing_fraction (dim={dim})", 0.0, MAX_PACKING_FRACTION[dim], closed=(False, True)
    )
    growth_rate = _checks.positive(growth_rate, "growth_rate")
    kT = _checks.positive(kT, "kT")
    generator = np.random.default_rng(seed)
    diameters = _checks.positive(_checks.per_particle(diameters, particles, "diameters"), "diameters", scalar=False)
    masses = _checks.per_particle(masses, particles, "masses")
    radii = diameters / 2.0
    side = (np.sum(_ball_volume(radii, dim)) / packing_fraction) ** (1.0 / dim)
    if side < 3.0 * float(diameters.max()):
        raise ValueError(
            f"{particles} particles at packing_fraction {packing_fraction} give a box of side {side:.3g}, "
            f"less than 3 diameters: use more particles"
        )
    positions = generator.uniform(0.0, side, size=(particles, dim))
    velocities = maxwell_boltzmann(masses, dim, kT, generator)
    # a small starting scale keeps the random points apart
    start = 0.5 * _smallest_distance_bound(positions, side, diameters)
    engine = system_options.pop("engine", "auto")  # the lists compress; the fluid then gets the engine asked for
    system = HardSphereSystem(positions, velocities, radii, side, masses, periodic=True, _growth=growth_rate,
                              _scale=start, engine="lists", **system_options)
    total_time = (1.0 - start) / growth_rate
    done = 0.0
    while done < total_time:
        step = min(1.0, total_time - done)
        system.run(time=step)
        done += step
        system.rescale_temperature(kT)
        if progress is not None:
            progress(min(done / total_time, 1.0))
    if system_options.get("neighbour_shell") is None:  # the compression's shell, now the dilute default's if wider
        dilute = default_shell(radii, np.full(dim, side), system_options.get("gravity") is None)
        system._shell_request = max(float(system._shell_request), dilute)
    straight = system.shear_rate == 0.0 and system_options.get("gravity") is None
    fit = cells_fit(np.full(dim, side), dim, np.ones(dim, dtype=bool), float(diameters.max()))
    system._engine_code = engine_code(engine, dim, packing_fraction, particles, straight, fit)
    system._stop_growing(1.0)
    system.check(tolerance=1e-7)
    system.set_velocities(maxwell_boltzmann(masses, dim, kT, generator))
    return system


def _smallest_distance_bound(positions, side, diameters):
    """A scale s0 such that s0 * diameters keeps the random points from overlapping."""
    from scipy.spatial import cKDTree

    tree = cKDTree(positions, boxsize=side)
    distances, _ = tree.query(positions, k=2)
    return min(1.0, float(distances[:, 1].min() / diameters.max()))
