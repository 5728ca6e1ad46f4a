"""CPU time of one cell sort of the EDMD engine: the former way against the engine's (issue 21).

Every ``SORT_INTERVAL`` N pair collisions ``HardSphereSystem._sort_by_cell``
renumbers the particles in the order of their cells. It used to rebuild
every list and re-predict every event to find the cells, renumber, and
rebuild and re-predict again (``former_sort`` below, kept here as the
baseline); it now only re-anchors the particles in the cells first
(``_refresh_lists(anchors_only=True)``): the same order, so the same
trajectory bit for bit, with one whole-system list build and prediction
fewer. The two alternate in one process (CPU time, ``--rounds`` rounds, each
after N collisions), at FCC starts melted by 5 N collisions, eta 0.45.

Usage: python benchmarks/bench_edmd_sort.py [--sizes 864 32000] [--rounds 9]
Writes benchmarks/results/edmd_sort.md.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from collisionkit import edmd
from collisionkit._io import atomic_write_text
from collisionkit._kernels import edmd as kernels
from collisionkit.edmd._system_setup import copy_masses_and_species
from collisionkit.edmd.system import SORT_INTERVAL

RESULTS = Path(__file__).parent / "results"


def former_sort(system) -> None:
    """The sort before issue 21: a full refresh for the cells, renumbering, a full refresh."""
    system._refresh_lists()
    order = np.argsort(system.cell_of, kind="stable")
    system.p[:] = system.p[order]
    system._mass = system._mass[order]
    system._species = system._species[order]
    system._image = system._image[order]
    system.ids = system.ids[order]
    system.book[:] = 0.0
    system.book[:, kernels.TARGET] = kernels.LIST_TARGET
    copy_masses_and_species(system)
    system._refresh_lists()
    system.last_sort = system.collisions


def one_size(particles: int, rounds: int) -> dict:
    positions, box = edmd.lattice("fcc", round((particles / 4) ** (1 / 3)), 0.45)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(len(positions)), 3, seed=1), 0.5, box)
    system.run(collisions=5 * system.count)
    times = {"former": [], "engine": []}
    for k in range(rounds):
        for side in (("former", "engine") if k % 2 == 0 else ("engine", "former")):
            system.run(collisions=system.count)
            start = time.process_time()
            former_sort(system) if side == "former" else system._sort_by_cell()
            times[side].append(time.process_time() - start)
    # run() checks for a sort once per chunk of max(N, 10^5) collisions
    between = max(SORT_INTERVAL * system.count, 100_000)
    return {"particles": system.count, "times": times, "collisions_between_sorts": between}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[864, 32000])
    parser.add_argument("--rounds", type=int, default=9)
    args = parser.parse_args()
    loads = os.getloadavg()
    rows = [one_size(n, args.rounds) for n in args.sizes]
    lines = [
        "# EDMD: CPU time of one cell sort, the former way against the engine's",
        "",
        f"Command: `{' '.join(['python benchmarks/bench_edmd_sort.py', *sys.argv[1:]])}`; load average {loads[0]:.2f} "
        f"{loads[1]:.2f} {loads[2]:.2f} before, {os.getloadavg()[0]:.2f} after; {args.rounds} alternating rounds in one "
        "process, medians (range).",
        "",
        "| N | former sort (ms) | engine's sort (ms) | saved per pair collision (ns) |",
        "|---|---|---|---|",
    ]
    for row in rows:
        former, engine = row["times"]["former"], row["times"]["engine"]
        saved = 1e9 * (statistics.median(former) - statistics.median(engine)) / row["collisions_between_sorts"]
        lines.append(
            f"| {row['particles']:,} | {1e3 * statistics.median(former):.2f} ({1e3 * min(former):.2f}-"
            f"{1e3 * max(former):.2f}) | {1e3 * statistics.median(engine):.2f} ({1e3 * min(engine):.2f}-"
            f"{1e3 * max(engine):.2f}) | {saved:.1f} (one sort per {row['collisions_between_sorts']:,}) |"
        )
    text = "\n".join(lines) + "\n"
    print(text)
    RESULTS.mkdir(exist_ok=True)
    atomic_write_text(RESULTS / "edmd_sort.md", text)


if __name__ == "__main__":
    main()
