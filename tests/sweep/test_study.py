"""collisionkit.sweep: study parsing and expansion, option names, checks against the command, seeds."""

from __future__ import annotations

import json
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from collisionkit import sweep
from tests.sweep.helpers import ENCOUNTERS, SMALL_EDMD, read_table, serial_run  # noqa: F401

def test_the_issue_example_parses_with_dashed_names():
    study = sweep.study_from_dict(
        {"command": "edmd", "replicas": 2, "seed": 1, "fixed": {"dim": 3, "particles": 500, "collisions": 20000},
         "vary": {"packing-fraction": [0.1, 0.2, 0.3]}}
    )  # fmt: skip
    assert study.vary == {"packing-fraction": (0.1, 0.2, 0.3)}
    assert study.fixed == {"dim": 3, "particles": 500, "collisions": 20000}
    assert study.main == "compressibility_factor"
    assert len(sweep.point_tasks(study, "out")) == 6


def test_underscored_keys_become_dashed_and_main_can_be_chosen():
    study = sweep.Study("edmd", seed=0, fixed={"packing_fraction": 0.2}, vary={"dim": [2, 3]}, main="pressure")
    assert study.fixed == {"packing-fraction": 0.2} and study.main == "pressure"


@pytest.mark.parametrize(
    ("spec", "expected"),
    [
        ({"start": 0.1, "stop": 0.3, "num": 3}, (0.1, 0.2, 0.3)),
        ({"start": 0.1, "stop": 0.5, "step": 0.1}, (0.1, 0.2, 0.3, 0.4, 0.5)),
        ({"start": 100, "stop": 400, "step": 100}, (100, 200, 300, 400)),
        ({"start": 100, "stop": 350, "step": 100}, (100, 200, 300)),
        ({"start": 1.0, "stop": 0.0, "step": -0.5}, (1.0, 0.5, 0.0)),
        ({"start": 1, "stop": 100, "num": 3, "log": True}, (1.0, 10.0, 100.0)),
        ({"start": 2.0, "stop": 2.0, "num": 1}, (2.0,)),
    ],
)
def test_ranges_expand_to_tidy_values(spec, expected):
    values = sweep.Study("edmd", seed=0, vary={"x": spec}).vary["x"]
    assert values == expected
    assert [type(value) for value in values] == [type(value) for value in expected]


@pytest.mark.parametrize(
    ("data", "error", "message"),
    [
        ({"command": "edmd", "seed": 1, "vary": {"dim": [2]}, "replica": 2}, ValueError, "unknown study key 'replica'"),
        ({"command": "edmd", "vary": {"dim": [2]}}, ValueError, "needs 'seed'"),
        ({"command": "edmd", "seed": 1}, ValueError, "needs 'vary'"),
        ({"command": "edmd", "seed": 1, "vary": {}}, ValueError, "at least one option"),
        ({"command": "edmd", "seed": 1, "vary": {"dim": []}}, ValueError, "vary.dim is an empty list"),
        ({"command": "edmd", "seed": 1, "vary": {"dim": 3}}, TypeError, "vary.dim must be a list or a range"),
        ({"command": "edmd", "seed": 1, "vary": {"dim": [{"a": 2}]}}, TypeError, "vary.dim must be a number"),
        ({"command": "edmd", "seed": 1, "vary": {"dim": [2]}, "replicas": 0}, ValueError, r"replicas must be in \[1, 100000\]"),
        ({"command": "edmd", "seed": 1, "vary": {"dim": [2]}, "replicas": 1.5}, TypeError, "replicas must be an integer"),
        ({"command": "edmd", "seed": 1, "vary": {"dim": [2]}, "replicas": True}, TypeError, "replicas must be an integer"),
        ({"command": "edmd", "seed": -1, "vary": {"dim": [2]}}, ValueError, "seed must be >= 0"),
        ({"command": "", "seed": 1, "vary": {"dim": [2]}}, TypeError, "command must be a non-empty string"),
        ({"command": "edmd", "seed": 1, "vary": {"dim": [2]}, "fixed": {"dim": 3}}, ValueError, "both fixed and varied"),
        ({"command": "edmd", "seed": 1, "vary": {"a-b": [1], "a_b": [2]}}, ValueError, "names 'a-b' twice"),
        ({"command": "edmd", "seed": 1, "vary": {"x": {"start": 0, "stop": 1}}}, ValueError, "exactly one of num or step"),
        ({"command": "edmd", "seed": 1, "vary": {"x": {"start": 0, "stop": 1, "num": 2, "step": 1}}}, ValueError, "exactly one"),
        ({"command": "edmd", "seed": 1, "vary": {"x": {"start": 0, "stop": 1, "count": 2}}}, ValueError, "unknown range keys"),
        ({"command": "edmd", "seed": 1, "vary": {"x": {"start": 0, "stop": 1, "num": 0}}}, ValueError, r"num must be in \[1, 100000\]"),
        ({"command": "edmd", "seed": 1, "vary": {"x": {"start": 0, "stop": 1, "step": 1e-9}}}, ValueError,
         "gives 1000000001 values"),  # listed them all before: minutes and gigabytes
        ({"command": "edmd", "seed": 1, "vary": {"x": {"start": 0, "stop": 1, "num": 10**9}}}, ValueError,
         r"num must be in \[1, 100000\]"),
        ({"command": "edmd", "seed": 1, "vary": {"x": {"start": 0, "stop": 1, "step": -1}}}, ValueError, "lead from start"),
        ({"command": "edmd", "seed": 1, "vary": {"x": {"start": 0, "stop": 1, "num": 3, "log": True}}}, ValueError, "log range"),
        ({"command": "edmd", "seed": 1, "vary": {"x": [1, 2], "y": [1]}, "zip": [["x", "y"]]}, ValueError, "same number"),
        ({"command": "edmd", "seed": 1, "vary": {"x": [1, 2]}, "zip": [["x", "z"]]}, ValueError, "'z', which is not in vary"),
        ({"command": "edmd", "seed": 1, "vary": {"x": [1]}, "fixed": {"y": float("nan")}}, ValueError, "must be finite"),
        # 1e10 runs were accepted and grew 2.5 GB a minute before the first point ran
        ({"command": "edmd", "seed": 1, "vary": {"x": {"start": 0, "stop": 1, "num": 100_000},
                                                 "y": {"start": 0, "stop": 1, "num": 100_000}}}, ValueError,
         "= 10000000000 runs; at most 1000000"),
        ({"command": "edmd", "seed": 1, "replicas": 11, "vary": {"x": {"start": 0, "stop": 1, "num": 100_000}}},
         ValueError, "100000 points x 11 replicas"),
    ],
)
def test_bad_studies_are_rejected_with_a_clear_message(data, error, message):
    with pytest.raises(error, match=message):
        sweep.study_from_dict(data)


def test_load_study_reports_missing_and_malformed_files(tmp_path):
    with pytest.raises(ValueError, match="study file not found"):
        sweep.load_study(tmp_path / "missing.toml")
    broken = tmp_path / "broken.toml"
    broken.write_text("command = \n")
    with pytest.raises(ValueError, match="not valid TOML"):
        sweep.load_study(broken)


def test_a_study_file_that_is_not_utf8_is_one_line_naming_the_file(tmp_path):
    latin1 = tmp_path / "latin1.toml"
    latin1.write_bytes('command = "edmd"\nseed = 1\n# café\n'.encode("latin-1"))  # tomllib raised UnicodeDecodeError
    with pytest.raises(ValueError) as caught:
        sweep.load_study(latin1)
    message = str(caught.value)
    assert str(latin1) in message and "not UTF-8" in message and "\n" not in message


# ------------------------------------------------------------------ the command's options


@pytest.mark.parametrize(
    ("data", "error", "message"),
    [
        ({"command": "nbody", "seed": 1, "vary": {"x": [1]}}, ValueError, "unknown command 'nbody'; available: .*edmd"),
        ({"command": "demo", "seed": 1, "vary": {"x": [1]}}, ValueError, "cannot be swept"),
        ({"command": "sweep", "seed": 1, "vary": {"x": [1]}}, ValueError, "cannot be swept"),
        ({"command": "edmd", "seed": 1, "vary": {"packing": [0.1]}}, ValueError, "no option 'packing' \\(its options: .*packing-fraction"),
        ({"command": "edmd", "seed": 1, "vary": {"seed": [1, 2]}}, ValueError, "'seed' is set by the sweep"),
        ({"command": "edmd", "seed": 1, "vary": {"dim": [3]}, "fixed": {"summary": "x.json"}}, ValueError, "'summary' is set by"),
        ({"command": "edmd", "seed": 1, "vary": {"particles": ["many"]}}, TypeError, "particles must be an integer"),
        ({"command": "edmd", "seed": 1, "vary": {"packing-fraction": ["0.1"]}}, TypeError, "must be a number"),
        ({"command": "edmd", "seed": 1, "vary": {"dim": [3]}, "fixed": {"plots": False}}, ValueError, "'plots' is set by"),
        ({"command": "edmd", "seed": 1, "vary": {"dim": [3]}, "fixed": {"frame-every": "often"}}, TypeError,
         "'frame-every' takes a int"),
        ({"command": "swarm", "seed": 1, "fixed": {"model": "reid"}, "vary": {"E-N": [10.0, -1.0]}}, ValueError,
         r"the point \{'E-N': -1.0\} is refused by 'collisionkit swarm'"),
        ({"command": "encounter", "seed": 1, "vary": {"seed": [1]}}, ValueError, "no option 'seed'"),
    ],
)
def test_options_are_checked_against_the_command(data, error, message):
    with pytest.raises(error, match=message):
        sweep.check_command(sweep.study_from_dict(data))


def test_point_options_hold_the_seed_and_each_point_has_its_folder(tmp_path):
    study = sweep.study_from_dict(SMALL_EDMD)
    task = sweep.point_tasks(study, tmp_path)[3]
    assert task.command == "edmd" and task.name == "p0001-r01"
    assert task.options["packing-fraction"] == 0.2 and task.options["particles"] == 108
    assert task.options["seed"] == task.seed
    assert task.directory == tmp_path / "points" / "p0001-r01"
    trajectory = sweep.study_from_dict({**SMALL_EDMD, "fixed": {**SMALL_EDMD["fixed"], "trajectory": "run.gsd"}})
    assert sweep.point_tasks(trajectory, tmp_path)[1].options["trajectory"] == "run.gsd"  # in the point's folder


def test_option_names_are_the_flags_and_the_python_names_are_accepted():
    swarm = sweep.Study("swarm", seed=0, fixed={"model": "reid", "gas_temperature": 300.0},
                        vary={"reduced_field": [10.0, 20.0]})
    assert list(swarm.vary) == ["E-N"] and swarm.fixed == {"model": "reid", "gas-temperature": 300.0}
    assert swarm.main == "mean_energy"
    flags = sweep.Study("swarm", seed=0, fixed={"model": "reid"}, vary={"E-N": [10.0, 20.0]})
    python_names = sweep.Study("swarm", seed=0, fixed={"model": "reid"}, vary={"reduced_field": [10.0, 20.0]})
    assert flags.fingerprint() == python_names.fingerprint()
    with pytest.raises(ValueError, match="names 'E-N' twice"):
        sweep.Study("swarm", seed=0, vary={"E-N": [1.0], "reduced_field": [2.0]})
    encounter = sweep.Study("encounter", seed=0, vary={"v_inf": [0.5, 1.0]})
    assert list(encounter.vary) == ["vinf"]


# ------------------------------------------------------------------ points and seeds


def test_expansion_is_the_cartesian_product_last_option_fastest():
    study = sweep.Study("edmd", seed=0, vary={"a": [1, 2], "b": ["x", "y", "z"]})
    points = sweep.expand(study)
    assert len(points) == 6
    assert points[:4] == [{"a": 1, "b": "x"}, {"a": 1, "b": "y"}, {"a": 1, "b": "z"}, {"a": 2, "b": "x"}]


def test_zip_groups_need_equal_lengths_and_pair_values_in_order():
    with pytest.raises(ValueError, match="same number"):
        sweep.Study("edmd", seed=0, vary={"a": [1, 2], "c": [5, 6, 7]}, zip=[["a", "c"]])
    study = sweep.Study("edmd", seed=0, vary={"a": [1, 2], "b": [3, 4], "c": [5, 6]}, zip=[["a", "c"]])
    assert [tuple(point.values()) for point in sweep.expand(study)] == [(1, 3, 5), (1, 4, 5), (2, 3, 6), (2, 4, 6)]


def test_seeds_come_from_seed_sequence_spawn_and_are_all_different():
    study = sweep.study_from_dict(SMALL_EDMD)
    tasks = sweep.point_tasks(study, "out")
    children = [child.spawn(2) for child in np.random.SeedSequence(11).spawn(3)]
    for task in tasks:
        child = children[task.index][task.replica]
        assert task.spawn_key == child.spawn_key
        assert task.seed == int(child.generate_state(1, dtype=np.uint32)[0])
    assert len({task.seed for task in tasks}) == len(tasks)


def test_more_replicas_or_points_keep_the_existing_seeds():
    base = {task.name: task.seed for task in sweep.point_tasks(sweep.study_from_dict(SMALL_EDMD), "out")}
    larger = sweep.study_from_dict({**SMALL_EDMD, "replicas": 3, "vary": {"packing-fraction": [0.1, 0.2, 0.3, 0.4]}})
    grown = {task.name: task.seed for task in sweep.point_tasks(larger, "out")}
    assert all(grown[name] == seed for name, seed in base.items())
    other_root = sweep.study_from_dict({**SMALL_EDMD, "seed": 12})
    assert not set(base.values()) & {task.seed for task in sweep.point_tasks(other_root, "out")}




def test_a_numpy_array_of_values_is_varied_like_the_list_of_its_numbers():
    # np.linspace(...) was refused: "must be a list or a range"
    from_array = sweep.Study("edmd", seed=1, fixed={"particles": 200}, vary={"packing-fraction": np.linspace(0.1, 0.3, 3)})
    from_list = sweep.Study("edmd", seed=1, fixed={"particles": 200}, vary={"packing-fraction": [0.1, 0.2, 0.3]})
    assert from_array.vary == from_list.vary and from_array.fingerprint() == from_list.fingerprint()
    assert all(type(value) is float for value in from_array.vary["packing-fraction"])
