"""Tests of system checkpoints (collisionkit.edmd._system_state): bit-for-bit resumes, engine formats, crafted files."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from collisionkit import edmd
from collisionkit._io import CheckpointError, read_checkpoint, write_checkpoint
from collisionkit._kernels import edmd as _k
from tests.edmd.systems import fcc_system

ROOT = Path(__file__).resolve().parents[2]


def test_checkpoint_resume_is_bit_for_bit(tmp_path):
    straight = fcc_system(cells=4, eta=0.4)
    straight.run(collisions=10_000)
    straight.run(collisions=10_000)

    interrupted = fcc_system(cells=4, eta=0.4)
    interrupted.run(collisions=10_000)
    interrupted.save(tmp_path / "state.npz")
    resumed = edmd.HardSphereSystem.load(tmp_path / "state.npz")
    resumed.run(collisions=10_000)
    np.testing.assert_array_equal(resumed.positions(), straight.positions())
    np.testing.assert_array_equal(resumed.velocities(), straight.velocities())
    np.testing.assert_array_equal(resumed.acc, straight.acc)
    assert resumed.elapsed == straight.elapsed


def test_a_checkpoint_of_another_engine_format_is_refused():
    state = fcc_system(cells=2, eta=0.3).state_dict()
    edmd.HardSphereSystem.from_state_dict(state)  # its own format: fine
    del state["format"]  # as written before formats were numbered
    with pytest.raises(ValueError, match="engine format 1"):
        edmd.HardSphereSystem.from_state_dict(state)


def test_a_state_saved_as_a_run_stopped_to_grow_its_rows_restores_and_continues_bit_for_bit():
    # a progress callback sees the system between a kernel call that outgrew a list row or a cell and the
    # growth that follows: a state saved there holds a particle out of its cell; the restore grows the rows
    saved = []

    def save_when_outgrown(fraction):
        if system.acc[_k.ACC_LIST_OVERFLOW] or system.acc[_k.ACC_CELL_OVERFLOW]:
            saved.append({name: np.array(value) for name, value in system.state_dict().items()})  # copies: it runs on

    system = fcc_system(cells=3, eta=0.3)
    system.neighbours = system.neighbours[:, :2].copy()  # rows too short: the first rebuilds outgrow them
    system.neighbour_count[:] = np.minimum(system.neighbour_count, 2)
    system.run(collisions=2_000, progress=save_when_outgrown, chunk=100)
    assert saved
    restored = edmd.HardSphereSystem.from_state_dict(saved[0])
    assert restored.acc[_k.ACC_LIST_OVERFLOW] == restored.acc[_k.ACC_CELL_OVERFLOW] == 0
    assert restored.run(collisions=1_000) == 1_000 and restored.check() > -1e-9


def test_a_damaged_system_checkpoint_is_one_line_naming_the_file_and_the_array(tmp_path):
    from tests._io.test_checkpoints import _flip_bytes_inside

    path = tmp_path / "state.npz"
    fcc_system(cells=2, eta=0.3).save(path)
    _flip_bytes_inside(path, "p")
    with pytest.raises(CheckpointError) as caught:
        edmd.HardSphereSystem.load(path)
    assert str(caught.value).startswith(f"{path} is a damaged checkpoint: array 'p' cannot be read (Bad CRC-32")
    path.write_bytes(path.read_bytes()[:-10])
    with pytest.raises(CheckpointError, match="cut short"):
        edmd.HardSphereSystem.load(path)


# ------------------------------------------------------------------ crafted checkpoints: data, never trusted


def _with(array, index, value):
    array = np.array(array)
    array[index] = value
    return array


def _set(name, index, value):
    """A mutation: ``arrays[name][index] = value`` (value may be a function of the array)."""

    def mutate(arrays):
        array = arrays[name]
        arrays[name] = _with(array, index, value(array) if callable(value) else value)

    return mutate


def _replace(name, make):
    def mutate(arrays):
        arrays[name] = make(arrays[name])

    return mutate


def _remove(name):
    return lambda arrays: arrays.pop(name)


def _first_member(arrays):
    """(cell, slot) of the first particle in the cells."""
    cell = int(np.flatnonzero(arrays["cell_count"])[0])
    return cell, 0


def _member_mutation(value):
    def mutate(arrays):
        arrays["cell_members"] = _with(arrays["cell_members"], _first_member(arrays), value(arrays))

    return mutate


N = 108  # the crafted checkpoints' particles: 14 blocks of 8 in the queue, 16 leaves in the event tree

# (case, the array its error must name, the mutation of a real checkpoint's arrays)
CRAFTED = [
    ("leaves = 10**7 (segfaulted)", "leaves", _replace("leaves", lambda _: np.asarray(10**7))),
    ("leaves = 0", "leaves", _replace("leaves", lambda _: np.asarray(0))),
    ("a short tree (out-of-bounds writes)", "tree", _replace("tree", lambda tree: tree[:4].copy())),
    ("a tree winner out of range", "tree", _set("tree", (1, 1), 10.0**6)),
    ("a tree winner beyond the particles", "tree", _set("tree", (16 + 13, 1), float(N + 2))),
    ("a tree that is no tournament", "tree", _set("tree", (1, 0), lambda tree: tree[1, 0] - 1.0)),
    ("a NaN in the tree", "tree", _set("tree", (5, 0), np.nan)),
    ("a short queue", "queue", _replace("queue", lambda queue: queue[:-8].copy())),
    ("a NaN event time", "queue", _set("queue", 3, np.nan)),
    ("queue padding not inf", "queue", _set("queue", N + 1, 1.0)),
    ("one particle record short", "_mass", _replace("p", lambda p: p[:-1].copy())),
    ("records of 7 columns", "p", _replace("p", lambda p: p[:, :7].copy())),
    ("records in float32", "p", _replace("p", lambda p: p.astype(np.float32))),
    ("a NaN position", "p", _set("p", (0, _k.X), np.nan)),
    ("a position far outside the box", "p", _set("p", (0, _k.X), 1e6)),
    ("a position through a wall", "p", _set("p", (0, _k.X + 1), -3.0)),
    ("an infinite velocity", "p", _set("p", (2, _k.V), np.inf)),
    ("a radius of zero", "p", _set("p", (0, _k.R), 0.0)),
    ("a negative radius", "p", _set("p", (5, _k.R), -0.5)),
    ("an own time after the clock", "p", _set("p", (0, _k.T), 1.0)),
    ("a negative mass", "_mass", _replace("_mass", lambda mass: -mass)),
    ("masses unlike the records'", "book", _set("book", (0, _k.MASS), 7.0)),
    ("a species beyond the restitution matrix", "_species", _set("_species", 0, 5)),
    ("a species in the records beyond the matrix", "book", _set("book", (0, _k.SPECIES), 7.0)),
    ("a restitution of 1.5", "restitution", _set("restitution", (0, 0), 1.5)),
    ("an asymmetric restitution matrix", "restitution", _set("restitution", (0, 1), 0.2)),
    ("a restitution matrix that is not square", "restitution", _replace("restitution", lambda e: e[:1].copy())),
    ("an event partner beyond the particles", "book", _set("book", (0, _k.TARGET), float(N + 5))),
    ("an event partner that is the particle itself", "book", _set("book", (3, _k.TARGET), 3.0)),
    ("a fractional event partner", "book", _set("book", (0, _k.TARGET), 1.5)),
    ("a wall on a periodic axis", "book", _set("book", (0, _k.TARGET), -2.0)),
    ("a wall of an axis beyond the box", "book", _set("book", (0, _k.TARGET), -2.0 - 9)),
    ("an event numbered after the last event", "book", _set("book", (0, _k.PREDICTED_AT), 1e18)),
    ("an anchor outside the box", "book", _set("book", (0, _k.ANCHOR), -50.0)),
    ("ids with a repeat", "ids", _set("ids", 0, lambda ids: ids[1])),
    ("an id beyond the particles", "ids", _set("ids", 0, 10**9)),
    ("image counters of 2D", "_image", _replace("_image", lambda image: image[:, :2].copy())),
    ("a neighbour beyond the particles", "neighbours", _set("neighbours", (0, 0), N + 100)),
    ("a particle its own neighbour", "neighbours", _set("neighbours", (0, 0), 0)),
    ("neighbours as int64", "neighbours", _replace("neighbours", lambda lists: lists.astype(np.int64))),
    ("a list longer than its row", "neighbour_count", _set("neighbour_count", 0, lambda c: 10**6)),
    ("a negative list length", "neighbour_count", _set("neighbour_count", 0, -1)),
    ("a cell member beyond the particles", "cell_members", _member_mutation(lambda arrays: 10**6)),
    ("a particle in two cells", "cell_members",
     _member_mutation(lambda arrays: arrays["cell_members"][tuple(np.argwhere(arrays["cell_count"])[-1])[0], 0])),
    ("a cell fuller than its slots", "cell_count", _set("cell_count", 0, 10**6)),
    ("a cell index beyond the grid", "cell_of", _set("cell_of", 0, 10**6)),
    ("a grid unlike the box's", "ncell", _replace("ncell", lambda ncell: ncell * 2)),
    ("cell points unlike the anchors", "cell_points", _replace("cell_points", lambda points: points + 1)),
    ("a negative box length", "geom", _set("geom", (_k.G_BOX, 0), -5.0)),
    ("a periodic flag of 0.5", "geom", _set("geom", (_k.G_PERIODIC, 0), 0.5)),
    ("a shell wider than half the box", "params", _set("params", _k.P_SHELL, 1e6)),
    ("an unknown restitution law", "params", _set("params", _k.P_LAW, 7.0)),
    ("a wall restitution of 2", "params", _set("params", _k.P_WALL_RESTITUTION, 2.0)),
    ("a negative pair count", "acc", _set("acc", _k.ACC_PAIR_COLLISIONS, -1.0)),
    ("a list overflow of 10**12 (an allocation)", "acc", _set("acc", _k.ACC_LIST_OVERFLOW, 1e12)),
    ("dim = 4", "dim", _replace("dim", lambda _: np.asarray(4))),
    ("dim = 2 with the arrays of 3D", "geom", _replace("dim", lambda _: np.asarray(2))),
    ("a NaN clock", "time", _replace("time", lambda _: np.asarray(np.nan))),
    ("a shell request of 0", "_shell_request", _replace("_shell_request", lambda _: np.asarray(0.0))),
    ("last sort after the last collision", "last_sort", _replace("last_sort", lambda _: np.asarray(10**9))),
    ("an unknown restitution law name", "restitution_law", _replace("restitution_law", lambda _: np.asarray("sticky"))),
    ("a format that is text", "format", _replace("format", lambda _: np.asarray("two"))),
    ("no tree", "tree", _remove("tree")),
    ("no neighbour counts", "neighbour_count", _remove("neighbour_count")),
]
# the same through EdmdRun.resume: the run's checkpoint holds the system's arrays
CRAFTED_RUNS = [("run: leaves = 10**7", "leaves", CRAFTED[0][2]), ("run: a short tree", "tree", CRAFTED[2][2])]
# a checkpoint of the cell-crossing engine (the same system, engine="cells")
CRAFTED_CELLS = [
    ("cells: an engine code of 2", "_engine_code", _replace("_engine_code", lambda _: np.asarray(2))),
    ("cells: a pending partner beyond the particles", "pending", _set("pending", (0, 1), float(N + 3))),
    ("cells: a NaN pending time", "pending", _set("pending", (4, 0), np.nan)),
    ("cells: a pending event numbered after the last", "pending", _set("pending", (2, 2), 1e18)),
    ("cells: pending records of 2 columns", "pending", _replace("pending", lambda pending: pending[:, :2].copy())),
    ("cells: a crossing of a face beyond the box", "book", _set("book", (0, _k.TARGET), -8.0 - 6)),
    ("cells: a list rebuild", "book", _set("book", (0, _k.TARGET), float(_k.LIST_TARGET))),
    ("cells: a particle far from its cell", "cell_of",
     _set("cell_of", 0, lambda cell_of: (cell_of[0] + 13) % 27)),
    ("cells: a grid of the list radius", "ncell", _replace("ncell", lambda ncell: np.array([3, 3, 3]))),
    ("cells: compressing", "params", _set("params", _k.P_GROWTH, 0.1)),
    ("cells: gravity", "geom", _set("geom", (_k.G_GRAVITY, 1), -1.0)),
]


def crafted_system(engine="lists"):
    """108 spheres of two species between walls at y = 0 and L, after some collisions."""
    positions, box = edmd.lattice("fcc", 3, 0.2)
    species = np.arange(N) % 2
    velocities = edmd.maxwell_boltzmann(np.ones(N), 3, seed=1)
    radii = np.where(species, 0.4, 0.5)
    system = edmd.HardSphereSystem(positions, velocities, radii, box, periodic=[True, False, True], species=species,
                                   restitution=[[1.0, 0.9], [0.9, 0.8]], engine=engine)
    system.run(collisions=3_000)
    return system


def run_crafted_cases(folder):
    """Write each crafted checkpoint, load it and run it; one JSON line per case (run in a subprocess by the test)."""
    folder = Path(folder)
    system = crafted_system()
    assert system.count == N
    base = system.state_dict()
    parameters = edmd.EdmdParameters(particles=N, initial="fcc", equilibration=500, collisions=400, blocks=2, seed=1)
    edmd.EdmdRun(parameters, checkpoint=folder / "run.npz").save()
    run = read_checkpoint(folder / "run.npz", "edmd")
    cases = [(case, mutate, "system") for case, _, mutate in CRAFTED]
    cases += [(case, mutate, "run") for case, _, mutate in CRAFTED_RUNS]
    cases += [(case, mutate, "cells") for case, _, mutate in CRAFTED_CELLS]
    bases = {"system": base, "run": run.arrays, "cells": crafted_system("cells").state_dict()}
    for number, (case, mutate, kind) in enumerate(cases):
        arrays = {name: np.array(value) for name, value in bases[kind].items()}
        mutate(arrays)
        path = folder / f"case{number}.npz"
        try:
            if kind in ("system", "cells"):
                write_checkpoint(path, "hard-sphere-system", {}, {}, arrays)
                restored = edmd.HardSphereSystem.load(path)
                restored.run(collisions=500)
                restored.check()
            else:
                write_checkpoint(path, "edmd", run.parameters, run.state, arrays)
                edmd.EdmdRun.resume(path).run()
            outcome = ("ran", "")
        except CheckpointError as error:
            outcome = ("CheckpointError", str(error))
        except Exception as error:  # noqa: BLE001 - the test reports what happened instead
            outcome = (type(error).__name__, str(error))
        print(json.dumps({"case": case, "outcome": outcome[0], "message": outcome[1]}), flush=True)


@pytest.fixture(scope="module")
def crafted_outcomes(tmp_path_factory):
    """Each crafted case's outcome, all run in one subprocess: a segfault fails the tests, not pytest."""
    folder = tmp_path_factory.mktemp("crafted")
    environment = os.environ | {"PYTHONPATH": os.pathsep.join([str(ROOT / "src"), str(ROOT)])}
    result = subprocess.run(
        [sys.executable, "-c", "import sys; from tests.edmd.test_system_state import run_crafted_cases; "
                               "run_crafted_cases(sys.argv[1])", str(folder)],
        cwd=ROOT, env=environment, capture_output=True, text=True, timeout=600,
    )
    outcomes = {entry["case"]: entry for entry in map(json.loads, result.stdout.splitlines())}
    return outcomes, result


@pytest.mark.parametrize(("case", "array"),
                         [(case, array) for case, array, _ in CRAFTED + CRAFTED_RUNS + CRAFTED_CELLS])
def test_a_crafted_checkpoint_is_refused_naming_the_bad_array(crafted_outcomes, case, array):
    outcomes, result = crafted_outcomes
    died = f"the subprocess died (exit code {result.returncode}) before this case: {result.stderr[-2000:]}"
    assert case in outcomes, died
    outcome = outcomes[case]
    assert outcome["outcome"] == "CheckpointError", outcome
    message = outcome["message"]
    assert "\n" not in message and f"'{array}'" in message, message
    assert message.startswith("cannot load" if not case.startswith("run:") else "cannot resume from"), message


def test_the_crafted_cases_start_from_a_checkpoint_that_loads_and_runs(tmp_path):
    system = crafted_system()
    system.save(tmp_path / "real.npz")
    restored = edmd.HardSphereSystem.load(tmp_path / "real.npz")
    assert restored.run(collisions=500) == 500 and restored.check() > -1e-9
    state = system.state_dict()
    fortran = {name: np.asfortranarray(value) if np.ndim(value) > 1 else value for name, value in state.items()}
    assert edmd.HardSphereSystem.from_state_dict(fortran).run(collisions=100) == 100  # any memory order is fine


def test_a_format_2_checkpoint_without_the_transport_sums_loads_with_them_at_zero_and_runs_on():
    """Engine format 2 had a 10-slot accumulator: its state restores with the transport sums appended at 0
    (only their changes over a measurement mean anything) and runs on as the saved system would have."""
    system = fcc_system(cells=3, eta=0.3)
    system.run(collisions=3000)
    state = {name: np.array(value) for name, value in system.state_dict().items()}
    state["acc"] = state["acc"][: _k.ACC_SIZE_WITHOUT_TRANSPORT]
    state["format"] = np.asarray(2)
    old = edmd.HardSphereSystem.from_state_dict(state)
    np.testing.assert_array_equal(old.acc[: _k.ACC_SIZE_WITHOUT_TRANSPORT], system.acc[: _k.ACC_SIZE_WITHOUT_TRANSPORT])
    assert not np.any(old.acc[_k.ACC_SIZE_WITHOUT_TRANSPORT:]) and old.acc.shape == (_k.ACC_SIZE,)
    old.run(collisions=2000)
    system.run(collisions=2000)
    np.testing.assert_array_equal(old.positions(), system.positions())
    state["acc"] = state["acc"][:7]  # neither layout
    with pytest.raises(CheckpointError, match=rf"array 'acc' must have shape \({_k.ACC_SIZE},\)"):
        edmd.HardSphereSystem.from_state_dict(state)
