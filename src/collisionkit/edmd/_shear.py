r"""Lees-Edwards shear of a :class:`~collisionkit.edmd.HardSphereSystem`: the flow, its images, its thermostat.

Homogeneous shear at rate G, flow along x and gradient along y (Lees &
Edwards, J. Phys. C 5, 1921 (1972); Allen & Tildesley, Computer Simulation
of Liquids, 2nd ed., sec. 11.3): the image boxes at y +- L_y slide along x
at +- G L_y, so the streaming velocity :math:`u_x(y) = G (y - L_y/2)` is
continuous through the images and the particles' velocities relative to it,
the peculiar velocities :math:`c = v - u(y)`, are what the temperature
measures. The event loop keeps the engine's exactness (see
:mod:`collisionkit._kernels.edmd.motion`): flights are straight, a pair
meeting across a y face meets the partner's sliding image, with that
image's velocity.

The balance of the peculiar kinetic energy :math:`E = \sum \tfrac12 m c^2`
is exact event by event: between events :math:`dE/dt = -G \sum m c_x c_y`,
at a collision :math:`\Delta E = -\Delta E_{lost} - G\,\Delta p_{j,x} r_y`
(the impulse on j times the separation across the pair), so over any
stretch of time

.. math:: \Delta E + E_{lost} + E_{thermostat} = -G V \int P_{xy}\,dt ,

with :math:`P_{xy}` the xy element of the pressure tensor, kinetic plus
collisional. Hence the shear viscosity at rate G,
:math:`\eta = -\langle P_{xy}\rangle / G`, from energies the engine keeps
exactly; the collisional part alone is the engine's collisional stress sum.

The temperature the stress was measured at is the time average of kT, not
its value at the end: between two rescalings of the thermostat the flow's
work heats the fluid (kT doubles over an interval at
:math:`a^* = G/\nu \approx 0.17` in a disc fluid at packing fraction 0.3).
:func:`run_sheared` samples the peculiar energy every half interval
(``THERMOSTAT_INTERVAL N / 2`` pair collisions, with and without a
thermostat), just before and just after every rescaling and at the end,
and integrates E(t) piecewise over quadratics through three samples
(:func:`quadratic_area`): exact if E(t) is quadratic between rescalings,
as it is when the heating grows as :math:`\sqrt{E}` (a viscosity
:math:`\propto \sqrt{kT}`). The trapezoid of the values just after and
just before each rescaling is not enough: E(t) is convex there (the stress
lags behind the rescaled temperature), and in the disc fluid above it puts
the mean kT 3.7-3.8 % too high, against 0.1-0.3 % for the quadratics (both
against a sampling every 0.01 time units of the same trajectory, tested).
"""

from __future__ import annotations

import math

import numpy as np

from .._kernels import edmd as _k
from . import _checks

# the thermostat rescales after every THERMOSTAT_INTERVAL N pair collisions (8 per particle, some 4 mean free times:
# re-predicting every event costs about what N collisions do, so rescaling after every N cost 25 % of a run)
THERMOSTAT_INTERVAL = 4


def shear_parameters(system, shear_rate, thermostat):
    """Check the shear rate and thermostat of a new system and store them in its parameters.

    The shear needs every axis periodic, no gravity and no growth of the
    radii; the thermostat (a kT > 0) needs a shear rate.
    """
    rate = _checks.bounded(shear_rate, "shear_rate", 0.0)
    if thermostat is not None:
        thermostat = _checks.positive(thermostat, "thermostat")
        if rate == 0.0:
            raise ValueError("thermostat needs a shear_rate: it holds a sheared system at kT (an unsheared elastic "
                             "system keeps its temperature without one)")
    if rate != 0.0:
        if not np.all(system.periodic):
            raise ValueError("shear_rate needs every axis periodic (Lees-Edwards images); got walls on axes "
                             f"{np.flatnonzero(~system.periodic).tolist()}")
        if np.any(system.geom[_k.G_GRAVITY] != 0.0):
            raise ValueError("shear_rate cannot be combined with gravity (the flights under shear are straight)")
        if system.growth != 0.0:
            raise ValueError("shear_rate cannot be combined with growing radii (compress first, then shear)")
    system.params[_k.P_SHEAR_RATE] = rate
    system.params[_k.P_THERMOSTAT] = 0.0 if thermostat is None else thermostat


class ShearFlow:
    """Lees-Edwards shear of :class:`~collisionkit.edmd.HardSphereSystem` (a mixin): offsets, peculiar velocities.

    It reads the system's records, box, clock and parameters, and owns the
    shear entries of ``params`` and the thermostat slot of ``acc``.
    """

    @property
    def shear_rate(self) -> float:
        """The shear rate G (0: no shear): the image boxes at y +- L_y slide along x at +- G L_y.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box, shear_rate=0.1)
        >>> system.shear_rate
        0.1
        """
        return float(self.params[_k.P_SHEAR_RATE])

    @property
    def thermostat(self) -> float | None:
        """The kT the peculiar velocities of a sheared system are rescaled to (None: no thermostat)."""
        value = float(self.params[_k.P_THERMOSTAT])
        return value if value > 0.0 else None

    @property
    def thermostat_energy(self) -> float:
        """Kinetic energy the thermostat has removed so far (negative if it added energy)."""
        return float(self.acc[_k.ACC_THERMOSTAT])

    @property
    def shear_offset(self) -> float:
        """x offset of the image box above now: G L_y t modulo L_x (t the time sheared so far).

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box, shear_rate=0.1)
        >>> _ = system.run(time=2.0)
        >>> bool(np.isclose(system.shear_offset, 0.1 * box[1] * 2.0 % box[0]))
        True
        """
        return float(self._offset_at(self.time) % self.box[0])

    def _offset_at(self, t):
        return self.params[_k.P_SHEAR_OFFSET] + self.params[_k.P_SHEAR_RATE] * self.box[1] * t

    def _shear_clock(self, shift):
        """The clock restarts ``shift`` later (see ``synchronise``): carry over the offset, frame and lists' times."""
        if self.params[_k.P_SHEAR_RATE] != 0.0:
            self.params[_k.P_SHEAR_OFFSET] = float(self._offset_at(shift) % self.box[0])
            self.params[_k.P_SHEAR_SWEEP] -= shift
            self.params[_k.P_SHEAR_FRAME] -= shift
            self.anchor_time -= shift

    def _start_shear_frame(self):
        """Before all lists are built anew (shell set): the flow's frame starts now, its first sweep a strain later.

        The anchors are kept in the frame that moves with the flow (see
        :mod:`collisionkit._kernels.edmd.neighbour_lists`); the largest list
        radius R sets how fast a list's age spends its shell.
        """
        rate = self.params[_k.P_SHEAR_RATE]
        if rate != 0.0:
            self.params[_k.P_SHEAR_FRAME] = self.time
            self.params[_k.P_SHEAR_SWEEP] = self.time + _k.SHEAR_SWEEP_STRAIN / abs(rate)
            largest = 2.0 * float(np.max(self.p[:, _k.R])) * self.params[_k.P_LIST_SCALE]
            self.params[_k.P_SHEAR_REACH] = largest + self.params[_k.P_SHELL] + self.neighbour_list_slack

    def _streaming(self, y):
        """Streaming velocity along x at heights y (stored, any image): G (y - L_y / 2)."""
        return self.params[_k.P_SHEAR_RATE] * (y - 0.5 * self.box[1])

    def _peculiar(self):
        """Peculiar velocities of the stored records (synchronised), memory order: the same for every image."""
        velocities = self.vel.copy()
        velocities[:, 0] -= self._streaming(self.pos[:, 1])
        return velocities

    def _add_streaming(self):
        """Turn the stored velocities (taken as peculiar) into lab velocities: add the streaming velocity."""
        self.p[:, _k.V] += self._streaming(self.p[:, _k.X + 1])

    def _sheared_folded(self, ahead=0.0):
        """Positions folded into the box under shear (y first, x shifted by the offset), the image counters, v_x shifts.

        Returns ``(positions, image, slide)``: a particle folded down
        through y = L_y is its image there, shifted back along x by the
        offset and slower along x by G L_y (``slide``, add it to v_x).
        """
        pos = self.pos + self.vel * ahead
        image = self._image.copy()
        ly = self.box[1]
        across = np.floor(pos[:, 1] / ly)
        pos[:, 1] -= across * ly
        rounded = pos[:, 1] >= ly
        pos[rounded, 1] = 0.0
        across[rounded] = 0.0  # -tiny + L rounds to L: back at 0, no move to another image
        pos[:, 0] -= across * self._offset_at(self.time + ahead)
        image[:, 1] += across.astype(np.int64)
        for k in range(0, self.dim, 2):
            length = self.box[k]
            shift = np.floor(pos[:, k] / length)
            pos[:, k] -= shift * length
            image[:, k] += shift.astype(np.int64)
            up = pos[:, k] >= length
            pos[up, k] = 0.0
        slide = -across * self.params[_k.P_SHEAR_RATE] * ly
        return pos, image, slide

    def peculiar_velocities(self):
        """Velocities relative to the shear flow, c = v - G (y - L_y / 2) e_x, now (particle order).

        Without shear, the velocities.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> thermal = maxwell_boltzmann(np.ones(100), 2, seed=1)
        >>> system = HardSphereSystem(positions, thermal, 0.5, box, shear_rate=0.5)
        >>> bool(np.allclose(system.peculiar_velocities(), thermal))
        True
        """
        self.synchronise()
        return self._to_user_order(self._peculiar())

    def _apply_thermostat(self):
        """Rescale the peculiar velocities (synchronised system) to the thermostat's kT; re-predict every event.

        The energy removed is added to ``thermostat_energy``. Only the
        velocities relative to the flow change, so the flow itself and the
        positions stay as they are.
        """
        peculiar = self._peculiar()
        energy = 0.5 * float(np.sum(self._mass[:, None] * peculiar**2))
        if energy == 0.0:
            return
        target = 0.5 * self.dim * self.count * self.params[_k.P_THERMOSTAT]
        factor = math.sqrt(target / energy)
        streaming = self.vel.copy()
        streaming[:, 0] -= peculiar[:, 0]
        streaming[:, 1:] = 0.0
        self.p[:, _k.V : _k.V + self.dim] = streaming + factor * peculiar
        self.acc[_k.ACC_THERMOSTAT] += energy - 0.5 * float(np.sum(self._mass[:, None] * (factor * peculiar) ** 2))
        self._predict_all()

    def _thermostat_due_in(self) -> int:
        """Pair collisions until the next rescaling: after every THERMOSTAT_INTERVAL N (a fixed grid of the count)."""
        interval = THERMOSTAT_INTERVAL * self.count
        return interval - self.collisions % interval

    def _sheared_gap(self):
        """Smallest surface gap under shear (synchronised), from a k-d tree over the nearest images."""
        from scipy.spatial import cKDTree

        dim = self.dim
        points, _, _ = self._sheared_folded()
        radii = self.p[:, _k.R] * self.scale
        reach = 2.0 * float(radii.max()) + self.neighbour_shell_width
        box = self.box[:dim]
        offset = (self._offset_at(self.time) + 0.5 * box[0]) % box[0] - 0.5 * box[0]
        copies, owners = [], []
        shifts = np.array(np.meshgrid(*[[-1, 0, 1]] * dim, indexing="ij")).reshape(dim, -1).T
        for shift in shifts:
            image = points + shift * box
            image[:, 0] += shift[1] * offset
            copies.append(image)
            owners.append(np.arange(self.count))
        images, owners = np.concatenate(copies), np.concatenate(owners)
        pairs = cKDTree(points).query_ball_tree(cKDTree(images), reach)
        gap = math.inf
        for i, near in enumerate(pairs):
            near = np.asarray(near, dtype=np.int64)
            near = near[owners[near] != i]
            if near.size:
                distance = np.linalg.norm(images[near] - points[i], axis=1)
                gap = min(gap, float(np.min(distance - radii[i] - radii[owners[near]])))
        return gap


def quadratic_area(times, values) -> float:
    """Integral of a smooth curve through samples ``(times, values)``: over quadratics through three samples.

    Composite Simpson's rule for uneven steps: each pair of steps under the
    parabola through its three samples; with an odd number of steps the last
    one under the parabola through the last three samples; one step, the
    trapezoid; one sample, 0. Exact for quadratics.

    Examples
    --------
    >>> round(quadratic_area([0.0, 0.3, 1.0, 1.5], [0.0, 0.09, 1.0, 2.25]), 12)  # t^2 from 0 to 1.5
    1.125
    """
    t = np.asarray(times, dtype=float)
    f = np.asarray(values, dtype=float)
    steps = len(t) - 1
    if steps < 1:
        return 0.0
    if steps == 1:
        return float(0.5 * (f[0] + f[1]) * (t[1] - t[0]))
    area = 0.0
    for first in range(0, steps - 1, 2):
        area += _parabola_area(t[first : first + 3], f[first : first + 3], t[first], t[first + 2])
    if steps % 2:
        area += _parabola_area(t[-3:], f[-3:], t[-2], t[-1])
    return float(area)


def _parabola_area(t, f, low, high):
    """Integral from ``low`` to ``high`` of the parabola through three samples (times apart)."""
    h0, h1 = t[1] - t[0], t[2] - t[1]
    # Newton's form about t0: f0 + d1 s + d2 s (s - h0), s = t - t0
    d1 = (f[1] - f[0]) / h0
    d2 = ((f[2] - f[1]) / h1 - d1) / (h0 + h1)

    def antiderivative(s):
        return f[0] * s + 0.5 * d1 * s * s + d2 * (s**3 / 3.0 - 0.5 * h0 * s * s)

    return antiderivative(high - t[0]) - antiderivative(low - t[0])


def run_sheared(system, collisions, progress=None):
    r"""Run a sheared system ``collisions`` pair collisions; return the time integral of its peculiar kinetic energy.

    The run stops every half thermostat interval (``THERMOSTAT_INTERVAL N
    / 2`` pair collisions, on the grid of the collision count, whose every
    other point is a rescaling) to sample E; each stretch between
    rescalings is integrated with :func:`quadratic_area` from the energy
    just after the last rescaling (or the start) to the energy just before
    the next (the energy after plus what the thermostat removed) or the end.
    ``progress(fraction)`` reports the fraction of ``collisions`` done.

    Returns
    -------
    float
        :math:`\int E\,dt` over the run (divide by the time it took and
        :math:`dN/2` for the mean kT).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
    >>> positions, box = lattice("square", 8, 0.3)
    >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(64), 2, seed=1), 0.5, box, shear_rate=0.5,
    ...                           thermostat=1.0)
    >>> start = system.elapsed
    >>> area = run_sheared(system, 2560)
    >>> kT = area / (system.elapsed - start) / 64   # E = N kT for discs
    >>> 1.2 < kT < 1.7   # kT = 1 after each rescaling, about 2 before the next
    True
    """
    interval = THERMOSTAT_INTERVAL * system.count
    grid = max(interval // 2, 1)
    times, energies = [system.elapsed], [system.kinetic_energy()]
    area, done = 0.0, 0
    while done < collisions:
        step = min(collisions - done, grid - system.collisions % grid)
        removed = system.thermostat_energy
        report = None if progress is None else (
            lambda fraction, done=done, step=step: progress((done + fraction * step) / collisions))
        made = system.run(collisions=step, progress=report)
        done += made
        energy = system.kinetic_energy()
        removed = system.thermostat_energy - removed
        if system.elapsed == times[-1]:
            energies[-1] = energy + removed  # no time passed: the latest value holds (a jump of zero width)
        else:
            times.append(system.elapsed)
            energies.append(energy + removed)
        if system.thermostat is not None and made > 0 and system.collisions % interval == 0:
            area += quadratic_area(times, energies)  # the stretch ends just before the rescaling
            times, energies = [system.elapsed], [energy]
        if made < step:
            break  # nothing left to happen
    return area + quadratic_area(times, energies)
