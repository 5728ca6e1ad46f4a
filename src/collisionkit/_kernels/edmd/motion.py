"""Ballistic flight and the periodic box: moving a particle, minimum images, wrapping."""

from __future__ import annotations

import math

# no EDMD kernel allocates or returns an array: all of them borrow, without reference counting
from ..._jit import borrowing_inline_kernel as inline_kernel
from ..._jit import borrowing_kernel as kernel
from .layout import ACC_ENERGY_IMAGE, ACC_MOMENTUM_IMAGE, G_BOX, G_GRAVITY, G_PERIODIC, MASS, T, V, X


@inline_kernel
def advance(p, i, t, geom, dim):
    """Move particle i along its flight to time t (exact parabola)."""
    dt = t - p[i, T]
    if dt != 0.0:
        for k in range(dim):
            g = geom[G_GRAVITY, k]
            p[i, X + k] += (p[i, V + k] + 0.5 * g * dt) * dt
            p[i, V + k] += g * dt
        p[i, T] = t


@kernel
def minimum_image(dx, length, half):
    """Shortest periodic image of a separation no longer than 1.5 box lengths (half = inf: walls)."""
    if dx > half:
        return dx - length
    if dx < -half:
        return dx + length
    return dx


@inline_kernel
def half_box(geom, k):
    """Half the box length along axis k if it is periodic, else inf (no image to take)."""
    return 0.5 * geom[G_BOX, k] if geom[G_PERIODIC, k] != 0.0 else math.inf


@inline_kernel
def wrap_into_box(p, i, geom, dim, image, b, acc):
    """Bring particle i back into [0, L) on periodic axes (it is at most a box length out).

    The image counter keeps the unwrapped position ``x + image L``
    continuous. The Helfand moments of the stored positions (``sum m v_a
    x_b`` and ``sum (m v^2 / 2) x_b``) jump by the particle's share times
    the move ``dx``; the image slots of ``acc`` take it back (see
    :mod:`.layout`), so that moment plus the slots stays continuous.
    """
    for k in range(dim):
        if geom[G_PERIODIC, k] != 0.0:
            length = geom[G_BOX, k]
            before = p[i, X + k]
            if before >= length:
                p[i, X + k] -= length
                image[i, k] += 1
            elif before < 0.0:
                p[i, X + k] += length
                image[i, k] -= 1
                if p[i, X + k] >= length:  # -tiny + L rounds to L: put it at 0, the same image
                    p[i, X + k] = 0.0
                    image[i, k] += 1
            else:
                continue
            moved = p[i, X + k] - before
            mass = b[i, MASS]
            energy = 0.0
            for a in range(3):
                momentum = mass * p[i, V + a]
                acc[ACC_MOMENTUM_IMAGE + 3 * a + k] -= momentum * moved
                energy += 0.5 * momentum * p[i, V + a]
            acc[ACC_ENERGY_IMAGE + k] -= energy * moved
