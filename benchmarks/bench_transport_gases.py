"""Real collisions per CPU second of the swarm engine on real gases (many processes) against Reid's ramp (two).

Run from the repository root with the project venv:

    NUMBA_CACHE_DIR=.numba_cache .venv/bin/python benchmarks/bench_transport_gases.py [--repeats 3]

Cases: Reid's ramp at 12 Td (0 K, 2 processes), argon (IST-Lisbon, 39
processes) at 100 Td and N2 (IST-Lisbon, 26 processes: elastic, 10
vibrational, 13 electronic excitations, 2 ionizations; the set has no
rotational or reversible blocks, so no superelastic processes are added)
at 100 Td, each at 300 K (thermal targets)
and at 0 K (targets at rest), which separates the cost of drawing the
targets' velocities from the cost of the many processes. Same particle
count (20 000), one thread, a fixed budget of real collisions, the cases
in alternating order in each repeat. Every case starts from a Maxwellian at
its own steady mean energy (from a short probe), so that no case pays for a
longer relaxation. Reported: real collisions per CPU second of the whole
``simulate_swarm`` call, the null-trial fraction, and the ratio of Reid's
rate to each case's, per repeat (median). (The JSON also keeps the rate per
second of the kernel steps, ``SwarmResult.seconds``: wall-clock time, so on
a loaded machine it measures the load, not the code.)
Writes benchmarks/results/transport_gases.md and .json.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
os.environ.setdefault("NUMBA_CACHE_DIR", str(ROOT / ".numba_cache"))

from collisionkit._io import atomic_write_json, atomic_write_text  # noqa: E402
from collisionkit.transport import catalogue_gas, reid_ramp, simulate_swarm  # noqa: E402

RESULTS = Path(__file__).parent / "results"
# (label, gas, E/N in Td, gas temperature in K)
CASES = [("Reid 12 Td, 0 K", "Reid", 12.0, 0.0), ("Ar 100 Td, 300 K", "Ar", 100.0, 300.0),
         ("Ar 100 Td, 0 K", "Ar", 100.0, 0.0), ("N2 100 Td, 300 K", "N2", 100.0, 300.0),
         ("N2 100 Td, 0 K", "N2", 100.0, 0.0)]
REFERENCE = CASES[0][0]


def gases() -> dict:
    return {"Reid": reid_ramp(), "Ar": catalogue_gas("Ar"), "N2": catalogue_gas("N2")}


def processes(gas) -> int:
    return sum(len(species.processes) for species in gas.species)


def probe(gas, field: float, temperature: float) -> float:
    """Compile (first call) and return the steady mean energy, the start of the timed runs."""
    return simulate_swarm(gas, field, gas_temperature=temperature, particles=2000, threads=1, seed=99,
                          collision_budget=3e6, tolerances={"mean_energy": 1e-9}).mean_energy


def timed(gas, field: float, temperature: float, start: float, particles: int, collisions: float, seed: int) -> dict:
    load = os.getloadavg()
    wall, cpu = time.perf_counter(), time.process_time()
    result = simulate_swarm(gas, field, gas_temperature=temperature, particles=particles, threads=1, seed=seed,
                            initial_energy=start, collision_budget=collisions, tolerances={"mean_energy": 1e-9})
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    trials = result.collisions + result.null_collisions
    return {"collisions": result.collisions, "null_collisions": result.null_collisions, "cpu_seconds": cpu,
            "wall_seconds": wall, "kernel_seconds": result.seconds, "per_cpu_second": result.collisions / cpu,
            "per_kernel_second": result.collisions_per_second, "null_fraction": result.null_collisions / trials,
            "mean_energy": result.mean_energy, "mean_energy_error": result.mean_energy_error,
            "load_average_before": load}


def measure(args) -> dict:
    table = gases()
    starts = {label: probe(table[gas], field, temperature) for label, gas, field, temperature in CASES}
    repeats = []
    for repeat in range(args.repeats):
        order = CASES if repeat % 2 == 0 else CASES[::-1]
        runs = {label: timed(table[gas], field, temperature, starts[label], args.particles, args.collisions,
                             1 + repeat) for label, gas, field, temperature in order}
        reference = runs[REFERENCE]
        for run in runs.values():
            run["ratio_cpu"] = reference["per_cpu_second"] / run["per_cpu_second"]
            run["ratio_kernel"] = reference["per_kernel_second"] / run["per_kernel_second"]
        repeats.append(runs)
        print(f"repeat {repeat}: " + ", ".join(f"{label} {run['ratio_cpu']:.2f}" for label, run in runs.items()),
              flush=True)
    summary = {}
    for label, gas, field, temperature in CASES:
        runs = [r[label] for r in repeats]
        summary[label] = {"processes": processes(table[gas]), "start_energy": starts[label],
                          **{key: statistics.median(run[key] for run in runs)
                             for key in ("per_cpu_second", "per_kernel_second", "null_fraction", "ratio_cpu",
                                         "ratio_kernel", "mean_energy")}}
    return {"repeats": repeats, "summary": summary}


def report(data: dict) -> str:
    lines = ["# Many processes and the null-collision loop (collisionkit alone, one thread)", "",
             f"Machine: {data['machine']}; load average at start {data['load_average_at_start'][0]:.2f}, at end "
             f"{data['load_average_at_end'][0]:.2f} (shared: other jobs ran; CPU seconds are compared).",
             f"{data['particles']} particles, {data['collisions']:.3g} real collisions per run, {data['repeats_count']} "
             "repeats in alternating order; medians over the repeats.", "",
             "| case | processes | real coll. per CPU s | null trials | trials per real collision "
             "| Reid / case (CPU) | <e> (eV) |", "|---|---|---|---|---|---|---|"]
    for label, row in data["summary"].items():
        lines.append(f"| {label} | {row['processes']} | {row['per_cpu_second']:.3g} | "
                     f"{100 * row['null_fraction']:.0f} % | {1 / (1 - row['null_fraction']):.2f} | "
                     f"**{row['ratio_cpu']:.2f}** | {row['mean_energy']:.4g} |")
    lines += ["", "Per repeat (Reid / case, CPU): " + "; ".join(
        ", ".join(f"{label} {run['ratio_cpu']:.2f}" for label, run in repeat.items() if label != REFERENCE)
        for repeat in data["repeats"]), "", NOTES, f"Command: `{data['command']}`", ""]
    return "\n".join(lines)


NOTES = """Reading the table. A trial collision costs one table lookup whatever the number of processes: the
kernel first tests the trial against the species' summed cross section (one interpolation) and only a real
collision scans the processes, in file order, stopping at the chosen one (the elastic process, first, takes most
real collisions). What costs more in the real gases is not the number of processes but (1) the thermal targets at
300 K: every trial draws the target's velocity (three normal numbers; 0 K rows have none) and (2) in N2 the
resonant vibrational cross sections, whose sum times the speed changes fast with speed, so the bound of a flight
window is looser and more trials are null. Each case starts at its own steady mean energy (the default 1 eV start
would add a relaxation whose length differs from gas to gas)."""


def parse(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--particles", type=int, default=20_000)
    parser.add_argument("--collisions", type=float, default=4e7, help="real collisions per run")
    parser.add_argument("--from-json", action="store_true", help="only rewrite the .md from the .json")
    return parser.parse_args(argv)


def main(argv=None) -> None:
    args = parse(argv)
    if args.from_json:
        text = report(json.loads((RESULTS / "transport_gases.json").read_text()))
        atomic_write_text(RESULTS / "transport_gases.md", text)
        print(text)
        return
    command = " ".join(["NUMBA_CACHE_DIR=.numba_cache .venv/bin/python benchmarks/bench_transport_gases.py",
                        *(sys.argv[1:] if argv is None else argv)])
    data = {"command": command, "machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
            f"Python {platform.python_version()}", "load_average_at_start": os.getloadavg(),
            "particles": args.particles, "collisions": args.collisions, "repeats_count": args.repeats}
    data.update(measure(args))
    data["load_average_at_end"] = os.getloadavg()
    atomic_write_json(RESULTS / "transport_gases.json", data)
    text = report(data)
    atomic_write_text(RESULTS / "transport_gases.md", text)
    print(text)


if __name__ == "__main__":
    main()
