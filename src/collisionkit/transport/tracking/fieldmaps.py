"""Field maps: E or B on a regular 2D or 3D grid, read from .npz, .npy or CSV files, interpolated linearly.

A 3D map holds the three components on a grid of x, y, z; a 2D map holds
them on a grid of x, y (the field the same at every z, as for a long
electrode structure). Between grid points the field is interpolated
trilinearly (bilinearly in 2D); a particle that leaves the map's box ends
there (``outside-field``).

File formats (SI by default; the units are always checked):

* ``.npz`` with the axis arrays ``x``, ``y`` (and ``z`` for 3D), regular and
  increasing, and the field ``E`` (or ``B``) of shape (nx, ny[, nz], 3)
  (2 components are allowed in 2D: the z component is then 0); optional
  strings ``length_unit`` and ``field_unit``;
* ``.npy``: the field array alone, with ``origin`` and ``spacing`` given to
  :func:`read_field_map`;
* CSV: a header naming the columns ``x, y[, z], Ex, Ey[, Ez]`` (or ``Bx``...),
  each with its unit in brackets (``x [mm]``, ``Ex [kV/cm]``), then one row
  per grid point in any order (the grid must be complete).
"""

from __future__ import annotations

import csv
import math
import re
from pathlib import Path

import numpy as np

from ..._kernels.transport.tracking import codes as _c
from ..._kernels.transport.tracking.fields import no_field
from .fields import Field

__all__ = ["FieldMap", "read_field_map", "LENGTH_UNITS", "ELECTRIC_UNITS", "MAGNETIC_UNITS"]

LENGTH_UNITS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "µm": 1e-6}
ELECTRIC_UNITS = {"V/m": 1.0, "V/cm": 1e2, "kV/cm": 1e5, "V/mm": 1e3, "kV/mm": 1e6, "MV/m": 1e6, "kV/m": 1e3}
MAGNETIC_UNITS = {"T": 1.0, "mT": 1e-3, "G": 1e-4, "kG": 0.1}
RELATIVE_SPACING_TOLERANCE = 1e-6  # a grid axis is regular if every spacing is within this of the mean


def _shifted(array: np.ndarray, axis: int, step: int) -> np.ndarray:
    """``array`` moved by ``step`` along ``axis``, its edge repeated (the neighbour of an edge block is itself)."""
    index = np.clip(np.arange(array.shape[axis]) - step, 0, array.shape[axis] - 1)
    return np.take(array, index, axis=axis)


class FieldMap(Field):
    """A field on a regular grid.

    Parameters
    ----------
    origin : 2 or 3 numbers
        The first grid point (m): (x0, y0) for a 2D map, (x0, y0, z0) for 3D.
    spacing : 2 or 3 numbers
        Grid spacings (m, > 0).
    values : array
        The field at the grid points, shape (nx, ny, 3) (2D) or (nx, ny, nz, 3)
        (3D), at least 2 points per axis; V/m (electric) or T (magnetic).
    magnetic : bool
        True for a magnetic field.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.transport.tracking import FieldMap
    >>> x, y = np.meshgrid(np.arange(3) * 1e-3, np.arange(4) * 1e-3, indexing="ij")
    >>> values = np.stack([1e6 * x, 1e6 * y, 0 * x], axis=-1)  # a linear field: interpolated exactly
    >>> FieldMap((0, 0), (1e-3, 1e-3), values).at([[1.5e-3, 2.25e-3, 7.0]]).round(9).tolist()
    [[1500.0, 2250.0, 0.0]]
    """

    def __init__(self, origin, spacing, values, magnetic: bool = False):
        values = np.asarray(values, dtype=float)
        if values.ndim not in (3, 4) or values.shape[-1] != 3:
            raise ValueError("values must have shape (nx, ny, 3) for a 2D map or (nx, ny, nz, 3) for a 3D map; "
                             f"got {values.shape}")
        dims = values.ndim - 1
        origin = np.asarray(origin, dtype=float).reshape(-1)
        spacing = np.asarray(spacing, dtype=float).reshape(-1)
        if origin.shape != (dims,) or spacing.shape != (dims,):
            raise ValueError(f"a {dims}D map needs {dims} origin and {dims} spacing values; got {origin.size} and "
                             f"{spacing.size}")
        if not (np.all(np.isfinite(origin)) and np.all(np.isfinite(spacing)) and np.all(spacing > 0)):
            raise ValueError(f"origin must be finite and spacing finite and > 0 (m); got {origin}, {spacing}")
        if min(values.shape[:-1]) < 2:
            raise ValueError(f"a map needs at least 2 grid points along each axis; got {values.shape[:-1]}")
        if not np.all(np.isfinite(values)):
            raise ValueError("the map's field values must be finite (NaN or inf found)")
        self.dimensions = dims
        self.origin = origin
        self.spacing = spacing
        self.values = np.ascontiguousarray(values if dims == 3 else values[:, :, None, :])
        self.magnetic = bool(magnetic)
        self.kind = _c.B_MAP if self.magnetic else _c.E_MAP

    def __repr__(self):
        return (f"FieldMap({self.dimensions}D, shape={self.shape}, origin={self.origin.tolist()}, "
                f"spacing={self.spacing.tolist()}, magnetic={self.magnetic})")

    @property
    def shape(self) -> tuple[int, ...]:
        """Grid points per axis."""
        return tuple(self.values.shape[: self.dimensions])

    def meta(self) -> np.ndarray:
        """The kernel's description of the grid (origin, spacing, points, dimensions, largest |value|, levels of
        the local bounds of :meth:`blocks`, inverse spacing).

        Examples
        --------
        >>> import numpy as np
        >>> FieldMap((0, 0), (1.0, 1.0), np.ones((2, 2, 3))).meta()[6:12].tolist()
        [2.0, 2.0, 1.0, 2.0, 1.7320508075688772, 1.0]
        """
        meta = np.zeros(_c.MAP_META)
        meta[: self.dimensions] = self.origin
        meta[3: 3 + self.dimensions] = self.spacing
        if self.dimensions == 2:
            meta[5] = 1.0
        meta[6:9] = self.values.shape[:3]
        meta[9] = self.dimensions
        meta[10] = float(np.sqrt((self.values**2).sum(axis=-1)).max())
        meta[11] = len(self._levels())
        meta[12:15] = 1.0 / meta[3:6]
        return meta

    def _levels(self) -> list[np.ndarray]:
        """The local bounds, level by level: at level L, per block of 2^L cells along each axis, the largest
        |value| over the corners of the block's cells and of its neighbouring blocks (bilinear and trilinear
        interpolation never exceed the largest |value| of a cell's corners). Levels go on until one block
        covers the grid."""
        magnitude = np.sqrt((self.values**2).sum(axis=-1))
        cells = magnitude
        for axis in range(3):  # each cell's largest corner (an axis of one point is its own neighbour)
            if cells.shape[axis] > 1:
                cells = np.maximum(np.take(cells, range(cells.shape[axis] - 1), axis=axis),
                                   np.take(cells, range(1, cells.shape[axis]), axis=axis))
        levels = []
        while True:
            dilated = cells
            for axis in range(3):
                if cells.shape[axis] > 1:
                    dilated = np.maximum(dilated, np.maximum(_shifted(dilated, axis, 1), _shifted(dilated, axis, -1)))
            levels.append(np.ascontiguousarray(dilated))
            if max(cells.shape) == 1:
                return levels
            padded = np.pad(cells, [(0, n % 2) for n in cells.shape], mode="edge")  # whole pairs of blocks
            cells = padded.reshape(-1, 2 if padded.shape[0] > 1 else 1, padded.shape[1] // 2 or 1,
                                   2 if padded.shape[1] > 1 else 1, padded.shape[2] // 2 or 1,
                                   2 if padded.shape[2] > 1 else 1).max(axis=(1, 3, 5))

    def blocks(self) -> np.ndarray:
        """The null-collision method's local bounds of |field| (see :func:`collisionkit._kernels.transport.
        tracking.fields.electric_bound`), all levels in one array: the levels' offsets first, then level by level
        the bounds per block (2^L cells along each axis at level L, blocks in C order).

        Examples
        --------
        >>> import numpy as np
        >>> values = np.zeros((20, 3, 3)); values[19, 0] = (3.0, 4.0, 0.0)  # one large value at the far end
        >>> blocks = FieldMap((0, 0), (1.0, 1.0), values).blocks()
        >>> levels = FieldMap((0, 0), (1.0, 1.0), values)._levels()
        >>> [level.shape for level in levels], levels[2][:, 0, 0].tolist()  # blocks of 4 cells: 0-4, ..., 16-19
        ([(19, 2, 1), (10, 1, 1), (5, 1, 1), (3, 1, 1), (2, 1, 1), (1, 1, 1)], [0.0, 0.0, 0.0, 5.0, 5.0])
        >>> blocks[:6].tolist(), blocks.size  # the offsets of the levels, then 38 + 10 + 5 + 3 + 2 + 1 bounds
        ([6.0, 44.0, 54.0, 59.0, 62.0, 64.0], 65)
        """
        levels = self._levels()
        offsets = len(levels) + np.cumsum([0] + [level.size for level in levels[:-1]])
        return np.concatenate([offsets.astype(float)] + [level.ravel() for level in levels])

    def arrays(self):
        """The kernel's arguments (see :meth:`Field.arrays`).

        Examples
        --------
        >>> import numpy as np
        >>> FieldMap((0, 0), (1.0, 1.0), np.ones((2, 2, 3))).arrays()[3].shape
        (2, 2, 1, 3)
        """
        return self.kind, np.zeros(_c.FIELD_PARAMETERS), self.meta(), self.values, no_field()

    def bound(self):
        """The largest |value| on the grid (see :meth:`Field.bound`).

        Examples
        --------
        >>> import numpy as np
        >>> round(FieldMap((0, 0), (1.0, 1.0), np.full((2, 2, 3), 2.0)).bound() ** 2, 12)
        12.0
        """
        return float(self.meta()[10])

    def contains(self, points) -> np.ndarray:
        """True for the points (n x 3, m) inside the map's box (a 2D map: any z).

        Examples
        --------
        >>> import numpy as np
        >>> FieldMap((0, 0), (1.0, 1.0), np.ones((2, 2, 3))).contains([[0.5, 0.5, 9.0], [2.0, 0.0, 0.0]]).tolist()
        [True, False]
        """
        points = np.asarray(points, dtype=float).reshape(-1, 3)[:, : self.dimensions]
        top = self.origin + (np.array(self.shape) - 1) * self.spacing
        return np.all((points >= self.origin) & (points <= top), axis=1)


def _unit(name: str, unit: str, table: dict, what: str) -> float:
    if unit not in table:
        raise ValueError(f"{name}: unknown {what} unit {unit!r}; use one of {', '.join(table)}")
    return table[unit]


def _field_scale(unit: str, magnetic: bool, where: str) -> float:
    table = MAGNETIC_UNITS if magnetic else ELECTRIC_UNITS
    if unit in (ELECTRIC_UNITS if magnetic else MAGNETIC_UNITS):
        kind = "electric" if magnetic else "magnetic"
        raise ValueError(f"{where}: the field unit {unit!r} is {kind}, but a "
                         f"{'magnetic' if magnetic else 'electric'} map was asked for")
    return _unit(where, unit, table, "field")


def _regular_axis(values: np.ndarray, name: str, where: str) -> tuple[float, float]:
    values = np.asarray(values, dtype=float).reshape(-1)
    if values.size < 2:
        raise ValueError(f"{where}: the {name} axis needs at least 2 grid points; got {values.size}")
    steps = np.diff(values)
    if not np.all(np.isfinite(values)) or np.any(steps <= 0):
        raise ValueError(f"{where}: the {name} axis must be finite and strictly increasing")
    mean = steps.mean()
    if np.max(np.abs(steps - mean)) > RELATIVE_SPACING_TOLERANCE * mean:
        raise ValueError(f"{where}: the {name} axis is not regular (spacings from {steps.min():g} to "
                         f"{steps.max():g}); a field map needs a regular grid")
    return float(values[0]), float(mean)


def read_field_map(path, *, magnetic: bool = False, length_unit: str | None = None, field_unit: str | None = None,
                   origin=None, spacing=None) -> FieldMap:
    """Read a field map from a ``.npz``, ``.npy`` or ``.csv`` file (see the module docstring for the layouts).

    Parameters
    ----------
    path : path
        The file.
    magnetic : bool
        Read a magnetic field (B, T) instead of an electric one (E, V/m).
    length_unit, field_unit : str, optional
        Units of the grid and of the field (:data:`LENGTH_UNITS`,
        :data:`ELECTRIC_UNITS`, :data:`MAGNETIC_UNITS`). A .npz or CSV file
        that names its units must agree with them; without units anywhere
        the grid is in m and the field in V/m or T.
    origin, spacing : sequence, optional
        The grid of a .npy file (in ``length_unit``).

    Raises
    ------
    ValueError
        If the file is missing, of another kind, or its grid, shape or
        units are wrong (the message names the file and the problem).

    Examples
    --------
    >>> import numpy as np, pathlib, tempfile
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "plates.npz"
    >>> x = y = np.linspace(0.0, 10.0, 11)
    >>> field = np.zeros((11, 11, 2)); field[..., 1] = -2.0
    >>> np.savez(path, x=x, y=y, E=field, length_unit="mm", field_unit="kV/cm")
    >>> fieldmap = read_field_map(path)
    >>> fieldmap.shape, fieldmap.at([[5e-3, 5e-3, 0.0]]).tolist()
    ((11, 11), [[0.0, -200000.0, 0.0]])
    """
    path = Path(path)
    where = str(path)
    if path.is_dir():
        raise ValueError(f"{where} is a folder; give a field map file (.npz, .npy or .csv)")
    if not path.is_file():
        raise ValueError(f"field map not found: {where}")
    suffix = path.suffix.lower()
    if suffix == ".npz":
        axes, values, units = _read_npz(path, magnetic)
    elif suffix == ".npy":
        axes, values, units = _read_npy(path, origin, spacing)
    elif suffix == ".csv":
        axes, values, units = _read_csv(path, magnetic)
    else:
        raise ValueError(f"{where}: a field map must be a .npz, .npy or .csv file")
    length_unit = _agreed(where, "length_unit", units[0], length_unit) or "m"
    field_unit = _agreed(where, "field_unit", units[1], field_unit) or ("T" if magnetic else "V/m")
    length_scale = _unit(where, length_unit, LENGTH_UNITS, "length")
    field_scale = _field_scale(field_unit, magnetic, where)
    if values.shape[-1] == 2:
        if values.ndim != 3:
            raise ValueError(f"{where}: only a 2D map may give 2 field components; got shape {values.shape}")
        values = np.concatenate([values, np.zeros(values.shape[:-1] + (1,))], axis=-1)
    if values.ndim - 1 != len(axes) or values.shape[-1] != 3:
        raise ValueError(f"{where}: the field has shape {values.shape}, but the grid has {len(axes)} axes "
                         f"(expected ({', '.join(str(len(a)) for a in axes)}, 3))")
    for name, axis, n in zip("xyz", axes, values.shape):
        if len(axis) != n:
            raise ValueError(f"{where}: the {name} axis has {len(axis)} points but the field {n} along it")
    grid = [_regular_axis(axis, name, where) for name, axis in zip("xyz", axes)]
    try:
        return FieldMap([g[0] * length_scale for g in grid], [g[1] * length_scale for g in grid],
                        values * field_scale, magnetic=magnetic)
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None


def _agreed(where, name, in_file, given):
    if in_file is not None and given is not None and in_file != given:
        raise ValueError(f"{where} gives {name} {in_file!r}, but {given!r} was asked for")
    return in_file if in_file is not None else given


def _read_npz(path, magnetic):
    key = "B" if magnetic else "E"
    try:
        with np.load(path, allow_pickle=False) as data:
            contents = {name: data[name] for name in data.files}
    except (OSError, ValueError) as error:
        raise ValueError(f"{path} cannot be read as a .npz file: {error}") from None
    if key not in contents:
        other = "E" if magnetic else "B"
        hint = f" (it holds {other}: pass magnetic={not magnetic})" if other in contents else ""
        raise ValueError(f"{path} has no array {key!r}{hint}; it holds {sorted(contents)}")
    axes = [contents[name] for name in "xyz" if name in contents]
    if len(axes) < 2 or "x" not in contents or "y" not in contents:
        raise ValueError(f"{path} needs the grid axes x and y (and z for a 3D map)")
    units = tuple(str(contents[name]) if name in contents else None for name in ("length_unit", "field_unit"))
    return axes, np.asarray(contents[key], dtype=float), units


def _read_npy(path, origin, spacing):
    try:
        values = np.load(path, allow_pickle=False)
    except (OSError, ValueError) as error:
        raise ValueError(f"{path} cannot be read as a .npy file: {error}") from None
    if origin is None or spacing is None:
        raise ValueError(f"{path}: a .npy map holds only the field; give origin and spacing of its grid")
    values = np.asarray(values, dtype=float)
    origin = np.asarray(origin, dtype=float).reshape(-1)
    spacing = np.asarray(spacing, dtype=float).reshape(-1)
    dims = values.ndim - 1
    if origin.size != dims or spacing.size != dims:
        raise ValueError(f"{path}: a field of shape {values.shape} needs {dims} origin and spacing values; got "
                         f"{origin.size} and {spacing.size}")
    axes = [o + s * np.arange(n) for o, s, n in zip(origin, spacing, values.shape)]
    return axes, values, (None, None)


_HEADER = re.compile(r"^\s*([A-Za-z]+)\s*(?:\[\s*([^\]]+?)\s*\])?\s*$")


def _read_csv(path, magnetic):
    letter = "B" if magnetic else "E"
    try:
        with open(path, newline="", encoding="utf-8") as stream:
            rows = [row for row in csv.reader(stream) if row and not row[0].lstrip().startswith("#")]
    except (OSError, UnicodeDecodeError) as error:
        raise ValueError(f"{path} cannot be read as CSV text: {error}") from None
    if len(rows) < 2:
        raise ValueError(f"{path}: a CSV field map needs a header and rows of values")
    names, units = [], []
    for cell in rows[0]:
        match = _HEADER.match(cell)
        if match is None:
            raise ValueError(f"{path}: header cell {cell!r} is not a column name with an optional [unit]")
        names.append(match.group(1))
        units.append(match.group(2))
    dims = 3 if "z" in names else 2
    expected = ["x", "y", "z"][:dims] + [f"{letter}{c}" for c in "xyz"[:dims]]
    if dims == 2 and f"{letter}z" in names:
        expected.append(f"{letter}z")
    if sorted(names) != sorted(expected):
        raise ValueError(f"{path}: the header must name the columns {', '.join(expected)}; got {', '.join(names)}")
    length_units = {units[names.index(name)] for name in "xyz"[:dims]}
    field_units = {units[names.index(name)] for name in names if name.startswith(letter)}
    if len(length_units) != 1 or len(field_units) != 1:
        raise ValueError(f"{path}: every coordinate column needs the same unit, and every field column too")
    try:
        table = np.array([[float(cell) for cell in row] for row in rows[1:]])
    except ValueError as error:
        raise ValueError(f"{path}: a value is not a number ({error})") from None
    if table.ndim != 2 or table.shape[1] != len(names):
        raise ValueError(f"{path}: every row needs {len(names)} values")
    coordinates = np.column_stack([table[:, names.index(name)] for name in "xyz"[:dims]])
    components = [f"{letter}{c}" for c in "xyz"] if f"{letter}z" in names else [f"{letter}{c}" for c in "xy"]
    field_columns = np.column_stack([table[:, names.index(name)] for name in components])
    axes = [np.unique(coordinates[:, d]) for d in range(dims)]
    shape = tuple(len(axis) for axis in axes)
    if math.prod(shape) != table.shape[0]:
        raise ValueError(f"{path}: {table.shape[0]} rows do not fill a grid of {' x '.join(map(str, shape))} points "
                         "(a point is missing or repeated)")
    index = tuple(np.searchsorted(axis, coordinates[:, d]) for d, axis in enumerate(axes))
    values = np.full(shape + (field_columns.shape[1],), np.nan)
    values[index] = field_columns
    if np.isnan(values).any():
        raise ValueError(f"{path}: a grid point is repeated and another missing")
    return axes, values, (length_units.pop(), field_units.pop())
