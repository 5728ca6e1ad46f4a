r"""Angular scattering laws of electron-neutral collisions and their mean deflection cosines.

A law gives the distribution of the deflection angle :math:`\chi` in the
centre-of-mass frame at the collision energy :math:`\epsilon` (the
projectile's energy in the target's frame, eV). The kernels sample it by
inversion of its cumulative distribution (:func:`scattering_cosine_from_uniform`
is the same formula in NumPy); :func:`mean_scattering_cosine` is its first
moment, in closed form:

``isotropic``
    :math:`\cos\chi = 1 - 2R`; :math:`\langle\cos\chi\rangle = 0`.
``okhrimovskyy``
    Okhrimovskyy, Bogaerts & Gijbels, Phys. Rev. E 65, 037402 (2002): the
    screened-Coulomb form :math:`p(\cos\chi) = (1 - \xi^2) / (2 (1 - \xi\cos\chi)^2)`
    with :math:`\xi(\epsilon) = 4\epsilon / (E_h + 4\epsilon)` (:math:`E_h`
    = 27.211 eV, the hartree: :math:`4\epsilon/(1 + 4\epsilon)` in atomic
    units, the form of the anisotropic benchmarks of Flynn et al., J. Phys. D
    57, 255204 (2024)). Inversion:
    :math:`\cos\chi = 1 - 2R(1 - \xi)/(1 + \xi(1 - 2R))`; first moment
    :math:`\langle\cos\chi\rangle = 1/\xi - (1 - \xi^2)\,\mathrm{artanh}(\xi)/\xi^2`
    (:math:`2\xi/3 + 2\xi^3/15 + \dots` for small :math:`\xi`).
``vahedi-surendra``
    Vahedi & Surendra, Comput. Phys. Commun. 87, 179 (1995):
    :math:`\cos\chi = (2 + \epsilon - 2(1 + \epsilon)^R)/\epsilon` (:math:`\epsilon`
    in eV), i.e. :math:`P(1 - \cos\chi \le x) = \ln(1 + \epsilon x/2)/\ln(1 + \epsilon)`;
    :math:`\langle\cos\chi\rangle = 1 - 2(\epsilon - \ln(1 + \epsilon))/(\epsilon\ln(1 + \epsilon))`
    (:math:`\epsilon/6` for small :math:`\epsilon`).
``forward``
    :math:`\cos\chi = 1`: no deflection; :math:`\langle\cos\chi\rangle = 1`.
``screened_coulomb``
    Wentzel's screened Coulomb law with a screening energy :math:`\epsilon_s`:
    :math:`p \propto (1 + 2\eta - \cos\chi)^{-2}`, :math:`\eta = \epsilon_s/(4\epsilon)`
    (see :func:`screened_coulomb_momentum_ratio`).

An elastic (momentum-transfer) cross section :math:`\sigma_m` becomes the
integral cross section :math:`\sigma = \sigma_m / (1 - \langle\cos\chi\rangle)`
that the Monte Carlo samples (:func:`momentum_transfer_ratio`), so the
momentum the swarm loses per unit time is that of :math:`\sigma_m` whatever the
law.
"""

from __future__ import annotations

import numpy as np
from scipy import constants

from .. import _arrays

__all__ = ["SCATTERING_LAWS", "HARTREE_EV", "okhrimovskyy_parameter", "mean_scattering_cosine",
           "momentum_transfer_ratio", "scattering_cosine_from_uniform", "screened_coulomb_momentum_ratio"]

SCATTERING_LAWS = ("isotropic", "okhrimovskyy", "vahedi-surendra", "forward")
HARTREE_EV = constants.physical_constants["Hartree energy in eV"][0]
_SMALL = 1e-4  # below it, series replace the closed forms (their cancellation loses ~1e-8 relative at 1e-4)


def _energies(energy):
    return _arrays.as_finite_in_range(energy, "energy", 0.0)


def okhrimovskyy_parameter(energy):
    r"""The anisotropy :math:`\xi(\epsilon) = 4\epsilon/(E_h + 4\epsilon)` of the Okhrimovskyy law (energy in eV).

    Examples
    --------
    >>> from collisionkit.transport.angular import okhrimovskyy_parameter, HARTREE_EV
    >>> float(okhrimovskyy_parameter(0.0)), float(okhrimovskyy_parameter(HARTREE_EV / 4))
    (0.0, 0.5)
    """
    energy = _energies(energy)
    return 4.0 * energy / (HARTREE_EV + 4.0 * energy)


def mean_scattering_cosine(law: str, energy, screening_energy: float = 1.0):
    r"""The mean deflection cosine :math:`\langle\cos\chi\rangle(\epsilon)` of a law (energy in eV, >= 0).

    Parameters
    ----------
    law : {"isotropic", "okhrimovskyy", "vahedi-surendra", "forward", "screened_coulomb"}
    energy : float or array_like
        Collision energy in eV (finite, >= 0).
    screening_energy : float
        Screened Coulomb only (eV, > 0).

    Examples
    --------
    >>> from collisionkit.transport.angular import mean_scattering_cosine
    >>> [round(float(mean_scattering_cosine(law, 10.0)), 4) for law in ("isotropic", "forward")]
    [0.0, 1.0]
    >>> round(float(mean_scattering_cosine("vahedi-surendra", 1e-6)) / 1e-6, 4)  # epsilon / 6
    0.1667
    """
    energy = _energies(energy)
    if law == "isotropic":
        return np.zeros_like(energy)
    if law == "forward":
        return np.ones_like(energy)
    if law == "okhrimovskyy":
        xi = okhrimovskyy_parameter(energy)
        small = xi < _SMALL
        safe = np.where(small, 0.5, xi)
        exact = 1.0 / safe - (1.0 - safe**2) * np.arctanh(safe) / safe**2
        return np.where(small, 2.0 * xi / 3.0 + 2.0 * xi**3 / 15.0, exact)
    if law == "vahedi-surendra":
        small = energy < _SMALL
        safe = np.where(small, 1.0, energy)
        log = np.log1p(safe)
        exact = 1.0 - 2.0 * (safe - log) / (safe * log)
        return np.where(small, energy / 6.0 - energy**2 / 12.0, exact)
    if law == "screened_coulomb":
        return 1.0 - screened_coulomb_momentum_ratio(energy, screening_energy)
    raise ValueError(f"law must be one of {SCATTERING_LAWS + ('screened_coulomb',)}; got {law!r}")


def momentum_transfer_ratio(law: str, energy, screening_energy: float = 1.0):
    r"""The ratio :math:`\sigma_m/\sigma = 1 - \langle\cos\chi\rangle` of a law (0 for ``forward``).

    Divide a momentum-transfer cross section by it to get the integral cross
    section the Monte Carlo samples.

    Examples
    --------
    >>> from collisionkit.transport.angular import momentum_transfer_ratio
    >>> float(momentum_transfer_ratio("isotropic", 5.0))
    1.0
    >>> 0.4 < float(momentum_transfer_ratio("okhrimovskyy", 20.0)) < 0.6
    True
    """
    return 1.0 - mean_scattering_cosine(law, energy, screening_energy)


def scattering_cosine_from_uniform(law: str, energy, uniform, screening_energy: float = 1.0):
    r"""The deflection cosine a law gives a uniform number ``uniform`` in (0, 1): the kernels' inversion formula.

    Examples
    --------
    >>> from collisionkit.transport.angular import scattering_cosine_from_uniform
    >>> [float(scattering_cosine_from_uniform(law, 3.0, 0.25)) for law in ("isotropic", "forward")]
    [0.5, 1.0]
    """
    energy = _energies(energy)
    u = np.asarray(uniform, dtype=float)
    if law == "isotropic":
        return 1.0 - 2.0 * u + 0.0 * energy
    if law == "forward":
        return np.ones(np.broadcast(energy, u).shape)
    if law == "okhrimovskyy":
        xi = okhrimovskyy_parameter(energy)
        return 1.0 - 2.0 * u * (1.0 - xi) / (1.0 + xi * (1.0 - 2.0 * u))
    if law == "vahedi-surendra":
        small = energy < 1e-12
        safe = np.where(small, 1.0, energy)
        return np.where(small, 1.0 - 2.0 * u, 1.0 - 2.0 * np.expm1(u * np.log1p(safe)) / safe)
    if law == "screened_coulomb":
        eta = screening_energy / (4.0 * np.maximum(energy, 1e-300))
        return np.clip(1.0 + 2.0 * eta - 2.0 * eta * (1.0 + eta) / (eta + u), -1.0, 1.0)
    raise ValueError(f"law must be one of {SCATTERING_LAWS + ('screened_coulomb',)}; got {law!r}")


def screened_coulomb_momentum_ratio(energy, screening_energy):
    r"""Ratio sigma_m / sigma_el of the screened Coulomb (Wentzel) angular distribution.

    With :math:`p(\cos\chi) \propto (1 + 2\eta - \cos\chi)^{-2}` and
    :math:`\eta = \epsilon_s / (4 \epsilon)`,
    :math:`\langle 1 - \cos\chi \rangle = 2\eta(1 + \eta)\ln(1 + 1/\eta) - 2\eta`
    (1 for isotropic scattering, eta -> infinity). Divide a momentum-transfer
    cross section by this ratio to get the elastic cross section to sample.

    Parameters
    ----------
    energy : float or array_like
        Collision energy (eV), finite and >= 0 (0: isotropic, ratio 1).
    screening_energy : float or array_like
        The screening energy (eV), finite and > 0.

    Examples
    --------
    >>> from collisionkit.transport import screened_coulomb_momentum_ratio
    >>> round(float(screened_coulomb_momentum_ratio(1e-6, 1.0)), 4)
    1.0
    >>> 0 < float(screened_coulomb_momentum_ratio(10.0, 1.0)) < 0.5
    True
    """
    energy = _arrays.as_finite_in_range(energy, "energy", 0.0)
    screening_energy = _arrays.as_finite_in_range(screening_energy, "screening_energy", 0.0, inclusive=(False, False))
    eta = screening_energy / (4.0 * np.maximum(energy, 1e-300))
    small = eta > 1e6
    safe = np.where(small, 1.0, eta)
    exact = 2.0 * safe * (1.0 + safe) * np.log1p(1.0 / safe) - 2.0 * safe
    return np.where(small, 1.0, exact)
