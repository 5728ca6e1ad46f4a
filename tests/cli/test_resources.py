"""Memory and compiling: a run too big for the machine is refused before any work; compiling is said, never timed."""

from __future__ import annotations

import gc
import itertools
import json
import os
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

import pytest
from typer.testing import CliRunner

from collisionkit.cli import _memory, _warmup, app

runner = CliRunner()
ROOT = Path(__file__).resolve().parents[2]


def said(text: str) -> str:
    return " ".join(text.split())


# ------------------------------------------------------------------ item 6: memory


def test_an_edmd_run_too_big_for_the_memory_is_refused_before_any_work(tmp_path, monkeypatch):
    # edmd --particles 100000000 was accepted and died with a MemoryError traceback after 32 s
    monkeypatch.setattr(_memory, "available_memory", lambda: 8 * 10**9)
    monkeypatch.chdir(tmp_path)
    start = time.perf_counter()
    result = runner.invoke(app, ["edmd", "--particles", "100000000", "--summary", "s.json"])
    assert time.perf_counter() - start < 10
    assert result.exit_code == 2, result.output
    assert said(result.output) == (
        "error: --particles 100000000 needs about 247 GB of memory, more than the 8 GB available on this machine; "
        "the random start's compression needs the most (a lattice start, --initial fcc or hexagonal, needs about "
        "177 GB): use fewer particles")
    assert list(tmp_path.iterdir()) == []
    fits = runner.invoke(app, ["edmd", "--particles", "108", "--initial", "fcc", "--collisions", "200", "--no-plots"])
    assert fits.exit_code == 0, fits.output


def test_a_swarm_too_big_for_the_memory_is_refused_before_any_work(monkeypatch):
    monkeypatch.setattr(_memory, "available_memory", lambda: 10**9)
    result = runner.invoke(app, ["swarm", "--model", "lucas_saelee", "--E-N", "500", "--particles", "1000000"])
    assert result.exit_code == 2
    assert "--particles 1000000 of a gas that ionizes or attaches needs about 6.7 GB of memory, more than the 1 GB" \
        in said(result.output)
    assert runner.invoke(app, ["swarm", "--model", "maxwell", "--E-N", "10", "--particles", "640", "--tolerance",
                               "0.1", "--collision-budget", "1e4"]).exit_code == 0


def test_the_available_memory_comes_from_meminfo_or_the_system(tmp_path, monkeypatch):
    meminfo = tmp_path / "meminfo"
    meminfo.write_text("MemTotal:       24684096 kB\nMemFree:  100 kB\nMemAvailable:   23633292 kB\n")
    monkeypatch.setattr(_memory, "MEMINFO", meminfo)
    assert _memory.available_memory() == 23633292 * 1024
    monkeypatch.setattr(_memory, "MEMINFO", tmp_path / "missing")
    assert _memory.available_memory() in (None, os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))


def _traced_peak(run) -> int:
    """tracemalloc's peak during ``run()``, after one untraced call (the figures are measured after a warm-up:
    a first call's compiler or cache loading allocates Python objects that are not the run's)."""
    run()
    gc.collect()
    tracemalloc.start()
    try:
        run()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


@pytest.mark.parametrize(("initial", "particles", "eta"), [("random", 4000, 0.3), ("random", 4000, 0.1),
                                                           ("fcc", 4000, 0.3), ("fcc", 4000, 0.02)])
def test_the_memory_estimate_covers_what_a_run_allocates(initial, particles, eta, tmp_path):
    # the figures per particle were measured at larger N (see cli/_memory.py); here a small run checks them again,
    # with a checkpoint (a second copy of the state while it is written); eta 0.02 runs the cell engine, whose
    # cells (16 a sphere) need more than the lists' estimate (a traced 2.58 kB a particle against 1.77 kB)
    from collisionkit.edmd import EdmdParameters, EdmdRun

    parameters = EdmdParameters(particles=particles, initial=initial, packing_fraction=eta, equilibration=0,
                                collisions=20, blocks=10, seed=1)
    paths = (tmp_path / f"run{number}.npz" for number in itertools.count())
    peak = _traced_peak(lambda: EdmdRun(parameters, checkpoint=next(paths)).run().measurement())
    assert peak <= _memory.edmd_memory(parameters), (peak, _memory.edmd_memory(parameters))


def test_the_memory_estimate_counts_the_cells_where_the_cell_engine_may_run():
    from collisionkit.edmd import EdmdParameters
    from collisionkit.edmd._cell_crossings import cells_below_packing

    def per_particle(**options):
        return _memory.edmd_memory(EdmdParameters(particles=4000, initial="fcc", blocks=10, **options)) / 4000

    lists = _memory.EDMD_LATTICE_BYTES_PER_PARTICLE + 10 * _memory.EDMD_BYTES_PER_PARTICLE_AND_BLOCK
    cells = _memory.EDMD_CELLS_BYTES_PER_PARTICLE + 10 * _memory.EDMD_BYTES_PER_PARTICLE_AND_BLOCK
    threshold = cells_below_packing(3, 4000)
    below = threshold - 0.01
    assert per_particle(packing_fraction=below) == cells
    assert per_particle(packing_fraction=below, engine="lists") == lists
    assert per_particle(packing_fraction=0.3, engine="cells") == cells
    assert per_particle(packing_fraction=threshold) == lists
    assert per_particle(packing_fraction=below, shear_rate=0.1) == lists


def test_the_swarm_memory_estimate_covers_what_a_swarm_allocates():
    from collisionkit.transport import model_gas, simulate_swarm

    particles = 20_000
    peak = _traced_peak(lambda: simulate_swarm(model_gas("maxwell"), 10.0, particles=particles, seed=0,
                                               tolerances={"mean_energy": 0.5}, collision_budget=3e5))
    assert peak <= _memory.swarm_memory(particles, ionizing=False), peak


def test_the_swarm_memory_estimate_with_a_checkpoint_covers_the_saved_running_point(tmp_path):
    from collisionkit.transport import SwarmParameters, SwarmScan

    particles = 20_000  # past the transient (run with a 16th of them) and saved after every chunk of samples
    parameters = SwarmParameters(model="maxwell", reduced_field=[10.0], particles=particles, tolerance=0.001,
                                 collision_budget=3e7)
    peak = _traced_peak(lambda: SwarmScan(parameters, checkpoint=tmp_path / "scan.npz", save_every=0.0).run())
    assert _memory.swarm_memory(particles, ionizing=False) < peak  # the saved state is a real cost
    assert peak <= _memory.swarm_memory(particles, ionizing=False, checkpoint=True), peak


# ------------------------------------------------------------------ item 7: compiling said, never timed


def test_a_cold_kernel_cache_is_said_on_stderr(tmp_path, monkeypatch):
    # a cold first run sat at 0 % for ~25 s with no word
    monkeypatch.setattr(_warmup, "kernels_cached", lambda dispatchers: False)
    arguments = ["slab", "--particles", "640", "--summary", str(tmp_path / "s.json")]
    cold = runner.invoke(app, arguments)
    assert cold.exit_code == 0, cold.output
    assert "note: compiling kernels (first run only)" in said(cold.stderr) and "compiling" not in cold.stdout
    assert "kernels compiled in" in said(cold.stderr)
    monkeypatch.undo()
    warm = runner.invoke(app, [*arguments, "--overwrite"])
    assert warm.exit_code == 0 and "compiling" not in warm.output


def test_the_cache_check_reads_numba_s_cache_index(tmp_path):
    # once warmed up (compiled here if the cache was cold) the cache holds them; a fresh cache folder holds none
    domains = ["edmd", "swarm", "slab", "encounter", "core"]
    _warmup.warm_up(domains)
    assert _warmup.cold(domains) is False
    code = "from collisionkit.cli._warmup import cold; print(cold(['edmd']), cold([]))"
    env = os.environ | {"NUMBA_CACHE_DIR": str(tmp_path / "empty-cache"), "PYTHONPATH": str(ROOT / "src")}
    output = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True).stdout
    assert output.split() == ["True", "False"]


@pytest.fixture
def slow_first_g_of_r(monkeypatch):
    """The g(r) kernel's first call takes 2 s, as a compile on a cold cache does; later calls are as usual."""
    import collisionkit.edmd._pair_distribution as pair_distribution

    real, calls = pair_distribution.pair_histogram, []

    def first_call_slow(*args, **kwargs):
        if not calls:
            time.sleep(2.0)
        calls.append(1)
        return real(*args, **kwargs)

    monkeypatch.setattr(pair_distribution, "pair_histogram", first_call_slow)
    return 2.0


def test_edmd_s_collisions_per_second_leave_compiling_out(tmp_path, slow_first_g_of_r):
    # the measurement timed each block with the g(r) kernel in it: its first call (the compile) counted
    summary = tmp_path / "s.json"
    result = runner.invoke(app, ["edmd", "--particles", "108", "--initial", "fcc", "--equilibration", "0",
                                 "--collisions", "4000", "--blocks", "2", "--no-plots", "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    data = json.loads(summary.read_text())
    assert data["collisions"] / data["collisions_per_second"] < slow_first_g_of_r  # the timed seconds


def test_the_demo_s_speeds_leave_compiling_out(tmp_path, slow_first_g_of_r):
    # the first demo reported 3.1e4 collisions/s where the warm figure is 3e5
    summary = tmp_path / "s.json"
    result = runner.invoke(app, ["demo", "--pairs", "1000", "--no-plots", "--out", str(tmp_path / "demo"),
                                 "--summary", str(summary)])
    assert result.exit_code == 0, result.output
    spheres = json.loads(summary.read_text())["sections"]["event-driven MD"]["spheres"]
    assert spheres["collisions"] / spheres["collisions_per_second"] < slow_first_g_of_r
