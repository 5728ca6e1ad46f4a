"""collisionkit.plotting.sweep: the sweep plot of aggregated points and its theory curve."""

from __future__ import annotations

import math

import numpy as np
import pytest

from collisionkit import plotting, sweep

# EDMD_ROWS (below) aggregated across their two replicas: mean, standard error and the theory
EDMD_POINTS = [
    {"packing-fraction": eta, "mean": z + 0.005, "error": 0.005, "theory": z}
    for eta, z in [(0.1, 1.25), (0.2, 1.72), (0.3, 2.52)]
]


def test_plot_sweep_draws_the_theory_column_as_a_labelled_line():
    ax = plotting.plot_sweep(EDMD_POINTS, "packing-fraction", "compressibility_factor")
    [theory] = [line for line in ax.lines if line.get_label() == "theory"]
    assert theory.get_ydata().tolist() == [1.25, 1.72, 2.52]
    assert len(ax.containers) == 1  # the measured means with error bars
    assert sorted(text.get_text() for text in ax.get_legend().get_texts()) == ["measured", "theory"]
    assert ax.get_xlabel() == "packing-fraction"
    assert ax.get_ylabel() == "compressibility_factor (mean of replicas)"


def test_plot_sweep_draws_one_line_per_series_with_its_own_theory():
    points = [point | {"restitution": e, "theory": point["theory"] * e} for point in EDMD_POINTS for e in (0.5, 1)]
    ax = plotting.plot_sweep(points, "packing-fraction", "compressibility_factor", series=["restitution"], title="t")
    assert len(ax.containers) == 2 and ax.get_title() == "t"
    assert sorted(text.get_text() for text in ax.get_legend().get_texts()) == [
        "restitution = 0.5", "restitution = 0.5, theory", "restitution = 1", "restitution = 1, theory",
    ]  # fmt: skip


def test_plot_sweep_leaves_out_points_without_a_mean_and_bars_without_an_error():
    points = [{"x": 1, "mean": 2.0, "error": math.nan}, {"x": 2, "mean": math.nan, "error": 0.1},
              {"x": 3, "mean": 4.0, "error": 0.5}]  # fmt: skip
    ax = plotting.plot_sweep(points, "x", "y")
    [bars] = ax.containers
    assert bars.lines[0].get_xdata().tolist() == [1, 3]
    assert ax.get_legend() is None  # one line, no theory: nothing to tell apart
    [error_bars] = bars.lines[2]
    assert np.ptp(error_bars.get_segments()[0][:, 1]) == 0.0  # the NaN error draws no bar
    assert np.ptp(error_bars.get_segments()[1][:, 1]) == pytest.approx(1.0)


def test_plot_sweep_needs_a_point_with_a_finite_mean():
    with pytest.raises(ValueError, match="no finite mean of 'Z'"):
        plotting.plot_sweep([{"eta": 0.1, "mean": math.nan, "error": math.nan}], "eta", "Z")
    with pytest.raises(ValueError, match="no finite mean"):
        plotting.plot_sweep([], "eta", "Z")


EDMD_ROWS = [
    {"packing-fraction": eta, "replica": replica, "status": "ok", "compressibility_factor": z + 0.01 * replica,
     "compressibility_factor_theory": z}
    for eta, z in [(0.1, 1.25), (0.2, 1.72), (0.3, 2.52)]
    for replica in range(2)
]  # fmt: skip


def test_sweep_main_result_plot_shows_the_edmd_theory(tmp_path, monkeypatch):
    drawn = []
    monkeypatch.setattr(plotting, "save", lambda ax, path: drawn.append(ax) or path)
    study = sweep.Study("edmd", seed=1, vary={"packing_fraction": [0.1, 0.2, 0.3]}, replicas=2)
    sweep.write_outputs(study, tmp_path, EDMD_ROWS)
    [ax] = drawn
    assert "theory" in [line.get_label() for line in ax.lines]
    assert "theory" in [text.get_text() for text in ax.get_legend().get_texts()]
    drawn.clear()
    without = [{key: value for key, value in row.items() if not key.endswith("_theory")} for row in EDMD_ROWS]
    sweep.write_outputs(study, tmp_path, without)  # no theory column (e.g. inelastic runs): points only
    assert [line.get_label() for line in drawn[0].lines if line.get_label() == "theory"] == []
