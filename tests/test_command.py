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
        "error: invalid options: --particles: must be from 2 to 100000000; got 1"]


def test_import_collisionkit_loads_nothing_heavy():
    """The script's first import, collisionkit._command, brings no numpy: the window in which a Ctrl-C could
    interrupt an import outside the script's handler is that of the interpreter's own start."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    source = str(Path(_command.__file__).resolve().parents[1])
    check = "import sys, collisionkit._command; print(sorted({'numpy', 'numba', 'scipy'} & set(sys.modules)))"
    done = subprocess.run([sys.executable, "-c", check], capture_output=True, text=True, timeout=120,
                          env=dict(os.environ, PYTHONPATH=source))
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


def test_a_ctrl_c_while_the_command_line_loads_is_one_line_and_exit_130(monkeypatch, capsys):
    import sys

    class Interrupting:
        def find_spec(self, name, path=None, target=None):
            if name == "collisionkit.cli":
                raise KeyboardInterrupt
            return None

    monkeypatch.delitem(sys.modules, "collisionkit.cli", raising=False)
    monkeypatch.setattr(sys, "meta_path", [Interrupting(), *sys.meta_path])
    try:
        _command.main(["--version"])
    except KeyboardInterrupt:  # caught here: escaping, it would stop the test session
        pytest.fail("the Ctrl-C escaped the script (a traceback)")
    except SystemExit as stop:
        assert stop.code == 130
    else:
        pytest.fail("the script went on after the Ctrl-C")
    assert capsys.readouterr().err == "collisionkit: interrupted while starting\n"


def test_a_real_ctrl_c_during_the_imports_prints_no_traceback():
    """SIGINT sent to ``python -m collisionkit`` as soon as typer has loaded (its -X importtime line), while
    pydantic, numpy, rich and the commands still load (some 0.3 s; after numpy, the last large import, too little
    was left: under load the child could finish before the signal): exit code 130 and one line, no traceback."""
    import os
    import signal
    import subprocess
    import sys
    from pathlib import Path

    source = str(Path(_command.__file__).resolve().parents[1])
    # SIGINT as a terminal gives it: a test run started in the background by a shell without job control inherits
    # it ignored, and so would the child (Python keeps an ignored SIGINT): the child exited 0 in such a CI run
    child = subprocess.Popen([sys.executable, "-X", "importtime", "-m", "collisionkit", "edmd", "--help"],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             env=dict(os.environ, PYTHONPATH=source),
                             preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    lines = []
    for line in child.stderr:
        lines.append(line)
        if line.split("|")[-1].strip() == "typer":
            child.send_signal(signal.SIGINT)
            break
    _, rest = child.communicate(timeout=120)
    said = [line.strip() for line in lines + rest.splitlines() if not line.startswith("import time:")]
    assert child.returncode == 130, (child.returncode, said)
    assert said == ["collisionkit: interrupted while starting"]
