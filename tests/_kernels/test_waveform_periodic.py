"""The trials of a waveform flight with B from the periodic solution (collisionkit._kernels.transport.waveform_periodic).

Independent checks: the equation of motion integrated numerically (solve_ivp, as in test_waveform_magnetic) for
chained trials of one flight (inside a piece, across knots and jumps, over periods); the phi-function flight
(shaped_flight, a different formula) to a few ulps over many random flights; the tables' flag at and away from
cyclotron resonance and for slopes steep beside W.
"""

import math

import numpy as np
import pytest

from collisionkit._kernels.transport.flight import derived_field, flown_position
from collisionkit._kernels.transport.waveform_magnetic import PERIODIC_GAP, shaped_flight
from collisionkit._kernels.transport.waveform_periodic import (
    DISPLACEMENT_TURN, periodic_displacement, periodic_flight_constants, periodic_trials, periodic_velocity,
)
from collisionkit.transport._waveform import shaped_record

from .test_waveform_magnetic import AMPLITUDE, PERIOD, SHAPES, _integrated

EPSILON = np.finfo(float).eps


def _record(shape, angle, w):
    theta = math.radians(angle)
    return shaped_record(derived_field(np.zeros(3), w * np.array([0.0, math.sin(theta), math.cos(theta)])),
                         AMPLITUDE, PERIOD, SHAPES[shape])


def _trials(record, w, v0, t0, taus):
    """Velocity, zeta and displacement at each of the increasing flight times ``taus``, the walk chained."""
    u0, k, g0, along, _, _, gap, turn = periodic_flight_constants(*v0, t0, record)
    piece, periods = k, 0.0
    for tau in taus:
        half = 0.5 * w * tau
        vx, vy, vz, zeta, piece, periods, turn = periodic_velocity(along, g0, gap, u0, tau, math.sin(half),
                                                                   math.cos(half), piece, periods, turn,
                                                                   1.0 / PERIOD, 1.0 / w, record)
        moved = periodic_displacement(*v0, zeta, u0, k, tau, math.sin(half), math.cos(half), 1.0 / w, record)
        yield np.array([vx, vy, vz]), np.array(moved), u0, k


@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize("angle, w", [(90.0, 3.0), (60.0, 40.0), (30.0, 5.0)])
def test_chained_trials_solve_the_equation_of_motion(shape, angle, w):
    record = _record(shape, angle, w)
    assert periodic_trials(record)
    rng = np.random.default_rng(int(angle) + int(w))
    omega = w * np.array([0.0, math.sin(math.radians(angle)), math.cos(math.radians(angle))])
    for _ in range(3):
        v0, t0 = rng.normal(size=3), rng.uniform(0.0, 5.0)
        taus = (1e-3, 0.05, 0.4, 0.69, 2.3)
        for tau, (v, moved, _, _) in zip(taus, _trials(record, w, v0, t0, taus)):
            x, v_ref = _integrated(SHAPES[shape], np.zeros(3), omega, t0, tau, v0)
            scale = np.linalg.norm(v0) + 3.0 * np.linalg.norm(AMPLITUDE) * tau
            np.testing.assert_allclose(v, v_ref, rtol=0, atol=2e-11 * scale)
            np.testing.assert_allclose(moved, x, rtol=0, atol=2e-11 * scale * tau)


@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize("angle, w", [(90.0, 3.0), (60.0, 40.0), (60.0, math.pi / PERIOD), (80.0, 400.0)])
def test_chained_trials_agree_with_the_phi_function_flight_to_a_few_ulps(shape, angle, w):
    """Both are exact: they differ by rounding, about an ulp of the speeds per radian of the gyration's phase
    (the rotation's argument W tau carries one) plus a few ulps of the field's velocity in a period."""
    record = _record(shape, angle, w)
    assert periodic_trials(record)
    rng = np.random.default_rng(7)
    speed_scale = 1.0 + 2.5 * np.linalg.norm(AMPLITUDE) * min(PERIOD, 2.0 / w)
    worst = 0.0
    for _ in range(60):
        v0, t0 = rng.normal(size=3), rng.uniform(0.0, 5.0)
        taus = np.sort(rng.uniform(0.0, 3.0, 4)) * rng.choice([1e-3, 0.1, 1.0])
        for tau, (v, moved, u0, k) in zip(taus, _trials(record, w, v0, t0, taus)):
            reference = shaped_flight(*v0, u0, k, tau, record)
            position = np.array(flown_position(0.0, 0.0, 0.0, *v0, tau, record)) + reference[3:]
            allowed = 64 * EPSILON * speed_scale * (1.0 + w * tau)
            assert np.abs(v - reference[:3]).max() <= allowed
            assert np.abs(moved - position).max() <= allowed * tau
            worst = max(worst, np.abs(v - reference[:3]).max() / allowed)
    assert worst > 0.0  # the two formulas are not the same code


def test_short_flights_take_the_displacement_of_the_phi_functions():
    """Below DISPLACEMENT_TURN: within a few ulps of the displacement itself (not of the flight's scale), where the
    formula across b would lose digits; and at W tau = 0 (a flight of no time) nothing moves."""
    record = _record("cosine", 60.0, 3.0)
    rng = np.random.default_rng(5)
    for fraction in (1e-6, 1e-3, 0.3, 0.99):
        for _ in range(20):
            v0, t0 = rng.normal(size=3) * rng.choice([1e-3, 1.0]), rng.uniform(0.0, 5.0)
            tau = fraction * DISPLACEMENT_TURN / 3.0
            (_, moved, u0, k), = _trials(record, 3.0, v0, t0, [tau])
            reference = shaped_flight(*v0, u0, k, tau, record)
            position = np.array(flown_position(0.0, 0.0, 0.0, *v0, tau, record)) + reference[3:]
            assert np.abs(moved - position).max() <= 16 * EPSILON * np.abs(position).max()
    (_, moved, _, _), = _trials(record, 3.0, np.array([1.0, 2.0, 3.0]), 1.0, [0.0])
    assert not moved.any()


def test_the_periodic_solution_is_refused_near_resonance_and_for_slopes_steep_beside_w():
    resonant = 2 * math.pi / PERIOD
    assert not periodic_trials(_record("cosine", 60.0, resonant))  # |1 - q| = 0
    gap = abs(1 - np.exp(-1j * resonant * 1.01 * PERIOD))
    assert (gap >= PERIODIC_GAP) == periodic_trials(_record("cosine", 60.0, resonant * 1.01))
    assert periodic_trials(_record("cosine", 60.0, resonant * 1.5))
    # W T = 0.035: the cosine's slopes over W^2 are thousands of times the periodic solution
    assert not periodic_trials(_record("cosine", 60.0, 0.05))
    assert periodic_trials(_record("square", 60.0, 3.0))  # flat pieces: L is f / (i W) only
    assert not periodic_trials(_record("cosine", 0.0, 3.0))  # E along B: no perpendicular amplitude
    no_b = shaped_record(derived_field(np.zeros(3), np.zeros(3)), AMPLITUDE, PERIOD, SHAPES["cosine"])
    assert not periodic_trials(no_b)


@pytest.mark.parametrize("shape", SHAPES)
def test_a_flight_chained_from_the_last_trial_has_the_constants_of_its_start_time(shape):
    """periodic_chained_constants from a trial's walk (its phase, piece and rotation times turn) against
    periodic_flight_constants from the collision time: the same piece, the rest to rounding."""
    from collisionkit._kernels.transport.waveform_periodic import periodic_chained_constants

    w = 7.0
    record = _record(shape, 60.0, w)
    rng = np.random.default_rng(11)
    for _ in range(50):
        v0, t0, tau = rng.normal(size=3), rng.uniform(0.0, 5.0), rng.exponential(0.3)
        u0, k, g0, along, _, _, gap, turn = periodic_flight_constants(*v0, t0, record)
        half = 0.5 * w * tau
        *_, piece, periods, turn = periodic_velocity(along, g0, gap, u0, tau, math.sin(half), math.cos(half), k, 0.0,
                                                     turn, 1.0 / PERIOD, 1.0 / w, record)
        rotation = complex(math.cos(w * tau), -math.sin(w * tau))
        v1 = rng.normal(size=3)  # the velocity after the collision
        chained = periodic_chained_constants(*v1, u0 + tau / PERIOD - periods, piece, rotation * turn, 1.0 / w, record)
        direct = periodic_flight_constants(*v1, t0 + tau, record)
        assert chained[1] == direct[1]
        assert chained[0] == pytest.approx(direct[0], abs=1e-14)
        np.testing.assert_allclose([chained[2], *chained[3:6]], [direct[2], *direct[3:6]], rtol=0, atol=1e-13)
        assert abs(chained[6] - direct[6]) < 1e-13 * (1 + abs(direct[6]))
        assert abs(chained[7] - direct[7]) < 1e-13
