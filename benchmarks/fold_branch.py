"""What following the fibrous shell's folds through a flat fold costs an explicit step
(elements/fibrous/fold_branch.py; docs/theory.md §4.2, "The fold's branch"): the block's
history (each interior side's fold at the last accepted state, a pass over the cells'
normals and one over the sides after every accepted step) against the same run without it
(the block's ``initial_history`` None: no history, the principal branch), in one process,
the two alternating, best of ``--repeats``, CPU time. On the pinned sheet of shell_sheet.py
(G986 stack, gravity from rest) no side nears a flat fold: the two runs' positions are
compared to the bit.

Measured (one thread, 20k triangles, 200 steps, best of 3), the end positions the same to
the bit: a pass over every side after every step, 9.71 against 11.65 ms of CPU a step (1.20 x,
load 8); the watched sides alone between passes (fold_branch.py ``WATCHED``, ``REFRESH``),
9.81 against 10.75 ms (1.095 x, load 6.9), the update on the watched path 0.25 ms of the
shell's 8.0-ms force at 20k triangles; with the crossings looked for on the watched sides
alone (not a full-size jump and its tests each step), 9.15 against 9.41 ms (1.029 x, load 3.5;
the code before, run just before it, 1.082 x; 150 steps), 8.37 against 8.51 (1.017 x, load
1.7).

    python benchmarks/fold_branch.py [--triangles 20000] [--steps 200] [--repeats 3]
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import numpy as np  # noqa: E402
from shell_sheet import pinned_sheet  # noqa: E402

from elements import FibrousShell  # noqa: E402
from elements.fibrous.block import FibrousShellBlock  # noqa: E402
from materials import presets  # noqa: E402
from solvers import CentralDifference  # noqa: E402


def run(triangles: int, steps: int, followed: bool) -> tuple[float, np.ndarray]:
    """(CPU seconds per step, the end positions) of ``steps`` explicit steps on the sheet,
    with the folds followed or not."""
    model = pinned_sheet(FibrousShell(presets.g986_stack()), triangles)
    kept = FibrousShellBlock.initial_history
    if not followed:
        FibrousShellBlock.initial_history = lambda self: None  # type: ignore[method-assign]
    try:
        compiled = model.compile()
        dt = 0.9 * compiled.stable_dt(compiled.initial_state())
        solver = CentralDifference(duration=steps * dt, dt=dt, output_interval=steps * dt)
        started = time.process_time()
        result = solver.solve(compiled)
        cpu = time.process_time() - started
    finally:
        FibrousShellBlock.initial_history = kept  # type: ignore[method-assign]
    return cpu / result.steps, result.frames[-1].positions


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--triangles", type=int, default=20000)
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    run(200, 5, True), run(200, 5, False)  # the loops compiled or loaded, not timed
    best = {True: math.inf, False: math.inf}
    ends = {}
    for _ in range(args.repeats):
        for followed in (False, True):
            cpu, ends[followed] = run(args.triangles, args.steps, followed)
            best[followed] = min(best[followed], cpu)
    load = os.getloadavg()[0]
    print(
        f"{args.triangles} triangles, {args.steps} steps, best of {args.repeats}, load {load:.1f}"
    )
    print(f"  without the folds' history: {1e3 * best[False]:.3f} ms of CPU a step")
    ratio = best[True] / best[False]
    print(f"  with it:                    {1e3 * best[True]:.3f} ms ({ratio:.3f} x)")
    print(f"  end positions' largest difference: {np.abs(ends[True] - ends[False]).max():.3g} mm")


if __name__ == "__main__":
    main()
