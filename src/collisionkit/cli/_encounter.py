"""The ``encounter`` subcommand: a StarCrash-style hyperbolic two-body set-up."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, ClassVar, Literal

import typer
from pydantic import Field

from ._common import Deliveries, Options, OverwriteOption, fail, load_options, print_table, require_plotting, say, warn
from ._warmup import warm_up

UnitsName = Literal["nbody", "si", "cgs", "solar", "stellar"]
LayoutName = Literal["diagonal", "x"]


class EncounterOptions(Options):
    """Options of ``collisionkit encounter``; the physics is :class:`collisionkit.encounters.EncounterParameters`.

    Examples
    --------
    >>> EncounterOptions(vinf=2.0).parameters().v_inf
    2.0
    """

    m1: float = Field(default=1.0, gt=0, allow_inf_nan=False)
    m2: float = Field(default=1.0, gt=0, allow_inf_nan=False)
    rp: float = Field(default=1.0, gt=0, allow_inf_nan=False)
    vinf: float = Field(default=0.5, gt=0, allow_inf_nan=False)
    sep0: float = Field(default=10.0, gt=0, allow_inf_nan=False)
    units: UnitsName = "nbody"
    layout: LayoutName = "diagonal"
    radius1: float | None = Field(default=None, ge=0, allow_inf_nan=False)
    radius2: float | None = Field(default=None, ge=0, allow_inf_nan=False)
    out: Path = Path("encounter-output")
    plots: bool = True
    summary: Path | None = None

    output_folders: ClassVar[tuple[str, ...]] = ("out",)

    def parameters(self):
        """The set-up as :class:`collisionkit.encounters.EncounterParameters` (``--vinf`` is ``v_inf``).

        Examples
        --------
        >>> EncounterOptions(units="si").parameters().units
        'si'
        """
        from ..encounters import EncounterParameters

        values = {name: getattr(self, name) for name in EncounterParameters.names() if name != "v_inf"}
        return EncounterParameters(v_inf=self.vinf, **values)


def _rows(ic, contact, labels):
    orbit = ic.orbit
    rows = [
        ("total mass M_T", ic.total_mass, labels["mass"]),
        ("reduced mass mu", ic.reduced_mass, labels["mass"]),
        ("energy E_T = mu vinf^2 / 2 (eq. 34)", ic.energy, labels["energy"]),
        ("speed at sep0, v0 (eq. 35)", ic.v0, labels["velocity"]),
        ("speed at periastron, vp (eq. 36)", ic.vp, labels["velocity"]),
        ("angular momentum J_T (eq. 37)", ic.angular_momentum, labels["angular_momentum"]),
        ("impact parameter b (eq. 38)", ic.impact_parameter, labels["length"]),
        ("transverse speed vt (eq. 39)", ic.vt, labels["velocity"]),
        ("radial speed vr", ic.vr, labels["velocity"]),
        ("vt / v0 (grid limit sqrt(1/3) = 0.5774)", ic.speed_ratio, ""),
        ("eccentricity e", orbit.eccentricity, ""),
        ("semi-major axis a", orbit.semi_major_axis, labels["length"]),
        ("deflection angle (degrees)", math.degrees(orbit.deflection_angle), "deg"),
        ("time from sep0 to periastron", ic.time_to_periastron, labels["time"]),
    ]
    if contact is not None:
        rows.append(("bodies touch (rp < R1 + R2)", contact["touches"], ""))
        if contact["touches"]:
            rows.append(("time from start to contact", contact["time_from_start"], labels["time"]))
            rows.append(("relative speed at contact", contact["relative_speed"], labels["velocity"]))
        rows.append(("focusing cross section", contact["focusing_cross_section"], labels["area"]))
    return [(name, value if isinstance(value, (bool, str)) else f"{value:.10g}", unit) for name, value, unit in rows]


def encounter(
    m1: Annotated[float | None, typer.Option("--m1", help="Mass of body 1 (> 0).  \\[default: 1]")] = None,
    m2: Annotated[float | None, typer.Option("--m2", help="Mass of body 2 (> 0).  \\[default: 1]")] = None,
    rp: Annotated[float | None, typer.Option("--rp", help="Periastron distance (> 0).  \\[default: 1]")] = None,
    vinf: Annotated[float | None, typer.Option("--vinf", help="Relative speed at infinity (> 0).  \\[default: 0.5]")] = None,
    sep0: Annotated[float | None, typer.Option("--sep0", help="Initial separation (>= rp).  \\[default: 10]")] = None,
    units: Annotated[
        str | None,
        typer.Option(help="nbody (G = 1), si (kg m s), cgs (g cm s), solar (Msun AU yr), stellar (Msun Rsun km/s).  \\[default: nbody]"),
    ] = None,
    layout: Annotated[
        str | None, typer.Option(help="diagonal (opposite grid corners, as StarCrash) or x.  \\[default: diagonal]")
    ] = None,
    radius1: Annotated[float | None, typer.Option(help="Radius of body 1 for contact detection (>= 0).")] = None,
    radius2: Annotated[float | None, typer.Option(help="Radius of body 2 for contact detection (>= 0).")] = None,
    out: Annotated[
        Path | None, typer.Option(help="Folder for the initial conditions and the plot.  \\[default: encounter-output]")
    ] = None,
    plots: Annotated[bool | None, typer.Option("--plots/--no-plots", help="Plot the trajectories.  \\[default: plots]")] = None,
    summary: Annotated[Path | None, typer.Option("--summary", help="Write the results as JSON to this file.")] = None,
    config: Annotated[Path | None, typer.Option("--config", help="TOML file with these options (command line wins).")] = None,
    overwrite: OverwriteOption = None,
):
    """Set up a hyperbolic two-body encounter (StarCrash eqs. 34-39) and print its derived quantities."""
    given = dict(
        m1=m1, m2=m2, rp=rp, vinf=vinf, sep0=sep0, units=units, layout=layout,
        radius1=radius1, radius2=radius2, out=out, plots=plots, summary=summary, overwrite=overwrite,
    )  # fmt: skip
    options = load_options(EncounterOptions, config, given)
    if options.plots:
        require_plotting()
    from ..encounters import encounter_summary

    warm_up(["encounter"])

    parameters = options.parameters()
    try:
        result, ic = encounter_summary(parameters)
    except ValueError as error:
        raise fail(str(error)) from None
    system = parameters.unit_system()
    print_table(f"two-body encounter ({system.name} units, G = {system.G:.10g})", ("quantity", "value", "unit"),
                _rows(ic, result["contact"], result["unit_labels"]))
    for message in result["warnings"]:
        warn(message)
    deliveries = Deliveries("encounter")
    deliveries.write(f"the initial conditions in {options.out}", lambda: ic.write(options.out, units=system))
    if options.plots:
        import matplotlib

        matplotlib.use("Agg")
        from .. import plotting

        deliveries.write(f"the plot {options.out / 'encounter.png'}", lambda: plotting.save(
            plotting.plot_encounter(ic, units=system), options.out / "encounter.png"))
    result["files"] = [str(path) for path in deliveries.files]
    for path in deliveries.files:
        say(f"wrote {path}")
    deliveries.finish(options.summary, result)


def register(app: typer.Typer) -> None:
    """Add the ``encounter`` command to the ``collisionkit`` app."""
    app.command("encounter")(encounter)
