"""Command line: the limits of ``swarm``, ``slab`` and ``track`` (refused before any work with exit 2, named as the
user wrote them, stated in --help), the checkpoints' suffix, a track run stopped by its avalanches (exit 1), and
the swarm's tables at 80 columns."""

from types import SimpleNamespace

import numpy as np
import pytest
import typer.main
from typer.testing import CliRunner

from collisionkit.cli import _messages, _transport, app
from collisionkit.cli._transport import print_swarm_tables

runner = CliRunner()


def _said(result) -> str:
    return " ".join(result.output.split())


def _refused(result, *words):
    """Exit 2, one error line holding every word, no traceback and no raw warning."""
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output and "Warning" not in result.output, result.output
    said = _said(result)
    assert said.startswith("error:"), said
    for word in words:
        assert word in said, said
    return said


def test_the_command_line_ranges_are_the_library_ones():
    from collisionkit.transport import _validation

    assert _transport.MAX_REDUCED_FIELD == _validation.MAX_REDUCED_FIELD
    assert _transport.MAX_REDUCED_MAGNETIC_FIELD == _validation.MAX_REDUCED_MAGNETIC_FIELD
    assert _transport.MAX_GAS_TEMPERATURE == _validation.MAX_GAS_TEMPERATURE
    assert _transport.REDUCED_FREQUENCY_RANGE == _validation.REDUCED_FREQUENCY_RANGE
    assert _transport.QUASI_STATIC == _validation.QUASI_STATIC


def test_a_waveform_of_huge_values_is_refused_as_waveform_with_no_raw_warning(tmp_path):
    """``0 1e300`` and ``1 1e300``: numpy's overflow warnings (in the r.m.s.), then a runaway, exit 1."""
    waveform = tmp_path / "w9.txt"
    waveform.write_text("0 1e300\n1 1e300\n")
    result = runner.invoke(app, ["swarm", "--model", "reid", "--omega-N", "2e-14", "--waveform", str(waveform)])
    _refused(result, "--waveform: waveform E/E0 values must lie in [-1e+06, 1e+06]")
    peak = tmp_path / "peak.txt"
    peak.write_text("0 1\n0.5 1e5\n")
    result = runner.invoke(app, ["swarm", "--model", "reid", "--omega-N", "2e-14", "--waveform", str(peak)])
    _refused(result, "--waveform: the waveform's peak E/N", "it must be <= 1e+06 Td")


def test_a_missing_waveform_file_is_named_as_a_plain_path(tmp_path):
    missing = tmp_path / "nonexistent.txt"
    said = _refused(runner.invoke(app, ["swarm", "--model", "reid", "--omega-N", "2e-14", "--waveform",
                                        str(missing)]), f"--waveform: waveform file not found: {missing}")
    assert "PosixPath" not in said and "(got" not in said


@pytest.mark.parametrize("line, words", [
    ('E-N = "abc"', "E-N must be a number or a list of numbers, not 'abc'"),
    ('E-N = [12, "abc"]', "E-N must be a number or a list of numbers"),
    ('B-N = "abc"', "B-N must be a number, not 'abc'"),
    ('omega-N = true', "omega-N must be a number, not True"),
    ("E-N = 1e30", "--E-N: every E/N must be a finite number from 0 to 1e+06 Td"),
])
def test_a_config_file_value_is_named_as_the_command_line_spells_it(tmp_path, line, words):
    config = tmp_path / "swarm.toml"
    config.write_text(f'model = "reid"\n{line}\n')
    said = _refused(runner.invoke(app, ["swarm", "--config", str(config)]), words)
    assert "e-n must" not in said and "b-n must" not in said


def test_e_n_below_zero_names_the_flag_not_the_library_parameter():
    said = _refused(runner.invoke(app, ["swarm", "--model", "reid", "--E-N", "-5"]), "--E-N:", "0 to 1e+06 Td")
    assert "reduced_field" not in said


def test_a_nan_tolerance_is_said_to_be_not_finite():
    said = _refused(runner.invoke(app, ["swarm", "--model", "reid", "--tolerance", "nan"]),
                    "--tolerance: Input should be a finite number")
    assert "less than or equal to 0.5" not in said


def test_a_checkpoint_must_be_an_npz_file(tmp_path):
    for name in ("scan.json", "scan", "scan.npz.txt"):
        said = _refused(runner.invoke(app, ["swarm", "--model", "reid", "--checkpoint", str(tmp_path / name)]),
                        "--checkpoint must end in .npz")
        assert name in said
    device = tmp_path / "device.toml"
    device.write_text('[gas]\nmodel = "reid"\n[geometry]\ngap = 1e-3\n[source]\nelectrons = 2\n')
    _refused(runner.invoke(app, ["track", "--config", str(device), "--checkpoint", str(tmp_path / "run.json")]),
             "--checkpoint must end in .npz")
    device.write_text(f'checkpoint = "{tmp_path / "run.json"}"\n' + device.read_text())  # the file's own
    _refused(runner.invoke(app, ["track", "--config", str(device)]), "--checkpoint must end in .npz")
    assert not list(tmp_path.glob("*.json")) and not list(tmp_path.glob("scan*"))


def _helps(command: str) -> dict[str, str]:
    group = typer.main.get_command(app)
    return {parameter.name: " ".join((parameter.help or "").split()) for parameter in group.commands[command].params}


def test_the_help_states_the_limits_the_program_enforces():
    swarm, slab, track = _helps("swarm"), _helps("slab"), _helps("track")
    assert "0 to 1e6" in swarm["e_n"] and "0 to 1e6" in swarm["b_n"] and "0 to 1e5" in swarm["gas_temperature"]
    assert "0 (static) or 1e-20 to 1e-8" in swarm["omega_n"]
    assert "+-1e6" in swarm["waveform"] and "at most 1e6 Td" in swarm["waveform"]
    assert "in (0, 0.5]" in swarm["tolerance"] and "(>= 1e4)" in swarm["collision_budget"]
    assert ".npz" in swarm["checkpoint"] and "JSON" not in swarm["checkpoint"] and ".npz" in track["checkpoint"]
    assert "(0 to 1e4)" in slab["thickness"] and "(64 to 1e9)" in slab["particles"]
    assert "exit 1" in track["max_electrons"]


@pytest.mark.parametrize("line, words", [
    ("gap = -1e-3", "[geometry] gap: Input should be greater than 0"),
    ('kind = "sphere"', "[geometry] kind: Input should be 'parallel-plate' or 'coaxial'"),
    ("wire-radius = -1.0", "[geometry] wire-radius: Input should be greater than 0"),
])
def test_a_device_file_value_is_named_as_the_file_spells_it(tmp_path, line, words):
    device = tmp_path / "device.toml"
    geometry = {"gap": 'kind = "parallel-plate"\n', "kin": "gap = 1e-3\n", "wir": 'kind = "coaxial"\n'}[line[:3]]
    device.write_text(f'[gas]\nmodel = "reid"\n[geometry]\n{geometry}{line}\n[source]\nelectrons = 2\n')
    said = _refused(runner.invoke(app, ["track", "--config", str(device)]), words)
    assert "--gap" not in said and "--geometry" not in said and "--wire-radius" not in said
    device.write_text('[gas]\nmodel = "reid"\ntemperature = 1e9\n[geometry]\ngap = 1e-3\n')
    _refused(runner.invoke(app, ["track", "--config", str(device)]), "[gas] temperature: must be from 0 to 100000; "
             "got 1e+09")


ALPHA_N = 2.806e-22  # m^2: Lucas-Saelee (F = 1) at 10 Td, as tests/transport/test_tracking.py
DENSITY = 2.45e25


def _avalanche_device(electrons: int, max_electrons: int) -> str:
    """A gap of 5/alpha (~26 electrons a primary), from tests/transport/test_tracking.py."""
    return (f"seed = 2\nmax-electrons = {max_electrons}\n[gas]\nmodel = \"lucas_saelee\"\ndensity = {DENSITY}\n"
            f"temperature = 0.0\n[geometry]\ngap = {5.0 / ALPHA_N / DENSITY}\nvoltage = {10e-21 * 5.0 / ALPHA_N}\n"
            f"[source]\nelectrons = {electrons}\nposition = [0.0, 0.0, {1.0 / ALPHA_N / DENSITY}]\nenergy = 5.0\n")


def test_an_avalanche_past_max_electrons_is_a_run_failure_not_bad_input(tmp_path):
    """Stopped after part of the work (a user's run: minutes, then exit 2 "bad input, nothing run"): exit 1 with what
    was done and how to go on."""
    device = tmp_path / "device.toml"
    device.write_text(_avalanche_device(8, 200))
    result = runner.invoke(app, ["track", "--config", str(device), "--threads", "1"])
    assert result.exit_code == 1, result.output
    said = _said(result)
    assert "error: the run stopped: primaries 0 to 7" in said and "more than max_electrons = 200" in said
    assert "follow fewer primaries" in said and "raise max_electrons" in said and "the pressure times the gap" in said
    assert "no --checkpoint was given, so nothing is saved" in said and "Traceback" not in said
    # with a checkpoint: the chunks done are saved, and the message says how to go on
    device.write_text(_avalanche_device(200, 3000))
    checkpoint = tmp_path / "run.npz"
    result = runner.invoke(app, ["track", "--config", str(device), "--threads", "1", "--checkpoint", str(checkpoint)])
    assert result.exit_code == 1, result.output
    said = _said(result)
    assert "the first 16 primaries made" in said and "16 of 200 primaries are saved in" in said
    assert "--resume" in said and "--max-electrons" in said and checkpoint.is_file()


def _result(reduced_field, scale):
    """A result whose every cell is as wide as it gets (negative drift, exponents, errors with exponents)."""
    tensor = np.arange(1.0, 10.0).reshape(3, 3) * -1.2345e22 * scale
    return SimpleNamespace(
        reduced_field=reduced_field, mean_energy=12.345678, mean_energy_error=1.2345e-5,
        drift_velocity_bulk=np.array([-1.23456e5, 2.34567e5, -3.45678e5]) * scale,
        drift_velocity_bulk_error=np.array([1.234e2, 2.345e2, 3.456e2]) * scale,
        drift_velocity_flux=np.array([-1.23456e5, 2.34567e5, -3.45678e5]) * scale,
        drift_velocity_flux_error=np.array([1.234e2, 2.345e2, 3.456e2]) * scale, diffusion_N_bulk=tensor,
        diffusion_N_bulk_error=np.abs(tensor) / 37, diffusion_L_N=5.821234e23, diffusion_L_N_error=2.2345e22,
        diffusion_T_N=1.157234e24, diffusion_T_N_error=2.5345e22, alpha_N=1.234567e-22, alpha_N_error=1.2345e-24,
        eta_N=2.345678e-23, eta_N_error=3.456e-25, collisions_per_second=1.23456e7, converged=True)


@pytest.mark.parametrize("magnetic, oscillating", [(False, False), (True, False), (True, True)])
def test_the_swarm_tables_show_every_number_in_full_at_80_columns(monkeypatch, capsys, magnetic, oscillating):
    """At 80 columns (a terminal's default, and what rich takes for a file) the eight-column table cut its cells
    ("5.821e…") and its last header ("collis…")."""
    monkeypatch.setattr(_messages.console, "width", 80)
    results = [_result(12.0, 1.0), _result(1234.5678, 1.0), _result(0.001, 1.0)]
    print_swarm_tables(results, magnetic, oscillating, 60.0)
    output = capsys.readouterr().out
    assert "…" not in output
    assert max(len(line) for line in output.splitlines()) <= 80
    words = output.split()
    transverse = ("see", "below") if magnetic else ("1.157e+24", "2.5e+22")  # with B: the components table
    for word in ("5.821e+23", "2.2e+22", *transverse, "3.4568e+05", "3.5e+02", "1.235e-22", "1.2e-24", "2.346e-23",
                 "3.5e-25", "1.23e+07", "12.346", "1.2e-05", "1234.57", "0.001"):
        assert word in words, (word, output)
    for header in ("collisions/s", "alpha/N", "eta/N", "N D_L", "N D_T", "bulk W"):
        assert header in output
    if magnetic:
        assert {"-1.234e+22", "3.3e+20", "-1.235e+05", "1.2e+02", "-3.703e+22", "1e+21"} <= set(words), output


def test_a_swarm_run_prints_its_tables_whole_at_80_columns(monkeypatch):
    """The user's run (Reid's ramp at 12 Td), through the command, at 80 columns."""
    monkeypatch.setattr(_messages.console, "width", 80)
    result = runner.invoke(app, ["swarm", "--model", "reid", "--E-N", "12", "--gas-temperature", "0", "--particles",
                                 "640", "--tolerance", "0.05", "--collision-budget", "2e6", "--seed", "1",
                                 "--B-N", "100"])
    assert result.exit_code == 0, result.output
    assert "…" not in result.output and "collisions/s" in result.output
