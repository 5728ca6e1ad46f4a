"""Benchmark of swarms in fields at any angle and in oscillating fields: CPU time per real collision.

Reid's ramp at 12 Td (amplitude for the oscillating field), 0 K, one thread,
against the static-field cases (E alone; E perpendicular to B; B at 60
degrees). CPU time (``time.process_time``) of the whole call; the cases run
in turn, ``--repeats`` rounds (3 by default), and the table gives each
case's median, so a change of load on the shared machine falls on every
case alike; the load averages at the start and the end are written too.
Each AC case is compared with its static counterpart (the same B). Run it
also with ``PYTHONPATH`` pointing at an older checkout to time that code
(the cases it cannot run are skipped). Writes benchmarks/results/fields.md
and fields.json (``--tag`` names the rows of another checkout, written to
fields_<tag>.json). ``--compare OLD_SRC`` times this checkout and the one
whose ``src`` is OLD_SRC in alternating child processes (one round each,
``--repeats`` times) and writes benchmarks/results/fields_compare.md: each
case's median and range before and after, and of its ratio to E alone.
``--baseline REVISION`` does the same against the ``src`` of a git revision
of this repository (exported to a temporary directory), which runs only the
cases its code can (for ``015b4fc^``, the code issue 20 was filed against:
E alone and E perpendicular to B), and writes
benchmarks/results/fields_baseline.md: each case against that revision's
static-field cost. ``--collisions`` sets the collisions a run (2e7).

    NUMBA_CACHE_DIR=.numba_cache .venv/bin/python benchmarks/bench_fields.py
    NUMBA_CACHE_DIR=.numba_cache .venv/bin/python benchmarks/bench_fields.py --compare /tmp/old/src --repeats 5
    NUMBA_CACHE_DIR=.numba_cache .venv/bin/python benchmarks/bench_fields.py --baseline 015b4fc^ --repeats 5
"""

from __future__ import annotations

import inspect
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _bench_common import exported_source

from collisionkit._io import atomic_write_json, atomic_write_text
from collisionkit.transport import reid_ramp, simulate_swarm

RESULTS = Path(__file__).parent / "results"
COLLISIONS = 2e7
# a cosine sampled at 16 points a period (linear between them): the waveform cases run the sampled-field kernels
# (:mod:`collisionkit._kernels.transport.waveform_magnetic`) on nearly the AC cases' field
SAMPLED_COSINE = [(k / 16, math.cos(2.0 * math.pi * k / 16)) for k in range(17)]
CASES = {
    "E alone": {},
    "E perpendicular to B (200 Hx)": {"reduced_magnetic_field": 200.0},
    "B at 60 deg (200 Hx)": {"reduced_magnetic_field": 200.0, "field_angle": 60.0},
    "AC, omega/N = 2e-14": {"reduced_frequency": 2e-14},
    "AC + B at 60 deg (200 Hx)": {"reduced_frequency": 2e-14, "reduced_magnetic_field": 200.0, "field_angle": 60.0},
    "waveform (sampled cosine)": {"reduced_frequency": 2e-14, "waveform": SAMPLED_COSINE},
    "waveform + B at 60 deg (200 Hx)": {"reduced_frequency": 2e-14, "waveform": SAMPLED_COSINE,
                                        "reduced_magnetic_field": 200.0, "field_angle": 60.0},
}
# each AC case against the static case of the same B
STATIC_OF = {"AC, omega/N = 2e-14": "E alone", "AC + B at 60 deg (200 Hx)": "B at 60 deg (200 Hx)",
             "waveform (sampled cosine)": "E alone", "waveform + B at 60 deg (200 Hx)": "B at 60 deg (200 Hx)"}


def cost(options: dict) -> dict:
    start = time.process_time()
    result = simulate_swarm(reid_ramp(), 12.0, gas_temperature=0.0, particles=10_000, threads=1, seed=1,
                            tolerances={"mean_energy": 1e-9}, collision_budget=COLLISIONS, **options)
    cpu = time.process_time() - start
    return {"collisions": result.collisions, "null_collisions": result.null_collisions, "cpu_seconds": cpu,
            "ns_per_collision": 1e9 * cpu / result.collisions, "mean_energy": result.mean_energy}


def alternate(sources: dict[str, str], repeats: int) -> tuple[dict[str, list[dict]], list[tuple]]:
    """Run this script once per round in a child process for each ``label: src`` of ``sources`` (``PYTHONPATH``
    = src), alternating the order from round to round; return each label's rounds and the load averages."""
    rounds = {label: [] for label in sources}
    loads = [os.getloadavg()]
    for k in range(repeats):
        order = list(sources.items()) if k % 2 == 0 else list(sources.items())[::-1]
        for label, src in order:
            tag = f"child_{label}_{k}"
            # each checkout its own numba cache: one shared would be recompiled at every switch (its stamp differs)
            cache = Path(os.environ.get("NUMBA_CACHE_DIR", ".numba_cache")) / f"compare_{label}"
            environment = {**os.environ, "PYTHONPATH": src, "NUMBA_CACHE_DIR": str(cache)}
            subprocess.run([sys.executable, __file__, "--repeats", "1", "--tag", tag, "--collisions", str(COLLISIONS)],
                           check=True, env=environment)
            path = RESULTS / f"fields_{tag}.json"
            rounds[label].append(json.loads(path.read_text()))
            path.unlink()
        loads.append(os.getloadavg())
    return rounds, loads


def spread(values: list[float], digits: int) -> str:
    """``median (min-max)`` of ``values``."""
    return f"{statistics.median(values):.{digits}f} ({min(values):.{digits}f}-{max(values):.{digits}f})"


def compare(old_src: str, repeats: int) -> None:
    """Alternate child processes of the old and this checkout, one round each, and tabulate both."""
    here = str(Path(__file__).resolve().parents[1] / "src")
    rounds, loads = alternate({"before": old_src, "after": here}, repeats)
    lines = ["# Fields benchmark: before and after", "",
             f"benchmarks/bench_fields.py --compare {old_src} --repeats {repeats}: {repeats} rounds, the old and this "
             f"checkout in alternating child processes, one run of each case a round (CPU time per real collision, "
             f"{COLLISIONS:.0e} collisions a run); load average {loads[0][0]:.1f} at the start, "
             f"{loads[-1][0]:.1f} at the end. "
             "Medians (range) over the rounds; the ratio is each round's ratio to that round's E alone.", "",
             "| case | ns before | ns after | null / real before -> after | ratio to E alone before "
             "| ratio to E alone after |", "|---|---|---|---|---|---|"]
    for name in rounds["after"][0]:
        if not isinstance(rounds["after"][0][name], dict):
            continue
        cells = {}
        for label in ("before", "after"):
            found = [found[name] for found in rounds[label] if name in found]
            if not found:
                cells[label] = ("", "", "")
                continue
            ns = [run["ns_per_collision"] for run in found]
            ratio = [run["ns_per_collision"] / each["E alone"]["ns_per_collision"]
                     for run, each in zip(found, rounds[label])]
            cells[label] = (spread(ns, 0), f"{found[0]['null_collisions'] / found[0]['collisions']:.2f}",
                            spread(ratio, 2))
        lines.append(f"| {name} | {cells['before'][0]} | {cells['after'][0]} | {cells['before'][1]} -> "
                     f"{cells['after'][1]} | {cells['before'][2]} | {cells['after'][2]} |")
    atomic_write_text(RESULTS / "fields_compare.md", "\n".join(lines) + "\n")


def baseline(revision: str, repeats: int) -> None:
    """Each case of this checkout against the static-field cost of the code at ``revision`` (issue 20's
    "today's static-field cost": the code the issue was filed against), alternating child processes."""
    here = str(Path(__file__).resolve().parents[1] / "src")
    with tempfile.TemporaryDirectory() as scratch:
        old_src = exported_source(revision, Path(scratch))
        rounds, loads = alternate({"baseline": old_src, "today": here}, repeats)
    old_static = {name for name in rounds["baseline"][0] if isinstance(rounds["baseline"][0][name], dict)}
    lines = ["# Fields benchmark against the static-field cost of an earlier revision", "",
             f"benchmarks/bench_fields.py --baseline {revision} --repeats {repeats}: the code of git revision "
             f"{revision} (the static cases it can run: {', '.join(sorted(old_static))}) and this checkout in "
             f"alternating child processes, one run of each case a round (CPU time per real collision, "
             f"{COLLISIONS:.0e} collisions a run); load average {loads[0][0]:.1f} at the start, "
             f"{loads[-1][0]:.1f} at the end. Medians (range) over the rounds of each round's ratio; 'static of its "
             "kind' is the old E alone for a case without B and the old E perpendicular to B for a case with B.", "",
             f"| case | ns today | ns at {revision} | x old E alone | x old static of its kind | x today's E alone |",
             "|---|---|---|---|---|---|"]
    with_b = "E perpendicular to B (200 Hx)"
    for name, options in CASES.items():
        found = [each[name]["ns_per_collision"] for each in rounds["today"] if name in each]
        if not found:
            continue
        old = [each[name]["ns_per_collision"] for each in rounds["baseline"] if name in each]
        kind = with_b if "reduced_magnetic_field" in options and with_b in old_static else "E alone"
        to_old_alone = [new / each["E alone"]["ns_per_collision"] for new, each in zip(found, rounds["baseline"])]
        to_old_kind = [new / each[kind]["ns_per_collision"] for new, each in zip(found, rounds["baseline"])]
        to_today = [new / each["E alone"]["ns_per_collision"] for new, each in zip(found, rounds["today"])]
        lines.append(f"| {name} | {spread(found, 0)} | {spread(old, 0) if old else ''} | {spread(to_old_alone, 2)} "
                     f"| {spread(to_old_kind, 2)} | {spread(to_today, 2)} |")
    atomic_write_text(RESULTS / "fields_baseline.md", "\n".join(lines) + "\n")


def main() -> None:
    global COLLISIONS
    if "--collisions" in sys.argv:
        COLLISIONS = float(sys.argv[sys.argv.index("--collisions") + 1])
    if "--baseline" in sys.argv:
        repeats = int(sys.argv[sys.argv.index("--repeats") + 1]) if "--repeats" in sys.argv else 3
        baseline(sys.argv[sys.argv.index("--baseline") + 1], repeats)
        return
    if "--compare" in sys.argv:
        repeats = int(sys.argv[sys.argv.index("--repeats") + 1]) if "--repeats" in sys.argv else 3
        compare(sys.argv[sys.argv.index("--compare") + 1], repeats)
        return
    tag = sys.argv[sys.argv.index("--tag") + 1] if "--tag" in sys.argv else ""
    repeats = int(sys.argv[sys.argv.index("--repeats") + 1]) if "--repeats" in sys.argv else 3
    accepted = inspect.signature(simulate_swarm).parameters
    cases = {name: options for name, options in CASES.items() if all(key in accepted for key in options)}
    for options in cases.values():  # compile
        simulate_swarm(reid_ramp(), 12.0, gas_temperature=0.0, particles=640, collision_budget=1e6, threads=1,
                       tolerances={"mean_energy": 0.05}, **options)
    load_start = os.getloadavg()
    runs = {name: [] for name in cases}
    for _ in range(repeats):
        for name, options in cases.items():
            runs[name].append(cost(options))
    rows = {name: {**min(found, key=lambda run: abs(run["ns_per_collision"] - statistics.median(
        run["ns_per_collision"] for run in found))), "ns_per_collision_runs": [run["ns_per_collision"] for run in found]}
        for name, found in runs.items()}
    rows["load_average_at_start"] = load_start
    rows["load_average_at_end"] = os.getloadavg()
    atomic_write_json(RESULTS / (f"fields_{tag}.json" if tag else "fields.json"), rows)
    if tag:
        return
    base = rows["E perpendicular to B (200 Hx)"]["ns_per_collision"]
    lines = ["# Swarms in fields at any angle and AC fields: CPU time per real collision", "",
             f"Reid's ramp, 12 Td (amplitude), 0 K, 10 000 particles, one thread, {COLLISIONS:.0e} collisions a run, "
             f"benchmarks/bench_fields.py: the median of {repeats} runs of each case, the cases in turn, on the "
             f"shared 2-core machine (load average {load_start[0]:.1f} at the start, "
             f"{rows['load_average_at_end'][0]:.1f} at the end: other jobs running). The ratio to E alone is the "
             f"median (and range) of each round's ratio to that round's E alone run.", "",
             "| case | ns per real collision (runs) | null / real | ratio to E alone (range) "
             "| ratio to E perpendicular to B | ratio to the static case of the same B |", "|---|---|---|---|---|---|"]
    for name in cases:
        row = rows[name]
        runs_text = ", ".join(f"{value:.0f}" for value in row["ns_per_collision_runs"])
        static = STATIC_OF.get(name)
        ratio = f"{row['ns_per_collision'] / rows[static]['ns_per_collision']:.2f}" if static in rows else ""
        firsts = rows["E alone"]["ns_per_collision_runs"]
        alone = [run / first for run, first in zip(row["ns_per_collision_runs"], firsts)]
        lines.append(f"| {name} | {row['ns_per_collision']:.0f} ({runs_text}) "
                     f"| {row['null_collisions'] / row['collisions']:.2f} "
                     f"| {statistics.median(alone):.2f} ({min(alone):.2f}-{max(alone):.2f}) "
                     f"| {row['ns_per_collision'] / base:.2f} | {ratio} |")
    atomic_write_text(RESULTS / "fields.md", "\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
