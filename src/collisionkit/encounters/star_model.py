r"""Particle stars: an SPH model's particles with their units (:class:`StarModel`).

A star model is what an SPH code reads to start a run and writes as a
snapshot: for each gas particle a position, a velocity, a mass, a smoothing
length, an internal energy per unit mass and an ID, in one consistent unit
system (:mod:`~collisionkit.encounters.units`). :mod:`.star_files` reads and
writes it (:func:`~collisionkit.encounters.read_star`, :func:`~collisionkit.encounters.write_star`) in the GADGET/SWIFT HDF5 snapshot layout and as ``.npz``;
:mod:`.polytrope` makes one; :mod:`.placement` puts two on an orbit.

Properties of the particle set, each a plain sum over the particles
:math:`i` with masses :math:`m_i`:

* total mass :math:`M = \sum m_i`, centre of mass
  :math:`\mathbf X = \sum m_i \mathbf x_i / M` and its velocity
  :math:`\mathbf V = \sum m_i \mathbf v_i / M`;
* the radius holding a fraction :math:`f` of the mass about the centre of
  mass (:meth:`StarModel.radius`, :math:`f` = 0.99 by default);
* the gravitational potential energy
  :math:`W = -G\sum_{i<j} m_i m_j / \sqrt{r_{ij}^2 + \epsilon^2}` by direct
  summation (:meth:`StarModel.potential_energy`).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy.spatial import cKDTree

from .. import _arrays
from .units import UnitSystem, conversion_factors, unit_system

__all__ = ["StarModel", "neighbour_smoothing_lengths"]

_FIELDS = ("positions", "velocities", "masses", "smoothing_lengths", "internal_energies", "ids")


def _frozen(array: np.ndarray) -> np.ndarray:
    array = np.array(array, copy=True)
    array.flags.writeable = False
    return array


def _vectors(value, name: str, count: int | None) -> np.ndarray:
    array = _arrays.as_float_array(value, name)
    if array.ndim != 2 or array.shape[1] != 3 or (count is not None and array.shape[0] != count):
        wanted = "(N, 3)" if count is None else f"({count}, 3)"
        raise ValueError(f"{name} must have shape {wanted}; got {array.shape}")
    _arrays.require_finite(array, name)
    return array


def _scalars(value, name: str, count: int, low: float, *, open_low: bool) -> np.ndarray:
    array = _arrays.as_float_array(value, name)
    if array.shape != (count,):
        raise ValueError(f"{name} must have shape ({count},), one per particle; got {array.shape}")
    _arrays.require_finite(array, name)
    _arrays.require_in_range(array, name, low, np.inf, inclusive=(not open_low, False))
    return array


def _integers(value, name: str, count: int, low: int) -> np.ndarray:
    array = np.asarray(value)
    if array.shape != (count,):
        raise ValueError(f"{name} must have shape ({count},), one per particle; got {array.shape}")
    if array.size and not np.issubdtype(array.dtype, np.integer):
        raise TypeError(f"{name} must be integers; got {array.dtype}")
    if array.size and (int(array.min()) < low or int(array.max()) > np.iinfo(np.int64).max):
        raise ValueError(f"{name} must be integers >= {low}; got the range [{array.min()}, {array.max()}]")
    return array.astype(np.int64)


@dataclasses.dataclass(frozen=True, repr=False, eq=False)
class StarModel:
    """The gas particles of a star (or of two placed stars) and the unit system they are in.

    Every array is copied and read-only; :meth:`moved` and
    :meth:`in_units` give new models.

    Parameters
    ----------
    positions, velocities : array_like, shape (N, 3)
    masses : array_like, shape (N,)
        > 0.
    smoothing_lengths : array_like, shape (N,)
        > 0 (an SPH code's ``SmoothingLength``).
    internal_energies : array_like, shape (N,)
        Internal energy per unit mass, >= 0 (in velocity units squared).
    ids : array_like of int, shape (N,)
        Distinct particle IDs >= 0.
    units : UnitSystem or str
        The unit system of every array (default N-body units, G = 1).
    star_ids : array_like of int, shape (N,), optional
        Which star each particle belongs to (1, 2, ...), in a placed pair.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.encounters import StarModel
    >>> star = StarModel(positions=[[1.0, 0, 0], [-1.0, 0, 0]], velocities=np.zeros((2, 3)), masses=[1.0, 3.0],
    ...                  smoothing_lengths=[0.5, 0.5], internal_energies=[0.1, 0.1], ids=[1, 2])
    >>> len(star), star.mass, star.centre_of_mass.tolist()
    (2, 4.0, [-0.5, 0.0, 0.0])
    >>> star.potential_energy()  # -G m1 m2 / r
    -1.5
    """

    positions: np.ndarray
    velocities: np.ndarray
    masses: np.ndarray
    smoothing_lengths: np.ndarray
    internal_energies: np.ndarray
    ids: np.ndarray
    units: UnitSystem = dataclasses.field(default_factory=lambda: unit_system("nbody"))
    star_ids: np.ndarray | None = None

    def __post_init__(self):
        positions = _vectors(self.positions, "positions", None)
        count = positions.shape[0]
        if count == 0:
            raise ValueError("a star model needs at least one particle; got none")
        arrays = {
            "positions": positions,
            "velocities": _vectors(self.velocities, "velocities", count),
            "masses": _scalars(self.masses, "masses", count, 0.0, open_low=True),
            "smoothing_lengths": _scalars(self.smoothing_lengths, "smoothing_lengths", count, 0.0, open_low=True),
            "internal_energies": _scalars(self.internal_energies, "internal_energies", count, 0.0, open_low=False),
            "ids": _integers(self.ids, "ids", count, 0),
        }
        if np.unique(arrays["ids"]).size != count:
            raise ValueError("ids must be distinct: two particles share an ID")
        if self.star_ids is not None:
            arrays["star_ids"] = _integers(self.star_ids, "star_ids", count, 1)
        units = unit_system(self.units) if isinstance(self.units, str) else self.units
        if not isinstance(units, UnitSystem):
            raise TypeError(f"units must be a UnitSystem or one of its names; got {self.units!r}")
        object.__setattr__(self, "units", units)
        for name, array in arrays.items():
            object.__setattr__(self, name, _frozen(array))

    def __len__(self) -> int:
        return self.positions.shape[0]

    @property
    def mass(self) -> float:
        """Total mass M = sum of the particle masses."""
        return float(np.sum(self.masses))

    @property
    def centre_of_mass(self) -> np.ndarray:
        """X = sum m_i x_i / M."""
        return self.masses @ self.positions / self.mass

    @property
    def centre_of_mass_velocity(self) -> np.ndarray:
        """V = sum m_i v_i / M."""
        return self.masses @ self.velocities / self.mass

    @property
    def G(self) -> float:
        """The gravitational constant in the model's units."""
        return self.units.G

    def radius(self, fraction: float = 0.99) -> float:
        """The radius about the centre of mass that holds ``fraction`` of the mass.

        The distance of the particle at which the mass of the particles no
        farther from the centre of mass first reaches ``fraction`` M.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import StarModel
        >>> x = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 3, 0], [0, -3, 0]])
        >>> star = StarModel(x, np.zeros((4, 3)), np.ones(4), np.ones(4), np.zeros(4), np.arange(4))
        >>> star.radius(0.5), star.radius(0.99)
        (1.0, 3.0)
        """
        fraction = float(fraction)
        if not 0.0 < fraction <= 1.0:
            raise ValueError(f"fraction must be in (0, 1]; got {fraction!r}")
        distances = np.linalg.norm(self.positions - self.centre_of_mass, axis=1)
        order = np.argsort(distances, kind="stable")
        enclosed = np.cumsum(self.masses[order])
        index = min(int(np.searchsorted(enclosed, fraction * enclosed[-1], side="left")), len(self) - 1)
        return float(distances[order][index])

    def potential_energy(self, softening: float = 0.0) -> float:
        r"""Gravitational potential energy by direct summation over all pairs.

        :math:`W = -G \sum_{i<j} m_i m_j / \sqrt{r_{ij}^2 + \epsilon^2}`
        with Plummer softening :math:`\epsilon` (``softening``); O(N^2)
        work, in blocks of rows of about 4 million pairs.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import StarModel
        >>> x = np.array([[0.0, 0, 0], [3.0, 0, 0], [0, 4.0, 0]])
        >>> star = StarModel(x, np.zeros((3, 3)), [1.0, 2.0, 2.0], np.ones(3), np.zeros(3), [0, 1, 2])
        >>> round(star.potential_energy(), 12)  # -(2/3 + 2/4 + 4/5)
        -1.966666666667
        """
        softening = float(softening)
        if not (math.isfinite(softening) and softening >= 0.0):
            raise ValueError(f"softening must be finite and >= 0; got {softening!r}")
        x, m = self.positions, self.masses
        total, chunk = 0.0, max(1, 2**22 // len(self))
        for start in range(0, len(self), chunk):
            rows = slice(start, min(start + chunk, len(self)))
            block = x[rows, None, :] - x[None, start:, :]  # pairs (i, j >= start): the upper triangle and the block
            distance = np.sqrt(np.einsum("ijk,ijk->ij", block, block) + softening**2)
            upper = np.triu(np.ones(distance.shape, dtype=bool), k=1)
            total += float(np.sum((m[rows, None] * m[None, start:])[upper] / distance[upper]))
        return -self.G * total

    def moved(self, shift=(0.0, 0.0, 0.0), boost=(0.0, 0.0, 0.0)) -> StarModel:
        """The same star moved rigidly: every position plus ``shift``, every velocity plus ``boost``.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import StarModel
        >>> star = StarModel(np.zeros((1, 3)), np.zeros((1, 3)), [1.0], [1.0], [0.0], [7])
        >>> moved = star.moved(shift=[1, 2, 3], boost=[0, 0, -1])
        >>> moved.positions.tolist(), moved.velocities.tolist(), moved.ids.tolist()
        ([[1.0, 2.0, 3.0]], [[0.0, 0.0, -1.0]], [7])
        """
        shift = _vectors(np.reshape(shift, (1, 3)), "shift", 1)[0]
        boost = _vectors(np.reshape(boost, (1, 3)), "boost", 1)[0]
        return dataclasses.replace(self, positions=self.positions + shift, velocities=self.velocities + boost)

    def in_units(self, units: UnitSystem | str) -> StarModel:
        """The same star in another unit system (see :func:`~collisionkit.encounters.units.conversion_factors`).

        Each array is multiplied by one factor: lengths (positions, smoothing
        lengths), velocities, masses, and internal energies (velocity
        squared); converting back returns the numbers to within two
        roundings.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import StarModel
        >>> star = StarModel([[1.0, 0, 0]], [[0, 2.0, 0]], [1.0], [0.5], [3.0], [1], units="si")
        >>> cgs = star.in_units("cgs")
        >>> cgs.positions.tolist(), cgs.velocities.tolist(), cgs.masses.tolist(), cgs.internal_energies.tolist()
        ([[100.0, 0.0, 0.0]], [[0.0, 200.0, 0.0]], [1000.0], [30000.0])
        """
        target = unit_system(units) if isinstance(units, str) else units
        factors = conversion_factors(self.units, target)
        return dataclasses.replace(
            self,
            positions=self.positions * factors["length"],
            velocities=self.velocities * factors["velocity"],
            masses=self.masses * factors["mass"],
            smoothing_lengths=self.smoothing_lengths * factors["length"],
            internal_energies=self.internal_energies * factors["specific_energy"],
            units=target,
        )

    def arrays(self) -> dict[str, np.ndarray]:
        """The particle arrays by field name (``star_ids`` only if set).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import StarModel
        >>> sorted(StarModel(np.zeros((1, 3)), np.zeros((1, 3)), [1.0], [1.0], [0.0], [1]).arrays())
        ['ids', 'internal_energies', 'masses', 'positions', 'smoothing_lengths', 'velocities']
        """
        arrays = {name: getattr(self, name) for name in _FIELDS}
        if self.star_ids is not None:
            arrays["star_ids"] = self.star_ids
        return arrays

    def summary(self, fraction: float = 0.99) -> dict:
        """Particles, mass, centre of mass and its velocity, and the radius holding ``fraction`` of the mass.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import StarModel
        >>> star = StarModel([[1.0, 0, 0], [-1.0, 0, 0]], np.zeros((2, 3)), [1.0, 1.0], [1, 1], [0, 0], [1, 2])
        >>> star.summary()["radius_99"]
        1.0
        """
        return {
            "particles": len(self),
            "mass": self.mass,
            f"radius_{round(100 * fraction)}": self.radius(fraction),
            "centre_of_mass": self.centre_of_mass.tolist(),
            "centre_of_mass_velocity": self.centre_of_mass_velocity.tolist(),
            "units": self.units.name,
        }

    def __repr__(self) -> str:
        pair = "" if self.star_ids is None else f", stars={sorted(set(self.star_ids.tolist()))}"
        return f"StarModel({len(self)} particles, mass={self.mass:.6g}, units={self.units.name!r}{pair})"


def neighbour_smoothing_lengths(positions, neighbours: int = 50, *, chunk: int = 65536, progress=None) -> np.ndarray:
    """Smoothing lengths from a fixed number of neighbours: the distance to each particle's ``neighbours``-th nearest.

    h_i is the radius of the sphere about particle i that holds exactly
    ``neighbours`` other particles (GADGET-2's convention: the kernel
    vanishes at h and ``DesNumNgb`` neighbours lie within it), found with
    :class:`scipy.spatial.cKDTree`. SPH codes iterate h from this start
    under their own kernel and neighbour definition. ``progress``, if
    given, is called with the fraction done after each ``chunk`` of
    particles.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.encounters import neighbour_smoothing_lengths
    >>> line = np.c_[np.arange(5.0), np.zeros(5), np.zeros(5)]
    >>> neighbour_smoothing_lengths(line, neighbours=2).tolist()
    [2.0, 1.0, 1.0, 1.0, 2.0]
    """
    positions = _vectors(positions, "positions", None)
    if isinstance(neighbours, bool) or int(neighbours) != neighbours or neighbours < 1:
        raise ValueError(f"neighbours must be an integer >= 1; got {neighbours!r}")
    neighbours = int(neighbours)
    if neighbours >= positions.shape[0]:
        raise ValueError(f"neighbours must be < the number of particles ({positions.shape[0]}); got {neighbours}")
    tree = cKDTree(positions)
    lengths = np.empty(positions.shape[0])
    for start in range(0, positions.shape[0], chunk):
        rows = slice(start, start + chunk)
        distances, _ = tree.query(positions[rows], k=[neighbours + 1])  # the first is the particle itself
        lengths[rows] = distances[:, 0]
        if progress is not None:
            progress(min(1.0, (start + chunk) / positions.shape[0]))
    return lengths
