"""Transport kernels: random streams, exact free flight, window and rate bounds, angular sampling, collision
kinematics, the exactness of the null-collision method, and the slab's lab-frame scattering."""

import math

import numpy as np
import pytest
from scipy import constants, stats
from scipy.integrate import solve_ivp

from collisionkit._kernels.transport import (
    BOUND_COLUMN_OFFSET, DISPLACEMENT_COLUMN_OFFSET, EXTRA_COLUMNS, ISOTROPIC, NULL_COLUMN_OFFSET, SCREENED_COULOMB, SHARE_EQUAL, SHARE_UNIFORM,
    TIME_COLUMN_OFFSET, TRIAL_BUDGET, WINDOW_COLLISIONS, WINDOW_GROWTH, advance_swarm, derived_field,
)
from collisionkit._kernels.transport.collisions import ionized, two_body
from collisionkit._kernels.transport.cross_sections import node_index, rate_bound
from collisionkit._kernels.transport.flight import (
    flight_envelope, flown_position, flown_velocity, window_growth_speed, window_top_speed,
)
from collisionkit._kernels.transport.rng import normal_pair, seed_state, uniform
from collisionkit._kernels.transport.scattering import isotropic_direction, scattering_cosine
from collisionkit._kernels.transport.slab import elastic_lab
from collisionkit.transport import Gas, Process, Species, reid_ramp, screened_coulomb_momentum_ratio
from collisionkit.transport._tables import build_tables
from tests.sweep.helpers import deadline

E_CHARGE, ME = constants.e, constants.m_e


def _state(seed=1):
    state = np.zeros(4, np.uint64)
    seed_state(np.uint64(seed), state)
    return state


def _fly(pos, vel, dt, field):
    """Exact free flight for a time ``dt``, in place: the kernels advance_swarm moves a particle with."""
    position = flown_position(*pos, *vel, dt, field)
    velocity = flown_velocity(*vel, dt, field)
    pos[:], vel[:] = position, velocity


def _window_bound_speed(vel, field, t1, t2):
    """The speed bound advance_swarm puts on the window [t1, t2] of a flight that starts with ``vel``.

    The larger of the convex bound at the window's ends, capped by |v| + |a| t2 in a magnetic field.
    """
    exact = field[12] == 0.0
    acceleration = field[0:3]
    envelope = (0.0, 0.0, 0.0)
    if not exact:
        envelope = flight_envelope(*vel, *field[3:6], *field[9:12], float(field[6:9] @ field[3:6]))
    top = max(window_top_speed(*vel, *acceleration, t, exact, *envelope) for t in (t1, t2))
    growth = window_growth_speed(math.sqrt(vel @ vel), math.sqrt(acceleration @ acceleration), t2, exact,
                                 envelope[1])
    return min(top, growth)


def _mixture():
    return Gas.mixture({reid_ramp(): 0.6, Gas((Species("x", 1e-26, (
        Process("elastic", [0, 1, 3, 50], [1e-19, 3e-19, 5e-20, 2e-20]),
        Process("excitation", [1.5, 4, 50], [2e-20, 1e-19, 0.0], threshold=1.5))),)): 0.4})


def test_uniform_stream_has_the_right_moments_and_never_returns_zero():
    state = _state()
    values = np.array([uniform(state) for _ in range(200_000)])
    assert values.min() > 0.0 and values.max() < 1.0
    assert abs(values.mean() - 0.5) < 5 * math.sqrt(1 / 12 / values.size)
    assert abs(values.var() - 1 / 12) < 0.002


def test_exact_gyration_matches_numerical_integration():
    acceleration = np.array([1.0, -2.0, 3.0])
    omega = np.array([0.3, 1.1, -0.7])
    field = derived_field(acceleration, omega)
    pos, vel = np.array([0.1, 0.2, 0.3]), np.array([1.0, 0.5, -0.2])

    def rhs(_, y):
        return np.concatenate([y[3:], acceleration + np.cross(y[3:], omega)])

    solution = solve_ivp(rhs, (0, 7.3), np.concatenate([pos, vel]), rtol=1e-11, atol=1e-12)
    _fly(pos, vel, 7.3, field)
    np.testing.assert_allclose(np.concatenate([pos, vel]), solution.y[:, -1], rtol=1e-8, atol=1e-8)


# (2, 1) in any unit; and 1, 10, 100 eV with a screening energy of 0.5 eV, where read_lxcat converts
# momentum-transfer cross sections with screened_coulomb_momentum_ratio (tests/transport/test_lxcat.py)
@pytest.mark.parametrize("energy, screening", [(2.0, 1.0), (1.0, 0.5), (10.0, 0.5), (100.0, 0.5)])
def test_screened_coulomb_sampling_has_the_analytic_mean_cosine(energy, screening):
    state = _state(3)
    samples = np.array([scattering_cosine(SCREENED_COULOMB, energy, screening, state) for _ in range(200_000)])
    expected = screened_coulomb_momentum_ratio(energy, screening)
    error = samples.std() / math.sqrt(samples.size)
    assert abs(np.mean(1 - samples) - expected) < 5 * error


def test_rate_bound_is_never_below_the_true_rate():
    tables = build_tables(_mixture(), ME, 0.0)
    energies = np.concatenate([np.linspace(0, 120, 20001), [0.2, 1.5, 3.0]]) * E_CHARGE
    edges = np.arange(tables.bound.shape[1] + 1) * tables.bound_step  # speeds exactly on the bin edges too
    energies = np.concatenate([energies, 0.5 * ME * edges**2])
    inverse_step = (1.0 / tables.bound_step) * (1.0 + 1e-12)  # as advance_swarm
    for s in range(2):
        mine = [j for j in range(tables.kind.size) if tables.species_of[j] == s]
        for energy in energies:
            speed = math.sqrt(2 * energy / ME)
            # the rate advance_swarm evaluates at a trial: linear in the table, nothing below a threshold
            rate = sum(tables.const_rate[j] + (np.interp(energy, tables.nodes, tables.sigma[:, j]) * speed
                                               if energy >= tables.threshold[j] else 0.0) for j in mine)
            bound = rate_bound(s, speed, tables.bound, inverse_step, tables.sigma_max, tables.const_max)
            assert bound >= rate * (1 - 1e-12)


def test_the_node_lookup_finds_the_interval_of_every_energy():
    tables = build_tables(_mixture(), ME, 0.0)
    nodes = tables.nodes
    inverse_cell = (1.0 / tables.accelerator_step) * (1.0 - 1e-12)  # as advance_swarm
    rng = np.random.default_rng(2)
    energies = np.concatenate([nodes, np.nextafter(nodes, -np.inf), np.nextafter(nodes, np.inf),
                               rng.uniform(0.0, 1.2 * nodes[-1], 20_000)])
    for energy in energies:
        expected = np.searchsorted(nodes, energy, side="right") - 1  # -1 below the first node, last at the end
        assert node_index(energy, nodes, tables.accelerator, inverse_cell) == expected, energy


def test_rate_bound_is_a_running_maximum():
    tables = build_tables(_ATTACHING, ME, 0.0)
    assert np.all(np.diff(tables.bound, axis=1) >= 0)


def test_slab_elastic_energy_loss_matches_the_mass_ratio_law():
    state = _state(5)
    a = 12.0
    energies = np.array([elastic_lab(1.0, 1.0, a, state)[1] for _ in range(100_000)])
    alpha = ((a - 1) / (a + 1)) ** 2
    assert energies.min() >= alpha - 1e-12 and energies.max() <= 1 + 1e-12
    assert abs(energies.mean() - (1 + alpha) / 2) < 5 * energies.std() / math.sqrt(energies.size)


def test_lab_scattering_cosine_off_a_target_of_mass_a_averages_two_thirds_over_a():
    """Isotropic centre-of-mass scattering off a target of mass A (units of the projectile): the mean lab
    deflection cosine is 2 / (3 A) (neutron slowing down, e.g. Lamarsh ch. 3); from mu = 1 the new
    direction cosine is cos(theta_lab). Kills: cos_lab = (1 + A c) / |...| -> (A + c) / |...|."""
    state = _state(11)
    for a in (1.5, 12.0):
        mu = np.array([elastic_lab(1.0, 1.0, a, state)[0] for _ in range(100_000)])
        assert abs(mu.mean() - 2 / (3 * a)) < 5 * mu.std() / math.sqrt(mu.size)


def _ionize_many(sharing, draws=20_000, energy_ev=40.0, threshold_ev=15.0):
    """Energies (eV) of the primary and the new electron after ionizing collisions on a target at rest."""
    energy = energy_ev * E_CHARGE
    state = _state(12345)
    speed = math.sqrt(2 * energy / ME)
    primary, secondary = np.empty(draws), np.empty(draws)
    for n in range(draws):
        # target at rest: the relative velocity g is the projectile's
        velocities = np.array(ionized(0.0, 0.0, 0.0, 0.0, 0.0, speed, speed, energy, ME, threshold_ev * E_CHARGE,
                                      sharing, ISOTROPIC, 1.0, state))
        primary[n] = 0.5 * ME * velocities[:3] @ velocities[:3] / E_CHARGE
        secondary[n] = 0.5 * ME * velocities[3:] @ velocities[3:] / E_CHARGE
    return primary, secondary


def test_ionization_shares_the_energy_left_above_the_threshold():
    primary, secondary = _ionize_many(SHARE_EQUAL, draws=200)
    np.testing.assert_allclose(primary, 12.5, rtol=1e-12)
    np.testing.assert_allclose(secondary, 12.5, rtol=1e-12)
    primary, secondary = _ionize_many(SHARE_UNIFORM)
    np.testing.assert_allclose(primary + secondary, 25.0, rtol=1e-12)  # energy conserved
    assert stats.kstest(primary / 25.0, "uniform").pvalue > 1e-3  # the primary's share is uniform


def test_every_ionization_in_a_step_adds_one_living_child_to_its_parent():
    """An ionizing collision keeps the particle alive and stores the new electron in its parent's child slots,
    the children's own ionizations included: with slots to spare, a particle's children number exactly its
    family's ionizations (tallied on the parent), and with no field, a threshold of 0 and targets at rest the
    family keeps the parent's kinetic energy. Constant-rate ionization: nu t = 1, ~1.7 children a particle."""
    gas = Gas((Species("a", 1e-26, (Process("ionization", rate_coefficient=1e-15),)),))
    tables = build_tables(gas, ME, 0.0)
    n, slots = 2000, 64
    vel = np.random.default_rng(6).normal(0.0, 5e5, (n, 3))
    states = np.random.SeedSequence(6).generate_state(4 * n, np.uint64).reshape(n, 4)
    alive = np.ones(n, bool)
    tallies = np.zeros((n, tables.kind.size + EXTRA_COLUMNS))
    child_pos, child_vel = np.zeros((n, slots, 3)), np.zeros((n, slots, 3))
    child_state, child_alive = np.zeros((n, slots, 4), np.uint64), np.zeros((n, slots), bool)
    child_count = np.zeros(n, np.int64)
    energy_before = 0.5 * ME * (vel**2).sum(axis=1)
    advance_swarm(0, n, np.zeros((n, 3)), vel, states, alive, 0.0, 1e-9, derived_field(np.zeros(3), np.zeros(3)),
                  ME, 1e24, *tables.arrays(), SHARE_EQUAL, *tables.lookup(), tallies, child_pos, child_vel,
                  child_state, child_alive, child_count, True, WINDOW_COLLISIONS, WINDOW_GROWTH)
    assert child_count.max() <= slots and child_count.mean() > 1.0
    np.testing.assert_array_equal(tallies[:, 0], child_count)
    assert alive.all()
    born = np.arange(slots)[None, :] < child_count[:, None]
    np.testing.assert_array_equal(child_alive, born)
    energy_after = 0.5 * ME * ((vel**2).sum(axis=1) + (child_vel**2 * born[..., None]).sum(axis=(1, 2)))
    np.testing.assert_allclose(energy_after, energy_before, rtol=1e-9)


def test_the_displacement_tally_is_each_particle_s_path_from_its_start_to_its_end_or_attachment():
    """tallies[:, P + 3 .. 5] hold the time integral of the velocity over the step (the flux drift is their sum
    over the particle time): for a particle, its end position minus its start, where an attached particle ends
    at its attachment point (and its particle time ends there too). In a field, with attachment: every
    particle's tally equals its move to round-off, and the attached ones moved less on average."""
    gas = Gas((Species("a", 1e-26, (Process("elastic", [0.0, 100.0], [5e-20, 5e-20]),
                                    Process("attachment", rate_coefficient=2e-16))),))
    tables = build_tables(gas, ME, 0.0)
    n = 3000
    rng = np.random.default_rng(9)
    pos0 = rng.normal(0.0, 1e-3, (n, 3))
    pos, vel = pos0.copy(), rng.normal(0.0, 5e5, (n, 3))
    states = np.random.SeedSequence(9).generate_state(4 * n, np.uint64).reshape(n, 4)
    alive = np.ones(n, bool)
    tallies = np.zeros((n, tables.kind.size + EXTRA_COLUMNS))
    empty = (np.zeros((n, 0, 3)), np.zeros((n, 0, 3)), np.zeros((n, 0, 4), np.uint64), np.zeros((n, 0), bool),
             np.zeros(n, np.int64))
    field = derived_field(np.array([0.0, 0.0, 3e15]), np.zeros(3))
    advance_swarm(0, n, pos, vel, states, alive, 0.0, 2e-9, field, ME, 1e24, *tables.arrays(), SHARE_EQUAL,
                  *tables.lookup(), tallies, *empty, True, WINDOW_COLLISIONS, WINDOW_GROWTH)
    assert 300 < (~alive).sum() < n - 300
    moved = tallies[:, tables.kind.size + DISPLACEMENT_COLUMN_OFFSET:][:, :3]
    np.testing.assert_allclose(moved, pos - pos0, rtol=1e-12, atol=1e-18)
    lived = tallies[:, tables.kind.size + TIME_COLUMN_OFFSET]
    assert np.all(lived[alive] == 2e-9) and np.all(lived[~alive] < 2e-9)
    assert moved[~alive, 2].mean() < moved[alive, 2].mean()  # the field pushes +z: the attached moved less


def test_a_particle_that_never_collides_in_a_field_ends_its_call_within_the_budget():
    # zero cross sections (the Python side refuses such a gas; the kernel must not rely on it): no trial ever
    # comes, the windows of the flight grow no longer than a bound, and the step of 1e300 s never ended
    tables = build_tables(Gas((Species("z", 1e-26, (Process("elastic", [0.0, 10.0], [0.0, 0.0]),)),)), ME, 0.0)
    n = 4
    vel = np.tile([0.0, 0.0, 1e5], (n, 1))
    states = np.random.SeedSequence(8).generate_state(4 * n, np.uint64).reshape(n, 4)
    field = derived_field(np.array([0.0, 0.0, 1e15]), np.zeros(3))
    empty = (np.zeros((n, 0, 3)), np.zeros((n, 0, 3)), np.zeros((n, 0, 4), np.uint64), np.zeros((n, 0), bool),
             np.zeros(n, np.int64))

    def advance(budget):
        return advance_swarm(0, n, np.zeros((n, 3)), vel.copy(), states.copy(), np.ones(n, bool), 0.0, 1e300, field,
                             ME, 1e24, *tables.arrays(), SHARE_EQUAL, *tables.lookup(),
                             np.zeros((n, tables.kind.size + EXTRA_COLUMNS)), *empty, False, WINDOW_COLLISIONS,
                             WINDOW_GROWTH, budget)

    advance(10)  # compile outside the deadline
    with deadline(20.0):
        stalled, speed = advance(TRIAL_BUDGET)
    assert stalled == 0 and speed > 1e10  # the first particle, far beyond the table's 10 eV (1.9e6 m/s)


# ------------------------------------------------------------------ exactness of the null-collision method


def _advance(tables, field, vel, seed, t_end, check=True, window=WINDOW_COLLISIONS, scale=1.0):
    """Run advance_swarm on particles at the origin with velocities ``vel``; return (alive, tallies).

    ``scale`` multiplies the trial-frequency bound (table and beyond-table slope): below 1 it is wrong.
    """
    n = vel.shape[0]
    states = np.random.SeedSequence(seed).generate_state(4 * n, np.uint64).reshape(n, 4)
    tallies = np.zeros((n, tables.kind.size + EXTRA_COLUMNS))
    alive = np.ones(n, bool)
    lookup = list(tables.lookup())
    lookup[4] = scale * tables.bound
    lookup[6] = scale * tables.sigma_max
    advance_swarm(0, n, np.zeros((n, 3)), vel.copy(), states, alive, 0.0, t_end, field, ME, 1e24,
                  *tables.arrays(), SHARE_EQUAL, *lookup, tallies, np.zeros((n, 0, 3)), np.zeros((n, 0, 3)),
                  np.zeros((n, 0, 4), np.uint64), np.zeros((n, 0), bool), np.zeros(n, np.int64), check, window)
    return alive, tallies


# attachment only: a cross section that falls and rises (the bound, a running maximum, is loose there), and
# one that rises steeply (a window reaching far too high a speed would make a bound far above the rate)
_ATTACHING = Gas((Species("a", 1e-26, (
    Process("attachment", [0.0, 0.5, 2.0, 100.0], [0.25e-20, 1e-20, 0.125e-20, 0.75e-20]),)),))
_STEEP = Gas((Species("a", 1e-26, (Process("attachment", [0.0, 100.0], [0.2e-20, 20e-20]),)),))


def _survival(field, v0, t_end, points=200_001, gas=_ATTACHING):
    """Exact probability of no collision up to t: exp(-N int sigma(eps(t')) |v(t')| dt'), v(t) of the exact flight."""
    times = np.linspace(0.0, t_end, points)
    speeds = np.empty(points)
    for k, t in enumerate(times):
        pos, vel = np.zeros(3), v0.copy()
        _fly(pos, vel, t, field)
        speeds[k] = math.sqrt(vel @ vel)
    energies = 0.5 * ME * speeds**2 / E_CHARGE
    process = gas.species[0].processes[0]
    rate = 1e24 * np.interp(energies, process.energy, process.cross_section) * speeds
    hazard = np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(times))])
    return times, np.exp(-hazard)


@pytest.mark.parametrize("gas", [_ATTACHING, _STEEP], ids=["falling-rising", "steep"])
@pytest.mark.parametrize("magnetic", [False, True])
@pytest.mark.parametrize("window", [0.2, WINDOW_COLLISIONS, 5.0])
def test_first_collision_times_follow_the_exact_survival_law(gas, magnetic, window):
    """Windows, optical depths and nulls together give the exact collision statistics.

    Attachment ends a particle's flight at its first real collision, so the
    surviving fraction at t_end is exp(-integral of the true rate), and the
    mean time alive is the integral of that survival curve. The particle
    first slows down (v against a), then speeds up; the magnetic field has
    a component along a. The field is strong: the speed changes by more
    than itself between collisions.
    """
    tables = build_tables(gas, ME, 0.0)
    acceleration = np.array([0.3e15, 0.0, 4e15])
    omega = np.array([0.0, 3e10, 1e10]) if magnetic else np.zeros(3)
    field = derived_field(acceleration, omega)
    v0 = np.array([1e5, 2e5, -5e5])
    t_end = 2.5e-10
    times, survival = _survival(field, v0, t_end, gas=gas)
    n = 100_000
    alive, tallies = _advance(tables, field, np.tile(v0, (n, 1)), 7, t_end, window=window)
    P = tables.kind.size
    expected = survival[-1]
    assert 0.2 < expected < 0.8
    assert abs(alive.mean() - expected) < 4.5 * math.sqrt(expected * (1 - expected) / n)
    assert tallies[:, 0].sum() == n - alive.sum()  # every collision was an attachment
    mean_time = np.trapezoid(survival, times)
    time_alive = tallies[:, P + TIME_COLUMN_OFFSET]
    assert abs(time_alive.mean() - mean_time) < 4.5 * time_alive.std() / math.sqrt(n)
    nulls = tallies[:, P + NULL_COLUMN_OFFSET].sum()
    assert nulls > 0.02 * n  # the null path was exercised
    if window <= WINDOW_COLLISIONS:  # ... but the windows keep the bound tight (WINDOW_GROWTH)
        assert nulls < 0.5 * n
    assert tallies[:, P + BOUND_COLUMN_OFFSET].sum() == 0


def test_the_bound_check_catches_a_bound_below_the_true_rate():
    tables = build_tables(_ATTACHING, ME, 0.0)
    field = derived_field(np.array([0.0, 0.0, 4e15]), np.zeros(3))
    v0 = np.array([1e5, 2e5, -5e5])
    n = 20_000
    alive, tallies = _advance(tables, field, np.tile(v0, (n, 1)), 8, 2.5e-10, scale=0.5)
    assert tallies[:, tables.kind.size + BOUND_COLUMN_OFFSET].sum() > 0.01 * n
    _, survival = _survival(field, v0, 2.5e-10, points=20_001)
    assert alive.mean() > survival[-1] + 10 * math.sqrt(0.25 / n)  # too few collisions: visibly wrong


@pytest.mark.parametrize("omega", [np.zeros(3), np.array([0.0, 3e10, 1e10])])
def test_window_speed_bound_holds_along_the_whole_window(omega):
    rng = np.random.default_rng(4)
    for _ in range(200):
        field = derived_field(rng.normal(0, 4e15, 3), omega)
        vel = rng.normal(0, 3e5, 3)
        t1, t2 = np.sort(rng.uniform(0, 3e-10, 2))
        bound = _window_bound_speed(vel, field, t1, t2)
        speeds = []
        for t in np.linspace(t1, t2, 101):
            pos, v = np.zeros(3), vel.copy()
            _fly(pos, v, t, field)
            speeds.append(math.sqrt(v @ v))
        assert max(speeds) <= bound * (1 + 1e-12)
        if not omega.any():  # exact without B: the bound is attained at an end of the window
            assert max(speeds[0], speeds[-1]) == pytest.approx(bound, rel=1e-12)


# ------------------------------------------------------------------ random directions and variates


def test_isotropic_directions_are_uniform_on_the_sphere():
    state = _state(9)
    samples = np.array([isotropic_direction(state) for _ in range(100_000)])
    np.testing.assert_allclose(np.linalg.norm(samples, axis=1), 1.0, rtol=1e-12)
    error = 1 / math.sqrt(3 * samples.shape[0])
    assert np.all(np.abs(samples.mean(axis=0)) < 5 * error)
    for axis in range(3):  # Archimedes: each coordinate of a uniform point on the sphere is uniform on [-1, 1]
        assert stats.kstest(samples[:, axis], "uniform", args=(-1, 2)).pvalue > 1e-3
    assert stats.kstest(np.arctan2(samples[:, 1], samples[:, 0]), "uniform", args=(-math.pi, 2 * math.pi)).pvalue > 1e-3


def test_normal_pairs_are_independent_standard_normals():
    state = _state(10)
    pairs = np.array([normal_pair(state) for _ in range(50_000)])
    for column in pairs.T:
        assert stats.kstest(column, "norm").pvalue > 1e-3
    assert abs(np.corrcoef(pairs.T)[0, 1]) < 5 / math.sqrt(pairs.shape[0])


# ------------------------------------------------------------------ found by a mutation audit


@pytest.mark.parametrize("loss_ev", [0.0, 0.7, -0.7])
def test_two_body_collisions_conserve_momentum_and_lose_exactly_the_threshold(loss_ev):
    """Exact kinematics of two_body: the target's velocity after follows from momentum conservation, and
    the total kinetic energy drops by exactly the threshold (0 for elastic; a superelastic collision, loss < 0,
    gains it). Projectile 3 eV, target of 4 m moving, isotropic scattering. Kills: the relative energy lowered
    by 2 x threshold, the reduced mass replaced by m, the recoil share light <-> heavy, a gain ignored."""
    state = _state(4)
    m, big = ME, 4 * ME
    rng = np.random.default_rng(3)
    for _ in range(200):
        v = rng.normal(0, 1e6, 3)
        gas_v = rng.normal(0, 3e5, 3)
        g = v - gas_v
        speed = math.sqrt(g @ g)
        energy = 0.5 * m * speed**2
        mu = m * big / (m + big)
        loss = min(loss_ev * E_CHARGE, 0.5 * 0.5 * mu * speed**2)  # keep above threshold
        after = np.array(two_body(*v, *gas_v, *g, speed, energy, m, big, loss, ISOTROPIC, 1.0, state))
        target_after = (m * v + big * gas_v - m * after) / big
        before_energy = 0.5 * m * v @ v + 0.5 * big * gas_v @ gas_v
        after_energy = 0.5 * m * after @ after + 0.5 * big * target_after @ target_after
        assert after_energy == pytest.approx(before_energy - loss, rel=1e-9, abs=0)  # SI joules: no absolute slack
