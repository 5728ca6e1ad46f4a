"""Reid's ramp at 12 Td in crossed fields against LoKI-MC: mean energy, drift components and the diffusion tensor
with the Hall term, and the flux tensor against the bulk tensor (the ramp conserves the number of electrons).

Reference: tests/data/dias2023_fig2_reid_crossed.txt, LoKI-MC's markers read off the vector art of Fig. 2 of Dias
et al., Plasma Sources Sci. Technol. 32, 095003 (2023) (provenance, method, read-off uncertainty and the frame
conversion in its header). Frame: E along +z, B along +y (psi = 90 deg), E x B along -x.
"""

import functools
from pathlib import Path

import numpy as np
import pytest

from collisionkit.transport import reid_ramp, simulate_swarm

DATA = Path(__file__).parent.parent / "data" / "dias2023_fig2_reid_crossed.txt"
LOKI_MC = {row[0]: row[1:] for row in np.loadtxt(DATA)}
# LoKI-MC's own scatter, relative, measured by the B = 0 row against its published B = 0 values (file header):
# 0.06 % in <e>, 0.01 % in W (+ 12 m/s, the reading of a zero), 0.6 % in N D (+ 4.9e20, the Hall term's zero);
# then the read-off (0.001 pt of the PDF: 2e-6 eV, 0.7 m/s, 1.3e19 /(m s))
SCATTER = {"energy": (6e-4, 2e-6), "drift": (1e-4, 12.0 + 0.7), "diffusion": (6e-3, 4.9e20 + 1.3e19)}
SIGMAS = 4.0


@functools.cache
def _reids_ramp(b_over_n):
    """One run per B/N shared by the tests of this file (about 4e7 collisions, 20 s on two threads)."""
    return simulate_swarm(reid_ramp(), 12.0, reduced_magnetic_field=b_over_n, gas_temperature=0.0, particles=24000,
                          seed=20, threads=2, tolerances={"mean_energy": 1e-5}, collision_budget=4e7)


def _agrees(value, error, expected, kind):
    relative, absolute = SCATTER[kind]
    return abs(value - expected) <= SIGMAS * error + relative * abs(expected) + absolute


@pytest.mark.slow
@pytest.mark.parametrize("b_over_n", [50.0, 200.0, 500.0])
def test_reids_ramp_in_crossed_fields_matches_loki_mc(b_over_n):
    """<e>, W along E and E x B, N D along E, E x B and B, and N D_Hall = -2 D_zx against LoKI-MC: tolerance 4
    standard errors + LoKI-MC's scatter + the read-off. Measured (seed 20, 4e7 collisions, 12-18 s): within 1.6
    sigma but <e> at 500 Hx (+2.7 sigma, +0.14 %); with 20000 particles and 2-3e8 collisions the audit of issue 20
    found <e> at 50 Hx 0.26154 +- 0.00005 (LoKI-MC 0.26154). The mirror symmetry in the plane normal to B: no
    drift along B, D_xy = D_yz = 0."""
    energy, w_e, w_exb, d_e, d_exb, d_b, hall = LOKI_MC[b_over_n]
    r = _reids_ramp(b_over_n)
    w, w_error = r.drift_velocity_bulk, r.drift_velocity_bulk_error
    d, d_error = r.diffusion_N_bulk, r.diffusion_N_bulk_error
    # the run resolves what it checks: <e> to 0.1 %, the drift components to 0.5 %, N D to 3 %, the Hall term to 10 %
    # at 50 and 200 Hx (where it is a fifth of N D_B) and to 30 % at 500 Hx (a 150th)
    assert r.mean_energy_error < 1e-3 * energy
    assert np.all(w_error[[0, 2]] < 5e-3 * np.array([w_exb, w_e]))
    assert np.all(np.diag(d_error) < 0.03 * np.array([d_exb, d_b, d_e]))
    assert 2 * d_error[2, 0] < (0.1 if b_over_n < 500 else 0.3) * hall

    assert _agrees(r.mean_energy, r.mean_energy_error, energy, "energy")
    assert _agrees(-w[2], w_error[2], w_e, "drift")  # electrons drift against E
    assert _agrees(-w[0], w_error[0], w_exb, "drift")  # and along E x B (-x)
    assert abs(w[1]) <= SIGMAS * w_error[1]  # nothing along B
    for value, error, expected in [(d[2, 2], d_error[2, 2], d_e), (d[0, 0], d_error[0, 0], d_exb),
                                   (d[1, 1], d_error[1, 1], d_b), (-2 * d[2, 0], 2 * d_error[2, 0], hall)]:
        assert _agrees(value, error, expected, "diffusion")
    assert abs(d[0, 1]) <= SIGMAS * d_error[0, 1] and abs(d[1, 2]) <= SIGMAS * d_error[1, 2]


@pytest.mark.slow
@pytest.mark.parametrize("b_over_n", [50.0, 200.0, 500.0])
def test_flux_and_bulk_agree_when_the_number_of_electrons_is_conserved(b_over_n):
    """Reid's ramp has no ionization or attachment, so the flux and bulk drift velocities and diffusion tensors are
    the same (as Dias et al. 2023 note with their Fig. 2). The two estimators differ (d<r>/dt and d cov(r)/dt
    against <v> and <r v> - <r><v>) and each has its error: all 9 tensor elements and 3 drift components agree
    within 4 combined standard errors. The flux estimator is the noisier (measured errors of its diagonal 4-10 %
    at 50 and 200 Hx, up to 38 % at 500 Hx, against 1-2 % for the bulk one): the run must resolve the flux N D_B
    to 6 % and, at 50 and 200 Hx, the flux Hall element (-2 D_zx) to 3 sigma, so that the check is not empty."""
    r = _reids_ramp(b_over_n)
    flux, flux_error = r.diffusion_N_flux, r.diffusion_N_flux_error
    bulk, bulk_error = r.diffusion_N_bulk, r.diffusion_N_bulk_error
    np.testing.assert_array_less(np.abs(flux - bulk), SIGMAS * np.hypot(flux_error, bulk_error))
    w_flux, w_bulk = r.drift_velocity_flux, r.drift_velocity_bulk
    np.testing.assert_array_less(np.abs(w_flux - w_bulk),
                                 SIGMAS * np.hypot(r.drift_velocity_flux_error, r.drift_velocity_bulk_error))
    assert flux_error[1, 1] < 0.06 * flux[1, 1]
    if b_over_n < 500:
        assert abs(flux[2, 0]) > 3 * flux_error[2, 0]
