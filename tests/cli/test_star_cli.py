"""The ``collisionkit star`` command: an unrelaxed polytrope written as a star file, its summary and seed."""

from __future__ import annotations

import json

import h5py
import numpy as np
import pytest
from typer.testing import CliRunner

from collisionkit.cli import app
from collisionkit.encounters import lane_emden, read_star, unit_system

runner = CliRunner()


def invoke(*arguments):
    return runner.invoke(app, ["star", *map(str, arguments)])


def test_a_polytrope_in_stellar_units_as_an_hdf5_snapshot(tmp_path):
    out, summary = tmp_path / "sun.hdf5", tmp_path / "sun.json"
    result = invoke("--polytrope", 3, "--particles", 400, "--mass", 1.0, "--radius", 1.0, "--units", "stellar",
                    "--neighbours", 24, "--seed", 5, "--out", out, "--summary", summary)
    assert result.exit_code == 0, result.output
    said = " ".join(result.output.split())
    assert "note: seed 5 (--seed 5 repeats this run)" in said and "relax it with your SPH code" in said
    data = json.loads(summary.read_text())
    assert data["seed"] == 5 and data["relaxed"] is False and data["files"] == [str(out)]
    assert data["lane_emden"]["xi1"] == pytest.approx(lane_emden(3.0).xi1, rel=1e-15, abs=0)
    assert data["potential_energy_expected"] == pytest.approx(-1.5 * unit_system("stellar").G, rel=1e-15, abs=0)
    star = read_star(out)
    assert len(star) == 400 and star.units.name == "stellar" and star.mass == pytest.approx(1.0, rel=1e-14, abs=0)
    assert data["star"]["radius_99"] == star.radius(0.99)
    with h5py.File(out, "r") as file:
        assert file["Header"].attrs["NumPart_Total"][0] == 400 and "StarID" not in file["PartType0"]
    distances = np.linalg.norm(star.positions[:, None] - star.positions[None], axis=2)
    assert np.all(np.count_nonzero(distances <= star.smoothing_lengths[:, None], axis=1) == 25)
    again = tmp_path / "again.npz"
    assert invoke("--polytrope", 3, "--particles", 400, "--units", "stellar", "--neighbours", 24, "--seed", 5,
                  "--out", again).exit_code == 0
    assert np.array_equal(read_star(again).positions, star.positions)  # the seed repeats the star, in .npz too


def test_a_config_file_and_gamma_for_a_uniform_sphere(tmp_path):
    config = tmp_path / "star.toml"
    config.write_text('polytrope = 0.0\nparticles = 300\nneighbours = 16\ngamma = 1.6666666666666667\nseed = 1\n')
    summary = tmp_path / "s.json"
    result = invoke("--config", config, "--out", tmp_path / "uniform.npz", "--summary", summary)
    assert result.exit_code == 0, result.output
    data = json.loads(summary.read_text())
    assert data["gamma"] == pytest.approx(5 / 3, rel=1e-15, abs=0) and data["parameters"]["polytrope"] == 0.0
    star = read_star(tmp_path / "uniform.npz")
    # n = 0: P / rho = G M (1 - r^2 / R^2) / (2 R), u = 1.5 P / rho
    r = np.linalg.norm(star.positions, axis=1)
    assert np.allclose(star.internal_energies, 1.5 * (1 - r**2) / 2, rtol=1e-10, atol=1e-12)


def test_an_existing_star_file_is_replaced_only_with_overwrite(tmp_path):
    out = tmp_path / "star.npz"
    out.write_text("mine")
    result = invoke("--polytrope", 1.5, "--particles", 100, "--neighbours", 10, "--out", out)
    assert result.exit_code == 2 and "exists: pass --overwrite" in result.output and out.read_text() == "mine"
    assert invoke("--polytrope", 1.5, "--particles", 100, "--neighbours", 10, "--out", out, "--overwrite").exit_code == 0
    assert len(read_star(out)) == 100


def test_a_mesa_profile_becomes_a_star_with_its_checks(tmp_path):
    """--profile: the model's mass in the star's units, the virial ratio in the table and the summary, the star
    file; a profile in the wrong units is sampled but warned about."""
    from tests.encounters.test_profile_star import _write_mesa, polytrope_cells

    profile = _write_mesa(tmp_path / "profile1.data", polytrope_cells(1.5, zones=799))
    out, summary = tmp_path / "star.npz", tmp_path / "star.json"
    result = invoke("--profile", profile, "--particles", 600, "--units", "stellar", "--neighbours", 20, "--out", out,
                    "--summary", summary)
    assert result.exit_code == 0, result.output
    data = json.loads(summary.read_text())
    assert data["profile"]["zones"] == 799 and abs(data["profile"]["virial_ratio"] - 1.0) < 1e-3
    assert read_star(out).mass == pytest.approx(1.0, rel=1e-3) and data["warnings"] == []
    said = " ".join(result.output.split())
    assert "unrelaxed star of profile1.data (stellar units" in said and "virial ratio" in said
    wrong = _write_mesa(tmp_path / "profile2.data", polytrope_cells(1.5, zones=400), ("radius_cm", "logRho", "logP"))
    wrong.write_text(wrong.read_text().replace("radius_cm", "radius"))  # centimetres read as solar radii
    flagged = invoke("--profile", wrong, "--particles", 100, "--neighbours", 10, "--out", tmp_path / "w.npz")
    assert flagged.exit_code == 0, flagged.output
    assert "warning: the profile is not in hydrostatic equilibrium" in " ".join(flagged.output.split())
