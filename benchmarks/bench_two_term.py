"""collisionkit's two-term Boltzmann solver beside bolos, an independent implementation of the same equations.

Run from the repository root with the project venv:

    .venv/bin/python benchmarks/bench_two_term.py [--bolos /tmp/bolos_env] [--repeats 5]

bolos 0.2 (A. Luque, https://github.com/aluque/bolos, LGPL; pure Python, the
Hagelaar & Pitchford scheme with F0 piecewise exponential inside a cell) is
installed with ``pip install --target <dir> bolos future`` if ``--bolos`` does
not hold it, and used from there (its own numpy is removed so the project's
is used). Two fixes for today's scipy are applied at run time, not to its
files: ``scipy.integrate.simps`` is gone (``simpson`` stands in) and its
operator of the growth processes fails on a gas without any (an empty one
stands in).

Both solve the same gas on the same grid (the top energy collisionkit finds,
1000 cells), from a cold start each time: Reid's ramp (1, 12, 24 Td) and the
Lucas-Saelee model with F = 0.5 (10, 100 Td, ionizing: temporal growth), gas
at 0 K. Reported: mean energy, flux drift, N D and the ionization rate of
each, their relative differences, and the wall time per E/N point (median of
``--repeats`` alternating runs; bolos to its ``rtol = 1e-8``). Writes
benchmarks/results/two_term_bolos.md and .json.
"""

from __future__ import annotations

import argparse
import os
import platform
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import scipy.integrate
from scipy import constants, sparse

sys.path.insert(0, str(Path(__file__).parent))
from _bench_common import write_results  # noqa: E402

from collisionkit.transport import lucas_saelee, reid_ramp, two_term_boltzmann  # noqa: E402

CASES = [("reid", 1.0), ("reid", 12.0), ("reid", 24.0), ("lucas_saelee", 10.0), ("lucas_saelee", 100.0)]


def bolos_module(target: Path):
    """bolos imported from ``target`` (installed there first if missing), patched for today's scipy."""
    if not (target / "bolos").is_dir():
        subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--target", str(target), "bolos", "future"],
                       check=True)
    for name in target.glob("numpy*"):
        shutil.rmtree(name, ignore_errors=True)
    sys.path.append(str(target))
    scipy.integrate.simps = scipy.integrate.simpson
    from bolos import grid, solver

    original = solver.BoltzmannSolver._PQ

    def growth_operator(self, F0, reactions=None):
        reactions = None if reactions is None else list(reactions)
        if reactions == []:
            return sparse.csr_matrix((self.n, self.n))
        return original(self, F0, reactions)

    solver.BoltzmannSolver._PQ = growth_operator
    return grid, solver


def bolos_processes(model: str):
    """The model gas as bolos process dictionaries (tables fine enough to be exact for linear pieces)."""
    energy = np.linspace(0.0, 1000.0, 20001)
    if model == "reid":
        up = energy >= 0.2
        return [dict(target="X", kind="ELASTIC", mass_ratio=1.37145e-4, comment="",
                     data=np.c_[energy, np.full_like(energy, 6e-20)]),
                dict(target="X", kind="EXCITATION", threshold=0.2, comment="", product="X*",
                     data=np.c_[energy[up], 1e-19 * (energy[up] - 0.2)])]
    gamma = np.sqrt(2 * constants.e / constants.m_e)
    k = 4e-20 * gamma
    up = energy >= 15.6
    ramp = 1e-21 * (energy - 15.6)
    return [dict(target="X", kind="ELASTIC", mass_ratio=constants.m_e / (4 * constants.atomic_mass), comment="",
                 data=np.c_[energy[1:], k / (gamma * np.sqrt(energy[1:]))]),
            dict(target="X", kind="EXCITATION", threshold=15.6, comment="", product="X*",
                 data=np.c_[energy[up], 0.5 * ramp[up]]),
            dict(target="X", kind="IONIZATION", threshold=15.6, comment="", product="X+",
                 data=np.c_[energy[up], 0.5 * ramp[up]])]


def run_bolos(modules, model, reduced_field, top):
    grid, solver = modules
    boltzmann = solver.BoltzmannSolver(grid.LinearGrid(0.0, top, 1000))
    boltzmann.load_collisions(bolos_processes(model))
    boltzmann.target["X"].density = 1.0
    boltzmann.kT, boltzmann.EN = 0.0, reduced_field * solver.TOWNSEND
    boltzmann.init()
    f0 = boltzmann.converge(boltzmann.maxwell(0.3 if model == "reid" else 5.0), maxn=2000, rtol=1e-8)
    ionization = sum(boltzmann.rate(f0, process) for _, process in boltzmann.iter_growth())
    return (boltzmann.mean_energy(f0), boltzmann.mobility(f0) * reduced_field * solver.TOWNSEND,
            boltzmann.diffusion(f0), ionization)


def run_collisionkit(model, reduced_field, top=None):
    gas = reid_ramp() if model == "reid" else lucas_saelee(0.5)
    result = two_term_boltzmann(gas, reduced_field, 0.0, max_energy=top)
    return result, (result.mean_energy, result.drift_velocity, result.diffusion_N, result.ionization_frequency_N)


def timed(function, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bolos", type=Path, default=Path("/tmp/bolos_env"))
    parser.add_argument("--repeats", type=int, default=5)
    arguments = parser.parse_args()
    modules = bolos_module(arguments.bolos)
    rows, data = [], {"cases": []}
    for model, reduced_field in CASES:
        automatic, _ = run_collisionkit(model, reduced_field)
        top = automatic.max_energy
        ours = run_collisionkit(model, reduced_field, top)[1]
        theirs = run_bolos(modules, model, reduced_field, top)
        ours_time = timed(lambda: run_collisionkit(model, reduced_field, top), arguments.repeats)
        automatic_time = timed(lambda: run_collisionkit(model, reduced_field), arguments.repeats)
        theirs_time = timed(lambda: run_bolos(modules, model, reduced_field, top), arguments.repeats)
        differences = [ours[i] / theirs[i] - 1.0 if theirs[i] else 0.0 for i in range(4)]
        data["cases"].append({"model": model, "E_N": reduced_field, "top_eV": top, "collisionkit": ours,
                              "bolos": theirs, "relative_differences": differences,
                              "seconds": {"collisionkit_same_grid": ours_time, "collisionkit_automatic_grid":
                                          automatic_time, "bolos": theirs_time}})
        rows.append(f"| {model} | {reduced_field:g} | {top:.4g} | {ours[0]:.5g} / {theirs[0]:.5g} | "
                    f"{ours[1]:.6g} / {theirs[1]:.6g} | {ours[2]:.5g} / {theirs[2]:.5g} | "
                    f"{ours[3]:.5g} / {theirs[3]:.5g} | {max(abs(d) for d in differences):.1e} | "
                    f"{1e3 * ours_time:.0f} ({1e3 * automatic_time:.0f}) | {1e3 * theirs_time:.0f} |")
    load = os.getloadavg()
    text = "\n".join([
        "# Two-term Boltzmann: collisionkit beside bolos 0.2",
        "",
        f"`{' '.join(sys.argv)}` on {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"load {load[0]:.2f}; same grid (collisionkit's top, 1000 cells), gas at 0 K; times are medians of "
        f"{arguments.repeats} runs from a cold start (collisionkit on its own grid search in brackets).",
        "",
        "| gas | E/N (Td) | top (eV) | <e> (eV) ck / bolos | W (m/s) | N D (1/m/s) | k_ion (m^3/s) | "
        "max rel. diff. | ck (ms) | bolos (ms) |",
        "|---|---|---|---|---|---|---|---|---|---|",
        *rows,
        ""])
    write_results("two_term_bolos", text, data)


if __name__ == "__main__":
    main()
