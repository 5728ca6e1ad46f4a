"""Ballistic flight and the periodic box: moving a particle, minimum images, wrapping.

Under Lees-Edwards shear (Lees & Edwards, J. Phys. C 5, 1921 (1972); Allen
& Tildesley, Computer Simulation of Liquids, 2nd ed., sec. 11.3) the image
boxes above and below the box (y +- L_y) slide along x with velocities
+- G L_y: at clock time t the box above is shifted by the offset
``o(t) = o(0) + G L_y t`` (mod L_x). A particle stored at y beyond L_y
is the image of one at y - L_y, x - o and v_x - G L_y: every stored state
is one of a particle's images, and :func:`sheared_image` takes the image of
a partner nearest to a particle, with the relative velocity of that image.
"""

from __future__ import annotations

import math

# no EDMD kernel allocates or returns an array: all of them borrow, without reference counting
from ..._jit import borrowing_inline_kernel as inline_kernel
from ..._jit import borrowing_kernel as kernel
from .layout import (
    ACC_ENERGY_IMAGE, ACC_MOMENTUM_IMAGE, G_BOX, G_GRAVITY, G_PERIODIC, MASS, P_SHEAR_FRAME, P_SHEAR_OFFSET,
    P_SHEAR_RATE, T, V, X,
)


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
def pair_image(dx, length, half):
    """:func:`minimum_image` without a branch, for the pair tests in a small box.

    Bit for bit the same value (but for the sign of a zero): a subtraction
    of 0 or of ``length`` is exact either way. In a small box a pair in a
    list lies across a face often (one in five at N = 864: 3 E|dx| / L,
    with E|dx| = 3 r / 8 in a list of radius r), so a branch on it is
    mispredicted often, and a mispredicted branch in the pair loop discards
    the loads of the pairs after it.
    """
    return (dx - length * (dx > half)) + length * (dx < -half)


@inline_kernel
def half_box(geom, k):
    """Half the box length along axis k if it is periodic, else inf (no image to take)."""
    return 0.5 * geom[G_BOX, k] if geom[G_PERIODIC, k] != 0.0 else math.inf


@inline_kernel
def shear_offset(params, geom, t):
    """x offset of the sliding image box above at clock time t, in [0, L_x]."""
    offset = params[P_SHEAR_OFFSET] + params[P_SHEAR_RATE] * geom[G_BOX, 1] * t
    lx = geom[G_BOX, 0]
    return offset - lx * math.floor(offset / lx)  # cheaper than a modulo (fmod); at most L_x by round-off


@inline_kernel
def streaming_velocity(params, geom, y):
    """Velocity of the shear flow along x at height y (stored, any image): u_x = G (y - L_y / 2)."""
    return params[P_SHEAR_RATE] * (y - 0.5 * geom[G_BOX, 1])


@inline_kernel
def wrapped(x, length):
    """x brought into [0, length) (a value that rounds to ``length`` becomes 0)."""
    x -= length * math.floor(x / length)
    return x if x < length else 0.0


@inline_kernel
def frame_x(params, geom, x, y, t):
    """x of the co-moving frame of the flow, at clock time t, of lab position (x, y): x - u_x(y) (t - t_f), in [0, L_x).

    The frame moves with the flow at every height and coincides with the
    lab's at the frame time t_f: a point carried by the flow keeps its frame
    x. The sliding images are fixed in it: the image above is shifted by the
    offset at t_f, o(t) - G L_y (t - t_f) = o(t_f), so the frame is a
    periodic box with a constant offset (the frame of Lagrangian
    coordinates; see :mod:`.neighbour_lists`).
    """
    return wrapped(x - streaming_velocity(params, geom, y) * (t - params[P_SHEAR_FRAME]), geom[G_BOX, 0])


@inline_kernel
def sheared_image(dx, dy, geom, offset):
    """Lees-Edwards minimum image of a separation (dx, dy) of stored positions: ``(rx, ry, n)``.

    ``n`` (-1, 0 or 1) is the number of box heights taken off dy; the
    partner's image is then shifted by ``-n`` offsets along x and moves at
    ``-n G L_y`` relative to the partner (add that to the x relative
    velocity). |dy| must be below 1.5 L_y, |dx| below L_x plus a shell and
    the offset in [0, L_x]: then two compare-and-subtracts reduce dx, no
    division (the prediction's inner loop).
    """
    ly = geom[G_BOX, 1]
    lx = geom[G_BOX, 0]
    n = 0.0
    if dy > 0.5 * ly:
        n = 1.0
    elif dy < -0.5 * ly:
        n = -1.0
    half = 0.5 * lx
    rx = minimum_image(minimum_image(dx - n * offset, lx, half), lx, half)
    return rx, dy - n * ly, n


@inline_kernel
def _wrap_sheared(p, i, geom, dim, image, params):
    """Bring particle i back into the box under Lees-Edwards shear: y first (with its image's x and v_x), then x, z.

    A particle leaving through y = L_y re-enters at y - L_y as its image
    there: x shifted back by the offset at its time and v_x by G L_y, so its
    velocity relative to the shear flow is unchanged. The image counters
    count the box lengths crossed (along x they leave out the offsets).
    """
    ly = geom[G_BOX, 1]
    y = p[i, X + 1]
    n = 0
    if y >= ly:
        n = 1
    elif y < 0.0:
        n = -1
    if n != 0:
        p[i, X + 1] = y - n * ly
        if p[i, X + 1] >= ly:  # -tiny + L rounds to L: put it at 0, no move to another image
            p[i, X + 1] = 0.0
            n = 0
        else:
            p[i, X] -= n * shear_offset(params, geom, p[i, T])
            p[i, V] -= n * params[P_SHEAR_RATE] * ly
            image[i, 1] += n
    for k in range(0, dim, 2):  # x, then z
        length = geom[G_BOX, k]
        shift = math.floor(p[i, X + k] / length)
        if shift != 0.0:
            p[i, X + k] -= shift * length
            image[i, k] += int(shift)
            if p[i, X + k] >= length:
                p[i, X + k] = 0.0
                image[i, k] += 1


@inline_kernel
def wrap_into_box(p, i, geom, dim, image, b, acc, params):
    """Bring particle i back into [0, L) on periodic axes (it is at most a box length out).

    The image counter keeps the unwrapped position ``x + image L``
    continuous. The Helfand moments of the stored positions (``sum m v_a
    x_b`` and ``sum (m v^2 / 2) x_b``) jump by the particle's share times
    the move ``dx``; the image slots of ``acc`` take it back (see
    :mod:`.layout`), so that moment plus the slots stays continuous.
    Under shear the image of :func:`_wrap_sheared` (no Helfand moments).
    """
    if params[P_SHEAR_RATE] != 0.0:
        _wrap_sheared(p, i, geom, dim, image, params)
        return
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
            _book_wrap(p, i, k, p[i, X + k] - before, b, acc)


@inline_kernel
def _book_wrap(p, i, k, moved, b, acc):
    """Take back the jump of the Helfand moments when particle i's stored x_k moved by ``moved`` (a wrap)."""
    mass = b[i, MASS]
    energy = 0.0
    for a in range(3):
        momentum = mass * p[i, V + a]
        acc[ACC_MOMENTUM_IMAGE + 3 * a + k] -= momentum * moved
        energy += 0.5 * momentum * p[i, V + a]
    acc[ACC_ENERGY_IMAGE + k] -= energy * moved


@inline_kernel
def shift_by_box(p, i, k, step, geom, image, b, acc):
    """Move particle i's stored x_k by ``step`` (+-1) box lengths to another image, as :func:`wrap_into_box` does."""
    before = p[i, X + k]
    p[i, X + k] += step * geom[G_BOX, k]
    image[i, k] -= step
    _book_wrap(p, i, k, p[i, X + k] - before, b, acc)
