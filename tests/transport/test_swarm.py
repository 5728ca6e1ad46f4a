"""Swarm validation: Maxwell model (exact), non-conservative runs, errors against the scatter of repeated runs (the published benchmarks: test_swarm_published.py).

Reference values: /work/shared/reference/validation-data.md.
"""

import math
import time

import numpy as np
import pytest
from scipy import constants, special, stats

from collisionkit.transport import (
    Gas, hard_sphere_gas, lucas_saelee, maxwell_model, read_lxcat, reid_ramp, simulate_swarm,
)
from collisionkit.transport import _estimators, _swarm_run
from collisionkit.transport import swarm as swarm_module
from collisionkit.transport.swarm import HUXLEY, REFERENCE_DENSITY, TOWNSEND

E = constants.e
ME = constants.m_e
LIGHT_GAS = 10 * ME  # light targets relax the energy in a few collisions: a fast exact test
RATE = 1e-13  # m^3/s, nu = N k


def _maxwell_exact(e_over_n, temperature=0.0, mass=LIGHT_GAS, b_over_n=0.0):
    """Wannier's exact Maxwell-model drift (any mass ratio): mu nu W = q (E + W x B); E on z, B on y.

    Mean energy 3/2 kT + 1/2 (m + M) W^2 (validation-data.md, "Maxwell model").
    """
    mu = ME * mass / (ME + mass)
    nu = RATE * REFERENCE_DENSITY
    w0 = -E * e_over_n * TOWNSEND * REFERENCE_DENSITY / (mu * nu)
    beta = -E * b_over_n * HUXLEY * REFERENCE_DENSITY / (mu * nu)
    w = np.array([-beta * w0 / (1 + beta**2), 0.0, w0 / (1 + beta**2)])
    energy = 1.5 * constants.k * temperature + 0.5 * (ME + mass) * (w @ w)
    return w, energy / E


def _within(value, error, expected, sigmas=4.0):
    return np.all(np.abs(np.asarray(value) - expected) <= sigmas * np.asarray(error) + 1e-12 * np.abs(expected))


@pytest.mark.parametrize("temperature", [0.0, 3000.0])
def test_maxwell_model_drift_and_energy_are_exact(temperature):
    w, energy = _maxwell_exact(5.0, temperature)
    r = simulate_swarm(maxwell_model(RATE, mass=LIGHT_GAS), 5.0, gas_temperature=temperature, particles=4000, seed=11,
                       tolerances={"mean_energy": 3e-3, "drift_velocity_bulk": 1e-2}, threads=2)
    assert r.converged
    assert r.mean_energy_error < 3e-3 * energy and r.relative_error("drift_velocity_bulk") < 1e-2
    assert _within(r.mean_energy, r.mean_energy_error, energy)
    assert _within(r.drift_velocity_flux, r.drift_velocity_flux_error, w)
    assert _within(r.drift_velocity_bulk, r.drift_velocity_bulk_error, w)
    # collisions counted per unit particle time: a Poisson estimate of the constant k, not k itself (the
    # earlier rel=1e-12 check compared 1e-13 under pytest's silent abs=1e-12, so it could not fail)
    rate, rate_error = r.rate_coefficients["maxwell:elastic"], r.rate_coefficient_errors["maxwell:elastic"]
    assert 0 < rate_error < 1e-3 * RATE
    assert _within(rate, rate_error, RATE)


@pytest.mark.slow
def test_maxwell_model_transverse_diffusion_is_exact():
    """N D_T = N <v^2> (m + M) / (3 nu (2m + M)) for a constant collision frequency, targets at rest.

    The moments close (isotropic scattering in the centre-of-mass frame):
    d<x v_x>/dt = <v_x^2> - nu_m <x v_x> with nu_m = nu M / (m + M), and
    <v_x^2> (1 - (m/(m+M))^2) = (M/(m+M))^2 <v^2>/3 with <v^2> = (m + M) W^2 / m,
    so the bulk and flux estimators of D_T both have an exact target.
    """
    w, energy = _maxwell_exact(5.0)
    nu = RATE * REFERENCE_DENSITY
    v2 = 2 * energy * E / ME
    exact = REFERENCE_DENSITY * v2 * (ME + LIGHT_GAS) / (3 * nu * (2 * ME + LIGHT_GAS))
    r = simulate_swarm(maxwell_model(RATE, mass=LIGHT_GAS), 5.0, gas_temperature=0.0, particles=20000, seed=14,
                       threads=2, tolerances={"diffusion_T_N": 0.02}, collision_budget=2e8)
    assert r.converged and r.relative_error("diffusion_T_N") < 0.02
    assert _within(r.diffusion_T_N, r.diffusion_T_N_error, exact)
    assert r.diffusion_T_N_flux_error < 0.04 * exact
    assert _within(r.diffusion_T_N_flux, r.diffusion_T_N_flux_error, exact)


def test_maxwell_model_in_crossed_fields_gives_the_exact_e_cross_b_drift():
    w, energy = _maxwell_exact(5.0, b_over_n=400.0)
    r = simulate_swarm(maxwell_model(RATE, mass=LIGHT_GAS), 5.0, reduced_magnetic_field=400.0, particles=4000,
                       seed=12, gas_temperature=0.0, tolerances={"mean_energy": 3e-3, "drift_velocity_bulk": 3e-3},
                       threads=2)
    assert abs(w[0]) > 0.3 * abs(w[2])  # a real deflection
    assert _within(r.drift_velocity_flux, r.drift_velocity_flux_error, w)
    assert _within(r.mean_energy, r.mean_energy_error, energy)


def test_results_do_not_depend_on_the_number_of_threads():
    options = dict(particles=320, seed=5, tolerances={"mean_energy": 0.05}, collision_budget=5e5)
    one = simulate_swarm(lucas_saelee(0.5), 300.0, threads=1, **options)
    two = simulate_swarm(lucas_saelee(0.5), 300.0, threads=2, **options)
    assert one.collisions == two.collisions
    assert one.mean_energy == two.mean_energy
    np.testing.assert_array_equal(one.drift_velocity_bulk, two.drift_velocity_bulk)


def test_the_rate_leaves_out_the_probe_step_which_compiles_on_a_cold_cache(monkeypatch):
    # stand in for numba's first compilation (seconds on a cold cache) with a pause in the first step only
    original = _swarm_run.Stepper.step
    steps = []

    def slow_first_step(self, *args):
        if not steps:
            time.sleep(2.0)
        steps.append(None)
        return original(self, *args)

    options = dict(particles=320, seed=3, tolerances={"mean_energy": 0.05}, threads=1)
    plain = simulate_swarm(maxwell_model(), 10.0, **options)
    monkeypatch.setattr(_swarm_run.Stepper, "step", slow_first_step)
    paused = simulate_swarm(maxwell_model(), 10.0, **options)
    assert len(steps) > 1 and paused.collisions == plain.collisions
    assert paused.seconds < plain.seconds + 1.0  # the 2 s in the probe step are not in the timed steps


def test_different_seeds_give_different_but_compatible_results():
    options = dict(particles=1000, tolerances={"mean_energy": 0.01}, threads=2)
    a = simulate_swarm(maxwell_model(RATE, mass=LIGHT_GAS), 5.0, seed=1, **options)
    b = simulate_swarm(maxwell_model(RATE, mass=LIGHT_GAS), 5.0, seed=2, **options)
    assert a.mean_energy != b.mean_energy
    assert abs(a.mean_energy - b.mean_energy) < 5 * math.hypot(a.mean_energy_error, b.mean_energy_error)


@pytest.mark.slow
def test_ionization_makes_bulk_drift_exceed_flux_drift():
    # Lucas-Saelee with F = 1 (all inelastic collisions ionize) at high E/N: ionization at the swarm's
    # front raises the bulk velocity above the flux velocity (Ness & Robson, Phys. Rev. A 34, 2185 (1986)).
    r = simulate_swarm(lucas_saelee(1.0), 600.0, particles=2000, seed=4, threads=2,
                       tolerances={"mean_energy": 1e-2, "drift_velocity_bulk": 2e-2}, collision_budget=3e7)
    assert r.ionization_frequency_N > 10 * r.ionization_frequency_N_error > 0
    wf, wb = abs(r.drift_velocity_flux[2]), abs(r.drift_velocity_bulk[2])
    assert wb - wf > 4 * math.hypot(r.drift_velocity_flux_error[2], r.drift_velocity_bulk_error[2])
    assert 0 < r.eedf_above < 0.05  # the tail beyond four mean energies is in no bin
    assert r.eedf.sum() * (r.eedf_energy[1] - r.eedf_energy[0]) == pytest.approx(1.0 - r.eedf_above, rel=1e-12)


def test_attachment_in_an_lxcat_mixture_is_the_cross_section_integrated_over_the_runs_eedf():
    """k_att = x_B int sigma_att(e) v(e) f(e) de, with the file's attachment cross section (1e-22 m^2 up to 1 eV,
    linear to 0 at 100 eV) on half the gas, summed over the run's own EEDF (midpoint rule on its 200 bins), the
    tail beyond the last edge (eedf_above, ~0.1 %) bounded by its fraction times the largest sigma v above the
    edge. Tolerance 4 standard errors + 1 %: the binning of a smooth rate is worth < 0.5 % here (the constant
    1e-20 m^2 elastic rate of B came out 0.2-0.5 % above its EEDF integral over seeds 2-4), and over 30 seeds
    (3e6 collisions) (k_att - integral) / error scattered with sd 1.26, mean +0.4. Measured (seed 2, 2e7
    collisions, ~3 s): k_att = 5.908e-17 +- 0.50 %, +0.48 % (0.95 sd) from the integral. The attachment cross
    section x1.05 fails it (k_att 6.20e-17 against at most 6.13e-17); so would its species' fraction left out."""
    from pathlib import Path

    gas = read_lxcat(Path(__file__).parent.parent / "data" / "lxcat_new_mixture.txt", fractions=(0.5, 0.5))
    r = simulate_swarm(gas, 50.0, particles=1600, seed=2, threads=2, tolerances={"mean_energy": 1e-9},
                       collision_budget=2e7)
    k, error = r.attachment_frequency_N, r.attachment_frequency_N_error
    assert k == r.rate_coefficients["B:E + B -> B-, Attachment"]
    assert 0 < error < 0.01 * k

    def sigma_v(energy):
        return np.interp(energy, [0.0, 1.0, 100.0], [1e-22, 1e-22, 0.0]) * np.sqrt(2 * energy * E / ME)

    width = r.eedf_energy[1] - r.eedf_energy[0]
    integral = 0.5 * np.sum(sigma_v(r.eedf_energy) * r.eedf) * width
    edge = r.eedf_energy[-1] + width / 2
    tail = 0.5 * r.eedf_above * sigma_v(np.linspace(edge, 100.0, 1000)).max()
    assert integral - 4 * error - 0.01 * k < k < integral + tail + 4 * error + 0.01 * k


def test_screened_coulomb_scattering_runs_and_changes_the_drift():
    gas = reid_ramp()
    iso = simulate_swarm(gas, 12.0, particles=1600, seed=3, threads=2, tolerances={"mean_energy": 0.01})
    screened = simulate_swarm(gas.with_scattering("screened_coulomb", 0.1), 12.0, particles=1600, seed=3,
                              threads=2, tolerances={"mean_energy": 0.01})
    # forward scattering transfers less momentum: faster drift for the same elastic cross section
    assert abs(screened.drift_velocity_flux[2]) > abs(iso.drift_velocity_flux[2]) * 1.05


@pytest.mark.parametrize("case", ["reid 12 Td", "thermal mixture in crossed fields", "ionization"])
def test_the_trial_frequency_is_never_exceeded_in_whole_runs(case, monkeypatch):
    """With the kernel's check on, no trial collision ever finds a true rate above the trial bound."""
    from collisionkit.transport import swarm

    monkeypatch.setattr(swarm, "CHECK_BOUND", True)
    options = dict(particles=640, seed=21, threads=2, tolerances={"mean_energy": 0.05}, collision_budget=2e6)
    if case == "reid 12 Td":
        r = simulate_swarm(reid_ramp(), 12.0, **options)
    elif case == "thermal mixture in crossed fields":
        gas = Gas.mixture({reid_ramp(): 0.7, maxwell_model(RATE, mass=LIGHT_GAS): 0.3})
        r = simulate_swarm(gas, 20.0, reduced_magnetic_field=300.0, gas_temperature=3000.0, **options)
    else:
        r = simulate_swarm(lucas_saelee(1.0), 600.0, **options)
        assert r.ionization_frequency_N > 0
    assert r.null_collisions > 0.01 * r.collisions  # the bound is not trivially the true rate
    assert r.extras["bound_violations"] == 0


def test_the_bound_check_is_off_by_default():
    r = simulate_swarm(reid_ramp(), 12.0, particles=320, seed=22, threads=1, tolerances={"mean_energy": 0.05},
                       collision_budget=2e5)
    assert "bound_violations" not in r.extras


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(reduced_field=-1.0), "reduced_field"),
        (dict(reduced_field=1.0, gas_temperature=-5.0), "gas_temperature"),
        (dict(reduced_field=1.0, particles=10), "particles"),
        (dict(reduced_field=1.0, sharing="half"), "sharing"),
        (dict(reduced_field=1.0, tolerances={"speed": 0.1}), "tolerances"),
        (dict(reduced_field=1.0, tolerances={"mean_energy": 0.0}), r"tolerances\['mean_energy'\] must lie in \(0"),
        (dict(reduced_field=1.0, gravity=(np.nan, 0.0, 0.0)), r"gravity .* must lie in \(-inf, inf\); got nan"),
        (dict(reduced_field=1.0, gravity=(0.0, 0.0)), "gravity .* must be a 3-vector"),
        (dict(reduced_field=1.0, collisions_per_sample=0.0), r"collisions_per_sample must lie in \(0"),
        (dict(reduced_field=1.0, collisions_per_sample=np.inf), "collisions_per_sample"),
        (dict(reduced_field=1.0, energy_bins=0), "energy_bins must be an integer >= 1; got 0"),
        (dict(reduced_field=1.0, min_samples=0), "min_samples must be an integer >= 1"),
        (dict(reduced_field=1.0, collision_budget=-1.0), r"collision_budget must lie in \(0"),
        (dict(reduced_field=1.0, max_seconds=np.nan), "max_seconds"),
        (dict(reduced_field=1.0, max_seconds=0.0), "max_seconds"),
        (dict(reduced_field=1.0, threads=0), "threads must be an integer >= 1"),
        (dict(reduced_field=1.0, seed=-1), "seed must be an integer >= 0"),
        (dict(reduced_field=1.0, mass=np.nan), "mass"),
    ],
)
def test_bad_input_is_refused(kwargs, message):
    with pytest.raises(ValueError, match=message):
        simulate_swarm(reid_ramp(), **kwargs)


@pytest.mark.parametrize(
    "args, kwargs, message",
    [
        (("argon", 10.0), {}, "gas must be a Gas"),
        ((reid_ramp(), True), {}, "reduced_field .* not a bool"),
        ((reid_ramp(), 10.0), dict(particles=True), "particles .* must be an integer"),
        ((reid_ramp(), 10.0), dict(energy_bins=2.5), "energy_bins must be an integer"),
        ((reid_ramp(), 10.0), dict(tolerances=[0.1]), "tolerances must be a dict"),
        ((reid_ramp(), 10.0), dict(progress="yes"), "progress must be a callable"),
    ],
)
def test_wrong_types_are_refused(args, kwargs, message):
    with pytest.raises(TypeError, match=message):
        simulate_swarm(*args, **kwargs)


@pytest.mark.parametrize(
    "kwargs, error, message",
    [
        (dict(collisions=np.nan, points=5), ValueError, "collisions .* got nan"),  # used to hang
        (dict(collisions=-5.0, points=5), ValueError, "collisions"),  # used to return negative times
        (dict(points=0), ValueError, "points must be an integer >= 1; got 0"),
        (dict(particles=0, points=5), ValueError, "particles must be an integer >= 1; got 0"),
        (dict(particles=-1, points=5), ValueError, "particles must be an integer >= 1; got -1"),
        (dict(particles=True, points=5), TypeError, "particles"),
        (dict(points=5.5), TypeError, "points"),  # a whole float (5.0) counts as 5
        (dict(seed=-1, points=5), ValueError, "seed"),
        (dict(initial_energy=0.0, points=5), ValueError, "initial_energy"),
        (dict(reduced_magnetic_field=np.inf, points=5), ValueError, "reduced_magnetic_field"),
        (dict(reduced_magnetic_field=-5.0, points=5), ValueError, "reduced_magnetic_field"),
    ],
)
def test_trace_trajectories_refuses_bad_input(kwargs, error, message):
    from collisionkit.transport.swarm import trace_trajectories

    with pytest.raises(error, match=message):
        trace_trajectories(maxwell_model(RATE, mass=LIGHT_GAS), 10.0, **kwargs)


def test_trace_trajectories_refuses_a_gas_given_by_name():
    from collisionkit.transport.swarm import trace_trajectories

    with pytest.raises(TypeError, match="gas must be a Gas"):
        trace_trajectories("argon", 10.0, points=5)


# Reid's ramp: Dias et al., Comput. Phys. Commun. 282, 108554 (2023), Table 1 (LoKI-MC, MultiBolt,
# Raspopovic et al. 1999); copied in /work/shared/reference/validation-data.md.
# Columns: E/N (Td), mean energy (eV), bulk W (m/s), N D_T, N D_L (m^-1 s^-1); LoKI-MC and MultiBolt rows.
def test_a_neutral_particle_falling_through_the_gas_drifts_like_a_charge_in_a_field():
    """Wannier's Maxwell-model relation holds for any uniform force: m g plays the part of q E."""
    w, energy = _maxwell_exact(5.0)
    field = 5.0 * TOWNSEND * REFERENCE_DENSITY  # the E of 5 Td
    g = E * field / ME  # the acceleration that field gives an electron
    r = simulate_swarm(maxwell_model(RATE, mass=LIGHT_GAS), 0.0, charge=0.0, gravity=(0.0, 0.0, -g),
                       gas_temperature=0.0, particles=4000, seed=13,
                       tolerances={"mean_energy": 3e-3, "drift_velocity_bulk": 1e-2}, threads=2)
    assert r.converged and r.relative_error("drift_velocity_bulk") < 1e-2
    assert _within(r.drift_velocity_bulk, r.drift_velocity_bulk_error, w)
    assert _within(r.mean_energy, r.mean_energy_error, energy)


@pytest.mark.slow
def test_reported_errors_match_the_scatter_of_independent_runs():
    """The group standard errors are honest: independent seeds scatter as the errors say.

    Reid's ramp at 1 Td, where N D_T once came out 0.99 +- 0.009 (x1e24 /m/s) against MultiBolt's
    0.9746: eight independent runs of 1.5e8 collisions gave 0.9752 +- 0.0026 (bulk) and 0.970 +- 0.004
    (flux), their scatter 0.7-1.1 times the reported errors, so that value was a 1.7 sigma fluctuation,
    not a bias. Here (n - 1) s^2 / sigma^2 follows chi^2(n - 1); the band holds with probability 1 - 1e-4
    for each quantity, and fails if the errors are too small (or too large) by about a factor of two.
    Measured (seeds 100-115, band [0.14, 3.08]): <e> 0.60, N D_T 0.83 (flux 1.22), N D_L 0.91 (flux 1.33), W
    flux 0.65 and bulk 0.65, the elastic and excitation rate coefficients 0.58 and 0.61; every error halved
    (scratch: mean_and_error patched) puts <e> at 2.4 and N D_T at 3.3, out of the band.
    """
    runs = [simulate_swarm(reid_ramp(), 1.0, gas_temperature=0.0, particles=1600, seed=seed, threads=2,
                           tolerances={"mean_energy": 1e-9}, collision_budget=4e6) for seed in range(100, 116)]
    dof = len(runs) - 1
    low, high = stats.chi2.ppf([5e-5, 1 - 5e-5], dof) / dof
    ratios = {}
    for name in ("mean_energy", "diffusion_T_N", "diffusion_T_N_flux", "diffusion_L_N", "diffusion_L_N_flux",
                 "drift_velocity_flux", "drift_velocity_bulk"):
        # the drifts' z components (along E); the flux drift is the time average over every flight
        values = np.array([np.ravel(getattr(r, name))[-1] for r in runs])
        errors = np.array([np.ravel(getattr(r, f"{name}_error"))[-1] for r in runs])
        ratios[name] = values.var(ddof=1) / np.mean(errors**2)
    for label in ("reid:elastic", "reid:excitation"):  # collisions counted per unit particle time
        values = np.array([r.rate_coefficients[label] for r in runs])
        errors = np.array([r.rate_coefficient_errors[label] for r in runs])
        ratios[label] = values.var(ddof=1) / np.mean(errors**2)
    assert all(low < ratio < high for ratio in ratios.values()), ratios


def test_the_energy_distribution_of_a_thermalised_swarm_is_maxwellian():
    # E/N = 0 on a warm gas of light targets: the swarm thermalises at the gas temperature, so the EEDF is
    # f(e) = 2 sqrt(e / pi) (kT)^(-3/2) exp(-e / kT). The kernel binned energies in joules against a bin width in
    # eV, so every particle fell in the first bin (its normalisation still came out 1)
    from scipy import special

    kT = constants.k * 1000.0 / E
    r = simulate_swarm(hard_sphere_gas(6e-20, mass=10 * ME), 0.0, gas_temperature=1000.0, particles=1000, seed=3,
                       threads=2, initial_energy=1.5 * kT, tolerances={"mean_energy": 5e-3}, collision_budget=5e6)
    step = r.eedf_energy[1] - r.eedf_energy[0]
    upper_edges = r.eedf_energy + step / 2
    empirical = np.cumsum(r.eedf * step)
    maxwellian = special.gammainc(1.5, upper_edges / kT)  # the CDF of the energy with 3 degrees of freedom
    assert np.abs(empirical - maxwellian).max() < 0.02  # 0.003 measured; the bug gave ~1
    # the tail beyond the last edge is counted apart (it was added to the last bin: a spike 12x the bin before)
    tail = 1.0 - special.gammainc(1.5, upper_edges[-1] / kT)
    assert r.eedf_above == pytest.approx(tail, rel=0.2)
    pdf = 2 * np.sqrt(r.eedf_energy / np.pi) * kT**-1.5 * np.exp(-r.eedf_energy / kT)
    assert r.eedf[-1] < 2.0 * pdf[-1]  # tail bins scatter by 30 %; the overflow made the last one 40x the pdf
    # the first moment of the Maxwellian up to the last edge
    assert (r.eedf * r.eedf_energy).sum() * step == pytest.approx(
        1.5 * kT * special.gammainc(2.5, upper_edges[-1] / kT), rel=0.02)


def test_an_undriven_swarm_needs_a_warm_gas_and_takes_no_drift_tolerance(monkeypatch):
    # with no field and no gravity nothing heats the swarm: at 0 K it cools forever (a run used its whole budget)
    with pytest.raises(ValueError, match="no steady state"):
        simulate_swarm(maxwell_model(RATE, mass=LIGHT_GAS), 0.0, gas_temperature=0.0, particles=500, threads=1)
    with pytest.raises(ValueError, match="no steady state"):
        simulate_swarm(maxwell_model(RATE, mass=LIGHT_GAS), 5.0, charge=0.0, gas_temperature=0.0, particles=500,
                       threads=1)
    with pytest.raises(ValueError, match=r"tolerances\['drift_velocity_bulk'\] cannot be met"):
        simulate_swarm(maxwell_model(RATE, mass=LIGHT_GAS), 0.0, gas_temperature=300.0, particles=500, threads=1,
                       tolerances={"drift_velocity_bulk": 0.01})
    # in a warm gas it thermalises: the default tolerances, less the drift's, are met; <e> = 3 kT / 2
    # (defaults shortened to the mean energy and the drift here, so the run is quick)
    monkeypatch.setattr(swarm_module, "DEFAULT_TOLERANCES", {"mean_energy": 3e-3, "drift_velocity_bulk": 2e-3})
    r = simulate_swarm(maxwell_model(RATE, mass=LIGHT_GAS), 0.0, gas_temperature=3000.0, particles=2000, seed=4,
                       threads=2, collision_budget=1e8)
    assert r.converged and r.relative_error("mean_energy") < 3e-3
    assert _within(r.mean_energy, r.mean_energy_error, 1.5 * constants.k * 3000.0 / E)


# ------------------------------------------------------------------ found by a mutation audit


E_CHARGE, ME = constants.e, constants.m_e


def test_coarse_energy_distribution_of_a_thermalised_swarm_matches_the_maxwellian_bin_by_bin():
    """E/N = 0 on a warm gas of light targets: the swarm thermalises at T, energies follow the gamma(3/2, kT)
    law. With 20 bins (0.3 kT wide) each reported density times the bin width must equal the Maxwellian's
    probability of the bin [centre - w/2, centre + w/2) (the last one also holds the overflow) within 0.01
    (statistics ~0.002). Kills: eedf_energy = upper bin edges (bin 0 then claims [0.15, 0.45] kT: 0.122
    instead of 0.094)."""
    kT = constants.k * 1000.0 / E_CHARGE
    r = simulate_swarm(hard_sphere_gas(6e-20, mass=10 * ME), 0.0, gas_temperature=1000.0, particles=1000, seed=3,
                       threads=2, initial_energy=1.5 * kT, tolerances={"mean_energy": 5e-3}, collision_budget=5e6,
                       energy_bins=20)
    width = r.eedf_energy[1] - r.eedf_energy[0]
    low = np.maximum(r.eedf_energy - width / 2, 0.0) / kT  # the first edge is 0 (up to round-off)
    high = np.append((r.eedf_energy[:-1] + width / 2) / kT, np.inf)
    expected = special.gammainc(1.5, high) - special.gammainc(1.5, low)
    np.testing.assert_allclose(r.eedf * width, expected, atol=0.01)


def test_the_initial_swarm_has_the_requested_mean_energy():
    """initial_energy is the mean energy of the initial Maxwellian: 3/2 m sigma^2 per particle (eV);
    120000 particles give it to 0.4 % (relative sd sqrt(2/3 / N)). Kills: sigma^2 = 2 E / m (3 E)."""
    mass = 10 * ME
    swarm = _swarm_run.initial_swarm(120_000, 4, 1, mass, 2.5)
    energy = 0.5 * mass * (swarm.vel**2).sum(axis=1) / E_CHARGE
    assert energy.mean() == pytest.approx(2.5, rel=0.01)
    assert np.all(swarm.pos == 0) and swarm.alive.all()


def test_the_bulk_diffusion_error_floor_is_what_walkers_give_however_long_they_walk():
    """An independent check of diffusion_error_floor: N Gaussian walkers (D = 1/2 per step), the bulk estimator's
    least-squares slope of their variance, over many realisations. Its relative scatter is sqrt(6/5) sqrt(2 / N)
    for a window from the start of the spreading, at 100 steps and at 400 alike: the error does not fall with the
    run's length, only with N. With 300 realisations the scatter is known to about 4 %."""
    rng = np.random.default_rng(5)
    walkers = 200
    floor = swarm_module.diffusion_error_floor("diffusion_L_N", walkers)
    scatter = []
    for steps in (100, 400):
        times = np.arange(steps, dtype=float)
        estimates = [0.5 * _estimators.slope(times, np.cumsum(rng.normal(size=(steps, walkers)), axis=0)
                                             .var(axis=1, ddof=1)) for _ in range(300)]
        scatter.append(np.std(estimates, ddof=1) / 0.5)
    assert scatter[0] / floor == pytest.approx(math.sqrt(1.2), rel=0.15)
    assert scatter[1] / floor == pytest.approx(math.sqrt(1.2), rel=0.15)
    assert 0.8 < scatter[1] / scatter[0] < 1.25  # four times longer, not half the error
    assert swarm_module.diffusion_error_floor("diffusion_T_N", walkers) == pytest.approx(math.sqrt(1 / walkers))


def test_a_diffusion_tolerance_out_of_reach_of_the_swarm_size_warns_and_names_the_size_needed():
    with pytest.warns(UserWarning, match=r"particles >= 2000000"):
        simulate_swarm(reid_ramp(), 12.0, particles=2000, seed=1, threads=1, tolerances={"diffusion_L_N": 1e-3},
                       collision_budget=2e5)


def test_the_default_tolerances_reach_below_no_floor(recwarn):
    # the default diffusion tolerance (2 %) is above the floor of the default 20000 particles (1 %)
    simulate_swarm(reid_ramp(), 12.0, seed=1, threads=1, collision_budget=2e5)
    assert not [w for w in recwarn if "particles >=" in str(w.message)]


def test_the_error_floor_refuses_an_unknown_coefficient_or_swarm_size():
    with pytest.raises(ValueError, match="diffusion_L_N"):
        swarm_module.diffusion_error_floor("mean_energy", 100)
    with pytest.raises(ValueError, match="particles"):
        swarm_module.diffusion_error_floor("diffusion_L_N", 0)
    with pytest.raises(TypeError, match="particles"):
        swarm_module.diffusion_error_floor("diffusion_L_N", 2.5)


def test_a_result_row_holds_every_scalar_once_and_splits_the_vectors():
    r = simulate_swarm(reid_ramp(), 12.0, particles=640, groups=8, seed=2, threads=1, collision_budget=2e6,
                       tolerances={"mean_energy": 0.05})
    row = r.to_row()
    assert [row[f"drift_velocity_bulk_{axis}"] for axis in "xyz"] == r.drift_velocity_bulk.tolist()
    assert [row[f"drift_velocity_flux_error_{axis}"] for axis in "xyz"] == r.drift_velocity_flux_error.tolist()
    assert row["rate_coefficient[reid:elastic]"] == r.rate_coefficients["reid:elastic"]
    assert row["rate_coefficient_error[reid:excitation]"] == r.rate_coefficient_errors["reid:excitation"]
    assert row["diffusion_L_N"] == r.diffusion_L_N and row["converged"] == r.converged
    assert all(np.isscalar(value) for value in row.values())
    assert "eedf" not in row and "extras" not in row


def test_a_result_comes_back_from_its_strict_json_with_nan_as_nan(tmp_path):
    import dataclasses
    import json

    from collisionkit._io import atomic_write_json
    from collisionkit.transport import SwarmResult

    r = simulate_swarm(reid_ramp(), 12.0, particles=640, groups=8, seed=2, threads=1, collision_budget=2e6,
                       tolerances={"mean_energy": 0.05})
    r = dataclasses.replace(r, attachment_frequency_N_error=math.nan)  # strict JSON writes null for it
    path = atomic_write_json(tmp_path / "r.json", r.to_dict())
    back = SwarmResult.from_dict(json.loads(path.read_text()))
    for name in SwarmResult.__dataclass_fields__:
        value, original = getattr(back, name), getattr(r, name)
        if isinstance(original, np.ndarray):
            np.testing.assert_array_equal(value, original, err_msg=name)  # NaN equals NaN here
        elif name != "attachment_frequency_N_error":
            assert value == original, name
    assert math.isnan(back.attachment_frequency_N_error)
    with pytest.raises(ValueError, match="mean_energy"):
        SwarmResult.from_dict({"reduced_field": 1.0})
    with pytest.raises(TypeError, match="mapping"):
        SwarmResult.from_dict([1, 2])


def test_two_processes_with_the_same_label_keep_a_rate_coefficient_each():
    """An LXCat file may give two processes the same reaction text; a dict keyed by label kept only the last."""
    from collisionkit.transport import Process, Species

    gas = Gas((Species("x", 1e-26, (
        Process("elastic", [0, 100], [6e-20, 6e-20]),
        Process("excitation", [0.2, 100], [0.0, 1e-19], threshold=0.2, label="x*"),
        Process("excitation", [0.5, 100], [0.0, 5e-20], threshold=0.5, label="x*"))),))
    r = simulate_swarm(gas, 50.0, particles=640, groups=8, seed=2, threads=1, collision_budget=2e6,
                       tolerances={"mean_energy": 0.05})
    assert list(r.rate_coefficients) == ["x:elastic", "x:x*", "x:x* #2"]
    assert r.rate_coefficients["x:x*"] > r.rate_coefficients["x:x* #2"] > 0  # lower threshold, larger cross section


def test_default_diffusion_tolerances_out_of_reach_of_a_small_swarm_warn_once_and_say_they_are_the_defaults():
    with pytest.warns(UserWarning) as caught:
        simulate_swarm(reid_ramp(), 12.0, particles=640, seed=1, threads=1, collision_budget=2e5)
    messages = [str(w.message) for w in caught if "out of reach" in str(w.message)]
    assert len(messages) == 1
    assert "the default tolerances" in messages[0] and "diffusion_L_N" in messages[0] and "diffusion_T_N" in messages[0]


def test_the_collision_budget_is_kept_to_within_two_samples():
    """The budget was checked only after chunks of 25 samples and after the first 100 measured ones: a budget of
    2e6 ran 2.9e7 collisions. Now it is checked after every sample; a result needs two (20 collisions per
    particle each, 4e5 here)."""
    r = simulate_swarm(reid_ramp(), 12.0, particles=20_000, seed=1, threads=2, collision_budget=2e6,
                       tolerances={"mean_energy": 1e-6})
    assert not r.converged
    assert 2e6 <= r.collisions < 2e6 + 3 * 4e5


def test_group_errors_are_standard_errors_of_the_mean():
    """mean_and_error over independent groups: for n groups of unit variance the squared error averages
    1/n exactly (E s^2 = 1); 4000 replicas of 16 groups pin it to 1 %. Kills: std without / sqrt(n)."""
    rng = np.random.default_rng(5)
    squared = [_estimators.mean_and_error(rng.normal(size=(16, 3)))[1] ** 2 for _ in range(4000)]
    np.testing.assert_allclose(np.mean(squared, axis=0), 1 / 16, rtol=0.05)


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


def test_a_trace_in_an_ionizing_real_gas_drops_the_children_it_does_not_follow():
    """trace_trajectories follows no children (no slots): an ionization in argon at 50 Td made the step retry with
    twice zero slots on a swarm it had not kept, and fail. Kills: the retry without slots."""
    import warnings

    from collisionkit.transport import LXCatWarning, catalogue_gas, trace_trajectories

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", LXCatWarning)
        argon = catalogue_gas("Ar")
    times, positions = trace_trajectories(argon, 100.0, particles=4, collisions=2000.0, points=200, seed=2026)
    assert positions.shape == (200, 4, 3) and np.all(np.diff(times) > 0)
    assert np.all(positions[-1, :, 2] < positions[0, :, 2])  # the electrons drift against E (+z)
