"""Event-driven molecular dynamics of hard spheres (3D) and hard discs (2D).

Particles fly ballistically (parabolas under uniform gravity) between exact
pair collisions, processed one event at a time in time order; collision
times come from the contact quadratic and the collision rule acts along the
line of centres (the pair-collision notes). Boxes may be periodic or closed by
hard walls on each axis; radii and masses may differ (mixtures); collisions
may be inelastic with a coefficient of normal restitution per species pair,
optionally velocity dependent.

The numeric work runs in :mod:`collisionkit._kernels.edmd` (neighbour lists
with a shell, rebuilt from cell lists; an array-backed tournament tree over
blocks of event times; lazily updated particles).

Units: any consistent set; the CLI uses diameter 1 (largest species), mass 1
and initial kT = 1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import _arrays
from ._io import atomic_write_bytes
from ._kernels import edmd as _k

__all__ = [
    "HardSphereSystem",
    "Measurement",
    "Sampler",
    "measure",
    "OverlapError",
    "carnahan_starling",
    "hansen_goos",
    "henderson",
    "lattice",
    "maxwell_boltzmann",
    "random_fluid",
    "enskog_collision_frequency",
    "packing_fraction",
]

RESTITUTION_LAWS = {"constant": _k.LAW_CONSTANT, "bridges": _k.LAW_BRIDGES}

# re-sort particles in memory by cell after this many collisions per particle
SORT_INTERVAL = 20
# neighbour-list shell (skin) in units of the largest diameter; benchmarks/bench_edmd.py --shells tunes it
DEFAULT_SHELL = 0.7
# while compressing, lists cover radii up to the current scale plus this (then all are rebuilt)
LIST_SCALE_MARGIN = 0.05


class OverlapError(ValueError, RuntimeError):
    """Two particles (or a particle and a wall) overlap beyond round-off.

    A ``ValueError`` when the given positions overlap (bad input), and a
    ``RuntimeError`` as well, for :meth:`HardSphereSystem.check` after a run.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.edmd import HardSphereSystem, OverlapError
    >>> try:
    ...     HardSphereSystem([[1.0, 1.0], [1.5, 1.0]], np.zeros((2, 2)), 0.5, 10.0)
    ... except OverlapError as error:
    ...     print("refused:", error)
    refused: positions overlap: particles 0 and 1, surface gap -0.5
    """


# ------------------------------------------------------------------ argument checks


def _real_array(value, name):
    """``value`` as a float64 array; TypeError naming ``name`` for non-real or boolean input."""
    array = _arrays.as_float_array(value, name)
    if np.asarray(value).dtype.kind == "b":
        raise TypeError(f"{name} must hold numbers, not booleans; got {value!r}")
    return array


def _bounded(value, name, low, high=math.inf, *, closed=(True, False), scalar=True):
    """Finite number(s) from ``low`` to ``high`` (ends included as ``closed`` says).

    Returns a float, or a float64 array unless ``scalar``; raises TypeError
    for a non-real or boolean value, ValueError naming ``name`` and the range.
    """
    array = _real_array(value, name)
    if scalar and array.ndim:
        raise ValueError(f"{name} must be a single number; got shape {array.shape}")
    above = array >= low if closed[0] else array > low
    below = array <= high if closed[1] else array < high
    ok = np.isfinite(array) & above & below
    if not np.all(ok):
        if high == math.inf:
            allowed = f"{'>=' if closed[0] else '>'} {low:g}"
        else:
            allowed = f"in {'[' if closed[0] else '('}{low:g}, {high:g}{']' if closed[1] else ')'}"
        what = "be a finite number" if scalar else "hold finite numbers"
        raise ValueError(f"{name} must {what} {allowed}; got {array[~ok].flat[0]}")
    return float(array) if scalar else array


def _positive(value, name, scalar=True):
    """Finite number(s) > 0, as :func:`_bounded`."""
    return _bounded(value, name, 0.0, closed=(False, False), scalar=scalar)


def _is_integer(value):
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool)


def _count(value, name, minimum):
    """``value`` as an int >= ``minimum``; booleans and non-integers raise TypeError naming ``name``."""
    if not _is_integer(value):
        raise TypeError(f"{name} must be an integer >= {minimum}; got {value!r}")
    if value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}; got {value!r}")
    return int(value)


def _dimension(dim):
    """The space dimension: the integer 2 or 3."""
    if not _is_integer(dim):
        raise TypeError(f"dim must be the integer 2 or 3; got {dim!r}")
    if dim not in (2, 3):
        raise ValueError(f"dim must be 2 or 3; got {dim!r}")
    return int(dim)


def _packing(eta):
    """Packing fraction(s) for an equation of state: finite, in [0, 1)."""
    return _bounded(eta, "eta", 0.0, 1.0, scalar=False)


# ------------------------------------------------------------------ equations of state


def carnahan_starling(eta):
    r"""Carnahan-Starling compressibility factor of hard spheres.

    :math:`Z = (1 + \eta + \eta^2 - \eta^3)/(1 - \eta)^3`
    (J. Chem. Phys. 51, 635 (1969)).

    Parameters
    ----------
    eta : float or array_like
        Packing fraction(s), in [0, 1).

    Returns
    -------
    float or ndarray
        Z, shaped like ``eta``.

    Examples
    --------
    >>> from collisionkit.edmd import carnahan_starling
    >>> round(float(carnahan_starling(0.4)), 6)
    6.925926
    """
    eta = _packing(eta)
    return (1 + eta + eta**2 - eta**3) / (1 - eta) ** 3


_HANSEN_GOOS_B = (9.0, -19.0, 47.0 / 3.0, -2.635232, -1.265575, 0.041212, 0.248245, -0.096495)


def hansen_goos(eta):
    r"""Hansen-Goos compressibility factor of the hard-sphere fluid.

    :math:`Z = 8\ln(1-\eta)/\eta + \sum_{i=0}^7 b_i\eta^i/(1-\eta)^3`
    (J. Chem. Phys. 144, 164506 (2016)); more accurate than Carnahan-Starling
    near freezing.

    Parameters
    ----------
    eta : float or array_like
        Packing fraction(s), in [0, 1); Z = 1 at eta = 0.

    Returns
    -------
    float or ndarray
        Z, shaped like ``eta``.

    Examples
    --------
    >>> from collisionkit.edmd import hansen_goos
    >>> round(float(hansen_goos(0.4)), 4)
    6.945
    >>> float(hansen_goos(0.0))
    1.0
    """
    eta = _packing(eta)
    series = sum(b * eta**i for i, b in enumerate(_HANSEN_GOOS_B))
    # ln(1 - eta) / eta tends to -1 at eta = 0
    log_ratio = np.divide(np.log1p(-eta), eta, out=np.full_like(eta, -1.0), where=eta != 0)
    return 8.0 * log_ratio + series / (1 - eta) ** 3


def henderson(eta):
    r"""Henderson's hard-disc equation of state :math:`Z = (1 + \eta^2/8)/(1 - \eta)^2`.

    Mol. Phys. 30, 971 (1975).

    Parameters
    ----------
    eta : float or array_like
        Packing fraction(s) of the discs, in [0, 1).

    Returns
    -------
    float or ndarray
        Z, shaped like ``eta``.

    Examples
    --------
    >>> from collisionkit.edmd import henderson
    >>> round(float(henderson(0.3)), 6)
    2.063776
    """
    eta = _packing(eta)
    return (1 + eta**2 / 8) / (1 - eta) ** 2


def enskog_collision_frequency(compressibility, dim, diameter=1.0, kT=1.0, mass=1.0):
    r"""Collision frequency per particle from the pressure: :math:`\omega = (2d/\sigma)(Z-1)\sqrt{kT/(\pi m)}`.

    Each pair collision counts for both particles.

    Parameters
    ----------
    compressibility : float or array_like
        Compressibility factor Z = PV/(NkT), finite and >= 1 (the hard-core
        pressure is never below the ideal gas's).
    dim : {2, 3}
    diameter, kT, mass : float or array_like, optional
        Finite and > 0.

    Returns
    -------
    float or ndarray
        Collisions per particle per unit time.

    Examples
    --------
    >>> from collisionkit.edmd import enskog_collision_frequency
    >>> round(float(enskog_collision_frequency(2.0, 3)), 6)
    3.385138
    """
    compressibility = _bounded(compressibility, "compressibility", 1.0, scalar=False)
    dim = _dimension(dim)
    diameter, kT, mass = (_positive(diameter, "diameter", scalar=False), _positive(kT, "kT", scalar=False),
                          _positive(mass, "mass", scalar=False))
    return (2.0 * dim / diameter) * (compressibility - 1.0) * np.sqrt(kT / (np.pi * mass))


def _ball_volume(radius, dim):
    return np.pi * radius**2 if dim == 2 else 4.0 / 3.0 * np.pi * radius**3


def packing_fraction(radii, box):
    """Fraction of the box volume covered by the particles.

    Parameters
    ----------
    radii : float or array_like
        Radii of the discs or spheres, finite and > 0.
    box : array_like, shape (2,) or (3,)
        Box lengths, finite and > 0; the length gives the dimension.

    Returns
    -------
    float

    Examples
    --------
    >>> from collisionkit.edmd import packing_fraction
    >>> round(packing_fraction([0.5], [1.0, 1.0]), 6)
    0.785398
    """
    radii = _positive(radii, "radii", scalar=False)
    box = _positive(box, "box", scalar=False)
    if box.shape not in ((2,), (3,)):
        raise ValueError(f"box must have shape (2,) or (3,) (the dimension); got {box.shape}")
    return float(np.sum(_ball_volume(radii, box.size)) / np.prod(box))


# ------------------------------------------------------------------ initial states


def maxwell_boltzmann(masses, dim, kT=1.0, rng=None):
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
    rng : numpy.random.Generator or int, optional

    Returns
    -------
    ndarray, shape (N, dim)

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.edmd import maxwell_boltzmann
    >>> v = maxwell_boltzmann(np.ones(100), 3, kT=2.0, rng=1)
    >>> bool(np.allclose(v.sum(axis=0), 0)), round(float((v**2).sum() / (3 * 100)), 12)
    (True, 2.0)
    """
    dim = _dimension(dim)
    kT = _positive(kT, "kT")
    masses = _positive(masses, "masses", scalar=False)
    if masses.ndim != 1 or masses.size < 2:
        raise ValueError(
            f"masses must have shape (N,) with N >= 2 (zero total momentum leaves a single particle at rest, "
            f"so no temperature); got shape {masses.shape}"
        )
    generator = np.random.default_rng(rng)
    velocities = generator.normal(size=(masses.size, dim)) * np.sqrt(kT / masses)[:, None]
    velocities -= (masses[:, None] * velocities).sum(axis=0) / masses.sum()
    kinetic = 0.5 * np.sum(masses[:, None] * velocities**2)
    return velocities * math.sqrt(kT * dim * masses.size / (2.0 * kinetic))


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
    if not isinstance(kind, str) or kind not in _LATTICE_BASES:
        raise ValueError(f"kind must be one of {sorted(_LATTICE_BASES)}; got {kind!r}")
    cells = _count(cells, "cells", 1)
    packing_fraction = _positive(packing_fraction, "packing_fraction")
    diameter = _positive(diameter, "diameter")
    dim, basis, aspect = _LATTICE_BASES[kind]
    grid = np.stack(np.meshgrid(*[np.arange(cells)] * dim, indexing="ij"), axis=-1).reshape(-1, dim)
    unit = (grid[:, None, :] + basis[None, :, :]).reshape(-1, dim) * aspect
    count = unit.shape[0]
    cell_volume = float(np.prod(aspect)) * cells**dim
    particle_volume = _ball_volume(diameter / 2.0, dim)
    scale = (count * particle_volume / (packing_fraction * cell_volume)) ** (1.0 / dim)
    positions = unit * scale
    nearest = _nearest_distance(kind) * scale
    if nearest < diameter * (1 + 1e-12):
        raise ValueError(
            f"packing_fraction {packing_fraction} is above the close packing of the {kind} lattice"
        )
    return positions, aspect * cells * scale


def _nearest_distance(kind):
    return {"square": 1.0, "hexagonal": 1.0, "sc": 1.0, "fcc": math.sqrt(0.5)}[kind]


# ------------------------------------------------------------------ the system


def _per_particle(value, count, name, integer=False):
    """A scalar or shape (count,) input as a new float64 array (int64 if ``integer``)."""
    array = _real_array(value, name)
    if array.ndim == 0:
        array = np.full(count, array)
    elif array.shape != (count,):
        raise ValueError(f"{name} must be a scalar or have shape ({count},); got {array.shape}")
    if not integer:
        return array.copy()
    if not np.all(array % 1 == 0):
        raise ValueError(f"{name} must hold integers; got {array[~(array % 1 == 0)][0]}")
    return array.astype(np.int64)


def _periodic_axes(periodic, dim):
    """``periodic`` (a bool or one bool per axis) as a bool array of shape (dim,)."""
    array = np.asarray(periodic)
    if array.dtype != bool:
        raise TypeError(f"periodic must be a bool or a sequence of {dim} bools; got {periodic!r}")
    if array.shape not in ((), (dim,)):
        raise ValueError(f"periodic must be a bool or one bool per axis ({dim}); got shape {array.shape}")
    return np.broadcast_to(array, (dim,)).copy()


def _next_power_of_two(n):
    return 1 << max(n - 1, 1).bit_length()


def _aligned_zeros(shape, dtype=np.float64, alignment=64):
    """Zeros whose rows start on cache-line boundaries (64-byte particle records)."""
    itemsize = np.dtype(dtype).itemsize
    count = int(np.prod(shape))
    raw = np.zeros(count + alignment // itemsize, dtype=dtype)
    offset = (-raw.ctypes.data % alignment) // itemsize
    return raw[offset : offset + count].reshape(shape)


class HardSphereSystem:
    """N hard spheres (3D) or discs (2D) in a box, advanced event by event.

    Parameters
    ----------
    positions : array_like, shape (N, d)
        Centres, d = 2 or 3, inside the box [0, L) (for a walled axis the
        whole particle must be inside). No two particles may overlap.
    velocities : array_like, shape (N, d)
    radii : float or array_like, shape (N,)
        > 0.
    box : float or array_like, shape (d,)
        Box lengths L; each periodic axis must hold at least 3 cells of the
        largest contact distance (L >= 3 * max diameter).
    masses : float or array_like, shape (N,), optional
        > 0, default 1.
    periodic : bool or sequence of bool, optional
        Per axis: periodic (True, default) or hard walls at 0 and L.
    species : array_like of int, shape (N,), optional
        Species index per particle (0 .. S-1) for the restitution matrix.
    restitution : float or array_like, shape (S, S), optional
        Coefficient of normal restitution per species pair, in [0, 1].
    restitution_law : {"constant", "bridges"}
        "bridges": e = min(e_pair, (u_n / law_speed)^(-law_exponent)), the
        law measured for ice at planetary-ring temperatures (Bridges, Hatzes
        & Lin, Nature 309, 333 (1984), exponent 0.234).
    law_speed, law_exponent : float
        Parameters of the Bridges law.
    elastic_below : float, optional
        Contacts with normal approach speed below this are elastic: protects
        inelastic runs against inelastic collapse (infinitely many
        collisions in finite time), in the spirit of the TC model of Luding &
        McNamara (Granular Matter 1, 113 (1998)). Default: 0 for elastic
        systems, 1e-6 times the initial rms speed otherwise.
    wall_restitution : float
        Restitution of particle-wall contacts, in [0, 1].
    gravity : array_like, shape (d,), optional
        Uniform acceleration; flights become exact parabolas.
    neighbour_shell : float, optional
        Skin of the neighbour lists in units of the largest diameter, > 0
        (default 0.7, the fastest at eta = 0.45 in benchmarks/bench_edmd.py).
        A wider shell means longer lists but fewer rebuilds. Only speed
        depends on it; in small periodic boxes it is narrowed so that twice
        the list radius stays below the box.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
    >>> positions, box = lattice("fcc", 3, 0.3)
    >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(108), 3, rng=1), 0.5, box)
    >>> system.run(collisions=2000)
    2000
    >>> system.check() > -1e-9
    True
    """

    def __init__(
        self,
        positions,
        velocities,
        radii,
        box,
        masses=1.0,
        periodic=True,
        species=None,
        restitution=1.0,
        restitution_law="constant",
        law_speed=1.0,
        law_exponent=0.234,
        elastic_below=None,
        wall_restitution=1.0,
        gravity=None,
        neighbour_shell=DEFAULT_SHELL,
        *,
        _growth=0.0,
        _scale=1.0,
    ):
        positions = _real_array(positions, "positions")
        if positions.ndim != 2 or positions.shape[1] not in (2, 3):
            raise ValueError(f"positions must have shape (N, 2) or (N, 3); got {positions.shape}")
        count, dim = positions.shape
        if count < 2:
            raise ValueError(f"positions must hold at least 2 particles; got {count}")
        velocities = _real_array(velocities, "velocities")
        if velocities.shape != positions.shape:
            raise ValueError(f"velocities must have the shape of positions {positions.shape}; got {velocities.shape}")
        for array, name in ((positions, "positions"), (velocities, "velocities")):
            _arrays.require_finite(array, name)
        self.dim = dim
        radius = _positive(_per_particle(radii, count, "radii"), "radii", scalar=False)
        self._mass = _positive(_per_particle(masses, count, "masses"), "masses", scalar=False)
        box = _positive(_per_particle(box, dim, "box"), "box", scalar=False)
        periodic = _periodic_axes(periodic, dim)
        self._species = _per_particle(0 if species is None else species, count, "species", integer=True)
        self._set_restitution(restitution, restitution_law, law_speed, law_exponent, wall_restitution)
        gravity = np.zeros(dim) if gravity is None else _real_array(gravity, "gravity")
        if gravity.shape != (dim,):
            raise ValueError(f"gravity must have shape ({dim},); got {gravity.shape}")
        _arrays.require_finite(gravity, "gravity")
        self._shell_request = _positive(neighbour_shell, "neighbour_shell")

        self.geom = np.zeros((4, 3))
        self.geom[_k.G_BOX] = 1.0
        self.geom[_k.G_BOX, :dim] = box
        self.geom[_k.G_PERIODIC, :dim] = periodic
        self.geom[_k.G_GRAVITY, :dim] = gravity
        self.params[_k.P_SCALE0] = float(_scale)
        self.params[_k.P_GROWTH] = float(_growth)
        self.time = 0.0
        self.elapsed = 0.0
        self.p = _aligned_zeros((count, 8))
        self.p[:, _k.X : _k.X + dim] = positions
        self.p[:, _k.V : _k.V + dim] = velocities
        self.p[:, _k.R] = radius
        self._wrap_into_box()
        self._image = np.zeros((count, dim), dtype=np.int64)
        # particles live in memory in cell order (re-sorted as they move); ids maps slot -> particle
        self.ids = np.arange(count)
        self.last_sort = 0
        self.acc = np.zeros(_k.ACC_SIZE)
        if elastic_below is None:
            inelastic = np.any(self.restitution < 1.0) or restitution_law != "constant"
            rms = math.sqrt(np.mean(np.sum(velocities**2, axis=1))) if inelastic else 0.0
            elastic_below = 1e-6 * rms
        self.params[_k.P_ELASTIC_BELOW] = _bounded(elastic_below, "elastic_below", 0.0)
        self._new_events()
        self._refresh_lists()
        self._check_walls()
        gap = self._pair_gap()
        if gap < -1e-9 * float(np.max(radius)):
            raise OverlapError(f"positions overlap: {self._closest_pair_description(gap)}")

    # -------------------------------------------------------------- set-up helpers

    def _set_restitution(self, restitution, law, law_speed, law_exponent, wall_restitution):
        species_count = int(self._species.max()) + 1
        if np.any(self._species < 0):
            raise ValueError("species must be >= 0")
        matrix = _real_array(restitution, "restitution")
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
        law_speed = _positive(law_speed, "law_speed")
        law_exponent = _positive(law_exponent, "law_exponent")
        wall_restitution = _bounded(wall_restitution, "wall_restitution", 0.0, 1.0, closed=(True, True))
        self.restitution = np.ascontiguousarray(matrix)
        self.restitution_law = law
        self.params = np.zeros(_k.P_SIZE)
        self.params[_k.P_LAW] = RESTITUTION_LAWS[law]
        self.params[_k.P_LAW_SPEED] = law_speed
        self.params[_k.P_LAW_EXPONENT] = law_exponent
        self.params[_k.P_WALL_RESTITUTION] = wall_restitution

    def _wrap_into_box(self):
        for k in range(self.dim):
            column = self.p[:, _k.X + k]
            if self.periodic[k]:
                column %= self.box[k]
            elif np.any((column < 0) | (column > self.box[k])):
                raise ValueError(f"positions must lie inside the walls on axis {k}: [0, {self.box[k]}]")

    def _list_geometry(self, list_scale):
        """Shell and cells for lists valid up to radius scale ``list_scale``."""
        largest = 2.0 * float(np.max(self.p[:, _k.R])) * list_scale
        periodic_sides = self.box[: self.dim][self.periodic]
        if periodic_sides.size and periodic_sides.min() < 3.0 * largest * (1 - 1e-12):
            k = int(np.flatnonzero(self.periodic)[np.argmin(periodic_sides)])
            raise ValueError(
                f"box[{k}] = {self.box[k]:.6g} is too small: a periodic axis needs at least 3 times "
                f"the largest diameter ({largest:.6g})"
            )
        shell = self._shell_request * 2.0 * float(np.max(self.p[:, _k.R])) * max(list_scale, 1.0)
        if periodic_sides.size:
            # the minimum image must be unique within the list radius: 2 (largest + shell) < L
            shell = min(shell, 0.98 * (0.5 * periodic_sides.min() - largest))
        reach = largest + shell
        ncell = np.ones(3, dtype=np.int64)
        widths = np.ones(3)
        for k in range(self.dim):
            ncell[k] = max(int(math.floor(self.box[k] / reach * (1 - 1e-12))), 1)
            widths[k] = self.box[k] / ncell[k]
        return shell, ncell, widths

    def _refresh_lists(self):
        """Re-anchor every particle, rebuild every neighbour list and re-predict every event.

        Lists cover the radius scale of now (plus a margin while growing);
        cells and list rows are enlarged when needed.
        """
        self.synchronise()
        list_scale = self.scale0 + LIST_SCALE_MARGIN if self.growth > 0 else self.scale0
        shell, ncell, widths = self._list_geometry(list_scale)
        self.params[_k.P_SHELL] = shell
        self.params[_k.P_LIST_SCALE] = list_scale
        if not np.array_equal(ncell, getattr(self, "ncell", None)):
            self.ncell = ncell
            self._grow_cells(self.cell_members.shape[1] if hasattr(self, "cell_members") else 8)
        self.geom[_k.G_CELL] = widths
        while True:
            needed, fullest = _k.build_all_lists(
                self.p, self.book, self.cell_of, self.neighbours, self.neighbour_count, self.cell_members,
                self.cell_count, self.cell_points, self.ncell, self.geom, self.dim, self.params, self._image,
            )
            if fullest > self.cell_members.shape[1]:
                self._grow_cells(fullest)
            elif needed > self.neighbours.shape[1]:
                self._grow_lists(needed)
            else:
                break
        self._predict_all()

    @staticmethod
    def _room_for(needed):
        return max(needed + 4, int(1.25 * needed))

    def _grow_lists(self, needed):
        """Widen the neighbour-list rows to hold ``needed`` entries with room to spare."""
        self.neighbours = np.zeros((self.count, self._room_for(needed)), dtype=np.uint32)
        self.neighbour_count[:] = 0

    def _grow_cells(self, needed):
        """(Re)allocate the cells with ``needed`` slots each, with room to spare."""
        cells, slots = int(np.prod(self.ncell)), self._room_for(needed)
        self.cell_members = np.zeros((cells, slots), dtype=np.int32)
        self.cell_count = np.zeros(cells, dtype=np.int32)
        # anchors and radii in float32 (16 bytes a slot): a cell of 4 spheres in one cache line
        self.cell_points = np.zeros((cells, slots, 4), dtype=np.float32)

    def _check_walls(self):
        if not np.all(self.periodic):
            gap = _k.wall_gap(self.p, self.scale, self.geom, self.dim)
            if gap < -1e-9 * float(np.max(self.radius)):
                raise ValueError(f"positions must keep every particle inside the walls (overlap {-gap:.3g})")

    def _new_events(self):
        count = self.count
        # one 64-byte bookkeeping record per particle (next event, event numbers, anchor, mass, species)
        self.book = _aligned_zeros((count, 8))
        self.book[:, _k.TARGET] = _k.LIST_TARGET
        self._copy_masses_and_species()
        self.cell_of = np.zeros(count, dtype=np.int32)
        self.neighbours = np.zeros((count, 16), dtype=np.uint32)
        self.neighbour_count = np.zeros(count, dtype=np.int32)
        blocks = -(-count // _k.QUEUE_BLOCK)
        self.leaves = _next_power_of_two(blocks)
        self.queue = _aligned_zeros(blocks * _k.QUEUE_BLOCK)
        self.tree = _aligned_zeros((2 * self.leaves, 2))

    def _copy_masses_and_species(self):
        """The kernels read masses and species from the bookkeeping records."""
        self.book[:, _k.MASS] = self._mass
        self.book[:, _k.SPECIES] = self._species

    def _predict_all(self):
        _k.predict_all(
            self.p, self.book, self.neighbours, self.neighbour_count, self.geom, self.dim, self.params, self.queue,
            self.tree, self.leaves, self.acc,
        )

    @property
    def anchor(self):
        """Neighbour-list anchors: where each particle's list was last built (a view)."""
        return self.book[:, _k.ANCHOR : _k.ANCHOR + 3]

    # -------------------------------------------------------------- state

    @property
    def count(self) -> int:
        """Number of particles N."""
        return self.p.shape[0]

    @property
    def pos(self):
        """Positions at each particle's own time (a view; prefer :meth:`positions`)."""
        return self.p[:, _k.X : _k.X + self.dim]

    @property
    def vel(self):
        """Velocities at each particle's own time (a view; prefer :meth:`velocities`)."""
        return self.p[:, _k.V : _k.V + self.dim]

    @property
    def radius(self):
        """Radii at scale 1, in particle order."""
        return self._to_user_order(self.p[:, _k.R])

    @property
    def mass(self):
        """Masses, in particle order."""
        return self._to_user_order(self._mass)

    @property
    def species(self):
        """Species indices, in particle order."""
        return self._to_user_order(self._species)

    @property
    def image(self):
        """Periodic image counters (boundary crossings per axis) at the current time, in particle order."""
        self.synchronise()
        return self._to_user_order(self._folded()[1])

    def _folded(self, ahead=0.0):
        """Internal positions folded into [0, L) on periodic axes, and the matching image counters.

        The engine wraps a particle only when it rebuilds its neighbour list,
        so stored positions may lie up to half a shell outside the box.
        ``ahead`` > 0 moves them that far along their free flights first
        (exact only before the next event: see :meth:`_time_to_next_event`).
        """
        gravity = self.geom[_k.G_GRAVITY, : self.dim]
        pos = self.pos + self.vel * ahead + 0.5 * gravity * ahead**2
        image = self._image.copy()
        for k in np.flatnonzero(self.periodic):
            length = self.box[k]
            shift = np.floor(pos[:, k] / length)
            pos[:, k] -= shift * length
            image[:, k] += shift.astype(np.int64)
            rounded_up = pos[:, k] >= length  # -tiny + L rounds to L
            pos[rounded_up, k] -= length
            image[rounded_up, k] += 1
        return pos, image

    def _to_user_order(self, internal):
        result = np.empty_like(internal)
        result[self.ids] = internal
        return result

    def _sort_by_cell(self):
        """Renumber the memory slots in cell order so neighbours share cache lines.

        Particles keep their identity through ``ids``; all lists are rebuilt
        and all events re-predicted (the slots changed).
        """
        self._refresh_lists()
        order = np.argsort(self.cell_of, kind="stable")
        self.p[:] = self.p[order]
        self._mass = self._mass[order]
        self._species = self._species[order]
        self._image = self._image[order]
        self.ids = self.ids[order]
        self.book[:] = 0.0
        self.book[:, _k.TARGET] = _k.LIST_TARGET
        self._copy_masses_and_species()
        self._refresh_lists()
        self.last_sort = self.collisions

    @property
    def box(self):
        """Box lengths (3 entries; the third is 1 in 2D)."""
        return self.geom[_k.G_BOX]

    @property
    def periodic(self):
        return self.geom[_k.G_PERIODIC, : self.dim] != 0.0

    @property
    def cell_size(self):
        return self.geom[_k.G_CELL]

    @property
    def growth(self) -> float:
        """Relative growth rate of the radii (non-zero only while compressing)."""
        return float(self.params[_k.P_GROWTH])

    @property
    def scale0(self) -> float:
        return float(self.params[_k.P_SCALE0])

    def _stop_growing(self, scale):
        """End a compression: radii fixed at ``scale`` from now on (lists rebuilt)."""
        self.synchronise()
        self.params[_k.P_GROWTH] = 0.0
        self.params[_k.P_SCALE0] = scale
        self._refresh_lists()

    @property
    def elastic_below(self) -> float:
        """Normal approach speed below which contacts are elastic (the guard against inelastic collapse).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice
        >>> positions, box = lattice("square", 4, 0.3)
        >>> velocities = np.tile([1.0, 0.0], (16, 1))
        >>> HardSphereSystem(positions, velocities, 0.5, box, restitution=0.9).elastic_below  # 1e-6 rms speed
        1e-06
        """
        return float(self.params[_k.P_ELASTIC_BELOW])

    @property
    def scale(self) -> float:
        """Current radius scale factor (1 except during compression)."""
        return self.scale0 + self.growth * self.time

    @property
    def volume(self) -> float:
        return float(np.prod(self.box[: self.dim]))

    @property
    def collisions(self) -> int:
        """Pair collisions processed so far."""
        return int(self.acc[_k.ACC_PAIR_COLLISIONS])

    def synchronise(self):
        """Move every particle to the current time and restart the clock at 0.

        Keeping event times small keeps their round-off small; the total
        simulated time is kept in ``elapsed``.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, rng=1), 0.5, box)
        >>> _ = system.run(collisions=500)
        >>> system.synchronise()
        >>> system.time, system.elapsed > 0
        (0.0, True)
        """
        _k.synchronise(self.p, self.time, self.geom, self.dim)
        shift = self.time
        if shift != 0.0:
            self.p[:, _k.T] -= shift
            self.queue -= shift
            self.tree[:, 0] -= shift
            self.params[_k.P_SCALE0] += self.growth * shift
            self.elapsed += shift
            self.time = 0.0

    def positions(self, unwrapped=False):
        """Positions at the current time (a copy); ``unwrapped`` adds the periodic images.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, rng=1), 0.5, box)
        >>> _ = system.run(collisions=2000)
        >>> inside = system.positions()
        >>> bool((inside >= 0).all() and (inside < box).all())
        True
        >>> system.positions(unwrapped=True).shape
        (100, 2)
        """
        self.synchronise()
        internal = self.pos + self._image * self.box[: self.dim] if unwrapped else self._folded()[0]
        return self._to_user_order(internal)

    def velocities(self):
        """Velocities at the current time (a copy).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, rng=1), 0.5, box)
        >>> bool(np.allclose(system.velocities().sum(axis=0), 0.0))
        True
        """
        self.synchronise()
        return self._to_user_order(self.vel)

    def kinetic_energy(self) -> float:
        """Total kinetic energy sum(m v^2) / 2.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, rng=1), 0.5, box)
        >>> round(system.kinetic_energy(), 12)  # kT = 1 in 2D: K = N kT
        100.0
        """
        self.synchronise()
        return float(0.5 * np.sum(self._mass[:, None] * self.vel**2))

    def temperature(self) -> float:
        """kT = 2 K / (d N).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, rng=1), 0.5, box)
        >>> _ = system.run(collisions=1000)
        >>> round(system.temperature(), 12)  # elastic: unchanged
        1.0
        """
        return 2.0 * self.kinetic_energy() / (self.dim * self.count)

    def momentum(self):
        """Total momentum sum(m v).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, rng=1), 0.5, box)
        >>> bool(np.allclose(system.momentum(), 0.0))
        True
        """
        self.synchronise()
        return (self._mass[:, None] * self.vel).sum(axis=0)

    def set_velocities(self, velocities):
        """Replace all velocities (at the current time) and re-predict every event.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, rng=1), 0.5, box)
        >>> system.set_velocities(2.0 * system.velocities())
        >>> round(system.temperature(), 12)
        4.0
        """
        velocities = _real_array(velocities, "velocities")
        if velocities.shape != (self.count, self.dim):
            raise ValueError(f"velocities must have shape {(self.count, self.dim)}; got {velocities.shape}")
        _arrays.require_finite(velocities, "velocities")
        self.synchronise()
        self.p[:, _k.V : _k.V + self.dim] = velocities[self.ids]
        self._predict_all()

    def rescale_temperature(self, kT=1.0):
        """Scale all velocities to the temperature kT (kinetic definition); re-predicts events.

        Parameters
        ----------
        kT : float
            Finite and > 0. A system at rest cannot be rescaled.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, rng=1), 0.5, box)
        >>> system.rescale_temperature(0.25)
        >>> round(system.temperature(), 12)
        0.25
        """
        kT = _positive(kT, "kT")
        current = self.temperature()
        if current == 0.0:
            raise ValueError("cannot rescale the temperature of a system at rest (every velocity is zero)")
        self.set_velocities(self.velocities() * math.sqrt(kT / current))

    def check(self, tolerance=1e-9):
        """Verify the invariant: no overlaps between particles or with walls.

        Returns the smallest surface gap (negative only within round-off);
        raises :class:`OverlapError` if any gap is below ``-tolerance`` times
        the largest radius.

        Parameters
        ----------
        tolerance : float
            Allowed overlap relative to the largest radius, finite and >= 0.

        Returns
        -------
        float

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, rng=1), 0.5, box)
        >>> _ = system.run(collisions=5000)
        >>> system.check() > -1e-12
        True
        """
        tolerance = _bounded(tolerance, "tolerance", 0.0)
        self.synchronise()
        gap = self._pair_gap()
        if not np.all(self.periodic):
            gap = min(gap, _k.wall_gap(self.p, self.scale, self.geom, self.dim))
        if gap < -tolerance * float(np.max(self.radius)):
            raise OverlapError(f"overlap of {-gap:.3g} found at time {self.elapsed + self.time:.6g}")
        drift = _k.largest_anchor_drift(self.p, self.book, self.dim)
        allowed = 0.5 * self.params[_k.P_SHELL] + tolerance * float(np.max(self.box[: self.dim]))
        if drift > allowed:
            # the lists would miss collisions: an engine bug, never a user error
            raise RuntimeError(f"a particle drifted {drift:.6g} from its list anchor (allowed {allowed:.6g})")
        return gap

    def _time_to_next_event(self):
        """Time from now (particles synchronised) to the next queued event; inf if none.

        Until then every particle flies freely: no collision can come earlier
        (the queue holds each particle's earliest, list events included).
        """
        return float(self.tree[1, 0]) - self.time

    def _closest_pair_description(self, gap):
        """'particles i and j, surface gap g' for the most overlapping pair (user indices), found by a k-d tree."""
        from scipy.spatial import cKDTree

        dim, scale = self.dim, self.scale
        points, _ = self._folded()
        box = self.box[:dim]
        radii = self.p[:, _k.R] * scale
        tree = cKDTree(points, boxsize=box if np.all(self.periodic[:dim]) else None)
        pairs = tree.query_pairs(2.0 * float(radii.max()), output_type="ndarray")
        if len(pairs) == 0:
            return f"smallest surface gap {gap:.3g}"
        separation = points[pairs[:, 1]] - points[pairs[:, 0]]
        wrapped = np.asarray(self.periodic[:dim], dtype=bool)
        separation[:, wrapped] -= box[wrapped] * np.round(separation[:, wrapped] / box[wrapped])
        gaps = np.linalg.norm(separation, axis=1) - radii[pairs[:, 0]] - radii[pairs[:, 1]]
        worst = int(np.argmin(gaps))
        first, second = sorted(int(self.ids[k]) for k in pairs[worst])
        return f"particles {first} and {second}, surface gap {gaps[worst]:.3g}"

    def _pair_gap(self):
        return _k.min_gap(
            self.p, self.scale, self.cell_of, self.cell_members, self.cell_count, self.ncell, self.geom, self.dim
        )

    # -------------------------------------------------------------- running

    def run(self, collisions=None, time=None, progress=None, chunk=None):
        """Advance by a number of pair collisions and/or a stretch of time.

        Parameters
        ----------
        collisions : int, optional
            Pair collisions to process, >= 0.
        time : float, optional
            Simulated time to advance, finite and >= 0 (the run stops at
            whichever comes first).
        progress : callable, optional
            Called with the number of collisions done after each chunk.
        chunk : int, optional
            Collisions per kernel call, >= 1 (default: max(N, 10^5)).

        Returns
        -------
        int
            Pair collisions processed.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, rng=1), 0.5, box)
        >>> system.run(collisions=1000)
        1000
        >>> system.run(time=0.5) > 0, round(system.elapsed, 12) > 0
        (True, True)
        """
        if collisions is None and time is None:
            raise ValueError("give collisions or time (or both)")
        target = np.iinfo(np.int64).max if collisions is None else _count(collisions, "collisions", 0)
        remaining = math.inf if time is None else _bounded(time, "time", 0.0)
        chunk = max(self.count, 100_000) if chunk is None else _count(chunk, "chunk", 1)
        done = 0
        while done < target and remaining > 0:
            step = min(chunk, target - done)
            if self.collisions - self.last_sort >= SORT_INTERVAL * self.count:
                self._sort_by_cell()
            before, start = self.collisions, self.time
            # while growing, the lists hold only up to the radius scale they were built for
            lists_expire = (self.params[_k.P_LIST_SCALE] - self.scale) / self.growth if self.growth > 0 else math.inf
            span = max(min(remaining, lists_expire), 0.0)
            self.time = self._run_events(step, start + span)
            lists_expired = lists_expire < remaining and self.time == start + span
            advanced = self.collisions - before
            done += advanced
            remaining -= self.time - start
            if progress is not None:
                progress(advanced)
            self.synchronise()
            if self.acc[_k.ACC_LIST_OVERFLOW] > 0 or self.acc[_k.ACC_CELL_OVERFLOW] > 0:
                if self.acc[_k.ACC_LIST_OVERFLOW] > 0:
                    self._grow_lists(int(self.acc[_k.ACC_LIST_OVERFLOW]))
                if self.acc[_k.ACC_CELL_OVERFLOW] > 0:
                    self._grow_cells(int(self.acc[_k.ACC_CELL_OVERFLOW]))
                self.acc[_k.ACC_LIST_OVERFLOW] = self.acc[_k.ACC_CELL_OVERFLOW] = 0.0
                self._refresh_lists()
            elif lists_expired:
                self._refresh_lists()
            elif advanced < step:  # stopped by the time limit, or nothing left to happen
                break
        return done

    def compile_event_loop(self):
        """Compile the event loop now (numba compiles at the first call), so that a timed run times only events.

        A run of no collisions: the state does not change. Takes seconds on
        a cold numba cache, a fraction of one when the cache is warm.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, rng=1), 0.5, box)
        >>> system.compile_event_loop()
        >>> system.collisions, system.elapsed
        (0, 0.0)
        """
        self._run_events(0, self.time)

    def _run_events(self, collisions, t_stop):
        return _k.run_events(
            self.time, collisions, t_stop, self.p, self.book, self._image, self.cell_of, self.neighbours,
            self.neighbour_count, self.cell_members, self.cell_count, self.cell_points, self.ncell, self.geom, self.dim,
            self.restitution, self.params, self.queue, self.tree, self.leaves, self.acc,
        )

    # -------------------------------------------------------------- checkpoints

    _ARRAYS = ("p", "_mass", "_species", "_image", "ids", "acc", "geom", "params", "restitution", "book", "cell_of",
               "ncell", "queue", "tree", "neighbours", "neighbour_count", "cell_members", "cell_count", "cell_points")
    _SCALARS = ("dim", "time", "elapsed", "leaves", "last_sort", "_shell_request")
    # layout of the engine's arrays in a checkpoint; raise it when they change (2: bookkeeping records, block queue)
    STATE_FORMAT = 2

    def state_dict(self):
        """Every array and number needed to continue the run bit for bit.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, rng=1), 0.5, box)
        >>> copy = HardSphereSystem.from_state_dict(system.state_dict())
        >>> system.run(collisions=300), copy.run(collisions=300)
        (300, 300)
        >>> bool((system.positions() == copy.positions()).all())
        True
        """
        state = {name: getattr(self, name) for name in self._ARRAYS}
        state |= {name: np.asarray(getattr(self, name)) for name in self._SCALARS}
        state["restitution_law"] = np.asarray(self.restitution_law)
        state["format"] = np.asarray(self.STATE_FORMAT)
        return state

    @classmethod
    def from_state_dict(cls, state):
        """Rebuild a system from :meth:`state_dict` output (no re-prediction).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, rng=1), 0.5, box)
        >>> HardSphereSystem.from_state_dict(system.state_dict()).count
        100
        """
        written = int(state["format"]) if "format" in state else 1
        if written != cls.STATE_FORMAT:
            raise ValueError(
                f"state has engine format {written}; this collisionkit reads format {cls.STATE_FORMAT} "
                "(checkpoints do not carry over between engine versions: restart the run)"
            )
        system = cls.__new__(cls)
        for name in cls._ARRAYS:
            setattr(system, name, np.array(state[name]))
        for name in ("p", "book", "queue", "tree"):
            aligned = _aligned_zeros(getattr(system, name).shape)
            aligned[:] = getattr(system, name)
            setattr(system, name, aligned)
        for name in cls._SCALARS:
            setattr(system, name, state[name].item())
        system.restitution_law = str(state["restitution_law"])
        return system

    def save(self, path):
        """Write a checkpoint (.npz) atomically: a kill mid-write keeps the old one.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, rng=1), 0.5, box)
        >>> path = pathlib.Path(tempfile.mkdtemp()) / "run.npz"
        >>> _ = system.save(path)
        >>> HardSphereSystem.load(path).collisions == system.collisions
        True
        """
        import io

        buffer = io.BytesIO()
        np.savez(buffer, **self.state_dict())
        return atomic_write_bytes(path, buffer.getvalue())

    @classmethod
    def load(cls, path):
        """Read a checkpoint written by :meth:`save`.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, rng=1), 0.5, box)
        >>> path = pathlib.Path(tempfile.mkdtemp()) / "run.npz"
        >>> _ = system.run(collisions=100)
        >>> _ = system.save(path)
        >>> restored = HardSphereSystem.load(path)
        >>> restored.run(collisions=100), system.run(collisions=100)
        (100, 100)
        >>> bool((restored.velocities() == system.velocities()).all())
        True
        """
        with np.load(Path(path), allow_pickle=False) as data:
            return cls.from_state_dict({name: data[name] for name in data.files})

    def __repr__(self):
        kind = "spheres" if self.dim == 3 else "discs"
        return (
            f"HardSphereSystem({self.count} {kind}, eta={packing_fraction(self.radius * self.scale, self.box[: self.dim]):.4f}, "
            f"collisions={self.collisions}, time={self.elapsed + self.time:.6g})"
        )

    def _repr_html_(self):
        from ._repr import hard_sphere_system_rows, html_table

        return html_table("HardSphereSystem", hard_sphere_system_rows(self))


# ------------------------------------------------------------------ compression


def random_fluid(
    dim,
    particles,
    packing_fraction,
    rng=None,
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
        Target eta: up to 0.5 in 3D and 0.7 in 2D are supported (denser runs
        risk jamming before the target; the run fails clearly if so).
    rng : numpy.random.Generator or int, optional
    diameters, masses : float or array_like, shape (N,)
        Final diameters and masses (mixtures allowed), finite and > 0.
    kT : float
        Finite and > 0.
    growth_rate : float
        Relative growth of the diameters per unit time, finite and > 0.
    progress : callable, optional
        Called with the fraction of the compression done.
    **system_options
        Passed to :class:`HardSphereSystem` (restitution, ...); the box is
        periodic.

    Examples
    --------
    >>> from collisionkit.edmd import random_fluid
    >>> system = random_fluid(3, 200, 0.3, rng=1)
    >>> round(float(system.temperature()), 12), system.check() > -1e-9
    (1.0, True)
    """
    dim = _dimension(dim)
    particles = _count(particles, "particles", 2)
    limit = 0.5 if dim == 3 else 0.7
    packing_fraction = _bounded(packing_fraction, f"packing_fraction (dim={dim})", 0.0, limit, closed=(False, True))
    growth_rate = _positive(growth_rate, "growth_rate")
    kT = _positive(kT, "kT")
    generator = np.random.default_rng(rng)
    diameters = _positive(_per_particle(diameters, particles, "diameters"), "diameters", scalar=False)
    masses = _per_particle(masses, particles, "masses")
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
    system = HardSphereSystem(
        positions, velocities, radii, side, masses, periodic=True, _growth=growth_rate, _scale=start, **system_options
    )
    total_time = (1.0 - start) / growth_rate
    done = 0.0
    while done < total_time:
        step = min(1.0, total_time - done)
        system.run(time=step)
        done += step
        system.rescale_temperature(kT)
        if progress is not None:
            progress(done / total_time)
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


# ------------------------------------------------------------------ measurement


RECORDS = ("temperature", "compressibility", "pressure", "frequency", "time", "msd", "msd_groups")
MSD_GROUPS = 8  # particles dealt into groups (by index) for the error of the diffusion coefficient
MSD_FIT_FROM = 0.3  # the diffusive part of the MSD: fitted from this fraction of the run (or longest lag) on
MSD_MAX_LAGS = 8  # time origins kept for the multiple-origin MSD (memory: this many copies of the positions)


def _group_means(values):
    """Mean of per-particle ``values`` over each of the MSD_GROUPS groups (particle i in group i % MSD_GROUPS).

    A group with no particle (fewer particles than groups) gets NaN.
    """
    groups = np.arange(values.size) % MSD_GROUPS
    totals = np.bincount(groups, weights=values, minlength=MSD_GROUPS)
    counts = np.bincount(groups, minlength=MSD_GROUPS)
    return np.divide(totals, counts, out=np.full(MSD_GROUPS, math.nan), where=counts > 0)


class _LagMSD:
    """Mean squared displacement over block lags from every block end as a time origin.

    Keeps the last ``lags`` block-end positions; at each block end it adds,
    for each lag k, ``|r(t_b) - r(t_{b-k})|^2`` averaged over all particles
    and over each group of :data:`MSD_GROUPS`, and the time lag. Averaging
    over origins (Allen & Tildesley, Computer Simulation of Liquids, 2nd ed.,
    sec. 8.7; Frenkel & Smit, sec. 4.4.1) makes the error of D fall with the
    number of origins (blocks); from one origin it does not fall with the
    length of the run.
    """

    def __init__(self, lags, positions, time):
        self.lags = lags
        self.positions, self.times = [positions], [time]
        self.all = np.zeros(lags)
        self.groups = np.zeros((lags, MSD_GROUPS))
        self.time_lags = np.zeros(lags)
        self.counts = np.zeros(lags)

    def add(self, positions, time):
        for k in range(1, len(self.positions) + 1):
            squared = np.sum((positions - self.positions[-k]) ** 2, axis=1)
            self.all[k - 1] += np.mean(squared)
            self.groups[k - 1] += _group_means(squared)
            self.time_lags[k - 1] += time - self.times[-k]
            self.counts[k - 1] += 1
        self.positions = (self.positions + [positions])[-self.lags:]
        self.times = (self.times + [time])[-self.lags:]

    def diffusion(self, dim):
        """(D, error) from the slope over the longer lags, or None with fewer than 2 lags measured."""
        measured = int(np.count_nonzero(self.counts))
        if measured < 2:
            return None
        first = max(0, min(math.ceil(MSD_FIT_FROM * measured) - 1, measured - 2))
        counts = self.counts[first:measured]
        times = self.time_lags[first:measured] / counts
        slope = float(np.polyfit(times, self.all[first:measured] / counts, 1)[0])
        groups = self.groups[first:measured] / counts[:, None]
        if not np.all(np.isfinite(groups)):
            return slope / (2.0 * dim), math.nan
        return slope / (2.0 * dim), _block_error(np.polyfit(times, groups, 1)[0]) / (2.0 * dim)

    def state_dict(self):
        return {"sampler_lag_positions": np.array(self.positions), "sampler_lag_times": np.array(self.times),
                "sampler_lag_all": self.all, "sampler_lag_groups": self.groups,
                "sampler_lag_time_lags": self.time_lags, "sampler_lag_counts": self.counts}

    @classmethod
    def from_state_dict(cls, state):
        """The accumulators of a checkpoint, or None for one written before they existed."""
        if "sampler_lag_positions" not in state:
            return None
        lag = cls.__new__(cls)
        lag.lags = len(state["sampler_lag_counts"])
        lag.positions = list(np.array(state["sampler_lag_positions"]))
        lag.times = [float(t) for t in state["sampler_lag_times"]]
        lag.all = np.array(state["sampler_lag_all"])
        lag.groups = np.array(state["sampler_lag_groups"])
        lag.time_lags = np.array(state["sampler_lag_time_lags"])
        lag.counts = np.array(state["sampler_lag_counts"])
        return lag


def _diffusion_from_msd(msd_time, msd, msd_groups, dim):
    """D = slope / (2 d) of the MSD's later part (ballistic start left out), and its standard error.

    Every block's MSD is measured from one time origin, so blocks do not give
    independent values; independent groups of particles do: the error is the
    standard error of the groups' slopes (Frenkel & Smit, Understanding
    Molecular Simulation, sec. 4.4.1, for D from the MSD).
    """
    later = msd_time > MSD_FIT_FROM * msd_time[-1]
    if later.sum() < 2:
        return math.nan, math.nan
    slope = float(np.polyfit(msd_time[later], msd[later], 1)[0])
    groups = np.vstack([np.zeros(MSD_GROUPS), np.asarray(msd_groups, dtype=float)])[later]
    if not np.all(np.isfinite(groups)):
        return slope / (2.0 * dim), math.nan
    group_slopes = np.polyfit(msd_time[later], groups, 1)[0]
    return slope / (2.0 * dim), _block_error(group_slopes) / (2.0 * dim)


def _block_error(values):
    values = np.asarray(values, dtype=float)
    if values.size < 2:
        return math.nan
    return float(values.std(ddof=1) / math.sqrt(values.size))


@dataclass
class Measurement:
    """Observables of an EDMD run, block averaged; each ``*_error`` is one standard error.

    Attributes: ``compressibility_factor``, ``pressure``, ``temperature``
    (final kT), ``collision_frequency`` (per particle, each pair collision
    counting for both), ``mean_free_time``, ``mean_free_path``,
    ``diffusion_coefficient`` (from the mean squared displacement with
    every block end as a time origin, lags up to ``blocks // 2`` blocks, at
    most 8; its error from the scatter of 8 groups of particles,
    ``MSD_GROUPS``, since overlapping origins give no independent blocks),
    ``energy_lost``, ``contact_value`` (g at contact); arrays ``speeds`` (a
    sample), ``rdf_r``, ``rdf`` (g(r)), ``msd_time``, ``msd``, ``block_*`` per
    block; ``wall_seconds`` is the wall clock of the measurement (events and
    sampling, not compiling), so ``collisions_per_second`` is the rate a run
    of this size delivers.

    Examples
    --------
    >>> from collisionkit.edmd import henderson, measure, random_fluid
    >>> m = measure(random_fluid(2, 400, 0.3, rng=2), collisions=40_000, blocks=4)
    >>> abs(m.compressibility_factor - float(henderson(0.3))) < 5 * m.compressibility_factor_error + 0.05
    True
    """

    dim: int
    particles: int
    packing_fraction: float
    collisions: int
    time: float
    wall_seconds: float
    temperature: float
    compressibility_factor: float
    compressibility_factor_error: float
    pressure: float
    pressure_error: float
    collision_frequency: float
    collision_frequency_error: float
    mean_free_time: float
    mean_free_time_error: float
    mean_free_path: float
    mean_free_path_error: float
    mean_speed: float
    diffusion_coefficient: float
    diffusion_coefficient_error: float
    energy_lost: float
    contact_value: float
    contact_value_error: float
    speeds: np.ndarray = field(repr=False)
    rdf_r: np.ndarray = field(repr=False)
    rdf: np.ndarray = field(repr=False)
    msd_time: np.ndarray = field(repr=False)
    msd: np.ndarray = field(repr=False)
    block_temperature: np.ndarray = field(repr=False)
    block_compressibility: np.ndarray = field(repr=False)
    block_frequency: np.ndarray = field(repr=False)

    @property
    def collisions_per_second(self) -> float:
        return self.collisions / self.wall_seconds if self.wall_seconds > 0 else math.inf

    def summary(self) -> dict:
        """Scalars as a JSON-ready dict.

        Examples
        --------
        >>> from collisionkit.edmd import measure, random_fluid
        >>> summary = measure(random_fluid(2, 200, 0.3, rng=1), collisions=4000, blocks=2).summary()
        >>> summary["collisions"], "compressibility_factor" in summary
        (4000, True)
        """
        keys = (
            "dim particles packing_fraction collisions time temperature compressibility_factor "
            "compressibility_factor_error pressure pressure_error collision_frequency collision_frequency_error "
            "mean_free_time mean_free_time_error mean_free_path mean_free_path_error mean_speed diffusion_coefficient "
            "diffusion_coefficient_error energy_lost contact_value contact_value_error"
        ).split()
        result = {key: getattr(self, key) for key in keys}
        result["collisions_per_second"] = self.collisions_per_second
        return result

    def _repr_html_(self):
        from ._repr import html_table, measurement_rows

        return html_table("Measurement", measurement_rows(self))


def _pair_histogram(system, r_max, bins):
    """Counts of pairs (each counted twice) per distance bin up to r_max, in one snapshot.

    The snapshot is taken half-way to the next event, not at the last one:
    there the pair that just collided sits exactly at contact, one extra
    contact pair a snapshot (12 % of the contact bin for 400 discs).
    """
    dim = system.dim
    system.synchronise()
    gap = system._time_to_next_event()
    points = system._folded(ahead=0.5 * gap if 0.0 < gap < math.inf else 0.0)[0]
    return _pair_distance_histogram(points[:, :dim], system.box[:dim], system.periodic[:dim], r_max, bins)


def _pair_distance_histogram(points, box, periodic, r_max, bins):
    """Ordered pairs (i != j) per distance bin of width r_max / bins, points in [0, L) per axis.

    A cell-list kernel, O(N) for a fixed r_max (a k-d tree's
    ``count_neighbors`` over 500 radii took 3.6 s a snapshot for 4000
    spheres, most of an ``edmd`` run). Periodic axes use the minimum image
    (r_max <= L / 2 there), walled ones the plain distance.
    """
    count, dim = np.shape(points)
    padded = np.zeros((count, 3))  # 2D: z = 0 in one walled cell
    padded[:, :dim] = points
    cells_box = np.ones(3)
    cells_box[:dim] = box
    axes_periodic = np.zeros(3, dtype=np.bool_)
    axes_periodic[:dim] = periodic
    ncell = np.ones(3, dtype=np.int64)
    ncell[:dim] = np.maximum(np.floor(cells_box[:dim] / r_max), 1)
    coordinates = np.clip((padded / cells_box * ncell).astype(np.int64), 0, ncell - 1)
    cell = coordinates[:, 0] + ncell[0] * (coordinates[:, 1] + ncell[1] * coordinates[:, 2])
    in_cell_order = np.ascontiguousarray(padded[np.argsort(cell, kind="stable")])
    cell_start = np.concatenate([[0], np.cumsum(np.bincount(cell, minlength=int(np.prod(ncell))))])
    counts = np.zeros(bins)
    _k.pair_distance_counts(in_cell_order, cell_start, ncell, cells_box, axes_periodic, float(r_max), counts)
    return counts


def _contact_value(r, g, counts, diameter):
    """g at contact and its standard error: a weighted quadratic fit to the bins
    within 0.1 diameter of contact, extrapolated to contact (Poisson errors per bin,
    of the pairs: ``counts`` counts each pair twice)."""
    near = (r > diameter) & (r < 1.1 * diameter) & (counts > 0)
    if near.sum() < 4:
        return math.nan, math.nan
    sigma = g[near] / np.sqrt(0.5 * counts[near])
    x = r[near] - diameter
    coefficients, covariance = np.polyfit(x, g[near], 2, w=1.0 / sigma, cov="unscaled")
    return float(coefficients[-1]), float(math.sqrt(covariance[-1, -1]))


class Sampler:
    r"""Block-by-block measurement of an EDMD run, resumable from a checkpoint.

    Each block runs ``collisions // blocks`` pair collisions, then records:
    kT = 2K/(dN); the compressibility factor from the collisional virial,
    :math:`Z = 1 + \sum_{coll} J\sigma / (d N kT\,t)` (J the impulse, sigma
    the contact distance; Allen & Tildesley, Computer Simulation of Liquids,
    2nd ed., sec. 3.7); the collision frequency per particle
    :math:`\omega = 2 C / (N t)`; speeds; pair distances for g(r); and the
    mean squared displacement, from the start and from the earlier block ends
    as time origins (it keeps up to 8 copies of the positions for them, 24 MB
    per copy at 10^6 spheres). Errors are standard errors of the block means
    (of groups of particles for the diffusion coefficient).

    Parameters
    ----------
    system : HardSphereSystem
    collisions : int
        Pair collisions over all blocks, >= blocks.
    blocks : int
        Number of blocks, >= 2.
    rdf_bins : int
        Bins of g(r) up to min(L/2, 5 diameters).

    Examples
    --------
    >>> from collisionkit.edmd import Sampler, random_fluid
    >>> system = random_fluid(3, 300, 0.3, rng=1)
    >>> sampler = Sampler(system, collisions=30_000, blocks=3)
    >>> while not sampler.finished:
    ...     sampler.run_block()
    >>> m = sampler.result()
    >>> m.collisions, 3.5 < m.compressibility_factor < 4.5
    (30000, True)
    """

    def __init__(self, system: HardSphereSystem, collisions: int, blocks: int = 10, rdf_bins: int = 500):
        if not isinstance(system, HardSphereSystem):
            raise TypeError(f"system must be a HardSphereSystem; got {type(system).__name__}")
        self.blocks = _count(blocks, "blocks", 2)
        self.per_block = _count(collisions, "collisions", self.blocks) // self.blocks
        rdf_bins = _count(rdf_bins, "rdf_bins", 10)
        self.system = system
        dim = system.dim
        self.r_max = float(min(system.box[:dim].min() / 2.0, 5.0 * 2.0 * np.max(system.radius)))
        self.histogram = np.zeros(rdf_bins)
        self.start_positions = system.positions(unwrapped=True)
        self.start_time = system.elapsed
        self.lag_msd = _LagMSD(min(MSD_MAX_LAGS, max(1, self.blocks // 2)), self.start_positions, self.start_time)
        self.start_lost = float(system.acc[_k.ACC_ENERGY_LOST])
        self.wall_seconds = 0.0
        self.records = {name: [] for name in RECORDS}
        self.speeds = []

    @property
    def done(self) -> int:
        """Blocks finished."""
        return len(self.records["temperature"])

    @property
    def finished(self) -> bool:
        return self.done >= self.blocks

    def run_block(self, progress=None):
        """Run and record one block.

        Examples
        --------
        >>> from collisionkit.edmd import Sampler, lattice, maxwell_boltzmann, HardSphereSystem
        >>> import numpy as np
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, rng=1), 0.5, box)
        >>> sampler = Sampler(system, collisions=4000, blocks=2)
        >>> sampler.run_block()
        >>> sampler.done, sampler.finished
        (1, False)
        """
        import time as _time

        system = self.system
        dim, count = system.dim, system.count
        kT_before = system.temperature()
        virial0, collisions0, time0 = system.acc[_k.ACC_VIRIAL], system.collisions, system.elapsed
        system.compile_event_loop()  # numba compiles at the first call: not a part of the timed run
        # the measurement's wall clock: the events and the sampling of this block
        tick = _time.perf_counter()
        system.run(collisions=self.per_block, progress=progress)
        kT_after = system.temperature()
        kT = 0.5 * (kT_before + kT_after)
        duration = system.elapsed - time0
        virial = system.acc[_k.ACC_VIRIAL] - virial0
        record = self.records
        record["temperature"].append(kT_after)
        record["compressibility"].append(1.0 + virial / (dim * count * kT * duration))
        record["pressure"].append((count * kT + virial / (dim * duration)) / system.volume)
        record["frequency"].append(2.0 * (system.collisions - collisions0) / (count * duration))
        record["time"].append(system.elapsed - self.start_time)
        unwrapped = system.positions(unwrapped=True)
        squared = np.sum((unwrapped - self.start_positions) ** 2, axis=1)
        record["msd"].append(float(np.mean(squared)))
        record["msd_groups"].append(_group_means(squared))
        if self.lag_msd is not None:
            self.lag_msd.add(unwrapped, system.elapsed)
        self.speeds.append(np.linalg.norm(system.velocities(), axis=1))
        self.histogram += _pair_histogram(system, self.r_max, self.histogram.size)
        self.wall_seconds += _time.perf_counter() - tick

    def state_dict(self):
        """The sampler's accumulators as arrays (the system is saved separately).

        Examples
        --------
        >>> from collisionkit.edmd import Sampler, lattice, maxwell_boltzmann, HardSphereSystem
        >>> import numpy as np
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, rng=1), 0.5, box)
        >>> sampler = Sampler(system, collisions=4000, blocks=2)
        >>> sampler.run_block()
        >>> sorted(sampler.state_dict())[:3]
        ['sampler_compressibility', 'sampler_frequency', 'sampler_histogram']
        """
        state = {f"sampler_{name}": np.asarray(values, dtype=float) for name, values in self.records.items()}
        state |= {
            "sampler_speeds": np.asarray(self.speeds, dtype=float).reshape(len(self.speeds), -1),
            "sampler_histogram": self.histogram,
            "sampler_start_positions": self.start_positions,
            "sampler_scalars": np.array(
                [self.blocks, self.per_block, self.r_max, self.start_time, self.start_lost, self.wall_seconds]
            ),
        }
        if self.lag_msd is not None:
            state |= self.lag_msd.state_dict()
        return state

    @classmethod
    def from_state_dict(cls, system: HardSphereSystem, state):
        """Rebuild a sampler of ``system`` from :meth:`state_dict` output.

        Examples
        --------
        >>> from collisionkit.edmd import Sampler, lattice, maxwell_boltzmann, HardSphereSystem
        >>> import numpy as np
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, rng=1), 0.5, box)
        >>> sampler = Sampler(system, collisions=4000, blocks=2)
        >>> sampler.run_block()
        >>> Sampler.from_state_dict(system, sampler.state_dict()).done
        1
        """
        if not isinstance(system, HardSphereSystem):
            raise TypeError(f"system must be a HardSphereSystem; got {type(system).__name__}")
        sampler = cls.__new__(cls)
        sampler.system = system
        blocks, per_block, r_max, start_time, start_lost, wall = state["sampler_scalars"]
        sampler.blocks, sampler.per_block = int(blocks), int(per_block)
        sampler.r_max, sampler.start_time, sampler.start_lost, sampler.wall_seconds = r_max, start_time, start_lost, wall
        sampler.histogram = np.array(state["sampler_histogram"])
        sampler.start_positions = np.array(state["sampler_start_positions"])
        sampler.records = {name: list(state[f"sampler_{name}"]) for name in RECORDS if f"sampler_{name}" in state}
        # a checkpoint written before the groups were recorded: their blocks are unknown (no D error)
        sampler.records.setdefault("msd_groups", [np.full(MSD_GROUPS, math.nan)] * len(sampler.records["msd"]))
        sampler.speeds = [row for row in np.array(state["sampler_speeds"])]
        sampler.lag_msd = _LagMSD.from_state_dict(state)
        return sampler

    def result(self) -> Measurement:
        """The observables over the blocks done so far (at least 2).

        Examples
        --------
        >>> from collisionkit.edmd import Sampler, lattice, maxwell_boltzmann, HardSphereSystem
        >>> import numpy as np
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, rng=1), 0.5, box)
        >>> sampler = Sampler(system, collisions=4000, blocks=2)
        >>> while not sampler.finished:
        ...     sampler.run_block()
        >>> 1.5 < sampler.result().compressibility_factor < 2.6
        True
        """
        if self.done < 2:
            raise ValueError(f"need at least 2 finished blocks for errors; have {self.done}")
        system, dim, count = self.system, self.system.dim, self.system.count
        record = self.records
        edges = np.linspace(0.0, self.r_max, self.histogram.size + 1)
        centres = 0.5 * (edges[1:] + edges[:-1])
        shells = _ball_volume(edges[1:], dim) - _ball_volume(edges[:-1], dim)
        # ordered pairs: each of the N particles sees the other N - 1 at density (N - 1) / V
        rdf = self.histogram / (self.done * count * ((count - 1) / system.volume) * shells)
        speeds = np.concatenate(self.speeds)
        omega = float(np.mean(record["frequency"]))
        mean_speed = float(np.mean(speeds))
        msd_time = np.concatenate([[0.0], record["time"]])
        msd = np.concatenate([[0.0], record["msd"]])
        from_lags = self.lag_msd.diffusion(dim) if self.lag_msd is not None else None
        diffusion, diffusion_error = from_lags or _diffusion_from_msd(msd_time, msd, record["msd_groups"], dim)
        omega_error = _block_error(record["frequency"])
        diameter = 2.0 * float(np.max(system.radius))
        contact, contact_error = _contact_value(centres, rdf, self.histogram, diameter)
        return Measurement(
            dim=dim,
            particles=count,
            packing_fraction=packing_fraction(system.radius * system.scale, system.box[:dim]),
            collisions=self.per_block * self.done,
            time=float(msd_time[-1]),
            wall_seconds=self.wall_seconds,
            temperature=float(record["temperature"][-1]),
            compressibility_factor=float(np.mean(record["compressibility"])),
            compressibility_factor_error=_block_error(record["compressibility"]),
            pressure=float(np.mean(record["pressure"])),
            pressure_error=_block_error(record["pressure"]),
            collision_frequency=omega,
            collision_frequency_error=omega_error,
            mean_free_time=1.0 / omega,
            mean_free_time_error=omega_error / omega**2,
            mean_free_path=mean_speed / omega,
            mean_free_path_error=mean_speed * omega_error / omega**2,
            mean_speed=mean_speed,
            diffusion_coefficient=diffusion,
            diffusion_coefficient_error=diffusion_error,
            energy_lost=float(system.acc[_k.ACC_ENERGY_LOST] - self.start_lost),
            contact_value=contact,
            contact_value_error=contact_error,
            speeds=speeds,
            rdf_r=centres,
            rdf=rdf,
            msd_time=msd_time,
            msd=msd,
            block_temperature=np.asarray(record["temperature"]),
            block_compressibility=np.asarray(record["compressibility"]),
            block_frequency=np.asarray(record["frequency"]),
        )


def measure(system: HardSphereSystem, collisions: int, blocks: int = 10, rdf_bins: int = 500, progress=None):
    """Run ``collisions`` pair collisions in ``blocks`` blocks and return the observables.

    See :class:`Sampler` for the estimators.

    Examples
    --------
    >>> from collisionkit.edmd import measure, random_fluid
    >>> m = measure(random_fluid(2, 300, 0.3, rng=1), collisions=30_000, blocks=3)
    >>> 1.8 < m.compressibility_factor < 2.3
    True
    """
    sampler = Sampler(system, collisions, blocks, rdf_bins)
    while not sampler.finished:
        sampler.run_block(progress)
    return sampler.result()
