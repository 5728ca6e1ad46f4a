"""Particles in any force field and in real devices: Krasov's algorithm (sec. 5.5) in full.

A particle moves under E(x) and B(x), integrated numerically with error
control (exactly where both are uniform); its free path is drawn and used
up along the trajectory (the path-length method), or collisions come by
the null-collision method; it scatters, ionizes (the new electrons are
followed too), and ends on an electrode or another surface of the device.

* fields: :class:`UniformField`, :class:`ParallelPlateField`,
  :class:`CoaxialField`, :class:`PointChargeField`,
  :class:`UniformMagneticField`, :class:`DipoleMagneticField`,
  :class:`MagneticMirror`, :class:`UserField`, :class:`FieldMap` and
  :func:`read_field_map`;
* geometry: :class:`Plane`, :class:`Cylinder`, :class:`Sphere`,
  :class:`Geometry`, :func:`parallel_plate_geometry`, :func:`coaxial_geometry`;
* devices: :class:`Device` (gas, density, fields, geometry, readout),
  :class:`WeightingField`, :func:`gas_density`;
* runs: :func:`track` -> :class:`TrackingResult`; :class:`IonDrift`; :class:`ElectronLimitError`;
  :class:`TrackParameters` and :class:`TrackRun` (the ``track`` command, with
  checkpoints) and :func:`track_summary`.
"""

from .device import Device, WeightingField, gas_density
from .fieldmaps import FieldMap, read_field_map
from .fields import CoaxialField, Field, ParallelPlateField, PointChargeField, UniformField, UserField
from .magnetic import DipoleMagneticField, MagneticMirror, UniformMagneticField
from .geometry import Cylinder, Geometry, Plane, Sphere, Surface, coaxial_geometry, parallel_plate_geometry
from .command import TrackRun, track_summary
from .parameters import TrackParameters
from .result import TrackingResult
from .run import METHODS, ElectronLimitError, IonDrift, track

__all__ = [
    "CoaxialField", "Cylinder", "Device", "DipoleMagneticField", "ElectronLimitError", "Field", "FieldMap",
    "Geometry", "IonDrift", "METHODS", "MagneticMirror", "ParallelPlateField", "Plane", "PointChargeField", "Sphere", "Surface",
    "TrackParameters", "TrackRun", "TrackingResult", "UniformField", "UniformMagneticField", "UserField",
    "WeightingField", "coaxial_geometry", "gas_density", "parallel_plate_geometry", "read_field_map", "track",
    "track_summary",
]
