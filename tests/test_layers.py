"""The library stands without its command line and its plots: import contracts and a study with them blocked."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

WITHOUT_THE_EXTRAS = textwrap.dedent(
    """
    import sys
    for name in ("typer", "rich", "pydantic", "matplotlib", "h5py"):
        sys.modules[name] = None  # import of any of them now raises ImportError
    import collisionkit
    from collisionkit import compat, edmd, encounters, kinematics, scattering, sweep, trajectory, transport
    namespace = {}
    exec("from collisionkit import *", namespace)  # every name of __all__, none of them needing an extra
    assert {"edmd", "transport", "encounters", "trajectory", "resolve_contact"} <= set(namespace)
    from concurrent.futures import ThreadPoolExecutor
    study = {"command": "edmd", "seed": 4, "fixed": {"particles": 108, "initial": "fcc", "equilibration": 1000,
             "collisions": 2000, "blocks": 2}, "vary": {"packing-fraction": [0.1, 0.2]}}
    with ThreadPoolExecutor(1) as pool:
        results = sweep.run_study(study, sys.argv[1], executor=pool)
    assert not results.failed, results.failed
    assert [row["packing-fraction"] for row in results.table] == [0.1, 0.2]
    assert all(row["compressibility_factor"] > 1 for row in results.table)
    assert not any(name in sys.modules and sys.modules[name] is not None for name in ("typer", "rich", "pydantic"))
    star = encounters.polytrope_star(1.5, 100, neighbours=10, seed=1)  # stars without h5py: .npz files
    assert len(encounters.read_star(encounters.write_star(star, sys.argv[1] + "-star.npz"))) == 100
    print("ok", len(results.table))
    """
)


def test_the_library_and_a_study_work_without_the_command_line_and_plot_packages(tmp_path):
    environment = os.environ | {"PYTHONPATH": str(ROOT / "src")}
    result = subprocess.run([sys.executable, "-c", WITHOUT_THE_EXTRAS, str(tmp_path / "study")], capture_output=True,
                            text=True, env=environment, timeout=600)
    assert result.returncode == 0, result.stderr
    assert result.stdout.split() == ["ok", "2"]
    assert (tmp_path / "study" / "results.csv").exists() and not (tmp_path / "study" / "main_result.png").exists()


def test_the_import_contracts_hold():
    lint = Path(sys.executable).parent / "lint-imports"
    if not lint.exists():
        pytest.fail("lint-imports (import-linter, in the test extra) is not installed next to this Python")
    result = subprocess.run([str(lint), "--no-cache"], cwd=ROOT, capture_output=True, text=True, timeout=300,
                            env=os.environ | {"PYTHONPATH": str(ROOT / "src")})
    assert result.returncode == 0, result.stdout[-3000:]
    assert "0 broken" in result.stdout


def test_one_domain_does_not_import_the_others():
    """`import collisionkit.edmd` loads the collision core and the EDMD domain only; the other domains and tools load
    on first use through the package's attributes, and a misspelt attribute is still an AttributeError."""
    script = textwrap.dedent(
        """
        import sys
        import collisionkit.edmd
        loaded = {name for name in ("encounters", "transport", "sweep", "compat", "plotting", "scattering")
                  if f"collisionkit.{name}" in sys.modules}
        assert not loaded, loaded
        import collisionkit as ck
        assert ck.transport.simulate_swarm is sys.modules["collisionkit.transport"].simulate_swarm
        assert "encounters" in dir(ck) and "encounters" not in vars(ck)
        try:
            ck.transpot
        except AttributeError as error:
            assert "transpot" in str(error)
        else:
            raise AssertionError("no AttributeError")
        """
    )
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    done = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
