"""Resolving events: a pair collision (restitution laws, compression, rough spheres) and a bounce off a wall.

A pair collides only if it approaches by the prediction's own test,
``r . u - shift < 0`` with a sure sign (:func:`.exact.sure_approach`): for
a pair at one time the two agree bit for bit, so a pair the prediction
sends to collide at once is never found receding by the collision step
(which would leave it unchanged, to be predicted again at the same instant
for ever).

The velocity change is ``(1 + e) (m_j / M) (b / |r|^2) r`` for i and the
opposite of ``(1 + e) (m_i / M) (b / |r|^2) r`` for j: along ``r`` itself,
with ``b / |r|^2`` from error-free sums rounded once
(:func:`.exact.approach_ratio`). The former update along a normal rounded
to unit length raised the energy of every elastic collision by
``2 mu u_n^2 (|n|^2 - 1)``, and ``|n|^2 - 1`` is +8e-17 on average, not
zero: +5e-17 of the pair's energy per collision, always up. A plain
``b / |r|^2`` still left +4e-18 (the quotient of a rounded ``b`` by
``|r|^2`` within a few units in the last place of 1, contact at diameter
1, rounds up more often than down). What is left is unbiased round-off.

Rough spheres (:func:`rough_impulse`) add an impulse along the tangent of
the contact that turns the tangential relative velocity of the touching
surfaces into ``-beta`` times itself; it changes neither the normal
relative velocity nor the collision time, so it follows the normal impulse.
"""

from __future__ import annotations

import math

# no EDMD kernel allocates or returns an array: all of them borrow, without reference counting
from ..._jit import borrowing_inline_kernel as inline_kernel
from .layout import (
    ACC_ENERGY_IMAGE, ACC_ENERGY_LOST, ACC_HEAT, ACC_MOMENTUM_IMAGE, ACC_PAIR_COLLISIONS, ACC_STRESS, ACC_VIRIAL,
    ACC_WALL_COLLISIONS, ACC_WALL_IMPULSE, G_BOX, LAW_BRIDGES, LAW_VISCOELASTIC, MASS, P_ELASTIC_BELOW, P_FRICTION,
    P_INERTIA_FACTOR, P_LAW, P_LAW_EXPONENT, P_LAW_SPEED, P_SHEAR_RATE, P_TANGENTIAL_RESTITUTION, P_WALL_RESTITUTION,
    R, SPECIES, T, V, X,
)
from .exact import approach_ratio, sure_approach
from .motion import half_box, minimum_image, shear_offset, sheared_image
from .restitution_laws import viscoelastic_restitution

# the relative spacing of doubles: the smallest velocity change that is not lost to rounding, relative to the velocity
_LAST_PLACE = 2.0**-52


@inline_kernel
def restitution_for(i, j, approach, b, restitution, params):
    """Coefficient of normal restitution of one contact: the pair's, or its law's at ``approach`` if smaller."""
    if approach < params[P_ELASTIC_BELOW]:
        return 1.0
    e = restitution[int(b[i, SPECIES]), int(b[j, SPECIES])]
    speed = params[P_LAW_SPEED]
    if params[P_LAW] == LAW_BRIDGES and approach > speed:
        e = min(e, (approach / speed) ** (-params[P_LAW_EXPONENT]))
    elif params[P_LAW] == LAW_VISCOELASTIC:
        e = min(e, viscoelastic_restitution((approach / speed) ** 0.2))
    return e


@inline_kernel
def collide_pair(p, i, j, b, geom, scale, growth, restitution, params, acc, spin):
    """Resolve the contact of i and j (both at the current time); False if they do not approach (no collision).

    The approach test is the prediction's, and the impulse is along the
    separation itself (see the module docstring). ``spin`` holds the angular
    velocities of rough spheres (read only if ``params[P_INERTIA_FACTOR]`` is
    not 0: smooth spheres may pass an empty array).
    """
    dx = p[j, X] - p[i, X]
    dy = p[j, X + 1] - p[i, X + 1]
    dz = p[j, X + 2] - p[i, X + 2]
    slide = 0.0  # x velocity of j's nearest image relative to j (Lees-Edwards shear)
    if params[P_SHEAR_RATE] != 0.0:
        rx, ry, n = sheared_image(dx, dy, geom, shear_offset(params, geom, p[i, T]))
        slide = -n * params[P_SHEAR_RATE] * geom[G_BOX, 1]
    else:
        rx = minimum_image(dx, geom[G_BOX, 0], half_box(geom, 0))
        ry = minimum_image(dy, geom[G_BOX, 1], half_box(geom, 1))
    rz = minimum_image(dz, geom[G_BOX, 2], half_box(geom, 2))
    ux = p[j, V] + slide - p[i, V]
    uy = p[j, V + 1] - p[i, V + 1]
    uz = p[j, V + 2] - p[i, V + 2]
    contact = p[i, R] + p[j, R]
    # while compressing, the contact distance grows at contact * growth
    shift = (contact * scale) * (contact * growth)
    if not sure_approach(rx * ux + ry * uy + rz * uz - shift, rx, ry, rz, ux, uy, uz, shift) < 0.0:
        return False
    ratio = approach_ratio(rx, ry, rz, ux, uy, uz, shift)  # < 0: the same error-free sum's sign
    rr = rx * rx + ry * ry + rz * rz
    mi = b[i, MASS]
    mj = b[j, MASS]
    reduced = mi * mj / (mi + mj)
    approach = 0.0
    if growth != 0.0:
        # elastic in the frame of the growing surfaces
        e = 1.0
    else:
        approach = -ratio * math.sqrt(rr)
        e = restitution_for(i, j, approach, b, restitution, params)
        acc[ACC_ENERGY_LOST] += 0.5 * reduced * (1.0 - e * e) * approach * approach
    share_i = (1.0 + e) * (mj / (mi + mj)) * ratio
    share_j = (1.0 + e) * (mi / (mi + mj)) * ratio
    # the impulse on j is -(1 + e) mu ratio r; its energy change dp . (v + v') / 2 from j's velocity before
    push = -(1.0 + e) * reduced * ratio  # > 0: j is pushed along r, away from i
    gain = push * (rx * (p[j, V] + slide) + ry * p[j, V + 1] + rz * p[j, V + 2]) + 0.5 * push * push * rr / mj
    add_transfer(acc, push, gain, rx, ry, rz)
    # the pair meets across a periodic face: Erpenbeck's image terms (none under shear: no Helfand moments there)
    if (rx != dx or ry != dy or rz != dz) and params[P_SHEAR_RATE] == 0.0:
        add_image_terms(acc, push, gain, rx, ry, rz, dx, dy, dz, geom)
    p[i, V] += share_i * rx
    p[i, V + 1] += share_i * ry
    p[i, V + 2] += share_i * rz
    p[j, V] -= share_j * rx
    p[j, V + 1] -= share_j * ry
    p[j, V + 2] -= share_j * rz
    # rough spheres (never compressed): a contact below the elastic floor is smooth as well, so that it loses nothing
    if params[P_INERTIA_FACTOR] != 0.0 and params[P_TANGENTIAL_RESTITUTION] != -1.0 and growth == 0.0 and \
            approach >= params[P_ELASTIC_BELOW]:
        rough_impulse(p, i, j, rx, ry, rz, slide, rr, mi, mj, spin, params, acc, (1.0 + e) * approach)
    _separate(p, i, j, rx, ry, rz, shift, slide, mj / (mi + mj), mi / (mi + mj), rr)
    # impulse times contact distance: (1 + e) mu u_n |r|
    acc[ACC_VIRIAL] -= (1.0 + e) * reduced * ratio * rr
    acc[ACC_PAIR_COLLISIONS] += 1.0
    return True


@inline_kernel
def rough_impulse(p, i, j, rx, ry, rz, slide, rr, mi, mj, spin, params, acc, normal_change):
    r"""The tangential impulse of a collision of rough spheres (r = x_j - x_i at contact, j's image moving + slide).

    The surfaces' relative velocity at the contact point is
    :math:`g = v_j - v_i - (a_i \omega_i + a_j \omega_j) \times \hat n`;
    its tangential part :math:`g_t` becomes :math:`-\beta g_t`, through the
    impulse :math:`J = -(1 + \beta) \mu_t g_t` on j (and -J on i) with
    :math:`1/\mu_t = (1 + 1/\kappa)(1/m_i + 1/m_j)` for moments of inertia
    :math:`I = \kappa m a^2`; both spins change by
    :math:`-a \hat n \times J / I`. Linear momentum and the total angular
    momentum (orbital and spin) are kept; the energy falls by
    :math:`\mu_t (1 - \beta^2) g_t^2 / 2` (Huthmann & Zippelius, Phys. Rev. E
    56, R6275 (1997); Luding et al., Phys. Rev. E 58, 3416 (1998)). The
    normal impulse has acted already: it does not change :math:`g_t`.

    With a friction coefficient mu (Walton's model: Walton, Mech. Mater. 16,
    239 (1993); Luding et al. 1998) the tangential impulse is at most mu
    times the normal one, :math:`(1 + \beta)\mu_t |g_t| \le \mu \mu_n
    \Delta g_n` with ``normal_change`` :math:`\Delta g_n = (1 + e) u_n`:
    a contact sticks (beta) or slides with
    :math:`1 + \beta_{eff} = \mu \Delta g_n (1 + 1/\kappa) / |g_t|`.
    """
    norm = math.sqrt(rr)
    nx = rx / norm
    ny = ry / norm
    nz = rz / norm
    ai = p[i, R]
    aj = p[j, R]
    wx = ai * spin[i, 0] + aj * spin[j, 0]
    wy = ai * spin[i, 1] + aj * spin[j, 1]
    wz = ai * spin[i, 2] + aj * spin[j, 2]
    gx = p[j, V] + slide - p[i, V] - (wy * nz - wz * ny)
    gy = p[j, V + 1] - p[i, V + 1] - (wz * nx - wx * nz)
    gz = p[j, V + 2] - p[i, V + 2] - (wx * ny - wy * nx)
    normal = gx * nx + gy * ny + gz * nz
    tx = gx - normal * nx
    ty = gy - normal * ny
    tz = gz - normal * nz
    kappa = params[P_INERTIA_FACTOR]
    reduced = (kappa / (1.0 + kappa)) * (mi * mj / (mi + mj))
    beta = params[P_TANGENTIAL_RESTITUTION]
    roughness = 1.0 + beta
    slip = math.sqrt(tx * tx + ty * ty + tz * tz)
    if params[P_FRICTION] > 0.0 and slip > 0.0:
        sliding = params[P_FRICTION] * normal_change * (1.0 + 1.0 / kappa) / slip
        if sliding < roughness:
            roughness = sliding
            beta = roughness - 1.0
    jx = -roughness * reduced * tx
    jy = -roughness * reduced * ty
    jz = -roughness * reduced * tz
    p[i, V] -= jx / mi
    p[i, V + 1] -= jy / mi
    p[i, V + 2] -= jz / mi
    p[j, V] += jx / mj
    p[j, V + 1] += jy / mj
    p[j, V + 2] += jz / mj
    # torque arms: +a_i n on i (pushed by -J), -a_j n on j (pushed by J): both spins change by -(n x J) / (kappa m a)
    cx = ny * jz - nz * jy
    cy = nz * jx - nx * jz
    cz = nx * jy - ny * jx
    turn_i = 1.0 / (kappa * mi * ai)
    turn_j = 1.0 / (kappa * mj * aj)
    spin[i, 0] -= cx * turn_i
    spin[i, 1] -= cy * turn_i
    spin[i, 2] -= cz * turn_i
    spin[j, 0] -= cx * turn_j
    spin[j, 1] -= cy * turn_j
    spin[j, 2] -= cz * turn_j
    acc[ACC_ENERGY_LOST] += 0.5 * reduced * (1.0 - beta * beta) * slip * slip
    # the collisional stress gets the symmetric part of J r (no trace: J is normal to r, the pressure is unchanged)
    acc[ACC_STRESS] += jx * rx
    acc[ACC_STRESS + 1] += jy * ry
    acc[ACC_STRESS + 2] += jz * rz
    acc[ACC_STRESS + 3] += 0.5 * (jx * ry + jy * rx)
    acc[ACC_STRESS + 4] += 0.5 * (jx * rz + jz * rx)
    acc[ACC_STRESS + 5] += 0.5 * (jy * rz + jz * ry)


@inline_kernel
def add_transfer(acc, push, gain, rx, ry, rz):
    """Add a collision's momentum and energy transfer (impulse ``push r`` and energy ``gain`` given to j) to the sums.

    The collisional stress gets ``push r_a r_b`` (the impulse on j times the
    separation), the collisional heat flux ``gain r_a``: their time
    derivatives are the impulsive parts of the momentum and energy fluxes
    (Allen & Tildesley, Computer Simulation of Liquids, 2nd ed., sec. 2.7
    and 3.7; for hard spheres Alder, Gass & Wainwright, J. Chem. Phys. 53,
    3813 (1970)).
    """
    px = push * rx
    py = push * ry
    pz = push * rz
    acc[ACC_STRESS] += px * rx
    acc[ACC_STRESS + 1] += py * ry
    acc[ACC_STRESS + 2] += pz * rz
    acc[ACC_STRESS + 3] += px * ry
    acc[ACC_STRESS + 4] += px * rz
    acc[ACC_STRESS + 5] += py * rz
    acc[ACC_HEAT] += gain * rx
    acc[ACC_HEAT + 1] += gain * ry
    acc[ACC_HEAT + 2] += gain * rz


@inline_kernel
def add_image_terms(acc, push, gain, rx, ry, rz, dx, dy, dz, geom):
    """Erpenbeck's image terms of a collision across a periodic face (r the minimum image, d = x_j - x_i stored).

    The Helfand moment of the stored positions jumps by the transfer times
    ``d``, the stress integral's by the transfer times ``r``: the difference,
    the transfer times the image shift ``r - d`` (a box length or 0 per
    axis), is added to the image slots (see :mod:`.layout`).
    """
    for b in range(3):
        r = rx if b == 0 else (ry if b == 1 else rz)
        d = dx if b == 0 else (dy if b == 1 else dz)
        if r != d:
            shift = -geom[G_BOX, b] if d > r else geom[G_BOX, b]
            acc[ACC_MOMENTUM_IMAGE + b] += push * rx * shift
            acc[ACC_MOMENTUM_IMAGE + 3 + b] += push * ry * shift
            acc[ACC_MOMENTUM_IMAGE + 6 + b] += push * rz * shift
            acc[ACC_ENERGY_IMAGE + b] += gain * shift


@inline_kernel
def _approaches(p, i, j, rx, ry, rz, shift, slide):
    """The approach test of the prediction and the collision step for the pair's velocities now (j's image: + slide)."""
    ux = p[j, V] + slide - p[i, V]
    uy = p[j, V + 1] - p[i, V + 1]
    uz = p[j, V + 2] - p[i, V + 2]
    return sure_approach(rx * ux + ry * uy + rz * uz - shift, rx, ry, rz, ux, uy, uz, shift) < 0.0


@inline_kernel
def _separate(p, i, j, rx, ry, rz, shift, slide, share_i, share_j, rr):
    """Make sure the pair no longer approaches after its collision: else it would collide again at once, for ever.

    An impulse below the last place of the velocities changes nothing (a
    grazing or sticky contact, ``b`` of 1e-18): the pair is pushed apart
    along ``r`` by a kick from the velocities' last place, doubled until
    the approach test says it recedes.
    """
    kick = 0.0
    while _approaches(p, i, j, rx, ry, rz, shift, slide):
        if kick == 0.0:
            speed = 0.0
            for k in range(3):
                speed = max(speed, abs(p[i, V + k]), abs(p[j, V + k]))
            kick = _LAST_PLACE * max(speed / math.sqrt(rr), abs(shift) / rr)  # > 0 if the pair approaches
        else:
            kick *= 2.0
        for k in range(3):
            x = rx if k == 0 else (ry if k == 1 else rz)
            p[i, V + k] -= share_i * kick * x
            p[j, V + k] += share_j * kick * x


@inline_kernel
def bounce_off_wall(p, i, code, b, params, acc):
    """Reflect particle i off wall ``code`` (2 * axis + 1 upper, 2 * axis lower) if it moves into it."""
    axis = code // 2
    upward = code % 2 == 1
    v = p[i, V + axis]
    if (upward and v > 0.0) or ((not upward) and v < 0.0):
        e = params[P_WALL_RESTITUTION] if abs(v) >= params[P_ELASTIC_BELOW] else 1.0
        p[i, V + axis] = -e * v
        acc[ACC_WALL_IMPULSE] += b[i, MASS] * (1.0 + e) * abs(v)
        acc[ACC_WALL_COLLISIONS] += 1.0
