"""``collisionkit edmd --shear-rate G [--thermostat]``: the summary's shear keys and a bit-for-bit resume."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

from collisionkit.cli import app
from collisionkit.cli._edmd_report import rows
from collisionkit.edmd import EdmdParameters, EdmdRun, enskog_transport

runner = CliRunner()

SHEARED = ("--dim", 2, "--particles", 256, "--packing-fraction", 0.3, "--shear-rate", 0.2, "--thermostat",
           "--equilibration", 5000, "--collisions", 8000, "--blocks", 4, "--seed", 3, "--no-plots")


def invoke(*arguments):
    return runner.invoke(app, ["edmd", *map(str, arguments)])


def test_sheared_run_reports_the_shear_viscosity(tmp_path):
    result = invoke(*SHEARED, "--summary", tmp_path / "run.json")
    assert result.exit_code == 0, result.output
    summary = json.loads((tmp_path / "run.json").read_text())
    assert summary["shear_rate"] == 0.2 and summary["thermostat"] is True
    assert summary["shear_viscosity"] > 0 and 0 < summary["shear_viscosity_error"] < summary["shear_viscosity"]
    assert summary["shear_viscosity"] == pytest.approx(-summary["shear_stress"] / 0.2, rel=1e-12)
    assert summary["temperature"] == pytest.approx(1.0, abs=0.2)
    # heated between the rescalings: the mean kT, at which Enskog's viscosity is given, lies above the final 1
    assert summary["temperature_mean"] > 1.0 + 3 * summary["temperature_mean_error"]
    assert summary["shear_viscosity_enskog"] == pytest.approx(float(enskog_transport(
        summary["packing_fraction"], kT=summary["temperature_mean"], dim=2)["shear_viscosity"]), rel=1e-12)
    output = " ".join(result.output.split())
    assert "shear viscosity -P_xy/G" in output and "temperature kT (time average)" in output
    assert "energy: collisions / thermostat / heating" in output
    assert summary["reduced_shear_rate"] == pytest.approx(0.2 / summary["collision_frequency"], rel=1e-12)
    # heated by more than 5 % on average: the note says what the temperature means
    assert (summary["temperature_mean"] > 1.05) == ("the flow heats the fluid between the thermostat's rescalings"
                                                     in output)


def test_resumed_sheared_run_keeps_offset_clock_and_results(tmp_path):
    """A sheared run stopped half-way (after a measurement block) and resumed gives the uninterrupted run's results."""
    parameters = EdmdParameters(dim=2, particles=256, packing_fraction=0.3, shear_rate=0.2, thermostat=True,
                                equilibration=5000, collisions=8000, blocks=4, seed=3)
    whole = EdmdRun(parameters).run().summary()
    checkpoint = tmp_path / "run.npz"

    def stop_half_way(fraction):
        if fraction > 0.6:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        EdmdRun(parameters, checkpoint=checkpoint).run(progress=stop_half_way)
    resumed = EdmdRun.resume(checkpoint)
    assert resumed.system.shear_rate == 0.2 and resumed.system.thermostat == 1.0
    assert resumed.system.shear_offset > 0.0 and 0 < resumed.measured < 8000
    summary = resumed.run().summary()
    for key in ("shear_viscosity", "shear_viscosity_error", "shear_stress", "compressibility_factor", "temperature",
                "temperature_mean", "temperature_mean_error", "shear_viscosity_enskog", "thermostat_energy",
                "viscous_heating", "viscous_heating_total", "thermostat_energy_total"):
        assert summary[key] == whole[key], key


@pytest.mark.parametrize("thermostat, reference", [("--thermostat", "1 at each rescaling (thermostat)"),
                                                   ("--no-thermostat", "rises (viscous heating)")])
def test_the_table_does_not_promise_an_elastic_sheared_run_kT_1(tmp_path, thermostat, reference):
    arguments = [a for a in SHEARED if a != "--thermostat"]
    result = invoke(*arguments, thermostat, "--summary", tmp_path / "run.json")
    assert result.exit_code == 0, result.output
    summary = json.loads((tmp_path / "run.json").read_text())
    table = {quantity: theory for quantity, _, theory in rows(summary)}  # the cells, whatever the terminal's width
    assert table["temperature kT (final)"] == reference
    if thermostat == "--no-thermostat":  # the flow's work heats it: nothing is lost, the total is minus the heating
        assert summary["temperature"] > 1.0 and summary["energy_lost_total"] < 0.0
