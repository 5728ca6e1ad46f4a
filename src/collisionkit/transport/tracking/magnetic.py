"""Magnetic fields for particle tracking (T): uniform, a dipole, a magnetic mirror.

* :class:`UniformMagneticField`;
* :class:`DipoleMagneticField`: ``B = mu0 (3 r-hat (m . r-hat) - m) / (4 pi r^3)``;
* :class:`MagneticMirror`: ``B_z = B0 (1 + (z/L)^2)``, ``B_r = -(r/2) dB_z/dz``.

A field map (:mod:`.fieldmaps`) or a :class:`~collisionkit.transport.tracking.UserField` with
``magnetic=True`` gives any other.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from ..._kernels.transport.tracking import codes as _c
from .fields import Field, _finite, _parameters, _vector

__all__ = ["UniformMagneticField", "DipoleMagneticField", "MagneticMirror"]


@dataclass(frozen=True)
class UniformMagneticField(Field):
    """A uniform magnetic field (T).

    Examples
    --------
    >>> from collisionkit.transport.tracking import UniformMagneticField
    >>> UniformMagneticField((0, 0, 0.1)).at([[1, 2, 3]]).tolist()
    [[0.0, 0.0, 0.1]]
    """

    value: Any = (0.0, 0.0, 0.0)
    magnetic: bool = field(default=True, init=False)
    kind: int = field(default=_c.B_UNIFORM, init=False)

    def __post_init__(self):
        object.__setattr__(self, "value", _vector("value (T)", self.value))

    def parameters(self):
        """The components (see :meth:`Field.parameters`).

        Examples
        --------
        >>> UniformMagneticField((0, 0, 0.1)).parameters()[:3].tolist()
        [0.0, 0.0, 0.1]
        """
        return _parameters(*self.value)

    def is_uniform(self):
        """True (see :meth:`Field.is_uniform`).

        Examples
        --------
        >>> UniformMagneticField((0, 0, 0.1)).is_uniform()
        True
        """
        return True


@dataclass(frozen=True)
class DipoleMagneticField(Field):
    """A magnetic dipole of ``moment`` (A m^2) at ``position`` (m), felt from ``radius`` (m) outwards.

    ``B = mu0 / (4 pi) (3 r-hat (m . r-hat) - m) / r^3``.

    Examples
    --------
    >>> from collisionkit.transport.tracking import DipoleMagneticField
    >>> b = DipoleMagneticField((0, 0, 1.0)).at([[0, 0, 1.0], [1.0, 0, 0]])
    >>> (b / 1e-7).round(9).tolist()  # on the axis 2 mu0 m / (4 pi r^3), on the equator -mu0 m / (4 pi r^3)
    [[0.0, 0.0, 2.0], [0.0, 0.0, -1.0]]
    """

    moment: Any = (0.0, 0.0, 0.0)
    position: Any = (0.0, 0.0, 0.0)
    radius: float = 1e-6
    magnetic: bool = field(default=True, init=False)
    kind: int = field(default=_c.B_DIPOLE, init=False)

    def __post_init__(self):
        object.__setattr__(self, "moment", _vector("moment (A m^2)", self.moment))
        object.__setattr__(self, "position", _vector("position (m)", self.position))
        object.__setattr__(self, "radius", _finite("radius (m)", self.radius, 0.0, low_open=True))

    def parameters(self):
        """x, y, z, moment, radius (see :meth:`Field.parameters`).

        Examples
        --------
        >>> DipoleMagneticField((0, 0, 2.0), (1, 0, 0), 0.5).parameters()[:7].tolist()
        [1.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.5]
        """
        return _parameters(*self.position, *self.moment, self.radius)


@dataclass(frozen=True)
class MagneticMirror(Field):
    """A magnetic mirror about the z axis through ``centre``: ``B_z = B0 (1 + (z/L)^2)`` and the paraxial
    ``B_r = -(r/2) dB_z/dz = -B0 r z / L^2`` (divergence free); B0 in T, ``length`` L in m (> 0).

    A particle of pitch angle theta at the centre is reflected where
    ``B = B0 / sin^2(theta)`` (conservation of the magnetic moment).

    Examples
    --------
    >>> from collisionkit.transport.tracking import MagneticMirror
    >>> (MagneticMirror(0.1, 0.5).at([[0, 0, 0.5]]).round(12) + 0.0).tolist()
    [[0.0, 0.0, 0.2]]
    """

    b0: float = 0.0
    length: float = 1.0
    centre: Any = (0.0, 0.0, 0.0)
    magnetic: bool = field(default=True, init=False)
    kind: int = field(default=_c.B_MIRROR, init=False)

    def __post_init__(self):
        object.__setattr__(self, "b0", _finite("b0 (T)", self.b0))
        object.__setattr__(self, "length", _finite("length (m)", self.length, 0.0, low_open=True))
        object.__setattr__(self, "centre", _vector("centre (m)", self.centre))

    def parameters(self):
        """centre, B0, L (see :meth:`Field.parameters`).

        Examples
        --------
        >>> MagneticMirror(0.1, 0.5).parameters()[:5].tolist()
        [0.0, 0.0, 0.0, 0.1, 0.5]
        """
        return _parameters(*self.centre, self.b0, self.length)
