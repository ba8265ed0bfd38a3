"""The solvers' dense linear algebra on one BLAS thread.

The dense matrices a solve meets are small: the stability check's eigenvalues of at most 200
unknowns (solvers.stability.lowest_modes), ARPACK's vectors, a few Gram matrices. One thread
does each in milliseconds. OpenBLAS's default threads (as many as the cores) spin while idle
and then wait for a core: on this project's 2-core machine with other processes busy, the
200-unknown eigh took 408 ms on OpenBLAS's two threads against 7 ms on one
(``benchmarks/blas_threads.py``), and a static solve takes one per increment. The compiled
kernels have their own threads (femcore.jit), which follow the free cores; BLAS gains nothing
at these sizes, so it is held to one thread for the duration of a solve and given back after
it: the caller's own numpy keeps its threads.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import TypeVar

from threadpoolctl import ThreadpoolController

__all__ = ["one_blas_thread"]

Method = TypeVar("Method", bound=Callable)


def one_blas_thread(method: Method) -> Method:
    """Run ``method`` with every loaded BLAS library on one thread, restored on return or
    raise. The libraries are looked up at each call (about 1 ms): numpy's and scipy's
    OpenBLAS may be loaded after this module is imported."""

    @functools.wraps(method)
    def wrapper(*args, **kwargs):
        with ThreadpoolController().limit(limits=1, user_api="blas"):
            return method(*args, **kwargs)

    return wrapper  # type: ignore[return-value]
