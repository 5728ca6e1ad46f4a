"""Tests of the EDMD kernels themselves: contact and boundary times, the event queue's tournament tree."""

import math

import numba
import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy import optimize

from collisionkit._kernels import edmd as kernels
from collisionkit._kernels.edmd.motion import minimum_image, pair_image, wrap_into_box


@settings(max_examples=400, deadline=None)
@given(st.floats(-1.5, 1.5), st.floats(0.25, 1e3), st.booleans())
@example(0.5, 10.0, True)  # exactly half a box: no image either way
@example(-0.5, 10.0, True)
@example(0.5000000000000001, 10.0, True)
@example(-1.5, 10.0, False)
def test_pair_image_is_the_minimum_image_bit_for_bit(fraction, length, periodic):
    """The pair tests' branch-free image (small boxes) equals the branching one, also at half a box and for walls."""
    dx = fraction * length
    half = 0.5 * length if periodic else math.inf
    expected = minimum_image(dx, length, half)
    image = pair_image(dx, length, half)
    assert image == expected  # bit for bit: 0.0 == -0.0 is the one difference allowed
    assert abs(image) <= half * (1 + 4 * np.finfo(float).eps) if periodic else image == dx  # |dx| - L rounded


@pytest.mark.parametrize("growth", [0.0, 0.05, 0.5])
def test_pair_contact_time_matches_root_finding(growth):
    rng = np.random.default_rng(5)
    contact, scale = 1.0, 0.7
    times = np.linspace(0, 20, 40001)
    hits = misses = 0
    for _ in range(200):
        r = rng.normal(size=3) * 2
        if np.linalg.norm(r) <= contact * scale:
            continue
        u = -r * rng.uniform(0, 1) + rng.normal(size=3) * 0.5  # mostly approaching
        tau = kernels.pair_contact_time(*r, *u, contact, scale, growth, np.inf)

        def gap(t):
            return np.linalg.norm(r + np.multiply.outer(t, u), axis=-1) - contact * (scale + growth * t)

        crossing = np.flatnonzero(gap(times) <= 0)
        if crossing.size == 0:
            assert tau == math.inf or tau > times[-2]
            misses += 1
            continue
        first = crossing[0]
        expected = optimize.brentq(lambda t: float(gap(np.array(t))), times[first - 1], times[first], xtol=1e-14)
        assert tau == pytest.approx(expected, rel=1e-9, abs=1e-12)
        hits += 1
    assert hits > 30 and misses > 5


def test_boundary_root_cases():
    # a point 1 below a boundary moving up at 2: reaches it at 0.5
    assert kernels.first_root_from_below(0.0, 2.0, -1.0) == 0.5
    # thrown up against gravity it turns back before the boundary
    assert kernels.first_root_from_below(-1.0, 1.0, -1.0) == math.inf
    # accelerating towards it from rest: 0.5 t^2 = 2
    assert kernels.first_root_from_below(0.5, 0.0, -2.0) == pytest.approx(2.0, rel=1e-15)
    # round-off past the boundary but moving out: now
    assert kernels.first_root_from_below(0.0, 1.0, 1e-17) == 0.0


@numba.njit
def _apply_queue_updates(updates, queue, tree, leaves):
    """Apply (particle, time) updates through the kernel; return the tree's winner after each."""
    winners = np.empty((len(updates), 2))
    for k in range(len(updates)):
        kernels.queue_update(int(updates[k, 0]), updates[k, 1], queue, tree, leaves)
        winners[k, 0] = tree[1, 0]
        winners[k, 1] = tree[1, 1]
    return winners


@settings(max_examples=60, deadline=None)
@given(
    count=st.integers(1, 40),
    updates=st.lists(st.tuples(st.integers(0, 39), st.sampled_from([0.0, 0.5, 1.0, 2.0, math.inf])), max_size=60),
)
def test_event_queue_gives_the_earliest_event_lowest_index_on_ties(count, updates):
    blocks = -(-count // kernels.QUEUE_BLOCK)
    leaves = 1 << max(blocks - 1, 1).bit_length()
    queue = np.full(blocks * kernels.QUEUE_BLOCK, math.inf)
    queue[:count] = np.linspace(3.0, 4.0, count)
    tree = np.zeros((2 * leaves, 2))
    kernels.tree_build(tree, queue, leaves)
    reference = queue[:count].copy()
    assert tree[1, 1] == 0
    steps = np.array([(i % count, when) for i, when in updates], dtype=float).reshape(-1, 2)
    winners = _apply_queue_updates(steps, queue, tree, leaves)
    for (i, when), (winner_time, winner) in zip(steps, winners):
        reference[int(i)] = when
        assert winner_time == reference.min()
        assert winner == np.flatnonzero(reference == reference.min())[0]


@numba.njit
def _wrap(p, geom, image, b, acc, params):
    wrap_into_box(p, 0, geom, 2, image, b, acc, params)


def test_wrapping_a_particle_keeps_its_unwrapped_position_and_takes_back_the_moments_jump():
    """x + image L is continuous through a wrap, also when -tiny + L rounds to L (the particle is put at 0 in its
    own image); the image slots take back the jump of sum m v_a x_b and sum (m v^2 / 2) x_b."""
    geom = np.zeros((4, 3))
    geom[kernels.G_BOX] = [10.0, 10.0, 1.0]
    geom[kernels.G_PERIODIC, :2] = 1.0
    b = np.zeros((1, 8))
    b[0, kernels.MASS] = 2.0
    for x, wrapped, shift in ((10.5, 0.5, 1), (-1e-20, 0.0, 0), (-0.25, 9.75, -1)):
        p = np.zeros((1, 8))
        p[0, kernels.X : kernels.X + 2] = [x, 3.0]
        p[0, kernels.V : kernels.V + 2] = [1.5, -2.0]
        image, acc = np.zeros((1, 2), dtype=np.int64), np.zeros(kernels.ACC_SIZE)
        _wrap(p, geom, image, b, acc, np.zeros(kernels.P_SIZE))
        assert p[0, kernels.X] == wrapped and image[0, 0] == shift and image[0, 1] == 0
        moved = wrapped - x
        np.testing.assert_allclose(acc[kernels.ACC_MOMENTUM_IMAGE : kernels.ACC_MOMENTUM_IMAGE + 9],
                                   [-3.0 * moved, 0, 0, 4.0 * moved, 0, 0, 0, 0, 0], rtol=1e-15)
        assert acc[kernels.ACC_ENERGY_IMAGE] == pytest.approx(-0.5 * 2.0 * 6.25 * moved, rel=1e-15)


def test_sheared_wrap_moves_a_particle_to_its_sliding_image():
    """Through y = L_y a particle becomes its image below: x back by the offset at its time, v_x down by G L_y."""
    geom = np.zeros((4, 3))
    geom[kernels.G_BOX] = [10.0, 8.0, 1.0]
    geom[kernels.G_PERIODIC, :2] = 1.0
    params = np.zeros(kernels.P_SIZE)
    params[kernels.P_SHEAR_RATE] = 0.5
    params[kernels.P_SHEAR_OFFSET] = 3.0
    b = np.zeros((1, 8))
    b[0, kernels.MASS] = 1.0
    time = 2.0  # offset 3 + 0.5 * 8 * 2 = 11, 1 modulo 10
    for y, x, wrapped_x, wrapped_y, velocity, images in (
        (8.25, 4.0, 3.0, 0.25, 1.5 - 4.0, (0, 1)),  # up through L_y: x - 11 + 10
        (-0.5, 9.5, 0.5, 7.5, 1.5 + 4.0, (1, -1)),  # down through 0: x + 11 - 20
        (-1e-20, 2.0, 2.0, 0.0, 1.5, (0, 0)),  # -tiny + L_y rounds to L_y: at 0, no move
    ):
        p = np.zeros((1, 8))
        p[0, kernels.X : kernels.X + 2] = [x, y]
        p[0, kernels.V : kernels.V + 2] = [1.5, -2.0]
        p[0, kernels.T] = time
        image, acc = np.zeros((1, 2), dtype=np.int64), np.zeros(kernels.ACC_SIZE)
        _wrap(p, geom, image, b, acc, params)
        assert p[0, kernels.X] == pytest.approx(wrapped_x, abs=1e-12) and p[0, kernels.X + 1] == wrapped_y
        assert p[0, kernels.V] == velocity and tuple(image[0]) == images
        # its velocity relative to the flow G (y - L_y / 2) is unchanged
        assert velocity - 0.5 * (wrapped_y - 4.0) == pytest.approx(1.5 - 0.5 * (y - 4.0), abs=1e-12)


def test_shear_map_moves_two_points_together_by_at_most_half_the_strain():
    """The bound behind the sheared lists: |(dx + s dy, dy, dz)| >= (1 - |s| / 2) |(dx, dy, dz)|.

    The smallest singular value of [[1, s], [0, 1]] is sqrt(1 + s^2 / 4) - |s| / 2; checked here over
    directions on a fine grid (an independent minimisation), and that the bound is nearly reached.
    """
    angles = np.linspace(0.0, 2.0 * np.pi, 200001)
    for s in (-1.5, -0.25, 0.01, 0.25, 0.5, 1.0):
        stretched = np.hypot(np.cos(angles) + s * np.sin(angles), np.sin(angles))
        assert stretched.min() >= 1.0 - abs(s) / 2.0 - 1e-12
        assert stretched.min() == pytest.approx(math.sqrt(1.0 + s * s / 4.0) - abs(s) / 2.0, abs=1e-9)


def _sheared_particle(rng, dim):
    """One particle's records under shear, its anchor a little off (as after some flight), and the parameters."""
    p = np.zeros((1, 8))
    b = np.zeros((1, 8))
    third = 1.0 if dim == 3 else 0.0
    geom = np.array([[12.0, 9.0, 10.0 if dim == 3 else 1.0], [1.5, 1.5, 1.5], [0.0] * 3, [1.0, 1.0, third]])
    params = np.zeros(kernels.P_SIZE)
    params[kernels.P_SHEAR_RATE] = rng.choice([-1.0, 1.0]) * rng.uniform(0.05, 1.0)
    params[kernels.P_SHELL] = 0.6
    params[kernels.P_SHEAR_REACH] = 1.6
    params[kernels.P_SHEAR_FRAME] = -rng.uniform(0.0, 0.2)
    t = 0.3
    p[0, kernels.T] = t
    p[0, kernels.V : kernels.V + dim] = rng.normal(size=dim)
    b[0, kernels.ANCHOR : kernels.ANCHOR + dim] = rng.uniform(0.0, 1.0, size=dim) * geom[0, :dim]
    flow = params[kernels.P_SHEAR_RATE] * (b[0, kernels.ANCHOR + 1] - 0.5 * geom[0, 1])
    if rng.uniform() < 0.5:
        # carried by the flow to near the x limit (a quarter box outside): the other cause of expiry
        lx = geom[0, 0]
        edge = 1.25 * lx - 0.3 if flow > 0 else -0.25 * lx + 0.3
        params[kernels.P_SHEAR_FRAME] = t - (edge - b[0, kernels.ANCHOR]) / flow
    anchor_time = np.array([t - rng.uniform(0.0, 0.2)])
    offset = rng.normal(size=dim) * 0.05
    p[0, kernels.X : kernels.X + dim] = b[0, kernels.ANCHOR : kernels.ANCHOR + dim] + offset
    p[0, kernels.X] += flow * (t - params[kernels.P_SHEAR_FRAME])
    return p, b, anchor_time, geom, params, flow


@pytest.mark.parametrize("dim", [2, 3])
def test_sheared_list_expiry_spends_the_budget_exactly(dim):
    """The sheared list's expiry is the first time |x - x_a(t)| + |G| R / 4 (t - t_a) reaches shell / 2, or the time x
    strays a quarter box out, whichever is first: brute-force root finding on a fine grid of the same function,
    written here from the definitions (the anchor carried by the flow at its height)."""
    from collisionkit._kernels.edmd.prediction import sheared_list_expiry

    rng = np.random.default_rng(11)
    taus = np.linspace(0.0, 3.0, 300001)
    checked = strays = 0
    for _ in range(300):
        p, b, anchor_time, geom, params, flow = _sheared_particle(rng, dim)
        tau = sheared_list_expiry(p, 0, b, anchor_time, geom, dim, params)
        x = p[0, kernels.X : kernels.X + dim] + np.multiply.outer(taus, p[0, kernels.V : kernels.V + dim])
        anchor = np.tile(b[0, kernels.ANCHOR : kernels.ANCHOR + dim], (taus.size, 1))
        anchor[:, 0] += flow * (p[0, kernels.T] + taus - params[kernels.P_SHEAR_FRAME])
        ageing = abs(params[kernels.P_SHEAR_RATE]) * params[kernels.P_SHEAR_REACH] / 4.0
        away = x - anchor
        away[:, 0] -= geom[0, 0] * np.round(away[:, 0] / geom[0, 0])  # the anchor's frame x is kept in the box
        spent = np.linalg.norm(away, axis=1) + ageing * (p[0, kernels.T] - anchor_time[0] + taus)
        lx = geom[0, 0]
        out = (x[:, 0] < -0.25 * lx) | (x[:, 0] > 1.25 * lx)
        over = np.flatnonzero((spent >= 0.5 * params[kernels.P_SHELL]) | out)
        if over.size == 0:
            assert tau > taus[-1]
            continue
        expected = taus[over[0]]
        assert expected - 2e-5 <= tau <= expected + 1e-12
        checked += 1
        strays += bool(out[over[0]])
    assert checked > 200 and 0 < strays < checked  # both causes of expiry seen
