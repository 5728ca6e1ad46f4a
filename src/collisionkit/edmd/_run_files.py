"""The files an EDMD run holds while it runs (:meth:`~collisionkit.edmd.EdmdRun.run`): locks and trajectory frames.

:class:`RunFiles` is a context manager around one call of ``run``: on entry
it locks the run's checkpoint and trajectory (a second writer is refused,
:func:`collisionkit._io.exclusive`) and opens the trajectory, on exit it
closes both. In between, :meth:`RunFiles.frame` writes a frame when one is
due. The frame counters (``frames``, ``last_frame``) stay the run's: they
are part of its checkpoint.
"""

from __future__ import annotations

import contextlib

from .._io import exclusive


class RunFiles:
    """The checkpoint and trajectory of an :class:`~collisionkit.edmd.EdmdRun`, locked and open for one run.

    Parameters
    ----------
    run : EdmdRun
        The run whose ``checkpoint`` and ``trajectory`` (paths or None),
        ``frame_every``, ``frames`` and ``last_frame`` are used; its
        ``frames``, ``last_frame`` and ``_append`` are updated.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from collisionkit.edmd import EdmdParameters, EdmdRun
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "run.npz"
    >>> run = EdmdRun(EdmdParameters(dim=2, particles=64, initial="square", seed=1), checkpoint=path)
    >>> with RunFiles(run) as files:
    ...     files.frame(final=True)   # no trajectory: nothing written
    >>> run.frames
    0
    """

    def __init__(self, run):
        self.run = run
        self._locks = contextlib.ExitStack()
        self._writer = None

    def __enter__(self) -> RunFiles:
        """Lock the checkpoint and the trajectory for the run (a second writer is refused); open the trajectory.

        A resumed run appends to its trajectory: frames after the
        checkpoint's are dropped, and a file without all of the checkpoint's
        frames is refused (it is not this run's trajectory).
        """
        run = self.run
        try:
            for path in (run.checkpoint, run.trajectory):
                self._locks.enter_context(exclusive(path))
            if run.trajectory is None:
                return self
            from ..trajectory import GSDWriter, truncate_gsd

            append = getattr(run, "_append", False) and run.trajectory.exists()
            last_step = run.last_frame if run.frames > 0 else None
            run.frames = truncate_gsd(run.trajectory, run.frames, last_step=last_step) if append else 0
            self._writer = GSDWriter(run.trajectory, mode="a" if append else "w")
            run._append = True
        except BaseException:
            self._locks.close()
            raise
        return self

    def __exit__(self, *exception) -> None:
        """Close the trajectory, then release the locks."""
        if self._writer is not None:
            self._writer.close()
            self._writer = None
        self._locks.close()

    def frame(self, final: bool = False) -> None:
        """Write a frame of the run's system if one is due (or ``final``) and none was written at this step.

        A frame is due at the first call after every ``frame_every`` pair
        collisions (the first call of all, when no frame was written yet).
        Nothing is written without a trajectory.
        """
        run = self.run
        step = run.system.collisions
        if self._writer is None or step == run.last_frame:
            return
        every = run.frame_every
        due = every is not None and (run.last_frame < 0 or step // every > run.last_frame // every)
        if due or final:
            self._writer.write(run.system, step)
            run.frames += 1
            run.last_frame = step
