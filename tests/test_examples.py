"""Every gallery example (``examples/plot_*.py``) and the validation page's script run to the end."""

import runpy
from pathlib import Path

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = sorted((ROOT / "examples").glob("plot_*.py"))
VALIDATION = sorted((ROOT / "docs" / "validation_src").glob("plot_*.py"))


def run_script(path, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # anything a script writes lands here
    plt.close("all")
    try:
        namespace = runpy.run_path(str(path), run_name="__main__")
        assert plt.get_fignums(), f"{path.name} drew no figure"
    finally:
        plt.close("all")
    return namespace


def test_the_gallery_has_the_examples_of_the_issue():
    names = {path.stem for path in EXAMPLES}
    expected = {
        "plot_newtons_cradle", "plot_billiard_break", "plot_stationary_scan", "plot_hard_sphere_eos",
        "plot_granular_cooling", "plot_stellar_flyby", "plot_rutherford", "plot_reid_ramp",
        "plot_slab_transmission", "plot_star_collision",
    }  # fmt: skip
    assert expected <= names


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda path: path.stem)
def test_example_runs(path, tmp_path, monkeypatch):
    text = path.read_text()
    assert text.startswith('"""'), f"{path.name} needs a sphinx-gallery docstring header"
    title = text.split("\n")[1:3]
    assert title[1].startswith("===") and len(title[1]) >= len(title[0]), f"{path.name}: title and underline"
    run_script(path, tmp_path, monkeypatch)


def test_newtons_cradle_hands_the_momentum_along(tmp_path, monkeypatch):
    namespace = run_script(ROOT / "examples" / "plot_newtons_cradle.py", tmp_path, monkeypatch)
    for moving in (1, 2, 3):
        _, _, v = namespace["cradle"](moving)
        assert list(v > 0.5) == [False] * (5 - moving) + [True] * moving


@pytest.mark.slow
@pytest.mark.parametrize("path", VALIDATION, ids=lambda path: path.stem)
def test_validation_script_runs(path, tmp_path, monkeypatch):
    run_script(path, tmp_path, monkeypatch)


def test_slab_example_meets_the_exact_results(tmp_path, monkeypatch):
    namespace = run_script(ROOT / "examples" / "plot_slab_transmission.py", tmp_path, monkeypatch)
    for result, tau in zip(namespace["rod"], namespace["thickness"]):
        assert abs(result.transmission - 1 / (1 + tau / 2)) < 4 * result.transmission_error + 1e-12
    for result, tau in zip(namespace["absorbing"], namespace["thickness"]):
        assert abs(result.transmission - np.exp(-tau)) < 4 * result.transmission_error + 1e-12
    assert namespace["worst"] < 1e-12


def test_star_collision_example_writes_the_placed_pair(tmp_path, monkeypatch):
    from collisionkit.encounters import read_star

    namespace = run_script(ROOT / "examples" / "plot_star_collision.py", tmp_path, monkeypatch)
    pair = read_star(tmp_path / "initial_conditions.hdf5")
    assert len(pair) == 4500 and pair.units.name == "stellar" and namespace["summary"]["warnings"] == []
    assert np.array_equal(pair.positions, namespace["pair"].positions)
    assert namespace["ic"].sep0 == 8 * (namespace["R1"] + namespace["R2"])
