"""Tests of the locks on output files: a second writer is refused, a killed writer leaves no lock."""

import os

import pytest

from tests._io.processes import HOLD, held_by_another_process


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
