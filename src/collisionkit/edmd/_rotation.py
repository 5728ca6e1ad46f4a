"""Rough spheres and discs of a :class:`~collisionkit.edmd.HardSphereSystem`: spins and a tangential restitution.

A rough contact turns the tangential relative velocity of the touching
surfaces into ``-beta`` times itself (:func:`collisionkit._kernels.edmd.contacts.rough_impulse`):
beta = -1 is the smooth sphere, whose spin never changes, beta = 1 the
perfectly rough one, which keeps the energy. The spins do not change the
flights, so the engine keeps them apart from the particles' records, in
``spin`` (memory order, three components also in 2D, where only the third,
about the normal of the plane, moves); a smooth system holds none. A
system is rough when its inertia factor (> 0) is set: beta = -1 given
explicitly makes spinning spheres whose spins never change.
"""

from __future__ import annotations

import numpy as np

from .. import _arrays
from .._kernels import edmd as _k
from . import _checks

# the moment of inertia in units of m a^2 of a uniform sphere (3D) and a uniform disc (2D)
UNIFORM_INERTIA = {2: 0.5, 3: 0.4}


def rotational_degrees(dim):
    """Degrees of freedom of a particle's rotation: 3 for a sphere, 1 for a disc (about the normal of its plane).

    Examples
    --------
    >>> rotational_degrees(3), rotational_degrees(2)
    (3, 1)
    """
    return 3 if dim == 3 else 1


def rough_parameters(system, tangential_restitution, inertia_factor, angular_velocities, refusals, friction=None):
    """Set ``system``'s tangential restitution, inertia factor, friction and spins (memory order) from the
    constructor's arguments.

    ``refusals`` names what a rough system cannot combine with (a feature
    given -> its name, shown in the message). Smooth systems (beta None)
    refuse an inertia factor or angular velocities.
    """
    count, dim = system.p.shape[0], system.dim
    if tangential_restitution is None:
        for value, name in ((inertia_factor, "inertia_factor"), (angular_velocities, "angular_velocities"),
                            (friction, "friction")):
            if value is not None:
                raise ValueError(f"{name} needs rough spheres: give a tangential restitution in [-1, 1]")
        system.spin = np.zeros((0, 3))
        return
    beta = _checks.bounded(tangential_restitution, "tangential_restitution", -1.0, 1.0, closed=(True, True))
    kappa = UNIFORM_INERTIA[dim] if inertia_factor is None else _checks.bounded(
        inertia_factor, "inertia_factor", 0.0, 1.0, closed=(False, True))
    for name, given in refusals.items():
        if given:
            raise ValueError(f"tangential_restitution (rough spheres) cannot be combined with {name}")
    system.params[_k.P_TANGENTIAL_RESTITUTION] = beta
    system.params[_k.P_INERTIA_FACTOR] = kappa
    if friction is not None:
        system.params[_k.P_FRICTION] = _checks.positive(friction, "friction")
    system.spin = np.zeros((count, 3))
    if angular_velocities is not None:
        system.spin[:] = _spins(angular_velocities, count, dim)[system.ids]


def _spins(angular_velocities, count, dim):
    """Angular velocities as the engine keeps them, (N, 3); in 2D given as (N,), the spin about the plane's normal."""
    omega = _checks.real_array(angular_velocities, "angular_velocities")
    shape = (count, 3) if dim == 3 else (count,)
    if omega.shape != shape:
        raise ValueError(f"angular_velocities must have shape {shape}; got {omega.shape}")
    _arrays.require_finite(omega, "angular_velocities")
    spins = np.zeros((count, 3))
    if dim == 3:
        spins[:] = omega
    else:
        spins[:, 2] = omega
    return spins


def random_spins(moments, dim, kT=1.0, seed=None):
    r"""Angular velocities drawn from the Maxwell distribution at temperature kT: each component of variance kT / I.

    Parameters
    ----------
    moments : array_like, shape (N,)
        Moments of inertia I > 0 (:math:`\kappa m a^2`).
    dim : {2, 3}
        3: three components per sphere, shape (N, 3); 2: the spin of each
        disc about the plane's normal, shape (N,).
    kT : float
        >= 0.
    seed : int or numpy.random.Generator, optional

    Examples
    --------
    >>> from collisionkit.edmd import random_spins
    >>> omega = random_spins(np.full(20000, 0.1), 3, kT=2.0, seed=1)
    >>> omega.shape, round(float(0.1 * np.mean(omega**2)), 1)  # I <omega_k^2> = kT
    ((20000, 3), 2.0)
    """
    moments = _checks.positive(moments, "moments", scalar=False)
    if moments.ndim != 1:
        raise ValueError(f"moments must be a 1-D array of moments of inertia; got shape {moments.shape}")
    kT = _checks.bounded(kT, "kT", 0.0)
    dim = _checks.dimension(dim)
    rng = np.random.default_rng(seed)
    shape = (moments.size, 3) if dim == 3 else (moments.size,)
    scale = np.sqrt(kT / moments)
    return rng.standard_normal(shape) * (scale[:, None] if dim == 3 else scale)


class RoughSpheres:
    """Spins, rotational energy and the roughness of :class:`~collisionkit.edmd.HardSphereSystem` (a mixin)."""

    @property
    def rough(self) -> bool:
        """True if contacts are rough (a tangential restitution was given), so that the particles spin."""
        return bool(self.params[_k.P_INERTIA_FACTOR] != 0.0)

    @property
    def tangential_restitution(self):
        """beta in [-1, 1] of rough spheres, None for smooth ones."""
        return float(self.params[_k.P_TANGENTIAL_RESTITUTION]) if self.rough else None

    @property
    def friction(self):
        """Walton's friction coefficient mu of rough contacts (the Coulomb limit |J_t| <= mu |J_n|), None if none."""
        return float(self.params[_k.P_FRICTION]) if self.params[_k.P_FRICTION] > 0.0 else None

    @property
    def inertia_factor(self):
        """kappa = I / (m a^2) of rough spheres, None for smooth ones."""
        return float(self.params[_k.P_INERTIA_FACTOR]) if self.rough else None

    def moments_of_inertia(self):
        """I = kappa m a^2 per particle, in particle order (rough spheres only).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem
        >>> system = HardSphereSystem([[1.0, 1.0], [1.0, 5.0]], np.zeros((2, 2)), 0.5, 10.0,
        ...                           tangential_restitution=1.0)
        >>> system.moments_of_inertia()  # uniform discs: m a^2 / 2
        array([0.125, 0.125])
        """
        self._require_rough("moments_of_inertia")
        return self.inertia_factor * self.mass * self.radius**2

    def angular_velocities(self):
        """Angular velocities (a copy, particle order): (N, 3) for spheres, (N,) about the plane's normal for discs.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem
        >>> system = HardSphereSystem([[1.0, 1.0], [1.0, 5.0]], np.zeros((2, 2)), 0.5, 10.0,
        ...                           tangential_restitution=1.0, angular_velocities=[1.0, -2.0])
        >>> system.angular_velocities()
        array([ 1., -2.])
        """
        self._require_rough("angular_velocities")
        spins = self._to_user_order(self.spin)
        return spins if self.dim == 3 else spins[:, 2]

    def set_angular_velocities(self, angular_velocities):
        """Replace all angular velocities (the flights do not depend on them: no event changes).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem
        >>> system = HardSphereSystem([[1.0, 1.0], [1.0, 5.0]], np.zeros((2, 2)), 0.5, 10.0,
        ...                           tangential_restitution=1.0)
        >>> system.set_angular_velocities([4.0, 0.0])
        >>> system.rotational_energy()  # I omega^2 / 2 = 0.125 * 16 / 2
        1.0
        """
        self._require_rough("set_angular_velocities")
        self.spin[:] = _spins(angular_velocities, self.count, self.dim)[self.ids]

    def rotational_energy(self) -> float:
        """Total kinetic energy of rotation, sum(I omega^2) / 2 (0 for smooth spheres).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem
        >>> HardSphereSystem([[1.0, 1.0], [1.0, 5.0]], np.zeros((2, 2)), 0.5, 10.0).rotational_energy()
        0.0
        """
        if not self.rough:
            return 0.0
        return float(0.5 * np.sum(self._moments()[:, None] * self.spin**2))

    def rotational_temperature(self) -> float:
        """kT of rotation, 2 E_rot / (f N), f = 3 for spheres and 1 for discs (rough spheres only).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem
        >>> system = HardSphereSystem([[1.0, 1.0], [1.0, 5.0]], np.zeros((2, 2)), 0.5, 10.0,
        ...                           tangential_restitution=1.0, angular_velocities=[4.0, 0.0])
        >>> system.rotational_temperature()  # E_rot = 1 over 2 discs of one degree each
        1.0
        """
        self._require_rough("rotational_temperature")
        return 2.0 * self.rotational_energy() / (rotational_degrees(self.dim) * self.count)

    def total_kinetic_energy(self) -> float:
        """Kinetic energy of translation and rotation: the energy the collisions keep when elastic.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem
        >>> system = HardSphereSystem([[1.0, 1.0], [1.0, 5.0]], [[1.0, 0.0], [0.0, 0.0]], 0.5, 10.0,
        ...                           tangential_restitution=1.0, angular_velocities=[4.0, 0.0])
        >>> system.total_kinetic_energy()
        1.5
        """
        return self.kinetic_energy() + self.rotational_energy()

    def spin_angular_momentum(self):
        """Total spin angular momentum sum(I omega): (3,) for spheres, a number for discs (rough spheres only).

        With the orbital part sum(m x cross v) of unwrapped positions it makes
        the angular momentum each rough collision keeps.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem
        >>> system = HardSphereSystem([[1.0, 1.0], [1.0, 5.0]], np.zeros((2, 2)), 0.5, 10.0,
        ...                           tangential_restitution=1.0, angular_velocities=[4.0, 0.0])
        >>> system.spin_angular_momentum()
        0.5
        """
        self._require_rough("spin_angular_momentum")
        total = (self._moments()[:, None] * self.spin).sum(axis=0)
        return total if self.dim == 3 else float(total[2])

    def _moments(self):
        """I = kappa m a^2 in memory order (the engine's)."""
        return self.inertia_factor * self._mass * self.p[:, _k.R] ** 2

    def _require_rough(self, name):
        if not self.rough:
            raise ValueError(f"{name} needs rough spheres (give tangential_restitution when making the system)")
