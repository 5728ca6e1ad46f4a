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

Units: any consistent system.
:data:`~collisionkit.encounters.units.UNIT_SYSTEMS` gives G in N-body units
(G = 1), SI, cgs, solar units (Msun, AU, yr) and stellar units (Msun, Rsun,
km/s).

The package, by responsibility:

* :mod:`~collisionkit.encounters.units` - :class:`UnitSystem`, :func:`unit_system`,
  ``UNIT_SYSTEMS``, ``GM_SUN``, ``R_SUN``;
* :mod:`~collisionkit.encounters.relative_orbit` - the conic of the relative
  motion: shape, orientation, propagation and times
  (:class:`~collisionkit.encounters.relative_orbit.RelativeOrbit`);
* :mod:`~collisionkit.encounters.orbit` - two bodies on it: :class:`TwoBodyOrbit`
  (any conic) and :class:`Hyperbolic`;
* :mod:`~collisionkit.encounters.contact` - :class:`EncounterContact`,
  :class:`Impact`, :func:`merge_bodies` (:class:`MergedBody`) and
  :func:`focusing_cross_section`;
* :mod:`~collisionkit.encounters.initial_conditions` - the StarCrash set-up:
  :func:`starcrash_initial_conditions`, :class:`InitialConditions`,
  :class:`GridExitWarning`;
* :mod:`~collisionkit.encounters.star_model` - particle stars:
  :class:`StarModel` (SPH particles and their units) and
  :func:`neighbour_smoothing_lengths`;
* :mod:`~collisionkit.encounters.star_files` - :func:`read_star` and
  :func:`write_star` in the GADGET/SWIFT HDF5 snapshot layout (h5py, the
  ``stars`` extra) and as ``.npz``;
* :mod:`~collisionkit.encounters.polytrope` - :func:`lane_emden` and
  :func:`polytrope_star`, an unrelaxed polytrope as SPH particles
  (:class:`PolytropeParameters`, :func:`polytrope_summary`);
* :mod:`~collisionkit.encounters.profile_star` - stars from stellar-structure
  profiles: :class:`StellarProfile`, :func:`read_mesa_profile` (MESA) and
  :func:`profile_star`, an unrelaxed particle star of a real model
  (:class:`ProfileStarParameters`, :func:`profile_star_summary`);
* :mod:`~collisionkit.encounters.placement` - two particle stars placed on the
  StarCrash orbit: :func:`place_stars`, :class:`StarEncounterParameters`,
  :func:`star_encounter_summary`.
"""

from .contact import EncounterContact, Impact, MergedBody, focusing_cross_section, merge_bodies
from .initial_conditions import (
    GRID_SPEED_RATIO_LIMIT,
    GridExitWarning,
    InitialConditions,
    starcrash_initial_conditions,
)
from .orbit import Hyperbolic, TwoBodyOrbit
from .placement import StarEncounterParameters, TidalWarning, place_stars, star_encounter_summary
from .polytrope import LaneEmden, PolytropeParameters, lane_emden, polytrope_star, polytrope_summary
from .profile_star import (
    ProfileStarParameters, StellarProfile, profile_checks, profile_star, profile_star_summary, read_mesa_profile,
)
from .relative_orbit import ON_ORBIT_TOLERANCE
from .run import EncounterParameters, encounter_summary
from .star_files import StarFileError, read_star, write_star
from .star_model import StarModel, neighbour_smoothing_lengths
from .units import GM_SUN, R_SUN, UNIT_SYSTEMS, UnitSystem, conversion_factors, unit_system, unit_system_from_cgs

__all__ = [
    "EncounterParameters",
    "encounter_summary",
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
    "conversion_factors",
    "unit_system_from_cgs",
    "StarModel",
    "neighbour_smoothing_lengths",
    "StarFileError",
    "ProfileStarParameters",
    "StellarProfile",
    "profile_checks",
    "profile_star",
    "profile_star_summary",
    "read_mesa_profile",
    "read_star",
    "write_star",
    "LaneEmden",
    "lane_emden",
    "PolytropeParameters",
    "polytrope_star",
    "polytrope_summary",
    "StarEncounterParameters",
    "TidalWarning",
    "place_stars",
    "star_encounter_summary",
]
