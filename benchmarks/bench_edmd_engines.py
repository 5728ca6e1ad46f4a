"""The two EDMD engines side by side in one process: neighbour lists against cell crossings, over packing fractions.

At each packing fraction two systems start from the same state (an FCC or square lattice, run 5 collisions a
particle), one per engine (``HardSphereSystem(engine="lists")`` and ``engine="cells"``), and take turns at
``--chunk`` collisions (the order reversed every round), so that a slow spell of the host slows both. Reported:
the median of the per-round ratios lists / cells of CPU time (> 1: cells faster) and their quartiles, and each
engine's ns per collision. The crossover sets ``collisionkit.edmd._cell_crossings.CELLS_BELOW_PACKING``.

Example: ``python benchmarks/bench_edmd_engines.py --dim 3 --particles 4000 --eta 0.05 0.1 0.2 0.26``
"""

from __future__ import annotations

import argparse
import os
import statistics

import numpy as np
from _bench_common import write_results
from bench_edmd_ab import alternate

from collisionkit import edmd


def lattice_system(dim: int, particles: int, eta: float, engine: str):
    """About ``particles`` spheres (FCC) or discs (square lattice) of radius 0.5 at ``eta``, run 5 N collisions."""
    cells = round((particles / 4) ** (1 / 3)) if dim == 3 else round(particles**0.5)
    positions, box = edmd.lattice("fcc" if dim == 3 else "square", cells, eta)
    velocities = edmd.maxwell_boltzmann(np.ones(len(positions)), dim, seed=1)
    system = edmd.HardSphereSystem(positions, velocities, 0.5, box, engine=engine)
    system.run(collisions=5 * len(positions))
    return system


def compare(dim: int, particles: int, eta: float, chunk: int, rounds: int) -> dict:
    systems = {engine: lattice_system(dim, particles, eta, engine) for engine in ("lists", "cells")}
    seconds = alternate(systems, chunk, rounds)
    ratios = [lists / cells for lists, cells in zip(seconds["lists"], seconds["cells"])]
    return {"eta": eta, "particles": systems["cells"].count, "ratios": ratios, "seconds": seconds,
            "ns": {name: statistics.median(values) / chunk * 1e9 for name, values in seconds.items()}}


def table(points: list, args, chunk: int, load: tuple) -> str:
    kind = "spheres" if args.dim == 3 else "discs"
    lines = [f"# EDMD engines in one process: neighbour lists against cell crossings ({kind})", "",
             f"Command: `python benchmarks/bench_edmd_engines.py --dim {args.dim} --particles {args.particles} --eta "
             f"{' '.join(map(str, args.eta))} --chunk {chunk} --rounds {args.rounds}`; load average "
             f"{load[0]:.2f} {load[1]:.2f} {load[2]:.2f} after.", "",
             "| N | eta | lists ns/collision | cells ns/collision | lists / cells: median (quartiles) |",
             "|---|---|---|---|---|"]
    for point in points:
        quartiles = np.percentile(point["ratios"], [25, 75])
        lines.append(f"| {point['particles']} | {point['eta']} | {point['ns']['lists']:.0f} | "
                     f"{point['ns']['cells']:.0f} | {statistics.median(point['ratios']):.3f} "
                     f"({quartiles[0]:.3f}-{quartiles[1]:.3f}) |")
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dim", type=int, default=3)
    parser.add_argument("--particles", type=int, default=4000)
    parser.add_argument("--eta", type=float, nargs="+", default=[0.05, 0.1, 0.15, 0.2, 0.26])
    parser.add_argument("--chunk", type=float, default=5e4, help="collisions per turn")
    parser.add_argument("--rounds", type=int, default=16)
    parser.add_argument("--output", default=None, help="stem of the result files in benchmarks/results")
    args = parser.parse_args()
    limit = 0.74 if args.dim == 3 else 0.9
    if args.dim not in (2, 3) or args.rounds < 2 or args.chunk < 1 or args.particles < 4 or not all(
            0 < eta < limit for eta in args.eta):
        raise SystemExit(f"--dim must be 2 or 3, --rounds >= 2, --chunk >= 1, --particles >= 4, --eta in (0, {limit})")
    chunk = int(args.chunk)
    points = [compare(args.dim, args.particles, eta, chunk, args.rounds) for eta in args.eta]
    text = table(points, args, chunk, os.getloadavg())
    write_results(args.output or f"edmd_engines_{args.dim}d", text, {"dim": args.dim, "chunk": chunk,
                                                                    "points": points, "load": os.getloadavg()})


if __name__ == "__main__":
    main()
