"""A slab run that checkpoints: :class:`SlabRun` saves its batches' state and goes on from it exactly.

A thick scattering slab keeps a history for about d^2 collisions, so a run
of many histories can take hours; the run's checkpoint (``.npz``, written
atomically every ``save_every`` seconds and when the run is interrupted)
holds each batch's random stream, the history its last kernel call cut
short and its counts, so a resumed run finishes with the result, bit for
bit, of a run never stopped (:func:`~collisionkit.transport.simulate_slab`'s
result for the same parameters).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from .._io import CheckpointError, exclusive, read_checkpoint, write_checkpoint
from .._kernels import transport as _k
from .._params import check_integer, check_real, check_unchanged
from ._slab_batches import BATCHES, SlabBatches, run_batches, slab_physics
from .slab import SlabResult, slab_result
from .slab_parameters import SlabParameters

__all__ = ["SAVE_EVERY", "SlabRun"]

CHECKPOINT_KIND = "slab"
# seconds between checkpoints of a running slab
SAVE_EVERY = 60.0
# the exit histograms' bins (simulate_slab's defaults): the command's results
ANGLE_BINS = ENERGY_BINS = 20


class SlabRun:
    """The histories of a slab (:class:`SlabParameters`), checkpointed as they run.

    Parameters
    ----------
    parameters : SlabParameters
    checkpoint : path, optional
        ``.npz`` written atomically every ``save_every`` seconds, when the
        run is interrupted and when it ends.
    save_every : float, optional
        Seconds between checkpoints (default :data:`SAVE_EVERY`, 60).
    overwrite : bool
        Replace an existing ``checkpoint`` (another run's); without it such a
        file is refused (FileExistsError) before any work.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "slab.npz"
    >>> parameters = SlabParameters(thickness=2.0, particles=5000, seed=1)
    >>> result = SlabRun(parameters, checkpoint=path).run()
    >>> resumed = SlabRun.resume(path)
    >>> resumed.finished, resumed.run().transmission == result.transmission
    (True, True)
    """

    def __init__(self, parameters: SlabParameters, checkpoint=None, *, save_every: float | None = None,
                 overwrite: bool = False, _batches: SlabBatches | None = None):
        if not isinstance(parameters, SlabParameters):
            raise TypeError(f"parameters must be SlabParameters; got {type(parameters).__name__}")
        self.parameters = parameters
        self.checkpoint = None if checkpoint is None else Path(checkpoint)
        if _batches is None and not overwrite and self.checkpoint is not None and self.checkpoint.exists():
            raise FileExistsError(f"checkpoint {self.checkpoint} exists (another run's file): resume that run "
                                  "(SlabRun.resume), choose another file or pass overwrite=True")
        self.save_every = check_real("save_every (seconds)", SAVE_EVERY if save_every is None else save_every, 0.0,
                                     math.inf)
        p = parameters
        self.batches = _batches if _batches is not None else SlabBatches.start(p.seed, p.particles, ANGLE_BINS,
                                                                               ENERGY_BINS)

    def __repr__(self) -> str:
        return (f"SlabRun(d = {self.parameters.thickness:g} mfp, {self.done} of {self.parameters.particles} "
                f"histories, checkpoint={None if self.checkpoint is None else str(self.checkpoint)!r})")

    @property
    def done(self) -> int:
        """Histories finished so far."""
        return self.batches.done

    @property
    def finished(self) -> bool:
        """True once every history has ended."""
        return not self.batches.left.any()

    def run(self, progress: Callable[[float], Any] | None = None, threads: int | None = None) -> SlabResult:
        """Run the histories left; return the result (the same as :func:`~collisionkit.transport.simulate_slab`'s).

        Parameters
        ----------
        progress : callable, optional
            ``progress(fraction)``: the fraction of all histories finished.
        threads : int, optional
            Worker threads (default: all cores); the result does not depend on it.

        Raises
        ------
        collisionkit._io.FileLockedError
            If another process is writing the checkpoint.

        Examples
        --------
        >>> run = SlabRun(SlabParameters(thickness=1.0, particles=1000, seed=2))
        >>> result = run.run(threads=1)
        >>> run.finished, run.done, result.transmission + result.reflection
        (True, 1000, 1.0)
        """
        p = self.parameters
        threads = (os.cpu_count() or 1) if threads is None else check_integer("threads", threads, 1)
        physics = slab_physics(p.thickness, p.albedo, p.incidence, p.model, p.mass_ratio, ANGLE_BINS, ENERGY_BINS)
        with exclusive(self.checkpoint):
            if not self.finished:
                run_batches(self.batches, threads, progress, physics, save=self._save_batches,
                             save_every=self.save_every)
            self.save()
        if progress is not None:
            progress(1.0)
        return slab_result(self.batches, p.thickness, p.albedo, p.incidence, p.model)

    def _save_batches(self, batches: SlabBatches) -> None:
        if self.checkpoint is not None:
            _write(self.checkpoint, self.parameters, batches)

    def save(self, path=None) -> Path | None:
        """Write the run's state to ``path`` or its checkpoint (None if neither), atomically.

        Examples
        --------
        >>> import pathlib, tempfile
        >>> path = pathlib.Path(tempfile.mkdtemp()) / "start.npz"
        >>> SlabRun(SlabParameters(particles=1000)).save(path).name, SlabRun.resume(path).done
        ('start.npz', 0)
        """
        path = self.checkpoint if path is None else Path(path)
        return None if path is None else _write(path, self.parameters, self.batches)

    @classmethod
    def resume(cls, path, checkpoint=None, save_every: float | None = None, **given) -> SlabRun:
        """The run saved in ``path``, ready to go on; parameters ``given`` again must equal the saved ones.

        Raises
        ------
        ValueError
            If the file is not a slab checkpoint or a damaged one
            (:class:`~collisionkit._io.CheckpointError`, naming the entry), or
            a parameter given differs.

        Examples
        --------
        >>> import pathlib, tempfile
        >>> path = pathlib.Path(tempfile.mkdtemp()) / "slab.npz"
        >>> _ = SlabRun(SlabParameters(thickness=3.0, particles=1000), checkpoint=path).save()
        >>> SlabRun.resume(path, thickness=3.0).parameters.thickness   # given again: must agree
        3.0
        """
        saved = read_checkpoint(path, CHECKPOINT_KIND)
        try:
            parameters = SlabParameters.from_mapping(saved.parameters)
        except (TypeError, ValueError) as error:
            raise CheckpointError(f"{path} holds parameters that are not valid now: {error}") from None
        check_unchanged(parameters, given, path)
        batches = _read_batches(saved, parameters)
        if checkpoint is not None and Path(checkpoint).resolve() != Path(path).resolve() and Path(checkpoint).exists():
            raise FileExistsError(f"checkpoint {checkpoint} exists (another run's file): name another, or remove it")
        return cls(parameters, checkpoint=path if checkpoint is None else checkpoint, save_every=save_every,
                   _batches=batches)


def _write(path: Path, parameters: SlabParameters, batches: SlabBatches) -> Path:
    arrays = {f"batches_{name}": value for name, value in vars(batches).items()}
    return write_checkpoint(path, CHECKPOINT_KIND, parameters.to_dict(), {"done": batches.done}, arrays)


def _read_batches(saved, parameters: SlabParameters) -> SlabBatches:
    """The saved batches, every array checked against the parameters before a kernel sees it."""
    shapes = {"rng": (BATCHES, 4), "flights": (BATCHES, _k.FLIGHT_SIZE), "left": (BATCHES,), "counts": (BATCHES, 4),
              "angles": (BATCHES, 2, ANGLE_BINS), "energies": (BATCHES, 2, ENERGY_BINS)}
    values = {}
    for name, shape in shapes.items():
        array = saved.arrays.get(f"batches_{name}")
        if array is None or array.shape != shape:
            raise saved.damaged(f"batches_{name} must be an array of shape {shape}; got "
                                f"{None if array is None else array.shape}")
        values[name] = array
    batches = SlabBatches(rng=values["rng"].astype(np.uint64), flights=values["flights"].astype(float),
                          left=values["left"].astype(np.int64), counts=values["counts"].astype(float),
                          angles=values["angles"].astype(float), energies=values["energies"].astype(float))
    start = SlabBatches.start(parameters.seed, parameters.particles, ANGLE_BINS, ENERGY_BINS).left
    finished = batches.counts[:, :3].sum(axis=1)
    numbers = [batches.counts, batches.angles, batches.energies]
    fits = all(np.all(np.isfinite(array) & (array >= 0)) for array in numbers)
    fits &= bool(np.all((batches.left >= 0) & (batches.left <= start)))
    fits &= _flights_fit(batches.flights, parameters.thickness) and bool(np.all(batches.rng.any(axis=1)))
    fits &= bool(np.array_equal(finished, start - batches.left))
    for histogram in (batches.angles, batches.energies):  # every particle out is in both histograms
        fits &= bool(np.array_equal(histogram.sum(axis=2), batches.counts[:, :2]))
    if not fits:
        raise saved.damaged("its batches' counts do not add up to the histories its parameters give, or a history "
                            "in flight lies outside the slab (0 <= x <= d, |mu| <= 1, 0 < energy <= 1), or a random "
                            "stream is all zero")
    return batches


def _flights_fit(flights, thickness) -> bool:
    """Whether each batch's history cut short is one the kernel could have left: inactive, or inside the slab with a
    direction cosine and an energy (in units of the incident one) in range, as the histograms' bins need."""
    x, mu, energy, active = (flights[:, slot] for slot in
                             (_k.FLIGHT_X, _k.FLIGHT_MU, _k.FLIGHT_ENERGY, _k.FLIGHT_ACTIVE))
    inside = (x >= 0.0) & (x <= thickness) & (np.abs(mu) <= 1.0) & (energy > 0.0) & (energy <= 1.0)
    return bool(np.all(np.isfinite(flights)) and np.all((active == 0.0) | ((active == 1.0) & inside)))
