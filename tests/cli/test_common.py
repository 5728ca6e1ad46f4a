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
        (["star", "--polytrope", "1.5", "--out", "{tmp}/star.hdf5"], "h5py", "stars"),
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
    ("arguments", "reason"),
    [
        (["edmd", "--summary", "{folder}"], "is a folder: give a file name"),
        (["edmd", "--checkpoint", "{folder}"], "is a folder: give a file name"),
        (["edmd", "--xyz", "{folder}/../frames.xyz"], None),
        (["edmd", "--summary", "{file}/below-a-file.json"], "a-file is a file, not a folder"),
        (["edmd", "--out", "{file}"], "a-file is a file, not a folder"),
        (["slab", "--summary", "{folder}"], "is a folder: give a file name"),
        (["encounter", "--out", "{file}"], "a-file is a file, not a folder"),
        (["demo", "--pairs", "1000", "--out", "{file}"], "a-file is a file, not a folder"),
        (["animate", "--out", "{folder}"], None),
    ],
)
def test_an_output_path_that_cannot_be_written_stops_the_command_before_any_work(arguments, reason, tmp_path):
    folder, file = tmp_path / "a-place", tmp_path / "a-file"
    folder.mkdir()
    (tmp_path / "frames.xyz").mkdir()  # a folder where --xyz would write its file
    file.write_text("taken")
    arguments = [argument.format(folder=folder, file=file) for argument in arguments]
    result = runner.invoke(app, [*arguments, "--particles", "108"] if arguments[0] == "edmd" else arguments,
                           env={"COLUMNS": "200"})
    assert result.exit_code == 2, result.output
    said = " ".join(result.output.split())
    assert (reason or "is a folder") in said, said
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


def test_a_config_file_that_is_not_utf8_is_one_line_naming_the_file(tmp_path):
    config = tmp_path / "latin1.toml"
    config.write_bytes("particles = 108\n# café\n".encode("latin-1"))  # tomllib raised UnicodeDecodeError
    result = runner.invoke(app, ["edmd", "--config", str(config)])
    said = "".join(result.output.split())  # rich wraps, and may fold a long path
    assert result.exit_code == 2 and "".join(f"config file {config} is not UTF-8 text".split()) in said, said
    assert "Traceback" not in said


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


def test_an_unknown_config_key_comes_with_the_closest_names_and_the_valid_ones(tmp_path):
    config = tmp_path / "run.toml"
    config.write_text("particle = 100\n")
    result = runner.invoke(app, ["edmd", "--config", str(config)], env={"COLUMNS": "400"})
    assert result.exit_code == 2, result.output
    said = " ".join(result.output.split())
    assert "unknown option 'particle'; did you mean 'particles'?" in said
    assert "packing-fraction" in said and "frame-every" in said  # the valid options, spelled as on the command line


@pytest.mark.parametrize(
    ("arguments", "config", "sentence"),
    [
        (["swarm", "--model", "reid", "--cross-sections", "{tmp}/x.txt"], None,
         "error: invalid options: give exactly one of model, gas and cross_sections (--model, --gas, --cross-sections)"),
        (["edmd"], 'plots = "no"\n', "error: invalid options: --plots must be true or false, not 'no'"),
        (["encounter"], "no-plots = true\n",
         "error: invalid options: unknown option 'no-plots'; did you mean 'plots = false'? (options: layout, m1, m2, "
         "out, overwrite, plots, radius1, radius2, rp, sep0, star1, star2, summary, units, vinf)"),
        (["swarm", "--model", "reid", "--E-N=-1"], None,
         "error: invalid options: --E-N: every E/N must be a finite number from 0 to 1e+06 Td (got [-1.0])"),
    ],
)
def test_a_broken_rule_is_one_clean_sentence(tmp_path, arguments, config, sentence):
    # no pydantic "Value error, " prefix and no dump of every option
    if config is not None:
        (tmp_path / "run.toml").write_text(config)
        arguments = [*arguments, "--config", str(tmp_path / "run.toml")]
    result = runner.invoke(app, [argument.format(tmp=tmp_path) for argument in arguments], env={"COLUMNS": "400"})
    assert result.exit_code == 2, result.output
    assert result.output.strip() == sentence


def test_warnings_go_to_stderr_so_stdout_keeps_only_the_results(tmp_path):
    # swarm, encounter and edmd printed their warnings on stdout (animate on stderr)
    result = runner.invoke(app, ["swarm", "--model", "maxwell", "--E-N", "1", "--particles", "500",
                                 "--collision-budget", "1e5"], env={"COLUMNS": "200"})
    assert result.exit_code == 0, result.output
    assert "warning:" in result.stderr and "warning:" not in result.stdout
    assert "mean energy" in result.stdout


def test_messages_are_one_line_at_any_terminal_width(tmp_path):
    # rich wrapped messages at the terminal's width: a test looking for a sentence passed only with COLUMNS=200
    import os
    import subprocess
    import sys

    missing = tmp_path / ("a-long-folder-name-" * 4) / "missing.npz"
    for columns in ("40", "80", "200"):
        result = subprocess.run([sys.executable, "-c", "from collisionkit._command import main; main()", "edmd",
                                 "--resume", str(missing)],
                                capture_output=True, text=True, timeout=120,
                                env=os.environ | {"COLUMNS": columns, "LANG": "C", "LC_ALL": "C"})
        assert result.returncode == 2, result.stderr
        lines = [line for line in result.stderr.splitlines() if line.strip()]
        assert len(lines) == 1 and str(missing) in lines[0], (columns, result.stderr)


def test_messages_print_colon_words_as_written_not_as_emoji(capsys):
    # "--gas Ar:x:0.5" came out with an emoji where ":x:" stood
    from collisionkit.cli import _messages

    _messages.error("bad --gas Ar:x:0.5 (a :smile: path)")
    assert "Ar:x:0.5 (a :smile: path)" in " ".join(capsys.readouterr().err.split())


BOLTZMANN_HEADERS = ("E/N (Td)", "<e> (eV)", "W (m/s)", "N D (1/m/s)", "D/mu (eV)", "alpha/N (m^2)", "eta/N (m^2)")
BOLTZMANN_ROWS = [("10", "0.24695", "64496", "1.3426e+24", "0.2082", "0", "0"),
                  ("1000", "5.0213", "1.4348e+05", "8.9198e+23", "6.217", "1.2345e-22", "0")]
SWARM_HEADERS = ("E/N (Td)", "mean energy (eV)", "bulk W (m/s)", "N D_L (1/m/s)", "N D_T (1/m/s)")
SWARM_ROWS = [("12", "0.95123 ± 0.0021", "-6.1541e+04 ± 1.2e+02", "5.8213e+23 ± 3.1e+21", "1.0312e+24 ± 4.4e+21")]


def _printed_table(monkeypatch, capsys, width, headers, rows):
    from collisionkit.cli import _common, _messages

    monkeypatch.setattr(_messages.console, "width", width)
    _common.print_table("results", headers, rows)
    return capsys.readouterr().out


@pytest.mark.parametrize("width", [30, 45, 60, 80, 200])
@pytest.mark.parametrize(("headers", "rows"), [(BOLTZMANN_HEADERS, BOLTZMANN_ROWS), (SWARM_HEADERS, SWARM_ROWS)])
def test_a_table_never_drops_a_character_of_a_cell_at_any_width(monkeypatch, capsys, width, headers, rows):
    # with stdout redirected or COLUMNS=80/60, rich cut cells short: "6.1541e…"
    from collections import Counter

    printed = _printed_table(monkeypatch, capsys, width, headers, rows)
    assert "…" not in printed
    shown = Counter(printed.replace(" ", "").replace("\n", ""))
    wanted = Counter("".join([*headers, *(cell for row in rows for cell in row)]).replace(" ", ""))
    assert not wanted - shown, (width, printed)  # every character of every cell and header, folded or not
    assert max(len(line) for line in printed.splitlines()) <= width


@pytest.mark.parametrize("width", [60, 80])
def test_a_narrow_table_keeps_every_number_whole_on_one_line(monkeypatch, capsys, width):
    printed = _printed_table(monkeypatch, capsys, width, BOLTZMANN_HEADERS, BOLTZMANN_ROWS)
    for row in BOLTZMANN_ROWS:
        for cell in row:
            assert cell in printed, (cell, printed)


def test_a_reader_that_goes_away_stops_the_output_not_the_work(tmp_path):
    """``collisionkit encounter ... | head -1``: rich ended the process with exit code 1 at the first line after the
    reader left, before the summary was written; now the rest of the output goes nowhere and the files are written."""
    import os
    import subprocess
    import sys

    summary = tmp_path / "s.json"
    command = [sys.executable, "-c", "from collisionkit._command import main; main()", "encounter", "--summary",
               str(summary), "--out", str(tmp_path / "out")]
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                               env=os.environ | {"COLUMNS": "80"})
    process.stdout.readline()
    process.stdout.close()  # as head does after its lines
    assert process.wait(timeout=300) == 0
    assert summary.stat().st_size > 100
