"""A study's results: the table (CSV, Parquet), the means across replicas and the main plot."""

from __future__ import annotations

import io
import json
import math
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from .._io import atomic_write_bytes, write_csv
from .statistics import combine_rows, error_column, is_error_column
from .study import Study

__all__ = ["aggregate", "points_table", "results_table", "write_csv", "write_outputs", "write_parquet"]

TABLE_COLUMNS = ("point", "replica", "seed", "spawn_key", "status", "error", "elapsed")
NOT_RESULTS = ("parameters", "files", "options")  # summary keys that are not results (the row has the options)
MAX_VECTOR = 16  # numeric lists up to this size (vectors, 3x3 tensors) become columns; longer ones (spectra) do not
OUTPUT_FILES = ("results.csv", "points.csv", "results.parquet", "main_result.png")  # write_outputs' files in the folder


def _flatten(summary: Mapping[str, Any], prefix: str = "") -> Iterator[tuple[str, Any]]:
    """The results of a summary as (column, value): nested keys joined by dots, vector items as ``name[i]``.

    Numbers, strings and booleans are kept. A list of result objects
    (swarm's ``results``) gives ``results[i].key`` columns, except a single
    entry whose values are already at the top level; numeric lists longer
    than :data:`MAX_VECTOR` (spectra) and lists of strings are left out.
    """
    for key, value in summary.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping):
            yield from _flatten(value, name + ".")
        elif isinstance(value, (list, tuple)):
            yield from _flatten_list(name, value, summary)
        elif _is_number(value) or isinstance(value, (str, bool)):
            yield name, value


def _flatten_list(name: str, values: list, parent: Mapping[str, Any]) -> Iterator[tuple[str, Any]]:
    if values and all(isinstance(item, Mapping) for item in values):
        if len(values) == 1 and all(parent.get(key) == item for key, item in values[0].items()):
            return  # repeats the top level
        for index, item in enumerate(values):
            yield from _flatten(item, f"{name}[{index}].")
        return
    numbers = np.asarray(values, dtype=object)
    if numbers.size > MAX_VECTOR or not all(_is_number(item) or item is None for item in numbers.ravel()):
        return
    for index in np.ndindex(numbers.shape):
        yield name + "".join(f"[{i}]" for i in index), numbers[index]


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def results_table(study: Study, records: Iterable[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """One row per point and replica: varied options, sweep columns and the summary's numbers.

    Nested summary keys are joined with dots (``orbit.deflection_angle``),
    short numeric lists become ``name[i]`` columns; numbers, strings and
    booleans are kept. Failed points have empty summary columns.

    Examples
    --------
    >>> study = Study("encounter", seed=0, vary={"vinf": [0.5]})
    >>> record = {"point": 0, "replica": 0, "seed": 7, "spawn_key": [0, 0], "status": "ok", "error": None,
    ...           "elapsed": 0.1, "parameters": {"vinf": 0.5}, "summary": {"orbit": {"e": 1.1, "kind": "hyp"}}}
    >>> results_table(study, [record])[0]
    {'vinf': 0.5, 'point': 0, 'replica': 0, 'seed': 7, 'spawn_key': '[0, 0]', 'status': 'ok', 'error': '', 'elapsed': 0.1, 'orbit.e': 1.1, 'orbit.kind': 'hyp'}
    """
    rows = []
    for record in records:
        row = {name: record["parameters"][name] for name in study.vary}
        row |= {column: record[column] for column in TABLE_COLUMNS}
        row["spawn_key"] = json.dumps(list(record["spawn_key"]))
        row["error"] = record["error"] or ""
        reserved = set(row)
        results = {key: value for key, value in (record["summary"] or {}).items() if key not in NOT_RESULTS}
        row |= {key: value for key, value in _flatten(results) if key not in reserved}
        rows.append(row)
    return rows


def _columns(table: list[Mapping[str, Any]]) -> list[str]:
    columns: dict[str, None] = {}
    for row in table:
        columns |= dict.fromkeys(row)
    return list(columns)


def _arrow_column(values: list[Any]):
    import pyarrow as pa

    present = [value for value in values if value is not None and value != ""]
    if present and all(isinstance(value, bool) for value in present):
        return pa.array([value if isinstance(value, bool) else None for value in values], pa.bool_())
    if present and all(isinstance(value, int) and not isinstance(value, bool) for value in present):
        return pa.array([value if value in present else None for value in values], pa.int64())
    if present and all(isinstance(value, (int, float)) and not isinstance(value, bool) for value in present):
        return pa.array([None if value is None or value == "" else float(value) for value in values], pa.float64())
    return pa.array([None if value is None else str(value) for value in values], pa.string())


def write_parquet(path, table: list[Mapping[str, Any]]) -> Path | None:
    """Write the table as Parquet atomically if ``pyarrow`` is installed; return None otherwise.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = write_parquet(pathlib.Path(tempfile.mkdtemp()) / "t.parquet", [{"a": 0.1, "b": "x"}])
    >>> path is None or path.suffix == ".parquet"
    True
    """
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        return None
    columns = _columns(table)
    arrays = [_arrow_column([row.get(column) for row in table]) for column in columns]
    buffer = io.BytesIO()
    pq.write_table(pa.Table.from_arrays(arrays, names=columns), buffer)
    return atomic_write_bytes(path, buffer.getvalue())


def aggregate(table: Iterable[Mapping[str, Any]], key: str, by: Iterable[str]) -> list[dict[str, Any]]:
    """The value and error of ``key`` per combination of the ``by`` columns, combining the replicas.

    Only successful rows with a finite value count; a boolean counts as 1
    or 0 (its mean the fraction of replicas where true). The replicas are
    combined by :func:`~collisionkit.sweep.statistics.combine_replicas`: the
    weighted mean with their own errors (``<key>_error``) and their scatter,
    or the plain mean and ``std(ddof=1) / sqrt(n)`` without own errors.

    Returns
    -------
    list of dict
        The ``by`` values, ``n``, ``mean``, ``error``, ``scatter_error``,
        ``chi2_per_dof`` and ``disagree``, in first-appearance order.

    Examples
    --------
    >>> rows = [{"x": 1, "y": 2.0, "status": "ok"}, {"x": 1, "y": 4.0, "status": "ok"},
    ...         {"x": 2, "y": 5.0, "status": "failed"}]
    >>> [(point["x"], point["n"], point["mean"], point["error"]) for point in aggregate(rows, "y", ["x"])]
    [(1, 2, 3.0, 1.0)]
    """
    by = list(by)
    table = list(table)
    present = [row.get(key) for row in table if row.get("status") == "ok" and row.get(key) is not None]
    yes_no = bool(present) and all(isinstance(value, bool) for value in present)  # (not a bool among numbers)
    groups: dict[tuple, list[Mapping[str, Any]]] = {}
    for row in table:
        value = row.get(key)
        if row.get("status") == "ok" and yes_no:  # a yes/no result: the fraction of replicas
            groups.setdefault(group_key(row, by), []).append({**row, key: float(value)})
        elif row.get("status") == "ok" and _is_number(value) and math.isfinite(value):
            groups.setdefault(group_key(row, by), []).append(row)
    return [{name: rows[0][name] for name in by} | combine_rows(rows, key) for rows in groups.values()]


def group_key(row: Mapping[str, Any], names: Iterable[str]) -> tuple:
    """The values of ``names`` in ``row`` as a dictionary key: a list option's value (``diameters = [1, 0.6]``) as a
    tuple.

    Examples
    --------
    >>> group_key({"fractions": [0.5, 0.5], "seed": 1}, ["fractions", "seed"])
    ((0.5, 0.5), 1)
    """
    def hashable(value):
        return tuple(map(hashable, value)) if isinstance(value, list) else value

    return tuple(hashable(row[name]) for name in names)


def points_table(study: Study, table: list[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """One row per study point: its varied options, the replicas that succeeded, and every result with its error.

    Each numeric result column ``q`` of the replica table (not the sweep's
    own columns, not an ``*_error`` column) becomes ``q`` and ``q_error``
    (:func:`aggregate`); ``disagreeing`` lists the results whose replicas
    disagree beyond their errors. Of the successful replicas, a boolean
    result ``b`` gives ``b_fraction``, the fraction where it is true, and a
    text result its value, or its distinct values joined by ``;`` if they
    differ.

    Examples
    --------
    >>> study = Study("slab", seed=0, vary={"albedo": [0.5]})
    >>> rows = [{"albedo": 0.5, "status": "ok", "transmission": t, "transmission_error": 0.01} for t in (0.40, 0.42)]
    >>> point = points_table(study, rows)[0]
    >>> point["replicas_ok"], round(point["transmission"], 3), round(point["transmission_error"], 4)
    (2, 0.41, 0.01)
    """
    names = list(study.vary)
    own = set(TABLE_COLUMNS) | set(names) | {"spawn_key", "cpu_time"}
    quantities = [column for column in _columns(table) if column not in own and not is_error_column(column)
                  and any(_is_number(row.get(column)) for row in table)]
    points: dict[tuple, dict[str, Any]] = {}
    for row in table:
        point = points.setdefault(group_key(row, names), {name: row[name] for name in names} |
                                  {"replicas_ok": 0, "disagreeing": ""})
        point["replicas_ok"] += row.get("status") == "ok"
    for quantity in quantities:
        for combined in aggregate(table, quantity, names):
            point = points[group_key(combined, names)]
            point[quantity], point[error_column(quantity)] = combined["mean"], combined["error"]
            if combined["disagree"]:
                point["disagreeing"] = ";".join(filter(None, [point["disagreeing"], quantity]))
    labels = [column for column in _columns(table) if column not in own
              and any(isinstance(row.get(column), (str, bool)) for row in table)]
    for key, point in points.items():
        succeeded = [row for row in table if row.get("status") == "ok" and group_key(row, names) == key]
        point |= _labels(succeeded, labels)
    return list(points.values())


def _labels(rows: list[Mapping[str, Any]], labels: list[str]) -> dict[str, Any]:
    """A point's boolean results as the fraction of ``rows`` where true (``<name>_fraction``), its text results as
    their value, or their distinct values joined by ``;``."""
    result = {}
    for label in labels:
        present = [row[label] for row in rows if row.get(label) is not None]
        values = [value for value in present if isinstance(value, (str, bool))]
        if values and len(values) == len(present) and all(isinstance(value, bool) for value in values):
            result[f"{label}_fraction"] = sum(values) / len(values)
        elif values:  # text (beside numbers in some replicas: under its own name, the numbers' mean keeps the name)
            name = label if len(values) == len(present) else f"{label}_text"
            result[name] = ";".join(dict.fromkeys(map(str, values)))
    return result


def write_outputs(study: Study, out, table: list[Mapping[str, Any]]) -> list[Path]:
    """Write ``results.csv`` (a row per replica), ``points.csv`` (a row per point, :func:`points_table`),
    ``results.parquet`` (with pyarrow) and ``main_result.png`` (with matplotlib).

    The plot needs the study's main key in at least one successful row.

    Examples
    --------
    >>> import tempfile
    >>> study = Study("encounter", seed=0, vary={"vinf": [1.0, 2.0]}, main="deflection")
    >>> table = [{"vinf": 1.0, "replica": 0, "status": "ok", "deflection": 1.2},
    ...          {"vinf": 2.0, "replica": 0, "status": "ok", "deflection": 0.6}]
    >>> sorted(path.name for path in write_outputs(study, tempfile.mkdtemp(), table))
    ['main_result.png', 'points.csv', 'results.csv', 'results.parquet']
    """
    out = Path(out)
    results_path, points_path, parquet_path, plot_path = (out / name for name in OUTPUT_FILES)
    files = [write_csv(results_path, table), write_csv(points_path, points_table(study, table))]
    parquet = write_parquet(parquet_path, table)
    if parquet is not None:
        files.append(parquet)
    plot = _plot_main(study, plot_path, table)
    if plot is not None:
        files.append(plot)
    return files


def _plot_main(study: Study, path: Path, table: list[Mapping[str, Any]]) -> Path | None:
    if study.main is None or not aggregate(table, study.main, []):
        return None
    try:
        import matplotlib
    except ImportError:  # pragma: no cover - depends on the installation
        return None
    matplotlib.use("Agg")
    from .. import plotting

    x = next(iter(study.vary))
    along_x = next((group for group in study.zip if x in group), (x,))  # zipped options move with x
    series = [name for name in study.vary if name not in along_x]
    points = aggregate(table, study.main, [*series, x])
    theory = {group_key(point, [*series, x]): point["mean"]
              for point in aggregate(table, f"{study.main}_theory", [*series, x])}  # e.g. edmd's Z_theory
    for point in points:
        expected = theory.get(group_key(point, [*series, x]))
        if expected is not None:
            point["theory"] = expected
    ax = plotting.plot_sweep(points, x, study.main, series=series, title=f"collisionkit {study.command}")
    return plotting.save(ax, path)
