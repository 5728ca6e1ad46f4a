"""Tests of collisionkit.edmd.measurement: the sampler's estimators against theory, its clock and checks."""

import math
import time

import numpy as np
import pytest

from collisionkit import edmd
from collisionkit.edmd import _pair_distribution
from tests.edmd.systems import fcc_system, hexagonal_system, square_system


def test_sampler_needs_a_system():
    with pytest.raises(TypeError, match="system must be a HardSphereSystem"):
        edmd.Sampler("x", 100, 2)
    with pytest.raises(TypeError, match="system"):
        edmd.measure("x", 100, 2)
    with pytest.raises(TypeError, match="blocks"):
        edmd.Sampler(square_system(), 100, True)


def test_the_measured_rate_leaves_out_compiling_the_event_loop(monkeypatch):
    # stand in for numba's first compilation (tens of seconds on a cold cache) with a pause in the first call
    original = edmd.HardSphereSystem._run_events
    calls = []

    def slow_first_call(self, collisions, t_stop):
        if not calls:
            time.sleep(2.0)
        calls.append(collisions)
        return original(self, collisions, t_stop)

    monkeypatch.setattr(edmd.HardSphereSystem, "_run_events", slow_first_call)
    m = edmd.measure(fcc_system(cells=3, eta=0.3), collisions=4_000, blocks=2)
    assert calls[0] == 0 and m.collisions == 4_000  # compiled by a run of no collisions, before the clock
    assert m.wall_seconds < 1.0


def test_the_measured_rate_counts_the_sampling_of_each_block(monkeypatch):
    # the collisions_per_second is the wall clock of the measurement phase: g(r) and the
    # other samples are part of it, so a slow sample must slow the reported rate
    original = _pair_distribution.pair_histogram

    def slow_histogram(*args, **kwargs):
        time.sleep(0.5)
        return original(*args, **kwargs)

    monkeypatch.setattr(_pair_distribution, "pair_histogram", slow_histogram)
    m = edmd.measure(fcc_system(cells=3, eta=0.3), collisions=4_000, blocks=2)
    assert m.wall_seconds >= 2 * 0.5
    assert m.collisions_per_second <= 4_000 / (2 * 0.5)


def reference_check(measurement, reference, tolerance=0.005):
    z, error = measurement.compressibility_factor, measurement.compressibility_factor_error
    assert error < 0.3 * tolerance * reference  # the run is long enough to test at this tolerance
    assert abs(z - reference) < tolerance * reference


@pytest.mark.slow
@pytest.mark.parametrize("eta", [0.2, 0.4])
def test_hard_sphere_equation_of_state(eta):
    """Z within 0.5 % of Hansen-Goos (J. Chem. Phys. 144, 164506, 2016)."""
    system = fcc_system(cells=6, eta=eta, seed=11)
    system.run(collisions=100 * system.count)
    m = edmd.measure(system, collisions=1_000 * system.count, blocks=20)
    reference_check(m, float(edmd.hansen_goos(eta)))
    # Enskog: omega = (2d / sigma) (Z - 1) sqrt(kT / (pi m)), within the statistical errors
    expected = float(edmd.enskog_collision_frequency(m.compressibility_factor, 3, kT=m.temperature))
    spread = math.hypot(m.collision_frequency_error, expected * m.compressibility_factor_error / (m.compressibility_factor - 1))
    assert abs(m.collision_frequency - expected) < 4 * spread + 1e-3 * expected
    # contact value: Z = 1 + 4 eta g(sigma), g from the pair distribution extrapolated to contact
    from_pressure = (m.compressibility_factor - 1) / (4 * eta)
    assert abs(m.contact_value - from_pressure) < 4 * m.contact_value_error + 0.01 * from_pressure


@pytest.mark.slow
def test_hard_disc_equation_of_state():
    """Z within 0.5 % of Henderson (Mol. Phys. 30, 971, 1975) at eta = 0.3.

    The collision frequency against Enskog's omega = (4 / sigma) (Z - 1) sqrt(kT / (pi m)) of the measured Z (an
    equilibrium identity: both are g(sigma) times a mean of the collisions' normal speeds): 4 standard errors of
    the difference plus 0.1 % (finite N: the microcanonical speeds of 512 discs, O(1 / (d N))). The error is that
    of the 20 blocks' differences omega_b - omega_E(Z_b), which carries the covariance of the two estimates
    (both count the same collisions): 0.07-0.10 % of omega, where the two errors combined as if independent
    (hypot) give 0.17-0.23 %. Measured: seed 12 -0.026 % (0.4 sd); seeds 12-23 -0.20 % to +0.04 %, -2.2 to
    +0.4 sd (mean -0.05 %: the finite-N bias the 0.1 % holds); tolerance 0.37-0.52 % (was 1 %). Can fail
    (seed 12, scratch copy; tolerance 0.37 %): Enskog's omega x1.01, x1.005 and x0.996 put the difference at
    -1.0 %, -0.53 % and +0.37 %, each out (the old 1 % passed the last two)."""
    system = hexagonal_system(cells=16, eta=0.3, seed=12)
    system.run(collisions=100 * system.count)
    m = edmd.measure(system, collisions=1_000 * system.count, blocks=20)
    reference_check(m, float(edmd.henderson(0.3)))
    expected = float(edmd.enskog_collision_frequency(m.compressibility_factor, 2, kT=m.temperature))
    difference = m.block_frequency - edmd.enskog_collision_frequency(m.block_compressibility, 2, kT=m.temperature)
    error = difference.std(ddof=1) / math.sqrt(difference.size)
    assert difference.mean() == pytest.approx(m.collision_frequency - expected, rel=1e-9, abs=1e-12)  # linear in Z
    assert 0 < error < 2e-3 * expected
    assert abs(m.collision_frequency - expected) < 4 * error + 1e-3 * expected


@pytest.fixture(scope="module")
def dense_discs_of_diameter_two():
    """288 discs of diameter 2 (not 1, so that a virial missing its contact distance shows) at eta = 0.3."""
    positions, box = edmd.lattice("hexagonal", 12, 0.3, diameter=2.0)
    n = len(positions)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(n), 2, seed=5), 1.0, box)
    system.run(collisions=30 * n)
    # 502 bins up to 5 diameters: contact (bin edge 100.4) falls inside a bin, not on an edge
    return system, edmd.measure(system, collisions=200 * n, blocks=10, rdf_bins=502)


def test_pressure_of_discs_of_diameter_two_follows_henderson(dense_discs_of_diameter_two):
    """Z within 5 standard errors + 0.5 % of Henderson (0.3 % accurate at eta = 0.3, and O(1/N) for N = 288);
    P = Z n kT by definition (elastic: kT = 1 exactly). Kills: virial += impulse (no contact distance),
    the virial divided without d, the pressure without d or without its ideal part n kT."""
    system, m = dense_discs_of_diameter_two
    reference = float(edmd.henderson(0.3))
    assert m.compressibility_factor_error < 0.01 * reference
    assert abs(m.compressibility_factor - reference) < 5 * m.compressibility_factor_error + 0.005 * reference
    n_kT = system.count * m.temperature / system.volume
    assert m.pressure == pytest.approx(m.compressibility_factor * n_kT, rel=1e-9)
    assert m.pressure_error == pytest.approx(m.compressibility_factor_error * n_kT, rel=1e-9)


def test_collision_frequency_of_discs_matches_enskog_from_the_measured_pressure(dense_discs_of_diameter_two):
    """omega = (4 / sigma) (Z - 1) sqrt(kT / (pi m)) holds exactly in equilibrium (both sides ~ g(sigma));
    the two estimates share the run, so 5 combined standard errors bound the difference."""
    system, m = dense_discs_of_diameter_two
    expected = float(edmd.enskog_collision_frequency(m.compressibility_factor, 2, diameter=2.0, kT=m.temperature))
    spread = math.hypot(m.collision_frequency_error,
                        expected * m.compressibility_factor_error / (m.compressibility_factor - 1))
    assert abs(m.collision_frequency - expected) < 5 * spread + 0.005 * expected


def test_g_of_r_is_reported_at_the_bin_centres(dense_discs_of_diameter_two):
    """A histogram bin [r_k, r_k + dr) estimates g at its centre: the first non-empty bin is the one holding
    contact, so its reported r is within dr / 2 of sigma = 2 (here sigma = 100.4 dr). Kills: rdf_r = upper
    bin edges (g plotted, and extrapolated to contact, half a bin too far out)."""
    system, m = dense_discs_of_diameter_two
    dr = m.rdf_r[1] - m.rdf_r[0]
    assert m.rdf_r[0] == pytest.approx(dr / 2, rel=1e-9)
    first = m.rdf_r[np.flatnonzero(m.rdf > 0)[0]]
    assert abs(first - 2.0) < dr / 2


@pytest.fixture(scope="module")
def dilute_spheres():
    """256 spheres (diameter 1, mass 1, kT 1) at eta = 0.05: Enskog's g(sigma) from Carnahan-Starling is exact
    to 1e-4 there. 4000 N collisions in 200 blocks (~1.7 s): every block end is a time origin of the mean
    squared displacement, so D's error falls with the number of blocks (400 N in 20 blocks left it at 3-5 %)."""
    positions, box = edmd.lattice("fcc", 4, 0.05)
    n = len(positions)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(n), 3, seed=6), 0.5, box)
    system.run(collisions=30 * n)
    m = edmd.measure(system, collisions=4000 * n, blocks=200)
    eta = 0.05
    density = n / system.volume
    contact = (1 - eta / 2) / (1 - eta) ** 3  # Carnahan-Starling g(sigma)
    return system, m, density, contact


def test_collision_frequency_mean_free_time_and_path_of_a_dilute_gas(dilute_spheres):
    """omega = 4 n sigma^2 g(sigma) sqrt(pi kT / m) exactly in equilibrium; mean free time 1 / omega; mean free
    path <v> / omega = 1 / (sqrt(2) pi n sigma^2 g) (Chapman & Cowling). Tolerance: 5 standard errors of omega
    plus 1 % (finite N, g). Kills: omega = 2 C / (N t) -> C / (N t), 1/omega -> 2/omega, <v>/omega -> <v> omega."""
    system, m, density, g = dilute_spheres
    omega = 4 * density * g * math.sqrt(math.pi)
    relative = 5 * m.collision_frequency_error / m.collision_frequency + 0.01
    assert m.collision_frequency == pytest.approx(omega, rel=relative)
    assert m.mean_free_time == pytest.approx(1 / omega, rel=relative)
    assert m.mean_free_path == pytest.approx(1 / (math.sqrt(2) * math.pi * density * g), rel=relative)
    # Maxwell: <v> = sqrt(8 kT / (pi m)), within 4 standard errors of the 200 block ends' mean speeds (0.05 %:
    # the total energy is fixed, so a snapshot's mean speed scatters 4x less than 256 free speeds would) plus
    # 0.04 % (at fixed energy and momentum <v> of 256 particles is 0.033 % above Maxwell's). Seeds 6-21: +0.02 % on
    # average, error 0.041-0.049 %; seed 6 +0.051 % (1.0 sd; tolerance 0.24 %, was 2 %). Maxwell's <v> x1.003 fails
    # it (-0.25 % against 0.24 %; scratch copy)
    block_means = m.speeds.reshape(-1, system.count).mean(axis=1)
    assert block_means.size == 200
    speed_error = block_means.std(ddof=1) / math.sqrt(block_means.size)
    maxwell = math.sqrt(8 * m.temperature / math.pi)
    assert abs(m.mean_speed - maxwell) < 4 * speed_error + 4e-4 * maxwell


# NIST hard-sphere data (usnistgov/feasst, plugin/flat_histogram/test/data/stat_hs.csv, as in test_transport.py):
# n sigma^3: (D, its error), the two rows either side of the dilute fixture's n sigma^3 = 6 eta / pi = 0.0955
NIST_DIFFUSION = {0.075: (2.640503, 0.002924), 0.1: (1.934599, 0.003292)}


def test_self_diffusion_of_a_dilute_gas_is_the_published_one(dilute_spheres):
    """D from the mean squared displacement, <r^2> = 2 d D t, against the NIST hard-sphere D at n sigma^3 =
    0.0955: Enskog's D_E = 3 / (8 n sigma^2 g) sqrt(kT / (pi m)) times the published D / D_E, interpolated
    linearly between the NIST rows at 0.075 and 0.1 (1.0348, 1.0464: 1.0443 here; the curvature of D / D_E makes
    that < 0.03 % off). Tolerance 4 standard errors (the run's and the table's, 0.17 %, combined) plus 3 % for
    the finite size (Yeh-Hummer with Enskog's viscosity puts D of N = 256 in this box 2.8 % below the infinite
    system's; the NIST rows do not say their N) and the published uncertainty. D's error comes from 8 groups of
    particles (7 degrees of freedom), hence the 3 % is not left out. Measured: seed 6 D = 2.037 +- 1.4 %,
    +0.14 % from the reference (0.1 sd); seeds 6-21: -3.0 % to +1.2 %, mean -1.2 % (the finite size), their
    scatter 1.15 %, errors 0.6-1.7 %; tolerance 5.5-9.9 % (seed 6: 8.7 %; was [0.8, 1.25] D_E, i.e. -23 % to
    +20 %). Can fail (scratch copy, seed 6): the reference x1.1 (-9.0 % against 8.2 %) and x0.9 (+11.3 % against
    9.3 %); D with d -> 2 d (-50 %)."""
    system, m, density, g = dilute_spheres
    eta = math.pi / 6 * density
    assert eta == pytest.approx(0.05, rel=1e-9)
    (low, (d_low, e_low)), (high, (d_high, e_high)) = sorted(NIST_DIFFUSION.items())
    enskog_low, enskog_high = (edmd.enskog_transport(math.pi / 6 * rho)["self_diffusion"] for rho in (low, high))
    weight = (density - low) / (high - low)
    ratio = (1 - weight) * d_low / enskog_low + weight * d_high / enskog_high
    ratio_error = (1 - weight) * e_low / enskog_low + weight * e_high / enskog_high
    enskog = edmd.enskog_transport(eta)["self_diffusion"]
    assert enskog == pytest.approx(3 / (8 * density * g) / math.sqrt(math.pi), rel=1e-12)
    reference, reference_error = enskog * ratio, enskog * ratio_error
    assert 0 < m.diffusion_coefficient_error < 0.03 * reference  # the band is not all statistics
    error = math.hypot(m.diffusion_coefficient_error, reference_error)
    assert abs(m.diffusion_coefficient - reference) < 4 * error + 0.03 * reference


def test_energy_lost_counts_only_the_measurement():
    """The measurement's energy_lost is the kinetic energy lost during it (exact bookkeeping: sum of
    (1 - e^2) mu u_n^2 / 2), not since the system was made. Kills: energy_lost without - start_lost."""
    positions, box = edmd.lattice("sc", 5, 0.2)
    n = len(positions)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(n), 3, seed=2), 0.5, box, restitution=0.9)
    system.run(collisions=2 * n)
    before = system.kinetic_energy()
    assert system.energy_lost > 0.01 * before  # lost before the measurement starts
    m = edmd.measure(system, collisions=2 * n, blocks=2)
    assert m.energy_lost == pytest.approx(before - system.kinetic_energy(), rel=1e-9)


def test_mean_free_time_and_path_errors_follow_from_the_collision_frequency():
    """tau = 1 / omega and l = <v> / omega: their errors are omega's relative error times the value."""
    m = edmd.measure(fcc_system(cells=3, eta=0.3), collisions=20_000, blocks=5)
    relative = m.collision_frequency_error / m.collision_frequency
    assert m.mean_free_time_error == pytest.approx(relative * m.mean_free_time, rel=1e-12)
    assert m.mean_free_path_error == pytest.approx(relative * m.mean_free_path, rel=1e-12)
    assert m.summary()["diffusion_coefficient_error"] == m.diffusion_coefficient_error > 0


def test_a_block_and_a_measurement_report_the_fractions_of_their_collisions():
    system = fcc_system(cells=3, eta=0.3)
    fractions = []
    edmd.Sampler(system, collisions=4_000, blocks=2).run_block(fractions.append)
    assert fractions[-1] == 1.0 and fractions == sorted(fractions)
    overall = []
    edmd.measure(system, collisions=6_000, blocks=3, progress=overall.append)
    assert overall == sorted(overall) and all(0.0 < fraction <= 1.0 for fraction in overall)
    for block_end in (1 / 3, 2 / 3, 1.0):
        assert any(fraction == pytest.approx(block_end, rel=1e-12) for fraction in overall)
    assert overall[-1] == 1.0


def test_a_sampler_saved_before_its_first_block_resumes_to_the_same_measurement():
    # state_dict() of a sampler with no finished block raised "cannot reshape array of size 0"
    def measured(sampler):
        while sampler.done < sampler.blocks:
            sampler.run_block()
        return sampler.result()

    straight = measured(edmd.Sampler(fcc_system(cells=3, eta=0.3, seed=5), collisions=4 * 2_000, blocks=4))
    system = fcc_system(cells=3, eta=0.3, seed=5)
    fresh = edmd.Sampler(system, collisions=4 * 2_000, blocks=4)
    state, system_state = fresh.state_dict(), system.state_dict()
    resumed = edmd.Sampler.from_state_dict(edmd.HardSphereSystem.from_state_dict(system_state), state)
    assert resumed.done == 0
    again = measured(resumed)
    assert again.pressure == straight.pressure and again.diffusion_coefficient == straight.diffusion_coefficient


def test_a_sampler_runs_the_blocks_it_planned_and_then_asks_for_extend():
    # run_block() went on past the planned blocks: done 4 of 2, a measurement of twice the collisions asked for
    sampler = edmd.Sampler(square_system(), collisions=400, blocks=2)
    sampler.run_block()
    sampler.run_block()
    with pytest.raises(RuntimeError, match=r"all 2 blocks it planned.*extend\(blocks\)"):
        sampler.run_block()
    assert sampler.done == 2 and sampler.result().collisions == 400
    sampler.extend(1)
    sampler.run_block()
    assert sampler.done == 3 and sampler.result().collisions == 600


def test_a_system_at_rest_is_said_to_be_at_rest_not_collapsed():
    system = square_system(velocities=np.zeros((16, 2)))
    with pytest.raises(RuntimeError, match=r"at rest \(kT = 0\)"):
        edmd.measure(system, collisions=100, blocks=2)
