"""The dilute default shell: collisions per CPU second with the widened default against the fixed 0.7, alternating.

In a dilute gas a free path spans many shells of 0.7 diameters, and the
lists' rebuilds, not the pair tests, set the cost. ``default_shell``
widens the shell of a homogeneous system below ``DILUTE_PACKING`` until a
list's ball holds ``LIST_NEIGHBOURS`` particles on average. For each point
(lattice start, one core; with ``--shear`` Lees-Edwards at rate G with the
thermostat): two copies of the system, one with ``DEFAULT_SHELL`` and one
with the default, 10 collisions per particle of warm-up, then ``--repeats``
alternating pairs of runs of ``--per-particle`` collisions per particle.

Usage: python benchmarks/bench_edmd_dilute.py [--repeats 5] [--shear 0.05]
Writes benchmarks/results/edmd_dilute.md and .json.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time
from pathlib import Path

from collisionkit._io import atomic_write_text

RESULTS = Path(__file__).parent / "results"
POINTS = [(2, 0.01, 64), (2, 0.1, 64), (2, 0.35, 64), (3, 0.01, 16), (3, 0.1, 16), (3, 0.2, 16)]


def alternating(dim: int, packing: float, cells: int, shear: float, per_particle: int, repeats: int) -> dict:
    """Collisions per CPU second of a system with the fixed and with the default shell, alternating."""
    import numpy as np

    from collisionkit import edmd

    positions, box = edmd.lattice("fcc" if dim == 3 else "square", cells, packing)
    count = len(positions)
    velocities = edmd.maxwell_boltzmann(np.ones(count), dim, seed=1)
    options = {"shear_rate": shear, "thermostat": 1.0} if shear else {}
    systems = {"fixed": edmd.HardSphereSystem(positions, velocities, 0.5, box, neighbour_shell=edmd.DEFAULT_SHELL,
                                              **options),
               "default": edmd.HardSphereSystem(positions, velocities, 0.5, box, **options)}
    for system in systems.values():
        system.run(collisions=10 * count)
    rates = {mode: [] for mode in systems}
    for _ in range(repeats):
        for mode, system in systems.items():
            start = time.process_time()
            system.run(collisions=per_particle * count)
            rates[mode].append(per_particle * count / (time.process_time() - start))
    median = {mode: statistics.median(values) for mode, values in rates.items()}
    ratios = [d / f for d, f in zip(rates["default"], rates["fixed"])]
    return {"dim": dim, "particles": count, "packing_fraction": packing, "shear_rate": shear,
            "shell": systems["default"].neighbour_shell_width, "rates": rates, "median": median,
            "speedup": median["default"] / median["fixed"], "round_ratios": ratios}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--per-particle", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--shear", type=float, default=0.0)
    args = parser.parse_args()
    load_before = os.getloadavg()
    results = [alternating(dim, eta, cells, args.shear, args.per_particle, args.repeats)
               for dim, eta, cells in POINTS]
    load_after = os.getloadavg()
    name = "edmd_dilute" + ("_shear" if args.shear else "")
    RESULTS.mkdir(exist_ok=True)
    atomic_write_text(RESULTS / f"{name}.json", json.dumps(
        {"load_average_before": load_before, "load_average_after": load_after, "results": results}, indent=2) + "\n")
    lines = ["# EDMD: the dilute default shell against the fixed 0.7", "",
             f"Collisions per CPU second (median of {args.repeats} alternating runs of {args.per_particle} "
             f"collisions per particle{f'; shear rate G = {args.shear}, thermostat kT = 1' if args.shear else ''}; "
             "`python benchmarks/bench_edmd_dilute.py`). Speed-up: default over fixed of the medians; the range is "
             "that of the rounds' pairs. Load average (1, 5, 15 min) "
             f"{', '.join(f'{x:.2f}' for x in load_before)} before, {', '.join(f'{x:.2f}' for x in load_after)} after.",
             "", "| d | N | eta | default shell | fixed 0.7 | default | speed-up | range |",
             "|---|---|---|---|---|---|---|---|"]
    for r in results:
        lines.append(f"| {r['dim']} | {r['particles']} | {r['packing_fraction']} | {r['shell']:.2f} | "
                     f"{r['median']['fixed']:.4g} | {r['median']['default']:.4g} | {r['speedup']:.2f} | "
                     f"{min(r['round_ratios']):.2f}-{max(r['round_ratios']):.2f} |")
    atomic_write_text(RESULTS / f"{name}.md", "\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
