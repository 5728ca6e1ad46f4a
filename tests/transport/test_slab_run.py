"""collisionkit.transport.SlabRun: a slab run checkpointed, interrupted and resumed bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from collisionkit._io import CheckpointError, read_checkpoint, write_checkpoint
from collisionkit.transport import SlabParameters, SlabRun, _slab_batches, simulate_slab
from collisionkit.transport.slab_run import SAVE_EVERY

from .slab_helpers import interrupt_after

PARAMETERS = SlabParameters(thickness=8.0, albedo=0.95, mass_ratio=4.0, particles=40_000, seed=3)
RESULT_FIELDS = ("transmission", "reflection", "absorption", "collisions_per_particle", "transmitted_angles",
                 "reflected_angles", "transmitted_energies", "reflected_energies")


def _same(a, b) -> bool:
    return all(np.array_equal(getattr(a, name), getattr(b, name)) for name in RESULT_FIELDS)


def _straight():
    p = PARAMETERS
    return simulate_slab(p.thickness, p.albedo, incidence=p.incidence, model=p.model, mass_ratio=p.mass_ratio,
                         particles=p.particles, seed=p.seed)


def _interrupted(path, monkeypatch, save_every=None):
    """A run stopped by Ctrl-C in its 60th kernel call (of about 200)."""
    interrupt_after(monkeypatch, 60)
    run = SlabRun(PARAMETERS, checkpoint=path, save_every=save_every)
    with pytest.raises(KeyboardInterrupt):
        run.run()
    monkeypatch.undo()
    return run


def test_a_run_interrupted_resumes_to_the_result_of_a_run_never_stopped(tmp_path, monkeypatch):
    path = tmp_path / "slab.npz"
    run = _interrupted(path, monkeypatch)
    saved = read_checkpoint(path, "slab")
    assert 0 < saved.state["done"] < PARAMETERS.particles and saved.state["done"] == run.done
    resumed = SlabRun.resume(path, thickness=8.0)  # a parameter given again must agree
    assert resumed.done == run.done and not resumed.finished
    assert _same(resumed.run(threads=1), _straight())  # on another number of threads, too
    assert SlabRun.resume(path).finished


def test_the_run_saves_while_it_runs_each_save_a_state_it_could_go_on_from(tmp_path, monkeypatch):
    from collisionkit.transport import slab_run

    path = tmp_path / "slab.npz"
    done, real = [], slab_run._write

    def write_and_check(target, parameters, batches):
        done.append(batches.done)
        real(target, parameters, batches)
        SlabRun.resume(target)  # every save passes the checks of a resume: counts that add up

    monkeypatch.setattr(_slab_batches, "PROGRESS_SECONDS", 0.001)
    interrupt_after(monkeypatch, calls=-1, pause=0.01)  # no Ctrl-C; ~300 calls of 10 ms: 1.5 s on 2 threads
    monkeypatch.setattr(slab_run, "_write", write_and_check)
    SlabRun(PARAMETERS, checkpoint=path, save_every=0.0).run()
    assert len(done) >= 3 and done == sorted(done) and done[0] < done[-1] == PARAMETERS.particles
    assert 60.0 == SAVE_EVERY == SlabRun(PARAMETERS).save_every  # by default a minute of work at most is lost


def test_a_save_taken_while_the_run_ran_goes_on_to_the_result_of_a_run_never_stopped(tmp_path, monkeypatch):
    """A copy of the checkpoint from mid-run (taken between the batches' calls as they ran) resumed bit for bit."""
    import shutil

    from collisionkit.transport import slab_run

    path, kept = tmp_path / "slab.npz", tmp_path / "mid-run.npz"
    real = slab_run._write

    def write_and_keep_the_first(target, parameters, batches):
        real(target, parameters, batches)
        if not kept.exists() and 0 < batches.done < parameters.particles:
            shutil.copy(target, kept)

    monkeypatch.setattr(_slab_batches, "PROGRESS_SECONDS", 0.001)
    interrupt_after(monkeypatch, calls=-1, pause=0.01)
    monkeypatch.setattr(slab_run, "_write", write_and_keep_the_first)
    SlabRun(PARAMETERS, checkpoint=path, save_every=0.0).run()
    monkeypatch.undo()
    resumed = SlabRun.resume(kept)
    # the first save mid-run came early: the workers wait at a gate while the main thread copies the batches (they
    # took their batches' locks again call after call, and the first save waited until 38035 of 40000 were done)
    assert 0 < resumed.done < PARAMETERS.particles // 8
    assert _same(resumed.run(), _straight())


@pytest.mark.parametrize(("threads", "error"), [(0, ValueError), ("2", TypeError), (1.5, TypeError)])
def test_threads_must_be_a_whole_number_of_at_least_one(threads, error):
    with pytest.raises(error, match="threads"):
        SlabRun(PARAMETERS).run(threads=threads)


def test_a_resumed_run_does_not_write_over_another_existing_file(tmp_path, monkeypatch):
    path, other = tmp_path / "slab.npz", tmp_path / "other.npz"
    _interrupted(path, monkeypatch)
    other.write_text("a user's file")
    with pytest.raises(FileExistsError, match="other.npz exists"):
        SlabRun.resume(path, checkpoint=other)
    assert other.read_text() == "a user's file"


def test_a_run_never_stopped_gives_simulate_slab_s_result(tmp_path):
    assert _same(SlabRun(PARAMETERS).run(), _straight())


def test_an_existing_checkpoint_is_not_replaced_and_other_physics_is_refused(tmp_path, monkeypatch):
    path = tmp_path / "slab.npz"
    _interrupted(path, monkeypatch)
    with pytest.raises(FileExistsError, match="exists"):
        SlabRun(PARAMETERS, checkpoint=path)
    with pytest.raises(ValueError, match="albedo = 0.5 differs from the checkpoint"):
        SlabRun.resume(path, albedo=0.5)
    assert SlabRun(PARAMETERS, checkpoint=path, overwrite=True).done == 0


@pytest.mark.parametrize(
    ("change", "words"),
    [
        (lambda arrays: arrays.pop("batches_rng"), "batches_rng must be an array of shape (64, 4)"),
        (lambda arrays: arrays.__setitem__("batches_left", arrays["batches_left"] + 1), "do not add up"),
        (lambda arrays: arrays["batches_counts"].__setitem__((0, 0), -1.0), "do not add up"),
        (lambda arrays: arrays["batches_angles"].__setitem__((1, 0, 3), 1e9), "do not add up"),
        (lambda arrays: arrays["batches_flights"].__setitem__((2, 0), np.nan), "do not add up"),
        # a history in flight outside the slab: its exit would be binned outside the histograms
        (lambda arrays: arrays["batches_flights"].__setitem__((3, slice(None)), [1.0, 0.5, -1e12, 1.0]),
         "lies outside the slab"),
        (lambda arrays: arrays["batches_flights"].__setitem__((3, slice(None)), [1.0, -3.0, 0.5, 1.0]),
         "lies outside the slab"),
        (lambda arrays: arrays["batches_flights"].__setitem__((3, slice(None)), [9.0, 0.5, 0.5, 1.0]),
         "lies outside the slab"),
        (lambda arrays: arrays["batches_flights"].__setitem__((3, 3), 0.5), "lies outside the slab"),
        (lambda arrays: arrays["batches_rng"].__setitem__(4, 0), "random stream is all zero"),
    ],
)
def test_a_damaged_checkpoint_is_refused_naming_what_is_wrong(tmp_path, monkeypatch, change, words):
    path = tmp_path / "slab.npz"
    _interrupted(path, monkeypatch)
    saved = read_checkpoint(path, "slab")
    arrays = {name: np.array(value) for name, value in saved.arrays.items()}
    change(arrays)
    write_checkpoint(path, "slab", saved.parameters, saved.state, arrays)
    with pytest.raises(CheckpointError, match="damaged slab checkpoint") as caught:
        SlabRun.resume(path)
    assert words in str(caught.value)
