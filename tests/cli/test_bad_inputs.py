"""No traceback for any input a user can type: every row of tests/cli/bad_inputs.py is one line and exit code 2."""

from __future__ import annotations

import re

import pytest
import typer.main
from typer.testing import CliRunner

from collisionkit.cli import app
from tests.cli.bad_inputs import BAD_INPUTS, ROOT

runner = CliRunner()

STUDY = 'command = "encounter"\nseed = 1\n[vary]\nvinf = [0.5, 1.0]\n'


def _row_id(row) -> str:
    command, arguments, _ = row
    return " ".join([command or "collisionkit", *arguments])


def _places(tmp_path):
    folder, file, study = tmp_path / "a-folder", tmp_path / "a-file", tmp_path / "study.toml"
    folder.mkdir()
    file.write_text("taken")
    study.write_text(STUDY)
    return {"dir": folder, "file": file, "missing": tmp_path / "nothing-here", "new": tmp_path / "new-folder",
            "study": study}


@pytest.mark.parametrize("row", BAD_INPUTS, ids=_row_id)
def test_a_bad_input_is_one_line_and_exit_code_2(tmp_path, monkeypatch, row):
    command, arguments, words = row
    monkeypatch.chdir(tmp_path)  # default output folders land here, if any were made
    places = _places(tmp_path)
    arguments = [argument.format(**places) for argument in arguments]
    result = runner.invoke(app, [command, *arguments] if command else arguments)
    assert result.exit_code == 2, result.output
    assert isinstance(result.exception, SystemExit) and "Traceback" not in result.output, repr(result.exception)
    lines = result.output.strip().splitlines()
    assert len(lines) == 1, result.output  # one line whatever the terminal's width
    assert lines[0].startswith("error: ") and words in lines[0], lines[0]
    assert sorted(path.name for path in tmp_path.iterdir()) == ["a-file", "a-folder", "study.toml"]  # nothing ran
    assert places["file"].read_text() == "taken"


def _options(command) -> dict[str, list[str]]:
    """A click command's parameters: {name: the spellings a user types (options) or [] (an argument)}."""
    spelled = {}
    for parameter in command.params:
        spelled[parameter.name] = [*parameter.opts, *parameter.secondary_opts] if parameter.param_type_name == "option" \
            else []
    return spelled


def test_the_table_names_every_option_of_every_command():
    group = typer.main.get_command(app)
    commands = {ROOT: group} | dict(group.commands)
    assert set(commands) == {ROOT} | {command for command, _, _ in BAD_INPUTS if command}, "a command without rows"
    missing = []
    for name, command in commands.items():
        rows = [arguments for row_command, arguments, _ in BAD_INPUTS if row_command == name]
        typed = {re.sub("=.*", "", argument) for arguments in rows for argument in arguments}
        for parameter, spellings in _options(command).items():
            if spellings and not typed & set(spellings):
                missing.append(f"{name or 'collisionkit'} {spellings[0]}")
            if not spellings and not any(arguments and not arguments[0].startswith("-") for arguments in rows):
                missing.append(f"{name} {parameter.upper()} (an argument)")
    assert not missing, f"add a row to tests/cli/bad_inputs.py for: {', '.join(missing)}"
