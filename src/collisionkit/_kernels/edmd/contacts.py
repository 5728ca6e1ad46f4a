"""Resolving events: a pair collision (restitution laws, compression) and a bounce off a wall."""

from __future__ import annotations

import math

# no EDMD kernel allocates or returns an array: all of them borrow, without reference counting
from ..._jit import borrowing_inline_kernel as inline_kernel
from .layout import (
    ACC_ENERGY_LOST, ACC_PAIR_COLLISIONS, ACC_VIRIAL, ACC_WALL_COLLISIONS, ACC_WALL_IMPULSE, G_BOX, G_PERIODIC,
    LAW_BRIDGES, MASS, P_ELASTIC_BELOW, P_LAW, P_LAW_EXPONENT, P_LAW_SPEED, P_WALL_RESTITUTION, R, SPECIES, V, X,
)


@inline_kernel
def restitution_for(i, j, approach, b, restitution, params):
    """Coefficient of normal restitution of one contact."""
    if approach < params[P_ELASTIC_BELOW]:
        return 1.0
    e = restitution[int(b[i, SPECIES]), int(b[j, SPECIES])]
    speed = params[P_LAW_SPEED]
    if params[P_LAW] == LAW_BRIDGES and approach > speed:
        e = min(e, (approach / speed) ** (-params[P_LAW_EXPONENT]))
    return e


@inline_kernel
def collide_pair(p, i, j, b, geom, dim, scale, growth, restitution, params, acc):
    """Resolve the contact of i and j (both at the current time)."""
    rx = 0.0
    ry = 0.0
    rz = 0.0
    for k in range(dim):
        x = p[j, X + k] - p[i, X + k]
        if geom[G_PERIODIC, k] != 0.0:
            length = geom[G_BOX, k]
            x -= length * round(x / length)
        if k == 0:
            rx = x
        elif k == 1:
            ry = x
        else:
            rz = x
    distance = math.sqrt(rx * rx + ry * ry + rz * rz)
    nx = rx / distance
    ny = ry / distance
    nz = rz / distance
    approach = (p[i, V] - p[j, V]) * nx + (p[i, V + 1] - p[j, V + 1]) * ny + (p[i, V + 2] - p[j, V + 2]) * nz
    # while compressing, the contact distance grows at (r_i + r_j) * growth
    surface_rate = (p[i, R] + p[j, R]) * growth
    if approach + surface_rate <= 0.0:
        return
    mi = b[i, MASS]
    mj = b[j, MASS]
    reduced = mi * mj / (mi + mj)
    if growth != 0.0:
        impulse = reduced * 2.0 * (approach + surface_rate)
    else:
        e = restitution_for(i, j, approach, b, restitution, params)
        impulse = reduced * (1.0 + e) * approach
        acc[ACC_ENERGY_LOST] += 0.5 * reduced * (1.0 - e * e) * approach * approach
    p[i, V] -= impulse / mi * nx
    p[i, V + 1] -= impulse / mi * ny
    p[i, V + 2] -= impulse / mi * nz
    p[j, V] += impulse / mj * nx
    p[j, V + 1] += impulse / mj * ny
    p[j, V + 2] += impulse / mj * nz
    acc[ACC_VIRIAL] += impulse * distance
    acc[ACC_PAIR_COLLISIONS] += 1.0


@inline_kernel
def bounce_off_wall(p, i, code, b, params, acc):
    """Reflect particle i off wall ``code`` (2 * axis + 1 upper, 2 * axis lower) if it moves into it."""
    axis = code // 2
    upward = code % 2 == 1
    v = p[i, V + axis]
    if (upward and v > 0.0) or ((not upward) and v < 0.0):
        e = params[P_WALL_RESTITUTION]
        p[i, V + axis] = -e * v
        acc[ACC_WALL_IMPULSE] += b[i, MASS] * (1.0 + e) * abs(v)
        acc[ACC_WALL_COLLISIONS] += 1.0
