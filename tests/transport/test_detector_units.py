"""collisionkit.transport.detector_units: a swarm in a gas detector's units (V/cm, Torr, cm/us, sqrt(cm), 1/cm)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import constants

from collisionkit.transport import (
    TORR, detector_coefficients, gas_number_density, maxwell_model, reduced_fields, simulate_swarm,
)


def test_the_number_density_and_the_reduced_field_of_a_detector_gas():
    """N = p / (k T): Loschmidt's constant (CODATA 2018, 2.686780111e25 m^-3) at 760 Torr and 273.15 K; 1 kV/cm at 1 atm and 293.15 K is
    1e5 V/m / 2.50345e25 m^-3 = 3.99445 Td. Kills: Torr taken as 101325/750, V/cm as V/m."""
    loschmidt = constants.physical_constants["Loschmidt constant (273.15 K, 101.325 kPa)"][0]
    assert gas_number_density(760.0, 273.15) == pytest.approx(loschmidt, rel=1e-9)
    assert TORR == pytest.approx(133.322368, rel=1e-8)
    density = 101325.0 / (constants.k * 293.15)
    np.testing.assert_allclose(reduced_fields([1000.0, 0.0], 760.0, 293.15), [1e5 / density / 1e-21, 0.0],
                               rtol=1e-12)
    for bad, message in ((([-1.0], 760.0, 293.0), "field E"), (([1.0], 0.0, 293.0), "pressure"),
                         (([1.0], 760.0, 0.0), "temperature")):
        with pytest.raises(ValueError, match=message):
            reduced_fields(*bad)


@pytest.fixture(scope="module")
def maxwell_swarm():
    gas = maxwell_model(1e-13, mass=4 * constants.atomic_mass)
    return simulate_swarm(gas, 20.0, particles=4000, seed=3, tolerances={"mean_energy": 0.01}, gas_temperature=300.0)


def test_a_maxwell_swarm_drifts_at_its_exact_speed_in_cm_per_us(maxwell_swarm):
    """Constant nu = N k: W = (e / (m_r k)) E/N whatever the pressure; in cm/us within 4 of its errors (1 m/s =
    1e-4 cm/us). The field comes back as the E that gives 20 Td at 100 Torr. Kills: m/s reported as cm/us, the
    field's V/m."""
    row = detector_coefficients(maxwell_swarm, 100.0)
    reduced_mass = constants.m_e * 4 * constants.atomic_mass / (constants.m_e + 4 * constants.atomic_mass)
    exact = constants.e / (reduced_mass * 1e-13) * 20.0 * 1e-21 * 1e-4
    assert abs(row["drift_velocity"] - exact) < 4 * row["drift_velocity_error"] and row["drift_velocity_error"] > 0
    assert reduced_fields([row["field"]], 100.0, 300.0)[0] == pytest.approx(20.0, rel=1e-12)
    assert row["temperature"] == 300.0 and row["townsend_alpha"] == 0.0


def test_diffusion_is_sigma_per_root_drift_length_and_scales_as_one_over_root_pressure(maxwell_swarm):
    """sqrt(2 D / W) in sqrt(cm) from the bulk N D and W (an independent by-hand conversion), its error half the
    relative error of D / W, sqrt(r_D^2 + r_W^2 - 2 rho r_D r_W) with the groups' correlation rho; at 4 times the
    pressure it halves (D ~ 1/N, W fixed at one E/N). Kills: sqrt(m) reported as sqrt(cm), flux D for bulk, the
    error not halved, the correlation's sign."""
    row = detector_coefficients(maxwell_swarm, 760.0)
    density = 760.0 * TORR / (constants.k * 300.0)
    drift = abs(maxwell_swarm.drift_velocity_bulk[2])
    for axis, n_d, n_d_error in (("L", maxwell_swarm.diffusion_L_N, maxwell_swarm.diffusion_L_N_error),
                                 ("T", maxwell_swarm.diffusion_T_N, maxwell_swarm.diffusion_T_N_error)):
        by_hand = math.sqrt(2.0 * n_d / density / drift) * 100.0 ** 0.5  # sqrt(m) = 10 sqrt(cm)
        assert row[f"diffusion_{axis}"] == pytest.approx(by_hand, rel=1e-12)
        r_d, r_w = n_d_error / n_d, maxwell_swarm.drift_velocity_bulk_error[2] / drift
        rho = getattr(maxwell_swarm, f"drift_diffusion_{axis}_correlation")
        assert -1.0 <= rho <= 1.0
        relative = 0.5 * math.sqrt(r_d**2 + r_w**2 - 2.0 * rho * r_d * r_w)
        assert row[f"diffusion_{axis}_error"] == pytest.approx(by_hand * relative, rel=1e-9)
    assert detector_coefficients(maxwell_swarm, 4 * 760.0)["diffusion_L"] == pytest.approx(row["diffusion_L"] / 2,
                                                                                          rel=1e-12)


def test_fields_that_make_no_detector_table_are_refused(maxwell_swarm):
    cold = simulate_swarm(maxwell_model(1e-13), 20.0, particles=500, seed=1, tolerances={"mean_energy": 0.2},
                          gas_temperature=0.0)
    with pytest.raises(ValueError, match="temperature"):
        detector_coefficients(cold, 760.0)
    assert detector_coefficients(cold, 760.0, temperature=293.15)["temperature"] == 293.15
    with pytest.raises(TypeError, match="SwarmResult"):
        detector_coefficients({"drift": 1.0}, 760.0)


def test_townsend_and_attachment_coefficients_per_cm_are_the_sst_ones_times_n():
    """An ionizing gas (Lucas-Saelee, F = 1, 500 Td): alpha in 1/cm is the steady-state alpha/N times N / 100, by
    hand, with its error the same way; no attachment. Kills: 1/m reported as 1/cm, the error for the value."""
    from collisionkit.transport import lucas_saelee

    result = simulate_swarm(lucas_saelee(1.0), 500.0, particles=2000, seed=2, tolerances={"mean_energy": 0.05},
                            gas_temperature=300.0)
    row = detector_coefficients(result, 50.0)
    density = 50.0 * TORR / (constants.k * 300.0)
    assert result.alpha_N > 0 and result.alpha_N_error > 0
    assert row["townsend_alpha"] == pytest.approx(result.alpha_N * density / 100.0, rel=1e-12)
    assert row["townsend_alpha_error"] == pytest.approx(result.alpha_N_error * density / 100.0, rel=1e-12)
    assert row["attachment_eta"] == 0.0


def test_a_result_saved_without_the_correlations_takes_d_and_w_as_independent(maxwell_swarm):
    """A SwarmResult written before the correlations existed reads them as NaN: the error is then the quadrature sum
    (independent D and W), as before."""
    from collisionkit.transport import SwarmResult

    data = maxwell_swarm.to_dict()
    del data["drift_diffusion_L_correlation"], data["drift_diffusion_T_correlation"]
    old = SwarmResult.from_dict(data)
    assert math.isnan(old.drift_diffusion_L_correlation)
    row = detector_coefficients(old, 760.0)
    drift = abs(old.drift_velocity_bulk[2])
    relative = 0.5 * math.hypot(old.diffusion_L_N_error / old.diffusion_L_N, old.drift_velocity_bulk_error[2] / drift)
    assert row["diffusion_L_error"] == pytest.approx(row["diffusion_L"] * relative, rel=1e-12)
