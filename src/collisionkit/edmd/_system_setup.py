"""Construction of a :class:`~collisionkit.edmd.HardSphereSystem`: input checks, the engine and its arrays.

The kernels read every particle from 64-byte records: ``p`` (position,
velocity, own time, radius) and ``book`` (next event, event numbers, list
anchor, mass, species); the layouts are the ``_k`` column constants.
"""

from __future__ import annotations

import math

import numpy as np

from .. import _arrays
from .._kernels import edmd as _k
from . import _checks
from ._cell_crossings import cells_fit, engine_code
from .theory import packing_fraction

RESTITUTION_LAWS = {"constant": _k.LAW_CONSTANT, "bridges": _k.LAW_BRIDGES, "viscoelastic": _k.LAW_VISCOELASTIC}
# neighbour-list entries per particle a new system starts with (the rows grow when a run needs more)
INITIAL_LIST_WIDTH = 16


def particle_arrays(positions, velocities):
    """Checked float64 positions and velocities, both of shape (N, d) with N >= 2 and d = 2 or 3."""
    positions = _checks.real_array(positions, "positions")
    if positions.ndim != 2 or positions.shape[1] not in (2, 3):
        raise ValueError(f"positions must have shape (N, 2) or (N, 3); got {positions.shape}")
    count = positions.shape[0]
    if count < 2:
        raise ValueError(f"positions must hold at least 2 particles; got {count}")
    velocities = _checks.real_array(velocities, "velocities")
    if velocities.shape != positions.shape:
        raise ValueError(f"velocities must have the shape of positions {positions.shape}; got {velocities.shape}")
    for array, name in ((positions, "positions"), (velocities, "velocities")):
        _arrays.require_finite(array, name)
    return positions, velocities


def checked_particles(positions, velocities, radii, masses, box, periodic, species):
    """The particles' inputs checked, in this order: positions, velocities, radii, masses, box, periodic, species.

    Returns the positions and velocities (N, d), radii and masses (N,),
    box (d,), periodic flags (d,) and species indices (N,; 0 for None).

    Examples
    --------
    >>> _, _, radius, mass, box, periodic, species = checked_particles(
    ...     [[1.0, 1.0], [1.0, 5.0]], [[1.0, 0.0], [1.0, 0.0]], 0.5, 1.0, 10.0, True, None)
    >>> radius, box, periodic, species
    (array([0.5, 0.5]), array([10., 10.]), array([ True,  True]), array([0, 0]))
    """
    positions, velocities = particle_arrays(positions, velocities)
    count, dim = positions.shape
    radius = _checks.positive(_checks.per_particle(radii, count, "radii"), "radii", scalar=False)
    mass = _checks.positive(_checks.per_particle(masses, count, "masses"), "masses", scalar=False)
    box = _checks.positive(_checks.per_particle(box, dim, "box"), "box", scalar=False)
    periodic = periodic_axes(periodic, dim)
    species = _checks.per_particle(0 if species is None else species, count, "species", integer=True)
    return positions, velocities, radius, mass, box, periodic, species


def periodic_axes(periodic, dim):
    """``periodic`` (a bool or one bool per axis) as a bool array of shape (dim,)."""
    array = np.asarray(periodic)
    if array.dtype != bool:
        raise TypeError(f"periodic must be a bool or a sequence of {dim} bools; got {periodic!r}")
    if array.shape not in ((), (dim,)):
        raise ValueError(f"periodic must be a bool or one bool per axis ({dim}); got shape {array.shape}")
    return np.broadcast_to(array, (dim,)).copy()


def gravity_vector(gravity, dim):
    """The uniform acceleration: zeros for None, else a finite vector of shape (dim,)."""
    gravity = np.zeros(dim) if gravity is None else _checks.real_array(gravity, "gravity")
    if gravity.shape != (dim,):
        raise ValueError(f"gravity must have shape ({dim},); got {gravity.shape}")
    _arrays.require_finite(gravity, "gravity")
    return gravity


def restitution_parameters(species, restitution, law, law_speed, law_exponent, wall_restitution):
    """The checked restitution matrix (species x species) and a new kernel parameter array holding the law.

    ``species`` are the per-particle indices into the matrix.
    """
    species_count = int(species.max()) + 1
    if np.any(species < 0):
        raise ValueError("species must be >= 0")
    matrix = _checks.real_array(restitution, "restitution")
    _arrays.require_in_range(matrix, "restitution", 0.0, 1.0)
    if matrix.ndim == 0:
        matrix = np.full((species_count, species_count), float(matrix))
    if matrix.shape[0] < species_count or matrix.shape != (matrix.shape[0], matrix.shape[0]):
        raise ValueError(
            f"restitution must be a scalar or a square matrix covering {species_count} species; got {matrix.shape}"
        )
    if not np.allclose(matrix, matrix.T):
        raise ValueError("restitution matrix must be symmetric")
    if not isinstance(law, str) or law not in RESTITUTION_LAWS:
        raise ValueError(f"restitution_law must be one of {sorted(RESTITUTION_LAWS)}; got {law!r}")
    law_speed = _checks.positive(law_speed, "law_speed")
    law_exponent = _checks.positive(law_exponent, "law_exponent")
    wall_restitution = _checks.bounded(wall_restitution, "wall_restitution", 0.0, 1.0, closed=(True, True))
    params = np.zeros(_k.P_SIZE)
    params[_k.P_LAW] = RESTITUTION_LAWS[law]
    params[_k.P_LAW_SPEED] = law_speed
    params[_k.P_LAW_EXPONENT] = law_exponent
    params[_k.P_WALL_RESTITUTION] = wall_restitution
    return np.ascontiguousarray(matrix), params


def default_elastic_below(restitution, velocities, wall_restitution=1.0, gravity=None, box=None):
    """The elastic floor when none is given: 1e-6 of the speed scale if a constant restitution below 1 (of pairs or
    walls) can collapse, else 0.

    Pair contacts and wall bounces both obey it. The speed scale is
    sqrt(<v^2> + |g| L) (L the longest box edge): the rms speed without
    gravity, and the speed of a fall across the box under gravity, so that
    particles dropped at rest on an inelastic floor are guarded too. The
    restitution laws need none: their contacts turn elastic as they slow
    down (Bridges: e = 1 below u_c; viscoelastic: 1 - e ~ u_n^(1/5)), so no
    inelastic collapse, and a floor would stop the slow cooling they give.
    """
    inelastic = np.any(restitution < 1.0) or wall_restitution < 1.0
    if not inelastic:
        return 0.0
    fall = 0.0 if gravity is None or box is None else float(np.linalg.norm(gravity)) * float(np.max(box))
    return 1e-6 * math.sqrt(float(np.mean(np.sum(velocities**2, axis=1))) + fall)


def geometry(box, periodic, gravity):
    """The kernels' geometry rows: box lengths (1 on unused axes), cell widths, gravity, periodic flags."""
    dim = len(box)
    geom = np.zeros((4, 3))
    geom[_k.G_BOX] = 1.0
    geom[_k.G_BOX, :dim] = box
    geom[_k.G_PERIODIC, :dim] = periodic
    geom[_k.G_GRAVITY, :dim] = gravity
    return geom


def particle_records(positions, velocities, radius):
    """The particles' 64-byte records (position, velocity, own time 0, radius)."""
    count, dim = positions.shape
    p = aligned_zeros((count, 8))
    p[:, _k.X : _k.X + dim] = positions
    p[:, _k.V : _k.V + dim] = velocities
    p[:, _k.R] = radius
    return p


def start_records(system, positions, velocities, radius, box, periodic):
    """Give ``system`` its particles at time 0: records folded into the box, no images, slots in input order.

    Also the event loop's counters: the sort, the accumulators, the events
    in a row at one instant.
    """
    count, dim = positions.shape
    system.time = 0.0
    system.elapsed = 0.0
    system.p = particle_records(positions, velocities, radius)
    wrap_into_box(system.p, box, periodic)
    system._image = np.zeros((count, dim), dtype=np.int64)
    # particles live in memory in cell order (re-sorted as they move); ids maps slot -> particle
    system.ids = np.arange(count)
    system.last_sort = 0
    system.acc = np.zeros(_k.ACC_SIZE)
    system._still = 0  # events in a row at the current instant (the event loop's watch for a collapse)


def engine_choice(engine, radius, box, periodic, gravity, growth, scale, shear_rate):
    """The code of the event engine a system runs: ``engine`` as asked, "auto" resolved.

    The cell-crossing engine needs straight flights of fixed radii (no
    gravity, compression or shear) and cells that fit the box
    (:func:`~collisionkit.edmd._cell_crossings.engine_code`).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.edmd._cell_crossings import ENGINE_CELLS
    >>> engine_choice("auto", np.full(100, 0.5), np.full(2, 40.0), np.ones(2, bool), np.zeros(2), 0.0, 1.0,
    ...               0.0) == ENGINE_CELLS
    True
    """
    dim = len(box)
    straight = growth == 0.0 and not np.any(gravity) and shear_rate == 0.0
    fit = cells_fit(box, dim, periodic, 2.0 * float(np.max(radius)) * float(scale))
    return engine_code(engine, dim, packing_fraction(radius * float(scale), box), len(radius), straight, fit)


def wrap_into_box(p, box, periodic):
    """Fold the positions in ``p`` into [0, L) on periodic axes; refuse centres outside the walls on the others."""
    for k, wrapped in enumerate(periodic):
        column = p[:, _k.X + k]
        if wrapped:
            column %= box[k]
        elif np.any((column < 0) | (column > box[k])):
            raise ValueError(f"positions must lie inside the walls on axis {k}: [0, {box[k]}]")


def allocate_engine_arrays(system):
    """Give ``system`` empty bookkeeping records, neighbour lists and event queue for its particles."""
    count = system.count
    # one 64-byte bookkeeping record per particle (next event, event numbers, anchor, mass, species)
    system.book = aligned_zeros((count, 8))
    system.book[:, _k.TARGET] = _k.LIST_TARGET
    copy_masses_and_species(system)
    system.cell_of = np.zeros(count, dtype=np.int32)
    # under Lees-Edwards shear the clock time each list was built at (its age spends the list's shell budget)
    system.anchor_time = np.zeros(count if system.params[_k.P_SHEAR_RATE] != 0.0 else 1)
    system.neighbours = np.zeros((count, INITIAL_LIST_WIDTH), dtype=np.uint32)
    system.neighbour_count = np.zeros(count, dtype=np.int32)
    # the cell-crossing engine's best collision found so far of each particle (time, partner, event number)
    system.pending = np.zeros((count, 3))
    blocks = -(-count // _k.QUEUE_BLOCK)
    system.leaves = next_power_of_two(blocks)
    system.queue = aligned_zeros(blocks * _k.QUEUE_BLOCK)
    system.tree = aligned_zeros((2 * system.leaves, 2))


def copy_masses_and_species(system):
    """The kernels read masses and species from the bookkeeping records: copy them there (memory order)."""
    system.book[:, _k.MASS] = system._mass
    system.book[:, _k.SPECIES] = system._species


def check_walls(system):
    """Refuse a particle that overlaps a wall (its centre may be inside while its surface is not)."""
    if not np.all(system.periodic):
        gap = _k.wall_gap(system.p, system.scale, system.geom, system.dim)
        if gap < -1e-9 * float(np.max(system.radius)):
            raise ValueError(f"positions must keep every particle inside the walls (overlap {-gap:.3g})")


def closest_pair_description(system, gap):
    """'particles i and j, surface gap g' for the most overlapping pair (user indices), found by a k-d tree."""
    from scipy.spatial import cKDTree

    dim, scale = system.dim, system.scale
    points, _ = system._folded()
    box = system.box[:dim]
    radii = system.p[:, _k.R] * scale
    tree = cKDTree(points, boxsize=box if np.all(system.periodic[:dim]) else None)
    pairs = tree.query_pairs(2.0 * float(radii.max()), output_type="ndarray")
    if len(pairs) == 0:
        return f"smallest surface gap {gap:.3g}"
    separation = points[pairs[:, 1]] - points[pairs[:, 0]]
    wrapped = np.asarray(system.periodic[:dim], dtype=bool)
    separation[:, wrapped] -= box[wrapped] * np.round(separation[:, wrapped] / box[wrapped])
    gaps = np.linalg.norm(separation, axis=1) - radii[pairs[:, 0]] - radii[pairs[:, 1]]
    worst = int(np.argmin(gaps))
    first, second = sorted(int(system.ids[k]) for k in pairs[worst])
    return f"particles {first} and {second}, surface gap {gaps[worst]:.3g}"


def next_power_of_two(n):
    """The smallest power of two >= n (at least 2): the leaves of the event tree."""
    return 1 << max(n - 1, 1).bit_length()


def aligned_zeros(shape, dtype=np.float64, alignment=64):
    """Zeros whose rows start on cache-line boundaries (64-byte particle records)."""
    itemsize = np.dtype(dtype).itemsize
    count = int(np.prod(shape))
    raw = np.zeros(count + alignment // itemsize, dtype=dtype)
    offset = (-raw.ctypes.data % alignment) // itemsize
    return raw[offset : offset + count].reshape(shape)
