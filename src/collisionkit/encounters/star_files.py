"""Star models on disk: the GADGET/SWIFT HDF5 snapshot layout and plain ``.npz``.

HDF5 (``.hdf5``, ``.h5``, ``.hdf``), the layout SPH codes and analysis tools
read (GADGET-2/4, SWIFT, GIZMO, yt, pynbody; V. Springel, GADGET-2 user
guide, sec. 6.1, and SWIFT's "Snapshots" and "Initial Conditions" pages):

* ``/Header`` attributes: ``NumPart_ThisFile``, ``NumPart_Total``,
  ``NumPart_Total_HighWord`` (six entries, gas first, the others 0),
  ``MassTable`` (six zeros: the masses are in ``Masses``), ``Time`` = 0,
  ``Redshift`` = 0, ``BoxSize``, ``NumFilesPerSnapshot`` = 1,
  ``Flag_Entropy_ICs`` = 0 (``InternalEnergy`` holds u, not entropy),
  ``Dimension`` = 3, the other ``Flag_*``, ``Omega0``, ``OmegaLambda``,
  ``HubbleParam`` (a non-cosmological run), and ``UnitSystem`` (the name of
  the unit system, read back by collisionkit);
* ``/Units`` attributes as SWIFT writes them: ``Unit mass in cgs (U_M)``,
  ``Unit length in cgs (U_L)``, ``Unit time in cgs (U_t)``, ``Unit current
  in cgs (U_I)`` = 1, ``Unit temperature in cgs (U_T)`` = 1, and GADGET's
  names of the same units, ``UnitMass_in_g``, ``UnitLength_in_cm``,
  ``UnitVelocity_in_cm_per_s``. N-body units (G = 1) have no size in cgs:
  their files have no ``/Units`` group (SWIFT then takes its internal
  units) and ``UnitSystem = "nbody"``;
* ``/PartType0`` datasets: ``Coordinates`` and ``Velocities`` (N, 3),
  ``Masses``, ``SmoothingLength``, ``InternalEnergy`` (float64),
  ``ParticleIDs`` (uint64) and, for placed stars, ``StarID`` (int32: 1, 2).

Coordinates are in the centre-of-mass frame, centred on the origin;
``BoxSize`` is the side of the smallest origin-centred cube that holds every
particle with its smoothing length. A code that wants positions in
``[0, BoxSize)`` shifts them by ``BoxSize / 2`` (SWIFT:
``InitialConditions: shift``).

Reading takes the same layout, SWIFT's plural names (``SmoothingLengths``,
``InternalEnergies``), a ``MassTable`` mass instead of ``Masses``, and the
units from ``/Units`` (SWIFT's or GADGET's names), ``/Header`` or
``/Parameters`` (GADGET's names), else ``default_units``. Multi-file
snapshots, particle types other than gas and entropy in place of the
internal energy are refused with a one-line :class:`StarFileError`.

``.npz`` holds the same datasets under the same names (``Coordinates`` ...),
plus ``UnitSystem`` (its name) and ``Units_cgs`` (the mass, length and time
units in g, cm and s; NaN for N-body units).

h5py (the ``stars`` extra) is imported only when an HDF5 file is read or
written; without it :func:`require_h5py` raises an ImportError naming
``pip install 'collisionkit[stars]'``.
"""

from __future__ import annotations

import importlib
import math
import zipfile
from pathlib import Path

import numpy as np

from .._io import atomic_replacement
from .star_model import StarModel
from .units import UnitSystem, unit_system, unit_system_from_cgs

__all__ = ["HDF5_SUFFIXES", "STAR_SUFFIXES", "StarFileError", "read_star", "require_h5py", "write_star"]

HDF5_SUFFIXES = (".hdf5", ".h5", ".hdf")
STAR_SUFFIXES = (*HDF5_SUFFIXES, ".npz")
H5PY_MISSING = "HDF5 star files need h5py, which is not installed: pip install 'collisionkit[stars]'"

# model field -> dataset name (first: the name written; the others are read too)
DATASETS = {
    "positions": ("Coordinates",),
    "velocities": ("Velocities",),
    "masses": ("Masses",),
    "smoothing_lengths": ("SmoothingLength", "SmoothingLengths"),
    "internal_energies": ("InternalEnergy", "InternalEnergies"),
    "ids": ("ParticleIDs",),
    "star_ids": ("StarID",),
}
SWIFT_UNITS = {"mass": "Unit mass in cgs (U_M)", "length": "Unit length in cgs (U_L)", "time": "Unit time in cgs (U_t)"}
SWIFT_OTHER_UNITS = ("Unit current in cgs (U_I)", "Unit temperature in cgs (U_T)")
GADGET_UNITS = {"mass": "UnitMass_in_g", "length": "UnitLength_in_cm", "velocity": "UnitVelocity_in_cm_per_s"}


class StarFileError(ValueError):
    """A star file that cannot be read: not the format, a field missing or wrong, no units.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from collisionkit.encounters import StarFileError, read_star
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "star.npz"
    >>> _ = path.write_text("not a zip file")
    >>> try:
    ...     read_star(path)
    ... except StarFileError as error:
    ...     print(str(error).split(": ", 1)[1])
    not an .npz file (not a zip archive of arrays)
    """


def require_h5py():
    """The h5py module, or an ImportError naming the extra that installs it.

    Examples
    --------
    >>> from collisionkit.encounters.star_files import require_h5py
    >>> require_h5py().__name__
    'h5py'
    """
    try:
        return importlib.import_module("h5py")
    except ImportError:
        raise ImportError(H5PY_MISSING) from None


def _kind(path: Path) -> str:
    suffix = path.suffix.lower()
    if suffix in HDF5_SUFFIXES:
        return "hdf5"
    if suffix == ".npz":
        return "npz"
    raise ValueError(f"a star file must end in {', '.join(STAR_SUFFIXES)}; got {path.name!r}")


def _unit_sizes_cgs(units: UnitSystem) -> tuple[float, float, float]:
    return units.mass_si * 1e3, units.length_si * 1e2, units.time_si


def _box_size(star: StarModel) -> float:
    return float(2.0 * np.max(np.abs(star.positions) + star.smoothing_lengths[:, None]))


def _write_hdf5(star: StarModel, path: Path) -> None:
    h5py = require_h5py()
    count = len(star)
    if count > np.iinfo(np.int32).max:
        raise ValueError(f"an HDF5 star file holds at most {np.iinfo(np.int32).max} particles; got {count}")
    with h5py.File(path, "w") as file:
        header = file.create_group("Header")
        numbers = np.array([count, 0, 0, 0, 0, 0])
        header.attrs["NumPart_ThisFile"] = numbers.astype(np.int32)
        header.attrs["NumPart_Total"] = (numbers & 0xFFFFFFFF).astype(np.uint32)
        header.attrs["NumPart_Total_HighWord"] = (numbers >> 32).astype(np.uint32)
        header.attrs["MassTable"] = np.zeros(6)
        for name, value in (("Time", 0.0), ("Redshift", 0.0), ("BoxSize", _box_size(star)), ("Omega0", 0.0),
                            ("OmegaLambda", 0.0), ("HubbleParam", 1.0)):
            header.attrs[name] = np.float64(value)
        for name, value in (("NumFilesPerSnapshot", 1), ("Flag_Entropy_ICs", 0), ("Dimension", 3), ("Flag_Sfr", 0),
                            ("Flag_Cooling", 0), ("Flag_StellarAge", 0), ("Flag_Metals", 0), ("Flag_Feedback", 0),
                            ("Flag_DoublePrecision", 1)):
            header.attrs[name] = np.int32(value)
        header.attrs["UnitSystem"] = star.units.name
        if all(math.isfinite(size) for size in _unit_sizes_cgs(star.units)):
            mass, length, time = _unit_sizes_cgs(star.units)
            units = file.create_group("Units")
            for name, value in zip(SWIFT_UNITS.values(), (mass, length, time)):
                units.attrs[name] = np.float64(value)
            for name in SWIFT_OTHER_UNITS:
                units.attrs[name] = np.float64(1.0)
            for name, value in zip(GADGET_UNITS.values(), (mass, length, length / time)):
                units.attrs[name] = np.float64(value)
        gas = file.create_group("PartType0")
        for field, array in star.arrays().items():
            dtype = {"ids": np.uint64, "star_ids": np.int32}.get(field, np.float64)
            gas.create_dataset(DATASETS[field][0], data=np.asarray(array, dtype=dtype))


def _write_npz(star: StarModel, stream) -> None:
    arrays = {DATASETS[field][0]: array for field, array in star.arrays().items()}
    np.savez(stream, **arrays, UnitSystem=np.array(star.units.name),
             Units_cgs=np.array(_unit_sizes_cgs(star.units)))


def write_star(star: StarModel, path) -> Path:
    """Write ``star`` to ``path`` (atomically): the HDF5 snapshot layout or ``.npz``, by the file's suffix.

    Parameters
    ----------
    star : StarModel
    path : str or Path
        Ending in ``.hdf5``, ``.h5``, ``.hdf`` (needs h5py) or ``.npz``.

    Returns
    -------
    Path

    Examples
    --------
    >>> import h5py, numpy as np, pathlib, tempfile
    >>> from collisionkit.encounters import StarModel, write_star
    >>> star = StarModel(np.zeros((2, 3)), np.zeros((2, 3)), [1.0, 1.0], [0.5, 0.5], [1.0, 1.0], [1, 2], units="cgs")
    >>> path = write_star(star, pathlib.Path(tempfile.mkdtemp()) / "star.hdf5")
    >>> with h5py.File(path) as file:
    ...     print(file["Header"].attrs["NumPart_Total"], file["Units"].attrs["Unit length in cgs (U_L)"])
    [2 0 0 0 0 0] 1.0
    """
    if not isinstance(star, StarModel):
        raise TypeError(f"star must be a StarModel; got {type(star).__name__}")
    path = Path(path)
    kind = _kind(path)
    if kind == "hdf5":
        require_h5py()
    with atomic_replacement(path) as temporary:
        if kind == "hdf5":
            _write_hdf5(star, temporary)
        else:
            with open(temporary, "wb") as stream:
                _write_npz(star, stream)
    return path


def _scalar(value) -> float:
    return float(np.asarray(value).reshape(-1)[0])


def _units_from_attributes(groups, path: Path) -> UnitSystem | None:
    """The unit system an HDF5 file states: SWIFT's /Units, else GADGET's names in /Units, /Header or /Parameters."""
    units = groups.get("Units")
    if units is not None and all(name in units for name in SWIFT_UNITS.values()):
        return unit_system_from_cgs(*(_scalar(units[name]) for name in SWIFT_UNITS.values()))
    for group in (groups.get("Units"), groups.get("Header"), groups.get("Parameters")):
        if group is not None and all(name in group for name in GADGET_UNITS.values()):
            mass, length, velocity = (_scalar(group[name]) for name in GADGET_UNITS.values())
            return unit_system_from_cgs(mass, length, length / velocity)
    stated = groups.get("Header", {}).get("UnitSystem")
    if stated is not None:
        name = stated.decode() if isinstance(stated, bytes) else str(stated)
        if name != "nbody":
            raise StarFileError(f"{path}: the header names the unit system {name!r} but the file has no /Units")
        return unit_system("nbody")
    return None


def _read_hdf5(path: Path) -> tuple[dict, UnitSystem | None]:
    h5py = require_h5py()
    try:
        file = h5py.File(path, "r")
    except OSError as failure:
        raise StarFileError(f"{path}: not an HDF5 file ({' '.join(str(failure).split())})") from None
    with file:
        header = dict(file["Header"].attrs) if isinstance(file.get("Header"), h5py.Group) else {}
        if int(_scalar(header.get("NumFilesPerSnapshot", 1))) > 1:
            raise StarFileError(f"{path}: one file of a snapshot in {int(_scalar(header['NumFilesPerSnapshot']))} "
                                "files; join them into one file first")
        if int(_scalar(header.get("Flag_Entropy_ICs", 0))) != 0:
            raise StarFileError(f"{path}: Flag_Entropy_ICs is set (the InternalEnergy field holds entropies); "
                                "give the internal energy per unit mass")
        others = [(kind, int(count)) for kind, count in enumerate(np.ravel(header.get("NumPart_ThisFile", [])))
                  if kind > 0 and count > 0]
        if others:
            kind, count = others[0]
            raise StarFileError(f"{path}: {count} particles of type {kind}; a star model holds gas (PartType0) only")
        gas = file.get("PartType0")
        if not isinstance(gas, h5py.Group):
            raise StarFileError(f"{path}: no PartType0 group (the gas particles)")
        fields = {}
        for field, names in DATASETS.items():
            found = next((name for name in names if isinstance(gas.get(name), h5py.Dataset)), None)
            if found is not None:
                fields[field] = gas[found][()]
        if "masses" not in fields and "MassTable" in header and float(np.ravel(header["MassTable"])[0]) > 0:
            fields["masses"] = np.full(len(fields.get("ids", [])), float(np.ravel(header["MassTable"])[0]))
        groups = {name: dict(file[name].attrs) for name in ("Units", "Header", "Parameters")
                  if isinstance(file.get(name), h5py.Group)}
        return fields, _units_from_attributes(groups, path)


def _read_npz(path: Path) -> tuple[dict, UnitSystem | None]:
    if not zipfile.is_zipfile(path):
        raise StarFileError(f"{path}: not an .npz file (not a zip archive of arrays)")
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {name: data[name] for name in data.files}
    except (zipfile.BadZipFile, ValueError, EOFError, OSError) as failure:
        raise StarFileError(f"{path}: not an .npz file ({' '.join(str(failure).split())})") from None
    fields = {}
    for field, names in DATASETS.items():
        found = next((name for name in names if name in arrays), None)
        if found is not None:
            fields[field] = arrays[found]
    units = None
    if "UnitSystem" in arrays:
        name = str(arrays["UnitSystem"])
        if name == "nbody":
            units = unit_system("nbody")
        elif "Units_cgs" in arrays and np.shape(arrays["Units_cgs"]) == (3,):
            units = unit_system_from_cgs(*map(float, arrays["Units_cgs"]))
        else:
            raise StarFileError(f"{path}: UnitSystem {name!r} without Units_cgs (the sizes of its units)")
    return fields, units


def read_star(path, default_units: UnitSystem | str | None = None) -> StarModel:
    """Read a star model from an HDF5 snapshot or an ``.npz`` file (see the module's description).

    Parameters
    ----------
    path : str or Path
    default_units : UnitSystem or str, optional
        The units of a file that states none (a GADGET snapshot without
        unit attributes: its units are in the code's parameter file). A
        file that states its units is read in them.

    Returns
    -------
    StarModel

    Raises
    ------
    StarFileError
        A file that is not of the format, lacks a field or its units.
    ImportError
        An HDF5 file without h5py installed.

    Examples
    --------
    >>> import numpy as np, pathlib, tempfile
    >>> from collisionkit.encounters import StarModel, read_star, write_star
    >>> star = StarModel(np.eye(3), np.zeros((3, 3)), np.ones(3), np.ones(3), np.ones(3), [3, 4, 5], units="solar")
    >>> path = write_star(star, pathlib.Path(tempfile.mkdtemp()) / "star.hdf5")
    >>> again = read_star(path)
    >>> again.units.name, again.ids.tolist(), bool(np.array_equal(again.positions, star.positions))
    ('solar', [3, 4, 5], True)
    """
    path = Path(path)
    kind = _kind(path)
    if not path.is_file():
        raise FileNotFoundError(f"star file not found: {path}")
    fields, units = _read_hdf5(path) if kind == "hdf5" else _read_npz(path)
    missing = [DATASETS[field][0] for field in DATASETS if field != "star_ids" and field not in fields]
    if missing:
        raise StarFileError(f"{path}: no {', '.join(missing)} for the gas particles")
    if units is None:
        if default_units is None:
            raise StarFileError(f"{path}: the file does not state its units; say which (default_units, or --units "
                                "on the command line)")
        units = unit_system(default_units) if isinstance(default_units, str) else default_units
    try:
        return StarModel(**fields, units=units)
    except (ValueError, TypeError) as failure:
        raise StarFileError(f"{path}: {failure}") from None
