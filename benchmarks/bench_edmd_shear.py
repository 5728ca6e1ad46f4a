"""Cost of Lees-Edwards shear: collisions per CPU second of a sheared run against a periodic one, alternating.

Under shear a pair across a y face meets the partner's sliding image (a
floor per separation in the prediction), the lists of pairs across the
faces reach a shear margin further, and every particle anchored in the
first or last row of cells rebuilds its list at each sweep (every margin /
(G L_y) in time). The issue allows at most 1.5 times the cost of a periodic
run at the same density.

For each N (FCC start, 3D, one core): two copies of the system, one
periodic and one sheared at rate G with the thermostat at kT = 1 (so both
run at the same temperature; the thermostat re-predicts every event after
every 4N collisions, part of the cost measured), 20 collisions per particle
of warm-up, then ``--repeats`` pairs of runs of ``--per-particle``
collisions each, alternating in one process; the rate is collisions per
CPU second.

Usage: python benchmarks/bench_edmd_shear.py [--sizes 4000 32000] [--packing 0.3 0.45] [--rate 0.1]
Writes benchmarks/results/edmd_shear.md and .json.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
from pathlib import Path

from collisionkit._io import atomic_write_text

RESULTS = Path(__file__).parent / "results"


def alternating(particles: int, packing: float, rate: float, per_particle: int, repeats: int) -> dict:
    """Collisions per CPU second of a periodic and a sheared copy of one system, alternating."""
    import numpy as np

    from collisionkit import edmd

    cells = round((particles / 4) ** (1 / 3))
    positions, box = edmd.lattice("fcc", cells, packing)
    count = len(positions)
    velocities = edmd.maxwell_boltzmann(np.ones(count), 3, seed=1)
    systems = {"periodic": edmd.HardSphereSystem(positions, velocities, 0.5, box),
               "sheared": edmd.HardSphereSystem(positions, velocities, 0.5, box, shear_rate=rate, thermostat=1.0)}
    for system in systems.values():
        system.run(collisions=20 * count)
    rates = {mode: [] for mode in systems}
    for _ in range(repeats):
        for mode, system in systems.items():
            start = time.process_time()
            system.run(collisions=per_particle * count)
            rates[mode].append(per_particle * count / (time.process_time() - start))
    median = {mode: statistics.median(values) for mode, values in rates.items()}
    return {"particles": count, "packing_fraction": packing, "shear_rate": rate, "rates": rates,
            "median": median, "cost_ratio": median["periodic"] / median["sheared"],
            "reduced_shear_rate_box": rate * box[1]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[4000, 32000])
    parser.add_argument("--packing", type=float, nargs="+", default=[0.3, 0.45])
    parser.add_argument("--rate", type=float, default=0.1)
    parser.add_argument("--per-particle", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    results = [alternating(n, eta, args.rate, args.per_particle, args.repeats)
               for n in args.sizes for eta in args.packing]
    RESULTS.mkdir(exist_ok=True)
    atomic_write_text(RESULTS / "edmd_shear.json", json.dumps(results, indent=2) + "\n")
    lines = ["# EDMD: Lees-Edwards shear against a periodic run", "",
             f"Collisions per CPU second (median of {args.repeats} alternating runs of {args.per_particle} "
             f"collisions per particle; shear rate G = {args.rate}, thermostat kT = 1; "
             "`python benchmarks/bench_edmd_shear.py`).", "",
             "| N | eta | periodic | sheared | cost ratio |", "|---|---|---|---|---|"]
    for r in results:
        lines.append(f"| {r['particles']} | {r['packing_fraction']} | {r['median']['periodic']:.4g} | "
                     f"{r['median']['sheared']:.4g} | {r['cost_ratio']:.2f} |")
    atomic_write_text(RESULTS / "edmd_shear.md", "\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
