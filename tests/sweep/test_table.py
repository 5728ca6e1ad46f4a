"""collisionkit.sweep: the results table flattens nested results and vectors; the means across replicas."""

from __future__ import annotations

import math

import numpy as np
import pytest

from collisionkit import sweep
from collisionkit.sweep.table import MAX_VECTOR


def _record(summary, replica=0):
    return {"point": 0, "replica": replica, "seed": 7, "spawn_key": [0, replica], "status": "ok", "error": None,
            "elapsed": 0.1, "parameters": {"E-N": 10.0}, "summary": summary}


STUDY = sweep.Study("swarm", seed=0, fixed={"model": "reid"}, vary={"E-N": [10.0]})


def test_vectors_tensors_and_nested_results_become_columns():
    summary = {"mean_energy": 1.5, "mean_energy_error": 0.01, "drift": [1.0, 2.0, 3.0],
               "tensor": [[1.0, 0.0], [0.0, 2.0]], "rates": {"a": 4.0}, "eedf": list(range(MAX_VECTOR + 1)),
               "name": "reid", "converged": True, "parameters": {"particles": 640}, "files": ["x.png"]}
    (row,) = sweep.results_table(STUDY, [_record(summary)])
    assert row["E-N"] == 10.0 and row["mean_energy"] == 1.5 and row["mean_energy_error"] == 0.01
    assert [row[f"drift[{i}]"] for i in range(3)] == [1.0, 2.0, 3.0]
    assert row["tensor[1][1]"] == 2.0 and row["tensor[0][1]"] == 0.0 and row["rates.a"] == 4.0
    assert row["name"] == "reid" and row["converged"] is True  # text and booleans are results too
    assert not any(key.startswith(("eedf", "parameters", "files")) for key in row)


def test_points_give_a_boolean_s_fraction_of_successful_replicas_and_text_that_agrees_or_each_value():
    rows = [_record({"homogeneous": flag, "engine": engine, "y": 1.0}, replica)
            for replica, (flag, engine) in enumerate([(True, "cells"), (False, "cells"), (True, "cells")])]
    failed = _record({"homogeneous": False, "engine": "lists"}, 3) | {"status": "failed"}
    table = sweep.results_table(STUDY, rows + [failed])
    (point,) = sweep.points_table(STUDY, table)
    assert point["homogeneous_fraction"] == pytest.approx(2 / 3) and point["engine"] == "cells"
    assert "homogeneous" not in point and point["replicas_ok"] == 3
    mixed = sweep.results_table(STUDY, [_record({"engine": "cells"}, 0), _record({"engine": "lists"}, 1)])
    assert sweep.points_table(STUDY, mixed)[0]["engine"] == "cells;lists"
    odd = sweep.results_table(STUDY, [_record({"k": 1.5, "mix": True}, 0), _record({"k": "auto", "mix": 2.0}, 1)])
    (point,) = sweep.points_table(STUDY, odd)  # a column of numbers and text keeps both; a bool among numbers is text
    assert point["k"] == 1.5 and point["k_text"] == "auto" and point["mix"] == 2.0 and point["mix_text"] == "True"
    assert sweep.aggregate(odd, "mix", [])[0]["n"] == 1
    (fraction,) = sweep.aggregate(table, "homogeneous", [])  # as a study's main result: 2 of 3, binomial scatter
    assert fraction["n"] == 3 and fraction["mean"] == pytest.approx(2 / 3)
    assert fraction["error"] == pytest.approx(np.std([1, 0, 1], ddof=1) / math.sqrt(3))


def test_the_parquet_table_keeps_booleans_numbers_and_text_apart(tmp_path):
    import pyarrow.parquet as pq
    table = sweep.results_table(STUDY, [_record({"homogeneous": True, "engine": "cells", "y": 1.5}, 0),
                                        _record({"homogeneous": False, "engine": "lists", "y": 2.0}, 1)])
    types = {field.name: str(field.type) for field in pq.read_table(sweep.write_parquet(tmp_path / "t.parquet",
                                                                                         table)).schema}
    assert (types["homogeneous"], types["engine"], types["y"]) == ("bool", "string", "double")


def test_a_list_of_results_becomes_columns_unless_it_repeats_the_top_level():
    entry = {"mean_energy": 1.5, "E_N": 10.0}
    (single,) = sweep.results_table(STUDY, [_record(entry | {"results": [entry]})])
    assert not any(key.startswith("results") for key in single)
    (scan,) = sweep.results_table(STUDY, [_record({"results": [entry, {"mean_energy": 2.5, "E_N": 20.0}]})])
    assert scan["results[0].mean_energy"] == 1.5 and scan["results[1].E_N"] == 20.0


def test_means_across_replicas_and_a_single_replica_s_own_error():
    table = sweep.results_table(STUDY, [_record({"y": 1.0, "y_error": 0.5}, 0), _record({"y": 3.0, "y_error": 0.5}, 1)])
    (both,) = sweep.aggregate(table, "y", ["E-N"])
    # weighted mean 2 +- 0.5/sqrt(2), chi2 = 8 on 1 dof: the error scales by sqrt(8) to 1.0, and they disagree
    assert both["n"] == 2 and both["mean"] == 2.0 and both["error"] == pytest.approx(1.0, rel=1e-12)
    assert both["chi2_per_dof"] == pytest.approx(8.0, rel=1e-12) and both["disagree"]
    (one,) = sweep.aggregate(table[:1], "y", ["E-N"])
    assert one["error"] == 0.5
    assert math.isnan(sweep.aggregate(sweep.results_table(STUDY, [_record({"y": 1.0})]), "y", [])[0]["error"])
    no_errors = sweep.results_table(STUDY, [_record({"y": 1.0}, 0), _record({"y": 3.0}, 1)])
    assert sweep.aggregate(no_errors, "y", [])[0]["error"] == pytest.approx(1.0, rel=1e-12)  # std(ddof=1)/sqrt(2)


def test_the_issue_s_two_replicas_keep_their_own_errors_not_their_chance_agreement():
    # 2.41624 +- 0.0012 was quoted where each replica's error was ~0.007: 5.7 sigma from theory instead of 1.3
    table = sweep.results_table(STUDY, [_record({"Z": 2.4150, "Z_error": 0.0070}, 0),
                                        _record({"Z": 2.4174, "Z_error": 0.0072}, 1)])
    (point,) = sweep.aggregate(table, "Z", [])
    assert point["error"] == pytest.approx((1 / 0.0070**2 + 1 / 0.0072**2) ** -0.5, rel=1e-12)
    assert point["scatter_error"] == pytest.approx(0.0012, rel=1e-9) and not point["disagree"]


def test_replica_errors_match_their_scatter_in_repeated_draws():
    # the combined error is honest: over many simulated points, (mean - truth) / error has unit spread
    rng = np.random.default_rng(5)
    pulls = []
    for _ in range(4000):
        sigma = rng.uniform(0.5, 2.0, size=3)
        values = 10.0 + sigma * rng.standard_normal(3)
        combined = sweep.combine_replicas(values, sigma)
        pulls.append((combined["mean"] - 10.0) / combined["error"])
    spread = float(np.std(pulls))
    assert 0.85 < spread < 1.0  # <= 1: the scale factor only enlarges; 4000 draws: +-0.02 statistical


def test_points_csv_has_a_row_per_point_with_every_result_and_its_error(tmp_path):
    study = sweep.Study("swarm", seed=0, fixed={"model": "reid"}, vary={"E-N": [10.0, 20.0]})
    records = [_record({"mean_energy": e, "mean_energy_error": 0.01, "drift": [0.0, 0.0, -v]}, r)
               | {"point": p, "parameters": {"E-N": f}}
               for p, (f, e, v) in enumerate([(10.0, 1.0, 5.0), (20.0, 2.0, 9.0)]) for r, e in ((0, e), (1, e + 0.02))]
    table = sweep.results_table(study, records)
    points = sweep.points_table(study, table)
    assert [point["E-N"] for point in points] == [10.0, 20.0] and [p["replicas_ok"] for p in points] == [2, 2]
    assert points[0]["mean_energy"] == pytest.approx(1.01, rel=1e-12)
    assert points[0]["mean_energy_error"] == pytest.approx(0.01 / math.sqrt(2) * math.sqrt(2.0), rel=1e-9)
    assert points[1]["drift[2]"] == -9.0 and points[1]["drift_error[2]"] == 0.0  # a list's element: as results.csv
    files = sweep.write_outputs(study.__class__("swarm", seed=0, fixed={"model": "reid"}, vary={"E-N": [10.0, 20.0]},
                                                main="mean_energy"), tmp_path, table)
    assert (tmp_path / "points.csv") in files and (tmp_path / "points.csv").read_text().count("\n") == 3


def test_an_option_varied_through_lists_gives_its_points_table_and_plot(tmp_path):
    """``vary = {diameters = [[1, 0.5], [1, 0.8]]}`` (a list option): points grouped by the lists, drawn as categories."""
    study = sweep.Study("edmd", seed=0, fixed={"fractions": [0.5, 0.5]}, vary={"diameters": [[1.0, 0.5], [1.0, 0.8]]},
                        main="compressibility_factor")
    records = [_record({"compressibility_factor": z, "compressibility_factor_error": 0.05}, r)
               | {"point": p, "parameters": {"diameters": d}}
               for p, d in enumerate([[1.0, 0.5], [1.0, 0.8]]) for r, z in ((0, 3.5 + p), (1, 3.6 + p))]
    table = sweep.results_table(study, records)
    points = sweep.points_table(study, table)
    assert [point["diameters"] for point in points] == [[1.0, 0.5], [1.0, 0.8]]
    assert [point["compressibility_factor"] for point in points] == pytest.approx([3.55, 4.55])
    assert [point["n"] for point in sweep.aggregate(table, "compressibility_factor", ["diameters"])] == [2, 2]
    files = sweep.write_outputs(study, tmp_path, table)
    assert tmp_path / "main_result.png" in files and '"[1.0, 0.8]",2' in (tmp_path / "points.csv").read_text()


def test_a_nested_result_combines_with_its_own_error_column():
    """A swarm scan's results[i].mean_energy pairs with results[i].mean_energy_error (the error rule applies to the
    last part of a nested key): the replicas' own errors count, and no error column becomes a result."""
    study = sweep.Study("swarm", seed=0, fixed={"model": "reid"}, vary={"tolerance": [0.01]})
    records = [_record({"results": [{"mean_energy": e, "mean_energy_error": 0.05},
                                    {"mean_energy": 2 * e, "mean_energy_error": 0.05}]}, r)
               | {"point": 0, "parameters": {"tolerance": 0.01}} for r, e in ((0, 1.0), (1, 1.001))]
    point = sweep.points_table(study, sweep.results_table(study, records))[0]
    assert point["results[0].mean_energy_error"] == pytest.approx(0.05 / math.sqrt(2), rel=1e-6)  # own, not scatter
    assert not any(key.startswith("results_error") or key.endswith("_error_error") for key in point)
