"""The ``encounter`` command as a library call: checked parameters in, the set-up and its summary out."""

from __future__ import annotations

import dataclasses
import warnings
from typing import Any, ClassVar

from .._params import Parameters, check_choice, check_real
from .initial_conditions import GridExitWarning, InitialConditions, check_set_up, starcrash_initial_conditions
from .units import UNIT_SYSTEMS, UnitSystem, unit_system

__all__ = ["EncounterParameters", "encounter_summary", "unit_labels"]

LAYOUTS = ("diagonal", "x")


@dataclasses.dataclass(frozen=True)
class EncounterParameters(Parameters):
    """A StarCrash-style hyperbolic set-up (eqs. 34-39), checked when made.

    Parameters
    ----------
    m1, m2 : float
        Masses (> 0), in the mass unit of ``units``.
    rp : float
        Periastron distance (> 0).
    v_inf : float
        Relative speed at infinity (> 0; ``--vinf`` on the command line).
    sep0 : float
        Initial separation (>= rp, checked when the set-up is made).
    units : str
        ``nbody`` (G = 1), ``si``, ``cgs``, ``solar`` or ``stellar``.
    layout : {"diagonal", "x"}
        Opposite grid corners (StarCrash) or along x.
    radius1, radius2 : float, optional
        Radii (>= 0) for contact detection.

    Examples
    --------
    >>> EncounterParameters.from_mapping({"vinf": 2.0}).v_inf
    2.0
    """

    m1: float = 1.0
    m2: float = 1.0
    rp: float = 1.0
    v_inf: float = 0.5
    sep0: float = 10.0
    units: str = "nbody"
    layout: str = "diagonal"
    radius1: float | None = None
    radius2: float | None = None

    FLAGS: ClassVar = {"v_inf": "vinf"}

    def __post_init__(self):
        for name in ("m1", "m2", "rp", "v_inf", "sep0"):
            object.__setattr__(self, name, check_real(name, getattr(self, name), 0.0, low_open=True))
        check_choice("units", self.units, UNIT_SYSTEMS)
        check_choice("layout", self.layout, LAYOUTS)
        check_set_up(self.m1, self.m2, self.rp, self.v_inf, self.sep0, self.unit_system().G)
        for name in ("radius1", "radius2"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, check_real(name, getattr(self, name), 0.0))

    def unit_system(self) -> UnitSystem:
        """The unit system the masses, lengths and speeds are in.

        Examples
        --------
        >>> EncounterParameters(units="cgs").unit_system().name
        'cgs'
        """
        return unit_system(self.units)

    def initial_conditions(self) -> tuple[InitialConditions, list[str]]:
        """The set-up, and the grid-exit warnings it raised (as text).

        Raises
        ------
        ValueError
            If ``sep0 < rp`` or the set-up is impossible.

        Examples
        --------
        >>> ic, warnings = EncounterParameters(v_inf=0.5, sep0=10.0).initial_conditions()
        >>> round(ic.sep0, 12), warnings
        (10.0, [])
        >>> EncounterParameters(rp=2.0, sep0=1.0).initial_conditions()
        Traceback (most recent call last):
        ...
        ValueError: sep0 must be >= rp (the stars start outside periastron); got sep0=1.0, rp=2.0
        """
        if self.sep0 < self.rp:
            raise ValueError(f"sep0 must be >= rp (the stars start outside periastron); got sep0={self.sep0}, "
                             f"rp={self.rp}")
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", GridExitWarning)
            ic = starcrash_initial_conditions(self.m1, self.m2, self.rp, self.v_inf, self.sep0,
                                              G=self.unit_system().G, layout=self.layout)
        return ic, [str(item.message) for item in caught if issubclass(item.category, GridExitWarning)]


def unit_labels(system: UnitSystem) -> dict[str, str]:
    """The units of each derived quantity, as text.

    Examples
    --------
    >>> unit_labels(unit_system("si"))["energy"]
    'kg (m/s)^2'
    """
    v = system.velocity
    return {
        "mass": system.mass,
        "length": system.length,
        "time": system.time,
        "velocity": v,
        "energy": f"{system.mass} ({v})^2",
        "angular_momentum": f"{system.mass} {system.length} ({v})",
        "area": f"{system.length}^2",
    }


def _contact(parameters: EncounterParameters, ic: InitialConditions) -> dict[str, Any] | None:
    """Contact summary for the given radii (None if no radii were given)."""
    if parameters.radius1 is None and parameters.radius2 is None:
        return None
    r1, r2 = parameters.radius1 or 0.0, parameters.radius2 or 0.0
    if r1 + r2 == 0.0:
        raise ValueError("radius1 + radius2 must be > 0 for contact detection")
    contact = ic.orbit.contact(r1, r2)
    touches = contact.touches
    return {
        "radius1": r1,
        "radius2": r2,
        "touches": touches,
        "time_from_start": contact.time + ic.time_to_periastron if touches else None,
        "time_from_periastron": contact.time if touches else None,
        "relative_speed": contact.relative_speed if touches else None,
        "normal_speed": contact.normal_speed if touches else None,
        "focusing_cross_section": ic.orbit.focusing_cross_section(r1, r2),
        "overlap_at_start": ic.sep0 < r1 + r2,
    }


def encounter_summary(parameters: EncounterParameters) -> tuple[dict[str, Any], InitialConditions]:
    """The encounter command's summary and the initial conditions it describes.

    The summary holds the units, the initial conditions, the orbit's
    derived quantities (``orbit.deflection_angle`` ...), the contact (if
    radii were given), the warnings and the ``parameters`` that make it again.

    Examples
    --------
    >>> summary, ic = encounter_summary(EncounterParameters(v_inf=0.5))
    >>> round(summary["orbit"]["eccentricity"], 6), summary["parameters"]["v_inf"]
    (1.125, 0.5)
    """
    system = parameters.unit_system()
    ic, messages = parameters.initial_conditions()
    contact = _contact(parameters, ic)
    if contact is not None and contact["overlap_at_start"]:
        messages.append(f"the bodies overlap at sep0 = {ic.sep0:g} < radius1 + radius2; contact precedes the start")
    summary = {
        "units": system.name,
        "G": system.G,
        "unit_labels": unit_labels(system),
        "initial_conditions": ic.to_dict(),
        "orbit": ic.orbit.derived_quantities(),
        "contact": contact,
        "warnings": messages,
        "parameters": parameters.to_dict(),
    }
    return summary, ic
