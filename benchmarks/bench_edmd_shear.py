"""Cost of Lees-Edwards shear: collisions per CPU second of a sheared run against a periodic one, alternating.

Under shear a pair across a y face meets the partner's sliding image (its
offset and velocity in the prediction), the pairs across the faces are
listed a shear margin further along x, the particles anchored in the first
and last rows of cells list those pairs anew at each sweep (every margin /
(G L_y) in time), and the streaming motion moves the particles off their
anchors sooner (more list events). The issue allows at most 1.5 times the
cost of a periodic run at the same density.

For each N (FCC start, 3D, one core): two copies of the system, one
periodic and one sheared at rate G with the thermostat at kT = 1 (so both
run at the same temperature; the thermostat re-predicts every event after
every 4N collisions, part of the cost measured), 20 collisions per particle
of warm-up, then ``--repeats`` pairs of runs of ``--per-particle``
collisions each, alternating in one process; the rate is collisions per
CPU second.

Usage: python benchmarks/bench_edmd_shear.py [--sizes 4000 32000] [--packing 0.3 0.45] [--rate 0.1] [--repeats 5]
Writes benchmarks/results/edmd_shear.md and .json (with the load average before and after).
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
    # the ratio of each round's pair (run back to back), for the spread
    ratios = [a / b for a, b in zip(rates["periodic"], rates["sheared"])]
    return {"particles": count, "packing_fraction": packing, "shear_rate": rate, "rates": rates,
            "median": median, "cost_ratio": median["periodic"] / median["sheared"],
            "round_ratios": ratios, "reduced_shear_rate_box": rate * box[1]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[4000, 32000])
    parser.add_argument("--packing", type=float, nargs="+", default=[0.3, 0.45])
    parser.add_argument("--rate", type=float, default=0.1)
    parser.add_argument("--per-particle", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    load_before = os.getloadavg()
    results = [alternating(n, eta, args.rate, args.per_particle, args.repeats)
               for n in args.sizes for eta in args.packing]
    load_after = os.getloadavg()
    RESULTS.mkdir(exist_ok=True)
    atomic_write_text(RESULTS / "edmd_shear.json", json.dumps(
        {"load_average_before": load_before, "load_average_after": load_after, "results": results}, indent=2) + "\n")
    lines = ["# EDMD: Lees-Edwards shear against a periodic run", "",
             f"Collisions per CPU second (median of {args.repeats} alternating runs of {args.per_particle} "
             f"collisions per particle; shear rate G = {args.rate}, thermostat kT = 1; "
             "`python benchmarks/bench_edmd_shear.py`). The cost ratio is periodic over sheared of the medians; "
             "the range is that of the ratios of the rounds' pairs. Load average (1, 5, 15 min) "
             f"{', '.join(f'{x:.2f}' for x in load_before)} before, {', '.join(f'{x:.2f}' for x in load_after)} after.",
             "", "| N | eta | periodic | sheared | cost ratio | range |", "|---|---|---|---|---|---|"]
    for r in results:
        lines.append(f"| {r['particles']} | {r['packing_fraction']} | {r['median']['periodic']:.4g} | "
                     f"{r['median']['sheared']:.4g} | {r['cost_ratio']:.2f} | "
                     f"{min(r['round_ratios']):.2f}-{max(r['round_ratios']):.2f} |")
    atomic_write_text(RESULTS / "edmd_shear.md", "\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
