"""collisionkit.plotting: colour bars, axis labels with units, the sweep plot's theory curve."""

from __future__ import annotations

import gc

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from collisionkit import plotting, sweep  # noqa: E402
from collisionkit.encounters import Hyperbolic, starcrash_initial_conditions, unit_system  # noqa: E402


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


def colour_bars(figure):
    """Labels of the figure's colour bars (matplotlib gives their axes a ``_colorbar``)."""
    return [ax._colorbar.ax.get_ylabel() for ax in figure.axes if hasattr(ax, "_colorbar")]


def test_3d_snapshot_has_a_labelled_depth_colour_bar_and_axes_in_sigma():
    positions = [[1.0, 1.0, 2.1], [3.0, 3.0, 1.8], [2.0, 2.0, 0.3]]
    ax = plotting.plot_snapshot(positions, 0.5, [4.0, 4.0, 4.0])
    [label] = colour_bars(ax.figure)
    assert "sigma" in label and "z" in label
    assert ax.get_xlabel() == r"$x\,/\,\sigma$" and ax.get_ylabel() == r"$y\,/\,\sigma$"
    assert ax.collections[0].get_array().max() == pytest.approx(0.2)  # colour = |z - L_z/2| in sigma


def test_2d_snapshot_has_one_colour_and_no_colour_bar():
    ax = plotting.plot_snapshot([[1.0, 1.0], [3.0, 3.0]], 0.5, [4.0, 4.0])
    assert colour_bars(ax.figure) == [] and ax.get_xlabel() == r"$x\,/\,\sigma$"


def test_encounter_axes_are_in_periastron_distances_or_the_given_units():
    orbit = Hyperbolic(1.0, 2.0, periastron=2.0, v_inf=1.0)
    ax = plotting.plot_encounter(orbit)
    assert "r_p" in ax.get_xlabel() and "r_p" in ax.get_ylabel()
    periastron = ax.lines[3].get_xydata()[0]  # body 2's periastron marker, at m1/M r_p = r_p/3
    assert periastron == pytest.approx([1.0 / 3.0, 0.0])  # in r_p, not in length units (2/3)
    ic = starcrash_initial_conditions(1.0, 1.0, rp=1.0, vinf=1.0, sep0=10.0)
    solar = plotting.plot_encounter(ic, units=unit_system("solar"))
    assert "(AU)" in solar.get_xlabel() and "(AU)" in solar.get_ylabel()
    assert "(AU)" in plotting.plot_encounter(ic, units="solar").get_xlabel()


@pytest.mark.filterwarnings("ignore:Animation was deleted")
def test_animations_label_their_axes_and_colour_bars_with_units():
    frames = [{"positions": np.array([[1.0 + t, 2.0], [3.0, 2.0]]), "box": np.array([5.0, 4.0]),
               "velocities": np.array([[1.0, 0.0], [0.0, 0.0]]), "typeids": np.array([0, 1])}
              for t in range(2)]  # fmt: skip
    animation = plotting.animate_frames(frames, colour_by="speed")
    ax = animation._fig.axes[0]
    assert ax.get_xlabel() == r"$x\,/\,\sigma$" and "kT/m" in colour_bars(animation._fig)[0]
    species = plotting.animate_frames(frames, colour_by="species")._fig.axes[0]
    assert [text.get_text() for text in species.get_legend().get_texts()] == ["species 0", "species 1"]
    flyby = plotting.animate_encounter(Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0), frames=3, units="si")
    assert "(m)" in flyby._fig.axes[0].get_xlabel() and "(m/s)" in colour_bars(flyby._fig)[0]
    flyby = plotting.animate_encounter(Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0), frames=3)
    assert "r_p" in flyby._fig.axes[0].get_xlabel()
    del animation, species, flyby
    gc.collect()  # the unrendered animations' warning, here under this test's filter rather than in a later test


@pytest.mark.parametrize(
    ("draw", "unit"),
    [
        (lambda: plotting.plot_speed_distribution(np.linspace(0.1, 3, 100), kT=1.0, dim=3), "kT/m"),
        (lambda: plotting.plot_energy_loss(np.linspace(0, 1, 5), np.zeros(5), 1.0, 0.5), "v^2"),
    ],
)
def test_other_figures_have_units_on_both_axes(draw, unit):
    ax = draw()
    assert unit in ax.get_xlabel() and unit in ax.get_ylabel()


EDMD_ROWS = [
    {"packing-fraction": eta, "replica": replica, "status": "ok", "compressibility_factor": z + 0.01 * replica,
     "compressibility_factor_theory": z}
    for eta, z in [(0.1, 1.25), (0.2, 1.72), (0.3, 2.52)]
    for replica in range(2)
]  # fmt: skip


def test_plot_sweep_draws_the_theory_column_as_a_labelled_line():
    theory = "compressibility_factor_theory"
    ax = plotting.plot_sweep(EDMD_ROWS, "packing-fraction", "compressibility_factor", theory=theory)
    [theory] = [line for line in ax.lines if line.get_label() == "theory"]
    assert theory.get_ydata().tolist() == [1.25, 1.72, 2.52]
    assert len(ax.containers) == 1  # the measured means with error bars
    assert sorted(text.get_text() for text in ax.get_legend().get_texts()) == ["measured", "theory"]


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
