r"""A spatially resolved steady-state Townsend (SST) run: the Townsend coefficient measured from exponential growth.

Electrons are released at the plane :math:`s = 0` (:math:`s` the distance
along the drift, i.e. along the force of the field) into an unbounded gas
and followed, with every electron their ionizations create, until they pass
the plane :math:`s = L` (absorbed there). The time-integrated density
:math:`\int n(s, t)\,dt` of this point release is the density of a steady
source; past the region where the electrons relax from their initial
energies it grows as :math:`e^{\alpha_{eff} s}`, the effective Townsend
coefficient :math:`\alpha_{eff} = \alpha - \eta` of SST conditions (the
spatial eigenvalue of the Boltzmann equation; Dujko et al., Phys. Rev. E
81, 046403 (2010); Blevin & Fletcher, Aust. J. Phys. 37, 593 (1984)). The
ionization and attachment events per unit length, proportional to that
density there, grow alike.

:func:`simulate_sst` samples the density at the end of every interval of
about ``collisions_per_sample`` collisions an electron, in ``bins`` slabs of
:math:`[0, L)`, and fits :math:`\ln\int n\,dt` with a straight line over a
window of :math:`[0, L)` (weights: the samples in each slab). The error is a
jackknife over the independent groups of electrons (each group the progeny
of its own initial electrons, on its own random streams). The bulk
conversion (:func:`~collisionkit.transport.townsend_coefficients`, first
order in the density gradient) agrees with it within errors where the
hydrodynamic regime holds (a test: the Lucas-Saelee model).
"""

from __future__ import annotations

import math
import os
import time
from dataclasses import dataclass

import numpy as np
from scipy import constants

from .._arrays import seed_value
from ._swarm_run import Stepper, initial_swarm
from ._tables import SHARING_CODES, build_tables
from ._validation import integer_in_range, real_in_range, validate_swarm_setup
from .gases import Gas
from .swarm import REFERENCE_DENSITY, _field_record, _require_collisions
from .._repr import dataclass_repr

__all__ = ["SSTResult", "simulate_sst"]

# electrons followed at once: a step holds about 1.7 kB an electron at most (16 child slots), so a few GB
MAX_ELECTRONS = 10**6


@dataclass
class SSTResult:
    """The result of :func:`simulate_sst` (N-scaled lengths: ``N s`` in m^-2).

    ``alpha_eff_N`` is :math:`(\\alpha - \\eta)/N` (m^2) with its jackknife
    error; ``position_N`` the slab centres (N s, m^-2), ``density`` the
    time-integrated density of the point release in each slab (per initial
    electron, s/m), ``window`` the fitted range of N s.

    Examples
    --------
    >>> from collisionkit.transport import lucas_saelee, simulate_sst
    >>> r = simulate_sst(lucas_saelee(1.0, mass=9.109e-28), 100.0, length_N=2e21, particles=64, groups=4, seed=1,
    ...                  gas_temperature=0.0, threads=1)
    >>> r.position_N.shape == r.density.shape, r.window[1] / r.window[0]
    (True, 2.0)
    """

    __repr__ = dataclass_repr  # arrays by their shape, not printed whole

    reduced_field: float
    gas_temperature: float
    alpha_eff_N: float
    alpha_eff_N_error: float
    position_N: np.ndarray
    density: np.ndarray
    window: tuple[float, float]
    particles: int
    groups: int
    collisions: int
    seconds: float


def _slope(positions, counts, weights):
    """Weighted least-squares slope of ln(counts) against positions (NaN if a count is not positive)."""
    if np.any(counts <= 0):
        return math.nan
    y = np.log(counts)
    w = weights / weights.sum()
    mean_x, mean_y = (w * positions).sum(), (w * y).sum()
    return float((w * (positions - mean_x) * (y - mean_y)).sum() / (w * (positions - mean_x) ** 2).sum())


def simulate_sst(gas: Gas, reduced_field: float, *, length_N: float, window=(0.4, 0.8), bins: int = 80,
                 gas_temperature: float = 300.0, particles: int = 2000, groups: int = 16, seed: int = 0,
                 sharing: str = "equal", initial_energy: float = 1.0, collisions_per_sample: float = 20.0,
                 collision_budget: float = 2e9, max_electrons: int = MAX_ELECTRONS,
                 threads: int | None = None) -> SSTResult:
    r"""Measure :math:`(\alpha - \eta)/N` from the growth of electrons released at a plane (see the module docstring).

    Parameters
    ----------
    gas : Gas
    reduced_field : float
        E/N in Td (> 0).
    length_N : float
        N L (m^-2, > 0): electrons are followed to the plane s = L; choose a
        few :math:`1/\alpha_{eff}` (the electrons multiply by about
        :math:`e^{\alpha_{eff} L}`).
    window : (float, float)
        The fitted range, as fractions of L (0 <= a < b <= 1): past the
        relaxation of the initial energies, short of the absorbing plane.
    bins : int
        Slabs of [0, L) (>= 4).
    gas_temperature, particles, groups, seed, sharing, initial_energy, collisions_per_sample, threads
        As in :func:`~collisionkit.transport.simulate_swarm` (``particles``:
        the electrons released, >= 2 per group).
    collision_budget : float
        Real collisions at most (> 0): a RuntimeError if the electrons have
        not all passed L by then (a run growing without end).
    max_electrons : int
        Electrons followed at once at most (from ``particles`` to 10^9;
        default 10^6, a few GB at the most): a RuntimeError before a step
        that would start with more (the avalanche outgrew the memory: the
        electrons multiply by about :math:`e^{\alpha_{eff} L}`).

    Returns
    -------
    SSTResult

    Examples
    --------
    Lucas-Saelee with every inelastic collision ionizing, 100 Td (a small run: the error is large):

    >>> from collisionkit.transport import lucas_saelee, simulate_sst
    >>> r = simulate_sst(lucas_saelee(1.0, mass=9.109e-28), 100.0, length_N=2e21, particles=64, groups=4, seed=1,
    ...                  gas_temperature=0.0, threads=1)
    >>> bool(r.alpha_eff_N > 0 and r.alpha_eff_N_error < r.alpha_eff_N)
    True
    """
    seed = seed_value(seed)
    validate_swarm_setup(gas, reduced_field, 0.0, gas_temperature, seed, constants.m_e, -constants.e, initial_energy)
    real_in_range(reduced_field, "reduced_field (Td, > 0 for an SST run)", 0.0)
    length = real_in_range(length_N, "length_N (m^-2)", 0.0) / REFERENCE_DENSITY
    low, high = (real_in_range(value, "window", 0.0, 1.0, inclusive=(True, True)) for value in window)
    if not low < high:
        raise ValueError(f"window must be two fractions of the length, the first below the second; got {window}")
    bins = integer_in_range(bins, "bins", 4)
    groups = integer_in_range(groups, "groups", 4, 1024)
    particles = integer_in_range(particles, f"particles (2 per group, {groups} groups)", 2 * groups)
    if sharing not in SHARING_CODES:
        raise ValueError(f"sharing must be one of {sorted(SHARING_CODES)}; got {sharing!r}")
    real_in_range(collisions_per_sample, "collisions_per_sample", 0.0)
    real_in_range(collision_budget, "collision_budget", 0.0)
    max_electrons = integer_in_range(max_electrons, f"max_electrons (at least particles, {particles})", particles,
                                     10**9)
    threads = integer_in_range(threads, "threads", 1) if threads is not None else (os.cpu_count() or 1)
    mass, charge = constants.m_e, -constants.e
    tables = build_tables(gas, mass, gas_temperature)
    _require_collisions(tables)
    field = _field_record(reduced_field, 0.0, REFERENCE_DENSITY, mass, charge, (0.0, 0.0, 0.0))
    stepper = Stepper(tables, field, mass, REFERENCE_DENSITY, SHARING_CODES[sharing], threads)
    swarm = initial_swarm(particles, groups, seed, mass, initial_energy)
    speed = math.sqrt(2.0 * initial_energy * constants.e / mass)
    bin_of_speed = min(int(speed / tables.bound_step), tables.bound.shape[1] - 1)
    dt = collisions_per_sample / max(REFERENCE_DENSITY * tables.bound[:, bin_of_speed].sum(), 1e-300)
    n_proc = tables.kind.size
    samples = np.zeros((groups, bins))
    t, collisions, seconds = 0.0, 0, 0.0
    try:
        def within_limit(swarm):
            """``swarm``, if it holds at most max_electrons (checked before every step and part of a step)."""
            if swarm.size > max_electrons:
                reached = float(np.max(-swarm.pos[:, 2])) / length  # the leading electrons, as a fraction of L
                raise RuntimeError(_too_many_electrons(swarm.size, max_electrons, reached, length_N))
            return swarm

        while within_limit(swarm).size:
            start = time.perf_counter()
            swarm, tally = stepper.step(swarm, t, t + dt, groups, control=within_limit)
            seconds += time.perf_counter() - start
            t += dt
            collisions += int(tally[:, :n_proc].sum())
            along = -swarm.pos[:, 2]  # the force on an electron points along -z
            inside = swarm.alive & (along < length)
            counted = inside & (along >= 0.0)
            slab = np.minimum((along[counted] / length * bins).astype(np.int64), bins - 1)
            np.add.at(samples, (swarm.group[counted], slab), 1.0)
            swarm = swarm.take(np.nonzero(inside)[0])
            if collisions > collision_budget and swarm.size:
                raise RuntimeError(f"the SST run used its collision budget ({collision_budget:g}) with {swarm.size} "
                                   "electrons still short of the plane s = L: use a shorter length_N or a larger "
                                   "budget")
    finally:
        stepper.close()
    centres = (np.arange(bins) + 0.5) * length / bins
    fitted = (centres >= low * length) & (centres < high * length)
    total = samples.sum(axis=0)
    slope = _slope(centres[fitted], total[fitted], total[fitted])
    jackknife = np.array([_slope(centres[fitted], (total - samples[g])[fitted], (total - samples[g])[fitted])
                          for g in range(groups)])
    error = math.sqrt((groups - 1) / groups * ((jackknife - jackknife.mean()) ** 2).sum())
    return SSTResult(reduced_field=float(reduced_field), gas_temperature=float(gas_temperature),
                     alpha_eff_N=slope / REFERENCE_DENSITY, alpha_eff_N_error=error / REFERENCE_DENSITY,
                     position_N=centres * REFERENCE_DENSITY, density=total * dt / particles,
                     window=(low * length * REFERENCE_DENSITY, high * length * REFERENCE_DENSITY),
                     particles=particles, groups=groups, collisions=collisions, seconds=seconds)


def _too_many_electrons(count: int, max_electrons: int, reached: float, length_N: float) -> str:
    """Why an SST run stopped: ``count`` electrons, more than ``max_electrons``, the leaders at ``reached`` L."""
    return (f"the SST run stopped with {count} electrons, more than max_electrons ({max_electrons}), the leading ones "
            f"at {reached:.2g} of the length: the avalanche grows as exp(alpha_eff s) and would outgrow the memory; "
            f"use a shorter length_N (now {length_N:g} m^-2, a few 1/(alpha_eff/N) is enough), fewer particles or a "
            "larger max_electrons")
