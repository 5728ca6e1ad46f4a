"""Transport of square-well fluids: the energy's Helfand moment with the pairs' potential energy, the scattering
angle of one pair against the engine, the collision integrals' hard-sphere limit, and the dilute gas against
Chapman-Enskog with square-well collision integrals."""

import math

import numpy as np
import pytest

from collisionkit import edmd

from .systems import hexagonal_system

SHIFTS = {3: np.array([1.3, 2.7, 0.6]), 2: np.array([2.9, 1.1])}


def _moment_changes(dim, shift, collisions):
    """The changes of the Helfand moments (energy, momentum) of one square-well fluid over ``collisions``, its
    positions shifted by ``shift`` (the same fluid seen from another origin)."""
    if dim == 3:
        positions, box = edmd.lattice("fcc", 3, 0.3)
    else:
        positions, box = edmd.lattice("hexagonal", 8, 0.4)
    velocities = edmd.maxwell_boltzmann(np.ones(len(positions)), dim, seed=2)
    system = edmd.HardSphereSystem((positions + shift) % box, velocities, 0.5, box, well_width=1.5, well_depth=1.0)
    momentum, energy = system.helfand_moments()
    system.run(collisions=collisions)
    momentum_after, energy_after = system.helfand_moments()
    assert system.well_events["captures"] > 20 and system.well_events["escapes"] > 20
    assert np.any(system.image != 0)  # some pairs met across the box's faces
    return energy_after - energy, momentum_after - momentum


@pytest.mark.parametrize("dim", [3, 2])
def test_the_helfand_moments_change_alike_from_any_origin(dim):
    """Only the fluxes' integrals may enter: a moment that kept a particle's absolute position in a capture's or an
    escape's energy change (the kinetic energy alone, the potential energy's image terms left out, or the potential
    part missing; each tried as a mutant: 8 to 50 apart) changes differently for a shifted copy. Short runs keep
    the two trajectories the same to round-off (chaos separates them after some 1000 collisions)."""
    energy, momentum = _moment_changes(dim, np.zeros(dim), 200)
    energy_shifted, momentum_shifted = _moment_changes(dim, SHIFTS[dim], 200)
    scale = np.abs(energy).max()
    assert scale > 1.0
    np.testing.assert_allclose(energy_shifted, energy, rtol=0, atol=1e-8 * scale)
    np.testing.assert_allclose(momentum_shifted, momentum, rtol=0, atol=1e-8 * np.abs(momentum).max())


def test_the_energy_moment_of_a_drifting_bound_pair_moves_with_its_energy():
    """A bound pair at rest relative to each other, drifting at v = 0.3 along y: the moment is
    sum_i (m v^2/2 - epsilon/2) x_i, so it changes by 2 (m v^2/2 - epsilon/2) v t over a time t (the energy
    carried along), and it starts as that sum itself."""
    system = edmd.HardSphereSystem([[4.0, 5.0, 5.0], [5.2, 5.0, 5.0]], [[0, 0.3, 0], [0, 0.3, 0]], 0.5, [10.0] * 3,
                                   well_width=1.5, well_depth=2.0)
    each = 0.5 * 0.3**2 - 1.0
    _, start = system.helfand_moments()
    np.testing.assert_allclose(start, each * np.array([9.2, 10.0, 10.0]), rtol=1e-15)
    system.run(time=30.0)  # y wraps the periodic box: the moment goes on smoothly
    _, after = system.helfand_moments()
    np.testing.assert_allclose(after - start, [0.0, 2.0 * each * 0.3 * 30.0, 0.0], atol=1e-12)
    assert system.well_pairs == 1 and np.any(system.image != 0)


@pytest.mark.parametrize("impact", [0.0, 0.3, 0.9, 1.2, 1.4, 1.49, 1.6])
@pytest.mark.parametrize("energy", [0.3, 1.0, 4.0])
def test_the_deflection_formula_is_the_engines_scattering_angle(impact, energy):
    """One pair of unit masses fired past each other at impact parameter b and relative energy E = mu g^2 / 2 in a
    walled box: the angle between the relative velocities before and after equals |chi| of the refraction formula
    to round-off, for pairs whose cores touch, pairs that only cross the well, and pairs that miss it."""
    speed = math.sqrt(4.0 * energy)  # mu = 1/2
    system = edmd.HardSphereSystem([[40.0, 50.0 + impact, 50.0], [60.0, 50.0, 50.0]], [[speed, 0, 0], [0, 0, 0]], 0.5,
                                   [100.0] * 3, periodic=False, well_width=1.5, well_depth=1.0)
    system.run(time=45.0 / speed)
    velocities = system.velocities()
    after = velocities[1] - velocities[0]
    angle = math.acos(np.clip(after[0] / -(np.linalg.norm(after)), -1.0, 1.0))
    assert system.well_pairs == 0  # the pair has left its well again
    assert angle == pytest.approx(abs(edmd.square_well_deflection(impact, energy, 1.5)), abs=1e-12)


def test_the_collision_integrals_reach_hard_spheres_as_the_depth_vanishes():
    """Omega^(2,s) of hard spheres is 2 sigma^2 sqrt(pi kT / m) (1, 4, 20) for s = 2, 3, 4 (the Gaussian moments
    3, 12, 60 of gamma^(2s+3)); the second Sonine factors are then 1 + 9/606 and 1 + 9/396 (Chapman & Cowling's
    1.0148 and 1.0227). A well of depth 1e-9 kT changes them by about 1e-9."""
    kT, diameter, mass = 1.7, 1.3, 2.5
    hard = 2.0 * diameter**2 * math.sqrt(math.pi * kT / mass)
    for power, moment in ((2, 1.0), (3, 4.0), (4, 20.0)):
        value = edmd.square_well_collision_integral(2, power, kT, 1.5, diameter=diameter, depth=1e-9, mass=mass)
        assert value == pytest.approx(moment * hard, rel=1e-7)
    dilute = edmd.square_well_dilute_transport(kT, 1.5, diameter=diameter, depth=1e-9, mass=mass)
    first = 5.0 * kT / (8.0 * hard)
    assert dilute["shear_viscosity"] == pytest.approx(first * (1.0 + 9.0 / 606.0), rel=1e-7)
    assert dilute["thermal_conductivity"] == pytest.approx(3.75 / mass * first * (1.0 + 9.0 / 396.0), rel=1e-7)


def test_deep_wells_at_low_temperature_scatter_more_than_hard_spheres():
    """The wells pull grazing pairs in: Omega^(2,2) at T* = 1, lambda = 1.5 is 1.47 times the hard spheres', and
    it falls towards 1 as kT grows (at T* = 100 within 1 %)."""
    hard = 2.0 * math.sqrt(math.pi)
    ratios = [edmd.square_well_collision_integral(2, 2, kT, 1.5) / (hard * math.sqrt(kT)) for kT in (1.0, 5.0, 100.0)]
    assert ratios[0] == pytest.approx(1.4748, abs=1e-4)
    assert ratios[0] > ratios[1] > ratios[2] > 1.0 and ratios[2] < 1.01


def test_the_transport_measurement_takes_the_given_temperature():
    """Einstein's relations divide by kT (viscosities) and kT^2 (conductivity): twice the kT, half and a quarter."""
    system = edmd.random_fluid(3, 108, 0.3, seed=1)
    sampler = edmd.TransportSampler(system)
    for _ in range(2):
        sampler.run_block(5000)
    free_time = 1.0 / edmd.enskog_collision_frequency(edmd.carnahan_starling(system.packing_fraction), 3)
    from collisionkit.edmd._transport import transport_measurement

    base = transport_measurement(sampler, 2, free_time, system.volume, 108, kT=1.0)
    hotter = transport_measurement(sampler, 2, free_time, system.volume, 108, kT=2.0)
    assert hotter.shear_viscosity == pytest.approx(base.shear_viscosity / 2.0, rel=1e-12)
    assert hotter.thermal_conductivity == pytest.approx(base.thermal_conductivity / 4.0, rel=1e-12)


def test_a_square_well_measurement_reports_transport_at_its_mean_temperature():
    """Dense discs with deep wells, started far from their equilibrium energy split: the kT at the measurement's
    start and its time mean differ by percents, and the coefficients are those of the mean."""
    from collisionkit.edmd._transport import transport_measurement

    system = hexagonal_system(cells=8, eta=0.5, well_width=1.5, well_depth=3.0)
    sampler = edmd.Sampler(system, collisions=300 * system.count, blocks=2, transport=True)
    while not sampler.finished:
        sampler.run_block()
    measurement = sampler.result()
    start_kT, mean_kT = sampler.transport.kT, measurement.temperature_mean
    assert abs(start_kT / mean_kT - 1.0) > 0.02
    free_time = measurement.mean_free_time
    at_mean = transport_measurement(sampler.transport, 2, free_time, system.volume, system.count, kT=mean_kT)
    at_start = transport_measurement(sampler.transport, 2, free_time, system.volume, system.count)
    for key in ("shear_viscosity", "thermal_conductivity"):
        assert getattr(measurement.transport, key) == pytest.approx(getattr(at_mean, key), rel=1e-12)
        assert getattr(measurement.transport, key) != pytest.approx(getattr(at_start, key), rel=1e-3)


@pytest.mark.slow
def test_the_dilute_square_well_gas_follows_chapman_enskog():
    """N = 500 at n sigma^3 = 0.01, lambda = 1.5, kT ~ 2.05 epsilon: shear viscosity and thermal conductivity (each
    measured to ~3.5 %) against the second Sonine approximation with the square-well collision integrals, within
    4 errors plus 2 % for what the theory leaves out: the density's corrections and the bound pairs (of the order
    of n |B2| = 1.2 %), and the third Sonine order (~0.2 %). Hard spheres' values are 25 % higher: the test tells
    the wells apart (tried: 0.972 +- 0.034 and 1.012 +- 0.037 of the theory; 0.78 and 0.81 of hard spheres')."""
    positions, box = edmd.lattice("fcc", 5, math.pi * 0.01 / 6.0)
    velocities = edmd.maxwell_boltzmann(np.ones(500), 3, seed=1) * math.sqrt(2.0)
    system = edmd.HardSphereSystem(positions, velocities, 0.5, box, well_width=1.5, well_depth=1.0)
    system.run(collisions=20 * 500)
    measurement = edmd.measure(system, collisions=8000 * 500, blocks=20, transport=True)
    theory = edmd.square_well_dilute_transport(measurement.temperature_mean, 1.5)
    hard = edmd.chapman_enskog_transport(0.01, kT=measurement.temperature_mean)
    for key in ("shear_viscosity", "thermal_conductivity"):
        value, error = getattr(measurement.transport, key), getattr(measurement.transport, key + "_error")
        assert error < 0.05 * value, (key, value, error)
        assert abs(value - theory[key]) <= 4.0 * error + 0.02 * theory[key], (key, value, error, theory[key])
        assert hard[key] - value > 4.0 * error, (key, value, error, hard[key])


@pytest.mark.parametrize(("arguments", "message"), [
    ((-0.1, 1.0, 1.5), "impact"),
    ((0.5, 0.0, 1.5), "energy"),
    ((0.5, 1.0, 0.9), "width"),
    ((0.5, 1.0, 1.5, 1.0, -1.0), "depth"),
])
def test_the_deflection_refuses_bad_input_by_name(arguments, message):
    with pytest.raises(ValueError, match=message):
        edmd.square_well_deflection(*arguments)
