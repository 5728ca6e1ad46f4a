"""Benchmark of particle tracking (issue 18): time per real collision in a non-uniform field against the
uniform-field swarm, and the cost of field-map interpolation.

Runs, each on one thread, all in Reid's ramp gas at N = 1e24 m^-3 and 0 K, timed in CPU time (the machine is
shared; wall time counts the other users), REPEATS rounds in which every run (the swarm too) takes its turn, so
that a change of the machine's load falls on all of them alike; the table quotes the median round:

* the swarm (simulate_swarm, exact flights, 12 Td): the reference time per real collision;
* tracking between parallel plates (uniform field: exact flights) at 12 Td;
* tracking in a proportional counter (wire 25 um, cathode 1 cm, 12 Td at 1.5 mm from the wire, so the
  field spans 0.1 to 700 Td): the Dormand-Prince integrator, by the null-collision and the path-length methods;
* the same counter with its field read from a 2D field map (512 x 512, bilinear), at the default tolerance and
  at 1e-5 (the map's own interpolation error is far above 1e-6 of the field);
* field-map interpolation alone: evaluations per second of a 3D map (64^3) and a 2D map at random points.

Writes benchmarks/results/tracking.md and tracking.json.

    NUMBA_CACHE_DIR=.numba_cache .venv/bin/python benchmarks/bench_tracking.py
"""

from __future__ import annotations

import math
import os
import platform
import time
from pathlib import Path

import numpy as np

from collisionkit._io import atomic_write_json, atomic_write_text
from collisionkit._kernels.transport.tracking.fields import field_values
from collisionkit.transport import reid_ramp, simulate_swarm
from collisionkit.transport.tracking import CoaxialField, Device, FieldMap, track

RESULTS = Path(__file__).parent / "results"
REPEATS = 5
PRIMARIES = 2000  # per tracking run: 1-3 million real collisions
DENSITY = 1e24
WIRE, CATHODE = 25e-6, 1e-2
START = 1.5e-3  # m from the axis
VOLTAGE = 12e-21 * DENSITY * START * math.log(CATHODE / WIRE)  # 12 Td at START


def per_collision(result, cpu_seconds: float) -> dict:
    collisions = float(result.collisions.sum())
    return {"collisions": collisions, "cpu_seconds": cpu_seconds, "ns_per_collision": 1e9 * cpu_seconds / collisions,
            "null_per_real": result.null_collisions / collisions, "steps_per_collision": result.steps / collisions,
            "rejected_per_collision": result.rejected_steps / collisions}


def swarm_run() -> dict:
    """The uniform-field swarm at 12 Td: 3e7 real collisions, the reference time per collision."""
    start = time.process_time()
    result = simulate_swarm(reid_ramp(), 12.0, gas_temperature=0.0, particles=20_000, threads=1, seed=1,
                            tolerances={"mean_energy": 1e-9}, collision_budget=3e7)
    cpu = time.process_time() - start
    return {"collisions": result.collisions, "cpu_seconds": cpu, "ns_per_collision": 1e9 * cpu / result.collisions}


def counter_map(points: int = 512) -> FieldMap:
    axis = np.linspace(-CATHODE, CATHODE, points)
    x, y = np.meshgrid(axis, axis, indexing="ij")
    field = CoaxialField(WIRE, CATHODE, VOLTAGE)
    values = field.at(np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])).reshape(points, points, 3)
    spacing = axis[1] - axis[0]
    return FieldMap((axis[0], axis[0]), (spacing, spacing), values)


def runs() -> dict:
    """Every run's figures, the median round of REPEATS alternating rounds (each run once per round)."""
    gas = reid_ramp()
    plates = Device.parallel_plate(gas, 5e-3, 12e-21 * DENSITY * 5e-3, density=DENSITY, temperature=0.0)
    counter = Device.coaxial(gas, WIRE, CATHODE, VOLTAGE, density=DENSITY, temperature=0.0)
    mapped = Device(gas, DENSITY, 0.0, counter_map(), geometry=counter.geometry, collector="wire")
    cases = {
        "plates, exact flights, null collisions": (plates, "null-collision", (0, 0, 1e-4), 1e-6),
        "counter, integrator, null collisions": (counter, "null-collision", (START, 0, 0), 1e-6),
        "counter, integrator, path length": (counter, "path-length", (START, 0, 0), 1e-6),
        "counter field map (2D, 512^2), null collisions": (mapped, "null-collision", (START, 0, 0), 1e-6),
        "counter field map (2D, 512^2), null collisions, tolerance 1e-5": (mapped, "null-collision", (START, 0, 0),
                                                                           1e-5)}

    def tracked(device, method, start, tolerance, primaries, seed):
        return track(device, primaries=primaries, position=start, method=method, seed=seed, threads=1,
                     signal_window=None, tolerance=tolerance)

    simulate_swarm(reid_ramp(), 12.0, gas_temperature=0.0, particles=640, collision_budget=1e6, threads=1,
                   tolerances={"mean_energy": 0.5})  # compile
    for case in cases.values():
        tracked(*case, 2, 0)
    rounds = {name: [] for name in ["swarm", *cases]}
    for _ in range(REPEATS):
        rounds["swarm"].append(swarm_run())
        for name, case in cases.items():
            begin = time.process_time()
            result = tracked(*case, PRIMARIES, 1)
            rounds[name].append(per_collision(result, time.process_time() - begin) | {"gain": result.gain,
                                                                                       "drift_time": result.drift_time})
    out = {}
    for name, results in rounds.items():
        times = sorted(run["ns_per_collision"] for run in results)
        median = next(run for run in results if run["ns_per_collision"] == times[len(times) // 2])
        out[name] = median | {"ns_per_collision_all": [run["ns_per_collision"] for run in results]}
    return out


def interpolation() -> dict:
    rng = np.random.default_rng(1)
    out = {}
    for name, shape in (("3D map 64^3", (64, 64, 64)), ("2D map 512^2", (512, 512))):
        values = rng.normal(size=(*shape, 3))
        fieldmap = FieldMap((0.0,) * len(shape), (1.0,) * len(shape), values)
        top = 63 if len(shape) == 3 else 511
        # points along random walks of small steps (as a tracked particle reads the map), not scattered ones
        steps = rng.normal(0.0, 0.05, (1_000_000, 3))
        points = np.mod(np.cumsum(steps, axis=0) + top / 2, top)
        out_values = np.zeros_like(points)
        kind, parameters, meta, grid, user = fieldmap.arrays()
        field_values(False, kind, parameters, meta, grid, user, points[:10], out_values[:10])
        start = time.perf_counter()
        field_values(False, kind, parameters, meta, grid, user, points, out_values)
        seconds = time.perf_counter() - start
        out[name] = {"evaluations_per_second": points.shape[0] / seconds, "ns_per_evaluation": 1e9 * seconds / 1e6}
    analytic = CoaxialField(WIRE, CATHODE, VOLTAGE)
    points = rng.uniform(-CATHODE, CATHODE, (1_000_000, 3))
    kind, parameters, meta, grid, user = analytic.arrays()
    values = np.zeros_like(points)
    start = time.perf_counter()
    field_values(False, kind, parameters, meta, grid, user, points, values)
    seconds = time.perf_counter() - start
    out["analytic coaxial field"] = {"evaluations_per_second": 1e6 / seconds, "ns_per_evaluation": 1e3 * seconds}
    return out


def main() -> None:
    load_start = os.getloadavg()
    measured = runs()
    rows = {"machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, Python "
                       f"{platform.python_version()}",
            "load_average_at_start": load_start, "load_average_at_end": os.getloadavg(), "repeats": REPEATS,
            "primaries": PRIMARIES, "swarm": measured.pop("swarm"), "tracking": measured,
            "interpolation": interpolation()}
    atomic_write_json(RESULTS / "tracking.json", rows)
    reference = rows["swarm"]["ns_per_collision"]
    lines = [f"| {name} | {run['ns_per_collision']:.0f} | {run['ns_per_collision'] / reference:.2f} "
             f"({min(run['ns_per_collision_all']) / max(rows['swarm']['ns_per_collision_all']):.2f}-"
             f"{max(run['ns_per_collision_all']) / min(rows['swarm']['ns_per_collision_all']):.2f}) | "
             f"{run['steps_per_collision']:.2f} | {run['rejected_per_collision']:.2f} | {run['null_per_real']:.2f} |"
             for name, run in rows["tracking"].items()]
    maps = [f"| {name} | {run['ns_per_evaluation']:.1f} | {run['evaluations_per_second']:.3g} |"
            for name, run in rows["interpolation"].items()]
    text = f"""# Particle tracking benchmark (Reid's ramp, N = 1e24 m^-3, one thread)

Machine: {rows['machine']}; load average {rows['load_average_at_start'][0]:.2f} at the start,
{rows['load_average_at_end'][0]:.2f} at the end (the machine is shared: CPU time, {REPEATS} alternating rounds, the
median round quoted; in brackets the extremes of the ratio over all rounds).
{PRIMARIES} primaries a tracking run (1-3 million real collisions).

Reference: the uniform-field swarm (simulate_swarm, 12 Td, 3e7 collisions): {reference:.0f} ns of CPU time per real
collision.

| run | CPU ns per real collision | / swarm (range) | steps per collision | rejected steps | null per real |
|---|---|---|---|---|---|
{chr(10).join(lines)}

The counter's field spans 0.1 to 700 Td between its electrodes (12 Td at the start, 1.5 mm from the wire).
Target: a non-uniform field within 3x of the uniform-field swarm per real collision (the null-collision method,
the default; the path-length method is Krasov's, kept to check it).

Field evaluation alone (1e6 points along random walks of 0.05-cell steps, one thread; the analytic field at
scattered points):

| field | ns per evaluation | evaluations/s |
|---|---|---|
{chr(10).join(maps)}
"""
    atomic_write_text(RESULTS / "tracking.md", text)
    print(text)


if __name__ == "__main__":
    main()
