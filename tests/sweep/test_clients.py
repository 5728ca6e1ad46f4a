"""collisionkit.sweep.clients: the embedded Dask cluster and the client of a running one."""

from __future__ import annotations

import os
import signal
import socket
import time

import pytest

from collisionkit import sweep
from tests.sweep.helpers import deadline


def test_an_embedded_cluster_needs_at_least_one_worker():
    with pytest.raises(ValueError, match="workers must be >= 1"):
        with sweep.local_client(0):
            pass


def test_a_scheduler_that_does_not_answer_is_a_connection_error_naming_its_address():
    with socket.socket() as probe:  # a free port: nothing listens there
        probe.bind(("127.0.0.1", 0))
        address = f"tcp://127.0.0.1:{probe.getsockname()[1]}"
    with deadline(60), pytest.raises(ConnectionError, match=f"cannot connect to the Dask scheduler at {address}"):
        with sweep.remote_client(address, timeout="1s"):
            pass


def _ignores_sigint() -> bool:
    return signal.getsignal(signal.SIGINT) == signal.SIG_IGN


def _worker_pids(client) -> set[int]:
    """The pids of the client's workers, once every worker answers (empty while one is gone)."""
    try:
        return set(client.run(os.getpid).values())
    except Exception:  # a worker just killed: the scheduler still lists it
        return set()


@pytest.fixture
def ctrl_c_raises():
    """Python's own SIGINT handler in this process for the test (a runner may have left SIGINT ignored)."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def test_the_embedded_cluster_s_workers_leave_ctrl_c_to_the_caller(ctrl_c_raises):
    # a terminal's Ctrl-C reached the workers too: their KeyboardInterrupt tracebacks came after the sweep's one line
    with deadline(120), sweep.local_client(workers=1) as client:
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # the caller's own Ctrl-C works
        assert list(client.run(_ignores_sigint).values()) == [True]
        (first,) = _worker_pids(client)
        os.kill(first, signal.SIGKILL)  # its nanny starts another one: it ignores SIGINT too (the preload)
        while not _worker_pids(client) - {first}:
            time.sleep(0.2)
        assert list(client.run(_ignores_sigint).values()) == [True]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
