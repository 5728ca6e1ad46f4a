"""Angular scattering laws: the closed-form <cos chi> of each law against numerical integration of the distribution
the kernels sample, the sampled cosines against the analytic densities, and the momentum-transfer conversion."""

import math

import numpy as np
import pytest
from scipy import constants, integrate

from collisionkit._kernels.transport import FORWARD, ISOTROPIC, OKHRIMOVSKYY, SCREENED_COULOMB, VAHEDI_SURENDRA
from collisionkit._kernels.transport.rng import seed_state
from collisionkit._kernels.transport.scattering import cosine_from_uniform, scattering_cosine
from collisionkit.transport import mean_scattering_cosine, momentum_transfer_ratio
from collisionkit.transport.angular import HARTREE_EV, okhrimovskyy_parameter, scattering_cosine_from_uniform

EV = constants.e
CODES = {"isotropic": ISOTROPIC, "okhrimovskyy": OKHRIMOVSKYY, "vahedi-surendra": VAHEDI_SURENDRA,
         "forward": FORWARD, "screened_coulomb": SCREENED_COULOMB}
LAWS = ["isotropic", "okhrimovskyy", "vahedi-surendra", "forward", "screened_coulomb"]
ENERGIES = [1e-5, 0.05, 1.0, 7.0, 50.0, 800.0]  # eV: both sides of the small-energy series


def _kernel_cosine(law, energy_ev, u, screening_ev=1.0):
    return cosine_from_uniform(CODES[law], energy_ev * EV, screening_ev * EV, u)


@pytest.mark.parametrize("law", LAWS)
@pytest.mark.parametrize("energy", ENERGIES)
def test_the_closed_form_mean_cosine_is_the_integral_of_the_sampled_distribution(law, energy):
    """<cos chi> = int_0^1 cos chi(u) du: the kernel's inverse CDF integrated over its uniform number (quad),
    against the closed forms of collisionkit.transport.angular (1e-10 absolute: Wentzel's inversion loses ~1e-11 a
    sample to cancellation at 1e-5 eV, where eta = 25 000)."""
    sampled, _ = integrate.quad(lambda u: _kernel_cosine(law, energy, u), 0.0, 1.0, epsabs=1e-13, epsrel=1e-11,
                                limit=200)
    assert float(mean_scattering_cosine(law, energy)) == pytest.approx(sampled, rel=1e-8, abs=1e-10)


@pytest.mark.parametrize("law", ["okhrimovskyy", "vahedi-surendra", "screened_coulomb"])
@pytest.mark.parametrize("energy", [0.3, 5.0, 100.0])
def test_the_sampled_cosines_follow_the_published_densities(law, energy):
    """P(cos chi > c(u)) = u (screened Coulomb: P(cos chi < c(u)) = u): each paper's density integrated (quad) from
    the kernel's cosine c(u).

    Okhrimovskyy et al. (2002): p(mu) = (1 - xi^2) / (2 (1 - xi mu)^2); Vahedi & Surendra (1995):
    1 - mu has the density (e/2) / ((1 + e (1 - mu)/2) ln(1 + e)) on [0, 2] (e in eV); Wentzel's screened
    Coulomb law (Z. Phys. 40, 590 (1927); collisionkit.transport.angular): p(mu) = 2 eta (1 + eta) /
    (1 + 2 eta - mu)^2, eta = e_s / (4 e), here with e_s = 1 eV (eta = 0.83, 0.05, 0.0025), whose inversion
    runs the other way (u -> 0 is backscattering, c(0) = -1), so there P(cos chi < c(u)) = u. Tolerance
    1e-9 relative: quad's accuracy, not statistics (no sampling). Can fail (scratch copy): eta 1 % larger in the
    density gives 0.01005-0.01010 for u = 0.01, the kernel's cosine at twice the screening energy (eta =
    e_s / (2 e)) 0.005-0.007, and c(1 - u) (the inversion's orientation) 0.99."""
    peak = []  # where quad should look: the screened Coulomb density is a peak eta wide at mu = 1
    if law == "okhrimovskyy":
        xi = float(okhrimovskyy_parameter(energy))

        def density(mu):
            return (1 - xi**2) / (2 * (1 - xi * mu) ** 2)
    elif law == "vahedi-surendra":
        def density(mu):
            return (energy / 2) / ((1 + energy * (1 - mu) / 2) * math.log1p(energy))
    else:
        eta = 1.0 / (4 * energy)  # the screening energy of _kernel_cosine, 1 eV

        def density(mu):
            return 2 * eta * (1 + eta) / (1 + 2 * eta - mu) ** 2
        peak = [max(-0.5, 1 - 10 * eta)]
    total, _ = integrate.quad(density, -1.0, 1.0, points=peak or None, limit=200)
    assert total == pytest.approx(1.0, rel=1e-10)
    for u in (0.01, 0.2, 0.5, 0.77, 0.99):
        c = _kernel_cosine(law, energy, u)
        if law == "screened_coulomb":
            below, _ = integrate.quad(density, -1.0, c, points=[x for x in peak if x < c] or None, epsabs=1e-13,
                                      limit=200)
            assert below == pytest.approx(u, rel=1e-9)
        else:
            above, _ = integrate.quad(density, c, 1.0, epsabs=1e-13)
            assert above == pytest.approx(u, rel=1e-9)


@pytest.mark.parametrize("law", LAWS)
def test_the_kernel_sampler_averages_to_the_closed_form(law):
    """200 000 draws of the kernel's random sampler: the mean cosine within 5 standard errors (and the numpy
    mirror of the inversion gives the kernel's numbers)."""
    state = np.zeros(4, np.uint64)
    seed_state(np.uint64(7), state)
    energy = 10.0
    draws = np.array([scattering_cosine(CODES[law], energy * EV, 1.0 * EV, state) for _ in range(200_000)])
    expected = float(mean_scattering_cosine(law, energy))
    error = max(draws.std(), 1e-300) / math.sqrt(draws.size)
    assert abs(draws.mean() - expected) <= 5 * error + 1e-15
    assert np.all(np.abs(draws) <= 1.0)
    u = np.linspace(0.001, 0.999, 37)
    mirrored = scattering_cosine_from_uniform(law, energy, u)
    np.testing.assert_allclose(mirrored, [_kernel_cosine(law, energy, x) for x in u], rtol=1e-12, atol=1e-12)


def test_the_laws_have_their_published_limits():
    # isotropic at zero energy; Okhrimovskyy xi = 1/2 at E_h/4: <cos> = 2 - 3 artanh(1/2) = 0.352082...
    for law in ("okhrimovskyy", "vahedi-surendra"):
        assert float(mean_scattering_cosine(law, 0.0)) == 0.0
    assert float(mean_scattering_cosine("okhrimovskyy", HARTREE_EV / 4)) == pytest.approx(2 - 3 * math.atanh(0.5))
    # Vahedi-Surendra at 1 eV: 1 - 2 (1 - ln 2) / ln 2
    vahedi = 1 - 2 * (1 - math.log(2)) / math.log(2)
    assert float(mean_scattering_cosine("vahedi-surendra", 1.0)) == pytest.approx(vahedi)
    # the series and the closed forms meet where they switch (1e-4)
    for law in ("okhrimovskyy", "vahedi-surendra"):
        switch = 1e-4 if law == "vahedi-surendra" else 1e-4 * HARTREE_EV / (4 * (1 - 1e-4))
        below, above = mean_scattering_cosine(law, [switch * (1 - 1e-9), switch * (1 + 1e-9)])
        assert above == pytest.approx(below, rel=1e-7)
    np.testing.assert_array_equal(momentum_transfer_ratio("forward", [0.0, 3.0]), [0.0, 0.0])


def test_an_unknown_law_or_energy_is_refused():
    with pytest.raises(ValueError, match="law must be one of"):
        mean_scattering_cosine("sideways", 1.0)
    with pytest.raises(ValueError, match="energy"):
        mean_scattering_cosine("okhrimovskyy", -1.0)
    with pytest.raises(ValueError, match="law must be one of"):
        scattering_cosine_from_uniform("sideways", 1.0, 0.5)


# ------------------------------------------------------------------ swarms: the momentum-transfer conversion

ME = constants.m_e
MAXWELL_RATE = 1e-13  # m^3/s: the momentum-transfer frequency N k of the Maxwell model


def _maxwell_run(law):
    from collisionkit.transport import maxwell_model, simulate_swarm

    gas = maxwell_model(MAXWELL_RATE, mass=10 * ME)
    if law != "isotropic":
        gas = gas.with_scattering(law)
    return simulate_swarm(gas, 200.0, gas_temperature=0.0, particles=4000, seed=11, threads=2,
                          tolerances={"mean_energy": 2e-3, "drift_velocity_bulk": 2e-3})


@pytest.fixture(scope="module")
def isotropic_maxwell():
    return _maxwell_run("isotropic")


@pytest.mark.parametrize("law", ["okhrimovskyy", "vahedi-surendra"])
def test_in_a_maxwell_gas_the_angular_law_changes_neither_drift_nor_mean_energy(law, isotropic_maxwell):
    """A constant momentum-transfer frequency fixes W = qE/(mu nu_m) and <e> = 1/2 (m + M) W^2 for any angular
    law (Wannier): the law's total cross section sigma_m / (1 - <cos chi>) must be sampled for that. At 200 Td on
    targets of 10 m_e, <e> = 4.7 eV, where <cos chi> is about 0.3: without the conversion W would be 40 % off.
    Each law against the exact values (4 standard errors) and against the isotropic run (4 combined errors); the
    elastic rate it counts is the integral one, above nu_m / N."""
    run = _maxwell_run(law)
    mu = ME * 10 * ME / (11 * ME)
    exact_w = -constants.e * 200e-21 * 1e24 / (mu * MAXWELL_RATE * 1e24)
    exact_energy = 0.5 * 11 * ME * exact_w**2 / constants.e
    assert run.converged and run.relative_error("drift_velocity_bulk") < 2e-3
    for r in (run, isotropic_maxwell):
        assert abs(r.drift_velocity_bulk[2] - exact_w) < 4 * r.drift_velocity_bulk_error[2]
        assert abs(r.drift_velocity_flux[2] - exact_w) < 4 * r.drift_velocity_flux_error[2]
        assert abs(r.mean_energy - exact_energy) < 4 * r.mean_energy_error
    combined = math.hypot(run.drift_velocity_bulk_error[2], isotropic_maxwell.drift_velocity_bulk_error[2])
    assert abs(run.drift_velocity_bulk[2] - isotropic_maxwell.drift_velocity_bulk[2]) < 4 * combined
    combined = math.hypot(run.mean_energy_error, isotropic_maxwell.mean_energy_error)
    assert abs(run.mean_energy - isotropic_maxwell.mean_energy) < 4 * combined
    counted = run.rate_coefficients["maxwell:elastic"]
    assert counted > 1.2 * MAXWELL_RATE and isotropic_maxwell.rate_coefficients["maxwell:elastic"] == pytest.approx(
        MAXWELL_RATE, rel=5e-3)


def test_an_elastic_table_cannot_be_scattered_forward_and_the_gas_says_why():
    from collisionkit.transport import reid_ramp

    with pytest.raises(ValueError, match="forward scattering transfers no momentum"):
        reid_ramp().with_scattering("forward")
    gas = reid_ramp().with_scattering({"excitation": "forward", "superelastic": "vahedi-surendra"})
    assert [p.scattering for p in gas.species[0].processes] == ["isotropic", "forward"]
    assert gas.species[0].processes[1].superelastic_scattering == "vahedi-surendra"
    with pytest.raises(ValueError, match="kind must be one of elastic"):
        reid_ramp().with_scattering({"rotation": "forward"})


def test_converted_elastic_tables_are_the_momentum_transfer_table_over_one_minus_the_mean_cosine():
    """The kernel's column for an anisotropic elastic table (and the rate it gives a rate coefficient), at energies
    between the nodes, against sigma_m / (1 - <cos chi>) within the refinement tolerance."""
    from collisionkit.transport import Gas, Process, Species
    from collisionkit.transport._tables import CURVE_RTOL, build_tables

    sigma_m = Process("elastic", [0.0, 1.0, 30.0, 200.0], [8e-20, 2e-20, 5e-20, 1e-20], rate_coefficient=1e-14,
                      scattering="okhrimovskyy")
    tables = build_tables(Gas((Species("x", 1e-25, (sigma_m,)),)), ME, 0.0)
    energies = np.linspace(0.01, 400.0, 7919)
    speed = np.sqrt(2 * energies * EV / ME)
    rate = np.interp(energies * EV, tables.nodes, tables.sigma[:, 0]) * speed + tables.const_rate[0]
    exact = (sigma_m.cross_section_at(energies) * speed + 1e-14) / momentum_transfer_ratio("okhrimovskyy", energies)
    np.testing.assert_allclose(rate, exact, rtol=2 * CURVE_RTOL)
