r"""Hard-sphere and hard-disc mixtures: equation of state, contact values, Enskog's collision rate.

A mixture of S species with number fractions x_i, diameters sigma_i and
masses m_i at packing fraction eta; the pair contact distance is
sigma_ij = (sigma_i + sigma_j) / 2. The references a mixture's EDMD run
is checked against (:class:`~collisionkit.edmd.EdmdParameters`'
``fractions``):

- spheres: the Boublik-Mansoori-Carnahan-Starling-Leland (BMCSL) equation
  of state and Boublik's contact values, which give it by the virial route
  (T. Boublik, J. Chem. Phys. 53, 471 (1970); G. A. Mansoori, N. F.
  Carnahan, K. E. Starling and T. W. Leland, J. Chem. Phys. 54, 1523
  (1971)); Carnahan-Starling for one species;
- discs: the equation of state of Santos, Yuste and Lopez de Haro (SYH),
  :math:`Z = 1/(1-\eta) + [Z_s(\eta) - 1/(1-\eta)]\langle\sigma\rangle^2 /
  \langle\sigma^2\rangle` with Henderson's Z_s of one species, and its
  contact values (A. Santos, S. B. Yuste and M. Lopez de Haro, Mol. Phys.
  96, 1 (1999)); Henderson's equation for one species. It holds the exact
  second virial coefficient of any disc mixture.

Both are approximations: BMCSL's Z is a little low for dense mixtures (as
Carnahan-Starling's is for one species), the disc equation a little high;
measured here for equal numbers at size ratio 0.6 (2000 particles, two seeds,
each +- 0.12 %): BMCSL 0.25-0.5 % low at eta = 0.4, the disc equation 0.3-0.6 %
high at eta = 0.5 (``tests/edmd/test_mixture_physics.py``).
"""

from __future__ import annotations

import math

import numpy as np

from . import _checks

__all__ = ["MIXTURE_EQUATION_OF_STATE", "mixture_collision_frequency", "mixture_compressibility",
           "mixture_contact_values"]

# the names of the mixtures' equations of state (:func:`mixture_compressibility`), by dimension
MIXTURE_EQUATION_OF_STATE = {3: "BMCSL (Mansoori et al. 1971)", 2: "SYH (Santos et al. 1999)"}

# how far the fractions given may sum from 1 (they are then normalised): round-off of decimal fractions such as 1/3
FRACTION_SUM_TOLERANCE = 1e-6


def _species(fractions, diameters):
    """The number fractions (normalised) and diameters as float arrays of one length, checked."""
    fractions = _checks.positive(fractions, "fractions", scalar=False)
    diameters = _checks.positive(diameters, "diameters", scalar=False)
    if fractions.ndim != 1 or fractions.shape != diameters.shape:
        raise ValueError(f"fractions and diameters must be sequences of one length (one per species); got shapes "
                         f"{fractions.shape} and {diameters.shape}")
    if abs(fractions.sum() - 1.0) > FRACTION_SUM_TOLERANCE:
        raise ValueError(f"fractions must sum to 1 (number fractions of the species); got sum {fractions.sum():.9g}")
    return fractions / fractions.sum(), diameters


def _moments(fractions, diameters):
    """<sigma>, <sigma^2>, <sigma^3> over the number fractions."""
    return tuple(float(np.sum(fractions * diameters**k)) for k in (1, 2, 3))


def mixture_contact_values(packing_fraction, fractions, diameters, dim=3):
    r"""Pair distribution functions at contact, g_ij(sigma_ij), of a hard-sphere or hard-disc mixture.

    Spheres (Boublik): with :math:`\xi_k = \frac{\pi}{6} n \sum_i x_i \sigma_i^k`,

    .. math:: g_{ij} = \frac{1}{1-\xi_3} + \frac{3 \xi_2}{(1-\xi_3)^2} \frac{\sigma_i \sigma_j}{\sigma_i + \sigma_j}
              + \frac{2 \xi_2^2}{(1-\xi_3)^3} \left(\frac{\sigma_i \sigma_j}{\sigma_i + \sigma_j}\right)^2 ;

    discs (SYH): :math:`g_{ij} = \frac{1}{1-\eta} + [g_s(\eta) - \frac{1}{1-\eta}]
    \frac{\langle\sigma\rangle}{\langle\sigma^2\rangle} \frac{\sigma_i \sigma_j}{\sigma_{ij}}` with
    Henderson's :math:`g_s = (1 - 7\eta/16)/(1-\eta)^2`. Both give their
    equation of state (:func:`mixture_compressibility`) by the virial route
    :math:`Z = 1 + \frac{2^{d-1} \pi}{d (d-1)} n \sum_{ij} x_i x_j \sigma_{ij}^d g_{ij}`
    (:math:`\frac{2\pi}{3}` for spheres, :math:`\frac{\pi}{2}` for discs).

    Parameters
    ----------
    packing_fraction : float
        eta in [0, 1).
    fractions : array_like, shape (S,)
        Number fractions, > 0, summing to 1.
    diameters : array_like, shape (S,)
        > 0.
    dim : {2, 3}

    Returns
    -------
    ndarray, shape (S, S)
        g_ij, symmetric.

    Examples
    --------
    >>> from collisionkit.edmd import mixture_contact_values
    >>> mixture_contact_values(0.3, [0.5, 0.5], [1.0, 0.5]).round(4)
    array([[2.6109, 2.1808],
           [2.1808, 1.9793]])
    """
    dim = _checks.dimension(dim)
    fractions, diameters = _species(fractions, diameters)
    eta = _checks.bounded(packing_fraction, "packing_fraction", 0.0, 1.0)
    mean, mean2, mean3 = _moments(fractions, diameters)
    reduced = np.outer(diameters, diameters) / np.add.outer(diameters, diameters)  # sigma_i sigma_j / (s_i + s_j)
    if dim == 3:
        xi2 = eta * mean2 / mean3
        return 1.0 / (1.0 - eta) + 3.0 * xi2 * reduced / (1.0 - eta) ** 2 + 2.0 * (xi2 * reduced) ** 2 / (1.0 - eta) ** 3
    one = (1.0 - 7.0 * eta / 16.0) / (1.0 - eta) ** 2
    return 1.0 / (1.0 - eta) + (one - 1.0 / (1.0 - eta)) * (mean / mean2) * 2.0 * reduced


def mixture_compressibility(packing_fraction, fractions, diameters, dim=3):
    r"""Compressibility factor Z = PV/(NkT) of a hard-sphere (BMCSL) or hard-disc (SYH) mixture.

    Spheres, with :math:`\xi_k = \frac{\pi}{6} n \sum_i x_i \sigma_i^k` (so
    :math:`\xi_3 = \eta`):

    .. math:: Z = \frac{6}{\pi n} \left[\frac{\xi_0}{1-\xi_3} + \frac{3 \xi_1 \xi_2}{(1-\xi_3)^2}
              + \frac{(3 - \xi_3) \xi_2^3}{(1-\xi_3)^3}\right]

    (Mansoori et al. 1971; Carnahan-Starling for one species). Discs:
    :math:`Z = \frac{1}{1-\eta} + [Z_s - \frac{1}{1-\eta}] \frac{\langle\sigma\rangle^2}{\langle\sigma^2\rangle}`,
    :math:`Z_s = (1 + \eta^2/8)/(1-\eta)^2` (Santos, Yuste and Lopez de Haro 1999; Henderson 1975).

    Parameters
    ----------
    packing_fraction : float
        eta in [0, 1).
    fractions, diameters : array_like, shape (S,)
        Number fractions (> 0, summing to 1) and diameters (> 0).
    dim : {2, 3}

    Returns
    -------
    float

    Examples
    --------
    >>> from collisionkit.edmd import mixture_compressibility, carnahan_starling
    >>> round(mixture_compressibility(0.3, [0.5, 0.5], [1.0, 0.5]), 5)
    3.50583
    >>> bool(abs(mixture_compressibility(0.3, [1.0], [2.0]) - carnahan_starling(0.3)) < 1e-12)
    True
    """
    dim = _checks.dimension(dim)
    fractions, diameters = _species(fractions, diameters)
    eta = _checks.bounded(packing_fraction, "packing_fraction", 0.0, 1.0)
    mean, mean2, mean3 = _moments(fractions, diameters)
    if dim == 3:
        # xi_k = xi_0 <sigma^k> and xi_0 = eta / <sigma^3>, so (6 / (pi n)) = 1 / xi_0 takes out one xi_0
        return float(1.0 / (1.0 - eta) + 3.0 * eta * mean * mean2 / (mean3 * (1.0 - eta) ** 2)
                     + (3.0 - eta) * eta**2 * mean2**3 / (mean3**2 * (1.0 - eta) ** 3))
    one = (1.0 + eta**2 / 8.0) / (1.0 - eta) ** 2
    return float(1.0 / (1.0 - eta) + (one - 1.0 / (1.0 - eta)) * mean**2 / mean2)


def mixture_collision_frequency(packing_fraction, fractions, diameters, masses=1.0, dim=3, kT=1.0):
    r"""Enskog's collision frequency per particle of a hard-sphere or hard-disc mixture.

    Each pair collision counts for both particles:

    .. math:: \omega = \sum_{ij} x_i n_j g_{ij} \times
              \begin{cases} \pi \sigma_{ij}^2 \sqrt{8 kT / (\pi \mu_{ij})} & \text{spheres} \\
                            2 \sigma_{ij} \sqrt{\pi kT / (2 \mu_{ij})} & \text{discs} \end{cases}

    with :math:`n_j = x_j n`, :math:`\mu_{ij} = m_i m_j / (m_i + m_j)` and
    the contact values of :func:`mixture_contact_values` (the collision
    cross-section times the mean relative speed of a Maxwell-Boltzmann pair,
    enhanced by g_ij; Chapman & Cowling, ch. 16). One species:
    :func:`~collisionkit.edmd.enskog_collision_frequency`.

    Parameters
    ----------
    packing_fraction : float
        eta in [0, 1).
    fractions, diameters : array_like, shape (S,)
        Number fractions (> 0, summing to 1) and diameters (> 0).
    masses : float or array_like, shape (S,)
        > 0.
    dim : {2, 3}
    kT : float
        > 0.

    Returns
    -------
    float
        Collisions per particle per unit time.

    Examples
    --------
    >>> from collisionkit.edmd import mixture_collision_frequency
    >>> round(mixture_collision_frequency(0.3, [0.5, 0.5], [1.0, 0.5], [1.0, 0.125]), 4)
    16.6369
    """
    dim = _checks.dimension(dim)
    fractions, diameters = _species(fractions, diameters)
    masses = _checks.positive(masses, "masses", scalar=False)
    masses = np.broadcast_to(masses, diameters.shape) if masses.ndim == 0 else masses
    if masses.shape != diameters.shape:
        raise ValueError(f"masses must be a number or one per species ({diameters.size}); got shape {masses.shape}")
    kT = _checks.positive(kT, "kT")
    g = mixture_contact_values(packing_fraction, fractions, diameters, dim)
    volume = (math.pi / 6.0 if dim == 3 else math.pi / 4.0) * float(np.sum(fractions * diameters**dim))
    density = float(packing_fraction) / volume
    contact = 0.5 * np.add.outer(diameters, diameters)
    reduced_mass = np.outer(masses, masses) / np.add.outer(masses, masses)
    if dim == 3:
        rate = math.pi * contact**2 * np.sqrt(8.0 * kT / (math.pi * reduced_mass))
    else:
        rate = 2.0 * contact * np.sqrt(math.pi * kT / (2.0 * reduced_mass))
    return float(density * np.sum(np.outer(fractions, fractions) * g * rate))
