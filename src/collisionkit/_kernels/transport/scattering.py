"""Directions after scattering: centre-of-mass deflection angles (isotropic, screened Coulomb, Okhrimovskyy,
Vahedi-Surendra, forward)."""

from __future__ import annotations

import math

from ..._jit import kernel
from .layout import ELECTRONVOLT, FORWARD, HARTREE, ISOTROPIC, OKHRIMOVSKYY, VAHEDI_SURENDRA
from .rng import uniform


@kernel
def cosine_from_uniform(model, energy, screening, u):
    """cos(chi) in the centre-of-mass frame from a uniform number ``u`` in (0, 1) (energy and screening in J).

    Inversion of the laws' cumulative distributions
    (:mod:`collisionkit.transport.angular`): isotropic 1 - 2u; screened
    Coulomb (Wentzel, density proportional to (1 + 2 eta - cos chi)^-2, eta =
    screening / (4 energy)) 1 + 2 eta - 2 eta (1 + eta) / (eta + u);
    Okhrimovskyy 1 - 2u (1 - xi) / (1 + xi (1 - 2u)) with xi = 4 energy /
    (E_h + 4 energy); Vahedi-Surendra (2 + e - 2 (1 + e)^u) / e with e the
    energy in eV; forward 1.
    """
    if model == ISOTROPIC or energy <= 0.0:
        return 1.0 - 2.0 * u
    if model == FORWARD:
        return 1.0
    if model == OKHRIMOVSKYY:
        xi = 4.0 * energy / (HARTREE + 4.0 * energy)
        return 1.0 - 2.0 * u * (1.0 - xi) / (1.0 + xi * (1.0 - 2.0 * u))
    if model == VAHEDI_SURENDRA:
        e = energy / ELECTRONVOLT
        return max(-1.0, 1.0 - 2.0 * math.expm1(u * math.log1p(e)) / e)
    eta = screening / (4.0 * energy)
    c = 1.0 + 2.0 * eta - 2.0 * eta * (1.0 + eta) / (eta + u)
    return min(1.0, max(-1.0, c))


@kernel
def scattering_cosine(model, energy, screening, state):
    """cos(chi) in the centre-of-mass frame, drawn with :func:`cosine_from_uniform`."""
    return cosine_from_uniform(model, energy, screening, uniform(state))


@kernel
def rotated(ux, uy, uz, cos_chi, phi):
    """Unit vector at angle chi from the unit vector u, azimuth ``phi`` (a tuple)."""
    sin_chi = math.sqrt(max(0.0, 1.0 - cos_chi * cos_chi))
    cp = math.cos(phi)
    sp = math.sin(phi)
    if abs(uz) > 0.99999999:
        return sin_chi * cp, sin_chi * sp, cos_chi * (1.0 if uz > 0 else -1.0)
    t = math.sqrt(1.0 - uz * uz)
    return (sin_chi * (ux * uz * cp - uy * sp) / t + ux * cos_chi,
            sin_chi * (uy * uz * cp + ux * sp) / t + uy * cos_chi,
            -sin_chi * cp * t + uz * cos_chi)


@kernel
def isotropic_direction(state):
    """A uniformly distributed unit vector (Marsaglia 1972: no trigonometry), as a tuple."""
    while True:
        u1 = 2.0 * uniform(state) - 1.0
        u2 = 2.0 * uniform(state) - 1.0
        s = u1 * u1 + u2 * u2
        if s < 1.0:
            f = 2.0 * math.sqrt(1.0 - s)
            return u1 * f, u2 * f, 1.0 - 2.0 * s


@kernel
def scattered_direction(model, energy, screening, gx, gy, gz, g_speed, state):
    """Direction of the relative velocity g after scattering (isotropic: g is not needed; forward: g's own)."""
    if model == ISOTROPIC or g_speed <= 0.0:
        return isotropic_direction(state)
    if model == FORWARD:
        return gx / g_speed, gy / g_speed, gz / g_speed
    cos_chi = scattering_cosine(model, energy, screening, state)
    return rotated(gx / g_speed, gy / g_speed, gz / g_speed, cos_chi, 2.0 * math.pi * uniform(state))
