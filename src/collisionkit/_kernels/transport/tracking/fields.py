"""Electric, magnetic and weighting fields at a point: analytic fields, field maps and compiled user functions.

Every evaluator returns a tuple and is inlined into the tracking kernel (a
numba call that is not inlined costs reference counting per array), except
the interpolation of a map (:func:`map_value`), which is called: inlined, it
was copied into every stage of the integrator twice (E and B), which made
most of the tracking kernel's first compilation (cold cache: 125 s of CPU
with the call, 210 s inlined). The tracking kernel, compiled without
reference counting, calls it without reference counts; the ions' kernel
pays them on its two arrays.

Analytic fields (SI units):

* parallel plates, gap d, the plane z = d at V and z = 0 at 0 V:
  phi = V z / d, E = -V/d z-hat;
* coaxial cylinders about the z axis through (x0, y0), wire radius a at V,
  cathode radius b at 0 V: phi = V ln(b/r) / ln(b/a),
  E = V / (r ln(b/a)) r-hat (r-hat outward); inside the wire radius the
  field of its surface is used (no particle goes there: the wire absorbs);
* point charge, k = Q / (4 pi eps0): phi = k / r, E = k r-hat / r^2 (r >= the
  smallest radius);
* magnetic dipole of moment m: B = mu0 / (4 pi) (3 r-hat (m . r-hat) - m) / r^3;
* magnetic mirror about the z axis through the centre: B_z = B0 (1 + (z/L)^2)
  and, paraxially, B_r = -(r/2) dB_z/dz, i.e. B_x = -B0 x z / L^2,
  B_y = -B0 y z / L^2 (divergence free).

A field map holds values on a regular grid (2D maps: x, y, the field
independent of z), interpolated bilinearly or trilinearly; outside its box a
point takes the value of the nearest point of the box (the kernel stops
particles that leave it). A user function ``f(x, y, z, out)`` is a numba
``cfunc`` (void(float64, float64, float64, float64*)) that writes the three
components.
"""

from __future__ import annotations

import functools
import math

import numba
import numpy as np

from ...._jit import borrowing_kernel, inline_kernel, kernel
from .codes import (
    B_DIPOLE, B_MAP, B_MIRROR, B_UNIFORM, B_USER, E_COAXIAL, E_MAP, E_PLATES, E_POINT, E_UNIFORM, E_USER, W_COAXIAL,
    W_PLATES,
)

MU0_OVER_4PI = 1e-7  # T m / A (SI, to the 1e-10 of the 2019 redefinition)


@borrowing_kernel
def map_value(meta, values, x, y, z):
    """The map's field at (x, y, z): trilinear (3D) or bilinear in x, y (2D) interpolation, a tuple.

    ``meta``: origin (0:3), spacing (3:6), points per axis (6:9), dimensions
    (9), inverse spacing (12:15). Points outside the box take the value at
    the nearest point of it.
    """
    nx, ny, nz = int(meta[6]), int(meta[7]), int(meta[8])
    fx = min(max((x - meta[0]) * meta[12], 0.0), nx - 1.0)
    fy = min(max((y - meta[1]) * meta[13], 0.0), ny - 1.0)
    i = min(int(fx), nx - 2)
    j = min(int(fy), ny - 2)
    u = fx - i
    w = fy - j
    w00 = (1.0 - u) * (1.0 - w)
    w10 = u * (1.0 - w)
    w01 = (1.0 - u) * w
    w11 = u * w
    if meta[9] == 2.0:
        a = values[i, j, 0]
        b = values[i + 1, j, 0]
        c = values[i, j + 1, 0]
        d = values[i + 1, j + 1, 0]
        return (w00 * a[0] + w10 * b[0] + w01 * c[0] + w11 * d[0], w00 * a[1] + w10 * b[1] + w01 * c[1] + w11 * d[1],
                w00 * a[2] + w10 * b[2] + w01 * c[2] + w11 * d[2])
    fz = min(max((z - meta[2]) * meta[14], 0.0), nz - 1.0)
    k = min(int(fz), nz - 2)
    s = fz - k
    out0 = out1 = out2 = 0.0
    for layer in range(2):
        weight = s if layer == 1 else 1.0 - s
        a = values[i, j, k + layer]
        b = values[i + 1, j, k + layer]
        c = values[i, j + 1, k + layer]
        d = values[i + 1, j + 1, k + layer]
        out0 += weight * (w00 * a[0] + w10 * b[0] + w01 * c[0] + w11 * d[0])
        out1 += weight * (w00 * a[1] + w10 * b[1] + w01 * c[1] + w11 * d[1])
        out2 += weight * (w00 * a[2] + w10 * b[2] + w01 * c[2] + w11 * d[2])
    return out0, out1, out2


@inline_kernel
def inside_map(meta, x, y, z):
    """True if (x, y, z) lies in the map's box (2D maps: any z)."""
    if x < meta[0] or y < meta[1]:
        return False
    if x > meta[0] + (meta[6] - 1.0) * meta[3] or y > meta[1] + (meta[7] - 1.0) * meta[4]:
        return False
    if meta[9] == 2.0:
        return True
    return meta[2] <= z <= meta[2] + (meta[8] - 1.0) * meta[5]


@inline_kernel
def map_clearance(meta, x, y, z):
    """The distance from (x, y, z), inside the map's box, to the box's nearest face (2D maps: in x and y)."""
    distance = min(x - meta[0], meta[0] + (meta[6] - 1.0) * meta[3] - x, y - meta[1],
                   meta[1] + (meta[7] - 1.0) * meta[4] - y)
    if meta[9] == 2.0:
        return distance
    return min(distance, z - meta[2], meta[2] + (meta[8] - 1.0) * meta[5] - z)


@inline_kernel
def electric_at(kind, p, meta, values, user, buffer, x, y, z):
    """The electric field (V/m) of a field of ``kind`` with parameters ``p`` at (x, y, z), a tuple."""
    if kind == E_UNIFORM:
        return p[0], p[1], p[2]
    if kind == E_PLATES:
        return 0.0, 0.0, -p[1] / p[0]
    if kind == E_COAXIAL:
        dx = x - p[0]
        dy = y - p[1]
        r2 = dx * dx + dy * dy
        if r2 == 0.0:
            return 0.0, 0.0, 0.0
        if r2 >= p[2] * p[2]:  # outside the wire: V / (ln(b/a) r^2) times (dx, dy), no square root
            scale = p[4] / (p[5] * r2)
        else:
            scale = p[4] / (p[2] * p[5] * math.sqrt(r2))
        return scale * dx, scale * dy, 0.0
    if kind == E_POINT:
        dx = x - p[0]
        dy = y - p[1]
        dz = z - p[2]
        r = max(math.sqrt(dx * dx + dy * dy + dz * dz), p[4])
        scale = p[3] / (r * r * r)
        return scale * dx, scale * dy, scale * dz
    if kind == E_MAP:
        return map_value(meta, values, x, y, z)
    if kind == E_USER:
        user(x, y, z, buffer.ctypes)
        return buffer[0], buffer[1], buffer[2]
    return 0.0, 0.0, 0.0


@inline_kernel
def magnetic_at(kind, p, meta, values, user, buffer, x, y, z):
    """The magnetic field (T) of a field of ``kind`` with parameters ``p`` at (x, y, z), a tuple."""
    if kind == B_UNIFORM:
        return p[0], p[1], p[2]
    if kind == B_DIPOLE:
        dx = x - p[0]
        dy = y - p[1]
        dz = z - p[2]
        r = max(math.sqrt(dx * dx + dy * dy + dz * dz), p[6])
        inv = 1.0 / r
        nx, ny, nz = dx * inv, dy * inv, dz * inv
        mn = p[3] * nx + p[4] * ny + p[5] * nz
        scale = MU0_OVER_4PI * inv * inv * inv
        return scale * (3.0 * mn * nx - p[3]), scale * (3.0 * mn * ny - p[4]), scale * (3.0 * mn * nz - p[5])
    if kind == B_MIRROR:
        dx = x - p[0]
        dy = y - p[1]
        dz = z - p[2]
        b0, length = p[3], p[4]
        slope = b0 * dz / (length * length)
        return -slope * dx, -slope * dy, b0 * (1.0 + (dz / length) ** 2)
    if kind == B_MAP:
        return map_value(meta, values, x, y, z)
    if kind == B_USER:
        user(x, y, z, buffer.ctypes)
        return buffer[0], buffer[1], buffer[2]
    return 0.0, 0.0, 0.0


@inline_kernel
def electric_bound(kind, p, meta, blocks, x, y, z, reach):
    """An upper bound of |E| (V/m) within ``reach`` (m) of (x, y, z); inf if none is known.

    Plates: V/d; coaxial: V / (ln(b/a) max(a, r - reach)); point charge:
    k / max(r_min, r - reach)^2; user functions: the bound given with them
    (parameter 0, 0: unknown).

    Maps: bilinear and trilinear interpolation never exceed the largest
    |value| of a cell's corners, so ``blocks`` (see
    :meth:`collisionkit.transport.tracking.FieldMap.blocks`) holds, level by
    level, the largest such value per block of 2^L cells along each axis
    and its neighbouring blocks: a point within ``reach`` of (x, y, z) lies
    in the block of (x, y, z) or a neighbour at the first level whose
    blocks are at least ``reach`` wide, whose entry is then the bound (one
    lookup). Beyond the last level, the largest value of the grid
    (``meta[10]``).
    """
    if kind == E_MAP:
        smallest = min(meta[3], meta[4]) if meta[9] == 2.0 else min(meta[3], meta[4], meta[5])
        level = 0
        cells = 1
        while cells * smallest < reach:
            cells *= 2
            level += 1
        if level >= meta[11]:
            return meta[10]
        # blocks along each axis at this level: ceil((points - 1) / cells)
        counts_x = (int(meta[6]) - 2) // cells + 1
        counts_y = (int(meta[7]) - 2) // cells + 1
        counts_z = 1 if meta[9] == 2.0 else (int(meta[8]) - 2) // cells + 1
        i = min(max(int((x - meta[0]) / (meta[3] * cells)), 0), counts_x - 1)
        j = min(max(int((y - meta[1]) / (meta[4] * cells)), 0), counts_y - 1)
        k = 0 if meta[9] == 2.0 else min(max(int((z - meta[2]) / (meta[5] * cells)), 0), counts_z - 1)
        return blocks[int(blocks[level]) + (i * counts_y + j) * counts_z + k]
    if kind == E_UNIFORM:
        return math.sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2])
    if kind == E_PLATES:
        return abs(p[1] / p[0])
    if kind == E_COAXIAL:
        r = math.sqrt((x - p[0]) ** 2 + (y - p[1]) ** 2)
        return abs(p[4]) / (p[5] * max(p[2], r - reach))
    if kind == E_POINT:
        r = math.sqrt((x - p[0]) ** 2 + (y - p[1]) ** 2 + (z - p[2]) ** 2)
        closest = max(p[4], r - reach)
        return abs(p[3]) / (closest * closest)
    if kind == E_USER:
        return p[0] if p[0] > 0.0 else math.inf
    return 0.0


@kernel
def potential_at(kind, p, x, y, z):
    """The electric potential (V) of an analytic field at (x, y, z) (uniform: -E . r; NaN for maps and users).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.tracking.codes import E_PLATES
    >>> from collisionkit._kernels.transport.tracking.fields import potential_at
    >>> potential_at(E_PLATES, np.array([0.01, 100.0, 0, 0, 0, 0, 0, 0]), 0.0, 0.0, 0.0025)
    25.0
    """
    if kind == E_UNIFORM:
        return -(p[0] * x + p[1] * y + p[2] * z)
    if kind == E_PLATES:
        return p[1] * z / p[0]
    if kind == E_COAXIAL:
        r = max(math.sqrt((x - p[0]) ** 2 + (y - p[1]) ** 2), p[2])
        return p[4] * math.log(p[3] / r) / p[5]
    if kind == E_POINT:
        r = max(math.sqrt((x - p[0]) ** 2 + (y - p[1]) ** 2 + (z - p[2]) ** 2), p[4])
        return p[3] / r
    if kind == 0:
        return 0.0
    return math.nan


@inline_kernel
def weighting_field(kind, p, x, y, z):
    """The weighting field E_w = -grad phi_w (1/m) of the readout electrode, a tuple.

    Parallel plates (the plane z = d reads out; ``p``: d): E_w = -z-hat/d;
    coaxial (the wire reads out; ``p``: axis x, y, a, b, ln(b/a)):
    E_w = r-hat / (r ln(b/a)) (Shockley, J. Appl. Phys. 9, 635 (1938); Ramo,
    Proc. IRE 27, 584 (1939)).
    """
    if kind == W_PLATES:
        return 0.0, 0.0, -1.0 / p[0]
    if kind == W_COAXIAL:
        dx = x - p[0]
        dy = y - p[1]
        r = max(math.sqrt(dx * dx + dy * dy), p[2])
        scale = 1.0 / (r * r * p[4])
        return scale * dx, scale * dy, 0.0
    return 0.0, 0.0, 0.0


@inline_kernel
def weighting_potential(kind, p, x, y, z):
    """The weighting potential phi_w of the readout electrode (1 on it, 0 on the others): z/d for plates,
    ln(b/r)/ln(b/a) for a counter (see :func:`weighting_field`)."""
    if kind == W_PLATES:
        return z / p[0]
    if kind == W_COAXIAL:
        r = max(math.sqrt((x - p[0]) ** 2 + (y - p[1]) ** 2), p[2])
        return math.log(p[3] / r) / p[4]
    return 0.0


@kernel
def field_values(magnetic, kind, p, meta, values, user, points, out):
    """The field at every row of ``points`` (n x 3) into ``out`` (n x 3): E (V/m), or B (T) if ``magnetic``.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.tracking.codes import B_MIRROR
    >>> from collisionkit._kernels.transport.tracking.fields import field_values, no_field
    >>> out = np.zeros((1, 3))
    >>> field_values(True, B_MIRROR, np.array([0, 0, 0, 1.0, 2.0, 0, 0, 0]), np.zeros(12), np.zeros((2, 2, 2, 3)),
    ...              no_field(), np.array([[0.1, 0.0, 2.0]]), out)
    >>> (out.round(6) + 0.0).tolist()  # B0 (1 + (z/L)^2) = 2 along z; B_x = -B0 x z / L^2 = -0.05
    [[-0.05, 0.0, 2.0]]
    """
    buffer = np.zeros(3)
    for i in range(points.shape[0]):
        x, y, z = points[i, 0], points[i, 1], points[i, 2]
        if magnetic:
            out[i, 0], out[i, 1], out[i, 2] = magnetic_at(kind, p, meta, values, user, buffer, x, y, z)
        else:
            out[i, 0], out[i, 1], out[i, 2] = electric_at(kind, p, meta, values, user, buffer, x, y, z)


USER_FIELD_SIGNATURE = "void(float64, float64, float64, CPointer(float64))"


@functools.lru_cache(maxsize=1)
def no_field():
    """The compiled function passed for a field that is not a user's (writes nothing; never called).

    Examples
    --------
    >>> from collisionkit._kernels.transport.tracking.fields import no_field
    >>> no_field() is no_field()
    True
    """
    return numba.cfunc(USER_FIELD_SIGNATURE, cache=True)(_nothing)


def _nothing(x, y, z, out):
    return None


def compile_user_field(function):
    """A user's field ``function(x, y, z, out)`` (writing 3 components into the array ``out``) as the kernels'
    compiled function: numba-compiled if it is not yet, wrapped in a ``cfunc`` of :data:`USER_FIELD_SIGNATURE`.

    The tracking kernel takes any such function without compiling again.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit._kernels.transport.tracking.codes import E_USER
    >>> from collisionkit._kernels.transport.tracking.fields import compile_user_field, field_values
    >>> def field(x, y, z, out):
    ...     out[0] = 2.0 * x
    ...     out[1] = 0.0
    ...     out[2] = z
    >>> out = np.zeros((1, 3))
    >>> field_values(False, E_USER, np.zeros(8), np.zeros(12), np.zeros((2, 2, 2, 3)), compile_user_field(field),
    ...              np.array([[1.5, 0.0, -1.0]]), out)
    >>> out.tolist()
    [[3.0, 0.0, -1.0]]
    """
    inner = function if isinstance(function, numba.core.dispatcher.Dispatcher) else numba.njit(function)

    def wrapper(x, y, z, pointer):
        inner(x, y, z, numba.carray(pointer, 3))

    return numba.cfunc(USER_FIELD_SIGNATURE)(wrapper)
