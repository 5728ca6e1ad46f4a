"""The results of a swarm checkpoint read back, every field checked for its type and shape.

:meth:`~collisionkit.transport.SwarmScan.resume` reads each saved point with
:func:`_saved_result`: a damaged one is a CheckpointError naming the file,
the result and the field. :func:`saved_running_point` reads the state of
the point that was running, checked as far as it can be without the run
(:func:`._run_snapshot.restore_run` checks the rest).
"""

from __future__ import annotations

import numpy as np

from .._io import Checkpoint
from ._run_snapshot import PREFIX
from .swarm_result import SwarmResult


def _saved_result(saved: Checkpoint, index: int, entry) -> SwarmResult:
    """Result ``index`` of a swarm checkpoint as a SwarmResult whose every field has its type and shape.

    A damaged one is a CheckpointError naming the file, the result and the field.
    """
    try:
        result = SwarmResult.from_dict(entry)
    except (TypeError, ValueError) as error:
        raise saved.damaged(f"result {index} cannot be read ({error})") from None
    for name, spec in SwarmResult.__dataclass_fields__.items():
        value = getattr(result, name)
        if spec.type == "int":
            valid = isinstance(value, int) and not isinstance(value, bool) and value >= 0
        elif spec.type == "bool":
            valid = isinstance(value, bool)
        elif spec.type == "np.ndarray":
            valid = value.shape == _saved_shape(name, result)
        elif spec.type == "dict" and name != "extras":
            valid = all(isinstance(key, str) and isinstance(item, (int, float)) and not isinstance(item, bool)
                        for key, item in value.items())
        else:  # floats (from_dict converted them) and the free-form extras
            valid = spec.type == "float" or isinstance(value, dict)
        if not valid:
            raise saved.damaged(f"result {index} has a {name} of the wrong type or shape: {value!r}")
    return result


def _saved_shape(name: str, result: SwarmResult) -> tuple[int, ...]:
    """The shape a saved result's array field must have."""
    phases = np.shape(result.phases)
    if name.startswith("diffusion_N_"):
        return (3, 3)
    if name.startswith("drift_velocity_flux_by_phase"):
        return (*phases, 3)
    if name.startswith("mean_energy_by_phase") or name == "phases":
        return phases
    if name.startswith("drift"):
        return (3,)
    return np.shape(result.eedf_energy)


def saved_running_point(saved: Checkpoint, done: int, points: int) -> tuple[int, dict, dict] | None:
    """The running point's ``(index, state, arrays)`` saved in a swarm checkpoint with ``done`` finished points out
    of ``points``, or None if it holds none.

    The point must be the first unfinished one; its state a mapping. A
    damaged one is a CheckpointError naming the file.
    """
    running = saved.entry("running_point", "mapping", optional=True)
    arrays = {name: value for name, value in saved.arrays.items() if name.startswith(PREFIX)}
    if running is None:
        if arrays:
            raise saved.damaged(f"it holds a running point's arrays ({', '.join(sorted(arrays)[:3])} ...) but no "
                                "running point")
        return None
    index, state = running.get("index"), running.get("run")
    if index != done or isinstance(index, bool) or done >= points:
        raise saved.damaged(f"its running point is number {index!r}, not the first unfinished one ({done} of "
                            f"{points} are done)")
    if not isinstance(state, dict):
        raise saved.damaged(f"its running point's state must be a mapping; got {type(state).__name__}")
    return done, state, arrays
