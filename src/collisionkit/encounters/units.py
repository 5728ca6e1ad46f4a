"""Unit systems for two-body encounters: the value of G in N-body, SI, cgs, solar and stellar units.

Any consistent system works; :data:`UNIT_SYSTEMS` names five of them and
:func:`unit_system` looks one up by name.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import scipy.constants as const

__all__ = ["GM_SUN", "R_SUN", "UNIT_SYSTEMS", "UnitSystem", "conversion_factors", "unit_system", "unit_system_from_cgs"]

#: IAU 2015 nominal solar mass parameter GM_sun (m^3 s^-2), Resolution B3.
GM_SUN = 1.3271244e20
#: IAU 2015 nominal solar radius (m), Resolution B3.
R_SUN = 6.957e8


@dataclass(frozen=True)
class UnitSystem:
    """A consistent set of units and the value of G in it.

    Parameters
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


def _sized(system: UnitSystem, role: str) -> None:
    if not all(math.isfinite(size) for size in (system.mass_si, system.length_si, system.time_si)):
        raise ValueError(f"{role} units {system.name!r} have no size in SI (G = 1 sets no scale): "
                         "a model in them converts to no other system")


def conversion_factors(source: UnitSystem | str, target: UnitSystem | str) -> dict[str, float]:
    r"""The numbers that multiply a quantity in ``source`` units to give it in ``target`` units.

    With unit sizes :math:`M_s, L_s, T_s` (in kg, m, s) of the source and
    :math:`M_t, L_t, T_t` of the target: mass :math:`M_s/M_t`, length
    :math:`L_s/L_t`, time :math:`T_s/T_t`, velocity
    :math:`(L_s/T_s)/(L_t/T_t)` and specific energy (an SPH particle's
    internal energy per unit mass) the square of the velocity factor. A
    system converts to itself with factors of exactly 1 (N-body units
    too); N-body units convert to no other system (G = 1 sets no scale).

    Parameters
    ----------
    source, target : UnitSystem or str

    Returns
    -------
    dict
        Keys ``mass``, ``length``, ``time``, ``velocity``, ``specific_energy``.

    Raises
    ------
    ValueError
        Between N-body units and a system with sizes.

    Examples
    --------
    >>> from collisionkit.encounters import conversion_factors
    >>> factors = conversion_factors("si", "cgs")
    >>> factors["mass"], factors["length"], factors["velocity"], factors["specific_energy"]
    (1000.0, 100.0, 100.0, 10000.0)
    >>> round(conversion_factors("stellar", "cgs")["velocity"])  # km/s in cm/s
    100000
    """
    source = unit_system(source) if isinstance(source, str) else source
    target = unit_system(target) if isinstance(target, str) else target
    if source == target:
        return dict.fromkeys(("mass", "length", "time", "velocity", "specific_energy"), 1.0)
    _sized(source, "the source")
    _sized(target, "the target")
    velocity = (source.length_si / source.time_si) / (target.length_si / target.time_si)
    return {
        "mass": source.mass_si / target.mass_si,
        "length": source.length_si / target.length_si,
        "time": source.time_si / target.time_si,
        "velocity": velocity,
        "specific_energy": velocity * velocity,
    }


def unit_system_from_cgs(mass_g: float, length_cm: float, time_s: float, *, rtol: float = 1e-12) -> UnitSystem:
    """The unit system whose units are ``mass_g`` grams, ``length_cm`` centimetres and ``time_s`` seconds.

    The named system of :data:`UNIT_SYSTEMS` whose three sizes agree within
    ``rtol`` (the units SPH snapshot files state in cgs, as SWIFT writes
    them); otherwise a system named ``"custom"`` with exactly these sizes,
    labelled in cgs, and G = 6.6743e-8 M_u T_u^2 / L_u^3 (CODATA 2018).

    Examples
    --------
    >>> from collisionkit.encounters import unit_system, unit_system_from_cgs
    >>> unit_system_from_cgs(1e3, 1e2, 1.0).name
    'si'
    >>> swift = unit_system_from_cgs(1.98841e33, 6.957e10, 1.0)  # SWIFT's Msun, Rsun, s
    >>> swift.name, swift.mass
    ('custom', '1.98841e+33 g')
    """
    sizes = (mass_g * 1e-3, length_cm * 1e-2, time_s)
    if not all(math.isfinite(size) and size > 0 for size in sizes):
        raise ValueError(f"unit sizes must be finite and > 0; got {mass_g!r} g, {length_cm!r} cm, {time_s!r} s")
    for system in UNIT_SYSTEMS.values():
        known = (system.mass_si, system.length_si, system.time_si)
        if all(math.isclose(size, size_known, rel_tol=rtol, abs_tol=0.0) for size, size_known in zip(sizes, known)):
            return system
    mass, length, time = f"{mass_g:.6g} g", f"{length_cm:.6g} cm", f"{time_s:.6g} s"
    return _system("custom", mass, length, time, f"{length}/{time}", *sizes)
