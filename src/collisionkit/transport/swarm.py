"""Swarm simulation: a cloud of charged particles drifting through a gas in E (and B) fields.

Krasov's trajectory algorithm (sec. 5.5: a random free path, exact motion
under the force, a collision, a new direction) with energy-dependent cross
sections through null collisions (Skullerud 1968); the kernels are in
:mod:`collisionkit._kernels.transport`.

Observables (Robson, Ness, White, Dujko; e.g. Dujko et al., J. Phys. D 41,
245205 (2008)) over the steady-state window, from per-step sums:

* flux drift velocity ``W_flux = <v>``; flux diffusion
  ``D_flux,zz = <z v_z> - <z><v_z>`` (transverse: the mean of xx and yy);
* bulk drift velocity ``W_bulk = d<r>/dt`` and bulk diffusion
  ``D_bulk,zz = (1/2) d(<z^2> - <z>^2)/dt`` (least-squares slopes);
* rate coefficients ``k_j = (collisions j) / (N x particle time)``;
  effective ionization / attachment frequencies the same without ``1/N``;
* mean energy and the energy distribution.

Statistical errors come from independent groups: particles are dealt into
``groups`` groups with their own random streams (``SeedSequence.spawn``),
ionization children stay in their parent's group, every quantity is
estimated per group, and the error is the standard error of the group
mean. The result does not depend on the number of threads.
"""

from __future__ import annotations

import math
import os
import time
import warnings
from collections.abc import Mapping
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np
from scipy import constants

from .. import _arrays
from .._kernels import transport as _k
from ._tables import KernelTables, build_tables
from .gases import Gas

__all__ = ["SwarmResult", "simulate_swarm", "diffusion_error_floor", "DEFAULT_TOLERANCES", "TOWNSEND", "HUXLEY",
           "REFERENCE_DENSITY"]

TOWNSEND = 1e-21  # V m^2
HUXLEY = 1e-27  # T m^3
REFERENCE_DENSITY = 1e24  # m^-3; N-scaled results do not depend on it
EV = constants.e
SHARING = {"equal": _k.SHARE_EQUAL, "uniform": _k.SHARE_UNIFORM}
DEFAULT_TOLERANCES = {"mean_energy": 2e-3, "drift_velocity_bulk": 2e-3, "diffusion_L_N": 2e-2, "diffusion_T_N": 2e-2}
STEPS_PER_CHUNK = 25
MIN_RESULT_SAMPLES = 2  # samples a result needs at the least (slopes)
GROWTH_LIMIT = 1.5  # population growth per sample that halves the interval during the transient
MAX_SLOTS = 16  # child slots per particle and step before a step is split
MOMENT_COLUMNS = 14
# Count the trial collisions at which the true collision rate exceeded the trial bound (the null-collision
# method is exact only if that never happens) and report them as ``extras["bound_violations"]``. Off by
# default (it evaluates every process at every trial); the tests switch it on.
CHECK_BOUND = False


@dataclass
class SwarmResult:
    """Transport coefficients of one swarm run (SI units, energies in eV).

    Every value has an ``*_error`` partner (standard error over the
    independent groups). N-scaled coefficients are per unit gas density.
    ``eedf`` is the energy distribution (1/eV) at the bin centres
    ``eedf_energy``, which span [0, 4 <e>) of the swarm when sampling began;
    ``eedf_above`` is the fraction of it beyond the last bin (in no bin, so
    the EEDF integrates to ``1 - eedf_above``).
    ``extras["bound_violations"]`` (only when the module switch
    ``CHECK_BOUND`` is on) counts the trial collisions at which the true
    collision rate exceeded the trial bound: 0 for an exact run.

    Examples
    --------
    >>> from collisionkit.transport import maxwell_model, simulate_swarm
    >>> result = simulate_swarm(maxwell_model(), 10.0, particles=1000, groups=4, seed=1,
    ...                         tolerances={"mean_energy": 0.05})
    >>> result.mean_energy > 0, result.drift_velocity_bulk.shape
    (True, (3,))
    """

    reduced_field: float
    reduced_magnetic_field: float
    gas_temperature: float
    mean_energy: float
    mean_energy_error: float
    drift_velocity_flux: np.ndarray
    drift_velocity_flux_error: np.ndarray
    drift_velocity_bulk: np.ndarray
    drift_velocity_bulk_error: np.ndarray
    diffusion_L_N_flux: float
    diffusion_L_N_flux_error: float
    diffusion_T_N_flux: float
    diffusion_T_N_flux_error: float
    diffusion_L_N: float
    diffusion_L_N_error: float
    diffusion_T_N: float
    diffusion_T_N_error: float
    rate_coefficients: dict
    rate_coefficient_errors: dict
    ionization_frequency_N: float
    ionization_frequency_N_error: float
    attachment_frequency_N: float
    attachment_frequency_N_error: float
    eedf_energy: np.ndarray
    eedf: np.ndarray
    eedf_above: float
    collisions: int
    null_collisions: int
    seconds: float
    simulated_time: float
    steady_from: float
    particles: int
    groups: int
    converged: bool
    extras: dict = field(default_factory=dict)

    @property
    def collisions_per_second(self) -> float:
        """Real collisions per wall-clock second."""
        return self.collisions / self.seconds if self.seconds > 0 else 0.0

    def relative_error(self, name: str) -> float:
        """Relative standard error of ``mean_energy``, ``drift_velocity_bulk`` (z), ``diffusion_L_N`` ...

        Examples
        --------
        >>> from collisionkit.transport import maxwell_model, simulate_swarm
        >>> result = simulate_swarm(maxwell_model(), 10.0, particles=1000, groups=4, seed=1,
        ...                         tolerances={"mean_energy": 0.05})
        >>> result.relative_error("mean_energy") < 0.05
        True
        """
        value = np.asarray(getattr(self, name), dtype=float)
        error = np.asarray(getattr(self, f"{name}_error"), dtype=float)
        if value.ndim:
            value, error = value[2], error[2]
        return float(abs(error / value)) if value != 0 else math.inf

    def to_dict(self) -> dict:
        """A JSON-ready dictionary (vectors as lists, with ``collisions_per_second``).

        Examples
        --------
        >>> import json
        >>> from collisionkit.transport import maxwell_model, simulate_swarm
        >>> data = simulate_swarm(maxwell_model(), 10.0, particles=1000, groups=4, seed=1,
        ...                       tolerances={"mean_energy": 0.05}).to_dict()
        >>> "collisions_per_second" in data, len(json.dumps(data)) > 100
        (True, True)
        """
        out = {}
        for name in self.__dataclass_fields__:
            value = getattr(self, name)
            out[name] = value.tolist() if isinstance(value, np.ndarray) else value
        out["collisions_per_second"] = self.collisions_per_second
        return out

    @classmethod
    def from_dict(cls, data: Mapping) -> SwarmResult:
        """The result back from :meth:`to_dict` output (after a JSON round trip too: the ``null`` that
        strict JSON writers put for NaN and infinities reads back as NaN).

        Examples
        --------
        >>> import json
        >>> from collisionkit.transport import maxwell_model, simulate_swarm
        >>> result = simulate_swarm(maxwell_model(), 10.0, particles=1000, groups=4, seed=1,
        ...                         tolerances={"mean_energy": 0.05})
        >>> SwarmResult.from_dict(json.loads(json.dumps(result.to_dict()))).mean_energy == result.mean_energy
        True
        """
        if not isinstance(data, Mapping):
            raise TypeError(f"data must be a mapping (SwarmResult.to_dict output); got {type(data).__name__}")
        missing = [name for name in cls.__dataclass_fields__ if name not in data and name != "extras"]
        if missing:
            raise ValueError(f"data is not a SwarmResult.to_dict output: missing {', '.join(missing)}")
        values = {}
        for name, spec in cls.__dataclass_fields__.items():
            if name not in data:
                continue
            values[name] = _from_json(data[name], spec.type)
        return cls(**values)

    def to_row(self) -> dict:
        """The scalars as one flat row for a table (CSV, pandas): vectors split into ``_x``, ``_y``, ``_z``,
        rate coefficients as ``rate_coefficient[label]``; the EEDF arrays and ``extras`` left out.

        Examples
        --------
        >>> from collisionkit.transport import maxwell_model, simulate_swarm
        >>> row = simulate_swarm(maxwell_model(), 10.0, particles=1000, groups=4, seed=1,
        ...                      tolerances={"mean_energy": 0.05}).to_row()
        >>> row["reduced_field"], "drift_velocity_bulk_z" in row, "rate_coefficient[maxwell:elastic]" in row
        (10.0, True, True)
        """
        row = {}
        for name in self.__dataclass_fields__:
            value = getattr(self, name)
            if name in ("eedf_energy", "eedf", "extras"):
                continue
            if isinstance(value, np.ndarray):
                row |= {f"{name}_{axis}": float(component) for axis, component in zip("xyz", value)}
            elif isinstance(value, dict):
                prefix = "rate_coefficient" if name == "rate_coefficients" else "rate_coefficient_error"
                row |= {f"{prefix}[{label}]": float(rate) for label, rate in value.items()}
            else:
                row[name] = value
        row["collisions_per_second"] = self.collisions_per_second
        return row


def _from_json(value, kind: str):
    """A to_dict value of a field of type ``kind`` ("float", "np.ndarray", "dict" ...), None read as NaN."""
    if kind == "np.ndarray":
        return np.array([math.nan if item is None else item for item in value], dtype=float)
    if kind == "float":
        return math.nan if value is None else float(value)
    if kind == "dict" and isinstance(value, Mapping):
        return {key: math.nan if item is None else item for key, item in value.items()}
    return value


# ------------------------------------------------------------------ the particle store


@dataclass
class _Swarm:
    pos: np.ndarray
    vel: np.ndarray
    states: np.ndarray
    alive: np.ndarray
    group: np.ndarray

    def copy(self):
        return _Swarm(self.pos.copy(), self.vel.copy(), self.states.copy(), self.alive.copy(), self.group.copy())

    @property
    def size(self):
        return self.pos.shape[0]

    def take(self, index):
        return _Swarm(self.pos[index], self.vel[index], self.states[index], self.alive[index], self.group[index])


def _initial_swarm(particles, groups, seed, mass, initial_energy):
    sequences = np.random.SeedSequence(seed).spawn(groups)
    per_group = np.full(groups, particles // groups)
    per_group[: particles % groups] += 1
    parts = []
    for g, (sequence, count) in enumerate(zip(sequences, per_group)):
        stream_seq, velocity_seq = sequence.spawn(2)
        states = stream_seq.generate_state(4 * count, np.uint64).reshape(count, 4)
        sigma = math.sqrt(2.0 * initial_energy * EV / (3.0 * mass))
        vel = np.random.default_rng(velocity_seq).normal(0.0, sigma, (count, 3))
        parts.append((np.zeros((count, 3)), vel, states, np.ones(count, bool), np.full(count, g, np.int64)))
    return _Swarm(*(np.ascontiguousarray(np.concatenate(column)) for column in zip(*parts)))


class _Stepper:
    """Advances the swarm by one sampling interval, in parallel threads."""

    def __init__(self, tables: KernelTables, field_record, mass, density, sharing, threads):
        self.tables = tables
        self.field = field_record
        self.mass = mass
        self.density = density
        self.sharing = sharing
        self.threads = threads
        self.slots = 4 if np.any(tables.kind == _k.IONIZATION) else 0
        self.check = bool(CHECK_BOUND)
        self.pool = ThreadPoolExecutor(threads) if threads > 1 else None

    def close(self):
        if self.pool is not None:
            self.pool.shutdown()

    def _run(self, swarm, t0, t1, buffers):
        tallies, child_pos, child_vel, child_state, child_alive, child_count = buffers
        n = swarm.size
        chunks = max(1, min(n, 8 * self.threads))
        bounds = np.linspace(0, n, chunks + 1).astype(np.int64)

        def work(c):
            # window and growth are passed although they have defaults: numba's specialization for
            # omitted arguments ran about 15 % slower
            _k.advance_swarm(int(bounds[c]), int(bounds[c + 1]), swarm.pos, swarm.vel, swarm.states, swarm.alive,
                             t0, t1, self.field, self.mass, self.density, *self.tables.arrays(), self.sharing,
                             *self.tables.lookup(), tallies, child_pos, child_vel, child_state, child_alive,
                             child_count, self.check, _k.WINDOW_COLLISIONS, _k.WINDOW_GROWTH)

        if self.pool is None:
            for c in range(chunks):
                work(c)
        else:
            list(self.pool.map(work, range(chunks)))

    def step(self, swarm: _Swarm, t0, t1, groups, control=None):
        """Advance from t0 to t1; return (swarm with children appended, per-group tallies).

        More children than slots: the step is repeated with twice the slots,
        up to MAX_SLOTS, then split into two half steps.
        """
        while True:
            n, slots = swarm.size, self.slots
            buffers = (np.zeros((n, self.tables.kind.size + _k.EXTRA_COLUMNS)), np.zeros((n, slots, 3)),
                       np.zeros((n, slots, 3)), np.zeros((n, slots, 4), np.uint64), np.zeros((n, slots), bool),
                       np.zeros(n, np.int64))
            backup = swarm.copy() if slots else None
            self._run(swarm, t0, t1, buffers)
            tallies, child_pos, child_vel, child_state, child_alive, child_count = buffers
            if np.all(child_count <= slots):
                break
            swarm = backup
            if self.slots < MAX_SLOTS:
                self.slots *= 2
                continue
            middle = 0.5 * (t0 + t1)
            swarm, first = self.step(swarm, t0, middle, groups, control)
            if control is not None:
                swarm = control(swarm)
            swarm, second = self.step(swarm, middle, t1, groups, control)
            return swarm, first + second
        group_tally = _k.group_sums(tallies, swarm.group, groups)
        if slots and child_count.any():
            born = (np.arange(slots)[None, :] < child_count[:, None]) & child_alive
            owner = np.nonzero(born)[0]
            swarm = _Swarm(np.concatenate([swarm.pos, child_pos[born]]), np.concatenate([swarm.vel, child_vel[born]]),
                           np.concatenate([swarm.states, child_state[born]]),
                           np.concatenate([swarm.alive, np.ones(owner.size, bool)]),
                           np.concatenate([swarm.group, swarm.group[owner]]))
        return swarm, group_tally


def _control_population(swarm: _Swarm, groups, target, rng):
    """Drop the dead; keep each group between target/2 and 2 target by random thinning or cloning."""
    if swarm.alive.all():
        alive_swarm = swarm
    else:
        alive_swarm = swarm.take(np.nonzero(swarm.alive)[0])
    counts = np.bincount(alive_swarm.group, minlength=groups)
    if np.all((counts >= target / 2) & (counts <= 2 * target)) or counts.min() == 0:
        return alive_swarm
    keep = []
    for g in range(groups):
        members = np.nonzero(alive_swarm.group == g)[0]
        if members.size > 2 * target or members.size < target / 2:
            members = np.sort(rng.choice(members, size=target, replace=members.size < target))
        keep.append(members)
    index = np.concatenate(keep)
    result = alive_swarm.take(index)
    repeated = np.zeros(index.size, bool)
    repeated[1:] = index[1:] == index[:-1]
    for row in np.nonzero(repeated)[0]:  # clones get fresh streams
        result.states[row] = np.random.SeedSequence(int(rng.integers(2**63))).generate_state(4, np.uint64)
    return result


# ------------------------------------------------------------------ estimators


def _slope(t, y):
    """Least-squares slope of y(t) along axis 0."""
    tc = t - t.mean()
    return np.tensordot(tc, y - y.mean(axis=0), axes=(0, 0)) / np.dot(tc, tc)


def _estimates(times, moments, tallies, kinds, density):
    """Per-group estimates (groups on the first axis) from the steady window."""
    n = moments[..., 0]
    mean = moments[..., 1:14] / n[..., None]
    centroid = mean[..., 0:3]
    variance = (mean[..., 3:6] - centroid**2) * (n / np.maximum(n - 1, 1))[..., None]
    velocity = mean[..., 6:9]
    energy = mean[..., 9] / EV
    cross = mean[..., 10:13] - centroid * velocity
    rates_time = tallies.sum(axis=0)
    n_proc = len(kinds)
    particle_time = rates_time[:, n_proc + _k.TIME_COLUMN_OFFSET]
    counts = rates_time[:, :n_proc]
    est = {
        "mean_energy": energy.mean(axis=0),
        "drift_velocity_flux": velocity.mean(axis=0),
        "drift_velocity_bulk": _slope(times, centroid),
        "diffusion_L_N_flux": density * cross[..., 2].mean(axis=0),
        "diffusion_T_N_flux": density * 0.5 * (cross[..., 0] + cross[..., 1]).mean(axis=0),
        "diffusion_L_N": density * 0.5 * _slope(times, variance[..., 2]),
        "diffusion_T_N": density * 0.25 * _slope(times, variance[..., 0] + variance[..., 1]),
        "rates": counts / (particle_time[:, None] * density),
    }
    ionization = np.array([kind == "ionization" for kind in kinds])
    attachment = np.array([kind == "attachment" for kind in kinds])
    est["ionization_frequency_N"] = counts[:, ionization].sum(axis=1) / (particle_time * density)
    est["attachment_frequency_N"] = counts[:, attachment].sum(axis=1) / (particle_time * density)
    return est


def _mean_and_error(values):
    values = np.asarray(values, dtype=float)
    return values.mean(axis=0), values.std(axis=0, ddof=1) / math.sqrt(values.shape[0])


def _real(value, name, low=-math.inf, high=math.inf, *, inclusive=(False, False), length=None):
    """``value`` as a float (a vector if ``length`` is given) in the range from ``low`` to ``high``.

    Bools and non-numbers raise TypeError; a wrong shape, NaN or a value out of range raise ValueError
    naming ``name`` and the range. The ends are open by default, so infinities are refused.
    """
    array = _arrays.as_float_array(value, name)  # refuses bools
    shape = () if length is None else (length,)
    if array.shape != shape:
        what = "a single number" if length is None else f"a {length}-vector"
        raise ValueError(f"{name} must be {what}; got shape {array.shape}")
    _arrays.require_in_range(array, name, low, high, inclusive=inclusive)
    return float(array) if length is None else array


def _integer(value, name, low, high=None):
    """``value`` as an int in [low, high] (no upper end if ``high`` is None); bools are refused."""
    allowed = f">= {low}" if high is None else f"in [{low}, {high}]"
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer {allowed}; got {value!r}")
    if not (value >= low and (high is None or value <= high)):
        raise ValueError(f"{name} must be an integer {allowed}; got {value}")
    return int(value)


def _validated(gas, reduced_field, reduced_magnetic_field, gas_temperature, seed, mass, charge, initial_energy):
    """Check the arguments shared by :func:`simulate_swarm` and :func:`trace_trajectories`."""
    if not isinstance(gas, Gas):
        raise TypeError("gas must be a Gas (e.g. from collisionkit.transport.gases or read_lxcat); "
                        f"got {type(gas).__name__}")
    _real(reduced_field, "reduced_field (Td)", 0.0, inclusive=(True, False))
    _real(reduced_magnetic_field, "reduced_magnetic_field (Hx)")
    _real(gas_temperature, "gas_temperature (K)", 0.0, inclusive=(True, False))
    _integer(seed, "seed", 0)
    _real(mass, "mass (kg)", 0.0)
    _real(charge, "charge (C)")
    _real(initial_energy, "initial_energy (eV)", 0.0)


def _validated_run(particles, groups, gravity, sharing, tolerances, collision_budget, max_seconds,
                   collisions_per_sample, min_samples, energy_bins, threads, progress):
    """Check the run settings of :func:`simulate_swarm`; return ``gravity`` as a float 3-vector."""
    _integer(groups, "groups", 4, 1024)
    _integer(particles, f"particles (8 per group, {groups} groups)", 8 * groups)
    gravity = _real(gravity, "gravity (m/s^2)", length=3)
    if not (isinstance(sharing, str) and sharing in SHARING):
        raise ValueError(f"sharing must be one of {sorted(SHARING)}; got {sharing!r}")
    if not isinstance(tolerances, Mapping):
        raise TypeError(f"tolerances must be a dict of target relative errors; got {type(tolerances).__name__}")
    unknown = set(tolerances) - set(DEFAULT_TOLERANCES)
    if unknown:
        raise ValueError(f"tolerances keys must be among {sorted(DEFAULT_TOLERANCES)}; got {sorted(unknown)}")
    for key, value in tolerances.items():
        _real(value, f"tolerances[{key!r}]", 0.0)
    _real(collision_budget, "collision_budget", 0.0)
    _real(max_seconds, "max_seconds", 0.0, inclusive=(False, True))
    _real(collisions_per_sample, "collisions_per_sample", 0.0)
    _integer(min_samples, "min_samples", 1)
    _integer(energy_bins, "energy_bins", 1)
    if threads is not None:
        _integer(threads, "threads", 1)
    if progress is not None and not callable(progress):
        raise TypeError(f"progress must be a callable or None; got {type(progress).__name__}")
    return gravity


def _reachable(tolerances, defaults, reduced_field, charge, gravity, gas_temperature):
    """The tolerances a swarm can meet; an undriven one (no field on its charge, no gravity) is refused or thermal.

    Nothing heats an undriven swarm: in a gas at 0 K it cools without end (no
    steady state, so the run would use its whole budget); in a warm gas it
    thermalises, and its drift is zero by symmetry, so a relative error of
    the drift can never be reached: the default drift tolerance is dropped,
    an explicit one refused.
    """
    driven = (reduced_field > 0.0 and charge != 0.0) or bool(np.any(np.asarray(gravity) != 0.0))
    if driven:
        return dict(tolerances)
    if gas_temperature == 0.0:
        raise ValueError("nothing heats this swarm (reduced_field = 0 or charge = 0, and no gravity) and the gas is "
                         "at 0 K: it cools without end, with no steady state; give reduced_field > 0 or "
                         "gas_temperature > 0")
    drift = [name for name in tolerances if name.startswith("drift_velocity")]
    if drift and not defaults:
        raise ValueError(f"tolerances[{drift[0]!r}] cannot be met: the drift of a swarm without a field or gravity "
                         "is zero by symmetry (no relative error); leave it out")
    return {name: value for name, value in tolerances.items() if name not in drift}


# Components of the position spread behind each bulk diffusion coefficient (z; x and y)
DIFFUSION_COMPONENTS = {"diffusion_L_N": 1, "diffusion_T_N": 2}
# warn only well below the floor: its constant depends on the window (measured 0.9-1.2 sqrt(2 / N) for D_L)
FLOOR_MARGIN = 0.7


def diffusion_error_floor(name: str, particles: int) -> float:
    r"""Relative error below which a bulk diffusion coefficient of ``particles`` does not go, however long the run.

    The bulk coefficient is the growth rate of the swarm's spread,
    ``D = (1/2) d Var(z)/dt``. The sample variance of N walkers that have
    spread to ``Var = 2 D t`` scatters by ``Var sqrt(2 / N)``, in proportion
    to ``t``, so the least-squares slope keeps a relative error of about
    ``sqrt(2 / N)`` (``sqrt(1 / N)`` for the transverse coefficient, which
    averages two axes) instead of falling as ``1 / sqrt(t)``: exactly
    ``sqrt(6/5) sqrt(2 / N)`` for walkers fitted from the start of their
    spreading, more for a window that starts later. The value returned is
    ``sqrt(2 / N)`` (per axis), a lower bound. Reid's ramp at 1 Td: 3.7 % at
    N = 2000 after 5e7 and 2e8 collisions alike.

    Examples
    --------
    >>> from collisionkit.transport.swarm import diffusion_error_floor
    >>> round(diffusion_error_floor("diffusion_L_N", 20000), 4)
    0.01
    """
    if name not in DIFFUSION_COMPONENTS:
        raise ValueError(f"name must be one of {sorted(DIFFUSION_COMPONENTS)}; got {name!r}")
    return math.sqrt(2.0 / (DIFFUSION_COMPONENTS[name] * _integer(particles, "particles", 1)))


def _warn_unreachable_diffusion(tolerances, particles, defaults):
    """One warning naming the diffusion tolerances that lie well below the error floor only more particles lower."""
    out_of_reach = []
    needed = 0
    for name, tolerance in tolerances.items():
        if name in DIFFUSION_COMPONENTS:
            floor = diffusion_error_floor(name, particles)
            if tolerance < FLOOR_MARGIN * floor:
                out_of_reach.append(f"{name} {tolerance:g} (floor about {floor:.2g})")
                needed = max(needed, math.ceil(2.0 / (DIFFUSION_COMPONENTS[name] * tolerance**2)))
    if out_of_reach:
        which = "the default tolerances" if defaults else "tolerances"
        warnings.warn(f"{which} for {', '.join(out_of_reach)} are out of reach of {particles} particles: the error "
                      "of a bulk diffusion coefficient stops falling with run length at about sqrt(2 / particles) "
                      "(sqrt(1 / particles) transverse), so the run will likely use its whole collision budget; "
                      f"use particles >= {needed} or a looser diffusion tolerance", stacklevel=3)


def _field_record(reduced_field, reduced_magnetic_field, density, mass, charge, gravity):
    electric = np.array([0.0, 0.0, reduced_field * TOWNSEND * density])
    magnetic = np.array([0.0, reduced_magnetic_field * HUXLEY * density, 0.0])
    acceleration = charge * electric / mass + np.asarray(gravity, dtype=float)
    return _k.derived_field(acceleration, charge * magnetic / mass)


def simulate_swarm(
    gas: Gas,
    reduced_field: float,
    *,
    reduced_magnetic_field: float = 0.0,
    gas_temperature: float = 0.0,
    particles: int = 20_000,
    groups: int = 16,
    seed: int = 0,
    mass: float = constants.m_e,
    charge: float = -constants.e,
    gravity=(0.0, 0.0, 0.0),
    sharing: str = "equal",
    initial_energy: float = 1.0,
    tolerances: dict | None = None,
    collision_budget: float = 2e9,
    max_seconds: float = math.inf,
    collisions_per_sample: float = 20.0,
    min_samples: int = 4 * STEPS_PER_CHUNK,
    energy_bins: int = 200,
    threads: int | None = None,
    progress=None,
) -> SwarmResult:
    r"""Run a swarm to steady state and measure its transport coefficients.

    Parameters
    ----------
    gas : Gas
        Target gas (see :mod:`collisionkit.transport.gases`, :mod:`~collisionkit.transport.lxcat`).
    reduced_field : float
        E/N in Td (>= 0); E points along +z.
    reduced_magnetic_field : float
        B/N in Hx; B points along +y.
    gas_temperature : float
        K (>= 0); 0 puts the targets at rest.
    particles, groups, seed : int
        Initial particles (>= 8 groups), independent groups (errors; 4 to
        1024), seed of the streams (>= 0).
    mass, charge : float
        Projectile (kg > 0, C); an electron by default.
    gravity : 3-vector
        Extra uniform acceleration (m/s^2, finite).
    sharing : {"equal", "uniform"}
        Energy sharing between the two electrons after ionization.
    initial_energy : float
        Mean energy (eV, > 0) of the initial Maxwellian.
    tolerances : dict
        Target relative errors (> 0) of ``mean_energy``, ``drift_velocity_bulk``,
        ``diffusion_L_N``, ``diffusion_T_N``; the run stops when all are met,
        or at ``collision_budget`` real collisions, or after ``max_seconds``
        (both > 0; ``result.converged`` tells which). The error of a bulk
        diffusion coefficient stops falling with run length near
        :func:`diffusion_error_floor` (about ``sqrt(2 / particles)``): a
        diffusion tolerance well below it warns. A swarm with no field
        on its charge and no gravity needs ``gas_temperature > 0`` (else it
        cools forever); it thermalises with zero drift, so it takes no drift
        tolerance (the default one is dropped).
    collisions_per_sample : float
        Mean real collisions per particle between samples (> 0).
    min_samples : int
        Samples after the transient before convergence is tested (>= 1).
    energy_bins : int
        Bins of the energy distribution (>= 1).
    threads : int
        Worker threads (>= 1; default: all cores); results do not depend on it.
    progress : callable
        Called with the fraction of the collision budget used so far.

    Returns
    -------
    SwarmResult

    Raises
    ------
    TypeError
        If ``gas`` is not a :class:`Gas`, or an argument is not a number of the
        right kind (bools are refused).
    ValueError
        If an argument is out of its range; the message names it and the range.

    Notes
    -----
    The transient ends when the chunk-averaged mean energy of the last
    chunks shows no trend (its change over three chunks is below three
    standard errors or 1e-3 relative).

    Examples
    --------
    Maxwell model, W = qE/(mu nu) exactly:

    >>> from collisionkit.transport import maxwell_model, simulate_swarm
    >>> me = 9.1093837e-31
    >>> r = simulate_swarm(maxwell_model(1e-13, mass=10 * me), 10.0, particles=1000, seed=1,
    ...                    tolerances={"drift_velocity_bulk": 0.02}, threads=1)
    >>> exact = 1.602176634e-19 * 10e-21 * 1e24 / (me * 10 / 11 * 1e11)  # qE / (mu nu)
    >>> bool(abs(abs(r.drift_velocity_flux[2]) / exact - 1) < 0.03)
    True
    """
    defaults = tolerances is None
    tolerances = DEFAULT_TOLERANCES if defaults else tolerances
    _validated(gas, reduced_field, reduced_magnetic_field, gas_temperature, seed, mass, charge, initial_energy)
    gravity = _validated_run(particles, groups, gravity, sharing, tolerances, collision_budget, max_seconds,
                             collisions_per_sample, min_samples, energy_bins, threads, progress)
    tolerances = _reachable(tolerances, tolerances is DEFAULT_TOLERANCES, reduced_field, charge, gravity,
                            gas_temperature)
    _warn_unreachable_diffusion(tolerances, particles, defaults)
    threads = threads or os.cpu_count() or 1
    density = REFERENCE_DENSITY
    tables = build_tables(gas, mass, gas_temperature)
    field_record = _field_record(reduced_field, reduced_magnetic_field, density, mass, charge, gravity)
    swarm = _initial_swarm(particles, groups, seed, mass, initial_energy)
    rng = np.random.default_rng(np.random.SeedSequence(seed).spawn(groups + 1)[-1])
    stepper = _Stepper(tables, field_record, mass, density, SHARING[sharing], threads)
    target = max(1, particles // groups)
    run = _Run(stepper, swarm, groups, target, rng, tables, density)
    try:
        run.calibrate(collisions_per_sample)
        return run.until_converged(tolerances, collision_budget, max_seconds, min_samples, energy_bins, progress,
                                   (reduced_field, reduced_magnetic_field, gas_temperature, particles))
    finally:
        stepper.close()


class _Run:
    """State of one swarm run: the particles, the clock and the per-step sums."""

    def __init__(self, stepper, swarm, groups, target, rng, tables, density):
        self.stepper, self.swarm, self.groups, self.target, self.rng = stepper, swarm, groups, target, rng
        self.tables, self.density = tables, density
        self.t = 0.0
        self.dt = 0.0
        self.times, self.moments, self.tallies = [], [], []
        self.collisions = 0
        self.nulls = 0
        self.bound_violations = 0
        self.seconds = 0.0
        self.conservative = not np.any((tables.kind == _k.IONIZATION) | (tables.kind == _k.ATTACHMENT))
        self.histogram = None
        self.histogram_step = 0.0
        self.steady_found = False

    def step(self):
        start = time.perf_counter()
        control = None if self.conservative else self._control
        before = max(1, int(self.swarm.alive.sum()))
        swarm, group_tally = self.stepper.step(self.swarm, self.t, self.t + self.dt, self.groups, control)
        self.t += self.dt
        self.seconds += time.perf_counter() - start
        if not self.steady_found and int(swarm.alive.sum()) > GROWTH_LIMIT * before:
            self.dt *= 0.5  # keep the population change per sample moderate (transient only)
        if not self.conservative:
            swarm = _control_population(swarm, self.groups, self.target, self.rng)
        if swarm.size == 0 or not swarm.alive.any():
            raise RuntimeError("every particle was attached: no swarm left (lower attachment or raise E/N)")
        self.swarm = swarm
        moments = np.zeros((self.groups, MOMENT_COLUMNS))
        _k.group_moments(swarm.pos, swarm.vel, swarm.alive, swarm.group, self.groups, self.stepper.mass, moments)
        self.times.append(self.t)
        self.moments.append(moments)
        self.tallies.append(group_tally)
        n_proc = self.tables.kind.size
        real = int(group_tally[:, :n_proc].sum())
        self.collisions += real
        self.nulls += int(group_tally[:, n_proc + _k.NULL_COLUMN_OFFSET].sum())
        self.bound_violations += int(group_tally[:, n_proc + _k.BOUND_COLUMN_OFFSET].sum())
        if self.histogram is not None:
            # the kernel bins 1/2 m v^2 in joules: give it the bin width in joules (histogram_step is in eV)
            _k.energy_histogram(swarm.vel, swarm.alive, self.stepper.mass, self.histogram_step * EV, self.histogram)

    def _control(self, swarm):
        return _control_population(swarm, self.groups, self.target, self.rng)

    def calibrate(self, collisions_per_sample):
        """Pick the sampling interval from the measured collision frequency; the probe step is then forgotten."""
        speed = np.sqrt((self.swarm.vel**2).sum(axis=1)).mean()
        bound = self.tables.bound
        k = min(int(speed / self.tables.bound_step), bound.shape[1] - 1)
        self.dt = collisions_per_sample / max(self.density * bound[:, k].sum(), 1e-300)
        self.step()
        tally = self.tallies[-1]
        n_proc = self.tables.kind.size
        particle_time = max(tally[:, n_proc + _k.TIME_COLUMN_OFFSET].sum(), 1e-300)
        frequency = tally[:, :n_proc].sum() / particle_time
        ionizing = tally[:, :n_proc][:, self.tables.kind == _k.IONIZATION].sum() / particle_time
        if frequency > 0:
            self.dt = collisions_per_sample / frequency
        if ionizing > 0:
            self.dt = min(self.dt, 0.1 / ionizing)
        self.times, self.moments, self.tallies = [], [], []
        # the probe is the first step, which compiles the kernel on a cold numba cache (seconds): counting it
        # would make collisions_per_second measure the compiler
        self.seconds = 0.0
        self.collisions = self.nulls = 0

    def _chunk_energy(self, chunk):
        m = np.array(self.moments[-STEPS_PER_CHUNK * chunk:][:STEPS_PER_CHUNK] if chunk == 1 else
                     self.moments[-STEPS_PER_CHUNK * chunk:-STEPS_PER_CHUNK * (chunk - 1)])
        per_group = (m[..., 10] / m[..., 0]).mean(axis=0) / EV
        return _mean_and_error(per_group)

    def _steady(self):
        if len(self.moments) < 3 * STEPS_PER_CHUNK:
            return False
        (last, last_err), (first, first_err) = self._chunk_energy(1), self._chunk_energy(3)
        change = abs(last - first)
        return change < max(3.0 * math.hypot(last_err, first_err), 1e-3 * abs(last))

    def until_converged(self, tolerances, budget, max_seconds, min_samples, energy_bins, progress, setup):
        """Run the transient, then measure until the tolerances are met or the budget is spent.

        The budget (collisions or seconds) is checked after every sample, so it
        is overshot by at most one sample, or by the two samples a result needs
        at the least when the transient used it up.
        """
        def spent():
            return self.collisions >= budget or self.seconds >= max_seconds

        while not self._steady() and not spent():
            for _ in range(STEPS_PER_CHUNK):
                self.step()
                if spent():
                    break
            if progress:
                progress(min(1.0, self.collisions / budget))
        self.steady_found = True
        start = len(self.times)
        energies = self._current_energies()
        self.histogram_step = 4.0 * energies.mean() / energy_bins
        self.histogram = np.zeros(energy_bins + 1)  # the last slot counts energies beyond the last bin
        while True:
            for _ in range(STEPS_PER_CHUNK):
                self.step()
                if spent() and len(self.times) - start >= MIN_RESULT_SAMPLES:
                    break
            samples = len(self.times) - start
            if samples >= min_samples or spent():
                result = self._result(start, setup, False)
                converged = samples >= min_samples and all(
                    result.relative_error(name) < tol for name, tol in tolerances.items())
                if converged or spent():
                    result.converged = converged
                    return result
            if progress:
                progress(min(1.0, self.collisions / budget))

    def _current_energies(self):
        alive = self.swarm.alive
        return 0.5 * self.stepper.mass * (self.swarm.vel[alive] ** 2).sum(axis=1) / EV

    def _result(self, start, setup, converged):
        times = np.array(self.times[start:])
        moments = np.array(self.moments[start:])
        tallies = np.array(self.tallies[start + 1:]) if len(self.tallies) > start + 1 else np.array(self.tallies[start:])
        est = _estimates(times, moments, tallies, self.tables.kinds, self.density)
        values = {name: _mean_and_error(value) for name, value in est.items()}
        rates, rate_errors = values.pop("rates")
        total = max(self.histogram.sum(), 1.0)
        centres = (np.arange(self.histogram.size - 1) + 0.5) * self.histogram_step
        density = self.histogram[:-1] / total / self.histogram_step
        reduced_field, reduced_magnetic_field, gas_temperature, particles = setup
        return SwarmResult(
            reduced_field=float(reduced_field),
            reduced_magnetic_field=float(reduced_magnetic_field),
            gas_temperature=float(gas_temperature),
            mean_energy=float(values["mean_energy"][0]),
            mean_energy_error=float(values["mean_energy"][1]),
            drift_velocity_flux=values["drift_velocity_flux"][0],
            drift_velocity_flux_error=values["drift_velocity_flux"][1],
            drift_velocity_bulk=values["drift_velocity_bulk"][0],
            drift_velocity_bulk_error=values["drift_velocity_bulk"][1],
            diffusion_L_N_flux=float(values["diffusion_L_N_flux"][0]),
            diffusion_L_N_flux_error=float(values["diffusion_L_N_flux"][1]),
            diffusion_T_N_flux=float(values["diffusion_T_N_flux"][0]),
            diffusion_T_N_flux_error=float(values["diffusion_T_N_flux"][1]),
            diffusion_L_N=float(values["diffusion_L_N"][0]),
            diffusion_L_N_error=float(values["diffusion_L_N"][1]),
            diffusion_T_N=float(values["diffusion_T_N"][0]),
            diffusion_T_N_error=float(values["diffusion_T_N"][1]),
            rate_coefficients=dict(zip(self.tables.labels, rates.tolist())),
            rate_coefficient_errors=dict(zip(self.tables.labels, rate_errors.tolist())),
            ionization_frequency_N=float(values["ionization_frequency_N"][0]),
            ionization_frequency_N_error=float(values["ionization_frequency_N"][1]),
            attachment_frequency_N=float(values["attachment_frequency_N"][0]),
            attachment_frequency_N_error=float(values["attachment_frequency_N"][1]),
            eedf_energy=centres,
            eedf=density,
            eedf_above=float(self.histogram[-1] / total),
            collisions=self.collisions,
            null_collisions=self.nulls,
            seconds=self.seconds,
            simulated_time=self.t,
            steady_from=float(times[0]),
            particles=int(particles),
            groups=self.groups,
            converged=converged,
            extras={"bound_violations": self.bound_violations} if self.stepper.check else {},
        )


def trace_trajectories(gas: Gas, reduced_field: float, *, particles: int = 5, collisions: float = 200.0,
                       points: int = 2000, reduced_magnetic_field: float = 0.0, seed: int = 0,
                       initial_energy: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Positions of a few particles sampled on a uniform time grid (for plots).

    Returns ``(times, positions)`` with positions of shape (points, particles, 3);
    the run lasts about ``collisions`` real collisions per particle (finite, > 0).
    ``particles`` and ``points`` are integers >= 1; the other arguments are
    those of :func:`simulate_swarm` (an electron, no ionization children).

    Examples
    --------
    >>> from collisionkit.transport import reid_ramp
    >>> from collisionkit.transport.swarm import trace_trajectories
    >>> t, r = trace_trajectories(reid_ramp(), 12.0, particles=2, points=50, seed=1)
    >>> r.shape
    (50, 2, 3)
    """
    _validated(gas, reduced_field, reduced_magnetic_field, 0.0, seed, constants.m_e, -constants.e, initial_energy)
    _integer(particles, "particles", 1)
    _real(collisions, "collisions (per particle)", 0.0)
    _integer(points, "points", 1)
    tables = build_tables(gas, constants.m_e, 0.0)
    field_record = _field_record(reduced_field, reduced_magnetic_field, REFERENCE_DENSITY, constants.m_e,
                                 -constants.e, (0.0, 0.0, 0.0))
    swarm = _initial_swarm(particles, 1, seed, constants.m_e, initial_energy)
    stepper = _Stepper(tables, field_record, constants.m_e, REFERENCE_DENSITY, _k.SHARE_EQUAL, 1)
    stepper.slots = 0  # children are not followed in a trace
    run = _Run(stepper, swarm, 1, particles, None, tables, REFERENCE_DENSITY)
    run.conservative = True
    run.calibrate(collisions / points)
    positions = np.empty((points, particles, 3))
    for k in range(points):
        run.step()
        positions[k] = run.swarm.pos[:particles]
    return np.array(run.times), positions
