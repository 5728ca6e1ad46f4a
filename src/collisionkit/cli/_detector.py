"""The ``swarm`` command in a gas detector's units: ``--E`` in V/cm and ``--pressure`` in Torr (Magboltz's columns).

:func:`fields_from_volts` turns ``--E`` into the E/N values the scan runs
(before the options are checked, so that every check sees those E/N);
:func:`detector_report` prints the table and writes ``detector.csv``; the
command adds its rows to the summary as each point's ``detector`` (:mod:`collisionkit.transport.detector_units`).
"""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

from .._io import atomic_write_text
from ._common import print_table
from ._reduced_fields import MAX_REDUCED_FIELD

DETECTOR_FILE = "detector.csv"
COLUMNS = ("field", "drift_velocity", "diffusion_L", "diffusion_T", "townsend_alpha", "attachment_eta")
UNITS = {"field": "V/cm", "drift_velocity": "cm/us", "diffusion_L": "sqrt(cm)", "diffusion_T": "sqrt(cm)",
         "townsend_alpha": "1/cm", "attachment_eta": "1/cm"}


def _given(values: dict, *names):
    """The value of the first of ``names`` (a field's name or its spellings) in the raw ``values``, else None."""
    for name in names:
        if values.get(name) is not None:
            return values[name]
    return None


def fields_from_volts(values: dict) -> dict:
    """The raw option ``values`` with ``e_n`` from ``e`` (V/cm) at ``pressure`` and the gas temperature (300 K if
    not given); ValueError if they clash (--E with --E-N, without --pressure, in a gas at 0 K).

    Examples
    --------
    >>> values = fields_from_volts({"e": [1000.0], "pressure": 760.0, "gas_temperature": 293.15})
    >>> [round(value, 4) for value in values["e_n"]]
    [3.9944]
    """
    from ..transport import reduced_fields

    fields = _given(values, "e", "E")
    if fields is None:
        return values
    if _given(values, "e_n", "e-n", "E-N", "E_N") is not None:
        raise ValueError("give the field as --E (V/cm, with --pressure) or as --E-N (Td), not both")
    pressure = _given(values, "pressure")
    if pressure is None:  # (said after the other checks: a misspelt key is named first)
        return values
    temperature = _given(values, "gas_temperature", "gas-temperature")
    temperature = 300.0 if temperature is None else temperature
    for name, value in (("--pressure", pressure), ("--gas-temperature", temperature)):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError(f"{name} must be a number; got {value!r}")
    if not temperature > 0.0:
        raise ValueError("--E (V/cm) needs a gas temperature > 0 K for N = p / (k T)")
    if isinstance(fields, (int, float, str)):
        fields = [fields]
    if any(isinstance(item, str) for item in fields):  # a config's "500:1000:2", as on the command line
        from ._reduced_fields import _e_n_values

        fields = _e_n_values([str(item) for item in fields], "--E", "V/cm", math.inf)
    if any(isinstance(item, bool) or not isinstance(item, (int, float)) for item in fields):
        raise ValueError(f"--E must be numbers (V/cm); got {fields!r}")
    e_n = [float(value) for value in reduced_fields(fields, pressure, temperature)]
    beyond = [(field, value) for field, value in zip(fields, e_n) if value > MAX_REDUCED_FIELD]
    if beyond:
        raise ValueError(f"--E {beyond[0][0]:g} V/cm is E/N = {beyond[0][1]:.3g} Td at {pressure:g} Torr and "
                         f"{temperature:g} K, above the {MAX_REDUCED_FIELD:g} Td of --E-N")
    return {**{key: value for key, value in values.items() if key not in ("E",)}, "e": list(fields), "e_n": e_n}


def _cell(row: dict, name: str) -> str:
    value, error = row[name], row.get(f"{name}_error", math.nan)
    if not math.isfinite(value):
        return ""
    return f"{value:.5g}" if not math.isfinite(error) or error == 0 else f"{value:.5g} ± {error:.2g}"


def detector_report(results, pressure: float, out: Path | None, deliveries) -> list[dict]:
    """Print the detector table and write ``out/detector.csv``; the rows, one per result, for the summary."""
    from ..transport import detector_coefficients

    rows = [detector_coefficients(result, pressure) for result in results]
    temperature = rows[0]["temperature"]
    print_table(f"in a detector's units: {pressure:g} Torr, {temperature:g} K (diffusion: sigma / sqrt(drift length))",
                [f"{name} ({UNITS[name]})" for name in COLUMNS], [[_cell(row, name) for name in COLUMNS] for row in rows])
    if out is not None:
        text = io.StringIO()
        writer = csv.writer(text, lineterminator="\n")
        names = [name for column in COLUMNS for name in (column, f"{column}_error") if name != "field_error"]
        writer.writerow([f"{name} ({UNITS[name.removesuffix('_error')]})" for name in names])
        writer.writerows([[repr(float(row[name])) for name in names] for row in rows])
        path = out / DETECTOR_FILE

        def write() -> Path:
            atomic_write_text(path, text.getvalue())
            return path

        deliveries.write(f"the detector table {path}", write)
    return rows


def check_detector_options(options) -> None:
    """--pressure (and --E) need a static E without B in a warm gas; the pressure's range is the library's."""
    from ..transport import gas_number_density

    if options.pressure is None:
        if options.e is not None:
            raise ValueError("--E (V/cm) needs --pressure (Torr) to give E/N")
        return
    if options.b_n != 0.0 or options.omega_n != 0.0:
        raise ValueError("--pressure gives a detector's table of a static E without B: not with --B-N or --omega-N")
    if not options.gas_temperature > 0.0:
        raise ValueError("--pressure needs a gas temperature > 0 K (N = p / (k T))")
    gas_number_density(options.pressure, options.gas_temperature)  # its range, named
