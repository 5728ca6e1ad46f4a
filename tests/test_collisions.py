"""Tests of collisionkit.collisions: resolve_contact, time_to_contact, collide."""

import math

import numpy as np
import pytest
from hypothesis import assume, example, given
from hypothesis import strategies as st

import collisionkit as ck
from tests.strategies import components, contacts, masses, restitutions, vectors


def momentum(m1, v1, m2, v2):
    return m1 * np.asarray(v1) + m2 * np.asarray(v2)


def energy(m1, v1, m2, v2):
    return 0.5 * m1 * np.dot(v1, v1) + 0.5 * m2 * np.dot(v2, v2)


# ---------------------------------------------------------------- independent routes


def notes_equal_mass_rule(v1, v2, normal):
    """Pair-collision notes: v1' = v1 - r (r.(v1 - v2)), v2' = v2 + r (r.(v1 - v2))."""
    r = normal / np.linalg.norm(normal)
    return v1 - r * np.dot(r, v1 - v2), v2 + r * np.dot(r, v1 - v2)


def notes_mass_rule(m1, v1, m2, v2, normal):
    """Pair-collision notes, different masses: delta v1 = -r 2 m2/(m1+m2) (r.(v1-v2))."""
    r = normal / np.linalg.norm(normal)
    approach = np.dot(r, v1 - v2)
    return v1 - r * 2 * m2 / (m1 + m2) * approach, v2 + r * 2 * m1 / (m1 + m2) * approach


def centre_of_mass_route(m1, v1, m2, v2, normal, e):
    """Go to the CM frame, reverse e times the normal relative velocity, come back."""
    r = normal / np.linalg.norm(normal)
    v_cm = (m1 * v1 + m2 * v2) / (m1 + m2)
    w = v1 - v2  # relative velocity, the same in every frame
    w_after = w - (1 + e) * np.dot(w, r) * r
    return v_cm + m2 / (m1 + m2) * w_after, v_cm - m1 / (m1 + m2) * w_after


def smid_velocities(m1, v1, m2, v2, alpha, R):
    """Smid's eqs. (7)-(13) and (22)-(27), verbatim (with tan), for a 2D collision."""
    (vx1, vy1), (vx2, vy2) = v1, v2
    gamma_v = math.atan2(vy1 - vy2, vx1 - vx2)
    a = math.tan(gamma_v + alpha)
    dvx2 = 2 * (vx1 - vx2 + a * (vy1 - vy2)) / ((1 + a * a) * (1 + m2 / m1))
    after1 = np.array([vx1 - m2 / m1 * dvx2, vy1 - a * m2 / m1 * dvx2])
    after2 = np.array([vx2 + dvx2, vy2 + a * dvx2])
    v_cm = (m1 * np.asarray(v1) + m2 * np.asarray(v2)) / (m1 + m2)
    return (after1 - v_cm) * R + v_cm, (after2 - v_cm) * R + v_cm


# ---------------------------------------------------------------- resolve_contact


@pytest.mark.parametrize("d", [1, 2, 3])
def test_equal_masses_head_on_exchange_velocities(d):
    v1 = np.zeros(d)
    v1[0] = 2.5
    v2 = np.zeros(d)
    v2[0] = -0.5
    a1, a2 = ck.resolve_contact(1.0, v1, 1.0, v2, np.eye(d)[0])
    np.testing.assert_array_equal(a1, v2)
    np.testing.assert_array_equal(a2, v1)


@given(m1=masses, m2=masses, u1=components(100.0), u2=components(100.0), e=restitutions)
def test_one_dimensional_head_on_matches_textbook_formula(m1, m2, u1, u2, e):
    assume(u1 > u2)
    a1, a2 = ck.resolve_contact(m1, [u1], m2, [u2], [1.0], restitution=e)
    expected1 = ((m1 - e * m2) * u1 + (1 + e) * m2 * u2) / (m1 + m2)
    expected2 = ((m2 - e * m1) * u2 + (1 + e) * m1 * u1) / (m1 + m2)
    scale = abs(u1) + abs(u2)
    assert a1[0] == pytest.approx(expected1, abs=1e-13 * scale)
    assert a2[0] == pytest.approx(expected2, abs=1e-13 * scale)
    # Newton's experimental law: separation speed = e * approach speed
    assert a2[0] - a1[0] == pytest.approx(e * (u1 - u2), abs=1e-12 * scale)


@given(contacts(), st.sampled_from(["normal", "cm"]))
def test_momentum_is_conserved_to_round_off(pair, model):
    m1, v1, m2, v2, normal, e = pair
    a1, a2 = ck.resolve_contact(m1, v1, m2, v2, normal, restitution=e, restitution_model=model)
    scale = m1 * np.abs(v1).sum() + m2 * np.abs(v2).sum() + 1e-300
    np.testing.assert_allclose(momentum(m1, a1, m2, a2), momentum(m1, v1, m2, v2), rtol=0, atol=1e-13 * scale)


@given(contacts())
def test_elastic_contact_conserves_energy(pair):
    m1, v1, m2, v2, normal, _ = pair
    for model in ("normal", "cm"):
        a1, a2 = ck.resolve_contact(m1, v1, m2, v2, normal, restitution_model=model)
        before = energy(m1, v1, m2, v2)
        assert energy(m1, a1, m2, a2) == pytest.approx(before, rel=1e-12, abs=1e-300)


@given(contacts())
def test_normal_model_loses_exactly_half_mu_one_minus_e2_un2(pair):
    m1, v1, m2, v2, normal, e = pair
    a1, a2 = ck.resolve_contact(m1, v1, m2, v2, normal, restitution=e)
    unit = normal / np.linalg.norm(normal)
    u_n = max(np.dot(v1 - v2, unit), 0.0)
    mu = m1 * m2 / (m1 + m2)
    expected = 0.5 * mu * (1 - e * e) * u_n**2
    before = energy(m1, v1, m2, v2)
    assert before - energy(m1, a1, m2, a2) == pytest.approx(expected, abs=1e-12 * before + 1e-300)


@given(contacts())
def test_cm_model_scales_relative_velocity_by_restitution(pair):
    m1, v1, m2, v2, normal, R = pair
    unit = normal / np.linalg.norm(normal)
    assume(np.dot(v1 - v2, unit) > 1e-6 * np.linalg.norm(v1 - v2))
    a1, a2 = ck.resolve_contact(m1, v1, m2, v2, normal, restitution=R, restitution_model="cm")
    u = v1 - v2
    elastic = u - 2 * np.dot(u, unit) * unit
    np.testing.assert_allclose(a1 - a2, R * elastic, atol=1e-12 * (np.abs(v1).sum() + np.abs(v2).sum()))
    mu = m1 * m2 / (m1 + m2)
    before = energy(m1, v1, m2, v2)
    lost = before - energy(m1, a1, m2, a2)
    assert lost == pytest.approx(0.5 * mu * (1 - R * R) * np.dot(u, u), abs=1e-12 * before)


@given(contacts())
def test_vector_rule_agrees_with_pair_collision_notes_and_cm_frame(pair):
    m1, v1, m2, v2, normal, e = pair
    assume(np.dot(v1 - v2, normal) > 0)
    a1, a2 = ck.resolve_contact(m1, v1, m2, v2, normal)
    n1, n2 = notes_mass_rule(m1, v1, m2, v2, normal)
    scale = np.abs(v1).sum() + np.abs(v2).sum()
    np.testing.assert_allclose(a1, n1, atol=1e-12 * scale)
    np.testing.assert_allclose(a2, n2, atol=1e-12 * scale)
    b1, b2 = ck.resolve_contact(m1, v1, m2, v2, normal, restitution=e)
    c1, c2 = centre_of_mass_route(m1, v1, m2, v2, normal, e)
    np.testing.assert_allclose(b1, c1, atol=1e-12 * scale)
    np.testing.assert_allclose(b2, c2, atol=1e-12 * scale)


@given(v1=vectors(3), v2=vectors(3), normal=vectors(3, 10.0))
def test_equal_mass_rule_of_the_notes(v1, v2, normal):
    assume(np.linalg.norm(normal) > 1e-3 and np.dot(v1 - v2, normal) > 0)
    a1, a2 = ck.resolve_contact(1.0, v1, 1.0, v2, normal)
    n1, n2 = notes_equal_mass_rule(v1, v2, normal)
    scale = np.abs(v1).sum() + np.abs(v2).sum()
    np.testing.assert_allclose(a1, n1, atol=1e-12 * scale)
    np.testing.assert_allclose(a2, n2, atol=1e-12 * scale)


@given(
    m1=masses,
    m2=masses,
    v1=vectors(2, 100.0),
    v2=vectors(2, 100.0),
    alpha=st.floats(-1.5, 1.5),
    R=restitutions,
)
def test_smid_2d_equations_agree_with_cm_model(m1, v1, m2, v2, alpha, R):
    u = v1 - v2
    assume(np.linalg.norm(u) > 1e-3)
    gamma_v = math.atan2(u[1], u[0])
    # Smid's a = tan(gamma_v + alpha) is ill-conditioned near +-90 degrees
    assume(abs(math.cos(gamma_v + alpha)) > 1e-3)
    normal = [math.cos(gamma_v + alpha), math.sin(gamma_v + alpha)]
    a1, a2 = ck.resolve_contact(m1, v1, m2, v2, normal, restitution=R, restitution_model="cm")
    s1, s2 = smid_velocities(m1, v1, m2, v2, alpha, R)
    scale = (np.abs(v1).sum() + np.abs(v2).sum()) / abs(math.cos(gamma_v + alpha)) ** 2
    np.testing.assert_allclose(a1, s1, atol=1e-11 * scale)
    np.testing.assert_allclose(a2, s2, atol=1e-11 * scale)


def test_models_agree_for_head_on_collisions():
    # With no tangential relative velocity both laws scale the same component.
    for e in (0.0, 0.3, 1.0):
        normal_model = ck.resolve_contact(2.0, [1.0, 0, 0], 3.0, [-1.0, 0, 0], [1.0, 0, 0], e)
        cm_model = ck.resolve_contact(2.0, [1.0, 0, 0], 3.0, [-1.0, 0, 0], [1.0, 0, 0], e, "cm")
        np.testing.assert_allclose(normal_model, cm_model, rtol=1e-15)


def test_perfectly_inelastic_head_on_pair_moves_together():
    a1, a2 = ck.resolve_contact(1.0, [3.0], 2.0, [0.0], [1.0], restitution=0.0)
    np.testing.assert_allclose(a1, [1.0])
    np.testing.assert_allclose(a2, [1.0])


def test_separating_and_sliding_pairs_do_not_change():
    v1 = np.array([[-1.0, 0.0], [0.0, 1.0]])
    v2 = np.array([[1.0, 0.0], [0.0, 0.0]])
    a1, a2 = ck.resolve_contact(1.0, v1, 1.0, v2, [1.0, 0.0])
    np.testing.assert_array_equal(a1, v1)
    np.testing.assert_array_equal(a2, v2)


def test_zero_relative_velocity_changes_nothing():
    a1, a2 = ck.resolve_contact(1.0, [1.0, 2.0, 3.0], 5.0, [1.0, 2.0, 3.0], [0.0, 0.0, 1.0])
    np.testing.assert_array_equal(a1, [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(a2, [1.0, 2.0, 3.0])


@given(v=vectors(3, 100.0), normal=vectors(3, 10.0), e=restitutions)
def test_infinite_mass_is_a_wall(v, normal, e):
    assume(np.linalg.norm(normal) > 1e-3)
    unit = normal / np.linalg.norm(normal)
    assume(np.dot(v, unit) > 0)
    wall_velocity = np.zeros(3)
    a1, a2 = ck.resolve_contact(1.0, v, np.inf, wall_velocity, normal, restitution=e)
    np.testing.assert_array_equal(a2, wall_velocity)
    np.testing.assert_allclose(a1, v - (1 + e) * np.dot(v, unit) * unit, atol=1e-12 * np.abs(v).sum())
    # the same wall on the other side, as body 1
    b1, b2 = ck.resolve_contact(np.inf, wall_velocity, 1.0, -v, normal, restitution=e)
    np.testing.assert_array_equal(b1, wall_velocity)
    np.testing.assert_allclose(b2, -a1, atol=1e-12 * np.abs(v).sum())


def test_moving_infinite_mass_in_cm_model_keeps_its_velocity():
    a1, a2 = ck.resolve_contact(np.inf, [1.0, 0.0], 1.0, [-1.0, 0.0], [1.0, 0.0], 0.5, "cm")
    np.testing.assert_array_equal(a1, [1.0, 0.0])
    np.testing.assert_allclose(a2, [2.0, 0.0])  # v_cm + R (v'_elastic - v_cm) = 1 + 0.5 * 2


@given(contacts(), st.floats(-12, 12))
def test_normal_length_does_not_matter(pair, exponent):
    m1, v1, m2, v2, normal, e = pair
    a = ck.resolve_contact(m1, v1, m2, v2, normal, e)
    b = ck.resolve_contact(m1, v1, m2, v2, normal * 10.0**exponent, e)
    scale = np.abs(v1).sum() + np.abs(v2).sum()
    np.testing.assert_allclose(a, b, atol=1e-12 * scale)


@given(contacts(), st.sampled_from(["normal", "cm"]), st.integers(-600, 600))
def test_any_representable_normal_length_gives_the_same_result_exactly(pair, model, exponent):
    # the normal is scaled by a power of two first: exact, and |n|^2 never over- or underflows
    # (a normal of 2^600 gave no collision at all, one of 2^-600 a "zero normal" error)
    m1, v1, m2, v2, normal, e = pair
    a = ck.resolve_contact(m1, v1, m2, v2, normal, e, restitution_model=model)
    b = ck.resolve_contact(m1, v1, m2, v2, np.ldexp(normal, exponent), e, restitution_model=model)
    np.testing.assert_array_equal(a, b)


def test_broadcasting_over_leading_axes_matches_a_loop():
    rng = np.random.default_rng(3)
    v1 = rng.normal(size=(4, 5, 3))
    v2 = rng.normal(size=(5, 3))
    normal = rng.normal(size=(4, 1, 3))
    m2 = rng.uniform(1, 2, size=(4, 5))
    e = rng.uniform(0, 1, size=(5,))
    a1, a2 = ck.resolve_contact(2.0, v1, m2, v2, normal, restitution=e)
    assert a1.shape == a2.shape == (4, 5, 3)
    for i in range(4):
        for j in range(5):
            b1, b2 = ck.resolve_contact(2.0, v1[i, j], m2[i, j], v2[j], normal[i, 0], e[j])
            np.testing.assert_array_equal(a1[i, j], b1)
            np.testing.assert_array_equal(a2[i, j], b2)


def test_scalar_pair_returns_vectors_of_its_dimension():
    a1, a2 = ck.resolve_contact(1, [1, 0], 1, [0, 0], [1, 0])
    assert a1.shape == (2,) and a1.dtype == np.float64


@pytest.mark.parametrize(
    ("kwargs", "error", "words"),
    [
        ({"m1": 0.0}, ValueError, "m1"),
        ({"m1": -1.0}, ValueError, "m1"),
        ({"m2": np.nan}, ValueError, "m2"),
        ({"m1": np.inf, "m2": np.inf}, ValueError, "both be infinite"),
        ({"v1": [np.nan, 0.0]}, ValueError, "v1"),
        ({"v2": [np.inf, 0.0]}, ValueError, "v2"),
        ({"normal": [0.0, 0.0]}, ValueError, "normal"),
        ({"normal": [np.nan, 1.0]}, ValueError, "normal"),
        ({"restitution": 1.5}, ValueError, "restitution"),
        ({"restitution": -0.1}, ValueError, "restitution"),
        ({"restitution": np.nan}, ValueError, "restitution"),
        ({"restitution_model": "tangential"}, ValueError, "restitution_model"),
        ({"v2": [0.0, 0.0, 0.0]}, ValueError, "dimension"),
        ({"v1": [[1.0, 0.0]] * 3, "v2": [[0.0, 0.0]] * 4}, ValueError, "broadcast"),
        ({"v1": [1.0, 0, 0, 0]}, ValueError, "v1"),
        ({"v1": 1.0}, ValueError, "v1"),
        ({"m1": "heavy"}, TypeError, "m1"),
        ({"m1": True}, TypeError, "m1 must hold numbers, not a bool"),
        ({"normal": [True, False]}, TypeError, "normal must hold numbers, not a bool"),
        ({"v1": [1 + 1j, 0]}, TypeError, "v1"),
        ({"v1": [[1.0, 0.0], [1.0]]}, TypeError, "v1"),
    ],
)
def test_bad_input_is_named(kwargs, error, words):
    arguments = {"m1": 1.0, "v1": [1.0, 0.0], "m2": 1.0, "v2": [0.0, 0.0], "normal": [1.0, 0.0]}
    arguments.update(kwargs)
    with pytest.raises(error, match=words):
        ck.resolve_contact(**arguments)


def test_bad_value_reports_the_pair_index():
    with pytest.raises(ValueError, match=r"m1 must lie in \(0, inf\] .*; got -1.0 \(pair index \(1, 0\)\)"):
        ck.resolve_contact([[1.0], [-1.0]], np.ones((2, 1, 3)), 1.0, np.zeros(3), [1.0, 0, 0])


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [  # the value given, and no empty "(pair index ())" for one pair (m1 = -1 was reported as "not NaN")
        ({"m1": -1.0}, r"^m1 must lie in \(0, inf\] \(np.inf for a fixed body\); got -1.0$"),
        ({"m2": 0.0}, r"^m2 must lie in \(0, inf\] \(np.inf for a fixed body\); got 0.0$"),
        ({"normal": [0.0, 0.0]}, r"^normal must be a non-zero vector \(the line of centres\); got \[0.0, 0.0\]$"),
        ({"restitution": 1.5}, r"^restitution must lie in \[0, 1\]; got 1.5$"),
        ({"m1": np.inf, "m2": np.inf}, r"^m1 and m2 cannot both be infinite$"),
    ],
)
def test_kernel_errors_name_the_argument_its_range_and_the_value(kwargs, message):
    arguments = {"m1": 1.0, "v1": [1.0, 0.0], "m2": 1.0, "v2": [0.0, 0.0], "normal": [1.0, 0.0]} | kwargs
    with pytest.raises(ValueError, match=message):
        ck.resolve_contact(**arguments)


# ---------------------------------------------------------------- time_to_contact


def smid_contact_time(x1, v1, x2, v2, sigma):
    """Smid eq. (17): law of cosines in the collision triangle (2D)."""
    r = np.asarray(x2) - np.asarray(x1)
    u = np.asarray(v1) - np.asarray(v2)
    d = math.hypot(*r)
    gamma_xy = math.atan2(r[1], r[0])
    gamma_v = math.atan2(u[1], u[0])
    offset = d * math.sin(gamma_xy - gamma_v)
    if abs(offset) > sigma or math.cos(gamma_xy - gamma_v) <= 0:
        return math.inf
    root = math.sqrt(sigma**2 - offset**2)
    along = d * math.cos(gamma_xy - gamma_v)
    return (along - root) / math.hypot(*u)


@given(x2=vectors(2, 50.0), v1=vectors(2, 10.0), v2=vectors(2, 10.0), sigma=st.floats(0.1, 5.0))
def test_contact_time_agrees_with_smid_law_of_cosines(x2, v1, v2, sigma):
    x1 = np.zeros(2)
    assume(np.linalg.norm(x2) > sigma * 1.01 and np.linalg.norm(v1 - v2) > 1e-2)
    expected = smid_contact_time(x1, v1, x2, v2, sigma)
    got = float(ck.time_to_contact(x1, v1, x2, v2, sigma))
    u = v1 - v2
    offset = abs(x2[0] * u[1] - x2[1] * u[0]) / np.linalg.norm(u)
    assume(abs(offset - sigma) > 1e-6 * sigma)  # away from tangency, where both are ill-conditioned
    if math.isinf(expected):
        assert math.isinf(got)
    else:
        assert got == pytest.approx(expected, rel=1e-9, abs=1e-12)


@given(
    d=st.sampled_from([1, 2, 3]).flatmap(lambda d: st.tuples(vectors(d, 100.0), vectors(d, 10.0), vectors(d, 10.0))),
    sigma=st.floats(0.01, 10.0),
)
@example(d=(np.array([1.0, 1.0]), np.array([0.0, 1.0]), np.array([-1.13525714e-97, 1.0])), sigma=1.0)  # grazing, slow
def test_contact_time_puts_the_centres_exactly_sigma_apart(d, sigma):
    x2, v1, v2 = d
    x1 = np.zeros_like(x2)
    assume(np.linalg.norm(x2) > sigma * (1 + 1e-9))
    t = float(ck.time_to_contact(x1, v1, x2, v2, sigma))
    if math.isfinite(t):
        # in the relative frame: x2 + v2 t - (x1 + v1 t) would lose x2 to round-off when |v| t >> |x2|
        # (a near-grazing pair with a tiny relative speed touches only after ~1e97 time units)
        separation = x2 - x1 + (v2 - v1) * t
        scale = np.linalg.norm(x2) + np.linalg.norm(v2 - v1) * t
        assert np.linalg.norm(separation) == pytest.approx(sigma, abs=1e-12 * scale)
        assert np.dot(separation, v2 - v1) <= 1e-12 * scale * np.linalg.norm(v2 - v1)  # arriving, not leaving
        earlier = x2 + (v2 - v1) * (0.999 * t)
        assert np.linalg.norm(earlier) >= sigma * (1 - 1e-12)
    else:
        # never closer than sigma: the closest approach along the whole future path
        u = v2 - v1
        uu = np.dot(u, u)
        t_min = max(-np.dot(x2, u) / uu, 0.0) if uu > 0 else 0.0
        assert np.linalg.norm(x2 + u * t_min) >= sigma * (1 - 1e-9)


def test_head_on_from_far_away_has_no_cancellation():
    # naive (-b - sqrt(b^2 - a c)) / a loses every digit here: b^2 = 1e16, a c = 1e16 - 1
    t = ck.time_to_contact([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1e8, 0.0, 0.0], [0.0, 0.0, 0.0], 1.0)
    assert float(t) == pytest.approx(1e8 - 1.0, rel=4e-16)
    a, b, c = 1.0, -1e8, 1e16 - 1.0
    naive = (-b - math.sqrt(b * b - a * c)) / a
    assert abs(naive - (1e8 - 1.0)) > 0.5  # what the textbook root gives
    t = ck.time_to_contact([0.0], [1e-3], [1e12], [-1e-3], 2.0)
    assert float(t) == pytest.approx((1e12 - 2.0) / 2e-3, rel=1e-15)


@pytest.mark.parametrize(
    ("x2", "v2", "expected"),
    [
        ([3.0, 0.0], [1.0, 0.0], math.inf),  # separating
        ([3.0, 0.0], [-1.0, 0.0], 2.0),  # head-on
        ([3.0, 2.0], [-1.0, 0.0], math.inf),  # passes by, b = 2 > 1
        ([3.0, 1.0], [-1.0, 0.0], 3.0),  # grazing: b = sigma touches once, at tangency
        ([3.0, 0.0], [0.0, 0.0], math.inf),  # at relative rest
        ([1.0, 0.0], [-1.0, 0.0], 0.0),  # touching at t = 0, approaching
        ([1.0, 0.0], [1.0, 0.0], math.inf),  # touching at t = 0, separating
        ([0.0, 1.0], [1.0, 0.0], math.inf),  # touching at t = 0, sliding
        ([0.5, 0.0], [-1.0, 0.0], 0.0),  # overlapping, approaching: contact now
        ([0.5, 0.0], [1.0, 0.0], math.inf),  # overlapping, separating
        ([0.0, 0.0], [1.0, 0.0], math.inf),  # coincident centres: no line of centres
    ],
)
def test_contact_time_edge_cases(x2, v2, expected):
    assert float(ck.time_to_contact([0.0, 0.0], [0.0, 0.0], x2, v2, 1.0)) == expected


def test_point_particles_touch_only_head_on():
    assert float(ck.time_to_contact([0.0, 0.0], [1.0, 0.0], [4.0, 0.0], [0.0, 0.0], 0.0)) == 4.0
    assert math.isinf(ck.time_to_contact([0.0, 0.0], [1.0, 0.0], [4.0, 1e-9], [0.0, 0.0], 0.0))


@given(ahead=st.floats(0.1, 20.0), offset=st.floats(-0.9, 0.9), speed=st.floats(0.1, 5.0), sigma=st.floats(0.1, 3.0),
       length_exponent=st.integers(-900, 900), speed_exponent=st.integers(-900, 900))
def test_time_to_contact_scales_exactly_with_lengths_and_speeds(ahead, offset, speed, sigma, length_exponent,
                                                                  speed_exponent):
    # t(2^a r, 2^b u, 2^a sigma) = 2^(a - b) t: lengths of 1e200 gave nan, of 1e-200 a miss (inf)
    x2, v1 = np.array([sigma + ahead, offset * sigma]), np.array([speed, 0.0])  # on course to touch
    t = ck.time_to_contact([0.0, 0.0], v1, x2, [0.0, 0.0], sigma)
    assert math.isfinite(t) and t > 0
    scaled = ck.time_to_contact([0.0, 0.0], np.ldexp(v1, speed_exponent), np.ldexp(x2, length_exponent), [0.0, 0.0],
                                math.ldexp(sigma, length_exponent))
    with np.errstate(over="ignore", under="ignore"):  # beyond the float range t is inf (or 0) on both sides
        assert scaled == float(np.ldexp(t, length_exponent - speed_exponent))


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"contact_distance": -1.0}, "contact_distance"),
        ({"contact_distance": np.inf}, "contact_distance"),
        ({"x1": [np.nan, 0.0]}, "x1"),
        ({"x2": [np.inf, 0.0]}, "x2"),
        ({"v1": [np.nan, 0.0]}, "v1"),
        ({"v2": [np.nan, 0.0]}, "v2"),
        ({"x2": [1.0, 0.0, 0.0]}, "dimension"),
    ],
)
def test_time_to_contact_bad_input(kwargs, words):
    arguments = {"x1": [0.0, 0.0], "v1": [1.0, 0.0], "x2": [3.0, 0.0], "v2": [0.0, 0.0], "contact_distance": 1.0}
    arguments.update(kwargs)
    with pytest.raises(ValueError, match=words):
        ck.time_to_contact(**arguments)


# ---------------------------------------------------------------- collide


@given(
    m1=masses,
    m2=masses,
    x2=vectors(3, 20.0),
    v1=vectors(3, 5.0),
    v2=vectors(3, 5.0),
    sigma=st.floats(0.1, 3.0),
    e=restitutions,
)
# a graze at relative speed 4e-20: contact at t = 2.5e19, where the lab positions (~2.5e19) keep no digit of
# sigma = 1, so the line of centres must come from the relative state (as collide takes it)
@example(m1=1.0, m2=1.0, x2=np.array([0.0, 1.0, 1.0]), v1=np.array([4e-20, 4e-20, 1.0]),
         v2=np.array([4e-20, 0.0, 1.0]), sigma=1.0, e=0.0)
def test_collide_is_detection_then_resolution_at_contact(m1, m2, x2, v1, v2, sigma, e):
    x1 = np.zeros(3)
    assume(np.linalg.norm(x2) > sigma * 1.001)
    c = ck.collide(m1, x1, v1, m2, x2, v2, sigma, restitution=e)
    t = ck.time_to_contact(x1, v1, x2, v2, sigma)
    assert bool(c.hit) == math.isfinite(t)
    if c.hit:
        np.testing.assert_allclose(c.x1, x1 + v1 * t)
        np.testing.assert_allclose(c.x2, x2 + v2 * t)
        separation = (x2 - x1) + (v2 - v1) * t
        assert np.linalg.norm(separation) == pytest.approx(sigma, rel=1e-9)
        expected = ck.resolve_contact(m1, v1, m2, v2, separation, e)
        scale = np.abs(v1).sum() + np.abs(v2).sum()
        np.testing.assert_allclose(c.v1, expected[0], atol=1e-9 * scale)
        np.testing.assert_allclose(c.v2, expected[1], atol=1e-9 * scale)
        np.testing.assert_allclose(np.linalg.norm(c.normal), 1.0)
    else:
        np.testing.assert_array_equal(c.x1, x1)
        np.testing.assert_array_equal(c.v2, v2)
        assert math.isinf(c.time)


def test_collide_on_arrays_mixes_hits_and_misses():
    x2 = np.array([[3.0, 0.0], [3.0, 5.0], [-3.0, 0.0]])
    c = ck.collide(1.0, [0.0, 0.0], [1.0, 0.0], 1.0, x2, [0.0, 0.0], 1.0)
    np.testing.assert_array_equal(c.hit, [True, False, False])
    np.testing.assert_array_equal(c.time, [2.0, np.inf, np.inf])
    np.testing.assert_array_equal(c.x1, [[2.0, 0.0], [0.0, 0.0], [0.0, 0.0]])
    np.testing.assert_array_equal(c.v1, [[0.0, 0.0], [1.0, 0.0], [1.0, 0.0]])
    np.testing.assert_array_equal(c.v2, [[1.0, 0.0], [0.0, 0.0], [0.0, 0.0]])
    assert "hits=1" in repr(c)


def test_collide_resolves_overlapping_pair_now_along_current_line_of_centres():
    c = ck.collide(1.0, [0.0, 0.0], [0.0, 0.0], 1.0, [0.6, 0.0], [-1.0, 0.0], 1.0)
    assert bool(c.hit) and float(c.time) == 0.0
    np.testing.assert_array_equal(c.v1, [-1.0, 0.0])
    np.testing.assert_array_equal(c.v2, [0.0, 0.0])


def test_collide_point_particles_head_on():
    c = ck.collide(1.0, [0.0, 0.0], [1.0, 0.0], 3.0, [4.0, 0.0], [0.0, 0.0], 0.0)
    assert float(c.time) == 4.0
    np.testing.assert_allclose(c.v1, [-0.5, 0.0])
    np.testing.assert_allclose(c.v2, [0.5, 0.0])


def test_newtons_cradle_passes_the_velocity_down_the_line():
    # five touching equal balls; the first arrives with speed 1
    positions = np.array([[-1.0], [1.0], [2.0], [3.0], [4.0]])
    velocities = np.array([[1.0], [0.0], [0.0], [0.0], [0.0]])
    for i in range(4):
        c = ck.collide(1.0, positions[i], velocities[i], 1.0, positions[i + 1], velocities[i + 1], 1.0)
        assert bool(c.hit)
        positions[i], positions[i + 1] = c.x1, c.x2
        velocities[i], velocities[i + 1] = c.v1, c.v2
    np.testing.assert_array_equal(velocities[:, 0], [0.0, 0.0, 0.0, 0.0, 1.0])


# ------------------------------------------------------------------ edge cases found by a mutation audit


@pytest.mark.parametrize("model", ["normal", "cm"])
@pytest.mark.parametrize("e", [0.0, 0.5, 1.0])
def test_separating_and_sliding_pairs_do_not_change_in_either_model(model, e):
    # kills K20 (_kernels/collisions.py: `approach <= 0.0` -> `approach < 0.0`): a sliding pair
    # (u_n = 0 exactly) in the cm model had its whole relative velocity scaled by R.
    # Documented: "Only approaching pairs (u_n > 0) change; others are copies" -> exact equality.
    v1 = np.array([[-1.0, 0.0], [0.0, 1.0], [0.0, 1.0]])
    v2 = np.array([[1.0, 0.0], [0.0, 0.0], [0.0, -2.0]])
    a1, a2 = ck.resolve_contact(1.0, v1, 3.0, v2, [1.0, 0.0], restitution=e, restitution_model=model)
    np.testing.assert_array_equal(a1, v1)
    np.testing.assert_array_equal(a2, v2)


def test_collide_with_coincident_centres_is_a_miss_not_an_error():
    # kills C06 (collisions.py: non-hit pairs given their (zero) separation as normal): the
    # kernel then raised "normal must be a non-zero vector" for a pair that never touches.
    # time_to_contact documents coincident centres as inf (no line of centres).
    x2 = np.array([[0.0, 0.0], [3.0, 0.0]])
    c = ck.collide(1.0, [0.0, 0.0], [0.0, 0.0], 1.0, x2, [[1.0, 0.0], [-1.0, 0.0]], 1.0)
    np.testing.assert_array_equal(c.hit, [False, True])
    np.testing.assert_array_equal(c.v1[0], [0.0, 0.0])
    np.testing.assert_array_equal(c.v2[0], [1.0, 0.0])
    np.testing.assert_array_equal(c.v1[1], [-1.0, 0.0])  # equal masses head-on: exchange


def test_collide_normal_is_nan_where_there_is_no_hit():
    # kills C09 (collisions.py: `np.nan` -> `0.0` for the normal of misses); Contact documents NaN.
    x2 = np.array([[3.0, 0.0], [3.0, 5.0]])
    c = ck.collide(1.0, [0.0, 0.0], [1.0, 0.0], 1.0, x2, [0.0, 0.0], 1.0)
    np.testing.assert_array_equal(c.normal[0], [1.0, 0.0])
    assert np.all(np.isnan(c.normal[1]))


@pytest.mark.parametrize(
    ("r", "u"),
    [
        ([-0.10242798290336577, 0.9947404225818652], [-0.9947404222210048, -0.10242798640790038]),
        ([-0.6262504937980549, -0.7796219077332887], [0.7796219114732363, -0.626250489142178]),
    ],
)
def test_touching_pair_approaching_at_a_shallow_angle_touches_now(r, u):
    # kills K44 (_kernels/collisions.py `gap <= 0.0` -> `gap < 0.0`): for a pair exactly touching
    # (|r|^2 == sigma^2 in floats) the mutant fell through to the discriminant
    # |u|^2 sigma^2 - |r x u|^2 = (r.u)^2 ~ 1e-17, which rounds below 0 here: inf ("never") instead
    # of the documented 0 for a touching, approaching pair. Preconditions checked in floats.
    r, u = np.array(r), np.array(u)
    assert r @ r == 1.0 and r @ u < 0  # touching sigma = 1, approaching
    assert float(ck.time_to_contact([0.0, 0.0], [0.0, 0.0], r, u, 1.0)) == 0.0
    c = ck.collide(1.0, [0.0, 0.0], [0.0, 0.0], 1.0, r, u, 1.0)
    assert bool(c.hit) and float(c.time) == 0.0


def test_moving_infinite_second_mass_in_cm_model_keeps_its_velocity():
    # kills K29 (_kernels/collisions.py `centre = b` -> `centre = a` when m2 is infinite): mirror of
    # test_moving_infinite_mass_in_cm_model_keeps_its_velocity. The CM frame is body 2's frame, so
    # v2' = v2 and v1' = v2 - R (v1 - v2) = -1 - 0.5 * 2 = -2 (all values dyadic: exact in floats).
    a1, a2 = ck.resolve_contact(1.0, [1.0, 0.0], np.inf, [-1.0, 0.0], [1.0, 0.0], 0.5, "cm")
    np.testing.assert_array_equal(a2, [-1.0, 0.0])
    np.testing.assert_array_equal(a1, [-2.0, 0.0])


@pytest.mark.parametrize(
    ("x2", "v2"),
    [([1e308, 0.0], [0.0, 0.0]), ([3.0, 0.0], [-1e308, 0.0])],
)
def test_separation_or_relative_velocity_beyond_the_largest_float_is_refused(x2, v2):
    # kills K37 (_kernels/collisions.py: the finiteness check of |x2 - x1| and |v2 - v1| -> `if False:`):
    # each input is finite, but x2 - x1 = 2e308 (or v2 - v1 = -2e308) overflows to inf, after which the
    # mutant returned a meaningless time (NaN or inf) instead of the documented SEPARATION_OVERFLOW error.
    with pytest.raises(ValueError, match="must be finite"):
        ck.time_to_contact([-1e308, 0.0], [1e308, 0.0], x2, v2, 1.0)
