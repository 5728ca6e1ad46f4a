"""Settings for every test, the doctests of src/collisionkit included.

The test workers (pytest-xdist) share one numba cache: collisionkit's kernels compile one process at a time
(:func:`collisionkit._jit.compile_lock_path`), so two workers never compile the same kernel at once.
"""

import sys

import pytest


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
