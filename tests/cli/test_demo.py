"""Tests of the command line: conventions and the demo."""

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from collisionkit.cli import app

runner = CliRunner()


def test_help_lists_the_demo():
    result = runner.invoke(app, ["--help"])
    assert result.exit_code == 0
    assert "demo" in result.output


def test_demo_writes_summary_table_and_plots(tmp_path):
    out = tmp_path / "demo"
    summary = tmp_path / "summary.json"
    result = runner.invoke(app, ["demo", "--out", str(out), "--pairs", "2000", "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    data = json.loads(summary.read_text())
    core = data["sections"]["collision core"]
    assert core["momentum_relative_error"] < 1e-13
    assert core["energy_relative_error"] < 1e-13
    assert core["inelastic_loss_error"] < 1e-13
    assert core["time_to_contact_far"] == pytest.approx(1e8 - 1, rel=4e-16)
    argon = data["sections"]["Monte Carlo transport"]["argon_50Td"]
    assert argon["two_term_mean_energy"] == pytest.approx(6.221, rel=1e-3)  # solved in the demo (BOLOS: 6.221)
    assert json.loads((out / "summary.json").read_text()) == data
    for name in data["files"]:
        assert Path(name).stat().st_size > 1000
    assert any(name.endswith(".png") for name in data["files"])
    assert "collisionkit demo" in result.output


def test_demo_reads_a_toml_config_and_command_line_wins(tmp_path):
    config = tmp_path / "demo.toml"
    config.write_text(f'out = "{tmp_path / "from_file"}"\npairs = 3000\nplots = false\n')
    result = runner.invoke(app, ["demo", "--config", str(config), "--pairs", "4000"])
    assert result.exit_code == 0, result.output
    data = json.loads((tmp_path / "from_file" / "summary.json").read_text())
    assert data["sections"]["collision core"]["pairs"] == 4000
    assert data["files"] == []


@pytest.mark.parametrize(
    ("toml", "words"),
    [
        ("pears = 10\n", "unknown option 'pears'"),
        ("pairs = 10\n", "pairs"),
        ('pairs = "many"\n', "pairs"),
        ("seed = -1\n", "seed"),
        ("pairs = [\n", "not valid TOML"),
    ],
)
def test_bad_config_exits_with_2_and_says_why(tmp_path, toml, words):
    config = tmp_path / "bad.toml"
    config.write_text(toml)
    result = runner.invoke(app, ["demo", "--config", str(config), "--out", str(tmp_path)])
    assert result.exit_code == 2
    assert words in " ".join(result.output.split())


def test_bad_option_value_exits_with_2(tmp_path):
    result = runner.invoke(app, ["demo", "--pairs", "5", "--out", str(tmp_path)])
    assert result.exit_code == 2
    assert "pairs" in result.output
    result = runner.invoke(app, ["demo", "--config", str(tmp_path / "missing.toml")])
    assert result.exit_code == 2
    assert "not found" in result.output


def test_help_shows_no_docstring_examples():
    # the demo's --help printed its numpydoc Examples (a doctest); the docstring keeps them for the doc tests
    import typer.main

    for name in typer.main.get_command(app).commands:
        result = runner.invoke(app, [name, "--help"], env={"COLUMNS": "200"})
        assert result.exit_code == 0, name
        assert ">>>" not in result.output and "Examples" not in result.output, name
    from collisionkit.cli import demo

    assert "Examples" in demo.__doc__
