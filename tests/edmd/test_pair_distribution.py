"""Tests of the pair distances behind g(r) (collisionkit.edmd._pair_distribution) and of g(r) as measured."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from collisionkit import edmd
from collisionkit.edmd import _pair_distribution


def brute_force_pair_histogram(points, box, periodic, r_max, bins):
    """Every ordered pair by numpy broadcasting: the independent route for the cell-list kernel."""
    separation = points[None, :, :] - points[:, None, :]
    for k, wrapped in enumerate(periodic):
        if wrapped:
            separation[..., k] -= box[k] * np.round(separation[..., k] / box[k])
    distance = np.sqrt(np.sum(separation**2, axis=-1))
    distance = distance[~np.eye(len(points), dtype=bool)]
    return np.histogram(distance, bins=bins, range=(0.0, r_max))[0]


@given(
    dim=st.sampled_from([2, 3]),
    count=st.integers(2, 120),
    sides=st.lists(st.floats(1.0, 9.0), min_size=3, max_size=3),
    periodic=st.lists(st.booleans(), min_size=3, max_size=3),
    reach=st.floats(0.05, 0.5),
    seed=st.integers(0, 2**32 - 1),
)
def test_pair_distance_histogram_counts_every_pair_once_each_way(dim, count, sides, periodic, reach, seed):
    # cells of 1, 2, 3 or more per axis, walls and periodic axes mixed (a channel), 2D and 3D
    box, periodic = np.array(sides[:dim]), np.array(periodic[:dim])
    points = np.random.default_rng(seed).uniform(0.0, box, size=(count, dim))
    r_max = reach * box.min()
    counts = _pair_distribution.pair_distance_histogram(points, box, periodic, r_max, 40)
    np.testing.assert_array_equal(counts, brute_force_pair_histogram(points, box, periodic, r_max, 40))


def test_contact_value_error_matches_the_scatter_of_poisson_pair_counts():
    """Synthetic histograms: pairs per bin Poisson with mean 2000 g(r), g = 2 - 3x + 5x^2 (x = r - sigma),
    counted twice as the sampler does. Over 400 replicas the scatter of the extrapolated contact value
    matches its reported error: var / mean(error^2) lies in [0.75, 1.3] (chi^2 with 399 dof: +-3.5 sd);
    counting each pair once in the Poisson weights makes the errors sqrt(2) too small (ratio 2)."""
    rng = np.random.default_rng(2)
    sigma = 1.0
    r = np.arange(1.0025, 1.2, 0.005)
    x = r - sigma
    g_true = 2 - 3 * x + 5 * x**2
    values, errors = [], []
    for _ in range(400):
        counts = 2.0 * rng.poisson(2000 * g_true)
        value, error = _pair_distribution.contact_value(r, counts / 4000.0, counts, sigma)
        values.append(value)
        errors.append(error)
    values, errors = np.array(values), np.array(errors)
    assert abs(values.mean() - 2.0) < 4 * values.std() / math.sqrt(values.size)
    ratio = values.var(ddof=1) / np.mean(errors**2)
    assert 0.75 < ratio < 1.3, ratio


def test_g_of_r_is_zero_inside_contact():
    # snapshots were taken at the last collision, whose pair sits at contact: 400 discs gave g = 0.115 in the bin
    # just inside contact, which hard discs cannot have (and an inflated contact value)
    system = edmd.random_fluid(2, 400, 0.3, seed=1)
    m = edmd.measure(system, collisions=40_000, blocks=20)
    step = m.rdf_r[1] - m.rdf_r[0]
    assert np.all(m.rdf[m.rdf_r + step / 2 <= 2 * np.max(system.radius)] == 0.0)


def test_g_of_r_of_a_dilute_gas_tends_to_one():
    # beyond two diameters a hard-disc gas has g = 1 + O(n^2); the N^2 normalisation gave (N - 1) / N = 0.95 here
    system = edmd.random_fluid(2, 20, 0.02, seed=2)
    m = edmd.measure(system, collisions=2000 * 20, blocks=2000)
    far = m.rdf[m.rdf_r > 4 * np.max(system.radius)]
    error = far.std() / math.sqrt(far.size)  # independent bins
    assert abs(far.mean() - 1.0) < 4 * error, (far.mean(), error)


def test_a_sparse_histogram_s_contact_value_is_unbiased():
    """Few pairs a bin (a dilute or small system): about 2.6 expected, 1 in 14 bins empty. Weights from the
    counts seen favoured the bins that came out low, and leaving out the empty ones pushed g up (1.57 here): the
    fit's weights now come from the fit. Over 2000 replicas the mean lies within 4 standard errors of the true 1.3
    and the errors match the scatter (var / mean(error^2) in [0.85, 1.15], chi^2 with 1999 dof: +-4.7 sd)."""
    rng = np.random.default_rng(5)
    r = np.arange(1.0025, 1.2, 0.005)
    ideal = 4.0 * (1.0 + 2.0 * (r - 1.0))  # pairs counted twice at g = 1, growing with the shell
    g_true = 1.3 - 0.8 * (r - 1.0)
    values, errors = [], []
    for _ in range(2000):
        counts = 2.0 * rng.poisson(0.5 * ideal * g_true)
        value, error = _pair_distribution.contact_value(r, counts / ideal, counts, 1.0, ideal)
        values.append(value)
        errors.append(error)
    values, errors = np.array(values), np.array(errors)
    assert abs(values.mean() - 1.3) < 4 * values.std() / math.sqrt(values.size), values.mean()
    assert 0.85 < values.var(ddof=1) / np.mean(errors**2) < 1.15
    few = 2.0 * rng.poisson(0.05 * ideal)  # about 5 pairs near contact: no value
    assert math.isnan(_pair_distribution.contact_value(r, few / ideal, few, 1.0, ideal)[0])


@pytest.mark.parametrize("options", [{}, {"periodic": (True, False)}, {"shear_rate": 0.3}, {"restitution": 0.2}])
def test_the_pair_that_just_collided_is_left_out_of_the_snapshot(options):
    # a run stops at a collision: its pair sits at contact, one pair more than at a random time; only that pair
    # goes (an inelastic cluster keeps others at contact, as at any time), with walls and under shear too
    positions, box = edmd.lattice("square", 12, 0.3)
    system = edmd.HardSphereSystem(positions, edmd.maxwell_boltzmann(np.ones(144), 2, seed=3), 0.5, box, **options)
    system.run(collisions=3000)
    points, offset, colliding = _pair_distribution._snapshot(system)
    assert len(colliding) == 1 and system._last_partner in colliding[0]
    now = system._folded()[0][:, :2]
    separation, _ = _pair_distribution._separations(system, now, colliding[:, 0], colliding[:, 1],
                                                     system._offset_at(system.time) if "shear_rate" in options else None)
    assert np.linalg.norm(separation) == pytest.approx(1.0, abs=1e-9)  # at contact at the last event
    raw = _pair_distribution._histogram(points, system, offset, 2.0, 200)
    kept = _pair_distribution.pair_histogram(system, 2.0, 200)
    # from the contact bin [1, 1.01), or the next if the pair has already flown past it by the snapshot
    assert raw.sum() - kept.sum() == 2 and np.flatnonzero(raw - kept).tolist() in ([100], [101])
    system.run(time=0.01)  # a run that stops at a time, not a collision: nothing to leave out
    assert len(_pair_distribution._snapshot(system)[2]) == 0


def test_a_small_dilute_system_gives_the_contact_value_of_the_equation_of_state():
    # 300 discs at eta 0.05: 1.94 on average before the collided pair was left out and empty bins fitted, against
    # Henderson's 1.084 (g(sigma) = (Z - 1) / (2 eta)); now within 3 standard errors of 12 seeds
    values, errors = [], []
    for seed in range(12):
        summary = edmd.EdmdRun(edmd.EdmdParameters(dim=2, particles=300, packing_fraction=0.05, seed=seed)).run().summary()
        values.append(summary["contact_value"])
        errors.append(summary["contact_value_error"])
    expected = (float(edmd.henderson(0.05)) - 1) / (2 * 0.05)
    assert abs(np.mean(values) - expected) < 3 * np.std(values, ddof=1) / math.sqrt(len(values))
    assert 0.3 < np.var(values, ddof=1) / np.mean(np.square(errors)) < 2.3  # chi^2 with 11 dof: 2.5 and 97.5 %
