"""numba's compilation for the element kernels, optional: without numba the decorators return
the plain Python function and ``prange`` is ``range``, so the numpy paths keep working.

``jit`` compiles a loop over cells or nodes that runs in parallel (its ``prange`` loops split
over ``numba.set_num_threads`` threads); ``serial`` compiles a helper called from inside such
loops. Both cache the machine code next to the module (``cache=True``) and keep IEEE
arithmetic (no fastmath), so that a compiled loop gives the numbers of its numpy reference up
to the order of its sums.
"""

from __future__ import annotations

try:  # numba is a dependency; the numpy paths keep the package usable without it
    import numba

    AVAILABLE = True
except ImportError:  # pragma: no cover - exercised only where numba is missing
    numba = None  # type: ignore[assignment]
    AVAILABLE = False

__all__ = ["AVAILABLE", "jit", "prange", "serial"]


def jit(function):
    """``function`` compiled with its ``prange`` loops in parallel (as is without numba)."""
    if not AVAILABLE:
        return function
    return numba.njit(cache=True, parallel=True, fastmath=False)(function)


def serial(function):
    """``function`` compiled to run on the calling thread (as is without numba)."""
    if not AVAILABLE:
        return function
    return numba.njit(cache=True)(function)


def _prange(n):  # pragma: no cover - replaced by numba.prange inside compiled code
    return range(n)


prange = numba.prange if AVAILABLE else _prange
