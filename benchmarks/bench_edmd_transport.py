"""Cost of the transport measurement: collisions per second of plain and --transport runs, alternating.

Every pair collision adds its momentum and energy transfer to the transport
sums of the event loop, whether or not transport is measured; a transport
measurement also runs each block in stretches of a quarter of a mean free
time, sampling the Helfand moments and the velocities at each. The issue
allows at most 25 % fewer collisions per second than a plain run.

For each N (FCC start, 3D, one core): 20 collisions per particle of warm-up,
then ``--repeats`` pairs of measurements of ``--per-particle`` collisions
each (10 blocks), plain and with transport alternating in one process (a
load that changes during the benchmark hits both alike); the rate is
collisions per CPU second of the blocks (events and sampling; no compiling,
no final analysis), steadier than the wall clock on a shared machine. With ``--baseline
SRC`` (another checkout's ``src``, e.g. the engine before the transport
sums) the plain rate of that engine is measured too, in alternating
subprocesses with this one's: the cost of the sums in the event loop alone.

Usage: python benchmarks/bench_edmd_transport.py [--sizes 1372 4000 32000] [--density 0.5] [--baseline SRC]
Writes benchmarks/results/edmd_transport.md and .json.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

from collisionkit._io import atomic_write_text

RESULTS = Path(__file__).parent / "results"
SRC = Path(__file__).resolve().parents[1] / "src"


def alternating(particles: int, density: float, per_particle: int, repeats: int) -> dict:
    """Collisions per second of plain and transport measurements of one system, alternating."""
    import math

    import numpy as np

    from collisionkit import edmd

    cells = round((particles / 4) ** (1 / 3))
    positions, box = edmd.lattice("fcc", cells, math.pi / 6 * density)
    count = len(positions)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(count), 3, seed=1), 0.5, box)
    system.run(collisions=20 * count)
    edmd.measure(system, collisions=2 * count, blocks=2, transport=True)  # compiles everything once
    rates = {"plain": [], "transport": []}
    for _ in range(repeats):
        for mode in rates:
            sampler = edmd.Sampler(system, per_particle * count, 10, transport=mode == "transport")
            start = time.process_time()
            while not sampler.finished:
                sampler.run_block()
            rates[mode].append(per_particle * count / (time.process_time() - start))
    return {"particles": count, "density": density, "plain": rates["plain"], "transport": rates["transport"]}


def plain_rate(src: Path, particles: int, density: float, per_particle: int) -> float:
    """The plain measurement's collisions per second of the engine in ``src``, in a fresh process."""
    code = (
        "import json, math, numpy as np\n"
        "from collisionkit import edmd\n"
        f"positions, box = edmd.lattice('fcc', round(({particles} / 4) ** (1 / 3)), math.pi / 6 * {density})\n"
        "n = len(positions)\n"
        "s = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(n), 3, seed=1), 0.5, box)\n"
        "s.run(collisions=20 * n)\n"
        "edmd.measure(s, collisions=2 * n, blocks=2)\n"
        f"print(json.dumps(edmd.measure(s, collisions={per_particle} * n, blocks=10).collisions_per_second))\n"
    )
    env = dict(os.environ, PYTHONPATH=str(src))  # numba keeps the two checkouts' kernels apart by their paths
    output = subprocess.run([sys.executable, "-c", code], env=env, check=True, capture_output=True, text=True).stdout
    return float(output.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1372, 4000, 32000])
    parser.add_argument("--density", type=float, default=0.5)
    parser.add_argument("--per-particle", type=int, default=100)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--baseline", type=Path, default=None, help="src folder of the engine to compare with")
    args = parser.parse_args()
    load_before = os.getloadavg()[0]
    rows = [alternating(size, args.density, args.per_particle, args.repeats) for size in args.sizes]
    lines = [
        "# Cost of the transport measurement (3D hard spheres, one core)",
        "",
        f"Load average {load_before:.2f} before, {os.getloadavg()[0]:.2f} after (a shared machine: alternating runs).",
        f"FCC start at n sigma^3 = {args.density}, 20 collisions per particle of warm-up, then {args.repeats} pairs "
        f"of measurements of {args.per_particle} collisions per particle (10 blocks), plain and --transport "
        "alternating; medians of collisions per CPU second of the blocks.",
        "",
        "| N | plain collisions/CPU-s | --transport collisions/CPU-s | cost |",
        "|---|---|---|---|",
    ]
    for row in rows:
        plain, transport = statistics.median(row["plain"]), statistics.median(row["transport"])
        row["cost"] = 1.0 - transport / plain
        lines.append(f"| {row['particles']:,} | {plain:.3g} | {transport:.3g} | {100 * row['cost']:.0f} % |")
    if args.baseline is not None:
        lines += ["", f"The transport sums in the event loop: plain runs of this engine and of {args.baseline} "
                  "(fresh processes, alternating; medians).", "",
                  "| N | baseline collisions/s | this engine collisions/s | cost |", "|---|---|---|---|"]
        for row in rows:
            baseline, current = [], []
            for _ in range(args.repeats):
                baseline.append(plain_rate(args.baseline.resolve(), row["particles"], args.density, args.per_particle))
                current.append(plain_rate(SRC, row["particles"], args.density, args.per_particle))
            row["baseline"], row["current"] = baseline, current
            cost = 1.0 - statistics.median(current) / statistics.median(baseline)
            lines.append(f"| {row['particles']:,} | {statistics.median(baseline):.3g} | "
                         f"{statistics.median(current):.3g} | {100 * cost:.0f} % |")
    table = "\n".join(lines) + "\n"
    print(table)
    RESULTS.mkdir(exist_ok=True)
    atomic_write_text(RESULTS / "edmd_transport.md", table)
    atomic_write_text(RESULTS / "edmd_transport.json", json.dumps({"rows": rows, "arguments": {
        key: str(value) for key, value in vars(args).items()}}, indent=2) + "\n")


if __name__ == "__main__":
    main()
