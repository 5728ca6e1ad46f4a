"""collisionkit.sweep: running points (library calls), failures, the table, resume, a real dask cluster."""

from __future__ import annotations

import json
import os
import signal
import time
from concurrent.futures import ThreadPoolExecutor

import pytest

from collisionkit import sweep
from tests.sweep.helpers import (  # noqa: F401
    ENCOUNTERS, SMALL_EDMD, dask_client, deadline, physics_columns, read_table, serial_run,
)

# ------------------------------------------------------------------ running


def test_a_failing_point_is_recorded_and_the_others_finish(tmp_path):
    study = {**ENCOUNTERS, "vary": {"sep0": [10.0, 0.5, 20.0]}, "replicas": 1}
    seen = []
    fractions = []
    with ThreadPoolExecutor(2) as pool:
        results = sweep.run_study(study, tmp_path, executor=pool, on_point=seen.append, progress=fractions.append)
    assert len(seen) == 3 and fractions == pytest.approx([1 / 3, 2 / 3, 1.0], rel=1e-12)
    assert [record["status"] for record in results.records] == ["ok", "failed", "ok"]
    failed = results.failed[0]
    assert failed["error"].startswith("ValueError") and "sep0 must be >= rp" in failed["error"]
    saved = json.loads((tmp_path / "points" / "p0001-r00" / "result.json").read_text())
    assert saved["status"] == "failed" and "sep0 must be >= rp" in saved["error"]
    rows = read_table(tmp_path / "results.csv")
    assert [row["status"] for row in rows] == ["ok", "failed", "ok"]
    assert rows[1]["orbit.deflection_angle"] == "" and float(rows[0]["orbit.deflection_angle"]) > 0
    assert "sep0 must be >= rp" in rows[1]["error"]


def test_an_exception_in_the_command_is_recorded_not_raised(tmp_path):
    study = sweep.study_from_dict({**ENCOUNTERS, "replicas": 1})
    task = sweep.point_tasks(study, tmp_path)[0]
    broken = sweep.PointTask(**{**task.__dict__, "options": {**task.options, "no-such-option": 1}})
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
    assert (tmp_path / "points" / "p0002-r01" / "initial_conditions.json").exists()  # the run's files
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
    with pytest.raises(ValueError, match="is not a checkpoint"):
        sweep.resume_study(points / "p0000-r00" / "result.json")
    with pytest.raises(ValueError, match="holds a different study"):
        with ThreadPoolExecutor(1) as pool:
            sweep.run_study({**ENCOUNTERS, "seed": 6}, out, executor=pool, resume=True)
    with ThreadPoolExecutor(1) as pool:
        resumed = sweep.resume_study(out / "checkpoint.npz", executor=pool)  # the same as run_study(..., resume=True)
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
        sweep.run_study(SMALL_EDMD, out, executor=dask_client, on_point=progress)
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


def test_a_point_whose_worker_died_resumes_from_its_own_checkpoint(tmp_path, monkeypatch):
    # a study point that checkpoints could never recover after a killed worker: the rerun refused its file
    from collisionkit.edmd import HardSphereSystem

    study = {**SMALL_EDMD, "replicas": 1, "fixed": {**SMALL_EDMD["fixed"], "initial": "fcc"},
             "vary": {"packing-fraction": [0.2]}}
    reference = serial_run(study, tmp_path / "reference")
    real, calls = HardSphereSystem.run, []

    class WorkerDied(Exception):
        pass

    def dies_in_the_second_block(system, *args, **kwargs):
        calls.append(1)
        if len(calls) == 3:  # one equilibration chunk, one block, then the worker dies
            raise WorkerDied
        return real(system, *args, **kwargs)

    monkeypatch.setattr(HardSphereSystem, "run", dies_in_the_second_block)
    died = serial_run(study, tmp_path / "study")
    assert died.failed and (tmp_path / "study" / "points" / "p0000-r00" / "checkpoint.npz").exists()
    calls.clear()
    monkeypatch.setattr(HardSphereSystem, "run", lambda system, *a, **k: (calls.append(1), real(system, *a, **k))[1])
    with ThreadPoolExecutor(1) as pool:
        resumed = sweep.resume_study(tmp_path / "study" / "checkpoint.npz", executor=pool)
    assert not resumed.failed and len(calls) == 2  # the two blocks left, not the whole run again
    assert physics_columns(read_table(tmp_path / "study" / "results.csv")) == \
        physics_columns(read_table(tmp_path / "reference" / "results.csv"))
    assert reference.table[0]["compressibility_factor"] == resumed.table[0]["compressibility_factor"]


def test_a_second_sweep_of_a_running_study_is_refused(tmp_path):
    # a sweep and a concurrent sweep --resume of one folder replaced finished results with failures
    import subprocess
    import sys

    from collisionkit._io import FileLockedError

    out = tmp_path / "study"
    serial_run(ENCOUNTERS, out)
    holder = subprocess.Popen([sys.executable, "-c", "import sys, time\nfrom collisionkit._io import exclusive\n"
                               f"with exclusive({str(out / 'checkpoint.npz')!r}):\n    print('held', flush=True)\n"
                               "    time.sleep(60)"], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        before = (out / "results.csv").read_bytes()
        with pytest.raises(FileLockedError, match="pid"):
            with ThreadPoolExecutor(1) as pool:
                sweep.resume_study(out / "checkpoint.npz", executor=pool)
        assert (out / "results.csv").read_bytes() == before
    finally:
        holder.kill()
        holder.wait(timeout=30)
    with ThreadPoolExecutor(1) as pool:
        assert sweep.resume_study(out / "checkpoint.npz", executor=pool).skipped == 6  # free again


def test_a_point_still_run_by_an_earlier_client_s_worker_is_waited_for_not_failed(tmp_path):
    # a killed client's worker kept running a point; the resumed study's second attempt failed on its lock
    import subprocess
    import sys

    study = sweep.study_from_dict({**SMALL_EDMD, "replicas": 1, "vary": {"packing-fraction": [0.2]}})
    task = sweep.point_tasks(study, tmp_path)[0]
    task.directory.mkdir(parents=True)
    holder = subprocess.Popen([sys.executable, "-c", "import time\nfrom collisionkit._io import exclusive\n"
                               f"with exclusive({str(task.directory / 'checkpoint.npz')!r}):\n"
                               "    print('held', flush=True)\n    time.sleep(2)"], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        record = sweep.run_point(task)
    finally:
        holder.wait(timeout=60)
    assert record["status"] == "ok", record["error"]


def test_a_folder_that_takes_no_more_files_loses_no_result(tmp_path, monkeypatch):
    # issue 16, item 1: a failed checkpoint save stopped the study, and a failed results.csv lost every result
    from collisionkit.sweep import execute

    saves = []

    def full_after_the_first(study, out, records):
        saves.append(len(records))
        if len(saves) > 1:
            raise OSError(28, "No space left on device")
        return out / execute.CHECKPOINT_FILE

    def full(study, out, table):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(execute, "_save_checkpoint", full_after_the_first)
    monkeypatch.setattr(execute, "write_outputs", full)
    study = {**ENCOUNTERS, "replicas": 1}
    with ThreadPoolExecutor(1) as pool, pytest.raises(sweep.OutputsNotWritten) as caught:
        sweep.run_study(study, tmp_path, executor=pool)
    assert len(saves) == 4  # the set-up's save, then one after each point: the study went on
    results = caught.value.results
    assert [row["status"] for row in results.table] == ["ok", "ok", "ok"]
    assert all(row["orbit.deflection_angle"] > 0 for row in results.table)
    assert caught.value.errno == 28 and "could not be written in" in str(caught.value)


def test_a_two_term_scan_is_swept_like_the_other_commands(tmp_path):
    """boltzmann points: the library's numbers in the table, mean_energy its main result, a failed point recorded."""
    from collisionkit.transport import lucas_saelee, two_term_boltzmann

    study = {"command": "boltzmann", "seed": 0, "replicas": 1,
             "fixed": {"model": "lucas_saelee", "gas-temperature": 0.0, "growth": "spatial"},
             "vary": {"E-N": [50.0, 3000.0, 100.0]}}
    results = serial_run(study, tmp_path)
    rows = read_table(tmp_path / "results.csv")
    assert [row["status"] for row in rows] == ["ok", "failed", "ok"]
    assert float(rows[0]["mean_energy"]) == two_term_boltzmann(lucas_saelee(0.5), 50.0, 0.0,
                                                               growth="spatial").mean_energy
    assert "E/N = 3000 Td: no steady-state Townsend growth" in rows[1]["error"]
    summary = json.loads((tmp_path / "points" / "p0002-r00" / "summary.json").read_text())
    assert summary["parameters"]["reduced_field"] == [100.0] and summary["provenance"]["cross_sections"] == []
    assert sweep.sweep_command("boltzmann").main == "mean_energy" and len(results.table) == 3
