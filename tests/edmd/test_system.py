"""Tests of collisionkit.edmd.system: construction, the event loop's exact dynamics, conservation laws."""

import itertools
import math

import numpy as np
import pytest
from scipy import stats

from collisionkit import edmd
from tests.edmd.systems import fcc_system, hexagonal_system, square_system


@pytest.mark.parametrize("moved", [[0.2, 0.1], [-0.3, 0.0]])
def test_overlapping_positions_are_a_value_error_naming_the_pair(moved):
    # was a RuntimeError giving only "smallest surface gap -0.776": which of 36 discs?
    positions, box = edmd.lattice("square", 6, 0.3)
    positions = positions.copy()
    positions[17] = (positions[3] + moved) % box  # the second case wraps across x = 0
    with pytest.raises(ValueError, match=r"positions overlap: particles 3 and 17, surface gap -0\.\d+"):
        edmd.HardSphereSystem(positions, np.zeros_like(positions), 0.5, box)


def test_bad_input_is_rejected_with_names():
    positions, box = edmd.lattice("sc", 4, 0.3)
    v = np.zeros_like(positions)
    with pytest.raises(edmd.OverlapError):
        edmd.HardSphereSystem(positions, v, 0.7, box)
    with pytest.raises(ValueError, match="box"):
        edmd.HardSphereSystem(positions[:8] * 0.3, v[:8], 0.5, 2.0)
    with pytest.raises(ValueError, match="radii"):
        edmd.HardSphereSystem(positions, v, -0.5, box)
    with pytest.raises(ValueError, match="masses"):
        edmd.HardSphereSystem(positions, v, 0.5, box, masses=0.0)
    with pytest.raises(ValueError, match="restitution"):
        edmd.HardSphereSystem(positions, v, 0.5, box, restitution=1.2)
    with pytest.raises(ValueError, match="velocities"):
        edmd.HardSphereSystem(positions, v[:, :2], 0.5, box)
    with pytest.raises(ValueError, match="inside the walls"):
        edmd.HardSphereSystem(positions + box[0], v, 0.5, box, periodic=False)
    with pytest.raises(ValueError, match="packing_fraction"):
        edmd.random_fluid(3, 100, 0.55)
    system = edmd.HardSphereSystem(positions, v, 0.5, box)
    with pytest.raises(ValueError, match="collisions"):
        system.run(collisions=-1)
    with pytest.raises(ValueError, match="collisions or time"):
        system.run()


@pytest.mark.parametrize(
    ("options", "error", "name"),
    [
        (dict(collisions=10, chunk=0), ValueError, "chunk"),  # used to loop forever
        (dict(collisions=10, chunk=-5), ValueError, "chunk"),
        (dict(collisions=10, chunk=True), TypeError, "chunk"),
        (dict(collisions=10, chunk=2.5), TypeError, "chunk"),
        (dict(collisions=True), TypeError, "collisions"),
        (dict(time=True), TypeError, "time"),
        (dict(time="1"), TypeError, "time"),
        (dict(time=math.nan), ValueError, "time"),
    ],
)
def test_run_rejects_bad_counts_and_times(options, error, name):
    with pytest.raises(error, match=name):
        square_system().run(**options)


def test_rescale_temperature_and_check_reject_bad_values():
    system = square_system()
    for kT in (-1.0, 0.0, math.nan):
        with pytest.raises(ValueError, match="kT"):
            system.rescale_temperature(kT)
    with pytest.raises(ValueError, match="at rest"):
        square_system(np.zeros((16, 2))).rescale_temperature(1.0)
    for tolerance in (-1.0, math.nan):
        with pytest.raises(ValueError, match="tolerance"):
            system.check(tolerance=tolerance)
    assert system.temperature() == pytest.approx(1.0, rel=1e-12)  # untouched


@pytest.mark.parametrize(
    ("options", "error", "name"),
    [
        (dict(radii="a"), TypeError, "radii"),
        (dict(masses=1 + 1j), TypeError, "masses"),
        (dict(law_speed="1"), TypeError, "law_speed"),
        (dict(law_exponent=True), TypeError, "law_exponent"),
        (dict(neighbour_shell="1"), TypeError, "neighbour_shell"),
        (dict(neighbour_shell=np.array([0.5, 0.5])), ValueError, "neighbour_shell"),
        (dict(elastic_below="1"), TypeError, "elastic_below"),
        (dict(wall_restitution="1"), TypeError, "wall_restitution"),
        (dict(wall_restitution=1.5), ValueError, "wall_restitution"),
        (dict(periodic=[True, True, False]), ValueError, "periodic"),
        (dict(periodic="no"), TypeError, "periodic"),
        (dict(periodic=[0, 2]), TypeError, "periodic"),
        (dict(box="10"), TypeError, "box"),
        (dict(species=1.7), ValueError, "species"),
        (dict(species=True), TypeError, "species"),
        (dict(restitution=np.nan), ValueError, "restitution must lie"),
        (dict(restitution_law=["constant"]), ValueError, "restitution_law"),
        (dict(gravity=[True, False]), TypeError, "gravity"),
    ],
)
def test_system_arguments_are_named_when_rejected(options, error, name):
    positions, box = edmd.lattice("square", 4, 0.3)
    arguments = dict(positions=positions, velocities=np.zeros((16, 2)), radii=0.5, box=box) | options
    with pytest.raises(error, match=name):
        edmd.HardSphereSystem(**arguments)


@pytest.mark.parametrize(
    ("options", "name"),
    [
        (dict(species=[0, 1] * 18, restitution=[[1.0, 0.5], [0.9, 1.0]]), "symmetric"),
        (dict(species=[0, -1] * 18, restitution=[[1.0, 0.5], [0.5, 1.0]]), "species"),
        (dict(gravity=[0.0, -1.0, 0.0]), "gravity"),
    ],
)
def test_inconsistent_species_restitution_and_gravity_are_refused(options, name):
    """Kills the dropped checks: an asymmetric restitution matrix (e_ij != e_ji makes the collision rule
    depend on which particle is i), a negative species (indexes the matrix from the end), a 3-vector gravity
    for discs."""
    positions, box = edmd.lattice("square", 6, 0.3)
    with pytest.raises(ValueError, match=name):
        edmd.HardSphereSystem(positions, np.zeros((36, 2)), 0.5, box, **options)


@pytest.mark.parametrize("x", [0.2, 4.8])
def test_a_particle_overlapping_a_wall_is_refused(x):
    """Centres inside [0, L] are not enough: a sphere of radius 0.5 at x = 0.2 (or L - 0.2) overlaps the wall.
    Kills: the dropped wall-overlap check of the constructor; wall_gap without the radius at the upper wall."""
    positions = np.array([[x, 2.0, 2.0], [2.5, 2.5, 2.5]])
    with pytest.raises(ValueError, match="inside the walls"):
        edmd.HardSphereSystem(positions, np.zeros((2, 3)), 0.5, 5.0, periodic=False)


def test_two_spheres_collide_when_the_quadratic_says():
    positions = np.array([[2.0, 5.0, 5.0], [6.0, 5.3, 5.0]])
    velocities = np.array([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]])
    system = edmd.HardSphereSystem(positions, velocities, 0.5, 20.0)
    system.run(collisions=1)
    expected = (4.0 - math.sqrt(1.0 - 0.3**2)) / 2.0
    assert system.elapsed == pytest.approx(expected, rel=1e-14)
    v = system.velocities()
    np.testing.assert_allclose(v.sum(axis=0), 0.0, atol=1e-15)
    assert np.sum(v**2) == pytest.approx(2.0, rel=1e-14)


def test_long_elastic_run_keeps_the_invariants():
    system = fcc_system(cells=5, eta=0.45)
    energy = system.kinetic_energy()
    for _ in range(5):
        system.run(collisions=40_000)
        assert system.check() > -1e-9  # no overlaps: no event was missed
    assert system.kinetic_energy() == pytest.approx(energy, rel=1e-12)
    np.testing.assert_allclose(system.momentum(), 0.0, atol=1e-10)
    assert system.collisions == 200_000


def test_closed_box_with_gravity_conserves_energy_and_keeps_particles_in():
    positions, box = edmd.lattice("sc", 6, 0.2)
    n = len(positions)
    velocities = edmd.maxwell_boltzmann(np.ones(n), 3, seed=4)
    system = edmd.HardSphereSystem(positions, velocities, 0.5, box, periodic=False, gravity=[0.0, 0.3, -1.0])

    def energy():
        return system.kinetic_energy() - np.sum(system.positions() @ np.array([0.0, 0.3, -1.0]))

    before = energy()
    system.run(collisions=30_000)
    assert energy() == pytest.approx(before, rel=1e-11)
    assert system.check() > -1e-9
    inside = system.positions()
    assert np.all(inside >= 0.5 - 1e-9) and np.all(inside <= box - 0.5 + 1e-9)
    assert system.wall_collisions > 0


def test_polydisperse_mixture_in_a_channel():
    rng = np.random.default_rng(6)
    positions, box = edmd.lattice("sc", 6, 0.25)
    n = len(positions)
    radii = np.where(rng.random(n) < 0.5, 0.5, 0.3)
    masses = (radii / 0.5) ** 3
    velocities = edmd.maxwell_boltzmann(masses, 3, seed=rng)
    system = edmd.HardSphereSystem(positions, velocities, radii, box, masses, periodic=[True, False, True])
    energy, momentum = system.kinetic_energy(), system.momentum()
    system.run(collisions=30_000)
    assert system.check() > -1e-9
    assert system.kinetic_energy() == pytest.approx(energy, rel=1e-11)
    # walls only on y: momentum along x and z is conserved
    np.testing.assert_allclose(system.momentum()[[0, 2]], momentum[[0, 2]], atol=1e-10)


def test_species_restitution_matrix_and_energy_bookkeeping():
    positions, box = edmd.lattice("sc", 6, 0.3)
    n = len(positions)
    species = np.arange(n) % 2
    matrix = np.array([[1.0, 0.7], [0.7, 1.0]])
    system = edmd.HardSphereSystem(
        positions, edmd.maxwell_boltzmann(np.ones(n), 3, seed=7), 0.5, box, species=species, restitution=matrix
    )
    before = system.kinetic_energy()
    system.run(collisions=5_000)
    lost = before - system.kinetic_energy()
    assert lost > 0
    assert system.energy_lost == pytest.approx(lost, rel=1e-10)
    np.testing.assert_allclose(system.momentum(), 0.0, atol=1e-10)


def test_bridges_law_and_the_elastic_floor():
    def head_on(speed, **options):
        positions = np.array([[4.0, 5.0, 5.0], [6.0, 5.0, 5.0]])
        velocities = np.array([[speed / 2, 0, 0], [-speed / 2, 0, 0]])
        system = edmd.HardSphereSystem(positions, velocities, 0.5, 20.0, **options)
        system.run(collisions=1)
        v = system.velocities()
        return (v[1, 0] - v[0, 0]) / speed  # separation / approach speed

    assert head_on(4.0, restitution_law="bridges", law_speed=1.0) == pytest.approx(4.0**-0.234, rel=1e-12)
    assert head_on(0.5, restitution_law="bridges", law_speed=1.0) == pytest.approx(1.0, rel=1e-12)
    assert head_on(2.0, restitution=0.5) == pytest.approx(0.5, rel=1e-12)
    assert head_on(2.0, restitution=0.5, elastic_below=3.0) == pytest.approx(1.0, rel=1e-12)


def test_slow_contacts_stay_inelastic_above_the_default_elastic_floor():
    """The default floor is 1e-6 of the rms speed: a head-on approach at 0.05 (rms 1.4 from two fast
    bystanders) keeps e = 0.5. Kills: elastic_below = 1e-6 rms -> 0.1 rms."""
    positions = np.array([[4.0, 5.0, 5.0], [6.0, 5.0, 5.0], [1.0, 15.0, 15.0], [9.0, 15.0, 10.0]])
    velocities = np.array([[0.025, 0, 0], [-0.025, 0, 0], [2.0, 0, 0], [-2.0, 0, 0]])
    system = edmd.HardSphereSystem(positions, velocities, 0.5, 20.0, restitution=0.5)
    assert system.run(collisions=1) == 1
    v = system.velocities()
    assert (v[1, 0] - v[0, 0]) / 0.05 == pytest.approx(0.5, rel=1e-12)


@pytest.mark.parametrize(("e", "hits", "impulse", "final"), [(1.0, 6, 20.0, (1.0, 2.0)), (0.8, 5, 12.024, (0.64, 1.024))])
def test_wall_bounces_count_impulse_and_restitution_exactly(e, hits, impulse, final):
    """Two spheres (r = 0.5, m = 1) fly along x between walls at 0 and 10 on parallel lines (no pair contact),
    from x = 5 at +1 and -2, for t = 20. Each bounce reverses v_x times e and gives the wall m (1 + e) |v|:
    elastic, A hits at 4.5, 13.5 and B at 2.25, 6.75, 11.25, 15.75 (impulse 2 + 2 + 4 x 4 = 20); e = 0.8,
    A at 4.5, 15.75 and B at 2.25, 7.875, 14.906 (1.8 (1 + 0.8) + 1.8 (2 + 1.6 + 1.28) = 12.024).
    Kills: wall impulse m |v| (no 1 + e), v -> -v (wall restitution ignored), two counts per bounce."""
    positions = np.array([[5.0, 2.0, 5.0], [5.0, 7.0, 5.0]])
    velocities = np.array([[1.0, 0.0, 0.0], [-2.0, 0.0, 0.0]])
    system = edmd.HardSphereSystem(positions, velocities, 0.5, 10.0, periodic=[False, True, True],
                                   wall_restitution=e)
    system.run(time=20.0)
    assert system.collisions == 0
    assert system.wall_collisions == hits
    assert system.wall_impulse == pytest.approx(impulse, rel=1e-12)
    np.testing.assert_allclose(np.abs(system.velocities()[:, 0]), final, rtol=1e-12)


@pytest.mark.parametrize("dim", [2, 3])
def test_speeds_follow_maxwell_boltzmann(dim):
    system = fcc_system(cells=8, eta=0.3) if dim == 3 else hexagonal_system(cells=32, eta=0.3)
    system.run(collisions=30 * system.count)
    speeds = np.linalg.norm(system.velocities(), axis=1)
    scale = math.sqrt(system.temperature())
    law = stats.maxwell(scale=scale) if dim == 3 else stats.rayleigh(scale=scale)
    assert stats.kstest(speeds, law.cdf).pvalue > 1e-3
    # a lattice start is not Maxwellian in position, but the run has had time to relax the speeds
    assert abs(np.mean(speeds) - law.mean()) < 4 * law.std() / math.sqrt(len(speeds))


@pytest.mark.slow
def test_homogeneous_cooling_follows_haff_law():
    """T = T0 exp(-2 (1 - e^2) C / (d N)) while the gas stays homogeneous (e = 0.9, small N)."""
    e = 0.9
    means = []
    for seed in (11, 12, 13, 14):
        equilibrium = fcc_system(cells=4, eta=0.1, seed=seed)  # N = 256
        equilibrium.run(collisions=20 * equilibrium.count)
        system = edmd.HardSphereSystem(
            equilibrium.positions(), equilibrium.velocities(), 0.5, equilibrium.box[:3], restitution=e
        )
        t0 = system.temperature()
        ratios = []
        for _ in range(5):
            system.run(collisions=system.count)  # two collisions per particle
            expected = t0 * math.exp(-2 * (1 - e * e) * system.collisions / (3 * system.count))
            ratios.append(system.temperature() / expected)
        system.check()
        # the Sonine correction is under 0.4 %; T of a 256-particle gas fluctuates by ~2 %
        assert np.all(np.abs(np.array(ratios) - 1) < 0.06)
        means.append(np.mean(ratios))
    # one run's mean scatters by ~1.2 % (8 seeds); the mean of four by ~0.6 %: 4 sigma
    assert abs(np.mean(means) - 1) < 0.025


def _first_time_at_zero(a, b, c):
    """Smallest t > 0 where a t^2 + b t + c rises through 0 (inf if never), elementwise: a particle reaching a
    wall it moves towards (one just bounced off it sits at c ~ 0 moving away)."""
    a, b, c = np.broadcast_arrays(*(np.asarray(value, dtype=float) for value in (a, b, c)))
    linear = np.where(b > 0, -c / np.where(b > 0, b, 1.0), np.inf)
    discriminant = b * b - 4 * a * c
    root = np.sqrt(np.maximum(discriminant, 0.0))
    safe_a = np.where(a != 0, a, 1.0)
    roots = np.stack([(-b - root) / (2 * safe_a), (-b + root) / (2 * safe_a)])
    rising = 2 * a * roots + b > 0
    roots = np.where((roots > 0) & rising & (discriminant >= 0), roots, np.inf).min(axis=0)
    return np.where(a == 0, linear, roots)


def brute_force_collisions(x, v, radii, masses, box, count, walls=False, gravity=None, restitution=1.0):
    """Event-driven hard spheres the slow, obvious way: the earliest event over every pair and every
    neighbouring periodic image (root of |r + u t| = r_i + r_j: both fall alike, so the relative flight is
    straight) or, in a closed box, every particle and wall (x +- r = 0 or L on the parabola x + v t + g t^2 / 2);
    all particles moved to it; the rule along the line of centres with restitution e, or the normal velocity
    reversed at a wall. Returns [(time, velocities)] after each of the first ``count`` pair collisions."""
    x, v = x.astype(float).copy(), v.astype(float).copy()
    dim = x.shape[1]
    g = np.zeros(dim) if gravity is None else np.asarray(gravity, dtype=float)
    offsets = [(0.0,) * dim] if walls else list(itertools.product((-1.0, 0.0, 1.0), repeat=dim))
    shifts = np.array(offsets) * box
    first, second = np.triu_indices(len(x), 1)
    contact = radii[first] + radii[second]
    t, after = 0.0, []
    while len(after) < count:
        r = x[second][:, None, :] + shifts[None, :, :] - x[first][:, None, :]
        u = (v[second] - v[first])[:, None, :]
        b = np.sum(r * u, axis=-1)
        c = np.sum(r * r, axis=-1) - contact[:, None] ** 2
        discriminant = b * b - np.sum(u * u, axis=-1) * c
        hits = (b < 0) & (discriminant >= 0)
        tau = np.full(b.shape, np.inf)
        tau[hits] = c[hits] / (-b[hits] + np.sqrt(discriminant[hits]))
        pair = np.argmin(tau.min(axis=1))
        step = tau[pair].min()
        wall_step = np.full(x.shape, np.inf)
        if walls:
            upper = _first_time_at_zero(0.5 * g, v, x + radii[:, None] - box)
            lower = _first_time_at_zero(-0.5 * g, -v, radii[:, None] - x)
            wall_step = np.minimum(upper, lower)
        wall = wall_step.min() < step
        step = min(step, wall_step.min())
        x = x + v * step + 0.5 * g * step**2
        v = v + g * step
        t += step
        if wall:
            particle, axis = np.unravel_index(np.argmin(wall_step), wall_step.shape)
            v[particle, axis] = -v[particle, axis]
            continue
        if not walls:
            x %= box
        i, j = first[pair], second[pair]
        normal = x[j] - x[i]
        if not walls:
            normal -= box * np.round(normal / box)  # the nearest image at contact (a flight may cross an edge)
        normal /= np.linalg.norm(normal)
        reduced = masses[i] * masses[j] / (masses[i] + masses[j])
        impulse = (1 + restitution) * reduced * np.dot(v[i] - v[j], normal)
        v[i] -= impulse / masses[i] * normal
        v[j] += impulse / masses[j] * normal
        after.append((t, v.copy()))
    return after


BRUTE_FORCE_CASES = [  # dim, mixture, walls, falling, e
    (3, False, False, False, 1.0), (3, True, False, False, 1.0), (2, False, False, False, 1.0),
    (2, True, False, False, 1.0), (3, True, True, False, 1.0), (2, True, True, False, 1.0),
    (3, True, True, True, 0.9), (2, False, True, True, 0.8)]


@pytest.mark.parametrize("dim, mixture, walls, falling, e, engine", [
    *((*case, "lists") for case in BRUTE_FORCE_CASES),
    *((*case, "cells") for case in BRUTE_FORCE_CASES if not case[3])])  # the cells: straight flights only
def test_the_engine_finds_the_same_collisions_as_brute_force(dim, mixture, walls, falling, e, engine):
    """No event missed, none invented, in the right order: the first 100 pair collisions of a dense system
    (neighbour lists, rebuilds, stale events, periodic images or walls; and the cell engine's crossings where
    flights are straight) against an all-pairs search; after each
    pair collision the time and every velocity agree; also under gravity (parabolic flights to the walls)
    with inelastic collisions. Round-off grows by the Lyapunov instability: the largest
    velocity difference goes from 1e-14 to 2e-10 over these 100 collisions (walled 3D mixture; 4e-7 at 150,
    0.1 at 300), while a missed or wrong event changes velocities by order 1.

    Each engine named: "auto" takes the cells for every straight-flight system here but the 3D one of equal
    spheres (below CELLS_BELOW_PACKING: the discs, and the mixtures with their smaller spheres), which would leave
    the lists untested there."""
    rng = np.random.default_rng(dim + 10 * mixture + 100 * walls)
    positions, box = edmd.lattice("fcc" if dim == 3 else "hexagonal", 2 if dim == 3 else 6, 0.35)
    n = len(positions)
    radii = np.where(rng.random(n) < 0.5, 0.5, 0.35) if mixture else np.full(n, 0.5)
    masses = (radii / 0.5) ** dim
    velocities = edmd.maxwell_boltzmann(masses, dim, seed=rng)
    side = np.asarray(box, dtype=float)[:dim]
    if walls:  # the lattice's sites, shrunk into a box one diameter larger, stay clear of each other and the walls
        side = side + 1.0
        positions = positions + 0.5
    gravity = np.eye(dim)[-1] * -2.0 + np.eye(dim)[0] * 0.5 if falling else None
    system = edmd.HardSphereSystem(positions, velocities, radii, side, masses, periodic=not walls, gravity=gravity,
                                   restitution=e, engine=engine)
    expected = brute_force_collisions(positions, velocities, radii, masses, side, 100, walls=walls, gravity=gravity,
                                      restitution=e)
    for time_expected, velocities_expected in expected:
        assert system.run(collisions=1) == 1
        assert system.elapsed == pytest.approx(time_expected, rel=1e-8)
        np.testing.assert_allclose(system.velocities(), velocities_expected, rtol=0, atol=1e-7)


def test_run_reports_the_fraction_of_the_requested_collisions_done():
    system = fcc_system(cells=3, eta=0.3)
    seen = []
    assert system.run(collisions=2500, chunk=1000, progress=lambda f: seen.append((f, system.collisions))) == 2500
    assert len(seen) >= 3 and [f for f, _ in seen] == [done / 2500 for _, done in seen]
    assert seen[-1][0] == 1.0


def test_run_reports_the_fraction_of_the_requested_time_done():
    system = square_system()
    seen = []
    system.run(time=2.0, chunk=20, progress=lambda f: seen.append((f, system.elapsed + system.time)))
    assert len(seen) > 1 and all(0.0 < f <= 1.0 for f, _ in seen)
    for fraction, clock in seen:
        assert fraction == pytest.approx(clock / 2.0, rel=1e-12)
    assert seen[-1][0] == pytest.approx(1.0, rel=1e-12)
    # given both, the run stops at whichever comes first: its fraction is the larger share
    fractions = []
    system.run(collisions=10**9, time=0.5, progress=fractions.append)
    assert fractions[-1] == pytest.approx(1.0, rel=1e-12)


def test_the_totals_of_a_run_are_named_properties():
    system = fcc_system(cells=3, eta=0.3)
    assert (system.collisions, system.wall_collisions, system.wall_impulse, system.energy_lost, system.virial) == (
        0, 0, 0.0, 0.0, 0.0)
    system.run(collisions=1000)
    assert system.collisions == 1000 and system.virial > 0
    assert system.packing_fraction == pytest.approx(0.3, rel=1e-12)
    assert "eta=0.3000" in repr(system) and "<caption" in system._repr_html_()


@pytest.mark.parametrize("dim", [2, 3])
def test_the_box_has_one_length_per_axis_and_is_a_copy(dim):
    # box gave the engine's own array (3 entries in 2-D): halving box[0] in place squeezed the system into overlaps
    system = edmd.random_fluid(dim, 64, 0.3, seed=1)
    box = system.box
    assert box.shape == (dim,) and system.positions().shape == (64, dim)
    eta = system.packing_fraction
    box[0] *= 0.5
    assert system.packing_fraction == eta and system.box[0] == 2 * box[0]
    system.run(collisions=200)  # no overlap: the system kept its box


def test_counts_may_be_whole_floats_as_users_write_them():
    # run(collisions=1e4) was a TypeError, while EdmdParameters(particles=500.0) was accepted
    system = square_system()
    system.run(collisions=2e2)
    assert system.collisions == 200
    with pytest.raises(TypeError, match="collisions must be an integer"):
        system.run(collisions=2.5)
