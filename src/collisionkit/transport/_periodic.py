"""A swarm in an oscillating field E0 cos(omega t): sampling on a grid of phases and a periodic steady state.

Samples are taken on a grid of ``P`` phases over the period T = 2 pi/omega:
the run is first brought to a multiple of T/P, then every sample interval
is ``q T / P`` with q the whole number nearest to the interval the collision
frequency asks for, made coprime with P, so P consecutive samples visit every
phase once (stroboscopically when q > 1, at high frequency).

The steady state is periodic: the transient ends where the MSER rule
(:mod:`._steady`) cuts the series of the mean energy averaged over whole
sets of P samples (every phase once). The results then hold, per phase, the mean
energy and the flux drift velocity (group means and standard errors), and
their averages over the phases; the window of the bulk quantities holds a
whole number of sets of phases.
"""

from __future__ import annotations

import math

import numpy as np

from ._estimators import EV, mean_and_error
from ._steady import mser_truncation
from ._tensors import TensorRun

DEFAULT_PHASES = 16
CYCLE_BATCH = 2  # sets of phases per MSER batch (each set is already a mean over a period)


class PeriodicRun(TensorRun):
    """A :class:`~collisionkit.transport._tensors.TensorRun` in an oscillating field of angular frequency ``omega``."""

    def __init__(self, *args, omega, phases=DEFAULT_PHASES, **kwargs):
        super().__init__(*args, **kwargs)
        self.omega, self.phases = float(omega), int(phases)
        self.phase_step = 2.0 * math.pi / (self.omega * self.phases)  # T / P
        self.phase_index = []
        self.on_grid = False  # set once calibrated: every interval is then a multiple of T / P

    def _grid_interval(self, interval):
        """q T / P with q >= 1 the whole number nearest ``interval`` / (T / P), raised to be coprime with P."""
        q = max(1, round(interval / self.phase_step))
        while math.gcd(q, self.phases) != 1:
            q += 1
        return q * self.phase_step

    def step(self):
        """A sample, with the index of its phase on the grid (an interval halved in the transient is put back on it)."""
        if self.on_grid:
            self.dt = self._grid_interval(self.dt)
        super().step()
        self.phase_index.append(int(round(self.t / self.phase_step)) % self.phases)

    def calibrate(self, collisions_per_sample):
        """The interval q T / P nearest the collision-based one (q coprime with P), after a step onto the grid."""
        super().calibrate(collisions_per_sample)
        interval = self._grid_interval(self.dt)
        onto_grid = math.ceil(self.t / self.phase_step) * self.phase_step - self.t
        if onto_grid > 1e-9 * self.phase_step:
            self.dt = onto_grid
            self.step()
        self.t = round(self.t / self.phase_step) * self.phase_step
        self.dt = interval
        self.on_grid = True
        self.times, self.moments, self.tallies, self.tensor_moments, self.phase_index = [], [], [], [], []
        self.shifts, self.covariance_shifts = [], []  # (the jumps so far stay in self.shift: they are cumulative)
        self.seconds = 0.0
        self.collisions = self.nulls = 0

    def _steady_start(self):
        """First sample of the steady window: the MSER rule (:mod:`._steady`) on the mean energy averaged over
        each set of phases (P consecutive samples cover every phase once), or None while still transient."""
        m = np.array(self.moments)
        sets = m.shape[0] // self.phases
        if sets == 0:
            return None
        offset = m.shape[0] - sets * self.phases
        energy = m[offset:, :, 10].sum(axis=1) / np.maximum(m[offset:, :, 0].sum(axis=1), 1.0)
        cut = mser_truncation(energy.reshape(sets, self.phases).mean(axis=1), batch=CYCLE_BATCH)
        return None if cut is None else offset + cut * self.phases

    def _result(self, start, setup, converged):
        window = len(self.times) - start
        if window >= self.phases:
            start += window % self.phases  # whole sets of phases
        else:  # a run stopped by its budget a few samples after the transient: its last set of phases
            start = max(0, len(self.times) - self.phases)
        result = super()._result(start, setup, converged)
        moments = np.array(self.moments[start:])  # (samples, groups, columns)
        index = np.array(self.phase_index[start:])
        energy = moments[..., 10] / moments[..., 0] / EV
        velocity = moments[..., 7:10] / moments[..., 0][..., None]
        by_phase_energy = np.stack([_phase_mean(energy, index == k) for k in range(self.phases)], axis=1)
        by_phase_velocity = np.stack([_phase_mean(velocity, index == k) for k in range(self.phases)], axis=1)
        result.phases = 2.0 * math.pi * np.arange(self.phases) / self.phases
        result.mean_energy_by_phase, result.mean_energy_by_phase_error = mean_and_error(by_phase_energy)
        result.drift_velocity_flux_by_phase, result.drift_velocity_flux_by_phase_error = mean_and_error(
            by_phase_velocity)
        mean_energy, mean_energy_error = mean_and_error(by_phase_energy.mean(axis=1))
        result.mean_energy, result.mean_energy_error = float(mean_energy), float(mean_energy_error)
        result.drift_velocity_flux, result.drift_velocity_flux_error = mean_and_error(by_phase_velocity.mean(axis=1))
        return result


def _phase_mean(values, chosen):
    """Mean over the chosen samples (axis 0); NaN where none was taken (a run shorter than a set of phases)."""
    if not chosen.any():
        return np.full(values.shape[1:], np.nan)
    return values[chosen].mean(axis=0)
