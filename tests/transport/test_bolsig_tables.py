"""collisionkit.transport.bolsig_tables: a scan as BOLSIG+'s output tables, read back as a fluid code reads them."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import constants

AMU = constants.atomic_mass

from collisionkit.transport import (
    BOLSIG_SECTIONS, bolsig_tables, maxwell_model, missing_rows, read_bolsig_section, reid_ramp, simulate_swarm,
    two_term_boltzmann, write_bolsig_tables,
)


def _sections(text: str) -> list[str]:
    """The section headers of ``text``, in order (the line after each ``E/N (Td)<TAB>``)."""
    return [line.split("\t", 1)[1] for line in text.splitlines() if line.startswith("E/N (Td)\t")]


def test_a_two_term_scan_reads_back_section_by_section_in_rising_e_n(tmp_path):
    """Each coefficient under BOLSIG+'s header, to the 7 digits written; the scan given out of order is written in
    rising E/N; each process's rate after its C line; the gas temperature line as BOLSIG+ writes it."""
    results = [two_term_boltzmann(reid_ramp(), e_n, 0.0) for e_n in (24.0, 1.0, 12.0)]
    text = write_bolsig_tables(tmp_path / "bolsig.dat", results).read_text()
    ordered = sorted(results, key=lambda result: result.reduced_field)
    fields = {"Mean energy (eV)": "mean_energy", "Mobility *N (1/m/V/s)": "mobility_N",
              "Diffusion coefficient *N (1/m/s)": "diffusion_N", "Energy mobility *N (1/m/V/s)": "energy_mobility_N",
              "Energy diffusion coef. D*N (1/m/s)": "energy_diffusion_N",
              "Momentum frequency /N (m3/s)": "momentum_frequency_N"}
    for header, name in fields.items():
        table = read_bolsig_section(text, header)
        np.testing.assert_array_equal(table[:, 0], [1.0, 12.0, 24.0])
        np.testing.assert_allclose(table[:, 1], [getattr(result, name) for result in ordered], rtol=1e-6)
    rates = read_bolsig_section(text, "Rate coefficient (m3/s)", before="C1   reid:excitation")
    np.testing.assert_allclose(rates[:, 1], [result.rate_coefficients["reid:excitation"] for result in ordered],
                               rtol=1e-6)
    assert "Gas temperature (K)\t0.000" in text.splitlines()
    monte_carlo_only = ("Longitud. diffusion coef. *N (1/m/s)", "Bulk mobility *N (1/m/V/s)",
                        "Bulk L diffusion coef. *N (1/m/s)", "Bulk T diffusion coef. *N (1/m/s)")
    assert [header for header in _sections(text) if header != "Rate coefficient (m3/s)"] == [
        header for header in BOLSIG_SECTIONS if header not in monte_carlo_only]


def test_a_swarm_of_the_maxwell_model_gives_its_exact_mobility_and_its_flux_diffusion():
    """Maxwell model (constant nu = N k): mu N = e / (m_r k) exactly (Wannier), within the run's errors; the
    diffusion sections are the flux D_T N and D_L N; alpha/N = k_ion / W is 0 (no ionization), written as 0."""
    gas = maxwell_model(1e-13, mass=4 * AMU)
    results = [simulate_swarm(gas, e_n, particles=4000, seed=2, tolerances={"mean_energy": 0.01}, gas_temperature=0.0)
               for e_n in (5.0, 20.0)]
    text = bolsig_tables(results)
    mobility = read_bolsig_section(text, "Mobility *N (1/m/V/s)")[:, 1]
    reduced_mass = constants.m_e * 4 * AMU / (constants.m_e + 4 * AMU)
    exact = constants.e / (reduced_mass * 1e-13)
    errors = [abs(float(r.drift_velocity_flux_error[2])) / (r.reduced_field * 1e-21) for r in results]
    assert np.all(np.abs(mobility - exact) < 4 * np.asarray(errors) + 1e-6 * exact), (mobility, exact, errors)
    assert max(errors) < 0.02 * exact  # the test tells a 10 % error in the mobility
    np.testing.assert_allclose(read_bolsig_section(text, "Diffusion coefficient *N (1/m/s)")[:, 1],
                               [r.diffusion_T_N_flux for r in results], rtol=1e-6)
    np.testing.assert_allclose(read_bolsig_section(text, "Longitud. diffusion coef. *N (1/m/s)")[:, 1],
                               [r.diffusion_L_N_flux for r in results], rtol=1e-6)
    np.testing.assert_array_equal(read_bolsig_section(text, "Townsend ioniz. coef. alpha/N (m2)"), [[5, 0], [20, 0]])
    assert text.splitlines()[0].startswith("collisionkit: Monte Carlo swarm")
    # the bulk sections hold the bulk coefficients; without ionization or attachment bulk and flux drift agree
    bulk = read_bolsig_section(text, "Bulk mobility *N (1/m/V/s)")[:, 1]
    np.testing.assert_allclose(bulk, [abs(r.drift_velocity_bulk[2]) / (r.reduced_field * 1e-21) for r in results],
                               rtol=1e-6)
    bulk_errors = [abs(float(r.drift_velocity_bulk_error[2])) / (r.reduced_field * 1e-21) for r in results]
    assert np.all(np.abs(bulk - exact) < 4 * np.hypot(bulk_errors, errors) + 1e-6 * exact), (bulk, exact)
    np.testing.assert_allclose(read_bolsig_section(text, "Bulk L diffusion coef. *N (1/m/s)")[:, 1],
                               [r.diffusion_L_N for r in results], rtol=1e-6)
    np.testing.assert_allclose(read_bolsig_section(text, "Bulk T diffusion coef. *N (1/m/s)")[:, 1],
                               [r.diffusion_T_N for r in results], rtol=1e-6)
    assert results[0].diffusion_L_N != results[0].diffusion_L_N_flux  # two estimators: the test tells them apart


def test_a_swarm_s_alpha_is_its_ionization_rate_over_its_flux_drift_so_alpha_times_w_is_the_rate():
    """BOLSIG+'s definition with temporal growth: alpha/N W = k_ion, with the mobility written beside it."""
    from collisionkit.transport import lucas_saelee

    result = simulate_swarm(lucas_saelee(), 500.0, particles=2000, seed=1, tolerances={"mean_energy": 0.05},
                            gas_temperature=0.0)
    text = bolsig_tables([result])
    alpha = read_bolsig_section(text, "Townsend ioniz. coef. alpha/N (m2)")[0, 1]
    mobility = read_bolsig_section(text, "Mobility *N (1/m/V/s)")[0, 1]
    assert result.ionization_frequency_N > 0
    assert alpha * mobility * 500.0 * 1e-21 == pytest.approx(result.ionization_frequency_N, rel=1e-5)


def test_the_reader_takes_bolsig_s_own_layout_and_names_a_missing_section():
    """BOLSIG+ pads some headers with spaces and its last section runs to the end of the file."""
    text = "BOLSIG+ version\n\nE/N (Td)      \tGrid type\n0.1\t0.0\n\nE/N (Td)\tMean energy (eV)\n0.1\t0.04\n0.2\t0.05"
    np.testing.assert_array_equal(read_bolsig_section(text, "Grid type"), [[0.1, 0.0]])
    np.testing.assert_array_equal(read_bolsig_section(text, "Mean energy (eV)"), [[0.1, 0.04], [0.2, 0.05]])
    with pytest.raises(ValueError, match=r"no section .*Mobility \*N \(1/m/V/s\).* in the text"):
        read_bolsig_section(text, "Mobility *N (1/m/V/s)")


def test_values_that_are_not_numbers_leave_their_lines_out():
    """The mobility at E/N = 0 is undefined: its section starts at the next E/N, the others keep E/N = 0."""
    results = [two_term_boltzmann(reid_ramp(), e_n, 300.0) for e_n in (0.0, 10.0)]
    results[0] = type(results[0])(**{**results[0].__dict__, "mobility_N": math.nan})
    text = bolsig_tables(results)
    np.testing.assert_array_equal(read_bolsig_section(text, "Mobility *N (1/m/V/s)")[:, 0], [10.0])
    np.testing.assert_array_equal(read_bolsig_section(text, "Mean energy (eV)")[:, 0], [0.0, 10.0])
    assert missing_rows(results) == {"Mobility *N (1/m/V/s)": [0.0]}


@pytest.mark.parametrize(
    ("results", "error", "match"),
    [
        ([], ValueError, "at least one E/N point"),
        (["12 Td"], TypeError, "must all be SwarmResult or all TwoTermResult"),
        ("mixed", TypeError, "must all be SwarmResult or all TwoTermResult"),
        ("temperatures", ValueError, "one gas temperature"),
        ("oscillating", ValueError, "oscillating field"),
    ],
)
def test_results_that_make_no_bolsig_table_are_refused(results, error, match):
    cases = {
        "mixed": lambda: [two_term_boltzmann(reid_ramp(), 12.0, 0.0),
                          simulate_swarm(maxwell_model(), 5.0, particles=256, groups=4, seed=1,
                                         tolerances={"mean_energy": 0.2})],
        "temperatures": lambda: [two_term_boltzmann(reid_ramp(), 12.0, 0.0), two_term_boltzmann(reid_ramp(), 12.0)],
        "oscillating": lambda: [two_term_boltzmann(reid_ramp(), 12.0, 0.0, omega_N=1e-16)],
    }
    with pytest.raises(error, match=match):
        bolsig_tables(cases[results]() if isinstance(results, str) else results)
