"""The checkpoint of an EDMD run: what :meth:`~collisionkit.edmd.EdmdRun.save` writes, how ``resume`` reads it.

A checkpoint (kind ``"edmd"``, written atomically by :mod:`collisionkit._io`)
holds the run's parameters, its counters (``equilibrated``, ``frames``,
``last_frame``, ``initial_energy``, the ``trajectory`` and ``frame_every``
it wrote with) and the arrays of its system and, once measuring, of its
sampler. Every entry and array is checked before a kernel sees it; a
checkpoint that does not fit is refused with a
:class:`~collisionkit._io.CheckpointError`.
"""

from __future__ import annotations

from pathlib import Path

from .._io import CheckpointError, read_checkpoint, write_checkpoint
from .._params import check_unchanged
from ._run_checks import check_saved_run
from .measurement import Sampler
from .system import HardSphereSystem

CHECKPOINT_KIND = "edmd"


def save_run(run, path: Path) -> Path:
    """Write ``run``'s full state to ``path`` (atomically): parameters, counters, system and sampler arrays.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from collisionkit.edmd import EdmdParameters, EdmdRun
    >>> run = EdmdRun(EdmdParameters(dim=2, particles=64, initial="square", seed=1))
    >>> save_run(run, pathlib.Path(tempfile.mkdtemp()) / "run.npz").name
    'run.npz'
    """
    arrays = dict(run.system.state_dict())
    if run.sampler is not None:
        arrays |= run.sampler.state_dict()
    state = {"equilibrated": run.equilibrated, "frames": run.frames, "last_frame": run.last_frame,
             "initial_energy": run.initial_energy, "trajectory": None if run.trajectory is None else
             str(run.trajectory.resolve()), "frame_every": run.frame_every}
    return write_checkpoint(path, CHECKPOINT_KIND, run.parameters.to_dict(), state, arrays)


def resume_arguments(parameters_type, path, checkpoint, trajectory, frame_every, given) -> dict:
    """The arguments that make the run saved in ``path`` anew, as :meth:`~collisionkit.edmd.EdmdRun.resume` asks.

    ``parameters_type`` makes the saved parameters (which must still be
    valid, and equal to those ``given`` again); the saved trajectory is
    continued only when ``trajectory`` names it again, with its
    ``frame_every`` unless another is given. The ``_state`` argument carries
    the read checkpoint to :func:`restore_run`.
    """
    saved = read_checkpoint(path, CHECKPOINT_KIND)
    try:
        parameters = parameters_type.from_mapping(saved.parameters)
    except (TypeError, ValueError) as error:
        raise CheckpointError(f"{path} holds parameters that are not valid now: {error}") from None
    check_unchanged(parameters, given, path)
    saved_trajectory = saved.entry("trajectory", "text", optional=True)
    saved_frame_every = saved.entry("frame_every", "integer", 1, optional=True)
    append = trajectory is not None and saved_trajectory is not None and \
        Path(trajectory).resolve() == Path(saved_trajectory)
    if frame_every is None and append:
        frame_every = saved_frame_every
    return {"parameters": parameters, "checkpoint": path if checkpoint is None else checkpoint,
            "trajectory": trajectory, "frame_every": frame_every, "_state": {"saved": saved, "append": append}}


def restore_run(run, state) -> None:
    """Give ``run`` the system, sampler and counters of the checkpoint read by :func:`resume_arguments`.

    Raises a :class:`~collisionkit._io.CheckpointError` if the system's or
    the sampler's arrays cannot be read, or do not fit the run's parameters.
    """
    saved = state["saved"]
    try:  # every array is checked before a kernel sees it
        run.system = HardSphereSystem.from_state_dict(saved.arrays)
    except ValueError as error:  # written by another engine version, or arrays out of shape or range
        raise CheckpointError(f"cannot resume from {saved.path}: {error}") from None
    arrays = saved.arrays
    try:
        run.sampler = Sampler.from_state_dict(run.system, arrays) if "sampler_scalars" in arrays else None
    except (KeyError, TypeError, ValueError, IndexError) as error:
        raise saved.damaged(f"its measurement cannot be read (no array {error})" if isinstance(error, KeyError)
                            else f"its measurement cannot be read ({error})") from None
    check_saved_run(saved, run.sampler, run.parameters, run.system)
    run.equilibrated = saved.entry("equilibrated", "integer", 0, run.parameters.equilibration)
    run.frames = saved.entry("frames", "integer", 0) if state["append"] else 0
    run.last_frame = saved.entry("last_frame", "integer", -1)
    run.initial_energy = saved.entry("initial_energy", "number", 0.0)
    run._append = run._continued = state["append"]
