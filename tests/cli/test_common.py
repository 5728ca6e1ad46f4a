"""Options shared by the subcommands: a missing optional package stops a command before it runs."""

from __future__ import annotations

import importlib.util

import pytest
from typer.testing import CliRunner

from collisionkit.cli import app

runner = CliRunner()


@pytest.fixture
def without(monkeypatch):
    """Make the named modules look uninstalled to the commands' checks."""
    real_find_spec = importlib.util.find_spec

    def hide(*names):
        monkeypatch.setattr(importlib.util, "find_spec", lambda name: None if name in names else real_find_spec(name))

    return hide


@pytest.mark.parametrize(
    "arguments, module, extra",
    [
        (["edmd", "--particles", "108", "--plots"], "matplotlib", "plot"),
        (["edmd", "--particles", "108", "--no-plots", "--trajectory", "{tmp}/run.gsd"], "gsd", "io"),
        (["encounter", "--plots"], "matplotlib", "plot"),
        (["demo", "--pairs", "1000", "--plots"], "matplotlib", "plot"),
        (["swarm", "--model", "maxwell", "--E-N", "10", "--out", "{tmp}/plots"], "matplotlib", "plot"),
        (["animate", "--trajectory", "{tmp}/run.gsd"], "gsd", "io"),
    ],
)
def test_a_missing_extra_stops_the_command_before_any_work(arguments, module, extra, without, tmp_path):
    without(module)
    summary = tmp_path / "summary.json"
    arguments = [argument.format(tmp=tmp_path) for argument in arguments] + ["--summary", str(summary)]
    result = runner.invoke(app, arguments, env={"COLUMNS": "200"})
    assert result.exit_code == 2, result.output
    assert f"pip install 'collisionkit[{extra}]'" in result.output and module in result.output
    assert not summary.exists()  # nothing ran
