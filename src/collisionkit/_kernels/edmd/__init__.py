"""Numba kernels of the event-driven engine for hard spheres and discs.

Algorithm (Rapaport; Isobe, Int. J. Mod. Phys. C 10, 1281 (1999); neighbour
lists after Donev, Torquato & Stillinger, J. Comput. Phys. 202, 737 (2005),
as used for speed by Smallenburg, arXiv:2201.01100):

* particles move ballistically (parabolas under uniform gravity) and are
  updated lazily: row ``p[i]`` holds position, velocity, the particle's own
  time and its radius (one 64-byte record, so a neighbour costs one cache
  line);
* every particle carries a neighbour list: the particles whose *anchors*
  (positions when their lists were last built) lie within
  ``(r_i + r_j) * list_scale + shell``. A particle's list is rebuilt (a list
  event) when it has moved ``shell / 2`` from its anchor, so two particles
  that are not neighbours cannot touch before one of them rebuilds. Lists are
  symmetric: a rebuild removes the particle from its old neighbours' lists
  and adds it to its new ones'. A cell list of the anchors (cells no smaller
  than the list radius, each a contiguous block of slots holding the anchors
  and radii, so a scan streams memory instead of chasing pointers) finds the
  new neighbours;
* every particle keeps its best predicted collision (over its list) and its
  next boundary event (list expiry or a wall); its event is the earlier;
* the particles' event times sit in blocks of 8 (one cache line); a
  complete binary tree over the blocks' earliest events gives the next event
  in O(1) and updates in O(log N). The tree is 16 times smaller than one over
  the particles, small enough to stay in the core's cache, and most updates
  end at the block (a particle that is not its block's first stays behind
  it);
* events are numbered; an event with partner j is stale if j has changed
  velocity since it was predicted (j's CHANGED_AT is later than i's
  PREDICTED_AT). Unlike per-particle counters, this needs no read of the
  partner's record when predicting, one memory round trip fewer. Stale
  events are re-predicted;
* the prediction and the collision step judge whether a pair approaches by
  one test, bit for bit, and the impulse keeps the energy without bias
  (:mod:`.exact`); the loop runs in calls of a bounded number of events and
  gives up on a collapse (events in a row at one instant, without end);
* what an event needs of a particle sits in two 64-byte records: ``p``
  (position, velocity, own time, radius: all a neighbour's prediction
  reads) and ``b`` (next event, event numbers, anchor, mass, species), so
  an event touches few cache lines: memory latency, not arithmetic, bounds
  the engine once the particles outgrow the caches.

Positions are not wrapped into a periodic box at every crossing, only when a
particle rebuilds its list, so they may lie up to ``shell / 2`` outside
[0, L); separations use the minimum image, valid because every periodic box
length exceeds twice the largest list radius.

Under Lees-Edwards shear (:mod:`.motion`) the anchors move with the flow at
their heights and the cells hold them in the flow's frame, where the sliding
images stand still (:func:`.neighbour_lists._gather_sheared`); a list then
expires on the motion relative to the flow plus a term growing with the
list's age, or when x strays a quarter box outside [0, L_x)
(:func:`.prediction.sheared_list_expiry`), and a sweep at every strain of
0.25 moves the frame on and refills the cells (:func:`.neighbour_lists.sweep_frame`).

Growing particles (Lubachevsky-Stillinger compression) use radii
``radius * (scale0 + growth * t)``; lists cover radii up to ``list_scale``
and the caller stops the run when the scale reaches it. With growth 0 the
contact quadratic is the one of :mod:`collisionkit._kernels.collisions`.

The kernels are split by responsibility: :mod:`.layout` (the arrays'
columns and slots), :mod:`.motion` (flight, minimum images),
:mod:`.prediction` (contact, list and wall times), :mod:`.queue` (the event
tree), :mod:`.cells` and :mod:`.neighbour_lists`, :mod:`.exact`
(error-free sums and products), :mod:`.contacts` (resolving a collision),
:mod:`.wells` (square wells: edge events and the record of pairs inside),
:mod:`.loop` (the event loop) and
:mod:`.measurement` (gaps, drift, pair distances, Helfand moments). Every pair collision
also adds its momentum and energy transfer to the transport sums of the
accumulator (collisional stress and heat flux, and Erpenbeck's image terms
of the Helfand moments: :mod:`.layout`, :mod:`.contacts`). None of them allocates
or returns an array: all are compiled without reference counting
(:func:`collisionkit._jit.borrowing_kernel`). The names the public module
:mod:`collisionkit.edmd` uses are importable from here.
"""

from __future__ import annotations

from .layout import (
    ACC_BOUNCES,
    ACC_CAPTURES,
    ACC_ESCAPES,
    ACC_SIZE_WITHOUT_WELL,
    ACC_SIZE_WITHOUT_WELL_ENERGY,
    ACC_WELL_ENERGY,
    ACC_WELL_ENERGY_TIME,
    ACC_WELL_PAIR_TIME,
    ACC_WELL_PAIRS,
    ACC_WELL_SINCE,
    P_SIZE_WITHOUT_WELL,
    P_SIZE_WITHOUT_WELL_TABLE,
    P_WELL_DEPTH,
    P_WELL_SPECIES,
    P_WELL_WIDTH,
    WELL_TARGET_BASE,
    well_slot,
    well_target,
    ACC_CELL_OVERFLOW,
    ACC_ENERGY_LOST,
    ACC_ENERGY_IMAGE,
    ACC_EVENTS,
    ACC_HEAT,
    ACC_LIST_OVERFLOW,
    ACC_LIST_REBUILDS,
    ACC_MOMENTUM_IMAGE,
    ACC_PAIR_COLLISIONS,
    ACC_SIZE,
    ACC_SIZE_WITHOUT_TRANSPORT,
    ACC_STALE_EVENTS,
    ACC_STRESS,
    ACC_THERMOSTAT,
    ACC_SIZE_WITHOUT_THERMOSTAT,
    ACC_VIRIAL,
    ACC_WALL_COLLISIONS,
    ACC_WALL_IMPULSE,
    ANCHOR,
    ANCHOR_ROUNDING,
    CELL_SLOTS_PER_LINE,
    CHANGED_AT,
    G_BOX,
    G_CELL,
    G_GRAVITY,
    G_PERIODIC,
    LAW_BRIDGES,
    LAW_CONSTANT,
    LAW_VISCOELASTIC,
    LIST_TARGET,
    MASS,
    P_ELASTIC_BELOW,
    P_FRICTION,
    P_GROWTH,
    P_INERTIA_FACTOR,
    P_LAW,
    P_LAW_EXPONENT,
    P_LAW_SPEED,
    P_LIST_SCALE,
    P_SCALE0,
    P_SHELL,
    P_SHEAR_REACH,
    P_SHEAR_FRAME,
    P_SHEAR_OFFSET,
    P_SHEAR_RATE,
    P_SHEAR_SWEEP,
    P_TANGENTIAL_RESTITUTION,
    P_SIZE,
    P_SIZE_WITHOUT_FRAME,
    P_SIZE_WITHOUT_FRICTION,
    P_SIZE_WITHOUT_ROUGHNESS,
    P_SIZE_WITHOUT_SHEAR,
    SHEAR_SWEEP_STRAIN,
    SHEAR_X_EXCURSION,
    P_THERMOSTAT,
    P_WALL_RESTITUTION,
    PREDICTED_AT,
    QUEUE_BLOCK,
    SPECIES,
    STALLED_EVENTS,
    STOP_COLLISIONS,
    STOP_EVENTS,
    STOP_NO_EVENT,
    STOP_OVERFLOW,
    STOP_STALLED,
    STOP_TIME,
    STRESS_PAIRS,
    TARGET,
    TREE_LEVELS_PREFETCHED,
    R,
    T,
    V,
    X,
    wall_target,
)
from .loop import predict_all, run_events
from .wells import bound_energies
from .measurement import (
    largest_anchor_drift, min_gap, pair_distance_counts, stored_helfand_moments, synchronise, wall_gap,
)
from .neighbour_lists import anchor_all, build_all_lists
from .prediction import first_root_from_below, pair_contact_time
from .queue import queue_update, tree_build

__all__ = [
    "ACC_BOUNCES", "ACC_CAPTURES", "ACC_ESCAPES", "ACC_SIZE_WITHOUT_WELL", "ACC_SIZE_WITHOUT_WELL_ENERGY",
    "ACC_WELL_ENERGY", "ACC_WELL_ENERGY_TIME", "ACC_WELL_PAIR_TIME", "ACC_WELL_PAIRS", "ACC_WELL_SINCE",
    "P_SIZE_WITHOUT_WELL", "P_SIZE_WITHOUT_WELL_TABLE", "P_WELL_DEPTH", "P_WELL_SPECIES", "P_WELL_WIDTH",
    "WELL_TARGET_BASE", "well_slot", "well_target",
    "ACC_CELL_OVERFLOW", "ACC_ENERGY_IMAGE", "ACC_ENERGY_LOST", "ACC_EVENTS", "ACC_HEAT", "ACC_LIST_OVERFLOW",
    "ACC_LIST_REBUILDS", "ACC_MOMENTUM_IMAGE", "ACC_PAIR_COLLISIONS", "ACC_SIZE", "ACC_SIZE_WITHOUT_THERMOSTAT", "ACC_SIZE_WITHOUT_TRANSPORT",
    "ACC_STALE_EVENTS", "ACC_STRESS", "ACC_THERMOSTAT", "ACC_VIRIAL", "ACC_WALL_COLLISIONS", "ACC_WALL_IMPULSE",
    "ANCHOR", "ANCHOR_ROUNDING", "CELL_SLOTS_PER_LINE", "CHANGED_AT", "G_BOX", "G_CELL", "G_GRAVITY", "G_PERIODIC",
    "LAW_BRIDGES", "LAW_CONSTANT", "LAW_VISCOELASTIC", "LIST_TARGET", "MASS", "P_ELASTIC_BELOW", "P_FRICTION", "P_GROWTH", "P_INERTIA_FACTOR", "P_LAW", "P_LAW_EXPONENT",
    "P_LAW_SPEED", "P_LIST_SCALE", "P_SCALE0", "P_SHEAR_FRAME", "P_SHEAR_OFFSET", "P_SHEAR_RATE", "P_SHEAR_REACH",
    "P_TANGENTIAL_RESTITUTION", "P_SHEAR_SWEEP", "P_SHELL", "P_SIZE", "P_SIZE_WITHOUT_FRAME", "P_SIZE_WITHOUT_FRICTION", "P_SIZE_WITHOUT_ROUGHNESS", "P_SIZE_WITHOUT_SHEAR", "P_THERMOSTAT",
    "P_WALL_RESTITUTION", "PREDICTED_AT", "SHEAR_SWEEP_STRAIN", "SHEAR_X_EXCURSION",
    "QUEUE_BLOCK", "R", "SPECIES", "STALLED_EVENTS", "STOP_COLLISIONS", "STOP_EVENTS", "STOP_NO_EVENT",
    "STOP_OVERFLOW", "STOP_STALLED", "STOP_TIME", "STRESS_PAIRS", "T", "TARGET", "TREE_LEVELS_PREFETCHED", "V", "X",
    "anchor_all", "bound_energies", "build_all_lists", "first_root_from_below", "largest_anchor_drift", "min_gap", "pair_contact_time",
    "pair_distance_counts", "predict_all", "queue_update", "run_events", "stored_helfand_moments", "synchronise",
    "tree_build", "wall_gap", "wall_target",
]
