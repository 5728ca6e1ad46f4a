"""Compiling the numba kernels in the open: a notice on a cold cache, and speeds that leave compilation out.

numba compiles a kernel at its first call and keeps the machine code in its
on-disk cache. A cold first run would sit at 0 % for tens of seconds with no
word, and a speed timed over a first call measures the compiler. So before
the work, a command checks numba's cache index of its main kernels
(:func:`kernels_cached`); if one is missing or stale it says "compiling
kernels (first run only)" and compiles them on a tiny run under its own
spinner (:func:`warm_up`). The ``edmd`` command and the demo always make
that tiny run (a fraction of a second from a warm cache), so that their
collisions per second time the events alone: the measurement times each
block with the g(r) kernel in it, whose first call would otherwise count.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable

from ._messages import error_console, note

NOTICE = "compiling kernels (first run only)"


def _main_kernels(domain: str) -> list:
    """The numba dispatchers whose cache says whether a domain's kernels are compiled."""
    if domain == "edmd":
        from .._kernels.edmd import crossings, loop, measurement

        return [loop.run_events, crossings.run_crossing_events, measurement.pair_distance_counts]
    if domain == "swarm":
        from .._kernels.transport import advance

        return [advance.PARTICLE_LOOPS[advance.STATIC]]
    if domain == "slab":
        from .._kernels.transport import slab

        return [slab.slab_batch]
    if domain == "encounter":
        from .._kernels import encounters

        return [encounters.perifocal_states]
    if domain == "core":
        from .._kernels import collisions

        return [collisions.resolve_contacts]
    if domain == "track":
        from .._kernels.transport.tracking import track

        return [track.track_particles]
    raise ValueError(f"no kernels known for {domain!r}")


def kernels_cached(dispatchers: Iterable) -> bool:
    """True if numba's on-disk cache holds machine code of every dispatcher for today's kernel sources.

    A plain function (``NUMBA_DISABLE_JIT``) needs no compiling; a kernel
    without a cache (caching unavailable) compiles at every start.

    Examples
    --------
    >>> kernels_cached([len])  # not a numba kernel: nothing to compile
    True
    """
    for dispatcher in dispatchers:
        if not hasattr(dispatcher, "py_func"):
            continue
        cache_file = getattr(getattr(dispatcher, "_cache", None), "_cache_file", None)
        if cache_file is None:
            return False
        try:
            if not cache_file._load_index():  # empty when missing, of another numba, or stamped by older sources
                return False
        except Exception:  # an unreadable index is recompiled by numba: as good as missing
            return False
    return True


def cold(domains: Iterable[str]) -> bool:
    """True if a kernel of the named domains (``edmd``, ``swarm``, ``slab``, ``encounter``, ``core``, ``track``) must
    compile.

    Examples
    --------
    >>> cold([]) is False
    True
    """
    return not all(kernels_cached(_main_kernels(domain)) for domain in domains)


def _tiny_edmd() -> None:
    """Every kernel of an EDMD run and its measurement, on 108 spheres, without running an event (both engines)."""
    import numpy as np

    from ..edmd import HardSphereSystem, Sampler, lattice, maxwell_boltzmann
    from ..edmd._pair_distribution import pair_histogram

    positions, box = lattice("fcc", 3, 0.3)
    system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(len(positions)), 3, seed=0), 0.5, box)
    system.compile_event_loop()  # the event loop (and the lists and predictions, built above)
    sampler = Sampler(system, collisions=2, blocks=2)
    pair_histogram(system, sampler.r_max, 10)  # g(r): timed in every measurement block
    system.positions(unwrapped=True)
    dilute = HardSphereSystem(positions * 2.0, maxwell_boltzmann(np.ones(len(positions)), 3, seed=0), 0.5, box * 2.0,
                              engine="cells")
    dilute.compile_event_loop()  # the cell-crossing engine, taken by dilute runs


def _tiny_swarm() -> None:
    from ..transport import model_gas, simulate_swarm

    simulate_swarm(model_gas("maxwell"), 10.0, particles=128, seed=0, tolerances={"mean_energy": 0.5},
                   collision_budget=1e4)


def _tiny_slab() -> None:
    from ..transport import simulate_slab

    simulate_slab(1.0, particles=64, seed=0)


def _tiny_encounter() -> None:
    import numpy as np

    from ..encounters import starcrash_initial_conditions

    starcrash_initial_conditions(1.0, 1.0, rp=1.0, v_inf=0.5, sep0=10.0).orbit.state_at_time(np.zeros(2))


def _tiny_core() -> None:
    import numpy as np

    from .. import resolve_contact

    resolve_contact(np.ones(2), np.ones((2, 3)), np.ones(2), -np.ones((2, 3)), np.ones((2, 3)))


def _tiny_track() -> None:
    from ..transport import model_gas
    from ..transport.tracking import Device, track

    device = Device.parallel_plate(model_gas("maxwell"), 1e-5, 1.0, density=1e23)
    track(device, primaries=2, position=(0.0, 0.0, 5e-6), seed=0, threads=1, signal_window=1e-9)


TINY_RUNS: dict[str, Callable[[], None]] = {
    "edmd": _tiny_edmd, "swarm": _tiny_swarm, "slab": _tiny_slab, "encounter": _tiny_encounter, "core": _tiny_core,
    "track": _tiny_track,
}


def warm_up(domains: Iterable[str], always: Iterable[str] = ()) -> bool:
    """Compile the kernels of ``domains`` on tiny runs if their cache is cold, saying so; True if it was cold.

    ``always`` names domains whose tiny run is made even from a warm cache
    (it loads the kernels, so a timed run after it times no loading).

    Examples
    --------
    >>> compiled_here = warm_up(["slab"])  # compiled here, with a notice, only on a cold cache
    >>> cold(["slab"])
    False
    """
    domains, always = list(domains), set(always)
    compiling = cold(domains)
    runs = [domain for domain in domains if compiling or domain in always]
    if not runs:
        return False
    start = time.perf_counter()
    if compiling:
        note(f"{NOTICE}: numba turns them into machine code once and caches it; this takes one to a few minutes")
    with error_console.status(NOTICE if compiling else "loading kernels", spinner="dots"):
        for domain in runs:
            TINY_RUNS[domain]()
    if compiling:
        note(f"kernels compiled in {time.perf_counter() - start:.0f} s")
    return compiling
