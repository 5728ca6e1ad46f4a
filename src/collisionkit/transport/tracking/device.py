"""A device: a gas at a density, electric and magnetic fields, a bounding geometry and a readout electrode.

:meth:`Device.parallel_plate` and :meth:`Device.coaxial` build the shipped
devices with their fields, surfaces and weighting fields; any other device
is put together from a field (:mod:`.fields`, :mod:`.fieldmaps`) and a
:class:`~collisionkit.transport.tracking.geometry.Geometry`.

Weighting fields (Shockley, J. Appl. Phys. 9, 635 (1938); Ramo, Proc. IRE
27, 584 (1939)): the readout electrode at unit potential, every other at 0;
a charge q moving with velocity v induces the current ``I = q E_w . v`` on
it, ``E_w = -grad phi_w``, so that the charge induced along a path is
``-q (phi_w(end) - phi_w(start))``.

* parallel plates, the anode (z = d) read out: ``phi_w = z / d``, ``|E_w| = 1/d``;
* coaxial counter, the wire read out: ``phi_w = ln(b/r) / ln(b/a)``,
  ``E_w = r-hat / (r ln(b/a))``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy import constants

from ..._kernels.transport.tracking import codes as _c
from ..gases import Gas
from .fields import CoaxialField, Field, ParallelPlateField, _finite
from .geometry import Geometry, coaxial_geometry, parallel_plate_geometry

__all__ = ["Device", "WeightingField", "gas_density"]


def gas_density(pressure: float, temperature: float) -> float:
    """The number density N = p / (k_B T) (m^-3) of an ideal gas at ``pressure`` (Pa) and ``temperature`` (K).

    Examples
    --------
    >>> from collisionkit.transport.tracking import gas_density
    >>> round(gas_density(101325.0, 273.15) / 2.6867811e25, 6)  # Loschmidt's number
    1.0
    """
    pressure = _finite("pressure (Pa)", pressure, 0.0, low_open=True)
    temperature = _finite("temperature (K)", temperature, 0.0, low_open=True)
    return pressure / (constants.k * temperature)


@dataclass(frozen=True)
class WeightingField:
    """The weighting field of a readout electrode: ``kind`` "plates" (the plane z = ``gap`` reads out) or
    "coaxial" (the wire of a counter reads out).

    Examples
    --------
    >>> from collisionkit.transport.tracking import WeightingField
    >>> plates = WeightingField("plates", gap=2e-3)
    >>> plates.potential([[0, 0, 5e-4]]).tolist(), plates.field([[0, 0, 5e-4]]).tolist()
    ([0.25], [[0.0, 0.0, -500.0]])
    """

    kind: str
    gap: float = 0.0
    wire_radius: float = 0.0
    cathode_radius: float = 0.0
    axis: Any = (0.0, 0.0)

    def __post_init__(self):
        if self.kind == "plates":
            _finite("gap (m)", self.gap, 0.0, low_open=True)
        elif self.kind == "coaxial":
            a = _finite("wire_radius (m)", self.wire_radius, 0.0, low_open=True)
            if not self.cathode_radius > a:
                raise ValueError(f"cathode_radius must be > wire_radius; got {self.cathode_radius!r}")
        else:
            raise ValueError(f"kind must be 'plates' or 'coaxial'; got {self.kind!r}")

    def arrays(self) -> tuple[int, np.ndarray]:
        """(kind code, parameters) for the kernels.

        Examples
        --------
        >>> WeightingField("plates", gap=1e-3).arrays()[0]
        1
        """
        parameters = np.zeros(_c.FIELD_PARAMETERS)
        if self.kind == "plates":
            parameters[0] = self.gap
            return _c.W_PLATES, parameters
        parameters[:5] = (*self.axis, self.wire_radius, self.cathode_radius,
                          math.log(self.cathode_radius / self.wire_radius))
        return _c.W_COAXIAL, parameters

    def _radius(self, points):
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        d = points[:, :2] - np.asarray(self.axis, dtype=float)
        return points, d, np.maximum(np.linalg.norm(d, axis=1), self.wire_radius)

    def potential(self, points) -> np.ndarray:
        """phi_w at ``points`` (n x 3, m).

        Examples
        --------
        >>> WeightingField("coaxial", wire_radius=1e-5, cathode_radius=1e-2).potential([[1e-5, 0, 0]]).tolist()
        [1.0]
        """
        if self.kind == "plates":
            return np.asarray(points, dtype=float).reshape(-1, 3)[:, 2] / self.gap
        _, _, r = self._radius(points)
        return np.log(self.cathode_radius / r) / math.log(self.cathode_radius / self.wire_radius)

    def field(self, points) -> np.ndarray:
        """E_w = -grad phi_w at ``points`` (n x 3, m), in 1/m.

        Examples
        --------
        >>> import math
        >>> w = WeightingField("coaxial", wire_radius=1e-5, cathode_radius=1e-2).field([[1e-3, 0, 0]])
        >>> round(float(w[0, 0]) * 1e-3 * math.log(1e3), 12)
        1.0
        """
        points, d, r = self._radius(points)
        out = np.zeros_like(points)
        if self.kind == "plates":
            out[:, 2] = -1.0 / self.gap
        else:
            out[:, :2] = d / (r**2 * math.log(self.cathode_radius / self.wire_radius))[:, None]
        return out


@dataclass(frozen=True)
class Device:
    """What a tracking run needs besides its particles.

    Parameters
    ----------
    gas : Gas
        The gas (:mod:`collisionkit.transport.gases`, LXCat files, the catalogue).
    density : float
        Gas number density (m^-3, > 0); :func:`gas_density` from pressure and temperature.
    gas_temperature : float
        Temperature of the gas molecules' motion (K, >= 0; 0 puts them at rest).
    electric, magnetic : Field, optional
        The fields (none: zero).
    geometry : Geometry
        The bounding surfaces (none: an unbounded gas).
    weighting : WeightingField, optional
        The readout electrode's weighting field, for induced currents.
    collector : str, optional
        The surface that collects the electrons (gain and drift time count
        the electrons that end there).

    Examples
    --------
    >>> from collisionkit.transport import lucas_saelee
    >>> from collisionkit.transport.tracking import Device
    >>> device = Device.parallel_plate(lucas_saelee(1.0), gap=1e-3, voltage=2000.0, pressure=101325.0)
    >>> device.collector, round(float(device.reduced_field_at([[0, 0, 5e-4]])[0]), 1)  # E/N in Td
    ('anode', 81.8)
    """

    gas: Gas
    density: float
    gas_temperature: float = 300.0
    electric: Field | None = None
    magnetic: Field | None = None
    geometry: Geometry = Geometry()
    weighting: WeightingField | None = None
    collector: str | None = None

    def __post_init__(self):
        if not isinstance(self.gas, Gas):
            raise TypeError(f"gas must be a Gas; got {type(self.gas).__name__}")
        object.__setattr__(self, "density", _finite("density (m^-3)", self.density, 0.0, low_open=True))
        object.__setattr__(self, "gas_temperature", _finite("gas_temperature (K)", self.gas_temperature, 0.0))
        for name, magnetic in (("electric", False), ("magnetic", True)):
            value = getattr(self, name)
            if value is not None and (not isinstance(value, Field) or value.magnetic != magnetic):
                raise TypeError(f"{name} must be {'a magnetic' if magnetic else 'an electric'} field; got {value!r}")
        if not isinstance(self.geometry, Geometry):
            raise TypeError(f"geometry must be a Geometry; got {type(self.geometry).__name__}")
        if self.weighting is not None and not isinstance(self.weighting, WeightingField):
            raise TypeError(f"weighting must be a WeightingField; got {type(self.weighting).__name__}")
        if self.collector is not None:
            self.geometry.index(self.collector)

    @classmethod
    def parallel_plate(cls, gas: Gas, gap: float, voltage: float, *, pressure: float | None = None,
                       temperature: float = 300.0, density: float | None = None, magnetic: Field | None = None):
        """Parallel plates: the cathode z = 0 at 0 V, the anode z = ``gap`` at ``voltage`` (read out).

        Give ``pressure`` (Pa) or ``density`` (m^-3); ``temperature`` (K) is
        the gas's (and gives the density from the pressure). Electrons are
        collected by the anode for a positive voltage, by the cathode for a
        negative one.

        Examples
        --------
        >>> from collisionkit.transport import reid_ramp
        >>> Device.parallel_plate(reid_ramp(), 1e-3, -50.0, density=1e24).collector
        'cathode'
        """
        gap = _finite("gap (m)", gap, 0.0, low_open=True)
        return cls(gas, _density(pressure, temperature, density), temperature, ParallelPlateField(gap, voltage),
                   magnetic, parallel_plate_geometry(gap), WeightingField("plates", gap=gap),
                   "anode" if voltage >= 0 else "cathode")

    @classmethod
    def coaxial(cls, gas: Gas, wire_radius: float, cathode_radius: float, voltage: float, *,
                pressure: float | None = None, temperature: float = 300.0, density: float | None = None,
                magnetic: Field | None = None):
        """A proportional counter: the wire (read out) at ``voltage``, the cathode cylinder at 0 V, about the z axis.

        Electrons are collected by the wire for a positive voltage.

        Examples
        --------
        >>> from collisionkit.transport import reid_ramp
        >>> Device.coaxial(reid_ramp(), 25e-6, 0.01, 1500.0, density=1e24).collector
        'wire'
        """
        field = CoaxialField(wire_radius, cathode_radius, voltage)
        return cls(gas, _density(pressure, temperature, density), temperature, field, magnetic,
                   coaxial_geometry(field.wire_radius, field.cathode_radius),
                   WeightingField("coaxial", wire_radius=field.wire_radius, cathode_radius=field.cathode_radius),
                   "wire" if voltage >= 0 else "cathode")

    def reduced_field_at(self, points) -> np.ndarray:
        """E/N (Td) at ``points`` (n x 3, m).

        Examples
        --------
        >>> from collisionkit.transport import reid_ramp
        >>> from collisionkit.transport.tracking import UniformField
        >>> Device(reid_ramp(), 1e24, 0.0, UniformField((0, 0, 1.2e4))).reduced_field_at([[0, 0, 0]]).tolist()
        [12.0]
        """
        if self.electric is None:
            return np.zeros(np.asarray(points).reshape(-1, 3).shape[0])
        return np.linalg.norm(self.electric.at(points), axis=1) / self.density / 1e-21


def _density(pressure, temperature, density) -> float:
    if (pressure is None) == (density is None):
        raise ValueError("give exactly one of pressure (Pa) and density (m^-3)")
    if density is not None:
        return _finite("density (m^-3)", density, 0.0, low_open=True)
    return gas_density(pressure, temperature)
