"""Random streams: xoshiro256+ per particle, seeded by splitmix64; uniform and normal variates.

Every particle carries its own stream (a state of four uint64 words), so
the result does not depend on how particles are split over threads.

The per-trial functions (:func:`next_u64`, :func:`uniform`,
:func:`normal_pair`) are inlined into their callers: a numba call that is
not inlined increments and decrements the reference count of the state
array it takes (two atomic operations, about as much as the generator
itself), even from a caller compiled without reference counting.
"""

from __future__ import annotations

import math

import numpy as np

from ..._jit import inline_kernel, kernel

_SM1 = np.uint64(0x9E3779B97F4A7C15)
_SM2 = np.uint64(0xBF58476D1CE4E5B9)
_SM3 = np.uint64(0x94D049BB133111EB)
_TWO_M53 = 1.0 / 9007199254740992.0


@inline_kernel
def _rotl(x, k):
    return (x << np.uint64(k)) | (x >> np.uint64(64 - k))


@inline_kernel
def next_u64(state):
    """xoshiro256+ step on a length-4 uint64 state (Blackman & Vigna 2018)."""
    result = state[0] + state[3]
    t = state[1] << np.uint64(17)
    state[2] ^= state[0]
    state[3] ^= state[1]
    state[1] ^= state[2]
    state[0] ^= state[3]
    state[2] ^= t
    state[3] = _rotl(state[3], 45)
    return result


@inline_kernel
def uniform(state):
    """A double in the open interval (0, 1) (never 0: safe for log)."""
    return (float(next_u64(state) >> np.uint64(11)) + 0.5) * _TWO_M53


@kernel
def _splitmix(x):
    x = x + _SM1
    z = x
    z = (z ^ (z >> np.uint64(30))) * _SM2
    z = (z ^ (z >> np.uint64(27))) * _SM3
    return x, z ^ (z >> np.uint64(31))


@kernel
def seed_state(seed, out):
    """Fill a length-4 xoshiro state from one uint64 seed with splitmix64."""
    x = seed
    for k in range(4):
        x, z = _splitmix(x)
        out[k] = z


@inline_kernel
def normal_pair(state):
    """Two independent standard normal numbers (Marsaglia's polar method: no trigonometry)."""
    while True:
        u1 = 2.0 * uniform(state) - 1.0
        u2 = 2.0 * uniform(state) - 1.0
        s = u1 * u1 + u2 * u2
        if s < 1.0:
            f = math.sqrt(-2.0 * math.log(s) / s)
            return u1 * f, u2 * f
