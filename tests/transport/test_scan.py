"""collisionkit.transport.scan: SwarmParameters checks, and SwarmScan resumes from Python as if never stopped."""

from __future__ import annotations

from pathlib import Path

import pytest

from collisionkit._io import read_checkpoint
from collisionkit.transport import SwarmParameters, SwarmScan, scan

DATA = Path(__file__).parent.parent / "data"
QUICK = dict(model="reid", particles=640, seed=3, tolerance=0.05, collision_budget=2e6)


@pytest.mark.parametrize(
    ("values", "error", "words"),
    [
        ({}, ValueError, "give exactly one of model and cross_sections"),
        ({"model": "reid", "cross_sections": "x.txt"}, ValueError, "give exactly one"),
        ({"model": "argon"}, ValueError, "model must be one of"),
        ({"model": "reid", "species": ["Ar"]}, ValueError, "species and fractions pick gases"),
        ({"model": "reid", "reduced_field": [10.0, float("nan")]}, ValueError, "reduced_field (E/N) must be finite"),
        ({"model": "reid", "reduced_field": 0.0}, ValueError, "no steady state"),
        ({"model": "reid", "particles": 100}, ValueError, "particles must be in [128, 10000000]"),
        ({"model": "reid", "tolerance": 0.0}, ValueError, "tolerance must be in (0, 0.5]"),
        ({"model": "reid", "sharing": "half"}, ValueError, "sharing must be one of equal, uniform"),
        ({"model": "reid", "seed": True}, TypeError, "seed must be an integer"),
    ],
)
def test_bad_parameters_name_the_parameter_and_the_allowed_range(values, error, words):
    with pytest.raises(error) as caught:
        SwarmParameters(**values)
    assert words in str(caught.value)


def test_the_flags_and_the_python_names_spell_the_same_parameters():
    assert SwarmParameters.from_mapping({"model": "reid", "E-N": 5, "B-N": 100.0}) == \
        SwarmParameters(model="reid", reduced_field=[5.0], reduced_magnetic_field=100.0)
    relative = SwarmParameters(cross_sections=DATA / "lxcat_classic_reid.txt")
    assert relative.cross_sections.is_absolute()  # found again from any folder on resume


def test_a_scan_killed_mid_way_resumes_as_if_never_stopped(tmp_path, monkeypatch):
    parameters = SwarmParameters(reduced_field=[12.0, 24.0], **QUICK)
    straight = SwarmScan(parameters).run()
    real = scan.simulate_swarm

    def killed_at_24_td(gas, reduced_field, **options):
        if reduced_field == 24.0:
            raise KeyboardInterrupt
        return real(gas, reduced_field, **options)

    checkpoint = tmp_path / "scan.npz"
    monkeypatch.setattr(scan, "simulate_swarm", killed_at_24_td)
    with pytest.raises(KeyboardInterrupt):
        SwarmScan(parameters, checkpoint=checkpoint).run()
    monkeypatch.undo()
    assert [entry["reduced_field"] for entry in read_checkpoint(checkpoint, "swarm").state["results"]] == [12.0]
    resumed = SwarmScan.resume(checkpoint, particles=640)
    fractions = []
    results = resumed.run(progress=fractions.append)
    assert fractions[0] >= 0.5 and fractions[-1] == 1.0
    assert [r.mean_energy for r in results] == [r.mean_energy for r in straight]
    summary = resumed.summary()
    assert [entry["E_N"] for entry in summary["results"]] == [12.0, 24.0] and "mean_energy" not in summary
    assert SwarmParameters.from_mapping(summary["parameters"]) == parameters
    with pytest.raises(ValueError, match="particles = 1280 differs from the checkpoint"):
        SwarmScan.resume(checkpoint, particles=1280)


def test_a_single_point_summary_has_its_results_at_the_top_level():
    one = SwarmScan(SwarmParameters(reduced_field=12.0, **QUICK))
    one.run()
    summary = one.summary()
    assert summary["mean_energy"] == summary["results"][0]["mean_energy"] > 0
    assert len(summary["drift_velocity_bulk"]) == 3 and summary["mean_energy_error"] > 0
