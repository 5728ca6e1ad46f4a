"""Atomic writes: a reader, or a crash at any instant, sees the old file or the new one, never half of one.

:func:`atomic_write_bytes` and its text, JSON and CSV forms write through a
temporary file beside the target (``.<name>.<pid>.<random>.tmp``) and
``os.replace``; a temporary file that a killed process left behind is removed
at the next write of the same target (:func:`remove_stale_temporaries`).
"""

from __future__ import annotations

import contextlib
import csv
import hashlib
import io
import json
import math
import os
import re
import tempfile
import time
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from .locks import _locked_elsewhere, _process_alive

# temporary files of a killed process older than this are stale (no write of this process is older)
_PROCESS_START = time.time()


def _current_umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask



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
