"""Checkpoints of a :class:`~collisionkit.edmd.HardSphereSystem`: its arrays, saved and restored bit for bit.

A checkpoint holds every engine array as it is (memory order, pending
events, neighbour lists), so a restored system continues exactly as the
saved one would have; it carries the engine's layout number
(``STATE_FORMAT``) and is refused by an engine of another layout.
"""

from __future__ import annotations

import numpy as np

from .._io import read_checkpoint, write_checkpoint
from ._system_setup import aligned_zeros

CHECKPOINT_KIND = "hard-sphere-system"


class Checkpoints:
    """Saving and restoring the full state of :class:`~collisionkit.edmd.HardSphereSystem` (a mixin)."""

    _ARRAYS = ("p", "_mass", "_species", "_image", "ids", "acc", "geom", "params", "restitution", "book", "cell_of",
               "ncell", "queue", "tree", "neighbours", "neighbour_count", "cell_members", "cell_count", "cell_points")
    _SCALARS = ("dim", "time", "elapsed", "leaves", "last_sort", "_shell_request")
    # layout of the engine's arrays in a checkpoint; raise it when they change (2: bookkeeping records, block queue)
    STATE_FORMAT = 2

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
        written = int(state["format"]) if "format" in state else 1
        if written != cls.STATE_FORMAT:
            raise ValueError(
                f"state has engine format {written}; this collisionkit reads format {cls.STATE_FORMAT} "
                "(checkpoints do not carry over between engine versions: restart the run)"
            )
        system = cls.__new__(cls)
        for name in cls._ARRAYS:
            setattr(system, name, np.array(state[name]))
        for name in ("p", "book", "queue", "tree"):
            aligned = aligned_zeros(getattr(system, name).shape)
            aligned[:] = getattr(system, name)
            setattr(system, name, aligned)
        for name in cls._SCALARS:
            setattr(system, name, state[name].item())
        system.restitution_law = str(state["restitution_law"])
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
        return cls.from_state_dict(read_checkpoint(path, CHECKPOINT_KIND).arrays)
