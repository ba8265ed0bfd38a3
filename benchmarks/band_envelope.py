"""The band LDL^T within its envelope (solvers.band) against the whole band and QDLDL, on the
tangents of the paper cases' corner runs: CPU time of one numeric factorisation each (best of
ROUNDS, one thread), the operations each counts (the sum of the column reaches or counts
squared), and whether the envelope's factors and solution are the whole band's to the bit.

Each K_ff is the last one a paper case's run factorised (validation.paper.case.solve on the
case's specimen at that mesh, the run's own LinearSolver wrapped to keep it): bai-6.2.1's
gripped corner, fibrous (nodal h_m) and Mindlin, on 20 and 40 cells.

Measured (CPU ms, best of 5 / 3; load 5.5-6.6 / 9.7-10 on 2 cores shared with other jobs):
  model              n     band  QDLDL ops  band ops  envelope ops  QDLDL      band       envelope
  fibrous 20 cells   1023  287   1.50e7     8.43e7    4.16e7        4.7/5.4    4.8/4.2    3.3/3.0
  Mindlin 20 cells   1023  104   2.64e6     1.11e7    0.57e7        1.0/1.0    0.9/0.9    0.6/0.6
  fibrous 40 cells   4025  584   2.24e8     1.37e9    0.70e9        77.8/74.5  79.6/78.6  53.7/53.1
  Mindlin 40 cells   4025  204   2.90e7     1.68e8    0.86e8        9.9/10.1   12.9/12.4  8.4/7.9
The envelope's factors and solutions the whole band's to the bit on every matrix. Per counted
operation the envelope runs 3.5-4.5 times faster than QDLDL (fibrous 40 cells 13 against 3.0
billion a second, Mindlin 40 cells 10 against 2.9): solvers.linear.BAND_ADVANTAGE 3.5, which
gives all four to the envelope (before, with n b^2 against 3.0, the fibrous corners took QDLDL).
In bai-6.2.1's 40-cell fibrous run (74 Newton iterations, 76 factorisations) the
factorisations took 5.91 s of CPU by QDLDL, 4.44 s by the envelope (load 5-10).

The elimination by panels (solvers.band ``_factorise``, the column-by-column one kept as
``_factorise_by_column``, the "env" column above): each column below a panel of 8 takes the
panel's updates four at a time in one pass down the column (the same updates in the same
order). Measured beside the column by column (CPU ms, best of 5, load 6.5-6.9), "panels":
  fibrous 20 cells  3.7 -> 3.2     Mindlin 20 cells  0.6 -> 0.8
  fibrous 40 cells  54.1 -> 39.5   Mindlin 40 cells  9.0 -> 8.8
the factors and the negative pivots the same bits on every matrix (the last column). Narrow
bands are faster column by column (solvers.band.PANEL_FROM = 200). Panels of 4, 8, 12, 16, 32
and 64 columns on the 40-cell fibrous corner: 44, 42, 44, 47, 52, 53 ms. Tried and taken out
before: panels of 32 columns updated row by row below the panel (each row taking the panel's
updates in turn while in the cache): 54 -> 166 ms on the 40-cell fibrous corner (load 13),
the row-outer update compiled far worse than the column's axpys.

Run: python benchmarks/band_envelope.py [--rounds 5]
"""

from __future__ import annotations

import argparse
import os
import time

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ["FIBRESHELL_PROGRESS"] = "0"

import sys
from pathlib import Path

import numpy as np  # noqa: E402
import qdldl  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

import solvers.linear as linear  # noqa: E402
from solvers.band import BandPlan, _factorise, _factorise_by_column, _solve  # noqa: E402
from validation import specimens  # noqa: E402
from validation.cases.bai_6_2_1 import SPEC  # noqa: E402
from validation.paper.case import solve  # noqa: E402
from validation.paper.kinematics import ELEMENT, FIBROUS_THICKNESS  # noqa: E402

MODELS = (("fibrous", 20), ("mindlin", 20), ("fibrous", 40), ("mindlin", 40))


def last_tangent(kinematics: str, cells: int):
    """The upper triangle of the last K_ff the run of bai-6.2.1 at ``cells`` factorised."""
    kept = []
    original = linear.LinearSolver._ldlt

    def keeping(self, upper):
        kept[:] = [upper.copy()]
        return original(self, upper)

    specimen = SPEC.make_specimen(cells)
    model = specimens.build(
        specimen,
        ELEMENT[kinematics],
        SPEC.fabric,
        SPEC.displacement,
        SPEC.calibration,
        thickness=FIBROUS_THICKNESS.get(kinematics, "nodal"),
    )
    linear.LinearSolver._ldlt = keeping
    try:
        solve(model, SPEC.increments)
    finally:
        linear.LinearSolver._ldlt = original
    return kept[0]


def best(function, rounds: int) -> float:
    """The least CPU time (s) of ``rounds`` calls."""
    times = []
    for _ in range(rounds):
        started = time.process_time()
        function()
        times.append(time.process_time() - started)
    return min(times)


def measure(upper, rounds: int) -> str:
    """The line of one K_ff's upper triangle: sizes, operations, CPU ms, bits the same."""
    n = upper.shape[0]
    plan = BandPlan(upper)
    whole = np.minimum(plan.bandwidth, n - 1 - np.arange(n)).astype(np.int64)

    def factors(reaches, factorise=_factorise_by_column):
        flat = np.zeros(plan.fill)
        flat[plan.slots] = upper.data
        band = flat.reshape(n, plan.bandwidth + 1)
        return factorise(band, reaches), band

    ldl = qdldl.Solver(upper, upper=True)
    counts = np.diff(ldl.factors()[0].indptr).astype(float)
    rhs = np.linspace(-1.0, 1.0, n)
    (a, band_a), (b, band_b) = factors(whole), factors(plan.reaches)
    c, band_c = factors(plan.reaches, _factorise)
    same = a == b and np.array_equal(_solve(band_a, whole, rhs), _solve(band_b, plan.reaches, rhs))
    same_panels = c == b and np.array_equal(band_c.view(np.int64), band_b.view(np.int64))
    times = (
        best(lambda: ldl.update(upper, upper=True), rounds),
        best(lambda: factors(whole), rounds),
        best(lambda: factors(plan.reaches), rounds),
        best(lambda: factors(plan.reaches, _factorise), rounds),
    )
    sizes = f"{n:5d} {plan.bandwidth:5d} {np.sum(counts**2):10.3g} {n * plan.bandwidth**2:9.3g}"
    shown = " ".join(f"{1e3 * t:6.1f}" for t in times)
    return f"{sizes} {plan.operations:8.3g} {shown}  {same} {same_panels}"


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    print(f"load before: {os.getloadavg()}")
    print(f"{'model':18s} {'n':>5s} {'band':>5s} {'QDLDL ops':>10s} {'band ops':>9s} "
          f"{'env ops':>8s} {'QDLDL':>6s} {'band':>6s} {'env':>6s} {'panels':>6s}  same"
          " same-panels")  # fmt: skip
    for kinematics, cells in MODELS:
        upper = last_tangent(kinematics, cells)
        print(f"{kinematics + ' ' + str(cells) + ' cells':18s} " + measure(upper, args.rounds),
              flush=True)  # fmt: skip
    print(f"load after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
