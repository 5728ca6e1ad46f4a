"""Tests of ``collisionkit animate``: GIFs from a GSD trajectory and from an encounter, bad input exits 2."""

import json

import pytest
from typer.testing import CliRunner

from collisionkit.cli import app
from collisionkit.edmd import random_fluid
from collisionkit.plotting import ffmpeg_available
from collisionkit.trajectory import GSDWriter

runner = CliRunner()


@pytest.fixture(scope="module")
def trajectory(tmp_path_factory):
    """A tiny 2D EDMD trajectory: 3 frames of 24 discs, two species."""
    path = tmp_path_factory.mktemp("gsd") / "run.gsd"
    system = random_fluid(2, 24, 0.3, seed=4, species=[0, 1] * 12)
    with GSDWriter(path) as writer:
        for step in range(3):
            writer.write(system, step=10 * step)
            system.run(collisions=10)
    return path


def said(result):
    """The command's output with rich's line wrapping undone."""
    return " ".join(result.output.split())


def gif_frames(path):
    from PIL import Image

    with Image.open(path) as image:
        assert image.format == "GIF"
        return image.n_frames


def test_help_lists_animate():
    result = runner.invoke(app, ["--help"])
    assert result.exit_code == 0
    assert "animate" in result.output


@pytest.mark.parametrize("colour", ["speed", "species", "none"])
def test_gif_from_a_gsd_trajectory(tmp_path, trajectory, colour):
    out = tmp_path / "run.gif"
    summary = tmp_path / "summary.json"
    args = ["animate", "--trajectory", str(trajectory), "--out", str(out), "--colour", colour, "--dpi", "30"]
    result = runner.invoke(app, [*args, "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    assert gif_frames(out) == 3
    data = json.loads(summary.read_text())
    assert data["source"] == "trajectory" and data["frames"] == 3 and data["colour"] == colour


def test_every_and_frames_thin_the_trajectory(tmp_path, trajectory):
    out = tmp_path / "thin.gif"
    result = runner.invoke(app, ["animate", "--trajectory", str(trajectory), "--out", str(out), "--every", "2", "--dpi", "30"])
    assert result.exit_code == 0, result.output
    assert gif_frames(out) == 2


def test_gif_from_encounter_options(tmp_path):
    out = tmp_path / "flyby.gif"
    result = runner.invoke(
        app, ["animate", "--m1", "1", "--m2", "0.5", "--rp", "1", "--vinf", "0.5", "--sep0", "10", "--frames", "4",
              "--dpi", "30", "--out", str(out)],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    assert gif_frames(out) == 4


def test_gif_from_the_initial_conditions_and_summary_of_collisionkit_encounter(tmp_path):
    folder = tmp_path / "encounter"
    summary = tmp_path / "encounter.json"
    made = runner.invoke(app, ["encounter", "--m1", "2", "--out", str(folder), "--no-plots", "--summary", str(summary)])
    assert made.exit_code == 0, made.output
    for source in (folder / "initial_conditions.json", summary):
        out = tmp_path / f"{source.stem}.gif"
        args = ["animate", "--initial-conditions", str(source), "--frames", "3", "--colour", "species", "--dpi", "30"]
        result = runner.invoke(app, [*args, "--out", str(out)])
        assert result.exit_code == 0, result.output
        assert gif_frames(out) == 3


def test_config_file_is_read(tmp_path):
    config = tmp_path / "animate.toml"
    out = tmp_path / "from_config.gif"
    config.write_text(f'm1 = 3.0\nframes = 3\ndpi = 30\nout = "{out}"\n')
    result = runner.invoke(app, ["animate", "--config", str(config)])
    assert result.exit_code == 0, result.output
    assert gif_frames(out) == 3


def test_mp4_without_ffmpeg_names_ffmpeg(tmp_path, monkeypatch):
    from matplotlib import animation

    import collisionkit.plotting

    monkeypatch.setattr(collisionkit.plotting, "ffmpeg_available", lambda: False)
    monkeypatch.setattr(animation.writers, "is_available", lambda name: False)
    result = runner.invoke(app, ["animate", "--m1", "1", "--out", str(tmp_path / "flyby.mp4")])
    assert result.exit_code == 2
    assert "ffmpeg" in said(result)
    assert not (tmp_path / "flyby.mp4").exists()


def test_mp4_with_ffmpeg(tmp_path):
    assert ffmpeg_available()  # system ffmpeg, or the binary of the imageio-ffmpeg package
    out = tmp_path / "flyby.mp4"
    result = runner.invoke(app, ["animate", "--m1", "1", "--frames", "4", "--dpi", "40", "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert out.read_bytes()[4:8] == b"ftyp"  # an MP4 container


@pytest.mark.parametrize(
    "args, words",
    [
        ([], "nothing to animate"),
        (["--trajectory", "missing.gsd"], "not found"),
        (["--initial-conditions", "missing.json"], "not found"),
        (["--m1", "1", "--out", "movie.avi"], ".gif or .mp4"),
        (["--m1", "-1"], "m1"),
        (["--m1", "1", "--colour", "red"], "colour"),
        (["--m1", "1", "--fps", "0"], "fps"),
        (["--m1", "1", "--rp", "5", "--sep0", "2"], "sep0"),
        (["--m1", "1", "--unknown-thing", "3"], "unknown-thing"),
    ],
)
def test_bad_input_exits_2_with_a_message(tmp_path, monkeypatch, args, words):
    monkeypatch.chdir(tmp_path)
    result = runner.invoke(app, ["animate", *args])
    assert result.exit_code == 2, result.output
    assert words in said(result)


def test_two_inputs_at_once_is_an_error(tmp_path, trajectory):
    result = runner.invoke(app, ["animate", "--trajectory", str(trajectory), "--m1", "2", "--out", str(tmp_path / "a.gif")])
    assert result.exit_code == 2
    assert "only one input" in said(result)


def test_a_file_that_is_not_gsd_or_json_is_an_input_error(tmp_path):
    junk = tmp_path / "junk.gsd"
    junk.write_text("not a trajectory")
    result = runner.invoke(app, ["animate", "--trajectory", str(junk), "--out", str(tmp_path / "a.gif")])
    assert result.exit_code == 2 and "cannot read" in said(result)
    bad_json = tmp_path / "ic.json"
    bad_json.write_text("{not json")
    result = runner.invoke(app, ["animate", "--initial-conditions", str(bad_json), "--out", str(tmp_path / "b.gif")])
    assert result.exit_code == 2 and "not valid JSON" in said(result)
    bad_json.write_text('{"m1": 1.0}')
    result = runner.invoke(app, ["animate", "--initial-conditions", str(bad_json), "--out", str(tmp_path / "c.gif")])
    assert result.exit_code == 2 and "lacks m2" in said(result)


def test_a_trajectory_of_one_frame_warns_on_stderr(tmp_path):
    # edmd --trajectory without --frame-every writes only the last frame: the GIF was a still, with no word said
    path = tmp_path / "one.gsd"
    with GSDWriter(path) as writer:
        writer.write(random_fluid(2, 24, 0.3, seed=4), step=0)
    result = runner.invoke(app, ["animate", "--trajectory", str(path), "--out", str(tmp_path / "one.gif"), "--dpi", "30"],
                           env={"COLUMNS": "400"})
    assert result.exit_code == 0, result.output
    warning = " ".join(result.stderr.split())
    assert f"warning: {path} holds a single frame" in warning and "edmd --trajectory FILE.gsd --frame-every N" in warning
    assert "(1 frame)" in result.stdout


def test_a_trajectory_of_several_frames_does_not_warn(tmp_path, trajectory):
    result = runner.invoke(app, ["animate", "--trajectory", str(trajectory), "--out", str(tmp_path / "a.gif"), "--dpi", "30"])
    assert result.exit_code == 0, result.output
    assert "warning" not in result.output
