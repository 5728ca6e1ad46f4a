"""Helpers of the slab tests: a Ctrl-C at a chosen kernel call of a slab run."""

from __future__ import annotations

import time
import types

from collisionkit.transport import _slab_batches


def interrupt_after(monkeypatch, calls, pause=0.0):
    """Ctrl-C in the ``calls``-th kernel call of the run's batches (calls of 2000 collisions: many a batch); each
    call ``pause`` seconds longer (a run that outlasts many of the main thread's checks, however loaded the
    machine)."""
    real, count = _slab_batches._k, []

    def slab_batch(*args):
        count.append(1)
        if len(count) == calls:
            raise KeyboardInterrupt
        time.sleep(pause)
        return real.slab_batch(*args)

    monkeypatch.setattr(_slab_batches, "_k", types.SimpleNamespace(slab_batch=slab_batch, FLIGHT_SIZE=real.FLIGHT_SIZE))
    monkeypatch.setattr(_slab_batches, "COLLISIONS_PER_CALL", 2_000)
