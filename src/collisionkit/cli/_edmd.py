"""The ``edmd`` subcommand: event-driven molecular dynamics of hard spheres or discs.

The run itself is :class:`collisionkit.edmd.EdmdRun` (set-up, equilibration
chunks, measurement blocks, checkpoint and bit-for-bit resume, trajectory
frames); this command checks the options, the files and the memory before
any work, runs it with a progress bar, and prints the table, draws the
plots and writes the summary (:mod:`._edmd_report`).
"""

from __future__ import annotations

import math
import shlex
from pathlib import Path
from typing import Annotated, ClassVar, Literal

import typer
from pydantic import Field, field_validator, model_validator
from typer.core import TyperCommand

from .._io import FileLockedError
from ._common import (
    INTERRUPTED_EXIT_CODE, Options, OverwriteOption, fail, fail_for_option, fraction_reporter, load_options, note,
    option_values, progress_bar, refuse_folder, require_gsd, require_plotting, run_failed, validate_options, warn,
)
from ._edmd_report import OUT_FILES, report
from ._memory import edmd_memory, refuse_beyond_memory, size
from ._warmup import warm_up

InitialName = Literal["random", "fcc", "sc", "square", "hexagonal"]
EngineName = Literal["auto", "lists", "cells"]  # collisionkit.edmd._run_checks.ENGINES
LawName = Literal["constant", "bridges", "viscoelastic"]  # collisionkit.edmd.RESTITUTION_LAWS

OUTPUT_OPTIONS = ("summary", "trajectory", "frame_every", "xyz", "out", "plots", "checkpoint", "overwrite")
OUTPUT_SUFFIXES = {"trajectory": (".gsd",), "xyz": (".xyz", ".extxyz")}  # the formats --trajectory and --xyz write


class EdmdOptions(Options):
    """Options of ``collisionkit edmd``; None for equilibration, collisions and seed means "per particle" / random.

    Examples
    --------
    >>> EdmdOptions.model_validate({"particles": 108, "initial": "fcc"}).parameters().particles
    108
    """

    dim: Literal[2, 3] = 3
    particles: int = Field(default=500, ge=2, le=100_000_000)
    packing_fraction: float = Field(default=0.3, gt=0, allow_inf_nan=False)
    # a number, or (a config file's, with fractions) a matrix over the species; ranges: the library's messages
    restitution: float | list[list[float]] = 1.0
    elastic_below: float | None = Field(default=None, ge=0, allow_inf_nan=False)
    restitution_law: LawName = "constant"
    law_speed: float = 1.0  # ranges (with NaN and inf): the library's messages, which name them
    law_exponent: float = 0.234
    tangential_restitution: float | None = None  # ranges: the library's messages
    inertia_factor: float | None = None
    friction: float | None = None
    initial_rotational_temperature: float = 1.0
    equilibration: int | None = Field(default=None, ge=0)
    elastic_equilibration: bool = False
    collisions: int | None = Field(default=None, ge=2)
    blocks: int = Field(default=10, ge=2, le=100_000)
    seed: int | None = Field(default=None, ge=0)
    initial: InitialName = "random"
    transport: bool = False
    yeh_hummer: bool = False
    shear_rate: float = Field(default=0.0, ge=0, allow_inf_nan=False)
    thermostat: bool = False
    engine: EngineName = "auto"
    # a number, or (a config file's, with fractions) a matrix over the species; ranges: the library's messages
    well_width: float | list[list[float]] | None = None
    well_depth: float | list[list[float]] = 1.0
    fractions: list[float] | None = None  # a mixture; its ranges and rules: the library's messages
    diameters: list[float] | None = None
    masses: list[float] | None = None
    summary: Path | None = None
    trajectory: Path | None = None
    frame_every: int | None = Field(default=None, ge=1)
    xyz: Path | None = None
    out: Path = Path("edmd-output")
    plots: bool = True
    checkpoint: Path | None = None

    output_files: ClassVar[tuple[str, ...]] = ("summary", "trajectory", "xyz", "checkpoint")
    output_folders: ClassVar[tuple[str, ...]] = ("out",)

    @field_validator("restitution", "well_width", "well_depth", mode="before")
    @classmethod
    def _number_or_rows(cls, value):
        """A number, or a matrix as a list of rows: a flat list is neither (said so, not as pydantic's union errors).

        Examples
        --------
        >>> try:
        ...     EdmdOptions.model_validate({"fractions": [0.5, 0.5], "restitution": [0.9, 0.8]})
        ... except ValueError as error:
        ...     print(error.errors()[0]["msg"])
        Value error, must be a number or a matrix over the species of fractions, as a list of rows of numbers (e.g. [[0.9, 0.8], [0.8, 0.7]])
        """
        rows_of_numbers = isinstance(value, list) and all(
            isinstance(row, list) and all(isinstance(item, (int, float)) and not isinstance(item, bool) for item in row)
            for row in value)
        if isinstance(value, list) and not rows_of_numbers:
            raise ValueError("must be a number or a matrix over the species of fractions, as a list of rows of numbers "
                             "(e.g. [[0.9, 0.8], [0.8, 0.7]])")
        return value

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

    def folder_files(self, folder: str) -> tuple[str, ...]:
        """The plots and ``blocks.csv`` of ``--out`` (an earlier run's are not replaced without --overwrite)."""
        return OUT_FILES

    def unwritten(self) -> set[str]:
        """``out`` without plots: nothing goes there.

        Examples
        --------
        >>> EdmdOptions(plots=False).unwritten()
        {'out'}
        """
        return set() if self.plots else {"out"}

    def parameters(self):
        """The run's physics as :class:`collisionkit.edmd.EdmdParameters`.

        Examples
        --------
        >>> EdmdOptions(dim=2, particles=64, initial="square").parameters().initial
        'square'
        """
        from ..edmd import EdmdParameters

        values = {name: getattr(self, name) for name in EdmdParameters.names()}
        values |= {name: None if values[name] is None else tuple(values[name])
                   for name in ("fractions", "diameters", "masses")}
        values |= {name: tuple(map(tuple, values[name])) for name in ("well_width", "well_depth", "restitution")
                   if isinstance(values[name], list)}
        return EdmdParameters(**values)


def _refuse_beyond_memory(parameters) -> None:
    """Stop before any work if the run would not fit in the machine's available memory."""
    needed = edmd_memory(parameters)
    hint = ""
    lattice = edmd_memory(parameters, lattice=True)
    if parameters.initial == "random" and lattice < needed:
        hint = (f"; the random start's compression needs the most (a lattice start, --initial fcc or hexagonal, "
                f"needs about {size(lattice)})")
    refuse_beyond_memory(needed, f"--particles {parameters.particles}", hint + ": use fewer particles")


def _new_run(options: EdmdOptions):
    from ..edmd import EdmdRun, OverlapError
    from ..edmd.homogeneity import instability_note

    _require_outputs(options)
    given_law = sorted(options.model_fields_set & {"law_speed", "law_exponent"})
    if options.restitution_law == "constant" and given_law:  # (at its default value it would pass unseen)
        name = given_law[0]  # as the library says it for a value other than the default
        laws = "bridges or viscoelastic" if name == "law_speed" else "bridges"
        raise fail(f"--{name.replace('_', '-')} needs restitution_law {laws} (restitution_law constant has no {name});"
                   f" got {name} {getattr(options, name):g}")
    try:
        parameters = options.parameters().resolved()
    except ValueError as error:
        raise fail_for_option(error, EdmdOptions) from None
    _refuse_beyond_memory(parameters)
    _say_seed(parameters.seed, drawn=options.seed is None)
    cooling = _cooling_to_the_floor(parameters)
    if cooling is not None:
        note(cooling)
    if parameters.elastic and parameters.elastic_below:  # (a sweep over restitution may reach 1: not an error)
        warn(f"--elastic-below {parameters.elastic_below:g} changes nothing: every contact is elastic already "
             "(restitution 1, no --restitution-law)")
    extra = _frame_notes(parameters, options.frame_every)
    warm_up(["edmd"], always=["edmd"])
    try:
        with progress_bar("setting up", total=100) as advance:
            run = EdmdRun(parameters, checkpoint=options.checkpoint, trajectory=options.trajectory,
                          frame_every=options.frame_every, progress=fraction_reporter(advance, 100),
                          overwrite=bool(options.overwrite))
    except (ValueError, OverlapError) as error:
        raise fail(f"cannot set up the initial state: {error}") from None
    unstable = instability_note(parameters, run.system.box)
    if unstable is not None:
        note(unstable)
    return run, extra


def _cooling_to_the_floor(parameters) -> str | None:
    """What to say before the run if an inelastic gas at rest will cool, by Haff's law, to within 100 times its
    elastic floor (kT ~ elastic_below^2, the default 1e-6 of the rms speed), and how many collisions stay above it.

    Examples
    --------
    >>> from collisionkit.edmd import EdmdParameters
    >>> print(_cooling_to_the_floor(EdmdParameters(particles=100, restitution=0.9).resolved(seed=1)))
    restitution < 1: by Haff's law these 22000 pair collisions cool kT from 1 to about 1e-12, to its elastic floor (about 1e-12, where contacts turn elastic); to follow the cooling itself give --collisions 16178 or fewer
    >>> _cooling_to_the_floor(EdmdParameters(particles=100, restitution=0.9, collisions=5000).resolved(seed=1)) is None
    True
    """
    from ..edmd import homogeneous_cooling_rate, rough_cooling_state

    p = parameters
    if p.elastic or p.shear_rate != 0.0 or p.restitution_law != "constant":  # (a law: the rate falls with kT)
        return None
    kinds = len(p.species_counts)
    law, what = "Haff's law", "restitution < 1"
    if p.tangential_restitution is not None:  # (a mixture: the least restitution's, the fastest)
        law, what = "the rough cooling state", "rough contacts"
        least = p.restitution if not isinstance(p.restitution, tuple) else min(map(min, p.restitution))
        rate = rough_cooling_state(least, p.tangential_restitution, p.inertia_factor, p.dim)[1]
    else:
        rate = homogeneous_cooling_rate(p.packing_fraction, [n / p.particles for n in p.species_counts],
                                        p.diameters or (1.0,) * kinds, p.masses or 1.0, p.restitution, p.dim)
    values = [x for row in p.restitution for x in row] if isinstance(p.restitution, tuple) else [p.restitution]
    inelastic = min(values) < 1.0  # (rough losses alone: the default floor is 0)
    floor = (p.elastic_below if p.elastic_below is not None else 1e-6 if inelastic else 0.0) ** 2
    if rate <= 0.0 or floor <= 0.0 or 100.0 * floor >= 1.0:  # (a floor near kT = 1: the run stays elastic, and
        return None                                           # its end says so)
    cooling = p.total_collisions - (p.equilibration if p.elastic_equilibration else 0)  # pair collisions that cool
    final = math.exp(-rate * 2.0 * cooling / p.particles)
    if final > 100.0 * floor:
        return None
    above = int(math.log(1.0 / (100.0 * floor)) * p.particles / (2.0 * rate)) - (
        0 if p.elastic_equilibration else p.equilibration)
    advice = (f"give --collisions {max(above, p.blocks)} or fewer" if above > p.blocks else
              "give fewer --equilibration collisions, or a higher --elastic-below floor is reached at once")
    return (f"{what}: by {law} these {cooling} pair collisions cool kT from 1 to about "
            f"{max(final, floor):.0e}, to its elastic floor (about {floor:.0e}, where contacts turn elastic); to "
            f"follow the cooling itself {advice}")


def _resumed_run(resume: Path, given: dict, extend: int | None = None):
    """The run saved in ``resume``; physics options given now must agree with it, outputs are only those given now.

    Output paths stored in the checkpoint are never used: a resumed run writes
    what this command line names, continuing its own trajectory only if it
    is named again.
    """
    from ..edmd import EdmdRun

    refuse_folder(resume, "--resume")
    physics = {key: value for key, value in given.items() if key not in OUTPUT_OPTIONS}
    try:
        run = EdmdRun.resume(resume, checkpoint=given.get("checkpoint", resume), trajectory=given.get("trajectory"),
                             frame_every=given.get("frame_every"), **physics)
    except ValueError as error:
        hint = "; to measure more, give --extend N (more pair collisions)" if str(error).startswith("collisions =") else ""
        raise fail(f"{error}{hint}") from None
    _extend(run, extend)
    outputs = {key: value for key, value in given.items() if key in OUTPUT_OPTIONS}
    outputs |= {"checkpoint": run.checkpoint, "trajectory": run.trajectory, "frame_every": run.frame_every}
    keep = [resume] + ([run.trajectory] if run.continues_trajectory else [])
    options = validate_options(EdmdOptions, run.parameters.to_dict() | outputs, keep=keep)
    _require_outputs(options, resumed_from=resume)
    _say_seed(run.parameters.seed, drawn=False)
    extra = _frame_notes(run.parameters, run.frame_every)
    warm_up(["edmd"], always=["edmd"])
    return run, options, extra


def _resume_command(options: EdmdOptions) -> str:
    """The options that continue this run as it was going: --resume and the outputs, which a checkpoint does not
    keep (a resumed run writes only what its command line names).

    Examples
    --------
    >>> _resume_command(EdmdOptions(checkpoint=Path("ck.npz"), summary=Path("u.json"), out=Path("plots")))
    'collisionkit edmd --resume ck.npz --summary u.json --out plots'
    >>> _resume_command(EdmdOptions(checkpoint=Path("my run/ck.npz"), plots=False))  # pasted into a shell as is
    "collisionkit edmd --resume 'my run/ck.npz' --no-plots"
    """
    words = ["collisionkit edmd --resume", shlex.quote(str(options.checkpoint))]
    for name in ("summary", "trajectory", "xyz"):
        if getattr(options, name) is not None:
            words += [f"--{name}", shlex.quote(str(getattr(options, name)))]
    if not options.plots:
        words.append("--no-plots")
    elif options.out != EdmdOptions.model_fields["out"].default:
        words += ["--out", shlex.quote(str(options.out))]
    return " ".join(words)


def _extend(run, extend: int | None) -> None:
    """Add the blocks ``--extend`` asks for, with a note when the count is rounded up to whole blocks."""
    if extend is None:
        if run.finished:
            note("the run was already finished: its results are reported again; --extend N measures N more "
                 "pair collisions")
        return
    added = run.extend(extend)
    length = run.parameters.collisions // run.parameters.blocks
    rounded = f" ({extend} rounded up to whole blocks of {length})" if added != extend else ""
    note(f"extending the run by {added} measured pair collisions{rounded}: {run.parameters.blocks} blocks, "
         f"{run.parameters.collisions} in all")


def _require_outputs(options: EdmdOptions, resumed_from: Path | None = None) -> None:
    """Stop before the run if an output asked for needs an extra that is not installed, or misnames its format.

    A new checkpoint must end in .npz (the format it is: a zip of arrays);
    a resumed run writes on to the checkpoint it resumed from whatever its name.
    """
    checkpoint = options.checkpoint
    new = checkpoint is not None and (resumed_from is None or checkpoint.resolve() != Path(resumed_from).resolve())
    if new and checkpoint.suffix.lower() != ".npz":
        raise fail(f"--checkpoint must end in .npz (the format it writes: a zip of arrays); got "
                   f"{str(options.checkpoint)!r}")
    if options.plots:
        require_plotting()
    if options.trajectory is not None:
        require_gsd()


def _say_seed(seed: int, drawn: bool) -> None:
    how = "drawn at random; " if drawn else ""
    note(f"seed {seed} ({how}--seed {seed} repeats this run)")


def _frame_notes(parameters, every: int | None) -> dict:
    """Say (before any work) the frame interval the chunks give; the summary's ``frame_interval_effective``."""
    if every is None:
        return {}
    intervals, frames_note = frame_intervals(parameters, every)
    if frames_note is not None:
        note(frames_note)
    return {"frame_interval_effective": intervals}


def frame_intervals(parameters, every: int) -> tuple[dict[str, int], str | None]:
    """The mean frame interval of each phase and, unless the frames fall exactly every ``every``, a note saying so.

    Frames are written at the ends of equilibration chunks and measurement
    blocks (:class:`~collisionkit.edmd.EdmdRun`): at the first end after
    each multiple of ``every``. They are exactly ``every`` apart when every
    multiple of it is such an end; otherwise a phase's frames come about
    every ``max(every, its chunk or block)`` pair collisions.

    Examples
    --------
    >>> from collisionkit.edmd import EdmdParameters
    >>> parameters = EdmdParameters(particles=500, equilibration=20_000, collisions=40_000).resolved(seed=1)
    >>> intervals, note = frame_intervals(parameters, 1000)
    >>> intervals
    {'equilibration': 10000, 'measurement': 4000}
    >>> note.split(":")[0]
    'frames are written only at the ends of equilibration chunks (10000 pair collisions) and measurement blocks (4000)'
    >>> frame_intervals(parameters, 20_000)
    ({'equilibration': 20000, 'measurement': 20000}, None)
    """
    from ..edmd.run import MIN_CHUNK

    block, start = parameters.collisions // parameters.blocks, parameters.equilibration
    phases = {"measurement": (block, start)}  # (chunk or block length, first collision of the phase)
    if start > 0:
        phases = {"equilibration": (min(max(parameters.particles, MIN_CHUNK), start), 0)} | phases
    intervals = {phase: max(every, length) for phase, (length, _) in phases.items()}
    if all(every % length == 0 and first % length == 0 for length, first in phases.values()):
        return intervals, None
    names = {"equilibration": ("equilibration chunks", " pair collisions", "equilibrating"),
             "measurement": ("measurement blocks", "", "measuring")}
    sizes = " and ".join(f"{names[phase][0]} ({length}{names[phase][1]})" for phase, (length, _) in phases.items())
    spacings = " and ".join(f"every {interval} while {names[phase][2]}" for phase, interval in intervals.items())
    return intervals, (f"frames are written only at the ends of {sizes}: --frame-every {every} gives a frame "
                       f"about {spacings}, at the first end after each multiple of {every} "
                       "(frame_interval_effective in the summary)")


# ------------------------------------------------------------------ the command


def _help(text: str, default: str | None = None) -> str:
    """Option help with its default shown (escaped from rich markup)."""
    return text if default is None else f"{text}  \\[default: {default}]"


def engine_help(thresholds: dict[int, tuple[float, ...]] | None = None, counts: tuple[int, ...] = ()) -> str:
    """The --engine help; with ``thresholds`` also the packing fractions auto takes cells below.

    ``thresholds`` (discs 2, spheres 3) hold the packing fractions at the
    numbers of particles ``counts``, the library's
    (:data:`collisionkit.edmd._cell_crossings.CELLS_BELOW_PACKING` and
    ``CELLS_BELOW_PACKING_AT``), filled in by :class:`EdmdCommand` when the
    help is shown: importing :mod:`collisionkit.edmd` (and numba) for every
    command would slow the command line's start.

    Examples
    --------
    >>> engine_help({2: (0.5, 0.3), 3: (0.27, 0.22)}, (32000, 10**6)).endswith(
    ...     "(eta < 0.27 spheres, 0.5 discs up to 32000 particles; 0.22 and 0.3 from 1000000), lists otherwise]")
    True
    """
    below = ""
    if thresholds is not None:
        below = (f" (eta < {thresholds[3][0]:g} spheres, {thresholds[2][0]:g} discs up to {counts[0]} particles; "
                 f"{thresholds[3][-1]:g} and {thresholds[2][-1]:g} from {counts[-1]})")
    return _help("Event engine: auto, lists (neighbour lists, any run) or cells (cell crossings, no lists: faster in "
                 "dilute gases; not with --shear-rate). The summary's engine is the one that ran.",
                 f"auto: cells for dilute straight flights{below}, lists otherwise")


class EdmdCommand(TyperCommand):
    """The ``edmd`` command: its help gives auto's thresholds as the library has them (see :func:`engine_help`)."""

    def format_help(self, ctx, formatter) -> None:
        """Fill the thresholds into the --engine help, then format the help as any command's."""
        from ..edmd._cell_crossings import CELLS_BELOW_PACKING, CELLS_BELOW_PACKING_AT

        for parameter in self.params:
            if parameter.name == "engine":
                parameter.help = engine_help(CELLS_BELOW_PACKING, CELLS_BELOW_PACKING_AT)
        super().format_help(ctx, formatter)


def edmd(
    dim: Annotated[int | None, typer.Option(help=_help("2 (discs) or 3 (spheres).", "3"))] = None,
    particles: Annotated[int | None, typer.Option(help=_help("Number of particles (2 to 1e8; a periodic box must be 3 diameters wide: about 16 or more at eta 0.3).", "500"))] = None,
    packing_fraction: Annotated[
        float | None, typer.Option(help=_help("Packing fraction eta: (0, 0.5] in 3D, (0, 0.7] in 2D.", "0.3"))
    ] = None,
    restitution: Annotated[float | None, typer.Option(help=_help("Coefficient of normal restitution in [0, 1]; a config file may give a matrix over the species of --fractions (restitution = [[0.9, 0.8], [0.8, 0.7]]): the summary then gives each species' temperature against the homogeneous cooling state's.", "1"))] = None,
    elastic_below: Annotated[
        float | None,
        typer.Option(help=_help("Contacts with a normal approach speed below this are elastic (0 to 1000 thermal speeds; guards inelastic runs against collapse).", "1e-6 (rms speeds) if restitution < 1")),
    ] = None,
    restitution_law: Annotated[
        str | None,
        typer.Option(metavar="[constant|bridges|viscoelastic]", help=_help("Restitution as a function of the normal approach speed u_n, the smaller of --restitution and the law's: bridges, (u_n/u_c)^-p above u_c (ice, planetary rings); viscoelastic, viscoelastic spheres, 1 - e = (u_n/u_c)^(1/5) + ... (u_c: --law-speed, p: --law-exponent). The summary compares the cooling rate with the Maxwellian one (one species).", "constant")),
    ] = None,
    law_speed: Annotated[
        float | None, typer.Option(help=_help("The law's speed u_c, in (0, 1e30] thermal speeds.", "1"))
    ] = None,
    law_exponent: Annotated[
        float | None, typer.Option(help=_help("The bridges law's exponent p, in (0, 10].", "0.234, ice"))
    ] = None,
    tangential_restitution: Annotated[
        float | None,
        typer.Option(help=_help("Rough spheres: beta in [-1, 1], the touching surfaces' tangential relative velocity after a contact over before, reversed (-1 smooth, 1 perfectly rough). The spheres spin, starting at rotational kT = 1; the summary gives the rotational temperature and T_r / T against the rough cooling state's (one species).", "smooth spheres")),
    ] = None,
    inertia_factor: Annotated[
        float | None,
        typer.Option(help=_help("Rough spheres' moment of inertia over m a^2, in (0, 1].", "2/5 for spheres, 1/2 for discs")),
    ] = None,
    friction: Annotated[
        float | None,
        typer.Option(help=_help("Rough spheres' Coulomb friction mu in (0, 100] (Walton's model): a contact sticks, or slides when its tangential impulse would pass mu times the normal one.", "no limit")),
    ] = None,
    initial_rotational_temperature: Annotated[
        float | None,
        typer.Option(help=_help("Rough spheres' rotational kT at the start, 0 to 100 (0: no spin).", "1, equipartition")),
    ] = None,
    equilibration: Annotated[
        int | None, typer.Option(help=_help("Pair collisions before measuring (0 to 1e14); each takes two particles, so C = 2 pairs / N collisions per particle.", "20 N: C = 40"))
    ] = None,
    elastic_equilibration: Annotated[
        bool | None,
        typer.Option("--elastic-equilibration/--inelastic-equilibration",
                     help=_help("Equilibrate with every contact elastic and smooth: a cooling run starts at kT = 1 when the measurement begins.", "inelastic: the equilibration cools too")),
    ] = None,
    collisions: Annotated[
        int | None,
        typer.Option(help=_help("Pair collisions measured (>= blocks, at most 1e14; rounded down to a multiple of blocks).", "200 N: C = 400")),
    ] = None,
    blocks: Annotated[int | None, typer.Option(help=_help("Measurement blocks for the error bars (2 to 100000).", "10"))] = None,
    seed: Annotated[int | None, typer.Option(help=_help("Random seed (>= 0).", "random, reported"))] = None,
    initial: Annotated[
        str | None,
        typer.Option(
            help=_help("random (compressed fluid), fcc, sc (3D), square, hexagonal (2D); a lattice needs N = basis * cells^d.", "random")
        ),
    ] = None,
    transport: Annotated[
        bool | None,
        typer.Option("--transport/--no-transport",
                     help=_help("Also measure shear and bulk viscosity, thermal conductivity and self-diffusion (Einstein-Helfand moments; units sigma, m, kT), the pressure tensor and the velocity autocorrelation; needs restitution 1.", "no transport; with it the default --collisions is 2000 N")),
    ] = None,
    yeh_hummer: Annotated[
        bool | None,
        typer.Option("--yeh-hummer/--no-yeh-hummer",
                     help=_help("With --transport in 3D: also report D corrected to the infinite system (Yeh-Hummer, from the measured shear viscosity).", "no")),
    ] = None,
    shear_rate: Annotated[
        float | None,
        typer.Option(help=_help("Lees-Edwards shear at rate G (0 to 1000, in sqrt(kT/m)/sigma; flow x, gradient y): reports the shear stress and shear_viscosity = -P_xy / G.", "0, no shear")),
    ] = None,
    thermostat: Annotated[
        bool | None,
        typer.Option("--thermostat/--no-thermostat",
                     help=_help("With --shear-rate: hold kT = 1 by rescaling the velocities relative to the flow every 4 N pair collisions.", "no")),
    ] = None,
    engine: Annotated[
        str | None,
        typer.Option(metavar="[auto|lists|cells]", help=engine_help()),
    ] = None,
    well_width: Annotated[
        float | None,
        typer.Option(help=_help("Square wells: each pair attracts with depth --well-depth out to this many contact distances (lambda in (1, 5]). The equilibration holds kT = 1 by rescaling; the measurement runs at constant energy and reports the mean potential energy per particle and the mean kT (--transport: the coefficients at that kT, the heat flux carrying the pairs' potential energy); not with --shear-rate or --engine cells.", "none, hard spheres")),
    ] = None,
    well_depth: Annotated[
        float | None,
        typer.Option(help=_help("Depth epsilon of the square wells in units of kT (0 to 1000): the reduced temperature is T* = 1 / depth.", "1")),
    ] = None,
    fractions: Annotated[
        list[float] | None,
        typer.Option(help=_help("A mixture: the number fraction of each species (repeat: --fractions 0.5 --fractions 0.5; summing to 1). Needs --initial random; the summary compares Z with the BMCSL (spheres) or SYH (discs) equation of state.", "one species")),
    ] = None,
    diameters: Annotated[
        list[float] | None,
        typer.Option(help=_help("With --fractions: each species' diameter (repeat), relative to the largest, which is 1 (the others 0.1 to 1).", "all 1")),
    ] = None,
    masses: Annotated[
        list[float] | None,
        typer.Option(help=_help("With --fractions: each species' mass (repeat), 1e-3 to 1e3.", "all 1")),
    ] = None,
    summary: Annotated[Path | None, typer.Option("--summary", help="Write the results as JSON to this file.")] = None,
    trajectory: Annotated[
        Path | None, typer.Option(help="Write frames to this GSD file (HOOMD, OVITO, freud read it).")
    ] = None,
    frame_every: Annotated[
        int | None,
        typer.Option(help=_help("A frame at the first chunk or block end after every N pair collisions (a note says the interval this gives).", "only the last frame")),
    ] = None,
    xyz: Annotated[Path | None, typer.Option(help="Write the final state as extended XYZ (ASE, OVITO).")] = None,
    out: Annotated[Path | None, typer.Option(help=_help("Folder for the plots and, with them, blocks.csv (a row per block: C, time, kT, Z, collision frequency, a2, T_r/T, the shear modes' energy, ...).", "edmd-output"))] = None,
    plots: Annotated[bool | None, typer.Option("--plots/--no-plots", help=_help("Write plots.", "plots"))] = None,
    checkpoint: Annotated[
        Path | None, typer.Option(help="Write the full state to this .npz after every chunk (atomically).")
    ] = None,
    resume: Annotated[
        Path | None,
        typer.Option(help="Continue the run saved in this checkpoint, with its physics; checkpoints go on to it unless --checkpoint is given. Other outputs are only those given now (name its --trajectory again to continue it)."),
    ] = None,
    extend: Annotated[
        int | None,
        typer.Option(min=1, help="With --resume: measure N more pair collisions (whole blocks of the run's block length), also after a finished run."),
    ] = None,
    config: Annotated[
        Path | None, typer.Option("--config", help="TOML file with these options (command line wins).")
    ] = None,
    overwrite: OverwriteOption = None,
):
    """Event-driven MD of hard spheres (3D) or discs (2D), their mixtures (--fractions), or square-well fluids (--well-width): pressure, collision frequency, g(r), diffusion; viscosity and thermal conductivity with --transport.

    Units: diameter 1 (the largest species'), mass 1, initial kT = 1.
    """
    given = dict(
        dim=dim, particles=particles, packing_fraction=packing_fraction, restitution=restitution,
        elastic_below=elastic_below, restitution_law=restitution_law, law_speed=law_speed, law_exponent=law_exponent, tangential_restitution=tangential_restitution, inertia_factor=inertia_factor, friction=friction, initial_rotational_temperature=initial_rotational_temperature, equilibration=equilibration, elastic_equilibration=elastic_equilibration, collisions=collisions, blocks=blocks, seed=seed, initial=initial,
        transport=transport, yeh_hummer=yeh_hummer, shear_rate=shear_rate, thermostat=thermostat, engine=engine, well_width=well_width, well_depth=well_depth, fractions=fractions, diameters=diameters, masses=masses, summary=summary, trajectory=trajectory, frame_every=frame_every, xyz=xyz, out=out, plots=plots,
        checkpoint=checkpoint, overwrite=overwrite,
    )  # fmt: skip
    if resume is None:
        if extend is not None:
            raise fail("--extend needs --resume FILE: the checkpoint of the run to go on with")
        options = load_options(EdmdOptions, config, given)
        run, extra = _new_run(options)
    else:
        run, options, extra = _resumed_run(resume, option_values(EdmdOptions, config, given), extend)
    where = (f"the last checkpoint is in {options.checkpoint}; continue with {_resume_command(options)}"
             if options.checkpoint is not None else "no --checkpoint was given, so nothing is saved")
    try:
        with progress_bar("collisions", total=run.parameters.total_collisions) as advance:
            run.run(progress=fraction_reporter(advance, run.parameters.total_collisions))
    except FileLockedError as locked:
        raise fail(f"{locked}: another collisionkit run is writing it; wait for it or name other files") from None
    except KeyboardInterrupt:
        warn(f"interrupted: {where}")
        raise typer.Exit(INTERRUPTED_EXIT_CODE) from None
    except (OSError, RuntimeError) as failure:  # RuntimeError: the engine's watchdogs (collapse, no collision)
        raise run_failed(f"the run stopped: {failure}; {where}") from None
    report(run, options, extra)


def register(app: typer.Typer) -> None:
    """Add the ``edmd`` command to the ``collisionkit`` app."""
    app.command("edmd", cls=EdmdCommand)(edmd)
