"""Tests of collisionkit.kinematics: geometry, frames, angles, random impacts."""

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import assume, example, given
from hypothesis import strategies as st
from scipy import stats

import collisionkit as ck
from collisionkit import kinematics
from tests.strategies import masses, vectors


def angle_between(a, b):
    return math.acos(np.clip(np.dot(a, b) / (np.linalg.norm(a) * np.linalg.norm(b)), -1, 1))


@given(m1=masses, m2=masses, v1=vectors(3), v2=vectors(3))
@example(m1=0.001, m2=1.0, v1=np.array([0.0, 0.0, 1.0]), v2=np.zeros(3))
@example(m1=1e-3, m2=1e3, v1=np.array([1.0, 0.0, 0.0]), v2=np.zeros(3))  # light projectile, heavy target at rest
def test_centre_of_mass_frame_round_trip_and_zero_momentum(m1, m2, v1, v2):
    v_cm, w1, w2 = ck.to_centre_of_mass_frame(m1, v1, m2, v2)
    # the residual momentum is round-off of the momenta involved, however unequal the masses
    scale = m1 * (np.abs(v1) + np.abs(w1)) + m2 * (np.abs(v2) + np.abs(w2)) + 1e-300
    assert np.all(np.abs(m1 * w1 + m2 * w2) <= 1e-14 * scale)
    back1, back2 = ck.from_centre_of_mass_frame(v_cm, w1, w2)
    np.testing.assert_allclose(back1, v1, atol=1e-13 * (np.abs(v1).sum() + np.abs(v2).sum()))
    np.testing.assert_allclose(back2, v2, atol=1e-13 * (np.abs(v1).sum() + np.abs(v2).sum()))


@given(m1=st.floats(1e-12, 1e12), m2=st.floats(1e-12, 1e12), v1=vectors(2), v2=vectors(2))
@example(m1=1e-8, m2=1.0, v1=np.array([1.0, 0.0]), v2=np.zeros(2))  # 7e-9 relative error before the fix
@example(m1=9.1093837e-31 / 6.63e-26, m2=1.0, v1=np.array([1e6, 0.0]), v2=np.zeros(2))  # an electron on argon
def test_centre_of_mass_velocity_is_exact_to_round_off_for_any_mass_ratio(m1, m2, v1, v2):
    exact = [(Fraction(m1) * Fraction(a) + Fraction(m2) * Fraction(b)) / (Fraction(m1) + Fraction(m2))
             for a, b in zip(v1, v2)]
    v_cm = ck.centre_of_mass_velocity(m1, v1, m2, v2)
    light_share = min(m1, m2) / (m1 + m2)
    for computed, value, a, b in zip(v_cm, exact, v1, v2):
        # a few ulps of the result and of the lighter body's share of the velocity difference
        bound = 4 * np.finfo(float).eps * (abs(float(value)) + light_share * abs(a - b)) + 1e-300
        assert abs(Fraction(float(computed)) - value) <= Fraction(bound)


def test_infinite_mass_carries_the_centre_of_mass():
    np.testing.assert_array_equal(ck.centre_of_mass_velocity(np.inf, [1.0, 2.0], 3.0, [5.0, 5.0]), [1.0, 2.0])
    np.testing.assert_array_equal(ck.centre_of_mass_velocity(3.0, [5.0, 5.0], np.inf, [1.0, 2.0]), [1.0, 2.0])
    assert float(ck.reduced_mass(2.0, np.inf)) == 2.0
    with pytest.raises(ValueError, match="both be infinite"):
        ck.centre_of_mass_velocity(np.inf, [1.0], np.inf, [0.0])


def test_kinetic_energy_and_its_bad_input():
    np.testing.assert_allclose(ck.kinetic_energy([1.0, 2.0], [[1.0, 0.0], [0.0, 3.0]]), [0.5, 9.0])
    with pytest.raises(ValueError, match="m"):
        ck.kinetic_energy(-1.0, [1.0])


@given(x2=vectors(3, 20.0), v1=vectors(3, 5.0), v2=vectors(3, 5.0), sigma=st.floats(0.1, 3.0))
def test_impact_parameter_decides_whether_pairs_touch(x2, v1, v2, sigma):
    x1 = np.zeros(3)
    u = v1 - v2
    assume(np.linalg.norm(x2) > sigma * 1.001 and np.linalg.norm(u) > 1e-3)
    b = float(ck.impact_parameter(x1, v1, x2, v2))
    assume(abs(b - sigma) > 1e-7 * sigma)
    approaching = np.dot(x2, u) > 0
    hit = math.isfinite(ck.time_to_contact(x1, v1, x2, v2, sigma))
    assert hit == (approaching and b < sigma)
    # independent: distance of closest approach by minimising over time
    t_star = np.dot(x2, u) / np.dot(u, u)
    assert b == pytest.approx(np.linalg.norm(x2 - u * t_star), rel=1e-9, abs=1e-12)


def test_impact_parameter_of_pair_at_relative_rest_is_its_distance():
    assert float(ck.impact_parameter([0.0, 0.0], [1.0, 1.0], [3.0, 4.0], [1.0, 1.0])) == 5.0


@given(x2=vectors(2, 20.0), v1=vectors(2, 5.0), v2=vectors(2, 5.0), sigma=st.floats(0.1, 3.0))
def test_smid_impact_angle_gives_the_line_of_centres_at_contact(x2, v1, v2, sigma):
    x1 = np.zeros(2)
    u = v1 - v2
    assume(np.linalg.norm(x2) > sigma * 1.001 and np.linalg.norm(u) > 1e-3)
    # at exact tangency the two routes may round to different sides
    assume(abs(float(ck.impact_parameter(x1, v1, x2, v2)) - sigma) > 1e-9 * sigma)
    contact = ck.collide(1.0, x1, v1, 1.0, x2, v2, sigma)
    alpha = float(ck.impact_angle_2d(x1, v1, x2, v2, sigma))
    assert math.isnan(alpha) == (not bool(contact.hit))
    if contact.hit:
        assume(abs(abs(alpha) - math.pi / 2) > 1e-6)
        normal = ck.normal_from_impact_angles(u, alpha)
        np.testing.assert_allclose(normal, contact.normal, atol=1e-8)
        # Smid's eq. (14) with explicit angles
        gamma_xy = math.atan2(x2[1], x2[0])
        gamma_v = math.atan2(u[1], u[0])
        d = math.hypot(*x2)
        assert alpha == pytest.approx(math.asin(d * math.sin(gamma_xy - gamma_v) / sigma), abs=1e-9)


@given(x2=vectors(3, 20.0), v1=vectors(3, 5.0), v2=vectors(3, 5.0), sigma=st.floats(0.1, 3.0))
def test_3d_impact_angles_give_the_line_of_centres_at_contact(x2, v1, v2, sigma):
    x1 = np.zeros(3)
    u = v1 - v2
    assume(np.linalg.norm(x2) > sigma * 1.001 and np.linalg.norm(u) > 1e-3)
    assume(abs(float(ck.impact_parameter(x1, v1, x2, v2)) - sigma) > 1e-9 * sigma)
    contact = ck.collide(1.0, x1, v1, 1.0, x2, v2, sigma)
    alpha, phi = ck.impact_angles_3d(x1, v1, x2, v2, sigma)
    assert math.isnan(alpha) == (not bool(contact.hit))
    if contact.hit:
        assume(float(alpha) < math.pi / 2 - 1e-6)
        normal = ck.normal_from_impact_angles(u, alpha, phi)
        np.testing.assert_allclose(normal, contact.normal, atol=1e-8)
        assert float(alpha) == pytest.approx(angle_between(u, contact.normal), abs=1e-7)


@given(dimension=st.sampled_from([2, 3]), offset=st.floats(0.05, 0.95), direction=vectors(3, 1.0),
       v1=vectors(3, 5.0), sigma=st.floats(0.1, 3.0))
def test_overlapping_approaching_pairs_collide_along_their_present_line_of_centres(dimension, offset, direction,
                                                                                  v1, sigma):
    direction = direction[:dimension]
    assume(np.linalg.norm(direction) > 1e-3 and np.linalg.norm(v1[:dimension]) > 1e-3)
    x2 = offset * sigma * direction / np.linalg.norm(direction)  # centres closer than sigma
    v1 = v1[:dimension]
    x1, v2 = np.zeros(dimension), np.zeros(dimension)
    assume(np.dot(x2, v1) > 1e-6 * np.linalg.norm(x2) * np.linalg.norm(v1))  # approaching
    line_of_centres = x2 / np.linalg.norm(x2)
    if dimension == 2:
        normal = ck.normal_from_impact_angles(v1, ck.impact_angle_2d(x1, v1, x2, v2, sigma))
    else:
        normal = ck.normal_from_impact_angles(v1, *ck.impact_angles_3d(x1, v1, x2, v2, sigma))
    # arcsin near grazing magnifies round-off by tan(alpha) ~ 1 / cos(angle between u and the line of centres)
    cosine = np.dot(line_of_centres, v1) / np.linalg.norm(v1)
    np.testing.assert_allclose(normal, line_of_centres, atol=16 * np.finfo(float).eps / cosine)
    np.testing.assert_allclose(ck.collide(1.0, x1, v1, 1.0, x2, v2, sigma).normal, line_of_centres, atol=1e-15)


def test_planar_3d_collision_has_the_2d_impact_angle_magnitude():
    args = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [5.0, -0.5, 0.0], [0.0, 0.0, 0.0], 1.0)
    alpha_3d, _ = ck.impact_angles_3d(*args)
    alpha_2d = ck.impact_angle_2d(*(np.asarray(a)[:2] if np.ndim(a) else a for a in args))
    assert float(alpha_3d) == pytest.approx(abs(float(alpha_2d)), rel=1e-14)


@given(m1=masses, m2=masses, alpha=st.floats(-1.5, 1.5), v=st.floats(0.1, 100))
def test_elastic_cm_scattering_angle_is_pi_minus_two_alpha(m1, m2, alpha, v):
    v1, v2 = np.array([v, 0.0]), np.zeros(2)
    a1, a2 = ck.resolve_impact_angles(m1, v1, m2, v2, alpha)
    chi = float(ck.scattering_angle_cm(v1, v2, a1, a2))
    assert chi == pytest.approx(float(kinematics.scattering_angle_from_impact_angle(alpha)), abs=1e-9)
    assert abs(alpha) == pytest.approx(float(kinematics.impact_angle_from_scattering_angle(chi)), abs=1e-9)


@given(m1=masses, m2=masses, alpha=st.floats(0.0, 1.5), phi=st.floats(-3.1, 3.1))
def test_lab_angles_and_energy_transfer_off_a_target_at_rest(m1, m2, alpha, phi):
    v1, v2 = np.array([0.3, -1.2, 2.0]), np.zeros(3)
    a1, a2 = ck.resolve_impact_angles(m1, v1, m2, v2, alpha, phi)
    chi = ck.scattering_angle_cm(v1, v2, a1, a2)
    if np.linalg.norm(a1) > 1e-6 * np.linalg.norm(v1):
        assert float(ck.lab_scattering_angle(chi, m1, m2)) == pytest.approx(angle_between(v1, a1), abs=1e-7)
    if np.linalg.norm(a2) > 1e-6 * np.linalg.norm(v1):
        assert float(ck.recoil_angle(chi)) == pytest.approx(angle_between(v1, a2), abs=1e-7)
    transferred = ck.kinetic_energy(m2, a2) / ck.kinetic_energy(m1, v1)
    assert float(ck.energy_transfer_fraction(chi, m1, m2)) == pytest.approx(float(transferred), abs=1e-12)


def test_energy_transfer_limits():
    assert float(ck.energy_transfer_fraction(np.pi, 1.0, np.inf)) == 0.0
    assert float(ck.energy_transfer_fraction(np.pi, 1.0, 1.0)) == 1.0
    with pytest.raises(ValueError, match="m1"):
        ck.energy_transfer_fraction(1.0, np.inf, 1.0)
    with pytest.raises(ValueError, match="chi"):
        ck.lab_scattering_angle(4.0, 1.0, 1.0)


def test_sampled_3d_impacts_are_uniform_over_the_collision_disc():
    # b^2 / sigma^2 is uniform on [0, 1] for a uniform disc
    normal, b = ck.sample_impact([0.0, 0.0, 2.0], 1.5, size=20_000, seed=7)
    np.testing.assert_allclose(np.linalg.norm(normal, axis=1), 1.0)
    assert stats.kstest((b / 1.5) ** 2, "uniform").pvalue > 1e-3
    # the azimuth is uniform too: each quadrant of the disc gets a quarter (4 sigma binomial)
    quadrant = (normal[:, 0] > 0) * 2 + (normal[:, 1] > 0)
    counts = np.bincount(quadrant, minlength=4)
    assert np.all(np.abs(counts - 5000) < 4 * math.sqrt(20_000 * 0.25 * 0.75))
    # hard-sphere scattering is isotropic in the CM frame: cos(chi) uniform on [-1, 1]
    v1 = np.array([0.0, 0.0, 2.0])
    a1, a2 = ck.resolve_contact(1.0, v1, 3.0, np.zeros(3), normal)
    chi = ck.scattering_angle_cm(v1, np.zeros(3), a1, a2)
    assert stats.kstest(np.cos(chi), stats.uniform(-1, 2).cdf).pvalue > 1e-3


def test_sampled_2d_impacts_have_uniform_impact_parameter():
    normal, b = ck.sample_impact([1.0, 1.0], 2.0, size=20_000, seed=11)
    assert stats.kstest(b / 2.0, "uniform").pvalue > 1e-3
    signed = np.sign(normal[:, 1] - normal[:, 0])  # which side of the relative velocity
    assert abs(signed.mean()) < 4 / math.sqrt(20_000)


def test_sample_impact_bad_input():
    with pytest.raises(ValueError, match="contact_distance"):
        ck.sample_impact([1.0, 0.0], 0.0)
    with pytest.raises(ValueError, match="relative_velocity"):
        ck.sample_impact([0.0, 0.0], 1.0, size=3)


@pytest.mark.parametrize(
    ("call", "words"),
    [
        (lambda: ck.centre_of_mass_velocity(1.0, [np.nan, 0.0], 1.0, [0.0, 0.0]), "v1 must be finite"),
        (lambda: ck.centre_of_mass_velocity(1.0, [1.0, 0.0], 1.0, [0.0, 0.0, 0.0]), "v1, v2 must broadcast"),
        (lambda: ck.from_centre_of_mass_frame([np.inf], [1.0], [2.0]), "v_cm must be finite"),
        (lambda: ck.kinetic_energy(1.0, [np.nan, 0.0]), "v must be finite"),
        (lambda: ck.scattering_angle_cm([np.nan, 0.0], [0, 0], [0, 0], [1, 0]), "v1 must be finite"),
        (lambda: ck.impact_parameter([0.0, 0.0], [1.0, 0.0], [3.0, 0.0, 0.0], [0.0, 0.0]), "x1, v1, x2, v2 must"),
        (lambda: kinematics.resolve_impact_angles(1.0, [np.nan, 0.0], 1.0, [0.0, 0.0], 0.0), "v1 must be finite"),
        (lambda: kinematics.resolve_impact_angles(1.0, [1.0, 0.0], 1.0, [0.0, 0.0, 0.0], 0.0), "v1, v2 must"),
        (lambda: kinematics.resolve_impact_angles(1.0, [1.0, 0.0], 1.0, [1.0, 0.0], 0.0), "v1 and v2 must differ"),
    ],
)
def test_velocities_are_checked_finite_and_of_one_dimension(call, words):
    # these passed NaN through, or stopped on numpy's broadcast error without the arguments' names
    with pytest.raises(ValueError, match=words):
        call()


def test_geometry_bad_input_names_arguments():
    with pytest.raises(ValueError, match="x1"):
        ck.impact_parameter([np.nan, 0.0], [1.0, 0.0], [0.0, 0.0], [0.0, 0.0])
    with pytest.raises(ValueError, match="2D"):
        ck.impact_angle_2d([0.0] * 3, [1.0, 0, 0], [3.0, 0, 0], [0.0] * 3, 1.0)
    with pytest.raises(ValueError, match="3D"):
        ck.impact_angles_3d([0.0] * 2, [1.0, 0], [3.0, 0], [0.0] * 2, 1.0)
    with pytest.raises(ValueError, match="alpha"):
        ck.normal_from_impact_angles([1.0, 0.0, 0.0], -0.1)


# ------------------------------------------------------------------ edge cases found by a mutation audit


@pytest.mark.parametrize(("m1", "m2"), [(2.0, 3.0), (1e-3, 1e3), (7.0, 7.0)])
def test_reduced_mass_is_the_harmonic_combination(m1, m2):
    # kills KN01 (kinematics.py: `m1 * m2 / (m1 + m2)` -> `m1 / (m1 + m2)`).
    # independent definition 1/mu = 1/m1 + 1/m2; two roundings each side -> rel 4 eps.
    assert float(ck.reduced_mass(m1, m2)) == pytest.approx(1.0 / (1.0 / m1 + 1.0 / m2), rel=4e-16)
    assert float(ck.reduced_mass(2.0, 3.0)) == pytest.approx(1.2, rel=4e-16)


def test_reduced_mass_with_an_infinite_mass_is_the_finite_one_on_either_side():
    # kills KN02 (kinematics.py: where(isinf(m1), m2, ...) -> where(isinf(m1), m1, ...)):
    # a fixed body (inf) leaves the other's mass as reduced mass, whichever argument it is.
    assert float(ck.reduced_mass(np.inf, 3.0)) == 3.0
    assert float(ck.reduced_mass(3.0, np.inf)) == 3.0


def test_kinetic_energy_of_a_massless_body_is_zero():
    # kills KN09 (kinematics.py: m range [0, inf) -> (0, inf)): m = 0 is documented-valid input.
    assert float(ck.kinetic_energy(0.0, [3.0, 4.0])) == 0.0
    assert float(ck.kinetic_energy(2.0, [3.0, 4.0])) == 25.0  # m |v|^2 / 2, exact in binary


def test_impact_angles_need_a_positive_contact_distance():
    # kills KN14 (kinematics.py:210 contact_distance range (0, inf) -> [0, inf)): with sigma = 0
    # the 2D angle divided by zero and returned NaN silently instead of a named error.
    with pytest.raises(ValueError, match="contact_distance"):
        ck.impact_angle_2d([0.0, 0.0], [1.0, 0.0], [3.0, 0.0], [0.0, 0.0], 0.0)
    with pytest.raises(ValueError, match="contact_distance"):
        ck.impact_angles_3d([0.0] * 3, [1.0, 0.0, 0.0], [3.0, 0.0, 0.0], [0.0] * 3, 0.0)


@pytest.mark.parametrize("dimension", [2, 3])
def test_overlapping_pair_sliding_past_has_no_impact_angle(dimension):
    # kills KN16 (kinematics.py:215 `r.u > 0` -> `>= 0`) and KN21 (:268 `along > 0` -> `>= 0`):
    # an overlapping pair whose relative velocity is perpendicular to the line of centres
    # does not approach, so collide finds no hit (time inf); the angle must then be NaN,
    # not +-pi/2.
    x1, v2 = np.zeros(dimension), np.zeros(dimension)
    x2 = np.zeros(dimension)
    x2[0] = 0.5  # |r| = 0.5 < sigma = 1: overlapping
    v1 = np.zeros(dimension)
    v1[1] = 1.0  # r . u = 0
    assert not bool(ck.collide(1.0, x1, v1, 1.0, x2, v2, 1.0).hit)
    if dimension == 2:
        assert math.isnan(float(ck.impact_angle_2d(x1, v1, x2, v2, 1.0)))
    else:
        alpha, phi = ck.impact_angles_3d(x1, v1, x2, v2, 1.0)
        assert math.isnan(float(alpha)) and math.isnan(float(phi))


@pytest.mark.parametrize(("height", "expected"), [(1.0, math.pi / 2), (-1.0, -math.pi / 2)])
def test_grazing_pair_has_impact_angle_plus_minus_pi_over_2(height, expected):
    # kills KN18 (kinematics.py:217 `|ratio| <= 1` -> `< 1`): impact parameter exactly sigma is a
    # graze that collide resolves (time_to_contact documents one touch at tangency), and
    # Smid's alpha = asin(d sin(gamma_xy - gamma_v) / sigma) = asin(+-1) = +-pi/2 (exact in floats).
    args = ([0.0, 0.0], [1.0, 0.0], [5.0, height], [0.0, 0.0], 1.0)
    assert bool(ck.collide(1.0, *args[:2], 1.0, *args[2:]).hit)
    assert float(ck.impact_angle_2d(*args)) == expected


def test_grazing_3d_pair_has_polar_angle_pi_over_2_and_its_azimuth():
    # kills KN22 (kinematics.py:268 `b <= sigma` -> `b < sigma`) and KN20 (:231 e2 = u x e1 ->
    # e1 x u): u = +x, offset of the centre +z, b = sigma = 1. alpha = pi/2 (graze);
    # basis from the least aligned axis: e1 = +y, right-handed e2 = u x e1 = +z, so the line of
    # centres +z has phi = atan2(1, 0) = pi/2 exactly.
    args = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [5.0, 0.0, 1.0], [0.0, 0.0, 0.0], 1.0)
    assert bool(ck.collide(1.0, *args[:2], 1.0, *args[2:]).hit)
    alpha, phi = ck.impact_angles_3d(*args)
    assert float(alpha) == math.pi / 2
    assert float(phi) == math.pi / 2


@pytest.mark.parametrize("u", [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.3, -1.2, 2.0], [-5.0, 0.1, 0.2]])
def test_impact_angle_basis_is_right_handed(u):
    # kills KN20 (kinematics.py:231 np.cross(unit, e1) -> np.cross(e1, unit)): the docstring of
    # normal_from_impact_angles fixes (e1, e2, u_hat) right-handed: e1 x e2 = u_hat.
    # e1 and e2 are read off as the normals at alpha = pi/2, phi = 0 and pi/2 (cos(pi/2) = 6e-17
    # leaks u_hat into each, so the tolerance is 1e-15).
    unit = np.asarray(u) / np.linalg.norm(u)
    e1 = ck.normal_from_impact_angles(u, math.pi / 2, 0.0)
    e2 = ck.normal_from_impact_angles(u, math.pi / 2, math.pi / 2)
    np.testing.assert_allclose(np.cross(e1, e2), unit, atol=1e-15)


@pytest.mark.parametrize("alpha", [2.0, -1.6])
def test_2d_impact_angle_beyond_grazing_is_refused(alpha):
    # kills KN25 (kinematics.py:303 2D range check of alpha removed): |alpha| > pi/2 would put the
    # line of centres against the approach (no collision); documented range [-pi/2, pi/2].
    with pytest.raises(ValueError, match="alpha"):
        ck.normal_from_impact_angles([1.0, 0.0], alpha)
    with pytest.raises(ValueError, match="alpha"):
        kinematics.resolve_impact_angles(1.0, [1.0, 0.0], 1.0, [0.0, 0.0], alpha)


def test_masses_must_be_positive_not_zero():
    # kills A06 (_arrays.py: require_positive_masses `> 0` -> `>= 0`): a zero mass has no centre of
    # mass share and no reduced mass; the documented contract is m > 0 (inf allowed).
    with pytest.raises(ValueError, match="m1 must be positive"):
        ck.centre_of_mass_velocity(0.0, [1.0, 0.0], 1.0, [0.0, 0.0])
    with pytest.raises(ValueError, match="m2 must be positive"):
        ck.reduced_mass(1.0, 0.0)
    with pytest.raises(ValueError, match="m2"):
        kinematics.energy_transfer_fraction(1.0, 1.0, 0.0)
