"""The ``collisionkit encounter`` command: table, summary JSON, initial-conditions files, errors."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

from collisionkit.cli import app
from collisionkit.encounters import unit_system

runner = CliRunner()


def invoke(*arguments):
    return runner.invoke(app, ["encounter", *map(str, arguments)])


def test_summary_and_initial_conditions(tmp_path):
    out, summary = tmp_path / "out", tmp_path / "summary.json"
    result = invoke(
        "--m1", 1.0, "--m2", 3.0, "--rp", 2.0, "--vinf", 0.5, "--sep0", 20.0,
        "--out", out, "--summary", summary, "--no-plots",
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "impact parameter b (eq. 38)" in result.output
    data = json.loads(summary.read_text())
    ic = data["initial_conditions"]
    M, mu = 4.0, 0.75
    # StarCrash eqs. 34-39 with G = 1
    assert ic["energy"] == pytest.approx(0.5 * mu * 0.25, rel=1e-15, abs=0)
    assert ic["v0"] == pytest.approx(math.sqrt(0.25 + 2 * M / 20.0), rel=1e-15, abs=0)
    assert ic["vp"] == pytest.approx(math.sqrt(0.25 + 2 * M / 2.0), rel=1e-15, abs=0)
    assert ic["impact_parameter"] == pytest.approx(math.sqrt(4.0 + 2 * M * 2.0 / 0.25), rel=1e-15, abs=0)
    assert ic["angular_momentum"] == pytest.approx(mu * 2.0 * math.sqrt(0.25 + 2 * M / 2.0), rel=1e-15, abs=0)
    assert ic["vt"] == pytest.approx(0.5 * ic["impact_parameter"] / 20.0, rel=1e-15, abs=0)
    assert ic["vr"] ** 2 + ic["vt"] ** 2 == pytest.approx(ic["v0"] ** 2, rel=1e-14, abs=0)
    assert data["orbit"]["eccentricity"] == pytest.approx(1 + 2.0 * 0.25 / M, rel=1e-15, abs=0)
    assert data["units"] == "nbody" and data["G"] == 1.0 and data["contact"] is None and data["warnings"] == []
    # the initial-conditions files
    table = np.loadtxt(out / "initial_conditions.txt")
    assert table[:, 1] == pytest.approx([1.0, 3.0])
    positions, velocities = table[:, 2:5], table[:, 5:]
    assert np.linalg.norm(positions[1] - positions[0]) == pytest.approx(20.0, rel=1e-15, abs=0)
    assert 1.0 * positions[0] + 3.0 * positions[1] == pytest.approx([0, 0, 0], abs=1e-14)
    assert 1.0 * velocities[0] + 3.0 * velocities[1] == pytest.approx([0, 0, 0], abs=1e-15)
    assert positions[1] / np.linalg.norm(positions[1]) == pytest.approx(np.ones(3) / math.sqrt(3), rel=1e-15, abs=0)
    on_disk = json.loads((out / "initial_conditions.json").read_text())
    assert on_disk["positions"] == positions.tolist() and on_disk["impact_parameter"] == ic["impact_parameter"]
    assert not (out / "encounter.png").exists()


def test_units_contact_plot_and_grid_warning(tmp_path):
    summary = tmp_path / "s.json"
    result = invoke(
        "--units", "solar", "--rp", 1.0, "--vinf", 1.0, "--sep0", 1.6,
        "--radius1", 0.8, "--radius2", 0.7, "--out", tmp_path, "--summary", summary,
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    data = json.loads(summary.read_text())
    G = unit_system("solar").G
    assert data["G"] == G and data["unit_labels"]["length"] == "AU"
    assert data["initial_conditions"]["v0"] == pytest.approx(math.sqrt(1.0 + 2 * G * 2.0 / 1.6), rel=1e-15, abs=0)
    assert data["initial_conditions"]["vt_over_v0"] > math.sqrt(1 / 3)
    assert len(data["warnings"]) == 1 and "sqrt(1/3)" in data["warnings"][0]
    assert "warning" in result.output
    contact = data["contact"]
    assert contact["touches"] is True
    assert contact["relative_speed"] == pytest.approx(math.sqrt(1.0 + 2 * G * 2.0 / 1.5), rel=1e-13, abs=0)
    assert 0 < contact["time_from_start"] < data["initial_conditions"]["time_to_periastron"]
    assert contact["focusing_cross_section"] == pytest.approx(math.pi * 1.5**2 * (1 + 2 * G * 2.0 / 1.5), rel=1e-14, abs=0)
    assert (tmp_path / "encounter.png").stat().st_size > 0
    assert str(tmp_path / "encounter.png") in data["files"]


def test_overlapping_start_is_reported(tmp_path):
    summary = tmp_path / "s.json"
    result = invoke("--sep0", 1.2, "--radius1", 1.0, "--radius2", 1.0, "--out", tmp_path, "--summary", summary, "--no-plots")
    assert result.exit_code == 0, result.output
    data = json.loads(summary.read_text())
    assert data["contact"]["overlap_at_start"] is True and data["contact"]["time_from_start"] < 0
    assert any("overlap" in message for message in data["warnings"])


def test_config_file_and_command_line_precedence(tmp_path):
    config = tmp_path / "encounter.toml"
    config.write_text('m1 = 2.0\nvinf = 0.25\nsep0 = 30.0\nlayout = "x"\nplots = false\n')
    summary = tmp_path / "s.json"
    result = invoke("--config", config, "--vinf", 0.5, "--out", tmp_path, "--summary", summary)
    assert result.exit_code == 0, result.output
    ic = json.loads(summary.read_text())["initial_conditions"]
    assert (ic["m1"], ic["vinf"], ic["sep0"], ic["layout"]) == (2.0, 0.5, 30.0, "x")
    assert ic["positions"][1][1:] == [0.0, 0.0]


@pytest.mark.parametrize(
    "arguments",
    [
        ("--m1", -1.0),
        ("--m2", 0.0),
        ("--rp", 0.0),
        ("--vinf", 0.0),
        ("--vinf", -2.0),
        ("--sep0", 0.5),  # below rp = 1
        ("--units", "imperial"),
        ("--layout", "y"),
        ("--radius1", -1.0),
        ("--rp", "nan"),
    ],
)
def test_bad_input_exits_with_2(tmp_path, arguments):
    result = invoke(*arguments, "--out", tmp_path, "--no-plots")
    assert result.exit_code == 2
    assert "error" in result.output.lower()
    assert not (tmp_path / "initial_conditions.json").exists()


def test_sep0_below_rp_message(tmp_path):
    result = invoke("--rp", 2.0, "--sep0", 1.0, "--out", tmp_path, "--no-plots")
    assert result.exit_code == 2
    assert "sep0 must be >= rp" in result.output


def test_unknown_toml_key_exits_with_2(tmp_path):
    config = tmp_path / "bad.toml"
    config.write_text("m1 = 1.0\nperiastron = 2.0\n")
    result = invoke("--config", config, "--out", tmp_path, "--no-plots")
    assert result.exit_code == 2
    assert "unknown option 'periastron'" in result.output


@pytest.fixture(scope="module")
def star_files(tmp_path_factory):
    """A 1 Msun n = 3 star in stellar units (.hdf5) and a 0.5 Msun n = 1.5 star in cgs (.npz)."""
    from collisionkit.encounters import polytrope_star, write_star

    folder = tmp_path_factory.mktemp("stars")
    first = write_star(polytrope_star(3.0, 500, 1.0, 1.0, units="stellar", neighbours=20, seed=1), folder / "a.hdf5")
    second = polytrope_star(1.5, 300, 0.5, 0.5, units="stellar", neighbours=20, seed=2).in_units("cgs")
    return first, write_star(second, folder / "b.npz")


def test_two_star_files_are_placed_for_an_sph_code(tmp_path, star_files):
    from collisionkit.encounters import read_star

    out, summary = tmp_path / "out", tmp_path / "s.json"
    result = invoke("--star1", star_files[0], "--star2", star_files[1], "--units", "stellar", "--rp", 1.0,
                    "--vinf", 50.0, "--sep0", 20.0, "--out", out, "--summary", summary)
    assert result.exit_code == 0, result.output
    said = " ".join(result.output.split())
    assert f"note: --star2 {star_files[1]} is in cgs units: converted to stellar" in said
    data = json.loads(summary.read_text())
    stars = data["stars"]
    assert stars["star1"]["mass"] == pytest.approx(1.0, rel=1e-14) and stars["star2"]["mass"] == pytest.approx(0.5)
    assert stars["star1"]["particles"] == 500 and stars["star2"]["particles"] == 300
    r1, r2 = stars["star1"]["radius_99"], stars["star2"]["radius_99"]
    assert data["sep0_over_radii"] == pytest.approx(20.0 / (r1 + r2), rel=1e-15) and data["overlap_at_sep0"] is False
    assert data["warnings"] == [] and data["initial_conditions"]["m2"] == stars["star2"]["mass"]
    assert sorted(data["files"]) == sorted(str(out / name) for name in (
        "initial_conditions.json", "initial_conditions.txt", "initial_conditions.hdf5", "encounter.png"))
    pair = read_star(out / "initial_conditions.hdf5")
    assert len(pair) == 800 and pair.units.name == "stellar" and pair.star_ids.tolist() == [1] * 500 + [2] * 300
    ic = data["initial_conditions"]
    for number in (1, 2):
        mine = pair.star_ids == number
        centre = pair.masses[mine] @ pair.positions[mine] / pair.masses[mine].sum()
        assert centre == pytest.approx(ic["positions"][number - 1], abs=1e-12)
    assert np.linalg.norm(pair.masses @ pair.velocities) < 1e-12 * pair.mass * 50


def test_stars_too_close_are_warned_and_their_masses_are_not_given_twice(tmp_path, star_files):
    summary = tmp_path / "s.json"
    result = invoke("--star1", star_files[0], "--star2", star_files[1], "--units", "stellar", "--rp", 0.5,
                    "--vinf", 50.0, "--sep0", 1.0, "--layout", "x", "--no-plots", "--out", tmp_path, "--summary", summary)
    assert result.exit_code == 0, result.output
    data = json.loads(summary.read_text())
    assert data["overlap_at_sep0"] is True and len(data["warnings"]) == 2
    said = " ".join(result.output.split())
    assert "warning: the bodies overlap" in said and "tidal effects at the start are not negligible" in said
    config = tmp_path / "c.toml"
    config.write_text("m2 = 3.0\n")
    result = invoke("--config", config, "--star1", star_files[0], "--star2", star_files[1], "--out", tmp_path / "2")
    assert result.exit_code == 2 and "--m2 comes from the particles" in result.output


def test_a_star_file_that_is_not_a_star_is_exit_code_2(tmp_path, star_files):
    bad = tmp_path / "bad.hdf5"
    bad.write_text("not hdf5")
    result = invoke("--star1", star_files[0], "--star2", bad, "--out", tmp_path / "out", "--no-plots")
    assert result.exit_code == 2
    line = " ".join(result.output.split())
    assert line.startswith("error: --star2") and "not an HDF5 file" in line and "Traceback" not in result.output
    assert not (tmp_path / "out").exists()


def test_placing_stars_without_h5py_names_the_extra(tmp_path, star_files, monkeypatch):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name: None if name == "h5py" else real(name))
    npz = star_files[1]
    result = invoke("--star1", npz, "--star2", npz, "--out", tmp_path / "out", "--no-plots")
    assert result.exit_code == 2 and "pip install 'collisionkit[stars]'" in " ".join(result.output.split())
    assert not (tmp_path / "out").exists()
