"""The spatially resolved SST run: its Townsend coefficient against the bulk conversion, and its checks."""

import numpy as np
import pytest
from scipy import constants

from collisionkit.transport import lucas_saelee, maxwell_model, simulate_sst, simulate_swarm, townsend_coefficients

ME = constants.m_e


@pytest.mark.slow
def test_the_direct_sst_alpha_agrees_with_the_bulk_conversion_and_the_benchmark():
    """Lucas-Saelee, F = 1, 10 Td, m/M = 1e-3, 0 K: electrons released at a plane multiply as exp(alpha s) past
    their relaxation; the fitted alpha/N (jackknife error over 16 groups, 0.7 %) against the bulk conversion of an
    ordinary run (4 combined errors), and against the value the LoKI-MC benchmark's bulk coefficients imply (4
    errors plus the benchmark's 0.6 % spread). Released at the swarm's mean energy, followed over 4 e-folds."""
    gas = lucas_saelee(1.0, mass=ME / 1e-3)
    bulk = simulate_swarm(gas, 10.0, gas_temperature=0.0, particles=4000, seed=5, threads=2, initial_energy=5.0,
                          tolerances={"mean_energy": 1e-9}, collision_budget=6e7)
    sst = simulate_sst(gas, 10.0, length_N=4 / bulk.alpha_N, gas_temperature=0.0, particles=1000, seed=3, threads=2,
                       initial_energy=5.0)
    assert sst.alpha_eff_N_error < 0.015 * sst.alpha_eff_N and bulk.alpha_N_error < 0.01 * bulk.alpha_N
    assert abs(sst.alpha_eff_N - bulk.alpha_N) < 4 * np.hypot(sst.alpha_eff_N_error, bulk.alpha_N_error)
    loki, _ = townsend_coefficients(9.47e4, 2.89e25, 2.43e-17, 0.0)
    assert abs(sst.alpha_eff_N - loki) < 4 * sst.alpha_eff_N_error + 0.006 * loki
    # the profile grows by about e^(alpha L) over the run, and the window skips the source and the absorbing end
    assert sst.window == pytest.approx((0.4 * 4 / bulk.alpha_N, 0.8 * 4 / bulk.alpha_N))
    inside = (sst.position_N >= sst.window[0]) & (sst.position_N < sst.window[1])
    growth = np.log(sst.density[inside][-1] / sst.density[inside][0])
    assert growth == pytest.approx(sst.alpha_eff_N * (sst.position_N[inside][-1] - sst.position_N[inside][0]),
                                   rel=0.1)


def test_without_ionization_the_sst_density_is_flat():
    """A conservative gas: the time-integrated density past the source is the flux over the drift velocity, the
    same in every slab: alpha_eff = 0 within its errors."""
    r = simulate_sst(maxwell_model(1e-13, mass=10 * ME), 10.0, length_N=2e21, particles=256, groups=8, seed=2,
                     threads=2)  # L: about 1500 mean free paths
    assert abs(r.alpha_eff_N) < 4 * r.alpha_eff_N_error
    assert r.alpha_eff_N_error < 0.1 / 2e21  # a tenth of an e-fold over the length at the most


@pytest.mark.parametrize(
    "kwargs, words",
    [
        (dict(length_N=0.0), "length_N"),
        (dict(length_N=1e20, window=(0.8, 0.4)), "window must be two fractions"),
        (dict(length_N=1e20, window=(0.1, 1.5)), "window"),
        (dict(length_N=1e20, bins=2), "bins"),
        (dict(length_N=1e20, particles=4), "particles"),
        (dict(length_N=1e20, sharing="half"), "sharing"),
    ],
)
def test_bad_sst_settings_are_refused(kwargs, words):
    with pytest.raises(ValueError, match=words):
        simulate_sst(maxwell_model(), 10.0, **kwargs)
    with pytest.raises(ValueError, match="reduced_field"):
        simulate_sst(maxwell_model(), 0.0, length_N=1e20)


def test_an_avalanche_that_outgrows_max_electrons_stops_with_what_to_do():
    # 600 Td over 2e20 m^-2 with every inelastic collision ionizing grew without bound: killed at 23 GB of memory
    gas = lucas_saelee(1.0, mass=9.109e-28)
    with pytest.raises(RuntimeError, match=r"more than max_electrons \(2000\).*use a shorter length_N"):
        simulate_sst(gas, 600.0, length_N=2e20, particles=64, groups=4, seed=1, threads=1, max_electrons=2000)


def test_max_electrons_must_hold_the_released_particles():
    with pytest.raises(ValueError, match=r"max_electrons \(at least particles, 64\)"):
        simulate_sst(maxwell_model(), 10.0, length_N=1e20, particles=64, groups=4, max_electrons=63)
