"""The Static ply cases' cost: the ply contact's facing made once per Newton iteration (the
loads' facing carries the gap's Hessian for the tangent that follows at its state:
elements/ply_block.py ``PlyContactBlock.facing``, ``HESSIAN_WITH_LOADS``) against the
tangent making its own facing again (the reference pass, as before), on the stack of the
report's plies-bai-5.1 at coarse (validation/cases/plies_bai_5_1.py: the G986 strip of
cases/bai-5.1.toml, 12 cells, 4 Mindlin plies in frictionless contact, 10 increments per
phase): each solved in this process, CPU (``time.process_time``), one thread; the Newton
iterations and the final positions and directors compared to the bit; the machine's load.

    python benchmarks/static_plies.py [--solves 2]

Where the time goes: plies-bai-5.1 at the default resolution (30 cells, 8 plies; cProfile
with CPU time of one process, one thread, load 8-11; the fibrous and Mindlin runs compiled a
cold numba cache, 456 s of the 594 s profiled, left aside here). Newton's iterations of the
three runs (899 of them, most the plies'; 50 increments solved, cut attempts included): the
tangents 59 s (their assembly into K_ff 22 s, the parts 44 s: the ply contact's tangent 40 s
of which its facing made again with the gap's Hessian 32 s, the contact's own Hessian
products 8 s, of them the carry to the nodes' einsums 4 s; the Mindlin plies' tangents,
the fabric section's response 61 s over every call of the three runs), the watchdog line
search 47 s (845 trial force passes 33 s, 512 energies 9 s, 54 backtracks 4.7 s), the
factorisations 15 s, the solves 3 s. The ply contact's facing 64 s in all, 17185 calls: a
Newton iteration made it twice at one state, for the loads (without the Hessian) and again
for the tangent (with it), the only difference between the two being the Hessian of the
points that face an edge or a vertex. That second facing is what was cut. Where those Newton
iterations go increment by increment, and the stalled attempts cut since:
benchmarks/static_plies_newton.py.

Measured (one thread, CPU, 2 cores shared with other jobs):

* this script, load 13.9 -> 16.9: the coarse plies solve 19.9 s (the tangent's own facing,
  run first) -> 17.8 s (the loads' facing with the Hessian), the same 358 Newton iterations
  (611 in cut attempts; 470 since the structured carry tried below was taken out), the final
  positions and directors the same to the bit (both with that carry).
* the report's cases, case_cpu_s of ``python -m validation --cases ... --jobs 1`` (one numba
  thread), s: main's code (c0b0822, a ``git archive``) at the default resolution,
  plies-bai-5.1 80.3, plies-deck-of-cards 51.5, bai-5.1 21.2 (load 10-16); at coarse 21.8,
  13.2, 12.3 (load 10-12). This code (the facing's reuse alone) and main's again, side by
  side at the default resolution (load 15 -> 5): plies-bai-5.1 80.4 -> 75.7 s,
  plies-deck-of-cards 45.7 -> 43.9 s; results.json the same in every number but the times,
  and the three .vtu files of plies-bai-5.1 the same byte for byte (the facing's reuse gives
  the same forces, energies and tangent to the bit: tests/test_ply_facing_reuse.py). With
  the structured carry tried below as well: plies-bai-5.1 72.2 s beside main's code with the
  carry alone at 84.0 s (load 10-17), plies-deck-of-cards 46.4 s (2040 Newton iterations for
  main's 1977: the carry's round-off).

Tried and taken out: the contact's Hessian over z carried to the nodes by its structure
(A^T H A gathered by broadcasting, the rotations as 3 x 3 products) where one einsum over
the whole sparse map multiplies its zeros: 2-3 x faster on random blocks (2000 points 40 ->
18 ms; the fade's 300 points 11 -> 3.5 ms), the three contact blocks' tangents at the
coarse plies-bai-5.1 end state (34 touching rows) 2.01 -> 1.35 ms, about 4 of the 144 s of
the profiled default plies run; but its sums in another order moved every number of the ply
cases' results.json by round-off (1e-11 relative; the deck's small tilts 1e-10) and the
coarse plies-deck-of-cards took 916 Newton iterations for 890 (its linear convergence near
separation follows the round-off): not worth it.

bai-5.1's coarse cost above its default's (EXPECTED_CPU_S had 37.7 / 19.0 s): a cold numba
cache, not the case. Measured with a warm cache on main's code: coarse 13.0 s alone (load
9-10) and 12.3 s beside another report (load 10-12), default 19.5 and 21.2 s: the coarse
case solves 6-, 8- and 12-cell meshes for its orders, the default 15, 30 and 60 cells.
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

from elements import ply_block  # noqa: E402
from fibreshell.plies import plies_solver, ply_stack, stack_model  # noqa: E402
from validation.cases import plies_bai_5_1  # noqa: E402
from validation.ground_truth import _case  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--solves", type=int, default=1, help="rounds of the two solves")
    args = parser.parse_args()
    print(f"load before (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")
    solver = {
        **plies_bai_5_1.BEFORE_STALL_RULE,
        "increments": plies_bai_5_1.PLIES_INCREMENTS["coarse"],
    }
    case = _case(plies_bai_5_1.FILE, plies_bai_5_1.CELLS["coarse"], {"solver": solver})
    stack = ply_stack(case, plies_bai_5_1.PLIES["coarse"])
    finals = {}
    for _ in range(args.solves):
        for reuse in (False, True):
            ply_block.HESSIAN_WITH_LOADS = reuse
            model = stack_model(case, stack).compile()
            cpu = time.process_time()
            result = plies_solver(case, progress=False).solve(model)
            cpu = time.process_time() - cpu
            label = "loads' facing with the Hessian" if reuse else "tangent's own facing (before)"
            print(
                f"plies solve, {label:30s}: {cpu:6.1f} s CPU, {result.steps} Newton iterations "
                f"(+{result.info['iterations_cut']} cut), converged {result.converged}",
                flush=True,
            )
            finals[reuse] = result.frames[-1]
    ply_block.HESSIAN_WITH_LOADS = True
    same = all(
        np.array_equal(getattr(finals[False], name), getattr(finals[True], name))
        for name in ("positions", "directors")
    )
    print(f"final positions and directors the same to the bit: {same}")
    print(f"load after  (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")


if __name__ == "__main__":
    main()
