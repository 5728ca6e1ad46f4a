"""Sampling the Helfand moments of an EDMD run on a time grid, and the transport coefficients they give.

:class:`TransportSampler` runs a measurement block in stretches of a fixed
interval (half a mean free time), taking at each grid time the
Helfand moments of momentum and energy (and, in a binary mixture, the
interdiffusion moment) and the velocities for their autocorrelation; at
each block end, the moments again (the block's pressure tensor). The
estimators are in :mod:`._helfand`; :func:`transport_measurement` applies
them to what was sampled.

Memory: the moment series is kept for the whole run, ``d^2 + 2 d`` numbers
a sample, 2 samples a mean free time (240 bytes a mean free time in 3D);
velocities of a few time origins (``N d`` numbers each) only within a block.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._kernels import edmd as _k
from . import _helfand
from ._msd import block_error
from .theory import enskog_collision_frequency, hansen_goos, henderson

__all__ = ["GRID_PER_FREE_TIME", "VACF_LAGS", "VACF_ORIGIN_EVERY", "TransportMeasurement", "TransportSampler"]

GRID_PER_FREE_TIME = 2  # grid samples per (estimated) mean free time (each costs two passes over the particles)
VACF_LAGS = 40  # lags of the velocity autocorrelation, in grid intervals (20 mean free times)
VACF_ORIGIN_EVERY = 8  # a time origin of the velocity autocorrelation every this many grid samples


def free_time_estimate(system) -> float:
    """Enskog's mean free time of the system: 1 / its collision rate at the pressure of the equation of state.

    :func:`~collisionkit.edmd.enskog_collision_frequency` at the
    compressibility factor of Hansen-Goos (3D) or Henderson (2D) for the
    packing fraction, the mean diameter and mass and the temperature now
    (exact for one species, an estimate for mixtures): it sets the grid of
    a transport measurement before any collision is measured.

    Examples
    --------
    >>> from collisionkit.edmd import random_fluid
    >>> round(free_time_estimate(random_fluid(3, 200, 0.3, seed=1)), 4)  # Z = 3.984 (Hansen-Goos)
    0.099
    """
    equation = hansen_goos if system.dim == 3 else henderson
    compressibility = float(equation(min(system.packing_fraction, 0.6)))
    diameter = 2.0 * float(np.mean(system.radius)) * system.scale
    return 1.0 / float(enskog_collision_frequency(compressibility, system.dim, diameter, system.temperature(),
                                                  float(np.mean(system.mass))))


class TransportSampler:
    """The time-grid sampling of one system's Helfand moments and velocities, block by block (resumable).

    Parameters
    ----------
    system : HardSphereSystem
        Periodic on every axis, elastic, without gravity or growth (the
        Einstein-Helfand relations hold in equilibrium).
    interval : float, optional
        Time between samples (> 0); default half of
        :func:`free_time_estimate`.

    Examples
    --------
    >>> from collisionkit.edmd import random_fluid
    >>> sampler = TransportSampler(random_fluid(3, 100, 0.3, seed=1))
    >>> sampler.run_block(2000)
    >>> len(sampler.times) > 10, len(sampler.edge_times)
    (True, 2)
    """

    def __init__(self, system, interval=None):
        refuse_unsuitable(system)
        self.system = system
        self.interval = float(interval) if interval is not None else free_time_estimate(system) / GRID_PER_FREE_TIME
        if not (math.isfinite(self.interval) and self.interval > 0):
            raise ValueError(f"interval must be a finite time > 0; got {self.interval!r}")
        system.synchronise()
        self.start_time = system.elapsed
        self.kT = system.temperature()  # (synchronised: the clock at 0)
        self.times, self.moments, self.block_of = [], [], []
        self.edge_times, self.edge_moments = [self.start_time], [self._sample()]
        self.vacf_sum, self.vacf_count = [], []
        self._new_block()
        self._take(0)

    def _new_block(self):
        """Forget the velocity origins of the last block: each block's autocorrelation is its own."""
        self._in_block, self._origins = 0, []
        self._vacf_block = (np.zeros(VACF_LAGS), np.zeros(VACF_LAGS))

    # ---------------------------------------------------------------- sampling

    @property
    def binary(self) -> bool:
        """True if the system holds two species (the interdiffusion moment is sampled)."""
        if not hasattr(self, "_binary"):
            self._binary = np.unique(self.system.species).size == 2
        return self._binary

    def _sample(self):
        """The moments now as one row: momentum (d x d, row-major), energy (d), interdiffusion (d, binary only).

        The particles stay at their own times (free flights: no gravity here).
        """
        momentum, energy = self.system._helfand_moments_now()
        row = [momentum.ravel(), energy]
        if self.binary:
            species = self.system.species
            first = species == species.min()
            fraction = float(np.mean(first))
            unwrapped = self.system.positions(unwrapped=True)
            row.append((1.0 - fraction) * unwrapped[first].sum(axis=0) - fraction * unwrapped[~first].sum(axis=0))
        return np.concatenate(row)

    def _take(self, block):
        """Record a grid sample of ``block`` (and its velocities for the autocorrelation)."""
        system = self.system
        self.moments.append(self._sample())
        self.times.append(system.elapsed + system.time)
        self.block_of.append(block)
        index = self._in_block  # the sample's place in its block
        self._in_block += 1
        # velocities in memory order (constant in free flight): an origin's are put in the same order only when
        # the particles were re-sorted since (the slot -> particle map is then a new array)
        velocities, ids = system.p[:, _k.V : _k.V + system.dim].ravel(), system.ids
        if index % VACF_ORIGIN_EVERY == 0:
            self._origins.append((index, velocities, ids))
        sums, counts = self._vacf_block
        kept = []
        for start, origin, origin_ids in self._origins:
            if index - start >= VACF_LAGS:
                continue
            if origin_ids is not ids:
                origin = _reordered(origin, origin_ids, ids, self.system.dim)
            kept.append((start, origin, ids))
            sums[index - start] += float(np.einsum("i,i", origin, velocities)) / len(ids)  # not BLAS: no threads
            counts[index - start] += 1
        self._origins = kept

    def run_block(self, collisions, progress=None):
        """Run ``collisions`` pair collisions, sampling at every grid time; then record the block's end.

        ``progress(fraction)`` is called with the fraction of the block's
        collisions done after each stretch.
        """
        system, block = self.system, len(self.edge_times) - 1
        left = collisions
        while left > 0:
            target = self.start_time + len(self.times) * self.interval
            done = system._run_until(left, target)
            left -= done
            if left > 0:
                if done == 0 and system.elapsed + system.time < target - 1e-9 * self.interval:
                    raise RuntimeError("the system stopped moving: no event is left to happen")
                self._take(block)
            if progress is not None:
                progress((collisions - left) / collisions)
        system.synchronise()
        self.edge_times.append(system.elapsed)
        self.edge_moments.append(self._sample())
        self.vacf_sum.append(self._vacf_block[0])
        self.vacf_count.append(self._vacf_block[1])
        self._new_block()

    # ---------------------------------------------------------------- checkpoints

    def state_dict(self):
        """The samples as arrays (``transport_*``), for the sampler's checkpoint (taken at block ends)."""
        return {
            "transport_scalars": np.array([self.interval, self.start_time, self.kT]),
            "transport_times": np.asarray(self.times, dtype=float),
            "transport_moments": np.asarray(self.moments, dtype=float),
            "transport_block_of": np.asarray(self.block_of, dtype=np.int64),
            "transport_edge_times": np.asarray(self.edge_times, dtype=float),
            "transport_edge_moments": np.asarray(self.edge_moments, dtype=float),
            "transport_vacf_sum": np.asarray(self.vacf_sum, dtype=float).reshape(-1, VACF_LAGS),
            "transport_vacf_count": np.asarray(self.vacf_count, dtype=float).reshape(-1, VACF_LAGS),
        }

    @classmethod
    def from_state_dict(cls, system, state):
        """The sampler of ``system`` saved in ``state`` (at a block end); ValueError if its arrays do not fit."""
        refuse_unsuitable(system)
        sampler = cls.__new__(cls)
        sampler.system = system
        sampler.interval, sampler.start_time, sampler.kT = (float(x) for x in state["transport_scalars"])
        sampler.times = [float(t) for t in state["transport_times"]]
        sampler.moments = list(np.array(state["transport_moments"], dtype=float))
        sampler.block_of = [int(b) for b in state["transport_block_of"]]
        sampler.edge_times = [float(t) for t in state["transport_edge_times"]]
        sampler.edge_moments = list(np.array(state["transport_edge_moments"], dtype=float))
        sampler.vacf_sum = list(np.array(state["transport_vacf_sum"], dtype=float))
        sampler.vacf_count = list(np.array(state["transport_vacf_count"], dtype=float))
        width = system.dim * system.dim + system.dim * (2 if sampler.binary else 1)
        blocks = len(sampler.edge_times) - 1
        fits = (len(sampler.moments) == len(sampler.times) == len(sampler.block_of) > 0
                and all(row.shape == (width,) for row in sampler.moments + sampler.edge_moments)
                and len(sampler.edge_moments) == blocks + 1 == len(sampler.vacf_sum) + 1 == len(sampler.vacf_count) + 1
                and sampler.interval > 0 and max(sampler.block_of) <= blocks)
        if not fits:
            raise ValueError("its transport arrays (transport_*) do not fit together or the particles")
        sampler._new_block()
        return sampler


def _reordered(flat, old_ids, new_ids, dim):
    """Velocities (flattened rows) of the memory order ``old_ids`` (slot -> particle) in the order ``new_ids``."""
    by_particle = np.empty((len(old_ids), dim))
    by_particle[old_ids] = flat.reshape(-1, dim)
    return by_particle[new_ids].ravel()


def refuse_unsuitable(system) -> None:
    """ValueError unless ``system`` is periodic, elastic, without gravity and not growing (equilibrium transport).

    Examples
    --------
    >>> from collisionkit.edmd import random_fluid
    >>> refuse_unsuitable(random_fluid(3, 50, 0.2, seed=1)) is None
    True
    """
    if not np.all(system.periodic):
        raise ValueError("transport coefficients need a periodic box on every axis (walls carry momentum away)")
    if np.any(system.restitution < 1.0) or system.restitution_law != "constant":
        raise ValueError("transport coefficients need elastic collisions (restitution 1): the Einstein-Helfand "
                         "relations hold in equilibrium, which an inelastic gas never reaches")
    if np.any(system.geom[_k.G_GRAVITY] != 0.0) or system.growth != 0.0:
        raise ValueError("transport coefficients need a system without gravity that is not being compressed")


@dataclass
class TransportMeasurement:
    """Transport coefficients of an EDMD run with their standard errors (units of the system: sigma, m, kT).

    ``shear_viscosity``, ``bulk_viscosity``, ``thermal_conductivity``,
    ``interdiffusion`` (binary mixtures, else NaN) come from Einstein fits
    (``fits``: name -> :class:`~collisionkit.edmd._helfand.EinsteinFit`)
    over ``fit_window`` (also in mean free times); ``green_kubo_shear_viscosity``
    from the pressure-tensor series ``stress`` (n, d, d; the mean over each
    grid ``interval``) up to the window's end; ``pressure_tensor`` the block
    mean of the full pressure tensor; ``vacf`` the normalised velocity
    autocorrelation <v(0).v(t)>/<v^2> at ``vacf_time``.

    In a mixture ``thermal_conductivity`` is the coefficient of the total
    energy flux: the partial enthalpies the species carry as they
    interdiffuse are not taken out, so it is the thermal conductivity
    proper only where the species' energies per particle are alike (a
    single species, or like masses without wells between unlike species).

    Examples
    --------
    >>> from collisionkit.edmd import measure, random_fluid
    >>> transport = measure(random_fluid(3, 108, 0.3, seed=1), collisions=20_000, blocks=2, transport=True).transport
    >>> transport.pressure_tensor.shape, sorted(transport.fits)
    ((3, 3), ['bulk_viscosity', 'shear_viscosity', 'thermal_conductivity'])
    """

    interval: float
    fit_window: tuple[float, float]
    fit_window_free_times: tuple[float, float]
    shear_viscosity: float
    shear_viscosity_error: float
    bulk_viscosity: float
    bulk_viscosity_error: float
    thermal_conductivity: float
    thermal_conductivity_error: float
    interdiffusion: float
    interdiffusion_error: float
    green_kubo_shear_viscosity: float
    green_kubo_shear_viscosity_error: float
    pressure_tensor: np.ndarray
    pressure_tensor_error: np.ndarray
    vacf_time: np.ndarray = field(repr=False)
    vacf: np.ndarray = field(repr=False)
    vacf_error: np.ndarray = field(repr=False)
    stress: np.ndarray = field(repr=False)
    fits: dict = field(repr=False)

    def summary(self) -> dict:
        """The coefficients, the window, the pressure tensor and the autocorrelation as a JSON-ready dict.

        Examples
        --------
        >>> from collisionkit.edmd import measure, random_fluid
        >>> m = measure(random_fluid(3, 108, 0.3, seed=1), collisions=20_000, blocks=2, transport=True)
        >>> summary = m.transport.summary()
        >>> "shear_viscosity_error" in summary, len(summary["pressure_tensor"])
        (True, 3)
        """
        keys = ("shear_viscosity bulk_viscosity thermal_conductivity green_kubo_shear_viscosity"
                + (" interdiffusion" if math.isfinite(self.interdiffusion) else "")).split()
        result = {}
        for key in keys:
            result |= {key: getattr(self, key), f"{key}_error": getattr(self, f"{key}_error")}
        return result | {
            "transport_fit_window": list(self.fit_window),
            "transport_fit_window_free_times": list(self.fit_window_free_times),
            "transport_interval": self.interval,
            "pressure_tensor": self.pressure_tensor.tolist(),
            "pressure_tensor_error": self.pressure_tensor_error.tolist(),
            "vacf_time": self.vacf_time.tolist(),
            "vacf": self.vacf.tolist(),
        }


def _shear(change):
    """Per pair, the squared traceless symmetric part of a momentum-moment change, per independent component."""
    dim = change.shape[1]
    symmetric = 0.5 * (change + change.transpose(0, 2, 1))
    traceless = symmetric - np.trace(symmetric, axis1=1, axis2=2)[:, None, None] / dim * np.eye(dim)
    return np.sum(traceless**2, axis=(1, 2)) / ((dim - 1) * (dim + 2))


def transport_measurement(sampler: TransportSampler, blocks: int, free_time: float, volume: float,
                          particles: int, kT: float | None = None) -> TransportMeasurement:
    """The transport coefficients of the first ``blocks`` finished blocks of ``sampler`` (see :mod:`._helfand`).

    ``free_time`` is the measured mean free time (the window's unit),
    ``volume`` the box's, ``particles`` N (the interdiffusion's norm),
    ``kT`` the temperature of the Einstein relations: by default the
    sampler's, kT when it started (constant for hard spheres); with square
    wells, whose kinetic energy changes at every capture and escape, the
    measured time mean.

    Examples
    --------
    >>> from collisionkit.edmd import random_fluid
    >>> system = random_fluid(3, 108, 0.3, seed=1)
    >>> sampler = TransportSampler(system)
    >>> for _ in range(2):
    ...     sampler.run_block(10_000)
    >>> transport_measurement(sampler, 2, free_time_estimate(system), system.volume, 108).interval == sampler.interval
    True
    """
    dim, interval = sampler.system.dim, sampler.interval
    kT = sampler.kT if kT is None else kT
    square = dim * dim
    moments = np.asarray(sampler.moments)
    block_of = np.asarray(sampler.block_of)
    kept = block_of < blocks
    moments, block_of = moments[kept], block_of[kept]
    slices = _helfand.block_slices(block_of)
    longest = max(stop - start for start, stop in slices)
    lags = np.arange(1, max(2, min(longest - 1, math.ceil(2 * _helfand.FIT_END * free_time / interval))) + 1)
    time = lags * interval
    momentum = moments[:, :square].reshape(-1, dim, dim)
    shear = _helfand.block_curves(momentum, slices, lags, _shear) / (2 * volume * kT)
    shear_mean, shear_error = _helfand.column_statistics(shear, lags.size)
    window = _helfand.fit_window(time, shear_mean, shear_error, free_time)
    fits = {"shear_viscosity": _helfand.einstein_fit(time, shear, window)}
    pressure = np.trace(momentum, axis1=1, axis2=2) / dim
    mean_change = _mean_changes(pressure, slices, lags)
    bulk = _helfand.block_curves(pressure, slices, lags, lambda change: change**2)
    linear = _helfand.block_curves(pressure, slices, lags, lambda change: change)
    fits["bulk_viscosity"] = _helfand.einstein_fit(time, (bulk - 2 * linear * mean_change + mean_change**2)
                                                   / (2 * volume * kT), window)
    energy = moments[:, square : square + dim]
    heat = _helfand.block_curves(energy, slices, lags, lambda change: np.sum(change**2, axis=1) / dim)
    fits["thermal_conductivity"] = _helfand.einstein_fit(time, heat / (2 * volume * kT * kT), window)
    if sampler.binary:
        species = sampler.system.species
        fraction = float(np.mean(species == species.min()))
        mixing = moments[:, square + dim :]
        curves = _helfand.block_curves(mixing, slices, lags, lambda change: np.sum(change**2, axis=1) / dim)
        fits["interdiffusion"] = _helfand.einstein_fit(time, curves / (2 * particles * fraction * (1 - fraction)),
                                                       window)
    edges = np.asarray(sampler.edge_moments)[: blocks + 1, :square].reshape(-1, dim, dim)
    durations = np.diff(sampler.edge_times[: blocks + 1])
    tensors = np.diff(edges, axis=0) / (volume * durations[:, None, None])
    steps = np.diff(np.asarray(sampler.times)[kept])
    stress = np.diff(momentum, axis=0) / (volume * steps[:, None, None])
    green_kubo = _helfand.green_kubo_viscosity(stress, interval, volume, kT, _helfand.block_slices(block_of[1:]),
                                               window[1] if math.isfinite(window[1]) else 0.0)
    vacf, vacf_error = _vacf(sampler, blocks)
    missing = _helfand.EinsteinFit(math.nan, math.nan, math.nan, window, time, time * math.nan, time * math.nan,
                                   np.array([]))
    return TransportMeasurement(
        interval=interval,
        fit_window=window,
        fit_window_free_times=(window[0] / free_time, window[1] / free_time),
        shear_viscosity=fits["shear_viscosity"].value,
        shear_viscosity_error=fits["shear_viscosity"].error,
        bulk_viscosity=fits["bulk_viscosity"].value,
        bulk_viscosity_error=fits["bulk_viscosity"].error,
        thermal_conductivity=fits["thermal_conductivity"].value,
        thermal_conductivity_error=fits["thermal_conductivity"].error,
        interdiffusion=fits.get("interdiffusion", missing).value,
        interdiffusion_error=fits.get("interdiffusion", missing).error,
        green_kubo_shear_viscosity=green_kubo[0],
        green_kubo_shear_viscosity_error=green_kubo[1],
        pressure_tensor=tensors.mean(axis=0),
        pressure_tensor_error=tensors.std(axis=0, ddof=1) / math.sqrt(len(tensors)),
        vacf_time=np.arange(VACF_LAGS) * interval,
        vacf=vacf,
        vacf_error=vacf_error,
        stress=stress,
        fits=fits,
    )


def _mean_changes(values, slices, lags):
    """The mean change of ``values`` at each lag over every origin of every block (the drift of the trace)."""
    totals, counts = np.zeros(len(lags)), np.zeros(len(lags))
    for start, stop in slices:
        block = values[start:stop]
        for k, lag in enumerate(lags):
            if lag < len(block):
                totals[k] += np.sum(block[lag:] - block[:-lag])
                counts[k] += len(block) - lag
    with np.errstate(invalid="ignore"):
        return totals / counts


def _vacf(sampler, blocks):
    """The normalised velocity autocorrelation (block mean over origins) and its standard error."""
    sums = np.asarray(sampler.vacf_sum[:blocks])
    counts = np.asarray(sampler.vacf_count[:blocks])
    per_block = np.divide(sums, counts, out=np.full(sums.shape, math.nan), where=counts > 0)
    normalised = per_block / per_block[:, :1]  # each block by its own <v^2> (every block has lag 0)
    columns = [column[np.isfinite(column)] for column in normalised.T]
    mean = np.array([float(np.mean(column)) if column.size else math.nan for column in columns])
    return mean, np.array([block_error(column) for column in columns])
