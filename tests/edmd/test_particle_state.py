"""Tests of the particles' views (collisionkit.edmd._particle_state): folded positions, images, rescaling."""

import math

import numpy as np
import pytest

from collisionkit import edmd
from tests.edmd.systems import fcc_system


def test_positions_are_folded_into_the_box_with_consistent_images():
    system = fcc_system(cells=3, eta=0.2)
    system.run(collisions=3000)
    folded, unwrapped = system.positions(), system.positions(unwrapped=True)
    box = system.box[:3]
    assert np.all((folded >= 0) & (folded < box))
    np.testing.assert_allclose(folded + system.image * box, unwrapped, atol=1e-12)


def test_rescale_temperature_scales_every_velocity_by_the_square_root_of_the_ratio():
    """kT = 2K / (d N) is quadratic in the velocities: reaching kT' multiplies each by sqrt(kT' / kT).
    Kills: sqrt(kT / current) -> kT / current."""
    positions, box = edmd.lattice("square", 6, 0.3)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(36), 2, kT=1.7, seed=3), 0.5, box)
    before = system.velocities()
    system.rescale_temperature(0.25)
    assert system.temperature() == pytest.approx(0.25, rel=1e-12)
    np.testing.assert_allclose(system.velocities(), before * math.sqrt(0.25 / 1.7), rtol=1e-12)


def test_snapshot_ahead_of_time_follows_the_parabola_under_gravity():
    """_folded(ahead=t) must equal the state after a free flight of t (no event before it): x + v t + g t^2/2.
    Kills: the g t^2 / 2 term dropped from the g(r) snapshot."""
    positions, box = edmd.lattice("sc", 4, 0.1)
    n = len(positions)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(n), 3, seed=8), 0.5, box,
                                   periodic=False, gravity=[0.0, 0.0, -3.0])
    system.run(collisions=200)
    system.synchronise()
    ahead = 0.5 * system._time_to_next_event()
    predicted = system._folded(ahead=ahead)[0].copy()
    system.run(time=ahead)
    system.synchronise()
    np.testing.assert_allclose(system.pos, predicted, rtol=0, atol=1e-12)
