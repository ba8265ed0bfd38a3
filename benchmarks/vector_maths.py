"""What the C library's transcendental functions cost inside a compiled loop, and whether numba
here can run them on vectors (SVML): the question behind the fibrous cells' pass
(elements/fibrous/kernels.py), whose fibre levels call a log twice and an arcsine once each,
and whose normals and side folds call arctan2.

Printed: numba's SVML state (``numba.config.USING_SVML`` and llvmlite's ``has_svml``: numba
calls Intel's vectorised functions only with an llvmlite built on its patched LLVM, and with
the icc-rt package installed); whether LLVM vectorises a loop of ``np.log`` and ``np.arcsin``
(the vector intrinsics ``llvm.log.v8f64`` in the optimised IR); then the CPU nanoseconds a
value of loops over 4096 values in [0.3, 0.8] (best of ``--repeats``): log, arcsin,
arctan2(y, 0.7), arctan, 1 / sqrt, beside a multiply-add (the reference: what the loop costs
without a call).

Measured on the 2-core AMD EPYC (znver4, AVX-512), numba 0.68.1, llvmlite 0.50.0 (LLVM 22)
from their PyPI wheels, load 2-4: SVML off and not available (llvmlite's wheel has no SVML
patch: installing icc-rt cannot switch it on); LLVM vectorises the loop to 8 lanes with
``llvm.log.v8f64`` and ``llvm.asin.v8f64``, and its code generator calls the scalar library
functions lane by lane (the option ``-vector-library=LIBMVEC-X86`` set through llvmlite
before numba loads, tried: no glibc vector function is called). ns a value (load 6.8): log
3.4, arcsin 4.0, arctan2 11.7, arctan 7.9, 1 / sqrt 3.7 (0.9 with numba's numpy error model,
without the division's zero test: then LLVM vectorises the loop), the multiply-add 0.2.

The branch-free functions of elements/lane_maths.py (fdlibm's algorithms by selects, no call,
the float's bits by an LLVM bitcast) in the same loops, which LLVM then runs 8 lanes at a
time (zmm registers, ``vdivpd``, no call in the loop), printed beside the library's: ns a
value at a load of 6.4, lane_log 1.57 (library 3.43), lane_arcsin 1.07 (4.04), lane_arctan2
1.91 (11.73; 9.5-12 when LLVM left it a call: numba's plain build of a helper
that size is not inlined, so it is spliced by numba, ``inline``, into callers built with
the numpy error model). What a loop needs to vectorise here, found on the way:

* no division with numba's default error model (its zero test raises, and a loop with an
  exit does not vectorise): the helpers are built with the numpy error model
  (femcore/jit.py ``lanes``), and a kernel whose loops divide by ``jit_lanes``;
* no read of a column of a 2-D argument (``a[start + i, f]``: "cannot identify array
  bounds") and rows of one scratch array at constant distances: a 2-D scratch array's rows
  at a run-time stride asked a test for each pair of rows ("too many memory checks"), a
  one-dimensional array with row k at k * CHUNK none;
* no call, and no gather through an index array (positions[connectivity[c, 0]]): those
  loops gather into the scratch rows first, one cell at a time.

The fibrous force with them (benchmarks/kernel_pairs.py, one thread, 100k triangles, paired
against main fdcebfd, median new / old of 10 rounds): the log and arcsine alone in the scalar
cell loop 1.099 (slower: a division each, not vectorised there); the fibre levels as loops
across chunks of 32 cells with them 0.873 (load 10), and the corner angles and the sides'
folds by lane_arctan2 across chunks too 0.807 (load 5.3; force and energy 0.819). Against
the chunked tree itself (HEAD), 8-10 rounds: the fibre levels skipped (wrong, timed only)
0.790, so the levels now cost 0.066 µs a cell of 0.32 (0.16 before); the membrane's laws
replaced by c x (the same bits on this sheet) 0.987; the pulls' pass (pass 3) as loops
across chunks too (vectorised, its 0.044 µs a cell) 0.981, not kept (below 5 %); each
membrane law over the chunk's strains of its family at once (level_lanes.py ``law_row``, an
odd polynomial vectorised a coefficient at a time), the same bits: force and energy 0.939
and 0.930 (load 7-7.6), the force 0.960-0.981, kept (the checked step's path). A control,
this tree against its own commit (the same code on both sides): the force 0.996, force and
energy 1.042 (8 rounds, load 7.5), the pairing's noise at that load. Chunks of 16 and 64
cells were not measured: the runs read numba's cached build of 32 (the cache of kernels.py
does not see a change of level_lanes.py's constants).

Run from the project root:

    python benchmarks/vector_maths.py
"""

from __future__ import annotations

import argparse
import re
import sys
import time
from pathlib import Path

import llvmlite.binding as llvm
import numba
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install
from elements.lane_maths import lane_arcsin, lane_arctan2, lane_log  # noqa: E402


@numba.njit
def _multiply_add(x, y):
    for i in range(x.shape[0]):
        y[i] = 1.5 * x[i] + 0.25


@numba.njit
def _log(x, y):
    for i in range(x.shape[0]):
        y[i] = np.log(x[i])


@numba.njit
def _arcsin(x, y):
    for i in range(x.shape[0]):
        y[i] = np.arcsin(x[i])


@numba.njit
def _arctan2(x, y):
    for i in range(x.shape[0]):
        y[i] = np.arctan2(x[i], 0.7)


@numba.njit
def _arctan(x, y):
    for i in range(x.shape[0]):
        y[i] = np.arctan(x[i])


@numba.njit
def _inverse_root(x, y):
    for i in range(x.shape[0]):
        y[i] = 1.0 / np.sqrt(x[i])


@numba.njit
def _log_and_arcsin(x, y):
    for i in range(x.shape[0]):
        y[i] = np.log(x[i]) + np.arcsin(x[i])


@numba.njit
def _lane_log(x, y):
    for i in range(x.shape[0]):
        y[i] = lane_log(x[i])


@numba.njit
def _lane_arcsin(x, y):
    for i in range(x.shape[0]):
        y[i] = lane_arcsin(x[i])


@numba.njit(error_model="numpy")  # lane_arctan2 is spliced: its division unchecked here
def _lane_arctan2(x, y):
    for i in range(x.shape[0]):
        y[i] = lane_arctan2(x[i], 0.7)


def per_value(loop, x: np.ndarray, repeats: int) -> float:
    """CPU ns per value of ``loop`` over ``x``, the best of ``repeats``."""
    y = np.empty_like(x)
    loop(x, y)
    best = np.inf
    for _ in range(repeats):
        started = time.process_time()
        for _ in range(50):
            loop(x, y)
        best = min(best, (time.process_time() - started) / 50)
    return best / len(x) * 1e9


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=40)
    args = parser.parse_args(argv)
    print(
        f"numba {numba.__version__}, llvmlite LLVM {'.'.join(map(str, llvm.llvm_version_info))}: "
        f"SVML in use {numba.config.USING_SVML}, llvmlite built with SVML {llvm.has_svml}"
    )
    x = np.random.default_rng(0).uniform(0.3, 0.8, 4096)
    _log_and_arcsin(x, np.empty_like(x))
    ir = _log_and_arcsin.inspect_llvm(_log_and_arcsin.signatures[0])
    lanes = sorted(set(re.findall(r"llvm\.(?:log|asin)\.v\d+f64", ir)))
    print(f"a loop of log and arcsin vectorised: {', '.join(lanes) or 'no'}")
    loops = {
        "multiply-add (reference)": _multiply_add,
        "log": _log,
        "arcsin": _arcsin,
        "arctan2(x, 0.7)": _arctan2,
        "arctan": _arctan,
        "1 / sqrt": _inverse_root,
        "lane_log": _lane_log,
        "lane_arcsin": _lane_arcsin,
        "lane_arctan2(x, 0.7)": _lane_arctan2,
    }
    for name, loop in loops.items():
        print(f"{name:>26}: {per_value(loop, x, args.repeats):.2f} ns a value", flush=True)


if __name__ == "__main__":
    main()
