"""The speed bound of the windows of a flight in E0 cos(omega t) with a static B, without static acceleration.

Independent check: the exact flight (:func:`oscillating_flown_velocity`, itself checked against numerical
integration in test_oscillating.py) sampled on a fine grid of each window; the bound must cover every sample.
"""

import math

import numpy as np
import pytest

from collisionkit._kernels.transport.ac_window import flight_envelope_ac, parallel_window
from collisionkit._kernels.transport.flight import derived_field
from collisionkit._kernels.transport.oscillating import oscillating_field, oscillating_flown_velocity

KINDS = ["no B", "oblique B", "resonance", "near resonance", "E along B"]


def _record(rng, kind):
    psi = 0.0 if kind == "E along B" else rng.uniform(0.0, math.pi)
    gyro = 0.0 if kind == "no B" else rng.uniform(0.1, 3.0)
    omega = gyro if kind == "resonance" else rng.uniform(0.05, 3.0)
    if kind == "near resonance":  # beta = 1/(|Omega| - omega) of 1e6 / |Omega|: D and P nearly cancel
        omega = gyro * (1.0 + 1e-6 * rng.choice([-1.0, 1.0]))
    b = np.array([0.0, math.sin(psi), math.cos(psi)])
    amplitude = np.array([0.0, 0.0, rng.uniform(-2.0, 2.0)])
    return oscillating_field(derived_field(np.zeros(3), gyro * b), amplitude, omega), np.linalg.norm(amplitude)


@pytest.mark.parametrize("kind", KINDS)
def test_chained_windows_bound_every_speed_of_the_flight(kind):
    """A flight cut into windows of random lengths: each window's bound covers the exact speed on a grid of
    it, and the parallel velocity and phase handed on equal the exact flight's at the window's end."""
    rng = np.random.default_rng(20 + KINDS.index(kind))
    for _ in range(20):
        record, accel = _record(rng, kind)
        omega = record[13]
        v0, t0 = rng.normal(size=3), rng.uniform(0.0, 20.0)
        c0, s0 = math.cos(omega * t0), math.sin(omega * t0)
        v_par, radius, w_speed, turning = flight_envelope_ac(*v0, c0, s0, record)
        p = record[26:29]
        assert v_par == pytest.approx(float(v0 @ p), abs=1e-15)
        c, s, start, turned = c0, s0, 0.0, turning
        for h in rng.uniform(0.01, 3.0, size=6):
            bound, v_par, c, s, turned = parallel_window(v_par, c, s, omega * (t0 + start), h, start + h, radius,
                                                         w_speed, turning, turned, float(np.linalg.norm(v0)), accel,
                                                         record)
            speeds = [math.hypot(*oscillating_flown_velocity(*v0, c0, s0, start + u, record)[:3])
                      for u in np.linspace(0.0, h, 301)]
            assert bound >= max(speeds) * (1 - 1e-12)
            end = oscillating_flown_velocity(*v0, c0, s0, start + h, record)
            assert v_par == pytest.approx(float(np.array(end[:3]) @ p), abs=1e-12 * (1 + abs(v_par)))
            assert (c, s) == pytest.approx(end[3:], abs=1e-12)
            start += h


def test_off_resonance_the_perpendicular_bound_is_the_gyration_about_the_particular_solution():
    """E perpendicular to B, from rest: zeta(t) = P(t) - P(t0) e^{-i |Omega| (t - t0)}, whose size reaches
    |P(t0)| + max |P| = R where the two line up (|Omega| and omega incommensurate): over 200 time units the
    speed never exceeds R and comes within 2 % of it (the bound is tight)."""
    record = oscillating_field(derived_field(np.zeros(3), np.array([0.0, 2.0, 0.0])), np.array([0.0, 0.0, 1.0]), 0.7)
    _, radius, w_speed, _ = flight_envelope_ac(0.0, 0.0, 0.0, 1.0, 0.0, record)
    assert w_speed == 0.0
    speeds = [math.hypot(*oscillating_flown_velocity(0.0, 0.0, 0.0, 1.0, 0.0, u, record)[:3])
              for u in np.linspace(0.0, 200.0, 40001)]
    assert max(speeds) <= radius * (1 + 1e-12)
    assert max(speeds) >= 0.98 * radius


def test_the_followed_gyration_bounds_the_speed_more_closely_than_the_flight_bound():
    """Oblique B off resonance (omega/|Omega| = 0.59, as in benchmarks/bench_fields.py), windows of a tenth of a
    gyration: the bound covers the exact speed on a grid of each window; its perpendicular part exceeds the
    largest exact |zeta| there by at most twice the particular solution's counter-rotating part (A/2) alpha (and
    1e-3 for the grid), and on average it exceeds the largest speed by less than half as much as the flight's
    bound R would (loose where the gyration and the particular solution do not line up)."""
    rng = np.random.default_rng(7)
    gyro, omega = 1.7, 1.0
    psi = math.radians(60.0)
    record = oscillating_field(derived_field(np.zeros(3), gyro * np.array([0.0, math.sin(psi), math.cos(psi)])),
                               np.array([0.0, 0.0, 1.0]), omega)
    slack = 0.5 * record[24] * record[31]
    followed, flight = [], []
    for _ in range(20):
        v0, t0 = rng.normal(size=3), rng.uniform(0.0, 20.0)
        c0, s0 = math.cos(omega * t0), math.sin(omega * t0)
        v_par, radius, w_speed, turning = flight_envelope_ac(*v0, c0, s0, record)
        c, s, start, h, turned = c0, s0, 0.0, 0.1 * 2.0 * math.pi / gyro, turning
        for _ in range(30):
            bound, v_par, c, s, turned = parallel_window(v_par, c, s, omega * (t0 + start), h, start + h, radius,
                                                         w_speed, turning, turned, math.inf, 1.0, record)
            flown = np.array([oscillating_flown_velocity(*v0, c0, s0, start + u, record)[:3]
                              for u in np.linspace(0.0, h, 101)])
            along = np.abs(flown @ record[26:29])
            across = np.linalg.norm(flown - (flown @ record[26:29])[:, None] * record[26:29], axis=1)
            top = np.linalg.norm(flown, axis=1).max()
            assert top * (1 - 1e-12) <= bound <= math.hypot(along.max(), across.max() + 2 * slack) * (1 + 1e-3)
            followed.append(bound - top)
            flight.append(math.hypot(along.max(), radius) - top)
            start += h
    assert np.mean(followed) < 0.5 * np.mean(flight)
