"""Kernels of the two-body propagation: Stumpff functions against their closed forms and series."""

from __future__ import annotations

import math

import pytest

from collisionkit._kernels import encounters as kernels


@pytest.mark.parametrize("z", [-50.0, -2.000001, -1.999999, -0.5, 0.5, 1.999999, 2.000001, 9.0, 39.0])
def test_stumpff_functions_against_closed_forms(z):
    """Series (|z| < 2) and closed forms agree with the definitions on both sides of the switch."""
    y = math.sqrt(abs(z))
    if z > 0:
        exact = (math.cos(y), math.sin(y) / y, (1 - math.cos(y)) / z, (y - math.sin(y)) / y**3)
    else:
        exact = (math.cosh(y), math.sinh(y) / y, (math.cosh(y) - 1) / -z, (math.sinh(y) - y) / y**3)
    assert kernels.stumpff(z) == pytest.approx(exact, rel=1e-13, abs=0)


def test_stumpff_functions_near_zero():
    for z in (0.0, 1e-12, -1e-12, 1e-3):
        c0, c1, c2, c3 = kernels.stumpff(z)
        assert (c2, c3) == pytest.approx((0.5 - z / 24 + z**2 / 720 - z**3 / 40320, 1 / 6 - z / 120 + z**2 / 5040 - z**3 / 362880), rel=1e-15, abs=0)
        assert (c0, c1) == pytest.approx((1 - z * c2, 1 - z * c3), rel=1e-16, abs=0)
