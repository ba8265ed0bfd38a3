"""The parallel build of the element loops (femcore/jit.py ``_Parallel``), this checkout beside
another (``--against``, e.g. a checkout of the previous commit): what its compilation costs in
a fresh checkout and how fast it runs, each pass a fresh process on a fresh empty numba cache
(NUMBA_CACHE_DIR), the two checkouts in turns.

In each pass, on a pinned square sheet of about ``--cells`` triangles (benchmarks/
shell_sheet.py's sheet, jittered), for the fibrous and the Mindlin shell: the CPU of the
first internal force on one thread (the plain builds compiled), then of the first on
``--threads`` threads with every loop parallel (``SMALL_LOOP = 0``, ``FOLLOW_LOAD = False``:
the parallel builds compiled), then the best of ``--repeats`` forces on those threads, wall
and CPU per element (µs), and on one thread. The forces' bits are hashed: the same hash in
both checkouts and on any thread count.

Measured (39762 cells, 2 threads, 10 repeats; 2 cores shared with other jobs), main c108a2a
(numba's parallel build of each whole kernel) then this checkout (the plain build in parts):

    pass (load)      first force: 1 thread, then 2   force us/cell wall (CPU): 1 thr., 2 thr.
    fibrous, main (4.3)    10.75 s, 30.83 s CPU      1.464 (0.540), 1.707 (0.557)
    fibrous, parts (5.1)   12.66 s, 10.16 s CPU      1.144 (0.591), 1.484 (0.651)
    Mindlin, main (4.3)     2.48 s,  5.83 s CPU      0.448 (0.141), 0.209 (0.143)
    Mindlin, parts (5.1)    3.05 s,  1.69 s CPU      0.360 (0.150), 0.346 (0.119)

An earlier pass of main at load 2.6: fibrous 11.61 s and 27.63 s, Mindlin 1.50 and 4.24 s.
The forces' bits the same in both checkouts and on both thread counts (fibrous b13fbad0fc99,
Mindlin e9d767b31767). At that load the 2-thread wall times measure the machine, not the
builds (a second core was seldom free); the CPU per cell, what a force costs, is the same
within the noise. The explicit step of benchmarks/explicit_step.py (fibrous, 10082 cells,
one thread, µs of CPU per element-step, old and new in turns, load 3.6-4.3): steady step
0.647 and 0.678 on main, 0.539 and 0.646 with the parted plain build; force 0.599, 0.562
against 0.405, 0.472.

The loop over the parts calling the plain build through its address (femcore/jit.py
``_call_at``: nothing of the plain build linked into the parallel one, where numba optimised
and compiled it again), this checkout against c0b0822 (which linked it), 19602 cells, 2
threads, 5 repeats, each pass on a fresh numba cache; 2 cores shared with other jobs, load
10.1 and 9.3 (old, new):

    pass             first force: 1 thread, then 2   force us/cell wall (CPU): 1 thr., 2 thr.
    fibrous, linked       25.88 s, 11.46 s CPU       0.772 (0.314), 0.675 (0.337)
    fibrous, address      25.42 s,  3.73 s CPU       0.494 (0.294), 0.891 (0.285)
    Mindlin, linked        1.99 s,  1.57 s CPU       0.101 (0.101), 0.094 (0.094)
    Mindlin, address       1.82 s,  0.69 s CPU       0.090 (0.090), 0.093 (0.093)

The forces' bits the same in both checkouts and on both thread counts (fibrous db0b2053ae47,
Mindlin 9e0e0ecd1770). The fibrous force pass's loop over the parts alone (its plain build
compiled first, each loop built without a cache, 2 threads, load 12.5): 27.18 s of CPU
linked, 1.22 s through the address, the same outputs to the bit. Looking the address up
costs each parallel call about 0.3-0.9 µs an argument (``_type_key``: 30 µs wall for the
fibrous force pass's 35 arguments at a load of 10, where numba's typeof took 79 µs). In a
whole run of the suite (benchmarks/suite_processes.py, c0b0822, load 1.7 -> 9.5) the 29
parallel builds the tests marked ``parallel`` compile took 24.5 s of CPU, all in one worker.

Run: python benchmarks/suite_parallel_build.py --against /tmp/old-checkout [--cells 40000]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

WORKLOAD = r"""
import hashlib, sys, time
import numpy as np
import numba
from elements import FibrousShell, MindlinShell
try:
    from femcore import jit
except ImportError:  # a checkout from before femcore/jit.py (it was elements/jit.py)
    from elements import jit
from femcore import Mesh, Model
from materials import ElasticShell, Fabric

cells, threads, repeats = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])
side = int(round((cells / 2) ** 0.5))
mesh = Mesh.rectangle(5.0 * side, 5.0 * side, nx=side, ny=side)
shells = {
    "fibrous": FibrousShell(Fabric(thickness=1.0, areal_density=1e-9, tension=500.0,
                                   shear=0.5, bending=2.0)),
    "mindlin": MindlinShell(ElasticShell(70e3, 0.3, 1.0, 2.7e-9)),
}


def best(call, n):
    walls, cpus = [], []
    for _ in range(n):
        w, c = time.perf_counter(), time.process_time()
        out = call()
        walls.append(time.perf_counter() - w)
        cpus.append(time.process_time() - c)
    return out, min(walls), min(cpus)


for name, shell in shells.items():
    model = Model(mesh)
    model.add(shell)
    model.fix("left")
    built = model.compile()
    state = built.initial_state()
    rng = np.random.default_rng(4)
    state.positions = state.positions + rng.normal(scale=0.3, size=state.positions.shape)
    m = len(mesh.triangles)
    force = lambda: np.hstack(built.internal_force(state))
    numba.set_num_threads(1)
    started = time.process_time()
    one = force()
    first_one = time.process_time() - started
    _, wall1, cpu1 = best(force, repeats)
    numba.set_num_threads(threads)
    jit.SMALL_LOOP, jit.FOLLOW_LOAD = 0, False
    started = time.process_time()
    many = force()
    first_many = time.process_time() - started
    many, wall, cpu = best(force, repeats)
    jit.SMALL_LOOP, jit.FOLLOW_LOAD = 2000, True
    same = hashlib.sha1(one.tobytes()).hexdigest()[:12]
    print(f"{name:8s} {m} cells: first force, 1 thread {first_one:6.2f} s CPU, "
          f"{threads} threads {first_many:6.2f} s CPU; force on 1 thread "
          f"{1e6 * wall1 / m:.3f} wall {1e6 * cpu1 / m:.3f} CPU us/cell, on {threads} "
          f"{1e6 * wall / m:.3f} wall {1e6 * cpu / m:.3f} CPU; bits {same} "
          f"{'same' if np.array_equal(one, many) else 'DIFFER'} on both", flush=True)
"""


def one_pass(checkout: Path, cells: int, threads: int, repeats: int) -> str:
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache, "PYTHONPATH": str(checkout),
               "NUMBA_NUM_THREADS": str(threads), "OPENBLAS_NUM_THREADS": "1",
               "OMP_NUM_THREADS": str(threads)}  # fmt: skip
        done = subprocess.run(
            [sys.executable, "-c", WORKLOAD, str(cells), str(threads), str(repeats)],
            cwd=checkout, env=env, capture_output=True, text=True,
        )  # fmt: skip
        return done.stdout + (done.stderr[-2000:] if done.returncode else "")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", type=Path, required=True)
    parser.add_argument("--cells", type=int, default=40000)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=10)
    parser.add_argument("--rounds", type=int, default=1)
    args = parser.parse_args()
    for _ in range(args.rounds):
        for label, checkout in (("other", args.against), ("this", ROOT)):
            print(f"--- {label} checkout {checkout}; load {os.getloadavg()[0]:.2f}", flush=True)
            print(one_pass(checkout, args.cells, args.threads, args.repeats), end="", flush=True)
    print(f"load after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
