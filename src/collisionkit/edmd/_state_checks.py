"""Checks of a restored :class:`~collisionkit.edmd.HardSphereSystem` state: every array before the kernels run on it.

A checkpoint is data, never trusted: the kernels index their arrays without
bounds checks, so :func:`check_state` checks every array (dtype, shape
against the particle count, the dimension and the cell grid, every stored
index and the invariants that tie the arrays together) and raises
:class:`~collisionkit._io.CheckpointError` naming the first bad one.
"""

from __future__ import annotations

import math

import numpy as np

from .._io import CheckpointError
from .._kernels import edmd as _k
from .._kernels.edmd.crossings import CROSSING_BASE
from ._cell_crossings import ENGINE_CELLS, ENGINE_LISTS, crossing_grid
from ._neighbour_lists import CELLS_PER_PARTICLE
from ._system_setup import RESTITUTION_LAWS, next_power_of_two
from ._wells import check_bonds, check_well_parameters

# dtype of every engine array (the kernels are compiled for these)
_DTYPES = {"p": np.float64, "_mass": np.float64, "_species": np.int64, "_image": np.int64, "ids": np.int64,
           "acc": np.float64, "geom": np.float64, "params": np.float64, "restitution": np.float64, "book": np.float64,
           "anchor_time": np.float64, "cell_of": np.int32, "ncell": np.int64, "queue": np.float64, "tree": np.float64, "neighbours": np.uint32,
           "neighbour_count": np.int32, "cell_members": np.int32, "cell_count": np.int32, "cell_points": np.float32,
           "pending": np.float64, "bonds": np.int32, "bond_count": np.int32, "spin": np.float64}
# accumulator slots that count (whole numbers), and those sized by a run that stopped to grow a row (<= N + 1)
_COUNTERS = (_k.ACC_PAIR_COLLISIONS, _k.ACC_WALL_COLLISIONS, _k.ACC_LIST_REBUILDS, _k.ACC_STALE_EVENTS, _k.ACC_EVENTS,
             _k.ACC_WELL_PAIRS, _k.ACC_CAPTURES, _k.ACC_ESCAPES, _k.ACC_BOUNCES)
_OVERFLOWS = (_k.ACC_LIST_OVERFLOW, _k.ACC_CELL_OVERFLOW)
_PARAMETERS = (_k.P_SCALE0, _k.P_GROWTH, _k.P_LAW, _k.P_LAW_SPEED, _k.P_LAW_EXPONENT, _k.P_ELASTIC_BELOW,
               _k.P_WALL_RESTITUTION, _k.P_SHELL, _k.P_LIST_SCALE, _k.P_SHEAR_RATE, _k.P_SHEAR_OFFSET, _k.P_SHEAR_SWEEP,
               _k.P_SHEAR_REACH, _k.P_THERMOSTAT, _k.P_SHEAR_FRAME, _k.P_WELL_WIDTH, _k.P_WELL_DEPTH,
               _k.P_WELL_SPECIES, _k.P_TANGENTIAL_RESTITUTION, _k.P_INERTIA_FACTOR, _k.P_FRICTION)
_TRANSPORT_SUMS = tuple(range(_k.ACC_STRESS, _k.ACC_SIZE))
_TOTALS = (_k.ACC_VIRIAL, _k.ACC_ENERGY_LOST, _k.ACC_WALL_IMPULSE, *_COUNTERS, *_OVERFLOWS, *_TRANSPORT_SUMS)


def _bad(name, what):
    return CheckpointError(f"array {name!r} {what}")


def _scalar(values, name, kind, low=-math.inf, high=math.inf, low_open=False):
    """``values[name]`` as a Python number: kind "i" an integer, "f" a finite real, in [low, high]."""
    value = np.asarray(values[name])
    what = "an integer" if kind == "i" else "a finite number"
    if value.shape != () or value.dtype.kind not in ("iu" if kind == "i" else "iuf"):
        raise _bad(name, f"must be {what}; got {value.dtype} of shape {value.shape}")
    value = value.item()
    if not (math.isfinite(value) and (low < value if low_open else low <= value) and value <= high):
        if low == high:
            allowed = f"{low:g}"
        elif high == math.inf:
            allowed = f"{what} {'>' if low_open else '>='} {low:g}"
        else:
            allowed = f"{what} in [{low:g}, {high:g}]"
        raise _bad(name, f"must be {allowed}; got {value!r}")
    return value


def _array(arrays, name, shape):
    """``arrays[name]``, of its dtype and of ``shape`` (None: any length >= 1 on that axis)."""
    array = arrays[name]
    if array.dtype != _DTYPES[name]:
        raise _bad(name, f"must hold {np.dtype(_DTYPES[name])}; got {array.dtype}")
    wanted = tuple(array.shape[k] if size is None and k < array.ndim else size for k, size in enumerate(shape))
    if array.shape != wanted or min(array.shape, default=1) < 1:
        wanted = ", ".join("n" if size is None else str(size) for size in shape) + ("," if len(shape) == 1 else "")
        raise _bad(name, f"must have shape ({wanted}); got {array.shape}")
    return array


def _require(condition, name, what):
    if not np.all(condition):
        raise _bad(name, what)


def _whole(values):
    return np.all(np.floor(values) == values)


def check_state(arrays, scalars):
    """Refuse a state the kernels could not run on safely: CheckpointError naming the first bad array.

    ``arrays`` are the engine arrays of :meth:`Checkpoints.state_dict`,
    ``scalars`` its numbers and the restitution law. Checked: every dtype;
    every shape against the particle count N, the dimension and the cell
    grid; finite values; positions and anchors in the box (up to a shell
    out on periodic axes), radii and masses > 0; the parameters in their
    ranges; every stored index (event partners and walls, species, list
    entries, cell members, the event tree's winners) in range; the cells
    holding each particle once, in the cell of its anchor; the event tree
    the tournament over the queue.
    """
    dim = _scalar(scalars, "dim", "i", 2, 3)
    p = _array(arrays, "p", (None, 8))
    count = p.shape[0]
    _require(count >= 2, "p", f"must hold at least 2 particles; got {count}")
    time = _scalar(scalars, "time", "f", 0.0)
    _scalar(scalars, "elapsed", "f", 0.0)
    _scalar(scalars, "_shell_request", "f", 0.0, low_open=True)
    law = np.asarray(scalars["restitution_law"])
    if law.shape != () or law.dtype.kind != "U" or str(law) not in RESTITUTION_LAWS:
        raise _bad("restitution_law", f"must be one of {sorted(RESTITUTION_LAWS)}; got {str(law)!r}")
    geom = _check_geometry(arrays, dim)
    params = _check_parameters(arrays, str(law), p, geom, dim)
    _check_particles(arrays, p, dim, geom, params, time)
    acc = _array(arrays, "acc", (_k.ACC_SIZE,))
    _require(np.isfinite(acc[list(_TOTALS)]), "acc", "must hold finite totals")
    counts, overflows = acc[list(_COUNTERS)], acc[list(_OVERFLOWS)]
    _require(_whole(counts) & (counts >= 0) & (counts <= 2.0**53), "acc", "must hold whole counts >= 0")
    _require(_whole(overflows) & (overflows >= 0) & (overflows <= count + 1), "acc",
             f"must hold row sizes in [0, {count + 1}] in its overflow slots")
    _scalar(scalars, "last_sort", "i", 0, acc[_k.ACC_PAIR_COLLISIONS])
    cells_engine = _scalar(scalars, "_engine_code", "i", ENGINE_LISTS, ENGINE_CELLS) == ENGINE_CELLS
    if cells_engine:
        _require(params[[_k.P_GROWTH, _k.P_SHEAR_RATE]] == 0, "params", "must hold no growth and no shear for "
                 "the cell-crossing engine")
        _require(geom[_k.G_GRAVITY] == 0, "geom", "must hold no gravity for the cell-crossing engine")
    wells = params[_k.P_WELL_WIDTH] != 0.0
    _require(~wells | ~cells_engine, "params", "must hold no well width for the cell-crossing engine")
    _require(~wells | (np.all(arrays["restitution"] == 1.0) & (params[_k.P_WALL_RESTITUTION] == 1.0)), "restitution",
             "must hold 1 everywhere with square wells (elastic)")
    _check_book(arrays, p, dim, geom, acc[_k.ACC_EVENTS], cells_engine, wells)
    check_bonds(arrays, count, wells, acc[_k.ACC_WELL_PAIRS])
    # saved as a run stopped to grow a list row or a cell (in a progress callback): the restore rebuilds them all
    rebuilt = bool(np.any(overflows > 0))
    if cells_engine:
        _check_crossing_cells(arrays, p, dim, geom, params, rebuilt)
    else:
        _check_cells(arrays, p, dim, geom, params, rebuilt)
    _check_lists(arrays, count, rebuilt)
    _check_pending(arrays, count, acc[_k.ACC_EVENTS])
    _check_queue(arrays, scalars, count)


def _check_geometry(arrays, dim):
    """The geometry rows: box, cell widths, gravity, periodic flags (unused axes of 2D as the engine sets them)."""
    geom = _array(arrays, "geom", (4, 3))
    _require(np.isfinite(geom), "geom", "must hold finite numbers")
    _require(geom[_k.G_BOX, :dim] > 0, "geom", "must hold box lengths > 0")
    _require(np.isin(geom[_k.G_PERIODIC], (0.0, 1.0)), "geom", "must hold periodic flags 0 or 1")
    unused = geom[[_k.G_BOX, _k.G_CELL, _k.G_GRAVITY, _k.G_PERIODIC], dim:]
    _require(unused == np.array([[1.0], [1.0], [0.0], [0.0]]), "geom", f"must leave the axes beyond {dim} unused")
    return geom


def _check_parameters(arrays, law, p, geom, dim):
    """The collision law, radius scale and neighbour-list shell, each in its range."""
    params = _array(arrays, "params", (None,))  # (a well table may follow the P_SIZE parameters)
    _require(params.ndim == 1 and params.size >= _k.P_SIZE, "params", f"must hold at least {_k.P_SIZE} entries")
    positive = params[[_k.P_SCALE0, _k.P_LAW_SPEED, _k.P_LAW_EXPONENT, _k.P_SHELL, _k.P_LIST_SCALE]]
    _require(np.isfinite(params[[*_PARAMETERS]]), "params", "must hold finite numbers")
    _require(positive > 0, "params", "must hold a radius scale, law speed and exponent, shell and list scale > 0")
    _require((params[_k.P_GROWTH] >= 0) & (params[_k.P_ELASTIC_BELOW] >= 0), "params",
             "must hold a growth rate and an elastic floor >= 0")
    _require(0 <= params[_k.P_WALL_RESTITUTION] <= 1, "params", "must hold a wall restitution in [0, 1]")
    _require(params[_k.P_LAW] == RESTITUTION_LAWS[law], "params", f"must hold the law of restitution_law {law!r}")
    _check_shear(params, geom, dim)
    check_well_parameters(params, p, arrays)
    _check_roughness(arrays, params, p.shape[0], dim)
    _require(params[_k.P_LIST_SCALE] >= params[_k.P_SCALE0] * (1 - 1e-9), "params",
             "must hold a list scale >= the radius scale")
    _require(np.isfinite(p[:, _k.R]) & (p[:, _k.R] > 0), "p", "must hold radii > 0")
    largest = 2.0 * float(np.max(p[:, _k.R])) * params[_k.P_LIST_SCALE]
    periodic = geom[_k.G_PERIODIC, :dim] != 0
    half = 0.5 * geom[_k.G_BOX, :dim][periodic]
    _require(largest + params[_k.P_SHELL] <= half * (1 + 1e-12), "params",
             "must hold a shell that keeps the list radius below half of each periodic box length")
    _require(3.0 * largest * (1 - 1e-12) <= 2.0 * half, "p", "must hold radii that fit 3 diameters in a periodic box")
    return params


def _check_roughness(arrays, params, count, dim):
    """Rough spheres (kappa set): beta in [-1, 1], kappa in (0, 1], finite spins of shape (N, 3), about z only in 2D,
    and no shear, wells, growth or radius scale; smooth ones: both 0 and no spins."""
    beta, kappa = params[_k.P_TANGENTIAL_RESTITUTION], params[_k.P_INERTIA_FACTOR]
    rough = kappa != 0.0
    spin = _array(arrays, "spin", (count, 3)) if rough else arrays["spin"]
    if not rough:
        _require((beta == 0.0) & (params[_k.P_FRICTION] == 0.0), "params", "must hold no tangential restitution or "
                 "friction without an inertia factor (smooth spheres)")
        _require(spin.dtype == np.float64 and spin.shape == (0, 3), "spin", "must be empty (shape (0, 3)) for "
                 "smooth spheres")
        return
    _require((-1.0 <= beta <= 1.0) & (0.0 < kappa <= 1.0) & (params[_k.P_FRICTION] >= 0.0), "params",
             "must hold a tangential restitution in [-1, 1], an inertia factor in (0, 1] and a friction >= 0")
    _require(np.isfinite(spin), "spin", "must hold finite angular velocities")
    _require(dim == 3 or np.all(spin[:, :2] == 0.0), "spin", "must spin discs about the normal of their plane only")
    _require((params[[_k.P_SHEAR_RATE, _k.P_WELL_WIDTH, _k.P_GROWTH]] == 0.0).all() & (params[_k.P_SCALE0] == 1.0),
             "params", "must hold no shear, wells, growth or radius scale for rough spheres")


def _check_shear(params, geom, dim):
    """The shear entries: none without a shear rate; else a periodic box, no growth, offset and margin in range."""
    rate = params[_k.P_SHEAR_RATE]
    _require(params[_k.P_THERMOSTAT] >= 0, "params", "must hold a thermostat kT >= 0")
    if rate == 0.0:
        shear = params[[_k.P_SHEAR_OFFSET, _k.P_SHEAR_SWEEP, _k.P_SHEAR_REACH, _k.P_THERMOSTAT, _k.P_SHEAR_FRAME]]
        _require(shear == 0.0, "params",
                 "must hold no shear offset, sweep, list radius, thermostat or frame time without a shear rate")
        return
    _require(np.all(geom[_k.G_PERIODIC, :dim] != 0) & np.all(geom[_k.G_GRAVITY] == 0), "params",
             "must hold a shear rate only for a periodic box without gravity")
    _require(params[_k.P_GROWTH] == 0.0, "params", "must hold no growth under shear")
    _require(0.0 <= params[_k.P_SHEAR_OFFSET] < geom[_k.G_BOX, 0], "params", "must hold a shear offset in [0, L_x)")
    _require(params[_k.P_SHEAR_REACH] > params[_k.P_SHELL], "params", "must hold a list radius > the shell under shear")
    _require(params[_k.P_SHEAR_FRAME] <= params[_k.P_SHEAR_SWEEP], "params",
             "must hold a frame time no later than the next sweep under shear")


def _check_particles(arrays, p, dim, geom, params, time):
    """Positions, velocities, own times, masses, species, image counters and the slot -> particle map."""
    count = p.shape[0]
    _require(np.isfinite(p), "p", "must hold finite positions, velocities and times")
    _require(p[:, _k.X + dim : _k.V].size == 0 or not np.any(p[:, _k.X + dim : _k.V]), "p",
             f"must hold zero coordinates beyond axis {dim}")
    _require(p[:, _k.V + dim : _k.T].size == 0 or not np.any(p[:, _k.V + dim : _k.T]), "p",
             f"must hold zero velocities beyond axis {dim}")
    _require(p[:, _k.T] <= time, "p", f"must hold own times <= the clock ({time:g})")
    margin = np.full(dim, params[_k.P_SHELL])
    if params[_k.P_SHEAR_RATE] != 0.0:
        # a sheared particle is carried along x by the flow until it rebuilds its list
        margin[0] = max(margin[0], _k.SHEAR_X_EXCURSION * geom[_k.G_BOX, 0])
    _check_in_box(p[:, _k.X : _k.X + dim], "p", geom, dim, margin)
    anchor_time = _array(arrays, "anchor_time", (count if params[_k.P_SHEAR_RATE] != 0.0 else 1,))
    _require(np.isfinite(anchor_time), "anchor_time", "must hold finite times")
    if params[_k.P_SHEAR_RATE] != 0.0:
        _require(anchor_time <= p[:, _k.T], "anchor_time", "must hold list times <= the particles' own times")
    mass = _array(arrays, "_mass", (count,))
    _require(np.isfinite(mass) & (mass > 0), "_mass", "must hold finite masses > 0")
    species = _array(arrays, "_species", (count,))
    restitution = _array(arrays, "restitution", (None, None))
    kinds = restitution.shape[0]
    _require(restitution.shape == (kinds, kinds), "restitution", f"must be square; got {restitution.shape}")
    _require((species >= 0) & (species < kinds), "_species", f"must hold species in [0, {kinds})")
    _require(np.isfinite(restitution) & (restitution >= 0) & (restitution <= 1), "restitution",
             "must hold coefficients in [0, 1]")
    _require(np.allclose(restitution, restitution.T), "restitution", "must be symmetric")
    _array(arrays, "_image", (count, dim))
    ids = _array(arrays, "ids", (count,))
    _require(np.array_equal(np.sort(ids), np.arange(count)), "ids", f"must be a permutation of 0 .. {count - 1}")


def _check_in_box(points, name, geom, dim, shell):
    """Points inside the walls, and within ``shell`` (per axis, or one for all) of [0, L] on periodic axes.

    Positions are wrapped lazily.
    """
    box = geom[_k.G_BOX, :dim]
    margin = np.where(geom[_k.G_PERIODIC, :dim] != 0, shell, 1e-9 * box)
    _require((points >= -margin) & (points <= box + margin), name, "must hold points inside the box")


def _check_book(arrays, p, dim, geom, events, cells_engine, wells):
    """The bookkeeping records: next event (partner, wall, list or cell crossing), event numbers, anchor, mass, species."""
    count = p.shape[0]
    book = _array(arrays, "book", (count, 8))
    _require(np.isfinite(book), "book", "must hold finite numbers")
    target = book[:, _k.TARGET]
    faces = -2 - target
    walled = np.flatnonzero(geom[_k.G_PERIODIC, :dim] == 0)
    wall = (faces >= 0) & np.isin(faces // 2, walled) & _whole(faces)
    partner = (target >= 0) & (target < count) & (target != np.arange(count))
    if cells_engine:
        crossing = (CROSSING_BASE - target >= 0) & (CROSSING_BASE - target < 2 * dim)
        _require(_whole(target) & (partner | crossing | wall), "book",
                 f"must hold next events with a partner in [0, {count}), a cell crossing or a wall")
    else:
        edge = _k.WELL_TARGET_BASE - target
        edge = wells & (edge >= 0) & (edge < count) & (edge != np.arange(count))
        _require(_whole(target) & (partner | (target == _k.LIST_TARGET) | wall | edge), "book",
                 f"must hold next events with a partner in [0, {count}), a list rebuild, a wall"
                 + (" or a well's edge" if wells else ""))
    numbers = book[:, [_k.PREDICTED_AT, _k.CHANGED_AT]]
    _require(_whole(numbers) & (numbers >= 0) & (numbers <= events), "book",
             f"must hold event numbers in [0, {events:.0f}]")
    _require(book[:, _k.MASS] == arrays["_mass"], "book", "must hold the masses of '_mass'")
    _require(book[:, _k.SPECIES] == arrays["_species"], "book", "must hold the species of '_species'")
    anchors = book[:, _k.ANCHOR : _k.ANCHOR + 3]
    _require(anchors[:, dim:] == 0, "book", f"must hold zero anchor coordinates beyond axis {dim}")
    _check_in_box(anchors[:, :dim], "book", geom, dim, 0.0)


def _check_cells(arrays, p, dim, geom, params, rebuilt):
    """The cell grid (as the shell and list scale give it), and each particle once in the cell of its anchor.

    Only the shapes if the cells are ``rebuilt`` before use.
    """
    count = p.shape[0]
    ncell = _array(arrays, "ncell", (3,))
    box = geom[_k.G_BOX, :dim]
    reach = 2.0 * float(np.max(p[:, _k.R])) * params[_k.P_LIST_SCALE] + params[_k.P_SHELL]
    # at most about CELLS_PER_PARTICLE cells a particle (at least 3 per axis under shear), as the lists make them
    most = max(3 if params[_k.P_SHEAR_RATE] != 0.0 else 1, int((CELLS_PER_PARTICLE * count) ** (1.0 / dim)))
    grid = np.minimum(np.maximum(np.floor(box / reach * (1 - 1e-12)), 1), most).astype(np.int64)
    _require(np.array_equal(ncell, np.concatenate([grid, np.ones(3 - dim, dtype=np.int64)])), "ncell",
             f"must hold the cell grid {grid.tolist()} of the box and the list radius; got {ncell.tolist()}")
    _require(geom[_k.G_CELL, :dim] == box / grid, "geom", "must hold the cell widths of the grid")
    cells = math.prod(ncell.tolist())
    members = _array(arrays, "cell_members", (cells, None))
    slots = members.shape[1]
    filled = _array(arrays, "cell_count", (cells,))
    cell_of = _array(arrays, "cell_of", (count,))
    points = _array(arrays, "cell_points", (cells, slots, 4))
    if rebuilt:
        return
    used, held = _check_members(members, filled, cell_of, count)
    anchors = arrays["book"][:, _k.ANCHOR : _k.ANCHOR + 3]
    coordinates = np.zeros((count, 3), dtype=np.int64)
    for k in range(dim):
        coordinates[:, k] = np.clip(np.floor(anchors[:, k] / geom[_k.G_CELL, k]), 0, ncell[k] - 1)
    home = coordinates[:, 0] + ncell[0] * (coordinates[:, 1] + ncell[1] * coordinates[:, 2])
    _require(cell_of == home, "cell_of", "must hold the cell of each particle's anchor")
    expected = np.column_stack([anchors[held], p[held, _k.R]]).astype(np.float32)
    _require(points[used] == expected, "cell_points", "must hold the anchors and radii of the cells' particles")


def _check_members(members, filled, cell_of, count):
    """Each particle once in the cells, in the cell ``cell_of`` names; (slots in use, their particles)."""
    slots = members.shape[1]
    _require((filled >= 0) & (filled <= slots), "cell_count", f"must hold counts in [0, {slots}]")
    _require(filled.sum() == count, "cell_count", f"must count {count} particles in all; got {filled.sum()}")
    used = np.arange(slots) < filled[:, None]
    held = members[used]
    _require((held >= 0) & (held < count), "cell_members", f"must hold particles in [0, {count})")
    _require(np.bincount(held, minlength=count) == 1, "cell_members", "must hold each particle once")
    _require(cell_of[held] == np.nonzero(used)[0], "cell_of", "must hold the cell that holds each particle")
    return used, held


def _check_crossing_cells(arrays, p, dim, geom, params, rebuilt):
    """The cell-crossing engine's grid (cells as wide as the largest contact) and each particle once in its cell.

    A particle may lie outside its cell by round-off (its cell is the
    engine's state, not a function of its position); more is refused.
    """
    count = p.shape[0]
    ncell = _array(arrays, "ncell", (3,))
    box = geom[_k.G_BOX, :dim]
    largest = 2.0 * float(np.max(p[:, _k.R])) * params[_k.P_SCALE0]
    try:
        grid, widths = crossing_grid(box, dim, geom[_k.G_PERIODIC, :dim] != 0, largest, count)
    except ValueError as error:
        raise _bad("geom", f"must hold a box the cell-crossing engine can run: {error}") from None
    _require(np.array_equal(ncell, grid), "ncell", f"must hold the cell grid {grid[:dim].tolist()} of the box and "
             f"the largest contact distance; got {ncell.tolist()}")
    _require(geom[_k.G_CELL, :dim] == widths[:dim], "geom", "must hold the cell widths of the grid")
    cells = math.prod(ncell.tolist())
    members = _array(arrays, "cell_members", (cells, None))
    filled = _array(arrays, "cell_count", (cells,))
    cell_of = _array(arrays, "cell_of", (count,))
    _array(arrays, "cell_points", (1, 1, 4))  # no anchors in this engine
    if rebuilt:
        return
    _check_members(members, filled, cell_of, count)
    coordinates = np.stack(np.unravel_index(cell_of, tuple(ncell[::-1].tolist()))[::-1], axis=1)[:, :dim]
    points = p[:, _k.X : _k.X + dim]
    slack = 1e-9 * widths[:dim]
    _require((points >= coordinates * widths[:dim] - slack) & (points <= (coordinates + 1) * widths[:dim] + slack),
             "cell_of", "must hold the cell of each particle's position (within round-off)")


def _check_pending(arrays, count, events):
    """The cell-crossing engine's pending collisions: a time (inf: none), a partner, an event number."""
    pending = _array(arrays, "pending", (count, 3))
    times, partners, numbers = pending[:, 0], pending[:, 1], pending[:, 2]
    _require(~np.isnan(times) & (times > -np.inf), "pending", "must hold collision times (no NaN or -inf)")
    _require(_whole(partners) & (partners >= -1) & (partners < count), "pending",
             f"must hold partners in [-1, {count})")
    _require(_whole(numbers) & (numbers >= 0) & (numbers <= events), "pending",
             f"must hold event numbers in [0, {events:.0f}]")


def _check_lists(arrays, count, rebuilt):
    """Neighbour lists: lengths within their rows, entries other particles (only the shapes if ``rebuilt``)."""
    neighbours = _array(arrays, "neighbours", (count, None))
    width = neighbours.shape[1]
    lengths = _array(arrays, "neighbour_count", (count,))
    if rebuilt:
        return
    _require((lengths >= 0) & (lengths <= width), "neighbour_count", f"must hold lengths in [0, {width}]")
    used = np.arange(width) < lengths[:, None]
    owners = np.nonzero(used)[0]
    listed = neighbours[used]
    _require((listed < count) & (listed != owners), "neighbours", f"must hold other particles in [0, {count})")


def _check_queue(arrays, scalars, count):
    """The event queue (padded with inf to whole blocks) and the tournament tree over its blocks."""
    blocks = -(-count // _k.QUEUE_BLOCK)
    queue = _array(arrays, "queue", (blocks * _k.QUEUE_BLOCK,))
    _require(~np.isnan(queue) & (queue > -np.inf), "queue", "must hold event times (no NaN or -inf)")
    _require(queue[count:] == np.inf, "queue", "must be padded with inf")
    leaves = next_power_of_two(blocks)
    _scalar(scalars, "leaves", "i", leaves, leaves)
    tree = _array(arrays, "tree", (2 * leaves, 2))
    times, winners = tree[1:, 0], tree[1:, 1]
    _require(~np.isnan(times) & _whole(winners) & (winners >= 0) & (winners < leaves * _k.QUEUE_BLOCK), "tree",
             "must hold event times and particles")
    leaf_times, leaf_winners = tree[leaves:, 0], tree[leaves:, 1]
    _require(leaf_times[blocks:] == np.inf, "tree", "must hold inf at the leaves beyond the queue")
    first = np.arange(blocks) * _k.QUEUE_BLOCK
    winners = leaf_winners[:blocks]
    inside = (winners >= first) & (winners < np.minimum(first + _k.QUEUE_BLOCK, count))
    _require(inside, "tree", "must hold at each leaf a particle of its block")
    _require(queue[winners.astype(np.int64)] == leaf_times[:blocks], "tree", "must hold at each leaf its event time")
    nodes = np.arange(1, leaves)
    left, right = tree[2 * nodes], tree[2 * nodes + 1]
    node = tree[nodes]
    from_left = np.all(node == left, axis=1) & (left[:, 0] <= right[:, 0])
    from_right = np.all(node == right, axis=1) & (right[:, 0] <= left[:, 0])
    _require(from_left | from_right, "tree", "must hold at each node the earlier of its two children")
