"""Tests of collisionkit.compat.irfpy, including irfpy's open TODO (CM-frame check)."""

import math

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import collisionkit as ck
from collisionkit.compat import irfpy
from tests.strategies import masses


def irfpy_documented_solution(m1, v1, m2, d, sigma):
    """The closed form exactly as irfpy's documentation writes it."""
    mu = m2 / m1
    delta = d / math.sqrt(sigma**2 - d**2)
    alpha = (mu + 1) * (1 + delta**2)
    return v1 * (1 - 2 * mu / alpha), 2 * v1 * mu * delta / alpha, 2 * v1 / alpha, -2 * v1 * delta / alpha


stationary_cases = st.tuples(masses, st.floats(0.01, 100.0), masses, st.floats(0.0, 0.999), st.floats(0.1, 10.0))


@given(stationary_cases)
def test_matches_irfpy_documented_closed_form(case):
    m1, v1, m2, fraction, sigma = case
    d = fraction * sigma
    got = irfpy.binary_collision_stationary(m1, v1, m2, d, sigma)
    np.testing.assert_allclose(got, irfpy_documented_solution(m1, v1, m2, d, sigma), rtol=1e-9, atol=1e-12 * v1)


@given(stationary_cases)
def test_irfpy_formulation_checked_in_the_centre_of_mass_frame(case):
    """irfpy's TODO: 'check the formulation ... using center of gravity system'.

    In the CM frame an elastic hard-sphere collision only rotates the two
    opposite momenta: both speeds are kept, total momentum stays zero, and
    the rotation angle is chi = 2 arccos(d / sigma) (b = sigma cos(chi/2)).
    The fourth equation, W2 = -delta V2, says the target recoils along the
    line of centres at contact; it is checked against that geometry.
    """
    m1, v1, m2, fraction, sigma = case
    d = fraction * sigma
    V1, W1, V2, W2 = irfpy.binary_collision_stationary(m1, v1, m2, d, sigma)
    v_cm = np.array([m1 * v1 / (m1 + m2), 0.0])
    w1_before, w2_before = np.array([v1, 0.0]) - v_cm, -v_cm
    w1_after, w2_after = np.array([V1, W1]) - v_cm, np.array([V2, W2]) - v_cm
    np.testing.assert_allclose(m1 * w1_after + m2 * w2_after, 0.0, atol=1e-12 * m1 * v1)
    # velocities of size v1 carry round-off of size eps v1: a tiny CM speed (m1 << m2) is known to that only
    assert np.linalg.norm(w1_after) == pytest.approx(np.linalg.norm(w1_before), rel=1e-10, abs=1e-12 * v1)
    assert np.linalg.norm(w2_after) == pytest.approx(np.linalg.norm(w2_before), rel=1e-10, abs=1e-12 * v1)
    turn = math.atan2(np.cross(np.append(w1_before, 0), np.append(w1_after, 0))[2], np.dot(w1_before, w1_after))
    assert abs(turn) == pytest.approx(2 * math.acos(fraction), abs=1e-9)
    assert turn >= -1e-12  # particle 1 passes above the target and is deflected upwards (+y)
    line_of_centres = np.array([math.sqrt(sigma**2 - d**2), -d]) / sigma  # from 1 to 2 at contact
    recoil = np.array([V2, W2])
    if fraction > 0:
        assert abs(np.cross(np.append(recoil, 0), np.append(line_of_centres, 0))[2]) <= 1e-12 * v1
        assert np.dot(recoil, line_of_centres) > 0


@given(stationary_cases)
def test_stationary_matches_the_vector_rule_at_the_contact_geometry(case):
    m1, v1, m2, fraction, sigma = case
    d = fraction * sigma
    normal = [math.sqrt(sigma**2 - d**2), -d]
    a1, a2 = ck.resolve_contact(m1, [v1, 0.0], m2, [0.0, 0.0], normal)
    got = irfpy.binary_collision_stationary(m1, v1, m2, d, sigma)
    np.testing.assert_allclose(got, [a1[0], a1[1], a2[0], a2[1]], atol=1e-12 * v1)


def test_no_collision_when_impact_parameter_reaches_collision_length():
    assert [float(x) for x in irfpy.binary_collision_stationary(1.0, 2.0, 1.0, 1.0, 1.0)] == [2.0, 0.0, 0.0, 0.0]
    assert [float(x) for x in irfpy.binary_collision_stationary(1.0, 2.0, 1.0, 3.0, 1.0)] == [2.0, 0.0, 0.0, 0.0]


def test_grazing_limit_and_fixed_target_stay_finite():
    V1, W1, V2, W2 = irfpy.binary_collision_stationary(1.0, 1.0, 1.0, np.nextafter(1.0, 0), 1.0)
    assert np.isfinite([V1, W1, V2, W2]).all() and float(V1) == pytest.approx(1.0)
    V1, W1, V2, W2 = irfpy.binary_collision_stationary(1.0, 1.0, np.inf, 0.0, 1.0)
    assert [float(V1), float(W1), float(V2), float(W2)] == [-1.0, 0.0, 0.0, 0.0]


def test_stationary_is_vectorised_over_impact_parameters():
    d = np.linspace(0.0, 1.2, 13)
    V1, W1, V2, W2 = irfpy.binary_collision_stationary(1.0, 1.0, 2.0, d, 1.0)
    assert V1.shape == (13,)
    energy = 0.5 * (V1**2 + W1**2) + 0.5 * 2.0 * (V2**2 + W2**2)
    np.testing.assert_allclose(energy, 0.5, rtol=1e-14)


@given(stationary_cases, st.integers(0, 2**32 - 1))
def test_vector1_reproduces_stationary_in_any_orientation(case, seed):
    m1, v1, m2, fraction, sigma = case
    assume(fraction < 0.99)
    d = fraction * sigma
    rotation = Rotation.random(random_state=seed)
    pos1 = rotation.apply([-5.0 * sigma, d, 0.0])  # irfpy: particle 1 in the (-x, +y) quadrant
    vel1 = rotation.apply([v1, 0.0, 0.0])
    after1, after2 = irfpy.binary_collision_stationary_vector1(m1, pos1, vel1, m2, sigma)
    V1, W1, V2, W2 = irfpy.binary_collision_stationary(m1, v1, m2, d, sigma)
    np.testing.assert_allclose(rotation.inv().apply(after1), [V1, W1, 0.0], atol=1e-9 * v1)
    np.testing.assert_allclose(rotation.inv().apply(after2), [V2, W2, 0.0], atol=1e-9 * v1)


def test_vector1_separating_particles_do_not_collide():
    after1, after2 = irfpy.binary_collision_stationary_vector1(1.0, [2.0, 0.1, 0.0], [1.0, 0.0, 0.0], 1.0, 1.0)
    np.testing.assert_array_equal(after1, [1.0, 0.0, 0.0])
    np.testing.assert_array_equal(after2, [0.0, 0.0, 0.0])


@given(masses, masses, st.integers(0, 2**32 - 1))
def test_binary_collision_is_galilean_invariant(m1, m2, seed):
    rng = np.random.default_rng(seed)
    pos1, pos2 = rng.normal(size=3) * 3, rng.normal(size=3) * 3
    vel1, vel2 = rng.normal(size=3), rng.normal(size=3)
    boost = rng.normal(size=3) * 10
    a1, a2 = irfpy.binary_collision(m1, pos1, vel1, m2, pos2, vel2, 1.5)
    b1, b2 = irfpy.binary_collision(m1, pos1, vel1 + boost, m2, pos2, vel2 + boost, 1.5)
    np.testing.assert_allclose(b1 - boost, a1, atol=1e-9 * (1 + np.abs(boost).sum()))
    np.testing.assert_allclose(b2 - boost, a2, atol=1e-9 * (1 + np.abs(boost).sum()))
    c = ck.collide(m1, pos1, vel1, m2, pos2, vel2, 1.5)
    np.testing.assert_array_equal(a1, c.v1)


def test_binary_collision_with_target_at_rest_equals_vector1():
    pos1, vel1 = np.array([-3.0, 0.4, 0.2]), np.array([2.0, 0.0, 0.0])
    a = irfpy.binary_collision(1.0, pos1, vel1, 4.0, np.zeros(3), np.zeros(3), 1.0)
    b = irfpy.binary_collision_stationary_vector1(1.0, pos1, vel1, 4.0, 1.0)
    np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize(
    ("args", "words"),
    [
        ((0.0, 1.0, 1.0, 0.5, 1.0), "mass1"),
        ((np.inf, 1.0, 1.0, 0.5, 1.0), "mass1"),
        ((1.0, 1.0, -1.0, 0.5, 1.0), "mass2"),
        ((1.0, 0.0, 1.0, 0.5, 1.0), "speed1"),
        ((1.0, 1.0, 1.0, -0.5, 1.0), "impact_parameter"),
        ((1.0, 1.0, 1.0, 0.5, 0.0), "collision_length"),
        ((1.0, 1.0, 1.0, np.nan, 1.0), "impact_parameter"),
    ],
)
def test_stationary_bad_input(args, words):
    with pytest.raises(ValueError, match=words):
        irfpy.binary_collision_stationary(*args)


@pytest.mark.parametrize(
    "arguments, error, words",
    [
        ((1.0, [np.nan, 0.0], [1.0, 0.0], 1.0, 1.0), ValueError, r"^pos1 must be finite"),
        ((1.0, [0.0, 0.0], [1.0, 0.0], 1.0, "x"), TypeError, r"^collision_length must be a number"),
        ((-1.0, [0.0, 0.0], [1.0, 0.0], 1.0, 1.0), ValueError, r"^mass1"),
    ],
)
def test_errors_use_irfpys_argument_names(arguments, error, words):
    # they named collide's arguments (x1, contact_distance, m1), which irfpy users never passed
    with pytest.raises(error, match=words):
        irfpy.binary_collision_stationary_vector1(*arguments)
