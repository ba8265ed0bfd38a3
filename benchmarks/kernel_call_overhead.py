"""What ``femcore.jit``'s wrapper adds to a compiled loop's call on one thread: a loop
below ``SMALL_LOOP`` items (every loop of the two-ply hemisphere's step, some fifty calls a
step) runs on one thread whatever numba's setting, so the wrapper no longer reads the
setting there (``_Parallel.__call__``); the reference pass reads it first, as the wrapper
did before (``_threads(len(args[0]), _setting())``), then calls the same plain build.

Measured on ``elements.ply_sides``-sized inputs: a loop over 384 points with 20 array
arguments that returns at once (the call is all overhead), best of 7 runs of 20000 calls
each, one thread, load printed. At a load of 8.0-8.5 on 2 cores (three runs): the wrapper
1.64-1.68 against 2.00-2.06 us a call (the plain build called directly 1.48-1.49): 0.36-0.38
us a call, some 19 us of the two-ply step's ~1.9 ms (~1 %).

Run: NUMBA_NUM_THREADS=1 python benchmarks/kernel_call_overhead.py
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from femcore import jit as jit_module  # noqa: E402
from femcore.jit import jit, prange  # noqa: E402

REPEATS, CALLS = 7, 20000


@jit
def _touch(
    a0, a1, a2, a3, a4, a5, a6, a7, a8, a9, a10, a11, a12, a13, a14, a15, a16, a17, a18, out
):  # fmt: skip
    """A loop of the ply contact's size that writes one entry: its call is the overhead."""
    for i in prange(min(a0.shape[0], 1)):
        out[i] = a1[i, 0] + a2[i, 0]


def _reference(kernel, *args):
    """The wrapper's one-thread path as it was: numba's setting read, then the threads."""
    cap = jit_module._setting()
    threads = jit_module._threads(len(args[0]), cap)
    assert threads == 1
    return kernel.serial(*args, 0, 1)


def _best(call) -> float:
    """Best CPU time of a call (us) over REPEATS runs of CALLS calls."""
    best = np.inf
    for _ in range(REPEATS):
        began = time.process_time()
        for _ in range(CALLS):
            call()
        best = min(best, (time.process_time() - began) / CALLS)
    return best * 1e6


def main() -> None:
    arrays = [np.random.default_rng(k).random((384, 3)) for k in range(19)]
    out = np.zeros(384)
    args = (*arrays, out)
    _touch(*args)  # compiled (or loaded) before timing
    print(f"load {os.getloadavg()}")
    wrapper = _best(lambda: _touch(*args))
    reference = _best(lambda: _reference(_touch, *args))
    plain = _best(lambda: _touch.serial(*args, 0, 1))
    print(f"the wrapper {wrapper:.2f} us a call, the reference pass {reference:.2f} us, "
          f"the plain build called directly {plain:.2f} us")  # fmt: skip
    print(f"load {os.getloadavg()}")


if __name__ == "__main__":
    main()
