"""``collisionkit edmd --engine auto|lists|cells``: the engine that ran in the summary, refusals before any work."""

from __future__ import annotations

import json
import math
import re
from typing import get_args

import pytest
import typer.main
from typer.testing import CliRunner

from collisionkit.cli import app
from collisionkit.cli._edmd import EngineName
from collisionkit.cli._edmd_report import rows
from collisionkit.edmd._cell_crossings import CELLS_BELOW_PACKING, CELLS_BELOW_PACKING_AT
from collisionkit.edmd._run_checks import ENGINES

runner = CliRunner()

# 64 discs at eta = 0.1 from a square lattice: dilute (auto takes the cells), a fraction of a second
DILUTE = ("--dim", 2, "--particles", 64, "--packing-fraction", 0.1, "--initial", "square", "--equilibration", 200,
          "--collisions", 400, "--blocks", 2, "--seed", 4, "--no-plots")


def invoke(*arguments):
    return runner.invoke(app, ["edmd", *map(str, arguments)])


def said(result) -> str:
    """The output as one line of words, whatever the terminal wrapped."""
    return " ".join(result.output.split())


@pytest.mark.parametrize(("given", "used"), [(("--engine", "lists"), "lists"), (("--engine", "cells"), "cells"),
                                             ((), "cells")])
def test_the_summary_names_the_engine_that_ran(tmp_path, given, used):
    summary = tmp_path / "s.json"
    result = invoke(*DILUTE, *given, "--summary", summary)
    assert result.exit_code == 0, result.output
    data = json.loads(summary.read_text())
    assert data["engine"] == used and data["parameters"]["engine"] == (given[1] if given else "auto")
    table = {quantity: theory for quantity, _, theory in rows(data)}  # the cells, whatever the terminal's width
    assert table["collisions per second"].endswith(f"{used} engine")
    # 64 discs at eta 0.1 over a few blocks leave under 25 pairs near contact: no contact value (JSON's null), said so
    measured = {quantity: value for quantity, value, _ in rows(data)}
    assert data["contact_value"] is None and measured["g(r) at contact"] == "-"
    assert table["g(r) at contact"].startswith("too few pairs near contact")


def test_auto_takes_the_lists_in_a_dense_fluid_and_a_config_file_sets_the_engine(tmp_path):
    dense = [str(value) for value in DILUTE]
    dense[dense.index("--packing-fraction") + 1] = "0.6"  # above CELLS_BELOW_PACKING[2]
    result = invoke(*dense, "--summary", tmp_path / "auto.json")
    assert result.exit_code == 0, result.output
    assert json.loads((tmp_path / "auto.json").read_text())["engine"] == "lists"
    config = tmp_path / "run.toml"
    config.write_text('engine = "cells"\n')
    result = invoke(*dense, "--config", config, "--summary", tmp_path / "cells.json")
    assert result.exit_code == 0, result.output
    assert json.loads((tmp_path / "cells.json").read_text())["engine"] == "cells"


@pytest.mark.parametrize(("arguments", "config", "words"), [
    (("--engine", "cells", "--shear-rate", 0.1), None, "engine cells cannot be combined with shear_rate"),
    (("--shear-rate", 0.1), 'engine = "cells"\n', "engine cells cannot be combined with shear_rate"),
    (("--engine", "bogus"), None, "--engine: Input should be 'auto', 'lists' or 'cells' (got 'bogus')"),
    ((), 'engine = "grid"\n', "--engine: Input should be 'auto', 'lists' or 'cells' (got 'grid')"),
])
def test_a_bad_engine_exits_2_in_one_line_before_any_work(tmp_path, monkeypatch, arguments, config, words):
    from collisionkit import edmd

    monkeypatch.setattr(edmd.EdmdRun, "__init__", lambda *a, **k: pytest.fail("the run was set up"))
    extra = ()
    if config is not None:
        (tmp_path / "run.toml").write_text(config)
        extra = ("--config", tmp_path / "run.toml")
    result = invoke(*DILUTE, *arguments, *extra, "--summary", tmp_path / "s.json")
    assert result.exit_code == 2, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and words in lines[0], result.output
    assert "Traceback" not in result.output and not (tmp_path / "s.json").exists()


def test_a_resumed_run_keeps_its_engine(tmp_path):
    checkpoint, first, again = tmp_path / "c.npz", tmp_path / "first.json", tmp_path / "again.json"
    assert invoke(*DILUTE, "--engine", "lists", "--checkpoint", checkpoint, "--summary", first).exit_code == 0
    refused = invoke("--resume", checkpoint, "--engine", "cells", "--no-plots")
    assert refused.exit_code == 2 and "engine = cells differs from the checkpoint" in said(refused)
    result = invoke("--resume", checkpoint, "--summary", again, "--no-plots")
    assert result.exit_code == 0, result.output
    data = json.loads(again.read_text())
    assert data["engine"] == "lists" and data["parameters"]["engine"] == "lists"
    assert data["compressibility_factor"] == json.loads(first.read_text())["compressibility_factor"]


def test_the_help_gives_the_choices_and_the_real_thresholds_of_auto():
    """The thresholds are the library's, filled in when the help is shown (the command line starts without
    importing collisionkit.edmd and numba)."""
    command = typer.main.get_command(app).commands["edmd"]
    (option,) = [parameter for parameter in command.params if parameter.name == "engine"]
    spheres, discs = CELLS_BELOW_PACKING[3], CELLS_BELOW_PACKING[2]
    first, last = CELLS_BELOW_PACKING_AT[0], CELLS_BELOW_PACKING_AT[-1]
    shown = runner.invoke(app, ["edmd", "--help"], env={"COLUMNS": "200"})
    assert shown.exit_code == 0, shown.output
    help_text = " ".join(re.sub("[│╭╮╰╯─]", " ", shown.output).split())  # rich's frame, at any width
    assert (f"(eta < {spheres[0]:g} spheres, {discs[0]:g} discs up to {first} particles; {spheres[-1]:g} and "
            f"{discs[-1]:g} from {last}), lists otherwise") in help_text
    assert option.metavar == "[auto|lists|cells]"
    assert get_args(EngineName) == ENGINES  # the command's choices are the library's


def _dilute_with(**changes):
    """DILUTE's arguments with some options changed (``packing_fraction=0.2``: --packing-fraction 0.2)."""
    arguments = [str(value) for value in DILUTE]
    for name, value in changes.items():
        arguments[arguments.index("--" + name.replace("_", "-")) + 1] = str(value)
    return arguments


@pytest.mark.parametrize("dim", [2, 3])
def test_auto_takes_the_cells_just_below_the_threshold_and_the_lists_at_it(tmp_path, dim):
    threshold = CELLS_BELOW_PACKING[dim][0]  # a small system's
    lattice = {"dim": dim, "particles": 64, "initial": "square"} if dim == 2 else {
        "dim": dim, "particles": 108, "initial": "fcc"}
    for eta, engine in ((round(threshold - 0.01, 6), "cells"), (threshold, "lists")):
        summary = tmp_path / f"{eta}.json"
        result = invoke(*_dilute_with(**lattice, packing_fraction=eta), "--summary", summary)
        assert result.exit_code == 0, result.output
        assert json.loads(summary.read_text())["engine"] == engine, eta


def test_a_mixture_s_contact_values_with_too_few_pairs_say_so():
    # a mixture of equal diameters keeps its one contact value even when too few pairs make it null; a partial
    # value without enough pairs says why instead of setting the theory beside a dash
    from collisionkit.cli._edmd_report import _partial_contact_rows
    from collisionkit.edmd import EdmdParameters, EdmdRun

    few = EdmdRun(EdmdParameters(dim=2, particles=64, packing_fraction=0.1, fractions=(0.5, 0.5), masses=(1.0, 2.0),
                                 equilibration=200, collisions=400, blocks=2, seed=1)).run().summary()
    assert "contact_value" in few and not math.isfinite(few["contact_value"])
    result = {"contact_values": [[None, 2.0], [2.0, 1.5]], "contact_values_error": [[None, 0.1], [0.1, 0.2]],
              "contact_values_theory": [[1.4, 1.3], [1.3, 1.2]], "theory": "SYH (1990)"}
    rows = {name: (value, beside) for name, value, beside in _partial_contact_rows(result)}
    assert rows["g_AA at contact"] == ("-", "too few pairs near contact")
    assert rows["g_AB at contact"] == ("2 ± 0.1", "1.3 (SYH)")
