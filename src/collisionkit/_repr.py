"""Rich HTML representations for Jupyter: a short table per object.

Each main class has a two-line ``_repr_html_`` that calls one of the
``*_rows`` functions below and :func:`html_table`; Jupyter shows the table
instead of the plain ``repr``.
"""

from __future__ import annotations

import html
import math
import numbers

import numpy as np

_STYLE = "border-collapse:collapse;font-family:monospace;font-size:0.9em"
_CELL = "padding:1px 8px;text-align:left"


def _format(value) -> str:
    """A short, human-readable text for one table cell."""
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value))
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        value = float(value)
        return str(value) if not math.isfinite(value) else f"{value:.6g}"
    if isinstance(value, np.ndarray):
        return np.array2string(value, precision=4, separator=", ", threshold=12)
    return str(value)


def html_table(title, rows):
    """An HTML table with a caption and one (name, value) row per item.

    Parameters
    ----------
    title : str
        Caption of the table (usually the class name).
    rows : iterable of (str, object)
        Names and values; numbers are shown with 6 significant digits,
        arrays abbreviated, and everything is HTML-escaped.

    Returns
    -------
    str
        The HTML text.

    Examples
    --------
    >>> from collisionkit._repr import html_table
    >>> print(html_table("Pair", [("mass", 2.0), ("name", "<a>")]))  # doctest: +NORMALIZE_WHITESPACE
    <table style="border-collapse:collapse;font-family:monospace;font-size:0.9em"><caption
    style="text-align:left;font-weight:bold">Pair</caption><tr><th style="padding:1px 8px;text-align:left">mass</th><td
    style="padding:1px 8px;text-align:left">2</td></tr><tr><th style="padding:1px 8px;text-align:left">name</th><td
    style="padding:1px 8px;text-align:left">&lt;a&gt;</td></tr></table>
    """
    cells = "".join(
        f'<tr><th style="{_CELL}">{html.escape(str(name))}</th><td style="{_CELL}">{html.escape(_format(value))}</td></tr>'
        for name, value in rows
    )
    caption = f'<caption style="text-align:left;font-weight:bold">{html.escape(str(title))}</caption>'
    return f'<table style="{_STYLE}">{caption}{cells}</table>'


def contact_rows(contact):
    """Rows for :class:`collisionkit.collisions.Contact`.

    Examples
    --------
    >>> import collisionkit as ck
    >>> c = ck.collide(1.0, [0.0], [1.0], 1.0, [3.0], [-1.0], contact_distance=1.0)
    >>> contact_rows(c)[:3]
    [('pairs', 1), ('hits', 1), ('dimension', 1)]
    """
    hits = np.asarray(contact.hit, dtype=bool)
    times = np.asarray(contact.time, dtype=float)[hits]
    rows = [("pairs", int(hits.size)), ("hits", int(np.count_nonzero(hits))), ("dimension", int(contact.x1.shape[-1]))]
    if times.size:
        rows += [("earliest contact", float(times.min())), ("latest contact", float(times.max()))]
    if hits.size == 1:
        rows += [("v1 after", np.asarray(contact.v1).ravel()), ("v2 after", np.asarray(contact.v2).ravel())]
    return rows


def hard_sphere_system_rows(system, packing_fraction):
    """Rows for :class:`collisionkit.edmd.HardSphereSystem`, given its packing fraction.

    Examples
    --------
    >>> from collisionkit.edmd import random_fluid
    >>> system = random_fluid(2, 20, 0.2, seed=1)
    >>> rows = dict(hard_sphere_system_rows(system, system.packing_fraction))
    >>> rows["particles"], round(rows["packing fraction"], 12)
    ('20 discs', 0.2)
    """
    dim = system.dim
    walls = "".join("p" if flag else "w" for flag in np.asarray(system.periodic)[:dim])
    return [
        ("particles", f"{system.count} {'spheres' if dim == 3 else 'discs'}"),
        ("box", np.asarray(system.box[:dim], dtype=float)),
        ("axes (p periodic, w walls)", walls),
        ("packing fraction", packing_fraction),
        ("species", int(np.max(system.species)) + 1),
        ("kT", float(system.temperature())),
        ("pair collisions", int(system.collisions)),
        ("time", float(system.elapsed + system.time)),
    ] + ([("square wells: width, depth, pairs inside", f"{number_or_table(system.well_width)}, "
                                                          f"{number_or_table(system.well_depth)}, {system.well_pairs}")]
         if getattr(system, "well_width", None) is not None else [])


def number_or_table(value) -> str:
    """A number as %g; a matrix per species pair as its range.

    Examples
    --------
    >>> number_or_table(1.5), number_or_table([[1.0, 0.0], [0.0, 2.0]])
    ('1.5', '0 to 2 by species pair')
    """
    if np.ndim(value) == 0:
        return f"{value:g}"
    return f"{np.min(value):g} to {np.max(value):g} by species pair"


def measurement_rows(measurement):
    """Rows for :class:`collisionkit.edmd.Measurement`: the main observables with errors.

    Examples
    --------
    >>> from collisionkit.edmd import measure, random_fluid
    >>> rows = dict(measurement_rows(measure(random_fluid(2, 60, 0.2, seed=1), collisions=2000, blocks=2)))
    >>> rows["particles"], rows["dimension"]
    (60, 2)
    """
    m = measurement

    def with_error(value, error):
        return f"{_format(value)} ± {_format(error)}"

    return [
        ("dimension", m.dim),
        ("particles", m.particles),
        ("packing fraction", m.packing_fraction),
        ("pair collisions", m.collisions),
        ("time", m.time),
        ("kT", m.temperature),
        ("Z = PV/(NkT)", with_error(m.compressibility_factor, m.compressibility_factor_error)),
        ("pressure", with_error(m.pressure, m.pressure_error)),
        ("collision frequency", with_error(m.collision_frequency, m.collision_frequency_error)),
        ("mean free path", with_error(m.mean_free_path, m.mean_free_path_error)),
        ("g(contact)", with_error(m.contact_value, m.contact_value_error)),
        ("diffusion coefficient", with_error(m.diffusion_coefficient, m.diffusion_coefficient_error)),
    ]


def orbit_rows(orbit):
    """Rows for :class:`collisionkit.encounters.TwoBodyOrbit` (and :class:`~collisionkit.encounters.Hyperbolic`).

    Examples
    --------
    >>> from collisionkit.encounters import Hyperbolic
    >>> dict(orbit_rows(Hyperbolic(1.0, 1.0, periastron=1.0, v_inf=1.0)))["kind"]
    'hyperbolic'
    """
    rows = [
        ("kind", orbit.kind),
        ("m1, m2", f"{_format(orbit.m1)}, {_format(orbit.m2)}"),
        ("force", "gravity" if orbit.k == 0 else ("Coulomb" if orbit.G == 0 else "gravity + Coulomb")),
        ("periastron", orbit.periastron),
        ("eccentricity", orbit.eccentricity),
        ("semi-major axis", orbit.semi_major_axis),
        ("specific energy", orbit.specific_energy),
    ]
    if orbit.kind == "elliptic":
        rows.append(("period", orbit.period))
    else:
        rows += [
            ("v_inf", orbit.v_inf),
            ("impact parameter", orbit.impact_parameter),
            ("deflection (degrees)", math.degrees(orbit.deflection_angle)),
        ]
    return rows


def initial_conditions_rows(ic):
    """Rows for :class:`collisionkit.encounters.InitialConditions` (StarCrash eqs. 34-39).

    Examples
    --------
    >>> from collisionkit.encounters import starcrash_initial_conditions
    >>> dict(initial_conditions_rows(starcrash_initial_conditions(1.0, 1.0, 1.0, 0.5, 10.0)))["layout"]
    'diagonal'
    """
    return [
        ("m1, m2", f"{_format(ic.m1)}, {_format(ic.m2)}"),
        ("rp, vinf, sep0", f"{_format(ic.rp)}, {_format(ic.v_inf)}, {_format(ic.sep0)}"),
        ("G", ic.G),
        ("layout", ic.layout),
        ("E_T (eq. 34)", ic.energy),
        ("v0 (eq. 35)", ic.v0),
        ("vp (eq. 36)", ic.vp),
        ("J_T (eq. 37)", ic.angular_momentum),
        ("b (eq. 38)", ic.impact_parameter),
        ("vt, vr (eq. 39)", f"{_format(ic.vt)}, {_format(ic.vr)}"),
        ("vt / v0", ic.speed_ratio),
        ("eccentricity", ic.orbit.eccentricity),
        ("time to periastron", ic.time_to_periastron),
    ]


def _short(value) -> str:
    """A field's value in a one-line repr: numbers and short texts as they are, containers by their size."""
    if isinstance(value, np.ndarray):
        if value.ndim == 0 or (value.ndim == 1 and value.size <= 4 and value.dtype.kind in "biuf"):
            return _short(value.item()) if value.ndim == 0 else "[" + ", ".join(_short(item) for item in value) + "]"
        return f"<array {value.shape} {value.dtype}>"
    if isinstance(value, (bool, np.bool_, str)) or value is None:
        return repr(value if not isinstance(value, np.bool_) else bool(value))
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        value = float(value)
        return repr(value) if not math.isfinite(value) else f"{value:.6g}"
    if isinstance(value, (tuple, list)):
        if len(value) <= 4 and all(isinstance(item, (numbers.Number, str)) for item in value):
            return "(" + ", ".join(_short(item) for item in value) + ("," if len(value) == 1 else "") + ")"
        return f"<{len(value)} items>"
    if isinstance(value, dict):
        return f"<{len(value)} entries>"
    return f"<{type(value).__name__}>"


def dataclass_repr(self) -> str:
    """A one-line repr of a result dataclass: its scalar fields' values, its arrays by shape (none printed whole).

    Set as the class's ``__repr__`` (the one ``dataclass`` writes prints
    every array in full: a swarm result's ran to 8000 characters). A field
    of an optional feature, ``field(default=..., metadata={"optional": True})``,
    is shown only when it differs from its default.

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> import numpy as np
    >>> @dataclass
    ... class Result:
    ...     mean_energy: float
    ...     drift: np.ndarray
    ...     spectrum: np.ndarray
    ...     processes: tuple
    ...     __repr__ = dataclass_repr
    >>> Result(1.2345678, np.array([0.0, 0.0, -1e4]), np.zeros((200, 2)), ("elastic", "ionization"))
    Result(mean_energy=1.23457, drift=[0, 0, -10000], spectrum=<array (200, 2) float64>, processes=('elastic', \
'ionization'))
    """
    import dataclasses

    shown = (f"{field.name}={_short(getattr(self, field.name))}" for field in dataclasses.fields(self)
             if field.repr and not (field.metadata.get("optional") and getattr(self, field.name) == field.default))
    return f"{type(self).__name__}({', '.join(shown)})"
