"""Where the ply contact's per-step chain spends its CPU, part by part, on a run's states:
the two-ply hemisphere of the report's hemisphere-plies case (fibrous [0/90] by default, 8
cells), run to step ``--start``, then ``--steps`` committed states replayed through both ply
contact blocks as a step asks for them (``update_history``, then ``internal_force``; as
benchmarks/ply_contact_replay.py, which compares two trees), with a CPU timer
(``time.process_time``) round each part: the wrappers (inclusive: their compiled calls and
the numpy between) and, with ``--kernels``, the compiled kernels' own calls (numba's
dispatch included). A part's wrapper less its kernels is the Python round them. The timers
cost about 0.3 us each; best of ``--repeats`` rounds, one numba thread.

    python benchmarks/ply_chain_parts.py --kernels

Measured (main d551120's chain, one thread, 2 cores shared, load 12.5), us a block-step, the
committed history 397 and the loads 108 (without the timers 392 and 104):

* the facing at the new state (``PlyContactBlock.facing``, once a block and step) ~295: the
  search's candidates 88 (``FacingSearch.near`` 60, the faces 11), ``closest_facing`` 185:
  ``candidates_at`` 24 (its kernel 18), ``choose_facing`` 31 (21), ``chosen`` 12 (6),
  ``edge_sides`` 33 (two kernels 10), ``outline_fade_at`` 47 (27), the rest of
  ``closest_facing`` 38 (the arrays between: copies, gathers, the Facing);
* the friction's history (``ply_friction_kernels.updated_history``) 76: ``_moved`` 9, the
  return mapping of the next loads 17 (its kernel 8);
* the loads (``ply_load_kernels.ply_loads``) 67: the pass 22, the stuck points' edge
  couples 11 (24 us a call on 46 % of the calls), numpy's ramp cubes 8.

The kernels' own calls are about 140 of the ~445 us a block-step (the search's lists aside);
the rest is Python between some twenty compiled calls a block and step: each wrapper's
allocations and conversions cost a few microseconds, the chain's some two hundred numpy
calls the rest. No single wrapper holds more than ~20 us of it: what is left to win is the
chain itself in one compiled pass per block and state (the facing's five passes, then the
mapping and the loads), not cuts of single calls.

The loads' edge couples computed for the stuck points facing an edge alone (not for every
stuck or sliding row, then gathered and scattered again): 24 -> 13 us a call (load 12.5
before, 7.8 after); ``python benchmarks/ply_contact_replay.py --steps 300 --reference`` beside
main d551120 (load 6-7, best of 3): the committed history 353.0 -> 340.3 us, the loads 91.8
-> 88.7 us a block-step, the same digest e7a6191daa154cf1 (the same histories, forces and
moments to the bit).

The facing's planes, choice and chosen arrays in one compiled call (elements/
ply_facing_pass.py ``facing_choice``, its outputs made in Python and passed in), beside main
bb171b8 (``git archive``, its own copy of this script run from its root), two rounds, best of
5, one thread, load 4.6-4.9, us a block-step: the three wrappers 69.4 / 67.2 (their kernels
47.3 / 46.1) -> ``facing_choice`` 46.1 / 46.6 (its kernel 36.6 / 36.8); ``closest_facing``
189.7 / 184.8 -> 160.3 / 162.1; the committed history 398.0 / 392.6 -> 365.8 / 367.4, the
loads 103.7 / 102.6 -> 102.1 / 102.4 (the chain 501.7 / 495.2 -> 467.9 / 469.8, 5-7 % less).
The kernel's 15 outputs made inside it and returned cost numba's boxing, about a microsecond
each: 47.0 us a block-step for the kernel alone, no faster than the three. numpy's arctan2
in ``edge_sides`` at the rows on an edge alone (with their gathers) took 35.0 / 35.1 us a
call against 33.1 / 32.3 at every row: not kept. ``python benchmarks/ply_contact_replay.py
--steps 300 --reference`` beside bb171b8: the same digest e7a6191daa154cf1.

The whole facing without the gap's Hessian in two compiled calls (elements/
ply_facing_whole.py: the planes, choice, chosen arrays, the edges' coordinates and fans and
the planes' copies; numpy's arctan2; the sides, the outline's edges and the fade), and the
friction's history in one (elements/ply_friction_pass.py: the mapping from the last history,
the moved anchors, the next loads' mapping). On the fibrous [0/90] replay's bent state (one
thread, load 3, best of 300 calls, us a call, 384 / 81 points): the facing 85 / 65, its two
kernels 25 + 24 / 21 + 11. ``python benchmarks/ply_contact_replay.py --steps 300
--reference`` beside main debd499 (``git archive``), two rounds, best of 3, one thread, load
3.3-3.9, us a block-step: the committed history fibrous [0/90] 312.6 / 320.2 -> 264.4 /
264.8, Mindlin [0/90] 267.5 / 270.0 -> 218.8 / 221.8; the loads unchanged (85.8 / 85.9 ->
88.1 / 86.3, 77.4 / 79.4 -> 78.4 / 79.7); the same digests (e7a6191daa154cf1,
37effb0f57aad048). The case (``python -m validation --cases hemisphere-plies --jobs 1``, one
numba thread, warm caches, debd499 and this tree back to back, three rounds, load 2.6-3.8):
case_cpu_s 43.89 / 44.96 / 44.47 -> 42.09 / 41.26 / 40.87 s, the four runs' CPU 40.23 /
41.39 / 40.80 -> 37.97 / 37.63 / 37.33 s (fibrous [0/90] 6.55-6.79 -> 6.04-6.31, [0/45]
8.20-8.66 -> 7.62-7.99, Mindlin [0/90] 12.14-12.74 -> 11.23-11.38, [0/45] 13.20-13.34 ->
12.10-12.67); results.json the same in every number but the times (313 of 324), 24 of 24
checks, 26376 steps. What is left of the facing is still Python round the calls (about 35 us a
facing: the 86 arguments' dispatch, some 25 arrays made for the outputs, the search's lists,
the Facing) and the kernels' own loops (the fade's about 17 us a call at 90 points near the
outline). The nearest outline edge by columns (the starts' and edges' coordinates a row
each, the distances in a loop LLVM runs several at a time, then numpy's argmin rule): the
second call at 384 points 23.9-24.0 us against 24.8-25.5 before (best of 300, one thread):
not worth its code, not kept.
"""

from __future__ import annotations

import argparse
import collections
import functools
import os
import pickle
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(HERE))  # run from anywhere, no install


def states_of(kinematics: str, layup: str, start: int, steps: int):
    """(the ply blocks pickled at step ``start``, their rows in the model's parts, the
    ``steps`` committed states from there)."""
    import femcore.compiled as compiled_model
    from elements.ply_block import PlyContactBlock
    from validation.studies import hemisphere_plies_setup as setup
    from validation.studies.hemisphere_plies_run import case_solver

    _, model = setup.model(8, setup.LAYUPS[layup], kinematics, 20.0)
    compiled = model.compile()
    blocks = [i for i, part in enumerate(compiled.parts) if isinstance(part, PlyContactBlock)]
    saved: list[bytes] = []
    states: list = []
    commit = compiled_model.CompiledModel.commit

    class Done(Exception):
        pass

    def capture(self, state):
        if len(saved) == 0 and capture.count == start:
            saved.append(pickle.dumps([self.parts[b] for b in blocks]))
        capture.count += 1
        if saved:
            states.append(state)
        if len(states) == steps:
            raise Done
        return commit(self, state)

    capture.count = 0
    compiled_model.CompiledModel.commit = capture
    solver = case_solver(layup, kinematics, output_interval=None)
    try:
        solver.solve(compiled)
    except Done:
        pass
    finally:
        compiled_model.CompiledModel.commit = commit
    return saved[0], blocks, states


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--kinematics", default="fibrous", choices=("fibrous", "mindlin"))
    parser.add_argument("--layup", default="0/90", choices=("0/90", "0/45"))
    parser.add_argument("--start", type=int, default=2000, help="the first replayed step")
    parser.add_argument("--steps", type=int, default=300, help="consecutive steps replayed")
    parser.add_argument("--repeats", type=int, default=3, help="rounds (best CPU)")
    parser.add_argument("--kernels", action="store_true", help="time the kernels' calls too")
    args = parser.parse_args()
    from elements import (
        ply_block,
        ply_choice,
        ply_chosen,
        ply_edge_couple_kernels,
        ply_edge_kernels,
        ply_face_points,
        ply_facing_pass,
        ply_facing_whole,
        ply_fade_kernels,
        ply_friction_kernels,
        ply_friction_pass,
        ply_kernels,
        ply_load_kernels,
        ply_penalty,
        ply_search,
        ply_sides,
    )
    from elements.ply_block import PlyContactBlock

    saved, blocks, states = states_of(args.kinematics, args.layup, args.start, args.steps)
    spent: dict[str, float] = collections.defaultdict(float)
    calls: collections.Counter[str] = collections.Counter()

    def timed(owner, name: str) -> None:
        function = getattr(owner, name)
        label = f"{getattr(owner, '__name__', owner)}.{name}"

        @functools.wraps(function)
        def wrapper(*arguments, **keywords):
            began = time.process_time()
            try:
                return function(*arguments, **keywords)
            finally:
                spent[label] += time.process_time() - began
                calls[label] += 1

        setattr(owner, name, wrapper)

    parts = [
        (PlyContactBlock, ["update_history", "internal_force", "facing", "_faces",
                           "_candidates", "friction_state", "offset_directions"]),
        (ply_block, ["closest_facing"]),
        (ply_search.FacingSearch, ["near"]),
        (ply_kernels, ["candidates_at"]),
        (ply_choice, ["choose_facing"]),
        (ply_chosen, ["chosen"]),
        (ply_edge_kernels, ["edge_sides"]),
        (ply_fade_kernels, ["outline_fade_at"]),
        (ply_sides, ["accepted_sides", "behind"]),
        (ply_friction_kernels, ["updated_history", "_mapped"]),
        (ply_load_kernels, ["ply_loads"]),
        (ply_edge_couple_kernels, ["edge_couples"]),
        (ply_penalty, ["ramp_cubes"]),
        (ply_face_points, ["face_points", "offset_toward"]),
        (ply_facing_pass, ["facing_choice"]),
        (ply_facing_whole, ["whole_facing"]),
        (ply_friction_pass, ["history_pass"]),
    ]  # fmt: skip
    if args.kernels:
        parts += [
            (ply_kernels, ["_facets_at_compiled"]),
            (ply_choice, ["_choose_compiled"]),
            (ply_chosen, ["_chosen_compiled"]),
            (ply_edge_kernels, ["_parts_compiled", "_sides_compiled"]),
            (ply_fade_kernels, ["_outline_compiled"]),
            (ply_friction_kernels, ["_return_mapping_compiled", "_moved_compiled"]),
            (ply_load_kernels, ["_loads"]),
            (ply_facing_pass, ["_facing_compiled"]),
            (ply_facing_whole, ["_choice_compiled", "_sides_fade_compiled"]),
            (ply_friction_pass, ["_history_compiled"]),
        ]
    for owner, names in parts:
        for name in names:
            timed(owner, name)

    def replay() -> list[float]:
        replayed = pickle.loads(saved)
        total = [0.0, 0.0]
        for state in states:
            for part, b in zip(replayed, blocks):
                history = state.history[b]
                began = time.process_time()
                part.update_history(state, history)
                middle = time.process_time()
                part.internal_force(state, history)
                total[0] += middle - began
                total[1] += time.process_time() - middle
        return total

    replay()  # compiled or read from numba's cache
    best = [float("inf")] * 2
    kept: tuple[dict, collections.Counter] = ({}, collections.Counter())
    for _ in range(args.repeats):
        spent.clear()
        calls.clear()
        total = replay()
        if total[0] + total[1] < best[0] + best[1]:
            best = total
            kept = (dict(spent), collections.Counter(calls))
    count = len(states) * len(blocks)
    print(f"{args.kinematics} [{args.layup}] steps {args.start}-{args.start + len(states)}: "
          f"committed history {best[0] / count * 1e6:.1f} us, loads {best[1] / count * 1e6:.1f} "
          f"us a block-step with the timers (best of {args.repeats}; load "
          f"{os.getloadavg()[0]:.1f})")  # fmt: skip
    for label, seconds in sorted(kept[0].items(), key=lambda item: -item[1]):
        each = seconds / kept[1][label] * 1e6
        print(f"  {label:52s} {seconds / count * 1e6:7.1f} us a block-step, "
              f"{kept[1][label] / count:5.2f} calls, {each:7.1f} us a call")  # fmt: skip


if __name__ == "__main__":
    main()
