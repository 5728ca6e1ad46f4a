"""collisionkit.plotting.encounters: axes in periastron distances or the given units."""

from __future__ import annotations

import numpy as np
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


def test_the_stars_sit_at_the_start_of_their_trajectories():
    from collisionkit.encounters import StarEncounterParameters, polytrope_star, star_encounter_summary

    first = polytrope_star(1.5, 400, mass=1.0, neighbours=10, seed=1)
    second = polytrope_star(3.0, 300, mass=0.5, radius=0.5, neighbours=10, seed=2)
    _, ic, pair = star_encounter_summary(first, second, StarEncounterParameters(rp=1.5, sep0=15.0))
    ax = plotting.plot_star_encounter(ic, pair, units="nbody")
    assert len(ax.collections) == 2 and "(L)" in ax.get_xlabel()
    for body, (collection, star) in enumerate(zip(ax.collections, (first, second))):
        offsets = np.asarray(collection.get_offsets())
        assert len(offsets) == len(star)  # every particle (below max_points)
        start = ax.lines[2 * body].get_xydata()[0]  # the trajectory of the body starts at sep0
        assert np.allclose(offsets.mean(axis=0), start, rtol=0, atol=1e-9)  # equal masses: the mean is the centre of mass
    thinned = plotting.plot_star_encounter(ic, pair, max_points=100)
    assert [len(collection.get_offsets()) for collection in thinned.collections] == [100, 100]
    with pytest.raises(ValueError, match="placed pair"):
        plotting.plot_star_encounter(ic, first)
