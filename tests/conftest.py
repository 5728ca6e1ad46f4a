"""Shared test settings: hypothesis profiles and helpers."""

import os

import pytest
from hypothesis import HealthCheck, settings

settings.register_profile("default", deadline=None, max_examples=200, suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("ci", parent=settings.get_profile("default"), max_examples=400, derandomize=True)
settings.load_profile("ci" if os.environ.get("CI") else "default")


def _approx_without_a_silent_floor(expected, rel=None, abs=None, nan_ok=False):
    """pytest.approx with no absolute tolerance unless a test asks for one.

    pytest's default ``abs=1e-12`` accepts *any* value below 1e-12: a test of
    a 2.3e-28 J m Coulomb strength at ``rel=1e-8`` passed with a factor-2
    error. Here ``abs`` is 0 unless given (``rel`` keeps pytest's 1e-6
    default), so a comparison near zero must state its absolute tolerance.
    """
    if abs is None:
        abs = 0.0
        rel = 1e-6 if rel is None else rel
    return _pytest_approx(expected, rel=rel, abs=abs, nan_ok=nan_ok)


_pytest_approx = pytest.approx
pytest.approx = _approx_without_a_silent_floor


@pytest.fixture(autouse=True)
def _an_empty_gas_data_folder(tmp_path_factory, monkeypatch):
    """Every test sees an empty data folder of placed cross-section files, not the user's own (COLLISIONKIT_DATA)."""
    monkeypatch.setenv("COLLISIONKIT_DATA", str(tmp_path_factory.mktemp("collisionkit-data")))
