"""The kinetic theory of rough spheres: the collision averages against a Monte Carlo of the rule, Luding's form."""

import math

import numpy as np
import pytest

from collisionkit.edmd import rough_cooling, rough_cooling_matrix, rough_cooling_state


def _sampled_energy_changes(dim, e, beta, kappa, kT, kT_rotation, pairs=400_000, seed=7):
    """Mean translational and rotational energy change per collision of Maxwellian pairs (unit masses, radius 1/2),
    with its standard errors: pairs drawn at random, weighted by the approach speed (the collision rate)."""
    rng = np.random.default_rng(seed)
    radius, inertia = 0.5, kappa * 0.25
    v = rng.normal(0.0, math.sqrt(kT), (pairs, 2, 3))
    w = rng.normal(0.0, math.sqrt(kT_rotation / inertia), (pairs, 2, 3))
    n = rng.normal(size=(pairs, 3))
    if dim == 2:
        v[..., 2] = 0.0
        w[..., :2] = 0.0
        n[:, 2] = 0.0
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    u = v[:, 1] - v[:, 0]
    weight = np.maximum(-np.sum(u * n, axis=1), 0.0)  # only approaching pairs collide, at a rate |u_n|
    # the surfaces' relative velocity at the contact point (j's minus i's), n from i to j
    g = u + np.cross(w[:, 1], -radius * n) - np.cross(w[:, 0], radius * n)
    g_n = np.sum(g * n, axis=1, keepdims=True) * n
    g_t = g - g_n
    impulse = -(1 + e) * 0.5 * g_n - (1 + beta) * (0.5 * kappa / (1 + kappa)) * g_t  # on j; -impulse on i
    v_new = v + np.stack([-impulse, impulse], axis=1)
    w_new = w + np.stack([np.cross(radius * n, -impulse), np.cross(-radius * n, impulse)], axis=1) / inertia
    translation = 0.5 * np.sum(v_new**2 - v**2, axis=(1, 2))
    rotation = 0.5 * inertia * np.sum(w_new**2 - w**2, axis=(1, 2))
    total = weight.sum()
    means = [float(np.sum(weight * change) / total) for change in (translation, rotation)]
    errors = [float(np.sqrt(np.sum(weight**2 * (change - mean) ** 2)) / total)
              for change, mean in zip((translation, rotation), means)]
    return np.array(means), np.array(errors)


@pytest.mark.parametrize("dim, e, beta, kappa, kT_rotation", [
    (3, 0.9, 0.5, 0.4, 0.7), (3, 0.7, -0.3, 0.25, 1.6), (3, 1.0, 1.0, 0.4, 0.2),
    (2, 0.8, 0.2, 0.5, 1.3), (2, 1.0, 0.9, 0.8, 0.5),
])
def test_the_collision_averages_are_those_of_a_monte_carlo_of_the_collision_rule(dim, e, beta, kappa, kT_rotation):
    means, errors = _sampled_energy_changes(dim, e, beta, kappa, 1.0, kT_rotation)
    # c counts collisions per particle, two per collision: dT/dc = <dE_tr> / d and dT_r/dc = <dE_rot> / f
    degrees = np.array([dim, 3 if dim == 3 else 1])
    theory = degrees * (rough_cooling_matrix(e, beta, kappa, dim) @ [1.0, kT_rotation])
    assert np.all(np.abs(means - theory) < 4.5 * errors), (means, theory, errors)


def test_in_3d_the_matrix_is_luding_et_al_s():
    """Luding, Huthmann, McNamara & Zippelius, PRE 58, 3416 (1998): dT/dt = G (-A T + B T_r) T^(1/2), dT_r/dt =
    G (B T - C T_r) T^(1/2); per collision per particle (G T^(1/2) dt = 4/3 dc in these units) the same with 4/3."""
    e, beta, q = 0.85, 0.3, 0.4
    eta = q * (1 + beta) / (2 * (1 + q))
    A, B, C = (1 - e * e) / 4 + eta * (1 - eta), eta * eta / q, (eta / q) * (1 - eta / q)
    np.testing.assert_allclose(rough_cooling_matrix(e, beta, q, 3), (4 / 3) * np.array([[-A, B], [B, -C]]),
                               rtol=1e-14)


@pytest.mark.parametrize("dim", [2, 3])
def test_smooth_spheres_cool_by_haff_and_elastic_rough_ones_keep_the_energy(dim):
    e = 0.8
    assert rough_cooling_matrix(e, -1.0, None, dim) == pytest.approx(np.array([[-(1 - e * e) / dim, 0], [0, 0]]))
    rotation = 3 if dim == 3 else 1
    for beta in (-1.0, 1.0):
        energy = dim * rough_cooling_matrix(1.0, beta, 0.3, dim)[0] + rotation * rough_cooling_matrix(1.0, beta, 0.3,
                                                                                                     dim)[1]
        assert np.abs(energy).max() < 1e-15
    ratio, rate = rough_cooling_state(0.8, -1.0, None, dim)
    assert math.isnan(ratio) and rate == pytest.approx((1 - e * e) / dim)


def test_the_temperatures_solve_the_equations_and_settle_to_the_cooling_state():
    e, beta = 0.9, 0.4
    c = np.array([2.0, 2.0 + 1e-6, 80.0])
    T, T_r = rough_cooling(1.0, 1.0, c, e, beta)
    slope = np.array([T[1] - T[0], T_r[1] - T_r[0]]) / 1e-6
    np.testing.assert_allclose(slope, rough_cooling_matrix(e, beta) @ [T[0], T_r[0]], rtol=1e-5)
    ratio, rate = rough_cooling_state(e, beta)
    assert T_r[2] / T[2] == pytest.approx(ratio, rel=1e-9)
    later, _ = rough_cooling(1.0, 1.0, 81.0, e, beta)
    assert -math.log(later / T[2]) == pytest.approx(rate, rel=1e-9)
    with pytest.raises(ValueError, match="tangential_restitution"):
        rough_cooling_matrix(0.9, 1.2)


@pytest.mark.parametrize("e, beta, q", [(0.9, 0.5, 0.4), (0.7, -0.5, 0.4), (0.95, 0.0, 0.25), (0.5, 1.0, 2 / 3)])
def test_the_cooling_state_ratio_is_luding_et_al_s_closed_form(e, beta, q):
    """Luding et al. 1998, eq. (9): T_r/T of the cooling state from -A + B R = B/R - C (both temperatures decaying
    at one rate), R = [A - C + sqrt((A - C)^2 + 4 B^2)] / (2 B) in their A, B, C; the rate is then (4/3)(A - B R)."""
    eta = q * (1 + beta) / (2 * (1 + q))
    A, B, C = (1 - e * e) / 4 + eta * (1 - eta), eta * eta / q, (eta / q) * (1 - eta / q)
    closed = (A - C + math.sqrt((A - C) ** 2 + 4 * B * B)) / (2 * B)
    ratio, rate = rough_cooling_state(e, beta, q, 3)
    assert ratio == pytest.approx(closed, rel=1e-12)
    assert rate == pytest.approx(4 / 3 * (A - B * closed), rel=1e-12)
