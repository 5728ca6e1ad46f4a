"""Tests of collisionkit.edmd.theory: equations of state, Enskog's collision rate, packing fractions."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from collisionkit import edmd
from collisionkit.edmd import theory


@pytest.mark.parametrize("function", [edmd.carnahan_starling, edmd.hansen_goos, edmd.henderson])
@pytest.mark.parametrize(("eta", "error"), [(-0.1, ValueError), (1.0, ValueError), (1.5, ValueError),
                                            (2.0, ValueError), (math.nan, ValueError), ([0.2, 1.0], ValueError),
                                            (True, TypeError), ("0.3", TypeError)])
def test_equations_of_state_need_a_packing_fraction_in_0_1(function, eta, error):
    with pytest.raises(error, match="eta"):
        function(eta)


def test_equations_of_state_give_the_ideal_gas_at_zero_density():
    for function in (edmd.carnahan_starling, edmd.hansen_goos, edmd.henderson):
        assert function(0.0) == 1.0
        np.testing.assert_allclose(function([0.0, 1e-12]), 1.0, rtol=1e-10)


@pytest.mark.parametrize(
    ("arguments", "error", "name"),
    [
        (dict(diameter=0), ValueError, "diameter"),
        (dict(diameter=math.inf), ValueError, "diameter"),
        (dict(mass=-1), ValueError, "mass"),
        (dict(kT=math.nan), ValueError, "kT"),
        (dict(kT=True), TypeError, "kT"),
        (dict(compressibility=0.5), ValueError, "compressibility"),
        (dict(dim=5), ValueError, "dim"),
        (dict(dim=True), TypeError, "dim"),
    ],
)
def test_enskog_collision_frequency_checks_its_arguments(arguments, error, name):
    with pytest.raises(error, match=name):
        edmd.enskog_collision_frequency(**(dict(compressibility=2.0, dim=3) | arguments))


@pytest.mark.parametrize(
    ("radii", "box", "name"),
    [([-0.5], [1.0, 1.0], "radii"), ([0.5], [1.0, 1.0, 1.0, 1.0], "box"), ([0.5], [0.0, 1.0], "box"),
     ([0.5], 1.0, "box"), ([math.nan], [1.0, 1.0], "radii")],
)
def test_packing_fraction_checks_its_arguments(radii, box, name):
    with pytest.raises(ValueError, match=name):
        edmd.packing_fraction(radii, box)


def _taylor(function, order):
    """Taylor coefficients c_0..c_order of function(eta) at 0, from a least-squares fit on [1e-3, 0.02]."""
    eta = np.linspace(1e-3, 0.02, 60)
    return np.polyfit(eta, np.asarray(function(eta), dtype=float), order + 2)[::-1][: order + 1]


def test_equations_of_state_reproduce_the_exact_virial_coefficients():
    """Z = 1 + B2 eta + B3 eta^2 + ...: hard spheres B2 = 4, B3 = 10 exactly, B4 = 18.3648 (Boltzmann);
    Carnahan-Starling's are the integers n^2 + n - 2 (4, 10, 18). Hard discs: B2 = 2, B3 = 16/3 - 4 sqrt(3)/pi
    = 3.1280 exactly; Henderson gives 25/8. Kills: carnahan_starling -eta^3 -> +eta^3 (B4 = 20),
    hansen_goos (1 - eta)^3 -> (1 - eta)^2 (B2 = -5), henderson eta^2/8 -> eta^2/4 (B3 = 3.25)."""
    cs = _taylor(edmd.carnahan_starling, 4)
    np.testing.assert_allclose(cs[:4], [1.0, 4.0, 10.0, 18.0], rtol=1e-4)
    hg = _taylor(edmd.hansen_goos, 4)
    np.testing.assert_allclose(hg[:3], [1.0, 4.0, 10.0], rtol=1e-4)
    assert hg[3] == pytest.approx(18.3648, rel=1e-3)
    disc = _taylor(edmd.henderson, 3)
    np.testing.assert_allclose(disc[:2], [1.0, 2.0], rtol=1e-5)
    assert disc[2] == pytest.approx(16 / 3 - 4 * math.sqrt(3) / math.pi, rel=2e-3)
    # and the two hard-sphere equations agree within 0.3 % up to eta = 0.45 (both fit simulation data to that)
    eta = np.linspace(0.05, 0.45, 9)
    np.testing.assert_allclose(edmd.carnahan_starling(eta), edmd.hansen_goos(eta), rtol=3e-3)


@pytest.mark.parametrize(("dim", "diameter", "kT", "mass"), [(3, 1.0, 1.0, 1.0), (3, 2.0, 1.5, 3.0), (2, 0.5, 2.0, 0.7)])
def test_enskog_collision_frequency_is_the_kinetic_theory_rate(dim, diameter, kT, mass):
    """Independent derivation: omega = n <v_rel> S g, with <v_rel> = sqrt(2) <v> and the cross 'section'
    S = pi sigma^2 (3D) or 2 sigma (2D); the same g(sigma) gives Z - 1 = (2 pi / 3) n sigma^3 g (3D) or
    (pi / 2) n sigma^2 g (2D). Kills: 2 d / sigma -> d / sigma, sqrt(kT / (pi m)) -> sqrt(kT / (2 pi m))."""
    n, g = 0.37, 1.23
    mean_speed = math.sqrt(8 * kT / (math.pi * mass)) if dim == 3 else math.sqrt(math.pi * kT / (2 * mass))
    if dim == 3:
        z = 1 + 2 * math.pi / 3 * n * diameter**3 * g
        expected = n * math.sqrt(2) * mean_speed * math.pi * diameter**2 * g
    else:
        z = 1 + math.pi / 2 * n * diameter**2 * g
        expected = n * math.sqrt(2) * mean_speed * 2 * diameter * g
    got = float(edmd.enskog_collision_frequency(z, dim, diameter=diameter, kT=kT, mass=mass))
    assert got == pytest.approx(expected, rel=1e-12)


def test_the_packing_fraction_limits_are_defined_once():
    """MAX_PACKING_FRACTION is the one definition of the densest supported packing, per dimension."""
    assert edmd.MAX_PACKING_FRACTION is theory.MAX_PACKING_FRACTION
    assert edmd.MAX_PACKING_FRACTION == {2: 0.7, 3: 0.5}


def test_granular_shear_flow_limits_and_balances():
    """Grad's uniform shear flow: the elastic limit gives Chapman-Enskog's first-Sonine viscosity; the balances hold."""
    import math

    from collisionkit.edmd import granular_shear_flow

    for dim, first_sonine in ((3, 5 / (16 * math.sqrt(math.pi))), (2, 1 / (2 * math.sqrt(math.pi)))):
        nearly_elastic = granular_shear_flow(1 - 1e-9, 0.01, 0.05, dim)
        kT = nearly_elastic["temperature"]
        assert nearly_elastic["viscosity"] == pytest.approx(first_sonine * math.sqrt(kT), rel=1e-6)
        assert nearly_elastic["normal_stress_yy"] == pytest.approx(1.0, abs=1e-8)
        flow = granular_shear_flow(0.7, 0.2, 0.02, dim)
        # energy: viscous heating a eta a = cooling zeta p d / 2, with zeta = zeta* nu_0, nu_0 = p / eta_0(T)
        alpha, n, T = 0.7, 0.02, flow["temperature"]
        zeta = (dim + 2) * (1 - alpha**2) / (4 * dim) * n * T / (first_sonine * math.sqrt(T))
        assert 0.2 * flow["viscosity"] * 0.2 == pytest.approx(zeta * n * T * dim / 2, rel=1e-12)
        # the temperature scales as the square of the shear rate at fixed alpha and density
        assert granular_shear_flow(0.7, 0.4, 0.02, dim)["temperature"] == pytest.approx(4 * T, rel=1e-12)


def _enskog_coefficients(dim, eta):
    """The y^2 chi coefficients of eta_E / eta_0, lambda_E / lambda_0 and zeta_E / eta_0, y = b n, after
    subtracting 1/chi and the linear terms (0.8 y, 1.2 y for spheres; y, 1.5 y for discs)."""
    enskog = edmd.enskog_transport(eta, dim=dim)
    chi, y = enskog["contact_value"], (4.0 if dim == 3 else 2.0) * eta
    density = eta / (math.pi ** (dim / 2) / math.gamma(dim / 2 + 1) / 2**dim)
    dilute = edmd.chapman_enskog_transport(density, dim=dim)
    linear = {3: (0.8, 1.2), 2: (1.0, 1.5)}[dim]
    viscosity = (enskog["shear_viscosity"] / dilute["shear_viscosity"] - 1 / chi - linear[0] * y) / (y * y * chi)
    conductivity = (enskog["thermal_conductivity"] / dilute["thermal_conductivity"] - 1 / chi - linear[1] * y) / (
        y * y * chi)
    return viscosity, conductivity, enskog["bulk_viscosity"] / dilute["shear_viscosity"] / (y * y * chi)


@pytest.mark.parametrize("eta", [0.05, 0.2, 0.4])
def test_enskog_transport_of_spheres_has_chapman_and_cowlings_coefficients(eta):
    """Chapman & Cowling sec. 16.5: 0.761 and 0.757 (their rounding) and 1.002 for the bulk viscosity."""
    viscosity, conductivity, bulk = _enskog_coefficients(3, eta)
    assert viscosity == pytest.approx(0.761, abs=6e-4)
    assert conductivity == pytest.approx(0.757, abs=6e-4)
    assert bulk == pytest.approx(1.002, abs=6e-4)


@pytest.mark.parametrize("eta", [0.05, 0.3, 0.6])
def test_enskog_transport_of_discs_has_gass_coefficients(eta):
    """Gass, J. Chem. Phys. 54, 1898 (1971): 1/chi + y + 0.8729 y^2 chi and 1/chi + 1.5 y + 0.8718 y^2 chi."""
    viscosity, conductivity, _ = _enskog_coefficients(2, eta)
    assert viscosity == pytest.approx(0.8729, abs=6e-5)
    assert conductivity == pytest.approx(0.8718, abs=6e-5)


def test_enskogs_bulk_viscosity_is_its_closed_form():
    """zeta_E = (4/9) n^2 sigma^4 chi sqrt(pi m kT) for spheres (Chapman & Cowling sec. 16.41), exact (no
    Sonine order); in d dimensions the collisional integral gives, for discs,
    zeta_E = (1/2) sqrt(pi) n^2 sigma^3 chi sqrt(m kT)."""
    for dim, eta, diameter, mass, kT in ((3, 0.3, 1.3, 2.0, 0.7), (2, 0.4, 0.8, 0.5, 3.0)):
        enskog = edmd.enskog_transport(eta, diameter=diameter, mass=mass, kT=kT, dim=dim)
        ball = math.pi ** (dim / 2) / math.gamma(dim / 2 + 1) * (diameter / 2) ** dim
        n, chi = eta / ball, enskog["contact_value"]
        prefactor = 4 / 9 * math.sqrt(math.pi) * diameter**4 if dim == 3 else 0.5 * math.sqrt(math.pi) * diameter**3
        assert enskog["bulk_viscosity"] == pytest.approx(prefactor * n * n * chi * math.sqrt(mass * kT), rel=1e-12)


@pytest.mark.parametrize("dim", [2, 3])
def test_enskog_transport_tends_to_the_dilute_gas_and_scales_with_the_units(dim):
    """eta -> 0: chi -> 1 and the collisional transfer vanishes; viscosity ~ sqrt(m kT) / sigma^(d-1),
    conductivity ~ sqrt(kT / m) / sigma^(d-1), D ~ sqrt(kT / m) sigma (at fixed packing fraction)."""
    eta = 1e-9
    density = eta / (math.pi ** (dim / 2) / math.gamma(dim / 2 + 1) / 2**dim)
    enskog, dilute = edmd.enskog_transport(eta, dim=dim), edmd.chapman_enskog_transport(density, dim=dim)
    for key in ("shear_viscosity", "thermal_conductivity", "self_diffusion"):
        assert enskog[key] == pytest.approx(dilute[key], rel=1e-7), key
    scaled = edmd.enskog_transport(0.3, diameter=2.0, mass=3.0, kT=5.0, dim=dim)
    unit = edmd.enskog_transport(0.3, dim=dim)
    assert scaled["shear_viscosity"] == pytest.approx(unit["shear_viscosity"] * math.sqrt(15) / 2 ** (dim - 1))
    assert scaled["thermal_conductivity"] == pytest.approx(
        unit["thermal_conductivity"] * math.sqrt(5 / 3) / 2 ** (dim - 1))
    assert scaled["self_diffusion"] == pytest.approx(unit["self_diffusion"] * math.sqrt(5 / 3) * 2)


def test_chapman_enskog_for_discs_is_gass_first_sonine_times_his_factors():
    """eta_0 = 1.022 / (2 sigma) sqrt(m kT / pi), lambda_0 = 1.029 (2 / sigma) sqrt(kT / (pi m)),
    D_0 = 1 / (2 n sigma) sqrt(kT / (pi m))."""
    dilute = edmd.chapman_enskog_transport(0.2, diameter=1.5, mass=2.0, kT=3.0, dim=2)
    assert dilute["shear_viscosity"] == pytest.approx(1.022 / 3.0 * math.sqrt(6.0 / math.pi), rel=1e-12)
    assert dilute["thermal_conductivity"] == pytest.approx(1.029 * 2 / 1.5 * math.sqrt(1.5 / math.pi), rel=1e-12)
    assert dilute["self_diffusion"] == pytest.approx(1 / (0.6) * math.sqrt(1.5 / math.pi), rel=1e-12)


@pytest.mark.parametrize(("arguments", "name"), [({"eta": 0.6, "dim": 3}, "eta"), ({"eta": 0.8, "dim": 2}, "eta"),
                                                 ({"eta": 0.3, "dim": 4}, "dim"), ({"eta": 0.3, "kT": 0.0}, "kT")])
def test_enskog_transport_checks_its_arguments(arguments, name):
    with pytest.raises(ValueError, match=name):
        edmd.enskog_transport(**arguments)


@pytest.mark.parametrize("dim", [2, 3])
def test_the_transport_theories_take_arrays_as_the_equations_of_state_do(dim):
    # each element as the scalar call gives it; kT broadcast against eta; a float for scalars
    eta = np.array([0.05, 0.2, 0.4])
    kT = np.array([[1.0], [2.0]])
    curves = edmd.enskog_transport(eta, kT=kT, dim=dim)
    dilute = edmd.chapman_enskog_transport(eta, kT=kT, dim=dim)
    for key in ("shear_viscosity", "bulk_viscosity", "thermal_conductivity", "self_diffusion"):
        assert curves[key].shape == (2, 3) and dilute[key].shape == (2, 3)
        for i, temperature in enumerate(kT[:, 0]):
            for j, value in enumerate(eta):
                assert curves[key][i, j] == edmd.enskog_transport(float(value), kT=temperature, dim=dim)[key]
                assert dilute[key][i, j] == edmd.chapman_enskog_transport(float(value), kT=temperature,
                                                                          dim=dim)[key]
    assert isinstance(edmd.enskog_transport(0.2, dim=dim)["shear_viscosity"], float)
    with pytest.raises(ValueError, match=r"the inputs' shapes \[\(3,\), \(2,\), \(\), \(\)\] do not broadcast"):
        edmd.enskog_transport(eta, diameter=[1.0, 2.0], dim=dim)
    with pytest.raises(ValueError, match="eta"):
        edmd.enskog_transport([0.2, 0.95], dim=dim)


@given(alpha=st.floats(0.0, 1.0))
@settings(max_examples=50, deadline=None)
def test_the_cooling_state_a2_of_spheres_is_brilliantov_and_poschels(alpha):
    """van Noije and Ernst's a2 for any d at d = 3 against Brilliantov and Poschel's sphere formula."""
    spheres = 16 * (1 - alpha) * (1 - 2 * alpha**2) / (81 - 17 * alpha + 30 * alpha**2 * (1 - alpha))
    assert float(edmd.cooling_state_a2(alpha, 3)) == pytest.approx(spheres, abs=1e-15)


def test_the_cooling_state_a2_vanishes_when_elastic_and_at_one_over_root_two_and_checks_its_arguments():
    np.testing.assert_allclose(edmd.cooling_state_a2([1.0, 2**-0.5], 2), 0.0, atol=1e-15)
    assert edmd.cooling_state_a2(0.9, 2) < 0 < edmd.cooling_state_a2(0.5, 2)  # sign changes at 1/sqrt 2
    with pytest.raises(ValueError, match="restitution"):
        edmd.cooling_state_a2(1.5)
    with pytest.raises(ValueError, match="dim"):
        edmd.cooling_state_a2(0.9, 4)
