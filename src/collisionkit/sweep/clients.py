"""Where a study's points run: an embedded Dask cluster (:func:`local_client`) or a running one (:func:`remote_client`).

Both are context managers yielding a ``distributed.Client``, which
:func:`.execute.run_study` takes as its executor; dask.distributed is the
``cluster`` extra, imported only here and only when a client is made.
"""

from __future__ import annotations

import contextlib
import logging
import os
import signal
import threading

from .study import _check_integer

__all__ = ["local_client", "remote_client"]

WORKER_SETUP = "collisionkit.sweep._worker"  # a Dask preload: each worker of the embedded cluster ignores SIGINT
CLUSTER_LOG_LEVEL = logging.ERROR  # the embedded cluster's warnings (a cancelled point, a worker killed) are not shown


@contextlib.contextmanager
def local_client(workers: int | None = None):
    """An embedded ``dask.distributed`` cluster of worker processes (one thread each) and its client.

    Parameters
    ----------
    workers : int, optional
        Worker processes (>= 1); default: the machine's cores.

    Yields
    ------
    distributed.Client
        Closed, with the cluster, on leaving the ``with`` block.

    Notes
    -----
    Ctrl-C is the caller's: the worker processes ignore SIGINT (they start
    with it ignored, and a restarted one ignores it from its preload), so a
    terminal's Ctrl-C, sent to the whole process group, raises
    KeyboardInterrupt in this process only, and leaving the block closes
    the cluster. While the workers start, and while the cluster closes (a
    worker busy in a point is stopped after a few seconds), this process
    ignores SIGINT too. Dask's log lines below ERROR (a cancelled point, a
    worker killed on closing) are not shown while the cluster lives.

    Examples
    --------
    >>> with local_client(workers=1) as client:
    ...     print(client.submit(sum, [1, 2, 3]).result())
    6
    """
    if workers is not None:
        _check_integer("workers", workers, 1, None)
    try:
        import dask
        from distributed import Client, LocalCluster
    except ImportError:  # pragma: no cover - depends on the installation
        raise ImportError("the embedded cluster needs dask.distributed: pip install 'collisionkit[cluster]'") from None
    count = workers or os.cpu_count() or 1
    preload = [*dask.config.get("distributed.worker.preload", []), WORKER_SETUP]
    closing = contextlib.ExitStack()
    with _sigint_ignored():  # the worker processes inherit it
        cluster = closing.enter_context(LocalCluster(n_workers=count, threads_per_worker=1, processes=True,
                                                     dashboard_address=":0", silence_logs=CLUSTER_LOG_LEVEL,
                                                     preload=preload))
    # distributed 2024's sync() can log "NameError: cannot access free variable 'future'" through tornado when a
    # Ctrl-C lands while it is waiting (its own bug, harmless: the interrupt is handled here); not shown
    closing.enter_context(_logger_level("tornado.application", logging.CRITICAL))
    try:
        yield closing.enter_context(Client(cluster))
    finally:
        with _sigint_ignored():  # closing waits (seconds) for a busy worker: a second Ctrl-C does not break it off
            closing.close()


@contextlib.contextmanager
def _logger_level(name: str, level: int):
    """Set the logger ``name`` to ``level`` for the block."""
    logger = logging.getLogger(name)
    previous = logger.level
    logger.setLevel(level)
    try:
        yield
    finally:
        logger.setLevel(previous)


@contextlib.contextmanager
def _sigint_ignored():
    """Ignore SIGINT in this process for the block (in the main thread, where Python handles it; else nothing)."""
    previous = signal.getsignal(signal.SIGINT)
    if threading.current_thread() is not threading.main_thread() or previous is None:
        yield
        return
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


@contextlib.contextmanager
def remote_client(address: str, timeout: str = "15s"):
    """A client of the running Dask scheduler at ``address`` (e.g. ``tcp://host:8786``).

    Its workers need collisionkit installed and must see the study's folder
    at the same path.

    Raises
    ------
    ImportError
        Without dask.distributed (``pip install 'collisionkit[cluster]'``).
    ConnectionError
        If the scheduler cannot be reached within ``timeout``.

    Examples
    --------
    >>> with local_client(workers=1) as client, remote_client(client.scheduler.address) as remote:
    ...     print(remote.submit(sum, [1, 2]).result())
    3
    """
    try:
        from distributed import Client
    except ImportError:  # pragma: no cover - depends on the installation
        raise ImportError("sweeps on a cluster need dask.distributed: pip install 'collisionkit[cluster]'") from None
    try:
        client = Client(address, timeout=timeout)
    except (OSError, TimeoutError, ValueError) as error:
        raise ConnectionError(f"cannot connect to the Dask scheduler at {address}: {error}") from None
    with client:
        yield client
