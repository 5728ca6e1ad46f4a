"""The checkpoint format of every kind of run: one ``.npz`` file, a JSON header and named arrays.

:func:`write_checkpoint` writes it atomically under :func:`.locks.exclusive`;
:func:`read_checkpoint` reads it back, and a damaged file is a one-line
:class:`CheckpointError`, never a traceback of zipfile or numpy.
"""

from __future__ import annotations

import io
import json
import math
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .atomic import _strict_json, atomic_write_bytes
from .locks import exclusive

CHECKPOINT_FORMAT = "collisionkit checkpoint"
CHECKPOINT_VERSION = 1
_HEADER = "checkpoint_header"


class CheckpointError(ValueError):
    """A file that is not a readable checkpoint of the expected kind and version."""


def write_checkpoint(path, kind: str, parameters, state=None, arrays=None) -> Path:
    """Write a checkpoint atomically: one ``.npz`` file, the same layout for every kind of run.

    The file holds a JSON header (``format``, ``version``, ``kind``, the
    ``parameters`` that started the run and a JSON-ready ``state``) and
    any numpy ``arrays`` (the bulk state, stored exactly).

    Parameters
    ----------
    path : path
        The ``.npz`` file to write (replaced atomically).
    kind : str
        What wrote it (``"edmd"``, ``"swarm"``, ``"sweep"``): a run resumes
        only from its own kind.
    parameters : mapping
        The run's parameters, JSON-ready (NaN and inf become ``null``).
    state : mapping, optional
        Progress counters and small results, JSON-ready.
    arrays : mapping of str to array, optional
        Bulk state; names must not be ``checkpoint_header``.

    Returns
    -------
    Path

    Raises
    ------
    FileLockedError
        If another process is writing ``path`` (it holds :func:`exclusive`
        on it; this process may hold it, as a run does for its lifetime).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import numpy as np
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "run.npz"
    >>> _ = write_checkpoint(path, "demo", {"n": 3}, {"done": 1}, {"x": np.arange(3.0)})
    >>> checkpoint = read_checkpoint(path, "demo")
    >>> checkpoint.parameters, checkpoint.state, checkpoint.arrays["x"].tolist()
    ({'n': 3}, {'done': 1}, [0.0, 1.0, 2.0])
    """
    arrays = dict(arrays or {})
    if _HEADER in arrays:
        raise ValueError(f"arrays must not use the name {_HEADER!r}")
    header = {"format": CHECKPOINT_FORMAT, "version": CHECKPOINT_VERSION, "kind": kind,
              "parameters": _strict_json(dict(parameters)), "state": _strict_json(dict(state or {}))}
    buffer = io.BytesIO()
    np.savez(buffer, **{_HEADER: np.asarray(json.dumps(header, allow_nan=False))}, **arrays)
    with exclusive(path):
        return atomic_write_bytes(path, buffer.getvalue())


@dataclass(frozen=True)
class Checkpoint:
    """What :func:`read_checkpoint` found: the run's kind, parameters, state and arrays.

    :meth:`entry` reads the ``state`` with checks: a value of the wrong type
    or out of range is a :class:`CheckpointError` naming the file and the entry.
    """

    path: Path
    kind: str
    parameters: dict
    state: dict
    arrays: dict

    def damaged(self, what: str) -> CheckpointError:
        """The error for a damaged entry: ``"<path> is a damaged <kind> checkpoint: <what>"``.

        Examples
        --------
        >>> Checkpoint(Path("run.npz"), "edmd", {}, {}, {}).damaged("no state")
        CheckpointError('run.npz is a damaged edmd checkpoint: no state')
        """
        return CheckpointError(f"{self.path} is a damaged {self.kind} checkpoint: {what}")

    def entry(self, name: str, kind: str, low: float = -math.inf, high: float = math.inf, optional: bool = False):
        """``state[name]``, checked to be of ``kind``: ``integer``, ``number``, ``text``, ``mapping`` or ``list``.

        Numbers are finite and in [low, high] (a ``number`` comes back as a
        float); None is allowed if ``optional``.

        Examples
        --------
        >>> saved = Checkpoint(Path("run.npz"), "edmd", {}, {"frames": 3, "every": "x"}, {})
        >>> saved.entry("frames", "integer", 0), saved.entry("outputs", "mapping", optional=True)
        (3, None)
        >>> saved.entry("every", "integer", 1)
        Traceback (most recent call last):
        ...
        collisionkit._io.checkpoints.CheckpointError: run.npz is a damaged edmd checkpoint: state 'every' must be an integer >= 1...
        """
        value = self.state.get(name)
        if value is None and optional:
            return None
        numeric = kind in ("integer", "number")
        valid = isinstance(value, _ENTRY_TYPES[kind]) and not isinstance(value, bool)
        if valid and numeric:
            valid = math.isfinite(value) and low <= value <= high
        if not valid:
            bounds = "" if not numeric else f" >= {low:g}" if high == math.inf else f" in [{low:g}, {high:g}]"
            raise self.damaged(f"state {name!r} must be {'an' if kind == 'integer' else 'a'} {kind}{bounds}; "
                               f"got {value!r}")
        return float(value) if kind == "number" else value


_ENTRY_TYPES = {"integer": int, "number": (int, float), "text": str, "mapping": dict, "list": list}


def _one_line(error: BaseException) -> str:
    text = " ".join(str(error).split())
    return text or type(error).__name__


def _read_arrays(path: Path) -> dict[str, np.ndarray]:
    """Every array of an ``.npz`` file; CheckpointError for a damaged one (bad CRC, truncated, not ``.npy``)."""
    arrays = {}
    try:
        with zipfile.ZipFile(path) as archive:
            for member in archive.infolist():
                name = member.filename
                if not name.endswith(".npy"):
                    raise CheckpointError(f"{path} is not a checkpoint: it holds {name!r}, which is no numpy array")
                try:
                    with archive.open(member) as stream:
                        arrays[name[: -len(".npy")]] = np.lib.format.read_array(stream, allow_pickle=False)
                        stream.read()  # to the end: zipfile checks the CRC there
                except CheckpointError:
                    raise
                except Exception as error:  # noqa: BLE001 - whatever zipfile or numpy say, the array is unreadable
                    raise CheckpointError(f"{path} is a damaged checkpoint: array {name[:-4]!r} cannot be read "
                                          f"({_one_line(error)})") from None
    except CheckpointError:
        raise
    except Exception as error:  # noqa: BLE001 - a damaged zip directory (truncated file, bad offsets)
        raise CheckpointError(f"{path} is a damaged checkpoint ({_one_line(error)})") from None
    return arrays


def _read_header(path: Path, arrays: dict, kind: str) -> dict:
    """The JSON header of a checkpoint, checked: format, kind, version, and mappings for parameters and state."""
    header = arrays.pop(_HEADER, None)
    if header is None or header.shape != () or header.dtype.kind != "U":
        raise CheckpointError(f"{path} is not a checkpoint of 'collisionkit {kind}' (no {CHECKPOINT_FORMAT!r} header)")
    try:
        header = json.loads(str(header))
    except ValueError as error:
        raise CheckpointError(f"{path} is a damaged checkpoint: its header is not JSON ({_one_line(error)})") from None
    if not isinstance(header, dict) or header.get("format") != CHECKPOINT_FORMAT:
        raise CheckpointError(f"{path} is not a collisionkit checkpoint")
    if header.get("kind") != kind:
        raise CheckpointError(f"{path} is not a checkpoint of 'collisionkit {kind}': it was written by "
                              f"'collisionkit {header.get('kind')}'")
    if header.get("version") != CHECKPOINT_VERSION:
        raise CheckpointError(f"{path} is a checkpoint of version {header.get('version')!r}; this collisionkit reads "
                              f"version {CHECKPOINT_VERSION}")
    for entry in ("parameters", "state"):
        if not isinstance(header.get(entry) or {}, dict):
            raise CheckpointError(f"{path} is a damaged checkpoint: its header's {entry!r} is "
                                  f"{type(header[entry]).__name__}, not a mapping")
    return header


def read_checkpoint(path, kind: str) -> Checkpoint:
    """Read a checkpoint written by :func:`write_checkpoint` for a run of ``kind``.

    Every array is read (no pickles) and checked against its zip CRC; the
    arrays' contents are the caller's to validate.

    Raises
    ------
    CheckpointError
        If the file is missing, a folder, not a checkpoint, of another kind
        or of another version, or damaged (bad CRC, truncated, an entry of
        the header of the wrong type); the one-line message names the file
        and what is wrong.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "run.npz"
    >>> _ = path.write_bytes(write_checkpoint(path, "demo", {}, {"done": 1}).read_bytes()[:100])   # cut short
    >>> read_checkpoint(path, "demo")
    Traceback (most recent call last):
    ...
    collisionkit._io.checkpoints.CheckpointError: ...run.npz is a damaged checkpoint: cut short (its zip directory is missing)
    """
    path = Path(path)
    if not path.exists():
        raise CheckpointError(f"checkpoint not found: {path}")
    if path.is_dir():
        raise CheckpointError(f"checkpoint {path} is a folder; give the checkpoint file")
    try:
        is_zip = zipfile.is_zipfile(path)
    except OSError as error:
        raise CheckpointError(f"cannot read checkpoint {path}: {_one_line(error)}") from None
    if not is_zip:  # numpy would talk of pickles
        with open(path, "rb") as stream:
            if stream.read(4) == b"PK\x03\x04":  # a zip file without its directory at the end
                raise CheckpointError(f"{path} is a damaged checkpoint: cut short (its zip directory is missing)")
        raise CheckpointError(f"{path} is not a checkpoint (the .npz file a collisionkit {kind} run writes)")
    arrays = _read_arrays(path)
    header = _read_header(path, arrays, kind)
    return Checkpoint(path, kind, dict(header.get("parameters") or {}), dict(header.get("state") or {}), arrays)
