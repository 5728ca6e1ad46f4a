"""The ``slab`` subcommand: transmission and reflection of a beam by a scattering slab (Krasov, sec. 5.5)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, ClassVar, Literal

import typer
from pydantic import Field, field_validator, model_validator

from .._io import FileLockedError
from ._common import (
    INTERRUPTED_EXIT_CODE, Options, OverwriteOption, fail, fraction_reporter, load_options, note, option_values,
    print_table, progress_bar, refuse_folder, validate_options, warn, write_summary,
)
from ._transport import refuse_checkpoint_suffix
from ._warmup import warm_up

SLAB_OUTPUTS = ("summary", "checkpoint", "overwrite")  # what a resumed run may change; the rest is physics


class SlabOptions(Options):
    """Options of ``collisionkit slab``; the physics is :class:`collisionkit.transport.SlabParameters`.

    Examples
    --------
    >>> SlabOptions.model_validate({"thickness": 2, "mass-ratio": None}).mass_ratio
    inf
    """

    thickness: float = Field(default=1.0, ge=0, le=1e4, allow_inf_nan=False)
    albedo: float = Field(default=1.0, ge=0, le=1)
    incidence: Literal["normal", "isotropic"] = "normal"
    model: Literal["isotropic", "rod"] = "isotropic"
    mass_ratio: float = Field(default=float("inf"), ge=1)
    particles: int = Field(default=100_000, ge=64, le=1_000_000_000)
    seed: int = Field(default=2026, ge=0)
    summary: Path | None = None
    checkpoint: Path | None = None

    output_files: ClassVar[tuple[str, ...]] = ("summary", "checkpoint")

    @field_validator("mass_ratio", mode="before")
    @classmethod
    def _null_is_infinite(cls, value: Any) -> Any:
        """``null``, as a JSON summary records an infinite mass ratio, reads back as ``inf``."""
        return float("inf") if value is None else value

    @model_validator(mode="after")
    def _physics(self):
        """The library's rules (the rod model is 1D and elastic ...), so a sweep checks every point."""
        self.parameters()
        return self

    def parameters(self):
        """The run as :class:`collisionkit.transport.SlabParameters`.

        Examples
        --------
        >>> SlabOptions(model="rod").parameters().model
        'rod'
        """
        from ..transport import SlabParameters

        return SlabParameters(**{name: getattr(self, name) for name in SlabParameters.names()})


def slab(
    thickness: Annotated[float | None, typer.Option(
        help="Slab thickness in mean free paths (0 to 1e4).  \\[default: 1]")] = None,
    albedo: Annotated[float | None, typer.Option(help="Single-scattering albedo in [0, 1].  \\[default: 1]")] = None,
    incidence: Annotated[str | None, typer.Option(help="normal or isotropic.  \\[default: normal]")] = None,
    model: Annotated[str | None, typer.Option(
        help="isotropic (3D) or rod (1D: normal incidence, no mass ratio).  \\[default: isotropic]")] = None,
    mass_ratio: Annotated[float | None, typer.Option(
        help="Target/particle mass (>= 1; inf: no energy loss).  \\[default: inf]")] = None,
    particles: Annotated[int | None, typer.Option(help="Histories (64 to 1e9).  \\[default: 100000]")] = None,
    seed: Annotated[int | None, typer.Option(help="Random seed (>= 0).  \\[default: 2026]")] = None,
    summary: Annotated[Path | None, typer.Option("--summary", help="Write the results as JSON to this file.")] = None,
    checkpoint: Annotated[Path | None, typer.Option(
        help="Write the run's state to this .npz every minute, when interrupted and at the end (atomically): "
             "--resume goes on from it to the result of a run never stopped.")] = None,
    resume: Annotated[Path | None, typer.Option(
        help="Continue the run saved in this checkpoint, with its options (only --summary and --checkpoint may "
             "change); checkpoints go on to it unless --checkpoint is given.")] = None,
    config: Annotated[Path | None, typer.Option(
        "--config", help="TOML file with these options (command line wins).")] = None,
    overwrite: OverwriteOption = None,
):
    """Transmission and reflection of a beam by a scattering slab (Krasov, sec. 5.5)."""
    given = dict(thickness=thickness, albedo=albedo, incidence=incidence, model=model, mass_ratio=mass_ratio,
                 particles=particles, seed=seed, summary=summary, checkpoint=checkpoint, overwrite=overwrite)
    if resume is None:
        options = load_options(SlabOptions, config, given)
        refuse_checkpoint_suffix(options.checkpoint)
        run = _new_run(options)
    else:
        run, options = _resumed_run(resume, option_values(SlabOptions, config, given))
    note(f"seed {options.seed} (--seed {options.seed} repeats this run)")
    warm_up(["slab"])
    where = (f"the last checkpoint is in {run.checkpoint}; continue with --resume {run.checkpoint}"
             if run.checkpoint is not None else "no --checkpoint was given, so nothing is saved")
    try:
        with progress_bar("histories", total=options.particles) as advance:
            result = run.run(progress=fraction_reporter(advance, options.particles))
    except FileLockedError as locked:
        raise fail(f"{locked}: another collisionkit run is writing it; wait for it or name another --checkpoint") \
            from None
    except KeyboardInterrupt:
        warn(f"interrupted after {run.done} of {options.particles} histories: {where}")
        raise typer.Exit(INTERRUPTED_EXIT_CODE) from None
    rows = [("transmission (x > d)", f"{result.transmission:.6f}", f"{result.transmission_error:.2g}"),
            ("reflection (x < 0)", f"{result.reflection:.6f}", f"{result.reflection_error:.2g}"),
            ("absorption", f"{result.absorption:.6f}", f"{result.absorption_error:.2g}"),
            ("collisions per particle", f"{result.collisions_per_particle:.4f}", "")]
    from ..transport import slab_summary

    print_table(f"slab d = {options.thickness:g} mfp, albedo {options.albedo:g}, {options.incidence} incidence",
                ("quantity", "value", "error"), rows)
    write_summary(options.summary, slab_summary(options.parameters(), result) | {"seed": options.seed}, "slab")


def _new_run(options: SlabOptions):
    from ..transport import SlabRun

    return SlabRun(options.parameters(), checkpoint=options.checkpoint, overwrite=bool(options.overwrite))


def _resumed_run(resume: Path, given: dict):
    """The run saved in ``resume``: physics options given now must agree with it; outputs are only those given now."""
    from ..transport import SlabRun

    refuse_folder(resume, "--resume")
    refuse_checkpoint_suffix(given.get("checkpoint"))
    physics = {key: value for key, value in given.items() if key not in SLAB_OUTPUTS}
    try:
        run = SlabRun.resume(resume, checkpoint=given.get("checkpoint", resume), **physics)
    except ValueError as error:
        raise fail(str(error)) from None
    outputs = {key: value for key, value in given.items() if key in SLAB_OUTPUTS} | {"checkpoint": run.checkpoint}
    options = validate_options(SlabOptions, run.parameters.to_dict() | outputs, keep=[resume])
    if run.finished:
        note("the run was already finished: its results are reported again")
    else:
        note(f"going on from {run.done} of {options.particles} histories saved in {resume}")
    return run, options


def register(app: typer.Typer) -> None:
    """Add the ``slab`` command to the ``collisionkit`` app."""
    app.command("slab")(slab)
