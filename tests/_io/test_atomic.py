"""Tests of atomic writes and of the temporary files a killed write leaves."""

import json
import os

import numpy as np
import pytest

from collisionkit import _io

from tests._io.processes import HOLD, held_by_another_process


def test_json_with_numpy_values_round_trips(tmp_path):
    path = _io.atomic_write_json(tmp_path / "sub" / "s.json", {"a": np.float64(1.5), "b": np.arange(3), "c": np.int64(7)})
    assert json.loads(path.read_text()) == {"a": 1.5, "b": [0, 1, 2], "c": 7}


def test_json_is_strict_non_finite_numbers_become_null(tmp_path):
    data = {"period": np.inf, "d": [np.nan, 1.0], "v": np.array([-np.inf, 2.0]), "e": np.float64(np.nan), "ok": True}

    def reject(constant):
        raise ValueError(f"strict JSON has no {constant}")

    text = _io.atomic_write_json(tmp_path / "s.json", data).read_text()
    assert json.loads(text, parse_constant=reject) == {"period": None, "d": [None, 1.0], "v": [None, 2.0],
                                                       "e": None, "ok": True}


def test_failed_write_keeps_the_old_file_and_leaves_no_temporary(tmp_path, monkeypatch):
    path = tmp_path / "results.json"
    path.write_text("old")

    def crash(*args, **kwargs):
        raise OSError("disk died mid-rename")

    monkeypatch.setattr(os, "replace", crash)
    with pytest.raises(OSError, match="disk died"):
        _io.atomic_write_text(path, "new")
    assert path.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["results.json"]


def test_unserialisable_value_is_a_type_error(tmp_path):
    with pytest.raises(TypeError, match="object"):
        _io.atomic_write_json(tmp_path / "x.json", {"a": object()})
    assert not (tmp_path / "x.json").exists()


def test_written_files_get_ordinary_permissions(tmp_path):
    mask = os.umask(0o022)
    try:
        path = _io.atomic_write_text(tmp_path / "a.txt", "x")
    finally:
        os.umask(mask)
    assert path.stat().st_mode & 0o777 == 0o644


# ------------------------------------------------------------------ temporary files


def test_a_temporary_file_a_killed_write_left_is_removed_at_the_next_write_of_its_target(tmp_path):
    import subprocess
    import sys

    from collisionkit._io import atomic_write_text

    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    dead_pid = int(dead.stdout)  # a process that has ended
    long_ago = 1_000_000_000
    stale = [tmp_path / f".out.json.{dead_pid}.abcd1234.tmp", tmp_path / ".out.json.k2j4h5g6.tmp"]  # new and old names
    alive = tmp_path / f".out.json.{os.getppid()}.zzzz9999.tmp"  # its writer still runs
    fresh = tmp_path / f".out.json.{dead_pid}.fresh123.tmp"  # newer than this process: not ours to judge
    other = tmp_path / f".other.json.{dead_pid}.abcd1234.tmp"  # another target's
    for path in (*stale, alive, fresh, other):
        path.write_text("half")
    for path in (*stale, alive, other):
        os.utime(path, (long_ago, long_ago))
    atomic_write_text(tmp_path / "out.json", "{}")
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["out.json", alive.name, fresh.name, other.name])


def test_temporary_files_of_a_target_another_process_is_writing_are_left_alone(tmp_path):
    from collisionkit._io import remove_stale_temporaries

    stale = tmp_path / ".run.npz.4194303.abcd1234.tmp"
    stale.write_text("half")
    os.utime(stale, (1_000_000_000, 1_000_000_000))
    with held_by_another_process(HOLD, tmp_path / "run.npz"):
        assert remove_stale_temporaries(tmp_path / "run.npz") == [] and stale.exists()
    assert remove_stale_temporaries(tmp_path / "run.npz") == [stale] and not stale.exists()


def test_an_interrupted_write_leaves_no_temporary_file(tmp_path, monkeypatch):
    from collisionkit._io import write_checkpoint

    path = write_checkpoint(tmp_path / "run.npz", "demo", {}, {"done": 1})

    def interrupted(descriptor):
        raise KeyboardInterrupt

    monkeypatch.setattr(os, "fsync", interrupted)
    with pytest.raises(KeyboardInterrupt):
        write_checkpoint(path, "demo", {}, {"done": 2})
    monkeypatch.undo()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.npz"]  # the old checkpoint, no temporary, no lock
