"""EDMD speed against a published C code, run side by side on this machine.

The reference is F. Smallenburg's event-driven code (Efficient event-driven
simulations of hard spheres, Eur. Phys. J. E 45, 22 (2022);
https://github.com/FSmallenburg/EDMD), in its variants Single (neighbour
lists, one event per particle), Multi (neighbour lists, several events per
particle) and Cell (cell crossings as events, no lists). It is not on PyPI
or in Debian and is not vendored here: pass a checkout of that repository
with ``--source``. For each variant the script copies the variant's
``md<Variant>.c``, ``.h`` and ``mt19937ar.c`` into a temporary folder, sets
its parameters (FCC start, packing fraction, N, run length, no thermostat,
no snapshots) by rewriting the global initialisers, and builds it with the
flags of the repository's Makefiles (``-Ofast -funroll-loops -march=native``).

Both codes run one thread from an FCC start at the same state point
(diameter 1, mass 1, kT = 1) and are timed over the same simulated-time
window [L, 2 L]: the C code's rate is the difference of two runs (to L and
to 2 L) in collisions and in CPU time, which drops its start-up and the
melting of the crystal; collisionkit runs to L, then times the run from L
to 2 L (``bench_edmd.time_window``). At each state point every variant runs
once and the fastest is kept; then the fastest variant and collisionkit
alternate in ``--pairs`` pairs, and the table reports the median ratio of
the rates (collisions per CPU second) with its range, since this machine is
shared and noisy. CPU time is the child's own (``os.wait4``), as is its
peak memory; but Linux keeps a process's peak resident size across exec, so
every child's peak includes this script's at the fork (about 160 MB here):
peaks near that are floors, not the program's own.

With ``--dynamo DIR`` (the folder holding ``dynamod`` and ``dynarun`` of a
build of DynamO, https://github.com/dynamomd/DynamO: Bannerman, Sargant &
Lue, J. Comput. Chem. 32, 3329 (2011); not on PyPI or in Debian, built from
source with cmake and boost) DynamO runs too, at the state points of
``--dynamo-sizes``, in ``--dynamo-pairs`` more alternating pairs: ``dynamod
-m 0`` makes the FCC start at n sigma^3 = 6 eta / pi, and its rate is the
difference of two ``dynarun -f`` runs (to L and 2 L; its pair collisions are
the two-particle events of its output).

Usage: python benchmarks/bench_edmd_reference.py --source PATH/TO/EDMD [--pairs 7] [--sizes 864 4000 ...]
       [--dynamo PATH/TO/BUILD --dynamo-sizes 4000 --dynamo-pairs 3]
Writes benchmarks/results/edmd_reference.md and .json.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from xml.etree import ElementTree

from collisionkit._io import atomic_write_text

sys.path.insert(0, str(Path(__file__).parent))
import bench_edmd  # noqa: E402  (the collisionkit side of the comparison)

RESULTS = Path(__file__).parent / "results"
FLAGS = ["-Wall", "-Ofast", "-funroll-loops", "-march=native"]  # the variants' Makefiles
VARIANTS = {"Single": "mdSingle", "Multi": "mdMulti", "Cell": "mdCell"}
# (particles, packing fraction, window L in simulated time): about 2e6 collisions a window (7e6 at 10^6 particles)
STATE_POINTS = {
    864: (864, 0.45, 150.0),
    4000: (4000, 0.2618, 130.0),
    32000: (32000, 0.45, 5.0),
    108000: (108000, 0.45, 1.5),
    1000188: (1000188, 0.45, 0.5),
}
# --dilute: a dilute gas, where collisionkit runs its cell-crossing engine (engine="auto") and the C Cell variant is
# at home; the window gives about 2e6 collisions as above (--dilute-sizes picks them)
DILUTE_POINTS = {
    4000: (4000, 0.1, 600.0),
    32000: (32000, 0.1, 75.0),
}


def variant_sources(source: Path, variant: str) -> dict[str, Path]:
    """The three files of a variant."""
    stem = VARIANTS[variant]
    folder = source / variant
    files = {f"{stem}.c": folder / f"{stem}.c", f"{stem}.h": folder / f"{stem}.h", "mt19937ar.c": folder / "mt19937ar.c"}
    missing = [name for name, path in files.items() if not path.exists()]
    if missing:
        raise SystemExit(f"--source {source}: not a checkout of FSmallenburg/EDMD (missing {variant}/{', '.join(missing)})")
    return files


def set_global(code: str, declaration: str, value: str) -> str:
    """Rewrite the initialiser of a global such as ``double maxtime = 10;``."""
    pattern = re.compile(rf"^({re.escape(declaration)}\s*=\s*)[^;]*;", re.MULTILINE)
    code, count = pattern.subn(rf"\g<1>{value};", code)
    if count != 1:
        raise SystemExit(f"could not set '{declaration}' in the C code (found {count} times)")
    return code


def build(source: Path, variant: str, folder: Path, particles: int, eta: float, duration: float) -> Path:
    """Build one variant set up for a run from an FCC start to simulated time ``duration``; the program's path."""
    files = variant_sources(source, variant)
    stem = VARIANTS[variant]
    code = files[f"{stem}.c"].read_text()
    for declaration, value in (
        ("double maxtime", repr(duration)),
        ("int makesnapshots", "0"),
        ("double writeinterval", repr(duration)),
        ("double snapshotinterval", repr(duration)),
        ("int initialconfig", "1"),
        ("double packfrac", repr(eta)),
        ("int N", str(particles)),
        ("const int usethermostat", "0"),
    ):
        code = set_global(code, declaration, value)
    folder.mkdir(parents=True, exist_ok=True)
    (folder / f"{stem}.c").write_text(code)
    shutil.copy(files[f"{stem}.h"], folder)
    shutil.copy(files["mt19937ar.c"], folder)
    subprocess.run(["gcc", *FLAGS, f"{stem}.c", "-o", "md", "-lm"], cwd=folder, check=True, capture_output=True)
    return folder / "md"


def run_reference(program: Path) -> tuple[int, float, float]:
    """(pair collisions, CPU seconds, peak memory in MB) of one run of the C code."""
    with tempfile.TemporaryFile("w+") as out:
        child = subprocess.Popen([str(program)], cwd=program.parent, stdout=out, stderr=subprocess.DEVNULL)
        _, status, usage = os.wait4(child.pid, 0)
        child.returncode = os.waitstatus_to_exitcode(status)
        if child.returncode != 0:
            raise SystemExit(f"{program} failed with exit code {child.returncode}")
        out.seek(0)
        output = out.read()
    counts = re.findall(r"Collisions: (\d+)", output)
    if not counts:
        raise SystemExit(f"no 'Collisions:' line in the output of {program}")
    return int(counts[-1]), usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024


def reference_rate(short: Path, long: Path) -> dict:
    """Collisions per CPU second of the C code over the window between its short and long runs."""
    collisions_short, cpu_short, _ = run_reference(short)
    collisions_long, cpu_long, memory = run_reference(long)
    collisions = collisions_long - collisions_short
    return {"collisions": collisions, "cpu_seconds": cpu_long - cpu_short,
            "rate": collisions / (cpu_long - cpu_short), "peak_memory_mb": memory}


def ours_rate(particles: int, eta: float, duration: float) -> dict:
    row = bench_edmd.in_subprocess(particles, eta, window=duration)
    return {**row, "rate": row["collisions"] / row["cpu_seconds"]}


def dynamo_start(dynamo: Path, folder: Path, particles: int, eta: float) -> Path:
    """DynamO's FCC start of ``particles`` hard spheres (4 C^3) at packing fraction ``eta``: its config file."""
    cells = round((particles / 4) ** (1 / 3))
    folder.mkdir(parents=True, exist_ok=True)
    config = folder / "config.start.xml"
    subprocess.run([str(dynamo / "dynamod"), "-m", "0", "-C", str(cells), "-d", repr(6 * eta / math.pi), "-o",
                    str(config)], cwd=folder, check=True, capture_output=True)
    return config


def run_dynamo(dynamo: Path, config: Path, duration: float) -> tuple[int, float, float, float]:
    """(pair collisions, CPU seconds, peak memory in MB, simulated time) of one ``dynarun`` to time ``duration``."""
    folder = config.parent
    command = [str(dynamo / "dynarun"), str(config), "-f", repr(duration), "--out-data-file", "output.xml",
               "-o", "config.end.xml"]
    child = subprocess.Popen(command, cwd=folder, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(child.pid, 0)
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"{' '.join(command)} failed with exit code {os.waitstatus_to_exitcode(status)}")
    duration_tag = ElementTree.parse(folder / "output.xml").getroot().find(".//Duration")
    return (int(duration_tag.get("TwoParticleEvents")), usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024,
            float(duration_tag.get("Time")))


def dynamo_rate(dynamo: Path, config: Path, duration: float) -> dict:
    """Collisions per CPU second of DynamO over the window [duration, 2 duration]."""
    collisions_short, cpu_short, _, time_short = run_dynamo(dynamo, config, duration)
    collisions_long, cpu_long, memory, time_long = run_dynamo(dynamo, config, 2 * duration)
    collisions = collisions_long - collisions_short
    return {"collisions": collisions, "cpu_seconds": cpu_long - cpu_short, "rate": collisions / (cpu_long - cpu_short),
            "peak_memory_mb": memory, "simulated_time": [time_short, time_long]}


def spread(values: list[float]) -> str:
    return f"{statistics.median(values):.2f} ({min(values):.2f}-{max(values):.2f})"


def measure_point(source: Path, scratch: Path, particles: int, eta: float, duration: float, pairs: int,
                  variants: list[str], dynamo: Path | None = None, dynamo_pairs: int = 0) -> dict:
    programs = {}
    for variant in variants:
        folder = scratch / f"{variant}_{particles}_{eta}"
        programs[variant] = (build(source, variant, folder / "short", particles, eta, duration),
                             build(source, variant, folder / "long", particles, eta, 2 * duration))
    trial = {variant: reference_rate(*programs[variant]) for variant in variants}
    fastest = max(trial, key=lambda variant: trial[variant]["rate"])
    print(f"N = {particles}, eta = {eta}: " + ", ".join(f"{v} {r['rate']:.3g}/s" for v, r in trial.items())
          + f"; fastest {fastest}", flush=True)
    # a first run of ours, not kept, fills numba's cache: no measured run compiles (nor counts the compiler's memory)
    ours_rate(particles, eta, duration / 100)
    reference, ours, loads = [], [], []
    for _ in range(pairs):
        loads.append(os.getloadavg()[0])
        reference.append(reference_rate(*programs[fastest]))
        ours.append(ours_rate(particles, eta, duration))
        print(f"  C {reference[-1]['rate']:.3g}/s ({reference[-1]['collisions']} collisions), collisionkit "
              f"{ours[-1]['rate']:.3g}/s ({ours[-1]['collisions']}), ratio {ours[-1]['rate'] / reference[-1]['rate']:.2f}",
              flush=True)
    row = {"particles": particles, "packing_fraction": eta, "window": duration, "variant_trial": trial,
           "fastest_variant": fastest, "reference": reference, "collisionkit": ours,
           "ratios": [a["rate"] / b["rate"] for a, b in zip(ours, reference)], "load_averages": loads}
    if dynamo is not None and dynamo_pairs:
        config = dynamo_start(dynamo, scratch / f"dynamo_{particles}_{eta}", particles, eta)
        row["dynamo"], row["dynamo_collisionkit"] = [], []
        for _ in range(dynamo_pairs):
            row["dynamo"].append(dynamo_rate(dynamo, config, duration))
            row["dynamo_collisionkit"].append(ours_rate(particles, eta, duration))
            print(f"  DynamO {row['dynamo'][-1]['rate']:.3g}/s ({row['dynamo'][-1]['collisions']} collisions), "
                  f"collisionkit {row['dynamo_collisionkit'][-1]['rate']:.3g}/s", flush=True)
        row["dynamo_ratios"] = [a["rate"] / b["rate"] for a, b in zip(row["dynamo_collisionkit"], row["dynamo"])]
    return row


def table(rows: list[dict], pairs: int, load_before: float, load_after: float) -> str:
    lines = [
        "# EDMD speed against Smallenburg's C code (one core, CPU time)",
        "",
        f"Machine: {bench_edmd.machine()}; load average {load_before:.2f} before, {load_after:.2f} after "
        "(2 cores shared with other jobs). Peak memory includes this script's at the fork (~160 MB). C code built with gcc "
        f"{' '.join(FLAGS)}; at each point every variant ran once and the fastest was kept; then {pairs} "
        "alternating pairs over the same simulated-time window [L, 2 L] from an FCC start.",
        "",
        "| N | eta | L | trial rates of the C variants (collisions/CPU-s) | fastest | C (median) | collisionkit (median) "
        "| ratio: median (range) | peak memory C / collisionkit (MB) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for row in rows:
        trial = ", ".join(f"{variant} {result['rate']:.3g}" for variant, result in row["variant_trial"].items())
        memory_c = max(result["peak_memory_mb"] for result in row["reference"])
        memory_ours = max(result["peak_memory_mb"] for result in row["collisionkit"])
        lines.append(
            f"| {row['particles']:,} | {row['packing_fraction']:.4f} | {row['window']:g} | {trial} | "
            f"{row['fastest_variant']} | {statistics.median(r['rate'] for r in row['reference']):.3g} | "
            f"{statistics.median(r['rate'] for r in row['collisionkit']):.3g} | {spread(row['ratios'])} | "
            f"{memory_c:.0f} / {memory_ours:.0f} |"
        )
    dynamo_rows = [row for row in rows if "dynamo" in row]
    if dynamo_rows:
        lines += [
            "",
            "DynamO (built from source, Release), the same windows, alternating with collisionkit:",
            "",
            "| N | eta | pairs | DynamO collisions/CPU-s (median) | collisionkit (median) | ratio: median (range) "
            "| peak memory DynamO (MB) |",
            "|---|---|---|---|---|---|---|",
        ]
        for row in dynamo_rows:
            lines.append(
                f"| {row['particles']:,} | {row['packing_fraction']:.4f} | {len(row['dynamo'])} | "
                f"{statistics.median(r['rate'] for r in row['dynamo']):.3g} | "
                f"{statistics.median(r['rate'] for r in row['dynamo_collisionkit']):.3g} | "
                f"{spread(row['dynamo_ratios'])} | {max(r['peak_memory_mb'] for r in row['dynamo']):.0f} |"
            )
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", type=Path, required=True, help="a checkout of github.com/FSmallenburg/EDMD")
    parser.add_argument("--pairs", type=int, default=7, help="alternating runs of the two codes per state point")
    parser.add_argument("--sizes", type=int, nargs="*", default=[864, 4000, 32000, 108000],
                        help=f"state points by N, of {sorted(STATE_POINTS)}")
    parser.add_argument("--variants", nargs="+", default=list(VARIANTS), choices=list(VARIANTS))
    parser.add_argument("--dilute", action="store_true", help="also eta = 0.1 at --dilute-sizes (after --sizes)")
    parser.add_argument("--dilute-sizes", type=int, nargs="+", default=[4000], choices=sorted(DILUTE_POINTS),
                        help="the sizes of the dilute points")
    parser.add_argument("--output", default="edmd_reference", help="stem of the result files in benchmarks/results")
    parser.add_argument("--dynamo", type=Path, help="a folder holding DynamO's dynamod and dynarun")
    parser.add_argument("--dynamo-sizes", type=int, nargs="+", default=[4000], help="state points (by N) to run DynamO at")
    parser.add_argument("--dynamo-pairs", type=int, default=3, help="alternating pairs of DynamO and collisionkit")
    args = parser.parse_args()
    if args.pairs < 1:
        raise SystemExit(f"--pairs must be >= 1; got {args.pairs}")
    unknown = [n for n in args.sizes if n not in STATE_POINTS]
    if unknown:
        raise SystemExit(f"--sizes must be among {sorted(STATE_POINTS)}; got {unknown}")
    points = [STATE_POINTS[size] for size in args.sizes] + [DILUTE_POINTS[n] for n in args.dilute_sizes] * args.dilute
    if not points:
        raise SystemExit("no state point: give --sizes or --dilute")
    load_before = os.getloadavg()[0]
    started = time.time()
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        for particles, eta, duration in points:
            dynamo_points = [STATE_POINTS[n][:2] for n in args.dynamo_sizes if n in STATE_POINTS]
            with_dynamo = args.dynamo is not None and (particles, eta) in dynamo_points
            rows.append(measure_point(args.source, Path(scratch), particles, eta, duration, args.pairs, args.variants,
                                      args.dynamo if with_dynamo else None, args.dynamo_pairs))
    text = table(rows, args.pairs, load_before, os.getloadavg()[0])
    print(text)
    print(f"{time.time() - started:.0f} s")
    RESULTS.mkdir(exist_ok=True)
    atomic_write_text(RESULTS / f"{args.output}.md", text)
    atomic_write_text(RESULTS / f"{args.output}.json",
                      json.dumps({"machine": bench_edmd.machine(), "flags": FLAGS, "pairs": args.pairs,
                                  "rows": rows}, indent=2) + "\n")


if __name__ == "__main__":
    main()
