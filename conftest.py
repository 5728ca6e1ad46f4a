"""Settings for every test, the doctests of src/collisionkit included."""

import fcntl
import sys

import pytest
from numba.core.compiler_lock import global_compiler_lock
from numba.core.dispatcher import Dispatcher

_compile = Dispatcher.compile
_locked_here = set()  # the kernels whose lock this process holds (compiles nest: a kernel types its callees)


def _compile_one_process_at_a_time(self, sig):
    """numba's compile of a cached kernel, one process at a time per kernel (the tests run in parallel, pytest-xdist).

    On a cold cache two workers that need one kernel would both compile it
    (the tracking kernel takes minutes): with the lock, the second waits and
    then loads the first one's machine code from the on-disk cache (numba
    looks there before compiling). It also makes numba's cache save safe: it
    reads a kernel's cache index, picks the first free data-file name for a
    new signature and writes the index back, unlocked, so two processes
    saving two signatures of one kernel could both pick ``name.1.nbc`` (one
    index entry then points at the other's machine code) or drop each
    other's entries. Locks follow the call graph (a kernel's lock, then its
    callees'; no kernel calls its callers), so two processes never wait for
    each other; taken under
    numba's compiler lock, so one thread of a process at a time.
    """
    cache_file = getattr(self._cache, "_cache_file", None)
    if cache_file is None:  # not cached (numba's own functions): nothing to share
        return _compile(self, sig)
    with global_compiler_lock:
        path = cache_file._index_path + ".lock"
        if path in _locked_here:
            return _compile(self, sig)
        with open(path, "a") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            _locked_here.add(path)
            try:
                return _compile(self, sig)
            finally:
                _locked_here.discard(path)


Dispatcher.compile = _compile_one_process_at_a_time


@pytest.fixture(autouse=True)
def _close_figures_after_each_test():
    """Close the figures a test or an example left open.

    pyplot keeps every figure until it is closed, and warns (a RuntimeWarning,
    an error under this project's filter) once more than 20 are open: the
    plotting examples opened them, and the sweep's examples that came after
    them failed.
    """
    yield
    if "matplotlib.pyplot" in sys.modules:
        sys.modules["matplotlib.pyplot"].close("all")


def pytest_collection_modifyitems(items):
    """Run the files that hold ``slow`` tests first, each file's tests in their own order.

    The tests run in parallel one file per worker (``--dist loadfile``), each
    worker taking the next file as it finishes one: a long file taken last
    would leave the other cores idle while it runs, the longest first
    balances the cores. The order of the other files is kept.
    """
    slow_files = {item.path for item in items if item.get_closest_marker("slow")}
    items.sort(key=lambda item: item.path not in slow_files)  # stable: the order within a group is kept
