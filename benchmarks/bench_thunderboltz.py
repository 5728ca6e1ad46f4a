"""Side-by-side speed of collisionkit and ThunderBoltz on Reid's ramp model, one thread each.

Run from the repository root with the project venv:

    NUMBA_CACHE_DIR=.numba_cache .venv/bin/python benchmarks/bench_thunderboltz.py [--tb-python /tmp/tbv/bin/python]

ThunderBoltz (``pip install thunderboltz``, 0.4.4) pins numpy<=1.27 and
matplotlib<=3.9, so it lives in its own venv: if ``--tb-python`` does not
exist, the script creates that venv (``python3 -m venv /tmp/tbv`` and
``/tmp/tbv/bin/pip install thunderboltz``). ThunderBoltz is driven through
``benchmarks/_thunderboltz_runner.py`` in that venv; it needs ``g++``.

Model: Reid's ramp (elastic 6e-20 m^2, m/M = 1.37145e-4, excitation
1e-19 m^2 (eps - 0.2 eV)/eV above 0.2 eV, gas at 0 K), 20 000 electrons.
At the main field (12 Td) the two codes run ``--repeats`` times back to back
(alternating which goes first) and the speed ratio is taken per pair; the
ThunderBoltz build as shipped (the wrapper compiles without -O) and a run
with a 4x smaller time step are measured once. ``--extra-fields`` (1 and
24 Td by default) get one pair each.

Timing: compilation is excluded on both sides (a collisionkit warm-up call
loads the numba cache; ThunderBoltz is compiled once per build and the
compile time is recorded separately). ThunderBoltz wall time is the
``thunderboltz.bin`` process only; collisionkit wall time is the whole
``simulate_swarm`` call. CPU seconds are reported too because the machine is
shared (2 cores, other jobs): a ratio of CPU rates is less sensitive to load.
Writes benchmarks/results/thunderboltz.md and thunderboltz.json.
"""

from __future__ import annotations

import argparse
import importlib.metadata
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
os.environ.setdefault("NUMBA_CACHE_DIR", str(ROOT / ".numba_cache"))

from collisionkit._io import atomic_write_json, atomic_write_text  # noqa: E402
from collisionkit.transport import reid_ramp, simulate_swarm  # noqa: E402

RESULTS = Path(__file__).parent / "results"
RUNNER = Path(__file__).with_name("_thunderboltz_runner.py")
DEFAULT_TB_PYTHON = "/tmp/tbv/bin/python"
GAS_DENSITY = 1e24  # m^-3, both codes (N-scaled results do not depend on it)
ELEMENTARY_CHARGE = 1.602176634e-19
ELECTRON_MASS = 9.1093837015e-31
# Dias et al., Comput. Phys. Commun. 282, 108554 (2023), Table 1 (via /work/shared/reference/validation-data.md):
# mean energy (eV) and bulk drift velocity (m/s).
PUBLISHED = {
    1.0: {"LoKI-MC": (0.1014, 1.264e4), "MultiBolt": (0.1014, 1.272e4), "Raspopovic 1999": (0.1017, 1.273e4)},
    12.0: {"LoKI-MC": (0.2691, 6.838e4), "MultiBolt": (0.2688, 6.839e4), "Raspopovic 1999": (0.2703, 6.834e4)},
    24.0: {"LoKI-MC": (0.4081, 8.881e4), "MultiBolt": (0.40922, 8.8522e4), "Raspopovic 1999": (0.4113, 8.804e4)},
}


# ------------------------------------------------------------------ ThunderBoltz side


def ensure_thunderboltz(tb_python: Path) -> str:
    """Create the ThunderBoltz venv if it is missing; return the installed ThunderBoltz version."""
    if shutil.which("g++") is None:
        sys.exit("ThunderBoltz compiles its C++ with g++, which is not on PATH (e.g. apt-get install g++)")
    if not tb_python.exists():
        venv = tb_python.parent.parent
        print(f"creating the ThunderBoltz venv {venv} (python3 -m venv; pip install thunderboltz)", flush=True)
        try:
            subprocess.run([shutil.which("python3") or sys.executable, "-m", "venv", str(venv)], check=True)
            subprocess.run([str(venv / "bin" / "pip"), "install", "thunderboltz"], check=True)
        except (subprocess.CalledProcessError, OSError) as error:
            sys.exit(f"could not create the venv ({error}); run by hand: python3 -m venv {venv} && "
                     f"{venv}/bin/pip install thunderboltz, then pass --tb-python {tb_python}")
    probe = "import importlib.metadata as m, thunderboltz; print(m.version('thunderboltz'))"
    done = subprocess.run([str(tb_python), "-c", probe], capture_output=True, text=True)
    if done.returncode:
        sys.exit(f"{tb_python} cannot import thunderboltz:\n{done.stderr}")
    return done.stdout.strip()


def run_thunderboltz(tb_python: Path, workdir: Path, build: str, field: float, electrons: int,
                     collisions: float, rate_coefficient: float, tag: str, step_scale: float = 1.0) -> dict:
    """One ThunderBoltz run through the runner in its venv; the runner's JSON record."""
    command = [str(tb_python), str(RUNNER), "--workdir", str(workdir), "--build", build, "--tag", tag,
               "--reduced-field", str(field), "--electrons", str(electrons), "--collisions", str(collisions),
               "--rate-coefficient", str(rate_coefficient), "--step-scale", str(step_scale)]
    load = os.getloadavg()
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode:
        raise RuntimeError(f"ThunderBoltz runner failed:\n{done.stderr[-3000:]}")
    record = json.loads(done.stdout.strip().splitlines()[-1])
    record["load_average_before"] = load
    record["label"] = f"ThunderBoltz {build}" + ("" if step_scale == 1.0 else f", DT x {step_scale:g}")
    record.update(half_step_corrected(record, field))
    return record


def half_step_corrected(record: dict, field: float) -> dict:
    """ThunderBoltz samples v right after the collision stage, i.e. at the end of each step.

    The time average over the following free flight is larger by a DT/2 in
    velocity and by e E W DT/2 in energy; the bulk drift (a slope of <z>) has
    no such offset.
    """
    electric = 1e-21 * field * GAS_DENSITY
    acceleration = ELEMENTARY_CHARGE * electric / ELECTRON_MASS
    dt = record["time_step"]
    return {"drift_velocity_flux_time_averaged": record["drift_velocity_flux"] + 0.5 * acceleration * dt,
            "mean_energy_time_averaged": record["mean_energy"] + 0.5 * electric * record["drift_velocity_bulk"] * dt}


# ------------------------------------------------------------------ collisionkit side


def warm_up(field: float) -> float:
    """Load/compile the numba kernels and estimate the total rate coefficient (sizes ThunderBoltz's run)."""
    result = simulate_swarm(reid_ramp(), field, gas_temperature=0.0, particles=2000, collision_budget=5e6, threads=1,
                            seed=99,
                            tolerances={"mean_energy": 1e-9})
    return sum(result.rate_coefficients.values())


def run_collisionkit(field: float, particles: int, collisions: float, seed: int) -> dict:
    """One single-thread collisionkit run up to the collision budget."""
    load = os.getloadavg()
    wall, cpu = time.perf_counter(), time.process_time()
    result = simulate_swarm(reid_ramp(), field, gas_temperature=0.0, particles=particles, threads=1, seed=seed,
                            collision_budget=collisions, tolerances={"mean_energy": 1e-9})
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    return {"code": "collisionkit", "label": "collisionkit", "reduced_field": field, "electrons": particles,
            "collisions": result.collisions, "null_collisions": result.null_collisions, "wall_seconds": wall,
            "cpu_seconds": cpu, "kernel_seconds": result.seconds, "collisions_per_second": result.collisions / wall,
            "collisions_per_cpu_second": result.collisions / cpu,
            "mean_energy": result.mean_energy, "mean_energy_error": result.mean_energy_error,
            "drift_velocity_bulk": float(-result.drift_velocity_bulk[2]),
            "drift_velocity_bulk_error": float(result.drift_velocity_bulk_error[2]),
            "drift_velocity_flux": float(-result.drift_velocity_flux[2]),
            "drift_velocity_flux_error": float(result.drift_velocity_flux_error[2]),
            "rate_coefficients": result.rate_coefficients, "load_average_before": load}


# ------------------------------------------------------------------ the measurement plan


def measure_field(args, field: float, repeats: int, main: bool) -> dict:
    """Back-to-back pairs at one field (+ the shipped build and a DT/4 run at the main field)."""
    rate = warm_up(field)

    def tb(build, tag, collisions, scale=1.0):
        return run_thunderboltz(args.tb_python, args.workdir, build, field, args.electrons, collisions, rate, tag,
                                scale)

    pairs = []
    for repeat in range(repeats):
        seed = 1 + repeat
        if repeat % 2 == 0:
            ck = run_collisionkit(field, args.electrons, args.collisions, seed)
            tbr = tb("native", f"E{field:g}-r{repeat}", args.collisions)
        else:
            tbr = tb("native", f"E{field:g}-r{repeat}", args.collisions)
            ck = run_collisionkit(field, args.electrons, args.collisions, seed)
        pairs.append({"collisionkit": ck, "thunderboltz": tbr,
                      "ratio_wall": ck["collisions_per_second"] / tbr["collisions_per_second"],
                      "ratio_cpu": ck["collisions_per_cpu_second"] / tbr["collisions_per_cpu_second"]})
        print(f"{field:g} Td pair {repeat}: ratio (wall) {pairs[-1]['ratio_wall']:.2f}", flush=True)
    extra = []
    if main:
        shipped = tb("shipped", f"E{field:g}-shipped", args.check_collisions)
        ck = run_collisionkit(field, args.electrons, args.check_collisions, 100)
        extra.append({"collisionkit": ck, "thunderboltz": shipped,
                      "ratio_wall": ck["collisions_per_second"] / shipped["collisions_per_second"],
                      "ratio_cpu": ck["collisions_per_cpu_second"] / shipped["collisions_per_cpu_second"]})
        extra.append({"thunderboltz": tb("native", f"E{field:g}-dt4", args.check_collisions, 0.25)})
    return {"reduced_field": field, "rate_coefficient_estimate": rate, "pairs": pairs, "checks": extra,
            "ratio_wall_median": statistics.median(p["ratio_wall"] for p in pairs),
            "ratio_cpu_median": statistics.median(p["ratio_cpu"] for p in pairs)}


def machine() -> dict:
    gxx = subprocess.run(["g++", "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    versions = {name: importlib.metadata.version(name) for name in ("collisionkit", "numba", "numpy")}
    return {"cpu": platform.processor() or platform.machine(), "cores": os.cpu_count(),
            "python": platform.python_version(), "g++": gxx, **versions}


# ------------------------------------------------------------------ report


def deviation(value: float, reference: float) -> str:
    return f"{100 * (value / reference - 1):+.2f} %"


def run_row(run: dict, field: float) -> str:
    energy, bulk = PUBLISHED[field]["LoKI-MC"]
    flux = run["drift_velocity_flux"]
    return (f"| {run['label']} | {run['collisions']:.3g} | {run['wall_seconds']:.1f} | {run['cpu_seconds']:.1f} | "
            f"{run['collisions_per_second']:.3g} | {run['collisions_per_cpu_second']:.3g} | "
            f"{run['mean_energy']:.4f} ± {run['mean_energy_error']:.1g} ({deviation(run['mean_energy'], energy)}) | "
            f"{bulk_text(run)} ({deviation(run['drift_velocity_bulk'], bulk)}) | {flux:.4g} | "
            f"{run['load_average_before'][0]:.2f} |")


def bulk_text(run: dict) -> str:
    return f"{run['drift_velocity_bulk']:.5g} ± {run['drift_velocity_bulk_error']:.1g}"


def field_section(block: dict) -> str:
    field = block["reduced_field"]
    lines = [f"## {field:g} Td", "",
             "| run | real collisions | wall s | CPU s | real coll./s (wall) | per CPU s | mean energy (eV) (vs LoKI-MC) "
             "| bulk W (m/s) (vs LoKI-MC) | flux W (m/s) | load avg |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for pair in block["pairs"] + block["checks"]:
        lines += [run_row(pair[code], field) for code in ("collisionkit", "thunderboltz") if code in pair]
    lines += ["", "Published: " + "; ".join(f"{source} {energy} eV, {bulk:.5g} m/s"
                                           for source, (energy, bulk) in PUBLISHED[field].items()), ""]
    ratios = ", ".join(f"{p['ratio_wall']:.2f}" for p in block["pairs"])
    cpu = ", ".join(f"{p['ratio_cpu']:.2f}" for p in block["pairs"])
    lines += [f"Speed ratio collisionkit / ThunderBoltz (-O3 -march=native), real collisions per second, back-to-back "
              f"pairs: wall {ratios} (median **{block['ratio_wall_median']:.2f}**); CPU {cpu} "
              f"(median **{block['ratio_cpu_median']:.2f}**)."]
    for check in block["checks"]:
        if "ratio_wall" in check:
            lines += [f"Against the build as shipped (no -O): wall {check['ratio_wall']:.2f}, CPU {check['ratio_cpu']:.2f}."]
    tb_runs = [p["thunderboltz"] for p in block["pairs"] + block["checks"]]
    lines += ["", "ThunderBoltz samples velocities at the end of each step (after the collision stage); the "
              "time average over the free flight (value + a DT/2, energy + e E W DT/2): "
              + "; ".join(f"{r['label']} (P = {r['collision_probability_per_step']:.3f}/step): "
                          f"{r['mean_energy_time_averaged']:.4f} eV, flux W {r['drift_velocity_flux_time_averaged']:.5g} m/s"
                          for r in tb_runs), ""]
    return "\n".join(lines)


def report(data: dict) -> str:
    compile_lines = "; ".join(f"{build}: {seconds:.1f} s (`{command}`)"
                              for build, (seconds, command) in data["thunderboltz_compile"].items())
    m = data["machine"]
    header = f"""# collisionkit vs ThunderBoltz on Reid's ramp (one thread each)

Machine: {m['cpu']}, {m['cores']} cores, shared (other jobs running: see the load averages), Python {m['python']},
numba {m['numba']}, numpy {m['numpy']}, collisionkit {m['collisionkit']}; ThunderBoltz {data['thunderboltz_version']} with
{m['g++']}. Load average at start {data['load_average_at_start'][0]:.2f}, at end {data['load_average_at_end'][0]:.2f}.
Electrons: {data['electrons']} in both codes; target {data['collisions']:.3g} real collisions per run
({data['check_collisions']:.3g} for the shipped build and the DT/4 check). Compilation excluded; ThunderBoltz compile time
(recorded once, not counted): {compile_lines}.
"""
    body = "\n".join(field_section(block) for block in data["fields"])
    return header + "\n" + summary(data) + "\n" + body + "\n" + CAVEATS + f"\nCommand: `{data['command'].strip()}`\n"


def summary(data: dict) -> str:
    """One line per field: the median back-to-back ratios."""
    lines = ["## Summary: real collisions per second, collisionkit / ThunderBoltz (1 thread each)", "",
             "| E/N (Td) | pairs | ratio vs -O3 -march=native build, CPU s (median) | same, wall s (median) "
             "| ratio vs build as shipped (-O0), CPU / wall |", "|---|---|---|---|---|"]
    for block in data["fields"]:
        shipped = [c for c in block["checks"] if "ratio_cpu" in c]
        as_shipped = f"{shipped[0]['ratio_cpu']:.2f} / {shipped[0]['ratio_wall']:.2f}" if shipped else "not run"
        lines.append(f"| {block['reduced_field']:g} | {len(block['pairs'])} | {block['ratio_cpu_median']:.2f} | "
                     f"{block['ratio_wall_median']:.2f} | {as_shipped} |")
    return "\n".join(lines) + "\n"


CAVEATS = """## Fairness notes

* Same model, same thread count (1), same number of electrons, similar numbers of real collisions, compilation
  excluded on both sides. Real collisions: collisionkit's `SwarmResult.collisions`; ThunderBoltz's last row of
  `Counts.dat` (cumulative count of accepted collisions per process), so both are counted, not derived from rates.
* Methods differ. collisionkit: test particles in a fixed background, exact free flight between collisions
  with null collisions (Skullerud), no time step. ThunderBoltz: 0D DSMC with a time step, No-Time-Counter pair
  selection (candidate pairs N1 N2 (v sigma)_max DT / V, (v sigma)_max re-estimated every step from 999 random pairs,
  accept with v sigma / (v sigma)_max), the field push and the collisions split within a step, equal-weight
  particles. Here the background is one fixed particle at rest (`*FixedParticle2` processes, TP = 0: exactly 0 K;
  with a fixed background all gas particles are identical, so one particle carries the density 1/L^3 and the
  per-step loops do not touch thousands of idle gas particles - the cheapest valid setting for ThunderBoltz).
* ThunderBoltz time step: its own `autostep` rule (an electron at EP_0 = 10 eV gains at most DE = 0.1 eV per step),
  capped at a collision probability of 0.1 per step (the rule alone would give 0.6 at 1 Td). Its cost per collision
  grows as DT shrinks (per-step sweeps over all electrons and the (v sigma)_max sampling); the DT/4 row shows both
  the cost and the effect on the results.
* Build: the ThunderBoltz Python wrapper compiles `g++ -std=c++17 DSMC0D.cpp` with no optimization flag (-O0); the
  headline ratio uses the same source built with `-O3 -march=native` (numba also compiles with LLVM at -O3 for the
  host CPU). The as-shipped ratio is reported separately.
* Timing: ThunderBoltz = the `thunderboltz.bin` process alone (includes its input reading and its diagnostics
  written every 100 steps); the wrapper's own `run()` polls every 2 s, so it was not used for timing.
  collisionkit = the whole `simulate_swarm` call (setup, steady-state detection, estimators). collisionkit's run
  length is set by a collision budget checked every 25 samples and a minimum of 100 samples after the transient,
  so its counts overshoot the target; rates (collisions per second) are compared, not totals.
* Observables: ThunderBoltz mean energy and flux drift are its end-of-step samples averaged over the second half
  of the run (errors from 8 blocks, correlated samples so only indicative); bulk drift is the slope of its mean
  z position. collisionkit values come with errors over 16 independent groups. Both use a cross-section table
  up to 100 eV; ThunderBoltz evaluates the table at the centre-of-mass energy (mu g^2 / 2), collisionkit at the
  target-frame energy (m g^2 / 2): a 1.4e-4 relative difference, negligible here.
* The machine has 2 cores and other jobs were running: single-run numbers move by 10-30 %; compare the per-pair
  ratios (measured back to back, order alternated) and the CPU-second ratios.
"""


def parse(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tb-python", type=Path, default=Path(DEFAULT_TB_PYTHON),
                        help="python of the ThunderBoltz venv (created if missing)")
    parser.add_argument("--workdir", type=Path, default=Path("/tmp/thunderboltz_bench"),
                        help="ThunderBoltz builds and simulation folders")
    parser.add_argument("--field", type=float, default=12.0, help="main E/N (Td)")
    parser.add_argument("--extra-fields", type=float, nargs="*", default=[1.0, 24.0])
    parser.add_argument("--repeats", type=int, default=3, help="back-to-back pairs at the main field")
    parser.add_argument("--electrons", type=int, default=20_000)
    parser.add_argument("--collisions", type=float, default=5e7, help="real collisions per run")
    parser.add_argument("--check-collisions", type=float, default=2e7,
                        help="real collisions for the shipped-build and DT/4 runs")
    parser.add_argument("--from-json", action="store_true",
                        help="only rewrite thunderboltz.md from an existing thunderboltz.json")
    return parser.parse_args(argv)


def main(argv=None) -> None:
    args = parse(argv)
    if args.from_json:
        text = report(json.loads((RESULTS / "thunderboltz.json").read_text()))
        atomic_write_text(RESULTS / "thunderboltz.md", text)
        print(text)
        return
    for field in [args.field, *args.extra_fields]:
        if field not in PUBLISHED:
            sys.exit(f"no published values for {field} Td; choose from {sorted(PUBLISHED)}")
    version = ensure_thunderboltz(args.tb_python)
    for build in ("native", "shipped"):  # compile afresh, so the recorded compile times belong to this run
        shutil.rmtree(args.workdir / f"bin-{build}", ignore_errors=True)
    command = ["NUMBA_CACHE_DIR=.numba_cache .venv/bin/python benchmarks/bench_thunderboltz.py",
               *(sys.argv[1:] if argv is None else argv)]
    data = {"command": " ".join(command),
            "machine": machine(), "thunderboltz_version": version, "load_average_at_start": os.getloadavg(),
            "electrons": args.electrons, "collisions": args.collisions, "check_collisions": args.check_collisions,
            "published": {str(k): v for k, v in PUBLISHED.items()}}
    data["fields"] = [measure_field(args, args.field, args.repeats, True)]
    data["fields"] += [measure_field(args, field, 1, False) for field in args.extra_fields]
    data["load_average_at_end"] = os.getloadavg()
    data["thunderboltz_compile"] = compile_times(args.workdir)
    atomic_write_json(RESULTS / "thunderboltz.json", data)
    text = report(data)
    atomic_write_text(RESULTS / "thunderboltz.md", text)
    print(text)


def compile_times(workdir: Path) -> dict:
    """Compile time and command of each ThunderBoltz build (written by the runner)."""
    out = {}
    for build in ("native", "shipped"):
        record = workdir / f"bin-{build}" / "compile.json"
        if record.exists():
            info = json.loads(record.read_text())
            out[build] = (info["compile_seconds"], info["compile_command"])
    return out


if __name__ == "__main__":
    main()
