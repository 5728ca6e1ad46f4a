"""Plots of transport results: the two-term EEDFs stay readable for a long scan."""

import numpy as np

from collisionkit import plotting
from collisionkit.transport import reid_ramp, two_term_boltzmann


def fake(field, mean):
    energy = np.linspace(0.0, 30.0 * mean, 400)[1:]
    return type("R", (), {"energy": energy, "eedf": np.exp(-energy / mean), "reduced_field": field,
                          "mean_energy": 1.5 * mean})()


def test_a_few_curves_are_named_in_a_legend_on_a_linear_energy_axis():
    ax = plotting.plot_two_term_eedf([two_term_boltzmann(reid_ramp(), field, 0.0) for field in (1.0, 2.0)])
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["E/N = 1 Td", "E/N = 2 Td"]
    assert ax.get_xscale() == "linear" and len(ax.figure.axes) == 1


def test_a_long_scan_is_coloured_by_e_n_on_a_colour_bar_and_a_log_energy_axis():
    """31 E/N values from 0.01 to 1e4 Td (a new user's scan squeezed the plot behind a 31-entry legend)."""
    results = [fake(field, 0.03 * field**0.5 + 0.02) for field in np.logspace(-2, 4, 31)]
    ax = plotting.plot_two_term_eedf(results)
    assert ax.get_legend() is None and len(ax.figure.axes) == 2  # the colour bar's axes
    assert ax.figure.axes[1].get_ylabel() == "E/N (Td)"
    assert ax.get_xscale() == "log"
    colours = {tuple(line.get_color()) for line in ax.get_lines()}
    assert len(colours) == 31
    peak = max(float(r.eedf.max()) for r in results)
    assert ax.get_ylim()[0] == 1e-12 * peak
