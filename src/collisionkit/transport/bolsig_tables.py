r"""Transport coefficients against E/N as BOLSIG+'s output tables, the form plasma fluid codes read.

BOLSIG+ (G. J. M. Hagelaar and L. C. Pitchford, Plasma Sources Sci.
Technol. 14, 722 (2005)) writes each coefficient as a section: a header
line ``E/N (Td)<TAB><quantity (unit)>``, then one line per E/N of two
tab-separated numbers, then a blank line; a rate coefficient's header is
preceded by a line naming its process (``C<k>   <process>``). Fluid and
streamer codes look a section up by its header line and read to the blank
line, so these tables can stand in for BOLSIG+'s: :func:`bolsig_tables`
writes the sections whose headers BOLSIG+ uses (``Mean energy (eV)``,
``Mobility *N (1/m/V/s)``, ``Diffusion coefficient *N (1/m/s)``, ...) from
a scan of :class:`~collisionkit.transport.SwarmResult` (Monte Carlo: flux
coefficients, the transverse diffusion as BOLSIG+'s, the longitudinal as
``Longitud. diffusion coef. *N``, the bulk drift and diffusion under
BOLSIG+'s bulk headers (``Bulk mobility *N (1/m/V/s)``, ``Bulk L diffusion
coef. *N (1/m/s)``, ``Bulk T diffusion coef. *N (1/m/s)``, which BOLSIG+
writes with temporal growth and streamer codes such as afivo-streamer read
to scale their reaction rates), and alpha/N = k_ion / W and eta/N =
k_att / W with W the flux drift, BOLSIG+'s definition with temporal growth,
so that alpha times the mobility written beside it gives the ionization
rate) or :class:`~collisionkit.transport.TwoTermResult` (the two-term
solution, as BOLSIG+'s own).

A value that is not a number (the mobility or alpha/N at E/N = 0, where
nothing drifts) leaves its line out of that section, so that section's E/N
column is shorter than the others' (:func:`missing_rows` lists them; the
commands warn). The file starts with a header naming
collisionkit, the method and the gas temperature (``Gas temperature (K)``,
as BOLSIG+ writes it).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .._io import atomic_write_text
from .swarm_result import SwarmResult
from .two_term import TwoTermResult

__all__ = ["BOLSIG_SECTIONS", "bolsig_tables", "missing_rows", "read_bolsig_section", "write_bolsig_tables"]

TOWNSEND = 1e-21  # V m^2 per Td

# the section headers (BOLSIG+'s names) and how each result type gives the value, in the order written
BOLSIG_SECTIONS = (
    "Mean energy (eV)",
    "Mobility *N (1/m/V/s)",
    "Diffusion coefficient *N (1/m/s)",
    "Longitud. diffusion coef. *N (1/m/s)",
    "Bulk mobility *N (1/m/V/s)",
    "Bulk L diffusion coef. *N (1/m/s)",
    "Bulk T diffusion coef. *N (1/m/s)",
    "Energy mobility *N (1/m/V/s)",
    "Energy diffusion coef. D*N (1/m/s)",
    "Momentum frequency /N (m3/s)",
    "Total ionization freq. /N (m3/s)",
    "Total attachment freq. /N (m3/s)",
    "Townsend ioniz. coef. alpha/N (m2)",
    "Townsend attach. coef. eta/N (m2)",
)


def _swarm_values(result: SwarmResult) -> dict[str, float]:
    """A Monte Carlo result's sections: flux drift along E over E/N, flux diffusion (transverse and longitudinal),
    and the bulk drift and diffusion under BOLSIG+'s bulk headers."""
    field = result.reduced_field * TOWNSEND
    drift = abs(float(result.drift_velocity_flux[2]))
    bulk_drift = abs(float(result.drift_velocity_bulk[2]))
    per_drift = 1.0 / drift if drift > 0 else math.nan
    return {
        "Mean energy (eV)": result.mean_energy,
        "Mobility *N (1/m/V/s)": drift / field if field > 0 else math.nan,
        "Diffusion coefficient *N (1/m/s)": result.diffusion_T_N_flux,
        "Longitud. diffusion coef. *N (1/m/s)": result.diffusion_L_N_flux,
        "Bulk mobility *N (1/m/V/s)": bulk_drift / field if field > 0 else math.nan,
        "Bulk L diffusion coef. *N (1/m/s)": result.diffusion_L_N,
        "Bulk T diffusion coef. *N (1/m/s)": result.diffusion_T_N,
        "Total ionization freq. /N (m3/s)": result.ionization_frequency_N,
        "Total attachment freq. /N (m3/s)": result.attachment_frequency_N,
        "Townsend ioniz. coef. alpha/N (m2)": result.ionization_frequency_N * per_drift,
        "Townsend attach. coef. eta/N (m2)": result.attachment_frequency_N * per_drift,
    }


def _two_term_values(result: TwoTermResult) -> dict[str, float]:
    """A two-term result's sections, each under BOLSIG+'s name for the same coefficient."""
    return {
        "Mean energy (eV)": result.mean_energy,
        "Mobility *N (1/m/V/s)": result.mobility_N,
        "Diffusion coefficient *N (1/m/s)": result.diffusion_N,
        "Energy mobility *N (1/m/V/s)": result.energy_mobility_N,
        "Energy diffusion coef. D*N (1/m/s)": result.energy_diffusion_N,
        "Momentum frequency /N (m3/s)": result.momentum_frequency_N,
        "Total ionization freq. /N (m3/s)": result.ionization_frequency_N,
        "Total attachment freq. /N (m3/s)": result.attachment_frequency_N,
        "Townsend ioniz. coef. alpha/N (m2)": result.alpha_N,
        "Townsend attach. coef. eta/N (m2)": result.eta_N,
    }


def _checked(results) -> tuple[list, str]:
    """The results as a list of one type, sorted by E/N, and the method's name; a static field without B only."""
    results = list(results)
    if not results:
        raise ValueError("results must hold at least one E/N point")
    if all(isinstance(result, SwarmResult) for result in results):
        moving = [result.reduced_field for result in results
                  if result.reduced_magnetic_field != 0.0 or result.reduced_frequency != 0.0]
        if moving:
            raise ValueError(f"BOLSIG+ tables hold a static E alone; the results at E/N = {moving[0]:g} Td have a "
                             "magnetic or oscillating field")
        method = "Monte Carlo swarm (flux coefficients)"
    elif all(isinstance(result, TwoTermResult) for result in results):
        moving = [result.reduced_field for result in results if result.omega_N != 0.0]
        if moving:
            raise ValueError(f"BOLSIG+ tables hold a static E alone; the results at E/N = {moving[0]:g} Td have an "
                             "oscillating field")
        method = "two-term Boltzmann equation"
    else:
        raise TypeError("results must all be SwarmResult or all TwoTermResult")
    if len({result.gas_temperature for result in results}) != 1:
        raise ValueError("results must share one gas temperature (one table)")
    return sorted(results, key=lambda result: result.reduced_field), method


def _section(header: str, points) -> list[str]:
    """One section: its header, a line per finite (E/N, value), a blank line; none if no value is finite."""
    rows = [f"{e_n:.6e}\t{value:.6e}" for e_n, value in points if math.isfinite(value)]
    return [f"E/N (Td)\t{header}", *rows, ""] if rows else []


def _values(result) -> dict[str, float]:
    return _swarm_values(result) if isinstance(result, SwarmResult) else _two_term_values(result)


def missing_rows(results: Sequence[SwarmResult] | Sequence[TwoTermResult]) -> dict[str, list[float]]:
    """The sections of :func:`bolsig_tables` that leave out some E/N (their value is not a number there), with
    those E/N in Td.

    Examples
    --------
    >>> from collisionkit.transport import missing_rows, reid_ramp, two_term_boltzmann
    >>> missing_rows([two_term_boltzmann(reid_ramp(), e_n, 0.0) for e_n in (1.0, 12.0)])
    {}
    """
    results, _ = _checked(results)
    gaps: dict[str, list[float]] = {}
    for result in results:
        for header, value in _values(result).items():
            if not math.isfinite(value):
                gaps.setdefault(header, []).append(result.reduced_field)
    return gaps


def bolsig_tables(results: Sequence[SwarmResult] | Sequence[TwoTermResult]) -> str:
    r"""The results of an E/N scan as the text of BOLSIG+'s output tables.

    Parameters
    ----------
    results : sequence of SwarmResult, or of TwoTermResult
        One per E/N (any order: written in rising E/N), one gas
        temperature; swarm results of a static E without B.

    Returns
    -------
    str
        A header, the coefficient sections of :data:`BOLSIG_SECTIONS` that
        the results give, then one section per process rate coefficient
        (``C<k>   <label>``, ``E/N (Td)<TAB>Rate coefficient (m3/s)``).

    Raises
    ------
    ValueError
        No results, several gas temperatures, or a magnetic or oscillating
        field. TypeError: results of both kinds, or of another.

    Examples
    --------
    >>> from collisionkit.transport import bolsig_tables, reid_ramp, two_term_boltzmann
    >>> text = bolsig_tables([two_term_boltzmann(reid_ramp(), e_n, 0.0) for e_n in (1.0, 12.0)])
    >>> section = text.split("E/N (Td)\tMobility *N (1/m/V/s)\n")[1].split("\n\n")[0]
    >>> section.splitlines()[1].split("\t")[0]
    '1.200000e+01'
    >>> "C1   reid:excitation\nE/N (Td)\tRate coefficient (m3/s)" in text
    True
    """
    results, method = _checked(results)
    values = [_values(result) for result in results]
    lines = [f"collisionkit: {method}, in the layout of BOLSIG+'s output tables",
             f"Gas temperature (K)\t{results[0].gas_temperature:.3f}", ""]
    for header in BOLSIG_SECTIONS:
        lines += _section(header, [(r.reduced_field, v.get(header, math.nan)) for r, v in zip(results, values)])
    labels = list(dict.fromkeys(label for result in results for label in result.rate_coefficients))
    for number, label in enumerate(labels, start=1):
        rates = [(r.reduced_field, float(r.rate_coefficients.get(label, math.nan))) for r in results]
        section = _section("Rate coefficient (m3/s)", rates)
        lines += [f"C{number}   {label}", *section] if section else []
    return "\n".join(lines) + "\n"


def write_bolsig_tables(path, results: Sequence[SwarmResult] | Sequence[TwoTermResult]) -> Path:
    """Write :func:`bolsig_tables` of ``results`` to ``path`` (atomically); returns the path.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from collisionkit.transport import reid_ramp, two_term_boltzmann, write_bolsig_tables
    >>> path = write_bolsig_tables(pathlib.Path(tempfile.mkdtemp()) / "bolsig.dat",
    ...                            [two_term_boltzmann(reid_ramp(), 12.0, 0.0)])
    >>> path.read_text().splitlines()[1]
    'Gas temperature (K)\\t0.000'
    """
    path = Path(path)
    atomic_write_text(path, bolsig_tables(results))
    return path


def read_bolsig_section(text: str, header: str, before: str | None = None) -> np.ndarray:
    r"""The (E/N, value) rows of the section ``header`` in BOLSIG+-style ``text`` (the first after the line
    ``before``, if given), as a reader of these tables finds them; shape (rows, 2).

    A section runs to a blank line or the end of the text; lines are compared
    without the spaces around them (BOLSIG+ pads some headers).

    Raises
    ------
    ValueError
        No such section (after ``before``), naming it.

    Examples
    --------
    >>> read_bolsig_section("E/N (Td)\tMean energy (eV)\n1.0\t0.5\n\n", "Mean energy (eV)")
    array([[1. , 0.5]])
    >>> read_bolsig_section("E/N (Td)      \tGrid type\n0.1\t0.0\n0.2\t3.0", "Grid type")  # to the end
    array([[0.1, 0. ],
           [0.2, 3. ]])
    """
    lines = [line.strip() for line in text.splitlines()]
    start = 0
    if before is not None:
        if before.strip() not in lines:
            raise ValueError(f"no line {before!r} in the text")
        start = lines.index(before.strip()) + 1
    wanted = f"E/N (Td)\t{header}".strip()
    headers = [index for index in range(start, len(lines))
               if lines[index].startswith("E/N (Td)") and lines[index][len("E/N (Td)"):].strip() == header.strip()]
    if not headers:
        raise ValueError(f"no section {wanted!r} in the text" + (f" after {before!r}" if before else ""))
    first = headers[0] + 1
    end = lines.index("", first) if "" in lines[first:] else len(lines)
    return np.array([[float(item) for item in line.split()] for line in lines[first:end]]).reshape(-1, 2)
