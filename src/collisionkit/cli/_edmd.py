"""The ``edmd`` subcommand: event-driven molecular dynamics of hard spheres or discs.

The run itself is :class:`collisionkit.edmd.EdmdRun` (set-up, equilibration
chunks, measurement blocks, checkpoint and bit-for-bit resume, trajectory
frames); this command parses the options, runs it with a progress bar,
prints the table, draws the plots and writes the summary.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, ClassVar, Literal

import typer
from pydantic import Field, model_validator

from ._common import (
    INTERRUPTED_EXIT_CODE, Options, console, fail, load_options, option_values, print_table, progress_bar,
    refuse_to_overwrite_checkpoint, require_gsd, require_plotting, validate_options, warn, write_summary,
)

InitialName = Literal["random", "fcc", "sc", "square", "hexagonal"]

OUTPUT_OPTIONS = ("summary", "trajectory", "frame_every", "xyz", "out", "plots", "checkpoint")
OUTPUT_SUFFIXES = {"trajectory": (".gsd",), "xyz": (".xyz", ".extxyz")}  # the formats --trajectory and --xyz write


class EdmdOptions(Options):
    """Options of ``collisionkit edmd``; None for equilibration, collisions and seed means "per particle" / random."""

    dim: Literal[2, 3] = 3
    particles: int = Field(default=500, ge=2, le=100_000_000)
    packing_fraction: float = Field(default=0.3, gt=0, allow_inf_nan=False)
    restitution: float = Field(default=1.0, ge=0, le=1, allow_inf_nan=False)
    elastic_below: float | None = Field(default=None, ge=0, allow_inf_nan=False)
    equilibration: int | None = Field(default=None, ge=0)
    collisions: int | None = Field(default=None, ge=2)
    blocks: int = Field(default=10, ge=2, le=100_000)
    seed: int | None = Field(default=None, ge=0)
    initial: InitialName = "random"
    summary: Path | None = None
    trajectory: Path | None = None
    frame_every: int | None = Field(default=None, ge=1)
    xyz: Path | None = None
    out: Path = Path("edmd-output")
    plots: bool = True
    checkpoint: Path | None = None

    output_files: ClassVar[tuple[str, ...]] = ("summary", "trajectory", "xyz", "checkpoint")
    output_folders: ClassVar[tuple[str, ...]] = ("out",)

    @model_validator(mode="after")
    def _consistent(self):
        """The library's rules (packing limits, lattices, collisions >= blocks ...), so a sweep checks every point."""
        self.parameters()
        if self.frame_every is not None and self.trajectory is None:
            raise ValueError("--frame-every needs --trajectory FILE.gsd to write the frames to")
        for name, suffixes in OUTPUT_SUFFIXES.items():
            path = getattr(self, name)
            if path is not None and path.suffix.lower() not in suffixes:
                raise ValueError(f"--{name} must end in {' or '.join(suffixes)} (the format it writes); got {str(path)!r}")
        return self

    def parameters(self):
        """The run's physics as :class:`collisionkit.edmd.EdmdParameters`."""
        from ..edmd import EdmdParameters

        return EdmdParameters(**{name: getattr(self, name) for name in EdmdParameters.names()})


def _percent_reporter(advance, total: float):
    """A ``progress(fraction)`` callback advancing a bar of ``total`` steps."""
    shown = [0.0]

    def report(fraction):
        advance(fraction * total - shown[0])
        shown[0] = fraction * total

    return report


def _new_run(options: EdmdOptions):
    from ..edmd import EdmdRun, OverlapError

    refuse_to_overwrite_checkpoint(options.checkpoint)
    _require_outputs(options)
    try:
        parameters = options.parameters().resolved()
    except ValueError as error:
        raise fail(str(error)) from None
    try:
        with progress_bar("setting up", total=100) as advance:
            return EdmdRun(parameters, checkpoint=options.checkpoint, trajectory=options.trajectory,
                           frame_every=options.frame_every, progress=_percent_reporter(advance, 100),
                           outputs=_saved_outputs(options))
    except (ValueError, OverlapError) as error:
        raise fail(f"cannot set up the initial state: {error}") from None


def _resumed_run(resume: Path, given: dict):
    """The run saved in ``resume``; physics options given now must agree with it, outputs may change."""
    from ..edmd import EdmdRun

    physics = {key: value for key, value in given.items() if key not in OUTPUT_OPTIONS}
    try:
        run = EdmdRun.resume(resume, checkpoint=given.get("checkpoint", resume), trajectory=given.get("trajectory"),
                             frame_every=given.get("frame_every"), **physics)
    except ValueError as error:
        raise fail(str(error)) from None
    outputs = run.outputs | {key: value for key, value in given.items() if key in OUTPUT_OPTIONS}
    outputs |= {"checkpoint": run.checkpoint, "trajectory": run.trajectory, "frame_every": run.frame_every}
    options = validate_options(EdmdOptions, run.parameters.to_dict() | outputs)
    _require_outputs(options)
    return run, options


def _saved_outputs(options: EdmdOptions) -> dict:
    """The output options a resumed run writes again unless told otherwise (paths resolved)."""
    return {key: str(Path(value).resolve()) if isinstance(value, Path) else value
            for key in ("summary", "xyz", "out", "plots") if (value := getattr(options, key)) is not None}


def _require_outputs(options: EdmdOptions) -> None:
    """Stop before the run if an output asked for needs an extra that is not installed."""
    if options.plots:
        require_plotting()
    if options.trajectory is not None:
        require_gsd()


# ------------------------------------------------------------------ results


def _theory_column(result: dict) -> tuple[str, str, str, str]:
    """Reference values for Z, omega, kT and the energy lost: theory if elastic, trends if not."""
    if not result["elastic"]:
        return "no equilibrium (inelastic)", "", "cools (Haff)", "> 0"
    z = f"{result['compressibility_factor_theory']:.5g} ({result['theory']})"
    omega = f"{result['collision_frequency_from_pressure']:.5g} (Enskog, from Z)"
    return z, omega, "1 (elastic)", "0 (elastic)"


def _rows(result: dict) -> list[tuple[str, str, str]]:
    def pm(key):
        return f"{result[key]:.5g} ± {result[key + '_error']:.2g}"

    z, omega, kT, lost = _theory_column(result)
    return [
        ("compressibility factor Z = PV/NkT", pm("compressibility_factor"), z),
        ("collision frequency per particle", pm("collision_frequency"), omega),
        ("temperature kT (final)", f"{result['temperature']:.6g}", kT),
        ("mean free path", pm("mean_free_path"), ""),
        ("diffusion coefficient", pm("diffusion_coefficient"), "from the MSD"),
        ("g(r) at contact", pm("contact_value"), ""),
        ("energy lost (measurement / total)", f"{result['energy_lost']:.5g} / {result['energy_lost_total']:.5g}", lost),
        ("pair collisions (measured)", str(result["collisions"]), f"after {result['equilibration_collisions']} equilibration"),
        ("collisions per second", f"{result['collisions_per_second']:.4g}", "wall clock, measurement"),
    ]


def _plots(run, measurement, out: Path) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    from .. import plotting

    system = run.system
    out.mkdir(parents=True, exist_ok=True)
    files = []
    if run.parameters.restitution == 1.0:
        m = measurement
        point = [(m.packing_fraction, m.compressibility_factor, m.compressibility_factor_error)]
        files.append(plotting.save(plotting.plot_equation_of_state(point, system.dim), out / "equation_of_state.png"))
    speeds = plotting.plot_speed_distribution(measurement.speeds, measurement.temperature, system.dim)
    files.append(plotting.save(speeds, out / "speed_distribution.png"))
    snapshot = plotting.plot_snapshot(system.positions(), system.radius, system.box[: system.dim])
    files.append(plotting.save(snapshot, out / "snapshot.png"))
    rdf = plotting.plot_radial_distribution(measurement.rdf_r, measurement.rdf)
    files.append(plotting.save(rdf, out / "radial_distribution.png"))
    return files


def _report(run, options: EdmdOptions) -> None:
    measurement = run.measurement()
    files = [run.write_xyz(options.xyz)] if options.xyz is not None else []
    if options.trajectory is not None:
        files.append(options.trajectory)
    if options.plots:
        files.extend(_plots(run, measurement, options.out))
    result = run.summary(files)
    p = run.parameters
    kind = "spheres" if p.dim == 3 else "discs"
    title = f"EDMD: {p.particles} hard {kind}, eta = {p.packing_fraction:g}, e = {p.restitution:g}, seed {p.seed}"
    print_table(title, ("quantity", "measured", "theory"), _rows(result))
    note = run.cooling_note()
    if note is not None:
        warn(note)
    write_summary(options.summary, result)
    for path in files:
        console.print(f"wrote {path}")


# ------------------------------------------------------------------ the command


def _help(text: str, default: str | None = None) -> str:
    """Option help with its default shown (escaped from rich markup)."""
    return text if default is None else f"{text}  \\[default: {default}]"


def edmd(
    dim: Annotated[int | None, typer.Option(help=_help("2 (discs) or 3 (spheres).", "3"))] = None,
    particles: Annotated[int | None, typer.Option(help=_help("Number of particles (>= 2; a periodic box must be 3 diameters wide: about 16 or more at eta 0.3).", "500"))] = None,
    packing_fraction: Annotated[
        float | None, typer.Option(help=_help("Packing fraction eta: (0, 0.5] in 3D, (0, 0.7] in 2D.", "0.3"))
    ] = None,
    restitution: Annotated[float | None, typer.Option(help=_help("Coefficient of restitution in [0, 1].", "1"))] = None,
    elastic_below: Annotated[
        float | None,
        typer.Option(help=_help("Contacts with a normal approach speed below this are elastic (>= 0; guards inelastic runs against collapse).", "1e-6 (rms speeds) if restitution < 1")),
    ] = None,
    equilibration: Annotated[
        int | None, typer.Option(help=_help("Pair collisions before measuring (>= 0).", "20 per particle"))
    ] = None,
    collisions: Annotated[
        int | None,
        typer.Option(help=_help("Pair collisions measured (>= blocks; rounded down to a multiple of blocks).", "200 per particle")),
    ] = None,
    blocks: Annotated[int | None, typer.Option(help=_help("Measurement blocks for the error bars (>= 2).", "10"))] = None,
    seed: Annotated[int | None, typer.Option(help=_help("Random seed (>= 0).", "random, reported"))] = None,
    initial: Annotated[
        str | None,
        typer.Option(
            help=_help("random (compressed fluid), fcc, sc (3D), square, hexagonal (2D); a lattice needs N = basis * cells^d.", "random")
        ),
    ] = None,
    summary: Annotated[Path | None, typer.Option("--summary", help="Write the results as JSON to this file.")] = None,
    trajectory: Annotated[
        Path | None, typer.Option(help="Write frames to this GSD file (HOOMD, OVITO, freud read it).")
    ] = None,
    frame_every: Annotated[
        int | None,
        typer.Option(help=_help("A frame at the first chunk or block end after every N pair collisions.", "only the last frame")),
    ] = None,
    xyz: Annotated[Path | None, typer.Option(help="Write the final state as extended XYZ (ASE, OVITO).")] = None,
    out: Annotated[Path | None, typer.Option(help=_help("Folder for the plots.", "edmd-output"))] = None,
    plots: Annotated[bool | None, typer.Option("--plots/--no-plots", help=_help("Write plots.", "plots"))] = None,
    checkpoint: Annotated[
        Path | None, typer.Option(help="Write the full state to this .npz after every chunk (atomically).")
    ] = None,
    resume: Annotated[
        Path | None,
        typer.Option(help="Continue the run saved in this checkpoint, with its options; checkpoints go on to it unless --checkpoint is given."),
    ] = None,
    config: Annotated[
        Path | None, typer.Option("--config", help="TOML file with these options (command line wins).")
    ] = None,
):
    """Event-driven MD of hard spheres (3D) or discs (2D): pressure, collision frequency, g(r), diffusion.

    Units: diameter 1, mass 1, initial kT = 1.
    """
    given = dict(
        dim=dim, particles=particles, packing_fraction=packing_fraction, restitution=restitution,
        elastic_below=elastic_below, equilibration=equilibration, collisions=collisions, blocks=blocks, seed=seed, initial=initial,
        summary=summary, trajectory=trajectory, frame_every=frame_every, xyz=xyz, out=out, plots=plots,
        checkpoint=checkpoint,
    )  # fmt: skip
    if resume is None:
        options = load_options(EdmdOptions, config, given)
        run = _new_run(options)
    else:
        run, options = _resumed_run(resume, option_values(EdmdOptions, config, given))
    try:
        with progress_bar("collisions", total=run.parameters.total_collisions) as advance:
            run.run(progress=_percent_reporter(advance, run.parameters.total_collisions))
    except KeyboardInterrupt:
        where = (f"the last checkpoint is in {options.checkpoint}; continue with --resume {options.checkpoint}"
                 if options.checkpoint is not None else "no --checkpoint was given, so nothing is saved")
        warn(f"interrupted: {where}")
        raise typer.Exit(INTERRUPTED_EXIT_CODE) from None
    _report(run, options)


def register(app: typer.Typer) -> None:
    """Add the ``edmd`` command to the ``collisionkit`` app."""
    app.command("edmd")(edmd)
