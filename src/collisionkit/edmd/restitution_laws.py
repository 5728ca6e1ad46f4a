r"""Velocity-dependent restitution: the laws the engine applies, and the cooling rate they give a granular gas.

A contact at normal approach speed :math:`u_n` gets the coefficient of
normal restitution :math:`e(u_n)` (:func:`restitution_coefficient`): the
pair's constant, or, with a law, the smaller of that and the law's value:

- ``"bridges"``: :math:`e = (u_n / u_c)^{-p}` above :math:`u_c`, 1 below
  (ice at planetary-ring temperatures, p = 0.234: Bridges, Hatzes & Lin,
  Nature 309, 333 (1984));
- ``"viscoelastic"``: viscoelastic spheres, the Hertz contact with a
  dissipative force (Brilliantov, Spahn, Hertzsch & Poeschel, Phys. Rev. E 53,
  5382 (1996)), its restitution a function of
  :math:`q = (u_n / u_c)^{1/5}` alone with :math:`1 - e = q + O(q^2)`,
  solved exactly (e to 1e-9, the loss 1 - e to 1e-5 of itself) with the contact ending when its force vanishes
  (Schwager & Poeschel, Phys. Rev. E 78, 051304 (2008)). From the material
  constants A and :math:`\rho / m_{eff}` of Brilliantov et al.,
  :math:`u_c = (\tfrac32 C_1 A (\rho/m_{eff})^{2/5})^{-5}` with
  :math:`C_1 = \sqrt\pi\, \Gamma(3/5) / (2^{1/5} 5^{2/5} \Gamma(21/10)) = 1.15345`
  (Ramirez, Poeschel, Brilliantov & Schwager, Phys. Rev. E 60, 4465 (1999)).
  One :math:`u_c` serves every pair.

Contacts slower than ``elastic_below`` are elastic whatever the law.

:func:`maxwellian_cooling_rate` is the rate at which such a gas of one
species loses its temperature per collision, :math:`-d\ln T/dC`, if its
velocities stay Maxwellian: exact for a constant e up to the first Sonine
correction (Haff's :math:`(1 - e^2)/d`), and for a law the rate at the
given kT (it falls as the gas cools and its contacts slow down:
:math:`\propto T^{1/10}` for slightly viscoelastic spheres, whence
:math:`T \propto t^{-5/3}`, Brilliantov & Poeschel, Phys. Rev. E 61, 5573
(2000)); :func:`maxwellian_cooling` follows kT through the collisions.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.polynomial import chebyshev
from scipy.integrate import quad, solve_ivp

from .._kernels.edmd.restitution_laws import VISCOELASTIC_LOG_COEFFICIENTS, VISCOELASTIC_Q_MAX, VISCOELASTIC_Q_SERIES
from . import _checks
from ._system_setup import RESTITUTION_LAWS

__all__ = ["maxwellian_cooling", "maxwellian_cooling_rate", "restitution_coefficient"]

# the Bridges law's exponent for ice (Bridges, Hatzes & Lin 1984)
BRIDGES_EXPONENT = 0.234


def _viscoelastic(q: np.ndarray) -> np.ndarray:
    """The viscoelastic law's e at q >= 0: the kernels' Chebyshev series (and tail) in numpy."""
    q = np.asarray(q, dtype=float)
    inside = np.minimum(q, VISCOELASTIC_Q_MAX)
    t = 2.0 * np.log1p(np.sqrt(inside)) / math.log1p(math.sqrt(VISCOELASTIC_Q_MAX)) - 1.0
    tail = np.where(q > VISCOELASTIC_Q_MAX, (np.maximum(q, VISCOELASTIC_Q_MAX) / VISCOELASTIC_Q_MAX) ** (-5.0 / 3.0),
                    1.0)
    series = 1.0 - q + 0.6 * q * q
    return np.where(q < VISCOELASTIC_Q_SERIES, series, np.exp(chebyshev.chebval(t, VISCOELASTIC_LOG_COEFFICIENTS)) * tail)


def _law_arguments(law, restitution, law_speed, law_exponent, elastic_below):
    """The checked arguments of a law, as :func:`restitution_coefficient` takes them."""
    if not isinstance(law, str) or law not in RESTITUTION_LAWS:
        raise ValueError(f"law must be one of {', '.join(RESTITUTION_LAWS)}; got {law!r}")
    restitution = _checks.bounded(restitution, "restitution", 0.0, 1.0, closed=(True, True))
    law_speed = _checks.positive(law_speed, "law_speed")
    law_exponent = _checks.positive(law_exponent, "law_exponent")
    elastic_below = _checks.bounded(elastic_below, "elastic_below", 0.0)
    return law, restitution, law_speed, law_exponent, elastic_below


def _coefficient(speed, law, restitution, law_speed, law_exponent, elastic_below):
    """e at ``speed`` (array, >= 0) for checked arguments: the engine's rule (``restitution_for`` of the kernels)."""
    e = np.full(np.shape(speed), restitution)
    if law == "bridges":
        faster = speed > law_speed
        e = np.where(faster, np.minimum(e, (np.where(faster, speed, law_speed) / law_speed) ** -law_exponent), e)
    elif law == "viscoelastic":
        e = np.minimum(e, _viscoelastic((speed / law_speed) ** 0.2))
    return np.where(speed < elastic_below, 1.0, e)


def restitution_coefficient(speed, law="constant", restitution=1.0, law_speed=1.0, law_exponent=BRIDGES_EXPONENT,
                            elastic_below=0.0):
    r"""The coefficient of normal restitution of a contact at normal approach speed ``speed``, as the engine applies it.

    ``law`` "constant": ``restitution``. "bridges": the smaller of ``restitution`` and
    :math:`(u_n / u_c)^{-p}` (:math:`u_c` = ``law_speed``, p = ``law_exponent``; 1 below :math:`u_c`).
    "viscoelastic": the smaller of ``restitution`` and the viscoelastic spheres' :math:`e(q)`,
    :math:`q = (u_n / u_c)^{1/5}`, :math:`1 - e = q + O(q^2)` (see the module docstring). Contacts slower than
    ``elastic_below`` have e = 1.

    Parameters
    ----------
    speed : float or array_like
        Normal approach speed(s) :math:`u_n \ge 0`.
    law : {"constant", "bridges", "viscoelastic"}
    restitution : float
        The pair's constant coefficient, in [0, 1].
    law_speed : float
        :math:`u_c` > 0.
    law_exponent : float
        The Bridges law's exponent p > 0 (default 0.234, ice).
    elastic_below : float
        The elastic floor (>= 0).

    Returns
    -------
    float or ndarray

    Examples
    --------
    >>> from collisionkit.edmd import restitution_coefficient
    >>> float(restitution_coefficient(4.0, "bridges", law_speed=1.0, law_exponent=0.5))
    0.5
    >>> round(float(restitution_coefficient(1e-5, "viscoelastic")), 4)  # q = (1e-5)^(1/5) = 0.1: 1 - q + O(q^2)
    0.9062
    """
    law, restitution, law_speed, law_exponent, elastic_below = _law_arguments(
        law, restitution, law_speed, law_exponent, elastic_below)
    speed = _checks.bounded(speed, "speed", 0.0, scalar=False)
    e = _coefficient(speed, law, restitution, law_speed, law_exponent, elastic_below)
    return float(e) if e.ndim == 0 else e


def maxwellian_cooling_rate(kT, dim=3, mass=1.0, law="constant", restitution=1.0, law_speed=1.0,
                            law_exponent=BRIDGES_EXPONENT, elastic_below=0.0):
    r"""-d ln T / dC of a granular gas of one species with Maxwellian velocities (C: collisions per particle).

    A collision loses :math:`\frac{m}{4} (1 - e^2) u_n^2`; collisions happen at normal approach speeds
    :math:`u_n` with probability :math:`\propto u_n e^{-u_n^2 / 2\sigma^2}`, :math:`\sigma^2 = 2kT/m`, so that

    .. math:: -\frac{d \ln T}{dC} = \frac{1}{2d} \int_0^\infty \left(1 - e(\sigma x)^2\right) x^3 e^{-x^2/2}\, dx,

    :math:`(1 - e^2)/d` for a constant e (Haff's law per collision). A density-independent rate per collision:
    Enskog's contact value scales the collisions and the loss alike.

    Parameters
    ----------
    kT : float or array_like
        Temperature(s) > 0.
    dim : {2, 3}
    mass : float
        The particles' mass (> 0).
    law, restitution, law_speed, law_exponent, elastic_below
        As :func:`restitution_coefficient`.

    Returns
    -------
    float or ndarray

    Examples
    --------
    >>> from collisionkit.edmd import maxwellian_cooling_rate
    >>> round(maxwellian_cooling_rate(1.0, restitution=0.9), 6)  # (1 - 0.81) / 3
    0.063333
    >>> maxwellian_cooling_rate(1.0, law="viscoelastic", law_speed=1e5) < maxwellian_cooling_rate(
    ...     4.0, law="viscoelastic", law_speed=1e5)   # faster contacts lose more
    True
    """
    arguments = _law_arguments(law, restitution, law_speed, law_exponent, elastic_below)
    temperatures = _checks.positive(kT, "kT", scalar=False)
    d = _checks.dimension(dim)
    sigma = np.sqrt(2.0 * temperatures / _checks.positive(mass, "mass"))
    rates = np.array([_cooling_integral(float(s), arguments) for s in sigma.ravel()]).reshape(sigma.shape) / (2 * d)
    return float(rates) if rates.ndim == 0 else rates


def _cooling_integral(sigma: float, arguments) -> float:
    r""":math:`\int_0^\infty (1 - e(\sigma x)^2) x^3 e^{-x^2/2} dx`, split where the law has a kink."""
    law, restitution, law_speed, _exponent, elastic_below = arguments

    def loss(x):
        e = float(_coefficient(np.asarray(sigma * x), *arguments))
        return (1.0 - e * e) * x**3 * math.exp(-0.5 * x * x)

    kinks = sorted({x for x in (elastic_below / sigma, law_speed / sigma if law == "bridges" else 0.0) if 0 < x < 40})
    edges = [0.0, *kinks, 40.0]  # beyond 40 the weight is below e^-800
    return sum(quad(loss, low, high, epsabs=0.0, epsrel=1e-11, limit=200)[0] for low, high in zip(edges, edges[1:]))


def maxwellian_cooling(collisions, kT0=1.0, dim=3, mass=1.0, law="constant", restitution=1.0, law_speed=1.0,
                       law_exponent=BRIDGES_EXPONENT, elastic_below=0.0):
    r"""kT after C collisions per particle of a granular gas of one species, from kT0 at C = 0, if it stays Maxwellian.

    Integrates :math:`d\ln T/dC = -\zeta(T)` with the rate of :func:`maxwellian_cooling_rate`:
    :math:`kT_0 e^{-(1 - e^2) C/d}` for a constant e (Haff's law per collision).

    Parameters
    ----------
    collisions : array_like
        Collisions per particle C >= 0 (2 per pair collision / N), increasing.
    kT0 : float
        kT at C = 0 (> 0).
    dim, mass, law, restitution, law_speed, law_exponent, elastic_below
        As :func:`maxwellian_cooling_rate`.

    Returns
    -------
    ndarray
        kT at each of ``collisions``.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.edmd import maxwellian_cooling
    >>> kT = maxwellian_cooling([0.0, 10.0], restitution=0.9)
    >>> bool(np.isclose(kT[1], np.exp(-10 * 0.19 / 3), rtol=1e-7))
    True
    """
    arguments = _law_arguments(law, restitution, law_speed, law_exponent, elastic_below)
    collisions = _checks.bounded(collisions, "collisions", 0.0, scalar=False).ravel()
    if np.any(np.diff(collisions) < 0.0):
        raise ValueError("collisions must be increasing")
    start = _checks.positive(kT0, "kT0")
    d = _checks.dimension(dim)
    mass = _checks.positive(mass, "mass")

    def slope(_c, log_kT):
        sigma = math.sqrt(2.0 * math.exp(log_kT[0]) / mass)
        return [-_cooling_integral(sigma, arguments) / (2 * d)]

    if collisions.size == 0 or collisions[-1] == 0.0:
        return np.full(collisions.shape, start)
    solution = solve_ivp(slope, (0.0, float(collisions[-1])), [math.log(start)], t_eval=collisions, rtol=1e-9,
                         atol=1e-12)
    return np.exp(solution.y[0])
