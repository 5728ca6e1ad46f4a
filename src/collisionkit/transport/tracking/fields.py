"""Electric and magnetic fields for particle tracking: analytic fields, user functions and field maps.

Every field is a small frozen object that the tracking kernel evaluates at
any point (:mod:`collisionkit._kernels.transport.tracking.fields`) and that
Python can evaluate too (:meth:`Field.at`). SI units throughout: metres,
V/m, T, volts.

Analytic fields (with their potential where there is one):

* :class:`UniformField`;
* :class:`ParallelPlateField`: the plane z = 0 at 0 V, z = gap at ``voltage``,
  ``E = -V/d`` along z;
* :class:`CoaxialField`: a wire of radius a at ``voltage`` inside a
  cylinder of radius b at 0 V, both about the z axis (through ``axis``):
  ``E = V / (r ln(b/a))`` radial, ``phi = V ln(b/r) / ln(b/a)``;
* :class:`PointChargeField`: ``E = Q r-hat / (4 pi eps0 r^2)``;
* magnetic fields in :mod:`.magnetic`.

A :class:`UserField` wraps a function ``f(x, y, z, out)`` compiled with
numba, and a :class:`~collisionkit.transport.tracking.fieldmaps.FieldMap`
interpolates a grid.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy import constants

from ..._kernels.transport.tracking import codes as _c
from ..._kernels.transport.tracking.fields import compile_user_field, field_values, no_field, potential_at

__all__ = ["Field", "UniformField", "ParallelPlateField", "CoaxialField", "PointChargeField", "UserField"]

_NO_MAP_META = np.zeros(_c.MAP_META)
_NO_MAP_VALUES = np.zeros((2, 2, 2, 3))


def _finite(name: str, value, low: float = -math.inf, low_open: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        raise TypeError(f"{name} must be a number; got {value!r}")
    value = float(value)
    if not math.isfinite(value) or value < low or (low_open and value == low):
        bound = f" {'>' if low_open else '>='} {low:g}" if math.isfinite(low) else ""
        raise ValueError(f"{name} must be finite{bound}; got {value!r}")
    return value


def _vector(name: str, value) -> np.ndarray:
    try:
        vector = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be three numbers; got {value!r}") from None
    if vector.shape != (3,) or not np.all(np.isfinite(vector)):
        raise ValueError(f"{name} must be three finite numbers; got {value!r}")
    return vector


def _parameters(*values) -> np.ndarray:
    out = np.zeros(_c.FIELD_PARAMETERS)
    out[: len(values)] = values
    return out


class Field:
    """Base of the fields: what the kernel needs (:meth:`arrays`) and evaluation in Python (:meth:`at`).

    ``magnetic`` tells a magnetic field (T) from an electric one (V/m).

    Examples
    --------
    >>> from collisionkit.transport.tracking import UniformField
    >>> UniformField((0, 0, -1e5)).at([[0, 0, 0]]).tolist()
    [[0.0, 0.0, -100000.0]]
    """

    magnetic: bool = False
    kind: int = 0

    def parameters(self) -> np.ndarray:
        """The kernel's parameter array of the field.

        Examples
        --------
        >>> from collisionkit.transport.tracking import ParallelPlateField
        >>> ParallelPlateField(1e-3, 500.0).parameters()[:2].tolist()
        [0.001, 500.0]
        """
        return np.zeros(_c.FIELD_PARAMETERS)

    def arrays(self) -> tuple[int, np.ndarray, np.ndarray, np.ndarray, Any]:
        """(kind, parameters, map meta, map values, compiled user function): the kernel's arguments.

        Examples
        --------
        >>> from collisionkit.transport.tracking import CoaxialField
        >>> kind, parameters, meta, values, user = CoaxialField(25e-6, 0.01, 1500.0).arrays()
        >>> kind, values.shape
        (3, (2, 2, 2, 3))
        """
        return self.kind, self.parameters(), _NO_MAP_META, _NO_MAP_VALUES, no_field()

    def blocks(self) -> np.ndarray:
        """The local bounds of |E| per block of cells that the null-collision method reads (maps only; one zero
        entry for other fields).

        Examples
        --------
        >>> from collisionkit.transport.tracking import UniformField
        >>> UniformField((0, 0, 1.0)).blocks().shape
        (1,)
        """
        return np.zeros(1)

    def at(self, points) -> np.ndarray:
        """The field at ``points`` (n x 3, m): an (n x 3) array of V/m (electric) or T (magnetic).

        Examples
        --------
        >>> from collisionkit.transport.tracking import CoaxialField
        >>> import math
        >>> e = CoaxialField(25e-6, 0.01, 1500.0).at([[1e-3, 0, 0]])[0, 0]
        >>> round(float(e) / (1500 / (1e-3 * math.log(0.01 / 25e-6))), 12)
        1.0
        """
        points = np.ascontiguousarray(np.asarray(points, dtype=float).reshape(-1, 3))
        out = np.zeros_like(points)
        kind, parameters, meta, values, user = self.arrays()
        field_values(self.magnetic, kind, parameters, meta, values, user, points, out)
        return out

    def potential(self, points) -> np.ndarray:
        """The electric potential (V) at ``points`` (n x 3, m), where the field has one (NaN otherwise).

        Examples
        --------
        >>> from collisionkit.transport.tracking import ParallelPlateField
        >>> ParallelPlateField(1e-3, 500.0).potential([[0, 0, 0.5e-3]]).tolist()
        [250.0]
        """
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        if self.magnetic:
            return np.full(points.shape[0], math.nan)
        parameters = self.parameters()
        return np.array([potential_at(self.kind, parameters, *point) for point in points])

    def bound(self) -> float:
        """An upper bound of the field's magnitude over all space (inf where it has none), for the null-collision
        method's step limits.

        Examples
        --------
        >>> from collisionkit.transport.tracking import ParallelPlateField
        >>> ParallelPlateField(1e-3, 500.0).bound()
        500000.0
        """
        return math.inf

    def is_uniform(self) -> bool:
        """True for a field that is the same everywhere (and none): the motion in it is exact.

        Examples
        --------
        >>> from collisionkit.transport.tracking import ParallelPlateField, UniformField
        >>> UniformField((0, 0, 1)).is_uniform(), ParallelPlateField(1e-3, 5.0).is_uniform()
        (True, True)
        """
        return False

    def uniform_value(self) -> np.ndarray:
        """The value of a uniform field (V/m or T) (ValueError for another).

        Examples
        --------
        >>> from collisionkit.transport.tracking import ParallelPlateField
        >>> ParallelPlateField(1e-3, 500.0).uniform_value().tolist()
        [0.0, 0.0, -500000.0]
        """
        if not self.is_uniform():
            raise ValueError(f"{type(self).__name__} is not uniform")
        return self.at([[0.0, 0.0, 0.0]])[0]


@dataclass(frozen=True)
class UniformField(Field):
    """A uniform electric field (V/m).

    Examples
    --------
    >>> from collisionkit.transport.tracking import UniformField
    >>> UniformField((0, 0, -2e4)).potential([[0, 0, 1e-3]]).tolist()  # phi = -E . r
    [20.0]
    """

    value: Any = (0.0, 0.0, 0.0)
    kind: int = field(default=_c.E_UNIFORM, init=False)

    def __post_init__(self):
        object.__setattr__(self, "value", _vector("value (V/m)", self.value))

    def parameters(self):
        """The field's components (see :meth:`Field.parameters`).

        Examples
        --------
        >>> UniformField((1.0, 2.0, 3.0)).parameters()[:3].tolist()
        [1.0, 2.0, 3.0]
        """
        return _parameters(*self.value)

    def bound(self):
        """|E| (see :meth:`Field.bound`).

        Examples
        --------
        >>> UniformField((3.0, 4.0, 0.0)).bound()
        5.0
        """
        return float(np.linalg.norm(self.value))

    def is_uniform(self):
        """True (see :meth:`Field.is_uniform`).

        Examples
        --------
        >>> UniformField((0, 0, 1.0)).is_uniform()
        True
        """
        return True


@dataclass(frozen=True)
class ParallelPlateField(Field):
    """The field between parallel plates: z = 0 at 0 V, z = ``gap`` (m, > 0) at ``voltage`` (V).

    ``E = -V/gap`` along z, ``phi = V z / gap``.

    Examples
    --------
    >>> from collisionkit.transport.tracking import ParallelPlateField
    >>> ParallelPlateField(2e-3, 400.0).at([[0, 0, 1e-3]]).tolist()
    [[0.0, 0.0, -200000.0]]
    """

    gap: float = 1e-3
    voltage: float = 0.0
    kind: int = field(default=_c.E_PLATES, init=False)

    def __post_init__(self):
        object.__setattr__(self, "gap", _finite("gap (m)", self.gap, 0.0, low_open=True))
        object.__setattr__(self, "voltage", _finite("voltage (V)", self.voltage))

    def parameters(self):
        """gap, voltage (see :meth:`Field.parameters`).

        Examples
        --------
        >>> ParallelPlateField(1e-3, 5.0).parameters()[:2].tolist()
        [0.001, 5.0]
        """
        return _parameters(self.gap, self.voltage)

    def bound(self):
        """|V| / gap (see :meth:`Field.bound`).

        Examples
        --------
        >>> ParallelPlateField(1e-3, -5.0).bound()
        5000.0
        """
        return abs(self.voltage) / self.gap

    def is_uniform(self):
        """True (see :meth:`Field.is_uniform`).

        Examples
        --------
        >>> ParallelPlateField(1e-3, 5.0).is_uniform()
        True
        """
        return True


@dataclass(frozen=True)
class CoaxialField(Field):
    """A proportional counter: a wire of ``wire_radius`` a at ``voltage`` V inside a cathode of ``cathode_radius``
    b at 0 V, about the z axis through ``axis`` (x, y).

    ``E(r) = V / (r ln(b/a))`` along r-hat, ``phi(r) = V ln(b/r) / ln(b/a)``
    (Gauss's law for a line charge; e.g. Knoll, *Radiation Detection and
    Measurement*, ch. 6).

    Examples
    --------
    >>> from collisionkit.transport.tracking import CoaxialField
    >>> counter = CoaxialField(25e-6, 0.01, 1500.0)
    >>> [round(float(v), 6) for v in counter.potential([[25e-6, 0, 0], [0, 0.01, 0]])]
    [1500.0, 0.0]
    """

    wire_radius: float = 25e-6
    cathode_radius: float = 0.01
    voltage: float = 0.0
    axis: Any = (0.0, 0.0)
    kind: int = field(default=_c.E_COAXIAL, init=False)

    def __post_init__(self):
        a = _finite("wire_radius (m)", self.wire_radius, 0.0, low_open=True)
        b = _finite("cathode_radius (m)", self.cathode_radius, 0.0, low_open=True)
        if not b > a:
            raise ValueError(f"cathode_radius must be > wire_radius ({a:g} m); got {b:g}")
        axis = np.asarray(self.axis, dtype=float).reshape(-1)
        if axis.shape != (2,) or not np.all(np.isfinite(axis)):
            raise ValueError(f"axis must be two finite numbers (x, y of the wire, m); got {self.axis!r}")
        object.__setattr__(self, "wire_radius", a)
        object.__setattr__(self, "cathode_radius", b)
        object.__setattr__(self, "voltage", _finite("voltage (V)", self.voltage))
        object.__setattr__(self, "axis", tuple(float(v) for v in axis))

    def parameters(self):
        """axis x, y, a, b, V, ln(b/a) (see :meth:`Field.parameters`).

        Examples
        --------
        >>> CoaxialField(1e-5, 1e-2, 100.0).parameters()[:5].tolist()
        [0.0, 0.0, 1e-05, 0.01, 100.0]
        """
        return _parameters(*self.axis, self.wire_radius, self.cathode_radius, self.voltage,
                           math.log(self.cathode_radius / self.wire_radius))

    def bound(self):
        """The field at the wire, |V| / (a ln(b/a)) (see :meth:`Field.bound`).

        Examples
        --------
        >>> import math
        >>> round(CoaxialField(1e-5, 1e-2, 100.0).bound() * 1e-5 * math.log(1e3), 9)
        100.0
        """
        return abs(self.voltage) / (self.wire_radius * math.log(self.cathode_radius / self.wire_radius))


@dataclass(frozen=True)
class PointChargeField(Field):
    """The field of a point charge ``charge`` (C) at ``position`` (m), felt from ``radius`` (m, > 0) outwards
    (inside it, the field at that radius): ``E = Q r-hat / (4 pi eps0 r^2)``, ``phi = Q / (4 pi eps0 r)``.

    Examples
    --------
    >>> from collisionkit.transport.tracking import PointChargeField
    >>> from scipy import constants
    >>> q = 4 * 3.141592653589793 * constants.epsilon_0  # k = 1 V m
    >>> PointChargeField(q, (0, 0, 0), 1e-6).at([[0, 0, 2.0]]).round(12).tolist()
    [[0.0, 0.0, 0.25]]
    """

    charge: float = 0.0
    position: Any = (0.0, 0.0, 0.0)
    radius: float = 1e-6
    kind: int = field(default=_c.E_POINT, init=False)

    def __post_init__(self):
        object.__setattr__(self, "charge", _finite("charge (C)", self.charge))
        object.__setattr__(self, "position", _vector("position (m)", self.position))
        object.__setattr__(self, "radius", _finite("radius (m)", self.radius, 0.0, low_open=True))

    def parameters(self):
        """x, y, z, Q/(4 pi eps0), radius (see :meth:`Field.parameters`).

        Examples
        --------
        >>> PointChargeField(0.0, (1, 2, 3), 0.5).parameters()[[0, 1, 2, 4]].tolist()
        [1.0, 2.0, 3.0, 0.5]
        """
        k = self.charge / (4.0 * math.pi * constants.epsilon_0)
        return _parameters(*self.position, k, self.radius)

    def bound(self):
        """The field at ``radius`` (see :meth:`Field.bound`).

        Examples
        --------
        >>> PointChargeField(0.0, (0, 0, 0), 1.0).bound()
        0.0
        """
        return abs(self.charge) / (4.0 * math.pi * constants.epsilon_0 * self.radius**2)


class UserField(Field):
    """A field computed by a user's function ``function(x, y, z, out)`` that writes the three components into
    ``out`` (a float64 array of 3), compiled by numba (a plain Python function is compiled here).

    Parameters
    ----------
    function : callable
        The field in SI units (V/m, or T with ``magnetic=True``).
    magnetic : bool
        True for a magnetic field.
    max_field : float, optional
        An upper bound of |E| (V/m) over the volume: the null-collision
        method needs it (the path-length method does not).

    Examples
    --------
    >>> from collisionkit.transport.tracking import UserField
    >>> def quadrupole(x, y, z, out):
    ...     out[0] = 1e6 * x
    ...     out[1] = -1e6 * y
    ...     out[2] = 0.0
    >>> UserField(quadrupole, max_field=1e4).at([[1e-3, 2e-3, 0]]).tolist()
    [[1000.0, -2000.0, 0.0]]
    """

    def __init__(self, function, magnetic: bool = False, max_field: float | None = None):
        if not callable(function):
            raise TypeError(f"function must be callable as function(x, y, z, out); got {function!r}")
        self.function = function
        self.magnetic = bool(magnetic)
        self.kind = _c.B_USER if self.magnetic else _c.E_USER
        self.max_field = None if max_field is None else _finite("max_field", max_field, 0.0, low_open=True)
        self._compiled = None

    def __repr__(self):
        return f"UserField({getattr(self.function, '__name__', self.function)!r}, magnetic={self.magnetic})"

    def compiled(self):
        """The function compiled for the kernels (once).

        Examples
        --------
        >>> field = UserField(lambda x, y, z, out: None)
        >>> field.compiled() is field.compiled()
        True
        """
        if self._compiled is None:
            try:
                self._compiled = compile_user_field(self.function)
            except Exception as error:  # numba's typing errors are long: one line naming the function
                first = str(error).strip().splitlines()[0] if str(error).strip() else type(error).__name__
                raise ValueError(f"the field function {getattr(self.function, '__name__', '?')} cannot be compiled "
                                 f"by numba as f(x, y, z, out) with float arguments and out a float array of 3: "
                                 f"{first}") from None
        return self._compiled

    def parameters(self):
        """parameter 0: the bound of |E|, 0 if unknown (see :meth:`Field.parameters`).

        Examples
        --------
        >>> UserField(lambda x, y, z, out: None, max_field=5.0).parameters()[0]
        np.float64(5.0)
        """
        return _parameters(self.max_field or 0.0)

    def arrays(self):
        """The kernel's arguments, with the compiled function (see :meth:`Field.arrays`).

        Examples
        --------
        >>> UserField(lambda x, y, z, out: None).arrays()[0]
        6
        """
        return self.kind, self.parameters(), _NO_MAP_META, _NO_MAP_VALUES, self.compiled()

    def bound(self):
        """``max_field`` (inf if not given) (see :meth:`Field.bound`).

        Examples
        --------
        >>> UserField(lambda x, y, z, out: None).bound()
        inf
        """
        return math.inf if self.max_field is None else self.max_field
