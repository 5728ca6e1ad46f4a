"""The physics of a ``track`` run: a device's parameters, flat as sweeps and the command line name them.

:class:`TrackParameters` holds the physics (flat, as sweeps and the command
line name them); :meth:`TrackParameters.from_sections` reads the device file's
``[gas]``, ``[geometry]``, ``[source]`` and ``[ions]`` tables::

    [gas]                      # as the swarm takes it
    model = "lucas_saelee"     # or gas = "Ar", or cross-sections = ["file.txt"]
    pressure = 101325.0        # Pa (or density, m^-3)
    temperature = 300.0        # K
    [geometry]
    kind = "parallel-plate"    # cathode z = 0 at 0 V, anode z = gap at voltage
    gap = 1e-3                 # m
    voltage = 1500.0           # V
    [source]
    electrons = 100
    position = [0.0, 0.0, 0.0] # m (coaxial: or radius = r in m)

:class:`~collisionkit.transport.tracking.TrackRun` runs them (:mod:`.command`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any, ClassVar

import numpy as np

from ..._params import Parameters, check_choice, check_integer, check_real, check_seed
from ..gases import Gas
from ..scan import SwarmParameters
from .device import Device
from .magnetic import UniformMagneticField
from .run import MAX_ELECTRONS, METHODS

__all__ = ["GEOMETRIES", "SECTIONS", "TrackParameters", "flatten_sections"]

GEOMETRIES = ("parallel-plate", "coaxial")
# the device file's tables and the parameters their keys set (keys may use dashes)
SECTIONS = {
    "gas": {"model": "model", "gas": "gas", "cross_sections": "cross_sections", "species": "species",
            "fractions": "fractions", "database": "database", "pressure": "pressure", "temperature": "temperature",
            "density": "density", "scattering": "scattering", "populations": "populations"},
    "geometry": {"kind": "geometry", "gap": "gap", "voltage": "voltage", "wire_radius": "wire_radius",
                 "cathode_radius": "cathode_radius", "magnetic_field": "magnetic_field"},
    "source": {"electrons": "electrons", "position": "position", "radius": "radius", "energy": "energy",
               "direction": "direction"},
    "ions": {"mobility": "ion_mobility"},
}
# tables of the swarm's config that a device file may hold at its top level as they are
WHOLE_TABLES = ("scattering", "populations")


def _vector_or_none(name: str, value):
    if value is None:
        return None
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != 3:
        raise ValueError(f"{name} must be three numbers; got {value!r}")
    return tuple(check_real(name, item) for item in value)


@dataclasses.dataclass(frozen=True)
class TrackParameters(Parameters):
    """The physics of a ``track`` run, checked when made.

    Parameters
    ----------
    geometry : {"parallel-plate", "coaxial"}
        The device: plates (``gap``; the cathode z = 0 at 0 V, the anode z =
        gap at ``voltage``) or a counter (``wire_radius``, ``cathode_radius``;
        the wire at ``voltage``, the cathode at 0 V; axis z).
    gap, wire_radius, cathode_radius : float
        Sizes in m (> 0).
    voltage : float
        V (finite).
    magnetic_field : 3 numbers, optional
        A uniform magnetic field (T).
    model, gas, cross_sections, species, fractions, database, scattering, populations
        The gas, exactly as :class:`~collisionkit.transport.SwarmParameters` takes it (angular laws and level
        populations too).
    pressure, temperature, density : float
        The gas: pressure (Pa, > 0; default 1 atm) and temperature (K, > 0), or
        its number density (m^-3) instead of the pressure; the temperature at
        most 1e5 K (the swarm's gas temperature).
    electrons : int
        Primary electrons (1 to 1e7).
    position : 3 numbers, optional
        Their start (m); default the cathode's centre (plates). A start on an
        electrode emits into the gas.
    radius : float, optional
        Coaxial: the start's distance from the axis (m), in (a, b).
    energy : float
        The primaries' energy (eV, >= 0).
    direction : 3 numbers, optional
        Their direction (default isotropic).
    method : {"null-collision", "path-length"}
    ion_mobility : float, optional
        Drift the ions at this mobility (m^2/(V s), > 0).
    seed : int
    tolerance : float
        The integrator's relative tolerance, in (0, 0.1].
    sharing : {"equal", "uniform"}
    max_electrons : int
        Electrons the run may follow, 1 to 1e12 (see :func:`track`; default 1e7).

    Examples
    --------
    >>> p = TrackParameters(model="reid", gap=1e-3, voltage=100.0, electrons=10)
    >>> p.device().collector, p.positions().tolist()
    ('anode', [[0.0, 0.0, 0.0]])
    >>> TrackParameters(model="reid", gap=-1.0)
    Traceback (most recent call last):
    ...
    ValueError: gap must be > 0; got -1
    """

    geometry: str = "parallel-plate"
    gap: float | None = None
    voltage: float = 0.0
    wire_radius: float | None = None
    cathode_radius: float | None = None
    magnetic_field: Any = None
    model: str | None = None
    gas: str | None = None
    cross_sections: Any = None
    species: Any = None
    fractions: Any = None
    database: str | None = None
    scattering: Any = None
    populations: Any = None
    pressure: float | None = None
    temperature: float = 300.0
    density: float | None = None
    electrons: int = 100
    position: Any = None
    radius: float | None = None
    energy: float = 0.1
    direction: Any = None
    method: str = "null-collision"
    ion_mobility: float | None = None
    seed: int = 2026
    tolerance: float = 1e-6
    sharing: str = "equal"
    max_electrons: int = MAX_ELECTRONS

    FLAGS: ClassVar = {}

    def __post_init__(self):
        set_ = object.__setattr__
        check_choice("geometry", self.geometry, GEOMETRIES)
        if self.geometry == "parallel-plate":
            if self.gap is None:
                raise ValueError("a parallel-plate device needs gap (m)")
            set_(self, "gap", check_real("gap", self.gap, 0.0, low_open=True))
            for name in ("wire_radius", "cathode_radius", "radius"):
                if getattr(self, name) is not None:
                    raise ValueError(f"{name} belongs to a coaxial device; a parallel-plate one takes gap")
        else:
            if self.wire_radius is None or self.cathode_radius is None:
                raise ValueError("a coaxial device needs wire_radius and cathode_radius (m)")
            set_(self, "wire_radius", check_real("wire_radius", self.wire_radius, 0.0, low_open=True))
            set_(self, "cathode_radius", check_real("cathode_radius", self.cathode_radius, self.wire_radius,
                                                    low_open=True))
            if self.gap is not None:
                raise ValueError("gap belongs to a parallel-plate device; a coaxial one takes wire_radius and "
                                 "cathode_radius")
        set_(self, "voltage", check_real("voltage", self.voltage))
        set_(self, "magnetic_field", _vector_or_none("magnetic_field (T)", self.magnetic_field))
        swarm = self.swarm_parameters()  # the gas's checks, exactly the swarm's
        set_(self, "cross_sections", swarm.cross_sections)
        set_(self, "species", swarm.species)
        set_(self, "fractions", swarm.fractions)
        set_(self, "scattering", swarm.scattering)
        set_(self, "populations", swarm.populations)
        if self.pressure is not None and self.density is not None:
            raise ValueError("give pressure (Pa) or density (m^-3), not both")
        if self.pressure is not None:
            set_(self, "pressure", check_real("pressure", self.pressure, 0.0, low_open=True))
        if self.density is not None:
            set_(self, "density", check_real("density", self.density, 0.0, low_open=True))
        # the gas's temperature gives the density from the pressure (> 0); with a density it may be 0 (targets at rest)
        set_(self, "temperature", check_real("temperature", self.temperature, 0.0, low_open=self.density is None))
        set_(self, "electrons", check_integer("electrons", self.electrons, 1, 10_000_000))
        set_(self, "position", _vector_or_none("position (m)", self.position))
        if self.radius is not None:
            if self.position is not None:
                raise ValueError("give position or radius, not both")
            set_(self, "radius", check_real("radius", self.radius, self.wire_radius, self.cathode_radius,
                                            low_open=True, high_open=True))
        set_(self, "energy", check_real("energy", self.energy, 0.0))
        set_(self, "direction", _vector_or_none("direction", self.direction))
        if self.direction is not None and not any(self.direction):
            raise ValueError("direction must not be zero")
        check_choice("method", self.method, tuple(METHODS))
        if self.ion_mobility is not None:
            set_(self, "ion_mobility", check_real("ion_mobility", self.ion_mobility, 0.0, low_open=True))
        set_(self, "seed", check_seed("seed", self.seed))
        set_(self, "tolerance", check_real("tolerance", self.tolerance, 0.0, 0.1, low_open=True))
        check_choice("sharing", self.sharing, ("equal", "uniform"))
        set_(self, "max_electrons", check_integer("max_electrons", self.max_electrons, 1, 10**12))
        self.positions()  # inside the device

    @classmethod
    def from_sections(cls, tables: Mapping[str, Any], **flat) -> TrackParameters:
        """The parameters of a device file's tables (``[gas]``, ``[geometry]``, ``[source]``, ``[ions]``) and of flat
        keys (``seed``, ``method`` ...); ValueError naming an unknown table or key.

        Examples
        --------
        >>> p = TrackParameters.from_sections({"gas": {"model": "reid", "density": 1e24},
        ...                                    "geometry": {"kind": "coaxial", "wire-radius": 25e-6,
        ...                                                 "cathode-radius": 0.01, "voltage": 1500.0},
        ...                                    "source": {"electrons": 5, "radius": 0.005}})
        >>> p.geometry, p.radius, p.device().collector
        ('coaxial', 0.005, 'wire')
        """
        return cls.from_mapping(flatten_sections(tables) | flat)

    def swarm_parameters(self) -> SwarmParameters:
        """The gas as the swarm takes it (a :class:`~collisionkit.transport.SwarmParameters`).

        Examples
        --------
        >>> TrackParameters(gas="Ar", gap=1e-3).swarm_parameters().gas_name()
        'Ar'
        """
        try:
            return SwarmParameters(model=self.model, gas=self.gas, cross_sections=self.cross_sections,
                                   species=self.species, fractions=self.fractions, database=self.database,
                                   gas_temperature=self.temperature, scattering=self.scattering,
                                   populations=self.populations)
        except ValueError as error:
            raise ValueError(str(error).replace("--cross-sections", "cross-sections").replace("--gas", "gas")
                             .replace("--model", "model").replace("gas_temperature", "temperature")) from None

    def make_gas(self) -> Gas:
        """The gas (see :meth:`collisionkit.transport.SwarmParameters.make_gas`).

        Examples
        --------
        >>> TrackParameters(model="reid", gap=1e-3).make_gas().species[0].name
        'reid'
        """
        return self.swarm_parameters().make_gas()

    def device(self, gas: Gas | None = None) -> Device:
        """The :class:`Device` (gas made here unless given).

        Examples
        --------
        >>> round(TrackParameters(model="reid", gap=1e-3).device().density / 2.446e25, 3)  # 1 atm, 300 K
        1.0
        """
        gas = self.make_gas() if gas is None else gas
        magnetic = None if self.magnetic_field is None else UniformMagneticField(self.magnetic_field)
        pressure = 101325.0 if self.pressure is None and self.density is None else self.pressure
        common = dict(pressure=pressure, density=self.density, temperature=self.temperature, magnetic=magnetic)
        if self.geometry == "parallel-plate":
            return Device.parallel_plate(gas, self.gap, self.voltage, **common)
        return Device.coaxial(gas, self.wire_radius, self.cathode_radius, self.voltage, **common)

    def positions(self) -> np.ndarray:
        """The start of the primaries (1 x 3, m), checked to lie in the device.

        Examples
        --------
        >>> TrackParameters(model="reid", wire_radius=1e-5, cathode_radius=1e-2, geometry="coaxial",
        ...                 radius=2e-3).positions().tolist()
        [[0.002, 0.0, 0.0]]
        """
        if self.position is not None:
            point = np.array([self.position])
        elif self.radius is not None:
            point = np.array([[self.radius, 0.0, 0.0]])
        elif self.geometry == "parallel-plate":
            point = np.zeros((1, 3))
        else:
            point = np.array([[0.5 * (self.wire_radius + self.cathode_radius), 0.0, 0.0]])
        if self.geometry == "parallel-plate":
            inside = 0.0 <= point[0, 2] <= self.gap
        else:
            inside = self.wire_radius <= math.hypot(point[0, 0], point[0, 1]) <= self.cathode_radius
        if not inside:
            raise ValueError(f"position {point[0].tolist()} (m) lies outside the device")
        return point


def flatten_sections(tables: Mapping[str, Any]) -> dict[str, Any]:
    """The flat parameters of a device file's tables (ValueError for an unknown table or key).

    Examples
    --------
    >>> flatten_sections({"geometry": {"kind": "coaxial"}, "seed": 3})
    {'geometry': 'coaxial', 'seed': 3}
    """
    flat: dict[str, Any] = {}
    for key, value in tables.items():
        if str(key) in WHOLE_TABLES and isinstance(value, Mapping):
            if key in flat:
                raise ValueError(f"{key} is given twice")
            flat[str(key)] = dict(value)
            continue
        section = SECTIONS.get(str(key).replace("-", "_")) if isinstance(value, Mapping) else None
        if isinstance(value, Mapping) and section is None:
            raise ValueError(f"unknown table [{key}]; the device file's tables are "
                             f"{', '.join([*SECTIONS, *WHOLE_TABLES])}")
        if section is None:
            flat[str(key).replace("-", "_")] = value
            continue
        for name, item in value.items():
            target = section.get(str(name).replace("-", "_"))
            if target is None:
                raise ValueError(f"unknown key {name!r} in [{key}]; allowed: {', '.join(section)}")
            if target in flat:
                raise ValueError(f"{target} is given twice")
            flat[target] = item
    return flat
