"""Advancing a :class:`~collisionkit.edmd.HardSphereSystem` in time: runs in chunks, and the clock's restart.

:meth:`~collisionkit.edmd.HardSphereSystem.run` checks what it is asked
(:func:`run_request`) and advances in chunks (:func:`advance`): between two
chunks the particles are re-sorted in memory, moved to the current time
(:func:`restart_clock`), the shear thermostat applied when due, full list
rows and cells grown, and the lists of a compression rebuilt when the radii
outgrow them. :func:`run_until` is the same loop without the checks and the
chunks, for the stretches of a transport measurement. Each event stretch
runs through the system's ``_run_events`` (:mod:`._system_events`).
"""

from __future__ import annotations

import contextlib
import math

import numpy as np

from .._kernels import edmd as _k
from .._kernels.edmd.crossings import PENDING_TIME
from . import _checks
from ._shear import THERMOSTAT_INTERVAL

# re-sort particles in memory by cell after this many collisions per particle
SORT_INTERVAL = 20


def run_request(system, collisions, time, chunk):
    """The checked request of a run: (collisions to make, time to advance, collisions per chunk).

    No limit on collisions is the largest int64, none on time is inf; the
    default chunk is max(N, 10^5) collisions.

    Examples
    --------
    >>> from collisionkit.edmd import HardSphereSystem
    >>> system = HardSphereSystem([[1.0, 1.0], [1.0, 5.0]], [[1.0, 0.0], [1.0, 0.0]], 0.5, 10.0)
    >>> run_request(system, 500, None, None)
    (500, inf, 100000)
    """
    if collisions is None and time is None:
        raise ValueError("give collisions or time (or both)")
    target = np.iinfo(np.int64).max if collisions is None else _checks.integer_at_least(collisions, "collisions", 0)
    duration = math.inf if time is None else _checks.bounded(time, "time", 0.0)
    chunk = max(system.count, 100_000) if chunk is None else _checks.integer_at_least(chunk, "chunk", 1)
    return target, duration, chunk


def advance(system, collisions=None, time=None, progress=None, chunk=None) -> int:
    """The work of :meth:`~collisionkit.edmd.HardSphereSystem.run` (its parameters): the pair collisions made.

    Each chunk runs the events up to its share of the collisions and the
    time left (or until the lists of a compression expire), then reports
    progress, synchronises, applies the thermostat when due and grows full
    rows (the chunk is then done again) or rebuilds expired lists; a chunk
    that made fewer collisions than asked ends the run.
    """
    target, duration, chunk = run_request(system, collisions, time, chunk)
    done, remaining = 0, duration
    while done < target and remaining > 0:
        step = _chunk_size(system, chunk, target - done)
        if system.collisions - system.last_sort >= SORT_INTERVAL * system.count:
            system._sort_by_cell()
        before, start = system.collisions, system.time
        # while growing, the lists hold only up to the radius scale they were built for
        lists_expire = system._lists_expire_in()
        span = max(min(remaining, lists_expire), 0.0)
        system.time = system._run_events(step, start + span)
        lists_expired = lists_expire < remaining and system.time == start + span
        advanced = system.collisions - before
        done += advanced
        remaining -= system.time - start
        if progress is not None:
            shares = ([done / collisions] if collisions else []) + ([1.0 - remaining / duration] if time else [])
            progress(min(max(shares), 1.0))
        system.synchronise()
        _thermostat_if_due(system, advanced)
        if system._grow_overflowed_storage():
            continue
        if lists_expired:
            system._refresh_lists()
        elif advanced < step:  # stopped by the time limit, or nothing left to happen
            break
    return done


def _chunk_size(system, chunk, left):
    """The collisions of the next chunk: ``chunk``, no more than are ``left``, ending at the thermostat's next turn."""
    step = min(chunk, left)
    if system.thermostat is not None:  # the peculiar velocities are rescaled on a grid of the collision count
        step = min(step, system._thermostat_due_in())
    return step


def _thermostat_if_due(system, advanced):
    """Rescale the peculiar velocities if the chunk just run (``advanced`` collisions) ended on the thermostat's grid."""
    if system.thermostat is not None and advanced > 0 and \
            system._thermostat_due_in() == THERMOSTAT_INTERVAL * system.count:
        system._apply_thermostat()


def run_until(system, collisions, elapsed):
    """Process events until ``collisions`` more pair collisions or the total time ``elapsed``: the collisions made.

    The core of :meth:`~collisionkit.edmd.HardSphereSystem.run` without
    its checks, progress and synchronisation (see the system's
    ``_run_until``). Re-sorts and grows overflowed rows as a run does.
    """
    if system.collisions - system.last_sort >= SORT_INTERVAL * system.count:
        system._sort_by_cell()
    start = system.collisions
    while True:
        left = collisions - (system.collisions - start)
        system.time = system._run_events(left, max(elapsed - system.elapsed, system.time))
        if not system._grow_overflowed_storage():
            return system.collisions - start


def restart_clock(system):
    """Move every particle to the current time and restart the clock at 0 (the work of ``synchronise``).

    Every stored absolute time (the particles', the event queue's, the
    cell-crossing engine's, the radius scale's origin, the shear frame's)
    moves back by the same shift, which is added to ``elapsed``.
    """
    _k.synchronise(system.p, system.time, system.geom, system.dim)
    shift = system.time
    if shift != 0.0:
        system.p[:, _k.T] -= shift
        system.queue -= shift
        system.tree[:, 0] -= shift
        system.pending[:, PENDING_TIME] -= shift  # the cell-crossing engine's absolute times too
        system.params[_k.P_SCALE0] += system.growth * shift
        system._restart_well_clock(shift)
        system._shear_clock(shift)
        system.elapsed += shift
        system.time = 0.0


@contextlib.contextmanager
def elastic_contacts(system, elastic: bool = True):
    """Within the block every contact of ``system`` is elastic and smooth (if ``elastic``): its elastic floor is
    raised to infinity, below which pairs and walls bounce elastically without a tangential impulse, and restored
    after (an error included).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
    >>> positions, box = lattice("square", 10, 0.3)
    >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box, restitution=0.5)
    >>> with elastic_contacts(system):
    ...     _ = system.run(collisions=1000)
    >>> system.energy_lost, system.elastic_below > 0
    (0.0, True)
    """
    floor = system.params[_k.P_ELASTIC_BELOW]
    if elastic:
        system.params[_k.P_ELASTIC_BELOW] = math.inf
    try:
        yield system
    finally:
        system.params[_k.P_ELASTIC_BELOW] = floor
