"""collisionkit.sweep: study parsing and expansion, seeds, running points, failures, resume, dask workers."""

from __future__ import annotations

import contextlib
import csv
import json
import os
import signal
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

from collisionkit import sweep

# 108 spheres, a few thousand collisions: well under a second per point once compiled
SMALL_EDMD = {
    "command": "edmd",
    "seed": 11,
    "replicas": 2,
    "fixed": {"particles": 108, "equilibration": 2000, "collisions": 3000, "blocks": 3},
    "vary": {"packing-fraction": [0.1, 0.2, 0.3]},
}
ENCOUNTERS = {"command": "encounter", "seed": 5, "replicas": 2, "fixed": {"rp": 1.0}, "vary": {"vinf": [0.5, 1.0, 2.0]}}
WALL_CLOCK_COLUMNS = {"elapsed", "collisions_per_second"}


@contextlib.contextmanager
def deadline(seconds: float):
    """Fail (TimeoutError) instead of hanging if the block takes longer than ``seconds``."""

    def expire(signum, frame):
        raise TimeoutError(f"test block took longer than {seconds} s")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def read_table(path: Path) -> list[dict[str, str]]:
    with open(path, newline="") as stream:
        return list(csv.DictReader(stream))


def physics_columns(rows: list[dict[str, str]]) -> list[dict[str, str]]:
    """The table without wall-clock columns (text of floats: equal text is equal numbers)."""
    return [{key: value for key, value in row.items() if key not in WALL_CLOCK_COLUMNS} for row in rows]


def serial_run(study, out: Path):
    with ThreadPoolExecutor(1) as pool:
        return sweep.run_study(study, out, executor=pool)


@pytest.fixture(scope="module")
def dask_client():
    """A real LocalCluster of two worker processes (one thread each), shut down after the module."""
    import distributed

    with deadline(120):
        cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0")
        client = distributed.Client(cluster)
    try:
        yield client
    finally:
        with deadline(60):
            client.close()
            cluster.close()


# ------------------------------------------------------------------ parsing and validation


def test_the_issue_example_parses_with_dashed_names():
    study = sweep.study_from_dict(
        {"command": "edmd", "replicas": 2, "seed": 1, "fixed": {"dim": 3, "particles": 500, "collisions": 20000},
         "vary": {"packing-fraction": [0.1, 0.2, 0.3]}}
    )  # fmt: skip
    assert study.vary == {"packing-fraction": (0.1, 0.2, 0.3)}
    assert study.fixed == {"dim": 3, "particles": 500, "collisions": 20000}
    assert study.main == "compressibility_factor"
    assert len(sweep.point_tasks(study, "out")) == 6


def test_underscored_keys_become_dashed_and_main_can_be_chosen():
    study = sweep.Study("edmd", seed=0, fixed={"packing_fraction": 0.2}, vary={"dim": [2, 3]}, main="pressure")
    assert study.fixed == {"packing-fraction": 0.2} and study.main == "pressure"


@pytest.mark.parametrize(
    ("spec", "expected"),
    [
        ({"start": 0.1, "stop": 0.3, "num": 3}, (0.1, 0.2, 0.3)),
        ({"start": 0.1, "stop": 0.5, "step": 0.1}, (0.1, 0.2, 0.3, 0.4, 0.5)),
        ({"start": 100, "stop": 400, "step": 100}, (100, 200, 300, 400)),
        ({"start": 100, "stop": 350, "step": 100}, (100, 200, 300)),
        ({"start": 1.0, "stop": 0.0, "step": -0.5}, (1.0, 0.5, 0.0)),
        ({"start": 1, "stop": 100, "num": 3, "log": True}, (1.0, 10.0, 100.0)),
        ({"start": 2.0, "stop": 2.0, "num": 1}, (2.0,)),
    ],
)
def test_ranges_expand_to_tidy_values(spec, expected):
    values = sweep.Study("edmd", seed=0, vary={"x": spec}).vary["x"]
    assert values == expected
    assert [type(value) for value in values] == [type(value) for value in expected]


@pytest.mark.parametrize(
    ("data", "error", "message"),
    [
        ({"command": "edmd", "seed": 1, "vary": {"dim": [2]}, "replica": 2}, ValueError, "unknown study key 'replica'"),
        ({"command": "edmd", "vary": {"dim": [2]}}, ValueError, "needs 'seed'"),
        ({"command": "edmd", "seed": 1}, ValueError, "needs 'vary'"),
        ({"command": "edmd", "seed": 1, "vary": {}}, ValueError, "at least one option"),
        ({"command": "edmd", "seed": 1, "vary": {"dim": []}}, ValueError, "vary.dim is an empty list"),
        ({"command": "edmd", "seed": 1, "vary": {"dim": 3}}, TypeError, "vary.dim must be a list or a range"),
        ({"command": "edmd", "seed": 1, "vary": {"dim": [[2]]}}, TypeError, "vary.dim must be a number"),
        ({"command": "edmd", "seed": 1, "vary": {"dim": [2]}, "replicas": 0}, ValueError, r"replicas must be in \[1, 100000\]"),
        ({"command": "edmd", "seed": 1, "vary": {"dim": [2]}, "replicas": 1.5}, TypeError, "replicas must be an integer"),
        ({"command": "edmd", "seed": 1, "vary": {"dim": [2]}, "replicas": True}, TypeError, "replicas must be an integer"),
        ({"command": "edmd", "seed": -1, "vary": {"dim": [2]}}, ValueError, "seed must be >= 0"),
        ({"command": "", "seed": 1, "vary": {"dim": [2]}}, TypeError, "command must be a non-empty string"),
        ({"command": "edmd", "seed": 1, "vary": {"dim": [2]}, "fixed": {"dim": 3}}, ValueError, "both fixed and varied"),
        ({"command": "edmd", "seed": 1, "vary": {"a-b": [1], "a_b": [2]}}, ValueError, "names 'a-b' twice"),
        ({"command": "edmd", "seed": 1, "vary": {"x": {"start": 0, "stop": 1}}}, ValueError, "exactly one of num or step"),
        ({"command": "edmd", "seed": 1, "vary": {"x": {"start": 0, "stop": 1, "num": 2, "step": 1}}}, ValueError, "exactly one"),
        ({"command": "edmd", "seed": 1, "vary": {"x": {"start": 0, "stop": 1, "count": 2}}}, ValueError, "unknown range keys"),
        ({"command": "edmd", "seed": 1, "vary": {"x": {"start": 0, "stop": 1, "num": 0}}}, ValueError, r"num must be in \[1, 100000\]"),
        ({"command": "edmd", "seed": 1, "vary": {"x": {"start": 0, "stop": 1, "step": 1e-9}}}, ValueError,
         "gives 1000000001 values"),  # listed them all before: minutes and gigabytes
        ({"command": "edmd", "seed": 1, "vary": {"x": {"start": 0, "stop": 1, "num": 10**9}}}, ValueError,
         r"num must be in \[1, 100000\]"),
        ({"command": "edmd", "seed": 1, "vary": {"x": {"start": 0, "stop": 1, "step": -1}}}, ValueError, "lead from start"),
        ({"command": "edmd", "seed": 1, "vary": {"x": {"start": 0, "stop": 1, "num": 3, "log": True}}}, ValueError, "log range"),
        ({"command": "edmd", "seed": 1, "vary": {"x": [1, 2], "y": [1]}, "zip": [["x", "y"]]}, ValueError, "same number"),
        ({"command": "edmd", "seed": 1, "vary": {"x": [1, 2]}, "zip": [["x", "z"]]}, ValueError, "'z', which is not in vary"),
        ({"command": "edmd", "seed": 1, "vary": {"x": [1]}, "fixed": {"y": float("nan")}}, ValueError, "must be finite"),
    ],
)
def test_bad_studies_are_rejected_with_a_clear_message(data, error, message):
    with pytest.raises(error, match=message):
        sweep.study_from_dict(data)


def test_load_study_reports_missing_and_malformed_files(tmp_path):
    with pytest.raises(ValueError, match="study file not found"):
        sweep.load_study(tmp_path / "missing.toml")
    broken = tmp_path / "broken.toml"
    broken.write_text("command = \n")
    with pytest.raises(ValueError, match="not valid TOML"):
        sweep.load_study(broken)


# ------------------------------------------------------------------ the command's options


@pytest.mark.parametrize(
    ("data", "error", "message"),
    [
        ({"command": "nbody", "seed": 1, "vary": {"x": [1]}}, ValueError, "unknown command 'nbody'; available: .*edmd"),
        ({"command": "sweep", "seed": 1, "vary": {"x": [1]}}, ValueError, "cannot be swept"),
        ({"command": "edmd", "seed": 1, "vary": {"packing": [0.1]}}, ValueError, "no option 'packing'; its options: .*packing-fraction"),
        ({"command": "edmd", "seed": 1, "vary": {"seed": [1, 2]}}, ValueError, "'seed' is set by the sweep"),
        ({"command": "edmd", "seed": 1, "vary": {"dim": [3]}, "fixed": {"summary": "x.json"}}, ValueError, "'summary' is set by"),
        ({"command": "edmd", "seed": 1, "vary": {"particles": ["many"]}}, TypeError, "'particles' takes an integer"),
        ({"command": "edmd", "seed": 1, "vary": {"packing-fraction": ["0.1"]}}, TypeError, "takes a number"),
        ({"command": "edmd", "seed": 1, "vary": {"dim": [3]}, "fixed": {"plots": "no"}}, TypeError, "is a switch"),
        ({"command": "encounter", "seed": 1, "vary": {"seed": [1]}}, ValueError, "no option 'seed'"),
    ],
)
def test_options_are_checked_against_the_command(data, error, message):
    with pytest.raises(error, match=message):
        sweep.check_command(sweep.study_from_dict(data))


def test_a_command_without_summary_cannot_be_swept():
    options = {name: spec for name, spec in sweep.ENCOUNTER_LIKE.items() if name != "summary"}
    with pytest.raises(ValueError, match="has no --summary option"):
        sweep.check_command(sweep.Study("encounter", seed=0, vary={"vinf": [1.0]}), options)


def test_point_arguments_hold_seed_summary_out_and_no_plots(tmp_path):
    study = sweep.study_from_dict(SMALL_EDMD)
    task = sweep.point_tasks(study, tmp_path)[3]
    arguments = list(task.arguments)
    assert arguments[0] == "edmd" and task.name == "p0001-r01"
    assert arguments[arguments.index("--packing-fraction") + 1] == "0.2"
    assert arguments[arguments.index("--particles") + 1] == "108"
    assert arguments[arguments.index("--seed") + 1] == str(task.seed)
    assert arguments[arguments.index("--out") + 1] == str(tmp_path / "points" / "p0001-r01")
    assert arguments[arguments.index("--summary") + 1] == str(tmp_path / "points" / "p0001-r01" / "summary.json")
    assert "--no-plots" in arguments
    trajectory = sweep.study_from_dict({**SMALL_EDMD, "fixed": {**SMALL_EDMD["fixed"], "trajectory": "run.gsd"}})
    arguments = list(sweep.point_tasks(trajectory, tmp_path)[1].arguments)
    assert arguments[arguments.index("--trajectory") + 1] == str(tmp_path / "points" / "p0000-r01" / "run.gsd")
    with_plots = sweep.study_from_dict({**SMALL_EDMD, "fixed": {**SMALL_EDMD["fixed"], "plots": True}})
    arguments = sweep.point_tasks(with_plots, tmp_path)[0].arguments
    assert "--plots" in arguments and "--no-plots" not in arguments


# ------------------------------------------------------------------ points and seeds


def test_expansion_is_the_cartesian_product_last_option_fastest():
    study = sweep.Study("edmd", seed=0, vary={"a": [1, 2], "b": ["x", "y", "z"]})
    points = sweep.expand(study)
    assert len(points) == 6
    assert points[:4] == [{"a": 1, "b": "x"}, {"a": 1, "b": "y"}, {"a": 1, "b": "z"}, {"a": 2, "b": "x"}]


def test_zip_groups_need_equal_lengths_and_pair_values_in_order():
    with pytest.raises(ValueError, match="same number"):
        sweep.Study("edmd", seed=0, vary={"a": [1, 2], "c": [5, 6, 7]}, zip=[["a", "c"]])
    study = sweep.Study("edmd", seed=0, vary={"a": [1, 2], "b": [3, 4], "c": [5, 6]}, zip=[["a", "c"]])
    assert [tuple(point.values()) for point in sweep.expand(study)] == [(1, 3, 5), (1, 4, 5), (2, 3, 6), (2, 4, 6)]


def test_seeds_come_from_seed_sequence_spawn_and_are_all_different():
    study = sweep.study_from_dict(SMALL_EDMD)
    tasks = sweep.point_tasks(study, "out")
    children = [child.spawn(2) for child in np.random.SeedSequence(11).spawn(3)]
    for task in tasks:
        child = children[task.index][task.replica]
        assert task.spawn_key == child.spawn_key
        assert task.seed == int(child.generate_state(1, dtype=np.uint32)[0])
    assert len({task.seed for task in tasks}) == len(tasks)


def test_more_replicas_or_points_keep_the_existing_seeds():
    base = {task.name: task.seed for task in sweep.point_tasks(sweep.study_from_dict(SMALL_EDMD), "out")}
    larger = sweep.study_from_dict({**SMALL_EDMD, "replicas": 3, "vary": {"packing-fraction": [0.1, 0.2, 0.3, 0.4]}})
    grown = {task.name: task.seed for task in sweep.point_tasks(larger, "out")}
    assert all(grown[name] == seed for name, seed in base.items())
    other_root = sweep.study_from_dict({**SMALL_EDMD, "seed": 12})
    assert not set(base.values()) & {task.seed for task in sweep.point_tasks(other_root, "out")}


# ------------------------------------------------------------------ running


def test_a_failing_point_is_recorded_and_the_others_finish(tmp_path):
    study = {**ENCOUNTERS, "vary": {"sep0": [10.0, 0.5, 20.0]}, "replicas": 1}
    seen = []
    with ThreadPoolExecutor(2) as pool:
        results = sweep.run_study(study, tmp_path, executor=pool, progress=seen.append)
    assert len(seen) == 3
    assert [record["status"] for record in results.records] == ["ok", "failed", "ok"]
    failed = results.failed[0]
    assert failed["exit_code"] == 2 and "sep0 must be >= rp" in failed["error"]
    saved = json.loads((tmp_path / "points" / "p0001-r00" / "result.json").read_text())
    assert saved["status"] == "failed" and "sep0 must be >= rp" in saved["error"]
    rows = read_table(tmp_path / "results.csv")
    assert [row["status"] for row in rows] == ["ok", "failed", "ok"]
    assert rows[1]["orbit.deflection_angle"] == "" and float(rows[0]["orbit.deflection_angle"]) > 0
    assert "sep0 must be >= rp" in rows[1]["error"]


def test_an_exception_in_the_command_is_recorded_not_raised(tmp_path):
    study = sweep.study_from_dict({**ENCOUNTERS, "replicas": 1})
    task = sweep.point_tasks(study, tmp_path)[0]
    broken = sweep.PointTask(**{**task.__dict__, "arguments": (*task.arguments, "--no-such-option")})
    record = sweep.run_point(broken)
    assert record["status"] == "failed" and "no-such-option" in record["error"]
    assert json.loads(broken.result_path.read_text())["status"] == "failed"
    assert "no-such-option" in (broken.directory / "output.log").read_text()


def test_table_plot_and_point_files(tmp_path):
    results = serial_run(ENCOUNTERS, tmp_path)
    rows = read_table(tmp_path / "results.csv")
    assert len(rows) == 6 == len(results.table)
    for column in ("vinf", "point", "replica", "seed", "spawn_key", "status", "error", "orbit.deflection_angle"):
        assert column in rows[0], column
    assert {row["vinf"] for row in rows} == {"0.5", "1.0", "2.0"}
    assert [json.loads(row["spawn_key"]) for row in rows[:2]] == [[0, 0], [0, 1]]
    assert (tmp_path / "main_result.png").stat().st_size > 1000
    assert (tmp_path / "points" / "p0002-r01" / "summary.json").exists()
    assert (tmp_path / "points" / "p0002-r01" / "initial_conditions.json").exists()  # the command's --out
    faster = [row for row in results.table if row["vinf"] == 2.0][0]["orbit.deflection_angle"]
    slower = [row for row in results.table if row["vinf"] == 0.5][0]["orbit.deflection_angle"]
    assert faster < slower  # a faster encounter is deflected less
    means = sweep.aggregate(results.table, "orbit.deflection_angle", ["vinf"])
    assert [mean["n"] for mean in means] == [2, 2, 2] and all(mean["error"] == 0.0 for mean in means)


def test_parquet_holds_the_same_table_when_pyarrow_is_installed(tmp_path):
    import pyarrow.parquet as parquet
    serial_run({**ENCOUNTERS, "vary": {"sep0": [10.0, 0.5]}}, tmp_path)
    table = parquet.read_table(tmp_path / "results.parquet").to_pylist()
    rows = read_table(tmp_path / "results.csv")
    assert len(table) == len(rows) == 4
    assert [row["status"] for row in table] == [row["status"] for row in rows]
    assert table[0]["orbit.eccentricity"] == float(rows[0]["orbit.eccentricity"]) and table[2]["orbit.eccentricity"] is None


def test_same_numbers_with_one_or_several_threads(tmp_path):
    one = serial_run(SMALL_EDMD, tmp_path / "one")
    with ThreadPoolExecutor(3) as pool:
        three = sweep.run_study(SMALL_EDMD, tmp_path / "three", executor=pool)
    assert [row["seed"] for row in one.table] == [row["seed"] for row in three.table]
    assert physics_columns(read_table(tmp_path / "one" / "results.csv")) == physics_columns(
        read_table(tmp_path / "three" / "results.csv")
    )
    assert all(row["status"] == "ok" for row in one.table)
    assert one.table[0]["compressibility_factor"] < one.table[-1]["compressibility_factor"]  # Z grows with eta


def test_resume_skips_complete_points_and_reruns_the_rest(tmp_path):
    reference = serial_run(ENCOUNTERS, tmp_path / "reference")
    out = tmp_path / "study"
    serial_run(ENCOUNTERS, out)
    points = out / "points"
    (points / "p0000-r01" / "result.json").unlink()  # lost
    (points / "p0001-r00" / "result.json").write_text('{"status": "ok", "summ')  # torn (not by us: we write atomically)
    failed = json.loads((points / "p0002-r00" / "result.json").read_text()) | {"status": "failed"}
    (points / "p0002-r00" / "result.json").write_text(json.dumps(failed))
    untouched = (points / "p0002-r01" / "result.json").stat().st_mtime_ns
    with pytest.raises(ValueError, match="already holds a study"):
        serial_run(ENCOUNTERS, out)
    with pytest.raises(ValueError, match="holds a different study"):
        with ThreadPoolExecutor(1) as pool:
            sweep.run_study({**ENCOUNTERS, "seed": 6}, out, executor=pool, resume=True)
    with ThreadPoolExecutor(1) as pool:
        resumed = sweep.run_study(ENCOUNTERS, out, executor=pool, resume=True)
    assert resumed.skipped == 3
    assert (points / "p0002-r01" / "result.json").stat().st_mtime_ns == untouched
    assert json.loads((points / "p0001-r00" / "result.json").read_text())["status"] == "ok"
    assert physics_columns(read_table(out / "results.csv")) == physics_columns(
        read_table(tmp_path / "reference" / "results.csv")
    )
    assert len(reference.table) == 6


def test_run_study_argument_errors(tmp_path):
    with pytest.raises(TypeError, match="study must be a Study"):
        sweep.run_study(42, tmp_path)
    with pytest.raises(ValueError, match="workers sets the size"):
        with ThreadPoolExecutor(1) as pool:
            sweep.run_study(ENCOUNTERS, tmp_path, executor=pool, workers=2)
    with pytest.raises(ValueError, match="workers must be >= 1"):
        with sweep.local_client(0):
            pass


# ------------------------------------------------------------------ a real dask cluster


class ClientStopped(Exception):
    """Raised from the progress callback: the client goes away mid-study."""


def _kill_a_busy_worker(client) -> str:
    processing = {worker: keys for worker, keys in client.processing().items() if keys}
    victim = next(iter(processing)) if processing else next(iter(client.scheduler_info()["workers"]))
    pid = client.run(os.getpid, workers=[victim])[victim]
    os.kill(pid, signal.SIGKILL)  # a hard crash of the worker process, mid-point
    return victim


@pytest.mark.slow
def test_killed_worker_and_stopped_client_resume_to_the_serial_table(tmp_path, dask_client):
    reference = tmp_path / "serial"
    serial_run(SMALL_EDMD, reference)
    out = tmp_path / "cluster"
    finished, victim = [], []

    def progress(record):
        finished.append(record["name"])
        if len(finished) == 1:
            victim.append(_kill_a_busy_worker(dask_client))
        if len(finished) == 3:
            raise ClientStopped

    with deadline(240), pytest.raises(ClientStopped):
        sweep.run_study(SMALL_EDMD, out, executor=dask_client, progress=progress)
    saved = {path.parent.name for path in (out / "points").glob("*/result.json")}
    assert set(finished) <= saved and len(saved) < 6
    assert not (out / "results.csv").exists()
    with deadline(60):
        while victim[0] in dask_client.scheduler_info()["workers"]:
            time.sleep(0.1)  # the scheduler has noticed the killed worker (its nanny starts a new one)
    with deadline(240):
        resumed = sweep.run_study(SMALL_EDMD, out, executor=dask_client, resume=True)
    assert resumed.skipped >= 3 and not resumed.failed
    assert len(dask_client.scheduler_info()["workers"]) >= 1
    cluster_rows = physics_columns(read_table(out / "results.csv"))
    assert cluster_rows == physics_columns(read_table(reference / "results.csv"))
    assert len(cluster_rows) == 6 and all(row["status"] == "ok" for row in cluster_rows)


def test_point_names_need_non_negative_integers():
    assert sweep.point_name(3, 1) == "p0003-r01"
    with pytest.raises(ValueError, match="index must be >= 0"):
        sweep.point_name(-1, 0)  # was 'p-001-r00'
    with pytest.raises(TypeError, match="replica must be an integer"):
        sweep.point_name(1, 0.5)
