"""Where the EDMD engine's pair tests come from: counts per collision by source (issue 21).

A pair test is one partner of a neighbour list tried by a prediction
(``prediction.predict_pairs``). After a collision of i and j both are
re-predicted against their lists; a third particle k whose event was a
collision with i or j is not touched then: its event turns out stale when it
comes up (j's ``CHANGED_AT`` is later than k's ``PREDICTED_AT``) and k is
re-predicted then. A list event re-anchors the particle, rebuilds its list
(a scan of the anchors in the 27 cells around it, its removal from its old
partners' lists) and re-predicts it. Every ``SORT_INTERVAL`` N collisions
the particles are renumbered in cell order: every list rebuilt and every
event re-predicted, twice (``HardSphereSystem._sort_by_cell``).

This script runs a counting copy of the engine's event loop
(:func:`counting_run_events`: ``loop.run_events`` with tallies, calling the
engine's own prediction, rebuild and collision kernels, so the events are
the engine's own, one for one) in place of ``run_events`` in this process
only, and counts the whole-system rebuilds and predictions at the Python
level. Its timing means nothing; the engine is unchanged. The state points
and windows are those of ``bench_edmd_reference.py``: FCC start, run to
time L, then the window [L, 2 L] counted.

With ``--source`` (a checkout of FSmallenburg/EDMD, as for
``bench_edmd_reference.py``) the same counts are taken from its Single
variant, built with counters added to a temporary copy (the list lengths at
its ``findcollisions`` calls after a collision, a stale event and a rebuild;
the anchors and list entries its rebuilds scan), at the same state points
and windows (the difference of a run to L and one to 2 L). Its scheme is the
engine's: after a collision both particles are re-predicted against their
lists, third parties only when their stale event comes up (its
``counter2``), a rebuild scans the 27 cells and removes the particle from
every old partner's list; its lists reach 1.5 diameters (shell 0.5).

Usage: python benchmarks/bench_edmd_event_counts.py [--sizes 864 32000] [--eta 0.45] [--shell S] [--source EDMD]
Writes benchmarks/results/edmd_event_counts.md and .json.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import numpy as np
from _bench_common import json_in_fresh_process, write_results

from collisionkit._jit import borrowing_kernel as kernel
from collisionkit._kernels import edmd as engine
from collisionkit._kernels.edmd.contacts import bounce_off_wall, collide_pair
from collisionkit._kernels.edmd.layout import (
    ACC_CELL_OVERFLOW, ACC_EVENTS, ACC_LIST_REBUILDS, ACC_STALE_EVENTS, CHANGED_AT, LIST_TARGET, P_GROWTH, P_SCALE0,
    P_SHEAR_RATE, P_SHEAR_SWEEP, PREDICTED_AT, SHEAR_SWEEP_STRAIN, STOP_COLLISIONS, STOP_EVENTS, STOP_NO_EVENT,
    STOP_OVERFLOW, STOP_STALLED, STOP_TIME, TARGET, wall_target,
)
from collisionkit._kernels.edmd.motion import advance
from collisionkit._kernels.edmd.neighbour_lists import rebuild_list, sweep_frame
from collisionkit._kernels.edmd.prediction import predict
from collisionkit._kernels.edmd.queue import queue_update


# tallies of the counting loop
EVENTS = 0
COLLISIONS = 1
COLLISION_TESTS = 2  # re-predicting i and j after their collision
STALE = 3
STALE_TESTS = 4  # re-predicting a particle whose partner changed since its prediction (third-party invalidation)
MISSES = 5  # pair events whose pair does not approach after all (no collision)
MISS_TESTS = 6
LIST_EVENTS = 7
LIST_TESTS = 8  # re-predicting a particle after its list rebuild
GATHER_CANDIDATES = 9  # anchors scanned in the 27 cells by a rebuild
DROP_SCANNED = 10  # entries of the old partners' lists a removal from every old partner would scan
LIST_LENGTH_AFTER = 11  # the rebuilt list's length (= appends to the partners' lists)
WALL_EVENTS = 12
WALL_TESTS = 13
PARTNER_SAME = 14  # j's own queued event was this very collision (its target was i)
PARTNER_OTHER = 15  # j's queued event was something else, dropped unprocessed by j's re-prediction
COLLIDER_LIST = 16  # sum of the colliding pair's list lengths (their mean, against the system's mean list)
SWEEPS = 17
DROPPED = 18  # old partners out of reach after a rebuild (their lists lose the particle)
ADDED = 19  # new partners after a rebuild (their lists gain it)
TALLIES = 20


@kernel
def _old_list_scan(i, neighbours, neighbour_count):
    """Entries scanned by a rebuild of i removing i from its partners' lists (``_drop_from_list``)."""
    scanned = 0
    for m in range(neighbour_count[i]):
        j = neighbours[i, m]
        for k in range(neighbour_count[j]):
            scanned += 1
            if neighbours[j, k] == i:
                break
    return scanned


@kernel
def _list_changes(i, old, old_count, neighbours, neighbour_count):
    """(dropped, added): i's old partners (``old[:old_count]``) not in its list now, and its partners not in ``old``."""
    kept = 0
    for m in range(old_count):
        for k in range(neighbour_count[i]):
            if neighbours[i, k] == old[m]:
                kept += 1
                break
    return old_count - kept, neighbour_count[i] - kept


@kernel
def _cell_candidates(i, cell_of, cell_count, ncell):
    """Anchors in the 27 cells around i's (periodic box, >= 3 cells a side: the gather's scan)."""
    cell = cell_of[i]
    cx = cell % ncell[0]
    rest = cell // ncell[0]
    cy, cz = rest % ncell[1], rest // ncell[1]
    total = 0
    for oz in range(-1, 2):
        for oy in range(-1, 2):
            for ox in range(-1, 2):
                nx = (cx + ox) % ncell[0]
                ny = (cy + oy) % ncell[1]
                nz = (cz + oz) % ncell[2]
                total += cell_count[nx + ncell[0] * (ny + ncell[1] * nz)]
    return total


@kernel
def counting_run_events(t, still, max_pair_collisions, max_events, t_stop, stall_limit, p, b, anchor_time, image,
                        cell_of, neighbours, neighbour_count, cell_members, cell_count, cell_points, ncell, geom, dim,
                        restitution, params, queue, tree, leaves, acc, spin, tally, old):
    """``loop.run_events`` without its prefetches, adding its counts to ``tally`` (same events, same results)."""
    done = 0
    events = 0
    longest = still
    stop = STOP_COLLISIONS
    target = LIST_TARGET
    scale0 = params[P_SCALE0]
    growth = params[P_GROWTH]
    event = int(acc[ACC_EVENTS])
    while done < max_pair_collisions:
        if events >= max_events:
            stop = STOP_EVENTS
            break
        event_time = tree[1, 0]
        i = int(tree[1, 1])
        if params[P_SHEAR_RATE] != 0.0 and event_time < np.inf and min(event_time, t_stop) >= params[P_SHEAR_SWEEP]:
            sweep = params[P_SHEAR_SWEEP]
            still = still + 1 if sweep == t else 0
            t = sweep
            events += 1
            tally[SWEEPS] += 1
            fullest = sweep_frame(p, b, cell_of, cell_members, cell_count, cell_points, ncell, geom, dim, params, t)
            params[P_SHEAR_SWEEP] = sweep + SHEAR_SWEEP_STRAIN / abs(params[P_SHEAR_RATE])
            if fullest > cell_members.shape[1]:
                acc[ACC_CELL_OVERFLOW] = fullest
                stop = STOP_OVERFLOW
                break
            continue
        if event_time > t_stop:
            if t_stop > t:
                still = 0
            t = t_stop
            stop = STOP_TIME
            break
        if event_time == np.inf:
            stop = STOP_NO_EVENT
            break
        still = still + 1 if event_time == t else 0
        longest = max(longest, still)
        if still >= stall_limit:
            stop = STOP_STALLED
            break
        t = event_time
        event += 1
        events += 1
        tally[EVENTS] += 1
        target = int(b[i, TARGET])
        advance(p, i, t, geom, dim)
        partner = -1
        kind = 0  # 0 stale, 1 collision, 2 miss, 3 list, 4 wall
        if target >= 0:
            j = target
            if b[j, CHANGED_AT] > b[i, PREDICTED_AT]:
                acc[ACC_STALE_EVENTS] += 1.0
                tally[STALE] += 1
            else:
                advance(p, j, t, geom, dim)
                kind = 2
                if collide_pair(p, i, j, b, geom, scale0 + growth * t, growth, restitution, params, acc, spin):
                    b[i, CHANGED_AT] = event
                    b[j, CHANGED_AT] = event
                    done += 1
                    kind = 1
                    tally[COLLISIONS] += 1
                    tally[COLLIDER_LIST] += neighbour_count[i] + neighbour_count[j]
                    if int(b[j, TARGET]) == i:
                        tally[PARTNER_SAME] += 1
                    else:
                        tally[PARTNER_OTHER] += 1
                else:
                    tally[MISSES] += 1
                partner = j
        elif target == LIST_TARGET:
            kind = 3
            acc[ACC_LIST_REBUILDS] += 1.0
            tally[LIST_EVENTS] += 1
            tally[DROP_SCANNED] += _old_list_scan(i, neighbours, neighbour_count)
            old_count = neighbour_count[i]
            for m in range(old_count):
                old[m] = neighbours[i, m]
            if not rebuild_list(p, i, b, anchor_time, cell_of, neighbours, neighbour_count, cell_members, cell_count,
                                cell_points, ncell, geom, dim, params, image, acc):
                stop = STOP_OVERFLOW
                break
            tally[GATHER_CANDIDATES] += _cell_candidates(i, cell_of, cell_count, ncell)
            tally[LIST_LENGTH_AFTER] += neighbour_count[i]
            dropped, added = _list_changes(i, old, old_count, neighbours, neighbour_count)
            tally[DROPPED] += dropped
            tally[ADDED] += added
        else:
            kind = 4
            tally[WALL_EVENTS] += 1
            bounce_off_wall(p, i, wall_target(target), b, params, acc)
            b[i, CHANGED_AT] = event
        for q in range(1 if partner < 0 else 2):
            k = i if q == 0 else partner
            tests = neighbour_count[k]
            if kind == 0:
                tally[STALE_TESTS] += tests
            elif kind == 1:
                tally[COLLISION_TESTS] += tests
            elif kind == 2:
                tally[MISS_TESTS] += tests
            elif kind == 3:
                tally[LIST_TESTS] += tests
            else:
                tally[WALL_TESTS] += tests
            queue_update(k, predict(p, k, b, anchor_time, neighbours, neighbour_count, geom, dim, params, event), queue,
                         tree, leaves)
    acc[ACC_EVENTS] = event
    return t, still, longest, stop, target


class Counter:
    """The counting loop put in place of the engine's, with the whole-system rebuilds counted beside it."""

    def __init__(self):
        self.tally = np.zeros(TALLIES)
        self.full_rebuilds = 0  # build_all_lists calls that completed (every particle's list)
        self.full_candidates = 0.0
        self.full_predictions = 0  # predict_all calls
        self.full_tests = 0.0
        self.sorts = 0

    def install(self):
        engine_run_events = engine.run_events
        engine_predict_all = engine.predict_all
        engine_build_all_lists = engine.build_all_lists
        counter = self

        def run_events(*args):
            neighbours = args[11]
            args = args[:-2]  # the square wells' record (bonds, bond_count): the counting loop runs hard spheres only
            return counting_run_events(*args, counter.tally, np.zeros(neighbours.shape[1], dtype=neighbours.dtype))

        def predict_all(p, b, anchor_time, neighbours, neighbour_count, *rest):  # the wells' record last in rest
            counter.full_predictions += 1
            counter.full_tests += float(neighbour_count[: p.shape[0]].sum())
            return engine_predict_all(p, b, anchor_time, neighbours, neighbour_count, *rest)

        def build_all_lists(p, b, anchor_time, cell_of, neighbours, neighbour_count, cell_members, cell_count,
                            cell_points, ncell, *rest):
            result = engine_build_all_lists(p, b, anchor_time, cell_of, neighbours, neighbour_count, cell_members,
                                            cell_count, cell_points, ncell, *rest)
            counter.full_rebuilds += 1
            grid = cell_count.reshape(ncell[2], ncell[1], ncell[0]).astype(float)
            around = sum(np.roll(grid, (dz, dy, dx), axis=(0, 1, 2))
                         for dz in (-1, 0, 1) for dy in (-1, 0, 1) for dx in (-1, 0, 1))
            counter.full_candidates += float((grid * around).sum())
            return result

        engine.run_events, engine.predict_all, engine.build_all_lists = run_events, predict_all, build_all_lists

    def reset(self):
        self.__init__()


def count_point(particles: int, eta: float, duration: float, shell: float | None) -> dict:
    from collisionkit import edmd
    from collisionkit.edmd import system as system_module

    counter = Counter()
    counter.install()
    sort = system_module.HardSphereSystem._sort_by_cell

    def counted_sort(self):
        counter.sorts += 1
        return sort(self)

    system_module.HardSphereSystem._sort_by_cell = counted_sort
    cells = round((particles / 4) ** (1 / 3))
    positions, box = edmd.lattice("fcc", cells, eta)
    options = {} if shell is None else {"neighbour_shell": shell}
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(len(positions)), 3, seed=1), 0.5, box,
                                   **options)
    system.run(time=duration)
    counter.reset()
    before = system.acc.copy()
    collisions = system.run(time=duration)
    system.check()
    t = counter.tally
    assert t[COLLISIONS] == collisions == system.acc[engine.ACC_PAIR_COLLISIONS] - before[engine.ACC_PAIR_COLLISIONS]
    per = 1.0 / collisions
    loop_tests = t[COLLISION_TESTS] + t[STALE_TESTS] + t[MISS_TESTS] + t[LIST_TESTS] + t[WALL_TESTS]
    return {
        "particles": len(positions), "packing_fraction": eta, "window": duration,
        "shell": float(system.params[engine.P_SHELL]), "collisions": collisions,
        "mean_list": float(system.neighbour_count.mean()),
        "collider_mean_list": t[COLLIDER_LIST] / (2 * collisions),
        "events_per_collision": t[EVENTS] * per,
        "tests_collision": t[COLLISION_TESTS] * per,
        "tests_stale": t[STALE_TESTS] * per,
        "tests_list": t[LIST_TESTS] * per,
        "tests_miss": t[MISS_TESTS] * per,
        "tests_wall": t[WALL_TESTS] * per,
        "tests_full": counter.full_tests * per,
        "tests_total": (loop_tests + counter.full_tests) * per,
        "stale_per_collision": t[STALE] * per,
        "stale_share_of_events": t[STALE] / t[EVENTS],
        "misses_per_collision": t[MISSES] * per,
        "rebuilds_per_collision": t[LIST_EVENTS] * per,
        "gather_candidates_per_rebuild": t[GATHER_CANDIDATES] / max(t[LIST_EVENTS], 1),
        "gather_candidates_per_collision": (t[GATHER_CANDIDATES] + counter.full_candidates) * per,
        "drop_scanned_per_rebuild": t[DROP_SCANNED] / max(t[LIST_EVENTS], 1),
        "list_after_rebuild": t[LIST_LENGTH_AFTER] / max(t[LIST_EVENTS], 1),
        "dropped_per_rebuild": t[DROPPED] / max(t[LIST_EVENTS], 1),
        "added_per_rebuild": t[ADDED] / max(t[LIST_EVENTS], 1),
        "partner_event_same_collision": t[PARTNER_SAME] / collisions,
        "partner_event_dropped": t[PARTNER_OTHER] / collisions,
        "full_rebuilds": counter.full_rebuilds, "full_predictions": counter.full_predictions, "sorts": counter.sorts,
    }


C_COUNTERS = ("tests_collision", "tests_stale", "tests_list", "stale", "rebuilds", "candidates", "scanned", "events")


def count_reference(source: Path, particles: int, eta: float, duration: float, scratch: Path) -> dict:
    """The counts of Smallenburg's Single variant over the window [L, 2 L] (see the module docstring)."""
    import re
    import subprocess

    from bench_edmd_reference import FLAGS, build

    patches = [
        ("int main()\n{", "long long COUNTS[8];\nint main()\n{"),
        ("    printstuff();\n", '    printstuff();\n    printf("COUNTS");\n    for (int k = 0; k < 8; k++) printf(" %lld", COUNTS[k]);\n'
                                 '    printf("\\n");\n'),
        ("    if (p1->counter2 != p2->counter)\n    {\n        findcollisions(p1);",
         "    if (p1->counter2 != p2->counter)\n    {\n        COUNTS[1] += p1->nneigh; COUNTS[3]++;\n        findcollisions(p1);"),
        ("    findcollisions(p1);\n    findcollisions(p2);\n}",
         "    COUNTS[0] += p1->nneigh + p2->nneigh;\n    findcollisions(p1);\n    findcollisions(p2);\n}"),
        ("            if (p2->neighbors[j] == p1)\n", "            COUNTS[6]++;\n            if (p2->neighbors[j] == p1)\n"),
        ("                    if (p2 != p1)\n", "                    COUNTS[5]++;\n                    if (p2 != p1)\n"),
        ("    findcollisions(p1);\n\n\n}", "    COUNTS[2] += p1->nneigh; COUNTS[4]++;\n    findcollisions(p1);\n\n\n}"),
        ("    simtime = ev->eventtime;\n", "    simtime = ev->eventtime;\n    COUNTS[7]++;\n"),
    ]
    totals = []
    for length in (duration, 2 * duration):
        folder = scratch / f"single_{particles}_{length}"
        program = build(source, "Single", folder, particles, eta, length)
        code = (folder / "mdSingle.c").read_text()
        for old, new in patches:
            if code.count(old) != 1:
                raise SystemExit(f"--source {source}: Single/mdSingle.c is not the version these counters fit")
            code = code.replace(old, new)
        (folder / "mdSingle.c").write_text(code)
        subprocess.run(["gcc", *FLAGS, "mdSingle.c", "-o", program.name, "-lm"], cwd=folder, check=True,
                       capture_output=True)
        output = subprocess.run([str(program)], cwd=folder, check=True, capture_output=True, text=True).stdout
        collisions = int(re.findall(r"Collisions: (\d+)", output)[-1])
        totals.append([collisions] + [int(x) for x in re.findall(r"COUNTS (.*)", output)[-1].split()])
    collisions, *counts = [b - a for a, b in zip(*totals)]
    c = dict(zip(C_COUNTERS, counts))
    per = 1.0 / collisions
    return {
        "particles": particles, "packing_fraction": eta, "window": duration, "shell": 0.5, "collisions": collisions,
        "code": "Single (C)",
        "tests_collision": c["tests_collision"] * per, "tests_stale": c["tests_stale"] * per,
        "tests_list": c["tests_list"] * per, "tests_full": 0.0, "tests_miss": 0.0,
        "tests_total": (c["tests_collision"] + c["tests_stale"] + c["tests_list"]) * per,
        "collider_mean_list": c["tests_collision"] / (2 * collisions),
        "events_per_collision": c["events"] * per, "stale_per_collision": c["stale"] * per,
        "stale_share_of_events": c["stale"] / c["events"], "rebuilds_per_collision": c["rebuilds"] * per,
        "gather_candidates_per_rebuild": c["candidates"] / c["rebuilds"],
        "gather_candidates_per_collision": c["candidates"] * per,
        "drop_scanned_per_rebuild": c["scanned"] / c["rebuilds"],
        "list_after_rebuild": c["tests_list"] / c["rebuilds"],
    }


def in_subprocess(particles: int, eta: float, duration: float, shell: float | None) -> dict:
    return json_in_fresh_process("bench_edmd_event_counts", f"count_point({particles}, {eta}, {duration}, {shell})")


ROWS = [
    ("pair tests per collision, total", "tests_total"),
    ("- re-predicting the colliding pair (i and j)", "tests_collision"),
    ("- re-predicting stale events (third parties whose partner collided)", "tests_stale"),
    ("- re-predicting after a list rebuild", "tests_list"),
    ("- whole-system re-predictions (sorts every 20 N collisions)", "tests_full"),
    ("- pair events that did not collide (not approaching)", "tests_miss"),
    ("mean list length (system) / of the colliding particles", None),
    ("events per collision", "events_per_collision"),
    ("stale events per collision", "stale_per_collision"),
    ("stale share of the events that came up", "stale_share_of_events"),
    ("list rebuilds per collision", "rebuilds_per_collision"),
    ("anchors scanned per rebuild (27 cells)", "gather_candidates_per_rebuild"),
    ("anchors scanned per collision (rebuilds + whole-system builds)", "gather_candidates_per_collision"),
    ("list entries scanned per rebuild to drop it from every old partner", "drop_scanned_per_rebuild"),
    ("list length after a rebuild", "list_after_rebuild"),
    ("old partners out of reach after a rebuild (dropped)", "dropped_per_rebuild"),
    ("new partners after a rebuild (added)", "added_per_rebuild"),
    ("the partner's queued event was this collision (share)", "partner_event_same_collision"),
    ("the partner's queued event was another, dropped (share)", "partner_event_dropped"),
    ("whole-system list builds / predictions / sorts in the window", None),
]


def table(rows: list[dict], command: str, loads: tuple, eta: float) -> str:
    head = " | ".join(f"{row.get('code', 'collisionkit')} N {row['particles']:,}, shell {row['shell']:.2f}"
                      for row in rows)
    lines = [
        "# EDMD: where the pair tests come from (counts per pair collision)",
        "",
        f"Command: `{command}`; load average {loads[0]:.2f} {loads[1]:.2f} {loads[2]:.2f} (counts do not depend on it).",
        f"FCC start at eta {eta}, run to time L, then the window [L, 2 L] counted (bench_edmd_reference.py's "
        "windows), with a counting copy of the event loop calling the engine's own kernels.",
        "",
        f"| per collision | {head} |",
        "|---|" + "---|" * len(rows),
    ]
    for label, key in ROWS:
        if key is None and label.startswith("mean list"):
            cells = [f"{row['mean_list']:.2f} / {row['collider_mean_list']:.2f}" if "mean_list" in row
                     else f"- / {row['collider_mean_list']:.2f}" for row in rows]
        elif key is None:
            cells = [f"{row['full_rebuilds']} / {row['full_predictions']} / {row['sorts']}" if "sorts" in row else "-"
                     for row in rows]
        else:
            cells = [f"{row[key]:.3f}" if key in row else "-" for row in rows]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[864, 32000])
    parser.add_argument("--eta", type=float, default=0.45)
    parser.add_argument("--shell", type=float, default=None, help="neighbour shell in diameters (default: the engine's)")
    parser.add_argument("--source", type=Path, help="a checkout of github.com/FSmallenburg/EDMD: count its Single too")
    parser.add_argument("--output", default="edmd_event_counts")
    args = parser.parse_args()
    from bench_edmd_reference import STATE_POINTS

    loads = os.getloadavg()
    rows = [in_subprocess(n, args.eta, STATE_POINTS[n][2], args.shell) for n in args.sizes]
    if args.source is not None:
        import tempfile

        with tempfile.TemporaryDirectory() as scratch:
            rows += [count_reference(args.source, n, args.eta, STATE_POINTS[n][2], Path(scratch)) for n in args.sizes]
    command = "python benchmarks/bench_edmd_event_counts.py " + " ".join(sys.argv[1:])
    write_results(args.output, table(rows, command.strip(), loads, args.eta), {"rows": rows})


if __name__ == "__main__":
    main()
