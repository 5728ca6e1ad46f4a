"""Tests of the EDMD kernels themselves: contact and boundary times, the event queue's tournament tree."""

import math

import numba
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import optimize

from collisionkit._kernels import edmd as kernels
from collisionkit._kernels.edmd.motion import wrap_into_box


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
