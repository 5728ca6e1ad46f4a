"""Scaling of ``collisionkit sweep``: a study of 32 EDMD points on 1 and on 2 dask workers.

For each worker count the script starts an embedded LocalCluster (one
process per worker, one thread each), warms every worker up (imports and
the numba cache, as the first point of any study would) and then times
:func:`collisionkit.sweep.run_study` on a fresh folder:

* speed-up = wall time on 1 worker / wall time on 2 workers (target >= 1.8);
* overhead per point = (wall time x workers - sum of the points' own run
  times) / points: everything the sweep adds (scheduling, transfers,
  result files, the table and the plot), target < 0.2 s;
* the same overhead measured directly on 32 trivially short points
  (``encounter``, a few ms each) on 1 worker;
* the cores the workers actually obtained (CPU time of the points / wall
  time), since on a shared machine other work competes for the cores.

The cluster start-up (a few seconds, once per study) is reported apart.
Both worker counts must give the same table (checked).

Usage: python benchmarks/bench_sweep.py [--particles 500] [--collisions 30000]
Writes benchmarks/results/sweep.md.
"""

from __future__ import annotations

import argparse
import csv
import os
import platform
import tempfile
import time
from pathlib import Path

from collisionkit import sweep

RESULTS = Path(__file__).parent / "results"
POINTS = 32
WALL_CLOCK_COLUMNS = {"elapsed", "collisions_per_second"}


def edmd_study(particles: int, collisions: int) -> dict:
    """8 packing fractions x 4 replicas = 32 EDMD points."""
    return {
        "command": "edmd",
        "seed": 2026,
        "replicas": 4,
        "fixed": {"dim": 3, "particles": particles, "equilibration": 10 * particles, "collisions": collisions},
        "vary": {"packing-fraction": {"start": 0.05, "stop": 0.40, "num": 8}},
    }


def trivial_study() -> dict:
    """32 encounter set-ups of a few milliseconds each."""
    return {"command": "encounter", "seed": 1, "replicas": 2, "vary": {"vinf": {"start": 0.1, "stop": 1.6, "num": 16}}}


def _warm_up() -> None:
    """Import the CLI and load the compiled kernels, as a worker's first point does."""
    with tempfile.TemporaryDirectory() as folder:
        study = sweep.study_from_dict(
            {"command": "edmd", "seed": 0, "fixed": {"particles": 32, "collisions": 200}, "vary": {"dim": [2, 3]}}
        )
        for task in sweep.point_tasks(study, folder):
            sweep.run_point(task)


def timed_study(study: dict, workers: int, folder: Path) -> dict:
    started = time.perf_counter()
    with sweep.local_client(workers) as client:
        client.run(_warm_up)
        ready = time.perf_counter()
        results = sweep.run_study(study, folder, executor=client)
        wall = time.perf_counter() - ready
    if results.failed:
        raise RuntimeError(f"{len(results.failed)} points failed: {results.failed[0]['error']}")
    compute = sum(record["elapsed"] for record in results.records)
    cpu = sum(record["cpu_time"] for record in results.records)
    points = len(results.records)
    return {
        "workers": workers,
        "points": points,
        "startup": ready - started,
        "wall": wall,
        "compute": compute,
        "overhead_per_point": (wall * workers - compute) / points,
        "cpu": cpu,
        "cores_used": cpu / wall,
        "table": folder / "results.csv",
    }


def physics(path: Path) -> list[dict]:
    with open(path, newline="") as stream:
        return [{key: value for key, value in row.items() if key not in WALL_CLOCK_COLUMNS} for row in csv.DictReader(stream)]


def report(edmd_runs: list[dict], trivial: dict, arguments, same_table: bool, load_before: float) -> str:
    one, two = edmd_runs
    speedup = one["wall"] / two["wall"]
    lines = [
        "# Sweep scaling (collisionkit sweep on an embedded dask LocalCluster)",
        "",
        f"Machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores (shared with other work), "
        f"Python {platform.python_version()}.",
        f"Study: {POINTS} EDMD points (8 packing fractions 0.05-0.40 x 4 replicas), {arguments.particles} hard spheres, "
        f"{10 * arguments.particles} + {arguments.collisions} collisions each.",
        "",
        "| workers | points | wall (s) | sum of point run times (s) | their CPU time (s) | cores obtained | overhead per point (s) | cluster start-up (s) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for run in (*edmd_runs, trivial):
        lines.append(
            f"| {run['workers']}{' (trivial points)' if run is trivial else ''} | {run['points']} | {run['wall']:.2f} | "
            f"{run['compute']:.2f} | {run['cpu']:.2f} | {run['cores_used']:.2f} | {run['overhead_per_point']:.3f} | "
            f"{run['startup']:.1f} |"
        )
    lines += [
        "",
        f"Speed-up 2 workers vs 1: **{speedup:.2f}x** (target >= 1.8).",
        f"Cores the workers obtained (CPU time of the points / wall time): {one['cores_used']:.2f} on 1 worker, "
        f"{two['cores_used']:.2f} on 2; CPU time of the 32 points {one['cpu']:.1f} s vs {two['cpu']:.1f} s. "
        f"Speed-up per core obtained: {speedup / (two['cores_used'] / one['cores_used']):.2f}.",
        f"Load average (1 min) before the runs, from other work on the machine: {load_before:.2f}.",
        f"Overhead per point: {one['overhead_per_point']:.3f} s (1 worker), {two['overhead_per_point']:.3f} s (2 workers), "
        f"{trivial['overhead_per_point']:.3f} s on trivially short points (target < 0.2 s).",
        f"Same table on 1 and 2 workers (wall-clock columns aside): {'yes' if same_table else 'NO'}.",
        "",
        "Overhead = (wall x workers - sum of the points' own run times) / points; it includes scheduling, the",
        "result files, results.csv and the plot. Cluster start-up and worker warm-up (imports, numba cache) are",
        "once per study and not in the wall time.",
        "",
        f"Command: `NUMBA_CACHE_DIR=.numba_cache python benchmarks/bench_sweep.py --particles {arguments.particles} "
        f"--collisions {arguments.collisions}`",
    ]
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--particles", type=int, default=500)
    parser.add_argument("--collisions", type=int, default=30_000)
    arguments = parser.parse_args()
    study = edmd_study(arguments.particles, arguments.collisions)
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as folder:
        runs = [timed_study(study, workers, Path(folder) / f"edmd-{workers}") for workers in (1, 2)]
        same_table = physics(runs[0]["table"]) == physics(runs[1]["table"])
        trivial = timed_study(trivial_study(), 1, Path(folder) / "trivial")
    text = report(runs, trivial, arguments, same_table, load_before)
    RESULTS.mkdir(exist_ok=True)
    from collisionkit._io import atomic_write_text

    atomic_write_text(RESULTS / "sweep.md", text)
    print(text)


if __name__ == "__main__":
    main()
