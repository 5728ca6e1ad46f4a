"""Run ThunderBoltz on Reid's ramp model and print one JSON record (helper of bench_thunderboltz.py).

This script runs inside the ThunderBoltz venv (ThunderBoltz 0.4.4 pins
numpy<=1.27 and matplotlib<=3.9, so it cannot live in the project venv):

    /tmp/tbv/bin/python benchmarks/_thunderboltz_runner.py --workdir /tmp/tb_bench --build native \
        --reduced-field 12 --electrons 20000 --collisions 2e7 --rate-coefficient 2.2e-14

What it does:

1. builds the ThunderBoltz binary once per build into ``WORKDIR/bin-<build>``
   and records the compile time there: ``shipped`` is the wrapper's own
   ``ThunderBoltz.compile_from`` (``g++ -std=c++17 ...``, no -O flag, i.e.
   -O0, exactly what ``ThunderBoltz(...).run()`` does); ``native`` is the
   same command with ``-O3 -march=native``;
2. writes the input deck with the ThunderBoltz Python API
   (``run(dryrun=True, bin_path=...)``) into a fresh simulation folder: two
   tabulated cross sections (``ElasticFixedParticle2``,
   ``InelasticFixedParticle2``), one background particle at rest (T = 0 K;
   with a fixed background every gas particle is identical, so one carries
   the density ``1 / L^3``), E from E/N, the time step from ThunderBoltz's own
   ``autostep`` rule (an electron of ``EP_0`` = 10 eV gains at most ``DE`` =
   0.1 eV per step), capped so that the mean collision probability per step
   stays <= 0.1 (the rule alone gives 0.1 at 12 Td but 0.6 at 1 Td), times
   ``--step-scale``; the number of steps from the wanted number of real
   collisions;
3. runs ``./thunderboltz.bin input.in`` itself, timing only that process
   (wall clock and the child's CPU time); the wrapper's own ``run()`` polls
   the child every 2 s, which would round the wall time up;
4. reads the outputs with the wrapper (``get_timeseries``): real collisions
   from ``Counts.dat`` (cumulative counts of accepted collisions per
   process), mean energy ``Mi``, flux drift ``Vzi`` and the bulk drift as the
   slope of ``Rzi``; averages over the second half of the run, errors from 8
   blocks.

With ``--lxcat FILE`` (``bench_thunderboltz_gas.py``) the model is a real gas
read by ThunderBoltz's own LXCat reader (``CrossSections.from_LXCat``) from
the same file collisionkit ships: every process on the fixed background
(``set_fixed_background``: ``ElasticFixedParticle2``,
``InelasticFixedParticle2``; ionization never moves its target), equal
energy sharing after ionization (``add_differential_model("Ionization",
"Equal")``; ThunderBoltz's default gives the ejected electron no energy),
the gas mass from the ELASTIC block's mass ratio, ``--vsigma-samples``
pairs for ThunderBoltz's per-step estimate of (v sigma)_max (its ``VS``) and
``--carry-remainder`` (its ``CR = 1``: the fractional number of candidate
pairs of a process is carried to the next step, as Bird's NTC scheme does;
with its default ``CR = 0`` a process with less than one candidate pair per
step, as most of argon's 37 excitations have, is never tried).
"""

from __future__ import annotations

import argparse
import importlib.metadata
import json
import math
import resource
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

import thunderboltz as tb
from thunderboltz import CrossSections, Process, ThunderBoltz

QE = 1.602176565e-19  # ThunderBoltz's C++ constants (DSMC0D.h)
ME = 9.10938215e-31
AMU = 1.660538921e-27
ELECTRON_AMU = ME / AMU
REID_MASS_RATIO = 1.37145e-4  # m / M
TOP_ENERGY = 100.0  # eV, same tabulation as collisionkit.transport.reid_ramp()
GAS_DENSITY = 1e24  # m^-3; N-scaled results do not depend on it
OUTPUT_STRIDE = 100  # ThunderBoltz default OS
BLOCKS = 8
MAX_COLLISION_PROBABILITY = 0.1  # per electron and step
NATIVE_FLAGS = "-O3 -march=native"


def reid_cross_sections() -> CrossSections:
    """Reid's ramp as two ThunderBoltz processes on a fixed background."""
    elastic = Process("ElasticFixedParticle2", name="elastic",
                      cs_data=[[0.0, 6e-20], [TOP_ENERGY, 6e-20]])
    excitation = Process("InelasticFixedParticle2", name="excitation", threshold=0.2,
                         cs_data=[[0.2, 0.0], [TOP_ENERGY, 1e-19 * (TOP_ENERGY - 0.2)]])
    cs = CrossSections()
    cs.add_processes([elastic, excitation])
    return cs


def lxcat_cross_sections(path: str) -> tuple[CrossSections, float]:
    """ThunderBoltz's own reading of an LXCat file, on a fixed background; and the electron/gas mass ratio."""
    cs = CrossSections().from_LXCat(path)
    cs.set_fixed_background(True)
    cs.add_differential_model("Ionization", "Equal")
    blocks = tb.parsing.read_LXCat_cs(path)
    ratios = blocks.loc[blocks.process_type.isin(["ELASTIC", "EFFECTIVE"]), "target_mass_ratio"].dropna().unique()
    if len(ratios) != 1:
        raise RuntimeError(f"{path}: expected one electron/target mass ratio, found {list(ratios)}")
    return cs, float(ratios[0])


def build(workdir: Path, name: str) -> dict:
    """Compile the ThunderBoltz binary once (cached); return its path and compile time."""
    folder = workdir / f"bin-{name}"
    record = folder / "compile.json"
    if record.exists() and (folder / "thunderboltz.bin").exists():
        return json.loads(record.read_text())
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    start = time.perf_counter()
    if name == "shipped":
        ThunderBoltz(directory=str(folder)).compile_from(tb.src_path)  # the wrapper's hard-coded g++ command
        command = "g++ -std=c++17 DSMC0D.cpp -o thunderboltz.bin -Wall -Wsign-compare (ThunderBoltz.compile_from)"
    else:
        for source in Path(tb.src_path).iterdir():
            if source.suffix in (".cpp", ".h"):
                shutil.copy(source, folder)
        command = f"g++ {NATIVE_FLAGS} -std=c++17 DSMC0D.cpp -o thunderboltz.bin -Wall -Wsign-compare"
        subprocess.run(command.split(), cwd=folder, check=True, capture_output=True)
    info = {"build": name, "compile_command": command, "compile_seconds": time.perf_counter() - start,
            "binary": str(folder / "thunderboltz.bin")}
    record.write_text(json.dumps(info))
    return info


def time_step(reduced_field: float, rate_coefficient: float, delta_energy: float = 0.1,
              probe_energy: float = 10.0) -> float:
    """ThunderBoltz's autostep rule DT = DE / (E v(EP_0)) (tb.py, _impose_nprod_crit), capped at P <= 0.1."""
    field = 1e-21 * reduced_field * GAS_DENSITY
    autostep = delta_energy / field * math.sqrt(ME / (2 * QE * probe_energy))
    return min(autostep, MAX_COLLISION_PROBABILITY / (GAS_DENSITY * rate_coefficient))


def simulation(folder: Path, args, dt: float, steps: int) -> ThunderBoltz:
    """A ThunderBoltz object with the input deck for this run (Reid's ramp, or an LXCat gas)."""
    cs, ratio = lxcat_cross_sections(args.lxcat) if args.lxcat else (reid_cross_sections(), REID_MASS_RATIO)
    extra = {"VS": args.vsigma_samples} if args.vsigma_samples else {}
    return ThunderBoltz(
        directory=str(folder), cs=cs, **extra,
        NP=[args.electrons, 1], TP=[args.initial_temperature, 0.0], VV=[0.0, 0.0],
        MP=[ELECTRON_AMU, ELECTRON_AMU / ratio], QP=[-1.0, 0.0],
        L=GAS_DENSITY ** (-1.0 / 3.0), DT=dt, NS=steps, Ered=args.reduced_field,
        OS=OUTPUT_STRIDE, FV=[steps + 1, steps + 1, 0], EX=0, CR=int(args.carry_remainder),
    )


def execute(folder: Path) -> dict:
    """Run the binary in its folder; wall clock and the child's CPU seconds."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    with open(folder / "thunderboltz.out", "w") as out, open(folder / "thunderboltz.err", "w") as err:
        status = subprocess.run(["./thunderboltz.bin", "input.in"], cwd=folder, stdout=out, stderr=err).returncode
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if status != 0:
        raise RuntimeError(f"thunderboltz.bin exited with {status}; see {folder / 'thunderboltz.err'}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {"wall_seconds": wall, "cpu_seconds": cpu}


def blocked(values: np.ndarray, statistic) -> tuple[float, float]:
    """Statistic over the whole window and its standard error from BLOCKS blocks."""
    pieces = [statistic(block) for block in np.array_split(values, BLOCKS)]
    return float(statistic(values)), float(np.std(pieces, ddof=1) / math.sqrt(BLOCKS))


def observables(calc: ThunderBoltz, electrons: int) -> dict:
    """Steady-state averages (second half of the run) and the real-collision counts."""
    series = calc.get_timeseries()
    counts = calc.get_counts()
    processes = [c for c in counts.columns if c != "step"]
    window = series[series.t >= 0.5 * series.t.max()]
    t, rz = window.t.to_numpy(), window.Rzi.to_numpy()
    mean_energy = blocked(window.Mi.to_numpy(), np.mean)
    flux = blocked(window.Vzi.to_numpy(), np.mean)
    pairs = np.column_stack([t, rz])
    bulk = blocked(pairs, lambda p: np.polyfit(p[:, 0], p[:, 1], 1)[0])
    steady = counts[counts.step >= window.step.min()]
    # electron time over the counted steps: the integral of the electron count (it grows by ionization)
    lo, hi = steady.step.min(), steady.step.max()
    grid = series[(series.step >= lo) & (series.step <= hi)]
    if "Ni" in grid and len(grid) > 1:  # Ni is the electron density: count / L^3 = count * GAS_DENSITY
        electron_time = float(np.trapz(grid.Ni.to_numpy(), grid.t.to_numpy())) / GAS_DENSITY  # numpy < 2 here
    else:
        electron_time = electrons * (hi - lo) * calc.tb_params["DT"]
    rates = {p: float((steady[p].iloc[-1] - steady[p].iloc[0]) / (GAS_DENSITY * electron_time)) for p in processes}
    energies = series.Mi.to_numpy()
    tail = window.Mi.to_numpy()
    steady_index = next((i for i in range(len(energies) - 3)
                         if abs(energies[i:i + 4].mean() - tail.mean()) < 1.5 * tail.std(ddof=1)), 0)
    final = counts.iloc[-1]
    return {"collisions": int(sum(final[p] for p in processes)),
            "collisions_by_process": {p.replace(".dat", ""): int(final[p]) for p in processes},
            "mean_energy": mean_energy[0], "mean_energy_error": mean_energy[1],
            "drift_velocity_flux": flux[0], "drift_velocity_flux_error": flux[1],
            "drift_velocity_bulk": bulk[0], "drift_velocity_bulk_error": bulk[1],
            "rate_coefficients": {p.replace(".dat", ""): k for p, k in rates.items()},
            "steady_from_seconds": float(window.t.min()), "simulated_seconds": float(series.t.max()),
            # the first output whose 4-output mean energy is within 3 standard errors (1.5 sigma of one
            # output) of the window mean: where a shorter run could have started averaging
            "relaxed_at_seconds": float(series.t.iloc[steady_index]),
            "electrons_final": round(series.Ni.iloc[-1] / GAS_DENSITY) if "Ni" in series else electrons}


def run(args) -> dict:
    workdir = Path(args.workdir)
    binary = build(workdir, args.build)
    dt = args.step_scale * time_step(args.reduced_field, args.rate_coefficient)
    per_step = args.electrons * GAS_DENSITY * args.rate_coefficient * dt  # expected real collisions per step
    steps = OUTPUT_STRIDE * max(4 * BLOCKS, math.ceil(args.collisions / per_step / OUTPUT_STRIDE))
    folder = workdir / args.tag
    shutil.rmtree(folder, ignore_errors=True)  # ThunderBoltz appends to old output files
    folder.mkdir(parents=True)
    calc = simulation(folder, args, dt, steps)
    calc.run(dryrun=True, bin_path=binary["binary"])  # writes input.in + cross_sections/, copies the binary
    timing = execute(folder)
    result = {"code": "ThunderBoltz", "version": importlib.metadata.version("thunderboltz"), **binary,
              "reduced_field": args.reduced_field, "electrons": args.electrons, "gas_particles": 1,
              "gas": args.lxcat or "Reid ramp", "vsigma_samples": args.vsigma_samples or 1000,
              "carry_remainder": bool(args.carry_remainder),
              "step_scale": args.step_scale,
              "gas_temperature_K": 0.0, "time_step": dt, "steps": steps, "collision_probability_per_step":
              args.rate_coefficient * GAS_DENSITY * dt, "folder": str(folder), **timing,
              **observables(calc, args.electrons)}
    result["collisions_per_second"] = result["collisions"] / result["wall_seconds"]
    result["collisions_per_cpu_second"] = result["collisions"] / result["cpu_seconds"]
    if not args.keep:
        shutil.rmtree(folder)
    return result


def parse(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workdir", required=True)
    parser.add_argument("--build", choices=("shipped", "native"), default="native")
    parser.add_argument("--tag", default="run")
    parser.add_argument("--reduced-field", type=float, default=12.0)
    parser.add_argument("--electrons", type=int, default=20_000)
    parser.add_argument("--collisions", type=float, default=2e7, help="wanted real collisions (sets NS)")
    parser.add_argument("--rate-coefficient", type=float, required=True,
                        help="expected total rate coefficient k (m^3/s), only to size NS")
    parser.add_argument("--step-scale", type=float, default=1.0, help="multiplies the time step")
    parser.add_argument("--initial-temperature", type=float, default=2.0 / 3.0, help="electron TP (eV)")
    parser.add_argument("--lxcat", help="an LXCat file: the gas instead of Reid's ramp")
    parser.add_argument("--vsigma-samples", type=int, default=0,
                        help="ThunderBoltz's VS (pairs sampled per step for (v sigma)_max); 0: its default")
    parser.add_argument("--carry-remainder", action="store_true",
                        help="CR = 1: carry the fractional number of candidate pairs to the next step (Bird's NTC); "
                             "ThunderBoltz's default CR = 0 drops it, which loses the collisions of weak processes")
    parser.add_argument("--keep", action="store_true", help="keep the simulation folder")
    return parser.parse_args(argv)


if __name__ == "__main__":
    json.dump(run(parse()), sys.stdout)
    print()
