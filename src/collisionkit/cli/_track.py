"""The ``track`` subcommand: electrons (and their avalanches) through a device described by a TOML file."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Annotated, Any, ClassVar, Literal

import typer
from pydantic import Field, field_validator, model_validator

from .._io import FileLockedError
from ._common import (
    INTERRUPTED_EXIT_CODE, Deliveries, Options, OverwriteOption, fail, fraction_reporter, note, print_table,
    progress_bar, read_toml, refuse_folder, require, run_failed, say, validate_options, warn,
)
from ._transport import MAX_GAS_TEMPERATURE, refuse_checkpoint_suffix
from ._warmup import warm_up

TRACK_OUTPUTS = ("out", "summary", "checkpoint", "overwrite", "threads")  # what a resumed run may change
MINIMAL_DEVICE = {"model": "maxwell", "gap": 1.0}  # completes the command line's options for their own checks


class TrackOptions(Options):
    """Options of ``collisionkit track``: the device file's tables flattened, and the outputs; the physics is
    :class:`collisionkit.transport.tracking.TrackParameters`.

    Examples
    --------
    >>> TrackOptions.model_validate({"model": "reid", "gap": 1e-3, "voltage": 50.0}).parameters().geometry
    'parallel-plate'
    """

    geometry: Literal["parallel-plate", "coaxial"] = "parallel-plate"
    gap: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    voltage: float = Field(default=0.0, allow_inf_nan=False)
    wire_radius: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    cathode_radius: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    magnetic_field: list[float] | None = None
    model: Literal["maxwell", "hard_sphere", "reid", "lucas_saelee"] | None = None
    gas: str | None = None
    cross_sections: list[Path] | None = None
    species: list[str] | None = None
    fractions: list[float] | None = None
    database: str | None = None
    scattering: str | dict[str, str] | None = None
    populations: dict[str, float] | None = None
    pressure: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    temperature: float = Field(default=300.0, ge=0, le=MAX_GAS_TEMPERATURE, allow_inf_nan=False)
    density: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    electrons: int = Field(default=100, ge=1, le=10_000_000)
    position: list[float] | None = None
    radius: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    energy: float = Field(default=0.1, ge=0, allow_inf_nan=False)
    direction: list[float] | None = None
    method: Literal["null-collision", "path-length"] = "null-collision"
    ion_mobility: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    seed: int = Field(default=2026, ge=0)
    tolerance: float = Field(default=1e-6, gt=0, le=0.1)
    max_electrons: int = Field(default=10_000_000, ge=1, le=10**12)
    sharing: Literal["equal", "uniform"] = "equal"
    threads: int | None = Field(default=None, ge=1, le=1024)
    out: Path | None = None
    summary: Path | None = None
    checkpoint: Path | None = None

    output_files: ClassVar[tuple[str, ...]] = ("summary", "checkpoint")
    output_folders: ClassVar[tuple[str, ...]] = ("out",)
    input_files: ClassVar[tuple[str, ...]] = ("cross_sections",)

    def folder_files(self, folder: str) -> tuple[str, ...]:
        """The plots of ``--out`` (an earlier run's are not replaced without --overwrite)."""
        return ("tracks.png", "spectra.png")

    @field_validator("cross_sections", mode="before")
    @classmethod
    def _one_file_is_a_list(cls, value: Any) -> Any:
        return [value] if isinstance(value, (str, Path)) else value

    @model_validator(mode="after")
    def _physics(self):
        """The library's rules (one gas, the device's sizes, a start inside it ...), so a sweep checks every point."""
        self.parameters()
        return self

    def parameters(self):
        """The run's physics as :class:`collisionkit.transport.tracking.TrackParameters`.

        Examples
        --------
        >>> TrackOptions(model="reid", gap=1e-3, seed=5).parameters().seed
        5
        """
        from ..transport.tracking.parameters import TrackParameters

        names = TrackParameters.names()
        return TrackParameters(**{name: getattr(self, name) for name in names})


class _FileSpellings(Mapping):
    """How a device file spells each option: ``[geometry] gap``, ``[geometry] kind``, ``[ions] mobility``, ``seed``;
    made on first use (the tables are the library's, which a command imports only when it runs).

    Examples
    --------
    >>> spellings = _FileSpellings()
    >>> spellings["gap"], spellings["geometry"], spellings["max_electrons"]
    ('[geometry] gap', '[geometry] kind', 'max-electrons')
    """

    def _table(self) -> dict[str, str]:
        from ..transport.tracking.parameters import SECTIONS

        spellings = {name: name.replace("_", "-") for name in TrackOptions.model_fields}
        for table, keys in SECTIONS.items():
            for key, name in keys.items():
                spellings[name] = f"[{table}] {key.replace('_', '-')}"
        return spellings

    def __getitem__(self, name: str) -> str:
        return self._table()[name]

    def __iter__(self):
        return iter(self._table())

    def __len__(self) -> int:
        return len(self._table())


class DeviceFileOptions(TrackOptions):
    """:class:`TrackOptions` as a device file sets them: an error names the option as the file spells it
    (``[geometry] gap``), not as a flag the command does not have (``--gap``). The command line's own values are
    checked before, as :class:`TrackOptions`, so an error here is the file's.

    Examples
    --------
    >>> DeviceFileOptions.flags["gap"]
    '[geometry] gap'
    """

    flags: ClassVar[Mapping[str, str]] = _FileSpellings()


def device_options(config: Path) -> dict[str, Any]:
    """The options a device file sets: its ``[gas]``, ``[geometry]``, ``[source]`` and ``[ions]`` tables flattened,
    with its top-level keys (an unknown table or key is an input error, exit 2).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "device.toml"
    >>> _ = path.write_text('seed = 3\\n[geometry]\\nkind = "coaxial"\\nwire-radius = 1e-5\\n')
    >>> device_options(path)
    {'seed': 3, 'geometry': 'coaxial', 'wire_radius': 1e-05}
    """
    from ..transport.tracking.parameters import flatten_sections

    try:
        return flatten_sections(read_toml(config))
    except ValueError as error:
        raise fail(f"config file {config}: {error}") from None


def _new_run(options: TrackOptions):
    from ..transport.tracking import TrackRun

    try:
        return TrackRun(options.parameters(), checkpoint=options.checkpoint, threads=options.threads)
    except ValueError as error:
        raise fail(str(error)) from None


def _resumed_run(resume: Path, given: dict):
    """The run saved in ``resume``; physics given now must agree with it; outputs are only those given now."""
    from ..transport.tracking import TrackRun

    refuse_folder(resume, "--resume")
    physics = {key: value for key, value in given.items() if key not in TRACK_OUTPUTS and key != "max_electrons"}
    try:
        run = TrackRun.resume(resume, checkpoint=given.get("checkpoint", resume), threads=given.get("threads"),
                              **physics)
        if "max_electrons" in given:  # a limit of the machine's memory, not physics: a resumed run may raise it
            run.parameters = run.parameters.replace(max_electrons=given["max_electrons"])
    except ValueError as error:
        raise fail(str(error)) from None
    outputs = {key: value for key, value in given.items() if key in TRACK_OUTPUTS} | {"checkpoint": run.checkpoint}
    options = validate_options(TrackOptions, run.parameters.to_dict() | outputs, keep=[resume])
    return run, options


def _where(run, options: TrackOptions) -> str:
    """What a stopped run has saved, and how to go on."""
    if options.checkpoint is None:
        return "no --checkpoint was given, so nothing is saved"
    return (f"{run.done} of {options.electrons} primaries are saved in {options.checkpoint}; continue with "
            f"--resume {options.checkpoint} (and --max-electrons to raise the limit)")


def _rows(summary: dict) -> list[tuple[str, str]]:
    def pm(value, error, fmt=".5g"):
        return f"{value:{fmt}} ± {error:.2g}" if error == error else f"{value:{fmt}}"

    rows = [("primaries", str(summary["primaries"])), ("collecting electrode", str(summary["collector"])),
            ("gain (electrons collected per primary)", pm(summary["gain"], summary["gain_error"])),
            ("drift time (s)", pm(summary["drift_time"], summary["drift_time_error"])),
            ("ionizations per primary", f"{summary['ionizations_per_primary']:.5g}"),
            ("Polya theta of the gain", pm(summary["polya_theta"], summary["polya_theta_error"], ".3g")),
            ("induced charge per primary (C)", pm(summary["induced_charge"], summary["induced_charge_error"]))]
    if "ion_drift_time" in summary:
        rows.append(("ion drift time (s)", pm(summary["ion_drift_time"], summary["ion_drift_time_error"] or
                                               float("nan"))))
    rows += [("real collisions", f"{summary['collisions']:.4g}"),
             ("collisions per second", f"{summary['collisions'] / max(summary['seconds'], 1e-300):.3g}")]
    return rows


def _plots(run, out: Path, deliveries: Deliveries) -> None:
    import matplotlib

    matplotlib.use("Agg")
    from .. import plotting

    deliveries.write(f"the folder {out}", lambda: out.mkdir(parents=True, exist_ok=True))
    deliveries.write(f"the plot {out / 'tracks.png'}",
                     lambda: plotting.save(plotting.plot_tracks(run.result, run.device), out / "tracks.png"))
    deliveries.write(f"the plot {out / 'spectra.png'}",
                     lambda: plotting.save(plotting.plot_tracking_spectra(run.result).flat[0], out / "spectra.png"))


def track(
    config: Annotated[Path | None, typer.Option(
        "--config", help="The device file (TOML): \\[gas], \\[geometry], \\[source] and \\[ions] tables; options "
                         "on the command line win.")] = None,
    electrons: Annotated[int | None, typer.Option(
        help="Primary electrons (1 to 1e7).  \\[default: 100, or the file's]")] = None,
    voltage: Annotated[float | None, typer.Option(
        help="Voltage of the anode (plates) or the wire (coaxial), V.")] = None,
    method: Annotated[str | None, typer.Option(
        help="Collisions by null-collision or path-length.  \\[default: null-collision]")] = None,
    seed: Annotated[int | None, typer.Option(help="Random seed (>= 0).  \\[default: 2026]")] = None,
    max_electrons: Annotated[int | None, typer.Option(
        help="Electrons the run may follow, primaries and secondaries (1 to 1e12; about 130 B each): a bigger "
             "avalanche is refused after a pilot of 8 primaries (runs of 800 primaries or more; exit 2) or stopped "
             "when reached (exit 1).  \\[default: 1e7]")] = None,
    threads: Annotated[int | None, typer.Option(
        help="Worker threads (results do not depend on them).  \\[default: all cores]")] = None,
    out: Annotated[Path | None, typer.Option(
        help="Folder for the plots of sample tracks and of the spectra (none if not given).")] = None,
    summary: Annotated[Path | None, typer.Option("--summary", help="Write the results as JSON to this file.")] = None,
    checkpoint: Annotated[Path | None, typer.Option(
        help="Save the run after every twentieth of the primaries to this checkpoint (atomically): a .npz file (a "
             "numpy zip archive), for --resume.")] = None,
    resume: Annotated[Path | None, typer.Option(
        help="Continue the run saved in this checkpoint (only --summary, --out, --checkpoint, --threads may "
             "change).")] = None,
    overwrite: OverwriteOption = None,
):
    """Electrons and their avalanches through a device: gain, drift time, spectra, profiles, induced current."""
    given = dict(electrons=electrons, voltage=voltage, method=method, seed=seed, max_electrons=max_electrons,
                 threads=threads, out=out,
                 summary=summary, checkpoint=checkpoint, overwrite=overwrite)
    given = {key: value for key, value in given.items() if value is not None}
    validate_options(TrackOptions, MINIMAL_DEVICE | given)  # the command line's own values first, whatever the file
    refuse_checkpoint_suffix(given.get("checkpoint"))
    if resume is None:
        if config is None:
            raise fail("--config FILE is required: the device (TOML with [gas], [geometry] and [source])")
        options = validate_options(DeviceFileOptions, device_options(config) | given)
        refuse_checkpoint_suffix(options.checkpoint)
        run = _new_run(options)
    else:
        if config is not None:
            given = device_options(config) | given
        refuse_checkpoint_suffix(given.get("checkpoint"))  # (a resumed run goes on writing --resume's own file)
        run, options = _resumed_run(resume, given)
    if options.out is not None:
        require("matplotlib", "plot", "plots (--out)")
    note(f"seed {options.seed} (--seed {options.seed} repeats this run)")
    warm_up(["track"])
    from ..transport.tracking.run import ElectronLimitError

    try:
        with progress_bar("track", total=100) as advance:
            report = fraction_reporter(advance, 100)
            report(run.done / options.electrons)
            run.run(progress=report)
    except FileLockedError as locked:
        raise fail(f"{locked}: another collisionkit run is writing it; wait for it or name another --checkpoint") \
            from None
    except ElectronLimitError as stopped:  # after some of the work: a run failure, not bad input
        raise run_failed(f"the run stopped: {stopped}; {_where(run, options)}") from None
    except ValueError as refused:  # a refusal before the work (the pilot's projection); after some, a failure
        if run.done:
            raise run_failed(f"the run stopped: {refused}; {_where(run, options)}") from None
        raise fail(str(refused)) from None
    except (KeyboardInterrupt, OSError) as stop:
        where = _where(run, options)
        if isinstance(stop, OSError):
            raise run_failed(f"the run stopped: {stop}; {where}") from None
        warn(f"interrupted: {where}")
        raise typer.Exit(INTERRUPTED_EXIT_CODE) from None
    result = run.summary()
    print_table("tracking (electrons and their avalanches)", ("quantity", "value"), _rows(result))
    stuck = int((run.result.records[:, 1] != 0).sum())
    if stuck:
        warn(f"{stuck} electrons ended without reaching an electrode (attached, time limit or step limit)")
    deliveries = Deliveries("track")
    if options.out is not None:
        _plots(run, options.out, deliveries)
    for path in deliveries.files:
        say(f"wrote {path}")
    deliveries.finish(options.summary, run.summary(deliveries.files) | {"seed": options.seed})


def register(app: typer.Typer) -> None:
    """Add the ``track`` command to the ``collisionkit`` app."""
    app.command("track")(track)
