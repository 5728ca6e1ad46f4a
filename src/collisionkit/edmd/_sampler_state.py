"""A :class:`~collisionkit.edmd.Sampler`'s accumulators as checkpoint arrays, and back (older checkpoints too).

The arrays are named ``sampler_*`` (one per record, the speeds, the g(r)
histogram, the start positions and ``sampler_scalars``), plus those of the
multiple-origin MSD (:class:`~collisionkit.edmd._msd.LagMSD`) and of a
transport measurement (:class:`~collisionkit.edmd.TransportSampler`).
Checkpoints written before a record existed still load: the blocks they
hold get NaN for it (no error of D without ``msd_groups``, no mean kT, no
thermostat energy, no shear-mode energy), and a sheared run saved before the transverse
diffusion coefficient loses its MSD (its displacements counted x too).
"""

from __future__ import annotations

import math

import numpy as np

from . import _msd
from ._sampler_records import (
    HOMOGENEITY_RECORDS, MIXTURE_RECORDS, RECORDS, ROUGH_RECORDS, SHEAR_RECORDS, homogeneity_measurable,
)
from ._transport import TransportSampler


def sampler_arrays(sampler) -> dict:
    """``sampler``'s accumulators as arrays named ``sampler_*`` (and the MSD's and transport's own).

    Examples
    --------
    >>> from collisionkit.edmd import Sampler, lattice, maxwell_boltzmann, HardSphereSystem
    >>> import numpy as np
    >>> positions, box = lattice("square", 10, 0.3)
    >>> system = HardSphereSystem(positions, maxwell_boltzmann(np.ones(100), 2, seed=1), 0.5, box)
    >>> sampler = Sampler(system, collisions=4000, blocks=2)
    >>> sampler.run_block()
    >>> sampler_arrays(sampler)["sampler_scalars"][:2]
    array([   2., 2000.])
    """
    state = {f"sampler_{name}": np.asarray(values, dtype=float) for name, values in sampler.records.items()}
    state |= {
        "sampler_speeds": _speed_rows(sampler.speeds),
        "sampler_histogram": sampler.histogram,
        "sampler_start_positions": sampler.start_positions,
        "sampler_scalars": np.array(
            [sampler.blocks, sampler.per_block, sampler.r_max, sampler.start_time, sampler.start_lost,
             sampler.wall_seconds]
        ),
    }
    if sampler.partial_histograms is not None:
        state["sampler_partial_histograms"] = sampler.partial_histograms
    if sampler.lag_msd is not None:
        state |= sampler.lag_msd.state_dict()
    if sampler.transport is not None:
        state |= sampler.transport.state_dict()
    return state


def _speed_rows(speeds) -> np.ndarray:
    """The blocks' speed samples as rows of a 2-D array ((0, 0) before the first block ends)."""
    return np.asarray(speeds, dtype=float).reshape(len(speeds), -1) if len(speeds) else np.empty((0, 0))


def restore_sampler(sampler, system, state) -> None:
    """Give the bare ``sampler`` (made without ``__init__``) of ``system`` the accumulators in ``state``.

    ``state`` holds :func:`sampler_arrays` output, maybe of an older
    version (see the module's notes); a missing array raises KeyError.
    """
    sampler.system = system
    blocks, per_block, r_max, start_time, start_lost, wall = state["sampler_scalars"]
    sampler.blocks, sampler.per_block = int(blocks), int(per_block)
    sampler.r_max, sampler.start_time, sampler.start_lost, sampler.wall_seconds = r_max, start_time, start_lost, wall
    sampler.histogram = np.array(state["sampler_histogram"])
    # a mixture's partial histograms (none saved before they were recorded: then none are measured)
    partial = state.get("sampler_partial_histograms")
    sampler.partial_histograms = None if partial is None else np.array(partial, dtype=float)
    sampler.start_positions = np.array(state["sampler_start_positions"])
    sampler.records = {name: list(state[f"sampler_{name}"]) for name in
                       RECORDS + SHEAR_RECORDS + MIXTURE_RECORDS + ROUGH_RECORDS + HOMOGENEITY_RECORDS
                       if f"sampler_{name}" in state}
    # a checkpoint written before the groups were recorded: their blocks are unknown (no D error)
    sampler.records.setdefault("msd_groups", [np.full(_msd.MSD_GROUPS, math.nan)] * len(sampler.records["msd"]))
    # ... or before the mean kT and the thermostat's energy were: unknown for the blocks done
    done = len(sampler.records["msd"])
    sampler.records.setdefault("temperature_mean", [math.nan] * done)
    sampler.records.setdefault("potential_energy", [0.0] * done)  # saved before square wells: hard spheres, none
    if "shear_stress" in sampler.records:
        sampler.records.setdefault("thermostat_energy", [math.nan] * done)
    if homogeneity_measurable(system):  # saved before the shear modes were recorded: unknown for the blocks done
        sampler.records.setdefault("shear_mode_energy", [math.nan] * done)
    kinds = int(np.max(system.species)) + 1
    if np.unique(system.species).size > 1:  # a mixture saved before its species' kT were recorded: unknown
        sampler.records.setdefault("species_temperature", [np.full(kinds, math.nan)] * done)
    sampler.speeds = [row for row in np.array(state["sampler_speeds"])]
    sampler.lag_msd = _msd.LagMSD.from_state_dict(state, system.species)
    if sampler.lag_msd is not None and len(sampler.lag_msd.positions[0]) and \
            np.shape(sampler.lag_msd.positions[0])[-1] != len(sampler._diffusion_axes()):
        # a sheared run saved before the transverse D: its displacements count x too, so it has none
        sampler.lag_msd = None
        sampler.records["msd"] = [math.nan] * len(sampler.records["msd"])
    has_transport = "transport_scalars" in state
    sampler.transport = TransportSampler.from_state_dict(system, state) if has_transport else None
