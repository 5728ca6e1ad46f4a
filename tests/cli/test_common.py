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


@pytest.mark.parametrize(
    "arguments",
    [
        ["edmd", "--summary", "{folder}"],
        ["edmd", "--checkpoint", "{folder}"],
        ["edmd", "--xyz", "{folder}"],
        ["edmd", "--summary", "{file}/below-a-file.json"],
        ["edmd", "--out", "{file}"],
        ["slab", "--summary", "{folder}"],
        ["encounter", "--out", "{file}"],
        ["demo", "--pairs", "1000", "--out", "{file}"],
        ["animate", "--out", "{folder}"],
    ],
)
def test_an_output_path_that_cannot_be_written_stops_the_command_before_any_work(arguments, tmp_path):
    folder, file = tmp_path / "a-folder", tmp_path / "a-file"
    folder.mkdir()
    file.write_text("taken")
    arguments = [argument.format(folder=folder, file=file) for argument in arguments]
    result = runner.invoke(app, [*arguments, "--particles", "108"] if arguments[0] == "edmd" else arguments,
                           env={"COLUMNS": "200"})
    assert result.exit_code == 2, result.output
    assert "folder" in result.output or "file" in result.output
    assert file.read_text() == "taken" and not any(folder.iterdir())  # nothing written


def test_config_keys_take_the_command_line_spelling_and_may_not_repeat(tmp_path):
    from collisionkit.cli._common import load_options
    from collisionkit.cli._edmd import EdmdOptions

    config = tmp_path / "run.toml"
    config.write_text("Packing-Fraction = 0.25\n")
    assert load_options(EdmdOptions, config, {}).packing_fraction == 0.25
    config.write_text("packing_fraction = 0.3\npacking-fraction = 0.4\n")
    result = runner.invoke(app, ["edmd", "--config", str(config)], env={"COLUMNS": "200"})
    assert result.exit_code == 2 and "twice" in result.output


@pytest.mark.parametrize(
    "line, option",
    [("seed = true", "seed"), ('packing-fraction = "0.3"', "packing-fraction"), ('plots = "yes"', "plots")],
)
def test_config_values_of_the_wrong_type_are_refused_not_coerced(tmp_path, line, option):
    # pydantic's lax mode took seed = true as seed 1 and plots = "yes" as True
    config = tmp_path / "run.toml"
    config.write_text(line + "\n")
    result = runner.invoke(app, ["edmd", "--config", str(config)], env={"COLUMNS": "200"})
    assert result.exit_code == 2, result.output
    assert option in result.output
