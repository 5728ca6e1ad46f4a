"""The batches of a slab run (:mod:`.slab`): their state between kernel calls, run in threads, and their result.

:class:`SlabBatches` is all a run needs to go on exactly (each batch's
random stream, the history its last kernel call cut short, its counts);
:func:`run_batches` runs them in threads, saving copies taken between
calls; :func:`~.slab.slab_result` makes the result of finished ones, and
:class:`~.slab_run.SlabRun` checkpoints them.
"""

from __future__ import annotations

import math
import threading
import time
from concurrent.futures import ThreadPoolExecutor, wait
from dataclasses import dataclass, fields

import numpy as np

from .._kernels import transport as _k
from .._repr import dataclass_repr

BATCHES = 64
# collisions in one kernel call of a batch at most (a few milliseconds): Ctrl-C waits for no more
COLLISIONS_PER_CALL = 1 << 18
# how often the progress callback hears of the histories finished
PROGRESS_SECONDS = 0.2


@dataclass
class SlabBatches:
    """The state of a slab run's ``BATCHES`` batches between kernel calls: all a run needs to go on exactly.

    ``rng`` holds each batch's generator state, ``flights`` a history cut
    short by a call's collision budget (:func:`collisionkit._kernels.transport.slab_batch`),
    ``left`` the histories each batch has still to start or finish;
    ``counts`` (transmitted, reflected, absorbed, collisions), ``angles`` and
    ``energies`` (transmitted, reflected) what the finished ones gave.

    Examples
    --------
    >>> batches = SlabBatches.start(seed=1, particles=1000, angle_bins=20, energy_bins=20)
    >>> int(batches.left.sum()), batches.done
    (1000, 0)
    """

    __repr__ = dataclass_repr

    rng: np.ndarray
    flights: np.ndarray
    left: np.ndarray
    counts: np.ndarray
    angles: np.ndarray
    energies: np.ndarray

    @classmethod
    def start(cls, seed: int, particles: int, angle_bins: int, energy_bins: int) -> SlabBatches:
        """The batches before any history: streams from ``SeedSequence(seed).spawn(BATCHES)``, the histories shared."""
        sequences = np.random.SeedSequence(seed).spawn(BATCHES)
        left = np.full(BATCHES, particles // BATCHES, dtype=np.int64)
        left[: particles % BATCHES] += 1
        return cls(rng=np.array([sequence.generate_state(4, np.uint64) for sequence in sequences]),
                   flights=np.zeros((BATCHES, _k.FLIGHT_SIZE)), left=left, counts=np.zeros((BATCHES, 4)),
                   angles=np.zeros((BATCHES, 2, angle_bins)), energies=np.zeros((BATCHES, 2, energy_bins)))

    @property
    def done(self) -> int:
        """Histories finished (transmitted, reflected or absorbed)."""
        return int(self.counts[:, :3].sum())

    def copy(self) -> SlabBatches:
        return SlabBatches(*(np.array(getattr(self, field.name)) for field in fields(self)))


def run_batches(batches: SlabBatches, threads, progress, physics, save=None, save_every=math.inf):
    """Run the histories ``batches`` has left in ``threads`` threads; ``batches`` goes on in place.

    Each batch's kernel calls end after at most ``COLLISIONS_PER_CALL``
    collisions; the workers stop between calls once the main thread is
    interrupted, and the main thread reports the fraction of all histories
    finished. With ``save``, the main thread calls ``save(copy)`` with a copy
    of the batches taken between their calls every ``save_every`` seconds, and
    once the workers have stopped when it is interrupted.
    """
    locks = [threading.Lock() for _ in range(BATCHES)]
    # a snapshot holds the gate: a worker passes it before each call, so it waits there, holding no batch, and the
    # snapshot gets every batch within one call (without it a worker took its batch's lock again at once, call
    # after call, and a save waited until whole batches had finished: 4 saves in a 1.2 s run asked to save always)
    gate = threading.Lock()
    particles = batches.done + int(batches.left.sum())
    stop = threading.Event()

    def work(b):
        while batches.left[b] > 0 and not stop.is_set():
            with gate:
                pass
            with locks[b]:
                batches.left[b] -= _k.slab_batch(batches.rng[b], batches.flights[b], int(batches.left[b]),
                                                 COLLISIONS_PER_CALL, *physics, batches.counts[b], batches.angles[b],
                                                 batches.energies[b])

    def snapshot():
        parts = []
        with gate:
            for b in range(BATCHES):
                with locks[b]:
                    parts.append([np.array(getattr(batches, field.name)[b]) for field in fields(batches)])
        return SlabBatches(*(np.array(column) for column in zip(*parts)))

    saved_at = time.monotonic()
    with ThreadPoolExecutor(threads) as pool:
        try:
            pending = {pool.submit(work, b) for b in range(BATCHES)}
            while pending:
                done, pending = wait(pending, timeout=PROGRESS_SECONDS)
                for future in done:
                    future.result()
                if progress is not None:
                    progress(1.0 - float(batches.left.sum()) / particles)
                if save is not None and pending and time.monotonic() - saved_at >= save_every:
                    save(snapshot())
                    saved_at = time.monotonic()
        except BaseException:
            stop.set()  # the workers end within one kernel call; the pool waits for them
            pool.shutdown(wait=True)
            if save is not None:
                save(batches.copy())
            raise


def slab_physics(thickness, albedo, incidence, model, mass_ratio, angle_bins, energy_bins) -> tuple:
    """The kernel's physics arguments of checked values."""
    return (float(thickness), float(albedo), incidence == "isotropic", model == "rod", float(mass_ratio), angle_bins,
            energy_bins)
