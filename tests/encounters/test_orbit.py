"""Two-body orbits: the closed forms of validation-data.md, the constructors and their checks.

Independent routes: the closed forms of validation-data.md ("Two-body
encounters") and of Rutherford scattering (:mod:`collisionkit.scattering`);
the invariants of the state an orbit is built from; exact arithmetic
(``decimal``) for the energy of a state.
"""

from __future__ import annotations

import decimal
import math

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from collisionkit import scattering
from collisionkit.encounters import Hyperbolic, TwoBodyOrbit, focusing_cross_section, unit_system
from tests.encounters.reference import distances, log_uniform, masses, relative_error, specific_invariants, speeds


# --------------------------------------------------------- validation-data.md


@given(m1=masses, m2=masses, rp=distances, v_inf=speeds)
def test_reference_formulas_for_gravity(m1, m2, rp, v_inf):
    """validation-data.md: b, e (two forms), deflection (two forms), a."""
    orbit = Hyperbolic(m1, m2, periastron=rp, v_inf=v_inf, G=1.0)
    mu_g = m1 + m2
    b = math.sqrt(rp**2 + 2 * mu_g * rp / v_inf**2)
    e = 1 + rp * v_inf**2 / mu_g
    assert orbit.impact_parameter == pytest.approx(b, rel=1e-14, abs=0)
    assert orbit.eccentricity == pytest.approx(e, rel=1e-14, abs=0)
    assert orbit.eccentricity == pytest.approx(math.sqrt(1 + b**2 * v_inf**4 / mu_g**2), rel=1e-10, abs=0)
    assert orbit.deflection_angle == pytest.approx(2 * math.atan(mu_g / (b * v_inf**2)), rel=1e-14, abs=0)
    assert orbit.deflection_angle == pytest.approx(2 * math.asin(1 / e), rel=1e-7, abs=1e-15)
    assert orbit.semi_major_axis == pytest.approx(-mu_g / v_inf**2, rel=1e-14, abs=0)


@pytest.mark.parametrize("k", [2.0, -2.0])
def test_rutherford_for_coulomb_orbits(k):
    """validation-data.md: tan(chi/2) = |k| / (mu v^2 b), dsigma/dOmega = (k/(2 mu v^2))^2 / sin^4(chi/2)."""
    m1, m2, v = 1.0, 3.0, 2.0
    mu = m1 * m2 / (m1 + m2)
    orbit = Hyperbolic.from_impact_parameter(m1, m2, 0.7, v, k=k)
    assert orbit.attractive is (k < 0)
    assert orbit.impact_parameter == pytest.approx(0.7, rel=1e-14, abs=0)
    chi = orbit.deflection_angle
    assert math.tan(chi / 2) == pytest.approx(abs(k) / (mu * v**2 * 0.7), rel=1e-14, abs=0)
    assert float(orbit.differential_cross_section(1.0)) == pytest.approx(
        (k / (2 * mu * v**2)) ** 2 / math.sin(0.5) ** 4, rel=1e-14
    )
    closest = float(scattering.coulomb_closest_approach(0.7, k, mu, v))
    assert orbit.periastron == pytest.approx(closest, rel=1e-15, abs=0)
    # energy at periastron: v_p^2 / 2 + (k / mu) / r_p = v^2 / 2
    assert 0.5 * orbit.periastron_speed**2 + k / mu / orbit.periastron == pytest.approx(0.5 * v**2, rel=1e-14, abs=0)


def test_repulsive_head_on_is_radial():
    orbit = Hyperbolic.from_impact_parameter(1.0, 1.0, 0.0, 1.0, k=1.0)
    assert orbit.periastron == pytest.approx(4.0, rel=1e-15, abs=0)  # 2 k / (mu v^2)
    assert orbit.deflection_angle == pytest.approx(math.pi, rel=1e-15, abs=0)
    r, v = orbit.relative_state_at_time(np.array([-3.0, 0.0, 5.0]))
    assert np.allclose(r[:, 1:], 0.0) and np.all(r[:, 0] >= 4.0)
    assert v[1] == pytest.approx([0.0, 0.0, 0.0], abs=1e-15)
    assert np.sign(v[0, 0]) == -1 and np.sign(v[2, 0]) == 1  # comes in along x, goes back out
    energy = 0.5 * np.sum(v * v, axis=1) + 2.0 / np.linalg.norm(r, axis=1)
    assert energy == pytest.approx(0.5, rel=1e-14, abs=0)


@pytest.mark.parametrize("b", [1e-8, 1e-6, 1e-4, 1e-2])
def test_near_head_on_repulsion_keeps_the_impact_parameter(b):
    # h^2 = r_p (mu_K + q) = r_p |mu_K| (e - 1) cancels as e -> 1: 9e-4 relative error at b = 1e-6 when
    # h came from r_p; from b v (or |r x v| of a state) it keeps every digit
    m1, m2, v, k = 1.0, 1.0, 1.0, 1.0
    mu = m1 * m2 / (m1 + m2)
    orbit = Hyperbolic.from_impact_parameter(m1, m2, b, v, k=k)
    assert orbit.impact_parameter == pytest.approx(b, rel=4e-16, abs=0)
    assert orbit.angular_momentum == pytest.approx(mu * b * v, rel=4e-16, abs=0)
    assert orbit.deflection_angle == pytest.approx(2 * math.atan(k / (mu * v**2 * b)), rel=4e-16, abs=0)
    far = 1e3
    state = TwoBodyOrbit.from_state(m1, m2, [-far, b], [v, 0.0], k=k)
    v_inf = math.sqrt(v**2 + 2 * (k / mu) / math.hypot(far, b))  # energy: v^2 / 2 + (k / mu) / r
    assert state.impact_parameter == pytest.approx(b * v / v_inf, rel=1e-15, abs=0)


def test_gravity_and_coulomb_add():
    """V = (k - G m1 m2) / r: gravity cancelled by an equal repulsion leaves no force."""
    with pytest.raises(ValueError, match="vanishes"):
        Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0, G=2.0, k=2.0)
    both = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0, G=2.0, k=1.0)
    assert both.kepler_parameter == pytest.approx(2.0 * 2.0 - 1.0 / 0.5)
    assert both.coulomb_strength == pytest.approx(1.0 - 2.0)


# --------------------------------------------------------------- constructors


@given(
    m1=masses, m2=masses,
    r=st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)).filter(lambda p: np.linalg.norm(p) > 0.1),
    v=st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)),
    length=distances, speed_ratio=log_uniform(-2, 2),
)  # fmt: skip
def test_from_state_round_trip(m1, m2, r, v, length, speed_ratio):
    r_vec = np.array(r) * length
    mu_k = m1 + m2
    circular = math.sqrt(mu_k / np.linalg.norm(r_vec))
    v_vec = np.array(v)
    assume(np.linalg.norm(np.cross(r_vec / np.linalg.norm(r_vec), v_vec)) > 1e-3 * np.linalg.norm(v_vec))
    v_vec = v_vec / np.linalg.norm(v_vec) * circular * speed_ratio
    orbit = TwoBodyOrbit.from_state(m1, m2, r_vec, v_vec)
    assert isinstance(orbit, Hyperbolic) == (orbit.kind == "hyperbolic")
    energy, h, lrl, _ = specific_invariants(mu_k, r_vec, v_vec)
    assert orbit.specific_energy == pytest.approx(energy, rel=1e-12, abs=1e-12 * circular**2)
    assert orbit.specific_angular_momentum == pytest.approx(np.linalg.norm(h), rel=1e-12, abs=0)
    assert orbit.eccentricity == pytest.approx(np.linalg.norm(lrl), rel=1e-8, abs=1e-8)
    t = orbit.time_since_periastron(r_vec, v_vec)
    r_back, v_back = orbit.relative_state_at_time(t)
    assert relative_error(r_back, r_vec) < 1e-8
    assert relative_error(v_back, v_vec) < 1e-8


def _exact_specific_energy(mu_k, r_vec, v_vec):
    """v^2/2 - mu_K/r of float vectors, evaluated to 40 digits (no cancellation of its own)."""
    with decimal.localcontext() as context:
        context.prec = 40
        r2 = sum(decimal.Decimal(float(x)) ** 2 for x in r_vec)
        v2 = sum(decimal.Decimal(float(x)) ** 2 for x in v_vec)
        return v2 / 2 - decimal.Decimal(mu_k) / r2.sqrt()


@given(
    r=st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)).filter(lambda p: np.linalg.norm(p) > 0.1),
    v=st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)),
    length=distances, excess=log_uniform(-7, 1),
)  # fmt: skip
def test_from_state_energy_holds_to_its_condition_number_for_a_long_time(r, v, length, excess):
    """E(t = 1e10) = E(state) to eps (v^2/2)/|E|: the conditioning of E = v^2/2 - mu/r, nothing more.

    Near a parabola (excess -> 0) E is a small difference of v^2/2 and mu/r, so
    the state fixes it only to eps v^2/(2|E|); the propagation must add nothing
    to that, out to 1e10 time units (both energies evaluated exactly).
    """
    r_vec = np.array(r) * length
    v_vec = np.array(v)
    assume(np.linalg.norm(np.cross(r_vec / np.linalg.norm(r_vec), v_vec)) > 1e-3 * np.linalg.norm(v_vec))
    escape = math.sqrt(2 * 2.0 / np.linalg.norm(r_vec))
    v_vec = v_vec / np.linalg.norm(v_vec) * escape * (1 + excess)
    orbit = TwoBodyOrbit.from_state(1.0, 1.0, r_vec, v_vec)
    assume(orbit.kind == "hyperbolic")
    start = _exact_specific_energy(2.0, r_vec, v_vec)
    later = _exact_specific_energy(2.0, *orbit.relative_state_at_time(1e10))
    condition = float(v_vec @ v_vec) / 2 / abs(float(start))
    assert abs(float((later - start) / start)) <= 8 * np.finfo(float).eps * (condition + 1)


def test_from_state_two_dimensional_and_bound():
    orbit = TwoBodyOrbit.from_state(1.0, 1.0, [2.0, 0.0], [0.1, 0.8])
    assert orbit.kind == "elliptic"
    t = orbit.time_since_periastron([2.0, 0.0], [0.1, 0.8])
    r, v = orbit.relative_state_at_time(t)
    assert r == pytest.approx([2.0, 0.0, 0.0], abs=1e-14) and v == pytest.approx([0.1, 0.8, 0.0], abs=1e-14)
    r_next, _ = orbit.relative_state_at_time(t + orbit.period)
    assert r_next == pytest.approx(r, abs=1e-13)  # closes after a period


@given(m1=masses, m2=masses, b=distances, v_inf=speeds)
def test_from_impact_parameter_inverts_eq_38(m1, m2, b, v_inf):
    orbit = TwoBodyOrbit.from_impact_parameter(m1, m2, b, v_inf)
    assert isinstance(orbit, Hyperbolic)
    assert orbit.impact_parameter == pytest.approx(b, rel=1e-12, abs=0)
    again = Hyperbolic(m1, m2, periastron=orbit.periastron, v_inf=v_inf)
    assert again.deflection_angle == pytest.approx(orbit.deflection_angle, rel=1e-12, abs=0)


def test_bound_orbit_elements():
    orbit = TwoBodyOrbit(2.0, 2.0, periastron=1.0, eccentricity=0.5)
    assert orbit.apoastron == pytest.approx(3.0)
    assert orbit.semi_major_axis == pytest.approx(2.0)
    assert orbit.period == pytest.approx(2 * math.pi * math.sqrt(8.0 / 4.0))
    assert math.isnan(orbit.v_inf) and math.isnan(orbit.impact_parameter) and math.isnan(orbit.deflection_angle)
    assert orbit.energy == pytest.approx(-1.0 * 4.0 / (2 * 2.0))  # -mu G M / (2a)
    with pytest.raises(ValueError, match="hyperbolic"):
        orbit.asymptotes()


# ------------------------------------------------------------------ bad input


@pytest.mark.parametrize(
    ("arguments", "match"),
    [
        (dict(m1=0.0), "m1"),
        (dict(m2=-1.0), "m2"),
        (dict(periastron=0.0), "periastron"),
        (dict(periastron=-2.0), "periastron"),
        (dict(v_inf=0.0), "v_inf"),
        (dict(v_inf=-1.0), "v_inf"),
        (dict(periastron=float("nan")), "periastron must be finite"),
        (dict(m1=float("inf")), "m1 must be finite"),
        (dict(G=-1.0), "G"),
    ],
)
def test_hyperbolic_rejects_bad_input(arguments, match):
    values = dict(m1=1.0, m2=1.0, periastron=1.0, v_inf=1.0) | arguments
    with pytest.raises(ValueError, match=match):
        Hyperbolic(**values)


def test_bad_types_and_ranges():
    with pytest.raises(TypeError, match="m1"):
        Hyperbolic("1", 1.0, periastron=1.0, v_inf=1.0)
    with pytest.raises(TypeError, match="single number"):
        Hyperbolic([1.0, 2.0], 1.0, periastron=1.0, v_inf=1.0)
    with pytest.raises(ValueError, match=r"periastron must be >= .*head-on"):
        Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0, k=1.0)
    with pytest.raises(ValueError, match="eccentricity"):
        TwoBodyOrbit(1.0, 1.0, periastron=1.0, eccentricity=-0.1)
    with pytest.raises(ValueError, match=r"eccentricity must lie in \[1.0"):
        TwoBodyOrbit(1.0, 1.0, periastron=1.0, eccentricity=0.5, k=1.0)
    with pytest.raises(ValueError, match="vanishes"):
        Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0, G=0.0)
    with pytest.raises(ValueError, match="impact_parameter"):
        Hyperbolic.from_impact_parameter(1.0, 1.0, 0.0, 1.0)
    with pytest.raises(ValueError, match="radial"):
        TwoBodyOrbit.from_state(1.0, 1.0, [1.0, 0.0, 0.0], [-1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="separation"):
        TwoBodyOrbit.from_state(1.0, 1.0, [0.0, 0.0, 0.0], [1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="units"):
        unit_system("imperial")


def test_methods_reject_bad_input():
    orbit = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0)
    with pytest.raises(ValueError, match=r"r must lie in \[1.0"):
        orbit.time_at_separation(0.5)
    with pytest.raises(ValueError, match="branch"):
        orbit.time_at_separation(2.0, branch="up")
    with pytest.raises(ValueError, match="t must be finite"):
        orbit.state_at_time([0.0, float("nan")])
    with pytest.raises(ValueError, match="radius1"):
        orbit.contact(-1.0, 1.0)
    with pytest.raises(ValueError, match="v_inf"):
        focusing_cross_section(1.0, 1.0, 1.0, 1.0, 0.0)
    bound = TwoBodyOrbit(1.0, 1.0, periastron=1.0, eccentricity=0.5)
    with pytest.raises(ValueError, match="r must lie in"):
        bound.time_at_separation(3.5)  # beyond apoastron 3
    with pytest.raises(ValueError, match="apoastron"):
        bound.contact(2.0, 2.0)


# --------------------------------------- edge cases found by a mutation audit


@pytest.mark.parametrize(
    ("r", "v"),
    [([1.0, 0.0, 0.0], [0.0, 3.0, 0.0]), ([1.0, 0.0, 0.0], [0.0, -3.0, 0.0]), ([0.0, 2.0, 0.0], [0.1, 0.0, 0.8])],
)
def test_angular_momentum_vector_of_an_orbit_from_a_state_is_mu_r_cross_v(r, v):
    # kills E06 (encounters.py:249 W = P x Q -> Q x P): from_state builds the basis from the state,
    # and W must point along r x v (the orbit's own angular momentum), not against it.
    # Independent value: J = mu r x v with mu = m1 m2 / (m1 + m2) = 0.5; r x v is exact here.
    orbit = TwoBodyOrbit.from_state(1.0, 1.0, r, v)
    np.testing.assert_allclose(orbit.angular_momentum_vector, 0.5 * np.cross(r, v), rtol=1e-14, atol=1e-15)
    # and the propagated state keeps that direction
    x, u = orbit.relative_state_at_time(0.3)
    np.testing.assert_allclose(np.cross(x, u), np.cross(r, v), rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize(("k", "sign"), [(0.3, -1.0), (None, 1.0)])
def test_semi_latus_rectum_is_positive_for_attraction_and_repulsion(k, sign):
    # kills E27 (encounters.py:472 h^2 / |mu_K| -> h^2 / mu_K): for a repulsive orbit p came out
    # negative. Independent: the conic r = p / (1 + sign e cos theta) at periastron gives
    # p = r_p (1 + e) (attraction) or r_p (e - 1) (repulsion), with the module's
    # e = |1 + r_p v_inf^2 / mu_K| (rel 1e-13: a few roundings). Repulsion: mu_K = -k / mu = -0.6,
    # e = 2 / 0.6 - 1, p = 2 (e - 1) = 8 / 3; gravity: mu_K = 2, e = 2, p = 6.
    m1, m2, rp, v_inf = 1.0, 1.0, 2.0, 1.0
    orbit = Hyperbolic(m1, m2, periastron=rp, v_inf=v_inf, k=k) if k else Hyperbolic(m1, m2, periastron=rp, v_inf=v_inf)
    mu_k = (m1 + m2) if k is None else -k * (m1 + m2) / (m1 * m2)
    e = abs(1.0 + rp * v_inf**2 / mu_k)
    expected = rp * (e + sign)
    assert orbit.semi_latus_rectum > 0
    assert orbit.semi_latus_rectum == pytest.approx(expected, rel=1e-13)


def test_parabolic_orbit_has_no_asymptotes_or_cross_sections():
    # kills E44 (encounters.py:705 `beta >= 0` -> `beta > 0`): a parabola (v_inf = 0) must get the
    # named "needs a hyperbolic orbit" error, not a ZeroDivisionError from 1 / v_inf^2.
    parabola = TwoBodyOrbit(1.0, 1.0, periastron=1.0, eccentricity=1.0)
    assert parabola.kind == "parabolic"
    for call in (parabola.asymptotes, lambda: parabola.differential_cross_section(1.0),
                 lambda: parabola.focusing_cross_section(0.5, 0.5)):
        with pytest.raises(ValueError, match="hyperbolic"):
            call()


def test_repulsive_periastron_below_the_head_on_distance_is_refused():
    # kills E51 (encounters.py:921 head-on distance 2 |mu_K| / v^2 -> |mu_K| / v^2).
    # Independent: head-on, all of E = mu v^2 / 2 becomes k / r at the turning point:
    # r = 2 k / (mu v^2) = 2 * 1 / (0.5 * 1) = 4 for m1 = m2 = 1, k = 1, v = 1.
    with pytest.raises(ValueError, match="head-on"):
        Hyperbolic(1.0, 1.0, periastron=3.0, v_inf=1.0, k=1.0)
    ok = Hyperbolic(1.0, 1.0, periastron=4.0, v_inf=1.0, k=1.0)
    assert ok.eccentricity == pytest.approx(1.0, abs=1e-15)  # exactly head-on: radial, e = 1


def test_repulsive_orbit_from_periastron_and_eccentricity():
    # kills E08 (encounters.py `abs(mu_k) * e` -> `mu_k * e` in TwoBodyOrbit.__init__): for a
    # repulsive force the mutant made beta = |mu_K| (e - 1) / r_p > 0, a bound "orbit".
    # Independent route: repulsive hyperbola r = p / (e cos f - 1), so r_p = p / (e - 1),
    # p = h^2 / |mu_K|, and energy v_p^2 = v_inf^2 - 2 |mu_K| / r_p. With m1 = m2 = 1, k = 1:
    # mu_K = -2; r_p = 1, e = 3 -> p = 2, h = v_p = 2, v_inf^2 = 8. Values are a few roundings
    # from exact, hence rtol 1e-14.
    orbit = TwoBodyOrbit(1.0, 1.0, periastron=1.0, eccentricity=3.0, k=1.0)
    assert orbit.kind == "hyperbolic" and not orbit.attractive
    assert orbit.eccentricity == pytest.approx(3.0, rel=1e-14)
    assert orbit.semi_latus_rectum == pytest.approx(2.0, rel=1e-14)
    assert orbit.periastron_speed == pytest.approx(2.0, rel=1e-14)
    assert orbit.v_inf == pytest.approx(math.sqrt(8.0), rel=1e-14)
    assert orbit.specific_energy == pytest.approx(4.0, rel=1e-14)  # v_inf^2 / 2
