"""Numba kernels of the Monte Carlo transport engine (swarms and slabs).

Algorithm (Krasov, sec. 5.5, extended as in Skullerud, J. Phys. D 1, 1567
(1968) and Lin & Bardsley, J. Chem. Phys. 66, 435 (1977)):

* every particle carries its own random stream (xoshiro256+, state of four
  uint64 words); a kernel call advances particles ``lo..hi`` independently,
  so the result does not depend on how particles are split over threads;
* free flight is exact: constant acceleration, or gyration about B plus the
  E x B drift (the closed-form solution of dv/dt = a + v x Omega);
* collisions by the null-collision method with an exact, speed-dependent
  trial frequency, piecewise constant in time: a flight (from one real
  collision to the next) is cut into windows of about WINDOW_COLLISIONS
  trial collisions; in a window the trial frequency is the table bound
  ``B(v)`` of ``sum_j N sigma_j(eps) g`` (a running maximum over speed
  bins, so it covers every lower speed) at the largest speed the particle
  can reach in the window (exact without B: |v + a t|^2 is convex in t, so
  the largest speed is at an end of the window; with B, |v| + |a| t), plus
  the largest gas speed that can occur. One exponential optical depth is
  drawn per trial and used up window by window (the integrated hazard of a
  piecewise-constant rate). Null trials do not move the particle: it is
  moved to a real collision, or to the end of the step;
* at a trial collision the target species is chosen by its share of the
  trial frequency, a target velocity is drawn from the gas Maxwellian, and
  the process by its rate ``N sigma_j(eps) g + N k_j``; otherwise the
  collision is null. A trial above the species' total rate (one table of
  the summed cross sections) is null without looking at the processes, so
  a gas of many processes costs no more per null trial than one of two;
* scattering in the centre-of-mass frame (isotropic, screened Coulomb,
  Okhrimovskyy, Vahedi-Surendra or forward), exact recoil for elastic
  collisions, thresholds subtracted from the relative kinetic energy (added
  back for a superelastic collision); ionization creates a new particle
  (children are advanced within the same call and stored in the parent's
  child slots).

The kernels are split by responsibility: :mod:`.layout` (process, angular
and sharing codes, tally columns), :mod:`.rng` (random streams),
:mod:`.flight` (exact flight, window speed bounds), :mod:`.cross_sections`
(table lookup, rate bounds), :mod:`.scattering` and :mod:`.collisions`
(velocities after a collision), :mod:`.advance` (the swarm step),
:mod:`.moments` (per-group sums), :mod:`.oscillating` (exact flight in E0 cos(omega t)
with a static B at any angle), :mod:`.waveform` and :mod:`.waveform_magnetic` (a periodic
field given as samples, with or without a static B; :mod:`.waveform_window` its window
bounds) and :mod:`.slab`. The names
:mod:`collisionkit.transport` uses are importable from here.
"""

from __future__ import annotations

from .advance import TRIAL_BUDGET, WINDOW_COLLISIONS, WINDOW_GROWTH, advance_swarm
from .flight import derived_field
from .layout import (
    ATTACHMENT,
    BOUND_COLUMN_OFFSET,
    DISPLACEMENT_COLUMN_OFFSET,
    ELASTIC,
    EXCITATION,
    EXTRA_COLUMNS,
    FORWARD,
    IONIZATION,
    ISOTROPIC,
    NULL_COLUMN_OFFSET,
    OKHRIMOVSKYY,
    SCREENED_COULOMB,
    SHARE_EQUAL,
    SHARE_UNIFORM,
    SUPERELASTIC,
    TIME_COLUMN_OFFSET,
    VAHEDI_SURENDRA,
)
from .moments import energy_histogram, group_moments, group_sums, group_tensor_moments
from .oscillating import oscillating_field
from .slab import FLIGHT_ACTIVE, FLIGHT_ENERGY, FLIGHT_MU, FLIGHT_SIZE, FLIGHT_X, slab_batch

__all__ = [
    "ATTACHMENT", "BOUND_COLUMN_OFFSET", "DISPLACEMENT_COLUMN_OFFSET", "ELASTIC", "EXCITATION", "EXTRA_COLUMNS", "FLIGHT_ACTIVE", "FLIGHT_ENERGY", "FLIGHT_MU", "FLIGHT_SIZE", "FLIGHT_X", "FORWARD",
    "IONIZATION", "ISOTROPIC", "NULL_COLUMN_OFFSET", "OKHRIMOVSKYY", "SCREENED_COULOMB", "SHARE_EQUAL",
    "SHARE_UNIFORM", "SUPERELASTIC", "TIME_COLUMN_OFFSET", "TRIAL_BUDGET", "VAHEDI_SURENDRA", "WINDOW_COLLISIONS",
    "WINDOW_GROWTH", "advance_swarm", "derived_field", "energy_histogram", "group_moments", "group_sums",
    "group_tensor_moments", "oscillating_field", "slab_batch",
]
