"""Atomic file writing: a reader (or a crash) never sees half a file."""

from __future__ import annotations

import json
import math
import os
import tempfile
from pathlib import Path

import numpy as np


def _current_umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def atomic_write_bytes(path, data: bytes) -> Path:
    """Write ``data`` to ``path`` through a temporary file and ``os.replace``.

    The temporary file lives in the same folder (same file system), is
    flushed and fsynced before the rename, so after a kill at any instant the
    path holds either the old content or the new one.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        # mkstemp makes the file private (0600); give it the usual permissions
        os.fchmod(handle, 0o666 & ~_current_umask())
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
            stream.flush()
            os.fsync(stream.fileno())
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
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
