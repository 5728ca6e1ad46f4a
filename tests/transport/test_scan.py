"""collisionkit.transport.scan: SwarmParameters checks, and SwarmScan resumes from Python as if never stopped."""

from __future__ import annotations

from pathlib import Path

import pytest

from collisionkit._io import CheckpointError, FileLockedError, read_checkpoint, write_checkpoint
from collisionkit.transport import SwarmParameters, SwarmScan, scan

DATA = Path(__file__).parent.parent / "data"
QUICK = dict(model="reid", particles=640, seed=3, tolerance=0.05, collision_budget=2e6)


@pytest.mark.parametrize(
    ("values", "error", "words"),
    [
        ({}, ValueError, "give exactly one of model, gas and cross_sections"),
        ({"model": "reid", "cross_sections": "x.txt"}, ValueError, "give exactly one"),
        ({"model": "argon"}, ValueError, "model must be one of"),
        ({"model": "reid", "species": ["Ar"]}, ValueError, "species, fractions and database pick gases"),
        ({"model": "reid", "reduced_field": [10.0, float("nan")]}, ValueError,
         "reduced_field (E/N, Td) must be finite"),
        ({"model": "reid", "reduced_field": 0.0, "gas_temperature": 0.0}, ValueError, "no steady state"),
        ({"model": "reid", "scattering": "sideways"}, ValueError, "scattering must be one of isotropic, okhrimovskyy"),
        ({"model": "reid", "scattering": {"elastic": "bent"}}, ValueError, "scattering['elastic'] must be one of"),
        ({"model": "reid", "scattering": {"rotation": "forward"}}, ValueError,
         "scattering kind must be one of elastic"),
        ({"model": "reid", "scattering": 3}, TypeError, "scattering must be a law"),
        ({"model": "reid", "populations": {"reid:excitation": 1.0}}, ValueError,
         "populations['reid:excitation'] must be in [0, 1)"),
        ({"model": "reid", "populations": [0.1]}, TypeError, "populations must be a table"),
        ({"model": "reid", "particles": 100}, ValueError, "particles must be in [128, 10000000]"),
        ({"model": "reid", "tolerance": 0.0}, ValueError, "tolerance must be in (0, 0.5]"),
        ({"model": "reid", "reduced_magnetic_field": -5.0}, ValueError,
         "reduced_magnetic_field (B/N, Hx) must be in [0, 1e+06]"),
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
    assert relative.cross_sections[0].is_absolute()  # found again from any folder on resume


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


def _finished_scan(path):
    scan = SwarmScan(SwarmParameters(model="maxwell", reduced_field=[5.0], particles=128, tolerance=0.5,
                                     collision_budget=1e4), checkpoint=path)
    scan.run()
    return read_checkpoint(path, "swarm")


@pytest.mark.parametrize(
    ("change", "words"),
    [
        (lambda result: result.pop("mean_energy"), "result 0 cannot be read (data is not a SwarmResult.to_dict output"),
        (lambda result: result.update(mean_energy="high"), "result 0 cannot be read"),
        (lambda result: result.update(collisions="many"), "result 0 has a collisions of the wrong type"),
        (lambda result: result.update(converged=1), "result 0 has a converged of the wrong type"),
        (lambda result: result.update(drift_velocity_bulk=[1.0, 2.0]), "result 0 has a drift_velocity_bulk of"),
        (lambda result: result.update(eedf=[1.0]), "result 0 has a eedf of the wrong type or shape"),
        (lambda result: result.update(rate_coefficients={"a": "fast"}), "result 0 has a rate_coefficients of"),
    ],
)
def test_a_swarm_checkpoint_with_a_damaged_result_is_refused_naming_it(tmp_path, change, words):
    # a result of the wrong types was taken as it was, to fail in the summary at the end of the resumed scan
    path = tmp_path / "scan.npz"
    saved = _finished_scan(path)
    results = saved.state["results"]
    change(results[0])
    write_checkpoint(path, "swarm", saved.parameters, saved.state | {"results": results})
    with pytest.raises(CheckpointError) as caught:
        SwarmScan.resume(path)
    message = str(caught.value)
    assert message.startswith(f"{path} is a damaged swarm checkpoint: ") and words in message, message


@pytest.mark.parametrize(
    ("state", "words"),
    [
        ({"results": {"0": 1}}, "state 'results' must be a list"),
        ({"cross_sections_sha256": 7}, "state 'cross_sections_sha256' must be a text"),
    ],
)
def test_a_swarm_checkpoint_with_entries_of_the_wrong_type_is_refused_naming_them(tmp_path, state, words):
    path = tmp_path / "scan.npz"
    saved = _finished_scan(path)
    write_checkpoint(path, "swarm", saved.parameters, saved.state | state)
    with pytest.raises(CheckpointError, match=words):
        SwarmScan.resume(path)


def test_a_scan_whose_checkpoint_another_process_writes_is_refused_before_any_point(tmp_path, monkeypatch):
    from tests._io.processes import HOLD, held_by_another_process

    path = tmp_path / "scan.npz"
    monkeypatch.setattr(scan, "simulate_swarm", lambda *args, **kwargs: pytest.fail("a point ran"))
    with held_by_another_process(HOLD, path) as pid, pytest.raises(FileLockedError, match=f"pid {pid}"):
        SwarmScan(SwarmParameters(reduced_field=[12.0], **QUICK), checkpoint=path).run()
    assert not path.exists()


def test_reduced_fields_may_be_a_numpy_array():
    # a numpy-first user's np.array([1., 2.]) was refused: "must be a number"
    import numpy as np

    assert SwarmParameters(model="reid", reduced_field=np.array([1.0, 2.0])).reduced_field == (1.0, 2.0)
    assert SwarmParameters(model="reid", reduced_field=np.float64(3.0)).reduced_field == (3.0,)
    with pytest.raises(ValueError, match="1-D array"):
        SwarmParameters(model="reid", reduced_field=np.ones((2, 2)))


def test_a_scan_and_a_result_have_short_reprs():
    # a swarm result's repr printed every array (8000 characters); a scan's was <object at 0x...>
    from collisionkit.transport import maxwell_model, simulate_swarm

    assert repr(SwarmScan(SwarmParameters(model="maxwell", reduced_field=[5.0, 10.0]))) == \
        "SwarmScan(E/N 5, 10 Td, 0 of 2 done, checkpoint=None)"
    result = simulate_swarm(maxwell_model(), 5.0, particles=256, threads=1, collision_budget=1e5,
                            tolerances={"mean_energy": 0.5})
    text = repr(result)
    assert text.startswith("SwarmResult(reduced_field=5, ") and len(text) < 2000 and "<array (" in text
    assert f"mean_energy={result.mean_energy:.6g}," in text


def test_a_scan_keeps_its_callers_annotations_through_a_checkpoint(tmp_path):
    """Annotations are saved and given back by resume (a checkpoint without them gives {}); keys must be text."""
    path = tmp_path / "scan.npz"
    parameters = SwarmParameters(model="maxwell", reduced_field=[5.0], particles=300, tolerance=0.3)
    SwarmScan(parameters, checkpoint=path, annotations={"pressure": 760.0, "note": "chamber A"}).save()
    assert SwarmScan.resume(path).annotations == {"pressure": 760.0, "note": "chamber A"}
    SwarmScan(parameters, checkpoint=path).save()
    assert SwarmScan.resume(path).annotations == {}
    with pytest.raises(TypeError, match="str keys"):
        SwarmScan(parameters, annotations={1: "x"})
