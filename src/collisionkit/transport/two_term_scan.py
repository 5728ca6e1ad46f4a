"""A scan of the two-term Boltzmann equation over E/N, as ``collisionkit boltzmann`` runs it, from Python.

:class:`TwoTermScan` solves :func:`~collisionkit.transport.two_term_boltzmann`
at each E/N in turn, keeps a point that fails (a growth without a steady
state) as a failure with its reason and goes on, collects the solver's
warnings, and writes the command's tables (``boltzmann.csv``, ``eedf.csv``).
"""

from __future__ import annotations

import dataclasses
import warnings
from pathlib import Path
from typing import Any, ClassVar

from .._io import file_digest, write_csv
from .._params import Parameters, check_choice, check_integer, check_real
from ._validation import check_reduced_frequency
from .gases import Gas
from .two_term import (
    GROWTH_MODELS, MIN_GAS_TEMPERATURE, SHARING, UNITS, TwoTermWarning, _checked_electrons, two_term_boltzmann,
)

__all__ = ["TwoTermParameters", "TwoTermScan", "run_two_term", "two_term_summary"]

TABLE_FILES = ("boltzmann.csv", "eedf.csv")


class TwoTermScan:
    """Two-term solutions at each E/N of a scan, the points that failed (with why) and the solver's warnings.

    Parameters
    ----------
    gas : Gas
    reduced_fields : sequence of float
        E/N values (Td), solved in this order.
    **options
        :func:`~collisionkit.transport.two_term_boltzmann`'s keywords (``gas_temperature``, ``cells``,
        ``max_energy``, ``sharing``, ``growth``, ``ionization_degree``, ``electron_density``, ``omega_N``).

    Attributes
    ----------
    results : list of TwoTermResult
        The points solved, in order.
    failed : list of dict
        ``{"E_N": value, "reason": message}`` of each point whose solution does not exist (a RuntimeError of
        the solver); the scan goes on past it.
    warnings : list of str
        The solver's :class:`~collisionkit.transport.TwoTermWarning` messages (results to read with care).

    Examples
    --------
    >>> from collisionkit.transport import lucas_saelee
    >>> scan = TwoTermScan(lucas_saelee(0.5), [50.0, 3000.0], gas_temperature=0.0, growth="spatial").run()
    >>> [r.reduced_field for r in scan.results], scan.failed[0]["E_N"]
    ([50.0], 3000.0)
    """

    def __init__(self, gas: Gas, reduced_fields, **options):
        self.gas = gas
        self.reduced_fields = [float(value) for value in reduced_fields]
        self.options = options
        self.results, self.failed, self.warnings = [], [], []

    def run(self, progress=None) -> TwoTermScan:
        """Solve every E/N not solved yet; ``progress()`` is called after each. A ValueError (an input the
        solution shows wrong, e.g. a Coulomb logarithm below 2) propagates, as does KeyboardInterrupt: the
        points solved so far stay in :attr:`results`, and ``run()`` again goes on from the next.

        Examples
        --------
        >>> from collisionkit.transport import reid_ramp
        >>> len(TwoTermScan(reid_ramp(), [1.0, 12.0], gas_temperature=0.0).run().results)
        2
        """
        for value in self.reduced_fields[len(self.results) + len(self.failed):]:
            self.solve(value)
            if progress is not None:
                progress()
        return self

    def solve(self, value: float) -> None:
        """Solve at one E/N, keeping a failure as this point's result and the warnings as messages.

        Examples
        --------
        >>> from collisionkit.transport import catalogue_gas
        >>> scan = TwoTermScan(catalogue_gas("Ar"), [])
        >>> scan.solve(1e4)
        >>> len(scan.results), "above 1000 eV" in scan.warnings[0]
        (1, True)
        """
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", TwoTermWarning)
            try:
                self.results.append(two_term_boltzmann(self.gas, value, **self.options))
            except RuntimeError as failure:
                self.failed.append({"E_N": value, "reason": str(failure)})
        for message in caught:
            if issubclass(message.category, TwoTermWarning):
                self.warnings.append(str(message.message))
            else:  # not ours to keep: shown as if not caught
                warnings.warn_explicit(message.message, message.category, message.filename, message.lineno)

    def table(self) -> list[dict]:
        """A row per E/N solved (:meth:`TwoTermResult.to_row <collisionkit.transport.TwoTermResult.to_row>`):
        ``boltzmann.csv``; the units are :data:`~collisionkit.transport.two_term.UNITS`.

        Examples
        --------
        >>> from collisionkit.transport import reid_ramp
        >>> TwoTermScan(reid_ramp(), [12.0], gas_temperature=0.0).run().table()[0]["E_N"]
        12.0
        """
        return [result.to_row() for result in self.results]

    def eedf_table(self) -> list[dict]:
        """The distributions, a row per E/N and cell (``E_N`` Td, ``energy`` eV, ``eedf`` eV^-3/2 normalised to
        the integral of eps^1/2 F0 = 1): ``eedf.csv``.

        Examples
        --------
        >>> from collisionkit.transport import reid_ramp
        >>> len(TwoTermScan(reid_ramp(), [12.0], gas_temperature=0.0, cells=200).run().eedf_table())
        200
        """
        return [{"E_N": r.reduced_field, "energy": float(energy), "eedf": float(value)}
                for r in self.results for energy, value in zip(r.energy, r.eedf)]

    def write(self, folder, overwrite: bool = False) -> list[Path]:
        """Write ``boltzmann.csv`` and ``eedf.csv`` into ``folder`` (made if missing), each atomically; a
        FileExistsError before writing anything if one exists and ``overwrite`` is False. Returns the paths.

        Examples
        --------
        >>> import tempfile
        >>> from collisionkit.transport import reid_ramp
        >>> scan = TwoTermScan(reid_ramp(), [12.0], gas_temperature=0.0).run()
        >>> [path.name for path in scan.write(tempfile.mkdtemp())]
        ['boltzmann.csv', 'eedf.csv']
        """
        folder = Path(folder)
        paths = [folder / name for name in TABLE_FILES]
        taken = [str(path) for path in paths if path.exists()]
        if taken and not overwrite:
            raise FileExistsError(f"{', '.join(taken)} exist(s): pass overwrite=True to replace")
        folder.mkdir(parents=True, exist_ok=True)
        write_csv(paths[0], self.table())
        write_csv(paths[1], self.eedf_table())
        return paths

    def summary(self) -> dict:
        """``results`` (one :meth:`~collisionkit.transport.TwoTermResult.to_dict` per E/N solved, with ``E_N``),
        ``failed``, ``warnings`` and ``units``: the command's JSON summary but for its parameters and files.

        Examples
        --------
        >>> from collisionkit.transport import reid_ramp
        >>> sorted(TwoTermScan(reid_ramp(), [12.0], gas_temperature=0.0).run().summary())
        ['failed', 'results', 'units', 'warnings']
        """
        return {"results": [result.to_dict() | {"E_N": result.reduced_field} for result in self.results],
                "failed": list(self.failed), "warnings": list(self.warnings), "units": dict(UNITS)}


@dataclasses.dataclass(frozen=True)
class TwoTermParameters(Parameters):
    """The ``boltzmann`` command's scan as checked data: the gas as :class:`~collisionkit.transport.SwarmParameters`
    chooses it, and :func:`~collisionkit.transport.two_term_boltzmann`'s options (what a sweep varies).

    Parameters
    ----------
    reduced_field : float or sequence of float
        E/N values (Td, 0 to 1e6; ``--E-N``).
    model, gas, cross_sections, species, fractions, database, populations
        The gas, as :class:`~collisionkit.transport.SwarmParameters`'s.
    gas_temperature, cells, max_energy, sharing, growth, ionization_degree, electron_density, omega_N
        As :func:`~collisionkit.transport.two_term_boltzmann`'s (``omega_N``: ``--omega-N``).

    Examples
    --------
    >>> parameters = TwoTermParameters(model="reid", reduced_field=[1, 12], gas_temperature=0.0)
    >>> scan = run_two_term(parameters)
    >>> [round(r.mean_energy, 4) for r in scan.results]
    [0.1016, 0.2736]
    """

    reduced_field: Any = (12.0,)
    model: str | None = None
    gas: str | None = None
    cross_sections: Any = None
    species: Any = None
    fractions: Any = None
    database: str | None = None
    populations: Any = None
    gas_temperature: float = 300.0
    cells: int = 1000
    max_energy: float | None = None
    sharing: str = "equal"
    growth: str = "temporal"
    ionization_degree: float = 0.0
    electron_density: float | None = None
    omega_N: float = 0.0

    FLAGS: ClassVar = {"reduced_field": "E-N", "omega_N": "omega-N"}

    def __post_init__(self):
        set_ = object.__setattr__
        gas = self.gas_parameters()  # the gas choice and E/N values, checked as the swarm's
        set_(self, "reduced_field", gas.reduced_field)
        set_(self, "cross_sections", gas.cross_sections)
        set_(self, "species", gas.species)
        set_(self, "fractions", gas.fractions)
        set_(self, "populations", gas.populations)
        set_(self, "gas_temperature", gas.gas_temperature)
        if 0.0 < self.gas_temperature < MIN_GAS_TEMPERATURE:
            raise ValueError(f"gas_temperature (K) must be 0 or at least {MIN_GAS_TEMPERATURE:g}; got "
                             f"{self.gas_temperature:g}")
        set_(self, "cells", check_integer("cells", self.cells, 50, 100_000))
        if self.max_energy is not None:
            set_(self, "max_energy", check_real("max_energy (eV)", self.max_energy, 0.0, 1e7, low_open=True))
        check_choice("sharing", self.sharing, SHARING)
        check_choice("growth", self.growth, GROWTH_MODELS)
        electrons = _checked_electrons(self.ionization_degree, self.electron_density)
        set_(self, "ionization_degree", electrons[0] if electrons else 0.0)
        set_(self, "electron_density", electrons[1] if electrons else None)
        set_(self, "omega_N", check_reduced_frequency(self.omega_N, "omega_N (omega/N, rad m^3/s)"))
        if self.omega_N and self.growth == "spatial":
            raise ValueError("growth='spatial' is for a DC field; a high-frequency field takes growth='temporal'")

    def gas_parameters(self):
        """The gas choice as :class:`~collisionkit.transport.SwarmParameters` (which makes and names it).

        Examples
        --------
        >>> TwoTermParameters(gas="Ar").gas_parameters().gas_files()[0].name
        'IST-Lisbon_Ar.txt'
        """
        from .scan import SwarmParameters

        return SwarmParameters(reduced_field=self.reduced_field, model=self.model, gas=self.gas,
                               cross_sections=self.cross_sections, species=self.species, fractions=self.fractions,
                               database=self.database, populations=self.populations,
                               gas_temperature=self.gas_temperature, sharing=self.sharing)

    def solver_options(self) -> dict:
        """:func:`~collisionkit.transport.two_term_boltzmann`'s keywords.

        Examples
        --------
        >>> TwoTermParameters(model="reid", cells=400).solver_options()["cells"]
        400
        """
        return {"gas_temperature": self.gas_temperature, "cells": self.cells, "max_energy": self.max_energy,
                "sharing": self.sharing, "growth": self.growth, "ionization_degree": self.ionization_degree,
                "electron_density": self.electron_density, "omega_N": self.omega_N}


def run_two_term(parameters: TwoTermParameters, progress=None) -> TwoTermScan:
    """The scan of ``parameters``, run (:class:`TwoTermScan`).

    Examples
    --------
    >>> len(run_two_term(TwoTermParameters(model="reid", reduced_field=12.0, gas_temperature=0.0)).results)
    1
    """
    gas = parameters.gas_parameters().make_gas()
    return TwoTermScan(gas, parameters.reduced_field, **parameters.solver_options()).run(progress)


def two_term_summary(parameters: TwoTermParameters, scan: TwoTermScan, files=()) -> dict:
    """The ``boltzmann`` command's JSON summary from Python: ``gas``, the scan's :meth:`TwoTermScan.summary`,
    ``provenance`` (collisionkit's version, the cross-section files with their SHA-256), ``files`` and
    ``parameters``; a scan of one E/N also has that point's values at the top level (a sweep point reads
    ``mean_energy`` directly).

    Examples
    --------
    >>> parameters = TwoTermParameters(model="reid", reduced_field=12.0, gas_temperature=0.0)
    >>> summary = two_term_summary(parameters, run_two_term(parameters))
    >>> summary["mean_energy"] == summary["results"][0]["mean_energy"], summary["gas"]
    (True, 'reid')
    """
    gas = parameters.gas_parameters()
    found = scan.summary()
    summary = dict(found["results"][0]) if len(found["results"]) == 1 else {}
    return summary | {"gas": gas.gas_name(), **found, "provenance": provenance(gas.gas_files()),
                      "files": [str(path) for path in files], "parameters": parameters.to_dict()}


def provenance(cross_section_files) -> dict:
    """What the numbers came from: collisionkit's version (its installed metadata) and each cross-section file
    with its SHA-256.

    Examples
    --------
    >>> provenance([])["cross_sections"]
    []
    """
    from importlib import metadata

    try:
        version = metadata.version("collisionkit")
    except metadata.PackageNotFoundError:  # run from a source tree that is not installed
        version = "unknown (not installed)"
    return {"collisionkit": version,
            "cross_sections": [{"path": str(path), "sha256": file_digest(path)} for path in cross_section_files]}
