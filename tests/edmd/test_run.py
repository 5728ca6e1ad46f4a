"""collisionkit.edmd.run: EdmdParameters checks, and EdmdRun resumes bit for bit from Python."""

from __future__ import annotations

import numpy as np
import pytest

from collisionkit import edmd
from collisionkit._io import CheckpointError, read_checkpoint
from collisionkit.edmd import EdmdParameters, EdmdRun, HardSphereSystem, TransportSampler

SMALL = dict(particles=108, initial="fcc", equilibration=12_000, collisions=4_000, blocks=4, seed=3)


@pytest.mark.parametrize(
    ("values", "error", "words"),
    [
        ({"dim": 4}, ValueError, "dim must be one of 2, 3"),
        ({"packing_fraction": 0.55}, ValueError, "packing_fraction must lie in (0, 0.5] for dim=3"),
        ({"dim": 2, "packing_fraction": 0.71}, ValueError, "(0, 0.7] for dim=2"),
        ({"restitution": -0.1}, ValueError, "restitution must be in [0, 1]"),
        ({"particles": 1}, ValueError, "particles must be in [2, 100000000]"),
        ({"particles": 2.5}, TypeError, "particles must be an integer"),
        ({"collisions": 5, "blocks": 10}, ValueError, "collisions must be >= blocks (10)"),
        ({"initial": "bcc"}, ValueError, "initial must be one of"),
        ({"initial": "fcc", "particles": 100}, ValueError, "needs particles = 4 * cells^3"),
        ({"seed": -1}, ValueError, "seed must be >= 0"),
        ({"transport": True, "restitution": 0.9}, ValueError, "transport needs restitution 1"),
        ({"transport": "yes"}, ValueError, "transport must be true or false; got 'yes'"),
        ({"yeh_hummer": True}, ValueError, "yeh_hummer needs transport"),
        ({"yeh_hummer": True, "transport": True, "dim": 2}, ValueError, "and dim 3"),
        ({"engine": "grid"}, ValueError, "engine must be one of auto, lists, cells; got 'grid'"),
        ({"engine": None}, ValueError, "engine must be one of auto, lists, cells; got None"),
        ({"engine": "cells", "shear_rate": 0.1}, ValueError, "engine cells cannot be combined with shear_rate"),
    ],
)
def test_bad_parameters_name_the_parameter_and_the_allowed_range(values, error, words):
    with pytest.raises(error) as caught:
        EdmdParameters(**values)
    assert words in str(caught.value)


def test_flags_and_python_names_read_the_same_and_defaults_resolve_per_particle():
    by_flag = EdmdParameters.from_mapping({"packing-fraction": 0.2, "particles": 256})
    assert by_flag == EdmdParameters(packing_fraction=0.2, particles=256)
    resolved = by_flag.resolved(seed=7)
    assert (resolved.equilibration, resolved.collisions, resolved.seed) == (20 * 256, 200 * 256, 7)
    assert resolved.total_collisions == 20 * 256 + 200 * 256
    assert EdmdParameters.from_mapping(resolved.to_dict()) == resolved  # the summary's block reruns it
    with pytest.raises(ValueError, match="unknown parameter 'packing'"):
        EdmdParameters.from_mapping({"packing": 0.2})
    with pytest.raises(ValueError, match=r"collisions \(400 by default for 2 particles\) must be >= blocks \(1000\)"):
        EdmdParameters(particles=2, blocks=1000).resolved()


def test_a_run_killed_mid_way_resumes_bit_for_bit_from_its_checkpoint(tmp_path, monkeypatch):
    straight = EdmdRun(EdmdParameters(**SMALL)).run()
    fractions = []
    checkpoint = tmp_path / "run.npz"
    run = EdmdRun(EdmdParameters(**SMALL), checkpoint=checkpoint)
    real, calls = HardSphereSystem.run, []

    def killed_in_the_second_block(system, *args, **kwargs):
        calls.append(1)
        if len(calls) == 4:  # two equilibration chunks, one block, then the kill
            raise KeyboardInterrupt
        return real(system, *args, **kwargs)

    monkeypatch.setattr(HardSphereSystem, "run", killed_in_the_second_block)
    with pytest.raises(KeyboardInterrupt):
        run.run(progress=fractions.append)
    monkeypatch.undo()
    assert read_checkpoint(checkpoint, "edmd").state["equilibrated"] == 12_000
    assert fractions == sorted(fractions) and 0 < fractions[-1] < 1  # progress(fraction), never back
    resumed = EdmdRun.resume(checkpoint, seed=3)  # a physics parameter given again must agree
    assert resumed.measured == 1_000 and not resumed.finished
    resumed.run()
    assert np.array_equal(resumed.system.positions(), straight.system.positions())
    assert np.array_equal(resumed.system.velocities(), straight.system.velocities())
    a, b = resumed.summary(), straight.summary()
    assert a["compressibility_factor"] == b["compressibility_factor"] and a["parameters"] == b["parameters"]
    with pytest.raises(ValueError, match="packing_fraction = 0.2 differs from the checkpoint"):
        EdmdRun.resume(checkpoint, packing_fraction=0.2)


QUICK = dict(particles=108, initial="fcc", equilibration=500, collisions=400, blocks=2, seed=3)


def _resaved(path, state=None, drop=(), arrays=None):
    """The run's checkpoint written again with entries of its state or arrays replaced (a crafted file)."""
    from collisionkit._io import write_checkpoint

    saved = read_checkpoint(path, "edmd")
    kept = {name: value for name, value in saved.arrays.items() if name not in drop} | (arrays or {})
    write_checkpoint(path, "edmd", saved.parameters, saved.state | (state or {}), kept)


@pytest.mark.parametrize(
    ("state", "drop", "arrays", "words"),
    [
        ({"equilibrated": "lots"}, (), None, "state 'equilibrated' must be an integer in [0, 500]; got 'lots'"),
        ({"equilibrated": 10**9}, (), None, "state 'equilibrated' must be an integer in [0, 500]"),
        ({"last_frame": -5}, (), None, "state 'last_frame' must be an integer >= -1; got -5"),
        ({"initial_energy": None}, (), None, "state 'initial_energy' must be a number >= 0; got None"),
        ({"trajectory": 5}, (), None, "state 'trajectory' must be a text; got 5"),
        ({"frame_every": 0}, (), None, "state 'frame_every' must be an integer >= 1; got 0"),
        ({}, ("tree",), None, "the state has no array 'tree'"),
        ({}, ("sampler_histogram",), None, "its measurement cannot be read (no array 'sampler_histogram')"),
        ({}, (), {"sampler_scalars": np.array([7.0, 1.0, 1.0, 0.0, 0.0, 0.0])},
         "measurement arrays (sampler_*) do not fit"),
    ],
)
def test_a_damaged_run_checkpoint_is_one_line_naming_the_entry(tmp_path, state, drop, arrays, words):
    # the state's entries went through int() and float() and the arrays through KeyError: tracebacks
    path = tmp_path / "run.npz"
    run = EdmdRun(EdmdParameters(**QUICK), checkpoint=path)
    run.run()  # a finished run: its checkpoint holds the measurement too
    _resaved(path, state, drop, arrays)
    with pytest.raises(CheckpointError) as caught:
        EdmdRun.resume(path)
    message = str(caught.value)
    assert str(path) in message and words in message and "\n" not in message, message


def test_a_run_whose_checkpoint_another_process_writes_is_refused_before_any_work(tmp_path, monkeypatch):
    from collisionkit._io import FileLockedError
    from tests._io.processes import HOLD, held_by_another_process

    path = tmp_path / "run.npz"
    run = EdmdRun(EdmdParameters(**QUICK), checkpoint=path)
    monkeypatch.setattr(HardSphereSystem, "run", lambda *args, **kwargs: pytest.fail("the run started"))
    with held_by_another_process(HOLD, path) as pid, pytest.raises(FileLockedError, match=f"pid {pid}"):
        run.run()
    monkeypatch.undo()
    assert not path.exists()
    run.run()  # the other process is gone
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.npz"]  # no lock file once the run ends


def test_a_resumed_run_appends_to_its_trajectory_and_refuses_one_with_fewer_frames(tmp_path):
    from collisionkit.trajectory import read_gsd, truncate_gsd

    path, frames = tmp_path / "run.npz", tmp_path / "run.gsd"
    run = EdmdRun(EdmdParameters(**QUICK), checkpoint=path, trajectory=frames, frame_every=100)
    run.run()
    written = run.frames
    assert read_gsd(frames)["frames"] == written > 2
    truncate_gsd(frames, written - 1)  # frames lost (or another file put in its place)
    with pytest.raises(ValueError, match=f"holds {written - 1} frames, fewer than the {written} its checkpoint wrote"):
        EdmdRun.resume(path, trajectory=frames).run()  # a stored path is used only when given again
    assert read_gsd(frames)["frames"] == written - 1  # left as it was


def test_a_checkpoint_of_another_kind_or_no_checkpoint_is_refused(tmp_path):
    from collisionkit.transport import SwarmParameters, SwarmScan

    other = tmp_path / "scan.npz"
    SwarmScan(SwarmParameters(model="maxwell", reduced_field=[5.0], particles=128, tolerance=0.5,
                              collision_budget=1e4), checkpoint=other).save()
    with pytest.raises(CheckpointError, match="not a checkpoint of 'collisionkit edmd'"):
        EdmdRun.resume(other)
    junk = tmp_path / "junk.npz"
    junk.write_bytes(b"junk")
    with pytest.raises(CheckpointError, match="is not a checkpoint"):
        EdmdRun.resume(junk)
    with pytest.raises(CheckpointError, match="checkpoint not found"):
        EdmdRun.resume(tmp_path / "missing.npz")
    with pytest.raises(RuntimeError, match="call run"):
        EdmdRun(EdmdParameters(**SMALL)).measurement()


def test_an_extended_run_measures_whole_more_blocks_exactly_as_a_longer_run_would(tmp_path):
    # issue 16, item 8: a finished run could not be extended with more collisions
    short = dict(SMALL, collisions=2_000, blocks=2)
    path = tmp_path / "short.npz"
    EdmdRun(EdmdParameters(**short), checkpoint=path).run()
    extended = EdmdRun.resume(path)
    assert extended.finished
    assert extended.extend(1_500) == 2_000  # rounded up to whole blocks of 1000
    assert not extended.finished
    extended.run()
    assert extended.finished and extended.measured == 4_000
    assert read_checkpoint(path, "edmd").parameters["blocks"] == 4  # the checkpoint records the new totals
    longer = EdmdRun(EdmdParameters(**SMALL)).run()
    for name in ("temperature", "compressibility", "pressure", "frequency", "time", "msd"):
        assert extended.sampler.records[name] == longer.sampler.records[name], name
    np.testing.assert_array_equal(extended.sampler.histogram, longer.sampler.histogram)
    with pytest.raises(ValueError, match="collisions must be >= 1"):
        extended.extend(0)


TRANSPORT = dict(particles=108, initial="fcc", equilibration=2_000, collisions=8_000, blocks=4, seed=5, transport=True)


def test_a_transport_run_killed_mid_block_resumes_and_extends_bit_for_bit(tmp_path, monkeypatch):
    """The time grid, the moment series and the velocity autocorrelation continue from a checkpoint exactly:
    a run killed inside its second block, resumed, then extended by two blocks reports what one straight run
    of four blocks does, to the last bit."""
    straight = EdmdRun(EdmdParameters(**TRANSPORT)).run().summary()
    checkpoint = tmp_path / "run.npz"
    short = dict(TRANSPORT, collisions=4_000, blocks=2)
    real = TransportSampler._take

    def killed_in_the_second_block(sampler, block):
        if block == 1 and sampler._in_block == 20:  # 20 grid samples into the second block
            raise KeyboardInterrupt
        return real(sampler, block)

    monkeypatch.setattr(TransportSampler, "_take", killed_in_the_second_block)
    with pytest.raises(KeyboardInterrupt):
        EdmdRun(EdmdParameters(**short), checkpoint=checkpoint).run()
    monkeypatch.undo()
    resumed = EdmdRun.resume(checkpoint, transport=True)
    assert resumed.measured == 2_000 and resumed.sampler.transport is not None
    resumed.run()
    resumed.extend(4_000)
    summary = resumed.run().summary()
    for key in ("shear_viscosity", "shear_viscosity_error", "bulk_viscosity", "thermal_conductivity",
                "green_kubo_shear_viscosity", "pressure_tensor", "vacf", "transport_fit_window"):
        assert summary[key] == straight[key], key
    with pytest.raises(ValueError, match="transport = False differs from the checkpoint"):
        EdmdRun.resume(checkpoint, transport=False)


def test_a_transport_run_reports_the_coefficients_with_errors_and_enskogs_values():
    summary = EdmdRun(EdmdParameters(**TRANSPORT, yeh_hummer=True)).run().summary()
    for key in ("shear_viscosity", "bulk_viscosity", "thermal_conductivity", "self_diffusion"):
        assert summary[key] > 0 and summary[key + "_error"] > 0 and summary[key + "_enskog"] > 0, key
    assert summary["self_diffusion"] == summary["diffusion_coefficient"]
    side = (108 * (3.141592653589793 / 6) / 0.3) ** (1 / 3)  # the box of 108 spheres at eta = 0.3
    correction = 2.837297 / (6 * 3.141592653589793 * summary["shear_viscosity"] * side)
    assert summary["yeh_hummer_correction"] == pytest.approx(correction, rel=1e-9)
    assert summary["self_diffusion_infinite"] == pytest.approx(summary["self_diffusion"] + correction, rel=1e-12)
    low, high = summary["transport_fit_window_free_times"]
    assert low < high and np.shape(summary["pressure_tensor"]) == (3, 3)
    assert EdmdParameters(particles=100, transport=True).resolved(seed=1).collisions == 200_000  # 2000 a particle


def test_a_disc_transport_run_reports_enskogs_values_for_discs():
    """2D: the summary's Enskog values are the hard-disc ones (Gass 1971) at the run's packing fraction."""
    run = EdmdRun(EdmdParameters(**(TRANSPORT | {"dim": 2, "particles": 100, "initial": "random"}))).run()
    summary = run.summary()
    enskog = edmd.enskog_transport(summary["packing_fraction"], kT=summary["temperature"], dim=2)
    for key in ("shear_viscosity", "bulk_viscosity", "thermal_conductivity", "self_diffusion"):
        assert summary[key + "_enskog"] == pytest.approx(enskog[key], rel=1e-12), key
    assert summary["shear_viscosity_enskog"] != edmd.enskog_transport(summary["packing_fraction"],
                                                                      kT=summary["temperature"])["shear_viscosity"]


def test_a_study_can_set_transport_as_it_sets_any_parameter():
    from collisionkit.sweep.commands import sweep_command

    command = sweep_command("edmd")
    assert command.options()["transport"] == "transport" and command.canonical("yeh_hummer") == "yeh-hummer"
    assert command.parameters.from_mapping({"transport": True, "particles": 108}).transport is True


# 64 discs at eta = 0.1 (a box of 22 diameters): dilute, so "auto" takes the cells
DILUTE = dict(dim=2, particles=64, packing_fraction=0.1, initial="square", equilibration=200, collisions=400, blocks=2,
              seed=4)


@pytest.mark.parametrize(("engine", "packing_fraction", "used"), [
    ("lists", 0.1, "lists"), ("cells", 0.1, "cells"), ("auto", 0.1, "cells"), ("auto", 0.6, "lists"),
    ("cells", 0.5, "cells"),  # asked for, the cells run a dense fluid too (slower than the lists there)
])
def test_the_engine_reaches_the_system_and_the_summary_says_which_ran(engine, packing_fraction, used):
    run = EdmdRun(EdmdParameters(**(DILUTE | {"packing_fraction": packing_fraction}), engine=engine))
    assert run.parameters.engine == engine and run.system.engine == used
    summary = run.run().summary()
    assert summary["engine"] == used and summary["parameters"]["engine"] == engine
    assert EdmdParameters.from_mapping(summary["parameters"]) == run.parameters  # the summary's block reruns it


def test_a_random_start_runs_the_engine_asked_for_after_its_compression():
    # the compression always runs on the lists; the fluid then gets the engine of the parameters
    lists = EdmdRun(EdmdParameters(**(DILUTE | {"initial": "random"}), engine="lists"))
    assert lists.system.engine == "lists"
    assert EdmdRun(EdmdParameters(**(DILUTE | {"initial": "random"}))).system.engine == "cells"


def test_a_resumed_run_keeps_its_engine_and_refuses_another(tmp_path):
    path = tmp_path / "run.npz"
    parameters = EdmdParameters(**DILUTE, engine="lists")  # dilute: "auto" would take the cells
    straight = EdmdRun(parameters).run().summary()
    EdmdRun(parameters, checkpoint=path).save()  # as after set-up
    assert read_checkpoint(path, "edmd").parameters["engine"] == "lists"
    resumed = EdmdRun.resume(path, engine="lists")  # given again, it must agree
    assert resumed.parameters.engine == "lists" and resumed.system.engine == "lists"
    summary = resumed.run().summary()
    assert summary["engine"] == "lists" and summary["compressibility_factor"] == straight["compressibility_factor"]
    with pytest.raises(ValueError, match="engine = cells differs from the checkpoint"):
        EdmdRun.resume(path, engine="cells")


def test_parameters_and_checkpoints_from_before_the_engine_option_load_with_auto(tmp_path):
    old = EdmdParameters(**DILUTE).to_dict()
    del old["engine"]
    assert EdmdParameters.from_mapping(old).engine == "auto"
    path = tmp_path / "run.npz"
    run = EdmdRun(EdmdParameters(**DILUTE), checkpoint=path)
    run.save()
    saved = read_checkpoint(path, "edmd")
    from collisionkit._io import write_checkpoint

    write_checkpoint(path, "edmd", old, saved.state, saved.arrays)
    resumed = EdmdRun.resume(path)
    assert resumed.parameters.engine == "auto" and resumed.system.engine == run.system.engine == "cells"
    assert resumed.run().summary()["engine"] == "cells"


def test_a_checkpoint_whose_system_runs_another_engine_than_its_parameters_is_refused(tmp_path):
    path = tmp_path / "run.npz"
    EdmdRun(EdmdParameters(**DILUTE, engine="lists"), checkpoint=path).save()
    saved = read_checkpoint(path, "edmd")
    from collisionkit._io import write_checkpoint

    write_checkpoint(path, "edmd", saved.parameters | {"engine": "cells"}, saved.state, saved.arrays)
    with pytest.raises(CheckpointError) as caught:
        EdmdRun.resume(path)
    message = str(caught.value)
    assert "its system runs the lists engine, its parameters ask for engine cells" in message and "\n" not in message


def test_a_new_run_does_not_replace_another_run_s_checkpoint_or_trajectory_unless_asked(tmp_path):
    # a new EdmdRun silently replaced the checkpoint (and the GSD file) of another, finished run
    checkpoint, trajectory = tmp_path / "run.npz", tmp_path / "run.gsd"
    first = EdmdRun(EdmdParameters(dim=2, particles=64, initial="square", collisions=400, blocks=2, seed=1),
                    checkpoint=checkpoint)
    first.run()
    saved = checkpoint.read_bytes()
    other = EdmdParameters(dim=2, particles=100, initial="square", collisions=400, blocks=2, seed=2)
    with pytest.raises(FileExistsError, match=r"checkpoint .*run\.npz exists .*overwrite=True"):
        EdmdRun(other, checkpoint=checkpoint)
    assert checkpoint.read_bytes() == saved
    trajectory.write_bytes(b"someone's frames")
    with pytest.raises(FileExistsError, match=r"trajectory .*run\.gsd exists"):
        EdmdRun(other, checkpoint=tmp_path / "new.npz", trajectory=trajectory)
    assert trajectory.read_bytes() == b"someone's frames" and not (tmp_path / "new.npz").exists()
    assert EdmdRun.resume(checkpoint).parameters.particles == 64  # the first run's, still resumable
    EdmdRun(other, checkpoint=checkpoint, overwrite=True).run()
    assert EdmdRun.resume(checkpoint).parameters.particles == 100


def test_a_run_and_its_sampler_say_what_they_are_and_how_far_they_got():
    run = EdmdRun(EdmdParameters(dim=2, particles=64, initial="square", collisions=400, blocks=2, seed=1))
    assert repr(run) == ("EdmdRun(64 particles in 2D, eta=0.3, equilibrated 0 of 1280, measured 0 of 400 collisions, "
                         "checkpoint=None)")
    run.run()
    assert "equilibrated 1280 of 1280, measured 400 of 400 collisions" in repr(run)
    assert repr(run.sampler).startswith("Sampler(2 of 2 blocks of 200 collisions done, HardSphereSystem(64 discs")
