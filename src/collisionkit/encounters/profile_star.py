r"""Stars from stellar-structure profiles: a MESA model (or any table of r, rho, P) sampled as SPH particles.

A :class:`StellarProfile` is a spherical star in cgs units: radius, density
and pressure at its zones (any order: kept sorted by radius), with the
enclosed mass and the specific internal energy if the model gives them.
:func:`read_mesa_profile` reads one from a MESA ``profile*.data`` file
(Paxton et al., ApJS 192, 3 (2011)): six header lines (the fifth the column
numbers, the sixth the column names), then one line per zone from the surface
to the centre, each a cell: radius and mass at its outer face, density,
pressure and energy averaged over it (``cells=True``). The columns it takes,
the first found of each:

* radius: ``radius_cm``, ``logR_cm`` (cm), ``radius``, ``logR`` (Rsun);
* density: ``rho``, ``logRho`` (g/cm^3); pressure: ``pressure``, ``logP``
  (dyn/cm^2);
* enclosed mass (optional): ``mass_grams`` (g), ``mass``, ``logM`` (Msun);
* specific internal energy (optional): ``energy``, ``logE`` (erg/g).

Solar units are the IAU 2015 nominal ones, as MESA uses them since release
15140 (older releases' differ by 4e-4 in mass and radius).

Two checks of a profile, exact for a star in hydrostatic equilibrium: the
enclosed mass from the density, :math:`m(r) = \int_0^r 4\pi r^2\rho\,dr`,
equals the model's own mass column (:meth:`StellarProfile.mass_mismatch`;
a MESA model's cells to 1e-14), and the virial theorem :math:`3\int P\,dV - 4\pi R^3 P_s = -W`,
:math:`W = -\int G m\,dm/r` (:meth:`StellarProfile.virial_ratio`, 1 for
equilibrium, MESA models' within 1e-12: a column read in the wrong units
puts it far from 1).

:func:`profile_star` samples the profile as particles the way
:func:`~collisionkit.encounters.polytrope_star` samples a polytrope: equal
masses, radii from the inverse of the enclosed mass (:math:`r^3` linear in
m between zones, exact for a uniform shell), isotropic directions, zero
velocities, smoothing lengths from a neighbour number, and the internal
energy per unit mass of the profile at each particle's radius: the model's
own (``energy``, which holds radiation and ionization), or
:math:`u = P/((\gamma - 1)\rho)` for an ideal gas of adiabatic index
:math:`\gamma` when it has none or a ``gamma`` is given. Like the
polytrope it is **unrelaxed**: the input to the SPH code's relaxation.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
from scipy import constants

from .._params import Parameters, check_choice, check_integer, check_real, check_seed
from .star_model import StarModel, neighbour_smoothing_lengths
from .units import GM_SUN, R_SUN, UNIT_SYSTEMS, UnitSystem, conversion_factors, unit_system, unit_system_from_cgs

__all__ = ["ProfileStarParameters", "StellarProfile", "profile_checks", "profile_star", "profile_star_summary",
           "read_mesa_profile"]

G_CGS = constants.G * 1e3  # cm^3 / (g s^2)
M_SUN_G = GM_SUN / constants.G * 1e3
R_SUN_CM = R_SUN * 1e2
IDEAL_GAS_GAMMA = 5.0 / 3.0
MAX_PARTICLES = 10_000_000

# MESA profile columns: name -> (quantity, factor to cgs, logarithmic)
MESA_COLUMNS = {
    "radius_cm": ("radius", 1.0, False), "logR_cm": ("radius", 1.0, True),
    "radius": ("radius", R_SUN_CM, False), "logR": ("radius", R_SUN_CM, True),
    "rho": ("density", 1.0, False), "logRho": ("density", 1.0, True),
    "pressure": ("pressure", 1.0, False), "logP": ("pressure", 1.0, True),
    "mass_grams": ("mass", 1.0, False), "mass": ("mass", M_SUN_G, False), "logM": ("mass", M_SUN_G, True),
    "energy": ("internal_energy", 1.0, False), "logE": ("internal_energy", 1.0, True),
}
REQUIRED = ("radius", "density", "pressure")


def _column(values, name: str, count: int | None) -> np.ndarray:
    array = np.array(values, dtype=float, copy=True)
    if array.ndim != 1 or (count is not None and array.size != count):
        raise ValueError(f"{name} must be a 1-D array" + ("" if count is None else f" of {count} values (as radius)")
                         + f"; got shape {array.shape}")
    if not np.all(np.isfinite(array)):
        raise ValueError(f"{name} must be finite; got {array[~np.isfinite(array)][0]} at zone "
                         f"{int(np.flatnonzero(~np.isfinite(array))[0])}")
    return array


@dataclasses.dataclass(frozen=True)
class StellarProfile:
    """A spherical star's structure in cgs units (see the module's description).

    Parameters
    ----------
    radius : array_like
        Zone radii (cm), distinct and >= 0, in any order (at least 3 zones).
    density, pressure : array_like
        g/cm^3 and dyn/cm^2 at those radii, > 0.
    mass : array_like, optional
        Enclosed mass (g), never falling with radius. Default: integrated from the
        density (:meth:`enclosed_mass`).
    internal_energy : array_like, optional
        Specific internal energy (erg/g), > 0.
    source : str
        Where the profile came from (a file name), for summaries.
    cells : bool
        The layout of the zones. False (points): every value is at its
        radius. True (cells, as MESA writes them): ``radius`` and ``mass`` are
        each cell's outer face, ``density``, ``pressure`` and
        ``internal_energy`` the averages over the cell between the face below
        (or the centre) and that face.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.encounters import StellarProfile
    >>> r = np.linspace(0.0, 1e10, 2001)        # a uniform sphere: rho = 1, P = (2 pi / 3) G rho^2 (R^2 - r^2)
    >>> profile = StellarProfile(r, np.ones_like(r), 2.0 * np.pi / 3.0 * 6.6743e-8 * (1e20 - r**2 + 1e10))
    >>> round(profile.total_mass / (4.0 / 3.0 * np.pi * 1e30), 6), round(profile.virial_ratio(), 5)
    (1.0, 1.0)
    """

    radius: np.ndarray
    density: np.ndarray
    pressure: np.ndarray
    mass: np.ndarray | None = None
    internal_energy: np.ndarray | None = None
    source: str = ""
    cells: bool = False

    def __post_init__(self):
        radius = _column(self.radius, "radius", None)
        if radius.size < 3:
            raise ValueError(f"a profile needs at least 3 zones; got {radius.size}")
        order = np.argsort(radius, kind="stable")
        columns = {"radius": radius}
        for name in ("density", "pressure", "mass", "internal_energy"):
            if getattr(self, name) is not None:
                columns[name] = _column(getattr(self, name), name, radius.size)
        columns = {name: array[order] for name, array in columns.items()}
        if columns["radius"][0] < 0 or np.any(np.diff(columns["radius"]) <= 0):
            raise ValueError("radius must hold distinct values >= 0 (one per zone)")
        for name in ("density", "pressure", "internal_energy"):
            if name in columns and np.any(columns[name] <= 0):
                raise ValueError(f"{name} must be > 0 in every zone; got {columns[name].min():g}")
        # (equal masses in a row: the outermost zones' dm lost to the file's printed digits)
        if "mass" in columns and (columns["mass"][0] < 0 or np.any(np.diff(columns["mass"]) < 0)):
            raise ValueError("mass (the enclosed mass) must be >= 0 and never fall with radius")
        for name, array in columns.items():
            array.flags.writeable = False
            object.__setattr__(self, name, array)
        object.__setattr__(self, "source", str(self.source))
        if not isinstance(self.cells, (bool, np.bool_)):
            raise TypeError(f"cells must be true or false; got {self.cells!r}")
        object.__setattr__(self, "cells", bool(self.cells))

    def __len__(self) -> int:
        return self.radius.size

    def __repr__(self) -> str:
        layout = "cells" if self.cells else "points"
        return (f"StellarProfile({len(self)} {layout}, mass={self.total_mass:.6g} g, radius={self.surface_radius:.6g} "
                f"cm{', ' + repr(self.source) if self.source else ''})")

    @property
    def surface_radius(self) -> float:
        """The outermost zone's radius (cm)."""
        return float(self.radius[-1])

    def integrated_mass(self) -> np.ndarray:
        r""":math:`m(r) = \int_0^r 4\pi r^2 \rho\,dr` at each zone (g). Points: a uniform sphere inside the
        first zone, then trapezoids of :math:`r^2\rho` in r; cells: the sum of each cell's density times its volume
        (exact).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import StellarProfile
        >>> r = np.linspace(0.0, 1.0, 1001)   # a uniform sphere of unit radius and density
        >>> sphere = StellarProfile(r, np.ones_like(r), 1.0 - r**2 + 1e-6)
        >>> round(float(sphere.integrated_mass()[-1] / (4.0 / 3.0 * np.pi)), 6)
        1.0
        """
        if self.cells:
            return np.cumsum(self.density * self._cell_volumes())
        r, shell = self.radius, 4.0 * np.pi * self.radius**2 * self.density
        core = 4.0 / 3.0 * np.pi * r[0] ** 3 * self.density[0]
        return core + np.concatenate(([0.0], np.cumsum(0.5 * (shell[1:] + shell[:-1]) * np.diff(r))))

    def enclosed_mass(self) -> np.ndarray:
        """The model's mass column if it has one, else :meth:`integrated_mass` (g).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import StellarProfile
        >>> r = np.linspace(0.0, 1.0, 1001)   # a uniform sphere of unit radius and density
        >>> sphere = StellarProfile(r, np.ones_like(r), 1.0 - r**2 + 1e-6)
        >>> given = StellarProfile(r[1:], np.ones(1000), 1.0 - r[1:]**2 + 1e-6, mass=4.0 / 3.0 * np.pi * r[1:]**3)
        >>> bool(np.array_equal(given.enclosed_mass(), given.mass)), sphere.enclosed_mass().shape
        (True, (1001,))
        """
        return self.mass if self.mass is not None else self.integrated_mass()

    @property
    def total_mass(self) -> float:
        """The enclosed mass at the surface (g)."""
        return float(self.enclosed_mass()[-1])

    def mass_mismatch(self) -> float:
        """Relative difference of the integrated and the given total mass (0 without a mass column).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import StellarProfile
        >>> r = np.linspace(0.0, 1.0, 1001)   # a uniform sphere of unit radius and density
        >>> sphere = StellarProfile(r, np.ones_like(r), 1.0 - r**2 + 1e-6)
        >>> heavier = StellarProfile(r[1:], np.ones(1000), 1.0 - r[1:]**2 + 1e-6, mass=1.01 * 4.0 / 3.0 * np.pi * r[1:]**3)
        >>> round(heavier.mass_mismatch(), 4), sphere.mass_mismatch()
        (-0.0099, 0.0)
        """
        return 0.0 if self.mass is None else float(self.integrated_mass()[-1] / self.mass[-1] - 1.0)

    def potential_energy(self) -> float:
        r""":math:`W = -\int_0^M G m\,dm / r` (erg), trapezoids in m (the uniform core inside the first zone:
        :math:`-\frac35 G m_0^2 / r_0`).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import StellarProfile
        >>> r = np.linspace(0.0, 1.0, 1001)   # a uniform sphere of unit radius and density
        >>> sphere = StellarProfile(r, np.ones_like(r), 1.0 - r**2 + 1e-6)
        >>> from collisionkit.encounters.profile_star import G_CGS
        >>> round(sphere.potential_energy() / (-0.6 * G_CGS * (4.0 / 3.0 * np.pi) ** 2), 5)  # -3/5 G M^2 / R
        1.0
        """
        m, r = self.enclosed_mass(), self.radius
        integrand = np.divide(m, r, out=np.zeros_like(m), where=r > 0)
        core = 0.6 * m[0] * integrand[0]
        return float(-G_CGS * (core + np.sum(0.5 * (integrand[1:] + integrand[:-1]) * np.diff(m))))

    def virial_ratio(self) -> float:
        r""":math:`(3\int P\,dV - 4\pi R^3 P_s) / (-W)`: 1 for a star in hydrostatic equilibrium (the virial
        theorem with the pressure :math:`P_s` of the outermost zone at its surface R; MESA's photosphere).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import StellarProfile
        >>> r = np.linspace(0.0, 1.0, 1001)   # a uniform sphere of unit radius and density
        >>> sphere = StellarProfile(r, np.ones_like(r), 1.0 - r**2 + 1e-6)
        >>> balanced = StellarProfile(r, np.ones_like(r), 2.0 * np.pi / 3.0 * 6.6743e-8 * (1.0 - r**2 + 1e-6))
        >>> round(balanced.virial_ratio(), 4), sphere.virial_ratio() > 1e6  # hydrostatic: P = (2 pi / 3) G (R^2 - r^2)
        (1.0, True)
        """
        r, shell = self.radius, 4.0 * np.pi * self.radius**2 * self.pressure
        if self.cells:
            volume_integral = float(self.pressure @ self._cell_volumes())
        else:
            volume_integral = 4.0 / 3.0 * np.pi * r[0] ** 3 * self.pressure[0] + float(
                np.sum(0.5 * (shell[1:] + shell[:-1]) * np.diff(r)))
        surface = 4.0 * np.pi * r[-1] ** 3 * self.pressure[-1]
        return float((3.0 * volume_integral - surface) / -self.potential_energy())

    def _cell_volumes(self) -> np.ndarray:
        """The volume of each cell, from the face below (the centre for the first) to its own face."""
        return 4.0 / 3.0 * np.pi * np.diff(self.radius**3, prepend=0.0)

    def specific_energy(self, radius, gamma: float | None = None) -> np.ndarray:
        """The internal energy per unit mass (erg/g) at ``radius`` (cm): the model's own if it has one and no
        ``gamma`` is given, else P / ((gamma - 1) rho) (gamma default 5/3). Points: log-linear between zones, the
        innermost and outermost zones' values beyond them; cells: the value of the cell holding the radius.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import StellarProfile
        >>> r = np.linspace(0.0, 1.0, 1001)   # a uniform sphere of unit radius and density
        >>> sphere = StellarProfile(r, np.ones_like(r), 1.0 - r**2 + 1e-6)
        >>> round(float(sphere.specific_energy(0.5)), 6), round(float(sphere.specific_energy(0.5, gamma=1.4)), 6)
        (1.125001, 1.875003)
        """
        radius = np.asarray(radius, dtype=float)
        if self.internal_energy is not None and gamma is None:
            return self._at(radius, self.internal_energy)
        gamma = IDEAL_GAS_GAMMA if gamma is None else gamma
        return self._at(radius, self.pressure) / ((gamma - 1.0) * self._at(radius, self.density))

    def _at(self, radius: np.ndarray, values: np.ndarray) -> np.ndarray:
        """``values`` at ``radius``: the holding cell's, or (points) log-linear between zones."""
        if self.cells:
            return values[np.minimum(np.searchsorted(self.radius, radius), values.size - 1)]
        return np.exp(np.interp(radius, self.radius, np.log(values)))

    def radius_of_mass(self, mass) -> np.ndarray:
        """The radius (cm) enclosing ``mass`` (g, in [0, M]): r^3 linear in m between zones, from (0, 0).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import StellarProfile
        >>> r = np.linspace(0.0, 1.0, 1001)   # a uniform sphere of unit radius and density
        >>> sphere = StellarProfile(r, np.ones_like(r), 1.0 - r**2 + 1e-6)
        >>> round(float(sphere.radius_of_mass(sphere.total_mass / 8.0)), 6)  # an eighth of the mass: half the radius
        0.5
        """
        m = np.concatenate(([0.0], self.enclosed_mass()))
        r3 = np.concatenate(([0.0], self.radius**3))
        return np.cbrt(np.interp(np.asarray(mass, dtype=float), m, r3))


def read_mesa_profile(path) -> StellarProfile:
    """A MESA ``profile*.data`` file as a :class:`StellarProfile` (the columns of the module's description).

    Raises
    ------
    ValueError
        A file that is not a MESA profile, naming what is missing (the
        column names line, a required column) or the first bad line.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from collisionkit.encounters import read_mesa_profile
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "profile1.data"
    >>> _ = path.write_text("1 2\\nmodel_number star_mass\\n1 1.0\\n\\n1 2 3 4\\nzone logR logRho logP\\n"
    ...                     "1 0.0 -7.0 4.0\\n2 -1.0 -1.0 14.0\\n3 -2.0 1.5 17.0\\n")
    >>> profile = read_mesa_profile(path)
    >>> len(profile), round(profile.surface_radius / 6.957e10, 12), profile.density.tolist()
    (3, 1.0, [31.622776601683793, 0.1, 1e-07])
    """
    path = Path(path)
    try:
        lines = path.read_text().splitlines()
    except UnicodeDecodeError:
        raise ValueError(f"{path} is not a MESA profile: it is not text") from None
    if len(lines) < 7:
        raise ValueError(f"{path} is not a MESA profile: it has {len(lines)} lines, a profile has 6 header lines "
                         "and then one line per zone")
    names = lines[5].split()
    chosen: dict[str, int] = {}
    for index, name in enumerate(names):
        quantity = MESA_COLUMNS.get(name, (None,))[0]
        if quantity is not None and quantity not in chosen:
            chosen[quantity] = index
    missing = [quantity for quantity in REQUIRED if quantity not in chosen]
    if missing:
        raise ValueError(f"{path}: no {' or '.join(missing)} column among the names on line 6 (takes "
                         f"{', '.join(name for name, spec in MESA_COLUMNS.items() if spec[0] in missing)})")
    rows = []
    for number, line in enumerate(lines[6:], start=7):
        if line.strip():
            fields = line.split()
            if len(fields) != len(names):
                raise ValueError(f"{path} line {number}: {len(fields)} values for {len(names)} column names")
            try:
                row = [float(fields[index]) for index in chosen.values()]
            except ValueError:
                raise ValueError(f"{path} line {number}: not a number among {fields[:4]} ...") from None
            if not all(math.isfinite(value) for value in row):
                bad = next(name for name, value in zip(chosen, row) if not math.isfinite(value))
                raise ValueError(f"{path} line {number}: the {bad} column holds {fields[chosen[bad]]}")
            rows.append(row)
    data = np.array(rows).reshape(-1, len(chosen))
    values = {}
    for quantity, column in zip(chosen, data.T):
        factor, logarithmic = MESA_COLUMNS[names[chosen[quantity]]][1:]
        values[quantity] = (10.0**column if logarithmic else column) * factor
    return StellarProfile(**values, source=path.name, cells=True)


def _target_units(units) -> tuple[UnitSystem, dict]:
    """The unit system of the particles and the cgs -> it factors; N-body units are refused: a real star has a
    size, which G = 1 would lose (two such stars would both have M = 1 and R = 1)."""
    system = unit_system(units) if isinstance(units, str) else units
    if not isinstance(system, UnitSystem):
        raise TypeError(f"units must be a UnitSystem or one of its names; got {units!r}")
    if system.name == "nbody":
        raise ValueError("units nbody (G = 1, no size) would lose the star's mass and radius: choose stellar, solar, "
                         "cgs or si")
    return system, conversion_factors("cgs", system)


def profile_star(profile: StellarProfile, particles: int, *, units="stellar", neighbours: int = 50,
                 gamma: float | None = None, seed=None, progress=None) -> StarModel:
    """An unrelaxed particle star of ``profile`` (see the module's description).

    Parameters
    ----------
    profile : StellarProfile
    particles : int
        K > neighbours (at most 1e7), all of mass M / K, IDs 1 ... K.
    units : UnitSystem or str
        Of the particles: ``stellar``, ``solar``, ``cgs``, ``si`` or a
        sized :class:`~collisionkit.encounters.UnitSystem` (not ``nbody``,
        which has no size).
    neighbours : int
        Each smoothing length holds this many neighbours (>= 1).
    gamma : float, optional
        Ideal-gas index (> 1) for u = P / ((gamma - 1) rho); default: the
        profile's own internal energy, or 5/3 if it has none.
    seed : int or numpy.random.Generator, optional
    progress : callable, optional
        Called with the fraction of the work done.

    Returns
    -------
    StarModel

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.encounters import StellarProfile, profile_star
    >>> r = np.linspace(0.0, 7e10, 500)
    >>> profile = StellarProfile(r, 1.4 * (1 - (r / 7.1e10) ** 2), 1e15 * (1 - (r / 7.1e10) ** 2) ** 2)
    >>> star = profile_star(profile, 1000, units="stellar", neighbours=20, seed=1)
    >>> round(star.mass / (profile.total_mass / 1.98841e33), 6)  # in Msun
    1.0
    >>> bool(np.linalg.norm(star.positions, axis=1).max() <= 7e10 / 6.957e10)  # inside the outermost zone (Rsun)
    True
    """
    if not isinstance(profile, StellarProfile):
        raise TypeError(f"profile must be a StellarProfile; got {type(profile).__name__}")
    neighbours = check_integer("neighbours", neighbours, 1)
    count = check_integer("particles", particles, neighbours + 1, MAX_PARTICLES)
    if gamma is not None:
        gamma = check_real("gamma", gamma, 1.0, low_open=True)
    system, factors = _target_units(units)
    rng = np.random.default_rng(seed)
    radius = profile.radius_of_mass(rng.random(count) * profile.total_mass)
    cos_polar = rng.uniform(-1.0, 1.0, count)
    azimuth = rng.uniform(0.0, 2.0 * math.pi, count)
    sin_polar = np.sqrt(1.0 - cos_polar**2)
    positions = (radius * factors["length"])[:, None] * np.c_[sin_polar * np.cos(azimuth),
                                                               sin_polar * np.sin(azimuth), cos_polar]
    if progress is not None:
        progress(0.2)
    return StarModel(
        positions=positions,
        velocities=np.zeros((count, 3)),
        masses=np.full(count, profile.total_mass * factors["mass"] / count),
        smoothing_lengths=neighbour_smoothing_lengths(
            positions, neighbours, progress=None if progress is None else lambda done: progress(0.2 + 0.8 * done)),
        internal_energies=profile.specific_energy(radius, gamma) * factors["specific_energy"],
        ids=np.arange(1, count + 1),
        units=system,
    )


# a profile whose virial ratio or mass check is off by more than these is reported as suspect (wrong units?)
VIRIAL_TOLERANCE = 0.05
MASS_TOLERANCE = 0.01


@dataclasses.dataclass(frozen=True)
class ProfileStarParameters(Parameters):
    """A star to sample from a MESA profile file (``collisionkit star --profile``), checked when made.

    Parameters
    ----------
    profile : str
        Path of the MESA ``profile*.data`` file (read by :func:`profile_star_summary`).
    particles : int
        Number of particles K, > ``neighbours`` (at most 1e7).
    units : str
        ``stellar`` (default), ``solar``, ``cgs`` or ``si`` (not ``nbody``: a real star has a size).
    neighbours : int
        Neighbour number of the smoothing lengths (>= 1).
    gamma : float, optional
        Ideal-gas index (> 1) for u = P/((gamma - 1) rho); default the
        profile's own internal energy, or 5/3.
    seed : int
        Random seed (>= 0).

    Examples
    --------
    >>> from collisionkit.encounters import ProfileStarParameters
    >>> ProfileStarParameters(profile="profile1.data", particles=1000).units
    'stellar'
    """

    profile: str = ""
    particles: int = 10_000
    units: str = "stellar"
    neighbours: int = 50
    gamma: float | None = None
    seed: int = 2026

    def __post_init__(self):
        if not isinstance(self.profile, (str, Path)) or not str(self.profile):
            raise ValueError(f"profile must name a MESA profile file; got {self.profile!r}")
        object.__setattr__(self, "profile", str(self.profile))
        check_choice("units", self.units, UNIT_SYSTEMS)
        _target_units(self.units)
        object.__setattr__(self, "seed", check_seed("seed", self.seed))
        neighbours = check_integer("neighbours", self.neighbours, 1)
        object.__setattr__(self, "neighbours", neighbours)
        object.__setattr__(self, "particles", check_integer("particles", self.particles, neighbours + 1, MAX_PARTICLES))
        if self.gamma is not None:
            object.__setattr__(self, "gamma", check_real("gamma", self.gamma, 1.0, low_open=True))


def profile_checks(profile: StellarProfile) -> list[str]:
    """What looks wrong with ``profile``: a virial ratio off 1 or a mass column off the density's integral.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.encounters import StellarProfile
    >>> r = np.linspace(0.0, 1e10, 2001)
    >>> profile_checks(StellarProfile(r, np.ones_like(r), 1e9 * (1e20 - r**2 + 1e10)))[0][:60]
    'the profile is not in hydrostatic equilibrium: (3 int P dV -'
    """
    notes = []
    virial = profile.virial_ratio()
    if not abs(virial - 1.0) <= VIRIAL_TOLERANCE:
        notes.append(f"the profile is not in hydrostatic equilibrium: (3 int P dV - 4 pi R^3 P_s) / -W = {virial:.4g}, not 1 (a "
                     "column in other units than the file's names say?)")
    mismatch = profile.mass_mismatch()
    if not abs(mismatch) <= MASS_TOLERANCE:
        notes.append(f"the profile's mass column and the integral of its density differ by {100 * mismatch:.3g} %")
    return notes


def profile_star_summary(parameters: ProfileStarParameters, progress=None,
                         profile: StellarProfile | None = None) -> tuple[dict, StarModel]:
    """The ``star --profile`` command as a library call: the sampled star and its summary.

    The summary holds the profile (file, zones, mass and radius in cgs, the
    virial ratio, the mass check, where the internal energy comes from and
    any ``warnings`` of :func:`profile_checks`), the star's properties, the
    profile's potential energy in the star's units, the particles' thermal
    energy, the seed and the ``parameters``. ``profile``: the file's profile if already
    read (:func:`read_mesa_profile`).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from collisionkit.encounters import ProfileStarParameters, profile_star_summary
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "profile1.data"
    >>> _ = path.write_text("1 2\\nmodel_number star_mass\\n1 1.0\\n\\n1 2 3\\nlogR logRho logP\\n"
    ...                     "0.0 -7.0 4.0\\n-1.0 -1.0 14.0\\n-2.0 1.5 17.0\\n")
    >>> summary, star = profile_star_summary(ProfileStarParameters(profile=str(path), particles=20, neighbours=5))
    >>> summary["profile"]["zones"], len(star), summary["warnings"][0][:48]
    (3, 20, 'the profile is not in hydrostatic equilibrium: (')
    """
    profile = read_mesa_profile(parameters.profile) if profile is None else profile
    star = profile_star(profile, parameters.particles, units=parameters.units, neighbours=parameters.neighbours,
                        gamma=parameters.gamma, seed=parameters.seed, progress=progress)
    _, factors = _target_units(parameters.units)
    own = profile.internal_energy is not None and parameters.gamma is None
    summary = {
        "units": parameters.units,
        "G": star.G,
        "profile": {"file": profile.source, "zones": len(profile), "mass_g": profile.total_mass,
                    "radius_cm": profile.surface_radius, "virial_ratio": profile.virial_ratio(),
                    "mass_mismatch": profile.mass_mismatch()},
        "internal_energy": "the profile's" if own else
                           f"P / ((gamma - 1) rho), gamma {parameters.gamma or IDEAL_GAS_GAMMA:.10g} (P the total "
                           "pressure, radiation included)",
        "warnings": profile_checks(profile),
        "star": star.summary(),
        "potential_energy_profile": profile.potential_energy() * factors["mass"] * factors["specific_energy"],
        "thermal_energy": float(star.masses @ star.internal_energies),
        "relaxed": False,
        "seed": parameters.seed,
        "parameters": parameters.to_dict(),
    }
    return summary, star
