"""Square-well EDMD speed against DynamO, run side by side on this machine.

DynamO (https://github.com/dynamomd/DynamO: Bannerman, Sargant & Lue,
J. Comput. Chem. 32, 3329 (2011)) is the event-driven code soft-matter users
pick for square wells. It is not on PyPI or in Debian and is not vendored
here: build it from source (cmake >= 3.28, Boost and Eigen from Debian, its
``stator`` submodule checked out; ``-DCMAKE_BUILD_TYPE=Release
-DVISUALIZER_ENABLED=OFF``) and pass the folder holding ``dynamod`` and
``dynarun`` with ``--dynamo``.

Both codes start from the same state: an FCC crystal of N = 4 C^3 particles
at n sigma^3 = ``--density``, wells of width lambda sigma = ``--width`` and
depth epsilon = 1, velocities at kT = 1 (``dynamod -m 1``), and run at
constant energy (no thermostat) over the same simulated-time window [L, 2 L]:
the crystal melts and cools in [0, L] alike, and the window's rate is the
difference of two runs (to L and to 2 L) for DynamO, a timed run from L to
2 L for collisionkit. Events are every pair event: core collisions, captures
into a well, escapes from it and bounces off its edge (DynamO's
``TwoParticleEvents``: CORE + STEP_IN + STEP_OUT + BOUNCE). CPU time is the
child's own (``os.wait4``) for DynamO and ``time.process_time`` for
collisionkit, run in a fresh process after a first run that fills numba's
cache. The two codes alternate in ``--pairs`` pairs per size; the table gives
the median ratio of the rates with its range, and the temperature at the end
of each code's window (the same state point reached, not only the same speed).

Usage: python benchmarks/bench_edmd_wells.py --dynamo PATH/TO/BUILD [--cells 7 14] [--pairs 5]
Writes benchmarks/results/edmd_wells_dynamo.md and .json.
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from xml.etree import ElementTree

sys.path.insert(0, str(Path(__file__).parent))
import bench_edmd  # noqa: E402  (machine description)
from _bench_common import json_in_fresh_process, write_results  # noqa: E402

# simulated-time window L per FCC size C at n sigma^3 = 0.5: about 1e6 pair events in [L, 2 L]
WINDOWS = {7: 50.0, 10: 17.0, 14: 6.0}


def time_window(cells: int, density: float, width: float, duration: float) -> dict:
    """Pair events (collisions, captures, escapes, bounces) and CPU seconds of collisionkit over [L, 2 L]."""
    import numpy as np

    from collisionkit import edmd

    eta = math.pi * density / 6.0
    positions, box = edmd.lattice("fcc", cells, eta)
    velocities = edmd.maxwell_boltzmann(np.ones(len(positions)), 3, seed=1)
    system = edmd.HardSphereSystem(positions, velocities, 0.5, box, well_width=width, well_depth=1.0)
    system.run(time=duration)
    before = system.collisions + sum(system.well_events.values())
    start = time.process_time()
    system.run(time=duration)
    cpu_seconds = time.process_time() - start
    events = system.collisions + sum(system.well_events.values()) - before
    system.check()
    kinetic = 0.5 * float(np.sum(system.velocities() ** 2))
    return {"particles": len(positions), "events": events, "cpu_seconds": cpu_seconds,
            "rate": events / cpu_seconds, "temperature": 2.0 * kinetic / (3.0 * len(positions))}


def dynamo_start(dynamo: Path, folder: Path, cells: int, density: float, width: float) -> Path:
    """DynamO's square-well FCC start (``dynamod -m 1``): its config file."""
    folder.mkdir(parents=True, exist_ok=True)
    config = folder / "config.start.xml"
    subprocess.run([str(dynamo / "dynamod"), "-m", "1", "-C", str(cells), "-d", repr(density), "--f1", repr(width),
                    "--f2", "1.0", "-o", str(config)], cwd=folder, check=True, capture_output=True)
    return config


def run_dynamo(dynamo: Path, config: Path, duration: float) -> dict:
    """Pair events, CPU seconds, end temperature and simulated time of one ``dynarun`` to time ``duration``."""
    folder = config.parent
    command = [str(dynamo / "dynarun"), str(config), "-f", repr(duration), "--out-data-file", "output.xml",
               "-o", "config.end.xml"]
    child = subprocess.Popen(command, cwd=folder, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(child.pid, 0)
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"{' '.join(command)} failed with exit code {os.waitstatus_to_exitcode(status)}")
    root = ElementTree.parse(folder / "output.xml").getroot()
    duration_tag = root.find(".//Duration")
    return {"events": int(duration_tag.get("TwoParticleEvents")), "cpu_seconds": usage.ru_utime + usage.ru_stime,
            "time": float(duration_tag.get("Time")),
            "temperature": float(root.find(".//Temperature").get("Current"))}


def dynamo_rate(dynamo: Path, config: Path, duration: float) -> dict:
    """Pair events per CPU second of DynamO over the window [duration, 2 duration]."""
    short = run_dynamo(dynamo, config, duration)
    long = run_dynamo(dynamo, config, 2 * duration)
    events = long["events"] - short["events"]
    cpu_seconds = long["cpu_seconds"] - short["cpu_seconds"]
    return {"events": events, "cpu_seconds": cpu_seconds, "rate": events / cpu_seconds,
            "temperature": long["temperature"], "simulated_time": [short["time"], long["time"]]}


def measure(dynamo: Path, scratch: Path, cells: int, density: float, width: float, pairs: int) -> dict:
    duration = WINDOWS.get(cells, 50.0 * (7 / cells) ** 3)
    config = dynamo_start(dynamo, scratch / f"dynamo_{cells}", cells, density, width)
    call = f"time_window({cells}, {density!r}, {width!r}, {{}})"
    json_in_fresh_process("bench_edmd_wells", call.format(duration / 50))  # fills numba's cache
    theirs, ours, loads = [], [], []
    for _ in range(pairs):
        loads.append(os.getloadavg()[0])
        theirs.append(dynamo_rate(dynamo, config, duration))
        ours.append(json_in_fresh_process("bench_edmd_wells", call.format(duration)))
        print(f"  C {cells}: DynamO {theirs[-1]['rate']:.3g}/s ({theirs[-1]['events']} events), collisionkit "
              f"{ours[-1]['rate']:.3g}/s ({ours[-1]['events']}), ratio {ours[-1]['rate'] / theirs[-1]['rate']:.2f}",
              flush=True)
    return {"particles": 4 * cells**3, "cells": cells, "density": density, "width": width, "window": duration,
            "dynamo": theirs, "collisionkit": ours, "ratios": [a["rate"] / b["rate"] for a, b in zip(ours, theirs)],
            "load_averages": loads}


def spread(values: list[float]) -> str:
    return f"{statistics.median(values):.2f} ({min(values):.2f}-{max(values):.2f})"


def table(rows: list[dict], load_before: float, load_after: float) -> str:
    lines = [
        "# Square-well EDMD speed against DynamO (one core, CPU time)",
        "",
        f"Machine: {bench_edmd.machine()}; load average {load_before:.2f} before, {load_after:.2f} after. "
        "FCC start at kT = 1, depth 1, no thermostat; pair events (collisions, captures, escapes, bounces) per CPU "
        "second over the same simulated-time window [L, 2 L], alternating runs; kT: at the end of the window "
        "(median over the runs).",
        "",
        "| N | n sigma^3 | lambda | L | pairs | DynamO events/CPU-s | collisionkit events/CPU-s "
        "| ratio: median (range) | kT at 2 L DynamO / collisionkit |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for row in rows:
        lines.append(
            f"| {row['particles']:,} | {row['density']:g} | {row['width']:g} | {row['window']:g} | "
            f"{len(row['ratios'])} | {statistics.median(r['rate'] for r in row['dynamo']):.3g} | "
            f"{statistics.median(r['rate'] for r in row['collisionkit']):.3g} | {spread(row['ratios'])} | "
            f"{statistics.median(r['temperature'] for r in row['dynamo']):.3f} / "
            f"{statistics.median(r['temperature'] for r in row['collisionkit']):.3f} |"
        )
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dynamo", type=Path, required=True, help="a folder holding DynamO's dynamod and dynarun")
    parser.add_argument("--cells", type=int, nargs="+", default=[7, 14], help="FCC cells a side (N = 4 C^3)")
    parser.add_argument("--density", type=float, default=0.5, help="number density n sigma^3")
    parser.add_argument("--width", type=float, default=1.5, help="well width lambda (outer radius / sigma)")
    parser.add_argument("--pairs", type=int, default=5, help="alternating runs of the two codes per size")
    parser.add_argument("--output", default="edmd_wells_dynamo", help="stem of the result files in benchmarks/results")
    args = parser.parse_args()
    if args.pairs < 1:
        raise SystemExit(f"--pairs must be >= 1; got {args.pairs}")
    if not (args.dynamo / "dynarun").exists():
        raise SystemExit(f"--dynamo must hold dynamod and dynarun; got {args.dynamo}")
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as scratch:
        rows = [measure(args.dynamo, Path(scratch), cells, args.density, args.width, args.pairs) for cells in args.cells]
    text = table(rows, load_before, os.getloadavg()[0])
    write_results(args.output, text, {"machine": bench_edmd.machine(), "rows": rows})


if __name__ == "__main__":
    main()
