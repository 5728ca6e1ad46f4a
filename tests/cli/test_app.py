"""The command line as a whole: --version, seeds said and recorded, frame intervals stated, exit codes documented."""

from __future__ import annotations

import json
import re
from pathlib import Path

import gsd.hoomd
import pytest
from typer.testing import CliRunner

import collisionkit
from collisionkit.cli import app
from collisionkit.cli._messages import BAD_INPUT_EXIT_CODE, INTERRUPTED_EXIT_CODE, OK_EXIT_CODE, RUN_FAILED_EXIT_CODE

runner = CliRunner()
ROOT = Path(__file__).resolve().parents[2]
# 108 spheres: equilibration in chunks of 10000 (the last of 5000), then 4 blocks of 2000
SMALL_EDMD = ["edmd", "--particles", "108", "--equilibration", "25000", "--collisions", "8000", "--blocks", "4",
              "--no-plots"]


def said(text: str) -> str:
    return " ".join(text.split())


def test_version_prints_the_package_version():
    result = runner.invoke(app, ["--version"])
    assert result.exit_code == 0
    assert result.stdout.strip() == f"collisionkit {collisionkit.__version__}"


def test_a_usage_error_is_one_line_naming_the_command_s_help():
    # typer printed a framed panel under the usage line
    result = runner.invoke(app, ["edmd", "--particles", "many"])
    assert result.exit_code == 2
    assert result.output.strip().splitlines() == [
        "error: invalid value for '--particles': Input should be a valid integer, unable to parse string as an "
        "integer (see collisionkit edmd --help)"]
    assert runner.invoke(app, []).exit_code == 2 and "Usage" in runner.invoke(app, []).output  # no command: the help


def test_an_os_error_during_a_run_is_one_line_and_exit_code_1(tmp_path, monkeypatch):
    from collisionkit.edmd import EdmdRun

    def disk_full(run, path=None):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(EdmdRun, "save", disk_full)
    result = runner.invoke(app, [*SMALL_EDMD, "--checkpoint", str(tmp_path / "c.npz")])
    assert result.exit_code == 1, result.output
    assert "error: the run stopped: [Errno 28] No space left on device" in said(result.output)
    assert "Traceback" not in result.output


def test_an_arithmetic_error_no_check_foresaw_is_one_line_and_exit_code_1(tmp_path, monkeypatch):
    import collisionkit.encounters as encounters

    def overflow(parameters):
        raise OverflowError(34, "Numerical result out of range")

    monkeypatch.setattr(encounters, "encounter_summary", overflow)
    result = runner.invoke(app, ["encounter", "--no-plots", "--out", str(tmp_path / "e")])
    assert result.exit_code == RUN_FAILED_EXIT_CODE, result.output
    assert result.output.strip().splitlines() == [said(result.output)]  # one line
    assert said(result.output).startswith(
        "error: the run failed: a number left the floating-point range (OverflowError")
    assert "Traceback" not in result.output


def test_edmd_says_the_seed_it_drew_and_records_it(tmp_path):
    # the default seed was random for edmd and not printed: a run could not be repeated
    summary = tmp_path / "s.json"
    result = runner.invoke(app, [*SMALL_EDMD, "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    seed = json.loads(summary.read_text())["seed"]
    assert f"note: seed {seed} (drawn at random; --seed {seed} repeats this run)" in said(result.stderr)
    repeated = tmp_path / "again.json"
    assert runner.invoke(app, [*SMALL_EDMD, "--seed", str(seed), "--summary", str(repeated)]).exit_code == 0
    assert json.loads(repeated.read_text())["compressibility_factor"] == json.loads(summary.read_text())[
        "compressibility_factor"]


@pytest.mark.parametrize(
    ("arguments", "seed"),
    [
        (["swarm", "--model", "maxwell", "--E-N", "10", "--particles", "640", "--tolerance", "0.05",
          "--collision-budget", "1e5"], 2026),
        (["swarm", "--model", "maxwell", "--E-N", "10", "--particles", "640", "--tolerance", "0.05",
          "--collision-budget", "1e5", "--seed", "7"], 7),
        (["slab", "--particles", "640"], 2026),
        (["slab", "--particles", "640", "--seed", "11"], 11),
        (["demo", "--pairs", "1000", "--no-plots", "--seed", "5"], 5),
    ],
)
def test_every_command_with_randomness_says_its_seed_and_records_it(tmp_path, arguments, seed):
    summary = tmp_path / "s.json"
    extra = ["--out", str(tmp_path / "demo")] if arguments[0] == "demo" else []
    result = runner.invoke(app, [*arguments, *extra, "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    assert f"note: seed {seed} (--seed {seed} repeats this run)" in said(result.stderr)
    assert json.loads(summary.read_text())["seed"] == seed
    assert "seed" not in result.stdout.lower() or arguments[0] == "demo"  # results on stdout, notes on stderr


def test_the_encounter_has_no_randomness_and_says_no_seed(tmp_path):
    result = runner.invoke(app, ["encounter", "--no-plots", "--out", str(tmp_path)])
    assert result.exit_code == 0 and "seed" not in result.output


def test_a_sweep_says_its_root_seed(tmp_path):
    study = tmp_path / "study.toml"
    study.write_text('command = "encounter"\nseed = 42\n[vary]\nvinf = [0.5]\n')
    summary = tmp_path / "s.json"
    result = runner.invoke(app, ["sweep", str(study), "--out", str(tmp_path / "out"), "--workers", "1",
                                 "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    assert "note: seed 42 (the study's root seed" in said(result.stderr)
    assert json.loads(summary.read_text())["seed"] == 42


def _steps(path: Path) -> list[int]:
    with gsd.hoomd.open(str(path), "r") as frames:
        return [int(frame.configuration.step) for frame in frames]


def test_a_frame_interval_the_chunks_cannot_give_is_stated(tmp_path):
    # --frame-every 1000 silently gave a frame every 4000 collisions
    trajectory, summary = tmp_path / "t.gsd", tmp_path / "s.json"
    result = runner.invoke(app, [*SMALL_EDMD, "--seed", "1", "--trajectory", str(trajectory), "--frame-every", "1000",
                                 "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    message = said(result.stderr)
    assert ("note: frames are written only at the ends of equilibration chunks (10000 pair collisions) and "
            "measurement blocks (2000): --frame-every 1000 gives a frame about every 10000 while equilibrating and "
            "every 2000 while measuring") in message
    assert json.loads(summary.read_text())["frame_interval_effective"] == {"equilibration": 10000, "measurement": 2000}
    assert _steps(trajectory) == [0, 10000, 20000, 25000, 27000, 29000, 31000, 33000]


def test_a_frame_interval_the_chunks_give_exactly_needs_no_note(tmp_path):
    trajectory, summary = tmp_path / "t.gsd", tmp_path / "s.json"
    result = runner.invoke(app, ["edmd", "--particles", "108", "--equilibration", "20000", "--collisions", "8000",
                                 "--blocks", "4", "--no-plots", "--seed", "1", "--trajectory", str(trajectory),
                                 "--frame-every", "10000", "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    assert "frames are written only" not in result.output
    assert json.loads(summary.read_text())["frame_interval_effective"] == {"equilibration": 10000,
                                                                           "measurement": 10000}
    assert _steps(trajectory) == [0, 10000, 20000, 28000]  # every 10000, and the last state


def test_the_exit_codes_are_documented_where_users_look():
    codes = {OK_EXIT_CODE: "0", RUN_FAILED_EXIT_CODE: "1", BAD_INPUT_EXIT_CODE: "2", INTERRUPTED_EXIT_CODE: "130"}
    assert codes == {0: "0", 1: "1", 2: "2", 130: "130"}
    for path in (ROOT / "docs" / "cli.rst", ROOT / "README.md"):
        text = said(path.read_text())
        section = text[text.index("Exit codes"):][:600]
        for code, meaning in zip(codes.values(), ("done", "the run failed", "bad input", "interrupted")):
            assert re.search(rf"\b{code}\b\W+{meaning}", section), (path.name, code)
    help_text = said(re.sub("[│╭╮╰╯─]", " ", runner.invoke(app, ["--help"]).output))  # rich's frame, at any width
    assert "Exit codes: 0 done, 1 the run failed" in help_text and "130 interrupted" in help_text
