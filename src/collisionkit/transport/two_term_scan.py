"""A scan of the two-term Boltzmann equation over E/N, as ``collisionkit boltzmann`` runs it, from Python.

:class:`TwoTermScan` solves :func:`~collisionkit.transport.two_term_boltzmann`
at each E/N in turn, keeps a point that fails (a growth without a steady
state) as a failure with its reason and goes on, collects the solver's
warnings, and writes the command's tables (``boltzmann.csv``, ``eedf.csv``).
"""

from __future__ import annotations

import warnings
from pathlib import Path

from .._io import write_csv
from .gases import Gas
from .two_term import UNITS, TwoTermWarning, two_term_boltzmann

__all__ = ["TwoTermScan"]

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
