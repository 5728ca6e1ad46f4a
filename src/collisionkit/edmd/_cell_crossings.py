"""The cell-crossing engine of a :class:`~collisionkit.edmd.HardSphereSystem`: when it is chosen, its cells.

Dilute systems spend the neighbour-list engine's time on list rebuilds (a
list expires after a fraction of a free path); the cell-crossing engine
(:mod:`collisionkit._kernels.edmd.crossings`) has no lists: cells as wide
as the largest contact distance, a particle's collisions searched in its
own and the adjacent cells, and a cell crossing an event that searches only
the cells it brings in. ``engine="auto"`` takes it for straight flights of
fixed radii (no gravity, compression or shear) below a packing fraction
measured where the two engines are level.
"""

from __future__ import annotations

import math

import numpy as np

from .._kernels import edmd as _k
from .._kernels.edmd import cell_search as _cell_search
from .._kernels.edmd import crossings as _crossings

ENGINE_LISTS = 0
ENGINE_CELLS = 1
ENGINE_NAMES = {"lists": ENGINE_LISTS, "cells": ENGINE_CELLS}
# packing fractions below which engine="auto" takes the cell crossings (discs 2, spheres 3) at the numbers of
# particles CELLS_BELOW_PACKING_AT, linear in log N between them and held beyond them (cells_below_packing): where
# the two engines are level, a little on the safe side. The level falls as N grows (the cells' arrays outgrow the
# caches sooner than the lists'). Measured on the 2-core Intel VM, in one process, alternating
# (benchmarks/bench_edmd_engines.py; results/edmd_engines_levels_by_n.md), levels for spheres after the crossing's
# bounded search and branch-free face times: 0.31 at N = 4000, 0.295 at 32000, 0.28 at 108000, 0.237 at 10^6
# (results/edmd_engines_levels_after_crossings.md); for discs 0.587 at 3969, 0.538 at 32041, 0.438 at 108241, 0.30
# at 10^6 (the same file; before these changes 0.54, 0.53, 0.37, 0.29) (on the AMD VM before the gathered search:
# spheres 0.225 and discs 0.33 at 32000)
CELLS_BELOW_PACKING_AT = (4_000, 32_000, 108_000, 1_000_000)
CELLS_BELOW_PACKING = {2: (0.55, 0.50, 0.40, 0.28), 3: (0.30, 0.28, 0.27, 0.22)}
# the most cells a particle, on average (per axis: (CELLS_PER_PARTICLE N)^(1/dim)), discs 2 and spheres 3: below
# this the cells are as narrow as the contact distance, above it wider. Wider cells mean fewer crossings but more pair
# tests a search; measured at N = 4000 against the lists (benchmarks/bench_edmd_engines.py, one cap a process): 3D
# eta = 0.1 1.77x the lists' rate with 16, 1.35x with 2, 1.14x with 1 (eta = 0.03: 1.94, 1.91, 1.72); 2D eta = 0.05
# 0.88x with 16, 1.51x with 4, 1.58x with 1 (eta = 0.15: 1.24x with 16, 1.36x with 2)
CELLS_PER_PARTICLE = {2: 2, 3: 16}
# slots per cell to start with (grown when a cell needs more)
INITIAL_SLOTS = 4


def cells_below_packing(dim, count) -> float:
    """The packing fraction below which ``engine="auto"`` takes the cell crossings for ``count`` particles.

    :data:`CELLS_BELOW_PACKING` at :data:`CELLS_BELOW_PACKING_AT`, linear in
    log N between them and held beyond them.

    Examples
    --------
    >>> cells_below_packing(3, 500), cells_below_packing(3, 32_000), cells_below_packing(3, 10**7)
    (0.3, 0.28, 0.22)
    """
    return float(np.interp(math.log(count), np.log(CELLS_BELOW_PACKING_AT), CELLS_BELOW_PACKING[dim]))


def engine_code(engine, dim, packing_fraction, count, straight_flights, cells_fit=True) -> int:
    """The engine a new system of ``count`` particles runs: ``engine`` ("auto", "lists" or "cells") resolved.

    ``straight_flights``: no gravity, compression or shear (the cell
    engine's only kind). "cells" for another kind is a ValueError.
    ``cells_fit``: the box holds 3 cells a periodic axis (else "auto" takes
    the lists; "cells" fails when its grid is made, naming the axis).
    The threshold is :func:`cells_below_packing`'s; a packing fraction
    within round-off of it counts as at it
    (a lattice's packing fraction can come out an ulp below the one asked
    for): "auto" takes the lists there.
    """
    if engine == "auto":
        dilute = packing_fraction < cells_below_packing(dim, count) * (1.0 - 1e-9)
        return ENGINE_CELLS if straight_flights and dilute and cells_fit else ENGINE_LISTS
    if engine not in ENGINE_NAMES:
        raise ValueError(f"engine must be 'auto', 'lists' or 'cells'; got {engine!r}")
    if engine == "cells" and not straight_flights:
        raise ValueError("engine='cells' runs straight flights of fixed radii only: no gravity, compression or "
                         "shear (use 'lists' or 'auto')")
    return ENGINE_NAMES[engine]


def cells_fit(box, dim, periodic, largest_contact) -> bool:
    """Whether every periodic axis holds 3 cells no narrower than ``largest_contact`` (:func:`crossing_grid`)."""
    return all(math.floor(box[k] / largest_contact * (1 - 1e-12)) >= 3 for k in range(dim) if periodic[k])


def crossing_grid(box, dim, periodic, largest_contact, count):
    """Cells per axis and their widths: no narrower than ``largest_contact``, at most about CELLS_PER_PARTICLE a particle.

    A periodic axis needs at least 3 cells (each neighbouring cell seen
    through one image); the list engine asks the same of the box.
    """
    ncell = np.ones(3, dtype=np.int64)
    widths = np.ones(3)
    most = max(3, int((CELLS_PER_PARTICLE[dim] * count) ** (1.0 / dim)))
    for k in range(dim):
        ncell[k] = min(max(int(math.floor(box[k] / largest_contact * (1 - 1e-12))), 1), most)
        if periodic[k] and ncell[k] < 3:
            raise ValueError(f"box[{k}] = {box[k]:.6g} is too small: a periodic axis needs at least 3 times the "
                             f"largest diameter ({largest_contact:.6g})")
        widths[k] = box[k] / ncell[k]
    return ncell, widths


class CellCrossings:
    """The cell-crossing engine's upkeep in :class:`~collisionkit.edmd.HardSphereSystem` (a mixin).

    Owns ``pending`` (each particle's best collision found so far) and,
    when the engine runs, the cells (``cell_of``, ``ncell``,
    ``cell_members``, ``cell_count``, the widths in ``geom``), and the cell
    searches' scratch and step table (not state: made when first needed).
    """

    _search_members = None  # the members of the cells around one (:func:`_search_scratch`)
    _search_steps = None  # the search order as cell-number differences (:func:`_steps`)
    _search_grid = None  # (dim, *ncell) the step table was made for

    @property
    def engine(self) -> str:
        """The event engine: "lists" (neighbour lists) or "cells" (cell crossings, for dilute systems)."""
        return "cells" if self._engine_code == ENGINE_CELLS else "lists"

    def _refresh_crossings(self, cells_only=False):
        """Wrap every particle into the box, put it in its cell and (unless ``cells_only``) predict every event."""
        self.synchronise()
        # the shell lists would have (reported, and kept valid for a checkpoint), though no list is built
        self.params[_k.P_SHELL] = self._list_geometry(self.scale0)[0]
        self.params[_k.P_LIST_SCALE] = self.scale0
        _crossings.wrap_all(self.p, self.geom, self.dim, self._image, self.book, self.acc, self.params)
        largest = 2.0 * float(np.max(self.p[:, _k.R])) * self.scale0
        ncell, widths = crossing_grid(self.box, self.dim, self.periodic, largest, self.count)
        if not np.array_equal(ncell, getattr(self, "ncell", None)):
            self.ncell = ncell
            self._grow_cells(INITIAL_SLOTS)
        self.geom[_k.G_CELL] = widths
        while (needed := _crossings.bin_into_cells(self.p, self.cell_of, self.cell_members, self.cell_count,
                                                   self.ncell, self.geom, self.dim)) > 0:
            self._grow_cells(needed)
        if not cells_only:
            self._predict_all_crossings()

    def _predict_all_crossings(self):
        _crossings.predict_all_crossings(
            self.p, self.book, self.pending, _offsets(self.dim), _steps(self), self.cell_of, self.cell_members,
            self.cell_count, self.ncell, self.geom, self.dim, self.params, self.queue, self.tree, self.leaves, self.acc,
            _search_scratch(self),
        )

    def _check_cell_drift(self, tolerance):
        """RuntimeError if a particle (synchronised) lies outside its cell beyond round-off: an engine bug."""
        width = self.geom[_k.G_CELL, : self.dim]
        coordinates = np.stack(np.unravel_index(self.cell_of, tuple(self.ncell[::-1]))[::-1], axis=1)[:, : self.dim]
        points = self.p[:, _k.X : _k.X + self.dim]
        allowed = 1e-9 * width + tolerance * float(np.max(self.box[: self.dim]))
        outside = np.maximum(coordinates * width - points, points - (coordinates + 1) * width).max()
        if outside > allowed.max():
            raise RuntimeError(f"a particle lies {outside:.6g} outside its cell (allowed {allowed.max():.6g})")


def run_crossing_kernel(system, time, still, collisions, max_events, t_stop, stall_limit):
    """One call of the cell-crossing event loop on ``system`` (:func:`._system_events.run_event_loop`'s kernel)."""
    return _crossings.run_crossing_events(
        time, still, collisions, max_events, t_stop, stall_limit, system.p, system.book, system.pending,
        system._image, _offsets(system.dim), _steps(system), system.cell_of, system.cell_members, system.cell_count,
        system.ncell, system.geom, system.dim, system.restitution, system.params, system.queue, system.tree,
        system.leaves, system.acc, _search_scratch(system), system.spin,
    )


def _steps(system):
    """The search order as cell-number differences in ``system``'s grid (:func:`.cell_search.linear_offsets`)."""
    grid = (system.dim, *system.ncell.tolist())
    if system._search_grid != grid:
        system._search_steps = _cell_search.linear_offsets(_offsets(system.dim), system.ncell)
        system._search_grid = grid
    return system._search_steps


def _search_scratch(system):
    """The cell searches' scratch of ``system`` (the members of the 3^dim cells around one), grown with its cells.

    Not state: a checkpoint does not hold it, a restored system makes its own.
    """
    size = 3**system.dim * system.cell_members.shape[1] + 2
    scratch = system._search_members
    if scratch is None or scratch.shape[0] < size:
        scratch = system._search_members = np.zeros(size, dtype=np.int64)
    return scratch


_OFFSET_TABLES = {}


def _offsets(dim):
    """The search order of the neighbouring cells (:func:`~collisionkit._kernels.edmd.cell_search.offset_table`)."""
    if dim not in _OFFSET_TABLES:
        _OFFSET_TABLES[dim] = _cell_search.offset_table(dim)
    return _OFFSET_TABLES[dim]
