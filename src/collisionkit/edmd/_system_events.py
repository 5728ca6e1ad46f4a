"""Running the event loop of a :class:`~collisionkit.edmd.HardSphereSystem`, and runs that cannot go on.

:meth:`~collisionkit.edmd.HardSphereSystem.run` calls the event loop
(:func:`collisionkit._kernels.edmd.run_events`) through
:func:`run_event_loop`, for at most
``EVENTS_PER_CALL`` events at a time, a fraction of a second even at
N = 10^6, so Ctrl-C lands between two calls. The loop gives up after
:func:`stall_limit` events in a row at one instant (counted across calls):
a collapse, infinitely many events in finite time, whose clock has stopped
in floating point and that would never end. A run asked for pair
collisions alone gives up when no pair collision came in ``QUIET_EVENTS``
events and in ``QUIET_FREE_TIMES`` mean free times of kinetic theory (list
rebuilds and wall bounces go on for ever when no pair can meet; the second
condition spares a dilute gas, whose collisions are rare among its
events). Each becomes a RuntimeError naming the likely cause and the way
out. A run of a system that can lose energy warns (RuntimeWarning) of
:func:`collapse_warning_limit` or more events in a row at one instant that
did end (round-off ended a collapse). Both limits grow with N: a symmetric
start (a lattice whose particles move in step) makes up to about N events
at one instant that are physics, not a collapse.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from .._kernels import edmd as _k
from .._kernels.edmd.crossings import CROSSING_BASE
from ._cell_crossings import ENGINE_CELLS, run_crossing_kernel

# events per call of the event loop: well under a second even at N = 10^6, so that Ctrl-C is answered at once
EVENTS_PER_CALL = 1 << 17
# events in a row at one instant that make a run warn of a collapse that round-off ended (an inelastic
# cluster's cascade with the default elastic_below takes up to about a thousand), at least 2 per particle
COLLAPSE_WARNING_EVENTS = 1 << 12
# events in a row at one instant that stop a run (a collapse whose clock has stopped), at least 8 per particle
STALL_EVENTS_PER_PARTICLE = 8


def stall_limit(count: int) -> int:
    """Events in a row at one instant that stop a run of ``count`` particles: max(2^16, 8 N).

    Examples
    --------
    >>> stall_limit(100), stall_limit(10**6)
    (65536, 8000000)
    """
    return max(_k.STALLED_EVENTS, STALL_EVENTS_PER_PARTICLE * count)


def collapse_warning_limit(count: int) -> int:
    """Events in a row at one instant (that ended) that make a run of ``count`` particles warn: max(2^12, 2 N).

    Examples
    --------
    >>> collapse_warning_limit(100), collapse_warning_limit(10**5)
    (4096, 200000)
    """
    return max(COLLAPSE_WARNING_EVENTS, 2 * count)


def loses_energy(system) -> bool:
    """True if a contact or a wall bounce of ``system`` can lose energy (a collapse is possible).

    Examples
    --------
    >>> from collisionkit.edmd import HardSphereSystem
    >>> system = HardSphereSystem([[1.0, 1.0], [1.0, 5.0]], [[1.0, 0.0], [1.0, 0.0]], 0.5, 10.0)
    >>> loses_energy(system)
    False
    """
    return bool(np.any(system.restitution < 1.0) or system.restitution_law != "constant"
                or system.params[_k.P_WALL_RESTITUTION] < 1.0)
# a run asked for collisions gives up after this many events without one (about a second of a small
# system's events) if they also lasted QUIET_FREE_TIMES mean free times (N / 2 collisions expected in each)
QUIET_EVENTS = 1 << 22
QUIET_FREE_TIMES = 100.0


def stall_message(system, target):
    """Why the event loop stopped at one instant, from the ``target`` of its last event, and what to change.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
    >>> positions, box = lattice("square", 4, 0.3)
    >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(16), 2, seed=1), 0.5, box, restitution=0.5,
    ...                           elastic_below=0.0)
    >>> stall_message(system, 3).split(":")[0]
    'inelastic collapse'
    """
    when = f"{stall_limit(system.count)} events in a row at time {system.elapsed + system.time:.17g}"
    if target <= _k.WELL_TARGET_BASE and system.well_width is not None:  # the codes below the walls' of the lists
        return f"the event loop stalled: {when}, at the edge of a square well (a bug: please report it)"
    if target <= CROSSING_BASE:
        return f"the event loop stalled: {when}, cell crossings (no particle moves)"
    if target < _k.LIST_TARGET:  # a wall
        return (f"wall collapse: {when}, bounces off a wall: a particle under gravity bounces ever lower on an "
                "inelastic wall (or rests on it), infinitely many bounces in finite time "
                f"(wall_restitution {system.params[_k.P_WALL_RESTITUTION]:g}, elastic_below "
                f"{system.elastic_below:g}); raise elastic_below (bounces and contacts slower than it are "
                "elastic; the default is 1e-6 of sqrt(<v^2> + |g| L)), or give wall_restitution 1")
    if target == _k.LIST_TARGET:
        return f"the event loop stalled: {when}, neighbour-list rebuilds (no particle moves)"
    if system.growth > 0:
        return (f"the compression jammed: {when}, pair collisions, at packing fraction "
                f"{system.packing_fraction:.4f}; aim at a lower packing fraction or compress more slowly")
    if np.any(system.restitution < 1.0) or system.restitution_law != "constant":
        return (f"inelastic collapse: {when}, pair collisions: with restitution < 1 a cluster of particles "
                f"collides infinitely often in finite time (elastic_below {system.elastic_below:g}); raise "
                "elastic_below (contacts slower than it are elastic; the default is 1e-6 of the rms speed) "
                "or the restitution")
    return (f"the event loop stalled: {when}, pair collisions: particles locked in contact collide infinitely "
            "often in finite time (e.g. pressed together by gravity)")


def collapse_warning(system, events):
    """The warning of a collapse that round-off ended: ``events`` events in a row at one instant.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
    >>> positions, box = lattice("square", 4, 0.3)
    >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(16), 2, seed=1), 0.5, box, restitution=0.5,
    ...                           elastic_below=0.0)
    >>> collapse_warning(system, 5000).split(":")[0]
    'inelastic collapse'
    """
    return (f"inelastic collapse: {events} events in a row at one instant (up to time "
            f"{system.elapsed + system.time:.6g}): a cluster of particles collided many times in vanishing time and "
            "only round-off ended it, so the run is not physical there; raise elastic_below (contacts slower than "
            f"it are elastic; now {system.elastic_below:g}) or the restitution")


def no_collision_message(system, events, duration):
    """Why a run asked for pair collisions made none in ``events`` events and ``duration`` of simulated time.

    Examples
    --------
    >>> from collisionkit.edmd import HardSphereSystem
    >>> system = HardSphereSystem([[1.0, 1.0], [1.0, 5.0]], [[1.0, 0.0], [1.0, 0.0]], 0.5, 10.0)
    >>> no_collision_message(system, 10**7, 1e6).split(":")[0]
    'no pair collision in 10000000 events and 1e+06 time units (100 mean free times of kinetic theory or more)'
    """
    head = (f"no pair collision in {events} events and {duration:.3g} time units ({QUIET_FREE_TIMES:g} mean free "
            "times of kinetic theory or more): ")
    if np.any(system.restitution < 1.0) and system.elastic_below == 0.0:
        return (f"{head}the inelastic gas has cooled almost to rest (kT now {system.temperature():.3g}; restitution "
                "< 1 with elastic_below 0 loses energy at every contact, Haff's law, until round-off); raise "
                "elastic_below (contacts slower than it are elastic) or the restitution")
    return (f"{head}no pair can collide, it seems (e.g. particles on parallel paths, or apart for good in a walled "
            "box); run(time=...) advances such a system by a stretch of time")


def mean_free_time(system):
    """The mean free time of kinetic theory for the system's density, smallest diameter and rms speed (inf at rest).

    A dilute gas's, longer than a dense one's (no Enskog factor), so a
    generous yardstick for "no collision in a long time".

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.edmd import HardSphereSystem
    >>> system = HardSphereSystem([[1.0, 1.0], [1.0, 5.0]], [[1.0, 0.0], [1.0, 0.0]], 0.5, 10.0)
    >>> round(mean_free_time(system), 3)  # 2D: 1 / (2 sqrt(2) n sigma v), n = 2 / 100
    17.678
    """
    diameter = 2.0 * float(np.min(system.radius)) * system.scale
    density = system.count / system.volume
    speed = math.sqrt(float(np.mean(np.sum(system.p[:, _k.V : _k.V + system.dim] ** 2, axis=1))))
    cross_section = math.sqrt(2.0) * (math.pi * diameter**2 if system.dim == 3 else 2.0 * diameter)
    return math.inf if speed == 0.0 else 1.0 / (cross_section * density * speed)


def no_pair_can_collide(system, events, duration):
    """True when ``events`` events and ``duration`` of simulated time without a pair collision are enough to give up.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.edmd import HardSphereSystem
    >>> system = HardSphereSystem([[1.0, 1.0], [1.0, 5.0]], [[1.0, 0.0], [1.0, 0.0]], 0.5, 10.0)
    >>> no_pair_can_collide(system, QUIET_EVENTS, 1e6), no_pair_can_collide(system, QUIET_EVENTS, 100.0)
    (True, False)
    """
    return events >= QUIET_EVENTS and duration >= QUIET_FREE_TIMES * mean_free_time(system)


def run_event_loop(system, collisions, t_stop):
    """Process the system's events until ``collisions`` pair collisions or time ``t_stop``; return the time reached.

    The kernel runs in calls of at most ``EVENTS_PER_CALL`` events, so
    Ctrl-C lands between two of them. Raises RuntimeError when the loop
    stalls (a collapse) and, without a time limit, when no pair collision
    comes for long (:func:`no_pair_can_collide`); warns of a collapse that
    round-off ended.

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
    >>> positions, box = lattice("square", 10, 0.3)
    >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
    >>> system.time = run_event_loop(system, 500, math.inf)
    >>> system.collisions
    500
    """
    left, quiet, quiet_since = collisions, 0, system.time
    while True:
        made, events = system.collisions, system.acc[_k.ACC_EVENTS]
        # captures and escapes are progress (a pair bound in its well need never collide); bounces alone are not
        edges = system.acc[_k.ACC_CAPTURES] + system.acc[_k.ACC_ESCAPES]
        if system._engine_code == ENGINE_CELLS:
            system.time, system._still, longest, stop, target = run_crossing_kernel(
                system, system.time, system._still, left, EVENTS_PER_CALL, t_stop, stall_limit(system.count))
        else:
            system.time, system._still, longest, stop, target = _k.run_events(
                system.time, system._still, left, EVENTS_PER_CALL, t_stop, stall_limit(system.count), system.p,
                system.book, system.anchor_time, system._image, system.cell_of, system.neighbours,
                system.neighbour_count, system.cell_members, system.cell_count, system.cell_points, system.ncell,
                system.geom, system.dim, system.restitution, system.params, system.queue, system.tree,
                system.leaves, system.acc, system.spin, *system._well_record(),
            )
        made = system.collisions - made
        # the partner of the collision the call ended at (a snapshot then leaves that pair out: _pair_distribution)
        system._last_partner = int(target) if stop == _k.STOP_COLLISIONS and made > 0 and target >= 0 else -1
        if stop == _k.STOP_STALLED:
            raise RuntimeError(stall_message(system, target))
        if longest >= collapse_warning_limit(system.count) and system._still < longest and loses_energy(system):
            warnings.warn(collapse_warning(system, longest), RuntimeWarning, stacklevel=4)
        if stop != _k.STOP_EVENTS:
            return system.time
        left -= made
        if made or system.acc[_k.ACC_CAPTURES] + system.acc[_k.ACC_ESCAPES] != edges:
            quiet, quiet_since = 0, system.time
        else:
            quiet += int(system.acc[_k.ACC_EVENTS] - events)
        if t_stop == math.inf and no_pair_can_collide(system, quiet, system.time - quiet_since):
            raise RuntimeError(no_collision_message(system, quiet, system.time - quiet_since))
