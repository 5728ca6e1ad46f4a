"""Does the particles' memory order matter to the EDMD engine? Cell order against a Z-order curve and a random order.

Every ``SORT_INTERVAL`` N collisions ``HardSphereSystem._sort_by_cell``
renumbers the particles' memory slots in the order of their cells (x
fastest, ``_slot_order``). Each child here starts from FCC at packing
fraction 0.45, runs 5 N collisions, re-sorts in one of three orders and
times max(5 N, 10^6) collisions in CPU time, as ``bench_edmd.one_size``:

* ``cells``: the engine's order;
* ``morton``: the cells along a Z-order (Morton) curve, the bits of their
  integer coordinates interleaved (G. M. Morton, IBM report (1966));
* ``random``: every particle at a random slot.

The trajectory is the same in every order (tests/edmd/test_neighbour_lists.py),
so the three time the same events; the variants alternate, ``--rounds`` rounds.

Usage: python benchmarks/bench_edmd_order.py [--sizes 1000188] [--rounds 3] [--output edmd_order]
Writes benchmarks/results/<output>.md and .json.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
from pathlib import Path

from _bench_common import json_in_fresh_process, write_results

VARIANTS = ("cells", "morton", "random")


def morton_keys(ncell):
    """Z-order key of every cell (indexed by the linear cell number, x fastest): the coordinates' bits interleaved."""
    import numpy as np

    ncell = [int(n) for n in ncell]
    cell = np.arange(ncell[0] * ncell[1] * ncell[2], dtype=np.int64)
    coordinates = (cell % ncell[0], cell // ncell[0] % ncell[1], cell // (ncell[0] * ncell[1]))
    key = np.zeros(cell.size, dtype=np.int64)
    for bit in range(max(n - 1 for n in ncell).bit_length()):
        for axis, c in enumerate(coordinates):
            key |= ((c >> bit) & 1) << (3 * bit + axis)
    return key


def one_run(particles: int, variant: str) -> dict:
    """5 N collisions, a re-sort in ``variant``'s order, then max(5 N, 10^6) collisions timed (CPU time)."""
    import resource
    import time

    import numpy as np

    from collisionkit import edmd

    cells = round((particles / 4) ** (1 / 3))
    positions, box = edmd.lattice("fcc", cells, 0.45)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(len(positions)), 3, seed=1), 0.5, box)
    del positions
    system.run(collisions=5 * system.count)
    if variant == "morton":
        system._slot_order = lambda: np.argsort(morton_keys(system.ncell)[system.cell_of], kind="stable")
    elif variant == "random":
        system._slot_order = lambda: np.random.default_rng(7).permutation(system.count)
    system._sort_by_cell()
    if variant != "cells":
        del system._slot_order  # a later sort (none within 10 N of N >= 10^5) in the engine's order
    start = time.process_time()
    collisions = system.run(collisions=max(5 * system.count, 1_000_000))
    cpu = time.process_time() - start
    system.check()
    return {"particles": system.count, "variant": variant, "collisions": collisions, "cpu_seconds": cpu,
            "rate": collisions / cpu, "peak_memory_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


def in_subprocess(particles: int, variant: str) -> dict:
    return json_in_fresh_process("bench_edmd_order", f"one_run({particles}, {variant!r})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000188])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--output", default="edmd_order")
    args = parser.parse_args()
    rows = []
    for size in args.sizes:
        runs = {variant: [] for variant in VARIANTS}
        loads = []
        for k in range(args.rounds):
            for variant in VARIANTS[k % 3:] + VARIANTS[: k % 3]:  # each variant first in turn
                loads.append(os.getloadavg()[0])
                runs[variant].append(in_subprocess(size, variant))
                print(f"N {size} round {k} {variant}: {runs[variant][-1]['rate']:.4g}/CPU-s load {loads[-1]:.2f}",
                      flush=True)
        rows.append({"particles": size, "runs": runs, "loads": loads})
    command = "python benchmarks/bench_edmd_order.py " + " ".join(sys.argv[1:])
    lines = [
        "# EDMD: the particles' memory order (cells, Z-order curve, random)",
        "",
        f"Command: `{command}`; eta 0.45, FCC start, 5 N collisions, a re-sort in the variant's order, then "
        f"max(5 N, 10^6) collisions timed in CPU time; {args.rounds} rounds, the variants alternating.",
        "",
        "| N | order | collisions/CPU-s: median (range) | / cells | peak memory (MB) | load averages |",
        "|---|---|---|---|---|---|",
    ]
    for row in rows:
        base = statistics.median(r["rate"] for r in row["runs"]["cells"])
        for variant in VARIANTS:
            rates = [r["rate"] for r in row["runs"][variant]]
            lines.append(
                f"| {row['particles']:,} | {variant} | {statistics.median(rates):.3g} ({min(rates):.3g}-{max(rates):.3g}) "
                f"| {statistics.median(rates) / base:.3f} | "
                f"{statistics.median(r['peak_memory_mb'] for r in row['runs'][variant]):.0f} | "
                f"{min(row['loads']):.2f}-{max(row['loads']):.2f} |"
            )
    write_results(args.output, "\n".join(lines) + "\n", {"rows": rows})


if __name__ == "__main__":
    main()
