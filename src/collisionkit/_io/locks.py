"""Advisory locks on output files: a second process writing the same file is refused, not let in to corrupt it.

:func:`exclusive` holds ``flock`` on a sidecar ``.<name>.lock`` beside the
output file while a run writes it; the lock file holds the writer's process
id, so the refusal (:class:`FileLockedError`) names it.
"""

from __future__ import annotations

import contextlib
import errno
import os
import threading
from collections.abc import Iterator
from pathlib import Path

try:
    import fcntl
except ImportError:  # not POSIX: files are not locked
    fcntl = None


def _process_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process
        return True
    return True



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
