"""Shared test settings: hypothesis profiles and helpers."""

import os

from hypothesis import HealthCheck, settings

settings.register_profile("default", deadline=None, max_examples=200, suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("ci", parent=settings.get_profile("default"), max_examples=400, derandomize=True)
settings.load_profile("ci" if os.environ.get("CI") else "default")
