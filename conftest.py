"""Settings for every test, the doctests of src/collisionkit included."""

import fcntl
import os
import sys

import pytest
from numba.core import caching

_save_cache_entry = caching.IndexDataCacheFile.save


def _save_cache_entry_under_a_lock(self, key, data):
    """numba's cache save, one process at a time per cache folder (the tests run in parallel, pytest-xdist).

    numba reads a function's cache index, picks the first free data-file name
    for a new signature and writes the index back, unlocked: two workers that
    compile two signatures of one kernel at once could both pick
    ``name.1.nbc`` (one index entry then points at the other's machine code)
    or drop each other's index entries. The lock makes that read-pick-write
    one step; a save takes milliseconds, compiling seconds.
    """
    with open(os.path.join(self._cache_path, ".collisionkit-tests.lock"), "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        return _save_cache_entry(self, key, data)


caching.IndexDataCacheFile.save = _save_cache_entry_under_a_lock


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
