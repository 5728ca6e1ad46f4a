"""Tests of atomic file writing."""

import json
import os

import numpy as np
import pytest

from collisionkit import _io


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


# ------------------------------------------------------------------ the one checkpoint format


def test_a_checkpoint_round_trips_parameters_state_and_arrays_exactly(tmp_path):
    import math

    from collisionkit._io import CHECKPOINT_VERSION, read_checkpoint, write_checkpoint

    arrays = {"x": np.random.default_rng(1).normal(size=(5, 3)), "n": np.arange(4, dtype=np.int64)}
    path = write_checkpoint(tmp_path / "run.npz", "demo", {"eta": 0.3, "inf": math.inf}, {"done": 2}, arrays)
    saved = read_checkpoint(path, "demo")
    assert saved.kind == "demo" and saved.parameters == {"eta": 0.3, "inf": None} and saved.state == {"done": 2}
    assert all(np.array_equal(saved.arrays[name], value) for name, value in arrays.items())
    assert CHECKPOINT_VERSION == 1


def test_a_checkpoint_of_another_kind_version_or_file_is_refused_by_name(tmp_path):
    import json
    import zipfile

    from collisionkit._io import CheckpointError, read_checkpoint, write_checkpoint

    path = write_checkpoint(tmp_path / "run.npz", "swarm", {}, {})
    with pytest.raises(CheckpointError, match="not a checkpoint of 'collisionkit edmd'"):
        read_checkpoint(path, "edmd")
    with zipfile.ZipFile(path) as archive:  # a later version: refused, not misread
        header = json.loads(str(np.load(archive.open("checkpoint_header.npy"))))
    np.savez(tmp_path / "later.npz", checkpoint_header=np.asarray(json.dumps(header | {"version": 99})))
    with pytest.raises(CheckpointError, match="version 99"):
        read_checkpoint(tmp_path / "later.npz", "swarm")
    with pytest.raises(CheckpointError, match="is a folder"):
        read_checkpoint(tmp_path, "swarm")
    with pytest.raises(ValueError, match="must not use the name"):
        write_checkpoint(tmp_path / "x.npz", "swarm", {}, {}, {"checkpoint_header": np.zeros(1)})
