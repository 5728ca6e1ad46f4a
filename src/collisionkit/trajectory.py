"""Trajectory files of hard-sphere systems: GSD (HOOMD schema) and extended XYZ.

GSD is the binary format that HOOMD-blue writes and OVITO, freud, MDAnalysis
and VMD read; writing it needs the optional ``gsd`` package
(``pip install 'collisionkit[io]'``). Frames follow the HOOMD conventions:
the box is centred on the origin (positions are shifted by -L/2), 2D frames
have ``dimensions = 2``, ``Lz = 0`` and z = 0, ``particles/image`` counts the
periodic crossings (``position + image * L`` unwraps the path, as freud's MSD
and OVITO's unwrap modifier expect), and floats are stored in single
precision as the HOOMD schema specifies (a checkpoint, not a trajectory, is
the exact state).

Extended XYZ is the text format of ASE (``ase.io.read``) and OVITO; it needs
nothing beyond numpy and is written atomically.

Both writers take any object with the attributes of
:class:`collisionkit.edmd.HardSphereSystem`: ``dim``, ``count``, ``box``,
``radius``, ``mass``, ``species``, ``periodic``, ``positions()``,
``velocities()`` (and ``image`` for GSD, ``elapsed`` and ``collisions`` for
XYZ).
"""

from __future__ import annotations

import contextlib
import stat
import string
from pathlib import Path

import numpy as np

from ._io import atomic_replacement, atomic_write_text, exclusive

__all__ = [
    "GSDWriter",
    "read_gsd",
    "read_gsd_frames",
    "truncate_gsd",
    "type_names",
    "write_extended_xyz",
    "write_gsd_frame",
]

# species X: ASE reads the species column as chemical symbols and X (its dummy atom) is the one for a
# particle that is no element; the particle type ("A", "B", ... as in GSD files) has a column of its own
_XYZ_PROPERTIES = "species:S:1:pos:R:3:vel:R:3:momenta:R:3:radius:R:1:masses:R:1:type:S:1"
# rough spheres add their angular velocities before the type (discs: about z)
_XYZ_ROUGH_PROPERTIES = _XYZ_PROPERTIES.replace(":type:S:1", ":omega:R:3:type:S:1")
_XYZ_SPECIES = "X"


def _gsd_hoomd():
    try:
        import gsd.hoomd
    except ImportError:
        raise ImportError(
            "writing or reading GSD files needs the 'gsd' package: pip install 'collisionkit[io]' (or pip install gsd)"
        ) from None
    return gsd.hoomd


@contextlib.contextmanager
def _readable(path):
    """Turn gsd's errors for a damaged file (RuntimeError "Corrupt GSD file: ...") into a ValueError naming ``path``."""
    try:
        yield
    except RuntimeError as error:
        reason = " ".join(str(error).split()).removesuffix(f": {path}") or type(error).__name__
        raise ValueError(f"{path} is damaged or is not a GSD trajectory (gsd: {reason})") from None


def _open_gsd(path, mode):
    """``gsd.hoomd.open`` of an existing file (ValueError naming it if it is damaged)."""
    hoomd = _gsd_hoomd()
    with _readable(path):
        return hoomd.open(str(path), mode)


def type_names(species):
    """Names of the particle types: "A", "B", ... for species 0, 1, ... (then "T26", "T27", ...).

    Parameters
    ----------
    species : array_like of int
        Species index per particle, >= 0.

    Returns
    -------
    list of str
        One name per species index from 0 to ``max(species)``.

    Examples
    --------
    >>> from collisionkit.trajectory import type_names
    >>> type_names([0, 2, 1, 0])
    ['A', 'B', 'C']
    """
    species = np.asarray(species)
    if species.dtype.kind not in "iu" and not (species.dtype.kind == "f" and np.all(species % 1 == 0)):
        raise TypeError(f"species must hold integers (the species indices); got dtype {species.dtype}")
    if species.size == 0 or np.any(species < 0):
        raise ValueError("species must be a non-empty array of integers >= 0")
    letters = string.ascii_uppercase
    return [letters[i] if i < len(letters) else f"T{i}" for i in range(int(species.max()) + 1)]


def _centred_positions_and_images(system):
    """Positions in the HOOMD box [-L/2, L/2) (3 columns, single precision) and image counters.

    ``position + image * L`` is the unwrapped trajectory (HOOMD's
    convention, which freud and OVITO use to unwrap), shifted by -L/2 like
    the positions.
    """
    dim = system.dim
    box = np.asarray(system.box[:dim], dtype=float)
    centred = (system.positions() - box / 2.0).astype(np.float32)
    half = (box / 2.0).astype(np.float32)
    rounded_up = centred >= half  # round-off at +L/2: the particle's next image
    centred = np.where(rounded_up, centred - box.astype(np.float32), centred)
    image = np.asarray(system.image, dtype=np.int64) + rounded_up
    if np.any(np.abs(image) > np.iinfo(np.int32).max):
        raise OverflowError("an image counter does not fit GSD's int32 (a particle crossed the box 2^31 times)")
    return _pad(centred), _pad(image, np.int32)


def _pad(array, dtype=np.float32):
    """(N, 2) or (N, 3) values as (N, 3) of ``dtype``, with z = 0 for 2D."""
    array = np.asarray(array, dtype=dtype)
    if array.shape[1] == 3:
        return array
    return np.column_stack([array, np.zeros(array.shape[0], dtype=dtype)])


def _gsd_frame(system, step):
    frame = _gsd_hoomd().Frame()
    dim = system.dim
    box = [float(length) for length in system.box[:dim]] + ([0.0] if dim == 2 else [])
    frame.configuration.step = int(step)
    frame.configuration.dimensions = dim
    frame.configuration.box = np.array(box + [0.0, 0.0, 0.0], dtype=np.float32)
    frame.particles.N = system.count
    frame.particles.types = type_names(system.species)
    frame.particles.typeid = np.asarray(system.species, dtype=np.uint32)
    frame.particles.position, frame.particles.image = _centred_positions_and_images(system)
    frame.particles.velocity = _pad(system.velocities())
    frame.particles.diameter = (2.0 * np.asarray(system.radius)).astype(np.float32)
    frame.particles.mass = np.asarray(system.mass, dtype=np.float32)
    if getattr(system, "rough", False):
        frame.particles.moment_inertia, frame.particles.angmom = _gsd_rotation(system)
    return frame


def _spins(system):
    """The angular velocities of a rough system as (N, 3) (discs: about z)."""
    omega = system.angular_velocities()
    return omega if system.dim == 3 else np.column_stack([np.zeros((omega.size, 2)), omega])


def _gsd_rotation(system):
    """HOOMD-blue's moment_inertia and angmom of rough spheres, at the orientation the frame leaves (the identity:
    the engine does not follow orientations).

    HOOMD-blue keeps the conjugate quaternion momentum p, with the body angular momentum (1/2) conj(q) p: at q = 1,
    p = (0, 2 I omega). Discs turn about z only (moment of inertia (0, 0, I)).
    """
    moments = np.asarray(system.moments_of_inertia(), dtype=float)
    principal = np.column_stack([moments] * 3) if system.dim == 3 else np.column_stack(
        [np.zeros((moments.size, 2)), moments])
    angmom = np.column_stack([np.zeros(moments.size), 2.0 * principal * _spins(system)])
    return principal.astype(np.float32), angmom.astype(np.float32)


class GSDWriter:
    """A GSD trajectory open for writing: append one frame per call, then close.

    Each frame is flushed to disk as it is written, so a run killed later
    keeps every frame written before. While it is open, the file is locked
    (:func:`collisionkit._io.exclusive`): a writer in another process is
    refused instead of corrupting it.

    Parameters
    ----------
    path : str or Path
        The ``.gsd`` file.
    mode : {"w", "a"}
        "w" creates or overwrites the file; "a" appends to it (creating it
        if needed).

    Raises
    ------
    ValueError
        If the file to append to is damaged or not a GSD file (the message
        names it).
    collisionkit._io.FileLockedError
        If another process is writing the file.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = tempfile.TemporaryDirectory()
    >>> from collisionkit.edmd import random_fluid
    >>> from collisionkit.trajectory import GSDWriter, read_gsd
    >>> system = random_fluid(2, 50, 0.3, seed=1)
    >>> path = pathlib.Path(folder.name) / "run.gsd"
    >>> with GSDWriter(path) as writer:
    ...     writer.write(system, step=0)
    ...     _ = system.run(collisions=100)
    ...     writer.write(system, step=100)
    >>> writer.frames, read_gsd(path)["step"]
    (2, 100)
    """

    def __init__(self, path, mode="w"):
        if mode not in ("w", "a"):
            raise ValueError(f"mode must be 'w' (overwrite) or 'a' (append); got {mode!r}")
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        _gsd_hoomd()  # the missing package first, before any file is locked
        self._lock = contextlib.ExitStack()
        self._lock.enter_context(exclusive(self.path))
        try:
            self._file = _open_gsd(self.path, mode)
            self.frames = len(self._file)
        except BaseException:
            self._lock.close()
            raise

    def write(self, system, step):
        """Append the system's current state as a frame labelled ``step`` (an integer >= 0).

        Examples
        --------
        >>> import pathlib, tempfile
        >>> from collisionkit.edmd import random_fluid
        >>> system = random_fluid(2, 50, 0.3, seed=1)
        >>> writer = GSDWriter(pathlib.Path(tempfile.mkdtemp()) / "run.gsd")
        >>> writer.write(system, step=0)
        >>> writer.frames
        1
        >>> writer.close()
        """
        if self._file is None:
            raise ValueError(f"the GSD writer of {self.path} is closed")
        if not (isinstance(step, (int, np.integer)) and step >= 0):
            raise ValueError(f"step must be an integer >= 0; got {step!r}")
        self._file.append(_gsd_frame(system, step))
        self._file.flush()
        self.frames += 1

    def close(self):
        """Flush and close the file (closing twice is harmless).

        Examples
        --------
        >>> import pathlib, tempfile
        >>> from collisionkit.edmd import random_fluid
        >>> writer = GSDWriter(pathlib.Path(tempfile.mkdtemp()) / "run.gsd")
        >>> writer.write(random_fluid(2, 50, 0.3, seed=1), step=0)
        >>> writer.close()
        >>> writer.close()
        >>> writer.write(random_fluid(2, 50, 0.3, seed=1), step=1)
        Traceback (most recent call last):
        ...
        ValueError: the GSD writer of ... is closed
        """
        if self._file is not None:
            self._file.close()
            self._file = None
        self._lock.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        self.close()


def write_gsd_frame(target, system, step):
    """Append one frame of ``system`` to a GSD file.

    Parameters
    ----------
    target : str, Path, GSDWriter or gsd.hoomd.HOOMDTrajectory
        A path (opened in append mode, created if missing, and closed
        again), or a file already open for writing.
    system : HardSphereSystem
    step : int
        The frame's ``configuration.step`` (collisionkit writes the number
        of pair collisions so far).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = tempfile.TemporaryDirectory()
    >>> from collisionkit.edmd import lattice, HardSphereSystem
    >>> from collisionkit.trajectory import read_gsd, write_gsd_frame
    >>> positions, box = lattice("sc", 3, 0.2)
    >>> system = HardSphereSystem(positions, positions * 0 + 1.0, 0.5, box)
    >>> path = pathlib.Path(folder.name) / "lattice.gsd"
    >>> write_gsd_frame(path, system, step=0)
    >>> read_gsd(path)["positions"].shape
    (27, 3)
    """
    if isinstance(target, GSDWriter):
        target.write(system, step)
    elif hasattr(target, "append") and hasattr(target, "flush"):
        target.append(_gsd_frame(system, step))
        target.flush()
    else:
        with GSDWriter(target, mode="a") as writer:
            writer.write(system, step)


def read_gsd(path, frame=-1):
    """One frame of a GSD file in collisionkit's conventions.

    Parameters
    ----------
    path : str or Path
    frame : int
        Frame index (negative counts from the end; default the last frame).

    Returns
    -------
    dict
        ``step`` (int), ``dim`` (2 or 3), ``box`` (the d box lengths),
        ``positions`` (N, d) shifted back into [0, L), ``velocities`` (N, d),
        ``diameters``, ``masses``, ``typeids`` (N,), ``types`` (list of str)
        and ``frames`` (the number of frames in the file); of rough spheres
        also ``angular_velocities`` ((N, 3), discs (N,): from HOOMD-blue's
        ``angmom`` and ``moment_inertia``, given only when every particle is
        at the identity orientation, as collisionkit writes them).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = tempfile.TemporaryDirectory()
    >>> from collisionkit.edmd import random_fluid
    >>> from collisionkit.trajectory import read_gsd, write_gsd_frame
    >>> path = pathlib.Path(folder.name) / "fluid.gsd"
    >>> write_gsd_frame(path, random_fluid(2, 40, 0.2, seed=3), step=7)
    >>> data = read_gsd(path)
    >>> data["dim"], data["positions"].shape, data["step"], data["types"]
    (2, (40, 2), 7, ['A'])
    """
    with _open_gsd(path, "r") as trajectory, _readable(path):
        count = _frame_count(trajectory, path)
        if not -count <= frame < count:
            raise ValueError(f"frame must lie in [{-count}, {count}) for {path}; got {frame}")
        return _frame_data(trajectory[frame], count)


def read_gsd_frames(path, every=1, max_frames=None):
    """Frames of a GSD file in collisionkit's conventions, thinned and capped (e.g. to animate them).

    Parameters
    ----------
    path : str or Path
    every : int
        Read every ``every``-th frame, starting with the first (>= 1).
    max_frames : int, optional
        Read at most this many frames (the first ones of the thinned sequence).

    Returns
    -------
    list of dict
        One per frame read, as :func:`read_gsd` returns it (``frames`` is the
        number of frames in the file).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from collisionkit.edmd import random_fluid
    >>> from collisionkit.trajectory import GSDWriter, read_gsd_frames
    >>> folder = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(folder.name) / "run.gsd"
    >>> system = random_fluid(2, 30, 0.3, seed=1)
    >>> with GSDWriter(path) as writer:
    ...     for step in range(3):
    ...         _ = system.run(collisions=20)
    ...         writer.write(system, step=20 * step)
    >>> frames = read_gsd_frames(path, every=2)
    >>> [frame["step"] for frame in frames], frames[0]["frames"]
    ([0, 40], 3)
    >>> [frame["step"] for frame in read_gsd_frames(path, max_frames=2)]
    [0, 20]
    """
    if not (isinstance(every, (int, np.integer)) and every >= 1):
        raise ValueError(f"every must be an integer >= 1; got {every!r}")
    if max_frames is not None and not (isinstance(max_frames, (int, np.integer)) and max_frames >= 1):
        raise ValueError(f"max_frames must be an integer >= 1 or None; got {max_frames!r}")
    with _open_gsd(path, "r") as trajectory, _readable(path):
        count = _frame_count(trajectory, path)
        return [_frame_data(trajectory[index], count) for index in range(0, count, every)[:max_frames]]


def _frame_count(trajectory, path):
    count = len(trajectory)
    if count == 0:
        raise ValueError(f"{path} holds no frames")
    return count


def _frame_data(snapshot, count):
    """A GSD snapshot as the dict of :func:`read_gsd` (``count``: frames in its file)."""
    dim = int(snapshot.configuration.dimensions)
    box = np.asarray(snapshot.configuration.box[:dim], dtype=float)
    positions = np.asarray(snapshot.particles.position[:, :dim], dtype=float) + box / 2.0
    return {
        "step": int(snapshot.configuration.step),
        "dim": dim,
        "box": box,
        "positions": positions,
        "velocities": np.asarray(snapshot.particles.velocity[:, :dim], dtype=float),
        "diameters": np.asarray(snapshot.particles.diameter, dtype=float),
        "masses": np.asarray(snapshot.particles.mass, dtype=float),
        "typeids": np.asarray(snapshot.particles.typeid, dtype=np.int64),
        "types": list(snapshot.particles.types),
        "frames": count,
    } | _angular_velocities(snapshot, dim)


def _angular_velocities(snapshot, dim) -> dict:
    """``angular_velocities`` of a frame with moments of inertia (rough spheres: (N, 3); discs: (N,) about z), every
    particle at the identity orientation (:func:`_gsd_rotation`); {} otherwise."""
    inertia = np.asarray(snapshot.particles.moment_inertia, dtype=float)
    orientation = np.asarray(snapshot.particles.orientation, dtype=float)
    if not np.any(inertia) or np.any(orientation != [1.0, 0.0, 0.0, 0.0]):
        return {}  # (turned bodies, from another program: their body-frame momenta are not read here)
    angmom = np.asarray(snapshot.particles.angmom, dtype=float)[:, 1:]
    with np.errstate(divide="ignore", invalid="ignore"):
        omega = np.where(inertia > 0, 0.5 * angmom / np.where(inertia > 0, inertia, 1.0), 0.0)
    return {"angular_velocities": omega if dim == 3 else omega[:, 2]}


def truncate_gsd(path, frames, *, last_step=None):
    """Keep only the first ``frames`` frames of a GSD file (atomically).

    Used when a run resumes from a checkpoint: frames written after the
    checkpoint are dropped and written again as the run continues; the
    frames the checkpoint knows of are never touched (a file that holds no
    more is left as it is).

    Parameters
    ----------
    path : str or Path
        An existing GSD file.
    frames : int
        Frames to keep, >= 0; more than the file holds keeps them all.
    last_step : int, optional
        The step of frame ``frames - 1`` as the checkpoint knows it: then the
        file must hold at least ``frames`` frames and that frame must have
        this step, else it is not the run's trajectory (ValueError, the file
        left as it is).

    Returns
    -------
    int
        Frames in the file afterwards.

    Raises
    ------
    ValueError
        If the file is damaged or not a GSD file, or fails ``last_step``.
    collisionkit._io.FileLockedError
        If another process is writing the file.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = tempfile.TemporaryDirectory()
    >>> from collisionkit.edmd import random_fluid
    >>> from collisionkit.trajectory import GSDWriter, read_gsd, truncate_gsd
    >>> system = random_fluid(3, 64, 0.2, seed=2)
    >>> path = pathlib.Path(folder.name) / "run.gsd"
    >>> with GSDWriter(path) as writer:
    ...     for step in range(3):
    ...         writer.write(system, step)
    >>> truncate_gsd(path, 2), read_gsd(path)["step"]
    (2, 1)
    >>> truncate_gsd(path, 3, last_step=2)
    Traceback (most recent call last):
    ...
    ValueError: ...run.gsd holds 2 frames, fewer than the 3 its checkpoint wrote: it is not that run's trajectory ...
    """
    if not (isinstance(frames, (int, np.integer)) and frames >= 0):
        raise ValueError(f"frames must be an integer >= 0; got {frames!r}")
    hoomd = _gsd_hoomd()
    path = Path(path)
    with exclusive(path), _open_gsd(path, "r") as source:
        with _readable(path):
            held = len(source)
            if last_step is not None and frames > 0:
                step = int(source[frames - 1].configuration.step) if held >= frames else None
                _check_last_step(path, held, frames, step, last_step)
        kept = min(frames, held)
        if kept == held:
            return kept
        with atomic_replacement(path, mode=stat.S_IMODE(path.stat().st_mode)) as temporary:
            with hoomd.open(str(temporary), "w") as copy:
                for index in range(kept):
                    with _readable(path):
                        frame = source[index]
                    copy.append(frame)
    return kept


def _check_last_step(path, held, frames, step, last_step):
    """ValueError unless a trajectory of ``held`` frames has its frame ``frames - 1`` (``step``) at ``last_step``."""
    if held < frames:
        raise ValueError(f"{path} holds {held} frames, fewer than the {frames} its checkpoint wrote: it is not that "
                         "run's trajectory (give the run's own file, or a new --trajectory)")
    if step != last_step:
        raise ValueError(f"{path} has frame {frames - 1} at step {step}, where its checkpoint wrote step {last_step}: "
                         "it is not that run's trajectory (give the run's own file, or a new --trajectory)")


def _xyz_header(system, comment):
    dim = system.dim
    lengths = [float(length) for length in system.box[:dim]]
    if dim == 2:
        lengths.append(float(2.0 * np.max(system.radius)))  # a slab one diameter thick
    lattice = np.diag(lengths).ravel()
    periodic = [bool(flag) for flag in system.periodic[:dim]] + ([False] if dim == 2 else [])
    fields = [
        'Lattice="' + " ".join(f"{value:.17g}" for value in lattice) + '"',
        f"Properties={_XYZ_ROUGH_PROPERTIES if getattr(system, 'rough', False) else _XYZ_PROPERTIES}",
        'pbc="' + " ".join("T" if flag else "F" for flag in periodic) + '"',
        f"Time={float(system.elapsed):.17g}",
        f"Step={int(system.collisions)}",
    ]
    if comment:
        if '"' in comment or "\n" in comment:
            raise ValueError("comment must not contain double quotes or newlines")
        fields.append(f'Comment="{comment}"')
    return " ".join(fields)


def write_extended_xyz(path, system, comment=None):
    """Write the system's current state as one extended-XYZ frame (atomically).

    The header line holds ``Lattice`` (the box as 3 cell vectors),
    ``Properties=species:S:1:pos:R:3:vel:R:3:momenta:R:3:radius:R:1:masses:R:1:type:S:1``,
    ``pbc`` (periodic axes "T", walls "F"), ``Time`` (simulated time) and
    ``Step`` (pair collisions); each particle line the species ``X`` (ASE's
    dummy atom: a hard sphere is no element), position in [0, L), velocity,
    momentum m v, radius, mass and the particle type ("A", "B", ..., as in
    GSD files), numbers written with 17 significant digits (exact round
    trip). 2D systems get z = 0, a third cell vector one diameter long and
    pbc "F" along z. ``momenta`` and ``masses`` are ASE's own names, so
    ``atoms = ase.io.read(path)`` gives ``atoms.get_masses()`` and
    ``atoms.get_velocities()`` (to round-off; the exact velocities are
    ``atoms.arrays["vel"]``), with positions, cell, pbc,
    ``atoms.arrays["radius"]`` and ``["type"]``, and Time and Step in
    ``atoms.info``. Rough spheres add ``omega:R:3`` (angular velocities;
    discs about z) before the type.

    Parameters
    ----------
    path : str or Path
    system : HardSphereSystem
    comment : str, optional
        Stored as ``Comment="..."`` in the header (no quotes or newlines).

    Returns
    -------
    Path
        The file written.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = tempfile.TemporaryDirectory()
    >>> from collisionkit.edmd import random_fluid
    >>> from collisionkit.trajectory import write_extended_xyz
    >>> path = write_extended_xyz(pathlib.Path(folder.name) / "fluid.xyz", random_fluid(3, 30, 0.1, seed=1))
    >>> lines = path.read_text().splitlines()
    >>> lines[0], len(lines), 'pbc="T T T"' in lines[1]
    ('30', 32, True)
    """
    header = _xyz_header(system, comment)
    names = np.asarray(type_names(system.species))[np.asarray(system.species)]
    positions, velocities = _pad(system.positions(), float), _pad(system.velocities(), float)
    masses = np.asarray(system.mass, dtype=float)
    columns = np.column_stack([positions, velocities, masses[:, None] * velocities, system.radius, masses])
    if getattr(system, "rough", False):
        columns = np.column_stack([columns, _spins(system)])
    body = "\n".join(
        f"{_XYZ_SPECIES} " + " ".join(f"{value:.17g}" for value in row) + f" {name}" for name, row in zip(names, columns)
    )
    return atomic_write_text(path, f"{system.count}\n{header}\n{body}\n")

