"""collisionkit.plotting.collisions: units on the axes."""

from __future__ import annotations

import numpy as np

from collisionkit import plotting


def test_energy_loss_has_units_on_both_axes():
    ax = plotting.plot_energy_loss(np.linspace(0, 1, 5), np.zeros(5), 1.0, 0.5)
    assert "v^2" in ax.get_xlabel() and "v^2" in ax.get_ylabel()
