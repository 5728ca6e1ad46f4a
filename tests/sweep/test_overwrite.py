"""collisionkit.sweep: a study started again in its folder (``overwrite``), removing only the sweep's own files."""

from __future__ import annotations

import json
import os
from concurrent.futures import ThreadPoolExecutor

import pytest

from collisionkit import sweep
from collisionkit._io import read_checkpoint, write_checkpoint
from tests.sweep.helpers import ENCOUNTERS, read_table, serial_run

SMALLER = {**ENCOUNTERS, "seed": 6, "vary": {"vinf": [0.5]}}  # one point (two replicas), another seed


class Interrupting:
    """An executor stopped by Ctrl-C before its first point runs."""

    def submit(self, function, *arguments):
        raise KeyboardInterrupt


def run(study, out, **options):
    with ThreadPoolExecutor(1) as pool:
        return sweep.run_study(study, out, executor=pool, **options)


def test_overwrite_starts_another_study_again_and_removes_only_the_old_one_s_files(tmp_path):
    out = tmp_path / "study"
    serial_run(ENCOUNTERS, out)  # three points, two replicas
    points = out / "points"
    (points / "p0000-r00" / "output.log").write_text("the traceback of an old failure")  # the sweep's name: stale
    (points / "p0000-r00" / "notes.txt").write_text("mine")
    (points / "p0002-r01" / "notes.txt").write_text("mine")
    (out / "notes.txt").write_text("mine")
    again = run(SMALLER, out, overwrite=True)
    assert again.skipped == 0 and not again.failed and len(again.table) == 2
    assert sorted(path.name for path in points.iterdir()) == ["p0000-r00", "p0000-r01", "p0002-r01"]
    assert sorted(path.name for path in (points / "p0002-r01").iterdir()) == ["notes.txt"]  # the old point's files go
    assert sorted(path.name for path in (points / "p0000-r00").iterdir()) == [
        "initial_conditions.json", "initial_conditions.txt", "notes.txt", "result.json", "summary.json"]
    assert json.loads((points / "p0000-r00" / "result.json").read_text())["seed"] == sweep.point_seed(6, 0, 0)
    assert (out / "notes.txt").read_text() == "mine"
    assert [row["vinf"] for row in read_table(out / "results.csv")] == ["0.5", "0.5"]
    saved = read_checkpoint(out / "checkpoint.npz", "sweep")
    assert saved.state["fingerprint"] == sweep.study_from_dict(SMALLER).fingerprint()
    assert run(SMALLER, tmp_path / "new", overwrite=True).skipped == 0  # a folder without a study: nothing to remove


DEAD_WRITER = 4194305  # above Linux's largest process id: a writer that is surely gone


def test_overwrite_removes_the_lock_and_temporary_files_killed_runs_left_and_keeps_a_live_writer_s(tmp_path):
    # a point killed mid-write left its hidden lock and temporary files; --overwrite left them in the folder
    out = tmp_path / "study"
    serial_run(ENCOUNTERS, out)
    point = out / "points" / "p0002-r01"  # not a point of the new study: its folder goes when emptied
    left = [point / ".result.json.lock", point / f".summary.json.{DEAD_WRITER}.abcd1234.tmp",
            point / ".checkpoint.npz.lock", out / f".results.csv.{DEAD_WRITER}.abcd1234.tmp"]
    for path in left:
        path.write_text(f"{DEAD_WRITER}\n")
        os.utime(path, (0, 0))  # older than this process, as a killed run's are
    live = out / "points" / "p0000-r00" / f".result.json.{os.getpid()}.abcd1234.tmp"  # this process: a live writer
    live.write_text("half a result")
    run(SMALLER, out, overwrite=True)
    assert not [path for path in left if path.exists()] and not point.exists()
    assert live.exists()
    assert not list(out.rglob(".*.lock"))


def test_an_interrupted_overwrite_keeps_none_of_the_old_results_for_a_resume(tmp_path):
    out = tmp_path / "study"
    serial_run(ENCOUNTERS, out)
    with pytest.raises(KeyboardInterrupt):
        sweep.run_study(ENCOUNTERS, out, executor=Interrupting(), overwrite=True)
    assert not list(out.glob("points/*/*")) and not (out / "results.csv").exists()
    with ThreadPoolExecutor(1) as pool:
        resumed = sweep.resume_study(out / "checkpoint.npz", executor=pool)
    assert resumed.skipped == 0 and len(resumed.table) == 6  # every point ran again: none of the old ones counted


def test_a_study_is_replaced_only_when_asked_and_only_if_it_is_a_study(tmp_path):
    out = tmp_path / "study"
    serial_run(ENCOUNTERS, out)
    with pytest.raises(ValueError, match=r"already holds a study; resume it .* start it again there .*--overwrite"):
        run(ENCOUNTERS, out)
    with pytest.raises(ValueError, match="resume continues the study in out, overwrite starts it again"):
        run(ENCOUNTERS, out, resume=True, overwrite=True)
    assert len(list(out.glob("points/*/result.json"))) == 6
    for name, write in [("damaged", lambda path: path.write_bytes(b"not a checkpoint")),
                        ("edmd", lambda path: write_checkpoint(path, "edmd", {"dim": 3}, {}))]:
        other = tmp_path / name
        other.mkdir()
        write(other / "checkpoint.npz")
        before = (other / "checkpoint.npz").read_bytes()
        with pytest.raises(ValueError, match="holds no study that can be replaced"):
            run(ENCOUNTERS, other, overwrite=True)
        assert (other / "checkpoint.npz").read_bytes() == before and not (other / "points").exists()
