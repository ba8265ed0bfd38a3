"""numba's compilations of a fresh checkout in two processes asking for the same kernels at
the same time (pytest-xdist's two workers on the tests of one module, the report's two jobs):
the CPU of the pair with each process compiling what it misses (numba alone,
``femcore.compile_lock.LOCKING = False``) and with the kernels' compile locks
(femcore/compile_lock.py, on by default: one process compiles a kernel, the other waits and
loads its build).

Each pass: a fresh empty numba cache (NUMBA_CACHE_DIR), two processes started together, each
building the 10-cell bias specimen of tests/test_bias_extension.py (FibrousShell, Static, one
increment of the pull): the fibrous force, energy and tangent kernels and the banded solver.
CPU is each process's user + system time (resource, its children), one numba and BLAS thread;
the machine's load (os.getloadavg) is printed before and after: other jobs share the cores.

Measured (2 cores shared with other jobs, load 9.2-10.7): numba alone, CPU of the pair
165.9 s (each solve 80.6 and 80.9 s of CPU, nearly all of it compiling; 1.8 s from a warm
cache), wall 715 s; with the lock (then tests/compile_once.py), 80.2 s (one solve 75.7 s,
the other, waiting, 0.7 s), wall 619 s: the second process loads the first one's builds
instead of compiling them again.

Tried and not kept: a lower LLVM optimisation level for the suite's builds (``NUMBA_OPT``,
set for the test processes and inherited by the report's). One process each, side by side,
on its own fresh cache, this script's workload (the bias specimen's solve, its compiling
nearly all of it), load 4-7: CPU 53.6 s at NUMBA_OPT=3 (numba's default), 52.5 s at 1, the
same shear angles to the bit (no fastmath, femcore/jit.py). tests/test_bias_extension.py and
test_mindlin.py (``-m "not slow"``) cold, three such processes: after 84 s of CPU each, the
builds at 3 and at 1 had written the same 52 cache indexes, the one at 0 only 25 (its runs
slower). numba's compile time is its own typing and lowering in Python, not LLVM's passes:
fewer or smaller kernels cut it, a lower level does not.

Run: python benchmarks/suite_compile.py
"""

import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

WORKLOAD = """
import sys, time
from femcore import compile_lock
compile_lock.LOCKING = {lock}
import numpy as np
from femcore import Model
from elements import FibrousShell
from materials import Fabric, ShearLaw
from solvers import Static
from validation import specimens
started = time.process_time()
mesh = specimens.bias_extension_mesh(200.0, 100.0, cells=10)
c = np.cos(np.pi / 4)
model = Model(mesh)
fabric = Fabric(thickness=0.3, areal_density=2.85e-10, tension=1.2e5,
                shear=ShearLaw.linear(0.2), bending=7.5)
model.add(FibrousShell(fabric, warp=(c, c, 0.0)))
model.fix("left")
model.fix("right", dofs=("uy", "uz", "alpha", "beta"))
model.displace("right", ux=30.0)
Static(increments=1, progress=False).solve(model)
print(f"{{time.process_time() - started:.1f}}")
"""


def run_pair(lock: bool) -> tuple[float, float, list[str]]:
    """Two processes on one fresh cache: (CPU s of both, wall s, each one's solve CPU)."""
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache, "PYTHONPATH": str(ROOT),
               "NUMBA_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1",
               "OMP_NUM_THREADS": "1"}  # fmt: skip
        code = WORKLOAD.format(lock=lock)
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        started = time.perf_counter()
        processes = [
            subprocess.Popen(
                [sys.executable, "-c", code], cwd=ROOT, env=env, stdout=subprocess.PIPE, text=True
            )  # fmt: skip
            for _ in range(2)
        ]
        solves = [p.communicate()[0].strip() for p in processes]
        wall = time.perf_counter() - started
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        return cpu, wall, solves


def main() -> None:
    print(f"load before: {os.getloadavg()[0]:.1f}")
    for lock in (False, True):
        cpu, wall, solves = run_pair(lock)
        label = "compile lock" if lock else "numba alone "
        print(f"{label}: CPU of the pair {cpu:6.1f} s, wall {wall:6.1f} s, "
              f"each solve's CPU {solves} s; load {os.getloadavg()[0]:.1f}")  # fmt: skip


if __name__ == "__main__":
    main()
