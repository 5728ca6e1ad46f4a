"""Error-free arithmetic for the approach test and the impulse: exact dot products, a sure sign.

A pair collides when it approaches: ``b = r . u - shift < 0`` (``r`` the
separation, ``u`` the relative velocity, ``shift`` the growth of the
contact distance while compressing). The prediction and the collision step
must agree on that test bit for bit for a pair at one time: a pair the
prediction sends to collide at once but the collision step finds receding
is predicted again, at the same instant, for ever. Both take ``b`` from
:func:`sure_approach`: the plain sum when its sign is certain (round-off
below ``|b|``), else the sum carried error-free, which two deterministic
evaluations give alike. The impulse divides the same error-free ``b`` by
``|r|^2`` (:func:`approach_ratio`) and rounds once: see
:mod:`.contacts` for why that removes the energy bias.
"""

from __future__ import annotations

# no EDMD kernel allocates or returns an array: all of them borrow, without reference counting
from ..._jit import borrowing_inline_kernel as inline_kernel

# Veltkamp's splitter 2^27 + 1: splits a double into two halves whose products are exact
_SPLITTER = 134217729.0
# bound on the relative round-off of a plain sum of four products (3 products and the shift): gamma_4 and a margin
_DOT_ROUNDING = 5e-16


@inline_kernel
def two_sum(a, b):
    """(s, e) with s = fl(a + b) and s + e = a + b exactly (Knuth)."""
    s = a + b
    z = s - a
    return s, (a - (s - z)) + (b - z)


@inline_kernel
def two_product(a, b):
    """(p, e) with p = fl(a * b) and p + e = a * b exactly (Dekker; |a|, |b| below 2^996)."""
    p = a * b
    c = _SPLITTER * a
    a_high = c - (c - a)
    a_low = a - a_high
    c = _SPLITTER * b
    b_high = c - (c - b)
    b_low = b - b_high
    return p, ((a_high * b_high - p) + a_high * b_low + a_low * b_high) + a_low * b_low


@inline_kernel
def exact_dot(rx, ry, rz, ux, uy, uz, shift):
    """r . u - shift as an unevaluated sum (high, low), the products and sums carried error-free."""
    high, low = two_product(rx, ux)
    product, product_low = two_product(ry, uy)
    high, carry = two_sum(high, product)
    low += carry + product_low
    product, product_low = two_product(rz, uz)
    high, carry = two_sum(high, product)
    low += carry + product_low
    high, carry = two_sum(high, -shift)
    return two_sum(high, low + carry)


@inline_kernel
def sure_approach(b, rx, ry, rz, ux, uy, uz, shift):
    """``b`` (the plain ``r . u - shift``) if its sign is certain, else the error-free sum rounded: a sure sign."""
    if abs(b) > _DOT_ROUNDING * (abs(rx * ux) + abs(ry * uy) + abs(rz * uz) + abs(shift)):
        return b
    high, _ = exact_dot(rx, ry, rz, ux, uy, uz, shift)
    return high


@inline_kernel
def approach_ratio(rx, ry, rz, ux, uy, uz, shift):
    """(r . u - shift) / |r|^2 from the error-free sums, rounded once (its sign is :func:`sure_approach`'s)."""
    b, b_low = exact_dot(rx, ry, rz, ux, uy, uz, shift)
    rr, rr_low = two_product(rx, rx)
    square, square_low = two_product(ry, ry)
    rr, carry = two_sum(rr, square)
    rr_low += carry + square_low
    square, square_low = two_product(rz, rz)
    rr, carry = two_sum(rr, square)
    rr_low += carry + square_low
    quotient = b / rr
    product, product_low = two_product(quotient, rr)
    return quotient + ((((b - product) - product_low) + b_low) - quotient * rr_low) / rr
