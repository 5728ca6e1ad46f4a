"""Unit systems for two-body encounters: the value of G in N-body, SI, cgs, solar and stellar units.

Any consistent system works; :data:`UNIT_SYSTEMS` names five of them and
:func:`unit_system` looks one up by name.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import scipy.constants as const

__all__ = ["GM_SUN", "R_SUN", "UNIT_SYSTEMS", "UnitSystem", "unit_system"]

#: IAU 2015 nominal solar mass parameter GM_sun (m^3 s^-2), Resolution B3.
GM_SUN = 1.3271244e20
#: IAU 2015 nominal solar radius (m), Resolution B3.
R_SUN = 6.957e8


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
