"""The one place where numba compilation flags are set.

Every numeric kernel in collisionkit is decorated with :func:`kernel`, so the
flags (lazy compilation, on-disk cache, strict IEEE arithmetic) are the same
everywhere and can be changed here alone.

``fastmath`` stays off: the collision formulas rely on IEEE semantics for
``inf`` masses and for the cancellation-free forms of the contact-time root.
Kernels that neither allocate nor return arrays can use the ``borrowing_``
variants, compiled without numba's reference counting (NRT): the arrays they
get are borrowed from the caller, who keeps them alive. Every array passed
to an inlined helper otherwise costs an atomic increment and decrement,
which took 11 % of the EDMD event loop (perf, N = 864).

Set the environment variable ``NUMBA_CACHE_DIR`` to choose where compiled
kernels are cached (``.ci/run`` does).

Processes that share a cache (a sweep's workers, the tests' workers, two
runs started at once) compile a kernel one at a time
(:func:`compile_lock_path`): the second waits and loads the first one's
machine code instead of compiling it again, and numba's unlocked save of the
cache index cannot mix two processes' entries.

A cached kernel is reused only while *every* kernel source is unchanged:
numba stamps a cache with the kernel's own file alone, so a kernel that
calls (or inlines) a helper of another module of ``_kernels`` would keep its
old machine code after the helper changed. :func:`kernel_sources_stamp`
hashes them all, and the cache locators registered here use it.
"""

from __future__ import annotations

import functools
import hashlib
import types
from pathlib import Path

import numba
from numba.core import caching
from numba.core.compiler_lock import global_compiler_lock

try:
    import fcntl
except ImportError:  # not POSIX: compiles are not serialised between processes
    fcntl = None

KERNEL_SOURCES = (Path(__file__).parent / "_kernels", Path(__file__))

JIT_OPTIONS = {
    "cache": True,
    "nogil": True,
    "fastmath": False,
    "error_model": "numpy",
}

# numba's private option for its reference-counting runtime; with it off a kernel may not allocate arrays
BORROWING_OPTIONS = {**JIT_OPTIONS, "_nrt": False}


def kernel(function):
    """Compile ``function`` lazily with the project's numba options.

    Compilation happens at the first call for each set of argument types,
    and the machine code is cached on disk for the next process.
    """
    return _one_process_at_a_time(numba.njit(**JIT_OPTIONS)(function))


def inline_kernel(function):
    """Like :func:`kernel`, but inlined into every kernel that calls it.

    For the small helpers of hot loops: a call between numba functions that
    take arrays costs tens of nanoseconds (argument unpacking and reference
    counting), more than the helper's arithmetic. Inlining at numba's IR
    level removes it (measured 5x on the list-expiry helper of the EDMD
    engine) at the price of longer first compilation, which is cached.
    """
    return _one_process_at_a_time(numba.njit(inline="always", **JIT_OPTIONS)(function))


def borrowing_kernel(function):
    """Like :func:`kernel`, without reference counting: for kernels that never allocate or return arrays."""
    return _one_process_at_a_time(numba.njit(**BORROWING_OPTIONS)(function))


def borrowing_inline_kernel(function):
    """Like :func:`inline_kernel`, without reference counting (see :func:`borrowing_kernel`)."""
    return _one_process_at_a_time(numba.njit(inline="always", **BORROWING_OPTIONS)(function))


# ------------------------------------------------------------------ one process at a time per kernel

_LOCKS_HELD = set()  # the kernels whose compile lock this process holds (compiles nest: a kernel types its callees)


def compile_lock_path(dispatcher) -> str | None:
    """The file whose ``flock`` a process holds while it compiles (or loads) ``dispatcher``'s machine code: beside
    the kernel's cache index, so processes sharing a cache share it; None for a kernel without an on-disk cache."""
    cache_file = getattr(dispatcher._cache, "_cache_file", None)
    return None if cache_file is None else cache_file._index_path + ".lock"


def _compile_under_lock(dispatcher, signature):
    """numba's compile of ``dispatcher`` for ``signature``, holding its :func:`compile_lock_path` lock.

    numba looks in the on-disk cache before it compiles, so a process that
    waited for another's compile loads that machine code. The cache save
    reads the index, picks the first free data-file name and writes the
    index back, unlocked: two processes saving two signatures of one kernel
    could both pick ``name.1.nbc`` (one index entry then pointing at the
    other's machine code) or drop each other's entries; under the lock they
    cannot. Locks are taken along the call graph (a kernel's, then its
    callees' as it types them; no kernel calls its callers), so two
    processes never wait for each other; and under numba's compiler lock,
    so one thread of a process at a time.
    """
    compile_unlocked = type(dispatcher).compile
    path = compile_lock_path(dispatcher)
    if path is None or fcntl is None:
        return compile_unlocked(dispatcher, signature)
    with global_compiler_lock:
        if path in _LOCKS_HELD:  # a recursive signature of the kernel being compiled
            return compile_unlocked(dispatcher, signature)
        with open(path, "a") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            _LOCKS_HELD.add(path)
            try:
                return compile_unlocked(dispatcher, signature)
            finally:
                _LOCKS_HELD.discard(path)


def _one_process_at_a_time(dispatcher):
    """``dispatcher`` with its compile under :func:`_compile_under_lock` (numba calls ``self.compile`` both for a
    call and when another kernel types a call to it)."""
    dispatcher.compile = types.MethodType(_compile_under_lock, dispatcher)
    return dispatcher


# ------------------------------------------------------------------ the on-disk cache's stamp


@functools.lru_cache(maxsize=1)
def kernel_sources_stamp() -> str:
    """SHA-256 of every kernel source (``_kernels/**/*.py`` and this file), by relative path and content.

    Examples
    --------
    >>> len(kernel_sources_stamp()), kernel_sources_stamp() == kernel_sources_stamp()
    (64, True)
    """
    digest = hashlib.sha256()
    folder, this_file = KERNEL_SOURCES
    for path in [*sorted(folder.rglob("*.py")), this_file]:
        digest.update(str(path.relative_to(folder.parent)).encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


def _is_kernel_source(py_file: str) -> bool:
    try:
        return Path(py_file).resolve().is_relative_to(KERNEL_SOURCES[0].resolve())
    except (OSError, ValueError):
        return False


class _KernelSourcesStamp:
    """A numba cache locator's stamp for collisionkit's kernels: all kernel sources, not one file."""

    def get_source_stamp(self):
        return kernel_sources_stamp()

    @classmethod
    def from_function(cls, py_func, py_file):
        if not _is_kernel_source(py_file):
            return None  # not ours: numba's own locators take it
        return super().from_function(py_func, py_file)


class _KernelCacheInUserDirectory(_KernelSourcesStamp, caching.UserProvidedCacheLocator):
    """Kernels cached in ``NUMBA_CACHE_DIR``, stamped by all kernel sources."""


class _KernelCacheInTree(_KernelSourcesStamp, caching.InTreeCacheLocator):
    """Kernels cached in ``__pycache__`` beside their source, stamped by all kernel sources."""


def _register_cache_locators() -> None:
    locators = caching.CacheImpl._locator_classes  # numba's (documented for extension) list of locators
    for locator in (_KernelCacheInTree, _KernelCacheInUserDirectory):
        if locator not in locators:
            locators.insert(0, locator)


_register_cache_locators()
