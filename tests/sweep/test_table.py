"""collisionkit.sweep: the results table flattens nested results and vectors; the means across replicas."""

from __future__ import annotations

import math

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
    assert not any(key.startswith(("eedf", "name", "converged", "parameters", "files")) for key in row)


def test_a_list_of_results_becomes_columns_unless_it_repeats_the_top_level():
    entry = {"mean_energy": 1.5, "E_N": 10.0}
    (single,) = sweep.results_table(STUDY, [_record(entry | {"results": [entry]})])
    assert not any(key.startswith("results") for key in single)
    (scan,) = sweep.results_table(STUDY, [_record({"results": [entry, {"mean_energy": 2.5, "E_N": 20.0}]})])
    assert scan["results[0].mean_energy"] == 1.5 and scan["results[1].E_N"] == 20.0


def test_means_across_replicas_and_a_single_replica_s_own_error():
    table = sweep.results_table(STUDY, [_record({"y": 1.0, "y_error": 0.5}, 0), _record({"y": 3.0, "y_error": 0.5}, 1)])
    (both,) = sweep.aggregate(table, "y", ["E-N"])
    assert both["n"] == 2 and both["mean"] == 2.0 and both["error"] == 1.0  # std(ddof=1) / sqrt(2)
    (one,) = sweep.aggregate(table[:1], "y", ["E-N"])
    assert one["error"] == 0.5
    assert math.isnan(sweep.aggregate(sweep.results_table(STUDY, [_record({"y": 1.0})]), "y", [])[0]["error"])
