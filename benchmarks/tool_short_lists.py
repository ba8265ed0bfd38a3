"""The meshed tools' forces of the hemisphere-plies case's fibrous [0/90] run (or its Mindlin
run, ``--kinematics mindlin``) (8 cells, holder
20 N: the die and the holder, elements/rigid_surface.py, elements/tool_contact.py
``surface_forces``) with short lists of 4 and of 8 facets (elements/facet_search.py
``SHORT``), replayed side by side in one process: the run (this tree) goes to step
``--start`` and records every computed call of the two tools' forces (the nodes where each
tool sees them, the load factor) up to ``--stop``; the two contact blocks as they were at
``--start`` are then asked those calls again, one copy with each list length, alternating
round by round (fresh copies each round), the CPU of each setting's calls a step, best of
``--rounds``, one thread, the machine's load printed. The forces of the two settings must
be the same to the last bit (checked at every call), and the full scans of the listed
kernel are counted (from the tools' kept arrays before each call).

    NUMBA_NUM_THREADS=1 nice -n 5 python benchmarks/tool_short_lists.py

Why: benchmarks/ply_step.py ``--parts`` put "the tools' forces for the history rows" at
0.248 ms of the fibrous run's 1.6 ms step against 0.018 in the Mindlin run. It is not a
second evaluation: the fibrous run keeps a history row at every step (its ~4100 steps are
fewer than twice ENERGY_RECORDS, solvers/explicit.py: thin 1; the Mindlin run's 30000
steps keep one in 7), the row asks each tool's forces at the new state, and the next step's
forces are served from the contact's kept forces (elements/contact.py ``_kept_forces``:
counted over steps 1700-2500, 800 computed calls a tool in the rows, none in the steps;
the Mindlin run computes 6 of 7 in its steps). One evaluation a step in both runs; the
fibrous one costs about twice the Mindlin's (0.30 against 0.15 ms a step's three tools)
because its stroke is four times as fast (0.1 s against 0.4 s, STROKE_SLOWING) at a step
1.8 times as long: its nodes move about 7 times as far a step. The die's candidate lists
were searched again 53 times in those 800 steps (1652 nodes; Mindlin steps 3400-5000:
twice, 8 nodes), 80 us a step, and the listed kernel scanned whole candidate lists 15
times a step on the holder (80 candidates each: the nodes sliding over its vertices, where
six facets meet within micrometres of each other and a short list of four had one of them
for its bound) and 6 on the die, 70 us a step.

Measured (one thread, nice 5, best of 6, load 3.1-3.7; the forces identical at every call):

* fibrous [0/90] steps 1700-2500 (1600 calls): 145.0 -> 137.9 and 139.9 -> 134.6 us a step
  (0.951, 0.962), full scans 15929 -> 4701;
* Mindlin [0/90] steps 3400-5000 (3200 calls): 41.2 -> 41.8 us a step (1.014), full scans
  2220 -> 67.

A replay asks the tools alone, their facets kept in the caches between calls; in the run
the step's other work evicts them, and the listed kernel's own CPU (``--parts``-style
timers round it, fibrous steps 1700-2500, separate processes alternating, load 4.5-5.4)
went from 70.0 / 70.2 to 55.9 / 59.3 us a step (Mindlin steps 3400-5000: 26.3 / 26.6
against 26.5 / 25.4). The whole step against main 1a2a08b (benchmarks/ply_step.py
--reference, best of 4 / 2, load 3.6-5.4): fibrous steps 1700-2500 1.660 against 1.632 ms,
Mindlin steps 3400-5000 1.128 against 1.163 (both within the two processes' noise), the
states at steps 2500 and 5000 identical to the bit.
"""

from __future__ import annotations

import argparse
import os
import pickle
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages


def record(
    start: int, stop: int, kinematics: str = "fibrous"
) -> tuple[list[bytes], list[tuple[int, np.ndarray, float]]]:
    """Run the ``kinematics`` [0/90] run to step ``stop``: (the meshed tools' contact blocks
    pickled at step ``start``, the computed calls of their forces from there: (block's
    index, x (s, 3) mm, load factor))."""
    from elements import tool_contact
    from solvers import CentralDifference
    from solvers.common import SolverError
    from solvers.interrupts import STOP, interruptible
    from validation.studies import hemisphere_plies_setup as setup
    from validation.studies.hemisphere_plies_run import case_settings

    _, model = setup.model(8, setup.LAYUPS["0/90"], kinematics, 20.0)
    compiled = model.compile()
    blocks = [
        b
        for b in compiled.interactions
        if type(getattr(b, "tool", None)).__name__ == "RigidSurface"
    ]
    saved: list[bytes] = []
    calls: list[tuple[int, np.ndarray, float]] = []
    step = [0]
    forces = tool_contact.surface_forces

    def recorded(block, x, load_factor):
        if step[0] == start and not saved:
            saved.extend(pickle.dumps(b) for b in blocks)
        if start <= step[0] < stop:
            calls.append((blocks.index(block), x.copy(), load_factor))
        return forces(block, x, load_factor)

    tool_contact.surface_forces = recorded
    commit = type(compiled).commit

    def counted(state):
        step[0] += 1
        if step[0] == stop:
            STOP.signal = "SIGINT"
        return commit(compiled, state)

    compiled.commit = counted  # type: ignore[method-assign]
    with tempfile.TemporaryDirectory() as folder, interruptible():
        solver = CentralDifference(
            **case_settings("0/90", kinematics), history=Path(folder) / "history.csv"
        )
        try:
            solver.solve(compiled)
        except SolverError:
            pass
    tool_contact.surface_forces = forces
    return saved, calls


def replay(saved, calls, short: int) -> tuple[float, list[np.ndarray], int]:
    """(CPU s of the calls, their forces, the listed kernel's full scans) of fresh copies of
    the blocks ``saved`` with short lists of ``short`` facets, asked ``calls``."""
    from elements import facet_search, rigid_surface, tool_contact

    blocks = [pickle.loads(b) for b in saved]
    facet_search.SHORT = rigid_surface.SHORT = short  # the lists made from here on
    for block in blocks:
        block.tool._near = None  # made anew with ``short`` facets (rooms -1: a first scan)
    got, scans, spent = [], 0, 0.0
    for index, x, load_factor in calls:
        tool = blocks[index].tool
        if tool._near is not None and tool._kept is not None:
            local = x - tool.offset(load_factor)
            kept = (tool._kept[0] >= 0) & (
                np.linalg.norm(local - tool._kept[1], axis=1) < tool._kept[2]
            )
            listed = ~kept & (np.linalg.norm(local - tool._near[0], axis=1) < tool._near[1])
            has = np.diff(tool._cache.start) > 0 if tool._cache is not None else True
            scans += int(np.count_nonzero(~kept & ~listed & has))
        began = time.process_time()
        forces = tool_contact.surface_forces(blocks[index], x, load_factor)
        spent += time.process_time() - began
        got.append(forces)
    return spent, got, scans


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--start", type=int, default=1700, help="first step replayed")
    parser.add_argument("--stop", type=int, default=2500, help="step the replay ends at")
    parser.add_argument("--kinematics", default="fibrous", help="fibrous or mindlin plies")
    parser.add_argument("--rounds", type=int, default=6, help="rounds (best CPU)")
    args = parser.parse_args()
    print(f"load {os.getloadavg()}")
    saved, calls = record(args.start, args.stop, args.kinematics)
    steps = args.stop - args.start
    best = {4: np.inf, 8: np.inf}
    answers: dict[int, list[np.ndarray]] = {}
    scans = {}
    for _ in range(args.rounds):
        for short in best:
            spent, got, scans[short] = replay(saved, calls, short)
            best[short] = min(best[short], spent)
            answers.setdefault(short, got)
    same = all(np.array_equal(a, b) for a, b in zip(answers[4], answers[8]))
    for short in best:
        print(f"short lists of {short}: {best[short] / steps * 1e6:.1f} us a step, "
              f"{scans[short]} full scans ({len(calls)} calls, steps "
              f"{args.start}-{args.stop})")  # fmt: skip
    print(f"ratio 8 / 4 {best[8] / best[4]:.3f}; forces {'identical' if same else 'DIFFERENT'}")
    print(f"load {os.getloadavg()}")


if __name__ == "__main__":
    main()
