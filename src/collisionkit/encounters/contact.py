"""Contact of two bodies on an encounter orbit, and what the collision core makes of it.

:class:`EncounterContact` (where and when spheres of radii R1, R2 first
touch), :class:`Impact` (the contact resolved by
:func:`collisionkit.resolve_contact`, or a merger into a :class:`MergedBody`
by :func:`merge_bodies`) and the gravitationally focused contact cross
section :func:`focusing_cross_section`. :class:`ContactMixin` gives
:class:`~collisionkit.encounters.orbit.TwoBodyOrbit` its ``contact``,
``impact`` and ``focusing_cross_section`` methods.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _arrays
from ..collisions import resolve_contact
from ._elements import unit_vector
from ._validation import interaction, scalar_above, state_vector

__all__ = ["ContactMixin", "EncounterContact", "Impact", "MergedBody", "focusing_cross_section", "merge_bodies"]


@dataclass(frozen=True, repr=False)
class EncounterContact:
    """First contact of two bodies on an orbit (:meth:`TwoBodyOrbit.contact <ContactMixin.contact>`).

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
        return unit_vector(self.positions[1] - self.positions[0])

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
    m1 = scalar_above(m1, "m1")
    m2 = scalar_above(m2, "m2")
    x1, v1 = state_vector(x1, "x1"), state_vector(v1, "v1")
    x2, v2 = state_vector(x2, "x2"), state_vector(v2, "v2")
    mass = m1 + m2
    share = m2 / mass
    position = x1 + share * (x2 - x1)
    velocity = v1 + share * (v2 - v1)
    spin = (m1 * share) * np.cross(x2 - x1, v2 - v1)
    return MergedBody(mass, position, velocity, spin)


@dataclass(frozen=True)
class Impact:
    """Outcome of :meth:`TwoBodyOrbit.impact <ContactMixin.impact>`.

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
        As in :class:`~collisionkit.encounters.orbit.TwoBodyOrbit`.

    Examples
    --------
    >>> from collisionkit.encounters import focusing_cross_section
    >>> float(focusing_cross_section(1.0, 1.0, 0.5, 0.5, 2.0)) / 3.141592653589793  # 1 + 4/4
    2.0
    """
    m1, m2, _, _, mu_k = interaction(m1, m2, G, k)
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


class ContactMixin:
    """Spheres of radii R1, R2 on an orbit: first contact, impact and the focusing cross section.

    Mixed into :class:`~collisionkit.encounters.orbit.TwoBodyOrbit`, which
    provides the bodies and the force (``m1``, ``m2``, ``G``, ``k``), the
    orbit (``periastron``, ``apoastron``, ``v_inf``, ``_require_unbound``)
    and its timing (``time_at_separation``, ``state_at_time``).

    Examples
    --------
    >>> from collisionkit.encounters import Hyperbolic
    >>> from collisionkit.encounters.contact import ContactMixin
    >>> orbit = Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0)
    >>> isinstance(orbit, ContactMixin), orbit.contact(0.6, 0.6).touches
    (True, True)
    """

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
        r1 = scalar_above(radius1, "radius1", inclusive=True)
        r2 = scalar_above(radius2, "radius2", inclusive=True)
        distance = r1 + r2
        if not self.periastron < distance:
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
