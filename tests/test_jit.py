"""collisionkit._jit: a cached kernel is stale as soon as any kernel source changes, not only its own file."""

from __future__ import annotations

import fcntl
import os
import select
import subprocess
import sys

import numba
from numba.core import caching

from collisionkit import _jit
from collisionkit._kernels.edmd import prediction


def test_kernel_caches_are_stamped_by_every_kernel_source(tmp_path, monkeypatch):
    assert caching.CacheImpl._locator_classes[:2] == [_jit._KernelCacheInUserDirectory, _jit._KernelCacheInTree]
    function = prediction.first_root_from_below.py_func
    locator = _jit._KernelCacheInTree.from_function(function, prediction.__file__)
    assert locator is not None and locator.get_source_stamp() == _jit.kernel_sources_stamp()
    assert _jit._KernelCacheInTree.from_function(function, caching.__file__) is None  # not a kernel: numba's own
    tree = tmp_path / "_kernels"
    (tree / "edmd").mkdir(parents=True)
    (tree / "edmd" / "helper.py").write_text("x = 1\n")
    jit_copy = tmp_path / "_jit.py"
    jit_copy.write_text("flags\n")
    monkeypatch.setattr(_jit, "KERNEL_SOURCES", (tree, jit_copy))
    _jit.kernel_sources_stamp.cache_clear()
    try:
        before = _jit.kernel_sources_stamp()
        (tree / "edmd" / "helper.py").write_text("x = 2\n")  # a helper another kernel inlines changes
        _jit.kernel_sources_stamp.cache_clear()
        assert _jit.kernel_sources_stamp() != before
    finally:
        monkeypatch.undo()
        _jit.kernel_sources_stamp.cache_clear()


CHILD = '''
import sys
from collisionkit._jit import compile_lock_path, kernel

def doubled(x):
    return 2.0 * x

compiled = kernel(doubled)
print(compile_lock_path(compiled), flush=True)
sys.stdin.readline()  # the parent holds the lock now
print(compiled(1.5), flush=True)
'''


def test_a_kernel_compiles_in_one_process_at_a_time(tmp_path):
    """While another process holds a kernel's compile lock, its first call waits; then it compiles and runs."""
    script = tmp_path / "child_kernel.py"  # a file of its own: numba caches only functions from files
    script.write_text(CHILD)
    environment = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}  # cold: the call must compile
    child = subprocess.Popen([sys.executable, str(script)], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
                             env=environment)
    try:
        path = child.stdout.readline().strip()
        assert path.startswith(str(tmp_path / "cache")) and path.endswith(".nbi.lock")
        with open(path, "a") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            child.stdin.write("go\n")
            child.stdin.flush()
            # compiling this function takes well under a second; the child must still be waiting after 5
            ready, _, _ = select.select([child.stdout], [], [], 5.0)
            assert not ready and child.poll() is None
        assert child.stdout.readline().strip() == "3.0"  # the lock released: it compiles and runs
        assert child.wait(timeout=120) == 0
    finally:
        child.kill()
        child.wait()


def test_a_kernel_without_an_on_disk_cache_has_no_compile_lock():
    assert _jit.compile_lock_path(numba.njit(lambda x: x)) is None
    assert _jit.compile_lock_path(prediction.first_root_from_below) is not None
