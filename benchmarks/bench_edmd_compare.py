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

With ``--collisions`` a child times as ``bench_edmd.one_size`` does
instead: 5 N collisions of warm-up, then max(5 N, 10^6) collisions; with
``--sort`` too it renumbers the particles in memory (``_sort_by_cell``, each
tree its own way) after the warm-up, so both sides are timed in the order a
long run keeps (a run re-sorts every ``SORT_INTERVAL`` N collisions, and
one_size's 10 N of N >= 10^5 hold none, so it times the lattice's order).
Any N is then allowed (FCC: 4 cells^3), with the packing fraction ``--eta``.

Usage: python benchmarks/bench_edmd_compare.py --old /tmp/base/src [--new SRC] [--sizes 864 32000] [--rounds 5]
       [--shell-old S] [--shell-new S] [--collisions [--sort]] [--output edmd_compare]
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

from _bench_common import write_results

HERE = Path(__file__).parent
NEW_SRC = HERE.parent / "src"


def child(src: Path, cache: Path, particles: int, eta: float, duration: float | None, shell: float | None,
          sort: bool = False) -> dict:
    """One timed window (or, if ``duration`` is None, one_size's collisions) in a fresh process importing ``src``."""
    if duration is None:
        timed = f"""
system.run(collisions=5 * system.count)
if {sort!r}:
    system._sort_by_cell()
start = time.process_time()
collisions = system.run(collisions=max(5 * system.count, 1_000_000))
cpu = time.process_time() - start"""
    else:
        timed = f"""
system.run(time={duration})
start = time.process_time()
collisions = system.run(time={duration})
cpu = time.process_time() - start"""
    code = f"""
import json, resource, time
import numpy as np
from collisionkit import edmd
cells = round(({particles} / 4) ** (1 / 3))
positions, box = edmd.lattice("fcc", cells, {eta})
options = {{}} if {shell!r} is None else {{"neighbour_shell": {shell!r}}}
system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(len(positions)), 3, seed=1), 0.5, box, **options)
{timed}
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
    parser.add_argument("--collisions", action="store_true", help="time as bench_edmd.one_size (not a time window)")
    parser.add_argument("--sort", action="store_true", help="with --collisions: re-sort the memory order first")
    parser.add_argument("--output", default="edmd_compare")
    args = parser.parse_args()
    cache = Path(os.environ.get("NUMBA_CACHE_DIR", ".numba_cache")).resolve()
    caches = {"old": cache / "compare_old", "new": cache / "compare_new"}
    sources = {"old": args.old.resolve(), "new": args.new.resolve()}
    shells = {"old": args.shell_old, "new": args.shell_new}
    rows = []
    for size in args.sizes:
        if args.collisions:
            particles, duration = size, None
        else:
            particles, _, duration = STATE_POINTS[size]
            duration = args.window or duration
        runs = {"old": [], "new": []}
        loads = []
        for k in range(args.rounds):
            loads.append(os.getloadavg()[0])
            for side in (("old", "new") if k % 2 == 0 else ("new", "old")):
                runs[side].append(child(sources[side], caches[side], particles, args.eta, duration, shells[side],
                                        args.sort))
            print(f"N {particles} round {k}: old {runs['old'][-1]['rate']:.4g}/s new {runs['new'][-1]['rate']:.4g}/s "
                  f"ratio {runs['new'][-1]['rate'] / runs['old'][-1]['rate']:.3f} load {loads[-1]:.2f} "
                  f"memory {runs['old'][-1]['peak_memory_mb']:.0f} / {runs['new'][-1]['peak_memory_mb']:.0f} MB",
                  flush=True)
        ratios = [n["rate"] / o["rate"] for n, o in zip(runs["new"], runs["old"])]
        rows.append({"particles": particles, "window": duration, "runs": runs, "ratios": ratios, "loads": loads})
    command = "python benchmarks/bench_edmd_compare.py " + " ".join(sys.argv[1:])
    timed = ("5 N collisions of warm-up" + (", a re-sort" if args.sort else "") + ", then max(5 N, 10^6) collisions"
             if args.collisions else "the window [L, 2 L]")
    lines = [
        f"# EDMD A/B: {args.new} (new) against {args.old} (old)",
        "",
        f"Command: `{command}`; eta {args.eta}, shells old {args.shell_old or 'default'} / new "
        f"{args.shell_new or 'default'}; {args.rounds} rounds of alternating child processes, CPU time of {timed} "
        "from an FCC start.",
        "",
        "| N (L) | old collisions/CPU-s | new collisions/CPU-s | new / old: median (range) | load averages "
        "| mean list old / new | peak memory old / new (MB) |",
        "|---|---|---|---|---|---|---|",
    ]
    for row in rows:
        lines.append(
            f"| {row['particles']:,} ({row['window'] or '-'}) | {spread([r['rate'] for r in row['runs']['old']])} | "
            f"{spread([r['rate'] for r in row['runs']['new']])} | {spread(row['ratios'])} | "
            f"{min(row['loads']):.2f}-{max(row['loads']):.2f} | {row['runs']['old'][0]['mean_list']:.2f} / "
            f"{row['runs']['new'][0]['mean_list']:.2f} | "
            f"{statistics.median(r['peak_memory_mb'] for r in row['runs']['old']):.0f} / "
            f"{statistics.median(r['peak_memory_mb'] for r in row['runs']['new']):.0f} |"
        )
    write_results(args.output, "\n".join(lines) + "\n", {"rows": rows})


if __name__ == "__main__":
    main()
