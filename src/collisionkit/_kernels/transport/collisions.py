"""Velocities after a real collision: two-body (elastic, excitation) and ionizing.

These helpers take scalars (and the random state) and return tuples: a
numba function that is not inlined increments and decrements the reference
count of every array it receives, which costs more than a collision when
the argument list is long.
"""

from __future__ import annotations

import math

from ..._jit import kernel
from .layout import SHARE_EQUAL
from .rng import uniform
from .scattering import isotropic_direction, scattered_direction


@kernel
def two_body(vx, vy, vz, gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy, mass, target_mass, loss, model,
             screening, state):
    """Projectile velocity after an elastic (``loss`` = 0), inelastic or superelastic (``loss`` < 0) two-body
    collision.

    The relative kinetic energy drops by ``loss`` (the threshold; a
    superelastic collision gains the excitation energy), the relative
    velocity turns in the centre-of-mass frame and the centre-of-mass
    velocity is kept (exact recoil).
    """
    total = mass + target_mass
    g_after = g_speed
    if loss != 0.0:
        mu = mass * target_mass / total
        g_after = math.sqrt(2.0 * max(0.0, 0.5 * mu * g_speed * g_speed - loss) / mu)
    nx, ny, nz = scattered_direction(model, energy, screening, gx, gy, gz, g_speed, state)
    light = mass / total
    heavy = target_mass / total
    share = heavy * g_after
    return (light * vx + heavy * gas_vx + share * nx,
            light * vy + heavy * gas_vy + share * ny,
            light * vz + heavy * gas_vz + share * nz)


@kernel
def ionized(gas_vx, gas_vy, gas_vz, gx, gy, gz, g_speed, energy, mass, loss, sharing, model, screening, state):
    """Velocities of the scattered and the new electron after an ionizing collision (a 6-tuple).

    The energy left above the threshold ``loss`` is shared equally or
    uniformly; the scattered electron follows the angular model, the new
    one leaves isotropically, both from the target's frame.
    """
    available = energy - loss
    share = 0.5 if sharing == SHARE_EQUAL else uniform(state)
    e1 = max(0.0, share * available)
    e2 = max(0.0, available - e1)
    nx, ny, nz = scattered_direction(model, energy, screening, gx, gy, gz, g_speed, state)
    u1 = math.sqrt(2.0 * e1 / mass)
    cx, cy, cz = isotropic_direction(state)
    u2 = math.sqrt(2.0 * e2 / mass)
    return (gas_vx + u1 * nx, gas_vy + u1 * ny, gas_vz + u1 * nz,
            gas_vx + u2 * cx, gas_vy + u2 * cy, gas_vz + u2 * cz)
