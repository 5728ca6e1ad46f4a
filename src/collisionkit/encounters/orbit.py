r"""Two bodies on an inverse-square orbit: :class:`TwoBodyOrbit` (any conic) and :class:`Hyperbolic`.

The shape and timing of the relative orbit are those of
:class:`~collisionkit.encounters.relative_orbit.RelativeOrbit`; the contacts
of finite bodies those of :class:`~collisionkit.encounters.contact.ContactMixin`.
Here the two bodies and the force between them: masses, the constructors,
energies and angular momenta, the states of both bodies in the
centre-of-mass frame and Rutherford scattering.
"""

from __future__ import annotations

import math

import numpy as np

from .. import scattering
from ._elements import elements_from_state
from ._validation import interaction, nonzero_speed, scalar_above, state_vector
from .contact import ContactMixin
from .relative_orbit import RelativeOrbit

__all__ = ["Hyperbolic", "TwoBodyOrbit"]


class TwoBodyOrbit(ContactMixin, RelativeOrbit):
    r"""Relative orbit of two bodies under an inverse-square force: any conic.

    Built from the periastron distance and the eccentricity (any conic:
    check :attr:`~collisionkit.encounters.relative_orbit.RelativeOrbit.kind`);
    see :class:`Hyperbolic` for (r_p, v_inf), :meth:`from_impact_parameter` for
    (b, v_inf) and :meth:`from_state` for a position and velocity. The orbit
    lies in the xy plane with periastron on +x and the angular momentum along
    +z, unless built from a state. The shape and timing of the orbit
    (periastron, eccentricity, ``relative_state_at_time``, ...) are those of
    :class:`~collisionkit.encounters.relative_orbit.RelativeOrbit`, the
    contacts of finite bodies (``contact``, ``impact``) those of
    :class:`~collisionkit.encounters.contact.ContactMixin`.

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
        m1, m2, G, k, mu_k = interaction(m1, m2, G, k)
        rp = scalar_above(periastron, "periastron")
        lowest = 0.0 if mu_k > 0 else 1.0
        e = scalar_above(eccentricity, "eccentricity", lowest, inclusive=True)
        beta = (mu_k - abs(mu_k) * e) / rp
        self._setup(m1, m2, G, k, mu_k, rp, beta, np.eye(3))

    # -- construction ---------------------------------------------------------

    def _setup(self, m1, m2, G, k, mu_k, rp, beta, basis, h=None) -> None:
        """Store the bodies, the force and the conic (see ``RelativeOrbit._set_elements`` for ``h``)."""
        self.m1, self.m2, self.G, self.k = m1, m2, G, k
        self._set_elements(mu_k, rp, beta, basis, h)

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
        m1, m2, G, k, mu_k = interaction(m1, m2, G, k)
        v = nonzero_speed(v_inf, "v_inf")
        b = scalar_above(impact_parameter, "impact_parameter", 0.0, inclusive=mu_k < 0)
        mu = m1 / (m1 + m2) * m2  # not m1 m2 / M: the product underflows for masses of ~1e-160
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
        the state is unbound. Use
        :meth:`~collisionkit.encounters.relative_orbit.RelativeOrbit.time_since_periastron`
        for the time of the given state.

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
        m1, m2, G, k, mu_k = interaction(m1, m2, G, k)
        r_vec = state_vector(separation, "separation")
        v_vec = state_vector(relative_velocity, "relative_velocity")
        rp, beta, basis, h = elements_from_state(mu_k, r_vec, v_vec)
        return cls._from_elements(m1, m2, G, k, mu_k, rp, beta, basis, h=h)

    # -- the bodies and the force ------------------------------------------------

    @property
    def total_mass(self) -> float:
        """m1 + m2."""
        return self.m1 + self.m2

    @property
    def reduced_mass(self) -> float:
        """mu = m1 m2 / (m1 + m2), taken as (m1 / M) m2 (the product m1 m2 underflows for masses of ~1e-160)."""
        return self.m1 / (self.m1 + self.m2) * self.m2

    @property
    def coulomb_strength(self) -> float:
        """Total inverse-square strength k_tot = k - G m1 m2 = -mu mu_K, V(r) = k_tot / r."""
        return -self.reduced_mass * self._mu_k

    @property
    def energy(self) -> float:
        """Conserved energy of the relative motion, E_T = mu v_inf^2 / 2 when unbound (eq. 34)."""
        return self.reduced_mass * self.specific_energy

    @property
    def angular_momentum(self) -> float:
        """J_T = mu v_p r_p = mu sqrt(r_p^2 v_inf^2 + 2 mu_K r_p) (eq. 37)."""
        return self.reduced_mass * self._h

    @property
    def angular_momentum_vector(self) -> np.ndarray:
        """J_T times the unit normal of the orbital plane."""
        return self.angular_momentum * self._basis[2]

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

    def __repr__(self) -> str:
        return (
            f"{type(self).__name__}(m1={self.m1!r}, m2={self.m2!r}, periastron={self.periastron!r}, "
            f"eccentricity={self.eccentricity!r}, kind={self.kind!r})"
        )

    # -- states of both bodies -------------------------------------------------

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

    # -- scattering -------------------------------------------------------------

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

    # -- summaries --------------------------------------------------------------

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
        from .._repr import html_table, orbit_rows

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
        m1, m2, G, k, mu_k = interaction(m1, m2, G, k)
        rp = scalar_above(periastron, "periastron")
        v = nonzero_speed(v_inf, "v_inf")
        head_on = -2.0 * mu_k / v**2
        if rp < head_on:
            raise ValueError(
                f"periastron must be >= 2 k_tot / (mu v_inf^2) = {head_on} (the head-on distance of "
                f"closest approach of a repulsive force); got {rp}"
            )
        self._setup(m1, m2, G, k, mu_k, rp, -v * v, np.eye(3))
