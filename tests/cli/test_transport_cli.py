"""Command line: ``collisionkit swarm`` and ``collisionkit slab``."""

import csv
import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from collisionkit.cli import app

runner = CliRunner()
DATA = Path(__file__).parent.parent / "data"


def test_swarm_sweep_writes_one_entry_per_e_n(tmp_path):
    summary = tmp_path / "swarm.json"
    result = runner.invoke(app, ["swarm", "--model", "reid", "--E-N", "12,24", "--particles", "640", "--seed", "3",
                                 "--tolerance", "0.02", "--collision-budget", "5e6", "--summary", str(summary),
                                 "--out", str(tmp_path / "plots")])
    assert result.exit_code == 0, result.output
    entries = json.loads(summary.read_text())["results"]
    assert [e["E_N"] for e in entries] == [12.0, 24.0]
    for entry in entries:
        for key in ("mean_energy", "diffusion_L_N", "diffusion_T_N", "collisions", "collisions_per_second"):
            assert isinstance(entry[key], (int, float))
        assert len(entry["drift_velocity_flux"]) == 3 and len(entry["drift_velocity_bulk"]) == 3
    assert entries[1]["mean_energy"] > entries[0]["mean_energy"]
    assert (tmp_path / "plots" / "transport_coefficients.png").stat().st_size > 1000
    # the same numbers as a table, a row per E/N, for spreadsheets and pandas
    with open(tmp_path / "plots" / "swarm.csv", newline="") as table:
        rows = list(csv.DictReader(table))
    assert [float(row["reduced_field"]) for row in rows] == [12.0, 24.0]
    for row, entry in zip(rows, entries):
        assert float(row["mean_energy"]) == entry["mean_energy"]
        assert float(row["drift_velocity_bulk_z"]) == entry["drift_velocity_bulk"][2]
        assert float(row["rate_coefficient[reid:excitation]"]) == entry["rate_coefficients"]["reid:excitation"]
    # and as BOLSIG+'s output tables (a static E): the mean energy section is the summary's
    from collisionkit.transport import read_bolsig_section

    energies = read_bolsig_section((tmp_path / "plots" / "bolsig.dat").read_text(), "Mean energy (eV)")
    assert energies[:, 0].tolist() == [12.0, 24.0]
    assert energies[:, 1] == pytest.approx([entry["mean_energy"] for entry in entries], rel=1e-6)


def test_swarm_reads_lxcat_and_a_toml_config(tmp_path):
    config = tmp_path / "swarm.toml"
    config.write_text(f'cross-sections = "{DATA / "lxcat_classic_reid.txt"}"\ne-n = [12.0]\nparticles = 640\n'
                      'tolerance = 0.05\ncollision-budget = 2e6\ngas-temperature = 300.0\nb-n = 100.0\n')
    summary = tmp_path / "s.json"
    result = runner.invoke(app, ["swarm", "--config", str(config), "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    (entry,) = json.loads(summary.read_text())["results"]
    assert entry["gas_temperature"] == 300.0 and entry["reduced_magnetic_field"] == 100.0
    assert abs(entry["drift_velocity_bulk"][0]) > 0  # E x B deflection


def test_swarm_bad_input_exits_with_2(tmp_path):
    assert runner.invoke(app, ["swarm", "--model", "reid", "--E-N", "-3"]).exit_code == 2
    assert runner.invoke(app, ["swarm", "--model", "argon"]).exit_code == 2
    assert runner.invoke(app, ["swarm"]).exit_code == 2  # no gas
    bad = runner.invoke(app, ["swarm", "--cross-sections", str(DATA / "lxcat_bad_negative.txt")])
    assert bad.exit_code == 2 and "line 8" in bad.output.replace("\n", "")


def test_slab_summary_has_transmission_reflection_and_errors(tmp_path):
    summary = tmp_path / "slab.json"
    result = runner.invoke(app, ["slab", "--thickness", "2", "--albedo", "1", "--incidence", "isotropic",
                                 "--particles", "20000", "--seed", "4", "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    data = json.loads(summary.read_text())
    assert abs(data["transmission"] + data["reflection"] - 1.0) < 1e-12
    assert data["transmission_error"] > 0 and data["reflection_error"] > 0
    assert runner.invoke(app, ["slab", "--albedo", "2"]).exit_code == 2
    assert runner.invoke(app, ["slab", "--incidence", "oblique"]).exit_code == 2


def test_swarm_warns_when_the_collision_budget_stops_a_run_before_the_tolerance(tmp_path):
    summary = tmp_path / "swarm.json"
    result = runner.invoke(app, ["swarm", "--model", "maxwell", "--E-N", "1", "--particles", "500",
                                 "--collision-budget", "1e5", "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    (entry,) = json.loads(summary.read_text())["results"]
    assert entry["converged"] is False
    output = " ".join(result.output.split())
    assert "warning: E/N = 1 Td stopped at the collision budget" in output
    assert "larger --collision-budget" in output


def test_swarm_and_slab_summaries_record_the_options(tmp_path):
    summary = tmp_path / "swarm.json"
    result = runner.invoke(app, ["swarm", "--model", "maxwell", "--E-N", "0", "--gas-temperature", "300",
                                 "--particles", "500", "--seed", "5", "--tolerance", "0.1", "--collision-budget", "1e5",
                                 "--sharing", "uniform", "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    parameters = json.loads(summary.read_text())["parameters"]  # rerun with SwarmParameters.from_mapping
    assert parameters["model"] == "maxwell" and parameters["reduced_field"] == [0.0]
    assert parameters["particles"] == 500 and parameters["seed"] == 5 and parameters["tolerance"] == 0.1
    assert parameters["collision_budget"] == 1e5 and parameters["sharing"] == "uniform"
    assert parameters["gas_temperature"] == 300.0
    slab_summary = tmp_path / "slab.json"
    result = runner.invoke(app, ["slab", "--thickness", "0.5", "--mass-ratio", "4", "--particles", "640",
                                 "--seed", "6", "--summary", str(slab_summary)])
    assert result.exit_code == 0, result.output
    parameters = json.loads(slab_summary.read_text())["parameters"]
    assert parameters == {"thickness": 0.5, "albedo": 1.0, "incidence": "normal", "model": "isotropic",
                          "mass_ratio": 4.0, "particles": 640, "seed": 6}


def test_a_slab_summary_s_parameters_read_back_as_the_same_parameters(tmp_path):
    from collisionkit.transport import SlabParameters

    summary = tmp_path / "slab.json"
    result = runner.invoke(app, ["slab", "--thickness", "0.5", "--particles", "640", "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    recorded = json.loads(summary.read_text())["parameters"]
    assert recorded["mass_ratio"] is None  # strict JSON has no Infinity
    assert SlabParameters.from_mapping(recorded) == SlabParameters(thickness=0.5, particles=640)
    assert SlabParameters.from_mapping(recorded).mass_ratio == float("inf")


def test_slab_refuses_options_the_rod_model_ignores():
    result = runner.invoke(app, ["slab", "--model", "rod", "--incidence", "isotropic"], env={"COLUMNS": "200"})
    assert result.exit_code == 2 and "rod model is one-dimensional" in " ".join(result.output.split())


def test_swarm_refuses_species_and_fractions_with_a_model_gas():
    # they choose gases of an LXCat file; with --model they were ignored in silence
    quick = ["--E-N", "1", "--particles", "128", "--collision-budget", "1e4"]
    for extra in (["--species", "Ar"], ["--fractions", "0.5"]):
        result = runner.invoke(app, ["swarm", "--model", "reid", *extra, *quick], env={"COLUMNS": "200"})
        assert result.exit_code == 2, result.output
        assert "--species, --fractions and --database pick gases from LXCat files (--cross-sections)" in result.output


def test_a_single_value_in_the_config_is_a_list_of_one(tmp_path):
    from collisionkit.cli._common import load_options
    from collisionkit.cli._transport import SwarmOptions

    config = tmp_path / "swarm.toml"
    config.write_text("E_N = 5\n")  # --E-N 5 works; the config said "Input should be a valid list"
    assert load_options(SwarmOptions, config, {"model": "reid"}).e_n == [5.0]
    config.write_text('species = "Ar"\nfractions = 1\n')
    options = load_options(SwarmOptions, config, {"cross_sections": DATA / "lxcat_classic_reid.txt"})
    assert options.species == ["Ar"] and options.fractions == [1.0]
    for value in ('"5"', "true", '["5"]', "[5, true]"):  # a string or a bool is not a number, in a list or not
        config.write_text(f"E_N = {value}\n")
        result = runner.invoke(app, ["swarm", "--model", "reid", "--config", str(config)], env={"COLUMNS": "200"})
        assert result.exit_code == 2, result.output
        assert "E-N must be a number or a list of numbers" in result.output  # as --E-N spells it


def test_swarm_at_zero_field_needs_a_warm_gas_and_then_converges_without_a_drift_tolerance(tmp_path):
    # E/N = 0 at 0 K has no steady state: a user's run took its whole 5e8-collision budget (25 min) for nothing
    result = runner.invoke(app, ["swarm", "--model", "reid", "--E-N", "0", "--gas-temperature", "0"],
                           env={"COLUMNS": "200"})
    assert result.exit_code == 2 and "no steady state" in " ".join(result.output.split())
    summary = tmp_path / "thermal.json"
    result = runner.invoke(app, ["swarm", "--model", "maxwell", "--E-N", "0", "--gas-temperature", "3000",
                                 "--particles", "500", "--tolerance", "0.02", "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    (entry,) = json.loads(summary.read_text())["results"]
    assert entry["converged"] is True  # the drift (zero by symmetry) had a relative tolerance it could never meet


SWEEP = ["swarm", "--model", "reid", "--E-N", "12,24", "--particles", "640", "--seed", "3", "--tolerance", "0.05",
         "--collision-budget", "2e6"]
WALL_CLOCK = ("seconds", "collisions_per_second")


def _physics(entry):
    return {key: value for key, value in entry.items() if key not in WALL_CLOCK}


def test_a_swarm_sweep_killed_mid_way_resumes_from_its_checkpoint_as_if_never_stopped(tmp_path, monkeypatch):
    straight = tmp_path / "straight.json"
    assert runner.invoke(app, [*SWEEP, "--summary", str(straight)]).exit_code == 0

    import collisionkit.transport.scan as scan
    from collisionkit._io import read_checkpoint

    real = scan.simulate_swarm

    def killed_at_24_td(gas, reduced_field, **options):
        if reduced_field == 24.0:
            raise KeyboardInterrupt  # the machine goes down during the second point
        return real(gas, reduced_field, **options)

    checkpoint = tmp_path / "sweep.npz"
    monkeypatch.setattr(scan, "simulate_swarm", killed_at_24_td)
    killed = runner.invoke(app, [*SWEEP, "--checkpoint", str(checkpoint)])
    assert killed.exit_code == 130  # as a shell reports Ctrl-C
    assert f"1 of 2 E/N points are saved in {checkpoint}" in killed.output.replace("\n", "")
    assert [entry["reduced_field"] for entry in read_checkpoint(checkpoint, "swarm").state["results"]] == [12.0]

    def only_the_unfinished_point(gas, reduced_field, **options):
        assert reduced_field == 24.0, "the finished 12 Td point was run again"
        return real(gas, reduced_field, **options)

    monkeypatch.setattr(scan, "simulate_swarm", only_the_unfinished_point)
    resumed_summary = tmp_path / "resumed.json"
    resumed = runner.invoke(app, ["swarm", "--resume", str(checkpoint), "--summary", str(resumed_summary)])
    assert resumed.exit_code == 0, resumed.output
    expected = [_physics(entry) for entry in json.loads(straight.read_text())["results"]]
    assert [_physics(entry) for entry in json.loads(resumed_summary.read_text())["results"]] == expected
    assert len(read_checkpoint(checkpoint, "swarm").state["results"]) == 2  # checkpoints went on to the same file


def test_a_swarm_sweep_killed_within_a_point_goes_on_from_its_saved_state(tmp_path, monkeypatch):
    straight = tmp_path / "straight.json"
    assert runner.invoke(app, [*SWEEP, "--summary", str(straight)]).exit_code == 0

    import collisionkit.transport.scan as scan

    monkeypatch.setattr(scan, "SAVE_EVERY", 0.0)  # save the running point after every chunk of samples
    save, running_saves = scan.SwarmScan.save, []

    def killed_after_two_saves_of_the_first_point(self, path=None):
        written = save(self, path)
        if self.running_point is not None:
            running_saves.append(self.running_point)
            if len(running_saves) == 2:
                raise KeyboardInterrupt  # Ctrl-C in the middle of the 12 Td point
        return written

    checkpoint = tmp_path / "sweep.npz"
    monkeypatch.setattr(scan.SwarmScan, "save", killed_after_two_saves_of_the_first_point)
    killed = runner.invoke(app, [*SWEEP, "--checkpoint", str(checkpoint)])
    monkeypatch.setattr(scan.SwarmScan, "save", save)
    assert killed.exit_code == 130 and running_saves == [0, 0]
    assert (f"0 of 2 E/N points are saved in {checkpoint}, and E/N = 12 Td as it was at its last save"
            in " ".join(killed.output.split()))
    resumed_summary = tmp_path / "resumed.json"
    resumed = runner.invoke(app, ["swarm", "--resume", str(checkpoint), "--summary", str(resumed_summary)])
    assert resumed.exit_code == 0, resumed.output
    assert f"E/N = 12 Td goes on from its state saved in {checkpoint}" in " ".join(resumed.output.split())
    expected = [_physics(entry) for entry in json.loads(straight.read_text())["results"]]
    assert [_physics(entry) for entry in json.loads(resumed_summary.read_text())["results"]] == expected


def test_a_resumed_swarm_sweep_keeps_its_physics_options(tmp_path):
    checkpoint = tmp_path / "sweep.npz"
    assert runner.invoke(app, [*SWEEP[:4], "12", *SWEEP[5:], "--checkpoint", str(checkpoint)]).exit_code == 0
    changed = runner.invoke(app, ["swarm", "--resume", str(checkpoint), "--particles", "1280"])
    assert changed.exit_code == 2 and "particles" in changed.output and "differs" in changed.output
    not_a_checkpoint = tmp_path / "other.json"
    not_a_checkpoint.write_text('{"results": []}')
    refused = runner.invoke(app, ["swarm", "--resume", str(not_a_checkpoint)])
    assert refused.exit_code == 2 and "not a checkpoint" in refused.output
    missing = runner.invoke(app, ["swarm", "--resume", str(tmp_path / "missing.json")])
    assert missing.exit_code == 2 and "not found" in missing.output
    same = runner.invoke(app, [*SWEEP, "--checkpoint", str(checkpoint), "--summary", str(checkpoint)])
    assert same.exit_code == 2 and "same file" in same.output


def test_a_resumed_lxcat_sweep_finds_its_file_from_anywhere_and_refuses_a_changed_one(tmp_path, monkeypatch):
    gas_file = tmp_path / "gas.txt"
    gas_file.write_bytes((DATA / "lxcat_classic_reid.txt").read_bytes())
    monkeypatch.chdir(tmp_path)
    options = ["--cross-sections", "gas.txt", "--particles", "640", "--seed", "3", "--tolerance", "0.05",
               "--collision-budget", "2e6"]
    assert runner.invoke(app, ["swarm", *options, "--E-N", "12", "--checkpoint", "ck.npz"]).exit_code == 0
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    same = runner.invoke(app, ["swarm", "--resume", str(tmp_path / "ck.npz"), "--cross-sections", str(gas_file)])
    assert same.exit_code == 0, same.output  # a relative path given then, the same file by another name now
    gas_file.write_text(gas_file.read_text().replace("6.000000e-20", "5.000000e-20"))
    changed = runner.invoke(app, ["swarm", "--resume", str(tmp_path / "ck.npz")])
    assert changed.exit_code == 2 and "has changed" in " ".join(changed.output.split())  # any terminal width


def test_a_new_sweep_does_not_overwrite_an_existing_checkpoint(tmp_path):
    checkpoint = tmp_path / "sweep.npz"
    assert runner.invoke(app, [*SWEEP[:4], "12", *SWEEP[5:], "--checkpoint", str(checkpoint)]).exit_code == 0
    saved = checkpoint.read_bytes()
    again = runner.invoke(app, [*SWEEP, "--checkpoint", str(checkpoint)])  # --resume forgotten
    assert again.exit_code == 2 and f"--resume {checkpoint}" in again.output.replace("\n", "")
    assert checkpoint.read_bytes() == saved


def test_ctrl_c_stops_a_slab_run_with_exit_130_and_says_nothing_is_saved(monkeypatch):
    # typer ended an interrupted slab run with 130 and no word
    from collisionkit.transport import SlabRun

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(SlabRun, "run", interrupted)
    result = runner.invoke(app, ["slab", "--thickness", "1", "--particles", "1000"])
    assert result.exit_code == 130
    assert ("warning: interrupted after 0 of 1000 histories: no --checkpoint was given, so nothing is saved"
            in " ".join(result.output.split()))


def test_a_slab_run_interrupted_resumes_from_its_checkpoint_as_if_never_stopped(tmp_path, monkeypatch):
    options = ["--thickness", "8", "--albedo", "0.9", "--particles", "40000", "--seed", "4"]
    whole = runner.invoke(app, ["slab", *options, "--summary", str(tmp_path / "whole.json")])
    assert whole.exit_code == 0, whole.output
    from tests.transport.slab_helpers import interrupt_after

    interrupt_after(monkeypatch, 60)
    checkpoint = tmp_path / "slab.npz"
    first = runner.invoke(app, ["slab", *options, "--checkpoint", str(checkpoint)])
    assert first.exit_code == 130 and f"continue with --resume {checkpoint}" in " ".join(first.output.split())
    monkeypatch.undo()
    other = runner.invoke(app, ["slab", "--resume", str(checkpoint), "--albedo", "0.5"])
    assert other.exit_code == 2 and "albedo = 0.5 differs from the checkpoint" in " ".join(other.output.split())
    resumed = runner.invoke(app, ["slab", "--resume", str(checkpoint), "--summary", str(tmp_path / "part.json")])
    assert resumed.exit_code == 0, resumed.output
    assert "going on from" in resumed.output
    a, b = (json.loads((tmp_path / name).read_text()) for name in ("whole.json", "part.json"))
    assert {k: v for k, v in a.items() if k != "files"} == {k: v for k, v in b.items() if k != "files"}


def test_swarm_at_zero_field_relaxes_to_the_default_gas_temperature_of_300_k(tmp_path):
    """--E-N 0 is a valid run by default: the swarm thermalises at 300 K, <e> = 3/2 kT within 4 standard errors
    (a Maxwell gas of light targets relaxes in a few collisions)."""
    from scipy import constants

    config = tmp_path / "thermal.toml"
    config.write_text('model = "maxwell"\ne-n = 0\nparticles = 500\ntolerance = 0.01\n')
    summary = tmp_path / "thermal.json"
    result = runner.invoke(app, ["swarm", "--config", str(config), "--summary", str(summary)], env={"COLUMNS": "200"})
    assert result.exit_code == 0, result.output
    entry = json.loads(summary.read_text())
    assert entry["gas_temperature"] == 300.0 and entry["converged"] is True
    thermal = 1.5 * constants.k * 300.0 / constants.e
    assert abs(entry["mean_energy"] - thermal) < 4 * entry["mean_energy_error"]
    assert entry["alpha_N"] == 0.0 and entry["eta_N"] == 0.0


def test_swarm_prints_and_writes_the_sst_townsend_coefficients(tmp_path):
    summary = tmp_path / "ls.json"
    result = runner.invoke(app, ["swarm", "--model", "lucas_saelee", "--E-N", "300", "--particles", "640",
                                 "--tolerance", "0.05", "--collision-budget", "3e6", "--summary", str(summary)],
                           env={"COLUMNS": "220"})
    assert result.exit_code == 0, result.output
    entry = json.loads(summary.read_text())
    assert entry["alpha_N"] > 0 and 0 < entry["alpha_N_error"] < entry["alpha_N"] and entry["eta_N"] == 0.0
    output = " ".join(result.output.split())
    assert "alpha/N (m^2)" in output and "eta/N (m^2)" in output
    assert f"{entry['alpha_N']:.4g} ± {entry['alpha_N_error']:.2g}" in output


def test_swarm_takes_a_scattering_law_for_every_process_or_per_kind_and_populations_from_a_config(tmp_path):
    summary = tmp_path / "s.json"
    quick = ["--E-N", "50", "--particles", "640", "--tolerance", "0.05", "--collision-budget", "2e6"]
    result = runner.invoke(app, ["swarm", "--model", "reid", "--scattering", "okhrimovskyy", *quick,
                                 "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    assert json.loads(summary.read_text())["parameters"]["scattering"] == "okhrimovskyy"
    config = tmp_path / "laws.toml"
    config.write_text('model = "reid"\n[scattering]\nelastic = "vahedi-surendra"\nexcitation = "forward"\n')
    result = runner.invoke(app, ["swarm", "--config", str(config), *quick, "--summary", str(summary), "--overwrite"])
    assert result.exit_code == 0, result.output
    recorded = json.loads(summary.read_text())["parameters"]
    assert recorded["scattering"] == {"elastic": "vahedi-surendra", "excitation": "forward"}
    # a population needs a reversible excitation: Reid's ramp has none, and the message lists the choices
    config.write_text('model = "reid"\n[populations]\n"reid:excitation" = 0.1\n')
    result = runner.invoke(app, ["swarm", "--config", str(config), *quick], env={"COLUMNS": "200"})
    assert result.exit_code == 2
    assert "'reid:excitation' is not a reversible excitation of the gas" in " ".join(result.output.split())


def test_a_scattering_law_can_be_swept_and_a_refused_one_names_the_point(tmp_path):
    from collisionkit.sweep import Study
    from collisionkit.sweep.tasks import point_tasks
    from collisionkit.transport import SwarmParameters

    fixed = {"model": "reid", "particles": 640, "E-N": 50.0}
    study = Study("swarm", seed=1, fixed=fixed, vary={"scattering": ["isotropic", "vahedi-surendra"]})
    laws = [SwarmParameters.from_mapping(task.options).make_gas().species[0].processes[0].scattering
            for task in point_tasks(study, tmp_path)]
    assert laws == ["isotropic", "vahedi-surendra"]
    with pytest.raises(ValueError, match="scattering must be one of"):
        point_tasks(Study("swarm", seed=1, fixed=fixed, vary={"scattering": ["isotropic", "bent"]}), tmp_path)


def test_swarm_in_an_oblique_ac_field_prints_cycle_averages_and_plots_the_phases(tmp_path):
    """--omega-N with --B-N at --angle: the summary keys of issue 20, the component table and phase.png."""
    summary = tmp_path / "ac.json"
    result = runner.invoke(app, ["swarm", "--model", "maxwell", "--E-N", "10", "--B-N", "100", "--angle", "30",
                                 "--omega-N", "1e-13", "--gas-temperature", "0", "--particles", "640",
                                 "--tolerance", "0.05", "--collision-budget", "2e6", "--summary", str(summary),
                                 "--out", str(tmp_path / "plots")])
    assert result.exit_code == 0, result.output
    text = " ".join(result.output.split())
    assert "cycle averages" in text and "at 30 deg" in text
    data = json.loads(summary.read_text())
    assert data["field_angle"] == 30.0 and data["reduced_frequency"] == 1e-13
    assert data["parameters"]["field_angle"] == 30.0 and data["parameters"]["reduced_frequency"] == 1e-13
    assert len(data["phases"]) == 16 and len(data["mean_energy_by_phase"]) == 16
    assert all(len(row) == 3 for row in data["drift_velocity_flux_by_phase"])
    for key in ("diffusion_N_flux", "diffusion_N_bulk", "diffusion_N_flux_error", "diffusion_N_bulk_error"):
        assert [len(row) for row in data[key]] == [3, 3, 3]
    assert len(data["drift_velocity_flux"]) == 3 and len(data["drift_velocity_bulk_error"]) == 3
    assert (tmp_path / "plots" / "phase.png").stat().st_size > 1000
    assert not (tmp_path / "plots" / "bolsig.dat").exists()  # BOLSIG+'s tables hold a static E alone


def test_the_angle_and_frequency_come_from_a_toml_file_resume_and_sweep(tmp_path):
    config = tmp_path / "swarm.toml"
    config.write_text('model = "maxwell"\ne-n = [10.0, 20.0]\nb-n = 200.0\nangle = 45.0\nomega-N = 5e-14\n'
                      'particles = 640\ntolerance = 0.05\ncollision-budget = 1e6\ngas-temperature = 0.0\n')
    checkpoint = tmp_path / "ck.npz"
    first = runner.invoke(app, ["swarm", "--config", str(config), "--checkpoint", str(checkpoint)])
    assert first.exit_code == 0, first.output
    changed = runner.invoke(app, ["swarm", "--resume", str(checkpoint), "--angle", "30"])
    assert changed.exit_code == 2 and "differs" in changed.output
    summary = tmp_path / "s.json"
    again = runner.invoke(app, ["swarm", "--resume", str(checkpoint), "--angle", "45", "--summary", str(summary)])
    assert again.exit_code == 0, again.output
    entries = json.loads(summary.read_text())["results"]
    assert [entry["field_angle"] for entry in entries] == [45.0, 45.0]
    assert all(len(entry["phases"]) == 16 for entry in entries)

    from collisionkit.sweep import Study, sweep_command
    from collisionkit.sweep.tasks import point_tasks
    from collisionkit.transport import SwarmParameters

    assert {"angle", "omega-N"} <= set(sweep_command("swarm").options())
    study = Study("swarm", seed=1, fixed={"model": "maxwell", "particles": 640, "B-N": 100.0},
                  vary={"angle": [0.0, 60.0], "omega-N": [0.0, 1e-13]})
    points = [SwarmParameters.from_mapping(task.options) for task in point_tasks(study, tmp_path / "study")]
    assert sorted((p.field_angle, p.reduced_frequency) for p in points) == [(0.0, 0.0), (0.0, 1e-13), (60.0, 0.0),
                                                                            (60.0, 1e-13)]
    with pytest.raises(ValueError, match="field_angle"):
        point_tasks(Study("swarm", seed=1, fixed={"model": "maxwell"}, vary={"angle": [0.0, 270.0]}), tmp_path / "x")


def test_a_waveform_file_or_toml_samples_drive_the_swarm_and_resume(tmp_path):
    """--waveform FILE (two columns) and waveform = [[u, f], ...] in TOML: the same samples in the parameters, the
    summary and the checkpoint; a resumed run keeps them; bad samples exit 2 naming the option."""
    wave = tmp_path / "square.txt"
    wave.write_text("# phase fraction, E/E0\n0 1\n0.5 1\n0.5 -1\n1 -1\n")
    summary = tmp_path / "w.json"
    checkpoint = tmp_path / "ck.npz"
    quick = ["--model", "maxwell", "--E-N", "10", "--omega-N", "1e-13", "--gas-temperature", "0", "--particles",
             "640", "--tolerance", "0.05", "--collision-budget", "1e6"]
    result = runner.invoke(app, ["swarm", *quick, "--waveform", str(wave), "--summary", str(summary),
                                 "--checkpoint", str(checkpoint)])
    assert result.exit_code == 0, result.output
    square = [[0.0, 1.0], [0.5, 1.0], [0.5, -1.0], [1.0, -1.0]]
    data = json.loads(summary.read_text())
    assert data["parameters"]["waveform"] == square and len(data["phases"]) == 16
    resumed = runner.invoke(app, ["swarm", "--resume", str(checkpoint), "--summary", str(tmp_path / "again.json")])
    assert resumed.exit_code == 0, resumed.output
    assert json.loads((tmp_path / "again.json").read_text())["parameters"]["waveform"] == square
    config = tmp_path / "swarm.toml"
    config.write_text('model = "maxwell"\ne-n = 10.0\nomega-N = 1e-13\nwaveform = [[0.0, 1.0], [0.5, 1.0], [0.5, -1.0], '
                      '[1.0, -1.0]]\nparticles = 640\ntolerance = 0.05\ncollision-budget = 1e6\ngas-temperature = 0.0\n')
    toml_summary = tmp_path / "t.json"
    result = runner.invoke(app, ["swarm", "--config", str(config), "--summary", str(toml_summary)])
    assert result.exit_code == 0, result.output
    assert json.loads(toml_summary.read_text())["parameters"]["waveform"] == square
    config.write_text('model = "maxwell"\nomega-N = 1e-13\nwaveform = [[0.5, 1.0], [0.2, 1.0]]\n')
    refused = runner.invoke(app, ["swarm", "--config", str(config)])
    assert refused.exit_code == 2 and "non-decreasing" in " ".join(refused.output.split())


def test_a_waveform_with_oblique_b_runs_from_options_and_toml_and_resumes_as_if_never_stopped(tmp_path, monkeypatch):
    """--waveform FILE with --B-N and --angle: the field in the parameters and in each result; a two-point sweep
    killed at its second point resumes to the straight run's results (the same seeds, the same field); a TOML file
    gives the first point's run."""
    wave = tmp_path / "square.txt"
    wave.write_text("0 1\n0.5 1\n0.5 -1\n1 -1\n")
    options = ["swarm", "--model", "maxwell", "--E-N", "10,12", "--omega-N", "1e-13", "--waveform", str(wave),
               "--B-N", "300", "--angle", "60", "--gas-temperature", "0", "--particles", "640", "--seed", "5",
               "--tolerance", "0.05", "--collision-budget", "1e6"]
    straight = tmp_path / "straight.json"
    result = runner.invoke(app, [*options, "--summary", str(straight)])
    assert result.exit_code == 0, result.output
    summary = json.loads(straight.read_text())
    square = [[0.0, 1.0], [0.5, 1.0], [0.5, -1.0], [1.0, -1.0]]
    assert summary["parameters"]["waveform"] == square and summary["parameters"]["reduced_magnetic_field"] == 300.0
    expected = [_physics(entry) for entry in summary["results"]]
    assert [(entry["reduced_magnetic_field"], entry["field_angle"]) for entry in expected] == [(300.0, 60.0)] * 2
    assert all(entry["extras"]["waveform"] == square and len(entry["phases"]) == 16 for entry in expected)

    import collisionkit.transport.scan as scan

    real = scan.simulate_swarm

    def killed_at_12_td(gas, reduced_field, **settings):
        if reduced_field == 12.0:
            raise KeyboardInterrupt
        return real(gas, reduced_field, **settings)

    checkpoint = tmp_path / "sweep.npz"
    monkeypatch.setattr(scan, "simulate_swarm", killed_at_12_td)
    assert runner.invoke(app, [*options, "--checkpoint", str(checkpoint)]).exit_code == 130
    monkeypatch.setattr(scan, "simulate_swarm", real)
    resumed = tmp_path / "resumed.json"
    result = runner.invoke(app, ["swarm", "--resume", str(checkpoint), "--summary", str(resumed)])
    assert result.exit_code == 0, result.output
    assert [_physics(entry) for entry in json.loads(resumed.read_text())["results"]] == expected
    config = tmp_path / "swarm.toml"
    config.write_text(f'model = "maxwell"\ne-n = 10.0\nomega-N = 1e-13\nwaveform = "{wave}"\nB-N = 300.0\n'
                      'angle = 60.0\ngas-temperature = 0.0\nparticles = 640\nseed = 5\ntolerance = 0.05\n'
                      'collision-budget = 1e6\n')
    from_toml = tmp_path / "toml.json"
    result = runner.invoke(app, ["swarm", "--config", str(config), "--summary", str(from_toml)])
    assert result.exit_code == 0, result.output
    single = json.loads(from_toml.read_text())
    assert single["parameters"]["waveform"] == square and single["parameters"]["field_angle"] == 60.0
    assert _physics(single["results"][0]) == expected[0]


def test_the_component_table_gives_every_component_with_its_error():
    """Issue 20's components in a field with B: drifts and tensor elements each with its error (an AC cycle average
    of a small drift component can be all noise), one row per quantity; N D_T gives way to the tensor."""
    from types import SimpleNamespace

    from collisionkit.cli._transport import _field_rows, _swarm_row

    tensor = np.arange(9.0).reshape(3, 3) * 1e22
    result = SimpleNamespace(
        reduced_field=12.0, mean_energy=0.22, mean_energy_error=3e-4, drift_velocity_bulk=np.array([-3e4, 68.07, -4e4]),
        drift_velocity_bulk_error=np.array([70.0, 60.0, 50.0]), drift_velocity_flux=np.array([-3.1e4, 1.0, -4.1e4]),
        drift_velocity_flux_error=np.array([71.0, 61.0, 51.0]), diffusion_N_bulk=tensor,
        diffusion_N_bulk_error=tensor / 10, diffusion_L_N=4e23, diffusion_L_N_error=1e22, diffusion_T_N=5e23, diffusion_T_N_error=2e22, alpha_N=0.0,
        alpha_N_error=0.0, eta_N=0.0, eta_N_error=0.0, collisions_per_second=1e6)
    rows = _field_rows([result])
    assert [row[1] for row in rows] == ["W bulk (m/s)", "W flux (m/s)", "N D bulk, diagonal (1/m/s)",
                                        "N D bulk, off-diagonal (1/m/s)"]
    assert rows[0][2:] == ("-3e+04 ± 70", "68.07 ± 60", "-4e+04 ± 50")
    assert rows[2][2:] == ("0 ± 0", "4e+22 ± 4e+21", "8e+22 ± 8e+21")
    assert rows[3][2:] == ("5e+22 ± 5e+21", "1e+22 ± 1e+21", "2e+22 ± 2e+21")  # yz, xy, xz
    assert _swarm_row(result, magnetic=True)[4] == "see below"
    assert _swarm_row(result)[4] == "5e+23 ± 2e+22"


def test_an_angle_without_b_is_noted():
    result = runner.invoke(app, ["swarm", "--model", "maxwell", "--E-N", "10", "--angle", "30", "--gas-temperature", "0",
                                 "--particles", "640", "--tolerance", "0.1", "--collision-budget", "1e5"])
    assert result.exit_code == 0, result.output
    assert "note: --angle 30 has no effect without --B-N" in " ".join(result.output.split())


@pytest.mark.parametrize("command", [
    ["swarm", "--particles", "128", "--tolerance", "0.5", "--collision-budget", "1e4"],
    ["boltzmann"],
])
def test_a_gas_chosen_on_the_command_line_replaces_the_config_files_gas(tmp_path, command):
    # model = "reid" in a config and --gas Ar on the command line: "give exactly one of model, gas and cross_sections"
    config, summary = tmp_path / "run.toml", tmp_path / "s.json"
    config.write_text('model = "reid"\nspecies = ["N2"]\nfractions = [1.0]\ndatabase = "Biagi"\nE-N = [10]\n')
    result = runner.invoke(app, [*command, "--config", str(config), "--gas", "Ar", "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    assert json.loads(summary.read_text())["gas"] == "Ar"
    config.write_text('gas = "Ar"\nE-N = [10]\n')  # and the other way round
    result = runner.invoke(app, [*command, "--config", str(config), "--model", "reid", "--summary", str(summary),
                                 "--overwrite"])
    assert result.exit_code == 0, result.output
    assert json.loads(summary.read_text())["gas"] == "reid"
    both = runner.invoke(app, [*command, "--model", "reid", "--gas", "Ar"])  # both on the command line: still refused
    assert both.exit_code == 2 and "give exactly one of" in both.output


def test_files_on_the_command_line_replace_the_config_files_files_with_their_species_only(tmp_path):
    # the config's species picked from its own files; species in a config without files pick from the command line's
    from collisionkit.cli._common import load_options
    from collisionkit.cli._transport import SwarmOptions

    config, reid = tmp_path / "run.toml", DATA / "lxcat_classic_reid.txt"
    config.write_text(f'cross-sections = "{tmp_path / "other.txt"}"\nspecies = ["N2"]\nfractions = [1.0]\n'
                      'database = "Biagi"\n')
    options = load_options(SwarmOptions, config, {"cross_sections": [reid]})
    assert (options.cross_sections, options.species, options.fractions, options.database) == ([reid], None, None, None)
    config.write_text('model = "reid"\nspecies = ["Ar"]\n')
    options = load_options(SwarmOptions, config, {"cross_sections": [reid]})
    assert (options.model, options.cross_sections, options.species) == (None, [reid], ["Ar"])


@pytest.mark.parametrize("command", ["swarm", "boltzmann"])
def test_the_fractions_help_gives_the_default(command):
    import re

    shown = re.sub(r"[│\s]+", " ", runner.invoke(app, [command, "--help"]).output)  # the help's box, folded lines
    assert "--fractions <list[float]> Their number fractions (repeat), one per species. [default: equal fractions]" \
        in shown, shown


@pytest.mark.parametrize("command", ["swarm", "boltzmann"])
def test_fractions_that_do_not_match_the_files_species_are_named_as_the_option(tmp_path, command):
    import collisionkit.transport

    data = Path(collisionkit.transport.__file__).parent / "data"
    both = ["--cross-sections", str(data / "IST-Lisbon_N2.txt"), "--cross-sections", str(data / "IST-Lisbon_Ar.txt"),
            "--fractions", "0.9"]
    result = runner.invoke(app, [command, *both])
    assert result.exit_code == 2 and "error: --fractions: give one per species" in result.output, result.output


def test_a_scan_in_a_detector_s_units_from_volts_per_cm_at_a_pressure(tmp_path):
    """--E in V/cm with --pressure in Torr: the E/N run are E / N (here 1000 V/cm at 760 Torr, 293.15 K: 3.99445
    Td); the table, each point's summary ``detector`` and detector.csv give the field back in V/cm with the drift in
    cm/us (the bulk drift times 1e-4)."""
    out, summary = tmp_path / "out", tmp_path / "s.json"
    result = runner.invoke(app, ["swarm", "--model", "maxwell", "--E", "1000,2000", "--pressure", "760",
                                 "--gas-temperature", "293.15", "--particles", "500", "--tolerance", "0.2",
                                 "--out", str(out), "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    data = json.loads(summary.read_text())
    points = data["results"]
    assert [round(point["reduced_field"], 4) for point in points] == [3.9944, 7.9889]
    assert [point["detector"]["field"] for point in points] == pytest.approx([1000.0, 2000.0], rel=1e-12)
    assert points[0]["detector"]["drift_velocity"] == pytest.approx(abs(points[0]["drift_velocity_bulk"][2]) * 1e-4,
                                                                    rel=1e-12)
    with (out / "detector.csv").open() as handle:
        rows = list(csv.reader(handle))
    assert rows[0][:2] == ["field (V/cm)", "drift_velocity (cm/us)"] and float(rows[1][0]) == pytest.approx(1000.0)
    assert "in a detector's units: 760 Torr, 293.15 K" in " ".join(result.output.split())


def test_detector_options_from_a_config_file_and_the_command_line(tmp_path):
    """A config's ``E = "1000:2000:2"`` (the --E-N forms) with ``pressure``; --E on the command line replaces the
    config's E-N; a pressure given as text is refused in one line; a later run without --pressure removes an
    earlier run's detector.csv from --out."""
    config = tmp_path / "det.toml"
    config.write_text('model = "maxwell"\nE = "1000:2000:2"\npressure = 760\ngas-temperature = 293.15\n'
                      'particles = 300\ntolerance = 0.3\n')
    out = tmp_path / "out"
    first = runner.invoke(app, ["swarm", "--config", str(config), "--out", str(out), "--summary", str(tmp_path / "a.json")])
    assert first.exit_code == 0, first.output
    points = json.loads((tmp_path / "a.json").read_text())["results"]
    assert [round(point["reduced_field"], 4) for point in points] == [3.9944, 7.9889]
    assert (out / "detector.csv").exists()
    config.write_text('model = "maxwell"\nE-N = [5]\npressure = 760\nparticles = 300\ntolerance = 0.3\n')
    replaced = runner.invoke(app, ["swarm", "--config", str(config), "--E", "1000", "--summary", str(tmp_path / "b.json")])
    assert replaced.exit_code == 0, replaced.output
    assert json.loads((tmp_path / "b.json").read_text())["results"][0]["detector"]["field"] == pytest.approx(1000.0)
    config.write_text('model = "maxwell"\nE = [1000]\npressure = "760"\n')
    text = runner.invoke(app, ["swarm", "--config", str(config)])
    assert text.exit_code == 2 and "--pressure must be a number; got '760'" in text.output
    again = runner.invoke(app, ["swarm", "--model", "maxwell", "--E-N", "3", "--particles", "300", "--tolerance", "0.3",
                                "--out", str(out), "--overwrite"])
    assert again.exit_code == 0, again.output
    assert not (out / "detector.csv").exists() and (out / "swarm.csv").exists()


def test_a_resumed_scan_keeps_its_detector_pressure_and_takes_a_new_one(tmp_path):
    """The checkpoint keeps --pressure: --resume without it gives the same detector table (and says so); a
    --pressure given with --resume replaces it (the table scales as the number density, W in cm/us unchanged)."""
    checkpoint = tmp_path / "scan.npz"
    first = runner.invoke(app, ["swarm", "--model", "maxwell", "--E", "1000", "--pressure", "760", "--particles",
                                "300", "--tolerance", "0.3", "--checkpoint", str(checkpoint), "--summary",
                                str(tmp_path / "a.json")])
    assert first.exit_code == 0, first.output
    kept = runner.invoke(app, ["swarm", "--resume", str(checkpoint), "--summary", str(tmp_path / "b.json")])
    assert kept.exit_code == 0, kept.output
    assert "--pressure 760 Torr, as the scan was started with" in " ".join(kept.output.split())
    before, after = (json.loads((tmp_path / name).read_text())["results"][0]["detector"] for name in ("a.json", "b.json"))
    assert after == before
    halved = runner.invoke(app, ["swarm", "--resume", str(checkpoint), "--pressure", "380", "--summary",
                                 str(tmp_path / "c.json")])
    assert halved.exit_code == 0, halved.output
    table = json.loads((tmp_path / "c.json").read_text())["results"][0]["detector"]
    assert table["field"] == pytest.approx(500.0, rel=1e-12) and table["pressure_torr"] == 380.0
