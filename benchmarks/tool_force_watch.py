"""What the force-driven tools' watch (solvers/tool_force_watch.py) adds to an explicit step:
on the report's two-ply hemisphere (validation/studies/hemisphere_plies_setup.py, fibrous
[0/90], 8 cells, a meshed die, a punch, the force-driven ring holder on both plies), the CPU
of ``explicit_step`` with its ``commit`` and of the watch's ``observe`` between them, the same
steps in one loop (so load changes hit both alike), per step, best of ``--repeats`` passes of
``--steps`` steps; one numba thread.

    NUMBA_NUM_THREADS=1 python benchmarks/tool_force_watch.py --steps 300 --repeats 3

Measured (2 cores shared with five other jobs, 300 steps x 3): load 8-11, explicit_step and
commit 1.286 ms a step, observe 0.057 ms (4.4 % of it); load 2, 1.146 and 0.051 ms (4.5 %): the
tools' pushes 21 us (the contact's kept forces read back; 8.5 us asked again at once), the
prescribed loads 6 us (the holder's amplitude), the running sums the rest. The watch observes
the last half of a run only, and a whole run's step also writes its history and frames
(3.5-3.7 ms a step on this model: benchmarks/forming_step_overhead.py), so the run's cost is
about 1 % or less.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=300)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--cells", type=int, default=8)
    options = parser.parse_args()

    from solvers import CentralDifference
    from solvers.step import LumpedMasses, explicit_step
    from solvers.tool_force_watch import ToolForceWatch
    from validation.studies import hemisphere_plies_setup as setup

    _, model = setup.model(options.cells, setup.LAYUPS["0/90"], "fibrous", 20.0)
    compiled = model.compile()
    short = CentralDifference(duration=1e-4, progress=False, kinetic_bound=None)
    dt = short.solve(compiled).info["dt"]  # the stable step; compiles the kernels
    duration = 0.1
    masses = LumpedMasses.of(compiled, compiled.initial_state())
    watch = ToolForceWatch(compiled, duration)
    watch.start = 0.0  # observe every step
    best_step = best_watch = np.inf
    for _ in range(options.repeats):
        state, previous = compiled.initial_state(), 0.0
        stepping = watching = 0.0
        for _ in range(options.steps):
            begun = time.process_time()
            outcome = explicit_step(
                compiled, state, dt, masses, dt_prev=previous, duration=duration
            )
            between = time.process_time()
            watch.observe(compiled, state, dt)
            ended = time.process_time()
            committed = compiled.commit(outcome.state)
            stepping += between - begun + time.process_time() - ended
            watching += ended - between
            state, previous = committed, dt
        best_step = min(best_step, stepping / options.steps)
        best_watch = min(best_watch, watching / options.steps)
    print(
        f"{len(compiled.driven_tools)} driven tool node(s), {options.steps} steps x "
        f"{options.repeats}: explicit_step and commit {1e3 * best_step:.3f} ms a step, observe "
        f"{1e3 * best_watch:.4f} ms ({best_watch / best_step:.2%} of the step)"
    )


if __name__ == "__main__":
    main()
