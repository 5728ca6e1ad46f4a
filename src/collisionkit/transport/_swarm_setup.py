"""Setting up and running a swarm for :func:`~collisionkit.transport.simulate_swarm`, its arguments checked.

:func:`new_run` builds the run of the transient (its share of the particles,
the stepper and the estimators, :mod:`._tensors` or :mod:`._periodic`);
:func:`run_to_steady_state` runs it until its tolerances are met and closes
the stepper; :func:`with_field_settings` records the field's settings in the
result. Inside :func:`resumable_point` a run starts from a saved state and
reports each chunk of samples (:class:`~collisionkit.transport.SwarmScan`'s
checkpoints within a point). The module-level switches (``CHECK_BOUND``) and the reference
density stay in :mod:`collisionkit.transport.swarm`, which passes them in.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass

import numpy as np

from ._periodic import PeriodicRun
from ._run_snapshot import restore_run
from ._swarm_run import Stepper, initial_swarm
from ._tables import SHARING_CODES
from ._tensors import TensorRun
from .swarm_result import SwarmResult

# The transient runs with 1/TRANSIENT_SHARE of the particles (at least TRANSIENT_PER_GROUP a group), which are then
# cloned to the full number: relaxing costs per particle, and in argon at low E/N it takes ~M/(2m) = 4e4 collisions
# a particle (the whole of a run that relaxed with every particle)
TRANSIENT_SHARE = 16
TRANSIENT_PER_GROUP = 64


@dataclass(frozen=True)
class PointHooks:
    """Where the next swarm run starts and whom it tells of its chunks (see :func:`resumable_point`)."""

    saved: tuple[dict, dict] | None  # (state, arrays) of :func:`._run_snapshot.run_snapshot`, or None: a new run
    on_chunk: Callable | None  # called with the run after each chunk of samples that does not end it


# set only inside resumable_point (a context variable: each thread, e.g. a sweep's worker, has its own)
_POINT_HOOKS: ContextVar[PointHooks | None] = ContextVar("swarm_point_hooks", default=None)


@contextmanager
def resumable_point(saved, on_chunk) -> Iterator[None]:
    """Inside: the swarm run of :func:`~collisionkit.transport.simulate_swarm` starts from ``saved`` (skipping the
    calibration; None: a new run) and calls ``on_chunk(run)`` after each chunk of samples that does not end it.

    :class:`~collisionkit.transport.SwarmScan` saves the running point this
    way without a second, private signature of ``simulate_swarm``.

    Examples
    --------
    >>> with resumable_point(None, print):
    ...     _POINT_HOOKS.get().saved is None
    True
    >>> _POINT_HOOKS.get() is None
    True
    """
    token = _POINT_HOOKS.set(PointHooks(saved, on_chunk))
    try:
        yield
    finally:
        _POINT_HOOKS.reset(token)


def new_run(tables, field_record, oscillating, reduced_frequency, particles, groups, seed, mass, initial_energy,
            sharing, threads, phases, density, check_bound):
    """The run of the transient: its swarm (a share of the particles), the stepper and the estimators.

    The transient runs with 1/:data:`TRANSIENT_SHARE` of the particles (at
    least :data:`TRANSIENT_PER_GROUP` a group), cloned to ``particles`` when
    it ends (``run.final_counts``); an oscillating field's run resolves the
    phase (:class:`~._periodic.PeriodicRun`), a static one the tensors.

    Parameters
    ----------
    tables, field_record
        The gas's tables and the kernel's field record.
    oscillating : bool
        Whether the field oscillates (at ``reduced_frequency``, omega/N in rad m^3/s).
    reduced_frequency : float
        omega/N.
    particles, groups, seed, mass, initial_energy, sharing, threads, phases
        :func:`~collisionkit.transport.simulate_swarm`'s arguments, checked (``threads`` None: all cores).
    density : float
        The gas's number density (m^-3) of the field record.
    check_bound : bool
        Count the trial collisions above the trial bound (``extras["bound_violations"]``).

    Returns
    -------
    tuple
        ``(run, stepper)``: the caller closes the stepper.

    Examples
    --------
    >>> from scipy import constants
    >>> from collisionkit.transport import reid_ramp
    >>> from collisionkit.transport._tables import build_tables
    >>> from collisionkit.transport.swarm import REFERENCE_DENSITY, _field_record
    >>> tables = build_tables(reid_ramp(), constants.m_e, 0.0)
    >>> record = _field_record(12.0, 0.0, REFERENCE_DENSITY, constants.m_e, -constants.e, np.zeros(3))
    >>> run, stepper = new_run(tables, record, False, 0.0, 4096, 16, 1, constants.m_e, 1.0, "equal", 1, 32,
    ...                        REFERENCE_DENSITY, False)
    >>> run.swarm.size, int(run.final_counts.sum())
    (1024, 4096)
    >>> stepper.close()
    """
    threads = threads or os.cpu_count() or 1
    counts = np.full(groups, particles // groups)
    counts[: particles % groups] += 1
    copies = max(1, min(TRANSIENT_SHARE, particles // groups // TRANSIENT_PER_GROUP))
    swarm = initial_swarm(groups * max(1, particles // groups // copies), groups, seed, mass, initial_energy)
    rng = np.random.default_rng(np.random.SeedSequence(seed).spawn(groups + 1)[-1])
    stepper = Stepper(tables, field_record, mass, density, SHARING_CODES[sharing], threads, check_bound)
    target = max(1, swarm.size // groups)
    if oscillating:
        run = PeriodicRun(stepper, swarm, groups, target, rng, tables, density, omega=reduced_frequency * density,
                          phases=phases)
    else:
        run = TensorRun(stepper, swarm, groups, target, rng, tables, density)
    run.final_counts = counts if copies > 1 else None
    return run, stepper


def run_to_steady_state(run, stepper, collisions_per_sample, tolerances, collision_budget, max_seconds, min_samples,
                        energy_bins, progress, conditions) -> SwarmResult:
    """Calibrate the sample interval (or restore a saved run: :func:`resumable_point`), run until the tolerances are
    met (or a limit is reached), close the stepper.

    Parameters
    ----------
    run, stepper
        From :func:`new_run`.
    collisions_per_sample, tolerances, collision_budget, max_seconds, min_samples, energy_bins, progress
        :func:`~collisionkit.transport.simulate_swarm`'s arguments, checked (``tolerances`` those the run can meet).
    conditions : tuple
        ``(reduced_field, reduced_magnetic_field, gas_temperature, particles)``, recorded in the result.

    Returns
    -------
    SwarmResult

    Examples
    --------
    >>> import math
    >>> from scipy import constants
    >>> from collisionkit.transport import maxwell_model
    >>> from collisionkit.transport._tables import build_tables
    >>> from collisionkit.transport.swarm import REFERENCE_DENSITY, _field_record
    >>> tables = build_tables(maxwell_model(1e-13, mass=10 * constants.m_e), constants.m_e, 0.0)
    >>> record = _field_record(10.0, 0.0, REFERENCE_DENSITY, constants.m_e, -constants.e, np.zeros(3))
    >>> run, stepper = new_run(tables, record, False, 0.0, 256, 8, 1, constants.m_e, 1.0, "equal", 1, 32,
    ...                        REFERENCE_DENSITY, False)
    >>> result = run_to_steady_state(run, stepper, 20.0, {"mean_energy": 0.05}, 2e6, math.inf, 4, 10, None,
    ...                              (10.0, 0.0, 0.0, 256))
    >>> result.reduced_field, result.particles
    (10.0, 256)
    """
    hooks = _POINT_HOOKS.get() or PointHooks(None, None)
    try:
        if hooks.saved is None:
            run.calibrate(collisions_per_sample)
        else:
            restore_run(run, *hooks.saved)
        return run.until_converged(tolerances, collision_budget, max_seconds, min_samples, energy_bins, progress,
                                   conditions, hooks.on_chunk)
    finally:
        stepper.close()


def with_field_settings(result: SwarmResult, field_angle, reduced_frequency, waveform) -> SwarmResult:
    """``result`` with the run's field angle, omega/N and waveform (in ``extras``, if any) recorded.

    Parameters
    ----------
    result : SwarmResult
        The run's result (changed in place).
    field_angle, reduced_frequency, waveform
        :func:`~collisionkit.transport.simulate_swarm`'s arguments.

    Returns
    -------
    SwarmResult
        ``result``.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> result = with_field_settings(SimpleNamespace(extras={}), 30, 0, [(0, 1), (1, -1)])
    >>> result.field_angle, result.reduced_frequency, result.extras["waveform"]
    (30.0, 0.0, [[0.0, 1.0], [1.0, -1.0]])
    """
    result.field_angle = float(field_angle)
    result.reduced_frequency = float(reduced_frequency)
    if waveform is not None:
        result.extras["waveform"] = np.asarray(waveform, dtype=float).tolist()
    return result
