"""Checkpoints of a :class:`~collisionkit.edmd.HardSphereSystem`: its arrays, saved and restored bit for bit.

A checkpoint holds every engine array as it is (memory order, pending
events, neighbour lists), so a restored system continues exactly as the
saved one would have; it carries the engine's layout number
(``STATE_FORMAT``) and is refused by an engine of another layout.

A checkpoint is data, never trusted: before a restored system exists
:func:`._state_checks.check_state` checks every array; a bad one is a
:class:`~collisionkit._io.CheckpointError` naming it.
"""

from __future__ import annotations

import numpy as np

from .._io import CheckpointError, read_checkpoint, write_checkpoint
from .._kernels import edmd as _k
from ._cell_crossings import ENGINE_LISTS
from ._state_checks import _scalar, check_state
from ._system_setup import aligned_zeros
from ._wells import upgraded_well_state

CHECKPOINT_KIND = "hard-sphere-system"


class Checkpoints:
    """Saving and restoring the full state of :class:`~collisionkit.edmd.HardSphereSystem` (a mixin)."""

    _ARRAYS = ("p", "_mass", "_species", "_image", "ids", "acc", "geom", "params", "restitution", "book", "anchor_time",
               "cell_of", "ncell", "queue", "tree", "neighbours", "neighbour_count", "cell_members", "cell_count",
               "cell_points", "pending", "bonds", "bond_count", "spin")
    _SCALARS = ("dim", "time", "elapsed", "leaves", "last_sort", "_shell_request", "_engine_code")
    # layout of the engine's arrays in a checkpoint; raise it when they change (2: bookkeeping records, block queue;
    # 3: the transport sums in the accumulator; 4: Lees-Edwards shear and its thermostat in the parameters and the
    # accumulator; 5: under shear, cells as high as the list radius and the pairs across the y faces listed within
    # a capsule; 6: under shear, anchors carried by the flow, the cells in its frame, the lists' times; 7: the
    # cell-crossing engine, its pending collisions and the engine's code; 8: square wells, their parameters, counts
    # and the record of pairs inside; 9: square wells per species pair, a table after the parameters, and the
    # depths of the pairs inside summed; 10: rough spheres, their roughness and inertia in the parameters before the
    # well table, and the spins; 11: the friction coefficient of rough contacts after them)
    STATE_FORMAT = 11
    # older formats a restore still reads: format 2 lacks the transport sums, which start at 0 (only their changes
    # over a measurement have a meaning, and a format-2 run measured none); formats 2 and 3 were never sheared, and
    # formats 4 and 5 are read only unsheared (their sheared lists and cells are kept differently); formats before 7
    # ran the list engine; formats before 8 had no wells; format 8 had one well for every pair; formats before 10
    # were smooth, format 10 without a Coulomb limit
    READABLE_FORMATS = (2, 3, 4, 5, 6, 7, 8, 9, 10, 11)

    def state_dict(self):
        """Every array and number needed to continue the run bit for bit.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> copy = HardSphereSystem.from_state_dict(system.state_dict())
        >>> system.run(collisions=300), copy.run(collisions=300)
        (300, 300)
        >>> bool((system.positions() == copy.positions()).all())
        True
        """
        state = {name: getattr(self, name) for name in self._ARRAYS}
        state |= {name: np.asarray(getattr(self, name)) for name in self._SCALARS}
        state["restitution_law"] = np.asarray(self.restitution_law)
        state["format"] = np.asarray(self.STATE_FORMAT)
        return state

    @classmethod
    def from_state_dict(cls, state):
        """Rebuild a system from :meth:`state_dict` output (no re-prediction).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> HardSphereSystem.from_state_dict(system.state_dict()).count
        100
        """
        written = _scalar(state, "format", "i") if "format" in state else 1
        if written not in cls.READABLE_FORMATS:
            raise CheckpointError(
                f"state has engine format {written}; this collisionkit reads formats "
                f"{' and '.join(map(str, cls.READABLE_FORMATS))} "
                "(checkpoints do not carry over between engine versions: restart the run)"
            )
        if written < 7:  # the list engine, no pending collisions
            count = np.shape(state["p"])[0] if "p" in state else 0
            state = dict(state) | {"pending": np.zeros((count, 3)), "_engine_code": np.asarray(ENGINE_LISTS)}
        if written < 6:
            state = dict(state) | {"anchor_time": np.zeros(1)}  # never sheared (refused below if it was)
        if written < 8:  # hard spheres: an empty record of pairs inside wells
            count = np.shape(state["p"])[0] if "p" in state else 0
            state = dict(state) | {"bonds": np.zeros((count, 1), np.int32), "bond_count": np.zeros(count, np.int32)}
        rough_ten = written == 10 and np.size(state.get("params", ())) > _k.P_INERTIA_FACTOR and \
            np.asarray(state["params"]).ravel()[_k.P_INERTIA_FACTOR] != 0.0
        if rough_ten:  # development versions wrote format 10 with 1 + beta, others with beta: not to be told apart
            raise CheckpointError("state has engine format 10 with rough spheres, written by a development version "
                                  "whose tangential restitution cannot be read safely: restart the rough run")
        if written < 10:  # smooth spheres: no spins
            state = dict(state) | {"spin": np.zeros((0, 3))}
        missing = [name for name in (*cls._ARRAYS, *cls._SCALARS, "restitution_law") if name not in state]
        if missing:
            raise CheckpointError(f"the state has no array {', '.join(map(repr, missing))}")
        arrays = {name: np.array(state[name], order="C") for name in cls._ARRAYS}  # copies: checked, then kept
        sheared = arrays["params"].size > _k.P_SHEAR_RATE and arrays["params"][_k.P_SHEAR_RATE] != 0.0
        if written in (4, 5) and sheared:
            raise CheckpointError(f"state has engine format {written} with Lees-Edwards shear, whose neighbour lists "
                                  f"this collisionkit keeps differently (format {cls.STATE_FORMAT}): restart the "
                                  "sheared run")
        if written < cls.STATE_FORMAT:
            arrays["acc"] = _padded(arrays["acc"], (_k.ACC_SIZE_WITHOUT_TRANSPORT, _k.ACC_SIZE_WITHOUT_THERMOSTAT,
                                                    _k.ACC_SIZE_WITHOUT_WELL, _k.ACC_SIZE_WITHOUT_WELL_ENERGY),
                                    _k.ACC_SIZE)
            arrays["params"] = _padded(arrays["params"], (_k.P_SIZE_WITHOUT_SHEAR, _k.P_SIZE_WITHOUT_FRAME,
                                                          _k.P_SIZE_WITHOUT_WELL, _k.P_SIZE_WITHOUT_WELL_TABLE),
                                       _k.P_SIZE_WITHOUT_ROUGHNESS)
            if arrays["params"].shape == (_k.P_SIZE_WITHOUT_ROUGHNESS,) and arrays["acc"].shape == (_k.ACC_SIZE,):
                upgraded_well_state(arrays, written)
            arrays["params"] = _upgraded_parameters(arrays["params"], written)
        check_state(arrays, {name: state[name] for name in (*cls._SCALARS, "restitution_law")})
        system = cls.__new__(cls)
        for name, array in arrays.items():
            if name in ("p", "book", "queue", "tree"):
                aligned = aligned_zeros(array.shape)
                aligned[:] = array
                array = aligned
            setattr(system, name, array)
        for name in cls._SCALARS:
            setattr(system, name, np.asarray(state[name]).item())
        system.restitution_law = str(state["restitution_law"])
        system._grow_overflowed_storage()  # saved as a run stopped to grow a row: grow it, as that run did next
        system._check_record_against_lists()
        system._still = 0  # the collapse watch starts afresh
        return system

    def save(self, path):
        """Write a checkpoint (.npz, the one collisionkit checkpoint format) atomically: a kill mid-write keeps the old one.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> path = pathlib.Path(tempfile.mkdtemp()) / "run.npz"
        >>> _ = system.save(path)
        >>> HardSphereSystem.load(path).collisions == system.collisions
        True
        """
        return write_checkpoint(path, CHECKPOINT_KIND, {}, {}, self.state_dict())

    @classmethod
    def load(cls, path):
        """Read a checkpoint written by :meth:`save`.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> path = pathlib.Path(tempfile.mkdtemp()) / "run.npz"
        >>> _ = system.run(collisions=100)
        >>> _ = system.save(path)
        >>> restored = HardSphereSystem.load(path)
        >>> restored.run(collisions=100), system.run(collisions=100)
        (100, 100)
        >>> bool((restored.velocities() == system.velocities()).all())
        True
        """
        saved = read_checkpoint(path, CHECKPOINT_KIND)
        try:
            return cls.from_state_dict(saved.arrays)
        except CheckpointError as error:
            raise CheckpointError(f"cannot load {path}: {error}") from None


def _padded(array, old_sizes, size):
    """An array of an older format (one of ``old_sizes`` long) with the newer slots appended at 0; others unchanged.

    Format 2 lacks the transport sums and the thermostat slot, format 3 the
    thermostat slot and the shear parameters: 0 is no shear, no thermostat.
    """
    if array.ndim != 1 or array.shape[0] not in old_sizes or array.dtype != np.float64:
        return array  # check_state names what is wrong with it
    return np.concatenate([array, np.zeros(size - array.shape[0])])


def _upgraded_parameters(params, written):
    """The parameters of a format before 11 with the newer entries inserted at 0 before the well table: rough
    spheres' (smooth) before format 10, the friction coefficient (none) before 11."""
    cut = _k.P_SIZE_WITHOUT_ROUGHNESS if written < 10 else _k.P_SIZE_WITHOUT_FRICTION
    if params.ndim != 1 or params.shape[0] < cut or params.dtype != np.float64:
        return params  # check_state names what is wrong with it
    species = params[_k.P_WELL_SPECIES]
    if not (species >= 0 and params.shape[0] == cut + 2 * species * species):
        return params  # not the old layout: check_state judges it as it is
    return np.concatenate([params[:cut], np.zeros(_k.P_SIZE - cut), params[cut:]])
