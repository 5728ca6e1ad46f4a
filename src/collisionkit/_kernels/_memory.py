"""Memory helpers for the kernels: a software prefetch.

The event-driven engine is bound by memory latency: each event touches a few
particles scattered over arrays far larger than the caches, and each miss
costs ~100-150 ns on the benchmark machine (benchmarks/bench_edmd.py). Loads
whose addresses are known early can be started together with
:func:`prefetch`, so their latencies overlap instead of adding up.
"""

from __future__ import annotations

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic


def _prefetch_codegen(context, builder, array_type, array_value, indices):
    """Emit llvm.prefetch (read, high locality, data cache) of the element at ``indices`` (the rest 0)."""
    view = context.make_array(array_type)(context, builder, array_value)
    index_values = [context.cast(builder, value, value_type, types.intp) for value, value_type in indices]
    zero = ir.Constant(index_values[0].type, 0)
    pointer = cgutils.get_item_pointer2(
        context, builder, data=view.data, shape=cgutils.unpack_tuple(builder, view.shape),
        strides=cgutils.unpack_tuple(builder, view.strides), layout=array_type.layout,
        inds=index_values + [zero] * (array_type.ndim - len(index_values)), wraparound=False, boundscheck=False,
    )
    int32 = ir.IntType(32)
    byte_pointer = ir.IntType(8).as_pointer()
    function_type = ir.FunctionType(ir.VoidType(), [byte_pointer, int32, int32, int32])
    function = cgutils.get_or_insert_function(builder.module, function_type, "llvm.prefetch.p0")
    address = builder.bitcast(pointer, byte_pointer)
    # arguments: address, read (0), high temporal locality (3), data cache (1)
    builder.call(function, [address, ir.Constant(int32, 0), ir.Constant(int32, 3), ir.Constant(int32, 1)])
    return context.get_dummy_value()


@intrinsic
def prefetch(typingctx, array, row):
    """Hint the CPU to start loading ``array[row]`` (a row of an array) into cache.

    Compiles to LLVM's ``llvm.prefetch`` (read, high locality); a hint only,
    with no effect on results. Only callable from compiled code.
    """
    if not (isinstance(array, types.Array) and array.ndim in (1, 2, 3) and isinstance(row, types.Integer)):
        return None

    def codegen(context, builder, signature, args):
        return _prefetch_codegen(context, builder, signature.args[0], args[0], [(args[1], signature.args[1])])

    return types.void(array, row), codegen


@intrinsic
def prefetch_at(typingctx, array, row, column):
    """Like :func:`prefetch`, for ``array[row, column]``: a later cache line of a long row."""
    if not (isinstance(array, types.Array) and array.ndim in (2, 3) and isinstance(row, types.Integer)
            and isinstance(column, types.Integer)):
        return None

    def codegen(context, builder, signature, args):
        indices = [(args[1], signature.args[1]), (args[2], signature.args[2])]
        return _prefetch_codegen(context, builder, signature.args[0], args[0], indices)

    return types.void(array, row, column), codegen
