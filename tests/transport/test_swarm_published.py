"""The Monte Carlo swarm against published benchmarks: Reid's ramp (LoKI-MC, MultiBolt) and Lucas-Saelee (LoKI-MC
Table 2, Raspopovic 1999), with tolerances from the run's errors and the published codes' spread."""

import math

import numpy as np
import pytest
from scipy import constants

from collisionkit.transport import lucas_saelee, reid_ramp, simulate_swarm

E = constants.e
ME = constants.m_e


REID = {
    1.0: {"LoKI-MC": (0.1014, 1.264e4, 0.9637e24, 0.7542e24), "MultiBolt": (0.1014, 1.272e4, 0.9746e24, 0.7593e24)},
    12.0: {"LoKI-MC": (0.2691, 6.838e4, 1.137e24, 0.5679e24), "MultiBolt": (0.2688, 6.839e4, 1.134e24, 0.5688e24)},
    24.0: {"LoKI-MC": (0.4081, 8.881e4, 1.138e24, 0.4595e24), "MultiBolt": (0.40922, 8.8522e4, 1.137e24, 0.4601e24)},
}


# the last digit LoKI-MC quotes (<e>, W, N D_T, N D_L): a rounding of sd digit / sqrt(12)
REID_DIGIT = np.array([1e-4, 10.0, 1e21, 1e20])


def _reid_reference(e_over_n):
    """The mean of the published values at e_over_n and its standard uncertainty, per column: the sample sd of
    the values listed (|LoKI-MC - MultiBolt| / sqrt(2)) with the rounding of the last digit in quadrature."""
    published = np.array(list(REID[e_over_n].values()))
    return published.mean(axis=0), np.hypot(published.std(axis=0, ddof=1), REID_DIGIT / math.sqrt(12))


@pytest.mark.slow
@pytest.mark.parametrize("e_over_n", sorted(REID))
def test_reids_ramp_matches_published_transport_coefficients(e_over_n):
    """<e>, bulk W, N D_T and N D_L against the mean of LoKI-MC and MultiBolt (REID above). Tolerance 4 combined
    standard errors, 4 sqrt(s_run^2 + s_pub^2): s_run the run's reported error, s_pub the published values' spread
    (_reid_reference; 0.03-0.8 %, largest at 1 Td, where W and N D_T differ by 0.6 % and 1.1 % between the
    codes). Bands: <e> 0.19-0.81 %, W 0.12-1.9 %, N D 2.9-6.1 % (was 0.5 % and 3 % from the nearer value, the
    3 % ~2.5 run sd for the bulk D's, at their floor ~sqrt(2.4 / N) = 1.1 % with 20000 electrons). Each run stops
    at its tolerances (4-8e7 collisions, 5-9 s CPU). Measured, seeds 7-10 at 1, 12, 24 Td (12 runs): every value
    within 2.2 combined sd (seed 7: 1 Td <e> +0.08 %, 1.7 sd; W +0.60 %, 1.3 sd; the D's within 1.7 sd; 12 Td
    all within 0.6 sd; 24 Td <e> -0.18 %, W +0.19 %, 0.9 and 0.8 sd, both next to LoKI-MC, which is itself
    Monte Carlo). Can fail (scratch copy, seed 7): <e> references x1.01 or x0.99 fail at every E/N (4.1-22 sd);
    W x1.01 at 12 Td, x0.99 at 12 and 24 Td (1 Td's band is 1.9 %); both D's x1.07 or x0.93 at every E/N.
    Raspopovic et al. 1999 (validation-data.md's third row) is not listed: an older Monte Carlo, up to 0.8 % off
    the two codes in <e> and W at 24 Td."""
    r = simulate_swarm(reid_ramp(), e_over_n, gas_temperature=0.0, particles=20000, seed=7, threads=2,
                       tolerances={"mean_energy": 1.5e-3, "drift_velocity_bulk": 1.5e-3,
                                   "diffusion_L_N": 0.015, "diffusion_T_N": 0.015},
                       collision_budget=4e8)
    reference, published_sd = _reid_reference(e_over_n)
    measured = np.array([r.mean_energy, -r.drift_velocity_bulk[2], r.diffusion_T_N, r.diffusion_L_N])
    errors = np.array([r.mean_energy_error, r.drift_velocity_bulk_error[2], r.diffusion_T_N_error,
                       r.diffusion_L_N_error])
    # the run met its tolerances (relative to its values): errors small enough for the comparison to mean something
    assert r.converged and np.all(errors <= np.array([1.5e-3, 1.5e-3, 0.015, 0.015]) * measured), errors / measured
    combined = np.hypot(errors, published_sd)
    sigmas = (measured - reference) / combined
    assert np.all(np.abs(sigmas) <= 4), dict(zip(["<e>", "W bulk", "N D_T", "N D_L"], sigmas.round(2)))


# Lucas-Saelee model at 10 Td, B = 0, m/M = 1e-3, gas at 0 K: LoKI-MC benchmark calculations (Dias et al., Comput.
# Phys. Commun. 282, 108554 (2023), Table 2) and, at F = 0.5, Raspopovic et al. 1999; validation-data.md. Columns:
# <e> (eV), nu_eff / N (m^3/s; the table's 1e3 /s at N = 1e20 m^-3), W flux, W bulk (m/s), N D_T flux, N D_T bulk,
# N D_L flux, N D_L bulk (1/m/s).
LUCAS_SAELEE = {
    0.0: {"LoKI-MC": (5.56, 0.0, 7.33e4, 7.33e4, 2.73e25, 2.73e25, 2.66e25, 2.68e25)},
    0.5: {"LoKI-MC": (5.22, 1.31e-17, 7.28e4, 8.50e4, 2.54e25, 2.70e25, 2.48e25, 2.85e25),
          "Raspopovic 1999": (5.22, 1.33e-17, 7.31e4, 8.58e4, 2.56e25, 2.73e25, 2.49e25, 2.85e25)},
    1.0: {"LoKI-MC": (4.97, 2.43e-17, 7.36e4, 9.47e4, 2.44e25, 2.75e25, 2.38e25, 2.89e25)},
}
_LS_BOTH = np.array(list(LUCAS_SAELEE[0.5].values()))
# the published values' spread: |LoKI-MC - Raspopovic| / their mean at F = 0.5, the one F with two sources
# (0, 1.5 %, 0.41 %, 0.94 %, 0.78 %, 1.1 %, 0.40 %, 0): taken for every F
LUCAS_SAELEE_SPREAD = np.abs(_LS_BOTH[0] - _LS_BOTH[1]) / _LS_BOTH.mean(axis=0)


@pytest.mark.slow
@pytest.mark.parametrize("fraction", sorted(LUCAS_SAELEE))
def test_lucas_saelee_matches_the_published_benchmark(fraction):
    """Every column of the published table (F = 0, 0.5, 1: no ionization, half, all of the inelastic cross
    section): <e>, nu_eff, flux and bulk W, N D_T and N D_L. Reference: the mean of the published sources;
    tolerance 4 standard errors + their spread (above) + half a unit of the table's third digit. nu_eff is the
    ionization rate coefficient the run counts (there is no attachment); at F = 0 it is exactly 0.
    8192 electrons (the bulk D's error floor is ~sqrt(2.4 / N) = 1.7 %), 1.2e8 collisions, ~11 s. Measured
    (seed 31): all within 1.7 sd of the reference but nu_eff at F = 0.5 (1.339e-17 +- 0.29 %: +2.2 % from
    LoKI-MC, +0.7 % from Raspopovic) and W flux (7.337e4 +- 0.10 %: +0.8 %, +0.4 %), which lie nearer
    Raspopovic's; seeds 32, 33 agree (7.334e4, 7.332e4; 1.335e-17, 1.329e-17). Errors: <e> 0.05 %, W 0.1-0.3 %,
    nu_eff 0.2-0.3 %, bulk D 1.4-2.4 %, flux D 3-6 %. At F = 0.5 also k_ion / k_exc = F / (1 - F) = 1 exactly
    in expectation (the two share one cross section's shape), within 4 standard errors of the ratio (the two
    rates' errors in quadrature, 0.36-0.53 %): seed 31 1.0083 +- 0.37 % (2.3 sd); seeds 32-39 within 2.1 sd;
    over seeds 31-39 the ratio scatters 0.56 %, ~1.2x the reported 0.45 % (16 groups, chi^2 p ~ 0.1).
    Replaces the tautology k_ion == ionization_frequency_N (equal by construction) dropped in bdc5cf3. Can fail
    (scratch copy): the expected ratio x1.025 puts seed 31 at -4.6 sd, x0.98 at +7.7 sd."""
    r = simulate_swarm(lucas_saelee(fraction, mass=ME / 1e-3), 10.0, gas_temperature=0.0, particles=8192, seed=31,
                       threads=2, initial_energy=5.0, tolerances={"mean_energy": 1e-9}, collision_budget=1.2e8)
    published = np.array(list(LUCAS_SAELEE[fraction].values()))
    reference = published.mean(axis=0)
    rounding = np.array([0.005, 0.005e-17, 0.005e4, 0.005e4, 0.005e25, 0.005e25, 0.005e25, 0.005e25])
    if fraction == 0:
        assert "lucas_saelee:ionization" not in r.rate_coefficients and r.ionization_frequency_N == 0
        nu, nu_error = 0.0, 0.0
    else:
        nu = r.rate_coefficients["lucas_saelee:ionization"]
        nu_error = r.rate_coefficient_errors["lucas_saelee:ionization"]
    if 0 < fraction < 1:
        # excitation and ionization are 1 - F and F of one cross section: whatever the EEDF, k_ion / k_exc = F / (1 - F)
        excitation = r.rate_coefficients["lucas_saelee:excitation"]
        ratio = nu / excitation
        ratio_error = ratio * math.hypot(nu_error / nu,
                                         r.rate_coefficient_errors["lucas_saelee:excitation"] / excitation)
        assert abs(ratio - fraction / (1 - fraction)) <= 4 * ratio_error, (ratio, ratio_error)
    assert r.attachment_frequency_N == 0
    measured = np.array([r.mean_energy, nu, -r.drift_velocity_flux[2], -r.drift_velocity_bulk[2],
                         r.diffusion_T_N_flux, r.diffusion_T_N, r.diffusion_L_N_flux, r.diffusion_L_N])
    errors = np.array([r.mean_energy_error, nu_error, r.drift_velocity_flux_error[2], r.drift_velocity_bulk_error[2],
                       r.diffusion_T_N_flux_error, r.diffusion_T_N_error, r.diffusion_L_N_flux_error,
                       r.diffusion_L_N_error])
    # small enough errors for the comparison to mean something
    caps = np.array([2e-3, 1e-2, 5e-3, 5e-3, 0.08, 0.03, 0.08, 0.03])
    assert np.all(errors <= caps * np.abs(reference)), errors / np.maximum(reference, 1e-300)
    tolerance = 4 * errors + LUCAS_SAELEE_SPREAD * reference + rounding * (reference > 0)
    names = ["<e>", "nu_eff", "W flux", "W bulk", "N D_T flux", "N D_T bulk", "N D_L flux", "N D_L bulk"]
    off = {n: (m, ref, e) for n, m, ref, e, t in zip(names, measured, reference, errors, tolerance)
           if not abs(m - ref) <= t}
    assert not off, off


@pytest.mark.slow
def test_flux_diffusion_coefficients_of_reids_ramp_match_the_published_values():
    """Reid's ramp at 24 Td is conservative, so flux and bulk diffusion coincide: bulk and flux N D_L and N D_T
    against the mean of LoKI-MC and MultiBolt (REID[24.0]: N D_L 0.4595e24 / 0.4601e24, N D_T 1.138e24 /
    1.137e24; Dias et al., CPC 282, 108554 (2023), Table 1). Tolerance 4 combined standard errors,
    4 sqrt(s_run^2 + s_pub^2), s_pub from _reid_reference (0.09 %, 0.07 %: the run's error dominates). D_T / D_L
    = 2.5 here, so a longitudinal estimator fed a transverse component is off by 150 %. The errors are capped
    (bulk D_L 2.5 %, D_T 1.5 %, flux D_L 12 %, flux D_T 6 %: 4-5 sd of their own scatter over seeds 1-5 and 7
    above its mean), so no band exceeds 4 x 12 % = 48 % (it was 4 sd + 3 % with errors up to 25 %: 103 %).
    32000 electrons, 1e8 collisions, ~13 s CPU (8000 and 4e7, the old run, gave the flux N D_L to 19 %; 64000
    and 1e8 to 5.8 %, no better than 32000). Errors over seeds 1-5, 7: bulk D_L 1.1-1.7 %, D_T 0.6-1.0 %, flux D_L
    4.1-7.7 %, flux D_T 1.6-3.6 %. Measured (seed 7): N D_L +0.1 % (0.06 sd), flux +7.4 % (1.5 sd), N D_T -0.9 %
    (1.2 sd), flux -0.2 % (0.06 sd); bands 5.1 %, 19.6 %, 2.9 %, 10.6 %. Seeds 1-5 within 2.4 sd (flux N D_T
    lies +1 to +6 % high on 4 of 6 seeds, never beyond 2.4 sd). Kills: D_L flux from the y component, D_T flux
    without 1/2, <r_k v_k> summed with v_z only (kernel), and the bulk D_L without 1/2, D_T with 1/2 instead of
    1/4. Can fail (scratch copy, seed 7, references scaled): x1.1 / x0.9 put bulk N D_T at -15 / +12.7 sd and
    bulk N D_L at -7.7 / +7.8 sd; x1.25 / x0.75 flux N D_T at -9.5 / +9.4 sd; flux N D_L fails x0.75 (+6.6 sd),
    not x1.25 (-3.6 sd): its band is 19.6 %."""
    r = simulate_swarm(reid_ramp(), 24.0, gas_temperature=0.0, particles=32000, seed=7, threads=2,
                       tolerances={"mean_energy": 1e-9}, collision_budget=1e8)
    reference, published_sd = _reid_reference(24.0)
    caps = {"diffusion_L_N": 0.025, "diffusion_L_N_flux": 0.12, "diffusion_T_N": 0.015, "diffusion_T_N_flux": 0.06}
    for column, name in ((2, "diffusion_T_N"), (3, "diffusion_L_N")):
        for estimator in (name, f"{name}_flux"):
            value, error = getattr(r, estimator), getattr(r, f"{estimator}_error")
            assert 0 < error < caps[estimator] * reference[column], (estimator, error / reference[column])
            sigmas = (value - reference[column]) / math.hypot(error, published_sd[column])
            assert abs(sigmas) <= 4, (estimator, value / reference[column] - 1, sigmas)
