"""Atomic file writing (a reader, or a crash, never sees half a file): JSON, CSV, and the one checkpoint format."""

from __future__ import annotations

import csv
import hashlib
import io
import json
import math
import os
import tempfile
import zipfile
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

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
    return atomic_write_bytes(path, buffer.getvalue())


@dataclass(frozen=True)
class Checkpoint:
    """What :func:`read_checkpoint` found: the run's kind, parameters, state and arrays."""

    path: Path
    kind: str
    parameters: dict
    state: dict
    arrays: dict


def read_checkpoint(path, kind: str) -> Checkpoint:
    """Read a checkpoint written by :func:`write_checkpoint` for a run of ``kind``.

    Raises
    ------
    CheckpointError
        If the file is missing, a folder, not a checkpoint, of another kind
        or of another version (the message names the file and what it is).
    """
    path = Path(path)
    if not path.exists():
        raise CheckpointError(f"checkpoint not found: {path}")
    if path.is_dir():
        raise CheckpointError(f"checkpoint {path} is a folder; give the checkpoint file")
    if not zipfile.is_zipfile(path):  # numpy would talk of pickles
        raise CheckpointError(f"{path} is not a checkpoint (the .npz file a collisionkit {kind} run writes)")
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {name: data[name] for name in data.files}
        header = json.loads(str(arrays.pop(_HEADER)))
    except KeyError:
        raise CheckpointError(f"{path} is not a checkpoint of 'collisionkit {kind}' "
                              f"(no {CHECKPOINT_FORMAT!r} header)") from None
    except (OSError, ValueError, zipfile.BadZipFile) as error:
        raise CheckpointError(f"{path} is not a readable checkpoint: {error}") from None
    if not isinstance(header, dict) or header.get("format") != CHECKPOINT_FORMAT:
        raise CheckpointError(f"{path} is not a collisionkit checkpoint")
    if header.get("kind") != kind:
        raise CheckpointError(f"{path} is not a checkpoint of 'collisionkit {kind}': it was written by "
                              f"'collisionkit {header.get('kind')}'")
    if header.get("version") != CHECKPOINT_VERSION:
        raise CheckpointError(f"{path} is a checkpoint of version {header.get('version')}; this collisionkit reads "
                              f"version {CHECKPOINT_VERSION}")
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
