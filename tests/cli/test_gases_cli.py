"""``collisionkit gases`` and ``collisionkit swarm --gas``: real gases by name from the shell, a TOML file and a sweep."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from collisionkit.cli import app
from collisionkit.transport import catalogue_gas, data_folder, simulate_swarm

runner = CliRunner()
DATA = Path(__file__).parent.parent / "data"
QUICK = ["--E-N", "100", "--particles", "640", "--seed", "3", "--tolerance", "0.05", "--collision-budget", "2e6"]


def _said(result) -> str:
    return " ".join(result.output.split())


def test_gases_lists_the_catalogue_with_status_and_where_to_get_what_is_missing(tmp_path):
    summary = tmp_path / "gases.json"
    result = runner.invoke(app, ["gases", "--summary", str(summary)], env={"COLUMNS": "200"})
    assert result.exit_code == 0, result.output
    said = _said(result)
    for name, processes, status in (("Ar", "1 elastic, 37 excitation, 1 ionization", "shipped"),
                                    ("O2", "1 elastic, 11 excitation, 1 ionization, 1 attachment", "shipped"),
                                    ("N2-Phelps", "-", "missing")):
        assert f"{name} " in said and processes in said and status in said
    assert f"Ar-Biagi: download Ar from https://www.lxcat.net/Biagi" in said
    assert f"save it as {data_folder() / 'Ar-Biagi.txt'}" in said
    rows = {row["name"]: row for row in json.loads(summary.read_text())["gases"]}
    assert rows["N2"]["processes"] == {"elastic": 1, "excitation": 23, "ionization": 2}
    assert rows["Ar"]["terms"].startswith("GPL-3.0") and rows["Ar-Phelps"]["status"] == "missing"


def test_gases_shows_a_placed_file_as_placed(tmp_path):
    data_folder().mkdir(parents=True, exist_ok=True)
    shutil.copy(DATA / "lxcat_classic_reid.txt", data_folder() / "MyReid.txt")
    result = runner.invoke(app, ["gases"], env={"COLUMNS": "200"})
    assert result.exit_code == 0, result.output
    (row,) = [line for line in result.output.splitlines() if "MyReid" in line]
    cells = [cell.strip() for cell in row.split("│")[1:-1]]
    assert cells[:2] == ["MyReid", "Reid"] and cells[3:5] == ["1 elastic, 1 excitation", "placed"]


def test_swarm_gas_ar_is_the_catalogue_argon_run_as_from_python(tmp_path):
    summary = tmp_path / "s.json"
    result = runner.invoke(app, ["swarm", "--gas", "Ar", *QUICK, "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    saved = json.loads(summary.read_text())
    assert saved["gas"] == "Ar" and saved["parameters"]["gas"] == "Ar"
    direct = simulate_swarm(catalogue_gas("Ar"), 100.0, particles=640, seed=3, tolerances={
        "mean_energy": 0.05, "drift_velocity_bulk": 0.05}, collision_budget=2e6)
    assert saved["mean_energy"] == direct.mean_energy  # the same gas, the same streams
    assert set(saved["rate_coefficients"]) >= {"Ar:E + Ar -> E + E + Ar+, Ionization"}


def test_swarm_prints_the_notes_of_the_reader_on_one_line_each():
    result = runner.invoke(app, ["swarm", "--gas", "N2", *QUICK], env={"COLUMNS": "80"})
    assert result.exit_code == 0, result.output
    notes = [line for line in result.output.splitlines() if line.startswith("note:") and "clipped to 0" in line]
    assert len(notes) == 1 and "IST-Lisbon_N2.txt, line 80 (the EFFECTIVE block of N2 at line 80)" in notes[0]


def test_swarm_joins_repeated_cross_section_files_with_species_and_fractions_across_them(tmp_path):
    summary = tmp_path / "s.json"
    argon = Path(catalogue_gas.__globals__["DATA"]) / "IST-Lisbon_Ar.txt"
    result = runner.invoke(app, ["swarm", "--cross-sections", str(argon), "--cross-sections",
                                 str(DATA / "lxcat_new_mixture.txt"), "--species", "Ar", "--species", "B",
                                 "--fractions", "0.9", "--fractions", "0.1", *QUICK, "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    saved = json.loads(summary.read_text())
    assert saved["parameters"]["cross_sections"] == [str(argon), str(DATA / "lxcat_new_mixture.txt")]
    assert "B:E + B -> O- , Attachment" not in saved["rate_coefficients"]
    assert any(key.startswith("B:") for key in saved["rate_coefficients"])
    assert "skipped 3 blocks of A (not asked for)" in _said(result)


def test_swarm_takes_the_database_of_a_species_from_a_multi_database_export(tmp_path):
    export = tmp_path / "export.txt"
    export.write_bytes((DATA / "lxcat" / "Alves_Ar.txt").read_bytes() +
                       (Path(catalogue_gas.__globals__["DATA"]) / "IST-Lisbon_Ar.txt").read_bytes())
    refused = runner.invoke(app, ["swarm", "--cross-sections", str(export), *QUICK], env={"COLUMNS": "200"})
    assert refused.exit_code == 2
    assert "species Ar is in 2 databases in export.txt: Alves, IST-Lisbon; choose one with database= (--database)" \
        in _said(refused)
    chosen = runner.invoke(app, ["swarm", "--cross-sections", str(export), "--database", "IST-Lisbon", *QUICK])
    assert chosen.exit_code == 0, chosen.output


def test_a_swarm_toml_file_names_the_gas(tmp_path):
    config = tmp_path / "swarm.toml"
    config.write_text('gas = "Ar:0.9,N2:0.1"\ne-n = [100.0]\nparticles = 640\ntolerance = 0.05\n'
                      'collision-budget = 2e6\n')
    summary = tmp_path / "s.json"
    result = runner.invoke(app, ["swarm", "--config", str(config), "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    rates = json.loads(summary.read_text())["rate_coefficients"]
    assert any(key.startswith("Ar:") for key in rates) and any(key.startswith("N2:") for key in rates)
    bad = tmp_path / "bad.toml"
    bad.write_text('gas = "Ar:0.9,N2:0.2"\n')
    refused = runner.invoke(app, ["swarm", "--config", str(bad)], env={"COLUMNS": "200"})
    assert refused.exit_code == 2 and "mole fractions must sum to 1" in _said(refused)


@pytest.mark.slow
def test_a_sweep_varies_the_gas_by_name(tmp_path):
    from tests.cli.test_sweep_cli import invoke, read_table, study_file

    study = ('command = "swarm"\nseed = 3\n[fixed]\nE-N = 100.0\nparticles = 640\ntolerance = 0.05\n'
             'collision-budget = 2e6\n[vary]\ngas = ["Ar", "N2"]\n')
    out = tmp_path / "out"
    result = invoke(study_file(tmp_path, study), "--out", out, "--workers", 1)
    assert result.exit_code == 0, result.output
    rows = read_table(out / "results.csv")
    assert [row["gas"] for row in rows] == ["Ar", "N2"]
    energies = [float(row["mean_energy"]) for row in rows]
    assert energies[0] > 2 * energies[1]  # at 100 Td argon (no vibrational losses) is far hotter than N2
