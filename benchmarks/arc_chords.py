"""The arc length's chord steps (``Static(arc_chords=...)``, docs/theory.md §6.6 "Chord
steps") on the paper cases: each case's seven Static runs (three kinematics on its default
mesh, the fibrous and the Mindlin on the two other meshes of its orders, with the case's
increments, order increments and arc_iterations), each solved without chords (the reference
pass, ``arc_chords=0``, the code before) and with the given ratio, back to back in this
process in turns whose order alternates, best of ROUNDS CPU seconds; the tangents formed, the
Newton iterations, the largest difference of the two runs' side profiles (mid-surface, mm)
and of the quantities the orders are measured on (relative).

Measured (one numba thread, CPU, 2 cores shared with other jobs, ratio 1e-3, best of 1 with
the reference always first, load 2.4-3.6: a bias for the chords, the first run loading the
kernels; alternating turns gave the 40-cell fibrous run of bai-6.1.1 4.97-5.60 -> 3.85-4.39 s,
12-20 %), the seven runs' CPU without -> with chords, and the largest changes:
  bai-6.1.1  8.60 -> 7.02 s (0.816; the 40-cell fibrous run 5.10 -> 3.96, 63 -> 49 tangents)
  bai-6.2.1  7.35 -> 5.90 s (0.803; 40-cell fibrous 3.8 -> 2.9)
  bai-6.1.2  5.80 -> 5.08 s (0.876; 24-cell fibrous 3.25 -> 2.65, 148 -> 121 tangents)
  bai-6.2.2  5.33 -> 4.75 s (0.892)
  bai-5.1    5.17 -> 5.04 s (0.975; the 60-cell fibrous run 1.52 -> 1.69, 195 -> 210 tangents:
             the case keeps arc_chords = 0, validation/cases/bai_5_1.py)
  all       32.24 -> 27.78 s (0.862). Tangents 0-35 % fewer on the corners (Newton iterations
  up by about as many chord steps, each a force evaluation and a solve); every run's side
  profiles within 4.4e-8 mm of the reference pass's, the order quantities within 2.3e-9
  relative (within 1e-10 but on the 6-cell Mindlin bai-6.1.2 run): both equilibria within
  the tolerance (1e-8 of the forces) of one another.

Where the paper cases' CPU went before (main debd499, one thread, load 2.9-3.2, CPU s of
``compute`` and ``render`` in one process; the seven runs as s (Newton iterations /
increments): fibrous, fibrous Eq. 15, Mindlin on the default mesh, then fibrous and Mindlin on
the coarser and the finer order meshes):
  bai-6.1.1  compute 8.05, render 1.54: 1.49 (74/19), 0.71, 0.31, 0.23, 0.08, 4.43 (61/12), 0.78
  bai-6.2.1  compute 6.83, render 1.61: 1.08 (73/21), 0.74, 0.26, 0.20, 0.07, 3.80 (46/11), 0.67
  bai-6.1.2  compute 5.29, render 1.42: 0.66 (108/20), 0.59, 0.22, 0.24, 0.07, 2.89 (120/25), 0.60
  bai-6.2.2  compute 5.20, render 1.57: 0.68 (109/24), 0.60, 0.24, 0.26, 0.13, 2.62 (105/23), 0.66
  bai-5.1    compute 4.43, render 1.01: 0.77 (134/18), 0.83, 0.37, 0.53, 0.21, 1.27 (141/19), 0.45
The finest fibrous run is half of each corner case; the render (four matplotlib figures, 0.17-
0.45 s each, and three XDMF files, 0.1 s each: gzip per frame and field) a fifth. Nothing
outside the solves and the render is above 1 %. In the solves (cProfile of bai-6.2.1, 406
tangents): the tangents 6.7 s (the fibrous membrane Hessians 2.1, J^T H J 1.0, the assembly
1.4, the bending blocks 1.0), the factorisations 4.0 (the supernodal LDL^T 2.2, the symbolic
choices 0.8), the solves 1.4, the residuals 0.65, the frames 0.3. Per iteration of the 40-cell
fibrous run of bai-6.1.1 (4025 unknowns, 63 tangents in 4.9 s): the tangent 38 ms (Hessians
14, J^T H J 7, node blocks 3, the bending blocks 4 of which 2 numpy), the factorisation 27
(the supernodal LDL^T 17), the two solves 6.5, the residual 1: compiled kernels, the Python
round them a few ms. Hence fewer tangents, not cheaper ones, in the time there was.

Tried and not kept: a chord at an increment's first iteration with the last increment's
factorisation (the predictor's residual is mostly the fibres' stretch): the 40-cell fibrous
run of bai-6.1.1 49 -> 318 tangents, its default run a spurious limit point at load factor
0.796; chords after a threefold or twofold gain (CHORD_GAIN 0.3, 0.5 with ratio 1e-2): the
same tangents to a few (48-49, 118-121, 99-103); fewer increments on bai-6.1.2's order runs
(20 -> 10 -> 5 a phase): more cuts, the 24-cell fibrous run 148 -> 193 -> 207 tangents; an
earlier "no progress" cut (the phase's first steps that fail sit near ratio 1 for the 12
iterations before the cut): bai-5.1's increments that converge sit as near 1 for up to 8.

Run: python benchmarks/arc_chords.py [--cases bai-6.1.1,bai-6.2.1] [--ratio 1e-3] [--rounds 2]
"""

from __future__ import annotations

import argparse
import importlib
import os
import time

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ["FIBRESHELL_PROGRESS"] = "0"

import sys
from pathlib import Path

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

from validation.paper.case import solve  # noqa: E402
from validation.paper.kinematics import ARC_CHORDS, KINEMATICS  # noqa: E402
from validation.paper.orders import ORDER_KINEMATICS, order_quantities  # noqa: E402
from validation.paper.profiles import side_data  # noqa: E402

MODULES = {
    "bai-5.1": "bai_5_1",
    "bai-6.1.1": "bai_6_1_1",
    "bai-6.1.2": "bai_6_1_2",
    "bai-6.2.1": "bai_6_2_1",
    "bai-6.2.2": "bai_6_2_2",
}


def paired_runs(spec, specimen, kinematics, increments, ratios, rounds):
    """[(best CPU s, result, side profiles)] of the runs with ``arc_chords`` each of
    ``ratios``, in turns whose order alternates (the first run of a turn pays for loading the
    kernels and meets the machine as it is then), best of ``rounds``."""
    best, results = [np.inf] * len(ratios), [None] * len(ratios)
    for turn in range(rounds):
        order = range(len(ratios)) if turn % 2 == 0 else reversed(range(len(ratios)))
        for i in order:
            model = spec.model(specimen, kinematics)
            started = time.process_time()
            results[i], _, _ = solve(model, increments, spec.arc_iterations, ratios[i])
            best[i] = min(best[i], time.process_time() - started)
    h = spec.fabric.thickness
    return [(t, r, side_data(r, specimen, kinematics, h)) for t, r in zip(best, results)]


def case_lines(name: str, ratio: float, rounds: int) -> tuple[float, float]:
    """Print each run of case ``name`` without and with chords; return the two totals."""
    spec = importlib.import_module(f"validation.cases.{MODULES[name]}").SPEC
    default = spec.cells["default"]
    order = spec.increments if spec.order_increments is None else spec.order_increments
    sequence = [(k, default, spec.increments) for k in KINEMATICS] + [
        (k, c, order) for c in spec.order_cells["default"] if c != default for k in ORDER_KINEMATICS
    ]
    totals = [0.0, 0.0]
    h = spec.fabric.thickness
    for kinematics, cells, increments in sequence:
        specimen = spec.make_specimen(cells)
        runs = paired_runs(spec, specimen, kinematics, increments, (0.0, ratio), rounds)
        gap = max(
            float(np.abs(np.asarray(a.midsurface) - np.asarray(b.midsurface)).max())
            for a, b in zip(runs[0][2].values(), runs[1][2].values())
        )
        before = order_quantities(runs[0][2], kinematics, h)
        after = order_quantities(runs[1][2], kinematics, h)
        moved = max(abs(after[q] - v) / max(abs(v), 1e-300) for q, v in before.items())
        counts = [
            (r[1].info["evaluations"]["tangent"], sum(r[1].info["iterations_per_increment"]))
            for r in runs
        ]
        for i in range(2):
            totals[i] += runs[i][0]
        print(
            f"{name} {kinematics:16s} {cells:3d} cells: {runs[0][0]:5.2f} -> {runs[1][0]:5.2f} s, "
            f"tangents {counts[0][0]} -> {counts[1][0]}, iterations {counts[0][1]} -> "
            f"{counts[1][1]}, chords {runs[1][1].info['arc_chords']}; sides within {gap:.1e} mm, "
            f"order quantities within {moved:.1e}",
            flush=True,
        )
    print(f"{name}: {totals[0]:.2f} -> {totals[1]:.2f} s ({totals[1] / totals[0]:.3f})")
    return totals[0], totals[1]


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--cases", default=",".join(MODULES))
    parser.add_argument("--ratio", type=float, default=ARC_CHORDS)
    parser.add_argument("--rounds", type=int, default=2)
    args = parser.parse_args()
    print(f"load before: {os.getloadavg()}")
    sums = np.zeros(2)
    for name in args.cases.split(","):
        sums += case_lines(name, args.ratio, args.rounds)
    print(f"all: {sums[0]:.2f} -> {sums[1]:.2f} s ({sums[1] / sums[0]:.3f})")
    print(f"load after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
