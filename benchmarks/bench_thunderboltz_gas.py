"""collisionkit and ThunderBoltz side by side on real argon (the same shipped IST-Lisbon LXCat file), one thread each.

Run from the repository root with the project venv:

    NUMBA_CACHE_DIR=.numba_cache .venv/bin/python benchmarks/bench_thunderboltz_gas.py [--repeats 3]

Both codes read ``src/collisionkit/transport/data/IST-Lisbon_Ar.txt``:
collisionkit through ``catalogue_gas("Ar")``, ThunderBoltz (0.4.4, its own
venv, see bench_thunderboltz.py) through its own LXCat reader
(``CrossSections.from_LXCat``; benchmarks/_thunderboltz_runner.py ``--lxcat``).
The gas is at 0 K in both (targets at rest): the one temperature both
treat exactly (ThunderBoltz draws thermal velocities as a sum of three
uniform numbers, not a Maxwellian, and collisionkit's 300 K default would
add superelastic-free thermal targets ThunderBoltz would approximate).
Elastic scattering isotropic with the file's momentum-transfer cross
section, excitation and ionization losses from the file, equal energy
sharing after ionization, in both.

Per field (100 and 30 Td by default): ``--repeats`` back-to-back pairs
(order alternated) of fixed-length runs, the same number of electrons and
similar numbers of real collisions, CPU time of the process (collisionkit:
the whole ``simulate_swarm`` call; ThunderBoltz: its binary). Both start
from a Maxwellian at the mean energy of a short collisionkit probe.

Time to the same accuracy, a relative standard error of ``--target``
(0.2 %) on the mean energy and the bulk drift: collisionkit runs to it by
its own stopping rule (``tolerances``), so its CPU time is measured, and the
scatter of the repeated runs checks its quoted errors (16 independent
groups). ThunderBoltz has no stopping rule: from its fixed-length runs,
``T(X) = T_relax + T_window (s_X / target)^2``, where ``T_window`` is the CPU
time of its averaging window (the second half), ``s_X`` the relative
standard error of the window average (two ways: its 8-block error and the
scatter of the repeated runs) and ``T_relax`` the CPU time before the first
output within 3 standard errors of the window mean. ThunderBoltz runs with
``CR = 1`` (Bird's NTC with the remainder carried); one run with its default
``CR = 0``, one with a 4x smaller step (at the first field) and one with 10x
more (v sigma)_max samples (``VS``, at the last field) show its biases.
Writes benchmarks/results/thunderboltz_argon.md and .json.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
os.environ.setdefault("NUMBA_CACHE_DIR", str(ROOT / ".numba_cache"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_thunderboltz import (  # noqa: E402
    DEFAULT_TB_PYTHON, RUNNER, compile_times, ensure_thunderboltz, half_step_corrected, machine,
)
from collisionkit._io import atomic_write_json, atomic_write_text  # noqa: E402
from collisionkit.transport import catalogue_files, catalogue_gas, simulate_swarm  # noqa: E402

RESULTS = Path(__file__).parent / "results"
GAS = "Ar"
OBSERVABLES = ("mean_energy", "drift_velocity_flux", "drift_velocity_bulk")
NAMES = {"mean_energy": "<e>", "drift_velocity_flux": "flux W", "drift_velocity_bulk": "bulk W"}


def ionization_rate(rates: dict) -> float:
    """The ionization rate coefficient (m^3/s) among a code's per-process rates (labels differ between codes)."""
    return sum(k for label, k in rates.items() if "Ionization" in label or "Ar+" in label)


# ------------------------------------------------------------------ the two codes


def probe(field: float) -> tuple[float, float]:
    """Load the numba cache; the steady mean energy (the initial energy of both codes) and total rate coefficient.

    2e4 collisions per electron: in argon at low E/N the energy relaxes over thousands of collisions (elastic
    losses of 2m/M per collision, rare excitations), so a short probe would start both codes below steady state.
    """
    result = simulate_swarm(catalogue_gas(GAS), field, gas_temperature=0.0, particles=1000, threads=1, seed=99,
                            collision_budget=2e7, tolerances={"mean_energy": 1e-9})
    return result.mean_energy, sum(result.rate_coefficients.values())


def run_collisionkit(field: float, args, seed: int, start_energy: float, tolerances=None) -> dict:
    """One single-thread collisionkit run: up to the collision budget, or to ``tolerances`` (its own stop)."""
    load = os.getloadavg()
    gas = catalogue_gas(GAS)
    wall, cpu = time.perf_counter(), time.process_time()
    if tolerances is None:
        result = simulate_swarm(gas, field, gas_temperature=0.0, particles=args.electrons, threads=1, seed=seed,
                                initial_energy=start_energy, collision_budget=args.collisions,
                                tolerances={"mean_energy": 1e-9})
    else:
        result = simulate_swarm(gas, field, gas_temperature=0.0, particles=args.electrons, threads=1, seed=seed,
                                initial_energy=start_energy, tolerances=tolerances)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    window = 1.0 - result.steady_from / result.simulated_time  # share of the simulated time that was averaged
    record = {"code": "collisionkit", "label": "collisionkit", "reduced_field": field, "electrons": args.electrons,
              "collisions": result.collisions, "null_collisions": result.null_collisions, "wall_seconds": wall,
              "cpu_seconds": cpu, "window_cpu_seconds": cpu * window, "relax_cpu_seconds": cpu * (1.0 - window),
              "converged": result.converged, "collisions_per_cpu_second": result.collisions / cpu,
              "mean_energy": result.mean_energy, "mean_energy_error": result.mean_energy_error,
              "ionization_rate": ionization_rate(result.rate_coefficients),
              "ionization_rate_error": ionization_rate(result.rate_coefficient_errors),
              "alpha_N": result.alpha_N, "load_average_before": load}
    for name in ("drift_velocity_flux", "drift_velocity_bulk"):
        record[name] = float(abs(getattr(result, name)[2]))
        record[f"{name}_error"] = float(getattr(result, f"{name}_error")[2])
    return record


def run_thunderboltz(args, field: float, rate: float, start_energy: float, tag: str, collisions: float,
                     step_scale: float = 1.0, vsigma_samples: int = 0, carry: bool = True) -> dict:
    """One ThunderBoltz run of the shipped argon file through the runner (in its venv)."""
    load = os.getloadavg()
    lxcat = catalogue_files(GAS)[0]
    command = [str(args.tb_python), str(RUNNER), "--workdir", str(args.workdir), "--build", "native", "--tag", tag,
               "--reduced-field", str(field), "--electrons", str(args.electrons), "--collisions", str(collisions),
               "--rate-coefficient", str(rate), "--step-scale", str(step_scale),
               "--initial-temperature", str(2.0 * start_energy / 3.0), "--lxcat", str(lxcat),
               "--vsigma-samples", str(vsigma_samples)] + (["--carry-remainder"] if carry else [])
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode:
        raise RuntimeError(f"ThunderBoltz runner failed:\n{done.stderr[-3000:]}")
    record = json.loads(done.stdout.strip().splitlines()[-1])
    record["load_average_before"] = load
    record["label"] = "ThunderBoltz" + ("" if step_scale == 1.0 else f", DT x {step_scale:g}") + (
        f", VS = {vsigma_samples}" if vsigma_samples else "") + ("" if carry else ", CR = 0 (its default)")
    record.update(half_step_corrected(record, field))
    simulated = record["simulated_seconds"]
    record["window_cpu_seconds"] = record["cpu_seconds"] * (1.0 - record["steady_from_seconds"] / simulated)
    record["relax_cpu_seconds"] = record["cpu_seconds"] * record["relaxed_at_seconds"] / simulated
    record["ionization_rate"] = ionization_rate(record["rate_coefficients"])
    return record


# ------------------------------------------------------------------ time to the same accuracy


def time_to_accuracy(runs: list[dict], target: float) -> dict:
    """CPU seconds to a relative standard error ``target`` per observable, from within-run errors and from scatter.

    For ThunderBoltz's fixed-length runs (collisionkit's runs to the target are timed directly).
    """
    window = statistics.mean(r["window_cpu_seconds"] for r in runs)
    relax = statistics.mean(r["relax_cpu_seconds"] for r in runs)
    out = {"window_cpu_seconds": window, "relax_cpu_seconds": relax}
    for name in OBSERVABLES:
        values = np.array([r[name] for r in runs])
        within = statistics.mean(r[f"{name}_error"] / abs(r[name]) for r in runs)
        scatter = float(values.std(ddof=1) / abs(values.mean())) if len(runs) > 1 else math.nan
        out[name] = {"relative_error_within": within, "relative_error_scatter": scatter,
                     "cpu_seconds_within": relax + window * (within / target) ** 2,
                     "cpu_seconds_scatter": relax + window * (scatter / target) ** 2}
    return out


def direct_accuracy(runs: list[dict]) -> dict:
    """collisionkit's runs to the target: their CPU time, and their quoted errors against their scatter."""
    out = {"cpu_seconds": [r["cpu_seconds"] for r in runs], "cpu_seconds_median": statistics.median(
        r["cpu_seconds"] for r in runs), "converged": all(r["converged"] for r in runs)}
    for name in OBSERVABLES:
        values = np.array([r[name] for r in runs])
        out[name] = {"relative_error_quoted": statistics.mean(r[f"{name}_error"] / abs(r[name]) for r in runs),
                     "relative_error_scatter": float(values.std(ddof=1) / abs(values.mean())) if len(runs) > 1
                     else math.nan}
    return out


def measure_field(args, field: float) -> dict:
    start_energy, rate = probe(field)
    pairs = []
    goal = {"mean_energy": args.target, "drift_velocity_bulk": args.target}
    for repeat in range(args.repeats):
        tag = f"Ar-E{field:g}-r{repeat}"
        order = ("ck", "tb") if repeat % 2 == 0 else ("tb", "ck")
        pair = {}
        for code in order:
            if code == "ck":  # run to the target by its own stopping rule: the time to accuracy, measured
                pair["collisionkit"] = run_collisionkit(field, args, 1 + repeat, start_energy, goal)
            else:
                pair["thunderboltz"] = run_thunderboltz(args, field, rate, start_energy, tag, args.collisions)
        pair["ratio_cpu"] = (pair["collisionkit"]["collisions_per_cpu_second"]
                             / pair["thunderboltz"]["collisions_per_cpu_second"])
        pairs.append(pair)
        print(f"{field:g} Td pair {repeat}: collision-rate ratio (CPU) {pair['ratio_cpu']:.2f}", flush=True)
    checks = []
    if field in args.dt_check_at:
        checks.append(run_thunderboltz(args, field, rate, start_energy, f"Ar-E{field:g}-dt4", args.check_collisions,
                                       step_scale=0.25))
        checks.append(run_thunderboltz(args, field, rate, start_energy, f"Ar-E{field:g}-cr0", args.check_collisions,
                                       carry=False))
    if field in args.vs_check_at:
        checks.append(run_thunderboltz(args, field, rate, start_energy, f"Ar-E{field:g}-vs",
                                       args.check_collisions / 3, vsigma_samples=10_000))  # ~8x the cost per collision
    ck = [p["collisionkit"] for p in pairs]
    tb = [p["thunderboltz"] for p in pairs]
    return {"reduced_field": field, "start_energy": start_energy, "rate_coefficient_estimate": rate,
            "pairs": pairs, "checks": checks,
            "ratio_cpu_median": statistics.median(p["ratio_cpu"] for p in pairs),
            "accuracy": {"collisionkit": direct_accuracy(ck), "thunderboltz": time_to_accuracy(tb, args.target)}}


# ------------------------------------------------------------------ report


def value(run: dict, name: str, digits: int = 5) -> str:
    return f"{run[name]:.{digits}g} ± {run[name + '_error']:.1g}"


def run_row(run: dict) -> str:
    extra = ""
    if run["code"] == "ThunderBoltz":
        extra = (f" (time-averaged: {run['mean_energy_time_averaged']:.4f} eV, flux "
                 f"{run['drift_velocity_flux_time_averaged']:.5g}; P = {run['collision_probability_per_step']:.3f}"
                 f"/step, {run['electrons']} -> {run['electrons_final']} electrons)")
    return (f"| {run['label']} | {run['collisions']:.3g} | {run['cpu_seconds']:.1f} | "
            f"{run['collisions_per_cpu_second']:.3g} | {value(run, 'mean_energy', 4)} | "
            f"{value(run, 'drift_velocity_bulk')} | {value(run, 'drift_velocity_flux')} | "
            f"{run['ionization_rate']:.3g} | {run['load_average_before'][0]:.2f} |{extra}")


def accuracy_rows(block: dict, target: float) -> list[str]:
    ck, tb = (block["accuracy"][c] for c in ("collisionkit", "thunderboltz"))
    n = len(block["pairs"])
    lines = [f"**Time to a relative standard error of {100 * target:g} % on <e> and bulk W** (CPU s, one thread):", "",
             f"* collisionkit, measured: runs to {100 * target:g} % by its own stopping rule took "
             + ", ".join(f"{t:.1f}" for t in ck["cpu_seconds"]) + f" CPU s (median **{ck['cpu_seconds_median']:.1f}**"
             f"; all converged: {ck['converged']}). Their quoted errors / the scatter of the {n} runs: "
             + "; ".join(f"{NAMES[o]} {100 * ck[o]['relative_error_quoted']:.2g} / "
                         f"{100 * ck[o]['relative_error_scatter']:.2g} %" for o in OBSERVABLES) + ".",
             "* ThunderBoltz, extrapolated from its fixed-length runs, T_relax + T_window (s / target)^2 with s from "
             f"its 8-block errors / from the scatter of the {n} runs (T_relax {tb['relax_cpu_seconds']:.3g} s, "
             f"T_window {tb['window_cpu_seconds']:.3g} s): "
             + "; ".join(f"{NAMES[o]} {tb[o]['cpu_seconds_within']:.3g} / {tb[o]['cpu_seconds_scatter']:.3g} s "
                         f"(s = {100 * tb[o]['relative_error_within']:.2g} / {100 * tb[o]['relative_error_scatter']:.2g} %)"
                         for o in OBSERVABLES) + "."]
    both = [max(tb["mean_energy"][k], tb["drift_velocity_bulk"][k]) for k in ("cpu_seconds_within", "cpu_seconds_scatter")]
    # collisionkit judged by the scatter of its runs instead of its quoted errors: its time scaled by (scatter/quoted)^2
    ck_scatter = ck["cpu_seconds_median"] * max(1.0, *((ck[o]["relative_error_scatter"] / target) ** 2
                                                     for o in ("mean_energy", "drift_velocity_bulk")))
    lines += [f"* ThunderBoltz on <e> and bulk W: {both[0]:.3g} s (block errors) / {both[1]:.3g} s (scatter): "
              f"**{both[0] / ck['cpu_seconds_median']:.2g} / {both[1] / ck['cpu_seconds_median']:.2g} times** "
              "collisionkit's measured time.",
              f"* If collisionkit's errors are taken from the scatter of its runs instead of its quoted errors, its time "
              f"scales to {ck_scatter:.3g} s (median time x (scatter / target)^2, the larger of <e> and bulk W), and "
              f"the ratio becomes {both[0] / ck_scatter:.2g} / {both[1] / ck_scatter:.2g}.", ""]
    return lines


def field_section(block: dict, target: float) -> str:
    field = block["reduced_field"]
    lines = [f"## {field:g} Td (both codes start from a Maxwellian of mean energy {block['start_energy']:.3f} eV)", "",
             "| run | real collisions | CPU s | real coll. per CPU s | <e> (eV) | bulk W (m/s) | flux W (m/s) "
             "| k_ion (m^3/s) | load avg | |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for pair in block["pairs"]:
        lines += [run_row(pair[code]) for code in ("collisionkit", "thunderboltz")]
    lines += [run_row(check) for check in block["checks"]]
    ratios = ", ".join(f"{p['ratio_cpu']:.2f}" for p in block["pairs"])
    lines += ["", f"Real collisions per CPU second, collisionkit / ThunderBoltz, back-to-back pairs: {ratios} "
              f"(median **{block['ratio_cpu_median']:.2f}**).", ""]
    lines += accuracy_rows(block, target)
    lines += [comparison(block), "", "ThunderBoltz's runs against collisionkit's mean (the checks isolate its biases, "
              "see the notes):", ""] + check_lines(block) + [""]
    return "\n".join(lines)


def comparison(block: dict) -> str:
    """Mean values of the two codes (over the repeats) and their difference in units of the combined error."""
    rows = ["| quantity | collisionkit | ThunderBoltz (end of step) | ThunderBoltz (time-averaged) | difference |",
            "|---|---|---|---|---|"]
    ck = [p["collisionkit"] for p in block["pairs"]]
    tb = [p["thunderboltz"] for p in block["pairs"]]
    for name, averaged in (("mean_energy", "mean_energy_time_averaged"), ("drift_velocity_bulk", None),
                           ("drift_velocity_flux", "drift_velocity_flux_time_averaged"), ("ionization_rate", None)):
        a = np.array([r[name] for r in ck])
        b = np.array([r[averaged or name] for r in tb])
        ea = a.std(ddof=1) / math.sqrt(a.size) if a.size > 1 else 0.0
        eb = b.std(ddof=1) / math.sqrt(b.size) if b.size > 1 else 0.0
        raw = np.mean([r[name] for r in tb])
        rows.append(f"| {name} | {a.mean():.5g} ± {ea:.1g} | {raw:.5g} | "
                    f"{b.mean():.5g} ± {eb:.1g} | {100 * (b.mean() / a.mean() - 1):+.2f} % |")
    return ("Values (mean ± standard error over the repeats; the difference uses ThunderBoltz's time-averaged "
            "value where it has one):\n\n" + "\n".join(rows))


def check_lines(block: dict) -> list[str]:
    """The check runs against collisionkit's mean over its repeats, in percent (what each of ThunderBoltz's biases does)."""
    ck = [p["collisionkit"] for p in block["pairs"]]
    base = {name: statistics.mean(r[name] for r in ck) for name in ("mean_energy", "drift_velocity_bulk",
                                                                     "ionization_rate")}
    lines = []
    for run in [p["thunderboltz"] for p in block["pairs"]][:1] + block["checks"]:
        energy = run.get("mean_energy_time_averaged", run["mean_energy"])
        late = run["relaxed_at_seconds"] / run["simulated_seconds"]
        lines.append(f"* {run['label']}{' (first of the repeats)' if run in [p['thunderboltz'] for p in block['pairs']] else ''}: "
                     f"<e> {100 * (energy / base['mean_energy'] - 1):+.2f} %, bulk W "
                     f"{100 * (run['drift_velocity_bulk'] / base['drift_velocity_bulk'] - 1):+.2f} %, k_ion "
                     f"{100 * (run['ionization_rate'] / base['ionization_rate'] - 1):+.1f} % against collisionkit"
                     + (f"; relaxed only at {100 * late:.0f} % of the run (still drifting: a lower bound of the shift)"
                        if late > 0.5 else "") + ".")
    return lines


def report(data: dict) -> str:
    m = data["machine"]
    compile_lines = "; ".join(f"{build}: {seconds:.1f} s (`{command}`)"
                              for build, (seconds, command) in data["thunderboltz_compile"].items())
    header = f"""# collisionkit vs ThunderBoltz on argon (IST-Lisbon LXCat, the same file), one thread each

Machine: {m['cpu']}, {m['cores']} cores, shared with other jobs (load averages per run below), Python {m['python']},
numba {m['numba']}, numpy {m['numpy']}, collisionkit {m['collisionkit']}; ThunderBoltz {data['thunderboltz_version']}
built with {m['g++']}: {compile_lines} (not counted). Load average at start {data['load_average_at_start'][0]:.2f},
at end {data['load_average_at_end'][0]:.2f}.
Gas: `{data['gas_file']}` (39 processes: elastic momentum transfer, 37 excitations, ionization), read by each code's
own LXCat reader; gas at 0 K in both. {data['electrons']} electrons in both; collisionkit runs to
{100 * data['target']:g} % on <e> and bulk W; ThunderBoltz runs are sized for {data['collisions']:.3g} real collisions
({data['check_collisions']:.3g} for the DT/4 and CR = 0 checks, a third of it for the VS check).
"""
    body = "\n".join(field_section(block, data["target"]) for block in data["fields"])
    return header + "\n" + body + "\n" + NOTES + f"\nCommand: `{data['command'].strip()}`\n"


NOTES = """## Fairness notes and where the values differ

* Same file, same processes: ThunderBoltz's reader (`CrossSections.from_LXCat`) and collisionkit's
  (`catalogue_gas("Ar")`) take the same 39 tables. Both scatter isotropically with the ELASTIC (momentum-transfer)
  table, subtract the thresholds, share the energy left after ionization equally (ThunderBoltz's default would
  give the new electron no energy, so the benchmark selects its `Equal` model) and keep the target at rest
  (ThunderBoltz `*FixedParticle2`, one background particle carrying the density; collisionkit at 0 K).
  ThunderBoltz evaluates the tables at the centre-of-mass energy, collisionkit at the target-frame energy
  (relative difference m/M = 1.4e-5).
* Methods: collisionkit follows each electron exactly between collisions (null collisions, no time step).
  ThunderBoltz is a time-stepped DSMC code: each step it re-estimates (v sigma)_max of every process from
  1000 random electron-gas pairs (`VS`), then draws N1 N2 (v sigma)_max DT / V No-Time-Counter candidate pairs per
  process and accepts each with v sigma / (v sigma)_max. Three biases follow, each shown by a check run:
  (1) the step: velocities are sampled at the end of a step (the time-averaged columns correct this to first
  order) and the push and the collisions are split (the DT/4 row); (2) (v sigma)_max is the largest of 1000
  samples, an under-estimate where few electrons reach a process (acceptance probabilities above 1 are cut
  to 1; the VS = 10000 row); (3) with its default `CR = 0` the fractional number of candidate pairs is dropped
  every step, about half a pair per process and step: argon's weak excitations (less than one pair per step)
  are then mostly never tried, the electrons lose less energy and the mean energy rises (the CR = 0 row).
  The main rows use `CR = 1` (the remainder carried, as in Bird's NTC).
* Cost: ThunderBoltz's cost per step grows with the number of processes (39 (v sigma)_max estimates of 1000 pairs
  each, with a linear search in a table per pair, and candidate pairs drawn process by process); collisionkit
  tests a trial against the summed table and scans the processes only at a real collision.
* Ionization: both codes let the swarm grow (collisionkit keeps its size by resampling, ThunderBoltz grows);
  bulk W is the centroid velocity in both (ThunderBoltz: the slope of its mean z position). ThunderBoltz's rate
  coefficients are counts divided by N times the integral of its electron count.
* Errors: collisionkit's over 16 independent groups of electrons, checked against the scatter of its repeated
  runs; ThunderBoltz's over 8 blocks of the second half of the run (correlated outputs within a block) and the
  scatter of its repeated runs, both shown. Three runs give a scatter that is itself uncertain by about 50 %.
* Time to accuracy: collisionkit's is measured (its runs stop at 0.2 %; they include its steady-state test and
  its minimum number of samples, a fixed cost that dominates at loose targets); ThunderBoltz's is extrapolated
  from its fixed-length runs (the standard error falls as one over the square root of the averaging time).
* Timing: CPU seconds of each code (the machine has 2 cores shared with other jobs; wall times move 10-30 %).
  ThunderBoltz's time includes its input reading and its output every 100 steps; collisionkit's the whole
  `simulate_swarm` call. Compilation excluded on both sides.
"""


def parse(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tb-python", type=Path, default=Path(DEFAULT_TB_PYTHON))
    parser.add_argument("--workdir", type=Path, default=Path("/tmp/thunderboltz_bench"))
    parser.add_argument("--fields", type=float, nargs="+", default=[100.0, 30.0], help="E/N (Td)")
    parser.add_argument("--repeats", type=int, default=3, help="back-to-back pairs per field")
    parser.add_argument("--electrons", type=int, default=20_000)
    parser.add_argument("--collisions", type=float, default=2e7, help="real collisions per ThunderBoltz run")
    parser.add_argument("--check-collisions", type=float, default=1.5e7,
                        help="real collisions of the DT/4 and VS check runs")
    parser.add_argument("--target", type=float, default=0.002, help="relative standard error aimed at")
    parser.add_argument("--dt-check-at", type=float, nargs="*", default=None,
                        help="fields of the DT/4 check run (default: the first field)")
    parser.add_argument("--vs-check-at", type=float, nargs="*", default=None,
                        help="fields of the VS = 10000 check run (default: the last field)")
    parser.add_argument("--append", action="store_true",
                        help="add the fields to those of the existing .json (same settings), replacing a field measured again")
    parser.add_argument("--from-json", action="store_true", help="only rewrite the .md from the .json")
    args = parser.parse_args(argv)
    args.dt_check_at = args.fields[:1] if args.dt_check_at is None else args.dt_check_at
    args.vs_check_at = args.fields[-1:] if args.vs_check_at is None else args.vs_check_at
    return args


def main(argv=None) -> None:
    args = parse(argv)
    if args.from_json:
        text = report(json.loads((RESULTS / "thunderboltz_argon.json").read_text()))
        atomic_write_text(RESULTS / "thunderboltz_argon.md", text)
        print(text)
        return
    version = ensure_thunderboltz(args.tb_python)
    command = ["NUMBA_CACHE_DIR=.numba_cache .venv/bin/python benchmarks/bench_thunderboltz_gas.py",
               *(sys.argv[1:] if argv is None else argv)]
    gas_file = catalogue_files(GAS)[0]
    data = {"command": " ".join(command), "machine": machine(), "thunderboltz_version": version,
            "load_average_at_start": os.getloadavg(), "gas_file": str(gas_file.relative_to(ROOT)),
            "electrons": args.electrons, "collisions": args.collisions, "check_collisions": args.check_collisions,
            "target": args.target, "fields": []}
    if args.append:
        previous = json.loads((RESULTS / "thunderboltz_argon.json").read_text())
        data["fields"] = [f for f in previous["fields"] if f["reduced_field"] not in args.fields]
        data["command"] = previous["command"] + "`, then `" + data["command"]
        data["load_average_at_start"] = previous["load_average_at_start"]
    for field in args.fields:
        data["fields"].append(measure_field(args, field))
        atomic_write_json(RESULTS / "thunderboltz_argon.json", data)  # keep what is measured so far
    data["load_average_at_end"] = os.getloadavg()
    data["thunderboltz_compile"] = compile_times(args.workdir)
    atomic_write_json(RESULTS / "thunderboltz_argon.json", data)
    text = report(data)
    atomic_write_text(RESULTS / "thunderboltz_argon.md", text)
    print(text)


if __name__ == "__main__":
    main()
