"""The particles of a :class:`~collisionkit.edmd.HardSphereSystem` as users see them.

The engine keeps each particle at its own time, in memory (cell) order,
with positions that may lie up to half a shell outside a periodic box; the
views here bring them to the current time, fold them into the box and put
them back in the user's particle order. Kinetic energy, temperature and
momentum follow from them.
"""

from __future__ import annotations

import math

import numpy as np

from .. import _arrays
from .._kernels import edmd as _k
from . import _checks


class ParticleState:
    """Positions, velocities and their sums for :class:`~collisionkit.edmd.HardSphereSystem` (a mixin).

    It reads the system's records ``p``, the masses, species and image
    counters (memory order), ``ids`` (memory slot -> particle), the box and
    :meth:`~collisionkit.edmd.HardSphereSystem.synchronise`.
    """

    @property
    def count(self) -> int:
        """Number of particles N."""
        return self.p.shape[0]

    @property
    def pos(self):
        """Positions at each particle's own time (a view; prefer :meth:`positions`)."""
        return self.p[:, _k.X : _k.X + self.dim]

    @property
    def vel(self):
        """Velocities at each particle's own time (a view; prefer :meth:`velocities`)."""
        return self.p[:, _k.V : _k.V + self.dim]

    @property
    def radius(self):
        """Radii at scale 1, in particle order."""
        return self._to_user_order(self.p[:, _k.R])

    @property
    def mass(self):
        """Masses, in particle order."""
        return self._to_user_order(self._mass)

    @property
    def species(self):
        """Species indices, in particle order."""
        return self._to_user_order(self._species)

    @property
    def image(self):
        """Periodic image counters (boundary crossings per axis) at the current time, in particle order."""
        self.synchronise()
        return self._to_user_order(self._folded()[1])

    def _folded(self, ahead=0.0):
        """Internal positions folded into [0, L) on periodic axes, and the matching image counters.

        The engine wraps a particle only when it rebuilds its neighbour list,
        so stored positions may lie up to half a shell outside the box.
        ``ahead`` > 0 moves them that far along their free flights first
        (exact only before the next event: see :meth:`_time_to_next_event`).
        Under shear, the images of Lees-Edwards (see ``_shear``).
        """
        if self.params[_k.P_SHEAR_RATE] != 0.0:
            return self._sheared_folded(ahead)[:2]
        gravity = self.geom[_k.G_GRAVITY, : self.dim]
        pos = self.pos + self.vel * ahead + 0.5 * gravity * ahead**2
        image = self._image.copy()
        for k in np.flatnonzero(self.periodic):
            length = self.box[k]
            shift = np.floor(pos[:, k] / length)
            pos[:, k] -= shift * length
            image[:, k] += shift.astype(np.int64)
            rounded_up = pos[:, k] >= length  # -tiny + L rounds to L
            pos[rounded_up, k] -= length
            image[rounded_up, k] += 1
        return pos, image

    def _to_user_order(self, internal):
        result = np.empty_like(internal)
        result[self.ids] = internal
        return result

    def positions(self, unwrapped=False):
        """Positions at the current time (a copy); ``unwrapped`` adds the periodic images.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> _ = system.run(collisions=2000)
        >>> inside = system.positions()
        >>> bool((inside >= 0).all() and (inside < box).all())
        True
        >>> system.positions(unwrapped=True).shape
        (100, 2)
        """
        self.synchronise()
        internal = self.pos + self._image * self.box[: self.dim] if unwrapped else self._folded()[0]
        return self._to_user_order(internal)

    def velocities(self):
        """Velocities at the current time (a copy); under shear those of the particles in the box (lab frame).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> bool(np.allclose(system.velocities().sum(axis=0), 0.0))
        True
        """
        self.synchronise()
        if self.params[_k.P_SHEAR_RATE] != 0.0:
            velocities = self.vel.copy()
            velocities[:, 0] += self._sheared_folded()[2]
            return self._to_user_order(velocities)
        return self._to_user_order(self.vel)

    def kinetic_energy(self) -> float:
        """Total kinetic energy sum(m v^2) / 2; under shear that of the peculiar velocities (relative to the flow).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> round(system.kinetic_energy(), 12)  # kT = 1 in 2D: K = N kT
        100.0
        """
        self.synchronise()
        velocities = self._peculiar() if self.params[_k.P_SHEAR_RATE] != 0.0 else self.vel
        return float(0.5 * np.sum(self._mass[:, None] * velocities**2))

    def temperature(self) -> float:
        """kT = 2 K / (d N).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> _ = system.run(collisions=1000)
        >>> round(system.temperature(), 12)  # elastic: unchanged
        1.0
        """
        return 2.0 * self.kinetic_energy() / (self.dim * self.count)

    def species_temperatures(self) -> np.ndarray:
        """kT of each species, 2 K_a / (d N_a) (under shear of the peculiar velocities); NaN for a species without
        particles.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem
        >>> system = HardSphereSystem([[1.0, 1.0], [1.0, 5.0]], [[1.0, 0.0], [0.0, 2.0]], 0.5, 10.0, masses=[2.0, 1.0],
        ...                           species=[0, 1])
        >>> system.species_temperatures()  # K_0 = 1, K_1 = 2, each over d = 2 degrees of freedom
        array([1., 2.])
        """
        self.synchronise()
        velocities = self._peculiar() if self.params[_k.P_SHEAR_RATE] != 0.0 else self.vel
        energy = 0.5 * self._mass * np.sum(velocities**2, axis=1)
        kinds = int(np.max(self._species)) + 1
        counts = np.bincount(self._species, minlength=kinds)
        with np.errstate(invalid="ignore", divide="ignore"):
            return 2.0 * np.bincount(self._species, weights=energy, minlength=kinds) / (self.dim * counts)

    def momentum(self):
        """Total momentum sum(m v); under shear that of the peculiar velocities (relative to the flow).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> bool(np.allclose(system.momentum(), 0.0))
        True
        """
        self.synchronise()
        velocities = self._peculiar() if self.params[_k.P_SHEAR_RATE] != 0.0 else self.vel
        return (self._mass[:, None] * velocities).sum(axis=0)

    def helfand_moments(self):
        r"""The Einstein-Helfand moments of momentum and energy now: ``(G, G_E)``, shapes (d, d) and (d,).

        :math:`G_{ab}(t) - G_{ab}(0) = \int_0^t J_{ab}\,dt'` and
        :math:`G_{E,a}(t) - G_{E,a}(0) = \int_0^t J_{E,a}\,dt'`, with the
        momentum flux :math:`J_{ab} = \sum_i m_i v_{ia} v_{ib} + \sum_{coll}
        \delta(t - t_c)\,\Delta p_{j,a} r_b` and the energy flux
        :math:`J_{E,a} = \sum_i \tfrac12 m_i v_i^2 v_{ia} + \sum_{coll}
        \delta(t - t_c)\,\Delta E_j r_a` (r the minimum-image separation),
        whose time correlations give the shear and bulk viscosities and the
        thermal conductivity (Helfand, Phys. Rev. 119, 1 (1960); Alder, Gass
        & Wainwright, J. Chem. Phys. 53, 3813 (1970)). Only differences in
        time have a meaning.

        They are :math:`\sum_i m_i v_{ia} x_{ib}` and
        :math:`\sum_i \tfrac12 m_i v_i^2 x_{ia}` over the stored positions x
        (with square wells the energy is kinetic plus potential, each particle
        carrying half of its pairs' -epsilon: the moment adds
        :math:`-\tfrac{1}{2}\sum_i \epsilon_i x_{ia}` over the unwrapped
        positions, epsilon_i the depths of the wells i is in summed, and the transfers at the wells'
        edges are the partners' whole energy changes)
        plus Erpenbeck's image terms the event loop accumulates: with
        periodic images the plain moment of positions jumps by the transfer
        times a box length when a pair collides across a face (and, for
        stored positions, when a particle is wrapped), a jump the flux does
        not have (Erpenbeck, Phys. Rev. E 51, 4296 (1995); Viscardy &
        Gaspard, Phys. Rev. E 68, 041204 (2003); García-Rojo, Luding &
        Brey, Phys. Rev. E 74, 061305 (2006)). So the changes of G are
        symmetric, as the flux is.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> start, _ = system.helfand_moments()
        >>> _ = system.run(collisions=5000)
        >>> momentum, energy = system.helfand_moments()
        >>> change = momentum - start
        >>> momentum.shape, energy.shape, bool(np.isclose(change[0, 1], change[1, 0], rtol=1e-9))
        ((2, 2), (2,), True)
        """
        self.synchronise()
        return self._helfand_moments_now()

    def _helfand_moments_now(self):
        """:meth:`helfand_moments` at the current time without moving the particles there (no gravity)."""
        stored = np.empty(12)
        _k.stored_helfand_moments(self.p, self.book, self.time, stored)
        dim = self.dim
        momentum = (stored[:9] + self.acc[_k.ACC_MOMENTUM_IMAGE : _k.ACC_MOMENTUM_IMAGE + 9]).reshape(3, 3)
        energy = stored[9:dim + 9] + self.acc[_k.ACC_ENERGY_IMAGE : _k.ACC_ENERGY_IMAGE + dim]
        if self.well_width is not None:  # the potential energy's part: -1/2 sum_i (sum of i's depths) x_i (unwrapped)
            ahead = (self.time - self.p[:, _k.T])[:, None]
            unwrapped = (self.p[:, _k.X : _k.X + dim] + self.p[:, _k.V : _k.V + dim] * ahead
                         + self._image * self.box[:dim])
            energy = energy - 0.5 * (self._bound_energies() @ unwrapped)
        return momentum[:dim, :dim], energy

    def set_velocities(self, velocities):
        """Replace all velocities (at the current time) and re-predict every event.

        Under shear the velocities are those :meth:`velocities` gives: of the
        particles in the box, lab frame.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> system.set_velocities(2.0 * system.velocities())
        >>> round(system.temperature(), 12)
        4.0
        """
        velocities = _checks.real_array(velocities, "velocities")
        if velocities.shape != (self.count, self.dim):
            raise ValueError(f"velocities must have shape {(self.count, self.dim)}; got {velocities.shape}")
        _arrays.require_finite(velocities, "velocities")
        self.synchronise()
        self.p[:, _k.V : _k.V + self.dim] = velocities[self.ids]
        if self.params[_k.P_SHEAR_RATE] != 0.0:
            self.p[:, _k.V] -= self._sheared_folded()[2]
        self._predict_all()

    def rescale_temperature(self, kT=1.0):
        """Scale all velocities to the temperature kT (kinetic definition); re-predicts events.

        Under shear the peculiar velocities are scaled (the flow stays).

        Parameters
        ----------
        kT : float
            Finite and > 0. A system at rest cannot be rescaled.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> system.rescale_temperature(0.25)
        >>> round(system.temperature(), 12)
        0.25
        """
        kT = _checks.positive(kT, "kT")
        current = self.temperature()
        if current == 0.0:
            raise ValueError("cannot rescale the temperature of a system at rest (every velocity is zero)")
        if self.params[_k.P_SHEAR_RATE] != 0.0:
            factor = math.sqrt(kT / current)
            self.p[:, _k.V] = self._streaming(self.p[:, _k.X + 1]) + factor * self._peculiar()[:, 0]
            self.p[:, _k.V + 1 : _k.V + self.dim] *= factor
            self._predict_all()
            return
        self.set_velocities(self.velocities() * math.sqrt(kT / current))

