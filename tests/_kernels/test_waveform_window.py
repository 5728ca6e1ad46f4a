"""The window bound of a flight in a periodic waveform, with and without B (waveform_window).

Independent checks: the extremes of G1 against a fine grid of the quadrature of f (scipy quad); the periodic
solution against the exact flight (itself checked against solve_ivp in test_waveform_magnetic) from P(0) over a
period; the window bound against the exact speed on a fine grid of random windows (short, across jumps, longer
than a period), with B at 0 to 90 degrees and at cyclotron resonance (|Omega| T = 2 pi); without B it is reached.
"""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from collisionkit._kernels.transport.flight import derived_field
from collisionkit._kernels.transport.waveform_magnetic import shaped_velocity
from collisionkit._kernels.transport.waveform_window import (
    periodic_start, shaped_flight_constants, shaped_tight_window, window_extremes, window_range,
)
from collisionkit.transport._waveform import shaped_record, waveform_knots

SHAPES = {
    "square": [(0.0, 1.0), (0.5, 1.0), (0.5, -1.0), (1.0, -1.0)],
    "offset sawtooth": [(0.0, -0.4), (1.0, 1.0)],
    "irregular": [(0.1, 0.3), (0.2, -2.0), (0.2, 1.5), (0.65, 0.4), (0.9, 2.5)],
    "cosine": [(k / 16, math.cos(2 * math.pi * k / 16)) for k in range(16)],
}
PERIOD = 0.7
AMPLITUDE = np.array([0.0, 0.0, 1.3])


def _f(samples):
    knots, values = waveform_knots(samples)

    def f(u):
        r = u - math.floor(u)
        k = min(int(np.searchsorted(knots, r, side="right")) - 1, len(knots) - 2)
        return values[k] + (values[k + 1] - values[k]) * (r - knots[k]) / (knots[k + 1] - knots[k]) \
            if knots[k + 1] > knots[k] else values[k]
    return f, knots


@pytest.mark.parametrize("shape", SHAPES)
def test_the_extremes_of_g1_over_a_window_are_those_of_its_quadrature(shape):
    f, knots = _f(SHAPES[shape])
    record = shaped_record(derived_field(np.zeros(3), np.zeros(3)), AMPLITUDE, PERIOD, SHAPES[shape])
    n = len(knots)
    rng = np.random.default_rng(len(shape))
    for length in (0.01, 0.2, 0.7, 1.5, 3.2):
        u0 = rng.uniform(0.0, 3.0)
        grid = np.linspace(u0, u0 + length, 2001)
        points = sorted({*grid, *(k + m for m in range(8) for k in knots if k + m < u0 + length)})
        g1, values = 0.0, []
        for a, b in zip([0.0, *points], points):  # integrated piece by piece from 0 (quad across a jump is inexact)
            g1 += quad(f, a, b, epsabs=1e-14, limit=200)[0] if b > a else 0.0
            if b >= u0:
                values.append(g1)
        low, high, _, _, _ = window_extremes(u0, u0 + length, record, n, 0, 0.0, 0)
        step = length / 2000 * np.abs(record[36 + n:36 + 2 * n]).max()  # G1 moves at most this between grid points
        assert low <= min(values) + 1e-12 and high >= max(values) - 1e-12
        if length < 1.0:  # exact below a period: reached within the grid's resolution
            assert low >= min(values) - step and high <= max(values) + step
        whole = math.floor(u0) * record[36 + 4 * n - 1]  # G1 at the flight's start from its phase in [0, 1)
        assert shaped_flight_constants(0.0, 0.0, 0.0, u0 * PERIOD, record)[2] == pytest.approx(values[0] - whole,
                                                                                               abs=1e-12)


def _independent_piece(knots, u):
    """The last piece k <= n - 2 whose knot is at or before u (the right side of a jump), by numpy."""
    return min(int(np.searchsorted(knots, u, side="right")) - 1, len(knots) - 2)


@pytest.mark.parametrize("shape", [*SHAPES, "many uneven"])
def test_the_table_extremes_of_g1_are_those_of_the_walk_over_the_pieces(shape):
    """window_range (cells and sparse tables, no walk) against window_extremes (the walk over the pieces, checked
    against the quadrature above), without and with the hint of the window's start; the hint it returns is the
    period and piece of the window's end: random windows from inside one piece to over a period, windows from and
    to knots, to the period's end and across it, and of no length."""
    rng = np.random.default_rng(41 + len(shape))
    if shape == "many uneven":  # 300 knots bunched near 0.2 and 0.7, with two jumps
        u = np.sort(np.concatenate([rng.uniform(0, 1, 100), 0.2 + 1e-3 * rng.uniform(0, 1, 100),
                                    0.7 + 1e-6 * rng.uniform(0, 1, 98)]))
        samples = list(zip(np.sort(np.concatenate([u, u[[10, 150]]])), rng.normal(size=u.size + 2)))
    else:
        samples = SHAPES[shape]
    knots, _ = waveform_knots(samples)
    record = shaped_record(derived_field(np.zeros(3), np.zeros(3)), AMPLITUDE, PERIOD, samples)
    n = len(knots)
    size = np.abs(record[36 + 3 * n:36 + 4 * n]).max() + abs(record[36 + 4 * n - 1]) * 4
    windows = [(u0, u0 + length) for u0 in rng.uniform(0, 3, 300) for length in (0.0, 1e-3, 0.05, 0.3, 0.9, 1.0, 2.5)]
    windows += [(m + a, m + b) for m in (0.0, 2.0) for a in knots for b in knots if a <= b]
    windows += [(m + a, m + 1.0 + b) for m in (0.0, 1.0) for a in knots[::7] for b in knots[::5] if b < a]
    windows += [(u0, math.ceil(u0)) for u0 in rng.uniform(0, 3, 50)]
    for u_start, u_end in windows:
        low, high, _, _, _ = window_extremes(u_start, u_end, record, n, 0, 0.0, 0)
        assert window_range(u_start, u_end, record, n, 0.0, 0)[:2] == pytest.approx((low, high), abs=1e-14 * size)
        # from the hint of the window's start (its period and piece, as the previous window returns them)
        m = math.floor(u_start)
        chained = window_range(u_start, u_end, record, n, float(m), _independent_piece(knots, u_start - m))
        assert chained[:2] == pytest.approx((low, high), abs=1e-14 * size)
        if u_end - u_start < 1.0:  # the hint for the next window: u_end's period and piece
            assert chained[2] == math.floor(u_end) and chained[3] == _independent_piece(knots, u_end - chained[2])


def _exact_speeds(v0, t0, start, h, record, points=401):
    return [np.linalg.norm(shaped_velocity(*v0, t0, start + u, record)) for u in np.linspace(0.0, h, points)]


@pytest.mark.parametrize("shape", SHAPES)
def test_without_b_the_window_bound_is_the_largest_speed(shape):
    """Along the field the speed's extremes are G1's; across it constant: the bound is reached (grid of 2001)."""
    record = shaped_record(derived_field(np.zeros(3), np.zeros(3)), AMPLITUDE, PERIOD, SHAPES[shape])
    rng = np.random.default_rng(7 + len(shape))
    for _ in range(25):
        v0, t0, start, h = rng.normal(size=3), rng.uniform(0, 5), rng.uniform(0, 1), rng.choice([0.02, 0.3, 1.6])
        constants = shaped_flight_constants(*v0, t0, record)
        bound = shaped_tight_window(*constants, start, h, record, 0.0, constants[1])[0]
        speeds = _exact_speeds(v0, t0, start, h, record, 2001)
        assert bound >= max(speeds) * (1 - 1e-12)
        if h < PERIOD:
            assert bound <= max(speeds) + np.linalg.norm(AMPLITUDE) * 2.5 * h / 2000 + 1e-9


@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize("w", [0.0, 0.05, 25.0])
def test_chained_window_hints_give_the_bounds_of_a_walk_from_the_flight_start(shape, w):
    """A flight's windows, each starting its walk over the pieces where the previous one ended (the swarm's
    chaining), bound exactly as windows walked from the flight's start piece; the hints stay at or before each
    window's start (else the walk would start past it) across several periods."""
    record = shaped_record(derived_field(np.zeros(3), w * np.array([0.0, 0.6, 0.8])), AMPLITUDE, PERIOD, SHAPES[shape])
    n = int(record[35])
    rng = np.random.default_rng(23 + len(shape))
    for _ in range(10):
        constants = shaped_flight_constants(*rng.normal(size=3), rng.uniform(0, 5), record)
        u0, k0 = constants[0], constants[1]
        start, hint_period, hint = 0.0, 0.0, k0
        for h in rng.choice([0.013, 0.05, 0.3, 1.2], size=12):
            chained, hint_period, hint = shaped_tight_window(*constants, start, h, record, hint_period, hint)
            assert chained == shaped_tight_window(*constants, start, h, record, 0.0, k0)[0]
            end = u0 + (start + h) / PERIOD
            assert hint_period + record[36 + hint] <= end + 1e-15 and 0 <= hint < n - 1
            start += h


@pytest.mark.parametrize("shape", ["square", "irregular", "cosine"])
def test_the_periodic_solution_is_the_flight_of_its_start_over_the_period(shape):
    """A velocity A P(0) across B at t = 0 flies to A P at every knot and back to A P(0) after a period; the pieces'
    tabulated bounds cover |P| on a fine grid."""
    knots, _ = waveform_knots(SHAPES[shape])
    n = len(knots)
    for w, angle in ((9.0, 90.0), (25.0, 60.0), (0.3, 30.0)):
        theta = math.radians(angle)
        record = shaped_record(derived_field(np.zeros(3), w * np.array([0.0, math.sin(theta), math.cos(theta)])),
                               AMPLITUDE, PERIOD, SHAPES[shape])
        tables = periodic_start(n)
        big_p = record[tables:tables + n] + 1j * record[tables + n:tables + 2 * n]
        big_a, e1, e2 = record[24], record[18:21], record[21:24]

        def velocity(p):
            return big_a * (p.real * e1 + p.imag * e2)

        def flown(time):
            v = np.array(shaped_velocity(*velocity(big_p[0]), 0.0, time, record)) / big_a
            return complex(v @ e1, v @ e2)

        for k in range(n):
            assert flown(knots[k] * PERIOD) == pytest.approx(big_p[k], abs=1e-11 * (1 + abs(big_p).max()))
        for k in range(n - 1):
            if knots[k + 1] > knots[k]:
                sizes = [abs(flown(t)) for t in np.linspace(knots[k], knots[k + 1], 201) * PERIOD]
                assert record[tables + 2 * n + k] >= max(sizes) * (1 - 1e-12)
        assert record[tables + 3 * n] == pytest.approx(record[tables + 2 * n:tables + 3 * n - 1].max())


def test_the_gyration_offset_is_fixed_along_a_flight():
    """|zeta - A P| at the flight's start (shaped_flight_constants) equals its value after any flight."""
    record = shaped_record(derived_field(np.zeros(3), 9.0 * np.array([0.0, 0.5, math.sqrt(0.75)])), AMPLITUDE,
                           PERIOD, SHAPES["irregular"])
    rng = np.random.default_rng(3)
    for _ in range(10):
        v0, t0, tau = rng.normal(size=3), rng.uniform(0, 5), rng.uniform(0, 2)
        offset = shaped_flight_constants(*v0, t0, record)[5]
        assert offset == pytest.approx(shaped_flight_constants(*shaped_velocity(*v0, t0, tau, record), t0 + tau,
                                                               record)[5], rel=1e-10)


@pytest.mark.parametrize("shape", ["square", "irregular", "cosine"])
def test_with_b_the_window_bound_covers_the_exact_speed(shape):
    """Random windows (short, across jumps, longer than a period) late in a flight, B at 0 to 90 degrees, off and at
    cyclotron resonance, and slow gyration: the bound covers the exact speed on a grid of 401 points."""
    rng = np.random.default_rng(11)
    for angle in (0.0, 45.0, 60.0, 90.0):
        theta = math.radians(angle)
        for w in (25.0, 2 * math.pi / PERIOD, 0.05):
            record = shaped_record(derived_field(np.zeros(3), w * np.array([0.0, math.sin(theta), math.cos(theta)])),
                                   AMPLITUDE, PERIOD, SHAPES[shape])
            for _ in range(12):
                v0, t0 = rng.normal(size=3), rng.uniform(0, 5)
                start, h = rng.uniform(0, 2), rng.choice([0.01, 0.2, 1.5])
                constants = shaped_flight_constants(*v0, t0, record)
                bound = shaped_tight_window(*constants, start, h, record, 0.0, constants[1])[0]
                assert bound >= max(_exact_speeds(v0, t0, start, h, record)) * (1 - 1e-12)


@pytest.mark.parametrize("shape", SHAPES)
def test_stepped_windows_chained_over_a_flight_cover_the_exact_speed(shape):
    """The swarm's window bound (stepped_shaped_window), chained window after window over a flight as the particle
    loop does (G1, periods and piece handed on), with and without B (off and at cyclotron resonance): it covers the
    exact speed on a grid of each window, its G1 at each end is the quadrature's, and it is at most the padding
    |a_p| max|f| h / 2 above the exact extremes' bound without B."""
    from collisionkit._kernels.transport.waveform_window import stepped_shaped_window

    f, knots = _f(SHAPES[shape])
    rng = np.random.default_rng(17)
    for w, angle in ((0.0, 0.0), (25.0, 60.0), (2 * math.pi / PERIOD, 90.0)):
        theta = math.radians(angle)
        record = shaped_record(derived_field(np.zeros(3), w * np.array([0.0, math.sin(theta), math.cos(theta)])),
                               AMPLITUDE, PERIOD, SHAPES[shape])
        for _ in range(6):
            v0, t0 = rng.normal(size=3), rng.uniform(0, 5)
            constants = shaped_flight_constants(*v0, t0, record)
            u0, k0, g0 = constants[:3]
            g, periods, piece, start = g0, 0.0, k0, 0.0
            for h in rng.choice([0.01, 0.05, 0.3, 1.5], size=8):
                bound, g, periods, piece = stepped_shaped_window(u0, g0, *constants[3:], start, h, record, g,
                                                                 periods, piece)
                assert bound >= max(_exact_speeds(v0, t0, start, h, record)) * (1 - 1e-12)
                u_end = u0 + (start + h) / PERIOD
                edges = sorted({u0, u_end, *(k + m for m in range(12) for k in knots if u0 < k + m < u_end)})
                # piece by piece (quad across a jump is inexact)
                integral = sum(quad(f, a, b, epsabs=1e-14, limit=200)[0] for a, b in zip(edges, edges[1:]))
                assert g - g0 == pytest.approx(integral, abs=1e-12)
                if w == 0.0:
                    exact = shaped_tight_window(*constants, start, h, record, 0.0, k0)[0]
                    assert bound <= exact + 0.5 * h * record[25] * (1 + 1e-9)
                start += h
