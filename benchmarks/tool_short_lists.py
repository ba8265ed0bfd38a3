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

Measured, "8" the lists of up to 8 (at least SHORT_LEAST = 4, lengthened where that takes
the room past half of 8's), "4" the lists of 4 before; one thread, nice 5, best of 6-8,
the forces identical at every call (us a step of the tools' calls, ratio 8 / 4, full scans):

* two-ply fibrous [0/90] steps 1700-2500 (1600 calls), load 5.4-5.9: 146.0 -> 141.8
  (0.972), scans 15933 -> 6635 (lists of 8 everywhere: 0.951, 0.962, 0.911 at load 2.7-3.7,
  scans 4701);
* two-ply Mindlin [0/90] steps 3400-5000 (3200 calls), load 4.3-5.4: 42.9 -> 43.7
  (1.019), scans 2220 -> 82 (lists of 8 everywhere: 1.014, 1.077);
* one-ply hemisphere-forming (``--forming``, the die, 20 cells) fibrous calls 5000-7000,
  load 5.8-6.2: 111.9 -> 119.9 (1.072) and 110.7 -> 105.0 (0.948), scans 16976 -> 4057
  (lists of 8 everywhere: 0.973); Mindlin calls 20000-24000, load 5.9: 69.8 -> 68.1
  (0.976), scans 17665 -> 3542 (lists of 8 everywhere: 1.016, 1.026).

A replay asks the tools alone, their facets warm in the caches between calls. In the run
(timers round the listed kernel, separate processes alternating, load 4.5-5.4), lists of 8
everywhere took the fibrous [0/90] kernel from 70.0 / 70.2 to 55.9 / 59.3 us a step
(Mindlin 26.3 / 26.6 against 26.5 / 25.4). The whole step against main 1a2a08b
(benchmarks/ply_step.py --reference): fibrous steps 1700-2500 1.894 against 1.946 ms (best
of 2, load 5.8-5.9; lists of 8 everywhere 1.660 against 1.632, load 3.6-5.4), Mindlin
steps 3400-5000 1.227 against 1.155 (one round, load 5.1-5.4) and 1.097 against 1.131
(best of 2, load 4.3-4.8; lists of 8 everywhere 1.128 against 1.163), 30-70 us a step
either way where the tools' calls themselves differ by about 1: the two processes' noise at
that load; the states at steps 2500 and 5000 identical to the bit; the hemisphere-plies
case (``python -m validation --cases hemisphere-plies --jobs 1`` from each tree, one after
the other, load 4-6) every number of results.json the same but the times, its three PNGs
byte for byte (77.1 s of CPU against main's 83.4, not alternated: no claim). A gain of a
few microseconds a step where the stroke is fast, none to speak of where it is slow: the
tools' forces of the fibrous run cost what they cost because its nodes move that far a
step, not because they are asked twice.
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


def record_forming(
    first: int, count: int, kinematics: str
) -> tuple[list[bytes], list[tuple[int, np.ndarray, float]]]:
    """``record`` for the one-ply hemisphere-forming case's ``kinematics`` run at 20 cells
    (validation/cases/hemisphere_forming.py ``run``, its default time scaling): the die's
    contact block pickled at its ``first`` computed call, and ``count`` calls from there."""
    import warnings

    from elements import tool_contact
    from validation.cases import hemisphere_forming as forming
    from validation.forming_scaling import TIME_SCALING

    warnings.simplefilter("ignore")
    blocks: list = []
    saved: list[bytes] = []
    calls: list[tuple[int, np.ndarray, float]] = []
    seen = [0]
    forces = tool_contact.surface_forces

    def recorded(block, x, load_factor):
        if not any(block is b for b in blocks):
            blocks.append(block)
        if seen[0] == first:
            saved.extend(pickle.dumps(b) for b in blocks)
        if first <= seen[0] < first + count:
            index = next(i for i, b in enumerate(blocks) if b is block)
            calls.append((index, x.copy(), load_factor))
        seen[0] += 1
        return forces(block, x, load_factor)

    tool_contact.surface_forces = recorded
    try:
        forming.run(20, kinematics, time_scaling=TIME_SCALING[kinematics]["default"])
    finally:
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
    parser.add_argument("--forming", action="store_true", help="the one-ply forming case's die")
    parser.add_argument("--lengths", default="4,8", help="the list lengths compared")
    parser.add_argument("--rounds", type=int, default=6, help="rounds (best CPU)")
    args = parser.parse_args()
    print(f"load {os.getloadavg()}")
    if args.forming:  # --start / --stop: the die's computed calls
        saved, calls = record_forming(args.start, args.stop - args.start, args.kinematics)
    else:
        saved, calls = record(args.start, args.stop, args.kinematics)
    steps = args.stop - args.start
    best = {int(length): np.inf for length in args.lengths.split(",")}
    answers: dict[int, list[np.ndarray]] = {}
    scans = {}
    for _ in range(args.rounds):
        for short in best:
            spent, got, scans[short] = replay(saved, calls, short)
            best[short] = min(best[short], spent)
            answers.setdefault(short, got)
    first, *others = best
    same = all(
        np.array_equal(a, b) for other in others for a, b in zip(answers[first], answers[other])
    )
    for short in best:
        print(f"short lists of {short}: {best[short] / steps * 1e6:.1f} us a step, "
              f"{scans[short]} full scans ({len(calls)} calls, steps "
              f"{args.start}-{args.stop})")  # fmt: skip
    ratios = ", ".join(f"{other} / {first} {best[other] / best[first]:.3f}" for other in others)
    print(f"{ratios}; forces {'identical' if same else 'DIFFERENT'}")
    print(f"load {os.getloadavg()}")


if __name__ == "__main__":
    main()
