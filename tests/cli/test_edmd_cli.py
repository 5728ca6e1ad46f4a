"""The ``collisionkit edmd`` command: summary, files, options, errors and bit-for-bit resume."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import gsd.hoomd
import numpy as np
import pytest
from typer.testing import CliRunner

from collisionkit import edmd
from collisionkit._io import read_checkpoint
from collisionkit.cli import _edmd, app
from collisionkit.edmd import EdmdRun
from collisionkit.trajectory import read_gsd

runner = CliRunner()

# 108 spheres: equilibration in 3 chunks (10000, 10000, 5000), then 4 blocks of 2000
SMALL = ("--particles", 108, "--equilibration", 25_000, "--collisions", 8_000, "--blocks", 4, "--seed", 5, "--no-plots")
WALL_CLOCK_KEYS = {"collisions_per_second", "files"}


def invoke(*arguments):
    return runner.invoke(app, ["edmd", *map(str, arguments)])


def physics(summary_path: Path, ignore=()) -> str:
    """The summary without wall-clock times and paths, as comparable text (NaN == NaN)."""
    data = json.loads(summary_path.read_text())
    left_out = WALL_CLOCK_KEYS | set(ignore)
    return json.dumps({key: value for key, value in data.items() if key not in left_out}, sort_keys=True)


def test_help_lists_the_command_and_its_defaults():
    assert "edmd" in runner.invoke(app, ["--help"]).output
    result = runner.invoke(app, ["edmd", "--help"], env={"COLUMNS": "200"})
    assert result.exit_code == 0
    for text in ("--packing-fraction", "[default: 0.3]", "[default: 20 N: C = 40]", "--resume", "--frame-every"):
        assert text in result.output, text


def test_summary_holds_the_required_keys_and_plausible_physics(tmp_path):
    summary = tmp_path / "s.json"
    result = invoke("--particles", 256, "--equilibration", 5_000, "--collisions", 40_000, "--blocks", 5,
                    "--seed", 1, "--no-plots", "--summary", summary)  # fmt: skip
    assert result.exit_code == 0, result.output
    data = json.loads(summary.read_text())
    assert data["dim"] == 3 and data["particles"] == 256 and data["collisions"] == 40_000
    assert data["packing_fraction"] == pytest.approx(0.3, rel=1e-12)
    assert data["equilibration_collisions"] == 5_000 and data["seed"] == 1
    assert data["temperature"] == pytest.approx(1.0, abs=1e-10)  # elastic: kT conserved
    assert data["energy_lost"] == 0.0 and abs(data["energy_lost_total"]) < 1e-9
    assert data["collisions_per_second"] > 1_000
    assert data["theory"] == "Hansen-Goos (2016)"
    assert data["compressibility_factor_theory"] == pytest.approx(float(edmd.hansen_goos(0.3)), rel=1e-12)
    assert data["compressibility_factor"] == pytest.approx(data["compressibility_factor_theory"], rel=0.03)
    assert 0 < data["compressibility_factor_error"] < 0.1
    assert data["compressibility_factor_carnahan_starling"] == pytest.approx(3.97376, rel=1e-5)
    # omega = (2d/sigma)(Z - 1) sqrt(kT/(pi m)): the collision count agrees with the virial pressure
    assert data["collision_frequency"] == pytest.approx(data["collision_frequency_from_pressure"], rel=0.02)
    for key in ("mean_free_time", "mean_free_path", "diffusion_coefficient", "pressure", "contact_value"):
        assert data[key] > 0, key
    assert data["parameters"]["collisions"] == 40_000 and data["files"] == []
    assert edmd.EdmdParameters.from_mapping(data["parameters"]).seed == 1  # the parameters rerun it
    assert "compressibility factor" in result.output and "Hansen-Goos" in result.output


def test_hard_discs_from_a_lattice_with_plots_and_xyz(tmp_path):
    summary, xyz, out = tmp_path / "s.json", tmp_path / "final.xyz", tmp_path / "plots"
    result = invoke("--dim", 2, "--initial", "hexagonal", "--particles", 200, "--equilibration", 4_000,
                    "--collisions", 30_000, "--blocks", 5, "--seed", 2, "--summary", summary, "--xyz", xyz, "--out", out)  # fmt: skip
    assert result.exit_code == 0, result.output
    data = json.loads(summary.read_text())
    assert data["dim"] == 2 and data["initial"] == "hexagonal" and data["theory"] == "Henderson (1975)"
    assert data["compressibility_factor"] == pytest.approx(float(edmd.henderson(0.3)), rel=0.03)
    names = {"equation_of_state.png", "speed_distribution.png", "snapshot.png", "radial_distribution.png"}
    assert {Path(name).name for name in data["files"]} == names | {"final.xyz", "blocks.csv"}
    for name in names:
        assert (out / name).stat().st_size > 10_000
    lines = xyz.read_text().splitlines()
    assert lines[0] == "200" and 'pbc="T T F"' in lines[1] and len(lines) == 202


def test_inelastic_run_cools_and_skips_the_theory(tmp_path):
    summary = tmp_path / "s.json"
    result = invoke("--restitution", 0.9, "--particles", 108, "--equilibration", 0, "--collisions", 2000,
                    "--blocks", 4, "--seed", 5, "--no-plots", "--summary", summary)  # fmt: skip
    assert result.exit_code == 0, result.output
    data = json.loads(summary.read_text())
    assert data["elastic"] is False and "compressibility_factor_theory" not in data
    assert 0.01 < data["temperature"] < 0.5  # ~37 collisions per sphere at e = 0.9
    # kT = 1 exactly at the start, so the energy lost is 3N/2 (1 - kT_final), all of it while measuring
    assert data["energy_lost_total"] == pytest.approx(1.5 * 108 * (1 - data["temperature"]), rel=1e-12)
    assert data["energy_lost"] == pytest.approx(data["energy_lost_total"], rel=1e-12)
    assert "no equilibrium" in result.output


def test_toml_config_and_command_line_wins(tmp_path):
    config = tmp_path / "run.toml"
    config.write_text('dim = 2\nparticles = 128\npacking-fraction = 0.5\ninitial = "square"\ncollisions = 4000\n'
                      f'equilibration = 0\nblocks = 2\nseed = 9\nplots = false\nsummary = "{tmp_path / "s.json"}"\n')  # fmt: skip
    result = invoke("--config", config, "--packing-fraction", 0.4, "--particles", 144)
    assert result.exit_code == 0, result.output
    data = json.loads((tmp_path / "s.json").read_text())
    assert (data["dim"], data["particles"], data["collisions"], data["seed"]) == (2, 144, 4000, 9)
    assert data["packing_fraction"] == pytest.approx(0.4, rel=1e-12)
    assert data["initial"] == "square" and data["equilibration_collisions"] == 0


@pytest.mark.parametrize(
    ("arguments", "words"),
    [
        (("--packing-fraction", 0.55), "--packing-fraction must lie in (0, 0.5] for dim=3"),
        (("--dim", 2, "--packing-fraction", 0.75), "--packing-fraction"),
        (("--dim", 4), "dim"),
        (("--restitution", 1.5), "restitution"),
        (("--particles", 1), "particles"),
        (("--initial", "fcc", "--particles", 100), "--initial fcc needs particles = 4 * cells^3"),
        (("--initial", "square", "--particles", 100), "--initial square is a 2D lattice; it cannot start a 3D run"),
        (("--initial", "bcc"), "initial"),
        (("--collisions", 5, "--blocks", 10), "collisions must be >= blocks"),
        (("--particles", 2, "--blocks", 1000), "collisions (400 by default for 2 particles) must be >= blocks (1000)"),
        (("--frame-every", 100), "--frame-every needs --trajectory"),
        (("--particles", 10, "--packing-fraction", 0.45), "less than 3 diameters"),
        (("--resume", "missing.npz"), "checkpoint not found"),
    ],
)
def test_bad_options_exit_with_2_and_say_why(tmp_path, arguments, words):
    result = invoke(*arguments, "--no-plots", "--out", tmp_path)
    assert result.exit_code == 2, result.output
    assert words in " ".join(result.output.split())


def test_unknown_or_bad_config_keys_exit_with_2(tmp_path):
    config = tmp_path / "bad.toml"
    config.write_text("particle = 100\n")
    result = invoke("--config", config)
    assert result.exit_code == 2 and "unknown option 'particle'" in result.output
    config.write_text('blocks = "ten"\n')
    result = invoke("--config", config)
    assert result.exit_code == 2 and "blocks" in result.output
    (tmp_path / "not_a_checkpoint.npz").write_bytes(b"junk")
    result = invoke("--resume", tmp_path / "not_a_checkpoint.npz")
    assert result.exit_code == 2 and "is not a checkpoint" in " ".join(result.output.split())
    assert "pickle" not in result.output  # numpy's message for a file it cannot read as .npz
    np.savez(tmp_path / "other.npz", x=np.zeros(2))  # an .npz, but not ours
    result = invoke("--resume", tmp_path / "other.npz")
    assert result.exit_code == 2 and "not a checkpoint of 'collisionkit edmd'" in " ".join(result.output.split())


def test_trajectory_frames_at_chunk_ends_or_only_the_last(tmp_path):
    every, last = tmp_path / "every.gsd", tmp_path / "last.gsd"
    assert invoke(*SMALL, "--trajectory", every, "--frame-every", 1, "--summary", tmp_path / "a.json").exit_code == 0
    assert invoke(*SMALL, "--trajectory", last, "--summary", tmp_path / "b.json").exit_code == 0
    with gsd.hoomd.open(str(every), "r") as frames:
        steps = [int(frame.configuration.step) for frame in frames]
    assert steps == [0, 10_000, 20_000, 25_000, 27_000, 29_000, 31_000, 33_000]
    final = read_gsd(last)
    assert final["frames"] == 1 and final["step"] == 33_000 and final["positions"].shape == (108, 3)
    assert np.array_equal(final["positions"], read_gsd(every)["positions"])
    # writing frames never changes the dynamics
    assert json.loads((tmp_path / "a.json").read_text())["trajectory_frames"] == 8
    frame_keys = ["trajectory_frames", "frame_interval_effective"]
    assert physics(tmp_path / "a.json", frame_keys) == physics(tmp_path / "b.json", frame_keys)


class Killed(Exception):
    """Stands for a kill of the process."""


def kill_at_checkpoint(monkeypatch, number):
    """Make the ``number``-th checkpoint write die before it starts (the previous one survives)."""
    real = EdmdRun.save
    calls = []

    def dying(run, path=None):
        calls.append(path)
        if len(calls) == number:
            raise Killed(f"killed while writing checkpoint {number}")
        return real(run, path)

    monkeypatch.setattr(EdmdRun, "save", dying)


@pytest.mark.parametrize("killed_at", [3, 7], ids=["during-equilibration", "during-measurement"])
def test_resume_continues_bit_for_bit(tmp_path, monkeypatch, killed_at):
    whole, part = tmp_path / "whole", tmp_path / "part"

    def outputs(folder):
        return ("--trajectory", folder / "t.gsd", "--frame-every", 1, "--checkpoint", folder / "c.npz", "--summary", folder / "s.json")

    assert invoke(*SMALL, *outputs(whole)).exit_code == 0
    kill_at_checkpoint(monkeypatch, killed_at)
    interrupted = invoke(*SMALL, *outputs(part))
    assert isinstance(interrupted.exception, Killed)
    assert not (part / "s.json").exists()
    monkeypatch.undo()
    saved = read_checkpoint(part / "c.npz", "edmd").state
    equilibrated, frames = saved["equilibrated"], saved["frames"]
    assert frames == killed_at - 1 and (equilibrated < 25_000) == (killed_at <= 4)
    assert read_gsd(part / "t.gsd")["frames"] == killed_at  # one frame more than the checkpoint knows

    # a physics option repeated; the outputs given again (paths stored in a checkpoint are never used)
    resumed = invoke("--resume", part / "c.npz", "--seed", 5, "--summary", part / "s.json", "--trajectory",
                     part / "t.gsd", "--no-plots")
    assert resumed.exit_code == 0, resumed.output
    assert physics(part / "s.json") == physics(whole / "s.json")
    with gsd.hoomd.open(str(whole / "t.gsd"), "r") as a, gsd.hoomd.open(str(part / "t.gsd"), "r") as b:
        assert len(a) == len(b) == 8
        for x, y in zip(a, b):
            assert x.configuration.step == y.configuration.step
            assert np.array_equal(x.particles.position, y.particles.position)
            assert np.array_equal(x.particles.velocity, y.particles.velocity)
    a, b = read_checkpoint(whole / "c.npz", "edmd"), read_checkpoint(part / "c.npz", "edmd")
    assert a.parameters == b.parameters and set(a.arrays) == set(b.arrays)
    paths = ("trajectory",)  # the two runs wrote to their own folders
    assert {key: value for key, value in a.state.items() if key not in paths} == \
        {key: value for key, value in b.state.items() if key not in paths}
    for name in set(a.arrays) - {"sampler_scalars"}:
        assert np.array_equal(a.arrays[name], b.arrays[name]), name
    assert np.array_equal(a.arrays["sampler_scalars"][:-1], b.arrays["sampler_scalars"][:-1])  # all but the wall clock


def test_resume_refuses_other_physics_and_finishes_a_finished_run(tmp_path):
    checkpoint, summary = tmp_path / "c.npz", tmp_path / "s.json"
    assert invoke(*SMALL, "--checkpoint", checkpoint, "--summary", summary).exit_code == 0
    result = invoke("--resume", checkpoint, "--packing-fraction", 0.35)
    assert result.exit_code == 2
    assert "packing_fraction = 0.35 differs from the checkpoint" in " ".join(result.output.split())
    again = tmp_path / "again.json"
    result = invoke("--resume", checkpoint, "--summary", again, "--no-plots")
    assert result.exit_code == 0, result.output
    assert physics(again) == physics(summary)


def test_resume_of_a_checkpoint_from_before_elastic_below_existed(tmp_path):
    # checkpoints written before --elastic-below have no such key in their parameters: a KeyError, not a message
    from collisionkit._io import write_checkpoint

    checkpoint = tmp_path / "c.npz"
    assert invoke(*SMALL, "--checkpoint", checkpoint).exit_code == 0
    saved = read_checkpoint(checkpoint, "edmd")
    parameters = dict(saved.parameters)
    del parameters["elastic_below"]
    write_checkpoint(checkpoint, "edmd", parameters, saved.state, saved.arrays)
    result = invoke("--resume", checkpoint, "--elastic-below", 0.01)
    assert result.exit_code == 2
    assert "elastic_below = 0.01 differs from the checkpoint" in " ".join(result.output.split())
    assert invoke("--resume", checkpoint, "--no-plots").exit_code == 0


def test_resume_refuses_a_checkpoint_of_another_engine_format(tmp_path):
    checkpoint = tmp_path / "c.npz"
    assert invoke(*SMALL, "--checkpoint", checkpoint).exit_code == 0
    from collisionkit._io import write_checkpoint

    saved = read_checkpoint(checkpoint, "edmd")
    write_checkpoint(checkpoint, "edmd", saved.parameters, saved.state, saved.arrays | {"format": np.asarray(1)})
    result = invoke("--resume", checkpoint)
    assert result.exit_code == 2
    assert "engine format 1" in " ".join(result.output.split())


@pytest.mark.parametrize(
    ("option", "name", "words"),
    [
        ("--trajectory", "out.xyz", "--trajectory must end in .gsd"),
        ("--trajectory", "out", "--trajectory must end in .gsd"),
        ("--xyz", "out.gsd", "--xyz must end in .xyz or .extxyz"),
        ("--xyz", "out.txt", "--xyz must end in .xyz or .extxyz"),
    ],
)
def test_an_output_file_named_for_another_format_is_refused(tmp_path, option, name, words):
    # GSD went into out.xyz and text into out.gsd, silently
    result = invoke(*SMALL, option, tmp_path / name, "--summary", tmp_path / "s.json")
    assert result.exit_code == 2, result.output
    assert words in " ".join(result.output.split())
    assert not any(tmp_path.iterdir())  # nothing ran


def test_an_inelastic_run_whose_floor_made_every_contact_elastic_does_not_say_it_cooled(tmp_path):
    # a new user's run: --elastic-below 1e10 --restitution 0.5 said "the gas cooled ... kT from 1 to 1"
    summary = tmp_path / "floor.json"
    result = runner.invoke(app, ["edmd", *map(str, SMALL), "--initial", "fcc", "--restitution", "0.5",
                                 "--elastic-below", "100", "--no-plots", "--summary", str(summary)],
                           env={"COLUMNS": "200"})
    assert result.exit_code == 0, result.output
    said = " ".join(result.output.split())
    assert json.loads(summary.read_text())["temperature"] > 0.99
    assert "the gas barely cooled" in said and "this is the run of an elastic gas" in said
    assert "Haff" not in said


def test_output_suffixes_are_matched_without_case():
    options = _edmd.EdmdOptions.model_validate({"trajectory": "run.GSD", "xyz": "final.extxyz"})
    assert options.trajectory.name == "run.GSD" and options.xyz.name == "final.extxyz"


def test_an_inelastic_run_says_it_cooled_and_takes_the_elastic_floor(tmp_path):
    # a user's e = 0.9 run ended at kT = 1.7e-12 with D = nan and no word on why: the gas cooled (Haff) down to
    # the elastic floor, which the command did not let them set
    summary = tmp_path / "granular.json"
    result = runner.invoke(app, ["edmd", *map(str, SMALL), "--initial", "fcc", "--restitution", "0.9",
                                 "--elastic-below", "0.01", "--out", str(tmp_path), "--summary", str(summary)],
                           env={"COLUMNS": "200"})
    assert result.exit_code == 0, result.output
    said = " ".join(result.output.split())
    data = json.loads(summary.read_text())
    assert data["elastic_below"] == 0.01 and data["parameters"]["elastic_below"] == 0.01
    assert f"kT from 1 to {data['temperature']:.3g}" in said and "Haff's law" in said
    assert ("elastic floor" in said) == (data["temperature"] < 100 * 0.01**2)
    elastic = runner.invoke(app, ["edmd", *map(str, SMALL), "--initial", "fcc", "--out", str(tmp_path)])
    assert elastic.exit_code == 0 and "Haff" not in elastic.output
    refused = runner.invoke(app, ["edmd", "--elastic-below", "-1", "--no-plots"], env={"COLUMNS": "200"})
    assert refused.exit_code == 2 and "--elastic-below" in " ".join(refused.output.split())


def test_an_interrupted_run_says_where_its_checkpoint_is(tmp_path, monkeypatch):
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(edmd.HardSphereSystem, "run", interrupted)  # Ctrl-C in the first chunk
    checkpoint = tmp_path / "run.npz"
    options = ["edmd", "--dim", "2", "--particles", "64", "--initial", "square", "--collisions", "2000", "--no-plots"]
    saved = runner.invoke(app, [*options, "--checkpoint", str(checkpoint), "--summary", str(tmp_path / "s.json")])
    assert saved.exit_code == 130 and checkpoint.exists()
    # the whole command: a checkpoint keeps no outputs, and following "--resume FILE" alone wrote no summary
    assert f"continue with collisionkit edmd --resume {checkpoint} --summary {tmp_path / 's.json'} --no-plots" in \
        saved.output.replace("\n", "")
    unsaved = runner.invoke(app, options)
    assert unsaved.exit_code == 130 and "nothing is saved" in unsaved.output.replace("\n", "")


def test_a_new_run_does_not_overwrite_an_existing_checkpoint(tmp_path):
    checkpoint = tmp_path / "c.npz"
    assert invoke(*SMALL, "--checkpoint", checkpoint).exit_code == 0
    saved = checkpoint.read_bytes()
    again = invoke(*SMALL, "--checkpoint", checkpoint)  # --resume forgotten
    assert again.exit_code == 2 and f"--resume {checkpoint}" in again.output.replace("\n", "")
    assert checkpoint.read_bytes() == saved
    assert invoke("--resume", checkpoint, "--no-plots").exit_code == 0  # resuming writes on to it, as before


def test_a_checkpoint_another_run_is_writing_is_refused_in_one_line(tmp_path):
    # a second `edmd --resume c.npz` against a running run was refused with a traceback and exit 1
    import subprocess
    import sys

    checkpoint = tmp_path / "c.npz"
    assert invoke(*SMALL, "--checkpoint", checkpoint).exit_code == 0
    holder = subprocess.Popen([sys.executable, "-c", "import time\nfrom collisionkit._io import exclusive\n"
                               f"with exclusive({str(checkpoint)!r}):\n    print('held', flush=True)\n    time.sleep(60)"],
                              stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        result = invoke("--resume", checkpoint, "--collisions", 8_000)
        said = " ".join(result.output.split())
        assert result.exit_code == 2 and "another collisionkit" in said and "Traceback" not in result.output
    finally:
        holder.kill()
        holder.wait(timeout=30)


def test_an_engine_watchdog_is_one_line_and_exit_1(monkeypatch):
    # the engine's RuntimeErrors (inelastic or wall collapse, no possible collision) reached the shell as tracebacks
    def collapsed(*args, **kwargs):
        raise RuntimeError("inelastic collapse: 65536 events at one instant")

    monkeypatch.setattr(edmd.HardSphereSystem, "run", collapsed)
    result = invoke("--dim", 2, "--particles", 64, "--initial", "square", "--collisions", 2000, "--no-plots")
    said = " ".join(result.output.split())
    assert result.exit_code == 1 and "the run stopped: inelastic collapse" in said and "Traceback" not in said


def test_extend_continues_a_finished_run_and_its_trajectory(tmp_path):
    # issue 16, item 8: `--extend N` continues a finished run (its checkpoint, its trajectory)
    checkpoint, trajectory = tmp_path / "c.npz", tmp_path / "t.gsd"
    first = tmp_path / "first.json"
    assert invoke(*SMALL, "--checkpoint", checkpoint, "--summary", first, "--trajectory", trajectory,
                  "--frame-every", 4_000).exit_code == 0
    steps_before = [int(frame.configuration.step) for frame in gsd.hoomd.open(trajectory)]
    second = tmp_path / "second.json"
    result = invoke("--resume", checkpoint, "--extend", 1, "--summary", second, "--trajectory", trajectory,
                    "--no-plots")
    assert result.exit_code == 0, result.output
    before, after = json.loads(first.read_text()), json.loads(second.read_text())
    length = before["collisions"] // before["parameters"]["blocks"]
    assert after["collisions"] == before["collisions"] + length
    assert f"extending the run by {length} measured pair collisions (1 rounded up" in " ".join(result.output.split())
    steps = [int(frame.configuration.step) for frame in gsd.hoomd.open(trajectory)]
    # the frames of the first run, then a frame at the new end, appended to the same file
    assert steps == steps_before + [25_000 + after["collisions"]], (steps_before, steps)


@pytest.mark.parametrize(("arguments", "words"), [
    (("--extend", 5), "--extend needs --resume FILE"),
    (("--resume", "CHECKPOINT", "--collisions", 10**6), "to measure more, give --extend N"),
])
def test_extend_is_refused_without_a_run_to_extend(tmp_path, arguments, words):
    checkpoint = tmp_path / "c.npz"
    assert invoke(*SMALL, "--checkpoint", checkpoint, "--no-plots").exit_code == 0
    result = invoke(*[checkpoint if value == "CHECKPOINT" else value for value in arguments])
    assert result.exit_code == 2
    assert words in " ".join(result.output.split())


def test_transport_adds_the_coefficients_with_errors_to_the_table_the_summary_and_the_plots(tmp_path):
    summary, out = tmp_path / "s.json", tmp_path / "plots"
    result = invoke("--particles", 108, "--initial", "fcc", "--equilibration", 2_000, "--collisions", 20_000,
                    "--blocks", 4, "--seed", 3, "--transport", "--yeh-hummer", "--summary", summary, "--out", out)
    assert result.exit_code == 0, result.output
    data = json.loads(summary.read_text())
    for key in ("shear_viscosity", "bulk_viscosity", "thermal_conductivity", "self_diffusion",
                "self_diffusion_infinite", "green_kubo_shear_viscosity"):
        assert data[key] > 0 and data[key + "_error"] > 0, key
    assert data["self_diffusion"] == data["diffusion_coefficient"]
    assert data["parameters"]["transport"] is True and data["parameters"]["yeh_hummer"] is True
    # the pressure tensor's trace is 3 P; the autocorrelation starts at 1
    assert sum(data["pressure_tensor"][k][k] for k in range(3)) / 3 == pytest.approx(data["pressure"], rel=1e-11)
    assert data["vacf"][0] == 1.0 and len(data["vacf_time"]) == len(data["vacf"])
    low, high = data["transport_fit_window"]
    text = " ".join(result.output.split())
    for words in ("shear viscosity", "thermal conductivity", "(Enskog)", "Yeh-Hummer", "transport fit window",
                  f"{low:.4g} to {high:.4g}"):
        assert words in text, words
    assert (out / "helfand_moments.png").stat().st_size > 10_000
    assert str(out / "helfand_moments.png") in data["files"]


def test_a_transport_run_resumes_with_its_transport_and_refuses_to_drop_it(tmp_path):
    checkpoint, whole, part = tmp_path / "c.npz", tmp_path / "whole.json", tmp_path / "part.json"
    run = ("--particles", 108, "--initial", "fcc", "--equilibration", 1_000, "--seed", 2, "--transport", "--no-plots")
    assert invoke(*run, "--collisions", 8_000, "--blocks", 4, "--summary", whole).exit_code == 0
    assert invoke(*run, "--collisions", 4_000, "--blocks", 2, "--checkpoint", checkpoint).exit_code == 0
    refused = invoke("--resume", checkpoint, "--no-transport")
    assert refused.exit_code == 2 and "transport = False differs from the checkpoint" in " ".join(refused.output.split())
    extended = invoke("--resume", checkpoint, "--extend", 4_000, "--summary", part, "--no-plots")
    assert extended.exit_code == 0, extended.output
    a, b = json.loads(part.read_text()), json.loads(whole.read_text())
    # (an extended run keeps the MSD's lags of its start: D differs, the transport samples do not)
    for key in ("shear_viscosity", "bulk_viscosity_error", "thermal_conductivity", "pressure_tensor", "vacf",
                "green_kubo_shear_viscosity", "transport_fit_window"):
        assert a[key] == b[key], key


def test_square_wells_report_their_energy_and_temperature_and_resume_bit_for_bit(tmp_path):
    wells = ("--well-width", 1.5, "--well-depth", 0.5)
    whole = invoke(*SMALL, *wells, "--summary", tmp_path / "whole.json")
    assert whole.exit_code == 0, whole.output
    assert "potential energy per particle" in whole.output and "T* = kT/epsilon" in whole.output
    summary = json.loads((tmp_path / "whole.json").read_text())
    assert summary["well_width"] == 1.5 and summary["well_depth"] == 0.5
    assert summary["potential_energy"] < 0 and summary["potential_energy_error"] > 0
    assert summary["reduced_temperature"] == summary["temperature_mean"] / 0.5
    assert "compressibility_factor_theory" not in summary  # the hard-sphere equation of state does not apply
    assert min(summary[f"well_{kind}"] for kind in ("captures", "escapes", "bounces")) > 0
    # half the blocks, then the rest from its checkpoint: the same run, bit for bit
    half = ("--particles", 108, "--equilibration", 25_000, "--collisions", 4_000, "--blocks", 2, "--seed", 5,
            "--no-plots")
    first = invoke(*half, *wells, "--checkpoint", tmp_path / "c.npz")
    assert first.exit_code == 0, first.output
    resumed = invoke("--resume", tmp_path / "c.npz", "--extend", 4_000, "--summary", tmp_path / "part.json",
                     "--no-plots")
    assert resumed.exit_code == 0, resumed.output
    # (D's lags are planned from the blocks a sampler starts with: 1 lag for 2 blocks, 2 for 4)
    lags = ("diffusion_coefficient", "diffusion_coefficient_error")
    assert physics(tmp_path / "part.json", lags) == physics(tmp_path / "whole.json", lags)


def test_square_wells_with_transport_report_the_coefficients_without_hard_sphere_theory(tmp_path):
    result = invoke("--particles", 108, "--equilibration", 25_000, "--collisions", 20_000, "--blocks", 2, "--seed", 5,
                    "--well-width", 1.5, "--well-depth", 0.5, "--transport", "--summary", tmp_path / "s.json",
                    "--out", tmp_path / "out")
    assert result.exit_code == 0, result.output
    assert "thermal conductivity" in result.output and "potential energy per particle" in result.output
    summary = json.loads((tmp_path / "s.json").read_text())
    assert summary["thermal_conductivity"] > 0 and summary["shear_viscosity"] > 0
    assert not [key for key in summary if key.endswith("_enskog")]  # Enskog's theory is of hard spheres
    assert (tmp_path / "out" / "helfand_moments.png").stat().st_size > 0


def test_a_mixture_from_a_config_file_reports_its_species_and_theory_and_resumes(tmp_path):
    config = tmp_path / "mixture.toml"
    config.write_text("particles = 120\nfractions = [0.25, 0.75]\ndiameters = [1.0, 0.6]\nmasses = [1.0, 0.3]\n"
                      "equilibration = 2000\ncollisions = 4000\nblocks = 4\nseed = 5\n")
    result = invoke("--config", config, "--summary", tmp_path / "s.json", "--out", tmp_path / "out",
                    "--checkpoint", tmp_path / "c.npz")
    assert result.exit_code == 0, result.output
    assert "species" in result.output and "BMCSL" in result.output and "g(r) at contact" not in result.output
    assert "g_AB" in result.output  # the partial contact values, a row a pair
    summary = json.loads((tmp_path / "s.json").read_text())
    assert summary["species_counts"] == [30, 90] and summary["parameters"]["masses"] == [1.0, 0.3]
    assert summary["theory"] == "BMCSL (Mansoori et al. 1971)"
    assert len(summary["contact_values"]) == len(summary["contact_values_theory"]) == 2
    assert (tmp_path / "out" / "equation_of_state.png").stat().st_size > 0
    again = invoke("--resume", tmp_path / "c.npz", "--fractions", 0.25, "--fractions", 0.75, "--no-plots")
    assert again.exit_code == 0, again.output
    other = invoke("--resume", tmp_path / "c.npz", "--masses", 1, "--masses", 0.5, "--no-plots")
    assert other.exit_code == 2 and "masses" in other.output and "differs from the checkpoint" in other.output


def test_a_well_per_species_pair_from_a_config_file(tmp_path):
    config = tmp_path / "wells.toml"
    config.write_text("particles = 300\nfractions = [0.5, 0.5]\ndiameters = [1.0, 0.8]\n"
                      "well_width = [[1.5, 1.4], [1.4, 1.3]]\nwell_depth = [[1.0, 0.5], [0.5, 0.0]]\n"
                      "equilibration = 3000\ncollisions = 4000\nblocks = 2\nseed = 2\nplots = false\n")
    result = invoke("--config", config, "--summary", tmp_path / "s.json")
    assert result.exit_code == 0, result.output
    summary = json.loads((tmp_path / "s.json").read_text())
    assert summary["well_depth"] == [[1.0, 0.5], [0.5, 0.0]] and summary["potential_energy"] < 0
    assert "potential energy per" in result.output
    config.write_text("well_width = [[1.5, 1.4], [1.4, 1.3]]\n")
    refused = invoke("--config", config)
    assert refused.exit_code == 2 and "--well-width as a matrix (one per species pair) needs fractions" in \
        " ".join(refused.output.split())


def test_a_restitution_per_species_pair_from_a_config_file(tmp_path):
    """A granular binary mixture: the summary and the table give each species' temperature beside the homogeneous
    cooling state's; a matrix without fractions is refused with its option named."""
    config = tmp_path / "granular.toml"
    config.write_text("particles = 300\npacking_fraction = 0.05\nfractions = [0.5, 0.5]\nmasses = [1.0, 0.25]\n"
                      "restitution = [[0.9, 0.8], [0.8, 0.7]]\nequilibration = 1000\ncollisions = 6000\nblocks = 3\n"
                      "seed = 2\nplots = false\n")
    result = invoke("--config", config, "--summary", tmp_path / "s.json")
    assert result.exit_code == 0, result.output
    summary = json.loads((tmp_path / "s.json").read_text())
    assert summary["restitution"] == [[0.9, 0.8], [0.8, 0.7]] and not summary["elastic"]
    theory = summary["temperature_species_theory"]
    assert theory[0] > 1.0 > theory[1] and len(summary["temperature_species"]) == 2
    output = " ".join(result.output.split())
    assert "e = 0.9 0.8 / 0.8 0.7" in output and "homogeneous cooling, Garzo-Dufty" in output
    drawn = invoke("--config", config, "--plots", "--out", tmp_path / "out")  # a gas that cooled: its cooling plot
    assert drawn.exit_code == 0 and (tmp_path / "out" / "cooling.png").stat().st_size > 10_000
    elastic = invoke("--particles", "64", "--collisions", "2000", "--out", tmp_path / "out", "--overwrite")
    assert elastic.exit_code == 0 and not (tmp_path / "out" / "cooling.png").exists()  # an earlier run's: gone
    config.write_text("restitution = [[0.9, 0.8], [0.8, 0.7]]\n")
    refused = invoke("--config", config)
    assert refused.exit_code == 2 and "--restitution as a matrix (one per species pair) needs fractions" in \
        " ".join(refused.output.split())
    config.write_text("fractions = [0.5, 0.5]\nrestitution = [0.9, 0.8]\n")  # a flat list: neither form
    flat = invoke("--config", config)
    assert flat.exit_code == 2 and "--restitution: must be a number or a matrix over the species of fractions, as a " \
        "list of rows" in " ".join(flat.output.split()) and "Traceback" not in flat.output
    config.write_text('fractions = [0.5, 0.5]\nrestitution = [[0.9, "a"], [0.8, 0.7]]\n')  # a word in the matrix
    word = invoke("--config", config)
    assert word.exit_code == 2 and "list of rows of numbers" in " ".join(word.output.split())


def test_a_cooling_gas_s_speed_plot_scales_each_block_by_its_thermal_speed():
    """Pooled, a cooling gas's speeds span every kT it passed; scaled block by block they have unit kT."""
    import matplotlib

    matplotlib.use("Agg")
    from collisionkit import plotting
    from collisionkit.cli._edmd_report import _speed_distribution
    from collisionkit.edmd import EdmdParameters, EdmdRun

    run = EdmdRun(EdmdParameters(particles=300, packing_fraction=0.05, restitution=0.8, equilibration=0,
                                 collisions=15_000, blocks=5, seed=1)).run()
    measurement = run.measurement()
    ax = _speed_distribution(run, measurement, plotting, {"mass": 1.0, "fractions": None})
    assert "cooling gas" in ax.get_title() and "kT = 1" in ax.get_legend().get_texts()[1].get_text()
    heights = [patch.get_height() * patch.get_width() for patch in ax.patches]
    centres = [patch.get_x() + patch.get_width() / 2 for patch in ax.patches]
    mean = sum(h * c for h, c in zip(heights, centres)) / sum(heights)
    assert abs(mean - (8 / math.pi) ** 0.5) < 0.05 * (8 / math.pi) ** 0.5  # Maxwell's mean speed at kT = m = 1
    assert measurement.block_temperature[-1] < 0.05  # (unscaled, the mean would be far below)


def test_an_inelastic_run_that_will_cool_to_its_elastic_floor_says_so_before_it_starts(tmp_path):
    """At e = 0.9 the default 200 pair collisions per particle cool kT to ~1e-12, the elastic floor: a note before
    the run gives the collisions that stay above it (the warning at the end came after minutes)."""
    result = invoke("--particles", "100", "--restitution", "0.9", "--seed", "1", "--no-plots")
    said = " ".join(result.output.split())
    assert result.exit_code == 0 and "by Haff's law these 22000 pair collisions cool kT from 1 to about 1e-12" in said
    assert "give --collisions 16178 or fewer" in said
    quiet = invoke("--particles", "100", "--restitution", "0.9", "--collisions", "10000", "--seed", "1", "--no-plots")
    assert quiet.exit_code == 0 and "by Haff's law" not in quiet.output


def test_a_viscoelastic_gas_reports_its_cooling_against_the_maxwellian_rate(tmp_path):
    """--restitution-law viscoelastic: the summary names the law and gives the Maxwellian rate over the blocks, the
    table says where the theory comes from, the cooling plot draws its curve; no note of Haff's law before the run;
    the resumed run keeps the law (a different one is refused)."""
    options = ("--particles", "300", "--packing-fraction", "0.05", "--restitution-law", "viscoelastic", "--law-speed",
               "1e4", "--equilibration", "0", "--collisions", "9000", "--blocks", "6", "--seed", "4")
    result = invoke(*options, "--summary", tmp_path / "s.json", "--out", tmp_path / "out",
                    "--checkpoint", tmp_path / "run.npz")
    assert result.exit_code == 0, result.output
    summary = json.loads((tmp_path / "s.json").read_text())
    assert summary["restitution_law"] == "viscoelastic" and summary["parameters"]["law_speed"] == 1e4
    assert 0.0 < summary["cooling_rate_theory"] < 0.1 and math.isfinite(summary["cooling_rate_deviation_sigmas"])
    output = " ".join(result.output.split())
    assert "Maxwellian, viscoelastic law" in output and "Haff" not in output
    assert (tmp_path / "out" / "cooling.png").stat().st_size > 10_000
    for law in ("bridges", "constant"):  # (constant: the saved law_speed then has no law, which is not the point)
        refused = invoke("--resume", tmp_path / "run.npz", "--restitution-law", law)
        assert refused.exit_code == 2 and f"restitution_law = {law} differs from the checkpoint" in \
            " ".join(refused.output.split())
    assert "(viscoelastic law, u_c = 10000)" in output


def test_an_elastic_floor_on_an_elastic_gas_is_said_to_change_nothing():
    """--elastic-below with restitution 1 and no law: the run goes (a sweep over restitution may reach 1), with a
    warning; with restitution below 1, none."""
    options = ("--particles", "108", "--initial", "fcc", "--collisions", "400", "--equilibration", "0", "--no-plots")
    elastic = invoke(*options, "--elastic-below", "0.5")
    assert elastic.exit_code == 0 and "--elastic-below 0.5 changes nothing" in " ".join(elastic.output.split())
    inelastic = invoke(*options, "--elastic-below", "0.5", "--restitution", "0.9")
    assert inelastic.exit_code == 0 and "changes nothing" not in inelastic.output


def test_a_cooling_run_says_whether_it_stayed_homogeneous(tmp_path):
    """A large 2D box at e = 0.7 forms vortices: the table's row, the note and the summary say so, and the cooling
    plot marks where; a small 3D box at e = 0.9 stays homogeneous."""
    large = invoke("--dim", "2", "--particles", "2000", "--packing-fraction", "0.05", "--restitution", "0.7",
                   "--collisions", "20000", "--blocks", "10", "--seed", "3", "--summary", tmp_path / "large.json",
                   "--out", tmp_path / "out")
    assert large.exit_code == 0, large.output
    said = " ".join(large.output.split())
    summary = json.loads((tmp_path / "large.json").read_text())
    assert summary["homogeneous"] is False and summary["homogeneity_lost_after"] == 2.0
    assert "shear flows / homogeneous share (max)" in said and "not homogeneous from C = 2" in said
    assert "it did not stay homogeneous" in said and "box 2.2 L_c" in said
    assert "is 2.17 times the shear instability's critical length at e = 0.7 (81.6" in said  # before the run
    assert summary["shear_instability_length"] == pytest.approx(81.57, abs=0.01)
    assert (tmp_path / "out" / "cooling.png").stat().st_size > 10_000
    with open(tmp_path / "out" / "blocks.csv") as handle:  # the blocks' records, as Measurement.block_table
        rows = list(csv.DictReader(handle))
    assert [float(row["collisions_per_particle"]) for row in rows] == [2.0 * k for k in range(1, 11)]
    assert max(float(row["shear_mode_energy"]) for row in rows) == summary["shear_mode_energy_max"]
    assert {"temperature", "compressibility", "frequency", "sonine_a2", "msd", "time"} <= set(rows[0])
    small = invoke("--particles", "500", "--packing-fraction", "0.02", "--restitution", "0.9", "--collisions",
                   "25000", "--seed", "3", "--no-plots", "--summary", tmp_path / "small.json")
    assert small.exit_code == 0, small.output
    assert json.loads((tmp_path / "small.json").read_text())["homogeneous"] is True
    said = " ".join(small.output.split())
    assert "homogeneous: below" in said and "box 0.16 L_c" in said and "critical length" not in said


def test_an_elastic_equilibration_leaves_the_cooling_to_the_measurement(tmp_path):
    """--elastic-equilibration: the summary's parameters keep it, the floor's advice counts only the measured
    collisions (they alone cool)."""
    result = invoke("--particles", "100", "--restitution", "0.9", "--seed", "1", "--no-plots", "--elastic-equilibration",
                    "--summary", tmp_path / "s.json")
    said = " ".join(result.output.split())
    assert result.exit_code == 0 and "these 20000 pair collisions cool kT from 1" in said  # (22000 without)
    assert json.loads((tmp_path / "s.json").read_text())["parameters"]["elastic_equilibration"] is True
