"""The machinery of a swarm run: the particle store, the parallel stepper, population control and the run loop.

:func:`collisionkit.transport.swarm.simulate_swarm` checks its arguments and
hands over to :class:`SwarmRun`, which steps the swarm with a
:class:`Stepper` (the kernel :func:`collisionkit._kernels.transport.advance_swarm`
in threads), keeps ionizing or attaching swarms at their size, finds the end
of the transient and measures until the tolerances are met.
"""

from __future__ import annotations

import math
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np
from scipy import constants

from .._kernels import transport as _k
from ._estimators import drift_diffusion_correlations, estimates, mean_and_error, spatial_moments, townsend_estimates
from ._steady import mser_truncation
from ._tables import KernelTables
from .swarm_result import SwarmResult

EV = constants.e
STEPS_PER_CHUNK = 25
MIN_RESULT_SAMPLES = 2  # samples a result needs at the least (slopes)
GROWTH_LIMIT = 1.5  # population growth per sample that halves the interval during the transient
MAX_SLOTS = 16  # child slots per particle and step before a step is split
MOMENT_COLUMNS = 14
# particles per kernel call at most: a step of a few tens of collisions each takes about 0.1 s of them, so
# Ctrl-C lands between calls however large the swarm (results do not depend on how particles are split)
PARTICLES_PER_CALL = 1 << 15
# trials a particle may take in a step per real collision planned for it (at least _k.TRIAL_BUDGET)
TRIALS_PER_PLANNED_COLLISION = 10_000


@dataclass
class Swarm:
    """The particles of a swarm: positions, velocities, random streams, alive flags and groups (one row each)."""

    pos: np.ndarray
    vel: np.ndarray
    states: np.ndarray
    alive: np.ndarray
    group: np.ndarray

    def copy(self):
        """A deep copy (the stepper keeps one to repeat a step)."""
        return Swarm(self.pos.copy(), self.vel.copy(), self.states.copy(), self.alive.copy(), self.group.copy())

    @property
    def size(self):
        """Number of particles, alive or not."""
        return self.pos.shape[0]

    def take(self, index):
        """The particles at ``index`` (an index array), as a new swarm."""
        return Swarm(self.pos[index], self.vel[index], self.states[index], self.alive[index], self.group[index])


def initial_swarm(particles, groups, seed, mass, initial_energy):
    """``particles`` at the origin dealt into ``groups`` with their own streams, Maxwellian velocities of mean
    energy ``initial_energy`` (eV)."""
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
    return Swarm(*(np.ascontiguousarray(np.concatenate(column)) for column in zip(*parts)))


class Stepper:
    """Advances the swarm by one sampling interval, in parallel threads."""

    def __init__(self, tables: KernelTables, field_record, mass, density, sharing, threads, check=False):
        self.tables = tables
        self.field = field_record
        self.mass = mass
        self.density = density
        self.sharing = sharing
        self.threads = threads
        self.slots = 4 if np.any(tables.kind == _k.IONIZATION) else 0
        self.check = bool(check)  # count trials whose true rate exceeds the bound
        self.trial_budget = _k.TRIAL_BUDGET  # windows and trials a particle may take in one step
        self.pool = ThreadPoolExecutor(threads) if threads > 1 else None

    def close(self):
        """Stop the worker threads (the calls not started are dropped: after Ctrl-C, nothing waits for them)."""
        if self.pool is not None:
            self.pool.shutdown(cancel_futures=True)

    def _run(self, swarm, t0, t1, buffers):
        tallies, child_pos, child_vel, child_state, child_alive, child_count = buffers
        n = swarm.size
        chunks = max(1, min(n, max(8 * self.threads, -(-n // PARTICLES_PER_CALL))))
        bounds = np.linspace(0, n, chunks + 1).astype(np.int64)

        def work(c):
            # window, growth and budget are passed although they have defaults: numba's specialization for
            # omitted arguments ran about 15 % slower
            return _k.advance_swarm(int(bounds[c]), int(bounds[c + 1]), swarm.pos, swarm.vel, swarm.states,
                                    swarm.alive, t0, t1, self.field, self.mass, self.density, *self.tables.arrays(),
                                    self.sharing, *self.tables.lookup(), tallies, child_pos, child_vel, child_state,
                                    child_alive, child_count, self.check, _k.WINDOW_COLLISIONS, _k.WINDOW_GROWTH,
                                    self.trial_budget)

        # one call per chunk of particles (a fraction of a second each), so Ctrl-C lands between calls; the
        # first runaway ends the step (the calls not started yet are dropped when the stepper closes)
        outcomes = map(work, range(chunks)) if self.pool is None else self.pool.map(work, range(chunks))
        for stalled, speed in outcomes:
            if stalled >= 0:
                raise RuntimeError(self._runaway_message(speed, t1 - t0))

    def _runaway_message(self, speed, duration):
        """Why a step could not end: a particle took ``TRIAL_BUDGET`` trials and reached ``speed`` (m/s).

        Above the top of the tables the field (or a tiny cross section) drove it past the energies they cover;
        below it, with a step far longer than its collisions take, either the step (an oscillating field's
        sampling, a fraction of its period) or a cross section that vanishes where it is (a gap in the tables).
        """
        energy = 0.5 * self.mass * speed**2 / EV
        top = float(self.tables.nodes[-1]) / EV
        head = (f"the swarm cannot be advanced: a particle took {self.trial_budget} trial collisions in a step of "
                f"{duration:.3g} s (planned for about collisions_per_sample real ones) and reached {energy:.3g} eV "
                f"({energy / top:.3g} times the top of the cross-section tables, {top:.3g} eV)")
        if energy > top:
            return (f"{head}: it ran away in the field. Either the field (E/N, or B/N, omega/N, a waveform's peak) "
                    "drives electrons beyond the energies the cross sections cover: lower it, or use cross sections "
                    "that extend to higher energies; or the cross sections are zero or tiny over these energies (an "
                    "all-zero block such as ELASTIC, or a units slip such as cm^2 for m^2)")
        return (f"{head}: it needs far more collisions in a step than planned. Either the step is too long for the "
                "gas (in an oscillating field a sample lasts at least a fraction of the period: raise omega/N), or "
                "the cross sections are zero or tiny over some energies (an all-zero block such as ELASTIC, or a "
                "units slip such as cm^2 for m^2)")

    def step(self, swarm: Swarm, t0, t1, groups, control=None):
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
            if not slots or np.all(child_count <= slots):  # no slots: children are not followed (a trace)
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
            swarm = Swarm(np.concatenate([swarm.pos, child_pos[born]]), np.concatenate([swarm.vel, child_vel[born]]),
                          np.concatenate([swarm.states, child_state[born]]),
                          np.concatenate([swarm.alive, np.ones(owner.size, bool)]),
                          np.concatenate([swarm.group, swarm.group[owner]]))
        return swarm, group_tally


def control_population(swarm: Swarm, groups, target, rng):
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


def grow_swarm(swarm: Swarm, counts, rng):
    """Each group's living particles cloned up to ``counts[g]`` (whole copies each, then extra ones at random).

    The transient runs with a fraction of the particles (it costs per
    particle, and its end does not depend on their number); once it ends,
    every particle is copied the same number of times, which keeps each
    group's distribution, and the clones get fresh random streams so that
    they part at their next collision.
    """
    keep = []
    for g, count in enumerate(counts):
        members = np.nonzero((swarm.group == g) & swarm.alive)[0]
        if members.size == 0:
            continue
        copies, extra = divmod(int(count), members.size)
        chosen = np.concatenate([np.repeat(members, copies), np.sort(rng.choice(members, extra, replace=False))])
        keep.append(np.sort(chosen, kind="stable"))
    index = np.concatenate(keep)
    result = swarm.take(index)
    repeated = np.zeros(index.size, bool)
    repeated[1:] = index[1:] == index[:-1]
    clones = np.nonzero(repeated)[0]
    result.states[clones] = rng.integers(1, 2**63, size=(clones.size, 4), dtype=np.uint64)  # fresh streams
    return result


class SwarmRun:
    """State of one swarm run: the particles, the clock and the per-step sums."""

    def __init__(self, stepper, swarm, groups, target, rng, tables, density):
        self.stepper, self.swarm, self.groups, self.target, self.rng = stepper, swarm, groups, target, rng
        self.tables, self.density = tables, density
        self.final_counts = None  # per-group particle counts to grow to once the transient ends (None: no growth)
        self.t = 0.0
        self.dt = 0.0
        self.times, self.moments, self.tallies = [], [], []
        self.shift = np.zeros((groups, 6))  # population control's jumps so far (centroid, variance), per group
        self.shifts = []  # self.shift at each sample
        self.collisions = 0
        self.nulls = 0
        self.bound_violations = 0
        self.seconds = 0.0
        self.conservative = not np.any((tables.kind == _k.IONIZATION) | (tables.kind == _k.ATTACHMENT))
        self.histogram = None
        self.histogram_step = 0.0
        self.steady_found = False
        self.found = False  # whether the MSER rule found the transient's end (else the window starts after it)
        self.window_start = 0  # first sample of the steady window, once the transient ended

    def step(self):
        """Advance one sampling interval, control the population and record the group moments and tallies."""
        start = time.perf_counter()
        control = None if self.conservative else self._control
        before = max(1, int(self.swarm.alive.sum()))
        swarm, group_tally = self.stepper.step(self.swarm, self.t, self.t + self.dt, self.groups, control)
        self.t += self.dt
        self.seconds += time.perf_counter() - start
        if not self.steady_found and int(swarm.alive.sum()) > GROWTH_LIMIT * before:
            self.dt *= 0.5  # keep the population change per sample moderate (transient only)
        if not self.conservative:
            swarm = self._control(swarm)
        if swarm.size == 0 or not swarm.alive.any():
            raise RuntimeError("every particle was attached: no swarm left (lower attachment or raise E/N)")
        if not np.isfinite(swarm.vel[swarm.alive]).all():
            raise RuntimeError("particles escaped to unbounded energy (their velocities overflowed): the field "
                               "(E/N, B/N, omega/N, a waveform's peak) drives them beyond the energies the cross "
                               "sections cover, or the cross sections are zero or tiny over the energies reached "
                               "(an all-zero block, or a units slip such as cm^2 for m^2?)")
        self.swarm = swarm
        moments = np.zeros((self.groups, MOMENT_COLUMNS))
        _k.group_moments(swarm.pos, swarm.vel, swarm.alive, swarm.group, self.groups, self.stepper.mass, moments)
        self.times.append(self.t)
        self.moments.append(moments)
        self.shifts.append(self.shift.copy())
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
        """Population control, its jumps of each group's centroid and spatial variance added to ``self.shift``.

        Thinning or cloning at random moves a group's centroid and variance
        by chance (the expected move is zero); the bulk coefficients are
        time slopes of those series, and the chance moves of a wide cloud
        (its spread grows as 2 D t) would dominate their error. The
        estimators subtract the recorded jumps (a control variate of mean
        zero): the series then follow the physical births, deaths and flights
        only.
        """
        controlled = control_population(swarm, self.groups, self.target, self.rng)
        self._record_jump(swarm, controlled)
        return controlled

    def _record_jump(self, before, after):
        """Add the change of each group's centroid and spatial variance from ``before`` to ``after`` to the
        jumps the bulk estimators take out (a subclass keeping more series records their jumps too)."""
        self.shift += self._spatial_moments(after) - self._spatial_moments(before)

    def _grow(self):
        """Clone the transient's swarm up to the run's size (its jumps of centroid and variance recorded)."""
        if self.final_counts is None:
            return
        grown = grow_swarm(self.swarm, self.final_counts, self.rng)
        self._record_jump(self.swarm, grown)
        self.swarm = grown
        self.target = max(1, int(round(np.mean(self.final_counts))))
        self.final_counts = None

    def _spatial_moments(self, swarm):
        """Per group: the centroid (3) and the spatial variance per axis (3) of the living particles."""
        moments = np.zeros((self.groups, MOMENT_COLUMNS))
        _k.group_moments(swarm.pos, swarm.vel, swarm.alive, swarm.group, self.groups, self.stepper.mass, moments)
        return spatial_moments(moments)

    def calibrate(self, collisions_per_sample):
        """Pick the sampling interval from the measured collision frequency; the probe step is then forgotten."""
        speed = np.sqrt((self.swarm.vel**2).sum(axis=1)).mean()
        bound = self.tables.bound
        k = min(int(speed / self.tables.bound_step), bound.shape[1] - 1)
        self.dt = collisions_per_sample / max(self.density * bound[:, k].sum(), 1e-300)
        planned = math.ceil(TRIALS_PER_PLANNED_COLLISION * collisions_per_sample)
        self.stepper.trial_budget = max(_k.TRIAL_BUDGET, planned)
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
        self.times, self.moments, self.tallies, self.shifts = [], [], [], []
        # the probe is the first step, which compiles the kernel on a cold numba cache (seconds): counting it
        # would make collisions_per_second measure the compiler
        self.seconds = 0.0
        self.collisions = self.nulls = 0

    def _steady_start(self):
        """First sample of the steady window by the MSER rule on the mean energy and drift series, or None.

        The series are the swarm's mean energy and mean velocity per sample
        (all groups together); see :mod:`._steady`.
        """
        moments = np.array(self.moments)
        count = np.maximum(moments[..., 0].sum(axis=1), 1.0)
        series = np.column_stack([moments[..., 10].sum(axis=1), moments[..., 7:10].sum(axis=1)]) / count[:, None]
        return mser_truncation(series)

    def until_converged(self, tolerances, budget, max_seconds, min_samples, energy_bins, progress, setup,
                        on_chunk=None):
        """Run the transient, then measure until the tolerances are met or the budget is spent.

        The transient ends where the MSER rule finds it (:mod:`._steady`);
        the rule is applied again to the whole record before every result,
        so a slow tail that the longer record resolves is cut too. The budget
        (collisions or seconds) is checked after every sample, so it is
        overshot by at most one sample, or by the two samples a result needs
        at the least when the transient used it up. ``on_chunk(run)``, if
        given, is called after each chunk of samples that does not end the
        run: there the run's state can be saved (:mod:`._run_snapshot`), and
        a run restored from it goes on exactly as this one.
        """
        def spent():
            return self.collisions >= budget or self.seconds >= max_seconds

        if not self.steady_found:
            start = None
            while start is None and not spent():
                for _ in range(STEPS_PER_CHUNK):
                    self.step()
                    if spent():
                        break
                if progress:
                    progress(min(1.0, self.collisions / budget))
                start = self._steady_start()
                if start is None and on_chunk is not None:
                    on_chunk(self)
            self._end_transient(start, energy_bins)
        while True:
            for _ in range(STEPS_PER_CHUNK):
                self.step()
                if spent() and len(self.times) - self.window_start >= MIN_RESULT_SAMPLES:
                    break
            if self.found:  # the longer record may resolve a slow tail: cut it too (at least half is kept)
                cut = self._steady_start()
                self.window_start = len(self.times) // 2 if cut is None else cut
            samples = len(self.times) - self.window_start
            if samples >= min_samples or spent():
                result = self._result(self.window_start, setup, False)
                converged = samples >= min_samples and all(
                    result.relative_error(name) < tol for name, tol in tolerances.items())
                if converged or spent():
                    result.converged = converged
                    return result
            if progress:
                progress(min(1.0, self.collisions / budget))
            if on_chunk is not None:
                on_chunk(self)

    def _end_transient(self, start, energy_bins):
        """Start the steady window at sample ``start`` (None: the rule found no end, the window starts now), grow
        the swarm to its full size and open the energy histogram."""
        self.found = start is not None
        self.window_start = start if self.found else len(self.times)
        self._grow()
        self.steady_found = True
        energies = self._current_energies()
        self.histogram_step = 4.0 * energies.mean() / energy_bins
        self.histogram = np.zeros(energy_bins + 1)  # the last slot counts energies beyond the last bin

    def _current_energies(self):
        alive = self.swarm.alive
        return 0.5 * self.stepper.mass * (self.swarm.vel[alive] ** 2).sum(axis=1) / EV

    def _result(self, start, setup, converged):
        times = np.array(self.times[start:])
        moments = np.array(self.moments[start:])
        first = start + 1 if len(self.tallies) > start + 1 else start  # the first sample's tallies are of the interval before the window
        tallies = np.array(self.tallies[first:])
        est = estimates(times, moments, tallies, self.tables.kinds, self.density, np.array(self.shifts[start:]))
        values = {name: mean_and_error(value) for name, value in est.items()}
        values |= townsend_estimates(est)
        rates, rate_errors = values.pop("rates")
        correlations = drift_diffusion_correlations(est)
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
            alpha_N=values["alpha_N"][0],
            alpha_N_error=values["alpha_N"][1],
            eta_N=values["eta_N"][0],
            eta_N_error=values["eta_N"][1],
            drift_diffusion_L_correlation=correlations[0],
            drift_diffusion_T_correlation=correlations[1],
        )
