"""Safe file writing: atomic writes (a reader, or a crash, never sees half a file), locks, the checkpoint format.

* :func:`atomic_write_bytes` and its text, JSON and CSV forms write through
  a temporary file beside the target (``.<name>.<pid>.<random>.tmp``) and
  ``os.replace``; a temporary file that a killed process left behind is
  removed at the next write of the same target.
* :func:`exclusive` holds an advisory lock on an output file (``flock`` on a
  sidecar ``.<name>.lock``) while a run writes it, so a second process
  writing the same file is refused (:class:`FileLockedError`) instead of
  corrupting it.
* :func:`write_checkpoint` and :func:`read_checkpoint`: the ``.npz``
  checkpoint of every kind of run; a damaged file is a one-line
  :class:`CheckpointError`, never a traceback of zipfile or numpy.
"""

from __future__ import annotations

import contextlib
import csv
import errno
import hashlib
import io
import json
import math
import os
import re
import tempfile
import threading
import time
import zipfile
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

try:
    import fcntl
except ImportError:  # not POSIX: files are not locked
    fcntl = None

# temporary files of a killed process older than this are stale (no write of this process is older)
_PROCESS_START = time.time()


def _current_umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _process_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process
        return True
    return True


def _temporary_pattern(path: Path) -> re.Pattern:
    """The names of the temporary files of writes of ``path``: ``.<name>.[<pid>.]<random>.tmp``."""
    return re.compile(rf"\.{re.escape(path.name)}\.(?:(\d+)\.)?[a-z0-9_]{{8}}\.tmp")


def remove_stale_temporaries(path) -> list[Path]:
    """Remove the temporary files that killed writes of ``path`` left beside it; return those removed.

    A temporary file is stale when it is older than this process, its
    writer (the process id in its name) is gone and no other process holds
    :func:`exclusive` on ``path``: a write in progress elsewhere is never
    touched. :func:`atomic_write_bytes` calls this before every write.

    Examples
    --------
    >>> import os, pathlib, tempfile
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> left = folder / ".run.npz.4194305.abcd1234.tmp"   # a write killed long ago
    >>> _ = left.write_bytes(b"half a checkpoint")
    >>> os.utime(left, (0, 0))
    >>> [p.name for p in remove_stale_temporaries(folder / "run.npz")], left.exists()
    (['.run.npz.4194305.abcd1234.tmp'], False)
    """
    path = Path(path)
    try:
        entries = list(path.parent.iterdir())
    except OSError:  # no folder yet, or not readable: nothing to clean
        return []
    pattern = _temporary_pattern(path)
    stale = []
    for entry in entries:
        match = pattern.fullmatch(entry.name)
        if match is None:
            continue
        writer = None if match.group(1) is None else int(match.group(1))
        if writer is not None and (writer == os.getpid() or _process_alive(writer)):
            continue
        try:
            if entry.lstat().st_mtime >= _PROCESS_START:
                continue
        except OSError:
            continue
        stale.append(entry)
    if stale and _locked_elsewhere(path):
        return []
    for entry in stale:
        with contextlib.suppress(OSError):
            entry.unlink()
    return stale


@contextlib.contextmanager
def atomic_replacement(path, mode: int | None = None) -> Iterator[Path]:
    """A temporary file beside ``path`` that replaces it when the block ends without an error.

    The temporary file (``.<name>.<pid>.<random>.tmp``, in the same folder)
    is yours to fill; it then replaces ``path`` (``os.replace``): a reader,
    or a kill at any instant, sees the old file or the new one. If the block
    raises, it is removed; stale ones are removed first
    (:func:`remove_stale_temporaries`).

    Parameters
    ----------
    path : path
        The file to replace (its folder is created if needed).
    mode : int, optional
        Permission bits of the new file (default: 0o666 less the umask, as
        an ordinary new file).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "data.txt"
    >>> with atomic_replacement(path) as temporary:
    ...     _ = temporary.write_text("new")
    >>> path.read_text(), [p.name for p in path.parent.iterdir()]
    ('new', ['data.txt'])
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    remove_stale_temporaries(path)
    handle, name = tempfile.mkstemp(prefix=f".{path.name}.{os.getpid()}.", suffix=".tmp", dir=path.parent)
    temporary = Path(name)
    try:
        try:  # mkstemp makes the file private (0600); give it the usual permissions
            os.fchmod(handle, 0o666 & ~_current_umask() if mode is None else mode)
        finally:
            os.close(handle)
        yield temporary
        os.replace(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def atomic_write_bytes(path, data: bytes) -> Path:
    """Write ``data`` to ``path`` through a temporary file and ``os.replace``.

    The temporary file lives in the same folder (same file system), is
    flushed and fsynced before the rename, so after a kill at any instant the
    path holds either the old content or the new one; a temporary file a
    killed write left behind is removed at the next write of ``path``.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> atomic_write_bytes(pathlib.Path(tempfile.mkdtemp()) / "a.bin", b"abc").read_bytes()
    b'abc'
    """
    path = Path(path)
    with atomic_replacement(path) as temporary, open(temporary, "wb") as stream:
        stream.write(data)
        stream.flush()
        os.fsync(stream.fileno())
    return path


def atomic_write_text(path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    return atomic_write_bytes(path, text.encode("utf-8"))


def _strict_json(value):
    """``value`` with numpy values as plain ones, paths as strings and NaN or +-inf as None."""
    if isinstance(value, dict):
        return {key: _strict_json(item) for key, item in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [_strict_json(item) for item in (value.tolist() if isinstance(value, np.ndarray) else value)]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, Path):
        return str(value)
    if value is None or isinstance(value, (str, int, float)):  # bool is an int
        return value
    raise TypeError(f"cannot write {type(value).__name__} as JSON")


def atomic_write_json(path, data) -> Path:
    """Write ``data`` as indented JSON atomically; numpy values become plain numbers.

    Non-finite numbers (NaN, +-inf: the period of an unbound orbit, a
    diffusion coefficient not yet measurable) are written as ``null``, as
    JavaScript's ``JSON.stringify`` does: strict JSON has no NaN or
    Infinity, and jq, browsers and many languages' parsers reject them.

    Examples
    --------
    >>> import json, math, pathlib, tempfile
    >>> path = atomic_write_json(pathlib.Path(tempfile.mkdtemp()) / "s.json", {"period": math.inf, "e": 1.5})
    >>> json.loads(path.read_text())
    {'period': None, 'e': 1.5}
    """
    return atomic_write_text(path, json.dumps(_strict_json(data), indent=2, allow_nan=False) + "\n")


# ------------------------------------------------------------------ locks


class FileLockedError(OSError):
    """An output file that another collisionkit process is writing (it holds :func:`exclusive` on it)."""


# the locks this process holds: lock file -> [descriptor, depth, pid] (a nested exclusive() of one file re-enters)
_held: dict[str, list] = {}
_held_guard = threading.Lock()


def _lock_file(path) -> Path:
    """The sidecar lock file of ``path``: ``.<name>.lock`` beside it (symbolic links resolved)."""
    path = Path(path).resolve()
    return path.parent / f".{path.name}.lock"


def _holder(lock: Path) -> int | None:
    """The process id written in a lock file, if any."""
    try:
        text = lock.read_text(encoding="ascii", errors="replace").strip()
    except OSError:
        return None
    return int(text) if text.isdigit() else None


def _locked_elsewhere(path) -> bool:
    """True if another live process holds the lock of ``path`` (its id in the lock file; a probe could fail writers)."""
    lock = _lock_file(path)
    entry = _held.get(str(lock))
    if entry is not None and entry[2] == os.getpid():
        return False
    holder = _holder(lock)
    return holder is not None and holder != os.getpid() and _process_alive(holder)


def _acquire(lock: Path, target: Path) -> int | None:
    """Open and lock ``lock`` (non-blocking); the descriptor, or None where files cannot be locked."""
    lock.parent.mkdir(parents=True, exist_ok=True)
    while True:
        descriptor = os.open(lock, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o666)
        try:
            fcntl.flock(descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as error:
            os.close(descriptor)
            if error.errno not in (errno.EAGAIN, errno.EWOULDBLOCK, errno.EACCES):
                return None  # a file system without locks (some network mounts): write unlocked, as before
            holder = _holder(lock)
            raise FileLockedError(
                f"{target} is being written by another collisionkit process "
                f"({'pid unknown' if holder is None else f'pid {holder}'}): wait for it to end or write elsewhere"
            ) from None
        # a holder that ended between our open and our lock removed the file: lock the one that is there now
        try:
            current = os.path.samestat(os.fstat(descriptor), os.stat(lock))
        except FileNotFoundError:
            current = False
        if current:
            os.ftruncate(descriptor, 0)
            os.write(descriptor, f"{os.getpid()}\n".encode())
            return descriptor
        os.close(descriptor)


def _release(lock: Path, descriptor: int | None) -> None:
    if descriptor is None:
        return
    with contextlib.suppress(FileNotFoundError):
        lock.unlink()  # while still locked: a process waiting on this file sees it gone and locks a new one
    os.close(descriptor)


def _forget_inherited_locks() -> None:
    """In a forked child: the parent's locks are the parent's (closing the copies does not unlock them)."""
    global _held_guard
    _held_guard = threading.Lock()  # another thread may have held it at the fork
    for descriptor, _, _ in _held.values():
        if descriptor is not None:
            with contextlib.suppress(OSError):
                os.close(descriptor)
    _held.clear()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_inherited_locks)


@contextlib.contextmanager
def exclusive(path) -> Iterator[Path | None]:
    """Hold an advisory lock on an output file for the block: a second process writing it is refused.

    The lock is ``flock`` on a sidecar file ``.<name>.lock`` beside
    ``path`` (holding the holder's process id), taken without waiting and
    removed when the block ends; the kernel releases it if the process dies.
    Nested blocks of one process on one file re-enter the lock (a run that
    holds its checkpoint can write it). Writers of checkpoints and GSD
    trajectories take it; readers do not. On a file system without locks
    the block runs unlocked.

    Parameters
    ----------
    path : path or None
        The output file (None: nothing to lock, the block just runs).

    Raises
    ------
    FileLockedError
        If another process holds the lock (the message names the file and
        that process's id).

    Examples
    --------
    >>> import pathlib, subprocess, sys, tempfile
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "run.npz"
    >>> other = "from collisionkit._io import exclusive; import sys; exclusive(sys.argv[1]).__enter__()"
    >>> with exclusive(path):
    ...     with exclusive(path):                      # the same process re-enters
    ...         pass
    ...     result = subprocess.run([sys.executable, "-c", other, str(path)], capture_output=True, text=True)
    >>> "is being written by another collisionkit process" in result.stderr
    True
    >>> sorted(p.name for p in path.parent.iterdir())   # the lock file is gone with the lock
    []
    """
    if path is None or fcntl is None:
        yield None if path is None else Path(path)
        return
    lock = _lock_file(path)
    key = str(lock)
    with _held_guard:
        entry = _held.get(key)
        if entry is None:
            entry = _held[key] = [_acquire(lock, Path(path)), 0, os.getpid()]
        entry[1] += 1
    try:
        yield Path(path)
    finally:
        with _held_guard:
            entry[1] -= 1
            if entry[1] == 0 and _held.get(key) is entry:
                del _held[key]
                _release(lock, entry[0])


# ------------------------------------------------------------------ checkpoints

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
        collisionkit._io.CheckpointError: run.npz is a damaged edmd checkpoint: state 'every' must be an integer >= 1...
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
    collisionkit._io.CheckpointError: ...run.npz is a damaged checkpoint: cut short (its zip directory is missing)
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


def file_digest(path) -> str | None:
    """SHA-256 of a file's bytes (None for no path): a resumed run checks that its inputs did not change."""
    return None if path is None else hashlib.sha256(Path(path).read_bytes()).hexdigest()


def _columns(table: list[Mapping[str, Any]]) -> list[str]:
    columns: dict[str, None] = {}
    for row in table:
        columns |= dict.fromkeys(row)
    return list(columns)


def write_csv(path, table: list[Mapping[str, Any]]) -> Path:
    """Write the table as CSV atomically (floats as their shortest exact text; missing cells empty).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = write_csv(pathlib.Path(tempfile.mkdtemp()) / "t.csv", [{"a": 0.1, "b": 1}, {"a": 0.2}])
    >>> path.read_text().splitlines()
    ['a,b', '0.1,1', '0.2,']
    """
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=_columns(table), restval="", lineterminator="\n")
    writer.writeheader()
    writer.writerows(table)
    return atomic_write_text(path, buffer.getvalue())
