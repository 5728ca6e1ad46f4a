"""Speed of the event-driven engine: collisions per second against N, memory, start-up.

For each N (FCC start at packing fraction 0.45, 3D, one core), the script runs
a warm-up of 5 collisions per particle, then times max(5 N, 10^6) pair
collisions. Each N runs in its own process so its peak memory (ru_maxrss)
is its own. It also times the start-up of a small run in a fresh process
with the numba cache warm (the issue asks for < 2 s), and the state point of
DynamO's benchmark (N = 4000, n sigma^3 = 0.5). DynamO itself, and
Smallenburg's C code, run side by side with collisionkit in
``bench_edmd_reference.py`` (DynamO with ``--dynamo``).

Usage: python benchmarks/bench_edmd.py [--sizes 864 4000 32000 256000 1000188] [--shells 0.3 0.5 0.7 0.9]
Writes benchmarks/results/edmd.md and .json.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import resource
import subprocess
import sys
import time
from pathlib import Path

from _bench_common import json_in_fresh_process

from collisionkit._io import atomic_write_text

RESULTS = Path(__file__).parent / "results"


def one_size(particles: int, eta: float, shell: float | None = None) -> dict:
    import numpy as np

    from collisionkit import edmd
    from collisionkit._kernels import edmd as kernels

    cells = round((particles / 4) ** (1 / 3))
    positions, box = edmd.lattice("fcc", cells, eta)
    count = len(positions)
    start = time.perf_counter()
    options = {} if shell is None else {"neighbour_shell": shell}
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(count), 3, seed=1), 0.5, box, **options)
    setup = time.perf_counter() - start
    system.run(collisions=5 * count)
    before = system.acc.copy()
    measured = max(5 * count, 1_000_000)
    start, cpu_start = time.perf_counter(), time.process_time()
    system.run(collisions=measured)
    seconds, cpu_seconds = time.perf_counter() - start, time.process_time() - cpu_start
    delta = system.acc - before
    events = delta[kernels.ACC_EVENTS]
    system.check()
    return {
        "particles": count,
        "shell": float(system.params[kernels.P_SHELL]),
        "packing_fraction": eta,
        "setup_seconds": setup,
        "collisions": measured,
        "seconds": seconds,
        "collisions_per_second": measured / seconds,
        "events_per_second": events / seconds,
        "microseconds_per_collision": 1e6 * seconds / measured,
        "peak_memory_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
        "cpu_seconds": cpu_seconds,
        "list_rebuilds_per_collision": delta[kernels.ACC_LIST_REBUILDS] / measured,
        "stale_events_per_collision": delta[kernels.ACC_STALE_EVENTS] / measured,
        "mean_neighbours": float(system.neighbour_count.mean()),
    }


def time_window(particles: int, eta: float, duration: float) -> dict:
    """Pair collisions and CPU seconds of the simulated-time window [duration, 2 duration] from an FCC start.

    The window of :mod:`bench_edmd_reference`'s C runs (the difference of a
    run to ``duration`` and one to ``2 duration``): the start-up and the
    melting of the crystal are left out alike.
    """
    import numpy as np

    from collisionkit import edmd

    cells = round((particles / 4) ** (1 / 3))
    positions, box = edmd.lattice("fcc", cells, eta)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(len(positions)), 3, seed=1), 0.5, box)
    system.run(time=duration)
    start = time.process_time()
    collisions = system.run(time=duration)
    cpu_seconds = time.process_time() - start
    system.check()
    return {"particles": len(positions), "collisions": collisions, "cpu_seconds": cpu_seconds,
            "peak_memory_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


def in_subprocess(particles: int, eta: float, shell: float | None = None, window: float | None = None) -> dict:
    """:func:`one_size` (or :func:`time_window` if ``window`` is given) in a fresh process."""
    call = f"time_window({particles}, {eta}, {window})" if window is not None else f"one_size({particles}, {eta}, {shell})"
    return json_in_fresh_process("bench_edmd", call)


def start_up_seconds() -> float:
    """Wall time of a fresh process that builds 500 spheres and runs 1000 collisions (cache warm)."""
    code = (
        "import numpy as np; from collisionkit import edmd; p, b = edmd.lattice('fcc', 5, 0.3); "
        "s = edmd.HardSphereSystem(p, edmd.maxwell_boltzmann(np.ones(len(p)), 3, seed=1), 0.5, b); s.run(collisions=1000)"
    )
    subprocess.run([sys.executable, "-c", code], check=True)  # fills the cache if needed
    start = time.perf_counter()
    subprocess.run([sys.executable, "-c", code], check=True)
    return time.perf_counter() - start


def machine() -> str:
    cpu = platform.machine()
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
    return f"{cpu}, Python {platform.python_version()}"


def row_line(row: dict) -> str:
    return (
        f"| {row['particles']:,} | {row['packing_fraction']:.4f} | {row['shell']:.2f} | "
        f"{row['collisions_per_second']:.3g} | {row['collisions'] / row['cpu_seconds']:.3g} | "
        f"{row['events_per_second']:.3g} | {row['microseconds_per_collision']:.2f} | "
        f"{row['list_rebuilds_per_collision']:.3f} | {row['stale_events_per_collision']:.3f} | "
        f"{row['mean_neighbours']:.1f} | {row['peak_memory_mb']:.0f} |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[864, 4000, 32000, 256000, 1000188])
    parser.add_argument("--shells", type=float, nargs="*", default=[0.3, 0.5, 0.7, 0.9],
                        help="neighbour shells to compare at N = 32000 (none: skip)")
    args = parser.parse_args()
    load_before = os.getloadavg()
    rows = [in_subprocess(n, 0.45) for n in args.sizes]
    shells = [in_subprocess(32000, 0.45, shell) for shell in args.shells]
    dynamo_point = in_subprocess(4000, math.pi / 6 * 0.5)
    start_up = start_up_seconds()
    header = [
        "| N | eta | shell | collisions/s | collisions/CPU-s | events/s | us/collision | rebuilds/collision "
        "| stale/collision | neighbours | peak memory (MB) |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    lines = [
        "# EDMD speed (3D hard spheres, one core)",
        "",
        f"Machine: {machine()}; load average {load_before[0]:.2f} before, {os.getloadavg()[0]:.2f} after.",
        "FCC start, 5 collisions per particle of warm-up, then max(5 N, 10^6) collisions timed.",
        "",
        *header,
        *(row_line(row) for row in rows + [dynamo_point]),
    ]
    if shells:
        lines += ["", "Neighbour-list shell (in diameters) at N = 32000:", "", *header, *(row_line(r) for r in shells)]
    lines += [
        "",
        f"DynamO's state point (N = 4000, n sigma^3 = 0.5): {dynamo_point['collisions_per_second']:.3g} collisions/s "
        f"({dynamo_point['events_per_second']:.3g} events/s); DynamO itself runs in bench_edmd_reference.py --dynamo.",
        f"Start-up of a small run in a fresh process, numba cache warm: {start_up:.2f} s.",
    ]
    table = "\n".join(lines) + "\n"
    print(table)
    RESULTS.mkdir(exist_ok=True)
    atomic_write_text(RESULTS / "edmd.md", table)
    payload = {"machine": machine(), "rows": rows, "shells": shells, "dynamo_point": dynamo_point,
               "start_up_seconds": start_up}
    atomic_write_text(RESULTS / "edmd.json", json.dumps(payload, indent=2) + "\n")


if __name__ == "__main__":
    main()
