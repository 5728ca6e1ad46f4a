"""The one place where numba compilation flags are set.

Every numeric kernel in collisionkit is decorated with :func:`kernel`, so the
flags (lazy compilation, on-disk cache, strict IEEE arithmetic) are the same
everywhere and can be changed here alone.

``fastmath`` stays off: the collision formulas rely on IEEE semantics for
``inf`` masses and for the cancellation-free forms of the contact-time root.
Kernels that neither allocate nor return arrays can use the ``borrowing_``
variants, compiled without numba's reference counting (NRT): the arrays they
get are borrowed from the caller, who keeps them alive. Every array passed
to an inlined helper otherwise costs an atomic increment and decrement,
which took 11 % of the EDMD event loop (perf, N = 864).

Set the environment variable ``NUMBA_CACHE_DIR`` to choose where compiled
kernels are cached (``.ci/run`` does).
"""

from __future__ import annotations

import numba

JIT_OPTIONS = {
    "cache": True,
    "nogil": True,
    "fastmath": False,
    "error_model": "numpy",
}

# numba's private option for its reference-counting runtime; with it off a kernel may not allocate arrays
BORROWING_OPTIONS = {**JIT_OPTIONS, "_nrt": False}


def kernel(function):
    """Compile ``function`` lazily with the project's numba options.

    Compilation happens at the first call for each set of argument types,
    and the machine code is cached on disk for the next process.
    """
    return numba.njit(**JIT_OPTIONS)(function)


def inline_kernel(function):
    """Like :func:`kernel`, but inlined into every kernel that calls it.

    For the small helpers of hot loops: a call between numba functions that
    take arrays costs tens of nanoseconds (argument unpacking and reference
    counting), more than the helper's arithmetic. Inlining at numba's IR
    level removes it (measured 5x on the list-expiry helper of the EDMD
    engine) at the price of longer first compilation, which is cached.
    """
    return numba.njit(inline="always", **JIT_OPTIONS)(function)


def borrowing_kernel(function):
    """Like :func:`kernel`, without reference counting: for kernels that never allocate or return arrays."""
    return numba.njit(**BORROWING_OPTIONS)(function)


def borrowing_inline_kernel(function):
    """Like :func:`inline_kernel`, without reference counting (see :func:`borrowing_kernel`)."""
    return numba.njit(inline="always", **BORROWING_OPTIONS)(function)
