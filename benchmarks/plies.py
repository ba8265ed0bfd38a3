"""The plies model of Bai §5.1 against one fibrous shell on the same mesh and load: wall time of
a full quasi-static solve, one thread and the default threads.

The strip of cases/bai-5.1.toml (150 x 30 mm, 30 x 2 cells, the 20-ply G986 stack h = 6 mm,
clamped at x = 0, the far end moved by (-30, 0, -50) mm, gravity) as N sliding plies
(elements/plies.py: N Mindlin shells, N - 1 PlyContact) and as one FibrousShell (the reference
pass), each solved to equilibrium with solvers.Static: gravity over load factor 0-1, then the
end's displacement over 1-2 (step_loads_first), 10 increments per phase. The fibrous shell
takes the same solver as the plies here (the report's bai-5.1 follows the arc length; the load
path converges on this strip too), so the two times differ by the model alone. Prints the
Newton iterations, cuts and wall time of each solve, and the machine's load (os.getloadavg)
before and after, as other jobs share the cores.

Measured (2 cores shared, load 3.9 before, 8.1 after): one thread, fibrous shell 21.2 s (222
Newton iterations, 4 cuts), 4 plies 166.6 s (394 iterations, 7 cuts); two threads 51.7 s and
222.6 s (the same iterations: the load, not the threads, set those times). 20 plies were run
apart (one thread): no convergence at the first displacement increment after 35 min.

Run: python benchmarks/plies.py [N ...]   (default N = 4 20; the default threads are
NUMBA_NUM_THREADS or the core count, and each model also runs on one thread)
"""

from __future__ import annotations

import os
import sys
import time

import numba
import numpy as np

from elements import FibrousShell
from elements.plies import PlyStack
from femcore import Mesh, Model
from materials.presets import g986_stack
from solvers import Static

INCREMENTS = 10  # per phase: the plies' 4- and 8-ply solves needed 7 cuts at 10


def _load(model: Model, far) -> Model:
    model.fix(far("left"))
    model.displace(far("right"), ux=-30.0, uz=-50.0)
    model.gravity((0.0, 0.0, -9810.0))
    return model


def solve(model: Model) -> tuple[float, int, int, bool]:
    """(wall time s, Newton iterations, cuts, converged) of one quasi-static solve."""
    solver = Static(increments=INCREMENTS, step_loads_first=True, progress=False)
    start = time.perf_counter()
    try:
        result = solver.solve(model)
        converged = bool(result.converged)
    except Exception as error:  # a stalled solve is a figure too: report where it stopped
        result, converged = error.result, False  # type: ignore[attr-defined]
    wall = time.perf_counter() - start
    return wall, int(sum(result.info["iterations_per_increment"])), result.info["cuts"], converged


def fibrous(mid: Mesh) -> Model:
    model = _load(Model(mid), mid.nodes)
    model.add(FibrousShell(g986_stack(), clamped="left"))
    return model


def plies(mid: Mesh, count: int) -> Model:
    stack = PlyStack(mid, g986_stack(), count)
    return _load(stack.model(), stack.nodes)


def main(counts: list[int]) -> None:
    default = numba.get_num_threads()
    print(f"threads: 1 and {default} (NUMBA_NUM_THREADS={os.environ.get('NUMBA_NUM_THREADS')})")
    print(f"load before (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")
    mid = Mesh.rectangle(150.0, 30.0, nx=30, ny=2)
    solve(fibrous(Mesh.rectangle(150.0, 30.0, nx=4, ny=1)))  # compile the kernels once
    for threads in sorted({1, default}):
        numba.set_num_threads(threads)
        for label, build in [("fibrous shell", fibrous)] + [
            (f"{count} plies", lambda m, c=count: plies(m, c)) for count in counts
        ]:
            wall, iterations, cuts, converged = solve(build(mid))
            print(
                f"{threads} thread(s) {label:14s}: {wall:8.1f} s, {iterations:4d} Newton "
                f"iterations, {cuts} cuts, {'converged' if converged else 'NOT converged'}",
                flush=True,
            )
    print(f"load after  (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [4, 20])
