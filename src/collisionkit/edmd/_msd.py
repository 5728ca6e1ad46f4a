"""Mean squared displacements of an EDMD run and the diffusion coefficient they give, with its error.

The error of D cannot come from the blocks (every block's displacement is
measured from overlapping time origins): it comes from independent groups
of particles (:data:`MSD_GROUPS`), whose slopes scatter independently.
"""

from __future__ import annotations

import math

import numpy as np

MSD_GROUPS = 8  # particles dealt into groups (by index) for the error of the diffusion coefficient
MSD_FIT_FROM = 0.3  # the diffusive part of the MSD: fitted from this fraction of the run (or longest lag) on
MSD_MAX_LAGS = 8  # time origins kept for the multiple-origin MSD (memory: this many copies of the positions)


def group_means(values):
    """Mean of per-particle ``values`` over each of the MSD_GROUPS groups (particle i in group i % MSD_GROUPS).

    A group with no particle (fewer particles than groups) gets NaN.
    """
    groups = np.arange(values.size) % MSD_GROUPS
    totals = np.bincount(groups, weights=values, minlength=MSD_GROUPS)
    counts = np.bincount(groups, minlength=MSD_GROUPS)
    return np.divide(totals, counts, out=np.full(MSD_GROUPS, math.nan), where=counts > 0)


class LagMSD:
    """Mean squared displacement over block lags from every block end as a time origin.

    Keeps the last ``lags`` block-end positions; at each block end it adds,
    for each lag k, ``|r(t_b) - r(t_{b-k})|^2`` averaged over all particles
    and over each group of :data:`MSD_GROUPS`, and the time lag. Averaging
    over origins (Allen & Tildesley, Computer Simulation of Liquids, 2nd ed.,
    sec. 8.7; Frenkel & Smit, sec. 4.4.1) makes the error of D fall with the
    number of origins (blocks); from one origin it does not fall with the
    length of the run.
    """

    def __init__(self, lags, positions, time, species=None):
        self.lags = lags
        self.positions, self.times = [positions], [time]
        self.all = np.zeros(lags)
        self.groups = np.zeros((lags, MSD_GROUPS))
        self.time_lags = np.zeros(lags)
        self.counts = np.zeros(lags)
        # a mixture: each species' MSD and its groups (the species' particles dealt as all are), per lag
        self.species = None if species is None else np.asarray(species)
        kinds = 0 if species is None else int(np.max(species)) + 1
        self.species_all = None if species is None else np.zeros((lags, kinds))
        self.species_groups = None if species is None else np.zeros((lags, kinds, MSD_GROUPS))

    def add(self, positions, time):
        """Add the displacements from each kept origin to the block-end ``positions`` (unwrapped) at ``time``."""
        for k in range(1, len(self.positions) + 1):
            squared = np.sum((positions - self.positions[-k]) ** 2, axis=1)
            self.all[k - 1] += np.mean(squared)
            self.groups[k - 1] += group_means(squared)
            if self.species is not None:
                for kind in range(self.species_all.shape[1]):
                    members = squared[self.species == kind]
                    self.species_all[k - 1, kind] += np.mean(members) if members.size else math.nan
                    self.species_groups[k - 1, kind] += group_means(members)
            self.time_lags[k - 1] += time - self.times[-k]
            self.counts[k - 1] += 1
        self.positions = (self.positions + [positions])[-self.lags:]
        self.times = (self.times + [time])[-self.lags:]

    def diffusion(self, dim):
        """(D, error) from the slope over the longer lags, or None with fewer than 2 lags measured."""
        return self._fit(self.all, self.groups, dim)

    def species_diffusion(self, dim):
        """(D, error) of each species (arrays), as :meth:`diffusion`; None for one species or too few lags."""
        if self.species_all is None:
            return None
        fits = [self._fit(self.species_all[:, kind], self.species_groups[:, kind], dim)
                for kind in range(self.species_all.shape[1])]
        if any(fit is None for fit in fits):
            return None
        return np.array([fit[0] for fit in fits]), np.array([fit[1] for fit in fits])

    def _fit(self, msd, groups, dim):
        measured = int(np.count_nonzero(self.counts))
        if measured < 2:
            return None
        first = max(0, min(math.ceil(MSD_FIT_FROM * measured) - 1, measured - 2))
        counts = self.counts[first:measured]
        times = self.time_lags[first:measured] / counts
        slope = float(np.polyfit(times, msd[first:measured] / counts, 1)[0])
        groups = groups[first:measured] / counts[:, None]
        if not np.all(np.isfinite(groups)):
            return slope / (2.0 * dim), math.nan
        return slope / (2.0 * dim), block_error(np.polyfit(times, groups, 1)[0]) / (2.0 * dim)

    def state_dict(self):
        """The accumulators as arrays, for a checkpoint of the sampler."""
        state = {"sampler_lag_positions": np.array(self.positions), "sampler_lag_times": np.array(self.times),
                 "sampler_lag_all": self.all, "sampler_lag_groups": self.groups,
                 "sampler_lag_time_lags": self.time_lags, "sampler_lag_counts": self.counts}
        if self.species is not None:
            state |= {"sampler_lag_species_all": self.species_all, "sampler_lag_species_groups": self.species_groups}
        return state

    @classmethod
    def from_state_dict(cls, state, species=None):
        """The accumulators of a checkpoint, or None for one written before they existed; a mixture's per-species
        ones with its ``species`` (none saved: D per species is not measured)."""
        if "sampler_lag_positions" not in state:
            return None
        lag = cls.__new__(cls)
        saved = "sampler_lag_species_all" in state and species is not None
        lag.species = np.asarray(species) if saved else None
        lag.species_all = np.array(state["sampler_lag_species_all"]) if saved else None
        lag.species_groups = np.array(state["sampler_lag_species_groups"]) if saved else None
        lag.lags = len(state["sampler_lag_counts"])
        lag.positions = list(np.array(state["sampler_lag_positions"]))
        lag.times = [float(t) for t in state["sampler_lag_times"]]
        lag.all = np.array(state["sampler_lag_all"])
        lag.groups = np.array(state["sampler_lag_groups"])
        lag.time_lags = np.array(state["sampler_lag_time_lags"])
        lag.counts = np.array(state["sampler_lag_counts"])
        return lag


def diffusion_from_msd(msd_time, msd, msd_groups, dim):
    """D = slope / (2 d) of the MSD's later part (ballistic start left out), and its standard error.

    Every block's MSD is measured from one time origin, so blocks do not give
    independent values; independent groups of particles do: the error is the
    standard error of the groups' slopes (Frenkel & Smit, Understanding
    Molecular Simulation, sec. 4.4.1, for D from the MSD).
    """
    later = msd_time > MSD_FIT_FROM * msd_time[-1]
    if later.sum() < 2:
        return math.nan, math.nan
    slope = float(np.polyfit(msd_time[later], msd[later], 1)[0])
    groups = np.vstack([np.zeros(MSD_GROUPS), np.asarray(msd_groups, dtype=float)])[later]
    if not np.all(np.isfinite(groups)):
        return slope / (2.0 * dim), math.nan
    group_slopes = np.polyfit(msd_time[later], groups, 1)[0]
    return slope / (2.0 * dim), block_error(group_slopes) / (2.0 * dim)


def block_error(values):
    """Standard error of the mean of independent ``values`` (blocks or groups); NaN for fewer than 2."""
    values = np.asarray(values, dtype=float)
    if values.size < 2:
        return math.nan
    return float(values.std(ddof=1) / math.sqrt(values.size))
