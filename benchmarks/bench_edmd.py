"""Speed of the event-driven engine: collisions per second against N, memory, start-up.

For each N (FCC start at packing fraction 0.45, 3D, one core), the script runs
a warm-up of 5 collisions per particle, then times max(5 N, 10^6) pair
collisions. Each N runs in its own process so its peak memory (ru_maxrss)
is its own. It also times the start-up of a small run in a fresh process
with the numba cache warm (the issue asks for < 2 s), and the state point of
the DynamO comparison (N = 4000, n sigma^3 = 0.5).

DynamO itself is neither on PyPI nor in Debian, so it is not run here; the
table quotes the issue's figure for it (0.15 M events/s) and says so.

Usage: python benchmarks/bench_edmd.py [--sizes 864 4000 32000 256000 1000188]
Writes benchmarks/results/edmd.md and .json.
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import resource
import subprocess
import sys
import time
from pathlib import Path

RESULTS = Path(__file__).parent / "results"
DYNAMO_QUOTED_EVENTS_PER_SECOND = 0.15e6


def one_size(particles: int, eta: float) -> dict:
    import numpy as np

    from collisionkit import edmd
    from collisionkit._kernels import edmd as kernels

    cells = round((particles / 4) ** (1 / 3))
    positions, box = edmd.lattice("fcc", cells, eta)
    count = len(positions)
    start = time.perf_counter()
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(count), 3, rng=1), 0.5, box)
    setup = time.perf_counter() - start
    system.run(collisions=5 * count)
    before = system.acc.copy()
    measured = max(5 * count, 1_000_000)
    start = time.perf_counter()
    system.run(collisions=measured)
    seconds = time.perf_counter() - start
    delta = system.acc - before
    events = delta[kernels.ACC_PAIR_COLLISIONS] + delta[kernels.ACC_CELL_CROSSINGS] + delta[kernels.ACC_STALE_EVENTS]
    system.check()
    return {
        "particles": count,
        "packing_fraction": eta,
        "setup_seconds": setup,
        "collisions": measured,
        "seconds": seconds,
        "collisions_per_second": measured / seconds,
        "events_per_second": events / seconds,
        "microseconds_per_collision": 1e6 * seconds / measured,
        "peak_memory_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    }


def in_subprocess(particles: int, eta: float) -> dict:
    code = f"import json, sys; sys.path.insert(0, {str(Path(__file__).parent)!r}); import bench_edmd; print(json.dumps(bench_edmd.one_size({particles}, {eta})))"
    output = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True).stdout
    return json.loads(output.strip().splitlines()[-1])


def start_up_seconds() -> float:
    """Wall time of a fresh process that builds 500 spheres and runs 1000 collisions (cache warm)."""
    code = (
        "import numpy as np; from collisionkit import edmd; p, b = edmd.lattice('fcc', 5, 0.3); "
        "s = edmd.HardSphereSystem(p, edmd.maxwell_boltzmann(np.ones(len(p)), 3, rng=1), 0.5, b); s.run(collisions=1000)"
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[864, 4000, 32000, 256000, 1000188])
    args = parser.parse_args()
    rows = [in_subprocess(n, 0.45) for n in args.sizes]
    dynamo_point = in_subprocess(4000, math.pi / 6 * 0.5)
    start_up = start_up_seconds()
    lines = [
        "# EDMD speed (3D hard spheres, one core)",
        "",
        f"Machine: {machine()}.",
        "",
        "| N | eta | collisions/s | events/s | us/collision | peak memory (MB) |",
        "|---|---|---|---|---|---|",
    ]
    for row in rows + [dynamo_point]:
        lines.append(
            f"| {row['particles']:,} | {row['packing_fraction']:.4f} | {row['collisions_per_second']:.3g} | "
            f"{row['events_per_second']:.3g} | {row['microseconds_per_collision']:.2f} | {row['peak_memory_mb']:.0f} |"
        )
    ratio = dynamo_point["events_per_second"] / DYNAMO_QUOTED_EVENTS_PER_SECOND
    lines += [
        "",
        f"DynamO state point (N = 4000, n sigma^3 = 0.5): {dynamo_point['events_per_second']:.3g} events/s, "
        f"{ratio:.2f} x the 0.15 M events/s quoted for DynamO (DynamO not run here: not on PyPI or Debian).",
        f"Start-up of a small run in a fresh process, numba cache warm: {start_up:.2f} s.",
    ]
    table = "\n".join(lines) + "\n"
    print(table)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "edmd.md").write_text(table)
    payload = {"machine": machine(), "rows": rows, "dynamo_point": dynamo_point, "start_up_seconds": start_up}
    (RESULTS / "edmd.json").write_text(json.dumps(payload, indent=2) + "\n")


if __name__ == "__main__":
    main()
