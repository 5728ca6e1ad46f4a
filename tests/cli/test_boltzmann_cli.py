"""Command line: ``collisionkit boltzmann``, the two-term Boltzmann equation against E/N."""

import csv
import json

import pytest
from typer.testing import CliRunner

from collisionkit.cli import app
from collisionkit.transport import lucas_saelee, reid_ramp, two_term_boltzmann

runner = CliRunner()


def test_a_scan_gives_the_librarys_results_in_the_summary_and_the_tables(tmp_path):
    summary, out = tmp_path / "b.json", tmp_path / "out"
    result = runner.invoke(app, ["boltzmann", "--model", "reid", "--E-N", "1,12", "--gas-temperature", "0",
                                 "--summary", str(summary), "--out", str(out)])
    assert result.exit_code == 0, result.output
    entries = json.loads(summary.read_text())["results"]
    assert [entry["E_N"] for entry in entries] == [1.0, 12.0]
    for entry in entries:  # a Python script calling the library gets the same numbers
        direct = two_term_boltzmann(reid_ramp(), entry["E_N"], 0.0)
        assert entry["mean_energy"] == direct.mean_energy and entry["drift_velocity"] == direct.drift_velocity
        assert entry["rate_coefficients"] == direct.rate_coefficients
    with open(out / "boltzmann.csv", newline="") as table:
        rows = list(csv.DictReader(table))
    assert [float(row["E_N"]) for row in rows] == [1.0, 12.0]
    assert float(rows[1]["rate_coefficient[reid:excitation]"]) == entries[1]["rate_coefficients"]["reid:excitation"]
    with open(out / "eedf.csv", newline="") as table:
        eedf = list(csv.DictReader(table))
    assert len(eedf) == 2 * 1000 and {float(row["E_N"]) for row in eedf} == {1.0, 12.0}
    assert (out / "eedf.png").stat().st_size > 1000
    units = json.loads(summary.read_text())["units"]  # every column of the table has its unit
    assert all(column in units or column.split("[")[0] + "[...]" in units for column in rows[0])
    assert units["eedf"] == "eV^-3/2" and units["mean_energy"] == "eV"
    assert "0.2736" in result.output  # the table: <e> at 12 Td
    # the same scan as BOLSIG+'s output tables, for fluid codes: the mobility section is the table's mobility_N
    from collisionkit.transport import read_bolsig_section

    mobility = read_bolsig_section((out / "bolsig.dat").read_text(), "Mobility *N (1/m/V/s)")
    assert mobility[:, 0].tolist() == [1.0, 12.0]
    assert mobility[:, 1] == pytest.approx([float(row["mobility_N"]) for row in rows], rel=1e-6)
    again = runner.invoke(app, ["boltzmann", "--model", "reid", "--E-N", "12", "--out", str(out)])
    assert again.exit_code == 2 and "pass --overwrite" in " ".join(again.output.split())


def test_a_config_file_gives_the_options(tmp_path):
    config = tmp_path / "b.toml"
    config.write_text('model = "lucas_saelee"\nE-N = [100]\ngas-temperature = 0\ncells = 400\nsharing = "uniform"\n')
    summary = tmp_path / "b.json"
    result = runner.invoke(app, ["boltzmann", "--config", str(config), "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    data = json.loads(summary.read_text())
    assert data["parameters"]["sharing"] == "uniform" and data["results"][0]["cells"] == 400
    assert data["results"][0]["alpha_N"] > 0


def test_spatial_growth_is_chosen_and_its_limit_is_a_failed_run_not_a_traceback(tmp_path):
    summary = tmp_path / "b.json"
    result = runner.invoke(app, ["boltzmann", "--model", "lucas_saelee", "--E-N", "50", "--gas-temperature", "0",
                                 "--growth", "spatial", "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    entry = json.loads(summary.read_text())["results"][0]
    temporal = two_term_boltzmann(lucas_saelee(0.5), 50.0, 0.0)
    assert entry["growth"] == "spatial" and 0 < entry["alpha_N"] < temporal.alpha_N
    kept, out = tmp_path / "kept.json", tmp_path / "out"
    beyond = runner.invoke(app, ["boltzmann", "--model", "lucas_saelee", "--E-N", "50,3000,100", "--gas-temperature",
                                 "0", "--growth", "spatial", "--summary", str(kept), "--out", str(out)])
    assert beyond.exit_code == 1 and "Traceback" not in beyond.output
    said = " ".join(beyond.output.split())
    assert "E/N = 3000 Td: no steady-state Townsend growth" in said and "use --growth temporal" in said
    # the points solved before and after the failure are written, the failure is in the summary
    data = json.loads(kept.read_text())
    assert [entry["E_N"] for entry in data["results"]] == [50.0, 100.0]
    assert data["failed"][0]["E_N"] == 3000.0 and "no steady-state Townsend growth" in data["failed"][0]["reason"]
    with open(out / "boltzmann.csv", newline="") as table:
        assert [float(row["E_N"]) for row in csv.DictReader(table)] == [50.0, 100.0]


def test_electron_electron_collisions_are_the_librarys(tmp_path):
    """--ionization-degree and --electron-density reach the library: the summary and the table hold its numbers,
    and the CLI's limit is the library's."""
    from collisionkit.cli import _boltzmann
    from collisionkit.transport import hard_sphere_gas, two_term

    assert _boltzmann.MAX_IONIZATION_DEGREE == two_term.MAX_IONIZATION_DEGREE
    assert _boltzmann.MIN_GAS_TEMPERATURE == two_term.MIN_GAS_TEMPERATURE
    summary, out = tmp_path / "b.json", tmp_path / "out"
    result = runner.invoke(app, ["boltzmann", "--model", "hard_sphere", "--E-N", "10", "--gas-temperature", "0",
                                 "--ionization-degree", "1e-3", "--electron-density", "1e18", "--summary",
                                 str(summary), "--out", str(out)])
    assert result.exit_code == 0, result.output
    entry = json.loads(summary.read_text())["results"][0]
    direct = two_term_boltzmann(hard_sphere_gas(), 10.0, 0.0, ionization_degree=1e-3, electron_density=1e18)
    assert entry["mean_energy"] == direct.mean_energy and entry["coulomb_logarithm"] == direct.coulomb_logarithm
    assert entry["ionization_degree"] == 1e-3 and entry["coulomb_logarithm"] > 2.0
    with open(out / "boltzmann.csv", newline="") as table:
        row = next(csv.DictReader(table))
    assert float(row["electron_density"]) == 1e18 and float(row["mean_energy"]) == direct.mean_energy
    assert "electron-electron collisions at n_e/N = 0.001" in " ".join(result.output.split())


def test_a_plasma_too_dense_for_the_coulomb_logarithm_is_one_line_naming_the_density():
    """ln(Lambda) depends on the solution's mean energy, so it is known only once an E/N is solved: a one-line error
    naming --electron-density (exit 2), no traceback."""
    result = runner.invoke(app, ["boltzmann", "--model", "hard_sphere", "--E-N", "5", "--ionization-degree", "1e-3",
                                 "--electron-density", "1e31"])
    assert result.exit_code == 2 and "Traceback" not in result.output
    errors = [line for line in result.output.splitlines() if line.startswith("error:")]
    assert len(errors) == 1 and "E/N = 5 Td: --electron-density: the Coulomb logarithm is" in errors[0]


def test_a_high_frequency_field_is_the_librarys(tmp_path):
    summary = tmp_path / "b.json"
    result = runner.invoke(app, ["boltzmann", "--model", "hard_sphere", "--E-N", "10", "--gas-temperature", "0",
                                 "--omega-N", "1e-14", "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    entry = json.loads(summary.read_text())["results"][0]
    from collisionkit.transport import hard_sphere_gas

    direct = two_term_boltzmann(hard_sphere_gas(), 10.0, 0.0, omega_N=1e-14)
    assert entry["omega_N"] == 1e-14 and entry["mean_energy"] == direct.mean_energy
    assert "E/N the amplitude at omega/N = 1e-14" in " ".join(result.output.split())


def test_the_solvers_warnings_are_shown_and_kept_in_the_summary(tmp_path):
    """Argon at 1e4 Td: 2 % of the electrons above its tables' 1000 eV is a warning line and a summary entry."""
    summary = tmp_path / "b.json"
    result = runner.invoke(app, ["boltzmann", "--gas", "Ar", "--E-N", "100,10000", "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    assert "E/N = 10000 Td: 2 % of the electrons lie above 1000 eV" in " ".join(result.output.split())
    data = json.loads(summary.read_text())
    assert len(data["warnings"]) == 1 and data["failed"] == []


def test_ctrl_c_keeps_the_points_already_solved(tmp_path, monkeypatch):
    """Ctrl-C during the second point: the first is written to the summary, exit 130."""
    from collisionkit.transport import TwoTermScan

    original = TwoTermScan.solve

    def interrupted_at_the_second(self, value):
        if self.results:
            raise KeyboardInterrupt
        original(self, value)

    monkeypatch.setattr(TwoTermScan, "solve", interrupted_at_the_second)
    summary = tmp_path / "b.json"
    result = runner.invoke(app, ["boltzmann", "--model", "reid", "--E-N", "1,12,24", "--gas-temperature", "0",
                                 "--summary", str(summary)])
    assert result.exit_code == 130
    assert "interrupted after 1 of 3 E/N points: the finished ones are written" in " ".join(result.output.split())
    assert [entry["E_N"] for entry in json.loads(summary.read_text())["results"]] == [1.0]


REVERSIBLE = """\
MOMENTUM
X
 1e-4
-----
 0 1e-19
 100 1e-19
-----
EXCITATION
X <-> X*
 0.5 / 3.0
-----
 0.5 0
 1 1e-20
 100 1e-20
-----
"""


def test_level_populations_come_from_a_config_table_as_for_swarm(tmp_path):
    """A config's [populations] sets the upper level of a reversible excitation (as swarm's; boltzmann refused it):
    a populated level feeds superelastic collisions, which heat the electrons."""
    from collisionkit.transport import read_lxcat

    (tmp_path / "x.txt").write_text(REVERSIBLE)
    config, summary = tmp_path / "b.toml", tmp_path / "b.json"
    label = [f"{s.name}:{p.label}" for s in read_lxcat(tmp_path / "x.txt").species for p in s.processes][1]
    config.write_text(f'cross-sections = ["{tmp_path / "x.txt"}"]\nE-N = [1]\ngas-temperature = 0\n'
                      f'[populations]\n"{label}" = 0.1\n')
    result = runner.invoke(app, ["boltzmann", "--config", str(config), "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    data = json.loads(summary.read_text())
    assert data["parameters"]["populations"] == {label: 0.1}
    cold = runner.invoke(app, ["boltzmann", "--cross-sections", str(tmp_path / "x.txt"), "--E-N", "1",
                               "--gas-temperature", "0", "--summary", str(tmp_path / "c.json")])
    assert cold.exit_code == 0, cold.output
    unpopulated = json.loads((tmp_path / "c.json").read_text())["results"][0]["mean_energy"]
    assert data["results"][0]["mean_energy"] > 1.05 * unpopulated


def test_the_grid_top_can_be_set_and_a_doubtful_one_is_a_warning(tmp_path):
    summary = tmp_path / "b.json"
    result = runner.invoke(app, ["boltzmann", "--model", "reid", "--E-N", "12", "--gas-temperature", "0",
                                 "--max-energy", "1000", "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    data = json.loads(summary.read_text())
    assert data["results"][0]["max_energy"] == 1000.0 and data["parameters"]["max-energy"] == 1000.0
    assert "the power balance is off by" in data["warnings"][0] and "(--max-energy 1000 eV" in data["warnings"][0]


def test_the_summary_says_what_the_numbers_came_from(tmp_path):
    import hashlib

    from collisionkit import __version__
    from collisionkit.transport import catalogue_files

    summary = tmp_path / "b.json"
    result = runner.invoke(app, ["boltzmann", "--gas", "Ar", "--E-N", "100", "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    provenance = json.loads(summary.read_text())["provenance"]
    (argon,) = catalogue_files("Ar")
    assert provenance["collisionkit"] == __version__
    assert provenance["cross_sections"] == [{"path": str(argon),
                                             "sha256": hashlib.sha256(argon.read_bytes()).hexdigest()}]


def test_e_n_ranges_give_evenly_or_logarithmically_spaced_values_and_minus_zero_is_zero(tmp_path):
    # BOLSIG+ and LoKI-B users expect ranges; --E-N 10,-0 printed "-0"
    summary = tmp_path / "b.json"
    result = runner.invoke(app, ["boltzmann", "--model", "reid", "--E-N", "1:1000:4:log,0:10:3", "--E-N", "-0",
                                 "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    values = [entry["E_N"] for entry in json.loads(summary.read_text())["results"]]
    assert values == [1.0, 10.0, 100.0, 1000.0, 0.0, 5.0, 10.0, 0.0]
    assert "-0" not in result.stdout
    assert "START:STOP:COUNT:log" in " ".join(runner.invoke(app, ["boltzmann", "--help"]).output.split())


def test_an_empty_e_n_list_in_a_config_file_says_what_to_give(tmp_path):
    config = tmp_path / "b.toml"
    config.write_text('model = "reid"\nE-N = []\n')
    result = runner.invoke(app, ["boltzmann", "--config", str(config)])
    assert result.exit_code == 2 and "--E-N: give at least one E/N value (Td, 0 to 1e6)" in result.output


def test_a_config_file_takes_the_command_lines_e_n_ranges(tmp_path):
    # E-N = "1:24:3" was refused ("must be a number or a list of numbers"): ranges were command-line only
    config = tmp_path / "b.toml"
    summary = tmp_path / "b.json"
    config.write_text('model = "reid"\ngas-temperature = 0\nE-N = ["0.5", "1:24:3"]\n')
    result = runner.invoke(app, ["boltzmann", "--config", str(config), "--summary", str(summary), "--out",
                                 str(tmp_path / "out")])
    assert result.exit_code == 0, result.output
    assert [entry["E_N"] for entry in json.loads(summary.read_text())["results"]] == [0.5, 1.0, 12.5, 24.0]
    config.write_text('model = "reid"\nE-N = "1:24:x"\n')
    result = runner.invoke(app, ["boltzmann", "--config", str(config)])
    assert result.exit_code == 2 and "--E-N: the COUNT of '1:24:x' must be a whole number" in result.output


def test_minus_zero_e_n_is_zero_in_the_table_and_the_summary(tmp_path):
    # --E-N 10,-0 printed "-0" for E/N and for W, and the summary held "E_N": -0.0
    summary = tmp_path / "b.json"
    result = runner.invoke(app, ["boltzmann", "--model", "reid", "--E-N", "10,-0", "--summary", str(summary)],
                           env={"COLUMNS": "200"})
    assert result.exit_code == 0, result.output
    assert "-0 " not in result.stdout and "-0.0" not in summary.read_text(), result.stdout
    assert [entry["E_N"] for entry in json.loads(summary.read_text())["results"]] == [10.0, 0.0]


def test_a_config_e_n_of_the_wrong_kind_is_refused_by_name(tmp_path):
    config = tmp_path / "b.toml"
    config.write_text('model = "reid"\nE-N = true\n')
    result = runner.invoke(app, ["boltzmann", "--config", str(config)])
    assert result.exit_code == 2 and "--E-N: must be numbers (Td) or text as on the command line" in result.output
