"""Command line: ``collisionkit track --config device.toml`` (plates and counter), checkpoint and resume, plots, the
summary's keys, and a sweep of the gain against the voltage."""

import json
from concurrent.futures import ThreadPoolExecutor

from typer.testing import CliRunner

from collisionkit import sweep
from collisionkit.cli import app
from collisionkit.transport.tracking import TrackParameters, TrackRun, track

runner = CliRunner()

PLATES = """
seed = 4
[gas]
model = "maxwell"
density = 1e25
temperature = 0.0
[geometry]
kind = "parallel-plate"
gap = 1e-4
voltage = 0.2
[source]
electrons = 40
position = [0.0, 0.0, 5e-5]
"""

COUNTER = """
[gas]
model = "lucas_saelee"
pressure = 10132.5
temperature = 300.0
[geometry]
kind = "coaxial"
wire-radius = 25e-6
cathode-radius = 2e-3
voltage = 150.0
[source]
electrons = 6
radius = 5e-4
energy = 1.0
[ions]
mobility = 1.5e-3
"""


def _run(tmp_path, text, *extra):
    config = tmp_path / "device.toml"
    config.write_text(text)
    summary = tmp_path / "out.json"
    result = runner.invoke(app, ["track", "--config", str(config), "--summary", str(summary), *extra])
    assert result.exit_code == 0, result.output
    return json.loads(summary.read_text()), " ".join(result.output.split())


def test_track_writes_gain_and_drift_time_with_their_errors(tmp_path):
    summary, output = _run(tmp_path, PLATES, "--threads", "1")
    assert summary["gain"] == 1.0 and summary["gain_error"] == 0.0
    assert summary["drift_time"] > 0 and 0 < summary["drift_time_error"] < 0.1 * summary["drift_time"]
    assert summary["collector"] == "anode" and summary["primaries"] == 40 and summary["seed"] == 4
    assert summary["parameters"]["gap"] == 1e-4 and summary["parameters"]["geometry"] == "parallel-plate"
    assert abs(sum(summary["arrival_time_spectrum"]["counts"]) - 1.0) < 1e-12
    assert len(summary["current"]["edges"]) == len(summary["current"]["current"]) + 1
    assert "gain (electrons collected per primary)" in output
    # electrons drifting from the middle of the gap: the drift time is (gap/2) / W with W = e E / (mu nu) of the
    # Maxwell model (4 amu, k = 1e-13 m^3/s at N = 1e25; cold: 1/2 M W^2 = 3 meV), within 4 standard errors
    w = 1.602176634e-19 * 2e3 / (9.1093837e-31 / (1 + 9.1093837e-31 / (4 * 1.66053906660e-27)) * 1e25 * 1e-13)
    assert abs(summary["drift_time"] - 5e-5 / w) < 4 * summary["drift_time_error"]


def test_a_counter_with_ions_from_the_command_line_overrides(tmp_path):
    summary, _ = _run(tmp_path, COUNTER, "--voltage", "170", "--electrons", "4", "--seed", "9",
                      "--method", "path-length", "--out", str(tmp_path / "plots"))
    assert summary["collector"] == "wire" and summary["parameters"]["voltage"] == 170.0
    assert summary["primaries"] == 4 and summary["method"] == "path-length"
    assert summary["gain"] > 1.0 and summary["ionizations_per_primary"] == summary["gain"] - 1.0
    assert summary["ion_drift_time"] > summary["drift_time"]
    assert summary["profiles"]["coordinate"] == "radius"
    for name in ("tracks.png", "spectra.png"):
        assert (tmp_path / "plots" / name).stat().st_size > 1000


def test_a_resumed_run_gives_the_same_summary(tmp_path):
    """A run stopped after its first chunk (16 of 40 primaries saved) resumes and ends with the summary of an
    uninterrupted run: every primary draws from its own stream."""
    full, _ = _run(tmp_path, PLATES, "--threads", "2")
    parameters = TrackParameters.from_sections(
        {"gas": {"model": "maxwell", "density": 1e25, "temperature": 0.0},
         "geometry": {"kind": "parallel-plate", "gap": 1e-4, "voltage": 0.2},
         "source": {"electrons": 40, "position": [0.0, 0.0, 5e-5]}}, seed=4)
    window = full["current"]["edges"][-1]
    first = track(parameters.device(), primaries=16, position=(0.0, 0.0, 5e-5), energy=parameters.energy, seed=4,
                  signal_window=window)
    checkpoint = tmp_path / "run.npz"
    TrackRun(parameters, checkpoint=checkpoint, result=first, signal_window=window).save()
    assert TrackRun.resume(checkpoint).done == 16
    summary = tmp_path / "resumed.json"
    result = runner.invoke(app, ["track", "--resume", str(checkpoint), "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    resumed = json.loads(summary.read_text())
    for key in ("gain", "drift_time", "drift_time_error", "induced_charge", "arrival_time_spectrum", "current"):
        assert resumed[key] == full[key], key


def test_resuming_with_other_physics_is_refused(tmp_path):
    _run(tmp_path, PLATES, "--checkpoint", str(tmp_path / "c.npz"), "--electrons", "16")
    result = runner.invoke(app, ["track", "--resume", str(tmp_path / "c.npz"), "--voltage", "3"])
    assert result.exit_code == 2
    assert "differs from the checkpoint" in " ".join(result.output.split())


def test_a_device_file_with_an_unknown_key_is_refused(tmp_path):
    config = tmp_path / "device.toml"
    config.write_text(PLATES.replace("gap = 1e-4", "gap = 1e-4\nspacing = 2"))
    result = runner.invoke(app, ["track", "--config", str(config)])
    message = " ".join(result.output.split())
    assert result.exit_code == 2 and "unknown key 'spacing' in [geometry]" in message
    config.write_text(PLATES.replace("position = [0.0, 0.0, 5e-5]", "position = [0.0, 0.0, 5e-3]"))
    result = runner.invoke(app, ["track", "--config", str(config)])
    assert result.exit_code == 2 and "outside the device" in " ".join(result.output.split())


def test_a_sweep_gives_the_gain_against_the_voltage(tmp_path):
    """Lucas-Saelee (F = 1) between plates 0.3 mm apart at 1 atm: the gain grows with the voltage."""
    study = {"command": "track", "seed": 2, "replicas": 1,
             "fixed": {"model": "lucas_saelee", "gap": 3e-4, "electrons": 30, "position": [0.0, 0.0, 1e-5],
                       "energy": 5.0, "temperature": 0.0, "density": 2.45e25},
             "vary": {"voltage": [60.0, 90.0]}}
    with ThreadPoolExecutor(1) as pool:
        results = sweep.run_study(study, tmp_path, executor=pool)
    assert [record["status"] for record in results.records] == ["ok", "ok"]
    gains = [json.loads((tmp_path / "points" / f"p000{i}-r00" / "result.json").read_text())["summary"]["gain"]
             for i in range(2)]
    assert gains[1] > gains[0] > 0.0  # (some electrons diffuse back to the cathode: gains below 1 are possible)
    assert [float(row["gain"]) for row in results.table] == gains  # the study's table: gain against voltage
