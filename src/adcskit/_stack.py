"""Small arrays on a compiled function's stack frame (numba CPU target).

:func:`stack_f64` gives a numba-compiled function a C-contiguous float64 matrix of a size
known at compile time, in its own stack frame: no allocation (it works in functions compiled
without numba's reference-counting runtime, ``_nrt=False``, where ``np.empty`` is refused),
and memory that LLVM knows no other pointer reaches. The second point is why it exists:
LLVM vectorises a loop that writes into such an array and reads from argument arrays, but
not the same loop writing into an argument array (it cannot prove the argument arrays
distinct, and numba passes no ``noalias``): the closed-loop kernel's RK4 step across lane
blocks runs 2-4x faster with its state here (docs/benchmarks.md, "Samples in lanes"). numba
has no public stack array for the CPU target (``numba.cuda.local.array`` is CUDA's), hence
this intrinsic. The array must not outlive the function that creates it (do not return it).
"""

from __future__ import annotations

from typing import Any

from numba import types
from numba.core import cgutils
from numba.extending import intrinsic
from numba.np.arrayobj import make_array, populate_array

__all__ = ["stack_f64"]


@intrinsic
def stack_f64(typingctx: Any, rows: Any, cols: Any) -> Any:
    """``stack_f64(rows, cols)``: an uninitialised ``rows x cols`` float64 C-contiguous array
    in the calling function's stack frame; ``rows`` and ``cols`` must be integer literals (or
    module-level integer constants, which numba freezes as literals). Inside numba only."""
    if not (isinstance(rows, types.IntegerLiteral) and isinstance(cols, types.IntegerLiteral)):
        return None
    r, c = int(rows.literal_value), int(cols.literal_value)
    if r < 1 or c < 1:
        return None
    aty = types.Array(types.float64, 2, "C")

    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        # alloca_once puts the allocation in the function's entry block: one per call, not per
        # loop iteration, whatever the call site
        ptr = cgutils.alloca_once(builder, context.get_data_type(types.float64), size=r * c)
        ary = make_array(aty)(context, builder)
        size = context.get_constant(types.intp, 8)
        populate_array(ary, data=ptr,
                       shape=[context.get_constant(types.intp, r), context.get_constant(types.intp, c)],
                       strides=[context.get_constant(types.intp, 8 * c), size],
                       itemsize=size, meminfo=None)
        return ary._getvalue()

    return aty(rows, cols), codegen
