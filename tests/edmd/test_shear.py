"""Lees-Edwards shear of the EDMD engine: exact balances event by event, images, lists, checkpoints, thermostat."""

from __future__ import annotations

import math

import numpy as np
import pytest

from collisionkit import edmd
from collisionkit._kernels import edmd as _k


def _sheared(dim, rate, restitution=1.0, thermostat=None, seed=1, cells=None, eta=0.4):
    if dim == 2:
        positions, box = edmd.lattice("square", cells or 12, eta)
    else:
        positions, box = edmd.lattice("fcc", cells or 4, eta)
    velocities = edmd.maxwell_boltzmann(np.ones(len(positions)), dim, seed=seed)
    return edmd.HardSphereSystem(positions, velocities, 0.5, box, restitution=restitution, shear_rate=rate,
                                 thermostat=thermostat)


def _peculiar(system):
    system.synchronise()
    return system._peculiar(), system._mass


@pytest.mark.parametrize(("dim", "restitution"), [(2, 1.0), (2, 0.8), (3, 0.7)])
def test_peculiar_energy_and_momentum_balance_at_every_collision(dim, restitution):
    """dE = flight work + collision work - loss at each collision, to round-off; the peculiar momentum is kept.

    Independent of the engine's bookkeeping: E = sum m c^2 / 2 from the
    velocities relative to the flow; in flight c_x = c_x0 - G v_y t, so
    the flight's work is -G sum m v_y (c_x0 t - G v_y t^2 / 2); the
    collision's is -G dp_jx r_y (the change of the collisional stress sum)
    minus the energy lost. Wraps through the y faces (list events) change
    neither E nor the momentum sum m c.
    """
    rate = 0.7
    system = _sheared(dim, rate, restitution)
    system.run(collisions=2000)
    worst_energy = worst_momentum = 0.0
    crossings = 0
    for _ in range(1500):
        c0, m = _peculiar(system)
        energy0 = 0.5 * np.sum(m[:, None] * c0**2)
        t0, lost0, stress0 = system.elapsed, system.energy_lost, system.collisional_stress[0, 1]
        images0 = system._image[:, 1].copy()
        assert system.run(collisions=1) == 1
        c1, m = _peculiar(system)
        crossings += int(np.sum(system._image[:, 1] != images0))
        tau = system.elapsed - t0
        flight = -rate * np.sum(m * c0[:, 1] * (c0[:, 0] * tau - 0.5 * rate * c0[:, 1] * tau**2))
        collision = -(system.energy_lost - lost0) - rate * (system.collisional_stress[0, 1] - stress0)
        energy1 = 0.5 * np.sum(m[:, None] * c1**2)
        worst_energy = max(worst_energy, abs(energy1 - energy0 - flight - collision) / energy0)
        change = np.abs((m[:, None] * c1).sum(axis=0) - (m[:, None] * c0).sum(axis=0))
        worst_momentum = max(worst_momentum, float(change.max()) / math.sqrt(energy0))
    assert crossings > 10  # wraps through the y faces happened
    assert worst_energy < 1e-13
    assert worst_momentum < 1e-13


def _brute_force_next(x, v, box, offset, rate, diameter):
    """Earliest contact over all pairs and their sliding images: (time, i, j, image shift, velocity shift).

    The images: x shifts of k L_x and the offset n o, y shifts of n L_y
    (positions unwrapped: their separations stay within a box or so).
    """
    lx, ly = box
    best = (math.inf, -1, -1, None, None)
    for i in range(len(x)):
        for j in range(i + 1, len(x)):
            for n in (-1, 0, 1):
                for k in (-2, -1, 0, 1, 2):
                    shift = np.array([n * offset + k * lx, n * ly])
                    slide = np.array([n * rate * ly, 0.0])
                    r = x[j] + shift - x[i]
                    u = v[j] + slide - v[i]
                    b = r @ u
                    if b >= 0:
                        continue
                    disc = b * b - (u @ u) * (r @ r - diameter**2)
                    if disc < 0:
                        continue
                    tau = (-b - math.sqrt(disc)) / (u @ u)
                    if -1e-9 < tau < best[0]:
                        best = (max(tau, 0.0), i, j, shift, slide)
    return best


def test_trajectory_matches_a_brute_force_lees_edwards_simulation():
    """25 discs, 40 collisions: the engine and an all-pairs, all-images simulation written here agree to 1e-9.

    The brute force keeps lab velocities and positions without wrapping;
    the offset of the image above is G L_y t. Compared: the collision times
    and the peculiar velocities after each collision.
    """
    rate = 1.3
    positions, box = edmd.lattice("square", 5, 0.15)
    velocities = edmd.maxwell_boltzmann(np.ones(25), 2, seed=4)
    system = edmd.HardSphereSystem(positions, velocities, 0.5, box, shear_rate=rate)
    x = np.array(positions, dtype=float)
    v = velocities.copy()
    v[:, 0] += rate * (x[:, 1] - 0.5 * box[1])
    t = 0.0
    for _ in range(40):
        tau, i, j, shift, slide = _brute_force_next(x, v, box, rate * box[1] * t % box[0], rate, 1.0)
        x += v * tau
        t += tau
        r = x[j] + shift + slide * tau - x[i]  # the image slid on during the flight
        u = v[j] + slide - v[i]
        impulse = (r @ u) / (r @ r) * r  # equal masses, elastic: v_i += (r.u / r^2) r
        v[i] += impulse
        v[j] -= impulse
        system.run(collisions=1)
        assert system.elapsed + system.time == pytest.approx(t, rel=1e-9, abs=1e-12)
        expected = v.copy()
        expected[:, 0] -= rate * (x[:, 1] - 0.5 * box[1])  # peculiar: the same for every image
        assert np.allclose(system.peculiar_velocities(), expected, rtol=0, atol=1e-9)


@pytest.mark.parametrize(("dim", "rate", "eta"), [(2, 3.0, 0.45), (3, 2.0, 0.4), (3, 6.0, 0.1)])
def test_no_overlap_at_high_shear(dim, rate, eta):
    """Images sliding past much faster than the particles move (G L_y >> v): no collision is missed."""
    system = _sheared(dim, rate, thermostat=1.0, cells=14 if dim == 2 else 5, eta=eta)
    for _ in range(8):
        system.run(collisions=4000)
        assert system.check() > -1e-9
    assert system.acc[_k.ACC_LIST_REBUILDS] > 0


def test_offset_follows_the_clock_and_peculiar_velocities_start_as_given():
    system = _sheared(2, 0.25)
    thermal = edmd.maxwell_boltzmann(np.ones(system.count), 2, seed=1)
    assert np.allclose(system.peculiar_velocities(), thermal, rtol=0, atol=1e-14)
    lab = system.velocities()
    y = system.positions()[:, 1]
    assert np.allclose(lab[:, 0] - 0.25 * (y - 0.5 * system.box[1]), thermal[:, 0], atol=1e-14)
    system.run(time=3.0)
    assert system.shear_offset == pytest.approx(0.25 * system.box[1] * 3.0 % system.box[0], abs=1e-12)
    inside = system.positions()
    assert np.all((inside >= 0) & (inside < system.box[:2]))
    # the lab velocities of the particles in the box are the flow there plus the peculiar velocities
    flow = 0.25 * (inside[:, 1] - 0.5 * system.box[1])
    assert np.allclose(system.velocities()[:, 0] - flow, system.peculiar_velocities()[:, 0], atol=1e-12)


def test_thermostat_rescales_to_kT_on_its_grid_of_collisions():
    system = _sheared(2, 1.0, thermostat=1.5)
    system.run(collisions=2 * edmd.THERMOSTAT_INTERVAL * system.count)
    assert system.temperature() == pytest.approx(1.5, rel=1e-12)
    assert system.thermostat_energy > 0  # viscous heating removed
    free = _sheared(2, 1.0)
    free.run(collisions=2 * edmd.THERMOSTAT_INTERVAL * free.count)
    assert free.temperature() > 1.1  # without it the elastic fluid heats up


def test_checkpoint_resumes_bit_for_bit():
    system = _sheared(3, 0.8, restitution=0.9, thermostat=1.0, cells=3)
    system.run(collisions=1500)
    copy = edmd.HardSphereSystem.from_state_dict(system.state_dict())
    assert copy.shear_rate == 0.8 and copy.thermostat == 1.0
    for one in (system, copy):
        one.run(collisions=700)
    assert np.array_equal(system.positions(), copy.positions())
    assert np.array_equal(system.velocities(), copy.velocities())
    assert system.shear_offset == copy.shear_offset


def test_older_checkpoint_formats_read_as_unsheared():
    positions, box = edmd.lattice("square", 8, 0.3)  # formats before 7 ran the list engine
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(64), 2, seed=1), 0.5, box, engine="lists")
    state = system.state_dict()
    state["format"] = np.asarray(3)
    state["params"] = state["params"][: _k.P_SIZE_WITHOUT_SHEAR]
    state["acc"] = state["acc"][: _k.ACC_SIZE_WITHOUT_THERMOSTAT]
    restored = edmd.HardSphereSystem.from_state_dict(state)
    assert restored.shear_rate == 0.0 and restored.thermostat is None
    assert restored.run(collisions=100) == 100


def test_format_4_checkpoints_load_only_unsheared():
    """Format 4 kept the sheared lists and cells otherwise: a sheared state of it is refused, an unsheared one runs."""
    sheared = _sheared(2, 0.5).state_dict()
    sheared["format"] = np.asarray(4)
    with pytest.raises(ValueError, match="engine format 4 with Lees-Edwards shear"):
        edmd.HardSphereSystem.from_state_dict(sheared)
    positions, box = edmd.lattice("square", 8, 0.3)
    plain = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(64), 2, seed=1), 0.5, box,
                                  engine="lists").state_dict()
    plain["format"] = np.asarray(4)
    assert edmd.HardSphereSystem.from_state_dict(plain).run(collisions=100) == 100


def test_pair_histogram_counts_pairs_across_the_sliding_faces():
    """g(r) under shear: the same ordered pairs as a brute-force count over the nearest sliding images."""
    from collisionkit.edmd import _pair_distribution

    system = _sheared(2, 0.9, cells=10, eta=0.35)
    system.run(time=1.7)
    r_max, bins = 3.0, 30
    counts = _pair_distribution.pair_histogram(system, r_max, bins)
    points = system._folded(ahead=0.5 * system._time_to_next_event())[0][:, :2]
    offset = system._offset_at(system.time + 0.5 * system._time_to_next_event())
    lx, ly = system.box[:2]
    expected = np.zeros(bins)
    for a in range(len(points)):
        d = points - points[a]
        n = np.round(d[:, 1] / ly)
        d[:, 1] -= n * ly
        d[:, 0] -= n * offset
        d[:, 0] -= lx * np.round(d[:, 0] / lx)
        r = np.hypot(d[:, 0], d[:, 1])
        r = r[(np.arange(len(points)) != a) & (r < r_max)]
        expected += np.bincount((r / r_max * bins).astype(int), minlength=bins)[:bins]
    assert np.array_equal(counts, expected)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"shear_rate": -1.0}, "shear_rate must be a finite number >= 0"),
        ({"shear_rate": math.nan}, "shear_rate must be a finite number >= 0"),
        ({"thermostat": 1.0}, "thermostat needs a shear_rate"),
        ({"shear_rate": 1.0, "thermostat": 0.0}, "thermostat must be"),
        ({"shear_rate": 1.0, "periodic": [True, False]}, "shear_rate needs every axis periodic"),
        ({"shear_rate": 1.0, "gravity": [0.0, -1.0]}, "shear_rate cannot be combined with gravity"),
    ],
)
def test_refusals(kwargs, message):
    positions, box = edmd.lattice("square", 8, 0.3)
    with pytest.raises(ValueError, match=message):
        edmd.HardSphereSystem(positions, np.zeros((64, 2)), 0.5, box, **kwargs)


def test_too_small_box_is_refused():
    with pytest.raises(ValueError, match="too small to shear"):
        edmd.HardSphereSystem([[0.5, 0.5], [2.0, 2.0]], np.zeros((2, 2)), 0.5, 3.02, shear_rate=1.0)


@pytest.mark.parametrize(("dim", "rate", "cells"), [(2, 0.9, 14), (3, 0.6, 5)])
def test_lists_hold_every_pair_whose_anchors_carried_by_the_flow_were_within_the_list_radius(dim, rate, cells):
    """After a run of list events and sweeps: every pair whose anchors, carried by the flow to the later of the two
    lists' times and seen as the nearest sliding images at the offset of then, lay within the list radius is listed,
    both ways; none beyond it (but for the anchors' float32 round-off).

    A brute force over all pairs and their images written here (an anchor at frame x xi and height y is at
    xi + G (y - L_y / 2) (t - t_f) at time t; y shifts of n L_y with x shifts of n offsets).
    Kills: a sweep that moves anchors or cells wrongly, a wrong frame shift or offset sign, lists not symmetric.
    """
    system = _sheared(dim, rate, thermostat=1.0, cells=cells, eta=0.35)
    sweeps = 0
    for _ in range(6):
        sweep = system.params[_k.P_SHEAR_SWEEP]
        system.run(collisions=3 * system.count)
        sweeps += system.params[_k.P_SHEAR_SWEEP] != sweep
        anchors = system.anchor[:, :dim]
        box = system.box[:dim]
        frame = system.params[_k.P_SHEAR_FRAME]
        flow = rate * (anchors[:, 1] - 0.5 * box[1])
        reach = 2 * 0.5 * system.neighbour_list_scale + system.neighbour_shell_width
        slack = system.neighbour_list_slack
        listed = {(i, int(j)) for i in range(system.count) for j in system.neighbours[i, : system.neighbour_count[i]]}
        within, allowed = set(), set()
        for i in range(system.count):
            built = np.maximum(system.anchor_time, system.anchor_time[i])
            d = anchors - anchors[i]
            d[:, 0] += (flow - flow[i]) * (built - frame)
            n = np.round(d[:, 1] / box[1])
            d[:, 1] -= n * box[1]
            d[:, 0] -= n * (system._offset_at(built) % box[0])
            d -= box * np.round(d / box)
            distance = np.sqrt(np.sum(d**2, axis=1))
            within |= {(i, int(j)) for j in np.flatnonzero(distance <= reach - 2 * slack) if j != i}
            allowed |= {(i, int(j)) for j in np.flatnonzero(distance <= reach + 2 * slack) if j != i}
        assert within <= listed <= allowed
        assert all((j, i) in listed for i, j in listed)
        assert any(abs(anchors[i, 1] - anchors[j, 1]) > 0.5 * box[1] for i, j in within)  # pairs across the faces
        system.check()  # every particle within its list's budget: shell / 2 - |G| R / 4 x age from its moving anchor
    assert sweeps >= 3


@pytest.mark.parametrize("dim", [2, 3])
def test_sampled_speeds_and_mean_free_path_are_relative_to_the_flow(dim):
    # speeds are sampled at the block ends, where kT (peculiar) is recorded: sum c^2 / N = d kT exactly,
    # whereas lab-frame speeds add G^2 <(y - L/2)^2> (about G^2 L^2 / 12: 0.5 here)
    system = _sheared(dim, 0.5, thermostat=1.0, cells=10 if dim == 2 else 3)
    m = edmd.measure(system, collisions=4000, blocks=4)
    per_block = m.speeds.reshape(4, -1)
    assert np.allclose(np.mean(per_block**2, axis=1), dim * m.block_temperature, rtol=1e-12)
    assert m.mean_free_path == pytest.approx(np.mean(m.speeds) / m.collision_frequency, rel=1e-12)


@pytest.mark.parametrize(("dim", "lattice", "cells", "rate"), [(2, "hexagonal", 16, 0.5), (3, "fcc", 6, 2.0)])
def test_list_events_do_not_follow_the_streaming_motion(dim, lattice, cells, rate):
    """Anchors carried by the flow: a strong shear (G L_y = 22 thermal speeds) leaves the list events per collision
    within 2x a periodic run's (0.82 against 0.51 for discs, 0.71 against 0.48 for spheres at G = 2); anchors fixed
    in the lab made them 7.2x and 3.6x (3.64 and 1.72), the particles leaving them at the streaming speed.

    Counts of a fixed seed, not timings (the periodic run on the lists too: "auto" would take the cells for the
    discs, whose crossings count in the same slot). Kills: anchors that do not move with the flow.
    """
    positions, box = edmd.lattice(lattice, cells, 0.35)
    velocities = edmd.maxwell_boltzmann(np.ones(len(positions)), dim, seed=1)
    per_collision = []
    for shear in ({}, {"shear_rate": rate, "thermostat": 1.0}):
        system = edmd.HardSphereSystem(positions, velocities, 0.5, box, engine="lists", **shear)
        system.run(collisions=5 * system.count)
        before = system.acc[_k.ACC_LIST_REBUILDS]
        system.run(collisions=10 * system.count)
        per_collision.append((system.acc[_k.ACC_LIST_REBUILDS] - before) / (10 * system.count))
        system.check()
    assert rate * box[1] > 20.0
    assert per_collision[1] < 2.0 * per_collision[0]


@pytest.mark.parametrize("slots_short", [False, True])
def test_a_sweep_moves_every_anchor_with_the_flow_and_refills_the_cells(slots_short):
    """sweep_frame against numpy: each anchor's frame x advanced by G (y - L_y / 2) (t - t_f) and wrapped, each
    particle in the cell of its new anchor, the frame time moved on; the lists untouched. With cells one slot short
    it returns the fullest cell's true count (more than the slots: the caller grows them and rebuilds).
    """
    from collisionkit._kernels.edmd.neighbour_lists import sweep_frame

    system = _sheared(2, 0.7, thermostat=1.0, cells=14, eta=0.35)
    system.run(collisions=2 * system.count)
    rate, box, widths = 0.7, system.box, system.geom[_k.G_CELL]
    later = system.params[_k.P_SHEAR_FRAME] + 0.3 / rate
    carried = rate * (system.anchor[:, 1] - 0.5 * box[1]) * (later - system.params[_k.P_SHEAR_FRAME])
    expected_x = (system.anchor[:, 0] + carried) % box[0]
    columns = np.minimum(np.floor(expected_x / widths[0]).astype(int), system.ncell[0] - 1)
    rows = np.minimum(np.floor(system.anchor[:, 1] / widths[1]).astype(int), system.ncell[1] - 1)
    home = columns + system.ncell[0] * rows
    fullest = int(np.bincount(home).max())
    slots = fullest - 1 if slots_short else fullest
    members = np.zeros((system.cell_members.shape[0], slots), dtype=np.int32)
    points = np.zeros((system.cell_points.shape[0], slots, 4), dtype=np.float32)
    lists = system.neighbours.copy(), system.neighbour_count.copy()
    most = sweep_frame(system.p, system.book, system.cell_of, members, system.cell_count, points, system.ncell,
                       system.geom, system.dim, system.params, later)
    assert most == fullest
    assert system.params[_k.P_SHEAR_FRAME] == later
    assert np.allclose(system.anchor[:, 0], expected_x, rtol=0, atol=1e-12 * box[0])
    assert np.array_equal(lists[0], system.neighbours) and np.array_equal(lists[1], system.neighbour_count)
    if not slots_short:
        assert np.array_equal(system.cell_of, home)
        for cell in range(members.shape[0]):
            held = np.sort(members[cell, : system.cell_count[cell]])
            assert np.array_equal(held, np.flatnonzero(home == cell))
            held_x = system.anchor[members[cell, : system.cell_count[cell]], 0].astype(np.float32)
            assert np.array_equal(points[cell, : system.cell_count[cell], 0], held_x)
