"""Settings for every test, the doctests of src/collisionkit included."""

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
