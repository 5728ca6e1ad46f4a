"""The ``swarm`` and ``slab`` subcommands: Monte Carlo transport."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, ClassVar, Literal

import typer
from pydantic import Field, field_validator, model_validator

from ._common import (
    INTERRUPTED_EXIT_CODE, Options, console, fail, load_options, option_values, print_table, progress_bar,
    refuse_to_overwrite_checkpoint, require, validate_options, warn, write_summary,
)

ModelName = Literal["maxwell", "hard_sphere", "reid", "lucas_saelee"]


class SwarmOptions(Options):
    model: ModelName | None = None
    cross_sections: Path | None = None
    species: list[str] | None = None
    fractions: list[float] | None = None
    e_n: list[float] = Field(default=[12.0], min_length=1)
    b_n: float = Field(default=0.0, allow_inf_nan=False)
    gas_temperature: float = Field(default=0.0, ge=0, allow_inf_nan=False)
    particles: int = Field(default=20_000, ge=128, le=10_000_000)
    seed: int = Field(default=2026, ge=0)
    tolerance: float = Field(default=2e-3, gt=0, le=0.5)
    collision_budget: float = Field(default=5e8, ge=1e4, allow_inf_nan=False)
    sharing: Literal["equal", "uniform"] = "equal"
    out: Path | None = None
    summary: Path | None = None
    checkpoint: Path | None = None

    output_files: ClassVar[tuple[str, ...]] = ("summary", "checkpoint")
    output_folders: ClassVar[tuple[str, ...]] = ("out",)

    @field_validator("e_n")
    @classmethod
    def _non_negative(cls, values):
        if any(not (v >= 0 and v < float("inf")) for v in values):
            raise ValueError("E/N values must be finite and >= 0 Td")
        return values

    @model_validator(mode="after")
    def _one_gas(self):
        if (self.model is None) == (self.cross_sections is None):
            raise ValueError("give exactly one of --model and --cross-sections")
        if self.model is not None and (self.species is not None or self.fractions is not None):
            raise ValueError("--species and --fractions pick gases from an LXCat file (--cross-sections); "
                             f"the model gas {self.model} takes neither")
        if self.summary is not None and self.checkpoint is not None and \
                self.summary.resolve() == self.checkpoint.resolve():
            raise ValueError("--summary and --checkpoint name the same file; the summary would overwrite the "
                             "checkpoint")
        if 0.0 in self.e_n and self.gas_temperature == 0.0:
            raise ValueError("E/N = 0 in a gas at 0 K has no steady state (nothing heats the swarm; it cools "
                             "without end): give --gas-temperature > 0 or E/N > 0")
        return self


def _e_n_values(raw: list[str] | None) -> list[float] | None:
    if raw is None:
        return None
    values = []
    for item in raw:
        for part in str(item).split(","):
            if part.strip():
                try:
                    values.append(float(part))
                except ValueError:
                    raise fail(f"--E-N: {part!r} is not a number (Td)") from None
    return values


def _gas(options: SwarmOptions):
    from ..transport import model_gas, read_lxcat

    if options.model is not None:
        return model_gas(options.model)
    try:
        return read_lxcat(options.cross_sections, species=options.species, fractions=options.fractions)
    except ValueError as error:
        raise fail(str(error)) from None


SWARM_CHECKPOINT_FORMAT = "collisionkit swarm checkpoint 1"
SWARM_OUTPUTS = ("out", "summary", "checkpoint")  # what a resumed sweep may change; the rest is its physics


def _file_digest(path: Path | None) -> str | None:
    """SHA-256 of a file's bytes (None for no file): a resumed sweep must read the same cross sections."""
    import hashlib

    return None if path is None else hashlib.sha256(Path(path).read_bytes()).hexdigest()


def _flag(key: str) -> str:
    return {"e_n": "--E-N", "b_n": "--B-N"}.get(key, "--" + key.replace("_", "-"))


def save_swarm_checkpoint(path: Path, options: SwarmOptions, results) -> Path:
    """Write the finished E/N points, the options and the cross-section file's digest (JSON, atomically): a crash
    loses at most the running point."""
    from .._io import atomic_write_json

    return atomic_write_json(path, {"format": SWARM_CHECKPOINT_FORMAT, "options": options.model_dump(mode="json"),
                                    "cross_sections_sha256": _file_digest(options.cross_sections),
                                    "results": [result.to_dict() for result in results]})


def load_swarm_checkpoint(path: Path) -> tuple[dict, list]:
    """The saved options (a dict) and finished results of a checkpoint written by :func:`save_swarm_checkpoint`."""
    import json

    from ..transport import SwarmResult

    try:
        data = json.loads(Path(path).read_text())
    except FileNotFoundError:
        raise fail(f"checkpoint not found: {path}") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        raise fail(f"{path} is not a readable swarm checkpoint (JSON): {error}") from None
    if not isinstance(data, dict) or data.get("format") != SWARM_CHECKPOINT_FORMAT:
        raise fail(f"{path} is not a checkpoint of 'collisionkit swarm' ({SWARM_CHECKPOINT_FORMAT})")
    try:
        saved = dict(data["options"]) | {"cross_sections_sha256": data.get("cross_sections_sha256")}
        return saved, [SwarmResult.from_dict(entry) for entry in data["results"]]
    except (KeyError, TypeError, ValueError) as error:
        raise fail(f"{path} is a damaged swarm checkpoint: {error}") from None


def _resumed_swarm_options(given: dict, saved: dict, resume: Path) -> SwarmOptions:
    """The checkpoint's options with the output options given now (command line or config); a physics option
    given must agree with the checkpoint's."""
    saved = dict(saved)
    digest = saved.pop("cross_sections_sha256", None)
    saved_options = validate_options(SwarmOptions, saved)
    now = validate_options(SwarmOptions, saved | given)
    for key in sorted(set(given) - set(SWARM_OUTPUTS)):
        value, before = getattr(now, key), getattr(saved_options, key)
        if isinstance(value, Path) and isinstance(before, Path):
            value, before = value.resolve(), before.resolve()
        if value != before:
            raise fail(f"{_flag(key)} {_shown(value)} differs from the checkpoint {resume} ({_shown(before)}); "
                       "a resumed sweep keeps the physics options it started with (only --summary, --out and "
                       "--checkpoint may change)")
    outputs = {key: value for key, value in given.items() if key in SWARM_OUTPUTS}
    options = validate_options(SwarmOptions, saved | outputs | {"checkpoint": given.get("checkpoint", resume)})
    if options.cross_sections is not None and options.cross_sections.is_file() and digest is not None \
            and _file_digest(options.cross_sections) != digest:
        raise fail(f"{options.cross_sections} has changed since {resume} was written (its SHA-256 differs): a "
                   "resumed sweep must use the same cross sections")
    return options


def _shown(value) -> str:
    """An option value as a user would type it."""
    if isinstance(value, list):
        return ",".join(f"{item:g}" if isinstance(item, float) else str(item) for item in value)
    return f"{value:g}" if isinstance(value, float) else str(value)


def _run_points(options: SwarmOptions, gas, results: list, tolerances: dict, thermal: dict) -> None:
    """Run the E/N points not yet in ``results``, appending each and saving the checkpoint after it."""
    from ..transport import simulate_swarm

    with progress_bar("swarm", total=len(options.e_n)) as advance:
        advance(len(results))
        for value in options.e_n[len(results):]:
            done = [0.0]

            def report(fraction, done=done):
                advance(fraction - done[0])
                done[0] = fraction

            result = simulate_swarm(gas, value, reduced_magnetic_field=options.b_n,
                                    gas_temperature=options.gas_temperature, particles=options.particles,
                                    seed=options.seed, sharing=options.sharing,
                                    tolerances=tolerances if value > 0 else thermal,
                                    collision_budget=options.collision_budget, progress=report)
            advance(1.0 - done[0])
            results.append(result)
            if options.checkpoint is not None:
                save_swarm_checkpoint(options.checkpoint, options, results)


def _swarm_row(result):
    return (f"{result.reduced_field:g}", f"{result.mean_energy:.5g} ± {result.mean_energy_error:.2g}",
            f"{-result.drift_velocity_bulk[2]:.5g} ± {result.drift_velocity_bulk_error[2]:.2g}",
            f"{result.diffusion_L_N:.4g} ± {result.diffusion_L_N_error:.2g}",
            f"{result.diffusion_T_N:.4g} ± {result.diffusion_T_N_error:.2g}",
            f"{result.collisions_per_second:.3g}")


def _swarm_plots(results, out: Path) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    from .. import plotting
    from ..sweep import write_csv

    out.mkdir(parents=True, exist_ok=True)
    files = [plotting.save(plotting.plot_energy_distribution(results), out / "eedf.png")]
    files.append(write_csv(out / "swarm.csv", [result.to_row() for result in results]))
    if len(results) > 1:
        files.append(plotting.save(plotting.plot_transport_coefficients(results).flat[0], out / "transport_coefficients.png"))
    return files


def swarm(
    model: Annotated[str | None, typer.Option(help="Model gas: maxwell, hard_sphere, reid, lucas_saelee.")] = None,
    cross_sections: Annotated[Path | None, typer.Option("--cross-sections", help="LXCat cross-section file.")] = None,
    species: Annotated[list[str] | None, typer.Option(help="Species of the LXCat file to use (repeat).")] = None,
    fractions: Annotated[list[float] | None, typer.Option(help="Their number fractions (repeat).")] = None,
    e_n: Annotated[list[str] | None, typer.Option("--E-N", help="E/N in Td; repeat or comma list for a sweep.  \\[default: 12]")] = None,
    b_n: Annotated[float | None, typer.Option("--B-N", help="B/N in Hx, B along y (E along z).  \\[default: 0]")] = None,
    gas_temperature: Annotated[float | None, typer.Option(help="Gas temperature in K (>= 0).  \\[default: 0]")] = None,
    particles: Annotated[int | None, typer.Option(help="Simulated particles (128 to 1e7).  \\[default: 20000]")] = None,
    seed: Annotated[int | None, typer.Option(help="Random seed (>= 0).  \\[default: 2026]")] = None,
    tolerance: Annotated[float | None, typer.Option(help="Target relative error of mean energy and drift (of mean energy alone at E/N = 0).  \\[default: 0.002]")] = None,
    collision_budget: Annotated[float | None, typer.Option(help="Stop after this many real collisions per E/N.  \\[default: 5e8]")] = None,
    sharing: Annotated[str | None, typer.Option(help="Ionization energy sharing: equal or uniform.  \\[default: equal]")] = None,
    out: Annotated[Path | None, typer.Option(help="Folder for plots and swarm.csv, a row per E/N (none if not given).")] = None,
    summary: Annotated[Path | None, typer.Option("--summary", help="Write the results as JSON to this file.")] = None,
    checkpoint: Annotated[Path | None, typer.Option(help="Write the finished E/N points to this JSON file after each one (atomically).")] = None,
    resume: Annotated[Path | None, typer.Option(help="Continue the sweep saved in this checkpoint, with its options (only --summary, --out, --checkpoint may change); skips its finished points; checkpoints go on to it unless --checkpoint is given.")] = None,
    config: Annotated[Path | None, typer.Option("--config", help="TOML file with these options (command line wins).")] = None,
):
    """Electron swarm transport coefficients (mean energy, drift, diffusion, rates) against E/N."""
    given = dict(model=model, cross_sections=cross_sections, species=species, fractions=fractions, e_n=_e_n_values(e_n),
                 b_n=b_n, gas_temperature=gas_temperature, particles=particles, seed=seed, tolerance=tolerance,
                 collision_budget=collision_budget, sharing=sharing, out=out, summary=summary, checkpoint=checkpoint)
    results = []
    if resume is None:
        options = load_options(SwarmOptions, config, given)
        refuse_to_overwrite_checkpoint(options.checkpoint)
        if options.cross_sections is not None:  # a checkpoint resumed from another folder finds it
            options = options.model_copy(update={"cross_sections": options.cross_sections.resolve()})
    else:
        saved, results = load_swarm_checkpoint(resume)
        options = _resumed_swarm_options(option_values(SwarmOptions, config, given), saved, resume)
        if [r.reduced_field for r in results] != options.e_n[: len(results)]:
            raise fail(f"{resume} holds results for E/N = {[r.reduced_field for r in results]}, not the first "
                       f"points of its sweep {options.e_n}")
    if options.out is not None:
        require("matplotlib", "plot", "plots (--out)")
    gas = _gas(options)
    tolerances = {"mean_energy": options.tolerance, "drift_velocity_bulk": options.tolerance}
    thermal = {"mean_energy": options.tolerance}  # E/N = 0: the drift is zero by symmetry (no relative error)
    try:
        _run_points(options, gas, results, tolerances, thermal)
    except KeyboardInterrupt:
        where = (f"{len(results)} of {len(options.e_n)} E/N points are saved in {options.checkpoint}; continue with "
                 f"--resume {options.checkpoint}" if options.checkpoint is not None else
                 "no --checkpoint was given, so nothing is saved")
        warn(f"interrupted: {where}")
        raise typer.Exit(INTERRUPTED_EXIT_CODE) from None
    print_table("swarm transport (W along -z for electrons)",
                ("E/N (Td)", "mean energy (eV)", "bulk W (m/s)", "N D_L (1/m/s)", "N D_T (1/m/s)", "collisions/s"),
                [_swarm_row(r) for r in results])
    unconverged = [f"{r.reduced_field:g}" for r in results if not r.converged]
    if unconverged:
        message = (f"E/N = {', '.join(unconverged)} Td stopped at the collision budget "
                   f"({options.collision_budget:g}) before reaching the tolerance {options.tolerance:g}: "
                   "their errors are larger than asked; rerun with a larger --collision-budget")
        warn(message)
    files = _swarm_plots(results, options.out) if options.out is not None else []
    entries = []
    for r in results:
        entry = r.to_dict()
        entry["E_N"] = r.reduced_field
        entries.append(entry)
    write_summary(options.summary, {"gas": str(options.model or options.cross_sections), "results": entries,
                                    "files": [str(p) for p in files], "options": options.model_dump(mode="json")})
    for path in files:
        console.print(f"wrote {path}")


class SlabOptions(Options):
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
    def _rod_is_one_dimensional(self):
        if self.model == "rod" and (self.incidence != "normal" or self.mass_ratio != float("inf")):
            raise ValueError("the rod model is one-dimensional and elastic: it takes incidence normal and "
                             "mass-ratio inf")
        return self


def slab(
    thickness: Annotated[float | None, typer.Option(help="Slab thickness in mean free paths (>= 0).  \\[default: 1]")] = None,
    albedo: Annotated[float | None, typer.Option(help="Single-scattering albedo in [0, 1].  \\[default: 1]")] = None,
    incidence: Annotated[str | None, typer.Option(help="normal or isotropic.  \\[default: normal]")] = None,
    model: Annotated[str | None, typer.Option(help="isotropic (3D) or rod (1D: normal incidence, no mass ratio).  \\[default: isotropic]")] = None,
    mass_ratio: Annotated[float | None, typer.Option(help="Target/particle mass (>= 1; inf: no energy loss).  \\[default: inf]")] = None,
    particles: Annotated[int | None, typer.Option(help="Histories (>= 64).  \\[default: 100000]")] = None,
    seed: Annotated[int | None, typer.Option(help="Random seed (>= 0).  \\[default: 2026]")] = None,
    summary: Annotated[Path | None, typer.Option("--summary", help="Write the results as JSON to this file.")] = None,
    config: Annotated[Path | None, typer.Option("--config", help="TOML file with these options (command line wins).")] = None,
):
    """Transmission and reflection of a beam by a scattering slab (Krasov, sec. 5.5)."""
    given = dict(thickness=thickness, albedo=albedo, incidence=incidence, model=model, mass_ratio=mass_ratio,
                 particles=particles, seed=seed, summary=summary)
    options = load_options(SlabOptions, config, given)
    from ..transport import simulate_slab

    with progress_bar("slab", total=1) as advance:
        result = simulate_slab(options.thickness, options.albedo, incidence=options.incidence, model=options.model,
                               mass_ratio=options.mass_ratio, particles=options.particles, seed=options.seed)
        advance()
    rows = [("transmission (x > d)", f"{result.transmission:.6f}", f"{result.transmission_error:.2g}"),
            ("reflection (x < 0)", f"{result.reflection:.6f}", f"{result.reflection_error:.2g}"),
            ("absorption", f"{result.absorption:.6f}", f"{result.absorption_error:.2g}"),
            ("collisions per particle", f"{result.collisions_per_particle:.4f}", "")]
    print_table(f"slab d = {options.thickness:g} mfp, albedo {options.albedo:g}, {options.incidence} incidence",
                ("quantity", "value", "error"), rows)
    write_summary(options.summary, result.to_dict() | {"options": options.model_dump(mode="json")})


def register(app: typer.Typer) -> None:
    """Add the ``swarm`` and ``slab`` commands to the ``collisionkit`` app."""
    app.command("swarm")(swarm)
    app.command("slab")(slab)
