"""Newton iterations per increment of the weight-carrying ply stacks, each with its case's own
solver: plies-bai-5.1's plies (validation/cases/plies_bai_5_1.py), plies-heavy-cantilever's
and plies-deck-of-cards' heavy stack of the fewest plies (``sag``), at a resolution; per case
the iterations of each converged increment, those of the attempts cut, the tangents
(``info["evaluations"]["tangent"]``) and the CPU time (``time.process_time``, one thread),
the machine's load printed with them. The table the remedies of docs/theory.md §6.5 and
§9.3a are measured against (benchmarks/static_plies_newton.py and
its siblings static_plies_*.py hold their figures).

    python benchmarks/ply_newton_table.py [--cases bai,heavy,sag] [--resolution coarse]
        [--heavy-plies [--tied] [--curved]]

Measured (one thread, CPU, the 2 cores shared, load 2.3-4.2), iterations per increment
(+ those of the attempts cut), tangents:

* coarse: bai 21-5-4-4-4-3-3-3-3-3 (gravity) and 82-19-18-18-18-8-11-10-8-12 (displacement),
  257 + 8, 271 tangents, 2.2-2.5 s; heavy 29-33-29-19-15, 125, 0.6-0.8 s; sag
  83-33-24-18-15-11, 184, 1.1-2.5 s (the CPU spread: the load, and the first solve of a
  process loading its kernels).
* default: bai 24-7-7-5-4-3-3-3-3-3 and 123-33-34-31-19-19-21-19-15-22, 398 + 0, 403
  tangents, 15-18 s; heavy 33-42-30-20-17, 142, 2.8 s; sag (its 4-ply stack, as coarse) 184.
* ``--heavy-plies --tied`` (coarse; without -> with the case's update cap, 0.03 rad):
  one ply of the N-ply stack's fabric alone, Static's defaults (curved steps, a chord, the
  fibre projection): N = 1 4-5-5-4-4, N = 2 4-5-7-6-4, N = 4 4-5-13-11-6; with the straight
  steps a stack gets (``STRAIGHT``: none of the three with an interaction) 17-11-15-18-11,
  15-11-14-19-8, 14-20-14-17-8 (+9 cut). The N plies with their contact's law zeroed (they
  pass through each other) take exactly their lone ply's straight iterations: 2 plies
  15-11-14-19-8 -> 13-28-24-18-14, 4 plies 14-20-14-17-8 (+9) -> 14-28-24-18-14 (98). With
  today's contact: 2 plies 33-67-80-33-11 -> 32-29-24-18-14, 4 plies 30-106-101-20-20 ->
  29-33-29-19-15 (125). Tied (W = k g^2 / 2 both sides, a smooth law without switching; the
  plies held at their gaps, so another equilibrium): 2 plies 14-35-33-18-18 -> 13-21-20-14-12,
  4 plies 12-38-24-23-10 (+16) -> 12-130-31-23-20. So on the case's solver 98 of the 4-ply
  stack's 125 iterations are its plies' straight steps, which a lone ply takes in 39 with
  Static's curved steps, chord and fibre projection; the contact adds 27, and a smooth law
  without switching does not take them away.
* ``--heavy-plies --tied --curved``, the 4 plies with ``curved_with_contact`` and no cap:
  contact zeroed 5-9-10-10-9 (43, near the lone ply's 39), today's 55-100-44-36-17 (+34
  cut), tied 9-37-9-21-7. The curved steps hold for the plies; the contact between plies
  that turn, even tied, is what they do not carry.

The remedies tried against this table: benchmarks/ply_simple_root.py (a law with a simple
root; today's law with a softer penalty, the inner solves of an augmented Lagrangian),
benchmarks/ply_curved_probe.py (the curved steps with the law held in their probes).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

from benchmarks.static_plies_case import solve_case  # noqa: E402

# The cases' own stall rule and first-turn limit (validation/cases/plies_bai_5_1.py
# PLIES_SOLVER; the others set neither).
CASE_RULES = {"bai": (25, 0.1), "heavy": (None, None), "sag": (None, None), "deck": (None, None)}


def table(names: list[str], resolution: str) -> dict:
    """Solve each case once; {name: (result, CPU s)}, each row printed as it comes."""
    rows = {}
    for name in names:
        stall, first_turn = CASE_RULES[name]
        cpu = time.process_time()
        result = solve_case(name, resolution, stall, first_turn)
        cpu = time.process_time() - cpu
        info = result.info
        print(
            f"{name:5s} {resolution}: per increment {info['iterations_per_increment']}, "
            f"{result.steps} converged + {info['iterations_cut']} cut, "
            f"{info['evaluations']['tangent']} tangents, {cpu:.1f} s CPU, "
            f"converged {result.converged}; "
            f"load {np.round(os.getloadavg(), 2).tolist()}",
            flush=True,
        )
        rows[name] = (result, cpu)
    return rows


# Static's steps for a lone shell (its defaults) and those a stack's contact leaves it
# (docs/theory.md §6.5: no curved steps, chords or fibre projection with interactions).
STRAIGHT = {"curved": False, "chords": 0, "fibre_projection": False}


def _heavy_row(resolution: str, count: int, lone: bool, options: dict, law, label: str) -> None:
    """Solve plies-heavy-cantilever's strip as ``count`` plies (``lone``: one ply of the
    ``count``-ply stack's fabric alone) with the case's solver updated by ``options`` (an
    ``update_turn`` of None: no cap) and the ply contact's law ``law`` (None: today's;
    benchmarks/ply_simple_root.py), and print its iterations per increment."""
    from benchmarks import ply_simple_root
    from elements.mindlin import MindlinShell
    from elements.plies import PlyStack
    from fibreshell.plies import _fibrous_part, plies_solver, ply_stack, stack_model
    from validation.cases import plies_heavy_cantilever as heavy
    from validation.ground_truth import _case

    assert heavy.PLIES_SOLVER is not None
    solver = {**heavy.PLIES_SOLVER, **options}
    if solver["update_turn"] is None:
        del solver["update_turn"]
    case = _case(heavy.FILE, heavy.CELLS[resolution], {"solver": solver})
    if lone:
        part = _fibrous_part(case)
        stack = PlyStack(
            case.mesh,
            part.fabric.plies(count),
            1,
            element=lambda ply: MindlinShell(ply, warp=part.warp),
        )
    else:
        stack = ply_stack(case, count)
    ply_simple_root.use(ply_simple_root.TODAY if law is None else law, None if law is None else 1.0)
    try:
        model = stack_model(case, stack).compile()
        cpu = time.process_time()
        result = plies_solver(case, progress=False).solve(model)
        cpu = time.process_time() - cpu
    finally:
        ply_simple_root.use(ply_simple_root.TODAY, None)
    print(
        f"heavy {resolution}, {label:46s} {options}: {result.info['iterations_per_increment']} "
        f"(+{result.info['iterations_cut']} cut), lowest z {result.positions[:, 2].min():.5f} "
        f"mm, {cpu:.1f} s CPU; load {np.round(os.getloadavg(), 2).tolist()}",
        flush=True,
    )


def heavy_plies(
    resolution: str,
    tied: bool = False,
    with_curved: bool = False,
    counts: tuple[int, ...] = (1, 2, 4),
) -> None:
    """Where plies-heavy-cantilever's iterations go: its strip as one ply of the N-ply stack's
    fabric alone, with Static's defaults and with the straight steps a stack gets
    (``STRAIGHT``), and as the N plies with their contact's law zeroed (``free_law``: the
    plies pass through each other), today's and (``tied``) tied (``tied_law``), each without
    and with the case's update cap, and (``with_curved``) with the curved steps without the
    cap."""
    from benchmarks import ply_simple_root

    cap = {"update_turn": 0.03}
    none = {"update_turn": None}
    for count in counts:
        _heavy_row(resolution, count, True, none, None, f"one ply of {count}, Static's defaults")
        _heavy_row(resolution, count, True, {**none, **STRAIGHT}, None, f"one ply of {count}")
        if count == 1:
            continue
        laws = [("free", ply_simple_root.free_law), ("today", None)]
        if tied:
            laws.append(("tied", ply_simple_root.tied_law))
        curved = {**none, "curved_with_contact": True}
        for name, law in laws:
            for options in (none, cap, curved) if with_curved else (none, cap):
                _heavy_row(resolution, count, False, options, law, f"{count} plies, contact {name}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", default="bai,heavy,sag")
    parser.add_argument("--resolution", default="coarse")
    parser.add_argument(
        "--heavy-plies", action="store_true", help="the heavy stack as 1, 2, 4 plies instead"
    )
    parser.add_argument("--tied", action="store_true", help="with --heavy-plies: tied too")
    parser.add_argument(
        "--curved", action="store_true", help="with --heavy-plies: the curved steps too"
    )
    args = parser.parse_args()
    print(f"load before (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")
    if args.heavy_plies:
        heavy_plies(args.resolution, args.tied, args.curved)
        return
    table(args.cases.split(","), args.resolution)


if __name__ == "__main__":
    main()
