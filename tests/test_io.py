"""Tests of safe file writing: atomic writes, temporary files, locks, and the checkpoint format."""

import contextlib
import json
import os
import re

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


# ------------------------------------------------------------------ locks: a second writer is refused


@contextlib.contextmanager
def held_by_another_process(code, path):
    """Run ``code`` (which takes a lock on ``path``, given as sys.argv[1]) in another process; yield its process id.

    The process holds what it took until the block ends.
    """
    import subprocess
    import sys
    from pathlib import Path

    source = f"import sys\n{code}\nprint('holding', flush=True)\nsys.stdin.read()\n"
    environment = os.environ | {"PYTHONPATH": str(Path(__file__).resolve().parent.parent / "src")}
    process = subprocess.Popen([sys.executable, "-c", source, str(path)], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True, env=environment)
    try:
        line = process.stdout.readline()
        assert line.strip() == "holding", process.stderr.read()
        yield process.pid
    finally:
        process.stdin.close()
        process.wait(timeout=60)


HOLD = "from collisionkit._io import exclusive\nheld = exclusive(sys.argv[1])\nheld.__enter__()"


def test_a_second_process_writing_a_checkpoint_is_refused_naming_the_file_and_the_writer(tmp_path):
    from collisionkit._io import FileLockedError, exclusive, write_checkpoint

    path = tmp_path / "run.npz"
    with held_by_another_process(HOLD, path) as pid:
        with pytest.raises(FileLockedError) as caught:
            write_checkpoint(path, "demo", {}, {})
        assert str(caught.value) == (f"{path} is being written by another collisionkit process (pid {pid}): wait for "
                                     "it to end or write elsewhere")
        with pytest.raises(FileLockedError), exclusive(path):
            pass
        assert not path.exists()
    with exclusive(path):  # the holder is gone: the lock is free again, and this process may nest it
        write_checkpoint(path, "demo", {}, {})
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.npz"]  # no lock file left


def test_a_killed_writer_leaves_no_lock_behind(tmp_path):
    import signal
    import subprocess
    import sys
    from pathlib import Path

    from collisionkit._io import exclusive

    path = tmp_path / "run.npz"
    source = f"import sys, time\n{HOLD}\nprint('holding', flush=True)\ntime.sleep(600)"
    holder = subprocess.Popen([sys.executable, "-c", source, str(path)], stdout=subprocess.PIPE, text=True,
                              env=os.environ | {"PYTHONPATH": str(Path(__file__).resolve().parent.parent / "src")})
    assert holder.stdout.readline().strip() == "holding"
    holder.send_signal(signal.SIGKILL)
    holder.wait(timeout=60)
    assert (tmp_path / ".run.npz.lock").exists()  # its file stays, its lock died with it
    with exclusive(path):
        pass
    assert not any(tmp_path.iterdir())


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
