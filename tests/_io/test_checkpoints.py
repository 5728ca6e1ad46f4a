"""Tests of the checkpoint format: exact round trips, refusals by name, damaged files in one line."""

import json
import re

import numpy as np
import pytest


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


# ------------------------------------------------------------------ damaged checkpoints: one line, never a traceback


def _real_checkpoint(path):
    from collisionkit._io import write_checkpoint

    arrays = {"x": np.linspace(0.0, 1.0, 4000), "n": np.arange(100, dtype=np.int64)}
    return write_checkpoint(path, "demo", {"eta": 0.3}, {"done": 2}, arrays)


def _flip_bytes_inside(path, array):
    """Damage the stored data of ``array`` (its CRC no longer matches)."""
    import zipfile

    with zipfile.ZipFile(path) as archive:
        member = archive.getinfo(f"{array}.npy")
    data = bytearray(path.read_bytes())
    start = member.header_offset + 30 + len(member.filename) + len(member.extra) + 200  # inside the array's bytes
    data[start : start + 8] = bytes(255 - b for b in data[start : start + 8])
    path.write_bytes(bytes(data))


def _rewrite(path, header=None, arrays=None, drop=()):
    """The checkpoint with its header or arrays replaced (as a crafted file would be)."""
    import io as _bytes
    import zipfile

    members = {}
    with zipfile.ZipFile(path) as archive:
        for name in archive.namelist():
            members[name[:-4]] = np.load(_bytes.BytesIO(archive.read(name)), allow_pickle=True)
    if header is not None:
        members["checkpoint_header"] = np.asarray(json.dumps(header))
    members.update(arrays or {})
    for name in drop:
        members.pop(name)
    np.savez(path, **members)


HEADER = {"format": "collisionkit checkpoint", "version": 1, "kind": "demo", "parameters": {}, "state": {}}


@pytest.mark.parametrize(
    ("damage", "words"),
    [
        (lambda path: _flip_bytes_inside(path, "x"), "array 'x' cannot be read (Bad CRC-32"),
        (lambda path: path.write_bytes(path.read_bytes()[: len(path.read_bytes()) // 2]), "cut short"),
        (lambda path: path.write_bytes(path.read_bytes()[:-30]), "cut short"),
        (lambda path: _rewrite(path, drop=["checkpoint_header"]), "no 'collisionkit checkpoint' header"),
        (lambda path: _rewrite(path, arrays={"checkpoint_header": np.arange(3)}), "no 'collisionkit checkpoint'"),
        (lambda path: _rewrite(path, arrays={"checkpoint_header": np.asarray("{not json")}), "header is not JSON"),
        (lambda path: _rewrite(path, header=HEADER | {"parameters": [1, 2]}), "header's 'parameters' is list"),
        (lambda path: _rewrite(path, header=HEADER | {"state": "done"}), "header's 'state' is str"),
        (lambda path: _rewrite(path, header=HEADER | {"version": "1"}), "version '1'"),
        (lambda path: _rewrite(path, arrays={"x": np.array([object()], dtype=object)}), "array 'x' cannot be read"),
    ],
    ids=["bad CRC", "truncated", "truncated end", "no header", "header of numbers", "header not JSON",
         "parameters a list", "state a string", "version a string", "a pickled array"],
)
def test_a_damaged_checkpoint_is_a_one_line_checkpoint_error_naming_the_file(tmp_path, damage, words):
    # a bad CRC, a truncated file or a header of the wrong types gave a traceback of zipfile, numpy or dict()
    from collisionkit._io import CheckpointError, read_checkpoint

    path = _real_checkpoint(tmp_path / "run.npz")
    damage(path)
    with pytest.raises(CheckpointError) as caught:
        read_checkpoint(path, "demo")
    message = str(caught.value)
    assert message.startswith(str(path)) and words in message and "\n" not in message, message


def test_a_missing_array_is_the_reader_s_to_name_and_a_member_that_is_no_array_is_refused(tmp_path):
    import zipfile

    from collisionkit._io import CheckpointError, read_checkpoint

    path = _real_checkpoint(tmp_path / "run.npz")
    _rewrite(path, drop=["x"])
    assert sorted(read_checkpoint(path, "demo").arrays) == ["n"]  # the run that needs "x" names it (its own test)
    with zipfile.ZipFile(path, "a") as archive:
        archive.writestr("notes.txt", "hello")
    with pytest.raises(CheckpointError, match="holds 'notes.txt', which is no numpy array"):
        read_checkpoint(path, "demo")


def test_the_state_entries_of_a_checkpoint_are_read_with_their_types_checked(tmp_path):
    from collisionkit._io import CheckpointError, read_checkpoint, write_checkpoint

    path = write_checkpoint(tmp_path / "run.npz", "demo", {}, {"done": 2, "energy": 1.5, "name": "x", "nan": None})
    saved = read_checkpoint(path, "demo")
    assert saved.entry("done", "integer", 0, 5) == 2 and saved.entry("energy", "number", 0.0) == 1.5
    assert saved.entry("name", "text") == "x" and saved.entry("missing", "mapping", optional=True) is None
    for name, kind, words in [("done", "integer", "must be an integer in [3, 5]; got 2"),
                              ("name", "number", "must be a number >= 3; got 'x'"),
                              ("nan", "number", "must be a number >= 3; got None"),
                              ("energy", "text", "must be a text; got 1.5")]:
        with pytest.raises(CheckpointError, match=re.escape(f"is a damaged demo checkpoint: state '{name}' {words}")):
            saved.entry(name, kind, 3, 5 if kind == "integer" else float("inf"))
