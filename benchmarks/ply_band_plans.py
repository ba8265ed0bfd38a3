"""The Static ply stacks' linear solves on plans kept over changing contact pairs: the band
plan kept for a new pattern within its envelope and made on the union of the patterns met
(solvers/linear.py ``KEEP_BAND_PLANS``, ``BAND_UNION_GROWTH``; solvers/band.py
``BandPlan.for_pattern``), and K_ff's structure kept over the node pairs met
(femcore/assembly.py ``FreeTangentAssembler(superset=True)``), against a new ordering, band
plan and structure at every new pattern (the reference: main before them), docs/theory.md
§6.5, "Plans kept over changing contact pairs".

Each Static ply solve of the report's ply cases (benchmarks/static_plies_case.py
``solve_case`` with the case's own solver: plies-bai-5.1's plies with its stall and first-turn
rules, plies-heavy-cantilever's, plies-deck-of-cards' deck at its largest N and its heavy
stack of the fewest plies) both ways in alternating turns in this process, best of
``--repeat``: CPU (``time.process_time``, one thread), the tangents, the orderings (the
plans made, ``LinearSolver.symbolic``; the checks' fresh plans, one at every 8th kept
pattern, not counted), and how far the kept plans moved the results: the largest change of the
displacements over every frame, over the largest displacement, and of the directors. Then,
once more with the kept plans, on every tangent factorised by the band on a kept plan (a
plan made for another pattern; the first factorisation of a new pattern given a kept plan
counted apart from the refactorisations that follow on it): its negative pivots (the inertia
the stability checks read) against those of a fresh plan of that very matrix (the
reference's ordering), the mismatches counted (``--inertia-only``: that count alone). The
machine's load is printed.

    python benchmarks/ply_band_plans.py [--cases bai,heavy,deck,sag]
        [--resolutions coarse,default] [--repeat 2] [--inertia-only]

Measured (one thread, CPU, 2 cores shared, load 8.7-10.3; docs/theory.md §6.5, "Plans kept
over changing contact pairs", with the controls and the report's cases):

* coarse: bai 1.35 -> 1.24 s, tangents 271 both ways, orderings 127 -> 11; heavy 0.38 ->
  0.38 s, 125, 21 -> 7; deck 0.28 -> 0.28 s, 51, 20 -> 5; sag 0.82 -> 0.73 s, 184 -> 167,
  87 -> 7.
* default: bai 11.82 -> 10.18 s (0.861 x), 403 both ways, 302 -> 18, the kept plans 0.49
  of a fresh plan's operations; heavy 1.42 -> 1.37 s, 142, 64 -> 17; deck 2.01 -> 2.60 s,
  tangents 134 -> 174 (round-off: main's code on equally good orderings took 123-187),
  81 -> 80, the kept plans 1.25 of fresh; sag 0.83 -> 0.73 s, 184 -> 167, 87 -> 7.
* displacements moved at most 6.9e-12 of the largest (sag), directors 1.1e-13.
* ``--inertia-only`` (load 0.7-0.9): negative pivots mismatched on none of the 1210 band
  factorisations on a kept plan (678 the first of a new pattern given a kept plan, the rest
  refactorisations on it) of 1462 band factorisations (QDLDL fallbacks not counted); coarse
  bai 271, 260 on a kept plan, 124 new, heavy 125, 63, 15, deck 51, 26, 15, sag 167, 140,
  66; default bai 403, 385, 284, heavy 142, 113, 54, deck 136, 83, 54, sag 167, 140, 66.
  Kept / fresh plans' operations summed over the kept plans' factorisations: coarse 0.55,
  3.20, 1.01, 1.03; default 0.49, 0.98, 1.06, 1.03 (the ratios above were summed over every
  band factorisation, the fresh plans' too).
"""

from __future__ import annotations

import argparse
import functools
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

from benchmarks.static_plies_case import solve_case  # noqa: E402
from femcore.assembly import FreeTangentAssembler  # noqa: E402
from solvers import linear, newton  # noqa: E402
from solvers.band import BandLDLT, BandPlan  # noqa: E402
from validation.cases import plies_bai_5_1  # noqa: E402


def configure(kept: bool) -> None:
    """The kept plans and structure (``kept``), or a new one at every new pattern."""
    linear.KEEP_BAND_PLANS = kept
    newton.FreeTangentAssembler = functools.partial(  # type: ignore[misc]
        FreeTangentAssembler, superset=kept
    )


def solve(name: str, resolution: str):
    """The case's Static ply solve: bai with its stall and first-turn rules."""
    if name == "bai":
        solver = plies_bai_5_1.PLIES_SOLVER
        return solve_case(
            name, resolution, solver["stall_iterations"], first_turn=solver["first_turn"]
        )
    return solve_case(name, resolution, None)


def timed(name: str, resolution: str) -> tuple[float, object]:
    start = time.process_time()
    result = solve(name, resolution)
    return time.process_time() - start, result


def moved(old, new) -> tuple[float, float]:
    """(largest |u_new - u_old| / largest |u_old| over the frames, largest |d_new - d_old|)
    of the displacements u and directors d (the last frame's where the counts differ)."""
    pairs = list(zip(old.frames, new.frames)) if len(old.frames) == len(new.frames) else []
    pairs = pairs or [(old.frames[-1], new.frames[-1])]
    start = old.frames[0].positions
    largest = max(float(np.abs(a.positions - start).max()) for a, _ in pairs)
    change = max(float(np.abs(b.positions - a.positions).max()) for a, b in pairs)
    turned = max(float(np.abs(b.directors - a.directors).max()) for a, b in pairs)
    return change / largest, turned


def inertia_check(name: str, resolution: str) -> tuple[int, int, int, int, float, float]:
    """(band factorisations, those on a kept plan (a plan made for another pattern: the new
    pattern it was kept for and the refactorisations on that pattern that follow), the new
    patterns given a kept plan, negative-pivot mismatches on a kept plan against a fresh
    plan of the same matrix, the sums over the kept plans' factorisations of their
    operations and envelope entries over the fresh plans') over one solve with the kept
    plans. A QDLDL fallback (the band met a zero pivot) is not a band factorisation."""
    counts = [0, 0, 0, 0]
    sums = np.zeros(4)
    original = linear.LinearSolver._ldlt
    on_kept: dict[int, bool] = {}  # per solver, whether its band plan was kept

    def checked(solver, upper):
        symbolic = solver.symbolic
        new = not solver._same((upper.indptr, upper.indices))
        found = original(solver, upper)
        if new:
            on_kept[id(solver)] = solver.symbolic == symbolic
        if isinstance(found[0], BandLDLT):
            counts[0] += 1
            if on_kept[id(solver)]:
                counts[1] += 1
                counts[2] += new
                plan = BandPlan(upper)
                fresh = plan.factorise(upper.data)
                counts[3] += fresh is None or fresh.negative != found[1]
                kept = solver._band
                sums[:] += (kept.operations, plan.operations, envelope(kept), envelope(plan))
        return found

    configure(True)
    linear.LinearSolver._ldlt = checked  # type: ignore[method-assign]
    try:
        solve(name, resolution)
    finally:
        linear.LinearSolver._ldlt = original  # type: ignore[method-assign]
    ratios = (sums[0] / sums[1], sums[2] / sums[3]) if counts[1] else (np.nan, np.nan)
    return counts[0], counts[1], counts[2], counts[3], ratios[0], ratios[1]


def inertia(name: str, resolution: str) -> str:
    """``inertia_check``'s counts in words."""
    band, on_kept, new, mismatched, operations, entries = inertia_check(name, resolution)
    return (
        f"band factorisations {band}, {on_kept} on a kept plan ({new} of them of a new "
        f"pattern), negative pivots mismatched {mismatched}; kept / fresh plans' "
        f"operations {operations:.2f}, envelope entries {entries:.2f}"
    )


def envelope(plan: BandPlan) -> float:
    """The entries of a band plan's envelope (the reaches and the diagonal)."""
    return float(np.sum(plan.reaches + 1))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", default="bai,heavy,deck,sag")
    parser.add_argument("--resolutions", default="coarse,default")
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument(
        "--inertia-only", action="store_true", help="only the kept plans' negative pivots"
    )
    args = parser.parse_args()
    load = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    print(f"load before: {load}", flush=True)
    for resolution in args.resolutions.split(","):
        for name in args.cases.split(","):
            if args.inertia_only:
                print(f"{name} ({resolution}): {inertia(name, resolution)}", flush=True)
                continue
            configure(True)
            solve(name, resolution)  # the kernels loaded
            runs: dict[bool, list] = {False: [], True: []}
            for turn in range(args.repeat):
                for kept in (False, True) if turn % 2 == 0 else (True, False):
                    configure(kept)
                    runs[kept].append(timed(name, resolution))
            old, new = min(runs[False], key=lambda r: r[0]), min(runs[True], key=lambda r: r[0])
            info = [r[1].info for r in (old, new)]
            tangents = [i["evaluations"]["tangent"] for i in info]
            symbolic = [i["linear_solver"]["symbolic_factorisations"] for i in info]
            relative, turned = moved(old[1], new[1])
            print(
                f"{name} ({resolution}): CPU {old[0]:.2f} -> {new[0]:.2f} s "
                f"({new[0] / old[0]:.3f} x), tangents {tangents[0]} -> {tangents[1]}, "
                f"orderings {symbolic[0]} -> {symbolic[1]}; displacements moved "
                f"{relative:.1e} of the largest, directors {turned:.1e}; "
                f"{inertia(name, resolution)}",
                flush=True,
            )
    load = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    print(f"load after: {load}")


if __name__ == "__main__":
    main()
