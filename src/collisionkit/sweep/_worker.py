"""Set-up of the embedded cluster's worker processes, loaded by Dask in each (a worker preload).

A terminal's Ctrl-C reaches every process of the foreground group: the
workers leave it to the sweep, which cancels the points and closes the
cluster (a worker that raised KeyboardInterrupt printed its traceback).
"""

from __future__ import annotations

import signal


def dask_setup(worker) -> None:
    """Ignore SIGINT in this worker process (Dask calls this as the worker starts).

    Parameters
    ----------
    worker : distributed.Worker
        The starting worker (unused).
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
