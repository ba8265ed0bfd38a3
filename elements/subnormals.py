"""Subnormal numbers flushed to zero while an explicit run steps (``flushed``): the x86-64
processor's flush-to-zero and denormals-are-zero modes (the MXCSR register's FTZ and DAZ
bits) on the calling thread and on numba's worker threads, the register as it was afterwards.

Why: an explicit run from rest spreads its disturbance one ring of cells a step, and ahead of
the wave the rates, moments and director components are tiny (1e-200 and below): their products
fall below the smallest normal double (2.2e-308), and every operation on such a subnormal
number costs the processor some hundred cycles. On the 20k-triangle forming blank
(benchmarks/hemisphere_forming.py, the first 0.3 % of the stroke, one thread) a step's element
force took 1.1 times and its nodal update 2.3 times as long as with them flushed (1.3 and 3
times on the state of step 250); by 2 % of the stroke the whole blank moves and none are left:
the gain is the start's, and a benchmark of the first steps then shows the stroke's pace. A
subnormal is zero in any physical sense (mm, N, s, rad): flushed, a run changes only numbers
below 2.2e-308 and what is made of them alone (a sum with a normal number is the same to the
last bit), and stays the same to the last bit from one run to the next and on any number of
threads (the worker threads flush as well).

The numpy passes on the calling thread flush too while the modes are on; other processors
(no MXCSR) run as before (``SUPPORTED`` False).
"""

from __future__ import annotations

import platform
from collections.abc import Iterator
from contextlib import contextmanager

from elements.jit import AVAILABLE

__all__ = ["ENABLED", "SUPPORTED", "flushed"]

#: Whether ``flushed`` turns the modes on (False: it changes nothing).
ENABLED = True
#: MXCSR's flush-to-zero (bit 15) and denormals-are-zero (bit 6).
FLAGS = 0x8040
SUPPORTED = AVAILABLE and platform.machine().lower() in ("x86_64", "amd64")

if SUPPORTED:
    import numba
    from llvmlite import ir  # type: ignore[import-untyped]
    from numba import types
    from numba.core import cgutils
    from numba.extending import intrinsic

    def _register(builder, name: str, slot) -> None:
        """Call LLVM's x86 intrinsic ``name`` (stmxcsr or ldmxcsr) on the 32-bit ``slot``."""
        pointer = ir.IntType(8).as_pointer()
        kind = ir.FunctionType(ir.VoidType(), [pointer])
        function = cgutils.get_or_insert_function(builder.module, kind, f"llvm.x86.sse.{name}")
        builder.call(function, [builder.bitcast(slot, pointer)])

    @intrinsic
    def _read_register(context):
        """The calling thread's MXCSR (uint32)."""

        def build(context, builder, signature, args):
            slot = cgutils.alloca_once(builder, ir.IntType(32))
            _register(builder, "stmxcsr", slot)
            return builder.load(slot)

        return types.uint32(), build

    @intrinsic
    def _write_register(context, value):
        """Load ``value`` (uint32) into the calling thread's MXCSR."""

        def build(context, builder, signature, args):
            slot = cgutils.alloca_once(builder, ir.IntType(32))
            builder.store(args[0], slot)
            _register(builder, "ldmxcsr", slot)
            return context.get_dummy_value()

        return types.void(types.uint32), build

    @numba.njit(cache=True)
    def _modes(on):
        """Turn FTZ and DAZ on (or off) on the calling thread; its MXCSR before."""
        before = _read_register()  # type: ignore[call-arg, var-annotated]
        if on:
            _write_register(numba.uint32(before | FLAGS))
        else:
            _write_register(numba.uint32(before & ~numba.uint32(FLAGS)))
        return before

    @numba.njit(cache=True, parallel=True)
    def _modes_everywhere(items, on):
        """``_modes`` on every thread of numba's pool: each takes a chunk of ``items``
        iterations (at least one each when there are as many as threads)."""
        for _ in numba.prange(items):
            _modes(on)


def _parallel() -> bool:
    """Whether the compiled loops may run on more than the calling thread: numba's setting of
    the calling thread above one (elements/jit.py never goes past it). A test session's (one
    thread) then never compiles ``_modes_everywhere`` nor starts numba's pool."""
    return numba.get_num_threads() > 1


def _workers(on: bool) -> None:
    """FTZ and DAZ on (or off) on every thread of numba's pool."""
    pool = numba.config.NUMBA_NUM_THREADS  # type: ignore[attr-defined]
    cap = numba.get_num_threads()
    numba.set_num_threads(pool)
    try:
        _modes_everywhere(64 * pool, on)
    finally:
        numba.set_num_threads(cap)


@contextmanager
def flushed() -> Iterator[None]:
    """Subnormal numbers flushed to zero inside the block (where ``SUPPORTED`` and
    ``ENABLED``) on the calling thread and, where the loops may run on more threads
    (``_parallel``), on numba's worker threads; the modes as they were afterwards (a block
    inside another, or on a thread that had them on already, leaves them on)."""
    if not (SUPPORTED and ENABLED):
        yield
        return
    before = int(_modes(True))
    already = before & FLAGS == FLAGS
    workers = not already and _parallel()
    if workers:
        _workers(True)
    try:
        yield
    finally:
        if workers:
            _workers(False)
        if not already:
            _modes(False)
