"""A kept band plan judged again against the supernodal factor once the pattern has shrunk
below REORDER_SHRINK of the pattern QDLDL last measured (solvers/linear.py), against the rule
before (a shrunk pattern kept the stale measurement: ``REORDER_SHRINK = 0``, the reference),
side by side in this process, alternating turns, best of ``--rounds``: the Static solve of
the ply stacks of benchmarks/static_plies_case.py ``solve_case`` (plies-bai-5.1's by
default; the case's own solver) at each resolution asked for and the 2560-triangle Mindlin
cantilever of benchmarks/static_solver.py (P L^2/EI = 3, 5 increments). CPU
(``time.process_time``), one thread; the tangents, the orderings (``LinearSolver.symbolic``
summed), the factorisations by the supernodal LDL^T and the largest change of the final
positions and directors; the machine's load.

    python benchmarks/measured_shrink.py [--cases bai,heavy,deck,sag]
        [--resolutions coarse,default] [--rounds 2] [--no-cantilever]

Measured (one thread, CPU, 2 cores shared with other jobs; best of 2, coarse 3; the rule
off -> on), REORDER_SHRINK 0.75: bai default 10.04 -> 9.54 s (load 5.0-5.8; the other
round 10.98 -> 10.67), 403 tangents both ways, orderings 18 -> 20, 42 factorisations by the
supernodal LDL^T; bai coarse 1.30 -> 1.27 s (load 4.6), 271 tangents, 11 -> 14, 37; heavy
default 1.56 -> 1.62 s, 142, 17 -> 31, 126; heavy coarse 0.39 -> 0.41 s, 125, 7 -> 7, 108
(the supernodal LDL^T taken where the band was faster); deck default 2.49 -> 3.66 s (load
4.6), tangents 174 -> 192 (the path moved by round-off, as in benchmarks/ply_band_plans.py);
sag default 0.70 -> 0.72 s; the Mindlin cantilever 0.83 -> 0.85 s, the same bits (no
pattern shrinks). REORDER_SHRINK 1/1.2 (load 3.0-6.1): bai coarse 1.35 -> 1.38 s, default
10.20 -> 10.60 s (orderings 18 -> 22, 43 supernodal), heavy default 1.38 -> 1.67 s, deck
2.73 -> 3.63 s, sag 0.87 -> 0.90 s, the cantilever 0.90 -> 0.88 s. Final positions within
4e-14 to 1.6e-12 mm of the rule off (the deck's the largest), directors within 5e-14.
Timers around the bai default solve's calls (load 5.9-6.7, two rounds): the linear
solver's factorise 3.88-3.94 s of 10.7-11.9 s both ways (the choice's measurements 0.13 ->
0.28-0.30 s, the rest 0.15 s less). So the rule is off (solvers/linear.py REORDER_SHRINK).

The linear solves of the bai stack (the ramp, the case's solver; timers around the calls,
one thread, CPU, load 5.9-6.7; docs/theory.md §6.5, "Plans kept over changing contact pairs"):
the linear solver's factorisations 3.9 of 10.7-11.9 s on the default stack, all on band plans
(302 of the 403 at a new pattern, 18 orderings); judged at a measurement of the plies
pressed, the band is kept as they hang apart (6.6 ms a factorisation against a fresh
supernodal one's 1.2 ms) and pressed again (5.5-5.9 against 4.1-5.0 ms). Measuring such
patterns anew (solvers/linear.py ``REORDER_SHRINK`` 0.75, this script, the
two rules alternately in one process, best of 2-3, load 4.6-5.8): default 10.04 -> 9.54 s,
coarse 1.30 -> 1.27 s, the same 403 and 271 tangents, within 5e-14 mm; the heavy stack 1.56 ->
1.62 s and the deck 2.49 -> 3.66 s (its path moved by round-off): not kept.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install
sys.path.insert(0, str(Path(__file__).resolve().parent))

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

COUNTS = {"symbolic": 0, "supernodal": 0}


def instrument() -> None:
    """Count the orderings and the supernodal factorisations of every LinearSolver."""
    from solvers import linear

    original = linear.LinearSolver._ldlt

    def counted(self, upper):
        before = self.symbolic
        out = original(self, upper)
        COUNTS["symbolic"] += self.symbolic - before
        COUNTS["supernodal"] += self._band is None and self._supernodal is not None
        return out

    linear.LinearSolver._ldlt = counted  # type: ignore[method-assign]


def cantilever():
    """The Mindlin cantilever of benchmarks/static_solver.py solved: (positions, directors,
    tangents)."""
    from static_solver import strip

    from solvers import Static

    model, _, _ = strip("force")
    result = Static(increments=5).solve(model)
    return result.positions, result.directors, int(result.steps)


def plies(case: str, resolution: str):
    """The plies of ``case`` (benchmarks/static_plies_case.py: bai, heavy, deck, sag)
    solved by the case's own solver: (positions, directors, tangents)."""
    import static_plies_case as bench

    result = bench.solve_case(case, resolution)
    return result.positions, result.directors, int(result.info["evaluations"]["tangent"])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", default="bai")
    parser.add_argument("--resolutions", default="coarse,default")
    parser.add_argument("--no-cantilever", action="store_true")
    parser.add_argument("--rounds", type=int, default=2)
    args = parser.parse_args()
    from solvers import linear

    instrument()
    rule = linear.REORDER_SHRINK
    runs = [
        (f"{c} {r}", lambda c=c, r=r: plies(c, r))
        for c in args.cases.split(",")
        for r in args.resolutions.split(",")
        if c and r
    ]
    if not args.no_cantilever:
        runs.append(("cantilever", cantilever))
    print(f"load before (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")
    for name, run in runs:
        best: dict[float, float] = {}
        results = {}
        for _ in range(args.rounds):
            for shrink in (0.0, rule):
                linear.REORDER_SHRINK = shrink
                COUNTS.update(symbolic=0, supernodal=0)
                cpu = time.process_time()
                results[shrink] = run()
                cpu = time.process_time() - cpu
                best[shrink] = min(best.get(shrink, np.inf), cpu)
                print(
                    f"{name} REORDER_SHRINK={shrink:.3f}: {cpu:.2f} s CPU, tangents "
                    f"{results[shrink][2]}, orderings {COUNTS['symbolic']}, supernodal "
                    f"factorisations {COUNTS['supernodal']}",
                    flush=True,
                )
        linear.REORDER_SHRINK = rule
        (p0, d0, _), (p1, d1, _) = results[0.0], results[rule]
        print(
            f"{name}: best {best[0.0]:.2f} -> {best[rule]:.2f} s; positions within "
            f"{np.abs(p1 - p0).max():.3g}, directors within {np.abs(d1 - d0).max():.3g}; load "
            f"{np.round(os.getloadavg(), 2).tolist()}",
            flush=True,
        )


if __name__ == "__main__":
    main()
