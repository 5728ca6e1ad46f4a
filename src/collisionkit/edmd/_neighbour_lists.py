"""Neighbour lists and cells of a :class:`~collisionkit.edmd.HardSphereSystem`.

Each particle lists the others whose anchors (where its list was built) lie
within the contact distance at the list's radius scale plus a shell; the
lists are built from cell lists of the anchors, a particle's own list is
rebuilt when it has moved half a shell from its anchor (a queued event of
its own), and all of them when the cells, the shell or the radius scale
change. The memory order of the particles follows the cells, re-sorted
every so often.
"""

from __future__ import annotations

import math

import numpy as np

from .._kernels import edmd as _k
from ._cell_crossings import ENGINE_CELLS
from ._system_setup import copy_masses_and_species

# while compressing, lists cover radii up to the current scale plus this (then all are rebuilt)
LIST_SCALE_MARGIN = 0.05
# slots per cell a new system starts with (grown when a cell needs more)
INITIAL_CELL_SLOTS = 8
# the most cells a particle, on average (per axis: (CELLS_PER_PARTICLE N)^(1/dim))
CELLS_PER_PARTICLE = 2


class NeighbourLists:
    """The neighbour-list and cell maintenance of :class:`~collisionkit.edmd.HardSphereSystem` (a mixin).

    It reads the system's particles (``p``, ``book``, ``dim``, ``box``,
    ``periodic``, radius ``scale0`` and ``growth``, the requested
    ``_shell_request``) and owns ``neighbours``, ``neighbour_count``,
    ``cell_of``, ``ncell``, ``cell_members``, ``cell_count``,
    ``cell_points`` and the shell and list scale in ``params``. After a
    rebuild it re-predicts every event (:meth:`_predict_all`, of either
    engine), and it finds the smallest pair gap through the cells
    (:meth:`_pair_gap`).
    """

    @property
    def anchor(self):
        """Neighbour-list anchors: where each particle's list was last built (a view, memory order)."""
        return self.book[:, _k.ANCHOR : _k.ANCHOR + 3]

    @property
    def neighbour_shell_width(self) -> float:
        """Width of the neighbour-list shell (skin) now, in units of length.

        The ``neighbour_shell`` asked for (in largest diameters) times the
        largest diameter at the list scale, narrowed in small periodic boxes.
        A particle's list holds every other particle within their contact
        distance (at :attr:`neighbour_list_scale`) plus this width of its anchor.
        """
        return float(self.params[_k.P_SHELL])

    @property
    def neighbour_list_scale(self) -> float:
        """Largest radius scale the neighbour lists are valid for (above the current scale while compressing)."""
        return float(self.params[_k.P_LIST_SCALE])

    @property
    def neighbour_list_slack(self) -> float:
        """How far beyond its list radius a listed pair's anchors may lie.

        The cells hold the anchors in float32: a list may also hold pairs
        within their round-off of the radius (a harmless superset).
        """
        return _k.ANCHOR_ROUNDING * (float(np.max(self.geom[_k.G_BOX])) + 1.0)  # all 3 entries, as always

    def _list_geometry(self, list_scale):
        """Shell and cells for lists valid up to radius scale ``list_scale``."""
        largest = 2.0 * float(np.max(self.p[:, _k.R])) * list_scale
        periodic_sides = self.box[: self.dim][self.periodic]
        if periodic_sides.size and periodic_sides.min() < 3.0 * largest * (1 - 1e-12):
            k = int(np.flatnonzero(self.periodic)[np.argmin(periodic_sides)])
            raise ValueError(
                f"box[{k}] = {self.box[k]:.6g} is too small: a periodic axis needs at least 3 times "
                f"the largest diameter ({largest:.6g})"
            )
        shell = self._shell_request * 2.0 * float(np.max(self.p[:, _k.R])) * max(list_scale, 1.0)
        sheared = self.params[_k.P_SHEAR_RATE] != 0.0
        if periodic_sides.size:
            # the minimum image must be unique within the list radius: 2 (largest + shell) < L
            shell = min(shell, 0.98 * (0.5 * periodic_sides.min() - largest))
        if sheared:
            # at least 3 rows of cells, each as high as the list radius, keep the first and last rows apart (the
            # cells are then scanned (1 + strain) list radii along x, within half the box: see
            # _kernels.edmd.neighbour_lists._gather_sheared)
            shell = min(shell, 0.98 * (periodic_sides.min() / 3.0 - largest))
            if shell < 0.01 * largest:
                raise ValueError(
                    f"box {self.box[: self.dim].tolist()} is too small to shear: every axis needs at least 3.1 times "
                    f"the largest diameter ({largest:.6g})"
                )
        reach = largest + shell
        ncell = np.ones(3, dtype=np.int64)
        widths = np.ones(3)
        # cells wider than the reach are as valid: at most about CELLS_PER_PARTICLE a particle (small radii of a
        # compression's start, or a dilute gas, would otherwise ask for many empty cells)
        most = max(3 if sheared else 1, int((CELLS_PER_PARTICLE * self.count) ** (1.0 / self.dim)))
        for k in range(self.dim):
            ncell[k] = min(max(int(math.floor(self.box[k] / reach * (1 - 1e-12))), 1), most)
            widths[k] = self.box[k] / ncell[k]
        return shell, ncell, widths

    def _refresh_lists(self, anchors_only=False):
        """Re-anchor every particle, rebuild every neighbour list and re-predict every event.

        Lists cover the radius scale of now (plus a margin while growing);
        cells and list rows are enlarged when needed. With ``anchors_only``
        it stops once the anchors are in the cells (``cell_of`` current),
        the lists and events left stale: for :meth:`_sort_by_cell`, which
        refreshes everything after renumbering. The cell-crossing engine
        (:attr:`engine` "cells") has no lists: its cells are refreshed instead.
        """
        if self._engine_code == ENGINE_CELLS:
            self._refresh_crossings(cells_only=anchors_only)
            return
        self.synchronise()
        list_scale = self.scale0 + LIST_SCALE_MARGIN if self.growth > 0 else self.scale0
        if self.params[_k.P_WELL_WIDTH] != 0.0:
            list_scale *= self.params[_k.P_WELL_WIDTH]  # a pair inside its well or entering it is listed
        shell, ncell, widths = self._list_geometry(list_scale)
        self.params[_k.P_SHELL] = shell
        self.params[_k.P_LIST_SCALE] = list_scale
        if not np.array_equal(ncell, getattr(self, "ncell", None)):
            self.ncell = ncell
            self._grow_cells(max(INITIAL_CELL_SLOTS, self._fullest_cell(ncell, widths)))
        self.geom[_k.G_CELL] = widths
        self._start_shear_frame()
        while anchors_only:
            fullest = _k.anchor_all(
                self.p, self.book, self.anchor_time, self.cell_of, self.cell_members, self.cell_count, self.cell_points,
                self.ncell, self.geom, self.dim, self.params, self._image, self.acc,
            )
            if fullest <= self.cell_members.shape[1]:
                return
            self._grow_cells(fullest)
        while True:
            needed, fullest = _k.build_all_lists(
                self.p, self.book, self.anchor_time, self.cell_of, self.neighbours, self.neighbour_count,
                self.cell_members, self.cell_count, self.cell_points, self.ncell, self.geom, self.dim, self.params,
                self._image, self.acc,
            )
            if fullest > self.cell_members.shape[1]:
                self._grow_cells(fullest)
            elif needed > self.neighbours.shape[1]:
                self._grow_lists(needed)
            else:
                break
        self._fit_bonds_to_lists()
        self._predict_all()

    def _predict_all(self):
        """Predict every particle's next event afresh and rebuild the event queue (either engine).

        The lists engine's prediction from the neighbour lists, or the
        cell-crossing engine's (:meth:`_predict_all_crossings`).
        """
        if self._engine_code == ENGINE_CELLS:
            self._predict_all_crossings()
            return
        _k.predict_all(
            self.p, self.book, self.anchor_time, self.neighbours, self.neighbour_count, self.geom, self.dim, self.params, self.queue,
            self.tree, self.leaves, self.acc, *self._well_record(),
        )

    def _pair_gap(self):
        """The smallest surface gap between two particles now, found through the cells (no shear: see ``_sheared_gap``)."""
        return _k.min_gap(
            self.p, self.scale, self.cell_of, self.cell_members, self.cell_count, self.ncell, self.geom, self.dim
        )

    def _fullest_cell(self, ncell, widths) -> int:
        """Particles in the fullest cell of a new grid: the slots sized from the grid itself.

        Sizing them from the old grid's (times the room to spare) compounded
        at every grid change of a compression: 828 slots for cells holding
        0.2 particles on average at eta = 0.02.
        """
        dim = self.dim
        index = np.zeros(self.count, dtype=np.int64)
        for k in range(dim):
            column = np.floor(self.p[:, _k.X + k] / widths[k]).astype(np.int64)
            index = index * ncell[k] + np.clip(column, 0, ncell[k] - 1)
        return int(np.bincount(index).max())

    @staticmethod
    def _room_for(needed):
        return max(needed + 4, int(1.25 * needed))

    def _grow_lists(self, needed):
        """Widen the neighbour-list rows to hold ``needed`` entries with room to spare."""
        self.neighbours = np.zeros((self.count, self._room_for(needed)), dtype=np.uint32)
        self.neighbour_count[:] = 0
        self._fit_bonds_to_lists()

    def _grow_cells(self, needed):
        """(Re)allocate the cells with ``needed`` slots each, with room to spare."""
        cells, slots = int(np.prod(self.ncell)), self._room_for(needed)
        self.cell_members = np.zeros((cells, slots), dtype=np.int32)
        self.cell_count = np.zeros(cells, dtype=np.int32)
        # anchors and radii in float32 (16 bytes a slot): a cell of 4 spheres in one cache line (the cell-crossing
        # engine has no anchors: one unused slot)
        shape = (1, 1, 4) if self._engine_code == ENGINE_CELLS else (cells, slots, 4)
        self.cell_points = np.zeros(shape, dtype=np.float32)

    def _grow_overflowed_storage(self) -> bool:
        """After a run stopped because a list row or a cell was full: grow them, rebuild all lists, True.

        False (and nothing done) if nothing overflowed.
        """
        lists, cells = self.acc[_k.ACC_LIST_OVERFLOW], self.acc[_k.ACC_CELL_OVERFLOW]
        if lists <= 0 and cells <= 0:
            return False
        if lists > 0:
            self._grow_lists(int(lists))
        if cells > 0:
            self._grow_cells(int(cells))
        self.acc[_k.ACC_LIST_OVERFLOW] = self.acc[_k.ACC_CELL_OVERFLOW] = 0.0
        self._refresh_lists()
        return True

    def _lists_expire_in(self) -> float:
        """Time from now until the growing radii outgrow the lists' scale (inf when not compressing)."""
        return (self.params[_k.P_LIST_SCALE] - self.scale) / self.growth if self.growth > 0 else math.inf

    def _slot_order(self):
        """The new memory order at a sort: slots in the order of their cells (x fastest), stably.

        A Z-order (Morton) curve of the cells was measured against it at
        N = 32000 to 10^6 and gained nothing (0.89-1.01 times the rate,
        within the run-to-run spread); even a random order cost only 8-18 %
        at 10^6 (benchmarks/results/edmd_morton.md): a particle's records
        fill a cache line each, so no order makes neighbours share one, and
        numpy's large arrays sit in huge pages (few TLB misses).
        """
        return np.argsort(self.cell_of, kind="stable")

    def _sort_by_cell(self):
        """Renumber the memory slots in cell order so neighbours lie close in memory.

        Particles keep their identity through ``ids``; all lists are rebuilt
        and all events re-predicted (the slots changed). The order is that
        of the cells of the particles' positions now (their anchors, set
        before renumbering; :meth:`_slot_order`), and the lists are built
        once, after it. The trajectory does not depend on the order.
        """
        self._last_partner = -1  # (the memory slots change)
        self._refresh_lists(anchors_only=True)
        order = self._slot_order()
        # the records column by column: a temporary of one column, not of the whole array (64 MB at N = 10^6)
        for array in (self.p, self._image):
            for column in range(array.shape[1]):
                array[:, column] = array[order, column]
        self._mass = self._mass[order]
        self._species = self._species[order]
        if self.spin.shape[0]:
            self.spin = self.spin[order]
        self.ids = self.ids[order]  # a new array: a transport measurement tells a re-sort by it
        self._renumber_bonds(order)
        self.book[:] = 0.0
        self.book[:, _k.TARGET] = _k.LIST_TARGET
        copy_masses_and_species(self)
        self._refresh_lists()
        self.last_sort = self.collisions

    def _check_anchor_drift(self, tolerance):
        """RuntimeError if a particle is further than half a shell from its anchor (its list could miss a collision)."""
        if self._engine_code == ENGINE_CELLS:
            self._check_cell_drift(tolerance)
            return
        drift = _k.largest_anchor_drift(self.p, self.book, self.anchor_time, self.geom, self.dim, self.params)
        allowed = 0.5 * self.params[_k.P_SHELL] + tolerance * float(np.max(self.box[: self.dim]))
        if drift > allowed:
            # the lists would miss collisions: an engine bug, never a user error
            raise RuntimeError(f"a particle drifted {drift:.6g} from its list anchor (allowed {allowed:.6g})")
