"""The tracking volume: surfaces (planes, cylinders, spheres) that absorb, reflect or let particles out.

The volume is the intersection of the surfaces' inner sides. A particle
whose step crosses a surface stops there (the crossing found by bisection on
the step's dense output, to 1e-15 of the step): an ``absorb`` surface (an
electrode) or a ``transparent`` one (the volume's open side) ends the
particle, which is recorded with where, when, its energy and direction; a
``reflect`` surface turns the velocity specularly about its normal.

:func:`parallel_plate_geometry` and :func:`coaxial_geometry` build the
volumes of the shipped devices.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..._kernels.transport.tracking import codes as _c
from .fields import _finite, _vector

__all__ = ["ACTIONS", "Surface", "Plane", "Cylinder", "Sphere", "Geometry", "parallel_plate_geometry",
           "coaxial_geometry"]

ACTIONS = {"absorb": _c.ABSORB, "reflect": _c.REFLECT, "transparent": _c.TRANSPARENT}


def _action(action: str) -> str:
    if action not in ACTIONS:
        raise ValueError(f"action must be one of {', '.join(ACTIONS)}; got {action!r}")
    return action


def _unit(name: str, value) -> np.ndarray:
    vector = _vector(name, value)
    norm = float(np.linalg.norm(vector))
    if norm == 0.0:
        raise ValueError(f"{name} must not be zero")
    return vector / norm


class Surface:
    """Base of the surfaces: a row of the kernel's surface table and a signed distance (>= 0 inside).

    Examples
    --------
    >>> from collisionkit.transport.tracking import Plane
    >>> Plane((0, 0, 0), (0, 0, 1)).distance([[0, 0, 2.0], [0, 0, -1.0]]).tolist()
    [2.0, -1.0]
    """

    name: str = ""
    action: str = "absorb"

    def row(self) -> np.ndarray:
        """The kernel's row: kind, action, parameters.

        Examples
        --------
        >>> from collisionkit.transport.tracking import Sphere
        >>> Sphere((0, 0, 0), 2.0).row()[[0, 8, 9]].tolist()
        [2.0, 2.0, 1.0]
        """
        raise NotImplementedError

    def distance(self, points) -> np.ndarray:
        """Signed distances of ``points`` (n x 3, m): >= 0 on the volume's side.

        Examples
        --------
        >>> from collisionkit.transport.tracking import Cylinder
        >>> Cylinder(1.0).distance([[0.5, 0, 7.0]]).tolist()
        [0.5]
        """
        raise NotImplementedError

    def inward_normal(self, points, step: float = 1e-7) -> np.ndarray:
        """Unit normals (n x 3) pointing into the volume at ``points``: the gradient of the signed distance
        (central differences of ``step`` times the distance scale, exact for the linear and quadratic parts).

        Examples
        --------
        >>> from collisionkit.transport.tracking import Sphere
        >>> Sphere((0, 0, 0), 1.0).inward_normal([[0, 0, 1.0]]).round(9).tolist()
        [[0.0, 0.0, -1.0]]
        """
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        scale = step * max(1.0, float(np.abs(points).max(initial=0.0)))
        gradient = np.column_stack([(self.distance(points + scale * e) - self.distance(points - scale * e))
                                    / (2 * scale) for e in np.eye(3)])
        return gradient / np.maximum(np.linalg.norm(gradient, axis=1), 1e-300)[:, None]


@dataclass(frozen=True)
class Plane(Surface):
    """The plane through ``point`` with ``normal`` pointing into the volume.

    Examples
    --------
    >>> from collisionkit.transport.tracking import Plane
    >>> Plane((0, 0, 1e-3), (0, 0, -1), action="absorb", name="anode").distance([[0, 0, 0]]).tolist()
    [0.001]
    """

    point: Any = (0.0, 0.0, 0.0)
    normal: Any = (0.0, 0.0, 1.0)
    action: str = "absorb"
    name: str = "plane"

    def __post_init__(self):
        object.__setattr__(self, "point", _vector("point (m)", self.point))
        object.__setattr__(self, "normal", _unit("normal", self.normal))
        _action(self.action)

    def row(self):
        """See :meth:`Surface.row`.

        Examples
        --------
        >>> Plane((0, 0, 0), (0, 0, 2)).row()[5:8].tolist()
        [0.0, 0.0, 1.0]
        """
        row = np.zeros(_c.SURFACE_COLUMNS)
        row[0], row[1] = _c.PLANE, ACTIONS[self.action]
        row[2:5], row[5:8] = self.point, self.normal
        return row

    def distance(self, points):
        """See :meth:`Surface.distance`.

        Examples
        --------
        >>> Plane((0, 0, 0), (1, 0, 0)).distance([[3.0, 1.0, 1.0]]).tolist()
        [3.0]
        """
        return (np.asarray(points, dtype=float).reshape(-1, 3) - self.point) @ self.normal


@dataclass(frozen=True)
class Cylinder(Surface):
    """A cylinder of ``radius`` (m) about the line through ``point`` along ``axis``; the volume is inside it
    (``inside=True``) or outside (a wire).

    Examples
    --------
    >>> from collisionkit.transport.tracking import Cylinder
    >>> Cylinder(25e-6, inside=False, name="wire").distance([[1e-4, 0, 0]]).round(9).tolist()
    [7.5e-05]
    """

    radius: float = 1.0
    point: Any = (0.0, 0.0, 0.0)
    axis: Any = (0.0, 0.0, 1.0)
    inside: bool = True
    action: str = "absorb"
    name: str = "cylinder"

    def __post_init__(self):
        object.__setattr__(self, "radius", _finite("radius (m)", self.radius, 0.0, low_open=True))
        object.__setattr__(self, "point", _vector("point (m)", self.point))
        object.__setattr__(self, "axis", _unit("axis", self.axis))
        _action(self.action)

    def row(self):
        """See :meth:`Surface.row`.

        Examples
        --------
        >>> Cylinder(2.0, inside=False).row()[[0, 8, 9]].tolist()
        [1.0, 2.0, -1.0]
        """
        row = np.zeros(_c.SURFACE_COLUMNS)
        row[0], row[1] = _c.CYLINDER, ACTIONS[self.action]
        row[2:5], row[5:8] = self.point, self.axis
        row[8], row[9] = self.radius, 1.0 if self.inside else -1.0
        return row

    def distance(self, points):
        """See :meth:`Surface.distance`.

        Examples
        --------
        >>> Cylinder(1.0, axis=(1, 0, 0)).distance([[5.0, 0.0, 2.0]]).tolist()
        [-1.0]
        """
        d = np.asarray(points, dtype=float).reshape(-1, 3) - self.point
        rho = np.linalg.norm(d - np.outer(d @ self.axis, self.axis), axis=1)
        return (1.0 if self.inside else -1.0) * (self.radius - rho)


@dataclass(frozen=True)
class Sphere(Surface):
    """A sphere of ``radius`` (m) about ``centre``; the volume is inside it (``inside=True``) or outside.

    Examples
    --------
    >>> from collisionkit.transport.tracking import Sphere
    >>> Sphere((0, 0, 0), 1.0, inside=False).distance([[0, 0, 3.0]]).tolist()
    [2.0]
    """

    centre: Any = (0.0, 0.0, 0.0)
    radius: float = 1.0
    inside: bool = True
    action: str = "absorb"
    name: str = "sphere"

    def __post_init__(self):
        object.__setattr__(self, "centre", _vector("centre (m)", self.centre))
        object.__setattr__(self, "radius", _finite("radius (m)", self.radius, 0.0, low_open=True))
        _action(self.action)

    def row(self):
        """See :meth:`Surface.row`.

        Examples
        --------
        >>> Sphere((1, 2, 3), 4.0).row()[2:5].tolist()
        [1.0, 2.0, 3.0]
        """
        row = np.zeros(_c.SURFACE_COLUMNS)
        row[0], row[1] = _c.SPHERE, ACTIONS[self.action]
        row[2:5] = self.centre
        row[8], row[9] = self.radius, 1.0 if self.inside else -1.0
        return row

    def distance(self, points):
        """See :meth:`Surface.distance`.

        Examples
        --------
        >>> Sphere((0, 0, 0), 1.0).distance([[0, 0, 0.25]]).tolist()
        [0.75]
        """
        r = np.linalg.norm(np.asarray(points, dtype=float).reshape(-1, 3) - self.centre, axis=1)
        return (1.0 if self.inside else -1.0) * (self.radius - r)


@dataclass(frozen=True)
class Geometry:
    """A volume bounded by surfaces.

    Parameters
    ----------
    surfaces : sequence of Surface
        Their names must differ (records and results name them).
    length_scale : float, optional
        The size of the smallest feature (m): the integrator's position
        tolerance is relative to it, and a step moves a particle at most
        that far (so that a step cannot cross a feature and come back).
        Default: the smallest radius, or the smallest distance between two
        parallel planes, or 1 mm.

    Examples
    --------
    >>> from collisionkit.transport.tracking import coaxial_geometry
    >>> counter = coaxial_geometry(25e-6, 0.01)
    >>> [s.name for s in counter.surfaces], counter.length_scale, counter.contains([[1e-3, 0, 0]]).tolist()
    (['wire', 'cathode'], 2.5e-05, [True])
    """

    surfaces: tuple = ()
    length_scale: float | None = None

    def __post_init__(self):
        surfaces = tuple(self.surfaces)
        if not all(isinstance(surface, Surface) for surface in surfaces):
            raise TypeError("surfaces must be Plane, Cylinder or Sphere objects")
        names = [surface.name for surface in surfaces]
        if len(set(names)) != len(names):
            raise ValueError(f"the surfaces need different names; got {names}")
        object.__setattr__(self, "surfaces", surfaces)
        if self.length_scale is None:
            object.__setattr__(self, "length_scale", self._smallest_feature())
        else:
            object.__setattr__(self, "length_scale", _finite("length_scale (m)", self.length_scale, 0.0, True))

    def _smallest_feature(self) -> float:
        sizes = [s.radius for s in self.surfaces if isinstance(s, (Cylinder, Sphere))]
        planes = [s for s in self.surfaces if isinstance(s, Plane)]
        for i, first in enumerate(planes):
            for second in planes[i + 1:]:
                if abs(abs(float(first.normal @ second.normal)) - 1.0) < 1e-12:
                    sizes.append(abs(float((second.point - first.point) @ first.normal)))
        sizes = [size for size in sizes if size > 0]
        return min(sizes) if sizes else 1e-3

    def table(self) -> np.ndarray:
        """The kernel's surface table (one row per surface).

        Examples
        --------
        >>> Geometry().table().shape
        (0, 12)
        """
        if not self.surfaces:
            return np.zeros((0, _c.SURFACE_COLUMNS))
        return np.ascontiguousarray(np.array([surface.row() for surface in self.surfaces]))

    def index(self, name: str) -> int:
        """The index of the surface called ``name`` (ValueError naming the others if none is).

        Examples
        --------
        >>> from collisionkit.transport.tracking import parallel_plate_geometry
        >>> parallel_plate_geometry(1e-3).index("anode")
        1
        """
        names = [surface.name for surface in self.surfaces]
        if name not in names:
            raise ValueError(f"no surface called {name!r}; the surfaces are {names}")
        return names.index(name)

    def contains(self, points) -> np.ndarray:
        """True for the points (n x 3, m) inside the volume (on every surface's inner side).

        Examples
        --------
        >>> from collisionkit.transport.tracking import parallel_plate_geometry
        >>> parallel_plate_geometry(1e-3).contains([[0, 0, 5e-4], [0, 0, 2e-3]]).tolist()
        [True, False]
        """
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        inside = np.ones(points.shape[0], bool)
        for surface in self.surfaces:
            inside &= surface.distance(points) >= 0.0
        return inside


def parallel_plate_geometry(gap: float) -> Geometry:
    """Two absorbing plates: the ``cathode`` z = 0 and the ``anode`` z = ``gap`` (m), unbounded in x and y.

    Examples
    --------
    >>> from collisionkit.transport.tracking import parallel_plate_geometry
    >>> geometry = parallel_plate_geometry(2e-3)
    >>> [s.name for s in geometry.surfaces], geometry.length_scale
    (['cathode', 'anode'], 0.002)
    """
    gap = _finite("gap (m)", gap, 0.0, low_open=True)
    return Geometry((Plane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), name="cathode"),
                     Plane((0.0, 0.0, gap), (0.0, 0.0, -1.0), name="anode")))


def coaxial_geometry(wire_radius: float, cathode_radius: float, axis=(0.0, 0.0)) -> Geometry:
    """An absorbing ``wire`` (radius a) inside an absorbing ``cathode`` cylinder (radius b), about the z axis
    through ``axis`` (x, y), unbounded in z.

    Examples
    --------
    >>> from collisionkit.transport.tracking import coaxial_geometry
    >>> coaxial_geometry(25e-6, 0.01).contains([[1e-5, 0, 0], [0.02, 0, 0]]).tolist()
    [False, False]
    """
    a = _finite("wire_radius (m)", wire_radius, 0.0, low_open=True)
    b = _finite("cathode_radius (m)", cathode_radius, 0.0, low_open=True)
    if not b > a:
        raise ValueError(f"cathode_radius must be > wire_radius ({a:g} m); got {b:g}")
    point = (float(axis[0]), float(axis[1]), 0.0)
    return Geometry((Cylinder(a, point, inside=False, name="wire"), Cylinder(b, point, inside=True, name="cathode")))

