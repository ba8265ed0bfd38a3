"""The whole facing's fans made once a vertex (elements/ply_edge_kernels.py ``_parts_once``,
which elements/ply_facing_whole.py ``_choice`` runs) against ``_parts`` (each point's
vertex's fan made again at that point), side by side in one process, on the inputs of the
hemisphere-plies case's run (Mindlin [0/90] by default, 8 cells): the run goes to step
``--stop``, every ``--every``-th call of the facing's front call (elements/ply_facing_front.py
``_front_chosen``, both passes) kept, then each kept call's fans made both ways, best of
``--repeats`` a call, CPU (``time.process_time``, one thread), the arrays compared to the bit.
The whole front call is timed too (its kernel, as the run makes it now).

    NUMBA_NUM_THREADS=1 python benchmarks/ply_fan_parts.py

Measured (one thread, 2 cores shared with other jobs), us a call, the same bits each time:

* ``--stop 4000 --every 10`` (load 5.6; 200 calls of each pass with the choice made): the
  lower ply's nodes' pass (81 points, 44 at a vertex) 6.31 -> 3.84, the upper ply's points'
  pass (384 points, 207 at a vertex) 23.19 -> 8.03; the whole front call as it runs now
  47.8 and 67.7: some 17.6 us saved a step (two passes) of the Mindlin run's ~1.1 ms;
* the run's front-call inputs of steps 0-8000, every 20th call (load 9-11, a first form of
  this script): 6.66 -> 3.22 and 26.10 -> 9.12 (some 290 of 384 points at some 76 vertices).

The hemisphere-plies case (``python -m validation --cases hemisphere-plies --jobs 1``, the
tree before and after, load 5-11): results.json the same in 471 of its 491 entries, the 20
others its times and stamp; the Mindlin [0/90] run's CPU 52.5 -> 52.3 s, within that load's
spread (the saving is some 2 % of its step): no case-level figure is claimed.
"""

from __future__ import annotations

import argparse
import collections
import copy
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(HERE))  # run from anywhere, no install

import numpy as np  # noqa: E402


def _kept_calls(kinematics: str, stop: int, every: int) -> list[tuple]:
    """Copies of the front call's arguments, every ``every``-th call of each pass, run to
    step ``stop``."""
    from benchmarks.ply_chain_parts import states_of
    from elements import ply_facing_front

    kept: collections.deque = collections.deque(maxlen=400)
    front = ply_facing_front._front_chosen
    count = [0]

    def recorded(*args):
        count[0] += 1
        if count[0] % every in (0, 1):
            kept.append(copy.deepcopy(args))
        return front(*args)

    ply_facing_front._front_chosen = recorded
    try:
        states_of(kinematics, "0/90", stop, 1)
    finally:
        ply_facing_front._front_chosen = front
    return list(kept)


def _best(kernel, arguments: tuple, repeats: int) -> float:
    """The least CPU of ``repeats`` calls of ``kernel(*arguments)``, s."""
    best = np.inf
    for _ in range(repeats):
        began = time.process_time()
        kernel(*arguments)
        best = min(best, time.process_time() - began)
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--kinematics", default="mindlin", choices=("fibrous", "mindlin"))
    parser.add_argument("--stop", type=int, default=8000, help="the run's last step")
    parser.add_argument("--every", type=int, default=20, help="keep every n-th call")
    parser.add_argument("--repeats", type=int, default=30, help="calls a kept call (best)")
    args = parser.parse_args()
    from elements import ply_edge_kernels, ply_facing_front
    from femcore.jit import plain_part

    each = plain_part(ply_edge_kernels._parts_compiled)
    once = ply_edge_kernels._parts_once
    calls = _kept_calls(args.kinematics, args.stop, args.every)
    for points in sorted({len(a[9]) for a in calls}):
        taken = [a for a in calls if len(a[9]) == points]
        spent = {"each": 0.0, "once": 0.0, "front": 0.0}
        same = True
        at_vertex = []
        for a in taken:
            if not ply_facing_front._front_chosen(*a)[2]:  # the choice's arrays of this state
                continue  # the lists did not serve: no choice made, its outputs unwritten
            given = (a[35], a[40], a[23], a[32], a[33], a[44], a[36], a[45], a[27])
            made = {k: [np.full_like(a[i], np.nan) for i in (49, 50, 51)]
                    for k in ("each", "once")}  # fmt: skip
            parts = (np.int64(0), np.int64(1))  # the whole loop, as the plain build runs it
            spent["each"] += _best(each, (*given, *made["each"], *parts), args.repeats)
            spent["once"] += _best(once, (*given, *made["once"]), args.repeats)
            spent["front"] += _best(ply_facing_front._front_chosen, a, args.repeats)
            same &= all(u.tobytes() == v.tobytes() for u, v in zip(made["each"], made["once"]))
            at_vertex.append(int(np.any(made["once"][1] != 0.0, axis=1).sum()))
        scale = 1e6 / max(len(at_vertex), 1)
        print(
            f"{points} points, {len(at_vertex)} calls with the choice made, "
            f"{np.mean(at_vertex):.0f} points at a vertex: fans "
            f"each point {spent['each'] * scale:.2f} -> once a vertex "
            f"{spent['once'] * scale:.2f} us a call (the same bits: {same}); the front call "
            f"as it runs now {spent['front'] * scale:.2f} us"
        )
    print(f"load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
