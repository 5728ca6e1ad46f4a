"""The ``collisionkit sweep`` command: bad studies, a remote scheduler, failures, the issue's study, a killed client."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from collisionkit import edmd
from collisionkit.cli import app
from tests.sweep.helpers import SMALL_EDMD, dask_client, deadline, physics_columns, read_table, serial_run  # noqa: F401

runner = CliRunner()

ISSUE_STUDY = """\
command = "edmd"
replicas = 2
seed = 1
[fixed]
dim = 3
particles = 500
collisions = 20000
[vary]
packing-fraction = [0.1, 0.2, 0.3]
"""

ENCOUNTER_STUDY = """\
command = "encounter"
replicas = 2
seed = 3
[fixed]
rp = 1.0
[vary]
sep0 = [10.0, 0.5, 20.0]
"""


def invoke(*arguments):
    return runner.invoke(app, ["sweep", *map(str, arguments)], env={"COLUMNS": "200"})


def study_file(tmp_path: Path, text: str, name: str = "study.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def small_edmd_toml() -> str:
    fixed = "\n".join(f"{key} = {value}" for key, value in SMALL_EDMD["fixed"].items())
    return (
        f'command = "edmd"\nreplicas = {SMALL_EDMD["replicas"]}\nseed = {SMALL_EDMD["seed"]}\n'
        f"[fixed]\n{fixed}\n[vary]\npacking-fraction = {SMALL_EDMD['vary']['packing-fraction']}\n"
    )


def test_help_lists_the_command_and_its_options():
    assert "sweep" in runner.invoke(app, ["--help"]).output
    result = invoke("--help")
    assert result.exit_code == 0
    for text in ("--out", "--workers", "--scheduler", "--resume", "--summary", "STUDY"):
        assert text in result.output, text


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('command = "edmd"\nseed = 1\nreplica = 2\n[vary]\ndim = [2, 3]\n', "unknown study key 'replica'"),
        ('command = "nbody"\nseed = 1\n[vary]\ndim = [2, 3]\n', "unknown command 'nbody'"),
        ('command = "edmd"\nseed = 1\n[vary]\npacking = [0.1]\n', "has no option 'packing'"),
        ('command = "edmd"\nseed = 1\n[fixed]\nparticls = 100\n[vary]\ndim = [2]\n',
         "has no option 'particls'; did you mean 'particles'?"),
        ('command = "edmd"\nseed = 1\n[vary]\n', "at least one option"),
        ('command = "edmd"\nseed = 1\n[vary]\ndim = []\n', "empty list"),
        ('command = "edmd"\nseed = 1\nreplicas = 0\n[vary]\ndim = [2, 3]\n', "replicas must be in"),
        ('command = "edmd"\nseed = 1\nreplicas = "two"\n[vary]\ndim = [2, 3]\n', "replicas must be an integer"),
        ('command = "edmd"\nseed = 1\n[vary]\nseed = [1, 2]\n', "set by the sweep"),
        ('command = "edmd"\nseed = 1\n[vary\n', "not valid TOML"),
        # values each point's command would refuse: found before any point runs (they failed one by one)
        ('command = "edmd"\nseed = 1\n[vary]\ndim = [2, 5]\n', "the point {'dim': 5} is refused by 'collisionkit edmd'"),
        ('command = "edmd"\nseed = 1\n[fixed]\ndim = 2\n[vary]\npacking-fraction = [0.3, 0.8]\n', "packing_fraction"),
        ('command = "swarm"\nseed = 1\n[vary]\nparticles = [10]\n', "particles"),
        # rules between options, too: a 3D point above the 3D packing limit, fewer collisions than blocks
        ('command = "edmd"\nseed = 1\n[fixed]\npacking-fraction = 0.6\n[vary]\ndim = [2, 3]\n',
         "the point {'dim': 3} is refused by 'collisionkit edmd': packing_fraction must lie in (0, 0.5] for dim=3"),
        ('command = "edmd"\nseed = 1\n[fixed]\nblocks = 10\n[vary]\ncollisions = [100, 5]\n',
         "collisions must be >= blocks (10); got 5"),
        ('command = "edmd"\nseed = 1\n[fixed]\ninitial = "fcc"\n[vary]\nparticles = [32, 100]\n',
         "needs particles = 4 * cells^3"),
    ],
)
def test_bad_studies_exit_with_2_and_a_clear_message(tmp_path, text, message):
    result = invoke(study_file(tmp_path, text), "--out", tmp_path / "out")
    assert result.exit_code == 2, result.output
    assert message in " ".join(result.output.split()), result.output
    assert not (tmp_path / "out").exists()


def test_missing_study_and_bad_worker_options_exit_with_2(tmp_path):
    assert "study file not found" in invoke(tmp_path / "none.toml").output
    study = study_file(tmp_path, ENCOUNTER_STUDY)
    result = invoke(study, "--out", tmp_path / "a", "--workers", 0)
    assert result.exit_code == 2 and "--workers must be >= 1" in result.output
    result = invoke(study, "--out", tmp_path / "b", "--workers", 2, "--scheduler", "tcp://127.0.0.1:1")
    assert result.exit_code == 2 and "cannot be used with --scheduler" in result.output


def test_scheduler_runs_the_study_records_failures_and_resumes(tmp_path, dask_client):
    study, out, summary = study_file(tmp_path, ENCOUNTER_STUDY), tmp_path / "out", tmp_path / "summary.json"
    address = dask_client.scheduler.address
    with deadline(120):
        result = invoke(study, "--out", out, "--scheduler", address, "--summary", summary)
    assert result.exit_code == 1, result.output  # two runs (sep0 < rp) failed, the others finished
    assert "2 of 6 runs failed" in result.output and "sep0 must be >= rp" in result.output
    rows = read_table(out / "results.csv")
    assert [row["status"] for row in rows] == ["ok", "ok", "failed", "failed", "ok", "ok"]
    data = json.loads(summary.read_text())
    assert (data["runs"], data["ok"], data["failed"], data["skipped"]) == (6, 4, 2, 0)
    assert (out / "main_result.png").exists()
    with deadline(60):
        again = invoke(study, "--out", out, "--scheduler", address)
    assert again.exit_code == 2 and "already holds a study" in again.output
    with deadline(120):
        # the summary of the first try exists: replacing it takes --overwrite
        resumed = invoke("--resume", out / "checkpoint.npz", "--scheduler", address, "--summary", summary, "--overwrite")
    assert resumed.exit_code == 1
    assert json.loads(summary.read_text())["skipped"] == 4  # only the failed runs ran again


@pytest.mark.slow
def test_the_issue_study_on_an_embedded_cluster(tmp_path):
    out = tmp_path / "out"
    with deadline(300):
        result = invoke(study_file(tmp_path, ISSUE_STUDY), "--out", out, "--workers", 2)
    assert result.exit_code == 0, result.output
    rows = read_table(out / "results.csv")
    assert len(rows) == 6
    for column in ("packing-fraction", "replica", "seed", "compressibility_factor", "pressure", "collision_frequency"):
        assert column in rows[0], column
    assert [(row["packing-fraction"], row["replica"]) for row in rows] == [
        (eta, replica) for eta in ("0.1", "0.2", "0.3") for replica in ("0", "1")
    ]
    assert len({row["seed"] for row in rows}) == 6
    for row in rows:  # elastic hard spheres: Z within 5 % of Hansen-Goos
        eta = float(row["packing-fraction"])
        assert float(row["compressibility_factor"]) == pytest.approx(float(edmd.hansen_goos(eta)), rel=0.05)
    assert "compressibility_factor" in result.output and (out / "main_result.png").exists()


@pytest.mark.slow
def test_a_killed_client_resumes_to_the_serial_table(tmp_path, dask_client):
    study = study_file(tmp_path, small_edmd_toml())
    serial_run(study, tmp_path / "serial")
    out = tmp_path / "out"
    command = [sys.executable, "-c", "from collisionkit.cli import main; main()", "sweep", str(study), "--out", str(out)]
    command += ["--scheduler", dask_client.scheduler.address]
    client = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=os.environ.copy())
    try:
        with deadline(180):
            while len(list(out.glob("points/*/result.json"))) < 2 and client.poll() is None:
                time.sleep(0.05)
    finally:
        client.send_signal(signal.SIGKILL)
        client.wait(timeout=30)
    assert client.returncode == -signal.SIGKILL  # killed mid-study, not finished
    assert not (out / "results.csv").exists()
    with deadline(180):
        result = invoke("--resume", out / "checkpoint.npz", "--scheduler", dask_client.scheduler.address)
    assert result.exit_code == 0, result.output
    assert physics_columns(read_table(out / "results.csv")) == physics_columns(read_table(tmp_path / "serial" / "results.csv"))


@pytest.mark.parametrize(
    ("option", "where", "words"),
    [
        ("--out", "{file}", "--out {file} is a file, not a folder"),
        ("--out", "{file}/below", "cannot be written: {file} is a file"),
        ("--summary", "{file}/below.json", "cannot be written: {file} is a file"),
    ],
)
def test_an_output_that_cannot_be_written_exits_with_2_before_any_point_runs(tmp_path, option, where, words):
    # --out on a file gave a FileExistsError traceback (exit 1), below a file a NotADirectoryError
    taken = tmp_path / "taken"
    taken.write_text("x")
    arguments = ["--out", tmp_path / "out"] if option == "--summary" else []
    result = invoke(study_file(tmp_path, small_edmd_toml()), *arguments, option, where.format(file=taken))
    assert result.exit_code == 2, result.output
    assert words.format(file=taken) in " ".join(result.output.split())
    assert "Traceback" not in result.output
    assert taken.read_text() == "x" and not (tmp_path / "out").exists()


SWARM_STUDY = """\
command = "swarm"
seed = 3
replicas = 2
[fixed]
model = "reid"
particles = 640
tolerance = 0.05
collision-budget = 2e6
[vary]
E-N = [12.0, 24.0]
"""


def test_a_swarm_study_collects_mean_energy_and_drift_with_errors_and_draws_its_plot(tmp_path):
    # the study of the swarm command collected nothing: its summary nested the results in a list
    out = tmp_path / "out"
    with deadline(300):
        result = invoke(study_file(tmp_path, SWARM_STUDY), "--out", out, "--workers", 1)
    assert result.exit_code == 0, result.output
    rows = read_table(out / "results.csv")
    assert [(row["E-N"], row["replica"]) for row in rows] == [("12.0", "0"), ("12.0", "1"), ("24.0", "0"), ("24.0", "1")]
    for row in rows:
        for column in ("mean_energy", "mean_energy_error", "drift_velocity_bulk[2]", "drift_velocity_bulk_error[2]",
                       "diffusion_L_N", "diffusion_L_N_error"):
            assert float(row[column]) == float(row[column]), column  # a number, not empty or NaN
        assert float(row["drift_velocity_bulk[2]"]) < 0  # electrons drift against E (+z)
        assert 0 < float(row["mean_energy_error"]) < 0.05 * float(row["mean_energy"])
    assert float(rows[2]["mean_energy"]) > float(rows[0]["mean_energy"])  # hotter at the higher field
    # a list's element combines with its own error column (was: the scatter alone, beside a column
    # drift_velocity_bulk_error[2]_error)
    points = read_table(out / "points.csv")
    assert "drift_velocity_bulk_error[2]" in points[0] and not any(key.endswith("]_error") for key in points[0])
    own = [float(row["drift_velocity_bulk_error[2]"]) for row in rows[:2]]
    assert float(points[0]["drift_velocity_bulk_error[2]"]) >= 0.5 * min(own)  # not below what one replica knows
    assert (out / "main_result.png").stat().st_size > 1000
    assert "mean_energy" in " ".join(result.output.split())
    again = invoke("--resume", out / "checkpoint.npz", "--workers", 1)
    assert again.exit_code == 0 and "4 runs" in " ".join(again.output.split())
    refused = invoke(study_file(tmp_path, SWARM_STUDY), "--resume", out / "checkpoint.npz")
    assert refused.exit_code == 2 and "neither STUDY.toml nor --out" in " ".join(refused.output.split())


def test_a_study_whose_folder_takes_no_table_saves_it_elsewhere_and_exits_1(tmp_path, monkeypatch):
    # issue 16, item 1: results.csv failing at the end printed a traceback and lost the table
    from collisionkit.sweep import execute

    def full(study, out, table):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(execute, "write_outputs", full)
    monkeypatch.chdir(tmp_path)
    result = invoke(study_file(tmp_path, ENCOUNTER_STUDY), "--out", tmp_path / "study", "--workers", 1)
    said = " ".join(result.output.split())
    assert result.exit_code == 1 and "Traceback" not in result.output
    assert "No space left on device; every run's results are saved in" in said
    rescued = sorted(tmp_path.glob("collisionkit-sweep-results-*.csv"))
    assert len(rescued) == 1
    rows = read_table(rescued[0])
    assert len(rows) == 6 and [row["status"] for row in rows].count("failed") == 2  # sep0 = 0.5 < rp fails


GOOD_ENCOUNTERS = """\
command = "encounter"
seed = 3
[fixed]
rp = 1.0
[vary]
sep0 = [10.0, 20.0]
"""


def test_overwrite_starts_a_study_again_in_its_folder_and_with_resume_replaces_only_the_summary(tmp_path, dask_client):
    # sweep --overwrite stopped with "already holds a study", as without it
    study, out, summary = study_file(tmp_path, GOOD_ENCOUNTERS), tmp_path / "out", tmp_path / "summary.json"
    address = dask_client.scheduler.address
    with deadline(120):
        assert invoke(study, "--out", out, "--scheduler", address).exit_code == 0
    (out / "points" / "p0000-r00" / "output.log").write_text("an old failure")  # the sweep's own file: it goes
    (out / "points" / "p0000-r00" / "notes.txt").write_text("mine")  # not the sweep's: it stays
    refused = invoke(study, "--out", out, "--scheduler", address)
    said = " ".join(refused.output.split())
    assert refused.exit_code == 2 and "Traceback" not in refused.output
    assert f"already holds a study; resume it (resume_study('{out / 'checkpoint.npz'}'), --resume" in said
    assert "start it again there (overwrite=True, --overwrite) or use another folder" in said
    with deadline(120):
        again = invoke(study, "--out", out, "--scheduler", address, "--overwrite", "--summary", summary)
    assert again.exit_code == 0, again.output
    assert (json.loads(summary.read_text())["runs"], json.loads(summary.read_text())["skipped"]) == (2, 0)
    assert not (out / "points" / "p0000-r00" / "output.log").exists()
    assert (out / "points" / "p0000-r00" / "notes.txt").read_text() == "mine"
    assert len(read_table(out / "results.csv")) == 2
    with deadline(120):  # with --resume, --overwrite lets --summary be replaced; the study goes on, nothing reruns
        resumed = invoke("--resume", out / "checkpoint.npz", "--scheduler", address, "--summary", summary,
                         "--overwrite")
    assert resumed.exit_code == 0, resumed.output
    assert json.loads(summary.read_text())["skipped"] == 2


def test_overwrite_refuses_a_folder_whose_checkpoint_is_not_a_study(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "checkpoint.npz").write_bytes(b"a file of mine")
    result = invoke(study_file(tmp_path, GOOD_ENCOUNTERS), "--out", out, "--overwrite", "--workers", 1)
    said = " ".join(result.output.split())
    assert result.exit_code == 2 and "Traceback" not in result.output
    checkpoint = out / "checkpoint.npz"
    assert f"invalid study {tmp_path / 'study.toml'}: {checkpoint} holds no study that can be replaced" in said
    assert checkpoint.read_bytes() == b"a file of mine" and sorted(out.iterdir()) == [checkpoint]


INTERRUPTED_STUDY = """\
command = "edmd"
seed = 1
[fixed]
particles = 108
equilibration = 2000
blocks = 3
[vary]
collisions = [3000, 200000000]
"""


@pytest.mark.slow
def test_ctrl_c_on_the_embedded_cluster_prints_one_line_and_exits_130(tmp_path):
    # a terminal's Ctrl-C (SIGINT to the whole process group) printed Dask's warnings and the workers' tracebacks
    study, out = study_file(tmp_path, INTERRUPTED_STUDY), tmp_path / "out"
    command = [sys.executable, "-c", "from collisionkit.cli import main; main()", "sweep", str(study),
               "--out", str(out), "--workers", "1"]
    sweep = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                             start_new_session=True, env=os.environ.copy() | {"COLUMNS": "200"})
    try:
        with deadline(300):  # the second point runs (the first is saved): the cluster is up
            while not (out / "points" / "p0001-r00").exists() and sweep.poll() is None:
                time.sleep(0.05)
        os.killpg(sweep.pid, signal.SIGINT)
        _, stderr = sweep.communicate(timeout=60)
    finally:
        if sweep.poll() is None:
            os.killpg(sweep.pid, signal.SIGKILL)
            sweep.wait(timeout=30)
    assert sweep.returncode == 130, stderr
    assert f"warning: interrupted: finished points are saved; continue with --resume {out / 'checkpoint.npz'}" in stderr
    for noise in ("Traceback", "KeyboardInterrupt", "distributed.", "WARNING", "CancelledError"):
        assert noise not in stderr, stderr
    assert json.loads((out / "points" / "p0000-r00" / "result.json").read_text())["status"] == "ok"


def test_a_main_key_that_no_run_gives_is_named_with_the_closest_results(tmp_path):
    """A misspelled main key ran the whole study and printed '-' everywhere without a word; now a warning names the
    closest result keys (the run itself still succeeds: its tables are complete)."""
    study = ENCOUNTER_STUDY.replace("seed = 3\n", 'seed = 3\nmain = "eccentricty"\n').replace(
        "replicas = 2", "replicas = 1").replace("[10.0, 0.5, 20.0]", "[10.0, 20.0]")
    result = invoke(study_file(tmp_path, study), "--out", tmp_path / "out", "--workers", 1)
    assert result.exit_code == 0, result.output
    said = " ".join(result.output.split())
    assert "main 'eccentricty' is not a number in the results of collisionkit encounter" in said
    assert "did you mean 'orbit.eccentricity'" in said and not (tmp_path / "out" / "main_result.png").exists()


def test_a_swarm_study_at_a_pressure_tabulates_the_detector_coefficients(tmp_path):
    """A fixed pressure (Torr) gives each point the detector's columns (E in V/cm, drift in cm/us): 10 Td at 100
    Torr and 300 K is 32.19 V/cm, and the drift is the bulk drift times 1e-4; main may be one of them."""
    study = ('command = "swarm"\nseed = 3\nmain = "detector.drift_velocity"\n[fixed]\nmodel = "maxwell"\n'
             'particles = 400\ntolerance = 0.2\npressure = 100\ngas-temperature = 300\n[vary]\nE-N = [10.0, 20.0]\n')
    out = tmp_path / "out"
    with deadline(300):
        result = invoke(study_file(tmp_path, study), "--out", out, "--workers", 1)
    assert result.exit_code == 0, result.output
    rows = read_table(out / "results.csv")
    assert float(rows[0]["detector.field"]) == pytest.approx(10e-21 * 100 * 133.322368 / (1.380649e-23 * 300) / 100,
                                                             rel=1e-6)
    for row in rows:
        assert float(row["detector.drift_velocity"]) == pytest.approx(abs(float(row["drift_velocity_bulk[2]"])) * 1e-4,
                                                                      rel=1e-9)
    bad = invoke(study_file(tmp_path, study.replace("pressure = 100", 'pressure = "high"')), "--out", tmp_path / "o2")
    assert bad.exit_code == 2 and "option 'pressure' takes a float" in " ".join(bad.output.split())


def test_a_swarm_study_varies_the_field_in_volts_per_cm_at_a_pressure(tmp_path):
    """``E`` (V/cm) with a fixed pressure runs E/N = E / N, as the command's --E does: each row's E/N and its detector
    field come back from E (1000 V/cm at 760 Torr and 293.15 K is 3.99445 Td). E with E-N, or without a pressure, is
    refused in one line before any run."""
    study = ('command = "swarm"\nseed = 3\n[fixed]\nmodel = "maxwell"\nparticles = 300\ntolerance = 0.3\n'
             'pressure = 760\ngas-temperature = 293.15\n[vary]\nE = [1000, 2000]\n')
    out = tmp_path / "out"
    with deadline(300):
        result = invoke(study_file(tmp_path, study), "--out", out, "--workers", 1)
    assert result.exit_code == 0, result.output
    rows = read_table(out / "results.csv")
    assert [float(row["E"]) for row in rows] == [1000.0, 2000.0]
    assert [float(row["detector.field"]) for row in rows] == pytest.approx([1000.0, 2000.0], rel=1e-12)
    assert float(rows[0]["E_N"]) == pytest.approx(3.99445, rel=1e-5)
    both = invoke(study_file(tmp_path, study.replace("tolerance = 0.3\n", "tolerance = 0.3\nE-N = [5.0]\n")), "--out",
                  tmp_path / "o2")
    assert both.exit_code == 2 and "as E (V/cm, with pressure) or as E-N (Td), not both" in " ".join(both.output.split())
    alone = invoke(study_file(tmp_path, study.replace("pressure = 760\n", "")), "--out", tmp_path / "o3")
    assert alone.exit_code == 2 and "E (V/cm) needs a pressure (Torr)" in " ".join(alone.output.split())
