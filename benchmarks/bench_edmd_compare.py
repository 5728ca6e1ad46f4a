"""A/B timing of the EDMD engine: this checkout against another source tree, alternating child processes.

Each child imports collisionkit from its tree (its own numba cache), starts
from FCC at packing fraction ``--eta``, runs to time L and times the window
[L, 2 L] in CPU time (``bench_edmd.time_window``, the windows of
``bench_edmd_reference.py``). The two trees alternate in each of
``--rounds`` rounds, the first of a round swapped every round; the table
gives the median rate (collisions per CPU second) of each, the median of the
per-round ratios new / old with its range, and the load average at each
round. ``--shell-old`` and ``--shell-new`` set the neighbour shell (in
diameters) of either side (default: the engine's), so one tree can be
timed against itself with two shells.

Usage: python benchmarks/bench_edmd_compare.py --old /tmp/base/src [--new SRC] [--sizes 864 32000] [--rounds 5]
       [--shell-old S] [--shell-new S] [--output edmd_compare]
Writes benchmarks/results/<output>.md and .json.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

from collisionkit._io import atomic_write_text

HERE = Path(__file__).parent
RESULTS = HERE / "results"
NEW_SRC = HERE.parent / "src"


def child(src: Path, cache: Path, particles: int, eta: float, duration: float, shell: float | None) -> dict:
    """One timed window in a fresh process importing collisionkit from ``src``."""
    code = f"""
import json, resource, time
import numpy as np
from collisionkit import edmd
cells = round(({particles} / 4) ** (1 / 3))
positions, box = edmd.lattice("fcc", cells, {eta})
options = {{}} if {shell!r} is None else {{"neighbour_shell": {shell!r}}}
system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(len(positions)), 3, seed=1), 0.5, box, **options)
system.run(time={duration})
start = time.process_time()
collisions = system.run(time={duration})
cpu = time.process_time() - start
system.check()
print(json.dumps({{"collisions": collisions, "cpu_seconds": cpu, "rate": collisions / cpu,
                  "mean_list": float(system.neighbour_count.mean()), "width": system.neighbours.shape[1],
                  "peak_memory_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}}))
"""
    env = {**os.environ, "PYTHONPATH": str(src), "NUMBA_CACHE_DIR": str(cache)}
    output = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True, env=env).stdout
    return json.loads(output.strip().splitlines()[-1])


def spread(values: list[float], digits: int = 3) -> str:
    return f"{statistics.median(values):.{digits}g} ({min(values):.{digits}g}-{max(values):.{digits}g})"


def main() -> None:
    from bench_edmd_reference import STATE_POINTS

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--old", type=Path, required=True, help="the src folder of the tree to compare with")
    parser.add_argument("--new", type=Path, default=NEW_SRC, help="the src folder of the new tree (default: this one)")
    parser.add_argument("--sizes", type=int, nargs="+", default=[864, 32000])
    parser.add_argument("--eta", type=float, default=0.45)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--window", type=float, default=None, help="simulated-time window L (default: the state point's)")
    parser.add_argument("--shell-old", type=float, default=None)
    parser.add_argument("--shell-new", type=float, default=None)
    parser.add_argument("--output", default="edmd_compare")
    args = parser.parse_args()
    cache = Path(os.environ.get("NUMBA_CACHE_DIR", ".numba_cache")).resolve()
    caches = {"old": cache / "compare_old", "new": cache / "compare_new"}
    sources = {"old": args.old.resolve(), "new": args.new.resolve()}
    shells = {"old": args.shell_old, "new": args.shell_new}
    rows = []
    for size in args.sizes:
        particles, _, duration = STATE_POINTS[size]
        duration = args.window or duration
        runs = {"old": [], "new": []}
        loads = []
        for k in range(args.rounds):
            loads.append(os.getloadavg()[0])
            for side in (("old", "new") if k % 2 == 0 else ("new", "old")):
                runs[side].append(child(sources[side], caches[side], particles, args.eta, duration, shells[side]))
            print(f"N {particles} round {k}: old {runs['old'][-1]['rate']:.4g}/s new {runs['new'][-1]['rate']:.4g}/s "
                  f"ratio {runs['new'][-1]['rate'] / runs['old'][-1]['rate']:.3f} load {loads[-1]:.2f}", flush=True)
        ratios = [n["rate"] / o["rate"] for n, o in zip(runs["new"], runs["old"])]
        rows.append({"particles": particles, "window": duration, "runs": runs, "ratios": ratios, "loads": loads})
    command = "python benchmarks/bench_edmd_compare.py " + " ".join(sys.argv[1:])
    lines = [
        f"# EDMD A/B: {args.new} (new) against {args.old} (old)",
        "",
        f"Command: `{command}`; eta {args.eta}, shells old {args.shell_old or 'default'} / new "
        f"{args.shell_new or 'default'}; {args.rounds} rounds of alternating child processes, CPU time of the window "
        "[L, 2 L] from an FCC start.",
        "",
        "| N (L) | old collisions/CPU-s | new collisions/CPU-s | new / old: median (range) | load averages | mean list old / new |",
        "|---|---|---|---|---|---|",
    ]
    for row in rows:
        lines.append(
            f"| {row['particles']:,} ({row['window']:g}) | {spread([r['rate'] for r in row['runs']['old']])} | "
            f"{spread([r['rate'] for r in row['runs']['new']])} | {spread(row['ratios'])} | "
            f"{min(row['loads']):.2f}-{max(row['loads']):.2f} | {row['runs']['old'][0]['mean_list']:.2f} / "
            f"{row['runs']['new'][0]['mean_list']:.2f} |"
        )
    text = "\n".join(lines) + "\n"
    print(text)
    RESULTS.mkdir(exist_ok=True)
    atomic_write_text(RESULTS / f"{args.output}.md", text)
    atomic_write_text(RESULTS / f"{args.output}.json", json.dumps({"rows": rows}, indent=2) + "\n")


if __name__ == "__main__":
    main()
