"""Rough spheres and discs in the engine: the collision rule against rigid-body mechanics, conservation, state."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from collisionkit import _kernels
from collisionkit._io import CheckpointError
from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann, random_spins

ANGLES = st.floats(-1.0, 1.0)


def _cross_matrix(vector):
    """[a]x, the matrix of a x . (a cross product from the left)."""
    x, y, z = vector
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def _rigid_body_collision(n, v, w, m, a, kappa, e, beta):
    """Post-collision velocities and spins of two rigid spheres (i = 0, j = 1, n from i to j at contact).

    The contact velocity g of j's surface relative to i's changes by K J under
    an impulse J on j (-J on i) at the contact point (Mirtich's collision
    matrix, built here from the rigid-body equations, not from the engine's
    reduced mass); J solves K J = g' - g with g' = -e g_n n - beta g_t.
    """
    arms = (a[0] * n, -a[1] * n)  # contact point from each centre
    inertia = kappa * m * a**2

    def contact_velocity(v, w):
        return (v[1] + np.cross(w[1], arms[1])) - (v[0] + np.cross(w[0], arms[0]))

    def apply(impulse):
        dv = np.array([-impulse / m[0], impulse / m[1]])
        dw = np.array([np.cross(arms[0], -impulse) / inertia[0], np.cross(arms[1], impulse) / inertia[1]])
        return dv, dw

    matrix = np.column_stack([contact_velocity(*apply(unit)) for unit in np.eye(3)])
    g = contact_velocity(v, w)
    normal = (g @ n) * n
    target = -e * normal - beta * (g - normal)
    dv, dw = apply(np.linalg.solve(matrix, target - g))
    return v + dv, w + dw


def _pair(direction, speed, spins, masses, radii, beta, kappa, e=1.0, dim=3):
    """Two particles 0.3 apart at contact-to-be, j approaching i along ``direction`` (a grazing offset allowed)."""
    contact = radii[0] + radii[1]
    x_i = np.full(dim, 10.0)
    x_j = x_i + (contact + 0.3) * direction
    velocities = np.zeros((2, dim))
    velocities[1] = -speed * direction
    velocities[1, 1 % dim] += 0.2  # a tangential component: the pair meets off-centre
    velocities[0, 0] += 0.1
    system = HardSphereSystem([x_i, x_j], velocities, radii, 20.0, masses, tangential_restitution=beta,
                              inertia_factor=kappa, restitution=e, angular_velocities=spins, elastic_below=0.0)
    return system, velocities


def _angular_momentum(system):
    x, v = system.positions(unwrapped=True), system.velocities()
    if system.dim == 2:
        return float(np.sum(system.mass * (x[:, 0] * v[:, 1] - x[:, 1] * v[:, 0]))) + system.spin_angular_momentum()
    return (system.mass[:, None] * np.cross(x, v)).sum(axis=0) + system.spin_angular_momentum()


@settings(max_examples=40, deadline=None)
@given(beta=ANGLES, kappa=st.floats(0.05, 1.0), e=st.floats(0.0, 1.0), ratio=st.floats(0.2, 5.0),
       size=st.floats(0.3, 1.0), spin=st.lists(st.floats(-3.0, 3.0), min_size=6, max_size=6))
def test_a_rough_collision_is_the_rigid_body_impulse_that_reverses_the_contact_velocity(beta, kappa, e, ratio, size,
                                                                                          spin):
    direction = np.array([1.0, 0.35, -0.2]) / np.linalg.norm([1.0, 0.35, -0.2])
    spins = np.reshape(spin, (2, 3))
    system, velocities = _pair(direction, 1.0, spins, [1.0, ratio], [0.5, 0.5 * size], beta, kappa, e)
    momentum_before = _angular_momentum(system)
    assert system.run(collisions=1) == 1
    x = system.positions()
    n = (x[1] - x[0]) / np.linalg.norm(x[1] - x[0])
    v_after, w_after = _rigid_body_collision(n, velocities, spins, np.array([1.0, ratio]), np.array([0.5, 0.5 * size]),
                                             kappa, e, beta)
    np.testing.assert_allclose(system.velocities(), v_after, atol=1e-12)
    np.testing.assert_allclose(system.angular_velocities(), w_after, atol=1e-11)
    np.testing.assert_allclose(_angular_momentum(system), momentum_before, atol=1e-11)


def test_a_disc_collision_spins_the_discs_about_the_plane_normal_only():
    direction = np.array([1.0, 0.4]) / np.linalg.norm([1.0, 0.4])
    system, velocities = _pair(direction, 1.0, [0.5, -1.0], [1.0, 2.0], [0.5, 0.4], 0.4, 0.5, dim=2)
    before = _angular_momentum(system)
    system.run(collisions=1)
    assert system.spin[:, :2].tolist() == [[0.0, 0.0], [0.0, 0.0]]
    x = system.positions()
    n = np.append((x[1] - x[0]) / np.linalg.norm(x[1] - x[0]), 0.0)
    v3 = np.pad(velocities, ((0, 0), (0, 1)))
    w3 = np.array([[0.0, 0.0, 0.5], [0.0, 0.0, -1.0]])
    v_after, w_after = _rigid_body_collision(n, v3, w3, np.array([1.0, 2.0]), np.array([0.5, 0.4]), 0.5, 1.0, 0.4)
    np.testing.assert_allclose(system.velocities(), v_after[:, :2], atol=1e-12)
    np.testing.assert_allclose(system.angular_velocities(), w_after[:, 2], atol=1e-12)
    assert _angular_momentum(system) == pytest.approx(before, abs=1e-12)


def _gas(dim, beta, engine, e=1.0, seed=1):
    positions, box = lattice("fcc" if dim == 3 else "square", 5 if dim == 3 else 16, 0.2)
    count = len(positions)
    moments = np.full(count, (0.4 if dim == 3 else 0.5) * 0.25)
    return HardSphereSystem(positions, maxwell_boltzmann(np.ones(count), dim, seed=seed), 0.5, box,
                            restitution=e, tangential_restitution=beta, engine=engine, elastic_below=0.0,
                            angular_velocities=random_spins(moments, dim, seed=seed + 1))


@pytest.mark.parametrize("engine", ["lists", "cells"])
@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("beta", [-1.0, 1.0])
def test_elastic_smooth_and_perfectly_rough_gases_keep_energy_and_momentum_to_round_off(engine, dim, beta):
    system = _gas(dim, beta, engine)
    energy, spins = system.total_kinetic_energy(), system.angular_velocities()
    system.run(collisions=25 * system.count)
    system.run(collisions=system.count)  # a run starts with a re-sort in memory when SORT_INTERVAL N have passed
    assert abs(system.total_kinetic_energy() / energy - 1.0) < 1e-13
    assert np.abs(system.momentum()).max() < 1e-12
    if beta == -1.0:  # smooth: no torque, the spins never change (through the re-sorts in memory as well)
        assert system.last_sort > 0 and np.array_equal(system.angular_velocities(), spins)
    else:  # perfectly rough: translation and rotation trade energy
        assert not np.array_equal(system.angular_velocities(), spins)


@pytest.mark.parametrize("engine", ["lists", "cells"])
def test_the_energy_rough_contacts_take_is_booked_as_lost(engine):
    system = _gas(3, 0.3, engine, e=0.9)
    energy = system.total_kinetic_energy()
    system.run(collisions=5 * system.count)
    assert system.energy_lost > 0.3 * energy
    assert system.total_kinetic_energy() + system.energy_lost == pytest.approx(energy, rel=1e-13)


def test_a_checkpoint_continues_a_rough_run_bit_for_bit():
    system = _gas(3, 0.3, "lists", e=0.95)
    system.run(collisions=3000)
    copy = HardSphereSystem.from_state_dict(system.state_dict())
    assert copy.tangential_restitution == 0.3 and copy.inertia_factor == 0.4  # as given, bit for bit
    system.run(collisions=3000)
    copy.run(collisions=3000)
    assert np.array_equal(system.angular_velocities(), copy.angular_velocities())
    assert np.array_equal(system.velocities(), copy.velocities())


def test_a_checkpoint_of_an_older_format_is_smooth_and_a_bad_spin_array_is_refused():
    state = _gas(2, 0.5, "lists").state_dict()
    bad = dict(state, spin=np.zeros((3, 3)))
    with pytest.raises(CheckpointError, match="spin"):
        HardSphereSystem.from_state_dict(bad)
    twisted = dict(state, spin=np.ones_like(state["spin"]))  # discs spinning about an axis in their plane
    with pytest.raises(CheckpointError, match="about the normal"):
        HardSphereSystem.from_state_dict(twisted)
    smooth = HardSphereSystem(*lattice("square", 16, 0.2)[:1], np.zeros((256, 2)), 0.5, lattice("square", 16, 0.2)[1])
    old = smooth.state_dict()
    cut = 18  # format 9 had no rough entries: the well table followed the 18 parameters
    nine = {name: value for name, value in old.items() if name != "spin"} | {
        "format": np.asarray(9), "params": np.concatenate([old["params"][:cut], old["params"][cut + 3:]])}
    restored = HardSphereSystem.from_state_dict(nine)
    assert not restored.rough and restored.rotational_energy() == 0.0
    ten = old | {"format": np.asarray(10), "params": np.delete(old["params"], 20)}  # smooth, no friction entry
    assert not HardSphereSystem.from_state_dict(ten).rough
    rough = _gas(2, 0.5, "lists").state_dict()  # development versions wrote rough format 10 two ways: refused
    with pytest.raises(CheckpointError, match="restart the rough run"):
        HardSphereSystem.from_state_dict(rough | {"format": np.asarray(10), "params": np.delete(rough["params"], 20)})


def test_rough_spheres_refuse_what_they_cannot_run_and_a_smooth_system_has_no_spins():
    positions, box = lattice("square", 16, 0.2)
    velocities = np.zeros((256, 2))
    with pytest.raises(ValueError, match="cannot be combined with shear"):
        HardSphereSystem(positions, velocities, 0.5, box, tangential_restitution=0.5, shear_rate=0.1)
    with pytest.raises(ValueError, match="cannot be combined with square wells"):
        HardSphereSystem(positions, velocities, 0.5, box, tangential_restitution=0.5, well_width=1.5)
    with pytest.raises(ValueError, match=r"tangential_restitution must .*\[-1, 1\]"):
        HardSphereSystem(positions, velocities, 0.5, box, tangential_restitution=1.5)
    with pytest.raises(ValueError, match="inertia_factor needs rough spheres"):
        HardSphereSystem(positions, velocities, 0.5, box, inertia_factor=0.4)
    with pytest.raises(ValueError, match=r"angular_velocities must have shape \(256,\)"):
        HardSphereSystem(positions, velocities, 0.5, box, tangential_restitution=0.5, angular_velocities=np.zeros((256, 3)))
    smooth = HardSphereSystem(positions, velocities, 0.5, box)
    assert smooth.tangential_restitution is None and smooth.rotational_energy() == 0.0
    with pytest.raises(ValueError, match="needs rough spheres"):
        smooth.angular_velocities()


def test_random_spins_have_the_variance_kT_over_I():
    moments = np.full(200_000, 0.2)
    omega = random_spins(moments, 2, kT=0.5, seed=3)
    # the sample variance of 200000 normals is within 4 of its relative error sqrt(2 / n) = 0.0032
    assert np.var(omega) * 0.2 == pytest.approx(0.5, rel=4 * math.sqrt(2 / 200_000))
    assert omega.shape == (200_000,)


def test_a_run_of_rough_spheres_starting_without_spin_shares_the_energy_with_the_spins(tmp_path):
    """beta = 1, e = 1 from rotational kT 0: the energy stays, and kT falls to its equipartition value 2E / ((d + f)
    N) = 1/2; smooth elastic spheres (beta = -1) keep their spins and get no ratio theory; a resumed run must keep
    its roughness."""
    from collisionkit.edmd import EdmdParameters, EdmdRun

    parameters = EdmdParameters(particles=256, packing_fraction=0.1, tangential_restitution=1.0,
                                initial_rotational_temperature=0.0, seed=2, collisions=8000, equilibration=4000,
                                blocks=4)
    odd = EdmdRun(parameters.replace(tangential_restitution=0.3, restitution=0.95, initial_rotational_temperature=0.7),
                  checkpoint=tmp_path / "odd.npz").run()
    assert odd.system.tangential_restitution == 0.3  # (a resume compares it exactly)
    resumed = EdmdRun.resume(tmp_path / "odd.npz")
    resumed.extend(2000)
    assert resumed.run().summary()["collisions"] == 10000
    run = EdmdRun(parameters, checkpoint=tmp_path / "run.npz").run()
    with pytest.raises(ValueError, match="tangential_restitution"):
        EdmdRun.resume(tmp_path / "run.npz", tangential_restitution=0.5)
    assert EdmdRun.resume(tmp_path / "run.npz").system.tangential_restitution == 1.0
    assert run.initial_energy == pytest.approx(1.5 * 256, rel=1e-12)  # no spin at the start: kT = 1 exactly
    summary = run.summary()
    assert summary["temperature_theory"] == pytest.approx(0.5, rel=1e-12)
    # kT of 256 particles at equipartition scatters by sqrt(2 / (3 N)) = 5 % about 1/2
    assert summary["temperature"] == pytest.approx(0.5, abs=4 * 0.5 * math.sqrt(2 / (3 * 256)))
    assert abs(summary["energy_lost_total"]) < 1e-11 * run.initial_energy
    smooth = EdmdRun(parameters.replace(tangential_restitution=-1.0, initial_rotational_temperature=2.0)).run()
    result = smooth.summary()
    assert "temperature_ratio_theory" not in result and result["temperature"] == pytest.approx(1.0, rel=1e-12)
    assert result["rotational_temperature"] == pytest.approx(2.0, rel=1e-12)  # scaled at the start, never turned
    with pytest.raises(ValueError, match="initial_rotational_temperature needs rough spheres"):
        EdmdParameters(initial_rotational_temperature=0.5)


def test_spins_start_at_the_rotational_temperature_asked_for_exactly():
    from collisionkit.edmd import EdmdParameters, EdmdRun

    for dim, kT in ((2, 0.7), (3, 2.5)):
        parameters = EdmdParameters(dim=dim, particles=64, packing_fraction=0.1, tangential_restitution=0.5,
                                    initial_rotational_temperature=kT, seed=1)
        assert EdmdRun(parameters).system.rotational_temperature() == pytest.approx(kT, rel=1e-12)


def test_walls_leave_the_spins_alone_and_slow_contacts_below_the_floor_are_smooth():
    """A wall is smooth: a bounce changes no spin. Below the elastic floor a contact is smooth too (no tangential
    impulse), so that nothing is lost there: a slow grazing pair keeps its spins and energy."""
    bouncing = HardSphereSystem([[1.0, 1.0], [5.0, 5.0]], [[-1.0, 0.3], [0.0, 0.0]], 0.5, 10.0, periodic=False,
                                tangential_restitution=1.0, angular_velocities=[2.0, 0.0])
    bouncing.run(time=1.0)
    assert bouncing.wall_collisions == 1 and bouncing.angular_velocities().tolist() == [2.0, 0.0]
    direction = np.array([1.0, 0.35, -0.2]) / np.linalg.norm([1.0, 0.35, -0.2])
    system, _ = _pair(direction, 1e-3, np.ones((2, 3)), [1.0, 1.0], [0.5, 0.5], 0.0, 0.4, e=0.5)
    system.params[_kernels.edmd.P_ELASTIC_BELOW] = 1.0  # every contact here is slower: elastic and smooth
    energy, spins = system.total_kinetic_energy(), system.angular_velocities()
    assert system.run(collisions=1) == 1
    assert np.array_equal(system.angular_velocities(), spins)
    assert system.total_kinetic_energy() == pytest.approx(energy, rel=1e-13) and system.energy_lost == 0.0


def test_rough_spheres_refuse_a_transport_measurement():
    from collisionkit.edmd import Sampler

    with pytest.raises(ValueError, match="rough spheres"):
        Sampler(_gas(3, 0.5, "lists"), collisions=1000, blocks=2, transport=True)


def test_an_inelastic_rough_mixture_gets_no_smooth_theory():
    """Garzo-Dufty's species temperatures and the mixture's cooling rate are smooth spheres': a rough inelastic
    mixture's summary gives no species theory and a NaN cooling theory."""
    from collisionkit.edmd import EdmdParameters, EdmdRun

    parameters = EdmdParameters(particles=200, packing_fraction=0.05, restitution=0.9, tangential_restitution=0.5,
                                fractions=(0.5, 0.5), masses=(1.0, 2.0), seed=1, collisions=2000, equilibration=200,
                                blocks=4)
    summary = EdmdRun(parameters).run().summary()
    assert "temperature_species" in summary and "temperature_species_theory" not in summary
    assert math.isnan(summary["cooling_rate_theory"]) and "temperature_ratio_theory" not in summary


@pytest.mark.parametrize("dim", [2, 3])
def test_trajectory_files_carry_the_spins(tmp_path, dim):
    """GSD frames give HOOMD-blue's moment_inertia and angmom (2 I omega at the identity orientation), read back as
    the angular velocities; extended XYZ adds an omega column."""
    from collisionkit.trajectory import read_gsd, write_extended_xyz, write_gsd_frame

    system = _gas(dim, 0.5, "lists", e=0.9)
    system.run(collisions=500)
    write_gsd_frame(tmp_path / "t.gsd", system, 0)
    frame = read_gsd(tmp_path / "t.gsd")
    import gsd.hoomd

    with gsd.hoomd.open(tmp_path / "t.gsd", "r") as raw:  # HOOMD-blue's own fields: p = (0, 2 I omega) at q = 1
        snapshot = raw[0]
    omega = system.angular_velocities() if dim == 3 else np.column_stack([np.zeros((system.count, 2)),
                                                                         system.angular_velocities()])
    moments = system.moments_of_inertia()[:, None]
    np.testing.assert_allclose(snapshot.particles.angmom[:, 1:], 2 * moments * omega, rtol=1e-6, atol=1e-7)
    assert np.all(snapshot.particles.angmom[:, 0] == 0.0)
    np.testing.assert_allclose(frame["angular_velocities"], system.angular_velocities(), rtol=1e-6)
    lines = write_extended_xyz(tmp_path / "s.xyz", system).read_text().splitlines()
    assert ":omega:R:3:type:S:1" in lines[1]
    spins = np.array([[float(value) for value in line.split()[12:15]] for line in lines[2:]])
    expected = system.angular_velocities()
    np.testing.assert_array_equal(spins if dim == 3 else spins[:, 2], expected)


@settings(max_examples=30, deadline=None)
@given(beta=ANGLES, friction=st.floats(0.01, 2.0), e=st.floats(0.0, 1.0), spin=st.lists(st.floats(-5.0, 5.0),
                                                                                          min_size=6, max_size=6))
def test_walton_friction_caps_the_tangential_impulse_at_mu_times_the_normal_one(beta, friction, e, spin):
    """With friction mu the contact sticks (beta) or slides: the rigid-body impulse for beta_eff = min(beta, -1 +
    mu (1 + e) u_n (1 + 1/kappa) / |g_t|), and the tangential impulse never exceeds mu times the normal one."""
    direction = np.array([1.0, 0.35, -0.2]) / np.linalg.norm([1.0, 0.35, -0.2])
    spins = np.reshape(spin, (2, 3))
    kappa, masses, radii = 0.4, np.array([1.0, 1.5]), np.array([0.5, 0.4])
    system, velocities = _pair(direction, 1.0, spins, masses, radii, beta, kappa, e)
    system.params[_kernels.edmd.P_FRICTION] = friction
    system.run(collisions=1)
    x = system.positions()
    n = (x[1] - x[0]) / np.linalg.norm(x[1] - x[0])
    arms = (radii[0] * n, -radii[1] * n)
    g = (velocities[1] + np.cross(spins[1], arms[1])) - (velocities[0] + np.cross(spins[0], arms[0]))
    u_n = -(g @ n)
    slip = np.linalg.norm(g - (g @ n) * n)
    effective = min(beta, -1.0 + friction * (1 + e) * u_n * (1 + 1 / kappa) / slip)
    v_after, w_after = _rigid_body_collision(n, velocities, spins, masses, radii, kappa, e, effective)
    np.testing.assert_allclose(system.velocities(), v_after, atol=1e-11)
    np.testing.assert_allclose(system.angular_velocities(), w_after, atol=1e-10)
    impulse = masses[1] * (system.velocities()[1] - velocities[1])
    tangential = np.linalg.norm(impulse - (impulse @ n) * n)
    assert tangential <= friction * abs(impulse @ n) * (1 + 1e-9) + 1e-12


def test_a_run_with_friction_keeps_it_through_a_checkpoint_and_gets_no_constant_beta_theory(tmp_path):
    from collisionkit.edmd import EdmdParameters, EdmdRun

    parameters = EdmdParameters(particles=256, packing_fraction=0.05, restitution=0.9, tangential_restitution=0.8,
                                friction=0.1, seed=4, collisions=4000, equilibration=1000, blocks=4)
    run = EdmdRun(parameters, checkpoint=tmp_path / "run.npz").run()
    summary = run.summary()
    assert summary["friction"] == 0.1 and run.system.friction == 0.1 and not parameters.elastic
    assert math.isnan(summary["cooling_rate_theory"]) and "temperature_ratio_theory" not in summary
    assert summary["energy_lost_total"] == pytest.approx(run.system.energy_lost, rel=1e-12)
    assert EdmdRun.resume(tmp_path / "run.npz").system.friction == 0.1
    with pytest.raises(ValueError, match="friction"):
        EdmdRun.resume(tmp_path / "run.npz", friction=0.2)
