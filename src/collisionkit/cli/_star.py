"""The ``star`` subcommand: an unrelaxed polytrope or stellar model (a MESA profile) as SPH particles, the input to an
SPH code's own relaxation."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, ClassVar, Literal

import typer
from pydantic import Field

from ._common import (
    Deliveries, Options, OverwriteOption, fail, fail_for_option, fraction_reporter, load_options, note, print_table,
    progress_bar, require, say, warn,
)

UnitsName = Literal["nbody", "si", "cgs", "solar", "stellar"]
STAR_FILE_ENDINGS = (".hdf5", ".h5", ".hdf", ".npz")


class StarOptions(Options):
    """Options of ``collisionkit star``; the physics is :class:`collisionkit.encounters.PolytropeParameters`.

    Examples
    --------
    >>> StarOptions(polytrope=3.0, particles=1000).parameters().polytrope
    3.0
    """

    polytrope: float | None = Field(default=None, ge=0, lt=5, allow_inf_nan=False)
    profile: Path | None = None
    particles: int = Field(default=10_000, ge=2, le=10_000_000)
    mass: float = Field(default=1.0, gt=0, allow_inf_nan=False)
    radius: float = Field(default=1.0, gt=0, allow_inf_nan=False)
    units: UnitsName | None = None  # nbody for a polytrope, stellar for a --profile (a real star has a size)
    neighbours: int = Field(default=50, ge=1)
    gamma: float | None = Field(default=None, gt=1, allow_inf_nan=False)
    seed: int = Field(default=2026, ge=0)
    out: Path = Path("star.hdf5")
    summary: Path | None = None

    output_files: ClassVar[tuple[str, ...]] = ("out", "summary")
    input_files: ClassVar[tuple[str, ...]] = ("profile",)

    def parameters(self):
        """The star as :class:`collisionkit.encounters.PolytropeParameters` (a ValueError if the options clash).

        Examples
        --------
        >>> StarOptions(polytrope=1.5, units="stellar").parameters().units
        'stellar'
        """
        from ..encounters import PolytropeParameters, ProfileStarParameters

        if self.profile is not None:
            values = {name: getattr(self, name) for name in ProfileStarParameters.names()}
            return ProfileStarParameters(**values | {"units": self.units or "stellar"})
        values = {name: getattr(self, name) for name in PolytropeParameters.names()}
        return PolytropeParameters(**values | {"units": self.units or "nbody"})


def check_star_file(path: Path, option: str) -> None:
    """Stop (exit 2) unless ``path`` ends in a star file's suffix; an HDF5 one needs h5py (the ``stars`` extra).

    Examples
    --------
    >>> check_star_file(Path("sun.npz"), "--out")
    >>> try:
    ...     check_star_file(Path("sun.txt"), "--out")
    ... except Exception as stop:
    ...     print(type(stop).__name__, stop.exit_code)
    Exit 2
    """
    if path.suffix.lower() not in STAR_FILE_ENDINGS:
        raise fail(f"{option} {path} must end in {', '.join(STAR_FILE_ENDINGS)} (an HDF5 snapshot or .npz)")
    if path.suffix.lower() != ".npz":
        require("h5py", "stars", f"the HDF5 star file {option} {path}")


def _profile_rows(summary, star):
    units, energy = star.units, f"{star.units.mass} ({star.units.velocity})^2"
    profile = summary["profile"]
    rows = [
        ("profile", profile["file"], f"{profile['zones']} zones"),
        ("mass of the profile", f"{profile['mass_g']:.10g}", "g"),
        ("radius of the outermost zone", f"{profile['radius_cm']:.10g}", "cm"),
        ("virial ratio (3 int P dV - 4 pi R^3 P_s) / -W", f"{profile['virial_ratio']:.6f}", "1 in hydrostatic equilibrium"),
        ("integral of rho / mass column - 1", f"{profile['mass_mismatch']:.3g}", ""),
        ("internal energy u", summary["internal_energy"], ""),
        ("particles", len(star), ""),
        ("mass", f"{star.mass:.10g}", units.mass),
        ("radius holding 99 % of the mass", f"{summary['star']['radius_99']:.10g}", units.length),
        ("neighbours in a smoothing length", summary["parameters"]["neighbours"], ""),
        ("potential energy of the profile", f"{summary['potential_energy_profile']:.10g}", energy),
        ("thermal energy, sum m u", f"{summary['thermal_energy']:.10g}", energy),
    ]
    return rows


def _rows(summary, star):
    units = star.units
    rows = [
        ("polytropic index n", summary["lane_emden"]["n"], ""),
        ("surface xi1 (Lane-Emden)", summary["lane_emden"]["xi1"], ""),
        ("omega_n = -xi1^2 theta'(xi1)", summary["lane_emden"]["omega"], ""),
        ("gamma of u = P / ((gamma - 1) rho)", summary["gamma"], ""),
        ("particles", len(star), ""),
        ("mass", star.mass, units.mass),
        ("radius holding 99 % of the mass", summary["star"]["radius_99"], units.length),
        ("neighbours in a smoothing length", summary["parameters"]["neighbours"], ""),
        ("median smoothing length", float(sorted(star.smoothing_lengths)[len(star) // 2]), units.length),
        ("potential energy -3/(5-n) G M^2 / R", summary["potential_energy_expected"], f"{units.mass} ({units.velocity})^2"),
        ("thermal energy, sum m u", summary["thermal_energy"], f"{units.mass} ({units.velocity})^2"),
        ("thermal energy -W / (3 (gamma - 1))", summary["thermal_energy_expected"], f"{units.mass} ({units.velocity})^2"),
    ]
    return [(name, value if isinstance(value, (int, str)) else f"{value:.10g}", unit) for name, value, unit in rows]


def star(
    polytrope: Annotated[float | None, typer.Option("--polytrope", help="Polytropic index n, 0 <= n < 5 (or --profile).")] = None,
    profile: Annotated[Path | None, typer.Option("--profile", help="A MESA profile*.data file: its stellar model as particles (mass and radius from it; u from its energy column, or P / ((gamma - 1) rho) with --gamma, 5/3 by default).")] = None,
    particles: Annotated[int | None, typer.Option(help="Number of SPH particles (> neighbours, <= 1e7).  \\[default: 10000]")] = None,
    mass: Annotated[float | None, typer.Option(help="Mass of the star (> 0), in the mass unit of --units.  \\[default: 1]")] = None,
    radius: Annotated[float | None, typer.Option(help="Radius of the star (> 0), in the length unit of --units.  \\[default: 1]")] = None,
    units: Annotated[
        str | None,
        typer.Option(help="nbody (G = 1; not with --profile), si (kg m s), cgs (g cm s), solar (Msun AU yr), stellar (Msun Rsun km/s).  \\[default: nbody; with --profile: stellar]"),
    ] = None,
    neighbours: Annotated[int | None, typer.Option(help="Neighbours within each smoothing length (>= 1).  \\[default: 50]")] = None,
    gamma: Annotated[float | None, typer.Option(help="Adiabatic index of the gas (> 1) for the internal energy.  \\[default: 1 + 1/n; a profile: its energy column, else 5/3]")] = None,
    seed: Annotated[int | None, typer.Option(help="Random seed (>= 0).  \\[default: 2026]")] = None,
    out: Annotated[Path | None, typer.Option(help="The star file: .hdf5 (GADGET/SWIFT snapshot layout) or .npz.  \\[default: star.hdf5]")] = None,
    summary: Annotated[Path | None, typer.Option("--summary", help="Write the results as JSON to this file.")] = None,
    config: Annotated[Path | None, typer.Option("--config", help="TOML file with these options (command line wins).")] = None,
    overwrite: OverwriteOption = None,
):
    """Sample an unrelaxed polytrope (Lane-Emden) or stellar model (--profile, MESA) as SPH particles, the input to an SPH code's own relaxation."""
    given = dict(
        polytrope=polytrope, profile=profile, particles=particles, mass=mass, radius=radius, units=units, neighbours=neighbours,
        gamma=gamma, seed=seed, out=out, summary=summary, overwrite=overwrite,
    )  # fmt: skip
    options = load_options(StarOptions, config, given)
    if (options.polytrope is None) == (options.profile is None):
        raise fail("give one of --polytrope N (the polytropic index, 0 <= N < 5; 1.5: fully convective, 3: "
                   "Eddington's standard model) and --profile FILE (a MESA profile*.data)")
    if options.profile is not None and options.model_fields_set & {"mass", "radius"}:
        raise fail("--mass and --radius come from the --profile itself: leave them out")
    check_star_file(options.out, "--out")
    try:
        parameters = options.parameters()
    except (ValueError, TypeError) as error:
        raise fail_for_option(error, StarOptions) from None
    from ..encounters import polytrope_summary, profile_star_summary, read_mesa_profile, write_star

    profile = None
    if options.profile is not None:
        try:
            profile = read_mesa_profile(options.profile)
        except (ValueError, OSError) as error:
            raise fail(f"--profile: {error}") from None
    note(f"seed {parameters.seed} (--seed {parameters.seed} repeats this run)")
    with progress_bar("sampling the star", 100) as advance:
        if profile is None:
            result, model = polytrope_summary(parameters, progress=fraction_reporter(advance, 100))
        else:
            result, model = profile_star_summary(parameters, fraction_reporter(advance, 100), profile)
    if options.profile is None:
        title, rows = f"unrelaxed polytrope n = {parameters.polytrope:g}", _rows(result, model)
    else:
        title, rows = f"unrelaxed star of {result['profile']['file']}", _profile_rows(result, model)
    print_table(f"{title} ({model.units.name} units, G = {model.G:.10g})", ("quantity", "value", "unit"), rows)
    for text in result.get("warnings", ()):
        warn(text)
    deliveries = Deliveries("star")
    deliveries.write(f"the star {options.out}", lambda: write_star(model, options.out))
    result["files"] = [str(path) for path in deliveries.files]
    for path in deliveries.files:
        say(f"wrote {path}")
    note("an unrelaxed star (random particle positions): relax it with your SPH code before a collision")
    deliveries.finish(options.summary, result)


def register(app: typer.Typer) -> None:
    """Add the ``star`` command to the ``collisionkit`` app."""
    app.command("star")(star)
