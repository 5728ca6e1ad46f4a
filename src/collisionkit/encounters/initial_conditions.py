r"""Initial conditions of a stellar encounter, set up as in StarCrash (eqs. 34-39).

Two stars of masses m1, m2 start at separation :math:`r_0` on a hyperbolic
orbit with periastron :math:`r_p` and relative speed at infinity
:math:`v_\infty` (StarCrash user manual, J. Faber 2003, "Hyperbolic
Collisions"): :func:`starcrash_initial_conditions` gives an
:class:`InitialConditions` with both stars' positions and velocities in the
centre-of-mass frame, laid out on the diagonal of the gravity grid (a
:class:`GridExitWarning` when a star can leave it) or along x.
"""

from __future__ import annotations

import math
import sys
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .._io import atomic_write_json, atomic_write_text
from ._validation import interaction, nonzero_speed, scalar_above
from .orbit import Hyperbolic
from .units import UnitSystem, unit_system

__all__ = [
    "GRID_SPEED_RATIO_LIMIT",
    "GridExitWarning",
    "InitialConditions",
    "starcrash_initial_conditions",
]

#: The speed ratio v_t / v0 above which a star started in a grid corner can leave the grid.
GRID_SPEED_RATIO_LIMIT = math.sqrt(1.0 / 3.0)


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
    ...     ic = starcrash_initial_conditions(1.0, 1.0, rp=1.0, v_inf=0.5, sep0=1.2)
    >>> caught[0].category is GridExitWarning, round(ic.speed_ratio, 3)
    (True, 0.908)
    """


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
    >>> ic = starcrash_initial_conditions(1.0, 2.0, rp=1.0, v_inf=0.5, sep0=10.0)
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
            :class:`~collisionkit.encounters.units.UnitSystem` or its name (see
            :data:`~collisionkit.encounters.units.UNIT_SYSTEMS`).

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
        from .._repr import html_table, initial_conditions_rows

        return html_table("InitialConditions", initial_conditions_rows(self))


def starcrash_initial_conditions(m1, m2, rp, v_inf, sep0, G=1.0, *, layout: str = "diagonal") -> InitialConditions:
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
    v_inf : float
        Relative speed at infinity, > 0 (the parameter VPEAK).
    sep0 : float
        Initial separation r0 >= rp (SEP0).
    G : float
        Gravitational constant, > 0 (see
        :data:`~collisionkit.encounters.units.UNIT_SYSTEMS`).
    layout : {"diagonal", "x"}

    Returns
    -------
    InitialConditions

    Examples
    --------
    >>> from collisionkit.encounters import starcrash_initial_conditions
    >>> ic = starcrash_initial_conditions(1.0, 1.0, rp=1.0, v_inf=0.5, sep0=10.0)
    >>> round(ic.impact_parameter, 12), round(ic.v0, 12)  # sqrt(1 + 4 / 0.25), sqrt(0.25 + 0.4)
    (4.123105625618, 0.80622577483)
    >>> ic.positions.sum(axis=0), float(ic.velocities[1, 0] - ic.velocities[1, 1])
    (array([0., 0., 0.]), 0.0)
    """
    if layout not in _LAYOUTS:
        raise ValueError(f"layout must be 'diagonal' or 'x'; got {layout!r}")
    G = scalar_above(G, "G")
    orbit = Hyperbolic(m1, m2, periastron=rp, v_inf=v_inf, G=G)
    m1, m2, rp, v_inf = orbit.m1, orbit.m2, orbit.periastron, orbit.v_inf
    r0 = scalar_above(sep0, "sep0")
    if r0 < rp:
        raise ValueError(f"sep0 must be >= rp = {rp} (the stars start outside periastron); got {r0}")
    _check_scales(m1, m2, rp, v_inf, r0, G)
    mu_g = orbit.kepler_parameter
    v0 = math.sqrt(v_inf**2 + 2.0 * mu_g / r0)
    b = orbit.impact_parameter
    vt = v_inf * b / r0
    vr = math.sqrt((r0 - rp) * (v_inf**2 * (r0 + rp) + 2.0 * mu_g)) / r0
    radial, transverse = _LAYOUTS[layout]
    separation = r0 * radial
    relative_velocity = -vr * radial + vt * transverse
    oriented = orbit._oriented_through(r0, radial, transverse)
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
    return _finite(InitialConditions(
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
    ))


def check_set_up(m1, m2, rp, v_inf, sep0, G) -> None:
    """ValueError unless a set-up's numbers are usable: v_inf^2 a normal float, and :func:`_check_scales`.

    Cheap (no orbit is solved), so a command can refuse bad input before any work.

    Examples
    --------
    >>> check_set_up(1.0, 1.0, 1.0, 0.5, 10.0, 1.0)
    >>> check_set_up(1e300, 1e300, 1.0, 0.5, 10.0, 1.0)
    Traceback (most recent call last):
    ...
    ValueError: the masses, rp, v_inf and sep0 give G m1 m2 / rp = inf, outside the floating-point range \
(2.23e-308 to 1.8e+308): choose units in which they are nearer 1
    """
    v_inf = nonzero_speed(v_inf, "v_inf")
    m1, m2, G, _, _ = interaction(m1, m2, G, None)
    _check_scales(m1, m2, scalar_above(rp, "rp"), v_inf, scalar_above(sep0, "sep0"), G)


def _check_scales(m1, m2, rp, v_inf, sep0, G) -> None:
    """ValueError unless the set-up's scales are normal floats: G m1 m2 / rp, mu v_inf^2 and v_inf sep0.

    The initial conditions are products of these with the masses and
    lengths given; beyond ~1e308 (or below ~1e-308) they overflow (or
    vanish) in double precision.
    """
    scales = {
        "G m1 m2 / rp": G * (m1 / rp) * m2,
        "mu v_inf^2": m1 / (m1 + m2) * m2 * v_inf * v_inf,
        "v_inf sep0": v_inf * sep0,
    }
    for name, value in scales.items():
        if not sys.float_info.min <= abs(value) < math.inf:
            raise ValueError(f"the masses, rp, v_inf and sep0 give {name} = {value:.3g}, outside the floating-point "
                             f"range ({sys.float_info.min:.3g} to {sys.float_info.max:.3g}): choose units in which "
                             "they are nearer 1")


def _finite(ic: InitialConditions) -> InitialConditions:
    """``ic``, or a ValueError naming its first number that is not finite (the set-up left the float range)."""
    for name, value in ic.to_dict().items():
        if not isinstance(value, str) and not np.isfinite(np.asarray(value, dtype=float)).all():
            raise ValueError(f"the initial condition {name} comes out {value}: the masses, distances and speeds "
                             "given leave the floating-point range; choose units in which they are nearer 1")
    return ic
