"""The hard-sphere (3D) or hard-disc (2D) system an EDMD run advances, event by event.

Particles fly ballistically (parabolas under uniform gravity) between exact
pair collisions, processed one event at a time in time order; collision
times come from the contact quadratic and the collision rule acts along the
line of centres. The numeric work runs in :mod:`collisionkit._kernels.edmd`;
the system keeps the kernels' arrays, with its responsibilities split over
helper modules: construction (``_system_setup``), named views of the
kernels' parameters and totals (``_system_parameters``), the particles as
users see them (``_particle_state``), neighbour lists and cells
(``_neighbour_lists``), checkpoints (``_system_state``), runs in chunks and
the clock (``_system_run``) and the event loop (``_system_events``).
"""

from __future__ import annotations

import math

import numpy as np

from .._kernels import edmd as _k
from .._repr import hard_sphere_system_rows, html_table, number_or_table
from . import _checks, _system_run, _system_setup
from ._cell_crossings import ENGINE_LISTS, CellCrossings
from ._neighbour_lists import NeighbourLists
from ._particle_state import ParticleState
from ._rotation import RoughSpheres, rough_parameters
from ._shear import THERMOSTAT_INTERVAL, ShearFlow, shear_parameters  # noqa: F401 (THERMOSTAT_INTERVAL: as before)
from ._system_events import run_event_loop
from ._system_parameters import SystemParameters
from ._system_setup import RESTITUTION_LAWS
from ._system_run import SORT_INTERVAL
from ._system_state import Checkpoints
from ._wells import SquareWells, well_parameters
from .theory import packing_fraction

__all__ = [
    "DEFAULT_SHELL", "DENSE_PACKING", "DENSE_SHELL", "DILUTE_PACKING", "LIST_NEIGHBOURS", "RESTITUTION_LAWS",
    "SORT_INTERVAL", "HardSphereSystem", "default_shell",
    "OverlapError",
]

# SORT_INTERVAL (collisions per particle between re-sorts in memory by cell) is defined in ._system_run
# neighbour-list shell (skin) in units of the largest diameter; benchmarks/bench_edmd.py --shells tunes it
DEFAULT_SHELL = 0.7
# the shell's default for 3D systems that start at a packing fraction of DENSE_PACKING or more, where a list holds
# more partners per width of shell: 0.6 ran 5-12 % faster than 0.7 at eta = 0.35-0.45 (N = 864-108000), 0.7 faster
# at eta = 0.26 (collisions per CPU second, alternating runs; issue 21). The same defaults serve under shear, whose
# cells no longer grow by the shear margin (benchmarks/bench_edmd_shear.py; issue 19)
DENSE_SHELL = 0.6
DENSE_PACKING = 0.35
# below these packing fractions (discs 2, spheres 3) the default shell of a homogeneous system (no gravity, no
# compression) grows so that a list's ball of radius (1 + shell) diameters holds LIST_NEIGHBOURS particles on
# average: a free path spans many shells there, and rebuilds, not pair tests, dominated (2D eta = 0.01: 26k -> 161k
# collisions per CPU second; 3D eta = 0.02: 38k -> 101k; 2D eta = 0.35: +25 %; 2D eta >= 0.6: -8 %, hence the bound)
LIST_NEIGHBOURS = 10.0
DILUTE_PACKING = {2: 0.5, 3: DENSE_PACKING}


# square wells: the default shell makes a list's ball of radius lambda sigma + shell hold WELL_LIST_NEIGHBOURS
# particles on average, and is at least WELL_MIN_SHELL diameters. Collisions plus edge events per CPU second, lambda
# = 1.5, N = 1372, kT = 1 (shell in diameters: events/s): rho sigma^3 = 0.5: 0.15: 0.57 M, 0.30: 0.75 M, 0.45:
# 0.76 M, 0.70: 0.67 M, 1.05 (the hard spheres' 0.7 of the list diameter): 0.57 M; rho = 0.1: 0.45: 0.63 M, 1.05:
# 0.83 M, 1.5: 0.83 M; rho = 0.8: 0.15: 0.58 M, 0.30: 0.70 M, 0.45: 0.66 M
WELL_LIST_NEIGHBOURS = 15.0
WELL_MIN_SHELL = 0.3


def well_shell(radii, box, width) -> float:
    r"""The default neighbour-list shell of a square-well system, in units of its largest list diameter.

    The shell s (in lengths) whose ball of radius :math:`\lambda \sigma + s`
    holds :math:`K` = :data:`WELL_LIST_NEIGHBOURS` particles on average,
    :math:`s = (K / (n V_1))^{1/d} - \lambda \sigma`, at least
    :data:`WELL_MIN_SHELL` diameters; divided by the list diameter
    :math:`\lambda \sigma`, the unit of ``neighbour_shell`` with wells.

    Examples
    --------
    >>> round(well_shell(np.full(1372, 0.5), np.full(3, 14.0), 1.5), 3)  # n sigma^3 = 0.5: shell 0.43 sigma
    0.285
    """
    radii, box = np.asarray(radii, dtype=float), np.asarray(box, dtype=float)
    dim = box.size
    diameter = 2.0 * float(np.max(radii))
    unit_ball = math.pi if dim == 2 else 4.0 * math.pi / 3.0
    density = radii.size / float(np.prod(box))
    shell = max(WELL_MIN_SHELL * diameter, (WELL_LIST_NEIGHBOURS / (density * unit_ball)) ** (1.0 / dim)
                - width * diameter)
    return shell / (width * diameter)


def default_shell(radii, box, homogeneous=True) -> float:
    r"""The neighbour-list shell a system gets by default, in units of its largest diameter.

    :data:`DENSE_SHELL` for spheres from :data:`DENSE_PACKING`, otherwise
    :data:`DEFAULT_SHELL`, widened in a dilute homogeneous system (packing
    fraction below :data:`DILUTE_PACKING`) to
    :math:`s = (K / (n V_1))^{1/d} / \sigma - 1`, the shell whose ball of
    radius :math:`(1 + s)\sigma` holds :math:`K` = :data:`LIST_NEIGHBOURS`
    particles on average (:math:`V_1` the unit ball's volume, n the number
    density, sigma the largest diameter). Under gravity or compression the
    mean density says little about the local one: no widening.

    Examples
    --------
    >>> from collisionkit.edmd import default_shell
    >>> default_shell(np.full(500, 0.5), np.full(3, 10.0))  # eta = 0.26
    0.7
    >>> round(default_shell(np.full(500, 0.5), np.full(3, 40.0)), 3)  # eta = 0.004: n sigma^3 = 0.0078
    5.736
    """
    radii, box = np.asarray(radii, dtype=float), np.asarray(box, dtype=float)
    dim, packing = box.size, packing_fraction(radii, box)
    if dim == 3 and packing >= DENSE_PACKING:
        return DENSE_SHELL
    if not homogeneous or packing >= DILUTE_PACKING[dim]:
        return DEFAULT_SHELL
    diameter = 2.0 * float(np.max(radii))
    unit_ball = math.pi if dim == 2 else 4.0 * math.pi / 3.0
    density = radii.size / float(np.prod(box))
    return max(DEFAULT_SHELL, (LIST_NEIGHBOURS / (density * unit_ball)) ** (1.0 / dim) / diameter - 1.0)


class OverlapError(ValueError, RuntimeError):
    """Two particles (or a particle and a wall) overlap beyond round-off.

    A ``ValueError`` when the given positions overlap (bad input), and a
    ``RuntimeError`` as well, for :meth:`HardSphereSystem.check` after a run.

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.edmd import HardSphereSystem, OverlapError
    >>> try:
    ...     HardSphereSystem([[1.0, 1.0], [1.5, 1.0]], np.zeros((2, 2)), 0.5, 10.0)
    ... except OverlapError as error:
    ...     print("refused:", error)
    refused: positions overlap: particles 0 and 1, surface gap -0.5
    """


class HardSphereSystem(SystemParameters, ParticleState, NeighbourLists, CellCrossings, Checkpoints, ShearFlow,
                       SquareWells, RoughSpheres):
    """N hard spheres (3D) or discs (2D) in a box, advanced event by event.

    Parameters
    ----------
    positions : array_like, shape (N, d)
        Centres, d = 2 or 3, inside the box [0, L) (for a walled axis the
        whole particle must be inside). No two particles may overlap.
    velocities : array_like, shape (N, d)
    radii : float or array_like, shape (N,)
        > 0.
    box : float or array_like, shape (d,)
        Box lengths L; each periodic axis must hold at least 3 cells of the
        largest contact distance (L >= 3 * max diameter).
    masses : float or array_like, shape (N,), optional
        > 0, default 1.
    periodic : bool or sequence of bool, optional
        Per axis: periodic (True, default) or hard walls at 0 and L.
    species : array_like of int, shape (N,), optional
        Species index per particle (0 .. S-1) for the restitution matrix.
    restitution : float or array_like, shape (S, S), optional
        Coefficient of normal restitution per species pair, in [0, 1]. At 0
        a contact is sticky: the pair's normal approach stops, and the pair
        slides apart along its tangent.
    restitution_law : {"constant", "bridges", "viscoelastic"}
        "bridges": e = min(e_pair, (u_n / law_speed)^(-law_exponent)), the
        law measured for ice at planetary-ring temperatures (Bridges, Hatzes
        & Lin, Nature 309, 333 (1984), exponent 0.234). "viscoelastic":
        e = min(e_pair, e_visco(q)), viscoelastic spheres with
        q = (u_n / law_speed)^(1/5) and 1 - e_visco = q + O(q^2)
        (:mod:`~collisionkit.edmd.restitution_laws`).
    law_speed, law_exponent : float
        Parameters of the laws (law_exponent: Bridges' only).
    elastic_below : float, optional
        Pair contacts and wall bounces with normal approach speed below
        this are elastic: protects inelastic runs against inelastic collapse
        (infinitely many collisions in finite time, which stops a run with a
        RuntimeError), in the spirit of the TC model of Luding & McNamara
        (Granular Matter 1, 113 (1998)). Default: 1e-6 times
        sqrt(<v^2> + |g| L) at the start (the rms speed without gravity; L the
        longest box edge) if a constant restitution of pairs or walls is below
        1, else 0 (elastic systems, and the laws alone, whose contacts turn
        elastic as they slow down).
    wall_restitution : float
        Restitution of particle-wall contacts, in [0, 1]. Below 1 under
        gravity a ball comes to rest on a wall after infinitely many
        bounces: a run stops there with a RuntimeError (a wall collapse).
    gravity : array_like, shape (d,), optional
        Uniform acceleration; flights become exact parabolas.
    neighbour_shell : float, optional
        Skin of the neighbour lists in units of the largest diameter, > 0
        (default 0.7, :data:`DEFAULT_SHELL`; 0.6, :data:`DENSE_SHELL`, for
        spheres starting at a packing fraction of 0.35 or more, the fastest
        at eta = 0.45 in benchmarks/bench_edmd.py; wider in dilute systems
        so that a list holds about 10 particles, :func:`default_shell`; the
        same under shear).
        With square wells the lists reach lambda times the contact distance
        plus the shell, and the shell is in units of that list diameter
        (default: :func:`well_shell`, 0.3-0.45 diameters in liquids).
        A wider shell means longer lists but fewer rebuilds. Only speed
        depends on it; in small periodic boxes it is narrowed so that twice
        the list radius stays below the box.
    shear_rate : float, optional
        Lees-Edwards shear at rate G (default 0: none), flow along x and
        gradient along y: the image boxes at y +- L_y slide along x at
        +- G L_y (Lees & Edwards, J. Phys. C 5, 1921 (1972)). Needs every
        axis periodic, no gravity. The ``velocities`` given are then those
        relative to the flow (peculiar velocities): the system adds the
        streaming velocity G (y - L_y / 2) along x.
    thermostat : float, optional
        Under shear: the kT to which the peculiar velocities are rescaled
        after every ``THERMOSTAT_INTERVAL`` N pair collisions (> 0; default
        None, no thermostat).
        Elastic spheres heat up under shear without one.
    engine : {"auto", "lists", "cells"}, optional
        The event engine. "lists": neighbour lists (any system). "cells":
        cell crossings as events, no lists, for straight flights of fixed
        radii (no gravity, compression or shear); in a dilute gas it makes
        the same trajectory up to round-off 1.2-1.8 times as fast (N = 4000,
        spheres at eta = 0.2-0.1, discs 1.3-1.8 at 0.25-0.05; N = 32000,
        spheres 1.2-1.6). "auto"
        (default) takes "cells" for such systems below the packing fraction
        where the two are level, which falls with N: 0.27 for spheres and
        0.5 for discs up to 32000 particles, 0.22 and 0.28 at 10^6
        (:func:`~collisionkit.edmd._cell_crossings.cells_below_packing`),
        else "lists". The choice is :attr:`engine`.
    well_width : float or array_like, shape (S, S), optional
        Square wells (default None: hard spheres): each pair attracts with
        depth ``well_depth`` from contact out to ``well_width`` times its
        contact distance, lambda in (1, 5]; the potential energy is
        -epsilon per pair inside (:meth:`potential_energy`), conserved with
        the kinetic energy event by event (Alder & Wainwright, J. Chem.
        Phys. 31, 459 (1959)). A symmetric matrix gives lambda per species
        pair. Needs elastic contacts (restitution and wall_restitution 1),
        fixed radii and no shear (the lists engine); gravity is allowed.
    well_depth : float or array_like, shape (S, S), optional
        epsilon > 0 (default 1), in the units of m v^2; a symmetric matrix
        per species pair, >= 0 (0: that pair has no well, only its core).
    tangential_restitution : float, optional
        beta in [-1, 1] of rough spheres (default None: smooth spheres,
        which do not spin). A contact turns the tangential relative velocity
        of the touching surfaces into -beta times itself: -1 is smooth, 1
        perfectly rough (elastic with restitution 1), 0 stops the sliding
        (Huthmann & Zippelius, Phys. Rev. E 56, R6275 (1997)). Not with
        shear, square wells or compression.
    inertia_factor : float, optional
        kappa = I / (m a^2) in (0, 1] of rough spheres: 2/5 (default in 3D)
        for uniform spheres, 1/2 (default in 2D) for uniform discs, 2/3 for
        thin shells.
    angular_velocities : array_like, optional
        Of rough spheres: shape (N, 3) in 3D, (N,) in 2D (about the plane's
        normal); default 0 (:func:`random_spins` draws them at a temperature).
    friction : float, optional
        Walton's Coulomb limit of rough contacts, mu > 0 (default None: no
        limit): the tangential impulse is at most mu times the normal one, so
        a contact either sticks (tangential restitution beta) or slides with
        :math:`1 + \\beta_{eff} = \\mu (1 + e) u_n (1 + 1/\\kappa) / |g_t|`
        (Walton, Mech. Mater. 16, 239 (1993)).

    Examples
    --------
    >>> import numpy as np
    >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
    >>> positions, box = lattice("fcc", 3, 0.3)
    >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(108), 3, seed=1), 0.5, box)
    >>> system.run(collisions=2000)
    2000
    >>> system.check() > -1e-9
    True
    """

    _last_partner = -1  # the partner (memory slot) of the collision the last event call ended at; -1: none

    def __init__(
        self,
        positions,
        velocities,
        radii,
        box,
        masses=1.0,
        periodic=True,
        species=None,
        restitution=1.0,
        restitution_law="constant",
        law_speed=1.0,
        law_exponent=0.234,
        elastic_below=None,
        wall_restitution=1.0,
        gravity=None,
        neighbour_shell=None,
        shear_rate=0.0,
        thermostat=None,
        engine="auto",
        well_width=None,
        well_depth=1.0,
        tangential_restitution=None,
        inertia_factor=None,
        angular_velocities=None,
        friction=None,
        *,
        _growth=0.0,
        _scale=1.0,
    ):
        positions, velocities, radius, self._mass, box, periodic, self._species = _system_setup.checked_particles(
            positions, velocities, radii, masses, box, periodic, species)
        self.dim = positions.shape[1]
        self.restitution, self.params = _system_setup.restitution_parameters(
            self._species, restitution, restitution_law, law_speed, law_exponent, wall_restitution
        )
        self.restitution_law = restitution_law
        gravity = _system_setup.gravity_vector(gravity, self.dim)
        self.geom = _system_setup.geometry(box, periodic, gravity)
        self.params[_k.P_SCALE0] = float(_scale)
        self.params[_k.P_GROWTH] = float(_growth)
        _system_setup.start_records(self, positions, velocities, radius, box, periodic)
        rough_parameters(self, tangential_restitution, inertia_factor, angular_velocities,
                         {"shear": shear_rate != 0.0, "square wells": well_width is not None,
                          "compression": _growth != 0.0 or _scale != 1.0}, friction)
        if elastic_below is None:
            elastic_below = _system_setup.default_elastic_below(self.restitution, velocities,
                                                                self.params[_k.P_WALL_RESTITUTION], gravity, box)
        self.params[_k.P_ELASTIC_BELOW] = _checks.bounded(elastic_below, "elastic_below", 0.0)
        shear_parameters(self, shear_rate, thermostat)
        well_parameters(self, well_width, well_depth, _growth, self.shear_rate, engine)
        if neighbour_shell is None and self.well_width is not None:
            neighbour_shell = well_shell(radius * float(_scale), box, float(self.params[_k.P_WELL_WIDTH]))
        elif neighbour_shell is None:
            homogeneous = _growth == 0.0 and not np.any(gravity)
            neighbour_shell = default_shell(radius * float(_scale), box, homogeneous)
        self._shell_request = _checks.positive(neighbour_shell, "neighbour_shell")
        if self.shear_rate != 0.0:
            self._add_streaming()
        self._engine_code = _system_setup.engine_choice(engine, radius, box, periodic, gravity, _growth, _scale,
                                                        self.shear_rate)
        if self.well_width is not None:
            self._engine_code = ENGINE_LISTS  # the cell-crossing engine has no wells ("cells" was refused)
        _system_setup.allocate_engine_arrays(self)
        self._start_wells()
        self._refresh_lists()
        _system_setup.check_walls(self)
        gap = self._sheared_gap() if self.shear_rate != 0.0 else self._pair_gap()
        if gap < -1e-9 * float(np.max(radius)):
            raise OverlapError(f"positions overlap: {_system_setup.closest_pair_description(self, gap)}")

    # -------------------------------------------------------------- the clock and the invariant

    def synchronise(self):
        """Move every particle to the current time and restart the clock at 0.

        Keeping event times small keeps their round-off small; the total
        simulated time is kept in ``elapsed``.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> _ = system.run(collisions=500)
        >>> system.synchronise()
        >>> system.time, system.elapsed > 0
        (0.0, True)
        """
        _system_run.restart_clock(self)

    def check(self, tolerance=1e-9):
        """Verify the invariant: no overlaps between particles or with walls.

        Returns the smallest surface gap (negative only within round-off);
        raises :class:`OverlapError` if any gap is below ``-tolerance`` times
        the largest radius.

        Parameters
        ----------
        tolerance : float
            Allowed overlap relative to the largest radius, finite and >= 0.

        Returns
        -------
        float

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> _ = system.run(collisions=5000)
        >>> system.check() > -1e-12
        True
        """
        tolerance = _checks.bounded(tolerance, "tolerance", 0.0)
        self.synchronise()
        gap = self._sheared_gap() if self.shear_rate != 0.0 else self._pair_gap()
        if not np.all(self.periodic):
            gap = min(gap, _k.wall_gap(self.p, self.scale, self.geom, self.dim))
        if gap < -tolerance * float(np.max(self.radius)):
            raise OverlapError(f"overlap of {-gap:.3g} found at time {self.elapsed + self.time:.6g}")
        self._check_anchor_drift(tolerance)
        self._check_wells(tolerance)
        return gap

    def _time_to_next_event(self):
        """Time from now (particles synchronised) to the next queued event; inf if none.

        Until then every particle flies freely: no collision can come earlier
        (the queue holds each particle's earliest, list events included).
        """
        return float(self.tree[1, 0]) - self.time

    def _stop_growing(self, scale):
        """End a compression: radii fixed at ``scale`` from now on (lists rebuilt)."""
        self.synchronise()
        self.params[_k.P_GROWTH] = 0.0
        self.params[_k.P_SCALE0] = scale
        self._refresh_lists()

    # -------------------------------------------------------------- running

    def run(self, collisions=None, time=None, progress=None, chunk=None):
        """Advance by a number of pair collisions and/or a stretch of time.

        Parameters
        ----------
        collisions : int, optional
            Pair collisions to process, >= 0.
        time : float, optional
            Simulated time to advance, finite and >= 0 (the run stops at
            whichever comes first).
        progress : callable, optional
            Called as ``progress(fraction)`` after each chunk, with the
            fraction of the requested collisions (or time, whichever is the
            larger share) done so far, in [0, 1].
        chunk : int, optional
            Collisions between progress reports, >= 1 (default: max(N,
            10^5)); Ctrl-C stops a run within a fraction of a second.

        Returns
        -------
        int
            Pair collisions processed (fewer than asked if every particle
            came to rest).

        Raises
        ------
        RuntimeError
            If the run cannot go on, with the cause: a collapse (infinitely
            many collisions in finite time), or no pair can collide.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> system.run(collisions=1000)
        1000
        >>> system.run(time=0.5) > 0, round(system.elapsed, 12) > 0
        (True, True)
        """
        return _system_run.advance(self, collisions, time, progress, chunk)

    def _run_until(self, collisions, elapsed):
        """Process events until ``collisions`` more pair collisions or the total time ``elapsed``: the collisions made.

        The core of :meth:`run` without its checks, progress and
        synchronisation: the stretches between the grid times of a transport
        measurement (a system neither growing nor walled; the particles stay
        at their own times). Re-sorts and grows overflowed rows as
        :meth:`run` does.
        """
        return _system_run.run_until(self, collisions, elapsed)

    def compile_event_loop(self):
        """Compile the event loop now (numba compiles at the first call), so that a timed run times only events.

        A run of no collisions: the state does not change. Takes seconds on
        a cold numba cache, a fraction of one when the cache is warm.

        Examples
        --------
        >>> import numpy as np
        >>> from collisionkit.edmd import HardSphereSystem, lattice, maxwell_boltzmann
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> system.compile_event_loop()
        >>> system.collisions, system.elapsed
        (0, 0.0)
        """
        self._run_events(0, self.time)

    def _run_events(self, collisions, t_stop):
        """Process events until ``collisions`` pair collisions or time ``t_stop``; return the time reached."""
        return run_event_loop(self, collisions, t_stop)

    def __repr__(self):
        kind = "spheres" if self.dim == 3 else "discs"
        return (
            f"HardSphereSystem({self.count} {kind}, eta={self.packing_fraction:.4f}, "
            + (f"well_width={number_or_table(self.well_width)}, well_depth={number_or_table(self.well_depth)}, "
               if self.well_width is not None else "")
            + f"collisions={self.collisions}, time={self.elapsed + self.time:.6g})"
        )

    def _repr_html_(self):
        return html_table("HardSphereSystem", hard_sphere_system_rows(self, self.packing_fraction))
