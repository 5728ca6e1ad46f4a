"""Time to a converged real-gas point: argon, 100 Td, 300 K, 0.2 % on the mean energy and the drift velocity.

Issue 17's target: under a minute on one core. The run is the command's
default (``collisionkit swarm --gas Ar --E-N 100``: 20 000 electrons,
tolerances 0.2 % on the mean energy and the bulk drift, 2 % on N D_L and
N D_T) on one thread, for several seeds; CPU seconds are what counts (the
machine is shared), wall seconds and the load averages are reported too.
The compile is excluded (a warm-up run loads the numba cache first).
Writes benchmarks/results/real_gas_point.md and .json.

    NUMBA_CACHE_DIR=.numba_cache .venv/bin/python benchmarks/bench_real_gas_point.py [--seeds 3]
"""

from __future__ import annotations

import argparse
import os
import platform
import time
import warnings
from pathlib import Path

from collisionkit._io import atomic_write_json, atomic_write_text
from collisionkit.transport import catalogue_gas, simulate_swarm

RESULTS = Path(__file__).parent / "results"
FIELD = 100.0  # Td


def one_point(gas, seed: int) -> dict:
    load = os.getloadavg()[0]
    cpu, wall = time.process_time(), time.perf_counter()
    result = simulate_swarm(gas, FIELD, seed=seed, threads=1)
    cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
    return {"seed": seed, "cpu_seconds": cpu, "wall_seconds": wall, "load_average": load,
            "converged": result.converged, "collisions": result.collisions,
            "mean_energy": result.mean_energy, "mean_energy_error": result.mean_energy_error,
            "drift_velocity_bulk": float(-result.drift_velocity_bulk[2]),
            "drift_velocity_bulk_error": float(result.drift_velocity_bulk_error[2]),
            "drift_velocity_flux": float(-result.drift_velocity_flux[2]),
            "drift_velocity_flux_error": float(result.drift_velocity_flux_error[2]),
            "alpha_N": result.alpha_N, "alpha_N_error": result.alpha_N_error,
            "steady_from": result.steady_from, "simulated_time": result.simulated_time}


def table(rows) -> str:
    lines = ["| seed | CPU s | wall s | load | converged | collisions | <e> (eV) | W bulk (m/s) | W flux (m/s) | "
             "alpha/N (1e-22 m^2) |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(
            f"| {r['seed']} | {r['cpu_seconds']:.1f} | {r['wall_seconds']:.1f} | {r['load_average']:.2f} | "
            f"{r['converged']} | {r['collisions']:.3g} | {r['mean_energy']:.4f} ± {r['mean_energy_error']:.4f} | "
            f"{r['drift_velocity_bulk']:.0f} ± {r['drift_velocity_bulk_error']:.0f} | "
            f"{r['drift_velocity_flux']:.0f} ± {r['drift_velocity_flux_error']:.0f} | "
            f"{r['alpha_N'] / 1e-22:.3f} ± {r['alpha_N_error'] / 1e-22:.3f} |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    args = parser.parse_args()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        gas = catalogue_gas("Ar")
    simulate_swarm(gas, FIELD, particles=256, collision_budget=1e6, threads=1,
                   tolerances={"mean_energy": 0.1})  # compile outside the timing
    rows = [one_point(gas, seed) for seed in range(1, args.seeds + 1)]
    cpu = sorted(r["cpu_seconds"] for r in rows)
    machine = f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}"
    atomic_write_json(RESULTS / "real_gas_point.json", {"machine": machine, "field_Td": FIELD, "runs": rows})
    text = "\n".join([
        "# Converged real-gas point: argon (IST-Lisbon), 100 Td, 300 K, one thread",
        "",
        f"Machine: {machine} (shared: see the load averages).",
        "Settings: the defaults of `collisionkit swarm --gas Ar --E-N 100` (20 000 electrons; 0.2 % on the mean",
        "energy and the bulk drift, 2 % on N D_L and N D_T), `threads=1`; compile excluded.",
        "",
        table(rows),
        "",
        f"Median CPU time to the converged point: **{cpu[len(cpu) // 2]:.1f} s** (target: under 60 s on one core).",
        "",
        "Command: `NUMBA_CACHE_DIR=.numba_cache .venv/bin/python benchmarks/bench_real_gas_point.py`",
        "",
    ])
    atomic_write_text(RESULTS / "real_gas_point.md", text)
    print(text)


if __name__ == "__main__":
    main()
