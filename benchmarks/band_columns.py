"""Many right-hand sides on one band LDL^T: the switched points' columns G_i^T of a predicted
contact set (solvers/contact_sets.py) solved in one compiled pass (solvers.band
``BandLDLT.solve_columns``) against one solve a column (``BandLDLT.solve``, the reference, as
before), and a factorisation of the same K_ff beside them: what a column costs each way, and
so how many new columns a prediction solves before a factorisation of the updated K_ff is
cheaper (``contact_sets.REFACTOR_AT``).

The K_ff and the columns are those of the first prediction of the displacement phase (load
factor past 1) of plies-bai-5.1's stack with ``PlyContact(static_law="active_set")``
(benchmarks/static_plies_case.py ``solve_case``), the plies pressed together (the gravity
phase's K_ff, plies apart, has a band of 11 on the default stack); each count of columns is
solved both ways, alternately, best of ``--repeat``, CPU (``time.process_time``), one
thread; the two solutions compared to the bit; the machine's load.

    python benchmarks/band_columns.py [--resolution default] [--repeat 5]

Measured (one thread, CPU, 2 cores shared with other jobs): see docs/theory.md §9.3a, "The
predicted set made cheaper, and each phase opened on the ramp".
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

COUNTS = (1, 4, 16, 48, 100, 200)


class Captured(Exception):
    """Raised by the patched prediction once it holds a K_ff and enough columns."""


def capture(resolution: str, wanted: int):
    """(K_ff's Factorisation, the (f, m) columns G_i^T of ``wanted`` points at the first
    prediction of the displacement phase with at least that many reachable points)."""
    import static_plies_case as bench

    from solvers import contact_sets

    original = contact_sets.SetRows.__init__
    found: dict = {}

    def keep(self, *args, **kwargs):
        original(self, *args, **kwargs)
        if found.get("load", 0.0) > 1.0 and len(self.gap) >= wanted:
            found["columns"] = self.columns(np.arange(wanted))
            raise Captured

    contact_sets.SetRows.__init__ = keep  # type: ignore[method-assign]
    real = contact_sets.predicted_sets

    def predicted(run, state, frames, factor, delta_free, left):
        found["factor"], found["load"] = factor, state.load_factor
        return real(run, state, frames, factor, delta_free, left)

    contact_sets.predicted_sets = predicted
    try:
        bench.solve_case("bai", resolution, static_law="active_set")
    except Captured:
        pass
    finally:
        contact_sets.SetRows.__init__ = original  # type: ignore[method-assign]
        contact_sets.predicted_sets = real
    if "columns" not in found:
        raise SystemExit(f"no prediction reached {wanted} points")
    return found["factor"], found["columns"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--resolution", default="default")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    print(f"load before (1, 5, 15 min): {[round(x, 2) for x in os.getloadavg()]}")
    factor, columns = capture(args.resolution, max(COUNTS))
    band = factor._ldl
    if not hasattr(band, "solve_columns"):
        raise SystemExit(f"the K_ff was not factorised by the band ({type(band).__name__})")
    print(
        f"K_ff: {factor.matrix.shape[0]} free unknowns, band {band.plan.bandwidth}, "
        f"envelope {band.plan.operations:.3g} operations"
    )
    from solvers.linear import LinearSolver

    solver = LinearSolver()
    solver.factorise(factor.matrix)  # its plan made once, as a kept plan serves the next
    best = np.inf
    for _ in range(args.repeat):
        start = time.process_time()
        solver.factorise(factor.matrix)
        best = min(best, time.process_time() - start)
    print(f"a factorisation (LinearSolver.factorise, the plan kept): {1e3 * best:.2f} ms")
    for m in COUNTS:
        rhs = np.ascontiguousarray(columns[:, :m])
        times = {"column by column": np.inf, "together": np.inf}
        for _ in range(args.repeat):
            start = time.process_time()
            alone = np.column_stack([band.solve(rhs[:, j]) for j in range(m)])
            times["column by column"] = min(times["column by column"], time.process_time() - start)
            start = time.process_time()
            together = band.solve_columns(rhs)
            times["together"] = min(times["together"], time.process_time() - start)
        same = np.array_equal(alone, together)
        print(
            f"{m:4d} columns: column by column {1e3 * times['column by column']:.2f} ms, "
            f"together {1e3 * times['together']:.2f} ms "
            f"({1e3 * times['together'] / m:.3f} ms a column), the same bits: {same}"
        )
    print(f"load after (1, 5, 15 min): {[round(x, 2) for x in os.getloadavg()]}")


if __name__ == "__main__":
    main()
