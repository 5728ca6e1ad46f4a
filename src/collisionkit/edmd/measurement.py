"""Measurement of an EDMD run: block averages of the pressure, collision rate, g(r) and diffusion.

:class:`Sampler` runs a system block by block and records what each block
gives (resumable from a checkpoint); :func:`measure` runs it to the end;
:class:`Measurement` holds the results with their standard errors.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from time import perf_counter

import numpy as np

from .._repr import html_table, measurement_rows
from . import _checks, _msd, _pair_distribution
from ._shear import run_sheared
from ._transport import TransportMeasurement, TransportSampler, transport_measurement
from .system import HardSphereSystem
from .theory import _ball_volume

__all__ = ["RECORDS", "SHEAR_RECORDS", "Measurement", "Sampler", "measure"]

# what the sampler records at the end of each block (temperature: kT at the end; temperature_mean: its time average)
RECORDS = ("temperature", "temperature_mean", "compressibility", "pressure", "frequency", "time", "msd", "msd_groups")
# and, under shear, the xy element of the pressure tensor (kinetic plus collisional), its collisional part and the
# energy the thermostat removed
SHEAR_RECORDS = ("shear_stress", "collisional_shear_stress", "thermostat_energy")


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
    ``energy_lost``, ``contact_value`` (g at contact); arrays ``speeds`` (a
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
        if self.transport is not None:
            result |= {"self_diffusion": self.diffusion_coefficient,
                       "self_diffusion_error": self.diffusion_coefficient_error} | self.transport.summary()
        return result

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
        self.start_positions = system.positions(unwrapped=True)
        self.start_time = system.elapsed
        lags = min(_msd.MSD_MAX_LAGS, max(1, self.blocks // 2))
        self.lag_msd = _msd.LagMSD(lags, self.start_positions[:, self._diffusion_axes()], self.start_time)
        self.start_lost = system.energy_lost
        self.wall_seconds = 0.0
        self.records = {name: [] for name in RECORDS + (SHEAR_RECORDS if system.shear_rate != 0.0 else ())}
        self.speeds = []
        if not isinstance(transport, (bool, np.bool_)):
            raise TypeError(f"transport must be True or False; got {transport!r}")
        if transport and system.shear_rate != 0.0:
            raise ValueError("transport cannot be measured under shear (the Einstein-Helfand relations hold in "
                             "equilibrium); the sheared system's shear viscosity comes from its stress")
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
            If the system cannot be measured: its run stalled (see
            :meth:`HardSphereSystem.run`), or the block took no time or
            left no kinetic energy (a collapse).

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
        system = self.system
        dim, count = system.dim, system.count
        kT_before = system.temperature()
        virial0, collisions0, time0 = system.virial, system.collisions, system.elapsed
        shear0 = _shear_totals(system)
        thermostat0 = system.thermostat_energy
        # numba compiles at the first call (seconds on a cold cache): not a part of the timed run
        system.compile_event_loop()
        _pair_distribution.pair_distance_histogram(np.zeros((1, dim)), system.box[:dim], system.periodic, 1.0, 1)
        # the measurement's wall clock: the events and the sampling of this block
        tick = perf_counter()
        area = None
        if system.shear_rate != 0.0:
            area = run_sheared(system, self.per_block, progress)
        elif self.transport is None:
            system.run(collisions=self.per_block, progress=progress)
        else:
            self.transport.run_block(self.per_block, progress)
        kT_after = system.temperature()
        duration = system.elapsed - time0
        # the time average of kT: under shear from the sampled energy, else the mean of the block's ends
        kT = 0.5 * (kT_before + kT_after) if area is None or not duration > 0 else 2.0 * area / (dim * count * duration)
        if not (duration > 0.0 and kT > 0.0):
            raise RuntimeError(
                f"a block of {self.per_block} pair collisions took no time (duration {duration:g}, kT {kT:g}): the "
                "system collapsed (e.g. restitution < 1 with elastic_below 0), so its pressure and collision "
                "frequency are undefined; raise elastic_below or the restitution"
            )
        virial = system.virial - virial0
        record = self.records
        record["temperature"].append(kT_after)
        record["temperature_mean"].append(kT)
        record["compressibility"].append(1.0 + virial / (dim * count * kT * duration))
        record["pressure"].append((count * kT + virial / (dim * duration)) / system.volume)
        record["frequency"].append(2.0 * (system.collisions - collisions0) / (count * duration))
        record["time"].append(system.elapsed - self.start_time)
        unwrapped = system.positions(unwrapped=True)
        axes = self._diffusion_axes()
        squared = np.sum((unwrapped[:, axes] - self.start_positions[:, axes]) ** 2, axis=1)
        record["msd"].append(float(np.mean(squared)))
        record["msd_groups"].append(_msd.group_means(squared))
        if system.shear_rate != 0.0:
            stress, collisional = _shear_stresses(system, shear0, duration)
            record["shear_stress"].append(stress)
            record["collisional_shear_stress"].append(collisional)
            record["thermostat_energy"].append(system.thermostat_energy - thermostat0)
        if self.lag_msd is not None:
            self.lag_msd.add(unwrapped[:, axes], system.elapsed)
        # relative to the flow under shear (as kT is): lab-frame speeds grow with the box and the rate
        self.speeds.append(np.linalg.norm(system.peculiar_velocities(), axis=1))
        self.histogram += _pair_distribution.pair_histogram(system, self.r_max, self.histogram.size)
        self.wall_seconds += perf_counter() - tick

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
        state = {f"sampler_{name}": np.asarray(values, dtype=float) for name, values in self.records.items()}
        state |= {
            "sampler_speeds": np.asarray(self.speeds, dtype=float).reshape(len(self.speeds), -1),
            "sampler_histogram": self.histogram,
            "sampler_start_positions": self.start_positions,
            "sampler_scalars": np.array(
                [self.blocks, self.per_block, self.r_max, self.start_time, self.start_lost, self.wall_seconds]
            ),
        }
        if self.lag_msd is not None:
            state |= self.lag_msd.state_dict()
        if self.transport is not None:
            state |= self.transport.state_dict()
        return state

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
        sampler.system = system
        blocks, per_block, r_max, start_time, start_lost, wall = state["sampler_scalars"]
        sampler.blocks, sampler.per_block = int(blocks), int(per_block)
        sampler.r_max, sampler.start_time, sampler.start_lost, sampler.wall_seconds = r_max, start_time, start_lost, wall
        sampler.histogram = np.array(state["sampler_histogram"])
        sampler.start_positions = np.array(state["sampler_start_positions"])
        sampler.records = {name: list(state[f"sampler_{name}"]) for name in RECORDS + SHEAR_RECORDS
                           if f"sampler_{name}" in state}
        # a checkpoint written before the groups were recorded: their blocks are unknown (no D error)
        sampler.records.setdefault("msd_groups", [np.full(_msd.MSD_GROUPS, math.nan)] * len(sampler.records["msd"]))
        # ... or before the mean kT and the thermostat's energy were: unknown for the blocks done
        done = len(sampler.records["msd"])
        sampler.records.setdefault("temperature_mean", [math.nan] * done)
        if "shear_stress" in sampler.records:
            sampler.records.setdefault("thermostat_energy", [math.nan] * done)
        sampler.speeds = [row for row in np.array(state["sampler_speeds"])]
        sampler.lag_msd = _msd.LagMSD.from_state_dict(state)
        if sampler.lag_msd is not None and len(sampler.lag_msd.positions[0]) and \
                np.shape(sampler.lag_msd.positions[0])[-1] != len(sampler._diffusion_axes()):
            # a sheared run saved before the transverse D: its displacements count x too, so it has none
            sampler.lag_msd = None
            sampler.records["msd"] = [math.nan] * len(sampler.records["msd"])
        has_transport = "transport_scalars" in state
        sampler.transport = TransportSampler.from_state_dict(system, state) if has_transport else None
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
        system, dim, count = self.system, self.system.dim, self.system.count
        record = self.records
        edges = np.linspace(0.0, self.r_max, self.histogram.size + 1)
        centres = 0.5 * (edges[1:] + edges[:-1])
        shells = _ball_volume(edges[1:], dim) - _ball_volume(edges[:-1], dim)
        # ordered pairs: each of the N particles sees the other N - 1 at density (N - 1) / V
        rdf = self.histogram / (self.done * count * ((count - 1) / system.volume) * shells)
        speeds = np.concatenate(self.speeds)
        omega = float(np.mean(record["frequency"]))
        mean_speed = float(np.mean(speeds))
        msd_time = np.concatenate([[0.0], record["time"]])
        msd = np.concatenate([[0.0], record["msd"]])
        axes = len(self._diffusion_axes())
        from_lags = self.lag_msd.diffusion(axes) if self.lag_msd is not None else None
        diffusion, diffusion_error = from_lags or _msd.diffusion_from_msd(msd_time, msd, record["msd_groups"], axes)
        omega_error = _msd.block_error(record["frequency"])
        diameter = 2.0 * float(np.max(system.radius))
        contact, contact_error = _pair_distribution.contact_value(centres, rdf, self.histogram, diameter)
        durations = np.diff(msd_time)
        block_kT = np.asarray(record["temperature_mean"], dtype=float)
        return Measurement(
            dim=dim,
            particles=count,
            packing_fraction=system.packing_fraction,
            collisions=self.per_block * self.done,
            time=float(msd_time[-1]),
            wall_seconds=self.wall_seconds,
            temperature=float(record["temperature"][-1]),
            compressibility_factor=float(np.mean(record["compressibility"])),
            compressibility_factor_error=_msd.block_error(record["compressibility"]),
            pressure=float(np.mean(record["pressure"])),
            pressure_error=_msd.block_error(record["pressure"]),
            collision_frequency=omega,
            collision_frequency_error=omega_error,
            mean_free_time=1.0 / omega,
            mean_free_time_error=omega_error / omega**2,
            mean_free_path=mean_speed / omega,
            mean_free_path_error=mean_speed * omega_error / omega**2,
            mean_speed=mean_speed,
            diffusion_coefficient=diffusion,
            diffusion_coefficient_error=diffusion_error,
            energy_lost=float(system.energy_lost - self.start_lost),
            contact_value=contact,
            contact_value_error=contact_error,
            speeds=speeds,
            rdf_r=centres,
            rdf=rdf,
            msd_time=msd_time,
            msd=msd,
            block_temperature=np.asarray(record["temperature"]),
            block_compressibility=np.asarray(record["compressibility"]),
            block_frequency=np.asarray(record["frequency"]),
            temperature_mean=float(np.sum(block_kT * durations) / np.sum(durations)),
            temperature_mean_error=_msd.block_error(block_kT),
            block_temperature_mean=block_kT,
            transport=None if self.transport is None else transport_measurement(
                self.transport, self.done, 1.0 / omega, system.volume, count),
            **_shear_results(system.shear_rate, record, system.volume * durations),
        )


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


def _shear_totals(system):
    """What the shear stress of a block is computed from: peculiar kinetic energy, energy lost and removed, stress."""
    if system.shear_rate == 0.0:
        return None
    return (system.kinetic_energy(), system.energy_lost, system.thermostat_energy,
            float(system.collisional_stress[0, 1]))


def _shear_stresses(system, before, duration):
    r"""P_xy over a block (kinetic plus collisional) and its collisional part, from the exact energy balance.

    Over the block :math:`\Delta E + E_{lost} + E_{thermostat} = -G V \int
    P_{xy} dt` (see :mod:`._shear`): the total needs no sampling of the
    kinetic stress; the collisional part is the collisional stress sum's
    change over V t.
    """
    energy, lost, removed, stress = before
    work = (system.kinetic_energy() - energy) + (system.energy_lost - lost) + (system.thermostat_energy - removed)
    volume_time = system.volume * duration
    return (-work / (system.shear_rate * volume_time),
            (float(system.collisional_stress[0, 1]) - stress) / volume_time)


def _shear_results(rate, record, volume_times):
    """The Measurement's shear fields from the block records (none without shear); V t of each block given."""
    if rate == 0.0:
        return {}
    stress, collisional = np.asarray(record["shear_stress"]), np.asarray(record["collisional_shear_stress"])
    return {"shear_rate": rate, "thermostat_energy": float(np.sum(record["thermostat_energy"])),
            "viscous_heating": -rate * float(np.sum(stress * volume_times)),
            "shear_stress": float(np.mean(stress)), "shear_stress_error": _msd.block_error(stress),
            "collisional_shear_stress": float(np.mean(collisional)),
            "collisional_shear_stress_error": _msd.block_error(collisional),
            "shear_viscosity": -float(np.mean(stress)) / rate, "shear_viscosity_error": _msd.block_error(stress) / rate}


def _share_of_blocks(progress, sampler):
    """The progress callback of the block ``sampler`` runs next: its fraction of that block, as one of all blocks."""
    finished = sampler.done
    return lambda fraction: progress((finished + fraction) / sampler.blocks)
