"""Checks of the encounter inputs: finite scalars, speeds, state vectors and the force law."""

from __future__ import annotations

import math
import sys

import numpy as np

from .. import _arrays


def scalar_above(value, name: str, low: float = 0.0, *, inclusive: bool = False) -> float:
    """A finite real number > low (>= low if inclusive), or a named error."""
    array = _arrays.as_float_array(value, name)
    if array.ndim != 0:
        raise TypeError(f"{name} must be a single number; got an array of shape {array.shape}")
    _arrays.require_finite(array, name)
    _arrays.require_in_range(array, name, low, np.inf, inclusive=(inclusive, False))
    return float(array)


def nonzero_speed(value, name: str) -> float:
    """A speed whose square is a normal, finite float (~1.5e-154 to ~1.3e154), or a named error.

    Below, v^2 would round to 0; above, it would overflow.
    """
    speed = scalar_above(value, name)
    low, high = math.sqrt(sys.float_info.min), math.sqrt(sys.float_info.max)
    if not low < speed < high:
        raise ValueError(f"{name} must lie in ({low:.3g}, {high:.3g}) (its square must be a normal float); "
                         f"got {speed!r}")
    return speed


def real_scalar(value, name: str) -> float:
    """A finite real number of either sign, or a named error."""
    array = _arrays.as_float_array(value, name)
    if array.ndim != 0:
        raise TypeError(f"{name} must be a single number; got an array of shape {array.shape}")
    _arrays.require_finite(array, name)
    return float(array)


def state_vector(value, name: str) -> np.ndarray:
    """A finite vector of length 1, 2 or 3, padded with zeros to 3D, or a named error."""
    array = _arrays.as_vector_array(value, name)
    if array.ndim != 1:
        raise ValueError(f"{name} must be one vector of length 1, 2 or 3; got shape {array.shape}")
    _arrays.require_finite(array, name)
    return np.concatenate([array, np.zeros(3 - array.size)])


def interaction(m1, m2, G, k):
    """Validated (m1, m2, G, k, mu_K); G defaults to 1 when k is not given."""
    m1 = scalar_above(m1, "m1")
    m2 = scalar_above(m2, "m2")
    G = (1.0 if k is None else 0.0) if G is None else scalar_above(G, "G", inclusive=True)
    k = 0.0 if k is None else real_scalar(k, "k")
    # k / mu = k (m1 + m2) / (m1 m2), without the product m1 m2 (it underflows to 0 for masses of ~1e-160)
    mu_k = G * (m1 + m2) - (k * ((m1 + m2) / m1) / m2 if k != 0.0 else 0.0)
    if not math.isfinite(mu_k):
        raise ValueError("G (m1 + m2) - k / mu overflows; rescale the units")
    if mu_k == 0.0:
        raise ValueError("the interaction vanishes (G (m1 + m2) = k / mu): the bodies move in straight lines")
    return m1, m2, G, k, mu_k
