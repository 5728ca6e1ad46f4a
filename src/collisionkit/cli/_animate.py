"""The ``animate`` subcommand: an EDMD trajectory or a two-body encounter as a GIF or MP4."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated, ClassVar, Literal

import typer
from pydantic import Field

from ._common import (
    Deliveries, Options, OverwriteOption, check_input_file, fail, fail_for_option, load_options, progress_bar, require,
    require_gsd,
    run_failed, say, warn,
)
from ._files import rescue_path

ColourName = Literal["speed", "species", "none"]
ENCOUNTER_KEYS = ("m1", "m2", "rp", "vinf", "sep0")
ENCOUNTER_DEFAULTS = {"m1": 1.0, "m2": 1.0, "rp": 1.0, "vinf": 0.5, "sep0": 10.0}


class AnimateOptions(Options):
    """Options of ``collisionkit animate``: one input (a trajectory, initial conditions or encounter values).

    Examples
    --------
    >>> AnimateOptions(m1=2.0, out="flyby.mp4").out.suffix
    '.mp4'
    """

    trajectory: Path | None = None
    initial_conditions: Path | None = None
    m1: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    m2: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    rp: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    vinf: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    sep0: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    out: Path = Path("animation.gif")
    colour: ColourName = "speed"
    fps: int = Field(default=20, ge=1, le=60)
    frames: int = Field(default=80, ge=2, le=5000)
    every: int = Field(default=1, ge=1)
    dpi: int = Field(default=80, ge=20, le=300)
    summary: Path | None = None

    output_files: ClassVar[tuple[str, ...]] = ("summary", "out")


def _check_output(options: AnimateOptions) -> str:
    """The output format ('gif' or 'mp4'); an input error for anything else or MP4 without ffmpeg."""
    from ..plotting import ffmpeg_available

    suffix = options.out.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise fail(f"--out must end in .gif or .mp4; got {str(options.out)!r}")
    if suffix == ".mp4" and not ffmpeg_available():
        raise fail(
            "writing MP4 needs ffmpeg, which matplotlib cannot find on this machine: "
            "install ffmpeg (e.g. apt-get install ffmpeg) or write a .gif (Pillow, always available)"
        )
    return suffix[1:]


def _source(options: AnimateOptions) -> str:
    """Which input to animate: 'trajectory', 'initial_conditions' or 'encounter' (exactly one)."""
    given = []
    if options.trajectory is not None:
        given.append("trajectory")
    if options.initial_conditions is not None:
        given.append("initial_conditions")
    if any(getattr(options, key) is not None for key in ENCOUNTER_KEYS):
        given.append("encounter")
    if not given:
        raise fail(
            "nothing to animate: give --trajectory FILE.gsd (from collisionkit edmd), "
            "--initial-conditions FILE.json (from collisionkit encounter) or encounter options --m1 --m2 --rp --vinf --sep0"
        )
    if len(given) > 1:
        names = {"trajectory": "--trajectory", "initial_conditions": "--initial-conditions", "encounter": "--m1/--m2/--rp/--vinf/--sep0"}
        raise fail(f"give only one input to animate; got {' and '.join(names[item] for item in given)}")
    return given[0]


def _trajectory_animation(options: AnimateOptions):
    """The animation of a GSD trajectory, with a warning if the file holds a single frame."""
    from .. import plotting, trajectory

    path = options.trajectory
    try:
        frames = trajectory.read_gsd_frames(path, every=options.every, max_frames=options.frames)
        animation = plotting.animate_frames(frames, colour_by=options.colour)
    except ImportError as error:
        raise fail(str(error)) from None
    except (OSError, RuntimeError, ValueError, KeyError) as error:
        raise fail(f"cannot read the GSD trajectory {path}: {error}") from None
    if frames[0]["frames"] == 1:
        message = (f"{path} holds a single frame, so the animation is a still picture; "
                   "'collisionkit edmd --trajectory FILE.gsd --frame-every N' writes a frame every N pair collisions")
        warn(message)
    return animation


def _encounter_parameters(options: AnimateOptions, source: str) -> dict:
    if source == "encounter":
        values = {key: getattr(options, key) for key in ENCOUNTER_KEYS}
        return {key: ENCOUNTER_DEFAULTS[key] if value is None else value for key, value in values.items()}
    path = options.initial_conditions
    try:
        data = json.loads(path.read_text())
    except FileNotFoundError:
        raise fail(f"initial-conditions file not found: {path}") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        raise fail(f"initial-conditions file {path} is not valid JSON: {error}") from None
    if isinstance(data, dict) and isinstance(data.get("initial_conditions"), dict):
        data = data["initial_conditions"]  # a --summary file of collisionkit encounter
    missing = [key for key in ENCOUNTER_KEYS if not isinstance(data, dict) or key not in data]
    if missing:
        raise fail(f"initial-conditions file {path} lacks {', '.join(missing)} (write it with collisionkit encounter)")
    parameters = {key: data[key] for key in ENCOUNTER_KEYS}
    parameters["G"] = data.get("G", 1.0)
    parameters["layout"] = data.get("layout", "diagonal")
    return parameters


def _encounter_animation(options: AnimateOptions, source: str):
    import warnings

    from .. import plotting
    from ..encounters import GridExitWarning, starcrash_initial_conditions

    p = _encounter_parameters(options, source)
    if not all(isinstance(p[key], (int, float)) and not isinstance(p[key], bool) for key in ENCOUNTER_KEYS):
        raise fail(f"m1, m2, rp, vinf and sep0 must be numbers; got {', '.join(repr(p[key]) for key in ENCOUNTER_KEYS)}")
    if p["sep0"] < p["rp"]:
        raise fail(f"sep0 must be >= rp (the bodies start outside periastron); got sep0={p['sep0']}, rp={p['rp']}")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GridExitWarning)  # the grid is irrelevant to a picture
        try:
            ic = starcrash_initial_conditions(
                p["m1"], p["m2"], p["rp"], p["vinf"], p["sep0"], G=p.get("G", 1.0), layout=p.get("layout", "diagonal")
            )
        except (TypeError, ValueError) as error:
            raise fail_for_option(error, AnimateOptions, {"v_inf": "vinf"}) from None
    return plotting.animate_encounter(ic, frames=options.frames, colour_by=options.colour)


def animate(
    trajectory: Annotated[
        Path | None, typer.Option(help="GSD trajectory to animate (collisionkit edmd --trajectory).")
    ] = None,
    initial_conditions: Annotated[
        Path | None,
        typer.Option(help="Encounter to animate: initial_conditions.json or the --summary JSON of collisionkit encounter."),
    ] = None,
    m1: Annotated[float | None, typer.Option("--m1", help="Encounter: mass of body 1 (> 0).  \\[default: 1]")] = None,
    m2: Annotated[float | None, typer.Option("--m2", help="Encounter: mass of body 2 (> 0).  \\[default: 1]")] = None,
    rp: Annotated[float | None, typer.Option("--rp", help="Encounter: periastron distance (> 0).  \\[default: 1]")] = None,
    vinf: Annotated[
        float | None, typer.Option("--vinf", help="Encounter: relative speed at infinity (> 0).  \\[default: 0.5]")
    ] = None,
    sep0: Annotated[
        float | None, typer.Option("--sep0", help="Encounter: initial and final separation (>= rp).  \\[default: 10]")
    ] = None,
    out: Annotated[
        Path | None, typer.Option(help="Output file, .gif (Pillow) or .mp4 (needs ffmpeg).  \\[default: animation.gif]")
    ] = None,
    colour: Annotated[
        str | None, typer.Option(help="Colour particles by speed, species (type or body) or none.  \\[default: speed]")
    ] = None,
    fps: Annotated[int | None, typer.Option(help="Frames per second (1 to 60).  \\[default: 20]")] = None,
    frames: Annotated[
        int | None, typer.Option(help="Frames of an encounter; most frames read from a trajectory (2 to 5000).  \\[default: 80]")
    ] = None,
    every: Annotated[int | None, typer.Option(help="Trajectory: use every n-th frame (>= 1).  \\[default: 1]")] = None,
    dpi: Annotated[int | None, typer.Option(help="Resolution of the frames (20 to 300).  \\[default: 80]")] = None,
    summary: Annotated[Path | None, typer.Option("--summary", help="Write the results as JSON to this file.")] = None,
    config: Annotated[Path | None, typer.Option("--config", help="TOML file with these options (command line wins).")] = None,
    overwrite: OverwriteOption = None,
):
    """Turn an EDMD trajectory (GSD) or a two-body encounter into a GIF or MP4 animation."""
    given = dict(
        trajectory=trajectory, initial_conditions=initial_conditions, m1=m1, m2=m2, rp=rp, vinf=vinf, sep0=sep0,
        out=out, colour=colour, fps=fps, frames=frames, every=every, dpi=dpi, summary=summary, overwrite=overwrite,
    )  # fmt: skip
    options = load_options(AnimateOptions, config, given)
    require("matplotlib", "plot", "an animation")
    if options.trajectory is not None:
        require_gsd()
    check_input_file(options.trajectory, "--trajectory")  # after the extras: a missing package is said first
    check_input_file(options.initial_conditions, "--initial-conditions")
    import matplotlib

    matplotlib.use("Agg")
    file_format = _check_output(options)
    source = _source(options)
    if source == "trajectory":
        animation = _trajectory_animation(options)
    else:
        animation = _encounter_animation(options, source)
    total = int(animation._save_count) if getattr(animation, "_save_count", None) else options.frames
    path = _save(animation, options, file_format, total)
    result = {
        "source": source,
        "input": str(options.trajectory or options.initial_conditions or ""),
        "out": str(path),
        "format": file_format,
        "frames": total,
        "fps": options.fps,
        "colour": options.colour,
    }
    say(f"wrote {path} ({total} frame{'' if total == 1 else 's'})")
    deliveries = Deliveries("animate")
    if path != options.out:
        deliveries.failures.append(f"the animation {options.out}")
    deliveries.finish(options.summary, result)


def _save(animation, options: AnimateOptions, file_format: str, total: int) -> Path:
    """Save the animation to ``--out``; if that fails, to a new file of the current (or temporary) folder.

    The summary's ``out`` then names where it went, and the command ends with 1.
    """
    from .. import plotting

    def save(path: Path) -> Path:
        with progress_bar(f"animate ({file_format})", total=total) as advance:
            return plotting.save_animation(animation, path, fps=options.fps, dpi=options.dpi,
                                           progress=lambda index, count: advance())

    try:
        return save(options.out)
    except OSError as failure:
        rescued = rescue_path("animate", options.out.suffix)
        if rescued is None:
            raise run_failed(f"cannot write {options.out} ({failure.strerror or failure}), nor a file in the "
                             "current or the temporary folder") from None
        warn(f"cannot write {options.out} ({failure.strerror or failure}): saving the animation in {rescued}")
        return save(rescued)


def register(app: typer.Typer) -> None:
    """Add the ``animate`` command to the ``collisionkit`` app."""
    app.command("animate")(animate)
