"""What one type per kernel input costs a call (elements/kernel_inputs.py): a wrapper that
hands numba a read-only view of the caller's array (``read_only``) against one that hands
the array as it comes (``np.ascontiguousarray``, a second build for a second type), and
against the other way to one build, a kernel declared with one signature whose arrays are
read-only and of any layout (numba converts a writable C array to it at each call).

Measured on ``elements.node_rows``' comparison of two (s, 3) rows (a loop that stops at the
first difference: here at the first row, so the call is all overhead), best of 7 runs of
20000 calls each, one thread. At a load of 8.8 (us a call): as given 0.50, read_only views of
writable arrays 3.13, read_only of read-only arrays 1.30, read-only arrays as given 0.70,
writable of writable arrays 0.89, the declared signature 0.42; alone, two read_only of
writable arrays 2.26, of read-only ones 0.58, two writable 0.48, two np.ascontiguousarray
0.09. So each input takes the flag the library's own path gives it (kernel_inputs.py).

Run: python benchmarks/kernel_input_types.py
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numba
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from elements.kernel_inputs import read_only, writable  # noqa: E402
from elements.node_rows import _same_rows  # noqa: E402

REPEATS, CALLS = 7, 20000


def _loop(a, b):
    for i in range(a.shape[0]):
        for j in range(3):
            if not a[i, j] == b[i, j]:
                return False
    return True


def best(call) -> float:
    """The best of REPEATS runs of CALLS calls, us a call."""
    times = []
    for _ in range(REPEATS):
        start = time.perf_counter()
        for _ in range(CALLS):
            call()
        times.append((time.perf_counter() - start) / CALLS * 1e6)
    return min(times)


def main() -> None:
    print(f"load {os.getloadavg()[0]:.2f}")
    a = np.random.default_rng(0).normal(size=(1000, 3))
    b = a.copy()
    b[0, 0] += 1.0
    frozen_a, frozen_b = a.copy(), b.copy()
    for array in (frozen_a, frozen_b):
        array.setflags(write=False)
    kind = numba.types.Array(numba.float64, 2, "A", readonly=True)
    declared = numba.njit(numba.boolean(kind, kind))(_loop)
    _same_rows(read_only(a), read_only(b))
    _same_rows(a, b)  # the writable build beside the read-only one
    rows = [
        ("as given (np.ascontiguousarray), writable", lambda: _same_rows(
            np.ascontiguousarray(a), np.ascontiguousarray(b))),
        ("read_only views of writable arrays", lambda: _same_rows(read_only(a), read_only(b))),
        ("read_only of read-only arrays (no view)", lambda: _same_rows(
            read_only(frozen_a), read_only(frozen_b))),
        ("read-only arrays as given", lambda: _same_rows(frozen_a, frozen_b)),
        ("writable of writable arrays (no copy)", lambda: _same_rows(writable(a), writable(b))),
        ("declared signature (readonly, any layout)", lambda: declared(a, b)),
        ("read_only of writable arrays alone (no call)", lambda: (read_only(a), read_only(b))),
        ("read_only of read-only arrays alone (no call)", lambda: (
            read_only(frozen_a), read_only(frozen_b))),
        ("writable of writable arrays alone (no call)", lambda: (writable(a), writable(b))),
        ("np.ascontiguousarray alone (no call)", lambda: (
            np.ascontiguousarray(a), np.ascontiguousarray(b))),
    ]  # fmt: skip
    for name, call in rows:
        print(f"{best(call):7.3f} us  {name}")
    print(f"load {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
