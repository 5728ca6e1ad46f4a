"""Throughput of ck.resolve_contact on 10^7 3D pairs against a plain memory copy.

The collision rule does a handful of flops per byte, so its floor is memory
bandwidth. The baseline, timed in the same run, copies the same input bytes
(v1, v2, normal, m1, m2) with numpy; the ratio (resolve_contact time / copy
time) is what the README quotes, since absolute times on shared machines are
noisy. Timing: best of several repeats with ``timeit``.

Usage: python benchmarks/bench_resolve_contact.py [--pairs N] [--repeat R]
Writes benchmarks/results/resolve_contact.md and .json.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import timeit
from pathlib import Path

import numpy as np

import collisionkit as ck

RESULTS = Path(__file__).parent / "results"


def make_pairs(count: int, seed: int = 1):
    rng = np.random.default_rng(seed)
    return (
        rng.uniform(0.5, 2.0, count),
        rng.normal(size=(count, 3)),
        rng.uniform(0.5, 2.0, count),
        rng.normal(size=(count, 3)),
        rng.normal(size=(count, 3)),
    )


def best_time(function, repeat: int) -> float:
    return min(timeit.repeat(function, number=1, repeat=repeat))


def machine() -> str:
    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}, numpy {np.__version__}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=10_000_000)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()

    m1, v1, m2, v2, normal = make_pairs(args.pairs)
    inputs = (m1, v1, m2, v2, normal)
    ck.resolve_contact(m1[:8], v1[:8], m2[:8], v2[:8], normal[:8])  # compile or load the cache

    copy_time = best_time(lambda: [array.copy() for array in inputs], args.repeat)
    elastic_time = best_time(lambda: ck.resolve_contact(m1, v1, m2, v2, normal), args.repeat)
    inelastic_time = best_time(lambda: ck.resolve_contact(m1, v1, m2, v2, normal, 0.8, "cm"), args.repeat)
    megabytes = sum(array.nbytes for array in inputs) / 1e6

    rows = [
        ("plain copy of the input bytes (numpy)", copy_time, 1.0),
        ("resolve_contact, elastic, normal model", elastic_time, elastic_time / copy_time),
        ("resolve_contact, e = 0.8, cm model", inelastic_time, inelastic_time / copy_time),
    ]
    lines = [
        f"# resolve_contact on {args.pairs:,} 3D pairs ({megabytes:.0f} MB of input)",
        "",
        f"Machine: {machine()}. Best of {args.repeat}.",
        "",
        "| operation | time (s) | pairs/s | ratio to copy |",
        "|---|---|---|---|",
    ]
    lines += [f"| {name} | {t:.3f} | {args.pairs / t:.3g} | {ratio:.2f} |" for name, t, ratio in rows]
    table = "\n".join(lines) + "\n"
    print(table)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "resolve_contact.md").write_text(table)
    summary = {"pairs": args.pairs, "machine": machine(), "rows": [dict(zip(("name", "seconds", "ratio"), r)) for r in rows]}
    (RESULTS / "resolve_contact.json").write_text(json.dumps(summary, indent=2) + "\n")


if __name__ == "__main__":
    main()
