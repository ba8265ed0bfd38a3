"""The linear solve's per-factorisation bookkeeping, compiled.

The band LDL^T's band written in its envelope alone (solvers.band ``BandPlan.band_of``: one
compiled pass into an uninitialised array) against the whole band zeroed and scattered (the
reference pass, as before), on every band factorisation of a Static ply solve
(benchmarks/static_plies_case.py ``solve_case``; plies-bai-5.1's stack by default): each
call's band made both ways, best of ``--repeat``, CPU (``time.process_time``), one thread;
the two bands' factors compared to the bit within the envelope (the only entries the kernels
read); and the accuracy check's ||K_ff||_inf (solvers.linear ``_infinity_norm``, one compiled
pass) against scipy's ``np.abs(k).sum(axis=1).max()`` (the reference) on each K_ff factorised,
compared to the bit; the machine's load.

    python benchmarks/band_fill.py [--case bai] [--resolution coarse] [--repeat 3]

Measured (one thread, CPU, 2 cores shared with other jobs; docs/theory.md §6.5):

* ``--resolution default``, the default plies-bai-5.1 stack (``solve_case`` with no stall
  rule; load 7-12, best of 2 a call): 1076 band factorisations, 0.95
  million band entries a call, envelope 0.57 of it; making the bands 1.947 -> 1.080 s (0.555
  x), the factors the same bits.
* coarse (load 8.4-8.5, best of 3): 924 band factorisations, 78664 entries a call, envelope
  0.58; 0.040 -> 0.023 s; ||K_ff||_inf at 975 factorisations 0.074 -> 0.031 s (0.416 x), the
  same bits.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

from benchmarks.static_plies_case import solve_case  # noqa: E402
from solvers import band, linear  # noqa: E402


def zeroed_band(plan: band.BandPlan, upper_data: np.ndarray) -> np.ndarray:
    """The reference: the whole band zeroed, then the upper triangle scattered."""
    flat = np.zeros(plan.fill)
    flat[plan.slots] = upper_data
    return flat.reshape(plan.n, plan.bandwidth + 1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", default="bai")
    parser.add_argument("--resolution", default="coarse")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    print("load before:", subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())
    totals = {"zeroed": 0.0, "envelope": 0.0, "scipy_norm": 0.0, "compiled_norm": 0.0}
    counts = {"calls": 0, "fill": 0, "envelope": 0, "differ": 0, "norms": 0, "norm_differ": 0}
    original = band.BandPlan.factorise
    original_solver = linear.LinearSolver.factorise

    def scipy_norm(k) -> float:
        """The reference: scipy's |K| matrix and its row sums."""
        return float(np.abs(k).sum(axis=1).max())

    def normed(solver: linear.LinearSolver, k_ff):
        k = k_ff if isinstance(k_ff, sp.csc_matrix) else sp.csc_matrix(k_ff)
        found = {}
        for name, norm in (("scipy_norm", scipy_norm), ("compiled_norm", linear._infinity_norm)):
            best = np.inf
            for _ in range(args.repeat):
                start = time.process_time()
                found[name] = np.float64(norm(k))
                best = min(best, time.process_time() - start)
            totals[name] += best
        counts["norms"] += 1
        counts["norm_differ"] += found["scipy_norm"].view(np.int64) != found["compiled_norm"].view(
            np.int64
        )
        return original_solver(solver, k_ff)

    def timed(plan: band.BandPlan, upper_data: np.ndarray):
        made = {}
        for name, make in (("zeroed", zeroed_band), ("envelope", band.BandPlan.band_of)):
            best = np.inf
            for _ in range(args.repeat):
                start = time.process_time()
                made[name] = make(plan, upper_data)
                best = min(best, time.process_time() - start)
            totals[name] += best
        factorise = (
            band._factorise if plan.bandwidth >= band.PANEL_FROM else band._factorise_by_column
        )
        negatives = [factorise(made[name], plan.reaches) for name in ("zeroed", "envelope")]
        inside = np.arange(plan.bandwidth + 1) <= plan.reaches[:, None]
        same = negatives[0] == negatives[1] and np.array_equal(
            made["zeroed"][inside].view(np.int64), made["envelope"][inside].view(np.int64)
        )
        counts["differ"] += not same
        counts["calls"] += 1
        counts["fill"] += plan.fill
        counts["envelope"] += int(inside.sum())
        return original(plan, upper_data)

    band.BandPlan.factorise = timed  # type: ignore[method-assign]
    linear.LinearSolver.factorise = normed  # type: ignore[method-assign]
    try:
        solve_case(args.case, args.resolution, None, None)  # no stall, no first-turn rule
    finally:
        band.BandPlan.factorise = original  # type: ignore[method-assign]
        linear.LinearSolver.factorise = original_solver  # type: ignore[method-assign]
    print(
        f"{args.case} ({args.resolution}): {counts['calls']} band factorisations, band "
        f"{counts['fill'] / max(counts['calls'], 1):.0f} entries a call, envelope "
        f"{counts['envelope'] / max(counts['fill'], 1):.2f} of it; making the band: whole band "
        f"zeroed {totals['zeroed']:.3f} s -> envelope alone {totals['envelope']:.3f} s "
        f"({totals['envelope'] / max(totals['zeroed'], 1e-12):.3f} x); factors "
        f"{'the same bits' if counts['differ'] == 0 else 'DIFFER at ' + str(counts['differ'])}"
    )
    print(
        f"  ||K_ff||_inf of the accuracy check at {counts['norms']} factorisations: scipy's "
        f"{totals['scipy_norm']:.3f} s -> one compiled pass {totals['compiled_norm']:.3f} s "
        f"({totals['compiled_norm'] / max(totals['scipy_norm'], 1e-12):.3f} x); "
        + ("the same bits" if counts["norm_differ"] == 0 else f"DIFFER at {counts['norm_differ']}")
    )
    print("load after:", subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())


if __name__ == "__main__":
    main()
