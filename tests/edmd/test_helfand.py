"""Tests of the Einstein-Helfand estimators (collisionkit.edmd._helfand) on series whose coefficients are known."""

import math

import numpy as np
import pytest
from scipy import signal, stats

from collisionkit.edmd import _helfand, _transport


def _random_walk(rng, steps, slope, interval, components=1):
    """A walk whose increments over an interval have variance slope * interval: <dX^2> = slope * t exactly."""
    return np.cumsum(rng.normal(scale=math.sqrt(slope * interval), size=(steps, components)), axis=0)


def test_block_curves_average_each_lag_over_the_origins_inside_each_block_only():
    """A walk stepping 1, then 3: inside a block every lag-k change is k * step; pairs across blocks never count."""
    walk = np.concatenate([np.arange(6.0), 5.0 + 3.0 * np.arange(1, 7)])[:, None]
    curves = _helfand.block_curves(walk, [(0, 6), (6, 12)], [1, 2, 6], lambda change: change[:, 0])
    np.testing.assert_array_equal(curves[:, :2], [[1.0, 2.0], [3.0, 6.0]])
    assert np.all(np.isnan(curves[:, 2]))  # no pair 6 apart inside a block of 6
    assert _helfand.block_slices([0, 0, 1, 1, 1, 3]) == [(0, 2), (2, 5), (5, 6)]


def test_the_einstein_fit_recovers_the_diffusive_slope_and_its_error_is_honest():
    """Random walks with <dX^2> = 2 D t: 300 replicas of 10 blocks give slopes whose scatter matches the quoted
    standard errors (chi^2 of the normalised deviations within its 1e-4 band) and whose mean is 2 D.
    Kills: a slope error of std / n, or fitted across blocks (correlated), or a biased window."""
    rng = np.random.default_rng(7)
    interval, slope = 0.25, 3.0
    lags = np.arange(1, 81)
    time = lags * interval
    deviations = []
    for _ in range(300):
        walk = _random_walk(rng, 4000, slope, interval)
        slices = [(k * 400, (k + 1) * 400) for k in range(10)]
        curves = _helfand.block_curves(walk, slices, lags, lambda change: change[:, 0] ** 2)
        fit = _helfand.einstein_fit(time, curves, (5.0, 20.0))
        deviations.append((fit.value - slope) / fit.error)
    deviations = np.array(deviations)
    assert abs(np.mean(deviations)) < 4 / math.sqrt(len(deviations))
    # the t-statistic of 10 blocks has variance 9/7: the sum of squares against chi^2(300) scaled by it
    scaled = np.sum(deviations**2) / (9 / 7)
    low, high = stats.chi2.ppf([1e-4, 1 - 1e-4], len(deviations))
    assert low < scaled < high, scaled / len(deviations)


def test_the_fit_window_opens_after_the_kinetic_regime_and_closes_before_the_noise():
    time = np.arange(1, 401) * 0.25
    # quiet curve: the window is [8, 32] free times of 1.5
    assert _helfand.fit_window(time, time, 0.01 * time, 1.5) == (12.0, 48.0)
    # a noisy curve (relative error t / 80) closes at the last lag within 25 %, t = 20
    assert _helfand.fit_window(time, time, time**2 / 80, 1.0) == (8.0, 20.0)
    # never shorter than twice its opening
    assert _helfand.fit_window(time, time, time**2, 1.0) == (8.0, 16.0)
    # blocks too short (lags up to 20): the window shrinks in proportion
    assert _helfand.fit_window(time[:80], time[:80], 0.01 * time[:80], 1.0) == (5.0, 20.0)


def test_green_kubo_of_an_ornstein_uhlenbeck_stress_is_the_integral_of_its_correlation():
    """Traceless components relaxing as exp(-t / tau) with variance s2: eta = V s2 tau / kT per component
    (the integral of the correlation), and the Einstein fit of the integrated series agrees with it."""
    rng = np.random.default_rng(3)
    interval, tau, s2, volume, kT = 0.05, 0.4, 2.0, 3.0, 1.5
    decay = math.exp(-interval / tau)
    steps = 100_000
    noise = rng.normal(scale=math.sqrt(s2 * (1 - decay**2)), size=(steps, 3, 3))
    noise[0] = rng.normal(scale=math.sqrt(s2), size=(3, 3))  # started in the stationary state
    stress = signal.lfilter([1.0], [1.0, -decay], noise, axis=0)  # P_k = decay P_k-1 + noise_k
    stress = 0.5 * (stress + stress.transpose(0, 2, 1))  # off-diagonal variance s2 / 2
    slices = [(k * 10_000, (k + 1) * 10_000) for k in range(10)]
    # exact: per off-diagonal component V (s2 / 2) * integral of the discrete correlation (trapezoid sum)
    expected = volume / kT * 0.5 * s2 * interval * (0.5 + decay / (1 - decay))
    value, error = _helfand.green_kubo_viscosity(stress, interval, volume, kT, slices, 20 * tau)
    assert abs(value - expected) < 4 * error, (value, expected, error)
    assert error < 0.06 * expected
    # the Einstein-Helfand form of the same series: the moment is the stress integral, G_k = V dt sum_j<k P_j
    moment = np.concatenate([np.zeros((1, 3, 3)), volume * interval * np.cumsum(stress, axis=0)])
    lags = np.arange(80, 321, 16)
    curves = _helfand.block_curves(moment, [(0, 50_000), (50_000, steps + 1)], lags, _transport._shear)
    fit = _helfand.einstein_fit(lags * interval, curves / (2 * volume * kT), (10 * tau, 40 * tau))
    assert fit.value == pytest.approx(expected, rel=4 * error / expected)
