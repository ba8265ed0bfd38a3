"""The supernodal LDL^T (solvers.supernodal) beside QDLDL and the band LDL^T (solvers.band,
column by column and by panels) on the tangents of the paper cases' corner runs: CPU ms of one
numeric factorisation and of one solve (best of ROUNDS, one thread), the operations each
counts (QDLDL's and the supernodal's: the sum of L's column counts squared; the band's: its
envelope's reaches squared), the symbolic analysis's ms, and the agreement: the negative
pivots of each, the supernodal solution against QDLDL's (largest difference over the largest
entry) and its backward error.

Each K_ff is the last one a run of bai-6.2.1 factorised (benchmarks/band_envelope.py
``last_tangent``): the gripped corner, fibrous (nodal h_m) and Mindlin, on 20 and 40 cells.

Measured (CPU ms, best of 5, one thread; load 5.1-5.8 on 2 cores shared with other jobs; the
band "column" column by column, "panels" by panels of 8, as solvers.band; the solves' band
is the column-by-column band's):
  model             n     sn ops   env ops  QDLDL  column  panels  supernodal  solve band / sn
  fibrous 20 cells  1023  1.52e7   4.16e7    5.01    3.31    3.03        1.88      0.24 / 0.12
  Mindlin 20 cells  1023  2.73e6   5.73e6    1.10    0.61    0.80        0.47      0.10 / 0.06
  fibrous 40 cells  4025  2.26e8   6.98e8   78.44   55.99   39.73       21.26      2.69 / 1.18
  Mindlin 40 cells  4025  2.96e7   8.60e7    9.73    8.69    7.64        3.65      0.90 / 0.33
A new pattern inside a kept analysis's L (``SupernodalPlan.for_pattern``): 0.35-6.4 ms
(fibrous 40 cells: 6.41; load 0.7-1.5), its rows checked canonical (ascending, none repeated,
none below the diagonal) by the mapping kernel as it goes and its frame (format, shape,
column pointers) by numpy in 0.007 ms; numpy's check of the rows, run where a pattern is
analysed, 0.07-0.66 ms (fibrous 40 cells: 3.1 % of a factorisation), which for_pattern ran
at first (7.33 against 6.41 ms then, at load 1.9-2.3).
Symbolic analysis of a new pattern: 2.5-29 ms (fibrous 40 cells: 28.6), after QDLDL's own
factorisation for its ordering (78 ms). The negative pivots the same (0) in all three; the
supernodal solutions within 2e-12 to 1e-10 of QDLDL's (the corners' conditioning), backward
errors 1.1e-17 to 2.1e-17. The first supernodal version (supernodes' own elimination column
by column, solve column by column): 24 and 4.2 ms on the 40-cell corners, 2.7 and 0.63 ms a
solve.

Tried and not kept: relaxed supernodes (a column joins its parent's supernode when the
supernode then stores at most 5-40 % more entries than L, as zeros): 456 -> 277-448
supernodes on the 40-cell fibrous corner and 20.8 -> 21.3-24.2 ms.

Run: python benchmarks/supernodal.py [--rounds 5]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ["FIBRESHELL_PROGRESS"] = "0"

import numpy as np  # noqa: E402
import qdldl  # noqa: E402
import scipy.sparse as sp  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

from band_envelope import MODELS, last_tangent  # noqa: E402

from solvers.band import BandPlan, _factorise, _factorise_by_column  # noqa: E402
from solvers.supernodal import SupernodalPlan, _checked_pattern  # noqa: E402


def best(function, rounds: int) -> float:
    """The least CPU time (s) of ``rounds`` calls."""
    times = []
    for _ in range(rounds):
        started = time.process_time()
        function()
        times.append(time.process_time() - started)
    return min(times)


def measure(upper: sp.csc_matrix, rounds: int) -> str:
    """The line of one K_ff's upper triangle."""
    n = upper.shape[0]
    ldl = qdldl.Solver(upper, upper=True)
    lower, pivots, ordering = ldl.factors()
    started = time.process_time()
    plan = SupernodalPlan(upper, ordering)
    symbolic = time.process_time() - started
    band = BandPlan(upper)

    def band_factors(factorise):
        flat = np.zeros(band.fill)
        flat[band.slots] = upper.data
        return factorise(flat.reshape(n, band.bandwidth + 1), band.reaches)

    factor = plan.factorise(upper.data)
    assert factor is not None
    banded = band.factorise(upper.data)
    assert banded is not None
    k = (upper + sp.triu(upper, 1).T).tocsc()
    rhs = np.linspace(-1.0, 1.0, n)
    x, reference = factor.solve(rhs), ldl.solve(rhs)
    difference = np.abs(x - reference).max() / np.abs(reference).max()
    norm = float(np.abs(k).sum(axis=1).max())
    backward = np.abs(k @ x - rhs).max() / (norm * np.abs(x).max() + np.abs(rhs).max())
    times = (
        best(lambda: ldl.update(upper, upper=True), rounds),
        best(lambda: band_factors(_factorise_by_column), rounds),
        best(lambda: band_factors(_factorise), rounds),
        best(lambda: plan.factorise(upper.data), rounds),
        best(lambda: banded.solve(rhs), rounds),
        best(lambda: factor.solve(rhs), rounds),
    )
    shown = " ".join(f"{1e3 * t:6.2f}" for t in times)
    # the pattern's checks: numpy's over the entries (an analysis's), and the frame alone
    # (format, shape, column pointers: for_pattern's, whose kernel checks the rows)
    check = best(lambda: _checked_pattern(upper), rounds)
    frame = best(lambda: _checked_pattern(upper, frame_only=True), rounds)
    kept = best(lambda: plan.for_pattern(upper), rounds)
    negatives = (int(np.sum(pivots < 0.0)), banded.negative, factor.negative)
    return (
        f"{n:5d} {plan.operations:9.3g} {band.operations:9.3g} {shown}  symbolic "
        f"{1e3 * symbolic:5.1f} ms, for_pattern {1e3 * kept:.2f} ms (its frame check "
        f"{1e3 * frame:.3f} ms), numpy's check {1e3 * check:.3f} ms ({check / times[3]:.1%} "
        f"of a factorisation), negative "
        f"{negatives}, x within {difference:.1e} of QDLDL's, backward error {backward:.1e}"
    )


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    print(f"load before: {os.getloadavg()}")
    print(f"{'model':18s} {'n':>5s} {'sn ops':>9s} {'env ops':>9s} {'QDLDL':>6s} {'column':>6s} "
          f"{'panels':>6s} {'supern':>6s} {'solve band':>6s} {'solve sn':>6s}")  # fmt: skip
    for kinematics, cells in MODELS:
        upper = last_tangent(kinematics, cells)
        print(f"{kinematics + ' ' + str(cells) + ' cells':18s} " + measure(upper, args.rounds),
              flush=True)  # fmt: skip
    print(f"load after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
