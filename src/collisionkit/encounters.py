r"""Two-body encounters: hyperbolic (and bound) orbits under gravity or a Coulomb force.

Two point bodies of masses ``m1``, ``m2`` interact through the inverse-square
potential :math:`V(r) = k_{tot}/r` with :math:`k_{tot} = k - G m_1 m_2`
(gravity, a Coulomb force :math:`k = q_1 q_2/(4\pi\varepsilon_0)` of either
sign, or both). The separation :math:`\mathbf r = \mathbf x_2 - \mathbf x_1`
then obeys Kepler's problem

.. math:: \ddot{\mathbf r} = -\mu_K\,\mathbf r / r^3,\qquad
          \mu_K = G(m_1 + m_2) - k/\mu,\qquad \mu = m_1 m_2/(m_1 + m_2),

attractive for :math:`\mu_K > 0`, repulsive for :math:`\mu_K < 0`.

Set-up (StarCrash user manual, J. Faber 2003, "Hyperbolic Collisions",
eqs. 34-39): for periastron distance :math:`r_p`, relative speed at infinity
:math:`v_\infty` and initial separation :math:`r_0`,

.. math::
    E_T = \tfrac12\mu v_\infty^2,\quad
    v_0 = \sqrt{v_\infty^2 + 2\mu_K/r_0},\quad
    v_p = \sqrt{v_\infty^2 + 2\mu_K/r_p},\quad
    J_T = \mu v_p r_p,\quad
    b = J_T/(\mu v_\infty),\quad
    v_t = v_\infty b / r_0,\quad v_r = \sqrt{v_0^2 - v_t^2}.

Orbit: eccentricity :math:`e = |1 + r_p v_\infty^2/\mu_K| = \sqrt{1 + b^2 v_\infty^4/\mu_K^2}`
(:math:`\mu_K < 0` for a repulsive force, where :math:`e = r_p v_\infty^2/|\mu_K| - 1`),
semi-major axis :math:`a = -\mu_K/v_\infty^2`, deflection
:math:`\chi = 2\arcsin(1/e) = 2\arctan(|\mu_K|/(b v_\infty^2))` (Rutherford's
law, :mod:`collisionkit.scattering`).

Propagation is exact for every eccentricity: Kepler's equation is solved in
the universal anomaly with Stumpff functions, measured from periastron
(Danby, *Fundamentals of Celestial Mechanics*, sec. 6.9), see
:mod:`collisionkit._kernels.encounters`. Times are always measured from a
periastron passage: negative before it, positive after.

Units: any consistent system. :data:`UNIT_SYSTEMS` gives G in N-body units
(G = 1), SI, cgs, solar units (Msun, AU, yr) and stellar units (Msun, Rsun,
km/s).
"""

from __future__ import annotations

import math
import sys
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import scipy.constants as const

from . import _arrays, scattering
from ._io import atomic_write_json, atomic_write_text
from ._kernels import encounters as _k
from .collisions import resolve_contact

__all__ = [
    "GridExitWarning",
    "UnitSystem",
    "UNIT_SYSTEMS",
    "unit_system",
    "TwoBodyOrbit",
    "Hyperbolic",
    "EncounterContact",
    "MergedBody",
    "Impact",
    "InitialConditions",
    "starcrash_initial_conditions",
    "focusing_cross_section",
    "merge_bodies",
]

#: IAU 2015 nominal solar mass parameter GM_sun (m^3 s^-2), Resolution B3.
GM_SUN = 1.3271244e20
#: IAU 2015 nominal solar radius (m), Resolution B3.
R_SUN = 6.957e8
#: The speed ratio v_t / v0 above which a star started in a grid corner can leave the grid.
GRID_SPEED_RATIO_LIMIT = math.sqrt(1.0 / 3.0)
# relative mismatch of energy or angular momentum up to which a state counts as lying on an orbit
ON_ORBIT_TOLERANCE = 1e-9


class GridExitWarning(UserWarning):
    """StarCrash set-up whose initial velocity can carry a star off the gravity grid.

    Raised (as a warning) when :math:`v_t/v_0 > \\sqrt{1/3}`; the seed's advice is to
    start the stars further apart.

    Examples
    --------
    >>> import warnings
    >>> from collisionkit.encounters import GridExitWarning, starcrash_initial_conditions
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     ic = starcrash_initial_conditions(1.0, 1.0, rp=1.0, vinf=0.5, sep0=1.2)
    >>> caught[0].category is GridExitWarning, round(ic.speed_ratio, 3)
    (True, 0.908)
    """


# --------------------------------------------------------------------------- units


@dataclass(frozen=True)
class UnitSystem:
    """A consistent set of units and the value of G in it.

    Attributes
    ----------
    name : str
        Key in :data:`UNIT_SYSTEMS`.
    G : float
        Gravitational constant in these units.
    mass, length, time, velocity : str
        Unit labels.
    mass_si, length_si, time_si : float
        Size of each unit in kg, m and s (NaN for N-body units).

    Examples
    --------
    >>> from collisionkit.encounters import UNIT_SYSTEMS
    >>> stellar = UNIT_SYSTEMS["stellar"]
    >>> stellar.velocity, round(stellar.G)  # G Msun / Rsun in (km/s)^2
    ('km/s', 190761)
    """

    name: str
    G: float
    mass: str
    length: str
    time: str
    velocity: str
    mass_si: float
    length_si: float
    time_si: float


def _system(name, mass, length, time, velocity, mass_si, length_si, time_si) -> UnitSystem:
    G = const.G * mass_si * time_si**2 / length_si**3
    return UnitSystem(name, G, mass, length, time, velocity, mass_si, length_si, time_si)


_M_SUN = GM_SUN / const.G  # kg, consistent with GM_SUN and CODATA G
_KM_S = 1e3

#: Unit systems by name. ``nbody``: G = 1 (StarCrash's units); ``si``: kg, m, s;
#: ``cgs``: g, cm, s; ``solar``: Msun, AU, Julian year (G close to 4 pi^2);
#: ``stellar``: Msun, Rsun, km/s (time unit Rsun / (km/s) = 695700 s).
UNIT_SYSTEMS: dict[str, UnitSystem] = {
    "nbody": UnitSystem("nbody", 1.0, "M", "L", "T", "L/T", math.nan, math.nan, math.nan),
    "si": _system("si", "kg", "m", "s", "m/s", 1.0, 1.0, 1.0),
    "cgs": _system("cgs", "g", "cm", "s", "cm/s", 1e-3, 1e-2, 1.0),
    "solar": _system("solar", "Msun", "AU", "yr", "AU/yr", _M_SUN, const.au, const.Julian_year),
    "stellar": _system("stellar", "Msun", "Rsun", "Rsun/(km/s)", "km/s", _M_SUN, R_SUN, R_SUN / _KM_S),
}


def unit_system(name: str) -> UnitSystem:
    """The unit system called ``name`` (see :data:`UNIT_SYSTEMS`).

    Examples
    --------
    >>> from collisionkit.encounters import unit_system
    >>> round(unit_system("cgs").G, 13)
    6.6743e-08
    >>> round(unit_system("solar").G, 3)  # AU^3 / (Msun yr^2)
    39.477
    """
    if name not in UNIT_SYSTEMS:
        allowed = ", ".join(repr(key) for key in UNIT_SYSTEMS)
        raise ValueError(f"units must be one of {allowed}; got {name!r}")
    return UNIT_SYSTEMS[name]


# --------------------------------------------------------------------------- validation


def _scalar(value, name: str, low: float = 0.0, *, inclusive: bool = False) -> float:
    """A finite real number > low (>= low if inclusive), or a named error."""
    array = _arrays.as_float_array(value, name)
    if array.ndim != 0:
        raise TypeError(f"{name} must be a single number; got an array of shape {array.shape}")
    _arrays.require_finite(array, name)
    _arrays.require_in_range(array, name, low, np.inf, inclusive=(inclusive, False))
    return float(array)


def _speed(value, name: str) -> float:
    """A speed whose square is a normal float (> ~1.5e-154), or a named error (v^2 would round to 0)."""
    speed = _scalar(value, name)
    if speed * speed < sys.float_info.min:
        raise ValueError(f"{name} must be > {math.sqrt(sys.float_info.min):.3g} (its square must not round to 0); "
                         f"got {speed!r}")
    return speed


def _real(value, name: str) -> float:
    array = _arrays.as_float_array(value, name)
    if array.ndim != 0:
        raise TypeError(f"{name} must be a single number; got an array of shape {array.shape}")
    _arrays.require_finite(array, name)
    return float(array)


def _state_vector(value, name: str) -> np.ndarray:
    array = _arrays.as_vector_array(value, name)
    if array.ndim != 1:
        raise ValueError(f"{name} must be one vector of length 1, 2 or 3; got shape {array.shape}")
    _arrays.require_finite(array, name)
    return np.concatenate([array, np.zeros(3 - array.size)])


def _interaction(m1, m2, G, k):
    """Validated (m1, m2, G, k, mu_K); G defaults to 1 when k is not given."""
    m1 = _scalar(m1, "m1")
    m2 = _scalar(m2, "m2")
    G = (1.0 if k is None else 0.0) if G is None else _scalar(G, "G", inclusive=True)
    k = 0.0 if k is None else _real(k, "k")
    mu_k = G * (m1 + m2) - k * (m1 + m2) / (m1 * m2)
    if not math.isfinite(mu_k):
        raise ValueError("G (m1 + m2) - k / mu overflows; rescale the units")
    if mu_k == 0.0:
        raise ValueError("the interaction vanishes (G (m1 + m2) = k / mu): the bodies move in straight lines")
    return m1, m2, G, k, mu_k


# --------------------------------------------------------------------------- orbit


def _unit(vector: np.ndarray) -> np.ndarray:
    return vector / np.linalg.norm(vector)


def _perpendicular(vector: np.ndarray) -> np.ndarray:
    """Some unit vector perpendicular to ``vector``."""
    axis = np.zeros(3)
    axis[int(np.argmin(np.abs(vector)))] = 1.0
    return _unit(np.cross(vector, axis))


def _basis_from_direction(r_hat, theta_hat, x_p, x_q) -> np.ndarray:
    """Rows P, Q, W of the perifocal basis, given the state's direction r_hat,
    the in-plane normal theta_hat (towards the motion) and the perifocal position."""
    length = math.hypot(x_p, x_q)
    p = (x_p * r_hat - x_q * theta_hat) / length
    q = (x_q * r_hat + x_p * theta_hat) / length
    return np.array([p, q, np.cross(p, q)])


class TwoBodyOrbit:
    r"""Relative orbit of two bodies under an inverse-square force: any conic.

    Built from the periastron distance and the eccentricity (any conic:
    check :attr:`kind`); see :class:`Hyperbolic` for (r_p, v_inf), :meth:`from_impact_parameter` for
    (b, v_inf) and :meth:`from_state` for a position and velocity. The orbit
    lies in the xy plane with periastron on +x and the angular momentum along
    +z, unless built from a state.

    Internally the orbit is held as :math:`(\mu_K, r_p, \beta)` with
    :math:`\beta = 2\mu_K/r_p - v_p^2` (minus twice the specific energy) and
    :math:`q = \mu_K - \beta r_p = |\mu_K| e`, which stay exact as
    :math:`e \to 1`.

    Parameters
    ----------
    m1, m2 : float
        Masses, > 0.
    periastron : float
        Distance of closest approach r_p, > 0.
    eccentricity : float
        e >= 0 (attractive; e < 1 elliptic, 1 parabolic, > 1 hyperbolic), or
        e >= 1 for a repulsive force (e = 1: head-on, radial orbit).
    G : float, optional
        Gravitational constant, >= 0; default 1 (N-body units) if ``k`` is
        not given, else 0 (pure Coulomb force).
    k : float, optional
        Coulomb constant q1 q2 / (4 pi eps0): > 0 repulsive, < 0 attractive
        (:func:`collisionkit.scattering.coulomb_strength` gives it in SI).

    Examples
    --------
    A bound orbit (capture) with e = 0.5 has period 2 pi a^(3/2) / sqrt(G M):

    >>> import math
    >>> from collisionkit.encounters import TwoBodyOrbit
    >>> orbit = TwoBodyOrbit(1.0, 1.0, periastron=1.0, eccentricity=0.5)
    >>> orbit.kind, orbit.semi_major_axis, round(orbit.period / (2 * math.pi * 2**1.5 / math.sqrt(2)), 12)
    ('elliptic', 2.0, 1.0)
    """

    def __init__(self, m1, m2, periastron, eccentricity, *, G=None, k=None):
        m1, m2, G, k, mu_k = _interaction(m1, m2, G, k)
        rp = _scalar(periastron, "periastron")
        lowest = 0.0 if mu_k > 0 else 1.0
        e = _scalar(eccentricity, "eccentricity", lowest, inclusive=True)
        beta = (mu_k - abs(mu_k) * e) / rp
        self._setup(m1, m2, G, k, mu_k, rp, beta, np.eye(3))

    # -- construction ---------------------------------------------------------

    def _setup(self, m1, m2, G, k, mu_k, rp, beta, basis, h=None):
        """Store the elements; ``h`` = |r x v| when the caller knows it better than r_p (mu_K + q) does.

        For a repulsive force mu_K + q = |mu_K| (e - 1) cancels as e -> 1 (a
        near head-on encounter): there h = b v_inf or |r x v| keeps all its digits.
        """
        self.m1, self.m2, self.G, self.k = m1, m2, G, k
        self._mu_k, self._rp, self._beta = mu_k, rp, beta
        self._q = max(mu_k - beta * rp, 0.0)  # |mu_K| e, >= 0 (round-off of a circular state)
        self._h = math.sqrt(max(rp * (mu_k + self._q), 0.0)) if h is None else float(h)
        self._basis = np.array(basis, dtype=float)

    @staticmethod
    def _from_elements(m1, m2, G, k, mu_k, rp, beta, basis, h=None) -> TwoBodyOrbit:
        orbit = object.__new__(Hyperbolic if beta < 0 else TwoBodyOrbit)
        orbit._setup(m1, m2, G, k, mu_k, rp, beta, basis, h)
        return orbit

    @classmethod
    def from_impact_parameter(cls, m1, m2, impact_parameter, v_inf, *, G=None, k=None) -> Hyperbolic:
        r"""Unbound orbit from the impact parameter b and the speed at infinity.

        The periastron is :func:`collisionkit.scattering.coulomb_closest_approach`:
        :math:`r_p = a + \sqrt{a^2 + b^2}` with :math:`a = -\mu_K/v_\infty^2`
        (the inverse of eq. 38 for gravity).

        Parameters
        ----------
        impact_parameter : float
            b > 0 (b >= 0 for a repulsive force: b = 0 is head-on).
        v_inf : float
            Relative speed at infinity, > 0.

        Examples
        --------
        >>> from collisionkit.encounters import Hyperbolic
        >>> orbit = Hyperbolic.from_impact_parameter(1.0, 1.0, 3.0, 1.0)
        >>> round(orbit.periastron, 12)  # b^2 = rp^2 + 2 G M rp / v^2 = 9 at rp = 1.6055...
        1.605551275464
        """
        m1, m2, G, k, mu_k = _interaction(m1, m2, G, k)
        v = _speed(v_inf, "v_inf")
        b = _scalar(impact_parameter, "impact_parameter", 0.0, inclusive=mu_k < 0)
        mu = m1 * m2 / (m1 + m2)
        rp = float(scattering.coulomb_closest_approach(b, -mu * mu_k, mu, v))
        return cls._from_elements(m1, m2, G, k, mu_k, rp, -v * v, np.eye(3), h=b * v)

    @classmethod
    def from_state(cls, m1, m2, separation, relative_velocity, *, G=None, k=None) -> TwoBodyOrbit:
        r"""The orbit through a given relative state (any conic, any orientation).

        Energy and angular momentum fix :math:`\beta = 2\mu_K/r - v^2` and
        :math:`h = |\mathbf r\times\mathbf v|`. The periastron is
        :math:`r_p = h^2/(\mu_K(1 + e))` with e the length of the
        Laplace-Runge-Lenz vector :math:`\mathbf v\times\mathbf h/\mu_K - \hat r`
        (attraction), or the root :math:`r_p = (D - \mu_K)/(2\varepsilon)` of
        :math:`v_p^2/2 - \mu_K/r_p = \varepsilon`, :math:`D = \sqrt{\mu_K^2 + 2\varepsilon h^2}`
        (repulsion); neither cancels. Returns a :class:`Hyperbolic` when
        the state is unbound. Use :meth:`time_since_periastron` for the time
        of the given state.

        Parameters
        ----------
        separation : array_like, shape (d,)
            x2 - x1, d = 1, 2 or 3 (padded with zeros to 3D).
        relative_velocity : array_like, shape (d,)
            v2 - v1.

        Examples
        --------
        >>> from collisionkit.encounters import TwoBodyOrbit
        >>> orbit = TwoBodyOrbit.from_state(1.0, 1.0, [1.0, 0.0], [0.0, 3.0])
        >>> type(orbit).__name__, orbit.periastron, orbit.eccentricity  # e = r v^2 / (G M) - 1
        ('Hyperbolic', 1.0, 3.5)
        >>> TwoBodyOrbit.from_state(1.0, 1.0, [1.0, 0.0], [0.0, 2.0]).kind  # v = escape speed
        'parabolic'
        """
        m1, m2, G, k, mu_k = _interaction(m1, m2, G, k)
        r_vec = _state_vector(separation, "separation")
        v_vec = _state_vector(relative_velocity, "relative_velocity")
        r = float(np.linalg.norm(r_vec))
        if r == 0.0:
            raise ValueError("separation must be a non-zero vector")
        h_vec = np.cross(r_vec, v_vec)
        h = float(np.linalg.norm(h_vec))
        beta = 2.0 * mu_k / r - float(v_vec @ v_vec)
        energy = -0.5 * beta
        if mu_k > 0 and h <= 1e-15 * r * math.sqrt(2.0 * mu_k / r + float(v_vec @ v_vec)):
            raise ValueError("the state is on a radial orbit (zero angular momentum): the bodies collide head-on")
        if mu_k > 0:
            # e from the Laplace-Runge-Lenz vector (good to round-off even for a circle,
            # where sqrt(mu^2 + 2 eps h^2) = mu e would only give e to sqrt(round-off))
            e = float(np.linalg.norm(np.cross(v_vec, h_vec) / mu_k - r_vec / r))
            rp = h * h / (mu_k * (1.0 + e))
        else:
            rp = (math.sqrt(mu_k * mu_k + 2.0 * energy * h * h) - mu_k) / (2.0 * energy)
        rp = min(rp, r)
        q = max(mu_k - beta * rp, 0.0)  # as in _setup, so the anomaly and the orbit agree
        sigma = float(r_vec @ v_vec)
        s = _k.anomaly_of_state(r, sigma, rp, beta, q)
        x_p, x_q = _k.perifocal_position(s, mu_k, rp, beta, q, h)
        r_hat = r_vec / r
        if h > 0.0:
            theta_hat = np.cross(h_vec / h, r_hat)
        else:
            theta_hat = _perpendicular(r_hat)
        basis = _basis_from_direction(r_hat, theta_hat, x_p, x_q)
        return cls._from_elements(m1, m2, G, k, mu_k, rp, beta, basis, h=h)

    # -- elements ---------------------------------------------------------------

    @property
    def total_mass(self) -> float:
        """m1 + m2."""
        return self.m1 + self.m2

    @property
    def reduced_mass(self) -> float:
        """mu = m1 m2 / (m1 + m2)."""
        return self.m1 * self.m2 / (self.m1 + self.m2)

    @property
    def kepler_parameter(self) -> float:
        """mu_K = G (m1 + m2) - k / mu in r'' = -mu_K r / r^3 (< 0: repulsive)."""
        return self._mu_k

    @property
    def coulomb_strength(self) -> float:
        """Total inverse-square strength k_tot = k - G m1 m2 = -mu mu_K, V(r) = k_tot / r."""
        return -self.reduced_mass * self._mu_k

    @property
    def attractive(self) -> bool:
        """Whether the net force pulls the bodies together."""
        return self._mu_k > 0

    @property
    def kind(self) -> str:
        """'elliptic', 'parabolic' or 'hyperbolic' (sign of the energy)."""
        return "elliptic" if self._beta > 0 else "parabolic" if self._beta == 0 else "hyperbolic"

    @property
    def periastron(self) -> float:
        """Distance of closest approach r_p."""
        return self._rp

    @property
    def periastron_speed(self) -> float:
        """Relative speed at periastron, v_p = sqrt(v_inf^2 + 2 mu_K / r_p) (eq. 36)."""
        return self._h / self._rp

    @property
    def apoastron(self) -> float:
        """Largest separation, r_p (1 + e) / (1 - e) (elliptic); inf otherwise."""
        return 2.0 * self._mu_k / self._beta - self._rp if self._beta > 0 else math.inf

    @property
    def eccentricity(self) -> float:
        """e = q / |mu_K| = 1 + r_p v_inf^2 / mu_K (attractive) or 1 + r_p v_p^2 / |mu_K| (repulsive)."""
        return self._q / abs(self._mu_k)

    @property
    def semi_major_axis(self) -> float:
        """a = mu_K / beta = -mu_K / v_inf^2 when unbound (inf for a parabola)."""
        return self._mu_k / self._beta if self._beta != 0 else math.inf

    @property
    def semi_latus_rectum(self) -> float:
        """p = h^2 / |mu_K|."""
        return self._h**2 / abs(self._mu_k)

    @property
    def specific_energy(self) -> float:
        """Energy of the relative motion per unit reduced mass, v^2/2 - mu_K/r = -beta/2."""
        return -0.5 * self._beta

    @property
    def energy(self) -> float:
        """Conserved energy of the relative motion, E_T = mu v_inf^2 / 2 when unbound (eq. 34)."""
        return self.reduced_mass * self.specific_energy

    @property
    def specific_angular_momentum(self) -> float:
        """h = |r x v| = r_p v_p."""
        return self._h

    @property
    def angular_momentum(self) -> float:
        """J_T = mu v_p r_p = mu sqrt(r_p^2 v_inf^2 + 2 mu_K r_p) (eq. 37)."""
        return self.reduced_mass * self._h

    @property
    def angular_momentum_vector(self) -> np.ndarray:
        """J_T times the unit normal of the orbital plane."""
        return self.angular_momentum * self._basis[2]

    @property
    def basis(self) -> np.ndarray:
        """Rows P (towards periastron), Q (velocity at periastron), W = P x Q."""
        return self._basis.copy()

    @property
    def v_inf(self) -> float:
        """Relative speed at infinity sqrt(-beta); 0 for a parabola, NaN when bound."""
        if self._beta > 0:
            return math.nan
        return math.sqrt(-self._beta) if self._beta < 0 else 0.0

    @property
    def impact_parameter(self) -> float:
        """b = J_T / (mu v_inf) = sqrt(r_p^2 + 2 mu_K r_p / v_inf^2) (eq. 38); inf parabolic, NaN bound."""
        if self._beta > 0:
            return math.nan
        return self._h / self.v_inf if self._beta < 0 else math.inf

    @property
    def deflection_angle(self) -> float:
        r"""Angle between incoming and outgoing relative velocities, in [0, pi].

        :math:`\chi = 2\arctan(|\mu_K|/(b v_\infty^2)) = 2\arcsin(1/e)`, from
        :func:`collisionkit.scattering.rutherford_deflection`; pi for a
        parabola, NaN for a bound orbit.
        """
        if self._beta > 0:
            return math.nan
        if self._beta == 0:
            return math.pi
        chi = scattering.rutherford_deflection(self.impact_parameter, self.coulomb_strength, self.reduced_mass, self.v_inf)
        return abs(float(chi))

    @property
    def period(self) -> float:
        """Orbital period 2 pi sqrt(a^3 / mu_K) (elliptic); inf otherwise."""
        return 2.0 * math.pi * self._mu_k / self._beta**1.5 if self._beta > 0 else math.inf

    def __repr__(self) -> str:
        return (
            f"{type(self).__name__}(m1={self.m1!r}, m2={self.m2!r}, periastron={self._rp!r}, "
            f"eccentricity={self.eccentricity!r}, kind={self.kind!r})"
        )

    # -- propagation ------------------------------------------------------------

    def _perifocal(self, times: np.ndarray) -> np.ndarray:
        out = np.empty((times.size, 4))
        _k.perifocal_states(
            np.ascontiguousarray(times.ravel()), self._mu_k, self._rp, self._beta, self._q, self._h, out
        )
        return out

    def relative_state_at_time(self, t):
        r"""Separation x2 - x1 and relative velocity v2 - v1 at time t from periastron.

        Solves Kepler's equation :math:`t = r_p s + q G_3(s)` for the
        universal anomaly (safeguarded Newton from a rigorous upper bound, an
        asinh bound for large hyperbolic times) and evaluates
        :math:`\mathbf r = (r_p - \mu_K G_2)\hat P + h G_1 \hat Q`,
        :math:`\mathbf v = (-\mu_K G_1\hat P + h G_0\hat Q)/r`.

        Parameters
        ----------
        t : float or array_like
            Times from periastron (negative: before).

        Returns
        -------
        separation, relative_velocity : ndarray, shape t.shape + (3,)

        Examples
        --------
        >>> from collisionkit.encounters import Hyperbolic
        >>> r, v = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0).relative_state_at_time(0.0)
        >>> r, v  # v_p = sqrt(1 + 2 * 2 / 1)
        (array([1., 0., 0.]), array([0.        , 2.23606798, 0.        ]))
        """
        times = _arrays.as_float_array(t, "t")
        _arrays.require_finite(times, "t")
        perifocal = self._perifocal(times)
        plane = self._basis[:2]
        separation = perifocal[:, :2] @ plane
        velocity = perifocal[:, 2:] @ plane
        shape = times.shape + (3,)
        return separation.reshape(shape), velocity.reshape(shape)

    def state_at_time(self, t):
        """Positions and velocities of both bodies in the centre-of-mass frame at time t.

        Body 1 is at :math:`-(m_2/M)\\mathbf r`, body 2 at :math:`(m_1/M)\\mathbf r`
        (same for the velocities), so the centre of mass rests at the origin.

        Parameters
        ----------
        t : float or array_like
            Times from periastron passage (negative: before it).

        Returns
        -------
        positions, velocities : ndarray, shape t.shape + (2, 3)
            Index 0 is body 1, index 1 body 2.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import Hyperbolic
        >>> orbit = Hyperbolic(1.0, 3.0, periastron=2.0, v_inf=0.5)
        >>> x, v = orbit.state_at_time(0.0)
        >>> x
        array([[-1.5,  0. ,  0. ],
               [ 0.5,  0. ,  0. ]])
        >>> x, v = orbit.state_at_time(np.linspace(-10.0, 10.0, 5))
        >>> x.shape, float(np.abs(1.0 * v[:, 0] + 3.0 * v[:, 1]).max()) < 1e-15
        ((5, 2, 3), True)
        """
        separation, velocity = self.relative_state_at_time(t)
        share1 = self.m2 / self.total_mass
        share2 = self.m1 / self.total_mass
        # 0 - x rather than -x: no negative zeros in the output
        positions = np.stack([0.0 - share1 * separation, share2 * separation], axis=-2)
        velocities = np.stack([0.0 - share1 * velocity, share2 * velocity], axis=-2)
        return positions, velocities

    def time_at_separation(self, r, branch: str = "inbound"):
        r"""Time from periastron at which the separation equals r.

        Inverts :math:`r = r_p + q G_2(s)` in closed form (an asinh for
        hyperbolae, an asin for ellipses) and returns
        :math:`t = \pm(r_p s + q G_3(s))`: negative on the way in
        (``branch="inbound"``, the default), positive on the way out
        (``branch="outbound"``); the orbit is symmetric about periastron, so
        the two differ only in sign. For an ellipse the time is that within the
        current orbit, in [-P/2, P/2].

        Parameters
        ----------
        r : float or array_like
            Separations, r_p <= r (<= apoastron for a bound orbit).
        branch : {"inbound", "outbound"}

        Examples
        --------
        >>> from collisionkit.encounters import Hyperbolic
        >>> orbit = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0)
        >>> t_in = orbit.time_at_separation(10.0)
        >>> t_out = orbit.time_at_separation(10.0, branch="outbound")
        >>> t_in < 0 < t_out == -t_in
        True
        """
        if branch not in ("inbound", "outbound"):
            raise ValueError(f"branch must be 'inbound' or 'outbound'; got {branch!r}")
        separations = _arrays.as_float_array(r, "r")
        _arrays.require_finite(separations, "r")
        _arrays.require_in_range(separations, "r", self._rp, self.apoastron)
        flat = np.ascontiguousarray(separations.ravel())
        out = np.empty(flat.size)
        _k.times_at_separations(flat, self._rp, self._beta, self._q, out)
        sign = -1.0 if branch == "inbound" else 1.0
        result = (sign * out).reshape(separations.shape)
        return float(result) if result.ndim == 0 else result

    def time_since_periastron(self, separation, relative_velocity) -> float:
        r"""Time from periastron of a relative state lying on this orbit.

        Uses :math:`G_1(s) = \mathbf r\cdot\mathbf v / q` (and, for ellipses,
        :math:`G_0 = 1 - \beta (r - r_p)/q` to pick the half-orbit), which is
        accurate right at periastron where inverting r(t) is not. A state
        whose energy or angular momentum differs from the orbit's by more
        than ``ON_ORBIT_TOLERANCE`` (relative) is refused: it has no time on
        this orbit.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import Hyperbolic
        >>> orbit = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0)
        >>> r, v = orbit.relative_state_at_time(-3.0)
        >>> round(orbit.time_since_periastron(r, v), 12)
        -3.0
        """
        r_vec = _state_vector(separation, "separation")
        v_vec = _state_vector(relative_velocity, "relative_velocity")
        r = float(np.linalg.norm(r_vec))
        self._require_on_orbit(r_vec, v_vec, r)
        s = _k.anomaly_of_state(max(r, self._rp), float(r_vec @ v_vec), self._rp, self._beta, self._q)
        return math.copysign(_k.time_of_anomaly(abs(s), self._rp, self._beta, self._q), s)

    def _require_on_orbit(self, r_vec, v_vec, r) -> None:
        """ValueError unless the state has this orbit's energy and angular momentum (to ON_ORBIT_TOLERANCE)."""
        if r == 0.0:
            raise ValueError("separation must be a non-zero vector")
        v2 = float(v_vec @ v_vec)
        energy_off = abs(0.5 * v2 - self._mu_k / r + 0.5 * self._beta) / (0.5 * v2 + abs(self._mu_k) / r)
        h = float(np.linalg.norm(np.cross(r_vec, v_vec)))
        momentum_off = abs(h - self._h) / max(r * math.sqrt(v2), self._h, 1e-300)
        if energy_off > ON_ORBIT_TOLERANCE or momentum_off > ON_ORBIT_TOLERANCE or r < self._rp * (1 - ON_ORBIT_TOLERANCE):
            raise ValueError(
                f"the state is not on this orbit: energy off by {energy_off:.2g}, angular momentum by "
                f"{momentum_off:.2g} (relative), separation {r:.6g} against periastron {self._rp:.6g}"
            )

    # -- asymptotes and cross sections -------------------------------------------

    def _require_unbound(self, what: str) -> None:
        if self._beta >= 0:
            raise ValueError(f"{what} needs a hyperbolic orbit (v_inf > 0); this one is {self.kind}")

    def asymptotes(self):
        r"""Directions of the incoming and outgoing relative velocity, and the centre of the hyperbola.

        With :math:`w = v_\infty` the velocity far away is
        :math:`(\mu_K \hat P \pm h w \hat Q)/q` (in: +; out: the mirror
        :math:`(-\mu_K, h w)/q`); both asymptotes pass through the centre
        :math:`(r_p + \mu_K/v_\infty^2)\hat P` (for gravity: :math:`a e` from
        the focus, towards periastron). The angle between the two directions is
        :attr:`deflection_angle`.

        Returns
        -------
        incoming, outgoing : ndarray, shape (3,)
            Unit vectors of the relative velocity before and after.
        centre : ndarray, shape (3,)
            Where the two asymptotes of the separation cross.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import Hyperbolic
        >>> orbit = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0)
        >>> v_in, v_out, centre = orbit.asymptotes()
        >>> bool(np.isclose(np.arccos(v_in @ v_out), orbit.deflection_angle))
        True
        """
        self._require_unbound("asymptotes")
        w = self.v_inf
        p_hat, q_hat = self._basis[0], self._basis[1]
        incoming = (self._mu_k * p_hat + self._h * w * q_hat) / self._q
        outgoing = (-self._mu_k * p_hat + self._h * w * q_hat) / self._q
        centre = (self._rp + self._mu_k / w**2) * p_hat
        return incoming, outgoing, centre

    def differential_cross_section(self, chi):
        r"""Rutherford cross section :math:`(k_{tot}/(2\mu v_\infty^2))^2/\sin^4(\chi/2)` at this energy.

        From :func:`collisionkit.scattering.rutherford_differential_cross_section`
        with :math:`k_{tot} = -\mu\mu_K` (gravity: :math:`-G m_1 m_2`).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import Hyperbolic
        >>> orbit = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0)
        >>> float(orbit.differential_cross_section(np.pi))  # (G M / (2 v^2))^2
        1.0
        """
        self._require_unbound("the cross section")
        return scattering.rutherford_differential_cross_section(
            chi, self.coulomb_strength, self.reduced_mass, self.v_inf
        )

    def focusing_cross_section(self, radius1, radius2) -> float:
        """Cross section for contact at this v_inf; see :func:`focusing_cross_section`.

        Examples
        --------
        >>> from collisionkit.encounters import Hyperbolic
        >>> Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=2.0).focusing_cross_section(0.5, 0.5) / 3.141592653589793
        2.0
        """
        self._require_unbound("the focusing cross section")
        return float(
            focusing_cross_section(self.m1, self.m2, radius1, radius2, self.v_inf, G=self.G, k=self.k)
        )

    # -- contact ----------------------------------------------------------------

    def contact(self, radius1, radius2) -> EncounterContact:
        r"""Whether and when bodies of radii R1, R2 touch, and their state then.

        They touch if :math:`r_p < R_1 + R_2` (a graze, :math:`r_p = R_1 + R_2`,
        is not a contact); the first contact is on the way in, at
        ``time_at_separation(R1 + R2)`` (< 0), where the relative speed is
        :math:`\sqrt{v_\infty^2 + 2\mu_K/(R_1 + R_2)}` (energy conservation).

        Examples
        --------
        >>> from collisionkit.encounters import Hyperbolic
        >>> orbit = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0)
        >>> c = orbit.contact(1.0, 1.0)
        >>> c.touches, c.time < 0, round(c.relative_speed, 12)  # sqrt(1 + 2 * 2 / 2)
        (True, True, 1.732050807569)
        >>> orbit.contact(0.4, 0.5).touches
        False
        """
        r1 = _scalar(radius1, "radius1", inclusive=True)
        r2 = _scalar(radius2, "radius2", inclusive=True)
        distance = r1 + r2
        if not self._rp < distance:
            return EncounterContact.miss(distance)
        if distance > self.apoastron:
            raise ValueError(
                f"radius1 + radius2 = {distance} exceeds the apoastron {self.apoastron}: "
                "the bodies overlap along the whole orbit"
            )
        time = self.time_at_separation(distance, branch="inbound")
        positions, velocities = self.state_at_time(time)
        return EncounterContact(True, time, distance, positions, velocities)

    def impact(self, radius1, radius2, restitution=1.0, restitution_model="normal", merge=False):
        """Resolve the first contact with the collision core; None if the bodies miss.

        The state at contact (:meth:`contact`) goes to
        :func:`collisionkit.resolve_contact` along the line of centres
        (restitution 0: a common normal velocity). ``merge=True`` instead joins
        the bodies into one (:func:`merge_bodies`): total mass and momentum, the
        orbital angular momentum as spin, and all the relative kinetic energy
        :math:`\\mu v^2/2` lost.

        Returns
        -------
        Impact or None

        Examples
        --------
        >>> from collisionkit.encounters import Hyperbolic
        >>> orbit = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0)
        >>> hit = orbit.impact(1.0, 1.0, merge=True)
        >>> hit.merged.mass, round(hit.energy_lost, 12)  # mu v^2 / 2 = 0.5 * 0.5 * 3
        (2.0, 0.75)
        """
        contact = self.contact(radius1, radius2)
        if not contact.touches:
            return None
        x, v = contact.positions, contact.velocities
        energy_before = 0.5 * (self.m1 * v[0] @ v[0] + self.m2 * v[1] @ v[1])
        if merge:
            merged = merge_bodies(self.m1, x[0], v[0], self.m2, x[1], v[1])
            energy_after = 0.5 * merged.mass * merged.velocity @ merged.velocity
            return Impact(contact, None, merged, float(energy_before - energy_after))
        v1, v2 = resolve_contact(self.m1, v[0], self.m2, v[1], contact.normal, restitution, restitution_model)
        energy_after = 0.5 * (self.m1 * v1 @ v1 + self.m2 * v2 @ v2)
        return Impact(contact, np.stack([v1, v2]), None, float(energy_before - energy_after))

    def derived_quantities(self) -> dict[str, float | str]:
        """The orbit's numbers by name (for tables and JSON summaries).

        Examples
        --------
        >>> from collisionkit.encounters import Hyperbolic
        >>> q = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0).derived_quantities()
        >>> q["kind"], q["eccentricity"], q["impact_parameter"]
        ('hyperbolic', 1.5, 2.23606797749979)
        """
        return {
            "kind": self.kind,
            "total_mass": self.total_mass,
            "reduced_mass": self.reduced_mass,
            "kepler_parameter": self.kepler_parameter,
            "periastron": self.periastron,
            "periastron_speed": self.periastron_speed,
            "v_inf": self.v_inf,
            "energy": self.energy,
            "angular_momentum": self.angular_momentum,
            "impact_parameter": self.impact_parameter,
            "eccentricity": self.eccentricity,
            "semi_major_axis": self.semi_major_axis,
            "deflection_angle": self.deflection_angle,
            "period": self.period,
        }

    def _repr_html_(self) -> str:
        from ._repr import html_table, orbit_rows

        return html_table(type(self).__name__, orbit_rows(self))


class Hyperbolic(TwoBodyOrbit):
    r"""Unbound encounter set by the periastron distance r_p and the speed at infinity.

    As in the StarCrash set-up (eqs. 34-38): :math:`E_T = \mu v_\infty^2/2`,
    :math:`v_p = \sqrt{v_\infty^2 + 2\mu_K/r_p}`, :math:`J_T = \mu v_p r_p`,
    :math:`b = \sqrt{r_p^2 + 2\mu_K r_p/v_\infty^2}`, and
    :math:`e = 1 + r_p v_\infty^2/\mu_K`. Periastron lies on +x, the motion is
    anticlockwise in the xy plane. All of :class:`TwoBodyOrbit` applies
    (propagation, contact, cross sections).

    Parameters
    ----------
    m1, m2 : float
        Masses, > 0.
    periastron : float
        r_p > 0; for a repulsive force at least the head-on distance
        :math:`2|\mu_K|/v_\infty^2`.
    v_inf : float
        Relative speed at infinity, > 0.
    G, k : float, optional
        As in :class:`TwoBodyOrbit` (default: gravity with G = 1).

    Examples
    --------
    >>> import math
    >>> from collisionkit.encounters import Hyperbolic
    >>> orbit = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0, G=1.0)
    >>> orbit.eccentricity, round(math.degrees(orbit.deflection_angle), 6)  # 2 asin(1/e)
    (1.5, 83.62063)

    Rutherford scattering of two protons (SI; k from ``scattering.coulomb_strength``):

    >>> from collisionkit import scattering
    >>> m_p, e = 1.67262192e-27, 1.602176634e-19
    >>> k = float(scattering.coulomb_strength(e, e))
    >>> proton = Hyperbolic(m_p, m_p, periastron=1e-12, v_inf=1e6, k=k)
    >>> proton.attractive, proton.eccentricity > 1
    (False, True)
    """

    def __init__(self, m1, m2, periastron, v_inf, *, G=None, k=None):
        m1, m2, G, k, mu_k = _interaction(m1, m2, G, k)
        rp = _scalar(periastron, "periastron")
        v = _speed(v_inf, "v_inf")
        head_on = -2.0 * mu_k / v**2
        if rp < head_on:
            raise ValueError(
                f"periastron must be >= 2 k_tot / (mu v_inf^2) = {head_on} (the head-on distance of "
                f"closest approach of a repulsive force); got {rp}"
            )
        self._setup(m1, m2, G, k, mu_k, rp, -v * v, np.eye(3))


# --------------------------------------------------------------------------- contact


@dataclass(frozen=True, repr=False)
class EncounterContact:
    """First contact of two bodies on an orbit (:meth:`TwoBodyOrbit.contact`).

    Attributes
    ----------
    touches : bool
        r_p < R1 + R2.
    time : float
        Time of first contact from periastron (< 0); inf if they miss.
    contact_distance : float
        R1 + R2.
    positions, velocities : ndarray, shape (2, 3)
        Centre-of-mass-frame state at contact (NaN if they miss).

    Examples
    --------
    >>> from collisionkit.encounters import Hyperbolic
    >>> contact = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0).contact(1.0, 1.0)
    >>> round(contact.normal_speed**2 + contact.tangential_speed**2, 12)  # v_inf^2 + 2 G M / 2
    3.0
    """

    touches: bool
    time: float
    contact_distance: float
    positions: np.ndarray
    velocities: np.ndarray

    @classmethod
    def miss(cls, distance: float) -> EncounterContact:
        """The outcome of an encounter whose bodies never come closer than ``distance``.

        Examples
        --------
        >>> from collisionkit.encounters import EncounterContact
        >>> contact = EncounterContact.miss(3.0)
        >>> contact.touches, contact.time
        (False, inf)
        """
        nan = np.full((2, 3), np.nan)
        return cls(False, math.inf, distance, nan, nan.copy())

    @property
    def normal(self) -> np.ndarray:
        """Unit line of centres from body 1 to body 2."""
        return _unit(self.positions[1] - self.positions[0])

    @property
    def relative_velocity(self) -> np.ndarray:
        """v2 - v1 at contact."""
        return self.velocities[1] - self.velocities[0]

    @property
    def relative_speed(self) -> float:
        """|v2 - v1| at contact."""
        return float(np.linalg.norm(self.relative_velocity))

    @property
    def normal_speed(self) -> float:
        """Approach speed along the line of centres, (v1 - v2) . n >= 0."""
        return float(-self.relative_velocity @ self.normal)

    @property
    def tangential_speed(self) -> float:
        """Relative speed across the line of centres, h / (R1 + R2)."""
        u = self.relative_velocity
        return float(np.linalg.norm(u - (u @ self.normal) * self.normal))

    def __repr__(self) -> str:
        return f"EncounterContact(touches={self.touches}, time={self.time!r}, contact_distance={self.contact_distance!r})"


@dataclass(frozen=True)
class MergedBody:
    """One body made of two: total mass and momentum, at the centre of mass.

    Attributes
    ----------
    mass : float
    position, velocity : ndarray, shape (3,)
    spin : ndarray, shape (3,)
        Angular momentum of the two bodies about their centre of mass.

    Examples
    --------
    >>> from collisionkit.encounters import merge_bodies
    >>> merge_bodies(1.0, [0, 0, 0], [0, 1.0, 0], 1.0, [2.0, 0, 0], [0, -1.0, 0]).spin  # mu r x v
    array([ 0.,  0., -2.])
    """

    mass: float
    position: np.ndarray
    velocity: np.ndarray
    spin: np.ndarray


def merge_bodies(m1, x1, v1, m2, x2, v2) -> MergedBody:
    r"""Merge two bodies: :math:`M = m_1 + m_2`, :math:`X = (m_1 x_1 + m_2 x_2)/M`, :math:`V = (m_1 v_1 + m_2 v_2)/M`.

    The spin is :math:`\mu\,(x_2 - x_1)\times(v_2 - v_1)`, the angular momentum
    about the centre of mass, which the merger keeps.

    Examples
    --------
    >>> from collisionkit.encounters import merge_bodies
    >>> body = merge_bodies(1.0, [0, 0, 0], [2.0, 0, 0], 3.0, [4.0, 0, 0], [-2.0, 0, 0])
    >>> body.mass, body.position, body.velocity
    (4.0, array([3., 0., 0.]), array([-1.,  0.,  0.]))
    """
    m1 = _scalar(m1, "m1")
    m2 = _scalar(m2, "m2")
    x1, v1 = _state_vector(x1, "x1"), _state_vector(v1, "v1")
    x2, v2 = _state_vector(x2, "x2"), _state_vector(v2, "v2")
    mass = m1 + m2
    share = m2 / mass
    position = x1 + share * (x2 - x1)
    velocity = v1 + share * (v2 - v1)
    spin = (m1 * share) * np.cross(x2 - x1, v2 - v1)
    return MergedBody(mass, position, velocity, spin)


@dataclass(frozen=True)
class Impact:
    """Outcome of :meth:`TwoBodyOrbit.impact`.

    Attributes
    ----------
    contact : EncounterContact
        Where and when the bodies touched.
    velocities_after : ndarray, shape (2, 3), or None
        Velocities after :func:`collisionkit.resolve_contact` (None if merged).
    merged : MergedBody or None
        The merger product (``merge=True``).
    energy_lost : float
        Kinetic energy dissipated.

    Examples
    --------
    >>> from collisionkit.encounters import Hyperbolic
    >>> impact = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0).impact(1.0, 1.0, restitution=1.0)
    >>> abs(impact.energy_lost) < 1e-14, impact.velocities_after.shape
    (True, (2, 3))
    """

    contact: EncounterContact
    velocities_after: np.ndarray | None
    merged: MergedBody | None
    energy_lost: float


def focusing_cross_section(m1, m2, radius1, radius2, v_inf, *, G=None, k=None):
    r"""Cross section for contact with gravitational focusing.

    .. math:: \sigma = \pi R^2\left(1 + \frac{2\mu_K}{R v_\infty^2}\right),\qquad R = R_1 + R_2,

    i.e. :math:`\pi b_{max}^2` with :math:`b_{max}` from eq. 38 at
    :math:`r_p = R`. With gravity :math:`\mu_K = G(m_1+m_2)`; for a repulsive
    Coulomb force the bracket shrinks, and the cross section is 0 once it
    would be negative (the bodies cannot reach contact).

    Parameters
    ----------
    m1, m2 : float
        Masses, > 0.
    radius1, radius2 : array_like
        Radii >= 0, R1 + R2 > 0.
    v_inf : array_like
        Relative speed at infinity, > 0.
    G, k : float, optional
        As in :class:`TwoBodyOrbit`.

    Examples
    --------
    >>> from collisionkit.encounters import focusing_cross_section
    >>> float(focusing_cross_section(1.0, 1.0, 0.5, 0.5, 2.0)) / 3.141592653589793  # 1 + 4/4
    2.0
    """
    m1, m2, _, _, mu_k = _interaction(m1, m2, G, k)
    r1 = _arrays.as_float_array(radius1, "radius1")
    r2 = _arrays.as_float_array(radius2, "radius2")
    v = _arrays.as_float_array(v_inf, "v_inf")
    for array, name in ((r1, "radius1"), (r2, "radius2"), (v, "v_inf")):
        _arrays.require_finite(array, name)
    _arrays.require_in_range(r1, "radius1", 0.0, np.inf)
    _arrays.require_in_range(r2, "radius2", 0.0, np.inf)
    _arrays.require_in_range(r1 + r2, "radius1 + radius2", 0.0, np.inf, inclusive=(False, True))
    _arrays.require_in_range(v, "v_inf", 0.0, np.inf, inclusive=(False, True))
    distance = r1 + r2
    return np.pi * np.maximum(distance**2 + 2.0 * mu_k * distance / v**2, 0.0)


# --------------------------------------------------------------------------- StarCrash set-up

_LAYOUTS = {
    # (direction from body 1 to body 2, direction of the transverse velocity)
    "diagonal": (np.ones(3) / math.sqrt(3.0), np.array([-1.0, -1.0, 2.0]) / math.sqrt(6.0)),
    "x": (np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])),
}


@dataclass(frozen=True, repr=False)
class InitialConditions:
    """Two stars at separation r0 on their way to periastron (StarCrash eqs. 34-39).

    Attributes
    ----------
    m1, m2, rp, v_inf, sep0, G : float
        The inputs.
    layout : str
        'diagonal' (opposite corners of the grid) or 'x'.
    positions, velocities : ndarray, shape (2, 3)
        Centre-of-mass frame, body 1 first.
    energy, v0, vp, angular_momentum, impact_parameter, vt, vr : float
        Eqs. 34-39.
    time_to_periastron : float
        Time from the start to periastron passage, >= 0.
    orbit : Hyperbolic
        The orbit, oriented like ``positions``:
        ``orbit.state_at_time(-time_to_periastron)`` is the start.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.encounters import starcrash_initial_conditions
    >>> ic = starcrash_initial_conditions(1.0, 2.0, rp=1.0, vinf=0.5, sep0=10.0)
    >>> x, v = ic.orbit.state_at_time(-ic.time_to_periastron)
    >>> bool(np.allclose(x, ic.positions) and np.allclose(v, ic.velocities))
    True
    """

    m1: float
    m2: float
    rp: float
    v_inf: float
    sep0: float
    G: float
    layout: str
    positions: np.ndarray
    velocities: np.ndarray
    energy: float
    v0: float
    vp: float
    angular_momentum: float
    impact_parameter: float
    vt: float
    vr: float
    time_to_periastron: float
    orbit: Hyperbolic = field(compare=False)

    @property
    def total_mass(self) -> float:
        """M_T = m1 + m2."""
        return self.m1 + self.m2

    @property
    def reduced_mass(self) -> float:
        """mu = m1 m2 / M_T."""
        return self.m1 * self.m2 / (self.m1 + self.m2)

    @property
    def speed_ratio(self) -> float:
        """v_t / v0: above sqrt(1/3) a star in a grid corner can leave the grid."""
        return self.vt / self.v0

    def to_dict(self) -> dict:
        """The inputs, eqs. 34-39, orbit elements and the arrays (JSON-ready).

        Examples
        --------
        >>> import json
        >>> from collisionkit.encounters import starcrash_initial_conditions
        >>> data = starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, 10.0).to_dict()
        >>> round(data["impact_parameter"], 6), len(json.dumps(data)) > 100  # sqrt(17)
        (4.123106, True)
        """
        orbit = self.orbit
        return {
            "m1": self.m1,
            "m2": self.m2,
            "rp": self.rp,
            "vinf": self.v_inf,
            "sep0": self.sep0,
            "G": self.G,
            "layout": self.layout,
            "total_mass": self.total_mass,
            "reduced_mass": self.reduced_mass,
            "energy": self.energy,
            "v0": self.v0,
            "vp": self.vp,
            "angular_momentum": self.angular_momentum,
            "impact_parameter": self.impact_parameter,
            "vt": self.vt,
            "vr": self.vr,
            "vt_over_v0": self.speed_ratio,
            "eccentricity": orbit.eccentricity,
            "semi_major_axis": orbit.semi_major_axis,
            "deflection_angle": orbit.deflection_angle,
            "time_to_periastron": self.time_to_periastron,
            "positions": self.positions.tolist(),
            "velocities": self.velocities.tolist(),
        }

    def write(self, folder, stem: str = "initial_conditions", units: UnitSystem | str | None = None):
        """Write ``<stem>.json`` and ``<stem>.txt`` (atomically) to ``folder``.

        The text file has ``#`` comment lines, then one row per body:
        ``body mass x y z vx vy vz`` (readable with ``numpy.loadtxt``).

        Parameters
        ----------
        folder : str or Path
        stem : str
            File name without the extension.
        units : UnitSystem or str, optional
            The units the numbers are in, recorded in the JSON file: a
            :class:`UnitSystem` or its name (see :data:`UNIT_SYSTEMS`).

        Returns
        -------
        json_path, text_path : Path

        Examples
        --------
        >>> import numpy as np, tempfile
        >>> from collisionkit.encounters import starcrash_initial_conditions
        >>> ic = starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, 10.0)
        >>> with tempfile.TemporaryDirectory() as folder:
        ...     _, text = ic.write(folder)
        ...     table = np.loadtxt(text)
        >>> bool(np.array_equal(table[:, 2:5], ic.positions))
        True
        """
        folder = Path(folder)
        data = self.to_dict()
        if isinstance(units, str):
            units = unit_system(units)
        elif units is not None and not isinstance(units, UnitSystem):
            raise TypeError(f"units must be a UnitSystem or one of its names; got {units!r}")
        if units is not None:
            data["units"] = {
                "name": units.name,
                "mass": units.mass,
                "length": units.length,
                "time": units.time,
                "velocity": units.velocity,
            }
        json_path = atomic_write_json(folder / f"{stem}.json", data)
        label = "" if units is None else f" ({units.name}: {units.mass}, {units.length}, {units.time}, {units.velocity})"
        lines = [
            f"# collisionkit two-body encounter initial conditions, layout {self.layout}",
            f"# G = {self.G!r}{label}",
            f"# m1 = {self.m1!r}  m2 = {self.m2!r}  rp = {self.rp!r}  vinf = {self.v_inf!r}  sep0 = {self.sep0!r}",
            f"# time to periastron = {self.time_to_periastron!r}",
            "# columns: body mass x y z vx vy vz (centre-of-mass frame)",
        ]
        for body, (mass, x, v) in enumerate(zip((self.m1, self.m2), self.positions, self.velocities), start=1):
            numbers = " ".join(repr(float(value)) for value in (mass, *x, *v))
            lines.append(f"{body} {numbers}")
        text_path = atomic_write_text(folder / f"{stem}.txt", "\n".join(lines) + "\n")
        return json_path, text_path

    def __repr__(self) -> str:
        return (
            f"InitialConditions(m1={self.m1!r}, m2={self.m2!r}, rp={self.rp!r}, v_inf={self.v_inf!r}, "
            f"sep0={self.sep0!r}, layout={self.layout!r})"
        )

    def _repr_html_(self) -> str:
        from ._repr import html_table, initial_conditions_rows

        return html_table("InitialConditions", initial_conditions_rows(self))


def starcrash_initial_conditions(m1, m2, rp, vinf, sep0, G=1.0, *, layout: str = "diagonal") -> InitialConditions:
    r"""Two stars on a hyperbolic orbit started at separation r0, set up as in StarCrash.

    StarCrash user manual (J. Faber 2003), "Hyperbolic Collisions", eqs. 34-39:
    :math:`E_T = \mu v_\infty^2/2`, :math:`v_0 = \sqrt{v_\infty^2 + 2GM_T/r_0}`,
    :math:`v_p = \sqrt{v_\infty^2 + 2GM_T/r_p}`, :math:`J_T = \mu v_p r_p`,
    :math:`b = J_T/(\mu v_\infty)`, :math:`v_t = v_\infty b/r_0` and
    :math:`v_r = \sqrt{v_0^2 - v_t^2}`, evaluated as
    :math:`\sqrt{(r_0 - r_p)(v_\infty^2 (r_0 + r_p) + 2GM_T)}/r_0` (the same
    number without the cancellation near periastron).

    ``layout="diagonal"`` puts the stars in opposite corners of the grid:
    body 2 towards (1, 1, 1)/sqrt3 and body 1 opposite, with the transverse
    velocity along (-1, -1, 2)/sqrt6, perpendicular to the separation with
    v_x = v_y. Body 2 then moves outwards through its corner (v_z > 0) exactly
    when :math:`v_t/v_0 > \sqrt{1/3}`, which gives a :class:`GridExitWarning`.
    ``layout="x"`` is the plain set-up: separation along x, transverse
    velocity along y (no warning).

    Parameters
    ----------
    m1, m2 : float
        Stellar masses, > 0.
    rp : float
        Periastron distance, > 0.
    vinf : float
        Relative speed at infinity, > 0 (the parameter VPEAK).
    sep0 : float
        Initial separation r0 >= rp (SEP0).
    G : float
        Gravitational constant, > 0 (see :data:`UNIT_SYSTEMS`).
    layout : {"diagonal", "x"}

    Returns
    -------
    InitialConditions

    Examples
    --------
    >>> from collisionkit.encounters import starcrash_initial_conditions
    >>> ic = starcrash_initial_conditions(1.0, 1.0, rp=1.0, vinf=0.5, sep0=10.0)
    >>> round(ic.impact_parameter, 12), round(ic.v0, 12)  # sqrt(1 + 4 / 0.25), sqrt(0.25 + 0.4)
    (4.123105625618, 0.80622577483)
    >>> ic.positions.sum(axis=0), float(ic.velocities[1, 0] - ic.velocities[1, 1])
    (array([0., 0., 0.]), 0.0)
    """
    if layout not in _LAYOUTS:
        raise ValueError(f"layout must be 'diagonal' or 'x'; got {layout!r}")
    G = _scalar(G, "G")
    orbit = Hyperbolic(m1, m2, periastron=rp, v_inf=vinf, G=G)
    m1, m2, rp, v_inf = orbit.m1, orbit.m2, orbit.periastron, orbit.v_inf
    r0 = _scalar(sep0, "sep0")
    if r0 < rp:
        raise ValueError(f"sep0 must be >= rp = {rp} (the stars start outside periastron); got {r0}")
    mu_g = orbit.kepler_parameter
    v0 = math.sqrt(v_inf**2 + 2.0 * mu_g / r0)
    b = orbit.impact_parameter
    vt = v_inf * b / r0
    vr = math.sqrt((r0 - rp) * (v_inf**2 * (r0 + rp) + 2.0 * mu_g)) / r0
    radial, transverse = _LAYOUTS[layout]
    separation = r0 * radial
    relative_velocity = -vr * radial + vt * transverse
    s = _k.anomaly_at_separation(r0, rp, orbit._beta, orbit._q)
    x_p, x_q = _k.perifocal_position(-s, mu_g, rp, orbit._beta, orbit._q, orbit._h)
    basis = _basis_from_direction(radial, transverse, x_p, x_q)
    oriented = TwoBodyOrbit._from_elements(m1, m2, G, 0.0, mu_g, rp, orbit._beta, basis)
    share1, share2 = m2 / (m1 + m2), m1 / (m1 + m2)
    positions = np.array([0.0 - share1 * separation, share2 * separation])
    velocities = np.array([0.0 - share1 * relative_velocity, share2 * relative_velocity])
    if layout == "diagonal" and vt / v0 > GRID_SPEED_RATIO_LIMIT:
        warnings.warn(
            f"v_t / v0 = {vt / v0:.4g} > sqrt(1/3): the stars' initial velocity can carry them off the "
            "cubic gravity grid; consider a larger sep0",
            GridExitWarning,
            stacklevel=2,
        )
    return InitialConditions(
        m1=m1,
        m2=m2,
        rp=rp,
        v_inf=v_inf,
        sep0=r0,
        G=G,
        layout=layout,
        positions=positions,
        velocities=velocities,
        energy=orbit.energy,
        v0=v0,
        vp=orbit.periastron_speed,
        angular_momentum=orbit.angular_momentum,
        impact_parameter=b,
        vt=vt,
        vr=vr,
        time_to_periastron=-oriented.time_at_separation(r0, branch="inbound"),
        orbit=oriented,
    )
