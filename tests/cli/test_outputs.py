"""The commands' output files: checked before the work, never lost after it, never replaced unasked (issue 16)."""

from __future__ import annotations

import errno
import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from collisionkit._io import read_checkpoint, write_checkpoint
from collisionkit.cli import _files, app
from collisionkit.trajectory import read_gsd

runner = CliRunner()

EDMD = ["edmd", "--dim", "2", "--particles", "64", "--initial", "square", "--equilibration", "0", "--collisions", "400",
        "--blocks", "2", "--seed", "1", "--no-plots"]
SWARM = ["swarm", "--model", "maxwell", "--E-N", "10", "--particles", "640", "--tolerance", "0.05",
         "--collision-budget", "1e5"]
SLAB = ["slab", "--particles", "640", "--seed", "3"]
ENCOUNTER = ["encounter", "--no-plots"]
NOWHERE = Path("/proc/collisionkit-cannot-write-here")  # root may write anywhere, says os.access, but not in /proc
linux_proc = pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs Linux's /proc")


def said(result) -> str:
    return " ".join(result.output.split())


def invoke(arguments):
    return runner.invoke(app, [str(argument) for argument in arguments])


# ------------------------------------------------------------------ item 1: checked before the work


@linux_proc
@pytest.mark.parametrize(
    "arguments",
    [
        [*EDMD, "--out", NOWHERE / "plots", "--plots"],
        [*EDMD, "--summary", NOWHERE / "s.json"],
        [*EDMD, "--xyz", NOWHERE / "final.xyz"],
        [*EDMD, "--trajectory", NOWHERE / "run.gsd"],
        [*EDMD, "--checkpoint", NOWHERE / "run.npz"],
        [*SWARM, "--out", NOWHERE],
        [*SWARM, "--checkpoint", NOWHERE / "scan.npz"],
        [*SLAB, "--summary", NOWHERE / "s.json"],
        [*ENCOUNTER, "--out", NOWHERE],
        ["demo", "--pairs", "1000", "--no-plots", "--out", NOWHERE],
        ["animate", "--m1", "1", "--out", NOWHERE / "a.gif"],
        ["sweep", "{study}", "--out", NOWHERE],
    ],
)
def test_an_output_in_an_unwritable_place_is_refused_before_any_work(tmp_path, monkeypatch, arguments):
    # edmd --out /proc/ckout computed everything, then printed a traceback and wrote nothing
    monkeypatch.chdir(tmp_path)
    study = tmp_path / "study.toml"
    study.write_text('command = "encounter"\nseed = 1\n[vary]\nvinf = [0.5]\n')
    result = invoke([str(argument).format(study=study) for argument in arguments])
    assert result.exit_code == 2, result.output
    assert "cannot be written: nothing can be written in /proc" in said(result)
    assert sorted(path.name for path in tmp_path.iterdir()) == ["study.toml"]  # nothing ran


@linux_proc
def test_a_folder_nothing_is_written_to_is_not_checked(tmp_path):
    result = invoke([*EDMD, "--out", NOWHERE, "--summary", tmp_path / "s.json"])  # --no-plots: no plots, no folder
    assert result.exit_code == 0, result.output


def test_the_probe_leaves_nothing_behind(tmp_path):
    _files.check_output_file(tmp_path / "s.json", "--summary")
    _files.check_output_folder(tmp_path / "new" / "plots", "--out")
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------------ item 1: results never lost after it


def _rescued(folder: Path, command: str) -> dict:
    (path,) = folder.glob(f"collisionkit-{command}-results-*.json")
    return json.loads(path.read_text())


def _disk_full(*args, **kwargs):
    raise OSError(errno.ENOSPC, "No space left on device", "the-disk")


def test_an_edmd_file_that_fails_at_the_end_leaves_the_results_in_a_rescue_file(tmp_path, monkeypatch):
    from collisionkit.edmd import EdmdRun

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(EdmdRun, "write_xyz", _disk_full)
    result = invoke([*EDMD, "--xyz", tmp_path / "final.xyz", "--summary", tmp_path / "s.json"])
    assert result.exit_code == 1, result.output
    message = said(result)
    assert "the work is done, but writing failed: --xyz" in message and "No space left on device" in message
    rescued = _rescued(tmp_path, "edmd")
    assert f"the results are saved in {tmp_path}" in message
    assert rescued["collisions"] == 400 and rescued["seed"] == 1 and "compressibility_factor" in rescued
    assert json.loads((tmp_path / "s.json").read_text()) == rescued  # the summary itself was written too
    assert "Traceback" not in result.output


def test_a_summary_that_cannot_be_written_at_the_end_is_rescued(tmp_path, monkeypatch):
    real = _files.atomic_write_json
    summary = tmp_path / "gone" / "s.json"

    def fails_for_the_summary(path, data):
        if Path(path) == summary:
            raise PermissionError(errno.EACCES, "Permission denied", str(summary))
        return real(path, data)

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(_files, "atomic_write_json", fails_for_the_summary)
    for command, arguments in (("slab", SLAB), ("swarm", SWARM)):
        result = invoke([*arguments, "--summary", summary])
        assert result.exit_code == 1, result.output
        assert f"the summary {summary} (Permission denied" in said(result)
        rescued = _rescued(tmp_path, command)
        assert rescued["seed"] == (3 if command == "slab" else 2026)
        assert ("transmission" if command == "slab" else "mean_energy") in rescued


def test_a_plot_that_fails_keeps_the_swarm_table_and_results(tmp_path, monkeypatch):
    # swarm printed its table, then a traceback
    import collisionkit.plotting

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(collisionkit.plotting, "save", _disk_full)
    result = invoke([*SWARM, "--out", tmp_path / "plots"])
    assert result.exit_code == 1, result.output
    # the table's title: its eight column headers wrap at the runner's 80 columns, the title does not
    assert "swarm transport" in result.stdout and "the plot" in said(result) and "eedf.png" in said(result)
    assert (tmp_path / "plots" / "swarm.csv").exists()  # the files that could be written are
    rescued = _rescued(tmp_path, "swarm")
    assert rescued["files"] == [str(tmp_path / "plots" / name) for name in ("swarm.csv", "bolsig.dat")]


def test_when_no_folder_takes_the_rescue_file_the_results_are_printed(tmp_path, monkeypatch):
    monkeypatch.setattr(_files, "_rescue_folders", lambda: iter([tmp_path / "missing"]))
    monkeypatch.setattr(_files, "atomic_write_json", _disk_full)
    result = invoke([*SLAB, "--summary", tmp_path / "s.json"])
    assert result.exit_code == 1
    printed = result.stdout[result.stdout.index("{"):]
    assert json.loads(printed)["parameters"]["seed"] == 3
    assert "nowhere could take them, so they are printed above" in said(result)


def test_an_animation_that_cannot_be_written_goes_to_a_rescue_file(tmp_path, monkeypatch):
    import collisionkit.plotting

    real = collisionkit.plotting.save_animation
    target = tmp_path / "movie.gif"

    def fails_at_the_target(animation, path, **options):
        if Path(path) == target:
            raise OSError(errno.EIO, "Input/output error", str(path))
        return real(animation, path, **options)

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(collisionkit.plotting, "save_animation", fails_at_the_target)
    result = invoke(["animate", "--m1", "1", "--frames", "3", "--dpi", "20", "--out", target])
    assert result.exit_code == 1, result.output
    (gif,) = tmp_path.glob("collisionkit-animate-results-*.gif")
    assert gif.stat().st_size > 0 and f"saving the animation in {gif}" in said(result)
    assert _rescued(tmp_path, "animate")["out"] == str(gif)


# ------------------------------------------------------------------ item 2: nothing replaced unasked


@pytest.mark.parametrize(
    ("first", "second", "name"),
    [("--summary", "--checkpoint", "run.npz"), ("--summary", "--trajectory", "run.gsd"), ("--summary", "--xyz", "a.xyz"),
     ("--checkpoint", "--trajectory", "run.gsd"), ("--checkpoint", "--xyz", "a.xyz")],
)
def test_two_outputs_naming_one_file_are_refused_before_any_work(tmp_path, first, second, name):
    # --summary x --checkpoint x was accepted: the checkpoint was replaced by the JSON
    result = invoke([*EDMD, first, tmp_path / name, second, tmp_path / "." / name])
    assert result.exit_code == 2, result.output
    message = said(result)
    assert "name the same file" in message and f"{first} " in message and f"{second} " in message
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("arguments", "option", "name"),
    [
        (EDMD, "--summary", "s.json"),
        (EDMD, "--trajectory", "run.gsd"),
        (EDMD, "--xyz", "final.xyz"),
        (EDMD, "--checkpoint", "run.npz"),
        (SWARM, "--summary", "s.json"),
        (SWARM, "--checkpoint", "scan.npz"),
        (SLAB, "--summary", "s.json"),
        (ENCOUNTER, "--summary", "s.json"),
        (["demo", "--pairs", "1000", "--no-plots"], "--summary", "s.json"),
        (["animate", "--m1", "1", "--frames", "3", "--dpi", "20"], "--out", "a.gif"),
        (["animate", "--m1", "1", "--frames", "3", "--dpi", "20"], "--summary", "s.json"),
    ],
)
def test_an_existing_file_is_replaced_only_with_overwrite(tmp_path, monkeypatch, arguments, option, name):
    # --trajectory existing.gsd silently replaced a trajectory
    monkeypatch.chdir(tmp_path)
    existing = tmp_path / name
    existing.write_text("a user's own file")
    refused = invoke([*arguments, option, existing])
    assert refused.exit_code == 2, refused.output
    assert "exists" in said(refused) and (option == "--checkpoint" or "pass --overwrite" in said(refused))
    assert existing.read_text() == "a user's own file"
    replaced = invoke([*arguments, option, existing, "--overwrite"])
    assert replaced.exit_code == 0, replaced.output
    assert existing.read_bytes() != b"a user's own file"


def test_an_earlier_run_s_files_in_an_out_folder_are_replaced_only_with_overwrite(tmp_path):
    # a new user's report: a second encounter into one --out replaced its files unasked and kept an earlier run's
    # initial_conditions.hdf5 (particle stars), which contradicted the new initial conditions
    flyby = tmp_path / "flyby"
    assert invoke(["encounter", "--out", flyby]).exit_code == 0
    (flyby / "initial_conditions.hdf5").write_bytes(b"an earlier run's stars")
    (flyby / "notes.txt").write_text("a user's own file, none of the command's business")
    before = (flyby / "initial_conditions.json").read_text()
    refused = invoke(["encounter", "--m1", "3", "--out", flyby])
    assert refused.exit_code == 2 and f"--out {flyby} already holds initial_conditions.json" in said(refused)
    assert "pass --overwrite" in said(refused) and (flyby / "initial_conditions.json").read_text() == before
    replaced = invoke(["encounter", "--m1", "3", "--out", flyby, "--no-plots", "--overwrite"])
    assert replaced.exit_code == 0, replaced.output
    assert json.loads((flyby / "initial_conditions.json").read_text())["m1"] == 3.0
    assert sorted(path.name for path in flyby.iterdir()) == ["initial_conditions.json", "initial_conditions.txt",
                                                             "notes.txt"]  # the stale stars and plot are gone
    edmd = ["edmd", "--particles", "64", "--collisions", "400", "--seed", "1", "--out", tmp_path / "gas"]
    assert invoke(edmd).exit_code == 0 and (tmp_path / "gas" / "snapshot.png").exists()
    assert invoke(edmd).exit_code == 2
    assert invoke([*edmd, "--no-plots"]).exit_code == 0  # no plots: the folder is not written
    assert invoke([*edmd, "--overwrite"]).exit_code == 0
    swarm = ["swarm", "--model", "reid", "--E-N", "12", "--particles", "1000", "--tolerance", "0.1", "--seed", "1",
             "--out", tmp_path / "swarm"]
    assert invoke(swarm).exit_code == 0 and (tmp_path / "swarm" / "swarm.csv").exists()
    assert invoke(swarm).exit_code == 2 and invoke([*swarm, "--overwrite"]).exit_code == 0


def test_a_resumed_run_does_not_erase_another_trajectory_unasked(tmp_path):
    # --resume c.npz --trajectory copy.gsd erased the copy's frames
    checkpoint, own, other = tmp_path / "c.npz", tmp_path / "own.gsd", tmp_path / "copy.gsd"
    assert invoke([*EDMD, "--checkpoint", checkpoint, "--trajectory", own, "--frame-every", 100]).exit_code == 0
    other.write_bytes(own.read_bytes())
    refused = invoke(["edmd", "--resume", checkpoint, "--trajectory", other, "--no-plots"])
    assert refused.exit_code == 2 and f"--trajectory {other} exists" in said(refused)
    assert other.read_bytes() == own.read_bytes()
    frames = read_gsd(own)["frames"]
    again = invoke(["edmd", "--resume", checkpoint, "--trajectory", own, "--no-plots"])  # its own: continued
    assert again.exit_code == 0, again.output
    assert read_gsd(own)["frames"] == frames
    assert invoke(["edmd", "--resume", checkpoint, "--summary", checkpoint, "--no-plots"]).exit_code == 2


# ------------------------------------------------------------------ item 12: stored paths are data


def test_output_paths_stored_in_an_edmd_checkpoint_are_never_used(tmp_path, monkeypatch):
    # a crafted checkpoint's stored outputs overwrote an arbitrary file on resume
    monkeypatch.chdir(tmp_path)
    checkpoint, victim, victim_gsd = tmp_path / "c.npz", tmp_path / "victim.json", tmp_path / "victim.gsd"
    assert invoke([*EDMD, "--checkpoint", checkpoint]).exit_code == 0
    assert "outputs" not in read_checkpoint(checkpoint, "edmd").state  # none is written any more
    victim.write_text("precious")
    victim_gsd.write_text("precious frames")
    saved = read_checkpoint(checkpoint, "edmd")
    crafted = saved.state | {"outputs": {"summary": str(victim), "out": str(tmp_path / "elsewhere"), "plots": True},
                             "trajectory": str(victim_gsd), "frame_every": 1}
    write_checkpoint(checkpoint, "edmd", saved.parameters, crafted, saved.arrays)
    result = invoke(["edmd", "--resume", checkpoint, "--no-plots"])
    assert result.exit_code == 0, result.output
    assert victim.read_text() == "precious" and victim_gsd.read_text() == "precious frames"
    assert not (tmp_path / "elsewhere").exists()


def test_output_paths_stored_in_a_swarm_checkpoint_are_never_used(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    checkpoint, victim = tmp_path / "scan.npz", tmp_path / "victim.json"
    assert invoke([*SWARM, "--checkpoint", checkpoint]).exit_code == 0
    assert "outputs" not in read_checkpoint(checkpoint, "swarm").state  # none is written any more
    victim.write_text("precious")
    saved = read_checkpoint(checkpoint, "swarm")
    crafted = saved.state | {"outputs": {"summary": str(victim), "out": str(tmp_path / "elsewhere")}}
    write_checkpoint(checkpoint, "swarm", saved.parameters, crafted, saved.arrays)
    result = invoke(["swarm", "--resume", checkpoint])
    assert result.exit_code == 0, result.output
    assert victim.read_text() == "precious" and not (tmp_path / "elsewhere").exists()


@pytest.mark.parametrize(
    ("arguments", "name"),
    [
        (["boltzmann", "--model", "reid", "--E-N", "10"], "boltzmann.csv"),
        (["boltzmann", "--model", "reid", "--E-N", "10"], "eedf.png"),
        (SWARM, "swarm.csv"),
        (SWARM, "eedf.png"),
    ],
)
def test_an_output_file_that_its_out_folder_also_writes_is_refused_before_any_work(tmp_path, arguments, name):
    # boltzmann --out fresh --summary fresh/boltzmann.csv exited 0, and boltzmann.csv then held the JSON summary
    out = tmp_path / "fresh"
    result = invoke([*arguments, "--out", out, "--summary", out / name])
    assert result.exit_code == 2, result.output
    message = said(result)
    assert f"--summary {out / name}" in message and f"--out {out}" in message, message
    assert list(tmp_path.iterdir()) == []
    other = invoke([*arguments, "--out", out, "--summary", out / "summary.json"])  # a file of its own: fine
    assert other.exit_code == 0, other.output
    assert json.loads((out / "summary.json").read_text())["results"]


TRACK_DEVICE = """[gas]\nmodel = "maxwell"\ndensity = 1e25\ntemperature = 0.0\n[geometry]\nkind = "parallel-plate"
gap = 1e-4\nvoltage = 0.2\n[source]\nelectrons = 4\nposition = [0.0, 0.0, 5e-5]\n"""


@pytest.mark.parametrize(
    ("arguments", "option", "name"),
    [
        ([*EDMD, "--plots"], "--summary", "snapshot.png"),
        (ENCOUNTER, "--summary", "initial_conditions.json"),
        (["track", "--config", "{device}"], "--summary", "tracks.png"),
    ],
)
def test_any_output_file_that_an_out_folder_also_writes_is_refused_before_any_work(tmp_path, arguments, option, name):
    # edmd, encounter and track: the same clash as boltzmann --out fresh --summary fresh/boltzmann.csv (a
    # --checkpoint or --xyz cannot clash: they must end in .npz and .xyz, which no --out folder writes)
    device = tmp_path / "device.toml"
    device.write_text(TRACK_DEVICE)
    out = tmp_path / "fresh"
    arguments = [str(device) if argument == "{device}" else argument for argument in arguments]
    result = invoke([*arguments, "--out", out, option, out / name])
    assert result.exit_code == 2, result.output
    message = said(result)
    assert f"{option} {out / name}" in message and f"--out {out}" in message, message
    assert not out.exists()
