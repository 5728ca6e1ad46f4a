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

An inelastic (granular) mixture cools, and its species cool at different
temperatures: :func:`mixture_cooling_rates` gives each species' cooling rate
for Maxwellian velocities at temperatures T_i, and
:func:`homogeneous_cooling_temperatures` the ratios T_i/T at which all cool
at one rate, the homogeneous cooling state's non-equipartition (V. Garzo and
J. W. Dufty, Phys. Rev. E 59, 5895 (1999)).

Both equations of state are approximations: BMCSL's Z is a little low for dense mixtures (as
Carnahan-Starling's is for one species), the disc equation a little high;
measured here for equal numbers at size ratio 0.6 (2000 particles, two seeds,
each +- 0.12 %): BMCSL 0.25-0.5 % low at eta = 0.4, the disc equation 0.3-0.6 %
high at eta = 0.5 (``tests/edmd/test_mixture_physics.py``).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import integrate, optimize

from . import _checks

__all__ = ["MIXTURE_EQUATION_OF_STATE", "homogeneous_cooling_rate", "homogeneous_cooling_temperatures",
           "mixture_collision_frequency", "mixture_compressibility", "mixture_contact_values", "mixture_cooling_rates"]

# the names of the mixtures' equations of state (:func:`mixture_compressibility`), by dimension
MIXTURE_EQUATION_OF_STATE = {3: "BMCSL (Mansoori et al. 1971)", 2: "SYH (Santos et al. 1999)"}

# the homogeneous cooling state is found by following the temperatures' relaxation: up to this many stretches of
# this many mean cooling collisions (most mixtures settle within one)
RELAXATION_ROUNDS = 20
RELAXATION_SPAN = 200.0

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


def _number_density(packing_fraction, fractions, diameters, dim) -> float:
    """n = eta / (the mean particle volume over the fractions)."""
    volume = (math.pi / 6.0 if dim == 3 else math.pi / 4.0) * float(np.sum(fractions * diameters**dim))
    return float(packing_fraction) / volume


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
    :func:`~collisionkit.edmd.enskog_collision_frequency`. Species at
    temperatures of their own (``kT`` one per species, a granular mixture)
    take :math:`kT / \mu_{ij} \to kT_i / m_i + kT_j / m_j`.

    Parameters
    ----------
    packing_fraction : float
        eta in [0, 1).
    fractions, diameters : array_like, shape (S,)
        Number fractions (> 0, summing to 1) and diameters (> 0).
    masses : float or array_like, shape (S,)
        > 0.
    dim : {2, 3}
    kT : float or array_like, shape (S,)
        > 0: one for all, or each species' own.

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
    masses = _per_species(masses, "masses", diameters.size)
    kT = _per_species(kT, "kT", diameters.size)
    g = mixture_contact_values(packing_fraction, fractions, diameters, dim)
    density = _number_density(packing_fraction, fractions, diameters, dim)
    return _collision_frequency(density, g, fractions, diameters, masses, kT, dim)


def _collision_frequency(density, g, fractions, diameters, masses, temperatures, dim) -> float:
    """:func:`mixture_collision_frequency` of checked arrays (number density, contact values given)."""
    contact = 0.5 * np.add.outer(diameters, diameters)
    spread = np.add.outer(temperatures / masses, temperatures / masses)  # kT / mu_ij, or kT_i / m_i + kT_j / m_j
    if dim == 3:
        rate = math.pi * contact**2 * np.sqrt(8.0 * spread / math.pi)
    else:
        rate = 2.0 * contact * np.sqrt(math.pi * spread / 2.0)
    return float(density * np.sum(np.outer(fractions, fractions) * g * rate))


def _per_species(values, name: str, count: int) -> np.ndarray:
    """A positive number or one per species, as an array of ``count``."""
    values = _checks.positive(values, name, scalar=False)
    values = np.broadcast_to(values, (count,)) if values.ndim == 0 else values
    if values.shape != (count,):
        raise ValueError(f"{name} must be a number or one per species ({count}); got shape {values.shape}")
    return values


def _restitution_matrix(restitution, count: int) -> np.ndarray:
    """alpha_ij: a number for every pair or a symmetric (S, S) matrix, each in [0, 1]."""
    alpha = np.asarray(restitution, dtype=float)
    if alpha.ndim == 0 and not 0.0 <= float(alpha) <= 1.0:
        raise ValueError(f"restitution must lie in [0, 1]; got {float(alpha):g}")
    alpha = np.full((count, count), float(alpha)) if alpha.ndim == 0 else alpha
    if alpha.shape != (count, count):
        raise ValueError(f"restitution must be a number or a symmetric {count} x {count} matrix (one per pair of "
                         f"species); got shape {alpha.shape}")
    if not np.all((alpha >= 0.0) & (alpha <= 1.0)):
        raise ValueError(f"restitution must lie in [0, 1]; got {alpha.tolist()}")
    if not np.array_equal(alpha, alpha.T):
        raise ValueError(f"restitution must be a symmetric matrix (pair i, j is pair j, i); got {alpha.tolist()}")
    return alpha


def mixture_cooling_rates(packing_fraction, fractions, diameters, masses=1.0, restitution=1.0, temperatures=1.0,
                          dim=3):
    r"""Each species' cooling rate zeta_i (dT_i/dt = -zeta_i T_i) in a homogeneous inelastic mixture.

    For Maxwellian velocities at temperatures T_i (Enskog's collision rate,
    contacts g_ij of :func:`mixture_contact_values`):

    .. math:: \zeta_i = \frac{2^{5/2} \pi^{(d-1)/2}}{d\, \Gamma(d/2)} \sum_j n_j g_{ij} \sigma_{ij}^{d-1}
              \mu_{ji} (1 + \alpha_{ij}) \sqrt{\frac{T_i}{m_i} + \frac{T_j}{m_j}}
              \left[1 - \frac{\mu_{ji}}{2} (1 + \alpha_{ij}) \left(1 + \frac{m_i T_j}{m_j T_i}\right)\right]

    with :math:`\mu_{ji} = m_j / (m_i + m_j)` and alpha_ij the pair's
    coefficient of normal restitution (Garzo & Dufty 1999, eq. 23, the
    leading Sonine order): the mean energy a collision with j takes from i,
    given the relative velocity g (:math:`m_i \mu_{ji} (1+\alpha) (g \cdot
    n)^2 [\frac{T_i/m_i}{T_i/m_i + T_j/m_j} - \frac{\mu_{ji}}{2} (1+\alpha)]`),
    averaged over the collisions. With equal temperatures and alpha = 1 every rate is 0; one species
    gives Haff's :math:`\zeta = \frac{2 \pi^{(d-1)/2}}{d \Gamma(d/2)} n g
    \sigma^{d-1} \sqrt{T/m} (1 - \alpha^2)`. A rate may be negative: a
    species colder than its partners is heated by them.

    Parameters
    ----------
    packing_fraction : float
        eta in [0, 1).
    fractions, diameters : array_like, shape (S,)
        Number fractions (> 0, summing to 1) and diameters (> 0).
    masses, temperatures : float or array_like, shape (S,)
        > 0 (kT_i in energy units).
    restitution : float or array_like, shape (S, S)
        alpha_ij in [0, 1], symmetric.
    dim : {2, 3}

    Returns
    -------
    ndarray, shape (S,)
        zeta_i, per unit time.

    Examples
    --------
    >>> from collisionkit.edmd import mixture_cooling_rates
    >>> mixture_cooling_rates(0.1, [0.5, 0.5], [1.0, 1.0], [1.0, 4.0], 0.8).round(4)  # equal temperatures
    array([0.2398, 0.0864])
    """
    dim = _checks.dimension(dim)
    fractions, diameters = _species(fractions, diameters)
    count = diameters.size
    masses = _per_species(masses, "masses", count)
    temperatures = _per_species(temperatures, "temperatures", count)
    alpha = _restitution_matrix(restitution, count)
    g = mixture_contact_values(packing_fraction, fractions, diameters, dim)
    density = _number_density(packing_fraction, fractions, diameters, dim)
    return _cooling_rates(density, g, fractions, diameters, masses, alpha, temperatures, dim)[0]


def _cooling_rates(density, g, fractions, diameters, masses, alpha, temperatures, dim):
    """:func:`mixture_cooling_rates` of checked arrays (number density, contact values g_ij given), and the mean rate
    of the collisions that cool (> 0 if the density is)."""
    contact = 0.5 * np.add.outer(diameters, diameters)
    partner_share = masses[None, :] / np.add.outer(masses, masses)  # mu_ji, row i, column j
    thermal = temperatures / masses
    relative = np.sqrt(np.add.outer(thermal, thermal))
    bracket = 1.0 - 0.5 * partner_share * (1.0 + alpha) * (1.0 + np.outer(1.0 / thermal, thermal))
    prefactor = 2.0**2.5 * math.pi ** ((dim - 1) / 2.0) / (dim * math.gamma(dim / 2.0))
    terms = prefactor * density * fractions[None, :] * g * contact ** (dim - 1) * partner_share * (1.0 + alpha) * relative
    return np.sum(terms * bracket, axis=1), float(np.sum(fractions[:, None] * terms))


def homogeneous_cooling_temperatures(packing_fraction, fractions, diameters, masses=1.0, restitution=1.0, dim=3):
    r"""The species' temperatures T_i / T in the homogeneous cooling state of an inelastic mixture.

    In that state every species cools at one rate,
    :math:`\zeta_1 = \zeta_2 = \dots` (:func:`mixture_cooling_rates`),
    which sets the ratios T_i / T with :math:`T = \sum_i x_i T_i`: unlike
    species do not share the energy equally (Garzo & Dufty 1999; confirmed
    by simulation, e.g. Montanero & Garzo, Granular Matter 4, 17 (2002),
    Dahl et al., Phys. Rev. E 66, 041301 (2002)). Elastic pairs (alpha = 1)
    give equipartition, T_i = T.

    Parameters
    ----------
    packing_fraction : float
        eta in [0, 1).
    fractions, diameters : array_like, shape (S,)
        Number fractions (> 0, summing to 1) and diameters (> 0).
    masses : float or array_like, shape (S,)
        > 0.
    restitution : float or array_like, shape (S, S)
        alpha_ij in [0, 1], symmetric.
    dim : {2, 3}

    Returns
    -------
    ndarray, shape (S,)
        T_i / T.

    Raises
    ------
    ValueError
        If the temperatures do not settle. They are found by following their
        relaxation (d ln T_i/dt = -zeta_i, each relative to T), then solving
        the equal rates from there; 1000 random mixtures of 2 to 4 species
        (mass ratios up to e^8, any restitution) all settled.

    Examples
    --------
    >>> from collisionkit.edmd import homogeneous_cooling_temperatures
    >>> homogeneous_cooling_temperatures(0.1, [0.5, 0.5], [1.0, 1.0], [1.0, 4.0], 0.8).round(4)  # heavier: hotter
    array([0.8543, 1.1457])
    """
    dim = _checks.dimension(dim)
    fractions, diameters = _species(fractions, diameters)
    count = diameters.size
    masses = _per_species(masses, "masses", count)
    alpha = _restitution_matrix(restitution, count)
    if count == 1 or np.all(alpha == 1.0):
        return np.ones(count)

    def temperatures(logs):
        ratios = np.exp(logs - np.max(logs))
        return ratios / np.sum(fractions * ratios)

    # every rate is proportional to the number density: the state is that of density 1 (so also at eta = 0)
    g = mixture_contact_values(packing_fraction, fractions, diameters, dim)

    def relaxation(_, logs):  # d ln T_i / d tau = -(zeta_i - zeta_mean), tau in units of the mean cooling collision
        theta = temperatures(logs)
        zeta, scale = _cooling_rates(1.0, g, fractions, diameters, masses, alpha, theta, dim)
        return -(zeta - np.sum(fractions * theta * zeta)) / scale

    # the state every start relaxes to: follow the relaxation itself, then solve its last step exactly
    logs = np.zeros(count)
    for _ in range(RELAXATION_ROUNDS):
        logs = integrate.solve_ivp(relaxation, (0.0, RELAXATION_SPAN), logs, method="LSODA", rtol=1e-10,
                                   atol=1e-12).y[:, -1]
        if np.max(np.abs(relaxation(0.0, logs))) < 1e-8:
            break

    def unequal_rates(others):  # ln T_i - ln T_0 of the other species: their rates less the first species'
        rates = relaxation(0.0, np.concatenate([[0.0], others]))
        return rates[1:] - rates[0]

    solution = optimize.root(unequal_rates, logs[1:] - logs[0], method="hybr")
    logs = np.concatenate([[0.0], solution.x]) if solution.success else logs
    if np.max(np.abs(relaxation(0.0, logs))) > 1e-10:
        raise ValueError(f"no homogeneous cooling state found for restitution {alpha.tolist()}: the species' "
                         "temperatures do not settle")
    return temperatures(logs)


def homogeneous_cooling_rate(packing_fraction, fractions, diameters, masses=1.0, restitution=1.0, dim=3):
    r"""How fast the homogeneous cooling state cools per collision: :math:`-d \ln T / dC = \zeta / \omega`.

    C counts collisions per particle (each pair collision counts for both),
    zeta is the state's common cooling rate (:func:`mixture_cooling_rates`
    at :func:`homogeneous_cooling_temperatures`) and omega Enskog's
    collision frequency at those temperatures
    (:func:`mixture_collision_frequency`). For one species it is
    :math:`(1 - \alpha^2)/d` at any density (Haff's law counted in
    collisions, :math:`T = T_0 e^{-2 (1-\alpha^2) C_{pairs} / (d N)}`).

    Parameters
    ----------
    packing_fraction : float
        eta in [0, 1).
    fractions, diameters : array_like, shape (S,)
        Number fractions (> 0, summing to 1) and diameters (> 0).
    masses : float or array_like, shape (S,)
        > 0.
    restitution : float or array_like, shape (S, S)
        alpha_ij in [0, 1], symmetric.
    dim : {2, 3}

    Returns
    -------
    float

    Examples
    --------
    >>> from collisionkit.edmd import homogeneous_cooling_rate
    >>> round(homogeneous_cooling_rate(0.3, [1.0], [1.0], 1.0, 0.9), 6)  # (1 - 0.81) / 3
    0.063333
    """
    theta = homogeneous_cooling_temperatures(packing_fraction, fractions, diameters, masses, restitution, dim)
    dim = _checks.dimension(dim)
    fractions, diameters = _species(fractions, diameters)
    masses = _per_species(masses, "masses", diameters.size)
    alpha = _restitution_matrix(restitution, diameters.size)
    g = mixture_contact_values(packing_fraction, fractions, diameters, dim)
    zeta, _ = _cooling_rates(1.0, g, fractions, diameters, masses, alpha, theta, dim)  # both per unit density
    return float(np.sum(fractions * theta * zeta) / _collision_frequency(1.0, g, fractions, diameters, masses, theta,
                                                                         dim))
