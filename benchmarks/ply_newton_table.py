"""Newton iterations per increment of the weight-carrying ply stacks, each with its case's own
solver: plies-bai-5.1's plies (validation/cases/plies_bai_5_1.py), plies-heavy-cantilever's
and plies-deck-of-cards' heavy stack of the fewest plies (``sag``), at a resolution; per case
the iterations of each converged increment, those of the attempts cut, the tangents
(``info["evaluations"]``) and the CPU time (``time.process_time``, one thread), the machine's
load printed with them. The table the remedies of docs/theory.md §6.5 and §9.3a are measured
against (benchmarks/static_plies_newton.py holds their figures).

    python benchmarks/ply_newton_table.py [--cases bai,heavy,sag] [--resolution coarse]
        [--heavy-plies]

Measured (one thread, CPU, the 2 cores shared, load 2.3-4.2), iterations per increment
(+ those of the attempts cut), tangents:

* coarse: bai 21-5-4-4-4-3-3-3-3-3 (gravity) and 82-19-18-18-18-8-11-10-8-12 (displacement),
  257 + 8, 271 tangents, 2.2-2.5 s; heavy 29-33-29-19-15, 125, 0.6-0.8 s; sag
  83-33-24-18-15-11, 184, 1.1-2.5 s (the first figure of each: a cold start in its process).
* default: bai 24-7-7-5-4-3-3-3-3-3 and 123-33-34-31-19-19-21-19-15-22, 398 + 0, 403
  tangents, 15-18 s; heavy 33-42-30-20-17, 142, 2.8 s; sag (its 4-ply stack, as coarse) 184.
* ``--heavy-plies`` (coarse): 1 ply (no contact) 10-82-60-42-32 with the case's update cap
  (0.03 rad) and 4-5-5-4-4 without it; 2 plies 32-29-24-18-14 and 33-67-80-33-11; 4 plies
  29-33-29-19-15 and 30-106-101-20-20. The strip alone meets 3-6 iterations an increment
  with straight updates; the contact between its turning plies is what takes it away (after
  the first increment 3-5 of the 60 points touch, and each increment alternates a step the
  cap shortens, its straight update pressing the plies into each other, with a whole step:
  ``benchmarks/static_plies_newton.py --case heavy --detail``).

The remedies tried against this table: benchmarks/ply_simple_root.py (a law with a simple
root; today's law with a softer penalty, the inner solves of an augmented Lagrangian).
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

from benchmarks.static_plies_newton import solve_case  # noqa: E402

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


def heavy_plies(resolution: str, counts: tuple[int, ...] = (1, 2, 4)) -> None:
    """plies-heavy-cantilever's stack as 1, 2 and 4 plies (one ply: no contact), each with
    the case's solver and without its update cap (``update_turn``): per increment, the
    iterations and the deepest point's z, mm."""
    from fibreshell.plies import plies_solver, ply_stack, stack_model
    from validation.cases import plies_heavy_cantilever as heavy
    from validation.ground_truth import _case

    assert heavy.PLIES_SOLVER is not None
    for count in counts:
        for cap in (heavy.PLIES_SOLVER["update_turn"], None):
            solver = {**heavy.PLIES_SOLVER, "update_turn": cap}
            if cap is None:
                del solver["update_turn"]
            case = _case(heavy.FILE, heavy.CELLS[resolution], {"solver": solver})
            model = stack_model(case, ply_stack(case, count)).compile()
            cpu = time.process_time()
            result = plies_solver(case, progress=False).solve(model)
            cpu = time.process_time() - cpu
            print(
                f"heavy {resolution}, {count} plies, update_turn={cap}: per increment "
                f"{result.info['iterations_per_increment']} (+{result.info['iterations_cut']} "
                f"cut), lowest z {result.positions[:, 2].min():.6f} mm, {cpu:.1f} s CPU; load "
                f"{np.round(os.getloadavg(), 2).tolist()}",
                flush=True,
            )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", default="bai,heavy,sag")
    parser.add_argument("--resolution", default="coarse")
    parser.add_argument(
        "--heavy-plies", action="store_true", help="the heavy stack as 1, 2, 4 plies instead"
    )
    args = parser.parse_args()
    print(f"load before (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")
    if args.heavy_plies:
        heavy_plies(args.resolution)
        return
    table(args.cases.split(","), args.resolution)


if __name__ == "__main__":
    main()
