"""Named read-only views of the kernels' geometry, parameter and accumulator arrays.

The kernels keep a system's box, cells, gravity and periodic flags in
``geom``, its collision law, radius scale and neighbour-list shell in
``params`` and its running sums in ``acc``, each indexed by a ``_k``
constant; these properties give users (and the measurement) their values by
name.
"""

from __future__ import annotations

import numpy as np

from .._kernels import edmd as _k
from . import theory


class SystemParameters:
    """Box, radius scale, collision law and running totals of :class:`~collisionkit.edmd.HardSphereSystem` (a mixin)."""

    @property
    def box(self):
        """Box lengths (3 entries; the third is 1 in 2D)."""
        return self.geom[_k.G_BOX]

    @property
    def periodic(self):
        """Per axis: True if periodic, False if closed by hard walls."""
        return self.geom[_k.G_PERIODIC, : self.dim] != 0.0

    @property
    def volume(self) -> float:
        """Volume (area in 2D) of the box."""
        return float(np.prod(self.box[: self.dim]))

    @property
    def packing_fraction(self) -> float:
        """Fraction of the box the particles cover, at the current radius scale."""
        return theory.packing_fraction(self.radius * self.scale, self.box[: self.dim])

    @property
    def growth(self) -> float:
        """Relative growth rate of the radii (non-zero only while compressing)."""
        return float(self.params[_k.P_GROWTH])

    @property
    def scale0(self) -> float:
        """Radius scale factor at time 0 of the clock (see :meth:`synchronise`)."""
        return float(self.params[_k.P_SCALE0])

    @property
    def scale(self) -> float:
        """Current radius scale factor (1 except during compression)."""
        return self.scale0 + self.growth * self.time

    @property
    def elastic_below(self) -> float:
        """Normal approach speed below which contacts are elastic (the guard against inelastic collapse).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice
        >>> positions, box = lattice("square", 4, 0.3)
        >>> velocities = np.tile([1.0, 0.0], (16, 1))
        >>> HardSphereSystem(positions, velocities, 0.5, box, restitution=0.9).elastic_below  # 1e-6 rms speed
        1e-06
        """
        return float(self.params[_k.P_ELASTIC_BELOW])

    @property
    def collisions(self) -> int:
        """Pair collisions processed so far."""
        return int(self.acc[_k.ACC_PAIR_COLLISIONS])

    @property
    def wall_collisions(self) -> int:
        """Particle-wall collisions processed so far."""
        return int(self.acc[_k.ACC_WALL_COLLISIONS])

    @property
    def wall_impulse(self) -> float:
        """Momentum transferred to the walls so far: the sum of the impulses' magnitudes."""
        return float(self.acc[_k.ACC_WALL_IMPULSE])

    @property
    def energy_lost(self) -> float:
        """Kinetic energy lost in inelastic pair collisions so far (exact bookkeeping, not a difference)."""
        return float(self.acc[_k.ACC_ENERGY_LOST])

    @property
    def virial(self) -> float:
        """Sum over the pair collisions so far of impulse times contact distance (the collisional virial)."""
        return float(self.acc[_k.ACC_VIRIAL])
