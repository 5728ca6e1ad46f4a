"""The ``encounter`` subcommand: a StarCrash-style hyperbolic two-body set-up."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, ClassVar, Literal

import typer
from pydantic import Field

from ._common import (
    Deliveries, Options, OverwriteOption, fail, fail_for_option, note, option_values, print_table, require,
    require_plotting, say,
    validate_options, warn,
)
from ._star import check_star_file
from ._warmup import warm_up

UnitsName = Literal["nbody", "si", "cgs", "solar", "stellar"]
# the files of --out: the initial conditions (JSON and text), the particle stars placed on the orbit, the plot
WRITTEN = ("initial_conditions.json", "initial_conditions.txt", "initial_conditions.hdf5", "encounter.png")
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
    star1: Path | None = None
    star2: Path | None = None
    out: Path = Path("encounter-output")
    plots: bool = True
    summary: Path | None = None

    output_folders: ClassVar[tuple[str, ...]] = ("out",)
    input_files: ClassVar[tuple[str, ...]] = ("star1", "star2")

    def folder_files(self, folder: str) -> tuple[str, ...]:
        """The files an encounter writes in ``--out`` (the stars' file and the plot among them, written or not:
        a stale one would contradict the new initial conditions)."""
        return WRITTEN

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

    def star_parameters(self):
        """The orbit of two particle stars as :class:`collisionkit.encounters.StarEncounterParameters`.

        Examples
        --------
        >>> EncounterOptions(sep0=30.0, layout="x").star_parameters().sep0
        30.0
        """
        from ..encounters import StarEncounterParameters

        return StarEncounterParameters(rp=self.rp, v_inf=self.vinf, sep0=self.sep0, units=self.units,
                                       layout=self.layout)


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
    star1: Annotated[Path | None, typer.Option(
        "--star1", help="Star 1 as SPH particles (.hdf5 snapshot or .npz): its mass and radius come from them, and "
                        "both stars are placed in OUT/initial_conditions.hdf5. With --star2.")] = None,
    star2: Annotated[Path | None, typer.Option("--star2", help="Star 2 as SPH particles (.hdf5 or .npz).")] = None,
    out: Annotated[
        Path | None, typer.Option(help="Folder for the initial conditions and the plot.  \\[default: encounter-output]")
    ] = None,
    plots: Annotated[bool | None, typer.Option("--plots/--no-plots", help="Plot the trajectories.  \\[default: plots]")] = None,
    summary: Annotated[Path | None, typer.Option("--summary", help="Write the results as JSON to this file.")] = None,
    config: Annotated[Path | None, typer.Option("--config", help="TOML file with these options (command line wins).")] = None,
    overwrite: OverwriteOption = None,
):
    """Set up a hyperbolic two-body encounter (StarCrash eqs. 34-39) and print its derived quantities; with --star1
    and --star2, place two particle stars on it for an SPH code."""
    given = dict(
        m1=m1, m2=m2, rp=rp, vinf=vinf, sep0=sep0, units=units, layout=layout, radius1=radius1, radius2=radius2,
        star1=star1, star2=star2, out=out, plots=plots, summary=summary, overwrite=overwrite,
    )  # fmt: skip
    values = option_values(EncounterOptions, config, given)
    options = validate_options(EncounterOptions, values)
    with_stars = _check_stars(options, values)
    if options.plots:
        require_plotting()
    if with_stars:
        stars = _read_stars(options)
    from ..encounters import encounter_summary, star_encounter_summary, write_star

    try:  # the set-up's numbers checked before any work (the stars' masses come from their files)
        options.star_parameters() if with_stars else options.parameters()
    except ValueError as error:
        raise fail_for_option(error, EncounterOptions, {"v_inf": "vinf"}) from None
    warm_up(["encounter"])

    try:
        if with_stars:
            result, ic, pair = star_encounter_summary(*stars, options.star_parameters())
        else:
            result, ic = encounter_summary(options.parameters())
    except ValueError as error:
        raise fail_for_option(error, EncounterOptions, {"v_inf": "vinf"}) from None
    system = options.parameters().unit_system()
    rows = _rows(ic, result["contact"], result["unit_labels"])
    if with_stars:
        rows += _star_rows(result)
    print_table(f"two-body encounter ({system.name} units, G = {system.G:.10g})", ("quantity", "value", "unit"), rows)
    for message in result["warnings"]:
        warn(message)
    deliveries = Deliveries("encounter")
    deliveries.write(f"the initial conditions in {options.out}", lambda: ic.write(options.out, units=system))
    placed = options.out / "initial_conditions.hdf5"
    if with_stars:
        deliveries.write(f"the stars {placed}", lambda: write_star(pair, placed))
    else:  # an earlier run's stars (replaced with --overwrite) would contradict these initial conditions
        placed.unlink(missing_ok=True)
    if options.plots:
        import matplotlib

        matplotlib.use("Agg")
        from .. import plotting

        def figure():
            return plotting.plot_star_encounter(ic, pair, units=system) if with_stars else \
                plotting.plot_encounter(ic, units=system)

        deliveries.write(f"the plot {options.out / 'encounter.png'}",
                         lambda: plotting.save(figure(), options.out / "encounter.png"))
    else:
        (options.out / "encounter.png").unlink(missing_ok=True)  # an earlier run's plot, of other conditions
    result["files"] = [str(path) for path in deliveries.files]
    for path in deliveries.files:
        say(f"wrote {path}")
    deliveries.finish(options.summary, result)


def _check_stars(options: EncounterOptions, values) -> bool:
    """Whether the run places particle stars; their options checked (exit 2) before any work."""
    if options.star1 is None and options.star2 is None:
        return False
    if options.star1 is None or options.star2 is None:
        raise fail("--star1 and --star2 go together: give both star files, or neither")
    for name in ("m1", "m2", "radius1", "radius2"):
        if name in values:
            raise fail(f"--{name} comes from the particles of --star1 and --star2 (masses, and radii holding 99 % of "
                       "the mass): leave it out")
    check_star_file(options.star1, "--star1")
    check_star_file(options.star2, "--star2")
    require("h5py", "stars", "placing particle stars (--star1, --star2) in initial_conditions.hdf5")
    return True


def _read_stars(options: EncounterOptions):
    """Both star files read (a file that states no units is taken in --units); a bad file is exit 2."""
    from ..encounters import StarFileError, read_star

    stars = []
    for option, path in (("--star1", options.star1), ("--star2", options.star2)):
        try:
            star = read_star(path, default_units=options.units)
        except (StarFileError, ValueError, OSError) as error:
            raise fail(f"{option} {' '.join(str(error).split())}") from None
        stars.append(star)
    for option, path, star in zip(("--star1", "--star2"), (options.star1, options.star2), stars):
        if star.units.name != options.units:
            note(f"{option} {path} is in {star.units.name} units: converted to {options.units}")
    return stars


def _star_rows(result):
    rows = []
    labels = result["unit_labels"]
    for number in (1, 2):
        star = result["stars"][f"star{number}"]
        rows += [
            (f"star {number}: particles", star["particles"], ""),
            (f"star {number}: mass", f"{star['mass']:.10g}", labels["mass"]),
            (f"star {number}: radius holding 99 % of the mass", f"{star['radius_99']:.10g}", labels["length"]),
            (f"star {number}: outermost particle's distance", f"{result['outer_radii'][number - 1]:.10g}",
             labels["length"]),
        ]
    rows += [
        ("sep0 / (R1 + R2) (tides negligible above 5)", f"{result['sep0_over_radii']:.10g}", ""),
        ("stars overlap at sep0", result["overlap_at_sep0"], ""),
        ("outer envelopes reach within rp", result["envelopes_touch"], ""),
    ]
    return rows


def register(app: typer.Typer) -> None:
    """Add the ``encounter`` command to the ``collisionkit`` app."""
    app.command("encounter")(encounter)
