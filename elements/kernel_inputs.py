"""The one numba type of a compiled kernel's input array, whoever calls the kernel.

numba builds a kernel once for each set of argument types it is called with, and an array's
type holds whether it is writable: a kernel read from arrays a block keeps read-only (the ply
contact's faces and directions, elements/ply_block.py) and from fresh writable arrays was
compiled twice, the second build the same machine code (12 of the ply contact's kernels, about
7 s of CPU from an empty cache, benchmarks/suite_signatures.py). The wrappers hand such inputs
through ``read_only`` or ``writable``: one type whatever the caller gives, with no copy of an
array that is already C-contiguous, of the kernel's dtype and of the flag asked (a copy only
where ``writable`` is given a read-only array). A compiled helper that two kernels call is
built with each for the types of what they hand it (rows of their inputs or of their own
writable scratch): the two kernels' wrappers hand those inputs alike.

Each input takes the flag the library's own call gives it, so that the library's path makes
no view or copy: read-only what the block keeps read-only (its faces, directions and facing,
elements/ply_block.py), writable what it makes fresh. The costs an array (benchmarks/
kernel_input_types.py, one thread, load 9): ``np.ascontiguousarray`` 0.04 us, ``read_only``
of a read-only array 0.29 us and of a writable one 1.1 us (the view and its flag),
``writable`` of a writable array 0.24 us; numba's call about 0.1 us more for a read-only
array than for a writable one. A kernel declared with one signature of read-only arrays of
any layout takes writable arrays at no cost (its call 0.42 us against 0.50 with two
``np.ascontiguousarray``), but femcore/jit.py builds its kernels lazily for the types they
are called with (their parted and parallel builds): not used.
"""

from __future__ import annotations

import numpy as np

__all__ = ["read_only", "writable"]


def read_only(array, dtype=np.float64) -> np.ndarray:
    """A read-only C-contiguous view of ``array`` as ``dtype`` (any shape; a copy only where
    ``array`` is not C-contiguous or not of ``dtype``): the array itself where it is one
    already, else a view whose flag is cleared (the caller's array keeps its own)."""
    array = np.ascontiguousarray(array, dtype=dtype)
    if not array.flags.writeable:
        return array
    view = array.view()
    view.flags.writeable = False
    return view


def writable(array, dtype=np.float64) -> np.ndarray:
    """A writable C-contiguous ``array`` as ``dtype`` (any shape): the array itself where it
    is one already, else a copy (the caller's array is never written through it)."""
    array = np.ascontiguousarray(array, dtype=dtype)
    return array if array.flags.writeable else array.copy()
