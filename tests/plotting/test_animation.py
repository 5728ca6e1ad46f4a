"""collisionkit.plotting.animation: axis labels and colour bars with units."""

from __future__ import annotations

import gc

import numpy as np
import pytest

from collisionkit import plotting
from collisionkit.encounters import Hyperbolic
from tests.plotting import colour_bars


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
