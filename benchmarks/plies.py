"""The plies model of Bai §5.1 against one fibrous shell on the same mesh and load: wall time
per explicit step and in total, one thread and the default threads.

The strip of cases/bai-5.1.toml (150 x 30 mm, 30 x 2 cells, the 20-ply G986 stack h = 6 mm,
clamped at x = 0, the far end moved by (-30, 0, -50) mm, gravity) as N sliding plies
(elements/plies.py: N Mindlin shells, N - 1 PlyContact) and as one FibrousShell (the reference
pass), both with solvers.CentralDifference (mass-proportional damping) over the same short
simulated time, so that the two runs take comparable step counts; the per-step time is what
carries over to a full run (its step count is duration / dt). Prints the machine's load
(os.getloadavg) before and after, as other jobs share the cores.

Run: NUMBA_NUM_THREADS=1 python benchmarks/plies.py [N ...]   (default N = 4 20)
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np

from elements import FibrousShell
from elements.plies import PlyStack
from femcore import Mesh, Model
from materials.presets import g986_stack
from solvers import CentralDifference

DURATION = 2e-3  # s of simulated time per run (a few hundred to a few thousand steps)
DAMPING = 200.0  # 1/s


def _load(model: Model, far) -> Model:
    model.fix(far("left"))
    model.displace(far("right"), ux=-30.0, uz=-50.0)
    model.gravity((0.0, 0.0, -9810.0))
    return model


def run(solver: CentralDifference, model: Model) -> tuple[float, int]:
    start = time.perf_counter()
    result = solver.solve(model)
    return time.perf_counter() - start, result.steps


def main(counts: list[int]) -> None:
    print(f"threads NUMBA_NUM_THREADS={os.environ.get('NUMBA_NUM_THREADS', 'default')}")
    print(f"load before (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")
    mid = Mesh.rectangle(150.0, 30.0, nx=30, ny=2)
    fabric = g986_stack()
    solver = CentralDifference(DURATION, damping=DAMPING, progress=False)
    model = _load(Model(mid), mid.nodes)
    model.add(FibrousShell(fabric, clamped="left"))
    run(solver, model)  # compile the kernels once
    wall, steps = run(solver, model)
    per_step = 1e3 * wall / steps
    print(f"fibrous shell      : {steps:6d} steps, {wall:8.2f} s, {per_step:8.3f} ms/step")
    for count in counts:
        stack = PlyStack(mid, fabric, count)
        model = _load(stack.model(), stack.nodes)
        wall, steps = run(solver, model)
        print(
            f"{count:2d} plies           : {steps:6d} steps, {wall:8.2f} s, "
            f"{1e3 * wall / steps:8.3f} ms/step"
        )
    print(f"load after  (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [4, 20])
