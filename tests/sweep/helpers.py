"""Shared studies and helpers of the sweep tests (a real LocalCluster fixture, deadlines, tables)."""

from __future__ import annotations

import contextlib
import csv
import json
import os
import signal
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

from collisionkit import sweep

# 108 spheres, a few thousand collisions: well under a second per point once compiled
SMALL_EDMD = {
    "command": "edmd",
    "seed": 11,
    "replicas": 2,
    "fixed": {"particles": 108, "equilibration": 2000, "collisions": 3000, "blocks": 3},
    "vary": {"packing-fraction": [0.1, 0.2, 0.3]},
}
ENCOUNTERS = {"command": "encounter", "seed": 5, "replicas": 2, "fixed": {"rp": 1.0}, "vary": {"vinf": [0.5, 1.0, 2.0]}}
WALL_CLOCK_COLUMNS = {"elapsed", "collisions_per_second"}


@contextlib.contextmanager
def deadline(seconds: float):
    """Fail (TimeoutError) instead of hanging if the block takes longer than ``seconds``."""

    def expire(signum, frame):
        raise TimeoutError(f"test block took longer than {seconds} s")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def read_table(path: Path) -> list[dict[str, str]]:
    with open(path, newline="") as stream:
        return list(csv.DictReader(stream))


def physics_columns(rows: list[dict[str, str]]) -> list[dict[str, str]]:
    """The table without wall-clock columns (text of floats: equal text is equal numbers)."""
    return [{key: value for key, value in row.items() if key not in WALL_CLOCK_COLUMNS} for row in rows]


def serial_run(study, out: Path):
    with ThreadPoolExecutor(1) as pool:
        return sweep.run_study(study, out, executor=pool)


@pytest.fixture(scope="module")
def dask_client():
    """A real LocalCluster of two worker processes (one thread each), shut down after the module."""
    import distributed

    with deadline(120):
        cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0")
        client = distributed.Client(cluster)
    try:
        yield client
    finally:
        with deadline(60):
            client.close()
            cluster.close()


