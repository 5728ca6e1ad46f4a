"""The memory a run needs, estimated from its size before any work, against what the machine has.

The figures per particle were measured, not derived: each run (set-up, a
few measurement blocks or the swarm's sampling) went in a fresh process
after a warm-up run, with ``tracemalloc`` recording the peak of the numpy
allocations (the kernels allocate nothing) and ``getrusage`` the growth of
the peak resident set; the figures are the resident ones, rounded up, at
N = 32 000 to 400 000 where they no longer depend on N (numba 0.68,
numpy 2, Linux x86-64, this version of collisionkit: re-measure after a
change to the engines' storage).
"""

from __future__ import annotations

import os
from pathlib import Path

from ._messages import fail

# EDMD from a random start: the Lubachevsky-Stillinger compression's cells are sized from the grid they hold
# and are at most 2 a particle, so the need no longer grows as the packing fraction falls. Resident bytes per
# particle, a fresh process per run after a warm-up run, with a checkpoint and 10 blocks (N = 160 000):
# 3D eta 0.02: 2.32 kB, 0.1: 2.08 kB, 0.3: 1.88 kB, 0.5: 1.90 kB; 2D eta 0.1: 2.22 kB, 0.3: 1.82 kB
# (before the cells were fixed: 109 kB at 3D eta 0.02, 9.5 kB at 0.3)
EDMD_RANDOM_BYTES_PER_PARTICLE = 2_300
# EDMD from a lattice: 703 B a particle resident at N = 108 000 and 256 000 (686 B traced), 1.56 kB with a
# checkpoint, whose arrays are a second copy of the state while it is written
EDMD_LATTICE_BYTES_PER_PARTICLE = 1_600
# EDMD on the cell-crossing engine (dilute straight flights): up to 16 cells a sphere, 4 member slots each, instead
# of neighbour lists. tracemalloc's peak of a run with a checkpoint and 10 blocks, after a warm-up run (N = 157 216
# fcc and 160 000 random, eta 0.02, the grid at its cap): 2.58 kB a particle from either start (the lists from the
# fcc start: 1.51 kB); eta 0.1 from a random start 1.77 kB; discs at eta 0.02 1.36 kB
EDMD_CELLS_BYTES_PER_PARTICLE = 2_800
# the measurement's record of the speeds, per particle and block: 3.8 kB a particle with 200 blocks against
# 0.7 kB with 10 (N = 108 000, fcc): 16.4 B per particle and block
EDMD_BYTES_PER_PARTICLE_AND_BLOCK = 17
# square wells: longer lists and the record of pairs inside, as wide as them: 360 B a particle at n sigma^3 = 0.05,
# 216 at 0.5, 224 at 0.9 (lambda 1.5, N = 32000; hard spheres' lists: 64 B), twice while a checkpoint is written
EDMD_WELL_BYTES_PER_PARTICLE = 720
# a swarm: 189 B an electron resident (178 B traced) at 100 000 and 400 000 electrons of the Maxwell model
SWARM_BYTES_PER_PARTICLE = 200
# a swarm in a gas that ionizes or attaches (its population controlled): 6.6 kB an electron resident at 100 000
# and 400 000 electrons of the Lucas-Saelee gas at 500 Td; 3.5 kB at 100 Td, 12.3 kB at 2000 Td
SWARM_IONIZING_BYTES_PER_PARTICLE = 6_700
# with --checkpoint: the running point's saved state (a copy of the particles) and the file's bytes while it is
# written: 205 B an electron more at the peak (tracemalloc, 20 000 electrons of the Maxwell model, 3e7 collisions)
SWARM_CHECKPOINT_BYTES_PER_PARTICLE = 220
MEMINFO = Path("/proc/meminfo")


def available_memory() -> int | None:
    """Bytes of memory this machine can give a new run now (``MemAvailable``), or None if unknown.

    Linux's ``/proc/meminfo`` counts the free memory and what the page cache
    can give back; elsewhere the free physical pages (``os.sysconf``).

    Examples
    --------
    >>> available = available_memory()
    >>> available is None or available > 0
    True
    """
    try:
        for line in MEMINFO.read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def edmd_memory(parameters, lattice: bool = False) -> int:
    """Bytes an EDMD run (:class:`~collisionkit.edmd.EdmdParameters`) needs at its peak (measured figures).

    ``lattice`` asks for the same run from a lattice start.

    Examples
    --------
    >>> from collisionkit.edmd import EdmdParameters
    >>> edmd_memory(EdmdParameters(particles=100_000_000)) / 1e9   # the issue's 1e8 spheres at eta = 0.3
    247.0
    >>> round(edmd_memory(EdmdParameters(particles=1_000_188, initial="fcc")) / 1e9, 2)
    1.77
    >>> round(edmd_memory(EdmdParameters(particles=1_000_188, initial="fcc", well_width=1.5)) / 1e9, 2)
    2.49
    """
    per_particle = EDMD_LATTICE_BYTES_PER_PARTICLE
    if parameters.initial == "random" and not lattice:
        per_particle = max(per_particle, EDMD_RANDOM_BYTES_PER_PARTICLE)
    if _may_run_cells(parameters):
        per_particle = max(per_particle, EDMD_CELLS_BYTES_PER_PARTICLE)
    if getattr(parameters, "well_width", None) is not None:
        per_particle += EDMD_WELL_BYTES_PER_PARTICLE
    return round(parameters.particles * (per_particle + EDMD_BYTES_PER_PARTICLE_AND_BLOCK * parameters.blocks))


def _may_run_cells(parameters) -> bool:
    """Whether the run may take the cell-crossing engine (asked for, or auto below its packing fraction, unsheared)."""
    if parameters.engine == "cells":
        return True
    if parameters.engine != "auto" or parameters.shear_rate != 0.0 or getattr(parameters, "well_width", None):
        return False  # (square wells run the lists)
    from ..edmd._cell_crossings import cells_below_packing

    return parameters.packing_fraction < cells_below_packing(parameters.dim, parameters.particles)


def swarm_memory(particles: int, ionizing: bool, checkpoint: bool = False) -> int:
    """Bytes a swarm of ``particles`` electrons needs (measured; more if the gas ionizes or attaches, and with a
    checkpoint, which saves the running point's particles).

    Examples
    --------
    >>> swarm_memory(10_000_000, ionizing=False) / 1e9, swarm_memory(10_000_000, ionizing=True) / 1e9
    (2.0, 67.0)
    >>> swarm_memory(10_000_000, ionizing=False, checkpoint=True) / 1e9
    4.2
    """
    per_particle = SWARM_IONIZING_BYTES_PER_PARTICLE if ionizing else SWARM_BYTES_PER_PARTICLE
    return particles * (per_particle + (SWARM_CHECKPOINT_BYTES_PER_PARTICLE if checkpoint else 0))


def size(count: float) -> str:
    """Bytes in a human unit: ``size(2.5e9) == '2.5 GB'``.

    Examples
    --------
    >>> size(2.5e9), size(812e6), size(4096)
    ('2.5 GB', '812 MB', '4.1 kB')
    """
    for unit, scale in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if count >= scale:
            return f"{count / scale:.3g} {unit}"
    return f"{count:.0f} B"


def refuse_beyond_memory(needed: int, what: str, hint: str = "") -> None:
    """Stop (exit 2) before any work if ``needed`` bytes exceed the machine's available memory.

    Examples
    --------
    >>> refuse_beyond_memory(1000, "--particles 10")  # a few kB: always fine
    """
    available = available_memory()
    if available is None or needed <= available:
        return
    raise fail(f"{what} needs about {size(needed)} of memory, more than the {size(available)} available on "
               f"this machine{hint}")
