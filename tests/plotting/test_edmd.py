"""collisionkit.plotting.edmd: snapshot colour bars and axes in sigma, speed units."""

from __future__ import annotations

import numpy as np
import pytest

from collisionkit import plotting
from tests.plotting import colour_bars


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


def test_speed_distribution_has_units_on_both_axes():
    ax = plotting.plot_speed_distribution(np.linspace(0.1, 3, 100), kT=1.0, dim=3)
    assert "kT/m" in ax.get_xlabel() and "kT/m" in ax.get_ylabel()
