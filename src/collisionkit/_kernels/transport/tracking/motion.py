"""One Dormand-Prince 5(4) step of a charged particle in E(x) and B(x), held in scalars.

The tableau of :mod:`.integrator` (Dormand & Prince 1980), for position and
velocity alone: the null-collision method's step. The path-length method
integrates the optical depth as a seventh component and takes the array
form of :mod:`.integrator`; this form keeps every stage in registers, where
the array form stores each stage and loads it back for the next (a stage
depends on all before it, so those round trips add up along the chain).
The two agree to rounding (tested).
"""

from __future__ import annotations

import math

from ...._jit import inline_kernel
from .fields import electric_at, magnetic_at
from .integrator import (
    A21, A31, A32, A41, A42, A43, A51, A52, A53, A54, A61, A62, A63, A64, A65, A71, A73, A74, A75, A76, E1, E3, E4,
    E5, E6, E7,
)


@inline_kernel
def acceleration(qm, e_kind, e_par, e_meta, e_values, e_user, b_kind, b_par, b_meta, b_values, b_user, buffer,
                 position, velocity):
    """(q/m)(E + v x B) at ``position`` for ``velocity`` (3-tuples), a tuple."""
    x, y, z = position
    vx, vy, vz = velocity
    ex, ey, ez = electric_at(e_kind, e_par, e_meta, e_values, e_user, buffer, x, y, z)
    bx, by, bz = magnetic_at(b_kind, b_par, b_meta, b_values, b_user, buffer, x, y, z)
    return qm * (ex + vy * bz - vz * by), qm * (ey + vz * bx - vx * bz), qm * (ez + vx * by - vy * bx)


@inline_kernel
def _advanced(base, h, w1, k1, w2, k2, w3, k3, w4, k4, w5, k5):
    """base + h (w1 k1 + ... + w5 k5) for 3-tuples."""
    return (base[0] + h * (w1 * k1[0] + w2 * k2[0] + w3 * k3[0] + w4 * k4[0] + w5 * k5[0]),
            base[1] + h * (w1 * k1[1] + w2 * k2[1] + w3 * k3[1] + w4 * k4[1] + w5 * k5[1]),
            base[2] + h * (w1 * k1[2] + w2 * k2[2] + w3 * k3[2] + w4 * k4[2] + w5 * k5[2]))


@inline_kernel
def _largest_error(h, k1, k3, k4, k5, k6, k7, scale):
    """max over the components of |h (E1 k1 + E3 k3 + ... + E7 k7)| / scale: the 5th minus the 4th-order solution."""
    worst = 0.0
    for c in range(3):
        difference = h * (E1 * k1[c] + E3 * k3[c] + E4 * k4[c] + E5 * k5[c] + E6 * k6[c] + E7 * k7[c])
        worst = max(worst, abs(difference) / scale)
    return worst


@inline_kernel
def field_step(position, velocity, accel, h, qm, e_kind, e_par, e_meta, e_values, e_user, b_kind, b_par, b_meta,
               b_values, b_user, buffer, position_scale, speed_floor, tolerance):
    """A Dormand-Prince 5(4) step of ``h`` from ``position``, ``velocity`` and ``accel`` (3-tuples, the last the
    acceleration there): (position, velocity, acceleration at the end, error norm).

    The error norm is that of :func:`.integrator.error_norm`: position
    components against ``tolerance * position_scale``, velocity ones against
    ``tolerance * max(|v0|, |v1|, speed_floor)``; <= 1 accepts the step.
    """
    zero = (0.0, 0.0, 0.0)
    v1, a1 = velocity, accel
    x2 = _advanced(position, h, A21, v1, 0.0, zero, 0.0, zero, 0.0, zero, 0.0, zero)
    v2 = _advanced(velocity, h, A21, a1, 0.0, zero, 0.0, zero, 0.0, zero, 0.0, zero)
    a2 = acceleration(qm, e_kind, e_par, e_meta, e_values, e_user, b_kind, b_par, b_meta, b_values,
                      b_user, buffer, x2, v2)
    x3 = _advanced(position, h, A31, v1, A32, v2, 0.0, zero, 0.0, zero, 0.0, zero)
    v3 = _advanced(velocity, h, A31, a1, A32, a2, 0.0, zero, 0.0, zero, 0.0, zero)
    a3 = acceleration(qm, e_kind, e_par, e_meta, e_values, e_user, b_kind, b_par, b_meta, b_values,
                      b_user, buffer, x3, v3)
    x4 = _advanced(position, h, A41, v1, A42, v2, A43, v3, 0.0, zero, 0.0, zero)
    v4 = _advanced(velocity, h, A41, a1, A42, a2, A43, a3, 0.0, zero, 0.0, zero)
    a4 = acceleration(qm, e_kind, e_par, e_meta, e_values, e_user, b_kind, b_par, b_meta, b_values,
                      b_user, buffer, x4, v4)
    x5 = _advanced(position, h, A51, v1, A52, v2, A53, v3, A54, v4, 0.0, zero)
    v5 = _advanced(velocity, h, A51, a1, A52, a2, A53, a3, A54, a4, 0.0, zero)
    a5 = acceleration(qm, e_kind, e_par, e_meta, e_values, e_user, b_kind, b_par, b_meta, b_values,
                      b_user, buffer, x5, v5)
    x6 = _advanced(position, h, A61, v1, A62, v2, A63, v3, A64, v4, A65, v5)
    v6 = _advanced(velocity, h, A61, a1, A62, a2, A63, a3, A64, a4, A65, a5)
    a6 = acceleration(qm, e_kind, e_par, e_meta, e_values, e_user, b_kind, b_par, b_meta, b_values,
                      b_user, buffer, x6, v6)
    x7 = _advanced(position, h, A71, v1, A73, v3, A74, v4, A75, v5, A76, v6)
    v7 = _advanced(velocity, h, A71, a1, A73, a3, A74, a4, A75, a5, A76, a6)
    a7 = acceleration(qm, e_kind, e_par, e_meta, e_values, e_user, b_kind, b_par, b_meta, b_values,
                      b_user, buffer, x7, v7)
    speed = max(speed_floor, math.sqrt(max(v1[0] * v1[0] + v1[1] * v1[1] + v1[2] * v1[2],
                                           v7[0] * v7[0] + v7[1] * v7[1] + v7[2] * v7[2])))
    error = max(_largest_error(h, v1, v3, v4, v5, v6, v7, tolerance * position_scale),
                _largest_error(h, a1, a3, a4, a5, a6, a7, tolerance * speed))
    return x7, v7, a7, error
