"""Kernel-level checks: random streams, exact free flight, angular sampling, rate bounds."""

import math

import numpy as np
import pytest
from scipy import constants, stats
from scipy.integrate import solve_ivp

from collisionkit._kernels import transport as K
from collisionkit.transport import (
    Gas, Process, Species, hard_sphere_gas, maxwell_model, reid_ramp, screened_coulomb_momentum_ratio, simulate_swarm,
)
from collisionkit.transport._tables import build_tables

E_CHARGE, ME = constants.e, constants.m_e


def _state(seed=1):
    state = np.zeros(4, np.uint64)
    K.seed_state(np.uint64(seed), state)
    return state


def test_uniform_stream_has_the_right_moments_and_never_returns_zero():
    state = _state()
    values = np.array([K.uniform(state) for _ in range(200_000)])
    assert values.min() > 0.0 and values.max() < 1.0
    assert abs(values.mean() - 0.5) < 5 * math.sqrt(1 / 12 / values.size)
    assert abs(values.var() - 1 / 12) < 0.002


def test_exact_gyration_matches_numerical_integration():
    acceleration = np.array([1.0, -2.0, 3.0])
    omega = np.array([0.3, 1.1, -0.7])
    field = K.derived_field(acceleration, omega)
    pos, vel = np.array([0.1, 0.2, 0.3]), np.array([1.0, 0.5, -0.2])

    def rhs(_, y):
        return np.concatenate([y[3:], acceleration + np.cross(y[3:], omega)])

    solution = solve_ivp(rhs, (0, 7.3), np.concatenate([pos, vel]), rtol=1e-11, atol=1e-12)
    K.fly(pos, vel, 7.3, field)
    np.testing.assert_allclose(np.concatenate([pos, vel]), solution.y[:, -1], rtol=1e-8, atol=1e-8)


def test_screened_coulomb_sampling_has_the_analytic_mean_cosine():
    state = _state(3)
    energy, screening = 2.0, 1.0
    samples = np.array([K.scattering_cosine(K.SCREENED_COULOMB, energy, screening, state) for _ in range(200_000)])
    expected = screened_coulomb_momentum_ratio(energy, screening)
    error = samples.std() / math.sqrt(samples.size)
    assert abs(np.mean(1 - samples) - expected) < 5 * error


def test_rate_bound_is_never_below_the_true_rate():
    gas = Gas.mixture({reid_ramp(): 0.6, Gas((Species("x", 1e-26, (
        Process("elastic", [0, 1, 3, 50], [1e-19, 3e-19, 5e-20, 2e-20]),
        Process("excitation", [1.5, 4, 50], [2e-20, 1e-19, 0.0], threshold=1.5))),)): 0.4})
    tables = build_tables(gas, constants.m_e, 0.0)
    energies = np.concatenate([np.linspace(0, 120, 20001), [0.2, 1.5, 3.0]]) * constants.e
    edges = np.arange(tables.bound.shape[1] + 1) * tables.bound_step  # speeds exactly on the bin edges too
    energies = np.concatenate([energies, 0.5 * constants.m_e * edges**2])
    inverse_step = (1.0 / tables.bound_step) * (1.0 + 1e-12)
    for s in range(2):
        for energy in energies:
            speed = math.sqrt(2 * energy / constants.m_e)
            i = K.node_index(energy, tables.nodes, tables.accelerator, tables.accelerator_step)
            rate = sum(K.cross_section(j, energy, i, tables.nodes, tables.sigma) * speed + tables.const_rate[j]
                       for j in range(tables.kind.size)
                       if tables.species_of[j] == s and energy >= tables.threshold[j])
            bound = K.rate_bound(s, speed, tables.bound, tables.bound_step, tables.sigma_max, tables.const_max)
            assert bound >= rate * (1 - 1e-12)
            # the kernel's form: a multiplication by the inverse bin width, rounded up
            fast = K._bound_fast(s, speed, tables.bound, inverse_step, tables.sigma_max, tables.const_max)
            assert fast >= bound


def test_slab_elastic_energy_loss_matches_the_mass_ratio_law():
    state = _state(5)
    a = 12.0
    energies = np.array([K._elastic_lab(1.0, 1.0, a, state)[1] for _ in range(100_000)])
    alpha = ((a - 1) / (a + 1)) ** 2
    assert energies.min() >= alpha - 1e-12 and energies.max() <= 1 + 1e-12
    assert abs(energies.mean() - (1 + alpha) / 2) < 5 * energies.std() / math.sqrt(energies.size)


@pytest.mark.parametrize("bad", [-1.0, math.nan])
def test_tables_refuse_bad_cross_sections(bad):
    with pytest.raises(ValueError, match="cross_section"):
        Process("elastic", [0, 1], [1e-20, bad])


def _ionize_many(sharing, draws=20_000, energy_ev=40.0, threshold_ev=15.0):
    """Energies (eV) of the primary and the new electron after ionizing collisions on a target at rest."""
    mass = constants.m_e
    energy = energy_ev * constants.e
    kind = np.array([K.IONIZATION])
    threshold = np.array([threshold_ev * constants.e])
    angular = np.array([K.ISOTROPIC])
    screening = np.array([1.0])
    state = np.zeros(4, dtype=np.uint64)
    K.seed_state(np.uint64(12345), state)
    gas_v = np.zeros(3)
    speed = math.sqrt(2 * energy / mass)
    primary, secondary = np.empty(draws), np.empty(draws)
    for n in range(draws):
        vel = np.array([0.0, 0.0, speed])
        g = vel.copy()
        child = np.zeros(3)
        outcome = K._collide(0, vel, gas_v, g, speed, energy, mass, 1e3 * mass, kind, threshold, angular,
                             screening, sharing, state, child, np.zeros(16))
        assert outcome == 2
        primary[n] = 0.5 * mass * vel @ vel / constants.e
        secondary[n] = 0.5 * mass * child @ child / constants.e
    return primary, secondary


def test_ionization_shares_the_energy_left_above_the_threshold():
    primary, secondary = _ionize_many(K.SHARE_EQUAL, draws=200)
    np.testing.assert_allclose(primary, 12.5, rtol=1e-12)
    np.testing.assert_allclose(secondary, 12.5, rtol=1e-12)
    primary, secondary = _ionize_many(K.SHARE_UNIFORM)
    np.testing.assert_allclose(primary + secondary, 25.0, rtol=1e-12)  # energy conserved
    assert stats.kstest(primary / 25.0, "uniform").pvalue > 1e-3  # the primary's share is uniform


# ------------------------------------------------------------------ exactness of the null-collision method


def _advance(tables, field, vel, seed, t_end, check=True, window=K.WINDOW_COLLISIONS, scale=1.0):
    """Run advance_swarm on particles at the origin with velocities ``vel``; return (alive, tallies).

    ``scale`` multiplies the trial-frequency bound (table and beyond-table slope): below 1 it is wrong.
    """
    n = vel.shape[0]
    states = np.random.SeedSequence(seed).generate_state(4 * n, np.uint64).reshape(n, 4)
    tallies = np.zeros((n, tables.kind.size + K.EXTRA_COLUMNS))
    alive = np.ones(n, bool)
    lookup = list(tables.lookup())
    lookup[4] = scale * tables.bound
    lookup[6] = scale * tables.sigma_max
    K.advance_swarm(0, n, np.zeros((n, 3)), vel.copy(), states, alive, 0.0, t_end, field, constants.m_e, 1e24,
                    *tables.arrays(), K.SHARE_EQUAL, *lookup, tallies, np.zeros((n, 0, 3)), np.zeros((n, 0, 3)),
                    np.zeros((n, 0, 4), np.uint64), np.zeros((n, 0), bool), np.zeros(n, np.int64), check, window)
    return alive, tallies


# attachment only: a cross section that falls and rises (the bound, a running maximum, is loose there), and
# one that rises steeply (a window reaching far too high a speed would make a bound far above the rate)
_ATTACHING = Gas((Species("a", 1e-26, (
    Process("attachment", [0.0, 0.5, 2.0, 100.0], [0.25e-20, 1e-20, 0.125e-20, 0.75e-20]),)),))
_STEEP = Gas((Species("a", 1e-26, (Process("attachment", [0.0, 100.0], [0.2e-20, 20e-20]),)),))


def _survival(field, v0, t_end, points=200_001, gas=_ATTACHING):
    """Exact probability of no collision up to t: exp(-N int sigma(eps(t')) |v(t')| dt'), with v(t) from fly."""
    times = np.linspace(0.0, t_end, points)
    speeds = np.empty(points)
    for k, t in enumerate(times):
        pos, vel = np.zeros(3), v0.copy()
        K.fly(pos, vel, t, field)
        speeds[k] = math.sqrt(vel @ vel)
    energies = 0.5 * constants.m_e * speeds**2 / constants.e
    process = gas.species[0].processes[0]
    rate = 1e24 * np.interp(energies, process.energy, process.cross_section) * speeds
    hazard = np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(times))])
    return times, np.exp(-hazard)


@pytest.mark.parametrize("gas", [_ATTACHING, _STEEP], ids=["falling-rising", "steep"])
@pytest.mark.parametrize("magnetic", [False, True])
@pytest.mark.parametrize("window", [0.2, K.WINDOW_COLLISIONS, 5.0])
def test_first_collision_times_follow_the_exact_survival_law(gas, magnetic, window):
    """Windows, optical depths and nulls together give the exact collision statistics.

    Attachment ends a particle's flight at its first real collision, so the
    surviving fraction at t_end is exp(-integral of the true rate), and the
    mean time alive is the integral of that survival curve. The particle
    first slows down (v against a), then speeds up; the magnetic field has
    a component along a. The field is strong: the speed changes by more
    than itself between collisions.
    """
    tables = build_tables(gas, constants.m_e, 0.0)
    acceleration = np.array([0.3e15, 0.0, 4e15])
    omega = np.array([0.0, 3e10, 1e10]) if magnetic else np.zeros(3)
    field = K.derived_field(acceleration, omega)
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
    time_alive = tallies[:, P + K.TIME_COLUMN_OFFSET]
    assert abs(time_alive.mean() - mean_time) < 4.5 * time_alive.std() / math.sqrt(n)
    nulls = tallies[:, P + K.NULL_COLUMN_OFFSET].sum()
    assert nulls > 0.02 * n  # the null path was exercised
    if window <= K.WINDOW_COLLISIONS:  # ... but the windows keep the bound tight (WINDOW_GROWTH)
        assert nulls < 0.5 * n
    assert tallies[:, P + K.BOUND_COLUMN_OFFSET].sum() == 0


def test_the_bound_check_catches_a_bound_below_the_true_rate():
    tables = build_tables(_ATTACHING, constants.m_e, 0.0)
    field = K.derived_field(np.array([0.0, 0.0, 4e15]), np.zeros(3))
    v0 = np.array([1e5, 2e5, -5e5])
    n = 20_000
    alive, tallies = _advance(tables, field, np.tile(v0, (n, 1)), 8, 2.5e-10, scale=0.5)
    assert tallies[:, tables.kind.size + K.BOUND_COLUMN_OFFSET].sum() > 0.01 * n
    _, survival = _survival(field, v0, 2.5e-10, points=20_001)
    assert alive.mean() > survival[-1] + 10 * math.sqrt(0.25 / n)  # too few collisions: visibly wrong


@pytest.mark.parametrize("omega", [np.zeros(3), np.array([0.0, 3e10, 1e10])])
def test_window_speed_bound_holds_along_the_whole_window(omega):
    rng = np.random.default_rng(4)
    for _ in range(200):
        field = K.derived_field(rng.normal(0, 4e15, 3), omega)
        vel = rng.normal(0, 3e5, 3)
        t1, t2 = np.sort(rng.uniform(0, 3e-10, 2))
        bound = K.window_bound_speed(vel, field, t1, t2)
        speeds = []
        for t in np.linspace(t1, t2, 101):
            pos, v = np.zeros(3), vel.copy()
            K.fly(pos, v, t, field)
            speeds.append(math.sqrt(v @ v))
        assert max(speeds) <= bound * (1 + 1e-12)
        if not omega.any():  # exact without B: the bound is attained at an end of the window
            assert max(speeds[0], speeds[-1]) == pytest.approx(bound, rel=1e-12)


def test_rate_bound_is_a_running_maximum():
    tables = build_tables(_ATTACHING, constants.m_e, 0.0)
    assert np.all(np.diff(tables.bound, axis=1) >= 0)


def test_isotropic_directions_are_uniform_on_the_sphere():
    state = _state(9)
    out = np.empty(3)
    samples = np.empty((100_000, 3))
    for k in range(samples.shape[0]):
        K.isotropic_direction(state, out)
        samples[k] = out
    np.testing.assert_allclose(np.linalg.norm(samples, axis=1), 1.0, rtol=1e-12)
    error = 1 / math.sqrt(3 * samples.shape[0])
    assert np.all(np.abs(samples.mean(axis=0)) < 5 * error)
    for axis in range(3):  # Archimedes: each coordinate of a uniform point on the sphere is uniform on [-1, 1]
        assert stats.kstest(samples[:, axis], "uniform", args=(-1, 2)).pvalue > 1e-3
    assert stats.kstest(np.arctan2(samples[:, 1], samples[:, 0]), "uniform", args=(-math.pi, 2 * math.pi)).pvalue > 1e-3


def test_normal_pairs_are_independent_standard_normals():
    state = _state(10)
    pairs = np.array([K.normal_pair(state) for _ in range(50_000)])
    for column in pairs.T:
        assert stats.kstest(column, "norm").pvalue > 1e-3
    assert abs(np.corrcoef(pairs.T)[0, 1]) < 5 / math.sqrt(pairs.shape[0])


# ------------------------------------------------------------------ found by a mutation audit


@pytest.mark.parametrize("loss_ev", [0.0, 0.7])
def test_two_body_collisions_conserve_momentum_and_lose_exactly_the_threshold(loss_ev):
    """Exact kinematics of _two_body: the target's velocity after follows from momentum conservation, and
    the total kinetic energy drops by exactly the threshold (0 for elastic). Projectile 3 eV, target of 4 m
    moving, isotropic scattering. Kills: the relative energy lowered by 2 x threshold, the reduced mass
    replaced by m, the recoil share light <-> heavy."""
    from collisionkit._kernels import transport as K

    state = np.zeros(4, np.uint64)
    K.seed_state(np.uint64(4), state)
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
        after = np.array(K._two_body(*v, *gas_v, *g, speed, energy, m, big, loss, K.ISOTROPIC, 1.0, state))
        target_after = (m * v + big * gas_v - m * after) / big
        before_energy = 0.5 * m * v @ v + 0.5 * big * gas_v @ gas_v
        after_energy = 0.5 * m * after @ after + 0.5 * big * target_after @ target_after
        assert after_energy == pytest.approx(before_energy - loss, rel=1e-9, abs=0)  # SI joules: no absolute slack


def test_rate_coefficients_in_a_mixture_carry_the_number_fractions():
    """Rate coefficients are per unit total density: k_j = x_s (sigma_j <g> + k_const). Three species of
    equal mass 10 m_e: a Maxwell-model species (x = 0.3, k = 1e-13: k_A = 3e-14 exactly in expectation) and
    two identical hard-sphere species (x = 0.5, 0.2: k_B / k_C = 2.5 whatever the speed distribution, and
    k_B = 0.5 sigma <v> with <v> from the EEDF, binning error ~1 %). Kills: constant rates or cross sections
    not multiplied by the species' fraction."""
    rate, sigma = 1e-13, 6e-20
    gas = Gas.mixture({maxwell_model(rate, mass=10 * ME, name="A"): 0.3,
                       hard_sphere_gas(sigma, mass=10 * ME, name="B"): 0.5,
                       hard_sphere_gas(sigma, mass=10 * ME, name="C"): 0.2})
    r = simulate_swarm(gas, 5.0, particles=1000, seed=4, threads=2, tolerances={"mean_energy": 1e-2})
    k, err = r.rate_coefficients, r.rate_coefficient_errors
    assert abs(k["A:elastic"] - 0.3 * rate) < 5 * err["A:elastic"]
    ratio = k["B:elastic"] / k["C:elastic"]
    spread = ratio * math.hypot(err["B:elastic"] / k["B:elastic"], err["C:elastic"] / k["C:elastic"])
    assert abs(ratio - 2.5) < 5 * spread
    width = r.eedf_energy[1] - r.eedf_energy[0]
    binned_speed = np.sum(r.eedf * np.sqrt(2 * r.eedf_energy * E_CHARGE / ME)) * width
    # the tail beyond the last edge (eedf_above, ~5 %) moves at least the edge speed, and at most 1.5 times it
    edge_speed = math.sqrt(2 * (r.eedf_energy[-1] + width / 2) * E_CHARGE / ME)
    low, high = (0.5 * sigma * (binned_speed + r.eedf_above * c * edge_speed) for c in (1.0, 1.5))
    assert 0.97 * low < k["B:elastic"] < 1.03 * high  # ~1e-15: no absolute slack


@pytest.mark.slow
def test_flux_diffusion_coefficients_of_reids_ramp_match_the_published_values():
    """Reid's ramp at 24 Td is conservative, so flux and bulk diffusion coincide; published N D_L = 0.4595e24
    (LoKI-MC) / 0.4601e24 (MultiBolt), N D_T = 1.138e24 / 1.137e24 (Dias et al., CPC 282, 108554 (2023),
    Table 1). D_T / D_L = 2.5 here, so a longitudinal estimator fed a transverse component is off by 150 %.
    4e7 collisions (~20 s) give the flux estimators to ~10 % (1 sd); tolerance 4 sd + 3 %.
    Kills: D_L flux from the y component, D_T flux without 1/2, <r_k v_k> summed with v_z only (kernel),
    and the bulk D_L without 1/2, D_T with 1/2 instead of 1/4."""
    r = simulate_swarm(reid_ramp(), 24.0, particles=8000, seed=7, threads=2, tolerances={"mean_energy": 1e-9},
                       collision_budget=4e7)
    published = {"diffusion_L_N": (0.4595e24, 0.4601e24), "diffusion_T_N": (1.138e24, 1.137e24)}
    for name, references in published.items():
        for estimator in (name, f"{name}_flux"):
            value, error = getattr(r, estimator), getattr(r, f"{estimator}_error")
            assert error < 0.15 * references[0], estimator
            assert min(abs(value - ref) for ref in references) < 4 * error + 0.03 * references[0], (estimator, value)
