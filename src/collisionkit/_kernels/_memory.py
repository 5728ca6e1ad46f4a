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


@intrinsic
def prefetch(typingctx, array, row):
    """Hint the CPU to start loading ``array[row]`` (a row of a 2-D array) into cache.

    Compiles to LLVM's ``llvm.prefetch`` (read, high locality); a hint only,
    with no effect on results. Only callable from compiled code.
    """
    if not (isinstance(array, types.Array) and array.ndim in (1, 2, 3) and isinstance(row, types.Integer)):
        return None

    def codegen(context, builder, signature, args):
        array_type, row_type = signature.args
        array_value, row_value = args
        view = context.make_array(array_type)(context, builder, array_value)
        index = context.cast(builder, row_value, row_type, types.intp)
        zero = ir.Constant(index.type, 0)
        pointer = cgutils.get_item_pointer2(
            context, builder, data=view.data, shape=cgutils.unpack_tuple(builder, view.shape),
            strides=cgutils.unpack_tuple(builder, view.strides), layout=array_type.layout,
            inds=[index] + [zero] * (array_type.ndim - 1), wraparound=False, boundscheck=False,
        )
        int32 = ir.IntType(32)
        byte_pointer = ir.IntType(8).as_pointer()
        function_type = ir.FunctionType(ir.VoidType(), [byte_pointer, int32, int32, int32])
        function = cgutils.get_or_insert_function(builder.module, function_type, "llvm.prefetch.p0")
        address = builder.bitcast(pointer, byte_pointer)
        # arguments: address, read (0), high temporal locality (3), data cache (1)
        builder.call(function, [address, ir.Constant(int32, 0), ir.Constant(int32, 3), ir.Constant(int32, 1)])
        return context.get_dummy_value()

    return types.void(array, row), codegen
