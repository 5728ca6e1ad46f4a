"""Numba kernels of the exact two-body collision core.

Conventions shared by every kernel here:

* pair inputs come flattened: per-pair scalars have shape ``(n,)`` or ``(1,)``
  and vectors ``(n, d)`` or ``(1, d)``; a length-1 input is broadcast over all
  ``n`` pairs by a zero index stride (``i * stride`` with stride 0 or 1);
* kernels validate their own numbers in the same pass (a second pass over
  10^7 pairs would double the memory traffic) and return ``(code, index)``:
  ``code == OK`` on success, otherwise one of the error codes below and the
  pair index where it was found. The public layer turns it into a message.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import inline_kernel, kernel

OK = 0
BAD_M1 = 1
BAD_M2 = 2
BOTH_MASSES_INFINITE = 3
BAD_V1 = 4
BAD_V2 = 5
BAD_NORMAL = 6
ZERO_NORMAL = 7
BAD_RESTITUTION = 8
BAD_X1 = 9
BAD_X2 = 10
BAD_CONTACT_DISTANCE = 11
SEPARATION_OVERFLOW = 12  # x2 - x1 or v2 - v1 beyond the largest float

MODEL_NORMAL = 0
MODEL_CM = 1


@kernel
def _stride(array):
    return 1 if array.shape[0] > 1 else 0


@kernel
def _mass_fractions(m1, m2):
    """Return (m2/(m1+m2), m1/(m1+m2)), the shares of the velocity change.

    Written so that one infinite mass gives exact 0 and 1.
    """
    if math.isinf(m1):
        return 0.0, 1.0
    if math.isinf(m2):
        return 1.0, 0.0
    total = m1 + m2
    return m2 / total, m1 / total


# squared normal lengths computed without over- or underflow; outside, the normal is rescaled first
NORM2_SAFE_LOW = 1e-280
NORM2_SAFE_HIGH = 1e280


@kernel
def resolve_contacts(m1, v1, m2, v2, normal, restitution, model, out1, out2):
    """Velocities after an instantaneous contact along ``normal``, in place.

    Normal model: impulse along the unit normal n, with approach speed
    ``u_n = (v1 - v2) . n > 0``::

        v1' = v1 - (1 + e) m2 / (m1 + m2) u_n n
        v2' = v2 + (1 + e) m1 / (m1 + m2) u_n n

    Centre-of-mass model (Smid): the elastic result, then the velocities
    relative to the centre of mass scaled by R::

        v' = v_cm + R (v'_elastic - v_cm)

    Pairs with ``u_n <= 0`` (separating or sliding) are copied unchanged.
    A normal whose squared length would over- or underflow (1e200, 1e-170)
    is first scaled by a power of two to a largest component in [0.5, 1):
    exact, so the result is the one the formula gives in exact range.
    """
    n = out1.shape[0]
    d = out1.shape[1]
    s_m1, s_m2, s_e = _stride(m1), _stride(m2), _stride(restitution)
    s_v1, s_v2, s_n = _stride(v1), _stride(v2), _stride(normal)
    for i in range(n):
        mass1 = m1[i * s_m1]
        mass2 = m2[i * s_m2]
        e = restitution[i * s_e]
        if not mass1 > 0.0:
            return BAD_M1, i
        if not mass2 > 0.0:
            return BAD_M2, i
        if math.isinf(mass1) and math.isinf(mass2):
            return BOTH_MASSES_INFINITE, i
        if not (0.0 <= e <= 1.0):
            return BAD_RESTITUTION, i
        i1, i2, i_n = i * s_v1, i * s_v2, i * s_n
        norm2 = 0.0
        approach = 0.0
        for k in range(d):
            a = v1[i1, k]
            b = v2[i2, k]
            c = normal[i_n, k]
            if not math.isfinite(a):
                return BAD_V1, i
            if not math.isfinite(b):
                return BAD_V2, i
            if not math.isfinite(c):
                return BAD_NORMAL, i
            norm2 += c * c
            approach += (a - b) * c
            out1[i, k] = a
            out2[i, k] = b
        to_unit_scale = 1.0
        if not NORM2_SAFE_LOW < norm2 < NORM2_SAFE_HIGH:
            largest = 0.0
            for k in range(d):
                largest = max(largest, abs(normal[i_n, k]))
            if largest == 0.0:
                return ZERO_NORMAL, i
            to_unit_scale = math.ldexp(1.0, -math.frexp(largest)[1])  # a power of two: scaling is exact
            norm2 = 0.0
            approach = 0.0
            for k in range(d):
                c = normal[i_n, k] * to_unit_scale
                norm2 += c * c
                approach += (v1[i1, k] - v2[i2, k]) * c
        if approach <= 0.0:
            continue
        share1, share2 = _mass_fractions(mass1, mass2)
        if model == MODEL_NORMAL:
            # (1 + e) (u . n_hat) n_hat == (1 + e) (u . n) n / |n|^2
            impulse = (1.0 + e) * approach / norm2
            for k in range(d):
                c = normal[i_n, k] * to_unit_scale
                out1[i, k] -= share1 * impulse * c
                out2[i, k] += share2 * impulse * c
        else:
            # v1'' = v_cm + R m2/M (u - 2 (u.n_hat) n_hat), v2'' = v_cm - R m1/M (...)
            reflect = 2.0 * approach / norm2
            for k in range(d):
                a = v1[i1, k]
                b = v2[i2, k]
                u_after = (a - b) - reflect * (normal[i_n, k] * to_unit_scale)
                if share1 == 0.0:
                    centre = a
                elif share2 == 0.0:
                    centre = b
                else:
                    centre = share2 * a + share1 * b
                out1[i, k] = centre + e * share1 * u_after
                out2[i, k] = centre - e * share2 * u_after
    return OK, -1


@kernel
def contact_times(x1, v1, x2, v2, contact_distance, out):
    """Earliest time t >= 0 at which ``|x2 - x1 + (v2 - v1) t| = sigma``, in place.

    With r = x2 - x1, u = v2 - v1, the contact condition is the quadratic
    ``|u|^2 t^2 + 2 (r.u) t + (|r|^2 - sigma^2) = 0``. Its discriminant is
    evaluated as ``|u|^2 sigma^2 - |r x u|^2`` (Lagrange's identity), and the
    smaller root as ``c / (-(r.u) + sqrt(D))``; neither subtracts two large
    nearly equal numbers. Pairs already in contact or overlapping get 0 while
    approaching, inf otherwise. When a square or product would over- or
    underflow (lengths or speeds beyond 1e+-70), lengths and speeds are
    scaled by powers of two first (t scales by their ratio, exactly).
    """
    n = out.shape[0]
    d = x1.shape[1]
    s_x1, s_v1, s_x2, s_v2 = _stride(x1), _stride(v1), _stride(x2), _stride(v2)
    s_s = _stride(contact_distance)
    r = np.empty(3)
    u = np.empty(3)
    for i in range(n):
        sigma = contact_distance[i * s_s]
        if not (sigma >= 0.0 and math.isfinite(sigma)):
            return BAD_CONTACT_DISTANCE, i
        for k in range(d):
            a = x1[i * s_x1, k]
            b = x2[i * s_x2, k]
            p = v1[i * s_v1, k]
            q = v2[i * s_v2, k]
            if not math.isfinite(a):
                return BAD_X1, i
            if not math.isfinite(b):
                return BAD_X2, i
            if not math.isfinite(p):
                return BAD_V1, i
            if not math.isfinite(q):
                return BAD_V2, i
            r[k] = b - a
            u[k] = q - p
        length = sigma
        speed = 0.0
        for k in range(d):
            length = max(length, abs(r[k]))
            speed = max(speed, abs(u[k]))
        if not (math.isfinite(length) and math.isfinite(speed)):
            return SEPARATION_OVERFLOW, i
        if (SAFE_LOW < length < SAFE_HIGH or length == 0.0) and (SAFE_LOW < speed < SAFE_HIGH or speed == 0.0):
            out[i] = _first_contact(r, u, d, sigma)
            continue
        # lengths and speeds to a largest component in [0.5, 1) by powers of two: exact
        length_exponent = math.frexp(length)[1] if length > 0.0 else 0
        speed_exponent = math.frexp(speed)[1] if speed > 0.0 else 0
        for k in range(d):
            r[k] = math.ldexp(r[k], -length_exponent)
            u[k] = math.ldexp(u[k], -speed_exponent)
        tau = _first_contact(r, u, d, math.ldexp(sigma, -length_exponent))
        out[i] = math.ldexp(tau, length_exponent - speed_exponent) if math.isfinite(tau) else tau
    return OK, -1


# lengths and speeds whose squares and products stay normal floats; beyond them contact_times rescales first
SAFE_LOW = 1e-70
SAFE_HIGH = 1e70


@inline_kernel
def _first_contact(r, u, d, sigma):
    """Earliest t >= 0 with |r + u t| = sigma (see :func:`contact_times`), for moderate magnitudes."""
    rr = 0.0
    uu = 0.0
    ru = 0.0
    for k in range(d):
        rr += r[k] * r[k]
        uu += u[k] * u[k]
        ru += r[k] * u[k]
    gap = rr - sigma * sigma
    if gap <= 0.0:
        return 0.0 if ru < 0.0 else math.inf
    if ru >= 0.0 or uu == 0.0:
        return math.inf
    cross2 = 0.0
    for k in range(d):
        for l in range(k + 1, d):
            w = r[k] * u[l] - r[l] * u[k]
            cross2 += w * w
    discriminant = uu * sigma * sigma - cross2
    if discriminant < 0.0:
        return math.inf
    return gap / (-ru + math.sqrt(discriminant))
