"""Benchmark of swarms in fields at any angle and in oscillating fields: CPU time per real collision.

Reid's ramp at 12 Td (amplitude for the oscillating field), 0 K, one thread,
against the static-field cases (E alone; E perpendicular to B). CPU time
(``time.process_time``) of the whole call, so a loaded machine slows every
case alike. Run it also with ``PYTHONPATH`` pointing at an older checkout to
time the static cases of that code (the cases it cannot run are skipped).
Writes benchmarks/results/fields.md and fields.json (``--tag`` names the
rows of another checkout, written to fields_<tag>.json).

    NUMBA_CACHE_DIR=.numba_cache .venv/bin/python benchmarks/bench_fields.py
"""

from __future__ import annotations

import inspect
import os
import sys
import time
from pathlib import Path

from collisionkit._io import atomic_write_json, atomic_write_text
from collisionkit.transport import reid_ramp, simulate_swarm

RESULTS = Path(__file__).parent / "results"
COLLISIONS = 2e7
CASES = {
    "E alone": {},
    "E perpendicular to B (200 Hx)": {"reduced_magnetic_field": 200.0},
    "B at 60 deg (200 Hx)": {"reduced_magnetic_field": 200.0, "field_angle": 60.0},
    "AC, omega/N = 2e-14": {"reduced_frequency": 2e-14},
    "AC + B at 60 deg (200 Hx)": {"reduced_frequency": 2e-14, "reduced_magnetic_field": 200.0, "field_angle": 60.0},
}


def cost(options: dict) -> dict:
    simulate_swarm(reid_ramp(), 12.0, gas_temperature=0.0, particles=640, collision_budget=1e6, threads=1,
                   tolerances={"mean_energy": 0.05}, **options)  # compile
    start = time.process_time()
    result = simulate_swarm(reid_ramp(), 12.0, gas_temperature=0.0, particles=10_000, threads=1, seed=1,
                            tolerances={"mean_energy": 1e-9}, collision_budget=COLLISIONS, **options)
    cpu = time.process_time() - start
    return {"collisions": result.collisions, "null_collisions": result.null_collisions, "cpu_seconds": cpu,
            "ns_per_collision": 1e9 * cpu / result.collisions, "mean_energy": result.mean_energy}


def main() -> None:
    tag = sys.argv[sys.argv.index("--tag") + 1] if "--tag" in sys.argv else ""
    accepted = inspect.signature(simulate_swarm).parameters
    rows = {name: cost(options) for name, options in CASES.items() if all(key in accepted for key in options)}
    rows["load_average_at_end"] = os.getloadavg()
    atomic_write_json(RESULTS / (f"fields_{tag}.json" if tag else "fields.json"), rows)
    if tag:
        return
    base = rows["E perpendicular to B (200 Hx)"]["ns_per_collision"]
    lines = ["# Swarms in fields at any angle and AC fields: CPU time per real collision", "",
             "Reid's ramp, 12 Td (amplitude), 0 K, 10 000 particles, one thread, 2e7 collisions, "
             "benchmarks/bench_fields.py, on the shared 2-core machine (other jobs running).", "",
             "| case | ns per real collision | null / real | ratio to E perpendicular to B |", "|---|---|---|---|"]
    for name, row in rows.items():
        if name == "load_average_at_end":
            continue
        lines.append(f"| {name} | {row['ns_per_collision']:.0f} | {row['null_collisions'] / row['collisions']:.2f} "
                     f"| {row['ns_per_collision'] / base:.2f} |")
    atomic_write_text(RESULTS / "fields.md", "\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
