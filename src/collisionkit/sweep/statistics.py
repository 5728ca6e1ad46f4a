"""Combining the replicas of a point: the weighted mean of their values with their own errors and their scatter.

Each replica of a study point is an independent run that quotes its own
standard error (``<key>_error`` in its summary). The point's value is the
inverse-variance weighted mean of the replicas, and its error combines the
replicas' own errors with their scatter (Particle Data Group, *Review of
Particle Physics*, Introduction, sec. 5.2.2 "Unconstrained averaging"):

.. math::

    \\bar x = \\frac{\\sum_i w_i x_i}{\\sum_i w_i}, \\quad w_i = \\sigma_i^{-2}, \\quad
    \\sigma_{\\bar x} = \\Big(\\sum_i w_i\\Big)^{-1/2} \\max(1, S), \\quad
    S^2 = \\frac{\\chi^2}{n - 1}, \\quad \\chi^2 = \\sum_i w_i (x_i - \\bar x)^2 .

The scale factor ``S`` enlarges the error when the replicas scatter more
than their errors say; when they disagree beyond chance (the probability of
a chi-square at least as large below :data:`DISAGREEMENT_P`), the point is
flagged. Without errors of their own, the replicas give the plain mean and
``std(ddof=1) / sqrt(n)``; a single replica keeps its own error.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from scipy import stats

__all__ = ["DISAGREEMENT_P", "combine_replicas"]

DISAGREEMENT_P = 0.01  # replicas whose chi-square is this improbable (or less) disagree beyond their errors


def combine_replicas(values: Sequence[float], errors: Sequence[float] | None = None) -> dict[str, Any]:
    """The point's value and error from its replicas' values and (optionally) their own errors.

    Parameters
    ----------
    values : sequence of float
        The replicas' values (finite).
    errors : sequence of float, optional
        Their own standard errors; used only if every one is finite and > 0.

    Returns
    -------
    dict
        ``n``, ``mean``, ``error``, ``scatter_error`` (``std(ddof=1)/sqrt(n)``,
        NaN for one replica), ``chi2_per_dof`` (NaN without own errors or
        with one replica) and ``disagree`` (True if the replicas disagree
        beyond their errors).

    Examples
    --------
    Two replicas that agree within their errors keep the combined error of
    those errors, not the (smaller, by chance) spread between them:

    >>> point = combine_replicas([2.4150, 2.4174], [0.0070, 0.0072])
    >>> round(point["mean"], 4), round(point["error"], 4), round(point["scatter_error"], 4), point["disagree"]
    (2.4162, 0.005, 0.0012, False)

    Replicas far apart for their errors enlarge the error and are flagged:

    >>> point = combine_replicas([1.0, 2.0], [0.01, 0.01])
    >>> round(point["error"], 3), point["disagree"]
    (0.5, True)
    >>> combine_replicas([2.0, 4.0])["error"]
    1.0
    """
    x = np.asarray(values, dtype=float)
    n = len(x)
    if n == 0:
        raise ValueError("combine_replicas needs at least one value")
    scatter = float(x.std(ddof=1) / math.sqrt(n)) if n > 1 else math.nan
    sigma = None if errors is None else np.asarray(errors, dtype=float)
    if sigma is None or len(sigma) != n or not np.all(np.isfinite(sigma) & (sigma > 0)):
        own = float(sigma[0]) if sigma is not None and n == 1 and len(sigma) == 1 else math.nan
        return {"n": n, "mean": float(x.mean()), "error": scatter if n > 1 else own, "scatter_error": scatter,
                "chi2_per_dof": math.nan, "disagree": False}
    weights = sigma**-2.0
    mean = float(np.sum(weights * x) / np.sum(weights))
    error = float(np.sum(weights) ** -0.5)
    if n == 1:
        return {"n": 1, "mean": mean, "error": error, "scatter_error": math.nan, "chi2_per_dof": math.nan,
                "disagree": False}
    chi2 = float(np.sum(weights * (x - mean) ** 2))
    scale = math.sqrt(chi2 / (n - 1))
    return {"n": n, "mean": mean, "error": error * max(1.0, scale), "scatter_error": scatter,
            "chi2_per_dof": chi2 / (n - 1), "disagree": bool(stats.chi2.sf(chi2, n - 1) < DISAGREEMENT_P)}


def error_column(key: str) -> str:
    """The column of ``key``'s error: ``Z_error``; for an element of a list ``T[0]`` the element of the list of
    errors, ``T_error[0]`` (the summaries give ``T`` and ``T_error`` as lists); in a nested key only its last part
    changes (``results[0].mean_energy_error``).

    Examples
    --------
    >>> error_column("Z"), error_column("temperature_species[1]"), error_column("contact_values[0][1]")
    ('Z_error', 'temperature_species_error[1]', 'contact_values_error[0][1]')
    >>> error_column("results[0].mean_energy"), error_column("results[1].drift[2]")
    ('results[0].mean_energy_error', 'results[1].drift_error[2]')
    """
    head, dot, last = key.rpartition(".")
    name, bracket, index = last.partition("[")
    return f"{head}{dot}{name}_error{bracket}{index}"


def is_error_column(column: str) -> bool:
    """True for an error column (:func:`error_column` of some key).

    Examples
    --------
    >>> is_error_column("Z_error"), is_error_column("T_error[0]"), is_error_column("T[0]")
    (True, True, False)
    >>> is_error_column("results[0].mean_energy_error"), is_error_column("results_error[0].x")
    (True, False)
    """
    return column.rpartition(".")[2].partition("[")[0].endswith("_error")


def combine_rows(rows: Sequence[Mapping[str, Any]], key: str) -> dict[str, Any]:
    """:func:`combine_replicas` of the rows' ``key`` with their own errors (:func:`error_column`, when every row has
    one).

    Examples
    --------
    >>> rows = [{"Z": 2.0, "Z_error": 0.1}, {"Z": 2.1, "Z_error": 0.1}]
    >>> round(combine_rows(rows, "Z")["mean"], 6), round(combine_rows(rows[:1] + [{"Z": 2.1}], "Z")["error"], 6)
    (2.05, 0.05)
    >>> rows = [{"T[0]": 1.21, "T_error[0]": 0.009}, {"T[0]": 1.20, "T_error[0]": 0.009}]
    >>> round(combine_rows(rows, "T[0]")["error"], 4)  # the replicas' own errors, not their scatter alone
    0.0064
    """
    values = [row[key] for row in rows]
    own = [row.get(error_column(key)) for row in rows]
    numeric = all(isinstance(error, (int, float)) and not isinstance(error, bool) for error in own)
    return combine_replicas(values, own if numeric else None)
