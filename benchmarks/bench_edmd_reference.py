"""EDMD speed against a published C code, run side by side on this machine.

The reference is the "Single" variant of F. Smallenburg's event-driven code
(Efficient event-driven simulations of hard spheres, Eur. Phys. J. E 45, 22
(2022); https://github.com/FSmallenburg/EDMD): neighbour lists, one event per
particle, a bucket event calendar. It is not on PyPI or in Debian and is not
vendored here: pass a checkout of that repository with ``--source``. The
script copies ``Single/mdSingle.c`` (and ``mdSingle.h``, ``mt19937ar.c``)
into a temporary folder, sets its parameters (FCC start, packing fraction,
N, run length, no thermostat, no snapshots) by rewriting the global
initialisers, and builds it with the flags of the repository's Makefile.

Both codes run one thread from an FCC start at the same state point. The C
code's rate is the difference of two runs (simulated time L and 2 L) in
collisions and in CPU time, which drops its start-up and the melting of the
crystal; collisionkit's is a timed run after 5 collisions per particle of
warm-up (as in bench_edmd.py). The two alternate in pairs, and the table
reports the median ratio of the rates (CPU time), since this machine is
shared and noisy.

Usage: python benchmarks/bench_edmd_reference.py --source PATH/TO/EDMD [--pairs 3]
Writes benchmarks/results/edmd_reference.md and .json.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from collisionkit._io import atomic_write_text

sys.path.insert(0, str(Path(__file__).parent))
import bench_edmd  # noqa: E402  (the collisionkit side of the comparison)

RESULTS = Path(__file__).parent / "results"
FLAGS = ["-Wall", "-Ofast", "-funroll-loops", "-march=native"]  # Single/Makefile
# (particles, packing fraction, simulated time L of the shorter C run): about 2e6 collisions per L
STATE_POINTS = [(864, 0.45, 150.0), (32000, 0.45, 5.0), (4000, 0.2618, 130.0)]


def reference_sources(source: Path) -> dict[str, Path]:
    """The three files of the Single variant (the random-number generator may sit in another variant)."""
    files = {"mdSingle.c": source / "Single" / "mdSingle.c", "mdSingle.h": source / "Single" / "mdSingle.h"}
    for folder in ("Single", "Grow", "Multi", "Cell"):
        if (source / folder / "mt19937ar.c").exists():
            files["mt19937ar.c"] = source / folder / "mt19937ar.c"
            break
    missing = [name for name, path in files.items() if not path.exists()] + (
        [] if "mt19937ar.c" in files else ["mt19937ar.c"])
    if missing:
        raise SystemExit(f"--source {source}: not a checkout of FSmallenburg/EDMD (missing {', '.join(missing)})")
    return files


def set_global(code: str, declaration: str, value: str) -> str:
    """Rewrite the initialiser of a global such as ``double maxtime = 10;``."""
    pattern = re.compile(rf"^({re.escape(declaration)}\s*=\s*)[^;]*;", re.MULTILINE)
    code, count = pattern.subn(rf"\g<1>{value};", code)
    if count != 1:
        raise SystemExit(f"could not set '{declaration}' in mdSingle.c (found {count} times)")
    return code


def build(files: dict[str, Path], folder: Path, particles: int, eta: float, duration: float) -> Path:
    code = files["mdSingle.c"].read_text()
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
    (folder / "mdSingle.c").write_text(code)
    shutil.copy(files["mdSingle.h"], folder)
    shutil.copy(files["mt19937ar.c"], folder)
    program = folder / "md"
    subprocess.run(["gcc", *FLAGS, "mdSingle.c", "-o", "md", "-lm"], cwd=folder, check=True, capture_output=True)
    return program


def run_reference(program: Path) -> tuple[int, float]:
    """(pair collisions, CPU seconds) of one run of the C code."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    output = subprocess.run([str(program)], cwd=program.parent, check=True, capture_output=True, text=True).stdout
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    counts = re.findall(r"Collisions: (\d+)", output)
    if not counts:
        raise SystemExit(f"no 'Collisions:' line in the output of {program}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return int(counts[-1]), cpu


def reference_rate(short: Path, long: Path) -> float:
    collisions_short, cpu_short = run_reference(short)
    collisions_long, cpu_long = run_reference(long)
    return (collisions_long - collisions_short) / (cpu_long - cpu_short)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", type=Path, required=True, help="a checkout of github.com/FSmallenburg/EDMD")
    parser.add_argument("--pairs", type=int, default=3, help="alternating runs of the two codes per state point")
    args = parser.parse_args()
    if args.pairs < 1:
        raise SystemExit(f"--pairs must be >= 1; got {args.pairs}")
    files = reference_sources(args.source)
    load_before = os.getloadavg()
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        for particles, eta, duration in STATE_POINTS:
            short = build(files, Path(scratch) / f"{particles}_{eta}_short", particles, eta, duration)
            long = build(files, Path(scratch) / f"{particles}_{eta}_long", particles, eta, 2 * duration)
            reference, ours = [], []
            for _ in range(args.pairs):
                reference.append(reference_rate(short, long))
                row = bench_edmd.in_subprocess(particles, eta)
                ours.append(row["collisions"] / row["cpu_seconds"])
            ratios = [a / b for a, b in zip(ours, reference)]
            rows.append({"particles": particles, "packing_fraction": eta, "reference": reference,
                         "collisionkit": ours, "ratios": ratios})
            print(rows[-1], flush=True)
    lines = [
        "# EDMD speed against Smallenburg's C code (one core, CPU time)",
        "",
        f"Machine: {bench_edmd.machine()}; load average {load_before[0]:.2f} before, {os.getloadavg()[0]:.2f} "
        f"after. Reference built with gcc {' '.join(FLAGS)}; {args.pairs} alternating pairs per state point.",
        "",
        "| N | eta | reference collisions/s (median) | collisionkit collisions/s (median) | ratio (median of pairs) |",
        "|---|---|---|---|---|",
    ]
    for row in rows:
        lines.append(
            f"| {row['particles']:,} | {row['packing_fraction']:.4f} | {statistics.median(row['reference']):.3g} | "
            f"{statistics.median(row['collisionkit']):.3g} | {statistics.median(row['ratios']):.2f} |"
        )
    table = "\n".join(lines) + "\n"
    print(table)
    RESULTS.mkdir(exist_ok=True)
    atomic_write_text(RESULTS / "edmd_reference.md", table)
    atomic_write_text(RESULTS / "edmd_reference.json",
                      json.dumps({"machine": bench_edmd.machine(), "flags": FLAGS, "rows": rows}, indent=2) + "\n")


if __name__ == "__main__":
    main()
