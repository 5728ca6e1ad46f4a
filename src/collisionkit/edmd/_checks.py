"""Argument checks of the EDMD API: each names the argument it rejects and the range it allows."""

from __future__ import annotations

import math

import numpy as np

from .. import _arrays


def real_array(value, name):
    """``value`` as a float64 array; TypeError naming ``name`` for non-real or boolean input."""
    array = _arrays.as_float_array(value, name)
    if np.asarray(value).dtype.kind == "b":
        raise TypeError(f"{name} must hold numbers, not booleans; got {value!r}")
    return array


def bounded(value, name, low, high=math.inf, *, closed=(True, False), scalar=True):
    """Finite number(s) from ``low`` to ``high`` (ends included as ``closed`` says).

    Returns a float, or a float64 array unless ``scalar``; raises TypeError
    for a non-real or boolean value, ValueError naming ``name`` and the range.
    """
    array = real_array(value, name)
    if scalar and array.ndim:
        raise ValueError(f"{name} must be a single number; got shape {array.shape}")
    above = array >= low if closed[0] else array > low
    below = array <= high if closed[1] else array < high
    ok = np.isfinite(array) & above & below
    if not np.all(ok):
        if high == math.inf:
            allowed = f"{'>=' if closed[0] else '>'} {low:g}"
        else:
            allowed = f"in {'[' if closed[0] else '('}{low:g}, {high:g}{']' if closed[1] else ')'}"
        what = "be a finite number" if scalar else "hold finite numbers"
        raise ValueError(f"{name} must {what} {allowed}; got {array[~ok].flat[0]}")
    return float(array) if scalar else array


def positive(value, name, scalar=True):
    """Finite number(s) > 0, as :func:`bounded`."""
    return bounded(value, name, 0.0, closed=(False, False), scalar=scalar)


def is_integer(value):
    """True for an int or numpy integer (not a bool)."""
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool)


def integer_at_least(value, name, minimum):
    """``value`` as an int >= ``minimum`` (a whole float such as 1e6 too, as :func:`collisionkit._params.check_integer`
    takes it); booleans and other non-integers raise TypeError naming ``name``."""
    if isinstance(value, float) and value.is_integer() and abs(value) < 2**53:
        value = int(value)
    if not is_integer(value):
        raise TypeError(f"{name} must be an integer >= {minimum}; got {value!r}")
    if value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}; got {value!r}")
    return int(value)


def dimension(dim):
    """The space dimension: the integer 2 or 3."""
    if not is_integer(dim):
        raise TypeError(f"dim must be the integer 2 or 3; got {dim!r}")
    if dim not in (2, 3):
        raise ValueError(f"dim must be 2 or 3; got {dim!r}")
    return int(dim)


def per_particle(value, count, name, integer=False):
    """A scalar or shape (count,) input as a new float64 array (int64 if ``integer``)."""
    array = real_array(value, name)
    if array.ndim == 0:
        array = np.full(count, array)
    elif array.shape != (count,):
        raise ValueError(f"{name} must be a scalar or have shape ({count},); got {array.shape}")
    if not integer:
        return array.copy()
    if not np.all(array % 1 == 0):
        raise ValueError(f"{name} must hold integers; got {array[~(array % 1 == 0)][0]}")
    return array.astype(np.int64)
