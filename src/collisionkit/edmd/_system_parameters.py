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
        """Box lengths, one per axis (``dim`` entries, like a row of :meth:`positions`; a copy).

        Examples
        --------
        >>> from collisionkit.edmd import random_fluid
        >>> system = random_fluid(2, 50, 0.3, seed=1)
        >>> system.box.shape
        (2,)
        >>> system.box[0] = 1.0                  # a copy: the system keeps its box
        >>> float(system.box[0]) > 1.0
        True
        """
        return self.geom[_k.G_BOX, : self.dim].copy()

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

    @property
    def collisional_stress(self):
        r"""The collisional stress sum so far, shape (d, d): :math:`\sum_{coll} \Delta p_{j,a} r_b`.

        Over every pair collision, the impulse on one partner j times the
        minimum-image separation r = x_j - x_i at contact (both along r, so
        the tensor is symmetric; rough spheres' tangential impulses add the
        symmetric part of theirs, without trace); its trace is :attr:`virial`. Divided by
        the volume and a stretch of time, it is the collisional part of the
        pressure tensor over that stretch (Allen & Tildesley, Computer
        Simulation of Liquids, 2nd ed., sec. 2.7).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> _ = system.run(collisions=1000)
        >>> stress = system.collisional_stress
        >>> bool(np.allclose(stress, stress.T)), bool(np.isclose(np.trace(stress), system.virial, rtol=1e-12))
        (True, True)
        """
        full = np.zeros((3, 3))
        for slot, (a, b) in enumerate(_k.STRESS_PAIRS):
            full[a, b] = full[b, a] = self.acc[_k.ACC_STRESS + slot]
        return full[: self.dim, : self.dim]

    @property
    def collisional_heat_transfer(self):
        r"""The collisional energy transfer sum so far, shape (d,): :math:`\sum_{coll} \Delta E_j\, r_a`.

        The energy gained by one partner j times the minimum-image
        separation r = x_j - x_i at contact (kinetic; at a well's edge plus
        j's half of the pair's potential-energy change): over a stretch of
        time, the collisional part of the energy flux times the volume
        (elastic spheres).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> system.collisional_heat_transfer.shape
        (2,)
        """
        return self.acc[_k.ACC_HEAT : _k.ACC_HEAT + self.dim].copy()
