"""The ``swarm`` subcommand: electron swarm transport coefficients against E/N (``slab`` is in ``_slab``)."""

from __future__ import annotations

import math
import warnings
from contextlib import contextmanager
from pathlib import Path
from typing import Annotated, Any, ClassVar, Literal

import typer
from pydantic import Field, field_validator, model_validator

from .._io import FileLockedError
from ._detector import check_detector_options, detector_report, fields_from_volts
from ._swarm_tables import _field_rows, _swarm_row, print_swarm_tables  # noqa: F401 (_field_rows, _swarm_row: tests)
from ._common import (
    INTERRUPTED_EXIT_CODE, Deliveries, Options, OverwriteOption, fail, fraction_reporter, load_options, named_as_option,
    note,
    option_values, progress_bar, refuse_folder, require, run_failed, say, validate_options, warn,
)
from ._memory import refuse_beyond_memory, swarm_memory
from ._reduced_fields import E_N_FORMS, MAX_REDUCED_FIELD, _e_n_values, _short  # noqa: F401 (boltzmann takes _e_n_values here)
from ._warmup import warm_up

ModelName = Literal["maxwell", "hard_sphere", "reid", "lucas_saelee"]
# the library's ranges (collisionkit.transport._validation), here so that the options are checked without importing
# the library (it is imported when a command runs); tests/cli/test_transport_cli.py checks that they agree
MAX_REDUCED_MAGNETIC_FIELD = 1e6  # Hx
MAX_GAS_TEMPERATURE = 1e5  # K
REDUCED_FREQUENCY_RANGE = (1e-20, 1e-8)  # rad m^3/s, or 0
QUASI_STATIC = "a slower field is quasi-static: scan its E/N values with a static field instead"
CHECKPOINT_SUFFIX = ".npz"  # what a checkpoint is: a numpy zip archive (collisionkit._io.write_checkpoint)


def refuse_checkpoint_suffix(path: Path | None, option: str = "--checkpoint") -> None:
    """Exit 2, before any work, if ``path`` does not end in .npz: a checkpoint is a numpy zip archive.

    Examples
    --------
    >>> refuse_checkpoint_suffix(Path("scan.npz")), refuse_checkpoint_suffix(None)
    (None, None)
    >>> try:
    ...     refuse_checkpoint_suffix(Path("scan.json"))
    ... except Exception as stop:
    ...     print(type(stop).__name__, stop.exit_code)
    Exit 2
    """
    if path is not None and Path(path).suffix.lower() != CHECKPOINT_SUFFIX:
        raise fail(f"{option} must end in {CHECKPOINT_SUFFIX} (a checkpoint is a numpy zip archive, not JSON); "
                   f"got {str(path)!r}")


def checked_frequency(value: float) -> float:
    """omega/N 0 (static) or in REDUCED_FREQUENCY_RANGE (the library's range), else a ValueError with the range.

    Examples
    --------
    >>> checked_frequency(1e-14)
    1e-14
    """
    low, high = REDUCED_FREQUENCY_RANGE
    if value != 0.0 and not low <= value <= high:
        slow = f" ({QUASI_STATIC})" if value < low else ""
        raise ValueError(f"must be 0 (a static field) or from {low:g} to {high:g} rad m^3/s{slow}")
    return value


class GasScanOptions(Options):
    """The gas and the E/N values of ``swarm`` and ``boltzmann``: a model gas, a catalogue gas or LXCat files.

    Examples
    --------
    >>> GasScanOptions.model_validate({"model": "reid", "e-n": [1, 12]}).e_n
    [1.0, 12.0]
    """

    model: ModelName | None = None
    gas: str | None = None
    cross_sections: list[Path] | None = None
    species: list[str] | None = None
    fractions: list[float] | None = None
    database: str | None = None
    e_n: list[float] = Field(default=[12.0])

    input_files: ClassVar[tuple[str, ...]] = ("cross_sections",)
    flags: ClassVar[dict[str, str]] = {"e_n": "--E-N"}
    text_forms: ClassVar[tuple[str, ...]] = ("e_n",)
    # a gas chosen on the command line replaces the config file's gas: its model, gas or LXCat files with their
    # species, fractions and database; a model or catalogue gas has no LXCat selectors at all, while selectors in a
    # config without files of its own pick from the command line's --cross-sections
    chosen_together: ClassVar = ((("model", "gas", "cross_sections"), ("model", "gas", "cross_sections")),
                                 (("model", "gas"), ("species", "fractions", "database")))
    goes_with: ClassVar = {"cross_sections": ("species", "fractions", "database")}

    @field_validator("cross_sections", mode="before")
    @classmethod
    def _one_file_is_a_list(cls, value: Any) -> Any:
        """``cross-sections = "ar.txt"`` in a TOML file (and a saved checkpoint's single path) is a list of one."""
        return [value] if isinstance(value, (str, Path)) else value

    @model_validator(mode="after")
    def _a_fraction_per_species(self):
        """--fractions, one per --species (the library's message names its arguments, not the options)."""
        if self.species is not None and self.fractions is not None and len(self.fractions) != len(self.species):
            raise ValueError(f"--fractions: give one per --species ({len(self.species)}: {', '.join(self.species)}); "
                             f"got {len(self.fractions)}")
        return self

    @field_validator("e_n", mode="before")
    @classmethod
    def _ranges_as_on_the_command_line(cls, value: Any) -> Any:
        """A config's ``E-N`` may use the command line's forms: ``"1:1000:7:log"``, ``"10, 20"`` or a list with them.

        Examples
        --------
        >>> GasScanOptions.model_validate({"model": "reid", "e-n": "1:100:3"}).e_n
        [1.0, 50.5, 100.0]
        >>> GasScanOptions.model_validate({"model": "reid", "e-n": [5, "10:30:3"]}).e_n
        [5.0, 10.0, 20.0, 30.0]
        """
        items = value if isinstance(value, list) else [value]
        if any(isinstance(item, bool) or not isinstance(item, (int, float, str)) for item in items):
            raise ValueError(f"must be numbers (Td) or text as on the command line ({E_N_FORMS})")
        if any(isinstance(item, str) for item in items):
            return _e_n_values([str(item) for item in items])
        return items

    @field_validator("e_n")
    @classmethod
    def _fields_in_range(cls, values: list[float]) -> list[float]:
        """Every E/N finite and in [0, MAX_REDUCED_FIELD] Td (the library's range, named here as --E-N)."""
        if not values:
            raise ValueError(f"give at least one E/N value (Td, 0 to {_short(MAX_REDUCED_FIELD)})")
        if not all(0.0 <= value <= MAX_REDUCED_FIELD for value in values):  # NaN fails too
            raise ValueError(f"every E/N must be a finite number from 0 to {MAX_REDUCED_FIELD:g} Td")
        return [value + 0.0 for value in values]  # -0 is 0


class SwarmOptions(GasScanOptions):
    """Options of ``collisionkit swarm``; the physics is :class:`collisionkit.transport.SwarmParameters`.

    Examples
    --------
    >>> SwarmOptions.model_validate({"model": "reid", "e-n": [12, 24]}).parameters().reduced_field
    (12.0, 24.0)
    """

    flags: ClassVar[dict[str, str]] = {"e_n": "--E-N", "b_n": "--B-N", "omega_n": "--omega-N", "e": "--E"}
    # the field given on the command line (--E or --E-N) replaces the config file's, in either form
    chosen_together: ClassVar = (*GasScanOptions.chosen_together, (("e", "e_n"), ("e", "e_n")))
    b_n: float = Field(default=0.0, ge=0, le=MAX_REDUCED_MAGNETIC_FIELD, allow_inf_nan=False)
    angle: float = Field(default=90.0, ge=0, le=180, allow_inf_nan=False)
    omega_n: float = Field(default=0.0, ge=0, allow_inf_nan=False)
    waveform: list[tuple[float, float]] | None = None
    gas_temperature: float = Field(default=300.0, ge=0, le=MAX_GAS_TEMPERATURE, allow_inf_nan=False)
    particles: int = Field(default=20_000, ge=128, le=10_000_000)
    seed: int = Field(default=2026, ge=0)
    tolerance: float = Field(default=2e-3, gt=0, le=0.5, allow_inf_nan=False)
    collision_budget: float = Field(default=5e8, ge=1e4, allow_inf_nan=False)
    sharing: Literal["equal", "uniform"] = "equal"
    scattering: str | dict[str, str] | None = None  # checked by SwarmParameters, whose message names the laws
    populations: dict[str, float] | None = None
    e: list[float] | None = None  # V/cm with --pressure: sets e_n (._detector)
    pressure: float | None = None  # Torr: the detector's table
    out: Path | None = None
    summary: Path | None = None
    checkpoint: Path | None = None

    output_files: ClassVar[tuple[str, ...]] = ("summary", "checkpoint")
    output_folders: ClassVar[tuple[str, ...]] = ("out",)

    def folder_files(self, folder: str) -> tuple[str, ...]:
        """The plots and the table of ``--out`` (an earlier run's are not replaced without --overwrite)."""
        return SWARM_FILES

    @model_validator(mode="before")
    @classmethod
    def _fields_in_volts(cls, values: Any) -> Any:
        """--E in V/cm with --pressure: the E/N values it gives (._detector)."""
        return fields_from_volts(values) if isinstance(values, dict) else values

    @model_validator(mode="before")
    @classmethod
    def _numbers_by_their_flags(cls, values: Any) -> Any:
        """A string or a bool for E/N, B/N or omega/N (``E-N = "abc"`` in a TOML file) is refused naming the key as
        the command line spells it (E-N), before the shared check would name it e-n. (E in V/cm takes the --E-N
        forms as text: ._detector.)"""
        if not isinstance(values, dict):
            return values
        for key, value in values.items():
            name = str(key).replace("-", "_").lower()
            entries = value if isinstance(value, list) else [value]
            if name in cls.flags and name != "e" and any(isinstance(entry, (bool, str)) for entry in entries):
                plural = " or a list of numbers" if name == "e_n" else ""
                raise ValueError(f"{cls.flags[name].lstrip('-')} must be a number{plural}, not {value!r}")
        return values

    @model_validator(mode="before")
    @classmethod
    def _samples_or_file(cls, values: Any) -> Any:
        """``--waveform FILE`` (and ``waveform = "FILE"`` in a TOML file): two columns, the phase fraction and E/E0,
        read into the samples; a TOML list of pairs is taken as it is. A file that cannot be read is one message
        naming --waveform and the file (a model-level error: no echo of the path object)."""
        if not isinstance(values, dict) or not isinstance(values.get("waveform"), (str, Path)):
            return values
        from ..transport import read_waveform

        try:
            return dict(values) | {"waveform": read_waveform(Path(values["waveform"]))}
        except ValueError as error:
            raise ValueError(f"--waveform: {error}") from None

    @field_validator("omega_n")
    @classmethod
    def _frequency_in_range(cls, value: float) -> float:
        """omega/N 0 (static) or in REDUCED_FREQUENCY_RANGE (the library's range, named here as --omega-N)."""
        return checked_frequency(value)

    @field_validator("scattering", mode="before")
    @classmethod
    def _law_or_table(cls, value: Any) -> Any:
        """A law (a string) or a table of laws by process kind; the laws are checked by SwarmParameters."""
        if value is not None and not isinstance(value, (str, dict)):
            raise ValueError("must be a law (isotropic, okhrimovskyy, vahedi-surendra, forward) or a table of laws "
                             "by process kind")
        return value

    @model_validator(mode="after")
    def _physics(self):
        """The library's rules (one gas, E/N >= 0, a warm gas at E/N = 0 ...), so a sweep checks every point; the
        waveform's first, named as --waveform (its samples are not echoed); --pressure's (._detector)."""
        check_detector_options(self)
        if self.waveform is not None:
            from ..transport.swarm import check_waveform_peak

            try:
                check_waveform_peak(self.waveform, max(self.e_n))
            except ValueError as error:
                raise ValueError(f"--waveform: {error}") from None
        self.parameters()
        return self

    def parameters(self):
        """The scan's physics as :class:`collisionkit.transport.scan.SwarmParameters`.

        Examples
        --------
        >>> SwarmOptions(model="maxwell", seed=5).parameters().seed
        5
        """
        from ..transport.scan import SwarmParameters

        return SwarmParameters(reduced_field=self.e_n, model=self.model, gas=self.gas,
                               cross_sections=self.cross_sections,
                               species=self.species, fractions=self.fractions, database=self.database,
                               reduced_magnetic_field=self.b_n, field_angle=self.angle,
                               reduced_frequency=self.omega_n, waveform=self.waveform,
                               gas_temperature=self.gas_temperature, particles=self.particles, seed=self.seed,
                               tolerance=self.tolerance, collision_budget=self.collision_budget, sharing=self.sharing,
                               scattering=self.scattering, populations=self.populations)


# the files of a swarm run's --out: the EEDF, the table, the coefficients against E/N (a scan), W and <e> against the
# phase (an oscillating field)
SWARM_FILES = ("eedf.png", "swarm.csv", "transport_coefficients.png", "phase.png", "bolsig.dat", "detector.csv")
SWARM_OUTPUTS = ("out", "summary", "checkpoint", "overwrite", "pressure")  # what a resumed scan may change; the rest is physics


@contextmanager
def lxcat_notes():
    """Show the notes of an LXCat read (skipped blocks, clipped values: LXCatWarning) as one-line notes.

    A ``ValueError`` making the gas (an ``LXCatError`` among them) keeps its
    type, its message naming the options (``--fractions``), not the
    library's arguments (``fractions``).

    Examples
    --------
    >>> import warnings
    >>> from collisionkit.transport import LXCatWarning
    >>> with lxcat_notes():
    ...     warnings.warn("a note", LXCatWarning)
    """
    from ..transport import LXCatWarning

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", LXCatWarning)
        try:
            yield
        except ValueError as refused:  # the gas read from its files: "fractions: give one per species" is --fractions
            refused.args = (named_as_option(str(refused), GasScanOptions), *refused.args[1:])
            raise
        finally:
            for item in caught:
                if issubclass(item.category, LXCatWarning):
                    note(str(item.message))
                else:
                    warnings.warn_explicit(item.message, item.category, item.filename, item.lineno)


def _new_scan(options: SwarmOptions):
    from ..transport.scan import SwarmScan

    try:
        with lxcat_notes():
            return SwarmScan(options.parameters(), checkpoint=options.checkpoint, annotations=_annotations(options))
    except ValueError as error:  # the gas read from its files: "fractions: give one per species" is --fractions
        raise fail(named_as_option(str(error), SwarmOptions)) from None


def _resumed_scan(resume: Path, given: dict):
    """The scan saved in ``resume``; physics options given now must agree with it, outputs are only those given now."""
    from ..transport.scan import SwarmScan

    refuse_folder(resume, "--resume")
    physics = {_library_name(key): value for key, value in given.items() if key not in SWARM_OUTPUTS}
    try:
        with lxcat_notes():
            scan = SwarmScan.resume(resume, checkpoint=given.get("checkpoint", resume), **physics)
    except ValueError as error:
        raise fail(str(error)) from None
    outputs = {key: value for key, value in given.items() if key in SWARM_OUTPUTS} | {"checkpoint": scan.checkpoint}
    saved_pressure = scan.annotations.get("pressure")
    if outputs.get("pressure") is None and isinstance(saved_pressure, (int, float)):
        outputs["pressure"] = saved_pressure
        note(f"--pressure {saved_pressure:g} Torr, as the scan was started with (its detector table)")
    options = validate_options(SwarmOptions, _options_of(scan.parameters) | outputs, keep=[resume])
    scan.annotations = _annotations(options)
    return scan, options


def _annotations(options: SwarmOptions) -> dict:
    """What the command line keeps with a scan's checkpoint: the detector's pressure, if any."""
    return {} if options.pressure is None else {"pressure": options.pressure}


def _before_the_work(scan, options: SwarmOptions) -> None:
    """The checks and notes before a scan runs: the plotting extra, the memory, the seed, the kernels."""
    if options.out is not None:
        require("matplotlib", "plot", "plots (--out)")
    ionizing = any(process.kind in ("ionization", "attachment") for _, process in scan.gas.processes)
    kind = " of a gas that ionizes or attaches" if ionizing else ""
    refuse_beyond_memory(swarm_memory(options.particles, ionizing, options.checkpoint is not None), f"--particles {options.particles}{kind}",
                         ": use fewer particles")
    if options.b_n == 0.0 and options.angle != 90.0:
        note(f"--angle {options.angle:g} has no effect without --B-N (no magnetic field)")
    if options.omega_n > 0.0 and ionizing:
        note("alpha/N and eta/N are NaN in an AC field: the steady-state Townsend growth they describe has no "
             "meaning there; the rate coefficients are cycle averages")
    note(f"seed {options.seed} (--seed {options.seed} repeats this run)")
    warm_up(["swarm"])


def _library_name(key: str) -> str:
    return {"e_n": "reduced_field", "b_n": "reduced_magnetic_field", "angle": "field_angle",
            "omega_n": "reduced_frequency"}.get(key, key)


def _options_of(parameters) -> dict:
    """The command's options for library parameters (E/N as e_n ...)."""
    names = {"reduced_field": "e_n", "reduced_magnetic_field": "b_n", "field_angle": "angle",
             "reduced_frequency": "omega_n"}
    return {names.get(key, key): value for key, value in parameters.to_dict().items()}


def _phase_plots(results, out: Path, deliveries: Deliveries) -> None:
    """W(phase) and <e>(phase) of an oscillating field, in ``out``/phase.png."""
    import matplotlib

    matplotlib.use("Agg")
    from .. import plotting

    deliveries.write(f"the plot {out / 'phase.png'}",
                     lambda: plotting.save(plotting.plot_phase_resolved(results)[0], out / "phase.png"))


def _swarm_plots(results, out: Path, deliveries: Deliveries, reid_benchmark: bool) -> None:
    """The plots and swarm.csv in ``out``, each written through ``deliveries``; the published Reid values are drawn
    only for the run they describe (``reid_benchmark``: Reid's ramp at 0 K without a magnetic field)."""
    import matplotlib

    matplotlib.use("Agg")
    from .. import plotting
    from ..sweep import write_csv

    deliveries.write(f"the folder {out}", lambda: out.mkdir(parents=True, exist_ok=True))
    deliveries.write(f"the plot {out / 'eedf.png'}",
                     lambda: plotting.save(plotting.plot_energy_distribution(results), out / "eedf.png"))
    deliveries.write(f"the table {out / 'swarm.csv'}",
                     lambda: write_csv(out / "swarm.csv", [result.to_row() for result in results]))
    if len(results) > 1:
        deliveries.write(f"the plot {out / 'transport_coefficients.png'}", lambda: plotting.save(
            plotting.plot_transport_coefficients(results, reference=plotting.REID_PUBLISHED if reid_benchmark else ())
            .flat[0], out / "transport_coefficients.png"))
    else:  # one E/N: no curve; an earlier scan's (replaced with --overwrite) would not be of these results
        (out / "transport_coefficients.png").unlink(missing_ok=True)
    _bolsig_table(results, out, deliveries)


def _bolsig_table(results, out: Path, deliveries: Deliveries) -> None:
    """bolsig.dat in ``out``: the scan as BOLSIG+'s output tables, for fluid codes (a static E alone: else none, and
    an earlier run's is removed)."""
    from ..transport import write_bolsig_tables

    if any(result.reduced_magnetic_field != 0.0 or result.reduced_frequency != 0.0 for result in results):
        (out / "bolsig.dat").unlink(missing_ok=True)
        return
    deliveries.write(f"the tables {out / 'bolsig.dat'}", lambda: write_bolsig_tables(out / "bolsig.dat", results))
    warn_missing_rows(results, out / "bolsig.dat")


def warn_missing_rows(results, path: Path) -> None:
    """Warn of each section of ``path`` (BOLSIG+'s tables) that leaves out E/N where its value is not a number."""
    from ..transport import missing_rows

    for header, fields in missing_rows(results).items():
        warn(f"{path}: {header} has no line at E/N = {', '.join(f'{value:g}' for value in fields)} Td (not a number "
             "there), so its E/N column is shorter than the other sections'")


# the gas and E/N options of swarm and boltzmann (GasScanOptions)
ModelOption = Annotated[str | None, typer.Option(help="Model gas: maxwell, hard_sphere, reid, lucas_saelee.")]
GasOption = Annotated[str | None, typer.Option(
    help="Real gas by name (collisionkit gases lists them), or a mixture by mole fraction: 'Ar:0.9,N2:0.1'.")]
CrossSectionsOption = Annotated[list[Path] | None, typer.Option(
    "--cross-sections", help="LXCat cross-section file (repeat to join files).")]
SpeciesOption = Annotated[list[str] | None, typer.Option(help="Species of the LXCat files to use (repeat).")]
FractionsOption = Annotated[list[float] | None, typer.Option(
    help="Their number fractions (repeat), one per species.  \\[default: equal fractions]")]
DatabaseOption = Annotated[str | None, typer.Option(
    help="Database to take a species from when the LXCat files hold it from several (e.g. Biagi).")]
ReducedFieldsOption = Annotated[list[str] | None, typer.Option(
    "--E-N", help="E/N in Td, 0 to 1e6; repeat or comma list for a sweep; START:STOP:COUNT gives COUNT values from "
                  "START to STOP evenly spaced, START:STOP:COUNT:log logarithmically spaced (START > 0), e.g. "
                  "1:1000:7:log.  \\[default: 12]")]
SharingOption = Annotated[str | None, typer.Option(help="Ionization energy sharing: equal or uniform.  \\[default: equal]")]


def swarm(
    model: ModelOption = None,
    gas: GasOption = None,
    cross_sections: CrossSectionsOption = None,
    species: SpeciesOption = None,
    fractions: FractionsOption = None,
    database: DatabaseOption = None,
    e_n: ReducedFieldsOption = None,
    e: Annotated[list[str] | None, typer.Option(
        "--E", help="The field in V/cm instead of --E-N, with --pressure (as --E-N: repeat, or 100:1000:10).")] = None,
    pressure: Annotated[float | None, typer.Option(
        help="Gas pressure in Torr (760 = 1 atm): also a table in a detector's units (E in V/cm, drift in cm/us, "
             "diffusion as sigma/sqrt(cm), alpha and eta in 1/cm; --out's detector.csv).")] = None,
    b_n: Annotated[float | None, typer.Option(
        "--B-N", help="B/N in Hx (0 to 1e6, static), in the y-z plane at --angle from E (E along z).  "
                      "\\[default: 0]")] = None,
    angle: Annotated[float | None, typer.Option(
        "--angle", help="Degrees between E and B, 0 to 180 (B = |B| (0, sin, cos)).  \\[default: 90]")] = None,
    omega_n: Annotated[float | None, typer.Option(
        "--omega-N", help="omega/N in rad m^3/s, 0 (static) or 1e-20 to 1e-8: E(t) = E0 cos(omega t) with --E-N the "
                          "amplitude E0/N; results by phase and cycle averages.  \\[default: 0]")] = None,
    waveform: Annotated[Path | None, typer.Option(
        "--waveform", help="A periodic field of any shape instead of the cosine, with --omega-N (and --B-N, --angle if "
                           "wanted): a file of two columns, the fraction of the period (0 to 1) and E/E0 "
                           "(within +-1e6; the peak E/N, --E-N times the largest |E/E0|, at most 1e6 Td), "
                           "linear between samples (the same fraction twice: a jump).")] = None,
    gas_temperature: Annotated[float | None, typer.Option(
        help="Gas temperature in K (0 to 1e5): targets' Maxwellian and Boltzmann populations of reversible excitations "
             "(superelastic collisions); 0 for the model-gas benchmarks.  \\[default: 300]")] = None,
    particles: Annotated[int | None, typer.Option(help="Simulated particles (128 to 1e7).  \\[default: 20000]")] = None,
    seed: Annotated[int | None, typer.Option(help="Random seed (>= 0).  \\[default: 2026]")] = None,
    tolerance: Annotated[float | None, typer.Option(
        help="Target relative error of mean energy and drift (of mean energy alone at E/N = 0 and with --omega-N), in "
             "(0, 0.5].  \\[default: 0.002]")] = None,
    collision_budget: Annotated[float | None, typer.Option(
        help="Stop after this many real collisions per E/N (>= 1e4).  \\[default: 5e8]")] = None,
    sharing: SharingOption = None,
    scattering: Annotated[str | None, typer.Option(
        help="Angular scattering law of every process: isotropic, okhrimovskyy, vahedi-surendra or forward (elastic "
             "tables are momentum transfer, converted; per process kind: a [scattering] table in --config).  "
             "\\[default: isotropic]")] = None,
    out: Annotated[Path | None, typer.Option(
        help="Folder for plots, swarm.csv (a row per E/N) and bolsig.dat (the coefficients as BOLSIG+'s output tables, "
             "which plasma fluid codes read; static E without B only) (none if not given).")] = None,
    summary: Annotated[Path | None, typer.Option("--summary", help="Write the results as JSON to this file.")] = None,
    checkpoint: Annotated[Path | None, typer.Option(
        help="Write the finished E/N points to this checkpoint after each one, and the running point's state every "
             "minute (atomically): a .npz file (a numpy zip archive) for --resume.")] = None,
    resume: Annotated[Path | None, typer.Option(
        help="Continue the scan saved in this checkpoint, with its options (only --summary, --out, --checkpoint may "
             "change): skips its finished points, goes on with a running one from its saved state; checkpoints go on "
             "to it unless --checkpoint is given.")] = None,
    config: Annotated[Path | None, typer.Option(
        "--config", help="TOML file with these options (command line wins).")] = None,
    overwrite: OverwriteOption = None,
):
    """Electron swarm transport coefficients (mean energy, drift, diffusion, rates, SST Townsend alpha/N and eta/N)
    against E/N."""
    given = dict(model=model, gas=gas, cross_sections=cross_sections, species=species, fractions=fractions,
                 database=database, e_n=_e_n_values(e_n), e=_e_n_values(e, "--E", "V/cm", math.inf),
                 pressure=pressure,
                 b_n=b_n, angle=angle, omega_n=omega_n, waveform=waveform, gas_temperature=gas_temperature,
                 particles=particles, seed=seed, tolerance=tolerance,
                 collision_budget=collision_budget, sharing=sharing, scattering=scattering, out=out, summary=summary,
                 checkpoint=checkpoint,
                 overwrite=overwrite)
    if resume is not None and e is not None:
        raise fail("--E is the scan's physics, saved as its E/N: a resumed scan keeps them (and its --pressure, for "
                   "the detector's table)")
    if resume is None:
        options = load_options(SwarmOptions, config, given)
        refuse_checkpoint_suffix(options.checkpoint)
        scan = _new_scan(options)
    else:
        values = option_values(SwarmOptions, config, given)
        refuse_checkpoint_suffix(values.get("checkpoint"))  # (a resumed scan goes on writing --resume's own file)
        scan, options = _resumed_scan(resume, values)
        if scan.running_point is not None:
            note(f"E/N = {options.e_n[scan.running_point]:g} Td goes on from its state saved in {resume}")
    _before_the_work(scan, options)
    results = scan.results
    try:
        with progress_bar("swarm", total=len(options.e_n)) as advance:
            report = fraction_reporter(advance, len(options.e_n))
            report(len(results) / len(options.e_n))
            scan.run(progress=report)
    except FileLockedError as locked:
        raise fail(f"{locked}: another collisionkit run is writing it; wait for it or name another --checkpoint") \
            from None
    except ValueError as refused:  # the gas cannot make a swarm (no collision process at all)
        raise fail(str(refused)) from None
    except RuntimeError as failure:  # the engine's watchdog: a runaway particle (zero or tiny cross sections)
        raise run_failed(f"the scan stopped: {failure}") from None
    except (KeyboardInterrupt, OSError) as stop:
        running = "" if scan.running_point is None else \
            f", and E/N = {options.e_n[scan.running_point]:g} Td as it was at its last save"
        where = (f"{len(results)} of {len(options.e_n)} E/N points are saved in {options.checkpoint}{running}; "
                 f"continue with --resume {options.checkpoint}" if options.checkpoint is not None else
                 "no --checkpoint was given, so nothing is saved")
        if isinstance(stop, OSError):
            raise run_failed(f"the scan stopped: {stop}; {where}") from None
        warn(f"interrupted: {where}")
        raise typer.Exit(INTERRUPTED_EXIT_CODE) from None
    print_swarm_tables(results, options.b_n != 0.0, options.omega_n > 0.0, options.angle)
    unconverged = [f"{r.reduced_field:g}" for r in results if not r.converged]
    if unconverged:
        message = (f"E/N = {', '.join(unconverged)} Td stopped at the collision budget "
                   f"({options.collision_budget:g}) before reaching the tolerance {options.tolerance:g}: "
                   "their errors are larger than asked; rerun with a larger --collision-budget")
        warn(message)
    deliveries = Deliveries("swarm")
    if options.out is not None:
        reid = options.model == "reid" and options.gas_temperature == 0.0 and options.b_n == 0.0 and \
            options.scattering is None
        _swarm_plots(results, options.out, deliveries, reid)
        if options.omega_n > 0.0:
            _phase_plots(results, options.out, deliveries)
        else:  # an earlier run's (replaced with --overwrite), of another field
            (options.out / "phase.png").unlink(missing_ok=True)
        if options.pressure is None:  # an earlier run's detector table, of another scan
            (options.out / "detector.csv").unlink(missing_ok=True)
    detector = None if options.pressure is None else detector_report(results, options.pressure, options.out,
                                                                     deliveries)
    for path in deliveries.files:
        say(f"wrote {path}")
    result = scan.summary(deliveries.files) | {"seed": options.seed}
    for entry, row in zip(result["results"] if detector else (), detector or ()):
        entry["detector"] = row
    if detector and len(detector) == 1:  # one E/N: its values are at the top level too (swarm_summary)
        result["detector"] = detector[0]
    deliveries.finish(options.summary, result)


def register(app: typer.Typer) -> None:
    """Add the ``swarm`` command to the ``collisionkit`` app."""
    app.command("swarm")(swarm)
