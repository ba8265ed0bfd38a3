"""The one numba type of a compiled kernel's input array, whoever calls the kernel.

numba builds a kernel once for each set of argument types it is called with, and an array's
type holds whether it is writable: a kernel read from arrays a block keeps read-only (the ply
contact's faces and directions, elements/ply_block.py) and from fresh writable arrays was
compiled twice, the second build the same machine code (12 of the ply contact's kernels, about
7 s of CPU from an empty cache, benchmarks/suite_signatures.py). The wrappers hand such inputs
through ``read_only``: one type whatever the caller gives, with no copy of an array that is
already C-contiguous and of the kernel's dtype. A compiled helper that two kernels call is
built once for each set of types its callers hand it: where one of them hands it rows of its
own writable scratch, the other's inputs of that place go through ``writable`` (a copy only of
an array that is read-only or of another layout or dtype).
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
