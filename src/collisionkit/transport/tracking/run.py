"""Tracking runs: primaries released in a device, followed with their avalanches until they end.

:func:`track` checks its arguments, prepares the kernel's arrays
(:mod:`collisionkit._kernels.transport.tracking`; the checks of single
arguments and the field arrays are in ``_track_setup``) and runs batches of
primaries in threads; each batch calls the kernel until its stack is empty,
emptying the record buffers and growing the stack when the kernel asks.
Every primary has its own random stream, derived from the seed and its
index alone, so results do not depend on threads, batches or on where a
checkpointed run was resumed.
"""

from __future__ import annotations

import math
import os
import time
from concurrent.futures import ThreadPoolExecutor
import threading
from dataclasses import dataclass, field
from types import SimpleNamespace

import numpy as np
from scipy import constants

from ..._kernels.transport.tracking import codes as _c
from ..._kernels.transport.tracking import track_particles
from ..._kernels.transport.tracking.ions import drift_ions
from ..._kernels.transport.tracking.track import launch
from .._tables import SHARING_CODES
from ._track_setup import (
    bounded, checked_times, integer, kernel_fields, profile_setting, start_positions, unit_direction,
)
from .device import Device
from .fields import _finite
from .result import TrackingResult
from .tables import tracking_tables

__all__ = ["METHODS", "ElectronLimitError", "IonDrift", "track"]

METHODS = {"null-collision": _c.NULL_COLLISION, "path-length": _c.PATH_LENGTH}
EV = constants.e
CALL_COLLISIONS = 1 << 18  # real collisions per kernel call at most: a call lasts a fraction of a second
PILOT_PRIMARIES = 8  # primaries of the pilot run that sizes the signal's time window and the avalanches
PILOT_SHARE = 100  # a pilot for the size alone runs before at least this many times its primaries (1 % more work)
SIGNAL_MARGIN = 2.0  # the signal window: this times the latest end seen in the pilot run
# electrons a run may follow by default (the primaries and every secondary): their end records take 88 B each
# and ion births 40 B (about 1.3 GB at the limit); an avalanche beyond it stops with a message, not a full memory
MAX_ELECTRONS = 10_000_000
RECORD_BYTES = 8 * (_c.RECORD_COLUMNS + _c.BIRTH_COLUMNS)
ON_SURFACE = 1e-12  # a start this close to a surface (relative to the length scale) is on it: emitted inward


class ElectronLimitError(RuntimeError, ValueError):
    """A run stopped, after some of its work, because its avalanches followed more electrons than ``max_electrons``.

    A run failure, not bad input: the ``track`` command exits with 1 for it. It is a ValueError too, as this stop
    was before, so code that caught that goes on working.

    Examples
    --------
    >>> from collisionkit.transport.tracking.run import ElectronLimitError
    >>> issubclass(ElectronLimitError, RuntimeError) and issubclass(ElectronLimitError, ValueError)
    True
    """


@dataclass(frozen=True)
class IonDrift:
    """Positive ions drifting at a constant ``mobility`` (m^2/(V s) at the device's density, > 0): v = K E.

    Examples
    --------
    >>> from collisionkit.transport.tracking import IonDrift
    >>> IonDrift(1.5e-4).charge == 1.602176634e-19
    True
    """

    mobility: float
    charge: float = constants.e

    def __post_init__(self):
        object.__setattr__(self, "mobility", _finite("ion mobility (m^2/(V s))", self.mobility, 0.0, True))
        object.__setattr__(self, "charge", _finite("ion charge (C)", self.charge))


@dataclass
class _Plan:
    """Everything a batch needs: the kernel's shared arguments and the run's settings."""

    device: Device
    tables: object
    fields: tuple
    settings: dict
    positions: np.ndarray
    speed: float
    direction: np.ndarray
    seed: int
    first_primary: int
    groups: int
    sample_times: np.ndarray
    signal_bins: int
    signal_step: float
    profile: tuple
    ions: IonDrift | None
    mass: float
    charge: float
    point_capacity: int
    max_electrons: int = MAX_ELECTRONS
    followed: list = field(default_factory=lambda: [0])  # electrons ended so far, over all batches
    lock: object = field(default_factory=threading.Lock)


def _states(seed: int, indices) -> np.ndarray:
    return np.array([np.random.SeedSequence(seed, spawn_key=(int(i),)).generate_state(4, np.uint64)
                     for i in indices], dtype=np.uint64).reshape(-1, 4)


def _run_batch(plan: _Plan, lo: int, hi: int, points_wanted: bool, report=None) -> TrackingResult:
    """Primaries lo..hi-1 (run indices) with their avalanches: the kernel called until the stack is empty."""
    start = time.perf_counter()
    n = hi - lo
    n_proc = plan.tables.tables.kind.size
    capacity = max(64, 4 * n)
    stack = {"pos": np.zeros((capacity, 3)), "vel": np.zeros((capacity, 3)), "time": np.zeros(capacity),
             "birth": np.zeros(capacity), "state": np.zeros((capacity, 4), np.uint64), "h": np.zeros(capacity),
             "primary": np.zeros(capacity, np.int64), "fresh": np.ones(capacity, bool),
             "id": np.zeros(capacity, np.int64)}
    order = np.arange(n)[::-1]  # the first primary on top of the stack: avalanches are followed one by one
    states = _states(plan.seed, plan.first_primary + lo + np.arange(n))
    velocities = np.zeros((n, 3))
    launch(states, plan.speed, plan.direction, velocities)
    _emit_inward(plan.device.geometry, plan.positions[lo:hi], velocities)
    stack["pos"][:n] = plan.positions[lo:hi][order]
    stack["vel"][:n] = velocities[order]
    stack["state"][:n] = states[order]
    stack["primary"][:n] = order
    stack["id"][:n] = order
    reference = max(plan.speed, math.sqrt(2.0 * 1e-3 * EV / plan.mass))
    stack["h"][:n] = 1e-3 * plan.settings["length"] / reference
    control = np.array([n, 0, 0, 0, 0, n], np.int64)
    tallies = np.zeros((n, n_proc + _c.TALLY_COLUMNS))
    records = np.zeros((max(64, 2 * n), _c.RECORD_COLUMNS))
    births = np.zeros((max(64, 2 * n), _c.BIRTH_COLUMNS))
    profile_code, profile_par, _, _, profile_bins = plan.profile
    profiles = np.zeros((2, profile_bins))
    signal = np.zeros(plan.signal_bins)
    moments = np.zeros((plan.groups, plan.sample_times.size, _c.MOMENT_COLUMNS))
    group = ((plan.first_primary + lo + np.arange(n)) % plan.groups).astype(np.int64)
    points = np.zeros((plan.point_capacity if points_wanted else 0, 5))
    kept_records, kept_births = [], []
    n_species = plan.tables.arrays()[0].shape[0]
    scratch = (np.zeros((7, 7)), np.zeros(7), np.zeros(7), np.zeros(7), np.zeros(n_species), np.zeros(n_species),
               np.zeros(4, np.uint64), np.zeros(3))
    s = plan.settings
    while True:
        outcome = track_particles(
            stack["pos"], stack["vel"], stack["time"], stack["birth"], stack["state"], stack["h"], stack["primary"],
            stack["fresh"], stack["id"], control, tallies, records, births, profiles, signal, moments, group,
            plan.sample_times, points, *plan.fields, s["mass"], s["charge"], s["density"], s["method"],
            s["tolerance"], s["depth_tolerance"], s["length"], s["step_length"], s["time_limit"], s["max_steps"],
            CALL_COLLISIONS, plan.ions is not None, s["sharing"], profile_code, profile_par, 0.0, plan.signal_step,
            *plan.tables.arrays(), *scratch)
        kept_records.append(records[: control[1]].copy())
        _count_followed(plan, int(control[1]), lo, hi)
        kept_births.append(births[: control[2]].copy())
        if report is not None and control[3]:
            report(int(control[3]))
        control[1] = control[2] = control[3] = 0
        if outcome == _c.DONE:
            break
        if control[0] + 2 > stack["pos"].shape[0]:
            for name, array in stack.items():
                grown = np.zeros((2 * array.shape[0],) + array.shape[1:], array.dtype)
                grown[: array.shape[0]] = array
                stack[name] = grown
    records = np.concatenate(kept_records)
    births = np.concatenate(kept_births)
    ion_records, ion_induced, ion_signal = _drift_ions(plan, births, n)
    collector = plan.device.collector
    surfaces = tuple(surface.name for surface in plan.device.geometry.surfaces)
    collected = np.zeros(n)
    if collector is not None:
        index = surfaces.index(collector)
        mask = (records[:, _c.RECORD_STATUS] == _c.ENDED_SURFACE) & (records[:, _c.RECORD_SURFACE] == index)
        collected = np.bincount(records[mask, _c.RECORD_PRIMARY].astype(np.int64), minlength=n).astype(float)
    tables = plan.tables.tables
    return TrackingResult(
        primaries=n, surfaces=surfaces, collector=collector, process_labels=tables.labels,
        process_kinds=tables.kinds, electrons=tallies[:, n_proc + _c.TALLY_ELECTRONS].copy(), collected=collected,
        collisions=tallies[:, :n_proc].copy(), null_collisions=int(tallies[:, n_proc + _c.TALLY_NULL].sum()),
        steps=int(tallies[:, n_proc + _c.TALLY_STEPS].sum()),
        rejected_steps=int(tallies[:, n_proc + _c.TALLY_REJECTED].sum()),
        particle_time=float(tallies[:, n_proc + _c.TALLY_TIME].sum()),
        induced_charge=tallies[:, n_proc + _c.TALLY_INDUCED].copy(),
        weighting_charge=tallies[:, n_proc + _c.TALLY_WEIGHTING].copy(), records=records, ion_records=ion_records,
        ion_induced_charge=ion_induced, signal=signal, ion_signal=ion_signal, signal_step=plan.signal_step,
        profile_coordinate=plan.profile[3], profile_edges=plan.profile[2], profiles=profiles,
        sample_times=plan.sample_times, moments=moments, seconds=time.perf_counter() - start,
        method=[name for name, code in METHODS.items() if code == s["method"]][0], points=points[: control[4]].copy(),
        mass=plan.mass)


def _emit_inward(geometry, positions, velocities) -> None:
    """Primaries that start on a surface (an electrode emitting) and would leave at once go into the volume: the
    velocity's outward normal part is turned inward (an isotropic source becomes one over the inner half-space)."""
    for surface in geometry.surfaces:
        on = np.abs(surface.distance(positions)) <= ON_SURFACE * geometry.length_scale
        if on.any():
            normal = surface.inward_normal(positions[on])
            along = (velocities[on] * normal).sum(axis=1)
            velocities[on] -= 2.0 * np.minimum(along, 0.0)[:, None] * normal


def _drift_ions(plan: _Plan, births, n):
    """The ions born in a batch drifted to the electrodes: (end records, induced charge per primary, signal)."""
    records = np.zeros((births.shape[0], _c.RECORD_COLUMNS))
    induced = np.zeros(n)
    signal = np.zeros(plan.signal_bins)
    if plan.ions is None or births.shape[0] == 0:
        return records, induced, signal
    kind, parameters, meta, values, _, user = plan.fields[:6]
    w_kind, w_par = plan.fields[11], plan.fields[12]
    drift_ions(np.ascontiguousarray(births), records, induced, signal, kind, parameters, meta, values, user, w_kind,
               w_par, plan.fields[13], plan.ions.mobility, plan.ions.charge, plan.settings["tolerance"],
               plan.settings["length"], math.inf, plan.settings["max_steps"], 0.0, plan.signal_step)
    return records, induced, signal


def track(device: Device, *, primaries: int = 100, position=(0.0, 0.0, 0.0), energy: float = 0.1,
          direction=None, method: str = "null-collision", seed: int = 0, mass: float = constants.m_e,
          charge: float = -constants.e, sharing: str = "equal", ions: IonDrift | None = None,
          time_limit: float | None = None, sample_times=None, tolerance: float = 1e-6, depth_tolerance: float = 1e-5,
          step_length: float | None = None, signal_window="auto", signal_bins: int = 200, profile=None,
          profile_bins: int = 100, groups: int = 16, threads: int | None = None, progress=None,
          record_points: int = 0, max_steps: int = 10_000_000, first_primary: int = 0,
          batch_size: int | None = None, max_electrons: int = MAX_ELECTRONS) -> TrackingResult:
    r"""Release ``primaries`` particles in ``device`` and follow them and their avalanches to the end.

    Krasov's algorithm (sec. 5.5) with numerical motion: see
    :mod:`collisionkit._kernels.transport.tracking.track`.

    Parameters
    ----------
    device : Device
        Gas, fields, surfaces, readout (:class:`Device.parallel_plate`, :class:`Device.coaxial` ...).
    primaries : int
        Particles released (>= 1).
    position : 3 numbers or (primaries x 3) array
        Where they start (m), inside the volume; a start on a surface (an
        electrode) emits into the volume.
    energy : float
        Their kinetic energy (eV, >= 0), along ``direction`` or isotropic (default).
    method : {"null-collision", "path-length"}
        How collisions are found: trial collisions at a rate bound, or the
        optical depth integrated along the trajectory (Krasov's path length).
    seed : int
        Seed (>= 0); primary i draws from ``SeedSequence(seed, spawn_key=(first_primary + i,))``.
    mass, charge : float
        The tracked particle (kg, C): an electron by default.
    sharing : {"equal", "uniform"}
        Energy sharing of the two electrons after an ionization.
    ions : IonDrift, optional
        Drift the ions of every ionization at a constant mobility to the electrodes.
    time_limit : float, optional
        Particles still moving at this time (s) end (``time-limit``); an
        unbounded device needs it or ``sample_times``.
    sample_times : sequence, optional
        Times (s, increasing) at which the moments of the particles alive are
        summed, per group (:meth:`TrackingResult.transport`).
    tolerance : float
        Relative tolerance of the integrated motion (position against the
        geometry's length scale, velocity against the speed), in (0, 0.1].
    depth_tolerance : float
        Absolute tolerance of the optical depth per step (path-length method), in (0, 0.1].
    step_length : float, optional
        Longest distance a step may move a particle (m); default the geometry's length scale.
    signal_window : float, "auto" or None
        Time span (s) of the induced-current histogram, from 0; "auto" sizes
        it from a pilot run of a few primaries; None records none.
    signal_bins, profile_bins : int
        Bins of the current and of the ionization / excitation profiles.
    profile : tuple, optional
        ("z" or "radius", low, high): the profile coordinate (default from the device).
    groups : int
        Independent groups of the sampled moments (2 to 1024).
    threads : int, optional
        Worker threads (default: all cores); results do not depend on it.
    progress : callable, optional
        Called with the fraction of primaries done.
    record_points : int
        Track points (particle, t, x, y, z) to keep for plots (the first batch's).
    max_steps : int
        Steps a particle may take at most (a guard against particles trapped for ever).
    first_primary : int
        Index of the first primary (a run continued from a checkpoint).
    max_electrons : int
        Electrons (primaries and secondaries) the run may follow, >= 1: a run
        whose avalanches would exceed it is refused after a pilot of a few
        primaries (ValueError; a pilot runs before 800 primaries or more, or
        for the signal's window), or stopped when it gets there
        (:class:`ElectronLimitError`, a ValueError too); each electron's
        record takes about 130 B.
    batch_size : int, optional
        Primaries per kernel batch (default: the primaries spread over the threads).

    Returns
    -------
    TrackingResult

    Examples
    --------
    Electrons drifting across a 1 mm gap in a Maxwell-model gas (no ionization): every one is collected.

    >>> from collisionkit.transport import maxwell_model
    >>> from collisionkit.transport.tracking import Device, track
    >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-3, 10.0, density=1e23)
    >>> result = track(device, primaries=8, position=(0, 0, 1e-4), seed=3)
    >>> result.gain, bool(result.drift_time > 0)
    (1.0, True)
    """
    args = _checked_arguments(device, primaries, method, sharing, seed, energy, mass, charge, tolerance,
                              depth_tolerance, groups, max_steps, record_points, first_primary, max_electrons, ions)
    direction = unit_direction(direction)
    positions = start_positions(position, args.primaries, device.geometry)
    sample_times, time_limit = checked_times(device, sample_times, time_limit)
    if step_length is not None:
        step_length = _finite("step_length (m)", step_length, 0.0, low_open=True)
    fields = kernel_fields(device, METHODS[method], args.charge, args.mass)
    plan = _make_plan(device, args, METHODS[method], sharing, fields, positions, direction, sample_times, time_limit,
                      step_length, profile, profile_bins, ions)
    pilot = _run_pilot(plan, args.primaries, device.weighting is not None and signal_window == "auto")
    _size_signal(plan, signal_window, signal_bins, args.primaries, pilot)
    return _run_batches(plan, args.primaries, threads, batch_size, progress)


def _checked_arguments(device, primaries, method, sharing, seed, energy, mass, charge, tolerance, depth_tolerance,
                       groups, max_steps, record_points, first_primary, max_electrons, ions) -> SimpleNamespace:
    """:func:`track`'s device, choices and numbers checked, in the order of its signature.

    Parameters
    ----------
    device, primaries, method, sharing, seed, energy, mass, charge, tolerance, depth_tolerance, groups, max_steps, \
record_points, first_primary, max_electrons, ions
        :func:`track`'s arguments of those names.

    Returns
    -------
    SimpleNamespace
        The numbers as checked (ints and floats), by their names.

    Raises
    ------
    TypeError, ValueError
        At the first argument of the wrong kind or out of its range.

    Examples
    --------
    >>> from collisionkit.transport import maxwell_model
    >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-4, 10.0, density=1e23)
    >>> args = _checked_arguments(device, 2, "null-collision", "equal", 0, 1, 9.1e-31, -1.6e-19, 1e-6, 1e-5, 16,
    ...                           100, 0, 0, 10, None)
    >>> args.primaries, args.energy
    (2, 1.0)
    """
    if not isinstance(device, Device):
        raise TypeError(f"device must be a Device; got {type(device).__name__}")
    checked = {"primaries": integer("primaries", primaries, 1)}
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}; got {method!r}")
    if sharing not in SHARING_CODES:
        raise ValueError(f"sharing must be one of {', '.join(SHARING_CODES)}; got {sharing!r}")
    checked |= {
        "seed": integer("seed", seed, 0), "energy": _finite("energy (eV)", energy, 0.0),
        "mass": _finite("mass (kg)", mass, 0.0, low_open=True), "charge": _finite("charge (C)", charge),
        "tolerance": bounded("tolerance", tolerance), "depth_tolerance": bounded("depth_tolerance", depth_tolerance),
        "groups": integer("groups", groups, 2, 1024), "max_steps": integer("max_steps", max_steps, 1),
        "record_points": integer("record_points", record_points, 0),
        "first_primary": integer("first_primary", first_primary, 0),
        "max_electrons": integer("max_electrons", max_electrons, 1),
    }
    if ions is not None and not isinstance(ions, IonDrift):
        raise TypeError(f"ions must be an IonDrift; got {type(ions).__name__}")
    return SimpleNamespace(**checked)


def _make_plan(device, args, method_code, sharing, fields, positions, direction, sample_times, time_limit,
               step_length, profile, profile_bins, ions) -> _Plan:
    """The plan of a run: the gas's tables, the kernel's settings and the checked arguments together.

    Parameters
    ----------
    device : Device
    args : SimpleNamespace
        The numbers of :func:`_checked_arguments`.
    method_code : int
        The collision method's code (:data:`METHODS`).
    sharing : str
        The energy sharing's name.
    fields : tuple
        The kernel's field arguments (:func:`~._track_setup.kernel_fields`).
    positions, direction, sample_times, time_limit
        As checked by ``_track_setup``.
    step_length : float or None
        Checked; None for the geometry's length scale.
    profile, profile_bins, ions
        :func:`track`'s arguments (the profile's bins checked here).

    Returns
    -------
    _Plan
        With no signal yet (:func:`_size_signal` sizes it).

    Examples
    --------
    >>> from collisionkit.transport import maxwell_model
    >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-4, 10.0, density=1e23)
    >>> args = _checked_arguments(device, 2, "null-collision", "equal", 0, 1, 9.1e-31, -1.6e-19, 1e-6, 1e-5, 16,
    ...                           100, 0, 0, 10, None)
    >>> fields = kernel_fields(device, METHODS["null-collision"], args.charge, args.mass)
    >>> plan = _make_plan(device, args, METHODS["null-collision"], "equal", fields, np.zeros((2, 3)), np.zeros(3),
    ...                   np.zeros(0), math.inf, 1e-4, None, 10, None)
    >>> plan.profile[3], plan.signal_bins
    ('z', 0)
    """
    tables = tracking_tables(device.gas, args.mass, device.gas_temperature)
    settings = {"mass": args.mass, "charge": args.charge, "density": device.density, "method": method_code,
                "tolerance": args.tolerance, "depth_tolerance": args.depth_tolerance,
                "length": device.geometry.length_scale,
                "step_length": device.geometry.length_scale if step_length is None else step_length, "time_limit": time_limit,
                "max_steps": args.max_steps, "sharing": SHARING_CODES[sharing]}
    return _Plan(device, tables, fields, settings, positions, math.sqrt(2.0 * args.energy * EV / args.mass),
                 direction, args.seed, args.first_primary, args.groups, np.ascontiguousarray(sample_times), 0, 1.0,
                 profile_setting(device, profile, integer("profile_bins", profile_bins, 1)), ions, args.mass,
                 args.charge, args.record_points, args.max_electrons)


def _run_pilot(plan: _Plan, primaries: int, auto_window: bool) -> TrackingResult | None:
    """A pilot run of a few primaries, if the signal's window is sized from it or the run is large; else None.

    A large run (:data:`PILOT_SHARE` times the pilot's primaries or more) is
    refused before its work if the pilot's avalanches, projected to it,
    exceed ``max_electrons``; a smaller run is stopped by the count as it
    goes. The pilot's electrons do not count towards the run's.

    Examples
    --------
    >>> from collisionkit.transport import maxwell_model
    >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-4, 10.0, density=1e23)
    >>> args = _checked_arguments(device, 2, "null-collision", "equal", 0, 1, 9.1e-31, -1.6e-19, 1e-6, 1e-5, 16,
    ...                           100, 0, 0, 10, None)
    >>> fields = kernel_fields(device, METHODS["null-collision"], args.charge, args.mass)
    >>> plan = _make_plan(device, args, METHODS["null-collision"], "equal", fields, np.zeros((2, 3)), np.zeros(3),
    ...                   np.zeros(0), math.inf, 1e-4, None, 10, None)
    >>> _run_pilot(plan, 2, False) is None
    True
    """
    if not (auto_window or primaries >= PILOT_SHARE * PILOT_PRIMARIES):
        return None
    pilot = _run_batch(plan, 0, min(PILOT_PRIMARIES, primaries), False)
    _check_projected_size(plan, pilot, primaries)
    plan.followed[0] = 0
    return pilot


def _size_signal(plan: _Plan, signal_window, signal_bins, primaries: int, pilot: TrackingResult | None) -> None:
    """Set the plan's induced-current histogram: ``signal_bins`` bins over the window (none without a readout).

    ``signal_window`` "auto" is :data:`SIGNAL_MARGIN` times the latest end of the ``pilot`` run
    (:func:`_pilot_window`); None records no current.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> plan = SimpleNamespace(device=SimpleNamespace(weighting=object()), signal_bins=0, signal_step=1.0)
    >>> _size_signal(plan, 1e-6, 4, 8, None)
    >>> plan.signal_bins, plan.signal_step
    (4, 2.5e-07)
    """
    if plan.device.weighting is None or signal_window is None:
        return
    bins = integer("signal_bins", signal_bins, 1)
    if signal_window == "auto":
        signal_window = _pilot_window(plan, primaries, pilot)
    window = _finite("signal_window (s)", signal_window, 0.0, low_open=True)
    plan.signal_bins, plan.signal_step = bins, window / bins


def _run_batches(plan: _Plan, primaries: int, threads, batch_size, progress) -> TrackingResult:
    """Every primary in batches (in threads), reporting the fraction done, joined into one result.

    Parameters
    ----------
    plan : _Plan
    primaries : int
    threads, batch_size, progress
        :func:`track`'s arguments: default all cores, and batches that spread the primaries four to a thread.

    Returns
    -------
    TrackingResult
        The batches' results joined in the order of their primaries (the first batch keeps its track points).

    Examples
    --------
    >>> from collisionkit.transport import maxwell_model
    >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-4, 10.0, density=1e23)
    >>> args = _checked_arguments(device, 2, "null-collision", "equal", 0, 1, 9.1e-31, -1.6e-19, 1e-6, 1e-5, 16,
    ...                           100, 0, 0, 10, None)
    >>> fields = kernel_fields(device, METHODS["null-collision"], args.charge, args.mass)
    >>> plan = _make_plan(device, args, METHODS["null-collision"], "equal", fields, np.full((2, 3), 5e-5),
    ...                   np.zeros(3), np.zeros(0), math.inf, 1e-4, None, 10, None)
    >>> _run_batches(plan, 2, 1, None, None).primaries
    2
    """
    threads = threads or os.cpu_count() or 1
    batch_size = batch_size or max(1, math.ceil(primaries / (4 * threads)))
    bounds = list(range(0, primaries, batch_size)) + [primaries]
    done = [0]

    def work(b):
        part = _run_batch(plan, bounds[b], bounds[b + 1], b == 0)
        done[0] += bounds[b + 1] - bounds[b]
        if progress is not None:
            progress(done[0] / primaries)
        return part

    if threads == 1 or len(bounds) == 2:
        parts = [work(b) for b in range(len(bounds) - 1)]
    else:
        with ThreadPoolExecutor(threads) as pool:
            parts = list(pool.map(work, range(len(bounds) - 1)))
    return TrackingResult.combine(parts)


def _pilot_window(plan: _Plan, primaries: int, pilot: TrackingResult) -> float:
    """The signal window from a pilot run of a few primaries: SIGNAL_MARGIN times the latest end (electrons, ions)."""
    latest = 0.0
    for records in (pilot.records, pilot.ion_records):
        finished = records[np.isfinite(records[:, _c.RECORD_TIME]), _c.RECORD_TIME] if records.size else []
        if len(finished):
            latest = max(latest, float(np.max(finished)))
    if not latest > 0.0:
        latest = plan.settings["time_limit"] if math.isfinite(plan.settings["time_limit"]) else 1e-6
    return SIGNAL_MARGIN * latest


def too_many_electrons(max_electrons: int, electrons: float, what: str, stopped: bool = False) -> ValueError:
    """The error of a run that follows (or would follow) more electrons than ``max_electrons``: a ValueError for a
    run refused on a projection, an :class:`ElectronLimitError` for one ``stopped`` after part of its work.

    Examples
    --------
    >>> str(too_many_electrons(100, 250.0, "the run has followed")).split(":")[0]
    'the run has followed 250 electrons, more than max_electrons = 100 (their records take about 128 B each)'
    >>> type(too_many_electrons(100, 250.0, "the run has followed", stopped=True)).__name__
    'ElectronLimitError'
    """
    kind = ElectronLimitError if stopped else ValueError
    return kind(f"{what} {electrons:.3g} electrons, more than max_electrons = {max_electrons} (their records take "
                f"about {RECORD_BYTES} B each): the avalanches are larger than that allows; follow fewer primaries, "
                "lower the gain (the voltage, or the pressure times the gap: the Townsend alpha times the gap), or "
                "raise max_electrons if the memory allows")


def _check_projected_size(plan: _Plan, pilot: TrackingResult, primaries: int) -> None:
    """Refuse, before the work, a run whose avalanches (as the pilot's primaries made them) exceed the limit."""
    projected = float(pilot.electrons.mean()) * primaries
    if projected > plan.max_electrons:
        raise too_many_electrons(plan.max_electrons, projected, f"the pilot's {pilot.primaries} primaries made "
                                         f"{pilot.electrons.mean():.3g} electrons each: {primaries} primaries would "
                                         f"follow about")


def _count_followed(plan: _Plan, ended: int, lo: int, hi: int) -> None:
    """Add the electrons that ended in a kernel call to the run's count; stop the run past the limit."""
    with plan.lock:
        plan.followed[0] += ended
        total = plan.followed[0]
    if total > plan.max_electrons:
        raise too_many_electrons(plan.max_electrons, total, f"primaries {plan.first_primary + lo} to "
                                 f"{plan.first_primary + hi - 1} (with the batches beside them) have followed",
                                 stopped=True)
