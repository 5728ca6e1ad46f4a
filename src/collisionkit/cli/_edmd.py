"""The ``edmd`` subcommand: event-driven molecular dynamics of hard spheres or discs.

The run is a fixed, deterministic sequence of chunks: equilibration in
chunks of ``max(N, 10^4)`` pair collisions, then ``blocks`` measurement
blocks of ``collisions // blocks``. A checkpoint is written atomically after
set-up and after every chunk and block, so a run resumed from it continues
bit for bit as if it had never stopped. Trajectory frames are written at
chunk and block ends (they never change the dynamics).
"""

from __future__ import annotations

import io
import json
import math
import secrets
import zipfile
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, ClassVar, Literal

import numpy as np
import typer
from pydantic import Field, ValidationError, model_validator

from .._io import atomic_write_bytes
from ..edmd.theory import MAX_PACKING_FRACTION as MAX_PACKING
from ._common import (
    INTERRUPTED_EXIT_CODE, Options, console, fail, load_options, print_table, progress_bar,
    refuse_to_overwrite_checkpoint, require_gsd, require_plotting, warn, write_summary,
)

if TYPE_CHECKING:  # the engine (numba) is imported only when a run starts
    from ..edmd import HardSphereSystem, Sampler

InitialName = Literal["random", "fcc", "sc", "square", "hexagonal"]

PHYSICS_OPTIONS = (
    "dim", "particles", "packing_fraction", "restitution", "elastic_below", "equilibration", "collisions", "blocks",
    "seed", "initial",
)  # fmt: skip
LATTICE_DIM = {"fcc": 3, "sc": 3, "square": 2, "hexagonal": 2}
LATTICE_BASIS = {"fcc": 4, "sc": 1, "square": 1, "hexagonal": 2}
EQUILIBRATION_PER_PARTICLE = 20
COLLISIONS_PER_PARTICLE = 200
MIN_CHUNK = 10_000
CHECKPOINT_FORMAT = 1
OUTPUT_SUFFIXES = {"trajectory": (".gsd",), "xyz": (".xyz", ".extxyz")}  # the formats --trajectory and --xyz write


class EdmdOptions(Options):
    """Options of ``collisionkit edmd``; None for equilibration, collisions and seed means "per particle" / random."""

    dim: Literal[2, 3] = 3
    particles: int = Field(default=500, ge=2, le=100_000_000)
    packing_fraction: float = Field(default=0.3, gt=0, le=0.7, allow_inf_nan=False)
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
        """The rules that tie options together; here, so a sweep checks every point before it starts."""
        limit = MAX_PACKING[self.dim]
        if self.packing_fraction > limit:
            raise ValueError(f"packing_fraction must lie in (0, {limit}] for dim={self.dim}; got {self.packing_fraction}")
        if self.initial != "random":
            _lattice_cells(self)
        if self.collisions is not None and self.collisions < self.blocks:
            raise ValueError(f"collisions must be >= blocks ({self.blocks}); got {self.collisions}")
        if self.frame_every is not None and self.trajectory is None:
            raise ValueError("--frame-every needs --trajectory FILE.gsd to write the frames to")
        for name, suffixes in OUTPUT_SUFFIXES.items():
            path = getattr(self, name)
            if path is not None and path.suffix.lower() not in suffixes:
                raise ValueError(f"--{name} must end in {' or '.join(suffixes)} (the format it writes); got {str(path)!r}")
        return self


# ------------------------------------------------------------------ options


def _lattice_cells(options: EdmdOptions) -> int:
    """Unit cells per axis of the chosen lattice; fails unless N = basis * cells^d."""
    kind, dim = options.initial, options.dim
    if LATTICE_DIM[kind] != dim:
        raise ValueError(f"--initial {kind} is a {LATTICE_DIM[kind]}D lattice; it cannot start a run with --dim {dim}")
    basis = LATTICE_BASIS[kind]
    cells = max(1, round((options.particles / basis) ** (1.0 / dim)))
    if basis * cells**dim != options.particles:
        examples = ", ".join(str(basis * n**dim) for n in range(3, 7))
        raise ValueError(
            f"--initial {kind} needs particles = {basis} * cells^{dim} (e.g. {examples}); got {options.particles}"
        )
    return cells


def _resolve(options: EdmdOptions) -> EdmdOptions:
    """Fill in the defaults that depend on other options (the model checked the rest)."""
    defaults = dict(
        equilibration=EQUILIBRATION_PER_PARTICLE * options.particles,
        collisions=COLLISIONS_PER_PARTICLE * options.particles,
        seed=secrets.randbits(32),
    )
    resolved = options.model_copy(update={key: value for key, value in defaults.items() if getattr(options, key) is None})
    if resolved.collisions < resolved.blocks:
        raise fail(f"collisions ({resolved.collisions} by default for {options.particles} particles) must be >= "
                   f"blocks ({resolved.blocks}); set --collisions")
    return resolved


def _require_outputs(options: EdmdOptions) -> None:
    """Stop before the run if an output asked for needs an extra that is not installed."""
    if options.plots:
        require_plotting()
    if options.trajectory is not None:
        require_gsd()


def _resumed_options(options: EdmdOptions, saved: dict, resume: Path) -> EdmdOptions:
    """The checkpoint's options, with the output options given now; physics options must agree."""
    given = options.model_fields_set
    for key in PHYSICS_OPTIONS:
        if key in given and getattr(options, key) != saved.get(key):
            raise fail(
                f"{key} = {getattr(options, key)!r} differs from the checkpoint {resume} ({key} = {saved.get(key)!r}); "
                "a resumed run keeps the physics options it started with"
            )
    merged = saved | {key: getattr(options, key) for key in given}
    merged["checkpoint"] = options.checkpoint if "checkpoint" in given else resume
    try:
        return EdmdOptions.model_validate(merged)
    except ValidationError as error:
        raise fail(f"the options saved in {resume} are not valid: {error}") from None


# ------------------------------------------------------------------ the run state


@dataclass
class _Run:
    """Everything a checkpoint holds: the system, the sampler and the progress counters."""

    options: EdmdOptions
    system: HardSphereSystem
    sampler: Sampler | None
    equilibrated: int = 0
    frames: int = 0
    last_frame: int = -1
    initial_energy: float = math.nan

    @property
    def measured(self) -> int:
        return 0 if self.sampler is None else self.sampler.done * self.sampler.per_block


def _share_reporter(advance, steps):
    """A progress callback taking fractions done, advancing a bar by that share of ``steps``."""
    reported = 0

    def report(fraction):
        nonlocal reported
        share = round(steps * fraction)
        advance(share - reported)
        reported = share

    return report


def _initial_system(options: EdmdOptions) -> HardSphereSystem:
    from .. import edmd

    if options.initial == "random":
        with progress_bar("compressing", total=100) as advance:
            report = _share_reporter(advance, 100)
            fluid = edmd.random_fluid(options.dim, options.particles, options.packing_fraction, seed=options.seed, progress=report)
        positions, velocities, box = fluid.positions(), fluid.velocities(), fluid.box[: options.dim]
    else:
        positions, box = edmd.lattice(options.initial, _lattice_cells(options), options.packing_fraction)
        velocities = edmd.maxwell_boltzmann(np.ones(options.particles), options.dim, kT=1.0, seed=options.seed)
    return edmd.HardSphereSystem(positions, velocities, 0.5, box, restitution=options.restitution,
                                 elastic_below=options.elastic_below)


def _new_run(options: EdmdOptions) -> _Run:
    from ..edmd import OverlapError

    try:
        system = _initial_system(options)
    except (ValueError, OverlapError) as error:
        raise fail(f"cannot set up the initial state: {error}") from None
    return _Run(options, system, None, initial_energy=system.kinetic_energy())


def save_checkpoint(path: Path, run: _Run) -> Path:
    """Write the run's full state to ``path`` (.npz) atomically."""
    state = dict(run.system.state_dict())
    if run.sampler is not None:
        state |= run.sampler.state_dict()
    state |= {
        "run_format": np.asarray(CHECKPOINT_FORMAT),
        "run_options": np.asarray(run.options.model_dump_json()),
        "run_counters": np.array([run.equilibrated, run.frames, run.last_frame], dtype=np.int64),
        "run_initial_energy": np.asarray(run.initial_energy),
    }
    buffer = io.BytesIO()
    np.savez(buffer, **state)
    return atomic_write_bytes(path, buffer.getvalue())


def load_checkpoint(path: Path) -> tuple[dict, dict]:
    """The saved options (a dict) and the arrays of a checkpoint written by :func:`save_checkpoint`."""
    if Path(path).is_file() and not zipfile.is_zipfile(path):  # numpy would talk of pickles
        raise fail(f"{path} is not a checkpoint: an .npz file written by collisionkit edmd --checkpoint")
    try:
        with np.load(path, allow_pickle=False) as data:
            state = {name: data[name] for name in data.files}
    except FileNotFoundError:
        raise fail(f"checkpoint not found: {path}") from None
    except (OSError, ValueError) as error:
        raise fail(f"{path} is not a readable checkpoint: {error}") from None
    if "run_format" not in state or int(state["run_format"]) != CHECKPOINT_FORMAT:
        raise fail(f"{path} is not a checkpoint of 'collisionkit edmd' (format {CHECKPOINT_FORMAT})")
    return json.loads(str(state["run_options"])), state


def _restore(options: EdmdOptions, state: dict) -> _Run:
    from ..edmd import HardSphereSystem, Sampler

    try:
        system = HardSphereSystem.from_state_dict(state)
    except ValueError as error:  # written by another engine version
        raise fail(f"cannot resume: {error}") from None
    sampler = Sampler.from_state_dict(system, state) if "sampler_scalars" in state else None
    equilibrated, frames, last_frame = (int(value) for value in state["run_counters"])
    return _Run(options, system, sampler, equilibrated, frames, last_frame, float(state["run_initial_energy"]))


# ------------------------------------------------------------------ running


class _Outputs:
    """The trajectory and checkpoint written as the run goes."""

    def __init__(self, run: _Run, append_frames: bool):
        self.run = run
        self.writer = None
        path = run.options.trajectory
        if path is not None:
            from ..trajectory import GSDWriter, truncate_gsd

            if append_frames and path.exists():
                run.frames = truncate_gsd(path, run.frames)
            else:
                run.frames = 0
            self.writer = GSDWriter(path, mode="a" if append_frames else "w")

    def frame(self, final=False):
        run, every = self.run, self.run.options.frame_every
        step = run.system.collisions
        if self.writer is None or step == run.last_frame:
            return
        due = every is not None and (run.last_frame < 0 or step // every > run.last_frame // every)
        if due or final:
            self.writer.write(run.system, step)
            run.frames += 1
            run.last_frame = step

    def chunk_done(self):
        self.frame()
        if self.run.options.checkpoint is not None:
            save_checkpoint(self.run.options.checkpoint, self.run)

    def close(self):
        if self.writer is not None:
            self.writer.close()


def _execute(run: _Run, outputs: _Outputs, advance) -> None:
    """Finish the equilibration chunks and the measurement blocks still to do."""
    from ..edmd import Sampler

    options, system = run.options, run.system
    chunk = max(options.particles, MIN_CHUNK)
    while run.equilibrated < options.equilibration:
        step = min(chunk, options.equilibration - run.equilibrated)
        done = system.run(collisions=step, progress=_share_reporter(advance, step))
        if done == 0:
            raise RuntimeError("the system stopped colliding during equilibration")
        run.equilibrated += done
        outputs.chunk_done()
    if run.sampler is None:
        run.sampler = Sampler(system, options.collisions, options.blocks)
    while not run.sampler.finished:
        run.sampler.run_block(_share_reporter(advance, run.sampler.per_block))
        outputs.chunk_done()


def _total_collisions(options: EdmdOptions) -> int:
    return options.equilibration + (options.collisions // options.blocks) * options.blocks


# ------------------------------------------------------------------ results


def _theory(dim: int):
    from .. import edmd

    return ("Hansen-Goos (2016)", edmd.hansen_goos) if dim == 3 else ("Henderson (1975)", edmd.henderson)


def _in_sigmas(difference: float, error: float) -> float:
    return difference / error if error > 0 else math.nan


def _results(run: _Run, measurement) -> dict:
    from .. import edmd

    options, system = run.options, run.system
    result = measurement.summary()
    result |= {
        "initial": options.initial,
        "restitution": options.restitution,
        "seed": options.seed,
        "blocks": options.blocks,
        "equilibration_collisions": run.equilibrated,
        "energy_lost_total": run.initial_energy - system.kinetic_energy(),
        "elastic": options.restitution == 1.0,
        "elastic_below": system.elastic_below,
    }
    if options.restitution == 1.0:
        name, equation = _theory(options.dim)
        eta, Z = measurement.packing_fraction, measurement.compressibility_factor
        theory = float(equation(eta))
        result |= {
            "theory": name,
            "compressibility_factor_theory": theory,
            "compressibility_factor_relative_deviation": Z / theory - 1.0,
            "compressibility_factor_deviation_sigmas": _in_sigmas(Z - theory, measurement.compressibility_factor_error),
            "collision_frequency_from_pressure": float(
                edmd.enskog_collision_frequency(Z, options.dim, kT=measurement.temperature)
            ),
            "collision_frequency_theory": float(edmd.enskog_collision_frequency(theory, options.dim, kT=1.0)),
        }
        if options.dim == 3:
            result["compressibility_factor_carnahan_starling"] = float(edmd.carnahan_starling(eta))
    result["options"] = options.model_dump(mode="json")
    return result


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


def _plots(run: _Run, measurement, result: dict) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    from .. import plotting

    out, system = run.options.out, run.system
    out.mkdir(parents=True, exist_ok=True)
    files = []
    if result["elastic"]:
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


def _cooling_note(system: HardSphereSystem) -> str:
    """What an inelastic run's averages mean: the gas cooled (Haff's law), maybe down to the elastic floor."""
    kT = system.temperature()
    note = (f"restitution < 1: the gas cooled as it ran (homogeneous cooling, Haff's law), kT from 1 to {kT:.3g}; "
            "Z, the collision frequency and D are averages over a cooling state, not equilibrium values")
    if system.elastic_below > 0 and kT < 100.0 * system.elastic_below**2:
        note += (f". It reached the elastic floor: contacts slower than --elastic-below {system.elastic_below:.3g} "
                 "are elastic (against inelastic collapse), so fewer --collisions follow the cooling itself")
    return note


def _report(run: _Run) -> None:
    options = run.options
    measurement = run.sampler.result()
    result = _results(run, measurement)
    files = []
    if options.xyz is not None:
        from ..trajectory import write_extended_xyz

        files.append(write_extended_xyz(options.xyz, run.system, comment=f"collisionkit edmd seed {options.seed}"))
    if options.trajectory is not None:
        files.append(options.trajectory)
        result["trajectory_frames"] = run.frames
    if options.plots:
        files.extend(_plots(run, measurement, result))
    result["files"] = [str(path) for path in files]
    kind = "spheres" if options.dim == 3 else "discs"
    title = (
        f"EDMD: {options.particles} hard {kind}, eta = {options.packing_fraction:g}, "
        f"e = {options.restitution:g}, seed {options.seed}"
    )
    print_table(title, ("quantity", "measured", "theory"), _rows(result))
    if options.restitution < 1.0:
        warn(_cooling_note(run.system))
    write_summary(options.summary, result)
    for path in files:
        console.print(f"wrote {path}")


# ------------------------------------------------------------------ the command


def _same_file(path: Path | None, saved: str | None) -> bool:
    return path is not None and saved is not None and path.resolve() == Path(saved).resolve()


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
    options = load_options(EdmdOptions, config, given)
    if resume is not None:
        saved, state = load_checkpoint(resume)
        options = _resumed_options(options, saved, resume)
        _require_outputs(options)
        run = _restore(options, state)
        appending = _same_file(options.trajectory, saved.get("trajectory"))
    else:
        options = _resolve(options)
        refuse_to_overwrite_checkpoint(options.checkpoint)
        _require_outputs(options)
        run = _new_run(options)
        appending = False
    outputs = _Outputs(run, append_frames=appending)
    try:
        if resume is None:
            outputs.chunk_done()  # the initial state: a frame (with --frame-every) and a checkpoint
        with progress_bar("collisions", total=_total_collisions(options)) as advance:
            advance(run.equilibrated + run.measured)
            _execute(run, outputs, advance)
        outputs.frame(final=True)
    except KeyboardInterrupt:
        where = (f"the last checkpoint is in {options.checkpoint}; continue with --resume {options.checkpoint}"
                 if options.checkpoint is not None else "no --checkpoint was given, so nothing is saved")
        warn(f"interrupted: {where}")
        raise typer.Exit(INTERRUPTED_EXIT_CODE) from None
    finally:
        outputs.close()
    _report(run)


def register(app: typer.Typer) -> None:
    """Add the ``edmd`` command to the ``collisionkit`` app."""
    app.command("edmd")(edmd)
