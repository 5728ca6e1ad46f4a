"""Measurement of an EDMD run: block averages of the pressure, collision rate, g(r) and diffusion.

:class:`Sampler` runs a system block by block and records what each block
gives (resumable from a checkpoint); :func:`measure` runs it to the end;
:class:`Measurement` holds the results with their standard errors. What a
block records and what the records give are in ``_sampler_records``, the
sampler's checkpoint arrays in ``_sampler_state``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from time import perf_counter

import numpy as np

from .._kernels import edmd as _k
from .._repr import html_table, measurement_rows
from . import _checks, _msd, _pair_distribution
from ._sampler_records import (
    HOMOGENEITY_RECORDS, MIXTURE_RECORDS, RECORDS, ROUGH_RECORDS, SHEAR_RECORDS, block_rows, block_start,
    homogeneity_measurable, observables, record_block,
)
from ._sampler_state import restore_sampler, sampler_arrays
from ._shear import run_sheared
from ._transport import TransportMeasurement, TransportSampler
from .homogeneity import homogeneity_summary
from .system import HardSphereSystem

__all__ = ["RECORDS", "SHEAR_RECORDS", "Measurement", "Sampler", "measure"]

# RECORDS (what the sampler records at the end of each block) and SHEAR_RECORDS (and under shear) are defined in
# ._sampler_records
# PARTIAL_RDF_SPECIES (the most species whose partial g(r) a sampler records) is defined in ._pair_distribution
PARTIAL_RDF_SPECIES = _pair_distribution.PARTIAL_RDF_SPECIES


@dataclass
class Measurement:
    r"""Observables of an EDMD run, block averaged; each ``*_error`` is one standard error.

    Attributes: ``compressibility_factor``, ``pressure``, ``temperature``
    (final kT), ``temperature_mean`` (the time average of kT over the
    measurement, with its error: what the pressure, Z and, under shear, the
    stress were measured at; see below), ``collision_frequency`` (per particle, each pair collision
    counting for both), ``mean_free_time``, ``mean_free_path``,
    ``diffusion_coefficient`` (from the mean squared displacement with
    every block end as a time origin, lags up to ``blocks // 2`` blocks, at
    most 8; its error from the scatter of 8 groups of particles,
    ``_msd.MSD_GROUPS``, since overlapping origins give no independent blocks),
    ``energy_lost``, ``contact_value`` (g at contact; NaN with fewer than
    ``_pair_distribution.MIN_CONTACT_PAIRS`` pairs near contact over the
    snapshots, as are the partial ones, and for unlike diameters, whose
    pairs touch at several distances: a mixture of up to 4 species has
    ``partial_rdf`` [a, b] over ``rdf_r``, g_ab(r), and ``contact_values``
    g_ab(r_a + r_b) with ``contact_values_error``; any mixture ``species_diffusion``,
    each species' D with its ``species_diffusion_error``, and
    ``species_temperatures``, each species' kT over the mixture's, T_a / T,
    the block mean of its value at each block's end, with
    ``species_temperatures_error`` and ``block_species_temperatures`` each
    block's: 1 at equipartition, which an inelastic mixture does not reach), ``cooling_rate`` (a gas that loses energy, at
    rest and without gravity: -d ln kT / dC, C the collisions per particle,
    the mean of the blocks' -ln(kT_k / kT_k-1) / dC after the first, with ``cooling_rate_error``;
    Haff's law gives (1 - e^2) / d for one species; else NaN; at rest in a
    periodic box without gravity ``block_shear_mode_energy`` is each block
    end's :func:`~collisionkit.edmd.shear_mode_energy`, about 1 for
    uncorrelated velocities, and :meth:`summary` adds, for a gas that lost
    energy, :func:`~collisionkit.edmd.homogeneity.homogeneity_summary`'s
    keys against uncorrelated velocities), ``sonine_a2``
    (particles of one mass at rest: the velocity distribution's fourth
    cumulant d/(d+2) <v^4>/<v^2>^2 - 1 at the block ends, 0 for Maxwell's,
    with ``sonine_a2_error``), ``potential_energy``
    (square wells: the time average of the potential energy per particle,
    -epsilon times the pairs inside per particle, with its error; 0 for hard
    spheres; ``temperature_mean`` is then the exact time average of kT,
    which Z and the pressure use); arrays ``speeds`` (a
    sample), ``rdf_r``, ``rdf`` (g(r)), ``msd_time``, ``msd``, ``block_*`` per
    block; ``wall_seconds`` is the wall clock of the measurement (events and
    sampling, not compiling), so ``collisions_per_second`` is the rate a run
    of this size delivers. ``transport``: the transport coefficients
    (:class:`~collisionkit.edmd.TransportMeasurement`) of a measurement
    asked for them, else None. Under shear (``shear_rate`` > 0):
    ``shear_stress`` (the block mean of P_xy, kinetic plus collisional),
    ``collisional_shear_stress`` (its collisional part) and
    ``shear_viscosity`` = -P_xy / G, each with its error; the diffusion
    coefficient is then the transverse one, from the displacements along y
    (the gradient) and z (the vorticity) alone, (D_yy + D_zz) / 2 in 3D and
    D_yy in 2D: along x the flow carries the particles (Taylor dispersion,
    the displacement grows as t^3). Under shear ``temperature_mean`` is the
    time integral of the kinetic energy sampled every half thermostat
    interval (:func:`~collisionkit.edmd._shear.run_sheared`: the viscous
    heating raises kT between the thermostat's rescalings, so the final kT
    is not the one the stress was measured at), ``thermostat_energy`` the
    energy the thermostat removed and ``viscous_heating`` the work of the
    flow, :math:`-G V \int P_{xy} dt`, over the measurement; without shear
    each block's mean kT is the mean of its first and last (exact when
    elastic).

    Examples
    --------
    >>> from collisionkit.edmd import henderson, measure, random_fluid
    >>> m = measure(random_fluid(2, 400, 0.3, seed=2), collisions=40_000, blocks=4)
    >>> abs(m.compressibility_factor - float(henderson(0.3))) < 5 * m.compressibility_factor_error + 0.05
    True
    """

    dim: int
    particles: int
    packing_fraction: float
    collisions: int
    time: float
    wall_seconds: float
    temperature: float
    compressibility_factor: float
    compressibility_factor_error: float
    pressure: float
    pressure_error: float
    collision_frequency: float
    collision_frequency_error: float
    mean_free_time: float
    mean_free_time_error: float
    mean_free_path: float
    mean_free_path_error: float
    mean_speed: float
    diffusion_coefficient: float
    diffusion_coefficient_error: float
    energy_lost: float
    contact_value: float
    contact_value_error: float
    speeds: np.ndarray = field(repr=False)
    rdf_r: np.ndarray = field(repr=False)
    rdf: np.ndarray = field(repr=False)
    msd_time: np.ndarray = field(repr=False)
    msd: np.ndarray = field(repr=False)
    block_temperature: np.ndarray = field(repr=False)
    block_compressibility: np.ndarray = field(repr=False)
    block_frequency: np.ndarray = field(repr=False)
    transport: TransportMeasurement | None = field(default=None, repr=False)
    shear_rate: float = 0.0
    shear_stress: float = math.nan
    shear_stress_error: float = math.nan
    collisional_shear_stress: float = math.nan
    collisional_shear_stress_error: float = math.nan
    shear_viscosity: float = math.nan
    shear_viscosity_error: float = math.nan
    temperature_mean: float = math.nan
    temperature_mean_error: float = math.nan
    block_temperature_mean: np.ndarray | None = field(default=None, repr=False)
    thermostat_energy: float = math.nan
    viscous_heating: float = math.nan
    potential_energy: float = 0.0
    potential_energy_error: float = 0.0
    partial_rdf: np.ndarray | None = field(default=None, repr=False)
    species_diffusion: np.ndarray | None = field(default=None, repr=False)
    species_diffusion_error: np.ndarray | None = field(default=None, repr=False)
    contact_values: np.ndarray | None = field(default=None, repr=False)
    contact_values_error: np.ndarray | None = field(default=None, repr=False)
    cooling_rate: float = math.nan
    cooling_rate_error: float = math.nan
    sonine_a2: float = math.nan
    sonine_a2_error: float = math.nan
    species_temperatures: np.ndarray | None = field(default=None, repr=False)
    species_temperatures_error: np.ndarray | None = field(default=None, repr=False)
    block_species_temperatures: np.ndarray | None = field(default=None, repr=False)
    temperature_ratio: float = math.nan
    temperature_ratio_error: float = math.nan
    block_temperature_ratio: np.ndarray | None = field(default=None, repr=False)
    block_shear_mode_energy: np.ndarray | None = field(default=None, repr=False)
    block_sonine_a2: np.ndarray | None = field(default=None, repr=False)

    @property
    def collisions_per_second(self) -> float:
        return self.collisions / self.wall_seconds if self.wall_seconds > 0 else math.inf

    def summary(self) -> dict:
        """Scalars as a JSON-ready dict.

        Examples
        --------
        >>> from collisionkit.edmd import measure, random_fluid
        >>> summary = measure(random_fluid(2, 200, 0.3, seed=1), collisions=4000, blocks=2).summary()
        >>> summary["collisions"], "compressibility_factor" in summary
        (4000, True)
        """
        keys = (
            "dim particles packing_fraction collisions time temperature compressibility_factor "
            "compressibility_factor_error pressure pressure_error collision_frequency collision_frequency_error "
            "mean_free_time mean_free_time_error mean_free_path mean_free_path_error mean_speed diffusion_coefficient "
            "diffusion_coefficient_error energy_lost contact_value contact_value_error"
        ).split()
        result = {key: getattr(self, key) for key in keys}
        result["collisions_per_second"] = self.collisions_per_second
        if self.shear_rate != 0.0:
            result |= {key: getattr(self, key) for key in (
                "shear_rate", "shear_stress", "shear_stress_error", "collisional_shear_stress",
                "collisional_shear_stress_error", "shear_viscosity", "shear_viscosity_error", "temperature_mean",
                "temperature_mean_error", "thermostat_energy", "viscous_heating")}
        if self.potential_energy != 0.0 or self.potential_energy_error != 0.0:
            result |= {key: getattr(self, key) for key in (
                "potential_energy", "potential_energy_error", "temperature_mean", "temperature_mean_error")}
        if math.isfinite(self.cooling_rate):
            result |= {"cooling_rate": self.cooling_rate, "cooling_rate_error": self.cooling_rate_error}
        if self.block_shear_mode_energy is not None and self.energy_lost > 0:  # a cooling gas: still homogeneous?
            per_block = 2.0 * self.collisions / (self.particles * self.block_shear_mode_energy.size)
            result |= homogeneity_summary(self.block_shear_mode_energy, self.dim, self.particles, per_block)
        if math.isfinite(self.sonine_a2):
            result |= {"sonine_a2": self.sonine_a2, "sonine_a2_error": self.sonine_a2_error}
        if self.block_temperature_ratio is not None:
            result |= {"temperature_ratio": self.temperature_ratio,
                       "temperature_ratio_error": self.temperature_ratio_error}
        if self.transport is not None:
            result |= {"self_diffusion": self.diffusion_coefficient,
                       "self_diffusion_error": self.diffusion_coefficient_error} | self.transport.summary()
        return result

    def block_table(self) -> list[dict]:
        """A row per block: ``block``, ``collisions_per_particle`` C and ``time`` at its end, each ``block_*``
        series (kT at the end, its mean, Z, the collision frequency, a2, T_r / T, the shear modes' energy,
        each species' T_a / T as ``species_temperatures[a]``, ...) and the MSD; ``collisionkit edmd`` writes it
        as ``blocks.csv``.

        Examples
        --------
        >>> from collisionkit.edmd import measure, random_fluid
        >>> rows = measure(random_fluid(2, 100, 0.2, seed=1), collisions=2000, blocks=4).block_table()
        >>> [key for key in rows[0]][:5]
        ['block', 'collisions_per_particle', 'time', 'temperature', 'compressibility']
        """
        return block_rows(self)

    def _repr_html_(self):
        return html_table("Measurement", measurement_rows(self))


class Sampler:
    r"""Block-by-block measurement of an EDMD run, resumable from a checkpoint.

    Each block runs ``collisions // blocks`` pair collisions, then records:
    kT = 2K/(dN); the compressibility factor from the collisional virial,
    :math:`Z = 1 + \sum_{coll} J\sigma / (d N kT\,t)` (J the impulse, sigma
    the contact distance; Allen & Tildesley, Computer Simulation of Liquids,
    2nd ed., sec. 3.7); the collision frequency per particle
    :math:`\omega = 2 C / (N t)`; speeds; pair distances for g(r); and the
    mean squared displacement, from the start and from the earlier block ends
    as time origins (it keeps up to 8 copies of the positions for them, 24 MB
    per copy at 10^6 spheres). Errors are standard errors of the block means
    (of groups of particles for the diffusion coefficient).

    Parameters
    ----------
    system : HardSphereSystem
    collisions : int
        Pair collisions over all blocks, >= blocks.
    blocks : int
        Number of blocks, >= 2.
    rdf_bins : int
        Bins of g(r) up to min(L/2, 5 diameters).
    transport : bool
        Also measure the transport coefficients: each block runs in
        stretches of a grid interval, sampling the Helfand moments and the
        velocities (:class:`~collisionkit.edmd._transport.TransportSampler`;
        the system must be periodic and elastic).

    Examples
    --------
    >>> from collisionkit.edmd import Sampler, random_fluid
    >>> system = random_fluid(3, 300, 0.3, seed=1)
    >>> sampler = Sampler(system, collisions=30_000, blocks=3)
    >>> while not sampler.finished:
    ...     sampler.run_block()
    >>> m = sampler.result()
    >>> m.collisions, 3.5 < m.compressibility_factor < 4.5
    (30000, True)
    """

    def __init__(self, system: HardSphereSystem, collisions: int, blocks: int = 10, rdf_bins: int = 500,
                 transport: bool = False):
        if not isinstance(system, HardSphereSystem):
            raise TypeError(f"system must be a HardSphereSystem; got {type(system).__name__}")
        self.blocks = _checks.integer_at_least(blocks, "blocks", 2)
        self.per_block = _checks.integer_at_least(collisions, "collisions", self.blocks) // self.blocks
        rdf_bins = _checks.integer_at_least(rdf_bins, "rdf_bins", 10)
        self.system = system
        dim = system.dim
        self.r_max = float(min(system.box[:dim].min() / 2.0, 5.0 * 2.0 * np.max(system.radius)))
        self.histogram = np.zeros(rdf_bins)
        kinds = int(np.max(system.species)) + 1
        # a mixture's partial g(r), of up to PARTIAL_RDF_SPECIES species (their kinds (kinds + 1) / 2 histograms)
        mixed = 1 < np.unique(system.species).size and kinds <= PARTIAL_RDF_SPECIES
        self.partial_histograms = np.zeros((kinds, kinds, rdf_bins)) if mixed else None
        self.start_positions = system.positions(unwrapped=True)
        self.start_time = system.elapsed
        lags = min(_msd.MSD_MAX_LAGS, max(1, self.blocks // 2))
        species = system.species if np.unique(system.species).size > 1 else None
        self.lag_msd = _msd.LagMSD(lags, self.start_positions[:, self._diffusion_axes()], self.start_time, species)
        self.start_lost = system.energy_lost
        self.wall_seconds = 0.0
        sheared = SHEAR_RECORDS if system.shear_rate != 0.0 else ()
        mixed = MIXTURE_RECORDS if np.unique(system.species).size > 1 else ()
        rough = ROUGH_RECORDS if system.rough else ()
        homogeneity = HOMOGENEITY_RECORDS if homogeneity_measurable(system) else ()
        self.records = {name: [] for name in RECORDS + sheared + mixed + rough + homogeneity}
        self.speeds = []
        if not isinstance(transport, (bool, np.bool_)):
            raise TypeError(f"transport must be True or False; got {transport!r}")
        if transport and system.shear_rate != 0.0:
            raise ValueError("transport cannot be measured under shear (the Einstein-Helfand relations hold in "
                             "equilibrium); the sheared system's shear viscosity comes from its stress")
        if transport and system.rough:
            raise ValueError("transport cannot be measured for rough spheres (the Helfand moments and the heat flux "
                             "have no spin terms)")
        self.transport = TransportSampler(system) if transport else None

    def _diffusion_axes(self) -> list[int]:
        """The axes whose displacements give D: all of them, or those across the flow under shear (y, z)."""
        dim = self.system.dim
        return list(range(dim)) if self.system.shear_rate == 0.0 else list(range(1, dim))

    @property
    def done(self) -> int:
        """Blocks finished."""
        return len(self.records["temperature"])

    @property
    def finished(self) -> bool:
        """All blocks done."""
        return self.done >= self.blocks

    def __repr__(self) -> str:
        return f"Sampler({self.done} of {self.blocks} blocks of {self.per_block} collisions done, {self.system!r})"

    def extend(self, blocks: int) -> None:
        """Plan ``blocks`` more blocks of the same length (the lags of the MSD's time origins stay as they were).

        Examples
        --------
        >>> from collisionkit.edmd import Sampler, random_fluid
        >>> sampler = Sampler(random_fluid(2, 100, 0.3, seed=1), collisions=2000, blocks=2)
        >>> sampler.extend(3)
        >>> sampler.blocks, sampler.per_block
        (5, 1000)
        """
        self.blocks += _checks.integer_at_least(blocks, "blocks", 1)

    def run_block(self, progress=None):
        """Run and record one block.

        Parameters
        ----------
        progress : callable, optional
            Called as ``progress(fraction)`` with the fraction of the block's
            collisions done, in [0, 1], as the block runs.

        Raises
        ------
        RuntimeError
            If every planned block is done (:meth:`extend` plans more), or
            the system cannot be measured: its particles are at rest, its run
            stalled (see :meth:`HardSphereSystem.run`), or the block took no
            time or left no kinetic energy (a collapse).

        Examples
        --------
        >>> from collisionkit.edmd import Sampler, lattice, maxwell_boltzmann, HardSphereSystem
        >>> import numpy as np
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> sampler = Sampler(system, collisions=4000, blocks=2)
        >>> sampler.run_block()
        >>> sampler.done, sampler.finished
        (1, False)
        """
        if self.finished:
            raise RuntimeError(f"the sampler has run all {self.blocks} blocks it planned (result() measures them); "
                               "extend(blocks) plans more")
        system = self.system
        dim, count = system.dim, system.count
        kT_before = system.temperature()
        if not kT_before > 0.0:
            raise RuntimeError("the particles are at rest (kT = 0): nothing collides, so nothing can be measured; "
                               "give them velocities (set_velocities, maxwell_boltzmann)")
        start = block_start(system)
        # numba compiles at the first call (seconds on a cold cache): not a part of the timed run
        system.compile_event_loop()
        _pair_distribution.pair_distance_histogram(np.zeros((1, dim)), system.box[:dim], system.periodic, 1.0, 1)
        # the measurement's wall clock: the events and the sampling of this block
        tick = perf_counter()
        area = self._run_block_events(progress)
        kT_after = system.temperature()
        duration = system.elapsed - start["time"]
        if system.well_width is not None and duration > 0 and not np.any(system.geom[_k.G_GRAVITY] != 0.0):
            # exactly: K = E - U(t) with E conserved and -U the depths of the pairs inside, whose integral the engine
            # keeps
            # (under gravity the fall changes K too: the mean of the block's ends, as for hard spheres)
            area = system.total_energy() * duration + (system.well_energy_time() - start["wells"])
        # the time average of kT: under shear or with wells from the energy's integral, else the mean of the block's ends
        kT = 0.5 * (kT_before + kT_after) if area is None or not duration > 0 else 2.0 * area / (dim * count * duration)
        if not (duration > 0.0 and kT > 0.0):
            raise RuntimeError(
                f"a block of {self.per_block} pair collisions took no time (duration {duration:g}, kT {kT:g}): the "
                "system collapsed (e.g. restitution < 1 with elastic_below 0), so its pressure and collision "
                "frequency are undefined; raise elastic_below or the restitution"
            )
        record_block(self, start, kT_after, kT, duration)
        self.wall_seconds += perf_counter() - tick

    def _run_block_events(self, progress):
        """Run the block's pair collisions (sheared, for transport or plain); under shear return the energy's integral.

        Under shear the time integral of the peculiar kinetic energy
        (:func:`~collisionkit.edmd._shear.run_sheared`), else None.
        """
        if self.system.shear_rate != 0.0:
            return run_sheared(self.system, self.per_block, progress)
        if self.transport is None:
            self.system.run(collisions=self.per_block, progress=progress)
        else:
            self.transport.run_block(self.per_block, progress)
        return None

    def state_dict(self):
        """The sampler's accumulators as arrays (the system is saved separately).

        Examples
        --------
        >>> from collisionkit.edmd import Sampler, lattice, maxwell_boltzmann, HardSphereSystem
        >>> import numpy as np
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> sampler = Sampler(system, collisions=4000, blocks=2)
        >>> sampler.run_block()
        >>> sorted(sampler.state_dict())[:3]
        ['sampler_compressibility', 'sampler_frequency', 'sampler_histogram']
        """
        return sampler_arrays(self)

    @classmethod
    def from_state_dict(cls, system: HardSphereSystem, state):
        """Rebuild a sampler of ``system`` from :meth:`state_dict` output.

        Examples
        --------
        >>> from collisionkit.edmd import Sampler, lattice, maxwell_boltzmann, HardSphereSystem
        >>> import numpy as np
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> sampler = Sampler(system, collisions=4000, blocks=2)
        >>> sampler.run_block()
        >>> Sampler.from_state_dict(system, sampler.state_dict()).done
        1
        """
        if not isinstance(system, HardSphereSystem):
            raise TypeError(f"system must be a HardSphereSystem; got {type(system).__name__}")
        sampler = cls.__new__(cls)
        restore_sampler(sampler, system, state)
        return sampler

    def result(self) -> Measurement:
        """The observables over the blocks done so far (at least 2).

        Examples
        --------
        >>> from collisionkit.edmd import Sampler, lattice, maxwell_boltzmann, HardSphereSystem
        >>> import numpy as np
        >>> positions, box = lattice("square", 10, 0.3)
        >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
        >>> sampler = Sampler(system, collisions=4000, blocks=2)
        >>> while not sampler.finished:
        ...     sampler.run_block()
        >>> 1.5 < sampler.result().compressibility_factor < 2.6
        True
        """
        if self.done < 2:
            raise ValueError(f"need at least 2 finished blocks for errors; have {self.done}")
        return Measurement(**observables(self))


def measure(system: HardSphereSystem, collisions: int, blocks: int = 10, rdf_bins: int = 500, progress=None,
            transport: bool = False):
    """Run ``collisions`` pair collisions in ``blocks`` blocks and return the observables.

    See :class:`Sampler` for the estimators and the parameters.

    Parameters
    ----------
    system : HardSphereSystem
    collisions, blocks, rdf_bins : int
        As for :class:`Sampler`.
    progress : callable, optional
        Called as ``progress(fraction)`` with the fraction of all the
        blocks' collisions done, in [0, 1], as the measurement runs.
    transport : bool
        Also measure the transport coefficients (see :class:`Sampler`).

    Returns
    -------
    Measurement

    Examples
    --------
    >>> from collisionkit.edmd import measure, random_fluid
    >>> m = measure(random_fluid(2, 300, 0.3, seed=1), collisions=30_000, blocks=3)
    >>> 1.8 < m.compressibility_factor < 2.3
    True
    """
    sampler = Sampler(system, collisions, blocks, rdf_bins, transport)
    while not sampler.finished:
        sampler.run_block(None if progress is None else _share_of_blocks(progress, sampler))
    return sampler.result()


def _share_of_blocks(progress, sampler):
    """The progress callback of the block ``sampler`` runs next: its fraction of that block, as one of all blocks."""
    finished = sampler.done
    return lambda fraction: progress((finished + fraction) / sampler.blocks)
