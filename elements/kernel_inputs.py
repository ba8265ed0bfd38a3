"""The one numba type of a compiled kernel's input array, whoever calls the kernel.

numba builds a kernel once for each set of argument types it is called with, and an array's
type holds whether it is writable: a kernel read from arrays a block keeps read-only (the ply
contact's faces and directions, elements/ply_block.py) and from fresh writable arrays was
compiled twice, the second build the same machine code (12 of the ply contact's kernels, about
7 s of CPU from an empty cache, benchmarks/suite_signatures.py). The wrappers hand such inputs
through ``read_only``: one type whatever the caller gives, with no copy of an array that is
already C-contiguous and of the kernel's dtype.
"""

from __future__ import annotations

import numpy as np

__all__ = ["read_only"]


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
