"""Square-well attraction of a :class:`~collisionkit.edmd.HardSphereSystem`: parameters, energies, the pairs inside.

Each pair attracts with depth epsilon between contact (sigma, the sum of
the radii) and lambda sigma; the kernels' :mod:`collisionkit._kernels.edmd.wells`
resolves the events at the well's edge and keeps the record of the pairs
inside (``bonds``, ``bond_count``), which this mixin starts, renumbers,
checks and reads.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from .._io import CheckpointError
from .._kernels import edmd as _k
from . import _checks

# the widest well accepted, in contact distances (wider wells make lists of hundreds: use a smooth potential)
MAX_WELL_WIDTH = 5.0
# rows of the record checked at once against the lists of a restored state (a rows x width x width comparison)
RECORD_CHECK_ROWS = 4096


def _pair_matrix(value, name, species_count):
    """A number (a 0-d array) or a symmetric square matrix covering ``species_count`` species, checked."""
    matrix = _checks.real_array(value, name)
    if matrix.ndim == 0:
        return matrix
    if matrix.ndim != 2 or matrix.shape[0] != matrix.shape[1] or matrix.shape[0] < species_count:
        raise ValueError(f"{name} must be a number or a square matrix covering the {species_count} species; got "
                         f"shape {matrix.shape}")
    if not np.array_equal(matrix, matrix.T):
        raise ValueError(f"{name} must be a symmetric matrix (the well of a and b is that of b and a)")
    return matrix


def well_parameters(system, well_width, well_depth, growth, shear_rate, engine):
    """Check the square-well arguments and store them in ``system.params`` (with the table); None: hard spheres.

    ``well_width`` and ``well_depth`` are numbers (every pair) or symmetric
    matrices over the species (a depth of 0: that pair has no well).
    Wells need fixed radii in the lists engine (no compression, shear or
    cell-crossing engine); gravity is allowed (relative motion stays straight).
    """
    if well_width is None:
        return
    species_count = int(system._species.max()) + 1
    width, depth = _pair_matrix(well_width, "well_width", species_count), _pair_matrix(well_depth, "well_depth",
                                                                                       species_count)
    size = max([m.shape[0] for m in (width, depth) if m.ndim == 2], default=species_count)
    width, depth = (np.full((size, size), float(m)) if m.ndim == 0 else m for m in (width, depth))
    if width.shape != depth.shape:
        raise ValueError(f"well_width and well_depth must cover the same species; got shapes {width.shape} and "
                         f"{depth.shape}")
    wrong = ~((width > 1.0) & (width <= MAX_WELL_WIDTH))  # (NaN is wrong too)
    if np.any(wrong):
        raise ValueError(f"well_width must be in (1, {MAX_WELL_WIDTH:g}]; got {width[wrong][0]}")
    if not (np.all(np.isfinite(depth) & (depth >= 0.0)) and np.any(depth > 0.0)) or (np.ndim(well_depth) == 0
                                                                                     and not depth[0, 0] > 0.0):
        raise ValueError(f"well_depth must be finite and > 0 (a matrix: >= 0, 0 for a pair without a well, some "
                         f"pair > 0); got {well_depth!r}")
    inelastic = bool(np.any(system.restitution != 1.0)) or system.params[_k.P_WALL_RESTITUTION] != 1.0
    clashes = [(growth != 0.0, "compression"), (shear_rate != 0.0, "shear_rate"), (engine == "cells", 'engine="cells"'),
               (inelastic, "restitution or wall_restitution below 1 (their energy balance is not kept with wells)"),
               (system.params[_k.P_LAW] != _k.LAW_CONSTANT, "a restitution_law (wells keep elastic pairs)")]
    for clash, name in clashes:
        if clash:
            raise ValueError(f"well_width: square wells run without {name} (elastic, fixed radii, no shear, in the "
                             "lists engine)")
    table = np.stack([width, depth], axis=-1)
    if np.all(table == table[0, 0]):  # one well for every pair: a table of one entry, read without the species
        table = table[:1, :1]
    widest = widest_well(table, np.unique(system._species))
    if widest == 0.0:
        raise ValueError("well_depth must be > 0 for some pair of the species present (the others' wells never act)")
    system.params = np.concatenate([system.params[: _k.P_SIZE], table.ravel()])
    system.params[_k.P_WELL_WIDTH] = widest  # the lists reach the widest well that acts
    system.params[_k.P_WELL_DEPTH] = float(np.max(depth))
    system.params[_k.P_WELL_SPECIES] = table.shape[0]


def table_species(table, species):
    """The rows of ``table`` the ``species`` read: their own, or row 0 of a table of one entry (every pair's)."""
    species = np.asarray(species, dtype=np.intp)
    return species if table.shape[0] > 1 else np.zeros_like(species)


def widest_well(table, present):
    """The largest lambda_ab among pairs of the ``present`` species with a well (epsilon_ab > 0); 0 if none."""
    present = np.unique(table_species(table, present))
    sub = table[np.ix_(present, present)]
    acting = sub[..., 1] > 0.0
    return float(np.max(sub[..., 0][acting])) if np.any(acting) else 0.0


def well_table(params):
    """The (S, S, 2) table of (lambda_ab, epsilon_ab) in ``params`` ((1, 1, 2): every pair's); None without wells."""
    species = int(params[_k.P_WELL_SPECIES])
    if species == 0:
        return None
    return params[_k.P_SIZE : _k.P_SIZE + 2 * species * species].reshape(species, species, 2)


def pairs_inside(positions, radius, box, periodic, table, species):
    """The pairs (i < j) closer than lambda_ab (r_i + r_j) with epsilon_ab > 0 (minimum images on the periodic
    axes), an (M, 2) array; ``table`` the (S, S, 2) well table, ``species`` per particle."""
    positions = np.asarray(positions, dtype=float)
    widths, depths = table[..., 0], table[..., 1]
    reach = float(np.max(widths)) * 2.0 * float(np.max(radius))
    # a walled axis as a period too long to wrap any pair within reach
    boxsize = np.where(periodic, box, box + 2.0 * reach + 1.0)
    wrapped = np.mod(positions, boxsize)
    wrapped[wrapped >= boxsize] = 0.0  # -tiny mod L rounds to L, which cKDTree refuses
    tree = cKDTree(wrapped, boxsize=boxsize)
    pairs = tree.query_pairs(reach, output_type="ndarray")
    if pairs.size == 0:
        return pairs.reshape(0, 2)
    separation = positions[pairs[:, 1]] - positions[pairs[:, 0]]
    separation -= np.where(periodic, box * np.round(separation / box), 0.0)
    distance = np.sqrt(np.sum(separation**2, axis=1))
    species = table_species(table, species)
    a, b = species[pairs[:, 0]], species[pairs[:, 1]]
    inside = (distance < widths[a, b] * (radius[pairs[:, 0]] + radius[pairs[:, 1]])) & (depths[a, b] > 0.0)
    return pairs[inside]


def bond_arrays(pairs, count, row):
    """The kernels' record of ``pairs`` inside: partners per particle (int32, count x row) and their numbers."""
    owners = np.concatenate([pairs[:, 0], pairs[:, 1]])
    partners = np.concatenate([pairs[:, 1], pairs[:, 0]])
    order = np.argsort(owners, kind="stable")
    owners, partners = owners[order], partners[order]
    bond_count = np.bincount(owners, minlength=count).astype(np.int32)
    first = np.cumsum(bond_count) - bond_count  # each owner's first entry in the sorted list
    bonds = np.zeros((count, row), dtype=np.int32)
    bonds[owners, np.arange(owners.size) - first[owners]] = partners
    return bonds, bond_count


class SquareWells:
    """The square-well attraction of :class:`~collisionkit.edmd.HardSphereSystem` (a mixin)."""

    @property
    def well_width(self):
        """lambda, the wells' outer radius in contact distances: a number, or the (S, S) matrix per species pair
        where they differ; None for hard spheres."""
        return self._well_entry(0)

    @property
    def well_depth(self):
        """epsilon, the depth of the wells: a number, or the (S, S) matrix per species pair where they differ (0 for
        hard spheres)."""
        depth = self._well_entry(1)
        return 0.0 if depth is None else depth

    @property
    def well_table(self):
        """The (S, S, 2) table of (lambda_ab, epsilon_ab) per species pair (a copy); None for hard spheres.

        One well for every pair is a table of one entry, (1, 1, 2), whatever
        the species.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem
        >>> positions = [[1.0, 1.0], [4.0, 1.0], [7.0, 1.0]]
        >>> depths = [[1.0, 0.0], [0.0, 2.0]]    # no well between the species
        >>> system = HardSphereSystem(positions, np.zeros((3, 2)), 0.5, 10.0, species=[0, 1, 1], well_width=1.5,
        ...                           well_depth=depths)
        >>> system.well_table[..., 1].tolist(), system.well_width
        ([[1.0, 0.0], [0.0, 2.0]], 1.5)
        """
        table = well_table(self.params)
        return None if table is None else table.copy()

    def _well_entry(self, column):
        table = well_table(self.params)
        if table is None:
            return None
        entries = table[..., column]
        return float(entries[0, 0]) if np.all(entries == entries[0, 0]) else entries.copy()

    @property
    def well_pairs(self) -> int:
        """Pairs inside their wells now."""
        return int(self.acc[_k.ACC_WELL_PAIRS])

    @property
    def well_events(self) -> dict:
        """Events at the wells' edges so far, by outcome: ``captures``, ``escapes``, ``bounces``."""
        return {"captures": int(self.acc[_k.ACC_CAPTURES]), "escapes": int(self.acc[_k.ACC_ESCAPES]),
                "bounces": int(self.acc[_k.ACC_BOUNCES])}

    def _well_record(self):
        """(bonds, bond_count) for the event loop; (None, None) for hard spheres, whose loop has no wells' code."""
        return (None, None) if self.well_width is None else (self.bonds, self.bond_count)

    def potential_energy(self) -> float:
        """Minus the depths epsilon_ab of the pairs inside their wells, summed (0 for hard spheres).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem
        >>> positions = [[1.0, 1.0], [2.2, 1.0], [5.0, 5.0]]    # the first two within 1.5 diameters
        >>> system = HardSphereSystem(positions, np.zeros((3, 2)), 0.5, 10.0, well_width=1.5, well_depth=2.0)
        >>> system.potential_energy()
        -2.0
        """
        return -0.5 * float(np.sum(self._bound_energies()))

    def _bound_energies(self):
        """Per particle (memory order): the depths of the wells it is inside, summed (zeros for hard spheres)."""
        energies = np.zeros(self.count)
        if self.well_width is not None:
            _k.bound_energies(self.book, self.bonds, self.bond_count, self.params, energies)
        return energies

    def total_energy(self) -> float:
        """Kinetic plus potential energy (the wells', and under gravity -sum m g . x): conserved when elastic.

        Under gravity the positions are the unwrapped ones (a periodic axis
        along g adds m g L at every crossing, as the fall it stands for).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import lattice, maxwell_boltzmann, HardSphereSystem
        >>> positions, box = lattice("fcc", 3, 0.2)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(108), 3, seed=1), 0.5, box,
        ...                           well_width=1.5)
        >>> before = system.total_energy()
        >>> _ = system.run(collisions=3000)
        >>> abs(system.total_energy() - before) < 1e-11 * abs(before)
        True
        """
        energy = self.kinetic_energy() + self.potential_energy()
        gravity = self.geom[_k.G_GRAVITY, : self.dim]
        if np.any(gravity != 0.0):
            energy -= float(np.sum(self.mass[:, None] * gravity * self.positions(unwrapped=True)))
        return energy

    def well_pair_time(self) -> float:
        """Time integral of the number of pairs inside their wells, from the system's start to now.

        Over a stretch of time its change divided by the stretch is the
        mean number of pairs inside, and -epsilon times that per particle
        the mean potential energy per particle.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem
        >>> positions = [[1.0, 1.0], [2.2, 1.0], [5.0, 5.0]]
        >>> system = HardSphereSystem(positions, np.zeros((3, 2)), 0.5, 10.0, well_width=1.5)
        >>> system.run(time=2.0)
        0
        >>> system.well_pair_time()    # one pair inside (at rest) for 2 time units
        2.0
        """
        since = float(self.acc[_k.ACC_WELL_SINCE])
        return float(self.acc[_k.ACC_WELL_PAIR_TIME]) + self.well_pairs * (self.time - since)

    def well_energy_time(self) -> float:
        """Time integral of the depths of the pairs inside their wells (minus the potential energy), start to now.

        Over a stretch of time its change divided by the stretch and by N is
        minus the mean potential energy per particle.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem
        >>> positions = [[1.0, 1.0], [2.2, 1.0], [5.0, 5.0]]
        >>> system = HardSphereSystem(positions, np.zeros((3, 2)), 0.5, 10.0, well_width=1.5, well_depth=0.5)
        >>> system.run(time=2.0)
        0
        >>> system.well_energy_time()    # one pair of depth 0.5 inside (at rest) for 2 time units
        1.0
        """
        since = float(self.acc[_k.ACC_WELL_SINCE])
        return float(self.acc[_k.ACC_WELL_ENERGY_TIME]) + float(self.acc[_k.ACC_WELL_ENERGY]) * (self.time - since)

    def _restart_well_clock(self, shift):
        """The clock moves back by ``shift``: carry the integrals up to now and restart their time at 0."""
        elapsed = shift - self.acc[_k.ACC_WELL_SINCE]
        self.acc[_k.ACC_WELL_PAIR_TIME] += self.acc[_k.ACC_WELL_PAIRS] * elapsed
        self.acc[_k.ACC_WELL_ENERGY_TIME] += self.acc[_k.ACC_WELL_ENERGY] * elapsed
        self.acc[_k.ACC_WELL_SINCE] = 0.0

    def _start_wells(self):
        """The record of the pairs inside their wells at the start (none, a row of 1, for hard spheres)."""
        count = self.count
        table = well_table(self.params)
        if table is None:
            self.bonds, self.bond_count = np.zeros((count, 1), dtype=np.int32), np.zeros(count, dtype=np.int32)
            return
        radius = self.p[:, _k.R] * self.scale0
        species = self.book[:, _k.SPECIES].astype(np.intp)
        pairs = pairs_inside(self.p[:, : self.dim], radius, self.box, self.periodic, table, species)
        row = max(1, int(np.bincount(pairs.ravel(), minlength=count).max(initial=0)))
        self.bonds, self.bond_count = bond_arrays(pairs, count, row)
        self.acc[_k.ACC_WELL_PAIRS] = len(pairs)
        rows = table_species(table, species)
        self.acc[_k.ACC_WELL_ENERGY] = float(np.sum(table[rows[pairs[:, 0]], rows[pairs[:, 1]], 1]))

    def _fit_bonds_to_lists(self):
        """Widen the record's rows to the neighbour lists' (a pair inside its well is listed: never more per row).

        The kernels add a pair to the record without a bounds check: this
        keeps room for every listed partner.
        """
        width = self.neighbours.shape[1]
        if self.well_width is None or self.bonds.shape[1] >= width:
            return
        wider = np.zeros((self.count, width), dtype=np.int32)
        wider[:, : self.bonds.shape[1]] = self.bonds
        self.bonds = wider

    def _renumber_bonds(self, order):
        """Follow a renumbering of the particles (``order[new] = old``) in the record of pairs inside."""
        new_number = np.empty_like(order)
        new_number[order] = np.arange(order.size)
        self.bonds = np.ascontiguousarray(new_number[self.bonds[order]].astype(np.int32))
        self.bond_count = np.ascontiguousarray(self.bond_count[order])

    def _check_record_against_lists(self):
        """CheckpointError unless every pair in the restored record is in its owner's neighbour list; unused slots 0.

        A pair inside its well is always listed: a record that is not a
        subset of the lists is damaged (and could outgrow its rows, which
        the kernels fill without a bounds check). Checked in chunks of rows.
        """
        if self.well_width is None:
            return
        columns = np.arange(self.bonds.shape[1])
        self.bonds[columns[None, :] >= self.bond_count[:, None]] = 0
        listed_columns = np.arange(self.neighbours.shape[1])
        for start in range(0, self.count, RECORD_CHECK_ROWS):
            rows = slice(start, start + RECORD_CHECK_ROWS)
            recorded = columns[None, :] < self.bond_count[rows, None]
            listed = listed_columns[None, :] < self.neighbour_count[rows, None]
            found = (self.bonds[rows, :, None] == self.neighbours[rows, None, :]) & listed[:, None, :]
            if np.any(recorded & ~found.any(axis=2)):
                raise CheckpointError("array 'bonds' must hold only pairs in each other's neighbour lists (a pair "
                                      "inside its well is always listed)")
        table = well_table(self.params)
        rows = table_species(table, self.book[:, _k.SPECIES])
        owners = np.repeat(np.arange(self.count), self.bond_count)
        partners = self.bonds[columns[None, :] < self.bond_count[:, None]]
        if np.any(table[rows[owners], rows[partners], 1] <= 0.0):
            raise CheckpointError("array 'bonds' must hold only pairs whose species share a well (depth > 0)")
        recorded_energy = -self.potential_energy()
        if abs(self.acc[_k.ACC_WELL_ENERGY] - recorded_energy) > 1e-9 * max(1.0, recorded_energy):
            raise CheckpointError(f"array 'acc' must hold the depths of the pairs inside their wells summed as the "
                                  f"record does ({recorded_energy!r})")

    def _check_wells(self, tolerance):
        """RuntimeError if the record of pairs inside disagrees with the distances now (particles synchronised).

        Pairs within ``tolerance`` (relative) of a well's edge may be on
        either side: their side is the record's.
        """
        table = well_table(self.params)
        if table is None:
            return
        positions = self.p[:, : self.dim]  # memory order, as the record
        radius = self.p[:, _k.R] * self.scale
        box, periodic, species = self.box, self.periodic, self.book[:, _k.SPECIES].astype(np.intp)
        inner = set(map(tuple, pairs_inside(positions, radius * (1 - tolerance), box, periodic, table,
                                            species).tolist()))
        outer = set(map(tuple, pairs_inside(positions, radius * (1 + tolerance), box, periodic, table,
                                            species).tolist()))
        owners = np.repeat(np.arange(self.count), self.bond_count)
        partners = self.bonds[np.arange(self.bonds.shape[1])[None, :] < self.bond_count[:, None]]
        recorded = set(zip(np.minimum(owners, partners).tolist(), np.maximum(owners, partners).tolist()))
        if not inner <= recorded <= outer or len(recorded) != self.well_pairs:
            raise RuntimeError(f"the record of pairs inside their wells ({len(recorded)}, counted {self.well_pairs}) "
                               f"disagrees with their distances ({len(inner)} to {len(outer)} inside)")
        counted, recorded_energy = float(self.acc[_k.ACC_WELL_ENERGY]), -self.potential_energy()
        if abs(counted - recorded_energy) > 1e-9 * max(1.0, recorded_energy):
            raise RuntimeError(f"the depths of the pairs inside their wells sum to {recorded_energy!r} by the record "
                               f"but to {counted!r} by the engine's count")



# ------------------------------------------------------------------ checks of a restored state


def _refuse(name, what):
    raise CheckpointError(f"array {name!r} {what}")


def check_well_parameters(params, p, arrays):
    """A restored state's wells: none (no table, 0 width and depth), or a table over the species (those of the
    bookkeeping records) of lambda_ab in (1, MAX_WELL_WIDTH] and epsilon_ab >= 0, symmetric, some epsilon > 0,
    whose widest real well and deepest well the parameters hold.

    Wells also mean no growth or shear (as the constructor refuses).
    """
    size = int(params[_k.P_WELL_SPECIES]) if np.isfinite(params[_k.P_WELL_SPECIES]) else -1
    if size != params[_k.P_WELL_SPECIES] or size < 0 or params.size != _k.P_SIZE + 2 * size * size:
        _refuse("params", f"must hold a well table of S x S pairs after its {_k.P_SIZE} entries (S = "
                f"{params[_k.P_WELL_SPECIES]!r}; {params.size} entries in all)")
    if size == 0:
        if params[_k.P_WELL_WIDTH] != 0.0 or params[_k.P_WELL_DEPTH] != 0.0:
            _refuse("params", "must hold no well width or depth without a well table")
        return
    table = well_table(params)
    width, depth = table[..., 0], table[..., 1]
    if not (np.all((width > 1.0) & (width <= MAX_WELL_WIDTH)) and np.all(np.isfinite(depth) & (depth >= 0.0))
            and np.any(depth > 0.0) and np.array_equal(table, table.transpose(1, 0, 2))):
        _refuse("params", f"must hold a symmetric well table of widths in (1, {MAX_WELL_WIDTH:g}] and depths >= 0, "
                "some > 0")
    book = arrays["book"]
    if book.ndim != 2 or book.shape != (p.shape[0], 8) or not np.all(np.isfinite(book[:, _k.SPECIES])):
        return  # the bookkeeping checks name what is wrong with it
    species = book[:, _k.SPECIES]
    if np.any((species < 0) | (species != np.round(species))) or (size > 1 and np.any(species >= size)):
        _refuse("book", f"must hold species the well table covers (whole numbers below {size})")
    widest = widest_well(table, np.unique(species).astype(np.intp))
    if widest == 0.0 or params[_k.P_WELL_WIDTH] != widest or params[_k.P_WELL_DEPTH] != np.max(depth):
        _refuse("params", "must hold the widest well acting between the species present (some must act) and the "
                "table's deepest depth")
    if params[_k.P_GROWTH] != 0.0 or params[_k.P_SHEAR_RATE] != 0.0:
        _refuse("params", "must hold no growth or shear with square wells")


def upgraded_well_state(arrays, written):
    """The wells of a format-8 state (one width and depth in the parameters, counted pairs) in this format's form:
    a table of one entry (every pair's well) and the depths' sums (depth times the counts)."""
    params, acc = arrays["params"], arrays["acc"]
    width, depth = params[_k.P_WELL_WIDTH], params[_k.P_WELL_DEPTH]
    if written >= 9 or width == 0.0:
        return
    params[_k.P_WELL_SPECIES] = 1
    arrays["params"] = np.concatenate([params, [width, depth]])
    acc[_k.ACC_WELL_ENERGY] = depth * acc[_k.ACC_WELL_PAIRS]
    acc[_k.ACC_WELL_ENERGY_TIME] = depth * acc[_k.ACC_WELL_PAIR_TIME]


def check_bonds(arrays, count, wells, pairs_inside_count):
    """The record of pairs inside wells: shapes, partners in range, no self or repeat, symmetric, counted.

    Without wells it must be empty; with wells its rows as wide as the
    neighbour lists' at least (the kernels add partners without a bounds
    check, relying on it).
    """
    bonds, bond_count = arrays["bonds"], arrays["bond_count"]
    if bonds.dtype != np.int32 or bonds.ndim != 2 or bonds.shape[0] != count or bonds.shape[1] < 1:
        _refuse("bonds", f"must hold int32 of shape ({count}, n); got {bonds.dtype} of shape {bonds.shape}")
    if wells and bonds.shape[1] < np.shape(arrays["neighbours"])[-1]:
        _refuse("bonds", "must hold rows as wide as the neighbour lists'")
    if bond_count.dtype != np.int32 or bond_count.shape != (count,):
        _refuse("bond_count", f"must hold int32 of shape ({count},); got {bond_count.dtype} of shape "
                f"{bond_count.shape}")
    if np.any(bond_count < 0) or np.any(bond_count > bonds.shape[1]) or (not wells and np.any(bond_count)):
        _refuse("bond_count", f"must hold counts in [0, {bonds.shape[1]}], and 0 without wells")
    owners = np.repeat(np.arange(count), bond_count)
    partners = bonds[np.arange(bonds.shape[1])[None, :] < bond_count[:, None]]
    if np.any((partners < 0) | (partners >= count) | (partners == owners)):
        _refuse("bonds", f"must hold partners in [0, {count}), none a particle's own")
    forward = set(zip(owners.tolist(), partners.tolist()))
    if len(forward) != partners.size or forward != {(j, i) for i, j in forward}:
        _refuse("bonds", "must hold each pair once in each partner's row")
    if partners.size != 2 * pairs_inside_count:
        _refuse("acc", f"must count the pairs inside wells as the record does ({partners.size // 2})")
