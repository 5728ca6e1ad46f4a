"""Argument checking and broadcasting shared by the public API.

Public functions take numpy-like inputs that broadcast over leading axes, with
vectors on the last axis (dimension 1, 2 or 3). They are turned here into the
flat contiguous float64 arrays the kernels expect: per-pair values of shape
``(n,)`` or ``(1,)`` and vectors of shape ``(n, d)`` or ``(1, d)``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

ALLOWED_DIMENSIONS = (1, 2, 3)


def as_float_array(value, name: str) -> np.ndarray:
    """Return ``value`` as a float64 array, or raise TypeError naming ``name``."""
    if isinstance(value, (str, bytes)):
        raise TypeError(f"{name} must be a number or an array of numbers, got {type(value).__name__}")
    try:
        array = np.asarray(value)
    except (TypeError, ValueError) as error:  # ragged nested sequences
        raise TypeError(f"{name} must be a number or a rectangular array of numbers: {error}") from None
    if array.dtype.kind == "c":
        raise TypeError(f"{name} must be real, got a complex array")
    if array.dtype.kind == "b":  # True is not a mass of 1
        raise TypeError(f"{name} must hold numbers, not a bool (True is not 1 here)")
    if array.dtype.kind not in "iuf":
        raise TypeError(f"{name} must hold real numbers, got dtype {array.dtype}")
    return array.astype(np.float64, copy=False)


def as_vector_array(value, name: str) -> np.ndarray:
    """Return ``value`` as a float64 array whose last axis is a 1-3 D vector."""
    array = as_float_array(value, name)
    if array.ndim == 0 or array.shape[-1] not in ALLOWED_DIMENSIONS:
        raise ValueError(
            f"{name} must have its last axis of length 1, 2 or 3 (the dimension); got shape {array.shape}"
        )
    return array


def require_finite(array: np.ndarray, name: str) -> None:
    """Raise ValueError if ``array`` holds a NaN or an infinity."""
    if not np.all(np.isfinite(array)):
        raise ValueError(f"{name} must be finite (no NaN or inf)")


def require_in_range(array: np.ndarray, name: str, low: float, high: float, *, inclusive=(True, True)) -> None:
    """Raise ValueError unless every element lies in the range [low, high]."""
    low_ok = array >= low if inclusive[0] else array > low
    high_ok = array <= high if inclusive[1] else array < high
    if not np.all(low_ok & high_ok):
        left = "[" if inclusive[0] else "("
        right = "]" if inclusive[1] else ")"
        bad = array[~(low_ok & high_ok)].flat[0]
        raise ValueError(f"{name} must lie in {left}{low}, {high}{right}; got {bad}")


def as_finite_in_range(value, name: str, low: float, high: float = np.inf, *, inclusive=(True, False)) -> np.ndarray:
    """:func:`as_float_array`, then :func:`require_finite` and :func:`require_in_range`: the usual check of a number."""
    array = as_float_array(value, name)
    require_finite(array, name)
    require_in_range(array, name, low, high, inclusive=inclusive)
    return array


def require_positive_masses(array: np.ndarray, name: str) -> None:
    """Masses are > 0; np.inf is allowed (a fixed body), NaN is not."""
    if not np.all(array > 0):
        bad = array[~(array > 0)].flat[0]
        raise ValueError(f"{name} must be positive (np.inf for a fixed body); got {bad}")


@dataclass(frozen=True)
class FlatPairs:
    """Pair inputs flattened for a kernel, and the shape to give results."""

    leading_shape: tuple[int, ...]
    dimension: int
    scalars: dict[str, np.ndarray]
    vectors: dict[str, np.ndarray]

    @property
    def count(self) -> int:
        return math.prod(self.leading_shape)


def _flatten(array: np.ndarray, own_leading: tuple[int, ...], leading: tuple[int, ...], tail: tuple[int, ...]):
    if math.prod(own_leading) == 1:
        return np.ascontiguousarray(array.reshape((1,) + tail))
    if own_leading == leading:
        return np.ascontiguousarray(array.reshape((-1,) + tail))
    return np.ascontiguousarray(np.broadcast_to(array, leading + tail).reshape((-1,) + tail))


def flatten_pairs(scalars: Mapping[str, object], vectors: Mapping[str, object]) -> FlatPairs:
    """Validate shapes and flatten per-pair scalars and vectors for a kernel.

    Parameters
    ----------
    scalars : mapping of name to array_like
        Per-pair numbers; their shapes broadcast against the vectors' leading axes.
    vectors : mapping of name to array_like
        Vectors whose last axis is the dimension (all equal, 1 to 3).

    Raises
    ------
    TypeError
        If an input is not real numeric.
    ValueError
        If dimensions differ or the shapes do not broadcast; the message names
        every argument with its shape.
    """
    scalar_arrays = {name: as_float_array(value, name) for name, value in scalars.items()}
    vector_arrays = {name: as_vector_array(value, name) for name, value in vectors.items()}
    dimensions = {name: array.shape[-1] for name, array in vector_arrays.items()}
    if len(set(dimensions.values())) > 1:
        listed = ", ".join(f"{name}: {dim}" for name, dim in dimensions.items())
        raise ValueError(f"vectors must share one dimension (last axis); got {listed}")
    dimension = next(iter(dimensions.values()))
    leading_shapes = {name: array.shape for name, array in scalar_arrays.items()}
    leading_shapes |= {name: array.shape[:-1] for name, array in vector_arrays.items()}
    try:
        leading = np.broadcast_shapes(*leading_shapes.values())
    except ValueError:
        listed = ", ".join(f"{name} {shape}" for name, shape in leading_shapes.items())
        raise ValueError(f"argument shapes do not broadcast together: {listed}") from None
    flat_scalars = {
        name: _flatten(array, array.shape, leading, ()) for name, array in scalar_arrays.items()
    }
    flat_vectors = {
        name: _flatten(array, array.shape[:-1], leading, (dimension,)) for name, array in vector_arrays.items()
    }
    return FlatPairs(leading, dimension, flat_scalars, flat_vectors)


def seed_value(seed):
    """An integer seed for runs that spawn their own streams: ``seed`` itself, or one drawn from a Generator.

    Runs that deal their work into groups (swarms, slabs, sweeps) seed a
    :class:`numpy.random.SeedSequence` with an integer; a Generator given as
    ``seed`` supplies that integer, so ``seed`` takes an int or a Generator
    everywhere.

    Examples
    --------
    >>> import numpy as np
    >>> seed_value(7), seed_value(np.random.default_rng(1)) == seed_value(np.random.default_rng(1))
    (7, True)
    """
    if isinstance(seed, np.random.Generator):
        return int(seed.integers(0, 2**63 - 1))
    return seed
