"""Checks of the DSMC reference solution of the uniform shear flow (tests/edmd/usf_dsmc.py) itself."""

import math

import pytest

from collisionkit import edmd
from tests.edmd.usf_dsmc import usf_dsmc


@pytest.mark.parametrize("dim", [3, 2])
def test_the_dsmc_reference_gives_chapman_enskogs_viscosity_in_the_elastic_limit(dim):
    """Elastic, thermostatted at kT = 1, a = 0.05 nu (nu the collision frequency): -P_xy / a is the
    Chapman-Enskog viscosity (with its higher Sonine orders), shear thinning O(a*^2) below 1 %; 4 sigma + 1 %."""
    density = 0.01
    frequency = density * math.sqrt(math.pi) * (4 if dim == 3 else 2)  # Enskog's omega at chi = 1, kT = m = 1
    _, _, viscosity, error = usf_dsmc(1.0, 0.05 * frequency, density, dim, particles=10_000, relax=10,
                                      measure=500, thermostat=True, seed=4)
    reference = edmd.chapman_enskog_transport(density, dim=dim)["shear_viscosity"]
    assert error < 0.015 * reference
    assert abs(viscosity / reference - 1) < 0.01 + 4 * error / reference


def test_the_dsmc_reference_is_steady_and_reproducible_with_its_seed():
    """The inelastic steady state does not depend on the start (kT from 1 or 4) within its errors, and a seed
    repeats a run bit for bit."""
    density = 0.01
    cold = usf_dsmc(0.8, 0.03, density, 3, particles=4_000, relax=40, measure=150, seed=2)
    again = usf_dsmc(0.8, 0.03, density, 3, particles=4_000, relax=40, measure=150, seed=2)
    hot = usf_dsmc(0.8, 0.03, density, 3, particles=4_000, relax=40, measure=150, seed=3, start_kT=4.0)
    assert cold == again
    assert abs(cold[0] - hot[0]) < 4 * math.hypot(cold[1], hot[1])
    assert abs(cold[2] - hot[2]) < 4 * math.hypot(cold[3], hot[3])
