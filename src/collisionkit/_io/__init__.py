"""Safe file writing: atomic writes (a reader, or a crash, never sees half a file), locks, the checkpoint format.

* :func:`atomic_write_bytes` and its text, JSON and CSV forms write through
  a temporary file beside the target (``.<name>.<pid>.<random>.tmp``) and
  ``os.replace``; a temporary file that a killed process left behind is
  removed at the next write of the same target (:mod:`.atomic`).
* :func:`exclusive` holds an advisory lock on an output file (``flock`` on a
  sidecar ``.<name>.lock``) while a run writes it, so a second process
  writing the same file is refused (:class:`FileLockedError`) instead of
  corrupting it (:mod:`.locks`).
* :func:`write_checkpoint` and :func:`read_checkpoint`: the ``.npz``
  checkpoint of every kind of run; a damaged file is a one-line
  :class:`CheckpointError`, never a traceback of zipfile or numpy
  (:mod:`.checkpoints`).
"""

from __future__ import annotations

from .atomic import (
    atomic_replacement,
    atomic_write_bytes,
    atomic_write_json,
    atomic_write_text,
    file_digest,
    remove_stale_temporaries,
    write_csv,
)
from .checkpoints import (
    CHECKPOINT_FORMAT,
    CHECKPOINT_VERSION,
    Checkpoint,
    CheckpointError,
    read_checkpoint,
    write_checkpoint,
)
from .locks import FileLockedError, exclusive

__all__ = [
    "CHECKPOINT_FORMAT",
    "CHECKPOINT_VERSION",
    "Checkpoint",
    "CheckpointError",
    "FileLockedError",
    "atomic_replacement",
    "atomic_write_bytes",
    "atomic_write_json",
    "atomic_write_text",
    "exclusive",
    "file_digest",
    "read_checkpoint",
    "remove_stale_temporaries",
    "write_checkpoint",
    "write_csv",
]
