"""The ``collisionkit`` script: it names the extra to install when the command line's packages are missing."""

from __future__ import annotations

import importlib.util

import pytest

from collisionkit import _command


def test_missing_command_line_packages_are_named_with_the_extra(monkeypatch, capsys):
    real_find_spec = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name: None if name == "typer" else real_find_spec(name))
    with pytest.raises(SystemExit) as stop:
        _command.main(["--help"])
    assert stop.value.code == 2
    message = capsys.readouterr().err
    assert "typer" in message and "pip install 'collisionkit[cli]'" in message
    assert "rich" not in message  # only what is missing


def test_with_the_packages_the_script_runs_the_command_line(capsys):
    with pytest.raises(SystemExit) as stop:
        _command.main(["--help"])
    assert stop.value.code == 0
    assert "edmd" in capsys.readouterr().out


def test_the_script_prints_its_version(capsys):
    import collisionkit

    with pytest.raises(SystemExit) as stop:
        _command.main(["--version"])
    assert stop.value.code == 0
    assert capsys.readouterr().out.strip() == f"collisionkit {collisionkit.__version__}"


def test_the_script_says_a_usage_error_in_one_line(capsys):
    with pytest.raises(SystemExit) as stop:
        _command.main(["edmd", "--particle", "5"])
    assert stop.value.code == 2
    error = capsys.readouterr().err
    assert error.strip().splitlines() == ["error: no such option: --particle (Possible options: --particles) "
                                          "(see collisionkit edmd --help)"]


def test_python_m_collisionkit_runs_the_same_command_line():
    import os
    import subprocess
    import sys
    from pathlib import Path

    source = str(Path(_command.__file__).resolve().parents[1])
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [source, os.environ.get("PYTHONPATH")])))
    done = subprocess.run([sys.executable, "-m", "collisionkit", "edmd", "--particles", "1"],
                          capture_output=True, text=True, env=env, timeout=120)
    assert done.returncode == 2
    assert "Traceback" not in done.stderr
    assert done.stderr.strip().splitlines() == [
        "error: invalid options: particles: Input should be greater than or equal to 2 (got 1)"]
