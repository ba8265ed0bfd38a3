"""A call run with numba's loops on one thread and again on all of its threads: the compiled
kernels' tests hold the two to the same bits (femcore/jit.py sums in the same order on any
thread count)."""

from collections.abc import Callable
from typing import Any

import numba

from femcore import jit


def on_one_thread_and_on_all(call: Callable[[], Any]) -> tuple[Any, Any]:
    """``call()`` with every loop on one thread, then with every loop on all of numba's
    threads (``jit.SMALL_LOOP`` 0, the machine's load not followed): (one, every). numba's
    thread count and jit's settings are restored afterwards, also when ``call`` raises."""
    before = numba.get_num_threads()
    small, follow = jit.SMALL_LOOP, jit.FOLLOW_LOAD
    answers = []
    try:
        for small_loop, threads in ((10**9, 1), (0, numba.config.NUMBA_NUM_THREADS)):
            jit.SMALL_LOOP, jit.FOLLOW_LOAD = small_loop, False
            numba.set_num_threads(threads)
            answers.append(call())
    finally:
        jit.SMALL_LOOP, jit.FOLLOW_LOAD = small, follow
        numba.set_num_threads(before)
    return answers[0], answers[1]
