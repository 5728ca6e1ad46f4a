r"""Is a cooling granular gas still homogeneous? The energy of its box-scale shear flows against a homogeneous gas's.

A granular gas cools homogeneously (Haff's law, the cooling state's
theories) only while it stays homogeneous. A large enough one is not: its
transverse (shear) velocity modes of the longest wavelengths cool more
slowly than the heat and grow, relative to it, into vortices, and density
clusters follow (Goldhirsch & Zanetti 1993, PRL 70, 1619; McNamara & Young
1996, PRE 53, 5089; Brey, Ruiz-Montero & Cubero 1999, PRE 60, 3150). The
box sets the longest wavelength, so the box decides.

:func:`shear_mode_energy` measures it: for each periodic axis a with
:math:`k = 2\pi / L_a` and each velocity component b across it, the mode

.. math::

    j_b(k) = \sum_i m_i u_{i,b}\, e^{-i k x_{i,a}}

(u the velocity relative to the centre of mass), its energy over an
uncorrelated gas's share, :math:`|j_b(k)|^2 / \sum_i m_i^2 u_{i,b}^2`,
averaged over the :math:`M = d(d - 1)` modes. In equilibrium the velocities
are independent of each other and of the positions (the canonical
distribution factorises), so at any density each mode's ratio has mean 1
and, its real and imaginary parts being sums of many independent terms,
an exponential distribution: the average of M is Gamma(M, 1/M)
distributed (mean 1, standard deviation :math:`1/\sqrt{M}`).
:func:`homogeneity_threshold` is the value such velocities exceed at one
block end of a run of ``blocks`` with probability ``false_alarm / blocks``.

A cooling gas is not in equilibrium: even in a box below the critical
length its shear flows are enhanced, by about :math:`1/(1 - (L/L_c)^2)`
(:func:`cooling_state_shear_energy`), and a run compares them with that
where the dilute theory gives L_c (:func:`box_instability`), with an
uncorrelated gas's elsewhere. :func:`shear_instability_length` is the
critical length, :func:`shear_mode_growth` the growth beyond it.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import stats

from . import _checks
from .theory import _ball_volume, _first_sonine, dilute_granular_rates

__all__ = ["DILUTE_INSTABILITY_LIMIT", "FALSE_ALARM", "VORTICES", "box_instability", "cooling_state_shear_energy",
           "homogeneity_summary", "homogeneity_threshold", "instability_note", "shear_flow_fraction",
           "shear_instability_length", "shear_mode_count", "shear_mode_energy", "shear_mode_growth"]

FALSE_ALARM = 1e-3  # the compared gas's probability (uncorrelated or a stable cooling state's) of a crossing in a run


def shear_mode_count(dim: int) -> int:
    """The transverse modes at the box's longest wavelengths, d (d - 1): 6 in 3D, 2 in 2D.

    Examples
    --------
    >>> shear_mode_count(3), shear_mode_count(2)
    (6, 2)
    """
    if dim not in (2, 3):
        raise ValueError(f"dim must be 2 or 3; got {dim!r}")
    return dim * (dim - 1)


def shear_mode_energy(positions, velocities, box, masses=None) -> float:
    r"""The energy of the box-scale shear flows over an uncorrelated gas's share: about 1 if homogeneous.

    :math:`\frac{1}{M} \sum_{a} \sum_{b \ne a} |\sum_i m_i u_{i,b} e^{-2\pi i
    x_{i,a} / L_a}|^2 / \sum_i m_i^2 u_{i,b}^2` over the M = d (d - 1)
    transverse modes (module notes), u the velocities relative to the
    centre of mass: the transverse momentum density of the longest
    wavelengths, whose growth is a cooling gas's first instability
    (Goldhirsch & Zanetti, Phys. Rev. Lett. 70, 1619 (1993)). A component
    without spread gives its modes no value (left out of the mean).

    Parameters
    ----------
    positions, velocities : array_like, shape (N, d)
        d = 2 or 3, every axis periodic with the box's lengths.
    box : array_like, shape (d,)
        The periodic box's lengths.
    masses : array_like, shape (N,), optional
        Default: equal masses.

    Returns
    -------
    float
        1 on average in equilibrium (standard deviation 1/sqrt(M)); a shear
        flow u_b = A sin(2 pi x_a / L_a) across the box raises its mode's
        ratio by about N m A^2 / (4 kT) (the average by 1/M of it), kT >> m A^2.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(1)
    >>> draws = [shear_mode_energy(rng.uniform(0, 10, (1000, 3)), rng.normal(size=(1000, 3)), [10, 10, 10])
    ...          for _ in range(400)]
    >>> round(float(np.mean(draws)), 1), round(float(np.std(draws)), 1)  # homogeneous: 1 and 1 / sqrt(6)
    (1.0, 0.4)
    >>> x, v = rng.uniform(0, 10, (100000, 2)), rng.normal(size=(100000, 2))
    >>> v[:, 1] += 0.1 * np.sin(2 * np.pi * x[:, 0] / 10)  # a shear flow: N A^2 / 4 = 250 in one mode of two
    >>> 100 < shear_mode_energy(x, v, [10, 10]) < 150
    True
    """
    positions = np.asarray(positions, dtype=float)
    velocities = np.asarray(velocities, dtype=float)
    box = np.asarray(box, dtype=float)
    if positions.ndim != 2 or positions.shape != velocities.shape or positions.shape[1] not in (2, 3):
        raise ValueError(f"positions and velocities must both have shape (N, 2) or (N, 3); got {positions.shape} and "
                         f"{velocities.shape}")
    dim = positions.shape[1]
    if box.shape != (dim,) or not np.all(np.isfinite(box) & (box > 0)):
        raise ValueError(f"box must be {dim} positive finite lengths; got {box.tolist()}")
    masses = np.ones(len(positions)) if masses is None else np.broadcast_to(np.asarray(masses, dtype=float),
                                                                           (len(positions),))
    relative = velocities - masses @ velocities / np.sum(masses)
    momenta = masses[:, None] * relative
    ratios = []
    for axis in range(dim):
        phase = np.exp(-2j * np.pi * positions[:, axis] / box[axis])
        for component in range(dim):
            if component != axis:
                share = float(np.sum(momenta[:, component] ** 2))
                ratios.append(abs(phase @ momenta[:, component]) ** 2 / share if share > 0 else math.nan)
    return float(np.nanmean(ratios)) if np.isfinite(ratios).any() else math.nan


def homogeneity_threshold(dim: int, blocks: int, false_alarm: float = FALSE_ALARM, expected: float = 1.0) -> float:
    """The :func:`shear_mode_energy` that uncorrelated velocities exceed at one of ``blocks`` block ends with
    probability ``false_alarm`` or less: ``expected`` times the Gamma(M, 1/M) quantile of ``false_alarm / blocks``
    (a Bonferroni bound over the blocks; correlated blocks only make it safer). It rises with the blocks, so a
    run extended by more blocks may no longer cross it where it crossed before.

    Parameters
    ----------
    dim : {2, 3}
    blocks : int
        The block ends looked at, >= 1.
    false_alarm : float
        In (0, 1).
    expected : float
        The mean ratio of the gas compared with: 1 for uncorrelated
        velocities; a stable cooling state's enhanced flows
        (:func:`cooling_state_shear_energy`) scale the quantile.

    Returns
    -------
    float

    Examples
    --------
    >>> round(homogeneity_threshold(3, 10), 2), round(homogeneity_threshold(2, 10), 2)
    (3.26, 5.88)
    """
    if not 0.0 < false_alarm < 1.0:
        raise ValueError(f"false_alarm must lie in (0, 1); got {false_alarm!r}")
    if not _checks.is_integer(blocks) or blocks < 1:
        raise ValueError(f"blocks must be an integer >= 1; got {blocks!r}")
    if not (math.isfinite(expected) and expected >= 1.0):
        raise ValueError(f"expected must be a finite number >= 1; got {expected!r}")
    modes = shear_mode_count(dim)
    return expected * float(stats.gamma.isf(false_alarm / blocks, modes, scale=1.0 / modes))


def shear_flow_fraction(value: float, dim: int, particles: int) -> float:
    """The fraction of the kinetic energy that box-scale shear flows hold beyond thermal noise, from a
    :func:`shear_mode_energy` R: about 2 M (R - 1) / (d N) (equal masses, isotropic temperature), 0 if R <= 1.

    A flow's mode holds the energy (|j|^2 - sum m^2 u^2) / sum m, and
    sum_i m_i^2 u_ib^2 = m 2K / d: the M modes hold (R - 1) M 2K / (d N).

    Examples
    --------
    >>> shear_flow_fraction(501.0, 2, 2000)  # vortices: half the kinetic energy
    0.5
    """
    return max(0.0, 2.0 * shear_mode_count(dim) * (value - 1.0) / (dim * particles))


VORTICES = 0.1  # box-scale shear flows holding this fraction of the kinetic energy or more are called vortices


def homogeneity_summary(block_values, dim: int, particles: int, collisions_per_block: float,
                        expected: float = 1.0) -> dict:
    """The summary keys of a cooling run's homogeneity from :func:`shear_mode_energy` at its block ends.

    Parameters
    ----------
    block_values : array_like
        :func:`shear_mode_energy` at each block end; NaN for blocks of a
        checkpoint written before it was recorded (left out).
    dim : {2, 3}
    particles : int
    collisions_per_block : float
        Collisions per particle in a block.
    expected : float
        The mean the gas is compared with (:func:`homogeneity_threshold`).

    Returns
    -------
    dict
        ``shear_mode_energy`` at the last block end with a value, its
        maximum, ``shear_mode_energy_expected``, the threshold for the
        blocks with values, ``homogeneous`` (no block above it),
        ``homogeneity_lost_after`` (collisions per particle measured to the
        first block end above it; None if none) and
        ``shear_flow_energy_fraction`` (:func:`shear_flow_fraction` at the
        maximum); empty if no block has a value.

    Examples
    --------
    >>> summary = homogeneity_summary([1.2, 0.7, 9.0, 40.0], 3, 1000, 10.0)
    >>> summary["homogeneous"], summary["homogeneity_lost_after"], summary["shear_mode_energy_max"]
    (False, 30.0, 40.0)
    """
    values = np.asarray(block_values, dtype=float)
    known = np.flatnonzero(np.isfinite(values))
    if known.size == 0:
        return {}
    threshold = homogeneity_threshold(dim, int(known.size), expected=expected)
    above = known[values[known] > threshold]
    most = float(np.max(values[known]))
    return {"shear_mode_energy": float(values[known[-1]]), "shear_mode_energy_max": most,
            "shear_mode_energy_expected": float(expected), "shear_mode_energy_threshold": threshold,
            "homogeneous": bool(above.size == 0),
            "homogeneity_lost_after": None if above.size == 0 else float((above[0] + 1) * collisions_per_block),
            "shear_flow_energy_fraction": shear_flow_fraction(most, dim, particles)}


def cooling_state_shear_energy(box_length: float, critical_length: float) -> float:
    r"""The mean :func:`shear_mode_energy` of a stable homogeneous cooling state: :math:`1/(1 - (L/L_c)^2)`.

    Below the critical length the shear modes are damped, but less than
    in equilibrium as the gas cools, and their fluctuations are enhanced by
    this factor (fluctuating hydrodynamics of the cooling state with
    equilibrium-like noise: van Noije, Ernst, Brito & Orza, Phys. Rev. Lett.
    79, 411 (1997)); measured for discs at eta 0.05, e = 0.9 (12 seeds):
    1.29 +- 0.13 at 0.5 L_c (1.33), 2.46 +- 0.33 at 0.7 L_c (1.96), 3.22 +-
    0.56 at 0.85 L_c (3.60). inf at and beyond L_c.

    Examples
    --------
    >>> round(cooling_state_shear_energy(50.0, 100.0), 3)
    1.333
    """
    ratio = box_length / critical_length
    return 1.0 / (1.0 - ratio**2) if ratio < 1.0 else math.inf


def _dilute_mode(restitution, packing_fraction, dim, diameter):
    """(zeta*, nu_eta* - zeta*/2, C_d, mean free path scale l = 1 / (n sigma^(d-1))), checked."""
    alpha = _checks.bounded(restitution, "restitution", 0.0, 1.0, closed=(True, True))
    eta = _checks.bounded(packing_fraction, "packing_fraction", 0.0, 1.0, closed=(False, False))
    dim = _checks.dimension(dim)
    if dim == 1:
        raise ValueError("dim must be 2 or 3: a line has no shear modes")
    diameter = _checks.positive(diameter, "diameter")
    cooling, momentum = dilute_granular_rates(alpha, dim)
    viscosity_constant = float(_first_sonine(dim, 1.0, 1.0, 1.0)[0])  # C_d = eta_0 sigma^(d-1) / sqrt(m kT)
    density = eta / float(_ball_volume(diameter / 2, dim))
    return cooling, momentum - cooling / 2, viscosity_constant, 1.0 / (density * diameter ** (dim - 1))


def shear_instability_length(restitution, packing_fraction, dim=3, diameter=1.0) -> float:
    r"""The box length above which a dilute cooling gas's shear flows grow into vortices (Navier-Stokes, Boltzmann).

    A transverse velocity mode of wavenumber k decays by viscosity,
    :math:`\rho\,\partial_t u = -\eta k^2 u`, while the temperature falls as
    :math:`\partial_t T = -\zeta T`: relative to the thermal speed it grows if
    :math:`\zeta/2 > \eta k^2/\rho`, for :math:`k < k_c = \sqrt{\rho\zeta/(2\eta)}`
    (Goldhirsch & Zanetti 1993; Brey, Ruiz-Montero & Cubero 1999). With
    :math:`\zeta = \zeta^* \nu_0`, :math:`\eta = \eta_0/(\nu_\eta^* -
    \zeta^*/2)` and :math:`\nu_0 = n kT/\eta_0`
    (:func:`~collisionkit.edmd.theory.dilute_granular_rates`),

    .. math:: k_c \ell = \frac{1}{C_d}\sqrt{\frac{\zeta^* (\nu_\eta^* - \zeta^*/2)}{2}},
        \qquad L_c = \frac{2\pi}{k_c},

    :math:`\ell = 1/(n\sigma^{d-1})`, :math:`C_d = \eta_0\sigma^{d-1}/\sqrt{mkT} =
    (d+2)\Gamma(d/2)/(8\pi^{(d-1)/2})`; it is independent of kT and the
    mass. A periodic box with a side above L_c is unstable. The dilute
    (Boltzmann) limit, Maxwellian first Sonine order: a guide at packing
    fractions up to about 0.1, where Enskog's corrections are some 10 %.

    Parameters
    ----------
    restitution : float
        alpha in [0, 1]; 1 gives inf (an elastic gas is stable).
    packing_fraction : float
        In (0, 1).
    dim : {2, 3}
    diameter : float
        > 0.

    Returns
    -------
    float
        L_c in the diameter's units.

    Examples
    --------
    >>> round(shear_instability_length(0.9, 0.02), 1)  # spheres: 5.70 l, l = 26.2 diameters
    148.9
    >>> round(shear_instability_length(0.7, 0.05, dim=2), 1)
    81.6
    """
    cooling, viscous, constant, free_path = _dilute_mode(restitution, packing_fraction, dim, diameter)
    if cooling == 0.0:
        return math.inf
    return 2.0 * math.pi * free_path * constant / math.sqrt(cooling * viscous / 2.0)


def shear_mode_growth(restitution, box_length, packing_fraction, dim=3, diameter=1.0) -> float:
    r"""The growth rate, per collision per particle, of the longest shear mode's amplitude over the thermal speed.

    :math:`(\zeta/2 - \eta k^2/\rho)/\omega` with :math:`k = 2\pi/L` (see
    :func:`shear_instability_length`) and :math:`\omega` the Boltzmann
    collision frequency, :math:`\nu_0/\omega = 4/(d+2)`:

    .. math:: g = \frac{4}{d+2}\left[\frac{\zeta^*}{2} - \frac{C_d^2 (k\ell)^2}{\nu_\eta^* - \zeta^*/2}\right]
        = \frac{1 - \alpha^2}{2d}\left[1 - \left(\frac{L_c}{L}\right)^2\right]\ (\alpha < 1).

    Negative in a stable box (an elastic gas: the viscous decay alone); the
    mode's energy grows as :math:`e^{2gC}`. Dilute limit, Maxwellian first
    Sonine order, as :func:`shear_instability_length`; Navier-Stokes needs
    :math:`k\ell \ll 1` (a box of many mean free paths).

    Parameters
    ----------
    restitution : float
        alpha in [0, 1].
    box_length : float
        L > 0, the mode's wavelength.
    packing_fraction : float
        In (0, 1).
    dim : {2, 3}
    diameter : float
        > 0.

    Returns
    -------
    float
        g, per collision per particle (2 per pair collision / N).

    Examples
    --------
    >>> round(shear_mode_growth(0.7, 177.2, 0.05, dim=2), 4)  # 2000 discs: L = 2.17 L_c
    0.1005
    >>> shear_mode_growth(1.0, 30.0, 0.02) < 0  # elastic: viscous decay
    True
    """
    length = _checks.positive(box_length, "box_length")
    cooling, viscous, constant, free_path = _dilute_mode(restitution, packing_fraction, dim, diameter)
    wavenumber = 2.0 * math.pi / length * free_path
    return 4.0 / (dim + 2) * (cooling / 2.0 - constant**2 * wavenumber**2 / viscous)


# the largest packing fraction the dilute theory of the instability is applied at (Enskog's contact value
# 1.3 there: its corrections grow beyond)
DILUTE_INSTABILITY_LIMIT = 0.1


def box_instability(parameters, box) -> dict | None:
    """The dilute theory's shear instability for a run's parameters and box, or None where it does not apply.

    It applies to one species of smooth spheres or discs with a constant
    restitution below 1, at rest, at packing fractions up to
    :data:`DILUTE_INSTABILITY_LIMIT` (the theory is of a constant e: a run
    that reached its elastic floor is not what it describes).

    Parameters
    ----------
    parameters : EdmdParameters
    box : array_like
        The run's box lengths.

    Returns
    -------
    dict or None
        ``box_length`` (the longest side), ``shear_instability_length``
        (:func:`shear_instability_length`) and ``shear_mode_growth``
        (:func:`shear_mode_growth` at the longest side).

    Examples
    --------
    >>> from collisionkit.edmd import EdmdParameters
    >>> found = box_instability(EdmdParameters(dim=2, particles=2000, packing_fraction=0.05, restitution=0.7),
    ...                         [177.2, 177.2])
    >>> round(found["shear_instability_length"], 1), round(found["shear_mode_growth"], 4)
    (81.6, 0.1005)
    >>> box_instability(EdmdParameters(particles=2000, packing_fraction=0.3, restitution=0.7), [20.3] * 3) is None
    True
    """
    p = parameters
    smooth = p.tangential_restitution is None or p.tangential_restitution == -1.0
    if (p.elastic or not smooth or len(p.species_counts) > 1 or p.restitution_law != "constant" or p.shear_rate != 0.0
            or p.packing_fraction > DILUTE_INSTABILITY_LIMIT):  # (wells are elastic)
        return None
    restitution = p.restitution if not isinstance(p.restitution, tuple) else p.restitution[0][0]
    side = float(np.max(np.asarray(box, dtype=float)[: p.dim]))
    return {"box_length": side,
            "shear_instability_length": shear_instability_length(restitution, p.packing_fraction, p.dim),
            "shear_mode_growth": shear_mode_growth(restitution, side, p.packing_fraction, p.dim)}


def instability_note(parameters, box, share: float = 100.0) -> str | None:
    """What to say before a cooling run whose box exceeds the shear instability's critical length; else None.

    The collisions per particle in which the longest shear mode's energy
    grows ``share`` times, ln(share) / (2 g), against the run's, and the
    most particles that keep the box below the critical length at the same
    packing fraction.

    Parameters
    ----------
    parameters : EdmdParameters
        Resolved (``total_collisions`` known).
    box : array_like
        The run's box lengths.
    share : float
        The growth of the mode's energy to report, > 1.

    Returns
    -------
    str or None

    Examples
    --------
    >>> from collisionkit.edmd import EdmdParameters
    >>> p = EdmdParameters(dim=2, particles=2000, packing_fraction=0.05, restitution=0.7, collisions=20000)
    >>> print(instability_note(p.resolved(seed=1), [177.2, 177.2]))
    the box (side 177) is 2.17 times the shear instability's critical length at e = 0.7 (81.6, dilute Navier-Stokes theory): its box-scale shear flows grow to 100 times an uncorrelated gas's share of the energy in about 23 collisions per particle (the run does 60, its equilibration included), into vortices; 423 particles or fewer keep the box below the critical length at this packing fraction (well below it, under half, its flows stay near an uncorrelated gas's)
    """
    found = box_instability(parameters, box)
    if found is None or found["shear_mode_growth"] <= 0.0:
        return None
    p = parameters
    side, critical = found["box_length"], found["shear_instability_length"]
    restitution = p.restitution if not isinstance(p.restitution, tuple) else p.restitution[0][0]
    growing = math.log(share) / (2.0 * found["shear_mode_growth"])
    collisions = 2.0 * (p.total_collisions - (p.equilibration if p.elastic_equilibration else 0)) / p.particles
    stable = int(p.particles * (critical / side) ** p.dim)
    return (f"the box (side {side:.3g}) is {side / critical:.3g} times the shear instability's critical length at "
            f"e = {restitution:g} ({critical:.3g}, dilute Navier-Stokes theory): its box-scale shear flows grow "
            f"to {share:g} times an uncorrelated gas's share of the energy in about {growing:.0f} collisions per particle "
            f"(the run does {collisions:.0f}{'' if p.elastic_equilibration else ', its equilibration included'}), "
            f"into vortices; {stable} particles or fewer "
            "keep the box below the critical length at this packing fraction (well below it, under half, its flows "
            "stay near an uncorrelated gas's)")
