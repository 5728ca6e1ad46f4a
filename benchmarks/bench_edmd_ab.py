"""EDMD engine A/B in one process: this checkout against git revisions, in alternating chunks of collisions.

On a shared virtual machine one run's rate varies by 10-20 % from the next (the host's other work), more than
the changes worth measuring. Here each revision's package is loaded under its own name in one interpreter, each
runs its own system of the same state point, and the systems take turns (the order reversed every round) at
``--chunk`` collisions each: a slow spell of the host slows both, and the per-round ratio cancels it. The median of
the ratios and their quartiles are reported; numba compiles each copy once (its own cache folder).

Example: ``python benchmarks/bench_edmd_ab.py --baseline HEAD~1 --particles 864 --eta 0.45 --rounds 40``
"""

from __future__ import annotations

import argparse
import importlib
import os
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _bench_common import BENCHMARKS, exported_source, write_results


def load_copy(source: Path, name: str, scratch: Path):
    """The ``collisionkit`` package under ``source`` imported as package ``name`` (its relative imports follow)."""
    shutil.copytree(source / "collisionkit", scratch / name, ignore=shutil.ignore_patterns("__pycache__"))
    if str(scratch) not in sys.path:
        sys.path.insert(0, str(scratch))
    return importlib.import_module(f"{name}.edmd")


def fcc_system(edmd, particles: int, eta: float, well_width: float | None = None):
    """An FCC start of about ``particles`` spheres (radius 0.5) at packing fraction ``eta`` (with square wells of
    depth kT if ``well_width`` is given), run 5 N collisions."""
    positions, box = edmd.lattice("fcc", round((particles / 4) ** (1 / 3)), eta)
    wells = {} if well_width is None else {"well_width": well_width, "well_depth": 1.0}
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(len(positions)), 3, seed=1), 0.5, box,
                                   **wells)
    system.run(collisions=5 * len(positions))
    return system


def alternate(systems: dict, chunk: int, rounds: int) -> dict:
    """CPU seconds of each system per round of ``chunk`` collisions, the order reversed every round."""
    seconds = {name: [] for name in systems}
    names = list(systems)
    for round_number in range(rounds):
        for name in names if round_number % 2 == 0 else names[::-1]:
            start = time.process_time()
            systems[name].run(collisions=chunk)
            seconds[name].append(time.process_time() - start)
    return seconds


def table(seconds: dict, chunk: int, args, load: tuple) -> str:
    base = next(iter(seconds))
    wells = "" if args.well_width is None else f" --well-width {args.well_width}"
    lines = [f"# EDMD A/B in one process: N ~ {args.particles}, eta {args.eta}"
             + ("" if args.well_width is None else f", square wells lambda {args.well_width}, depth kT"),
             "",
             f"Command: `python benchmarks/bench_edmd_ab.py --baseline {' '.join(args.baseline)} --particles "
             f"{args.particles} --eta {args.eta}{wells} --chunk {chunk} --rounds {args.rounds}`; load average "
             f"{load[0]:.2f} {load[1]:.2f} {load[2]:.2f} after.",
             "",
             f"| code | ns per collision, median (fastest round) | ratio to {base}: median (quartiles) |",
             "|---|---|---|"]
    for name, values in seconds.items():
        ns = [1e9 * value / chunk for value in values]
        ratios = [value / reference for value, reference in zip(values, seconds[base])]
        quartiles = np.percentile(ratios, [25, 75])
        lines.append(f"| {name} | {statistics.median(ns):.0f} ({min(ns):.0f}) | {statistics.median(ratios):.3f} "
                     f"({quartiles[0]:.3f}-{quartiles[1]:.3f}) |")
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", nargs="+", required=True, help="git revisions to compare this checkout with")
    parser.add_argument("--particles", type=int, default=864)
    parser.add_argument("--eta", type=float, default=0.45)
    parser.add_argument("--chunk", type=float, default=2e5, help="collisions per turn")
    parser.add_argument("--rounds", type=int, default=40)
    parser.add_argument("--well-width", type=float, default=None,
                        help="square wells of this width and depth kT (both revisions must have them)")
    parser.add_argument("--output", default=None, help="stem of the result files in benchmarks/results")
    args = parser.parse_args()
    if args.rounds < 2 or args.chunk < 1 or args.particles < 4 or not 0 < args.eta < 0.74:
        raise SystemExit("--rounds must be >= 2, --chunk >= 1, --particles >= 4 and --eta in (0, 0.74)")
    chunk = int(args.chunk)
    with tempfile.TemporaryDirectory() as folder:
        scratch = Path(folder)
        os.environ.setdefault("NUMBA_CACHE_DIR", str(scratch / "numba_cache"))
        sources = {"this checkout": BENCHMARKS.parent / "src"}
        for revision in args.baseline:
            sources[revision] = Path(exported_source(revision, scratch / f"rev{len(sources)}"))
        systems = {}
        for number, (label, source) in enumerate(sources.items()):
            systems[label] = fcc_system(load_copy(source, f"collisionkit_ab{number}", scratch), args.particles,
                                        args.eta, args.well_width)
        seconds = alternate(systems, chunk, args.rounds)
    text = table(seconds, chunk, args, os.getloadavg())
    stem = args.output or f"edmd_ab_{args.particles}"
    write_results(stem, text, {"particles": args.particles, "eta": args.eta, "chunk": chunk,
                               "seconds": seconds, "load": os.getloadavg()})


if __name__ == "__main__":
    main()
