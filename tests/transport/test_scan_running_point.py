"""SwarmScan saves its running E/N point and resumes it bit for bit: static, ionizing and oscillating runs.

A scan is stopped (KeyboardInterrupt, as Ctrl-C) right after its n-th save
within a point; the scan resumed from the file, and the same scan object
run again in the process, must give results identical to an uninterrupted
scan's in every field but the wall-clock ones.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from collisionkit._io import CheckpointError, read_checkpoint, write_checkpoint
from collisionkit._io.atomic import _strict_json
from collisionkit.transport import SwarmParameters, SwarmScan

CLOCK_FIELDS = {"seconds", "collisions_per_second"}  # wall-clock: the only fields a resumed run may change
STATIC = dict(model="reid", reduced_field=[12.0, 24.0], particles=1024, seed=3, tolerance=0.02, gas_temperature=0.0)
IONIZING = dict(model="lucas_saelee", reduced_field=[300.0], particles=1024, seed=5, tolerance=0.02,
                gas_temperature=0.0)
OSCILLATING = dict(model="reid", reduced_field=[12.0], reduced_frequency=1e-14, particles=512, seed=7,
                   tolerance=0.05, gas_temperature=0.0)


def physics_of(results):
    """Every field of each result but the wall-clock ones, as JSON text (NaN as null): equal means bit for bit."""
    return [json.dumps(_strict_json({key: value for key, value in result.to_dict().items()
                                     if key not in CLOCK_FIELDS})) for result in results]


def stopped_after_saves(parameters, checkpoint, saves):
    """A scan with a checkpoint written after every chunk, stopped as by Ctrl-C right after its ``saves``-th save of
    a running point; returns the scan and what each of those saves held (point index, transient over)."""
    stopped = SwarmScan(parameters, checkpoint=checkpoint, save_every=0.0)
    write, held = stopped.save, []

    def save(path=None):
        written = write(path)
        if stopped._running is not None:
            held.append((stopped._running[0], stopped._running[1]["scalars"]["steady_found"]))
            if len(held) == saves:
                raise KeyboardInterrupt
        return written

    stopped.save = save
    with pytest.raises(KeyboardInterrupt):
        stopped.run()
    stopped.save = write
    return stopped, held


@pytest.mark.parametrize(("values", "saves", "where"), [
    (STATIC, 1, (0, False)),   # in the first point's transient
    (STATIC, 3, (0, True)),    # measuring the first point
    (STATIC, 6, (1, True)),    # measuring the second point
    (IONIZING, 2, (0, False)),  # population control draws from the scan's generator
    (IONIZING, 3, (0, True)),
    (OSCILLATING, 3, (0, False)),  # samples on the grid of T / P
    (OSCILLATING, 6, (0, True)),
])
def test_a_scan_stopped_within_a_point_resumes_bit_for_bit(tmp_path, values, saves, where):
    parameters = SwarmParameters(**values)
    straight = physics_of(SwarmScan(parameters).run())
    checkpoint = tmp_path / "scan.npz"
    stopped, held = stopped_after_saves(parameters, checkpoint, saves)
    assert held[-1] == where
    saved = read_checkpoint(checkpoint, "swarm")
    assert saved.state["running_point"]["index"] == where[0] and len(saved.state["results"]) == where[0]
    assert physics_of(SwarmScan.resume(checkpoint).run()) == straight
    assert physics_of(stopped.run()) == straight  # the same object, run again after the interruption
    assert "running_point" not in read_checkpoint(checkpoint, "swarm").state  # finished: no running point left


def test_saving_the_running_point_changes_no_result(tmp_path):
    parameters = SwarmParameters(**STATIC)
    straight = physics_of(SwarmScan(parameters).run())
    assert physics_of(SwarmScan(parameters, checkpoint=tmp_path / "scan.npz", save_every=0.0).run()) == straight


def test_the_running_point_is_saved_only_every_save_every_seconds(tmp_path, monkeypatch):
    clock = iter(np.arange(0.0, 1e4, 7.0))  # each look at the clock 7 s later
    monkeypatch.setattr("collisionkit.transport.scan.time.monotonic", lambda: float(next(clock)))
    scan = SwarmScan(SwarmParameters(**STATIC), checkpoint=tmp_path / "scan.npz", save_every=20.0)
    write, times = scan.save, []
    scan.save = lambda path=None: times.append(scan._running is not None) or write(path)
    scan.run()
    every_chunk = []
    assert times.count(False) == 2  # after each finished point
    unthrottled = SwarmScan(SwarmParameters(**STATIC), checkpoint=tmp_path / "all.npz", save_every=0.0)
    write_all = unthrottled.save
    unthrottled.save = lambda path=None: every_chunk.append(unthrottled._running is not None) or write_all(path)
    unthrottled.run()
    assert 0 < times.count(True) < every_chunk.count(True)


def test_save_every_must_be_a_time(tmp_path):
    with pytest.raises(ValueError, match=r"save_every \(seconds\) must be >= 0; got -1"):
        SwarmScan(SwarmParameters(**STATIC), save_every=-1.0)


def damaged(checkpoint, change):
    """Rewrite ``checkpoint`` with ``change(state, arrays)`` applied."""
    saved = read_checkpoint(checkpoint, "swarm")
    state, arrays = dict(saved.state), dict(saved.arrays)
    change(state, arrays)
    write_checkpoint(checkpoint, "swarm", saved.parameters, state, arrays)


@pytest.mark.parametrize(("change", "words"), [
    (lambda state, arrays: state["running_point"].update(index=1), "its running point is number 1, not the first"),
    (lambda state, arrays: state["running_point"].update(run=[1]), "running point's state must be a mapping"),
    (lambda state, arrays: state.pop("running_point"), "holds a running point's arrays"),
])
def test_a_damaged_running_point_is_refused_when_resumed(tmp_path, change, words):
    checkpoint = tmp_path / "scan.npz"
    stopped_after_saves(SwarmParameters(**STATIC), checkpoint, 1)
    damaged(checkpoint, change)
    with pytest.raises(CheckpointError, match=words):
        SwarmScan.resume(checkpoint)


@pytest.mark.parametrize(("change", "words"), [
    (lambda state, arrays: state["running_point"]["run"].update({"class": "PeriodicRun"}),
     "holds a 'PeriodicRun' run, not a TensorRun"),
    (lambda state, arrays: state["running_point"]["run"]["scalars"].pop("dt"), "has the attributes"),
    (lambda state, arrays: state["running_point"]["run"]["scalars"].update(collisions=0.5),
     "'collisions' must be a int"),
    (lambda state, arrays: arrays.update({"point.swarm.vel": arrays["point.swarm.vel"][:, :2].copy()}),
     r"swarm's vel is float64\[\d+, 2\], not float64\[\d+, 3\]"),
    (lambda state, arrays: arrays.update({"point.swarm.group": arrays["point.swarm.group"] + 99}),
     "group numbers are not all in"),
    (lambda state, arrays: arrays.pop("point.times"), "the array 'point.times' is missing"),
    (lambda state, arrays: arrays.update({"point.times": arrays["point.times"][:-1]}),
     "series have different lengths"),
    (lambda state, arrays: state["running_point"]["run"].update(rng={"bit_generator": "MT19937"}),
     "generator cannot be restored"),
    (lambda state, arrays: state["running_point"]["run"].update(stepper={"slots": -1, "trial_budget": 5}),
     "stepper state must give slots, trial_budget as whole numbers"),
])
def test_a_running_point_that_does_not_fit_its_run_is_refused_naming_the_file(tmp_path, change, words):
    checkpoint = tmp_path / "scan.npz"
    stopped_after_saves(SwarmParameters(**STATIC), checkpoint, 1)
    damaged(checkpoint, change)
    resumed = SwarmScan.resume(checkpoint)
    with pytest.raises(CheckpointError, match=f"scan.npz is a damaged swarm checkpoint: its running point "
                                              rf"\(E/N = 12 Td\) cannot be restored: .*{words}"):
        resumed.run()
