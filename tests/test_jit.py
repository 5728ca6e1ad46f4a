"""collisionkit._jit: a cached kernel is stale as soon as any kernel source changes, not only its own file."""

from __future__ import annotations

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
