"""Exact flight in a periodic field of any shape given as samples (piecewise linear), without B.

Independent check: the integrals J1 = integral of f and J2 = its double integral by adaptive quadrature
(scipy quad, split at the knots and jumps), over flights inside one piece, across pieces and over many periods.
"""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from collisionkit._kernels.transport.flight import derived_field
from collisionkit._kernels.transport.waveform import waveform_integrals
from collisionkit._kernels.transport.waveform_magnetic import shaped_velocity, shaped_window
from collisionkit.transport._waveform import waveform_knots, shaped_record

SHAPES = {
    "square": [(0.0, 1.0), (0.5, 1.0), (0.5, -1.0), (1.0, -1.0)],
    "sawtooth": [(0.0, -1.0), (1.0, 1.0)],
    "irregular": [(0.1, 0.3), (0.2, -2.0), (0.2, 1.5), (0.65, 0.4), (0.9, 2.5)],
}


def _f(samples):
    """f(u) for any real u, by numpy interpolation of the periodic extension (the value right of a jump)."""
    knots, values = waveform_knots(samples)

    def f(u):
        r = u - math.floor(u)
        k = min(int(np.searchsorted(knots, r, side="right")) - 1, len(knots) - 2)
        return values[k] + (values[k + 1] - values[k]) * (r - knots[k]) / (knots[k + 1] - knots[k]) \
            if knots[k + 1] > knots[k] else values[k]
    return f, knots


def _quadrature(samples, period, t0, tau):
    f, knots = _f(samples)
    u0, u1 = t0 / period, (t0 + tau) / period
    points = [k + n for n in range(math.floor(u0) - 1, math.ceil(u1) + 1) for k in knots if u0 < k + n < u1]
    edges = [u0, *sorted(points), u1]
    j1 = lambda u: sum(quad(f, a, min(b, u), epsabs=1e-14, epsrel=1e-12, limit=200)[0]
                       for a, b in zip(edges, edges[1:]) if a < u)
    j2 = sum(quad(j1, a, b, epsabs=1e-15, epsrel=1e-12, limit=200)[0] for a, b in zip(edges, edges[1:]))
    return period * j1(u1), period * period * j2


@pytest.mark.parametrize("shape", SHAPES)
def test_the_integrals_are_those_of_the_piecewise_linear_field(shape):
    rng = np.random.default_rng(list(SHAPES).index(shape))
    period = 0.7
    record = shaped_record(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 1.0]), period, SHAPES[shape])
    for tau in (1e-4, 0.03, 0.2, 0.7, 2.3):
        for t0 in rng.uniform(0.0, 30.0, 3):
            exact = _quadrature(SHAPES[shape], period, t0, tau)
            value = waveform_integrals(t0, tau, record)
            assert value[0] == pytest.approx(exact[0], rel=1e-9, abs=1e-12 * tau)
            assert value[1] == pytest.approx(exact[1], rel=1e-8, abs=1e-12 * tau * tau)


def test_the_velocity_and_window_bound_with_gravity_and_across_the_field():
    """v = v0 + g tau + a T J1; the window bound covers the exact speed on a fine grid (with and without g)."""
    rng = np.random.default_rng(9)
    for gravity in (np.zeros(3), np.array([0.3, -0.2, 0.5])):
        record = shaped_record(derived_field(gravity, np.zeros(3)), np.array([0.0, 0.0, 2.0]), 0.5,
                               SHAPES["irregular"])
        accel = np.linalg.norm(gravity) + record[25]
        for _ in range(20):
            v0, t0, start, h = rng.normal(size=3), rng.uniform(0, 5), rng.uniform(0, 1), rng.uniform(0.01, 1)
            bound = shaped_window(*v0, t0, start, h, record, accel)
            speeds = [np.linalg.norm(shaped_velocity(*v0, t0, start + u, record)) for u in np.linspace(0, h, 401)]
            assert bound >= max(speeds) * (1 - 1e-12)
            j1 = _quadrature(SHAPES["irregular"], 0.5, t0, start)[0]
            np.testing.assert_allclose(shaped_velocity(*v0, t0, start, record),
                                       v0 + gravity * start + np.array([0.0, 0.0, 2.0]) * j1, atol=1e-9)


@pytest.mark.parametrize("shape", SHAPES)
def test_the_piecewise_integrals_from_a_known_piece_are_those_of_the_piecewise_linear_field(shape):
    """piece_integrals (from the phase's piece, piece by piece) against the quadrature, over flights inside one
    piece, across knots and jumps, over a period's end and longer than a period."""
    from collisionkit._kernels.transport.waveform import _piece, piece_integrals

    rng = np.random.default_rng(5 + list(SHAPES).index(shape))
    period = 0.7
    record = shaped_record(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 1.0]), period, SHAPES[shape])
    n = int(record[35])
    for tau in (1e-4, 0.03, 0.2, 0.6, 2.3):
        for t0 in rng.uniform(0.0, 30.0, 4):
            u0 = t0 / period - math.floor(t0 / period)
            exact = _quadrature(SHAPES[shape], period, t0, tau)
            value = piece_integrals(u0, _piece(u0, record, n), tau, record)
            assert value[0] == pytest.approx(exact[0], rel=1e-9, abs=1e-12 * tau)
            assert value[1] == pytest.approx(exact[1], rel=1e-8, abs=1e-12 * tau * tau)


def _independent_piece(knots, u):
    """The last piece k <= n - 2 whose knot is at or before u (the right side of a jump), by numpy."""
    return min(int(np.searchsorted(knots, u, side="right")) - 1, len(knots) - 2)


@pytest.mark.parametrize("shape", [*SHAPES, "many uneven", "jumps at the ends"])
def test_the_cell_table_gives_the_piece_of_every_phase(shape):
    """cell_piece (the record's cells, then forward) against numpy's search and the bisection _piece: random
    phases, every knot, the phases just before and after them, 0 and the largest phase below 1; the table holds
    at least CELLS_PER_PIECE cells per piece, a power of two."""
    from collisionkit._kernels.transport.waveform import CELLS_PER_PIECE, _piece, cell_piece

    rng = np.random.default_rng(31)
    if shape == "many uneven":  # 300 knots bunched near 0.2 and 0.7, with jumps
        u = np.sort(np.concatenate([rng.uniform(0, 1, 100), 0.2 + 1e-3 * rng.uniform(0, 1, 100),
                                    0.7 + 1e-6 * rng.uniform(0, 1, 98)]))
        u = np.sort(np.concatenate([u, u[[10, 150]]]))  # two jumps
        samples = list(zip(u, rng.normal(size=u.size)))
    elif shape == "jumps at the ends":
        samples = [(0.0, 1.0), (0.0, -1.0), (0.5, 2.0), (1.0, 0.5), (1.0, 3.0)]
    else:
        samples = SHAPES[shape]
    knots, _ = waveform_knots(samples)
    record = shaped_record(derived_field(np.zeros(3), np.zeros(3)), np.array([0.0, 0.0, 1.0]), 0.7, samples)
    n = int(record[35])
    assert n == knots.size and np.array_equal(record[36:36 + n], knots)
    cells = int(record[int(record[33])])
    assert cells >= CELLS_PER_PIECE * (n - 1) and cells & (cells - 1) == 0
    phases = [0.0, np.nextafter(1.0, 0.0), *rng.uniform(0, 1, 2000), *knots[knots < 1.0],
              *np.nextafter(knots[knots > 0.0], 0.0), *np.nextafter(knots[knots < 1.0], 1.0)]
    for u in phases:
        if 0.0 <= u < 1.0:
            assert cell_piece(u, record, n) == _independent_piece(knots, u) == _piece(u, record, n)


def test_the_record_holds_the_inverse_period_and_the_parallel_scale():
    """Entry 31 is 1/T, entry 32 |a| T without B and (a . b) T with B (the window bound's scale)."""
    from collisionkit._kernels.transport.oscillating import oscillating_field

    amplitude, period = np.array([0.3, 0.0, 1.2]), 0.7
    record = shaped_record(derived_field(np.zeros(3), np.zeros(3)), amplitude, period, SHAPES["irregular"])
    assert record[31] == pytest.approx(1.0 / period, rel=1e-15)
    assert record[32] == pytest.approx(np.linalg.norm(amplitude) * period, rel=1e-15)
    b = np.array([0.0, 0.6, 0.8])
    magnetic = shaped_record(derived_field(np.zeros(3), 5.0 * b), amplitude, period, SHAPES["irregular"])
    assert magnetic[31] == pytest.approx(1.0 / period, rel=1e-15)
    assert magnetic[32] == pytest.approx(float(amplitude @ b) * period, rel=1e-15)
    assert oscillating_field(derived_field(np.zeros(3), 5.0 * b), amplitude, 1.0)[17] == pytest.approx(amplitude @ b)
