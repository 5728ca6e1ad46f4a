"""collisionkit.plotting.encounters: axes in periastron distances or the given units."""

from __future__ import annotations

import pytest

from collisionkit import plotting
from collisionkit.encounters import Hyperbolic, starcrash_initial_conditions, unit_system


def test_encounter_axes_are_in_periastron_distances_or_the_given_units():
    orbit = Hyperbolic(1.0, 2.0, periastron=2.0, v_inf=1.0)
    ax = plotting.plot_encounter(orbit)
    assert "r_p" in ax.get_xlabel() and "r_p" in ax.get_ylabel()
    periastron = ax.lines[3].get_xydata()[0]  # body 2's periastron marker, at m1/M r_p = r_p/3
    assert periastron == pytest.approx([1.0 / 3.0, 0.0])  # in r_p, not in length units (2/3)
    ic = starcrash_initial_conditions(1.0, 1.0, rp=1.0, v_inf=1.0, sep0=10.0)
    solar = plotting.plot_encounter(ic, units=unit_system("solar"))
    assert "(AU)" in solar.get_xlabel() and "(AU)" in solar.get_ylabel()
    assert "(AU)" in plotting.plot_encounter(ic, units="solar").get_xlabel()
