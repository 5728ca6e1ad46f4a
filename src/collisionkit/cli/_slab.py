"""The ``slab`` subcommand: transmission and reflection of a beam by a scattering slab (Krasov, sec. 5.5)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Literal

import typer
from pydantic import Field, field_validator, model_validator

from ._common import (
    INTERRUPTED_EXIT_CODE, Options, OverwriteOption, fraction_reporter, load_options, note, print_table, progress_bar,
    warn, write_summary,
)
from ._warmup import warm_up


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
    config: Annotated[Path | None, typer.Option(
        "--config", help="TOML file with these options (command line wins).")] = None,
    overwrite: OverwriteOption = None,
):
    """Transmission and reflection of a beam by a scattering slab (Krasov, sec. 5.5)."""
    given = dict(thickness=thickness, albedo=albedo, incidence=incidence, model=model, mass_ratio=mass_ratio,
                 particles=particles, seed=seed, summary=summary, overwrite=overwrite)
    options = load_options(SlabOptions, config, given)
    from ..transport import run_slab, slab_summary

    note(f"seed {options.seed} (--seed {options.seed} repeats this run)")
    warm_up(["slab"])

    try:
        with progress_bar("histories", total=options.particles) as advance:
            result = run_slab(options.parameters(), progress=fraction_reporter(advance, options.particles))
    except KeyboardInterrupt:
        warn("interrupted: a slab run keeps no checkpoint, so nothing is saved (fewer --particles make it shorter)")
        raise typer.Exit(INTERRUPTED_EXIT_CODE) from None
    rows = [("transmission (x > d)", f"{result.transmission:.6f}", f"{result.transmission_error:.2g}"),
            ("reflection (x < 0)", f"{result.reflection:.6f}", f"{result.reflection_error:.2g}"),
            ("absorption", f"{result.absorption:.6f}", f"{result.absorption_error:.2g}"),
            ("collisions per particle", f"{result.collisions_per_particle:.4f}", "")]
    print_table(f"slab d = {options.thickness:g} mfp, albedo {options.albedo:g}, {options.incidence} incidence",
                ("quantity", "value", "error"), rows)
    write_summary(options.summary, slab_summary(options.parameters(), result) | {"seed": options.seed}, "slab")


def register(app: typer.Typer) -> None:
    """Add the ``slab`` command to the ``collisionkit`` app."""
    app.command("slab")(slab)
