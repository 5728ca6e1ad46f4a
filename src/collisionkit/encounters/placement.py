r"""Two particle stars placed on the StarCrash hyperbolic orbit: an SPH code's initial conditions.

Each star's mass :math:`M_k = \sum_i m_i` and centre of mass
:math:`\mathbf X_k`, :math:`\mathbf V_k` come from its particles; the
two-body set-up of :func:`~collisionkit.encounters.starcrash_initial_conditions`
(StarCrash eqs. 34-39, with its layouts and grid-exit warning) gives the
centre-of-mass-frame positions :math:`\mathbf x_k` and velocities
:math:`\mathbf v_k` of two point masses :math:`M_1, M_2`; then every
particle of star k is moved rigidly,

.. math:: \mathbf x_i \to \mathbf x_i + (\mathbf x_k - \mathbf X_k),\qquad
          \mathbf v_i \to \mathbf v_i + (\mathbf v_k - \mathbf V_k),

so the distances within each star, its internal velocities and its
structure are kept, its centre of mass moves on the orbit, the total
momentum is zero and the centre of mass of the pair is at the origin.

Star 1's particles come first, then star 2's; star 1 keeps its IDs and star
2's follow them (``ID - min(ID_2) + max(ID_1) + 1``), and ``star_ids`` says
which star a particle came from (1 or 2). Star k's size is the radius
:math:`R_k` holding 99 % of its mass: the stars overlap at the start when
:math:`r_0 < R_1 + R_2`, and tidal deformation at the start is not
negligible when :math:`r_0 < 5(R_1 + R_2)` (:class:`TidalWarning`; the
StarCrash page: spherical stars are acceptable only from a sufficiently
large separation).
"""

from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Mapping
from typing import Any, ClassVar

import numpy as np

from .._params import Parameters, check_choice, check_real
from .initial_conditions import GridExitWarning, InitialConditions
from .run import LAYOUTS, EncounterParameters, encounter_summary
from .star_model import StarModel
from .units import UNIT_SYSTEMS, UnitSystem, unit_system

__all__ = ["MASS_FRACTION", "TIDAL_FACTOR", "StarEncounterParameters", "TidalWarning", "place_stars",
           "star_encounter_summary"]

#: The fraction of a star's mass inside the radius that stands for its size.
MASS_FRACTION = 0.99
#: Below sep0 = TIDAL_FACTOR (R1 + R2) the stars start too close for tides to be negligible.
TIDAL_FACTOR = 5.0


class TidalWarning(UserWarning):
    """Stars placed closer than 5 (R1 + R2): tidal deformation at the start is not negligible.

    Examples
    --------
    >>> import warnings
    >>> from collisionkit.encounters import StarEncounterParameters, TidalWarning, place_stars, polytrope_star
    >>> star = polytrope_star(1.5, 200, neighbours=10, seed=1)
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     _ = place_stars(star, star, StarEncounterParameters(rp=1.0, sep0=4.0, layout="x"))
    >>> [item.category is TidalWarning for item in caught]
    [True]
    """


@dataclasses.dataclass(frozen=True)
class StarEncounterParameters(Parameters):
    """The orbit of a particle-star encounter (StarCrash eqs. 34-39); the masses come from the stars.

    Parameters
    ----------
    rp : float
        Periastron distance of the centres of mass (> 0).
    v_inf : float
        Relative speed at infinity (> 0; ``--vinf``).
    sep0 : float
        Initial separation of the centres of mass (>= rp, checked when placed).
    units : str
        The units of rp, v_inf, sep0 and of the placed stars (each star is
        converted to them).
    layout : {"diagonal", "x"}

    Examples
    --------
    >>> from collisionkit.encounters import StarEncounterParameters
    >>> StarEncounterParameters.from_mapping({"vinf": 1.5, "units": "stellar"}).v_inf
    1.5
    """

    rp: float = 1.0
    v_inf: float = 0.5
    sep0: float = 10.0
    units: str = "nbody"
    layout: str = "diagonal"

    FLAGS: ClassVar = {"v_inf": "vinf"}

    def __post_init__(self):
        for name in ("rp", "v_inf", "sep0"):
            object.__setattr__(self, name, check_real(name, getattr(self, name), 0.0, low_open=True))
        check_choice("units", self.units, UNIT_SYSTEMS)
        check_choice("layout", self.layout, LAYOUTS)

    def unit_system(self) -> UnitSystem:
        """The unit system of the orbit and of the placed stars.

        Examples
        --------
        >>> StarEncounterParameters(units="solar").unit_system().length
        'AU'
        """
        return unit_system(self.units)

    def point_masses(self, star1: StarModel, star2: StarModel) -> EncounterParameters:
        """The two-body set-up of the stars' masses and 99 %-mass radii (both stars in these units).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.encounters import StarModel
        >>> star = StarModel([[1.0, 0, 0], [-1.0, 0, 0]], np.zeros((2, 3)), [0.5, 0.5], [1, 1], [0, 0], [1, 2])
        >>> point = StarEncounterParameters().point_masses(star, star)
        >>> point.m1, point.radius2
        (1.0, 1.0)
        """
        star1, star2 = self._stars(star1, star2)
        return EncounterParameters(m1=star1.mass, m2=star2.mass, rp=self.rp, v_inf=self.v_inf, sep0=self.sep0,
                                   units=self.units, layout=self.layout, radius1=star1.radius(MASS_FRACTION),
                                   radius2=star2.radius(MASS_FRACTION))

    def _stars(self, star1, star2) -> tuple[StarModel, StarModel]:
        converted = []
        for name, star in (("star1", star1), ("star2", star2)):
            if not isinstance(star, StarModel):
                raise TypeError(f"{name} must be a StarModel; got {type(star).__name__}")
            try:
                converted.append(star.in_units(self.unit_system()))
            except ValueError as failure:
                raise ValueError(f"{name} is in {star.units.name} units and the encounter in {self.units}: "
                                 f"{failure}") from None
        return converted[0], converted[1]


def _parameters(parameters) -> StarEncounterParameters:
    """``parameters`` as StarEncounterParameters: itself, or made from a mapping of names or flags."""
    if isinstance(parameters, StarEncounterParameters):
        return parameters
    if isinstance(parameters, Mapping):
        return StarEncounterParameters.from_mapping(parameters)
    raise TypeError(f"parameters must be StarEncounterParameters (rp, v_inf, sep0, units, layout: the masses come "
                    f"from the particles) or a mapping of them; got {type(parameters).__name__}")


def _placed(star1: StarModel, star2: StarModel, ic: InitialConditions) -> StarModel:
    """Both stars moved rigidly to the two-body positions and velocities of ``ic``, as one model."""
    moved = [star.moved(shift=position - star.centre_of_mass, boost=velocity - star.centre_of_mass_velocity)
             for star, position, velocity in zip((star1, star2), ic.positions, ic.velocities)]
    ids2 = star2.ids - star2.ids.min() + star1.ids.max() + 1
    return StarModel(
        positions=np.concatenate([star.positions for star in moved]),
        velocities=np.concatenate([star.velocities for star in moved]),
        masses=np.concatenate([star1.masses, star2.masses]),
        smoothing_lengths=np.concatenate([star1.smoothing_lengths, star2.smoothing_lengths]),
        internal_energies=np.concatenate([star1.internal_energies, star2.internal_energies]),
        ids=np.concatenate([star1.ids, ids2]),
        units=star1.units,
        star_ids=np.repeat([1, 2], [len(star1), len(star2)]),
    )


def _tidal_message(sep0: float, radius1: float, radius2: float) -> str | None:
    if sep0 >= TIDAL_FACTOR * (radius1 + radius2):
        return None
    return (f"sep0 = {sep0:g} < 5 (R1 + R2) = {TIDAL_FACTOR * (radius1 + radius2):g} (R = the radius holding 99 % of "
            "each star's mass): tidal effects at the start are not negligible, so spherical stars are a poor start; "
            "consider a larger sep0")


def place_stars(star1: StarModel, star2: StarModel, parameters) -> StarModel:
    """Two particle stars on the StarCrash orbit, in one model (see the module's description).

    Parameters
    ----------
    star1, star2 : StarModel
        Each converted to ``parameters.units`` first.
    parameters : StarEncounterParameters or mapping
        The orbit (a mapping such as ``{"rp": 1, "vinf": 0.5, "sep0": 10}``
        is made into StarEncounterParameters).

    Returns
    -------
    StarModel
        Star 1's particles, then star 2's, with ``star_ids`` 1 and 2.

    Warns
    -----
    GridExitWarning
        Diagonal layout with v_t / v0 > sqrt(1/3).
    TidalWarning
        sep0 < 5 (R1 + R2).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.encounters import StarEncounterParameters, place_stars, polytrope_star
    >>> sun, dwarf = polytrope_star(1.5, 300, neighbours=10, seed=1), polytrope_star(3.0, 200, 0.5, 0.5, neighbours=10,
    ...                                                                              seed=2)
    >>> pair = place_stars(sun, dwarf, StarEncounterParameters(rp=1.0, v_inf=0.5, sep0=20.0))
    >>> len(pair), bool(np.allclose(pair.centre_of_mass, 0, atol=1e-14))
    (500, True)
    >>> bool(np.allclose(pair.masses @ pair.velocities, 0, atol=1e-15)), pair.ids[300], int(pair.star_ids[300])
    (True, np.int64(301), 2)
    """
    parameters = _parameters(parameters)
    star1, star2 = parameters._stars(star1, star2)
    point = parameters.point_masses(star1, star2)
    ic, messages = point.initial_conditions()
    for message in messages:
        warnings.warn(message, GridExitWarning, stacklevel=2)
    tidal = _tidal_message(point.sep0, point.radius1, point.radius2)
    if tidal is not None:
        warnings.warn(tidal, TidalWarning, stacklevel=2)
    return _placed(star1, star2, ic)


def star_encounter_summary(star1: StarModel, star2: StarModel,
                           parameters) -> tuple[dict[str, Any], InitialConditions, StarModel]:
    """The ``encounter --star1 --star2`` command as a library call: its summary, the two-body set-up, the placed stars.

    The summary is :func:`~collisionkit.encounters.encounter_summary`'s for
    point masses of the stars' masses (its ``contact`` uses the 99 %-mass
    radii), with ``stars`` (each star's particles, mass, radius holding 99 %
    of the mass, centre of mass and its velocity before placing),
    ``overlap_at_sep0``, ``sep0_over_radii`` = sep0 / (R1 + R2), each star's
    outermost particle's distance from its centre of mass (``outer_radii``)
    and ``envelopes_touch`` (rp below their sum: warned about when the 99 %
    radii do not touch), the tidal warning among the ``warnings``, the point-mass set-up as
    ``point_masses`` and these ``parameters`` (StarEncounterParameters or
    a mapping of them, as :func:`place_stars` takes).

    Examples
    --------
    >>> from collisionkit.encounters import StarEncounterParameters, polytrope_star, star_encounter_summary
    >>> star = polytrope_star(1.5, 300, neighbours=10, seed=1)
    >>> summary, ic, pair = star_encounter_summary(star, star, StarEncounterParameters(sep0=20.0))
    >>> summary["overlap_at_sep0"], summary["warnings"], round(summary["initial_conditions"]["m2"], 12)
    (False, [], 1.0)
    """
    parameters = _parameters(parameters)
    star1, star2 = parameters._stars(star1, star2)
    point = parameters.point_masses(star1, star2)
    summary, ic = encounter_summary(point)
    radius1, radius2 = point.radius1, point.radius2
    tidal = _tidal_message(point.sep0, radius1, radius2)
    if tidal is not None:
        summary["warnings"].append(tidal)
    summary["stars"] = {"star1": star1.summary(MASS_FRACTION), "star2": star2.summary(MASS_FRACTION)}
    summary["overlap_at_sep0"] = bool(point.sep0 < radius1 + radius2)
    summary["sep0_over_radii"] = point.sep0 / (radius1 + radius2)
    # a real star's envelope holds little mass far out: its outermost particles may graze where the 99 % radii do not
    outer1, outer2 = star1.radius(1.0), star2.radius(1.0)
    summary["outer_radii"] = [outer1, outer2]
    summary["envelopes_touch"] = bool(point.rp < outer1 + outer2)
    if summary["envelopes_touch"] and not point.rp < radius1 + radius2:
        summary["warnings"].append(
            f"the stars' outer envelopes reach within periastron: rp = {point.rp:.4g} < {outer1 + outer2:.4g}, the "
            f"sum of the outermost particles' distances from each centre of mass, though the 99 %-mass radii "
            f"({radius1:.4g} + {radius2:.4g}) do not touch")
    summary["point_masses"] = summary.pop("parameters")
    summary["parameters"] = parameters.to_dict()
    return summary, ic, _placed(star1, star2, ic)
