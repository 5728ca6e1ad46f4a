"""Micro-benchmark of the EDMD pair test: gathering partners by index against contiguous per-list copies (issue 21).

The engine predicts a particle's next collision by testing every partner in
its neighbour list (``prediction._first_contact_ballistic``): it gathers
each partner's position, velocity and own time by index from the particle
records. This script takes a real state of the engine (FCC start at packing
fraction ``--eta``, melted by 5 N collisions), then times, for every
particle in a shuffled order, the search for its first contact before its
list expires (its boundary event, as in the engine), with these layouts:

``gather``
    the engine's own kernel (partners gathered by index from ``p``).
``gather-2pass``
    a branch-free pass over the gathered partners that only marks those
    passing the cheap filter (approaching and able to touch before the
    horizon), then the exact root for the marked ones.
``gather-select``
    the engine's loop with the minimum image as selects instead of
    branches (the same results).
``buffer-tau``
    no copies kept: each prediction gathers its partners' records into a
    contiguous scratch buffer (lists padded with NaN to whole vectors of
    8 doubles), a branch-free vectorised pass computes every partner's
    contact time from the plain sums, and the engine's exact test (its
    sure sign of ``r . u``) runs for each time that beats the best so far.
``buffer-compact``
    the same buffer, a branch-free marking pass (approaching and able to
    touch before the horizon), the marked slots compacted without a
    branch, the exact test for those.
``copies``
    each list also keeps contiguous copies of its partners' x, v, t and
    radius (structure of arrays, one row of 8 components per list): the
    engine's loop, unchanged arithmetic, read from the copies.
``copies-2pass``
    the same copies, the branch-free marking pass (vectorisable: no
    gather) then the exact root for the marked ones. Bit-identical to
    ``gather`` (same arithmetic, the running-best filter re-applied).
``copies-tau``
    the same copies, ``buffer-tau``'s vectorised pass run on them
    directly (``tau-pass-only``: that pass alone).
``x0-2pass``
    copies of the partners' positions extrapolated to time 0
    (``x - v t``) and velocities: no per-pair time, the marking pass has
    fewer operations; the exact root recomputed from ``p`` for the marked
    ones (its separation at round-off of ``|v| t`` would differ otherwise).
``x0-f32``
    the ``x0`` copies in float32, the filter widened by a margin, the exact
    root from ``p``.

It also times the cost of keeping the copies current: after a collision
the two particles' copies in each of their partners' lists are rewritten
(found through a back index: the slot of i in the list of its m-th
partner), about 2 x 14 scattered writes of 7 doubles (``refresh``; and
``refresh-records`` with each copy one 64-byte record, the floor of any
layout). The per-collision table adds it to 38.7 pair tests (issue 21's
profile); rebuilds, which would also write copies, are not counted.

``gather-filter-only`` is the engine's loop with a horizon of 0 (no pair
passes the cheap filter): the cost of gathering and filtering alone.

Every variant must find the same partner and the same time as ``gather``
(checked). CPU time (``time.process_time``), variants alternated in
``--rounds`` rounds, medians with the range.

Measured here (benchmarks/results/edmd_pair_test.md): nothing pays. The
engine's scalar loop costs 7-9 ns a pair under load at N 864, of which
the gather and the cheap filter are ~87 % (``gather-filter-only``) and
the exact root the rest. The vectorised pass over contiguous copies
(``tau-pass-only``, zmm code) is about half of that, but keeping copies
current costs 160-190 ns a collision at N 864 (1.1-1.8 us at N 32000,
where the copies take 24 times the memory of the particle records): more
than the whole pair-test saving (38.7 tests x ~4 ns). Gathering into a
buffer each time (``buffer-tau``) breaks even with the engine's loop; the
marking passes lose to the mispredicted branch or the compaction after
them; time-0 positions (``x0``) have no fewer operations per pair (the
same subtract, multiply and add per axis) and lose the exact separation.

Usage: python benchmarks/bench_edmd_pair_test.py [--sizes 864 32000] [--eta 0.45] [--rounds 7]
Writes benchmarks/results/edmd_pair_test.md and .json.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import statistics
import sys
import time
from pathlib import Path

import numba
import numpy as np

from collisionkit import edmd
from collisionkit._io import atomic_write_text
from collisionkit._jit import BORROWING_OPTIONS
from collisionkit._kernels.edmd.layout import P_SCALE0

sys.path.insert(0, str(Path(__file__).parent))
from _edmd_pair_kernels import (  # noqa: E402  (the kernels, next to this script)
    COPY_WIDTH, PAD, _horizons, _marked, fill_copies, run_buffer_compact,
    run_buffer_tau, run_copies, run_copies_2pass, run_copies_tau, run_gather, run_gather_2pass, run_gather_select,
    run_refresh, run_refresh_records, run_x0, tau_pass_only,
)

RESULTS = Path(__file__).parent / "results"
# pair tests per pair collision in the engine (issue 21's profile at eta 0.45)
PAIR_TESTS_PER_COLLISION = 38.7


def _cpu(function, *args):
    start = time.process_time()
    function(*args)
    return time.process_time() - start


def one_size(particles: int, eta: float, rounds: int, repeats: int) -> dict:
    """Time every variant on a melted state of ``particles`` spheres; ns per pair test, medians and ranges."""
    cells = round((particles / 4) ** (1 / 3))
    positions, box = edmd.lattice("fcc", cells, eta)
    count = len(positions)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(count), 3, seed=1), 0.5, box)
    system.run(collisions=5 * count)
    p, neighbours, lengths, geom = system.p, system.neighbours, system.neighbour_count, system.geom
    scale = float(system.params[P_SCALE0])
    horizon = np.empty(count)
    _horizons(p, system.book, system.anchor_time, geom, system.dim, system.params, horizon)
    rng = np.random.default_rng(2)
    order = np.tile(rng.permutation(count), repeats).astype(np.int64)
    width = neighbours.shape[1]
    padded = (width + PAD - 1) // PAD * PAD
    exact_copies = np.full((count, COPY_WIDTH, padded), np.nan)
    zero_copies = np.zeros((count, COPY_WIDTH, width))
    back = np.zeros((count, width), dtype=np.int64)
    fill_copies(p, neighbours, lengths, exact_copies, False, back)
    fill_copies(p, neighbours, lengths, zero_copies, True, back)
    single_copies = zero_copies.astype(np.float32)
    mark = np.zeros(padded, dtype=np.bool_)
    picked = np.zeros(padded, dtype=np.int64)
    buffer = np.zeros((COPY_WIDTH, padded))
    tau = np.zeros(padded)
    # collisions: random listed pairs (each collision rewrites both particles' copies)
    owners = rng.integers(0, count, size=len(order) // 2)
    partners = neighbours[owners, (rng.random(len(owners)) * lengths[owners]).astype(np.int64)]
    pairs = np.stack([owners, partners.astype(np.int64)], axis=1)
    found = {name: np.zeros(count, dtype=np.int64) for name in ("reference", "probe")}
    taus = {name: np.zeros(count) for name in ("reference", "probe")}
    variants = {
        "gather": lambda f, t: run_gather(p, order, neighbours, lengths, geom, scale, horizon, f, t),
        "gather-2pass": lambda f, t: run_gather_2pass(p, order, neighbours, lengths, geom, scale, horizon, f, t, mark),
        "gather-select": lambda f, t: run_gather_select(p, order, neighbours, lengths, geom, scale, horizon, f, t),
        "buffer-tau": lambda f, t: run_buffer_tau(p, order, neighbours, lengths, geom, scale, horizon, f, t, buffer,
                                                  tau),
        "buffer-compact": lambda f, t: run_buffer_compact(p, order, neighbours, lengths, geom, scale, horizon, f, t,
                                                          buffer, mark, picked),
        "copies": lambda f, t: run_copies(p, order, neighbours, lengths, exact_copies, geom, scale, horizon, f, t),
        "copies-2pass": lambda f, t: run_copies_2pass(p, order, neighbours, lengths, exact_copies, geom, scale, horizon,
                                                      f, t, mark),
        "copies-tau": lambda f, t: run_copies_tau(p, order, neighbours, lengths, exact_copies, geom, scale, horizon,
                                                  f, t, tau),
        "x0-2pass": lambda f, t: run_x0(p, order, neighbours, lengths, zero_copies, geom, scale, horizon, f, t, mark,
                                        False),
        "x0-f32": lambda f, t: run_x0(p, order, neighbours, lengths, single_copies, geom, scale, horizon, f, t, mark,
                                      True),
    }
    variants["gather"](found["reference"], taus["reference"])
    for name, variant in variants.items():
        variant(found["probe"], taus["probe"])
        same = np.array_equal(found["probe"], found["reference"]) and np.array_equal(taus["probe"], taus["reference"])
        if not same:
            raise SystemExit(f"{name}: not the engine's partners and times")
    refresh_copies = exact_copies.copy()  # rewritten in place: keep the checked copies intact
    run_refresh(p, pairs[:2], neighbours, lengths, refresh_copies, back)
    records = np.zeros((count, width, COPY_WIDTH))
    run_refresh_records(p, pairs[:2], neighbours, lengths, records, back)
    tau_pass_only(p, order[:2], lengths, exact_copies, geom, scale, tau)
    tests = int(lengths[order].sum())
    times: dict[str, list[float]] = {name: [] for name in [*variants, "gather-filter-only", "tau-pass-only", "refresh",
                                                    "refresh-records"]}
    for _ in range(rounds):
        for name, variant in variants.items():
            times[name].append(_cpu(variant, found["probe"], taus["probe"]) / tests * 1e9)
        seconds = _cpu(run_gather, p, order, neighbours, lengths, geom, scale, np.zeros(count), found["probe"],
                       taus["probe"])
        times["gather-filter-only"].append(seconds / tests * 1e9)
        seconds = _cpu(tau_pass_only, p, order, lengths, exact_copies, geom, scale, tau)
        times["tau-pass-only"].append(seconds / tests * 1e9)
        seconds = _cpu(run_refresh, p, pairs, neighbours, lengths, refresh_copies, back)
        times["refresh"].append(seconds / len(pairs) * 1e9)
        times["refresh-records"].append(_cpu(run_refresh_records, p, pairs, neighbours, lengths, records, back)
                                        / len(pairs) * 1e9)
    marked = _marked(p, order, neighbours, lengths, geom, scale, horizon, mark)
    return {
        "particles": count, "eta": eta, "list_width": width, "mean_list": float(lengths.mean()),
        "marked_fraction": marked / tests, "found_fraction": float((found["reference"] >= 0).mean()),
        "copies_MB": exact_copies.nbytes / 1e6, "p_MB": p.nbytes / 1e6,
        "ns": {name: {"median": statistics.median(v), "min": min(v), "max": max(v)} for name, v in times.items()},
    }


def packed_operations(function) -> int:
    """Arithmetic instructions on 8 doubles or 16 singles (zmm) in a kernel's machine code, compiled afresh.

    Compiled again without the disk cache (numba shows no machine code for
    cached kernels) for the types the benchmark called it with; the code
    includes the kernels it calls.
    """
    fresh = numba.njit(**{**BORROWING_OPTIONS, "cache": False})(function.py_func)
    for signature in function.signatures:
        fresh.compile(signature)
    code = "\n".join(fresh.inspect_asm().values())
    return len(re.findall(r"\tv(?:add|sub|mul|div|sqrt|max|min|cmp)\w*p[sd]\t[^\n]*%zmm", code))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[864, 32000])
    parser.add_argument("--eta", type=float, default=0.45)
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--out", default="edmd_pair_test")
    args = parser.parse_args()
    rows = []
    for size in args.sizes:
        # about 6e6 pair tests a variant and round whatever the size
        rows.append(one_size(size, args.eta, args.rounds, max(1, round(3e5 / size))))
    vectors = {name: packed_operations(f) for name, f in (
        ("gather", run_gather), ("gather-2pass", run_gather_2pass), ("buffer-tau", run_buffer_tau),
        ("copies-2pass", run_copies_2pass), ("copies-tau", run_copies_tau), ("x0-2pass and x0-f32", run_x0))}
    load = os.getloadavg()
    result = {"rows": rows, "vector_registers": vectors, "load": load, "rounds": args.rounds,
              "command": f"python benchmarks/bench_edmd_pair_test.py --sizes {' '.join(map(str, args.sizes))} "
                         f"--eta {args.eta} --rounds {args.rounds}"}
    RESULTS.mkdir(exist_ok=True)
    atomic_write_text(RESULTS / f"{args.out}.json", json.dumps(result, indent=1) + "\n")
    names = list(rows[0]["ns"])
    lines = [f"# EDMD pair test: ns per pair test (median of {args.rounds} rounds, range), eta {args.eta}", "",
             f"Command: `{result['command']}`; load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}. "
             "`refresh` is ns per collision: both particles' copies rewritten in their partners' lists "
             "(`refresh-records`: the same with each copy a whole 64-byte record, the floor of any layout). "
             "`tau-pass-only`: the vectorised pass of `copies-tau` alone; `gather-filter-only`: the engine's "
             "loop with a horizon 0 (no pair passes the filter: the gather and the filter's arithmetic alone). "
             "N 32000 visits particles in random order "
             "(cold caches: an upper bound for the engine, whose events reuse lines).", "",
             "| variant | " + " | ".join(f"N {r['particles']}" for r in rows) + " |",
             "|---|" + "---|" * len(rows)]
    for name in names:
        cells = [f"{r['ns'][name]['median']:.2f} ({r['ns'][name]['min']:.2f}-{r['ns'][name]['max']:.2f})" for r in rows]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    lines += ["", "| | " + " | ".join(f"N {r['particles']}" for r in rows) + " |", "|---|" + "---|" * len(rows)]
    for key in ("list_width", "mean_list", "marked_fraction", "found_fraction", "copies_MB", "p_MB"):
        lines.append(f"| {key} | " + " | ".join(f"{r[key]:.3g}" for r in rows) + " |")
    lines += ["", f"Per collision ({PAIR_TESTS_PER_COLLISION} pair tests, issue 21's profile, plus `refresh` for the "
              "variants with copies; rebuilds writing copies not counted), ns:", "",
              "| variant | " + " | ".join(f"N {r['particles']}" for r in rows) + " |", "|---|" + "---|" * len(rows)]
    for name in names:
        if name in ("refresh", "refresh-records", "tau-pass-only", "gather-filter-only"):
            continue
        upkeep = name.startswith(("copies", "x0"))
        cells = [f"{PAIR_TESTS_PER_COLLISION * r['ns'][name]['median'] + upkeep * r['ns']['refresh']['median']:.0f}"
                 for r in rows]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    lines += ["", "zmm arithmetic instructions in each variant's machine code (vectorised if > 0): "
              + ", ".join(f"{k} {v}" for k, v in vectors.items())]
    atomic_write_text(RESULTS / f"{args.out}.md", "\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
