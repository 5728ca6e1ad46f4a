"""The ``boltzmann`` subcommand: the two-term Boltzmann equation against E/N, BOLSIG+'s job.

The gas options are the ``swarm`` command's (a model gas, a catalogue gas or
LXCat files); each E/N is :func:`collisionkit.transport.two_term_boltzmann`,
which a Python script calls the same way.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, ClassVar, Literal

import typer
from pydantic import Field, field_validator, model_validator

from ._common import (
    INTERRUPTED_EXIT_CODE, Deliveries, OverwriteOption, error, fail, load_options, named_as_option, note,
    print_table, progress_bar, run_failed, say, warn,
)
from ._transport import (
    MAX_GAS_TEMPERATURE, CrossSectionsOption, DatabaseOption, FractionsOption, GasOption, GasScanOptions, ModelOption,
    ReducedFieldsOption, SharingOption, SpeciesOption, _e_n_values, checked_frequency, lxcat_notes, warn_missing_rows,
)

# transport.two_term's (not imported: the library loads only when a command runs)
MAX_IONIZATION_DEGREE = 0.01
MIN_GAS_TEMPERATURE = 1e-6  # K, if not 0
# --out: a row per E/N; the EEDFs (E/N, energy, F0); their plot (with the plot extra); BOLSIG+'s tables (static E)
BOLTZMANN_FILES = ("boltzmann.csv", "eedf.csv", "eedf.png", "bolsig.dat")


class BoltzmannOptions(GasScanOptions):
    """Options of ``collisionkit boltzmann``; the gas is chosen as for ``swarm``.

    Examples
    --------
    >>> BoltzmannOptions.model_validate({"model": "reid", "e-n": [1, 12]}).e_n
    [1.0, 12.0]
    """

    gas_temperature: float = Field(default=300.0, ge=0, le=MAX_GAS_TEMPERATURE, allow_inf_nan=False)
    cells: int = Field(default=1000, ge=50, le=100_000)
    max_energy: float | None = Field(default=None, gt=0, le=1e7, allow_inf_nan=False)
    sharing: Literal["equal", "uniform"] = "equal"
    growth: Literal["temporal", "spatial"] = "temporal"
    ionization_degree: float = Field(default=0.0, ge=0, le=MAX_IONIZATION_DEGREE, allow_inf_nan=False)
    electron_density: float | None = Field(default=None, gt=0, le=1e32, allow_inf_nan=False)
    omega_n: float = Field(default=0.0, ge=0, allow_inf_nan=False)
    populations: dict[str, float] | None = None  # a config file's [populations] table, as swarm's
    out: Path | None = None
    summary: Path | None = None

    flags: ClassVar[dict[str, str]] = {"e_n": "--E-N", "omega_n": "--omega-N"}
    output_files: ClassVar[tuple[str, ...]] = ("summary",)
    output_folders: ClassVar[tuple[str, ...]] = ("out",)

    def folder_files(self, folder: str) -> tuple[str, ...]:
        """The tables of ``--out`` (an earlier run's are not replaced without --overwrite)."""
        return BOLTZMANN_FILES

    @field_validator("omega_n")
    @classmethod
    def _frequency_in_range(cls, value: float) -> float:
        """omega/N 0 (a DC field) or the swarm's range."""
        return checked_frequency(value)

    @model_validator(mode="after")
    def _physics(self):
        """The library's rules on the gas (one of model, gas, cross sections; a warm gas at E/N = 0) and on the
        electron-electron collisions (a degree and a density, or neither)."""
        self.parameters()
        if self.ionization_degree > 0.0 and self.electron_density is None:
            raise ValueError("--ionization-degree > 0 needs --electron-density (m^-3, in (0, 1e32]) for the "
                             "Coulomb logarithm")
        if self.ionization_degree == 0.0 and self.electron_density is not None:
            raise ValueError("--electron-density is used only with --ionization-degree > 0 (electron-electron "
                             "collisions); give both or neither")
        if 0.0 < self.gas_temperature < MIN_GAS_TEMPERATURE:
            raise ValueError(f"--gas-temperature must be 0 or from {MIN_GAS_TEMPERATURE:g} to "
                             f"{MAX_GAS_TEMPERATURE:g} K; got {self.gas_temperature:g}")
        if self.omega_n > 0.0 and self.growth == "spatial":
            raise ValueError("--growth spatial (steady-state Townsend) is for a DC field; with --omega-N use "
                             "--growth temporal")
        return self

    def parameters(self):
        """The gas and fields as :class:`collisionkit.transport.SwarmParameters` (its gas choice and checks).

        Examples
        --------
        >>> BoltzmannOptions(model="reid").parameters().make_gas().species[0].name
        'reid'
        """
        from ..transport.scan import SwarmParameters

        return SwarmParameters(reduced_field=self.e_n, model=self.model, gas=self.gas,
                               cross_sections=self.cross_sections, species=self.species, fractions=self.fractions,
                               database=self.database, gas_temperature=self.gas_temperature, sharing=self.sharing,
                               populations=self.populations)


# the library's spellings in its messages, as a user of this command writes them
_CLI_SPELLINGS = (("growth='temporal'", "--growth temporal"), ("growth='spatial'", "--growth spatial"),
                  ("use simulate_swarm", "use the Monte Carlo swarm (collisionkit swarm)"),
                  ("simulate_sst", "the Monte Carlo (collisionkit.transport.simulate_sst)"),
                  ("max_energy =", "--max-energy"), ("max_energy", "--max-energy"), ("cells =", "--cells"))


def _as_cli(message: str) -> str:
    """A library message with its argument spellings written as this command's options."""
    message = named_as_option(message, BoltzmannOptions)
    for library, cli in _CLI_SPELLINGS:
        message = message.replace(library, cli)
    return message


def _scan(options: BoltzmannOptions):
    """The scan at every E/N, with a progress bar (:class:`collisionkit.transport.TwoTermScan`, which a Python
    script runs the same way). A point that fails is kept as a failure and the scan goes on; Ctrl-C stops it,
    keeping the points solved (the caller writes them, then exits 130). Returns (scan, interrupted)."""
    from ..transport import TwoTermScan

    try:
        with lxcat_notes():
            gas = options.parameters().make_gas()
    except ValueError as error:
        raise fail(str(error)) from None
    scan = TwoTermScan(gas, options.e_n, gas_temperature=options.gas_temperature, cells=options.cells,
                       max_energy=options.max_energy, sharing=options.sharing, growth=options.growth,
                       ionization_degree=options.ionization_degree, electron_density=options.electron_density,
                       omega_N=options.omega_n)
    try:
        with progress_bar("E/N points", total=len(options.e_n)) as advance:
            scan.run(progress=lambda: advance(1))
    except ValueError as error:  # a Coulomb logarithm below 2 at the solution's mean energy: the density is wrong
        value = options.e_n[len(scan.results) + len(scan.failed)]
        raise fail(f"E/N = {value:g} Td: {_as_cli(str(error))}") from None
    except KeyboardInterrupt:
        done = len(scan.results) + len(scan.failed)
        warn(f"interrupted after {done} of {len(options.e_n)} E/N points: the finished ones are written")
        return scan, True
    return scan, False


def _print(results, options: BoltzmannOptions) -> None:
    rows = [(f"{r.reduced_field:g}", f"{r.mean_energy:.5g}", f"{r.drift_velocity:.5g}", f"{r.diffusion_N:.5g}",
             f"{r.characteristic_energy:.4g}", f"{r.alpha_N:.4g}", f"{r.eta_N:.4g}") for r in results]
    colliding = (f", electron-electron collisions at n_e/N = {options.ionization_degree:g}"
                 if options.ionization_degree else "")
    oscillating = f", E/N the amplitude at omega/N = {options.omega_n:g} rad m^3/s" if options.omega_n else ""
    print_table(f"two-term Boltzmann equation, {options.growth} growth{colliding}{oscillating} (flux values)",
                ("E/N (Td)", "<e> (eV)", "W (m/s)", "N D (1/m/s)", "D/mu (eV)", "alpha/N (m^2)", "eta/N (m^2)"),
                rows)


def _write_tables(scan, out: Path, deliveries: Deliveries) -> None:
    from .._io import write_csv

    deliveries.write(f"the folder {out}", lambda: out.mkdir(parents=True, exist_ok=True))
    deliveries.write(f"the table {out / 'boltzmann.csv'}", lambda: write_csv(out / "boltzmann.csv", scan.table()))
    deliveries.write(f"the table {out / 'eedf.csv'}", lambda: write_csv(out / "eedf.csv", scan.eedf_table()))
    if all(result.omega_N == 0.0 for result in scan.results):  # BOLSIG+'s tables: a static E
        from ..transport import write_bolsig_tables

        deliveries.write(f"the tables {out / 'bolsig.dat'}", lambda: write_bolsig_tables(out / "bolsig.dat",
                                                                                          scan.results))
        warn_missing_rows(scan.results, out / "bolsig.dat")
    else:  # an earlier run's is not of these results
        (out / "bolsig.dat").unlink(missing_ok=True)
    try:
        import matplotlib
    except ImportError:
        note("no eedf.png: plots need matplotlib (pip install 'collisionkit[plot]'); the tables are written")
        return
    matplotlib.use("Agg")
    from .. import plotting

    deliveries.write(f"the plot {out / 'eedf.png'}",
                     lambda: plotting.save(plotting.plot_two_term_eedf(scan.results), out / "eedf.png"))


def boltzmann_summary(options: BoltzmannOptions, scan, files=()) -> dict:
    """The command's JSON summary: ``gas``, the scan's :meth:`~collisionkit.transport.TwoTermScan.summary`
    (``results``, ``failed``, ``warnings`` with the options' spellings, ``units``), ``provenance``
    (collisionkit's version, the cross-section files with their SHA-256), ``files`` and ``parameters``.

    Examples
    --------
    >>> from collisionkit.transport import TwoTermScan, reid_ramp
    >>> options = BoltzmannOptions(model="reid", e_n=[12.0], gas_temperature=0.0)
    >>> summary = boltzmann_summary(options, TwoTermScan(reid_ramp(), [12.0], gas_temperature=0.0).run())
    >>> summary["gas"], summary["results"][0]["E_N"], summary["parameters"]["cells"]
    ('reid', 12.0, 1000)
    """
    parameters = options.model_dump(mode="json", by_alias=True, exclude={"out", "summary", "overwrite"})
    found = scan.summary()
    found["failed"] = [failure | {"reason": _as_cli(failure["reason"])} for failure in found["failed"]]
    found["warnings"] = [_as_cli(message) for message in found["warnings"]]
    return {"gas": options.parameters().gas_name(), **found, "provenance": _provenance(options),
            "files": [str(path) for path in files], "parameters": parameters}


def _provenance(options: BoltzmannOptions) -> dict:
    """What the numbers came from: collisionkit's version and each cross-section file with its SHA-256."""
    from ..transport.two_term_scan import provenance

    return provenance(options.parameters().gas_files())


def boltzmann(
    model: ModelOption = None,
    gas: GasOption = None,
    cross_sections: CrossSectionsOption = None,
    species: SpeciesOption = None,
    fractions: FractionsOption = None,
    database: DatabaseOption = None,
    e_n: ReducedFieldsOption = None,
    gas_temperature: Annotated[float | None, typer.Option(
        help="Gas temperature in K (0 to 1e5): thermal energy of the targets and Boltzmann populations of reversible "
             "excitations (superelastic collisions).  \\[default: 300]")] = None,
    cells: Annotated[int | None, typer.Option(
        help="Cells of the energy grid (50 to 1e5); its top is found where the EEDF has fallen 10-18 decades.  "
             "\\[default: 1000]")] = None,
    max_energy: Annotated[float | None, typer.Option(
        help="Top of the energy grid in eV (0 to 1e7), the same for every E/N; by default it is found for each "
             "E/N where the EEDF has fallen 10-18 decades.")] = None,
    sharing: SharingOption = None,
    growth: Annotated[str | None, typer.Option(
        help="Growth of an ionizing or attaching swarm: temporal (alpha/N = k_i/W) or spatial (steady-state Townsend, "
             "self-consistent alpha/N).  \\[default: temporal]")] = None,
    ionization_degree: Annotated[float | None, typer.Option(
        help="n_e/N (0 to 0.01): above 0 the electrons also collide with each other (Coulomb collisions, as BOLSIG+ "
             "and LoKI-B), which pulls the EEDF towards a Maxwellian.  \\[default: 0]")] = None,
    electron_density: Annotated[float | None, typer.Option(
        help="n_e in m^-3 (0 to 1e32) for the Coulomb logarithm; needed with --ionization-degree.")] = None,
    omega_n: Annotated[float | None, typer.Option(
        "--omega-N", help="omega/N in rad m^3/s, 0 (DC) or 1e-20 to 1e-8: a high-frequency field E0 cos(omega t), "
                          "--E-N its amplitude E0/N (as swarm's; BOLSIG+ takes the RMS value), faster than the "
                          "electrons' energy relaxation.  \\[default: 0]")] = None,
    out: Annotated[Path | None, typer.Option(
        help="Folder for boltzmann.csv (a row per E/N: moments and every rate coefficient; SI units, energies in "
             "eV, E/N in Td: the summary's units lists them), eedf.csv (E/N in Td, energy in eV, F0 in eV^-3/2 "
             "with the integral of eps^1/2 F0 equal to 1), eedf.png and bolsig.dat (the coefficients as BOLSIG+'s "
             "output tables, which plasma fluid codes read; static E only).")] = None,
    summary: Annotated[Path | None, typer.Option("--summary", help="Write the results as JSON to this file.")] = None,
    config: Annotated[Path | None, typer.Option(
        "--config", help="TOML file with these options (command line wins).")] = None,
    overwrite: OverwriteOption = None,
):
    """The two-term Boltzmann equation (as BOLSIG+): EEDF, mean energy, mobility, diffusion and rate coefficients
    against E/N (milliseconds per E/N for model gases, 0.1-0.7 s for the shipped LXCat gases); the swarm command
    is its exact Monte Carlo check."""
    given = dict(model=model, gas=gas, cross_sections=cross_sections, species=species, fractions=fractions,
                 database=database, e_n=_e_n_values(e_n), gas_temperature=gas_temperature, cells=cells,
                 max_energy=max_energy,
                 sharing=sharing, growth=growth, ionization_degree=ionization_degree,
                 electron_density=electron_density, omega_n=omega_n, out=out, summary=summary, overwrite=overwrite)
    options = load_options(BoltzmannOptions, config, given)
    scan, interrupted = _scan(options)
    for message in scan.warnings:
        warn(_as_cli(message))
    if scan.results:
        _print(scan.results, options)
    deliveries = Deliveries("boltzmann")
    if options.out is not None and scan.results:
        _write_tables(scan, options.out, deliveries)
    for path in deliveries.files:
        say(f"wrote {path}")
    deliveries.finish(options.summary, boltzmann_summary(options, scan, deliveries.files))
    if interrupted:
        raise typer.Exit(INTERRUPTED_EXIT_CODE)
    if scan.failed:
        reasons = [f"E/N = {failure['E_N']:g} Td: {_as_cli(failure['reason'])}" for failure in scan.failed]
        for reason in reasons[:-1]:
            error(reason)
        raise run_failed(reasons[-1])


def register(app: typer.Typer) -> None:
    """Add the ``boltzmann`` command to the ``collisionkit`` app."""
    app.command("boltzmann")(boltzmann)
