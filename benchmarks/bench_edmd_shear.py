"""Cost of Lees-Edwards shear: collisions per CPU second of a sheared run against a periodic one, alternating.

Under shear a pair across a y face meets the partner's sliding image (its
offset and velocity in the prediction), the list anchors move with the flow
(a list's age spends part of its shell) and the cells hold them in the
flow's frame, refilled at each sweep (every strain 0.25). The issue allows
at most 1.5 times the cost of a periodic run at the same density.

For each N (FCC start in 3D, hexagonal in 2D with ``--dim 2``, one core):
two copies of the system, one
periodic and one sheared at rate G with the thermostat at kT = 1 (so both
run at the same temperature; the thermostat re-predicts every event after
every 4N collisions, part of the cost measured), 20 collisions per particle
of warm-up, then ``--repeats`` pairs of runs of ``--per-particle``
collisions each, alternating in one process; the rate is collisions per
CPU second.

Usage: python benchmarks/bench_edmd_shear.py [--dim 3] [--sizes 4000 32000] [--packing 0.3 0.45] [--rate 0.1]
[--repeats 5]
Writes benchmarks/results/edmd_shear.md and .json (edmd_shear_2d.* with ``--dim 2``), with the load average
before and after.
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


def alternating(dim: int, particles: int, packing: float, rate: float, per_particle: int, repeats: int) -> dict:
    """Collisions per CPU second of a periodic and a sheared copy of one system, alternating."""
    import numpy as np

    from collisionkit import edmd

    if dim == 3:
        positions, box = edmd.lattice("fcc", round((particles / 4) ** (1 / 3)), packing)
    else:
        positions, box = edmd.lattice("hexagonal", round((particles / 2) ** (1 / 2)), packing)
    count = len(positions)
    velocities = edmd.maxwell_boltzmann(np.ones(count), dim, seed=1)
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
    return {"dim": dim, "particles": count, "packing_fraction": packing, "shear_rate": rate, "rates": rates,
            "median": median, "cost_ratio": median["periodic"] / median["sheared"],
            "round_ratios": ratios, "reduced_shear_rate_box": rate * box[1]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dim", type=int, choices=(2, 3), default=3)
    parser.add_argument("--sizes", type=int, nargs="+", default=[4000, 32000])
    parser.add_argument("--packing", type=float, nargs="+", default=[0.3, 0.45])
    parser.add_argument("--rate", type=float, default=0.1)
    parser.add_argument("--per-particle", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    load_before = os.getloadavg()
    results = [alternating(args.dim, n, eta, args.rate, args.per_particle, args.repeats)
               for n in args.sizes for eta in args.packing]
    load_after = os.getloadavg()
    RESULTS.mkdir(exist_ok=True)
    name = "edmd_shear" if args.dim == 3 else "edmd_shear_2d"
    atomic_write_text(RESULTS / f"{name}.json", json.dumps(
        {"load_average_before": load_before, "load_average_after": load_after, "results": results}, indent=2) + "\n")
    lines = [f"# EDMD: Lees-Edwards shear against a periodic run ({'spheres' if args.dim == 3 else 'discs'})", "",
             f"Collisions per CPU second (median of {args.repeats} alternating runs of {args.per_particle} "
             f"collisions per particle; shear rate G = {args.rate}, thermostat kT = 1; "
             f"`python benchmarks/bench_edmd_shear.py --dim {args.dim}`). The cost ratio is periodic over sheared of the medians; "
             "the range is that of the ratios of the rounds' pairs. Load average (1, 5, 15 min) "
             f"{', '.join(f'{x:.2f}' for x in load_before)} before, {', '.join(f'{x:.2f}' for x in load_after)} after.",
             "", "| N | eta | G L_y | periodic | sheared | cost ratio | range |", "|---|---|---|---|---|---|---|"]
    for r in results:
        lines.append(f"| {r['particles']} | {r['packing_fraction']} | {r['reduced_shear_rate_box']:.3g} | "
                     f"{r['median']['periodic']:.4g} | "
                     f"{r['median']['sheared']:.4g} | {r['cost_ratio']:.2f} | "
                     f"{min(r['round_ratios']):.2f}-{max(r['round_ratios']):.2f} |")
    atomic_write_text(RESULTS / f"{name}.md", "\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
