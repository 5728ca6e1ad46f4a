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


def test_the_equation_of_state_of_discs_is_not_drawn_against_the_theory_of_spheres():
    # disc measurements plotted with dim=3 were drawn on the Hansen-Goos curve under the title "hard spheres"
    from collisionkit import edmd

    system = edmd.random_fluid(2, 100, 0.3, seed=1)
    measured = edmd.measure(system, collisions=2000, blocks=2)
    with pytest.raises(ValueError, match="measurement 0 is of a 2-D system; dim is 3"):
        plotting.plot_equation_of_state([measured], 3)
    assert plotting.plot_equation_of_state([measured], 2).get_title() == "hard discs"


def test_a_system_s_own_positions_and_box_draw_its_snapshot():
    # the box had 3 entries in 2-D, which plot_snapshot refused beside the system's (N, 2) positions
    from collisionkit import edmd

    system = edmd.random_fluid(2, 50, 0.3, seed=1)
    ax = plotting.plot_snapshot(system.positions(), system.radius, system.box)
    assert len(ax.collections[0].get_offsets()) == 50


def test_the_cooling_plot_draws_the_theory_through_the_first_point_and_each_species():
    collisions = np.arange(1.0, 6.0)
    temperatures = np.exp(-0.1 * collisions)
    ax = plotting.plot_cooling(collisions, temperatures, rate=0.05, species=np.tile([1.2, 0.8], (5, 1)))
    theory = ax.lines[1].get_ydata()
    assert theory[0] == temperatures[0] and theory[-1] == pytest.approx(temperatures[0] * np.exp(-0.2))
    np.testing.assert_allclose(ax.lines[2].get_ydata(), 1.2 * temperatures)
    assert ax.get_yscale() == "log" and len(plotting.plot_cooling(collisions, temperatures).lines) == 1
    with_theory = plotting.plot_cooling(collisions, temperatures, species=np.tile([1.2, 0.8], (5, 1)),
                                        species_theory=[1.1, 0.9])
    np.testing.assert_allclose(with_theory.lines[2].get_ydata(), 1.1 * temperatures)  # A's theory after A
    with pytest.raises(ValueError, match=r"species_theory must have shape \(2,\)"):
        plotting.plot_cooling(collisions, temperatures, species=np.ones((5, 2)), species_theory=[1.0])
    with pytest.raises(ValueError, match=r"species must have shape \(5, S\)"):
        plotting.plot_cooling(collisions, temperatures, species=np.ones((4, 2)))
    with pytest.raises(ValueError, match="one length"):
        plotting.plot_cooling(collisions, temperatures[:3])


def test_the_cooling_plot_draws_a_rough_gas_s_rotational_temperature_and_its_theory():
    collisions = np.arange(1.0, 6.0)
    temperatures = np.exp(-0.1 * collisions)
    ax = plotting.plot_cooling(collisions, temperatures, theory_temperatures=temperatures * 1.01,
                               rotation=0.8 * temperatures, theory_rotation=0.85 * temperatures)
    labels = [text.get_text() for text in ax.get_legend().get_texts()]
    assert labels == ["translation", "theory (Maxwellian)", "rotation", "rotation, theory"]
    np.testing.assert_allclose(ax.lines[2].get_ydata(), 0.8 * temperatures)
    np.testing.assert_allclose(ax.lines[3].get_ydata(), 0.85 * temperatures)
    with pytest.raises(ValueError, match=r"rotation must have shape \(5,\)"):
        plotting.plot_cooling(collisions, temperatures, rotation=temperatures[:4])
