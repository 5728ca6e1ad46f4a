"""Tests of the particles' views (collisionkit.edmd._particle_state): folded positions, images, rescaling."""

import math

import numpy as np
import pytest

from collisionkit import edmd
from collisionkit._kernels import edmd as edmd_kernels
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


def _flux_integrals_collision_by_collision(system, collisions):
    """The momentum and energy flux integrals of ``collisions`` pair collisions, from the users' views alone.

    Between collisions the fluxes are sum m v_a v_b and sum (m v^2 / 2) v_a (velocities constant); at a
    collision of i and j they jump by dp_j,a r_b and dE_j r_a, r = x_j - x_i the minimum image, dp_j and dE_j
    read off j's velocity change: an integration independent of the kernel's sums and image terms.
    """
    dim, box, mass = system.dim, system.box[: system.dim], system.mass
    momentum, energy, crossings = np.zeros((dim, dim)), np.zeros(dim), 0
    for _ in range(collisions):
        v, start = system.velocities(), system.elapsed
        system.run(collisions=1)
        momentum += (system.elapsed - start) * np.einsum("i,ia,ib->ab", mass, v, v)
        energy += (system.elapsed - start) * np.einsum("i,ia->a", 0.5 * mass * np.sum(v**2, axis=1), v)
        after, x = system.velocities(), system.positions()
        i, j = np.flatnonzero(np.any(after != v, axis=1))
        separation = x[j] - x[i]
        r = separation - box * np.round(separation / box)
        crossings += bool(np.any(r != separation))
        momentum += np.outer(mass[j] * (after[j] - v[j]), r)
        energy += 0.5 * mass[j] * (after[j] @ after[j] - v[j] @ v[j]) * r
    return momentum, energy, crossings


@pytest.mark.parametrize("engine", ["lists", "cells"])
@pytest.mark.parametrize("lattice, cells, dim", [("hexagonal", 6, 2), ("fcc", 3, 3)])
def test_helfand_moments_change_by_the_integrals_of_the_momentum_and_energy_fluxes(lattice, cells, dim, engine):
    """G(t) - G(0) = int J dt with the minimum-image collisional flux: the stored-position moments plus
    Erpenbeck's image terms, through pairs colliding across faces and particles wrapped at list rebuilds (the
    lists) or at crossings of periodic faces (the cells).
    Kills: a sign or axis swap of an image term, a missing wrap correction, the energy transfer of i for j's."""
    positions, box = edmd.lattice(lattice, cells, 0.35)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(len(positions)), dim, seed=4), 0.5, box,
                                   engine=engine)
    system.run(collisions=500)
    momentum0, energy0 = system.helfand_moments()
    rebuilds = system.acc[edmd_kernels.ACC_LIST_REBUILDS]
    momentum, energy, crossings = _flux_integrals_collision_by_collision(system, 400)
    assert crossings > 10 and system.acc[edmd_kernels.ACC_LIST_REBUILDS] > rebuilds + 50  # both kinds of image
    momentum1, energy1 = system.helfand_moments()
    scale = np.abs(momentum).max()
    np.testing.assert_allclose(momentum1 - momentum0, momentum, rtol=0, atol=1e-13 * scale)
    np.testing.assert_allclose(energy1 - energy0, energy, rtol=0, atol=1e-13 * np.abs(energy).max())
    # the flux is symmetric, so are the moment's changes, though sum m v_x y and sum m v_y x are not
    change = momentum1 - momentum0
    np.testing.assert_allclose(change, change.T, rtol=0, atol=1e-13 * scale)


def test_the_trace_of_the_momentum_moment_is_the_pressure_integral_to_round_off():
    """trace dG = 2 K t + sum of impulse x contact distance (the virial of the pressure): an identity.
    Kills: a collisional stress slot summed with the wrong sign or pair of axes."""
    system = fcc_system(cells=3, eta=0.4)
    system.run(collisions=2000)
    momentum0, _ = system.helfand_moments()
    virial0, stress0, start = system.virial, system.collisional_stress, system.elapsed
    system.run(collisions=20_000)
    momentum1, _ = system.helfand_moments()
    pressure_integral = 2.0 * system.kinetic_energy() * (system.elapsed - start) + system.virial - virial0
    assert np.trace(momentum1 - momentum0) == pytest.approx(pressure_integral, rel=1e-12)
    stress = system.collisional_stress - stress0
    assert np.trace(stress) == pytest.approx(system.virial - virial0, rel=1e-12)
    np.testing.assert_array_equal(stress, stress.T)
    assert np.all(np.diag(stress) > 0)
