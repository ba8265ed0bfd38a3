"""The paper cases' refinement runs (validation/paper/case.py ``refinement_orders``: the fibrous
and the Mindlin models on the two meshes of the orders other than the resolution's own, whose
last equilibrium alone the orders read) on the case's ``increments`` arc-length increments a
phase (the reference pass: the path of the case's own runs) and on fewer: each run's CPU time,
increments, Newton iterations and cuts, and the largest relative difference of the compared
quantities (validation/paper/orders.py ``order_quantities``: the mid-surface z and the
fibrous thickness at the middle of each side) from the reference pass's.

    python benchmarks/paper_refinement.py --cases bai-6.1.1,bai-6.2.1 --increments 5,3
    python benchmarks/paper_refinement.py --cases bai-6.2.2 --increments 10 --turns 3

Measured (one numba thread, CPU, one run at a time, 2 cores shared with other jobs, load
9-10; reference 10 increments -> 5):
  bai-6.1.1 fibrous 10 cells 0.98 -> 0.38 s (18 -> 12 increments), 9.8e-11 apart
            Mindlin 10 cells 0.23 -> 0.13 s (20 -> 12), 3.4e-11
            fibrous 40 cells 7.89 -> 5.67 s (19 -> 12, 73 -> 61 Newton iterations), the
            quantities printed the same to 10 digits; on 3 increments 6.12 s (one cut)
  bai-6.2.1 fibrous 10 cells 0.98 -> 0.31 s (21 -> 12), 7.4e-10
            Mindlin 10 cells 0.22 -> 0.12 s (21 -> 11), 3.9e-13
            fibrous 40 cells 7.36 -> 4.27 s (21 -> 11, 74 -> 46), 2.3e-10
            Mindlin 40 cells 1.41 -> 0.94 s (21 -> 11), 3.5e-14
  the coarse sequences' 5- and 20-cell runs alike (at most 2.0e-9 apart, no cut on 5).
No gain where the path is set by its cuts: bai-5.1 (15 / 60 cells, 52 increments and 6 cuts
on either count: 1.84 -> 1.51 s and 3.64 -> 3.81 s), bai-6.1.2 (20 -> 10 increments: the
24-cell fibrous run 4.35 -> 4.97 s, 25 increments either way, 3 -> 5 cuts); so only the two
corner cases take ``order_increments`` (5). The orders' checks are at 1 %.

bai-6.2.2 and bai-6.1.2 on 20 (their ``increments``) -> 10, 5, 3 (``--increments 10,5,3``,
one run each, one thread, load 2.8-3.4; the first run of the process pays numba's cache
loads): bai-6.2.2 24 cells fibrous 2.91 -> 2.29 / 3.01 / 2.66 s (22 -> 15 / 14 / 16
increments, 2 -> 2 / 4 / 3 cuts), 1.1e-9 / 1.3e-15 / 4.2e-11 apart; Mindlin 0.73 -> 0.65 /
0.77 / 0.75 s; the 6-cell runs 0.26 / 0.24 / 0.32 s (fibrous) and 0.13 / 0.13 / 0.09 s
(Mindlin) against 0.22 and 0.14 in the case. The four runs in turns (``--increments 10
--turns 3``: one process, best of 3 alternating, load 1.0-1.3): 20 -> 10 increments 3.68 ->
2.95 s (4.18 / 3.86 / 3.68 against 2.95 / 3.18 / 3.03), so bai-6.2.2 takes
``order_increments`` 10. bai-6.1.2 gains on none (24 cells fibrous 2.89 -> 3.83 / 4.19 / 4.20
s, 2 -> 4 / 5 / 5 cuts).

Until then the runs here took Static's default arc-length settings, not the case's own
``arc_iterations`` and ``arc_chords`` (bai-5.1's 10 and 0, the others' the defaults): the
bai-5.1 figures above are of that other path. With its own (one run each, load 2.2-2.5; 10 ->
20 / 5 increments): 15 cells fibrous 0.94 (the process's first run) -> 0.49 / 0.59 s (5 -> 4 /
7 cuts), Mindlin 0.26 -> 0.24 / 0.26; 60 cells fibrous 1.37 -> 1.25 / 1.74 (4 -> 3 / 7 cuts,
195 -> 171 / 241 tangents), Mindlin 0.51 -> 0.48 / 0.65; at most 1.6e-11 apart (on 7 and 15,
without its settings, none faster). The four runs in turns (``--increments 20 --turns 3``,
load 1.3-1.5): 10 -> 20 increments 2.67 -> 2.50 s (3.30 / 2.92 / 2.67 against 2.52 / 2.55 /
2.50), so bai-5.1 takes ``order_increments`` 20, more than its own runs' 10.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

from validation.paper import ORDER_KINEMATICS, solve
from validation.paper.orders import order_quantities
from validation.paper.profiles import side_data


def _module(name: str):
    """The case module of ``name`` ("bai-6.1.1" -> validation.cases.bai_6_1_1)."""
    return importlib.import_module("validation.cases." + name.replace("-", "_").replace(".", "_"))


def measure(name: str, resolution: str, counts: list[int]) -> None:
    """Print each refinement run of case ``name`` at ``resolution`` on the case's increments
    and on each of ``counts``."""
    spec = _module(name).SPEC
    h = spec.fabric.thickness
    for cells in spec.order_cells[resolution]:
        if cells == spec.cells[resolution]:
            continue
        specimen = spec.make_specimen(cells)
        for kinematics in ORDER_KINEMATICS:
            reference = None
            for increments in [spec.increments, *counts]:
                model = spec.model(specimen, kinematics)
                started = time.process_time()
                result, note, _ = solve(model, increments, spec.arc_iterations, spec.arc_chords)
                cpu = time.process_time() - started
                sides = side_data(result, specimen, kinematics, h)
                found = order_quantities(sides, kinematics, h)
                reference = found if reference is None else reference
                apart = max(abs(found[k] - reference[k]) / abs(reference[k]) for k in found)
                run = note.split(": ", 1)[1]
                print(
                    f"{name} {cells:3d} cells {kinematics:8s} {increments:3d} increments "
                    f"{cpu:6.2f} s CPU, {run}; {apart:.1e} apart",
                    flush=True,
                )


def turns(name: str, resolution: str, counts: list[int], rounds: int) -> None:
    """Print, per increments count (the case's own first), the CPU of the case's refinement
    runs together (every other mesh, both kinematics), the counts run alternately ``rounds``
    times in one process, each round in another order: the best and every round's sum."""
    spec = _module(name).SPEC
    runs = [
        (spec.make_specimen(cells), kinematics)
        for cells in spec.order_cells[resolution]
        if cells != spec.cells[resolution]
        for kinematics in ORDER_KINEMATICS
    ]
    every = [spec.increments, *(n for n in counts if n != spec.increments)]
    sums: dict[int, list[float]] = {n: [] for n in every}
    for round_ in range(rounds):
        order = every[round_ % len(every) :] + every[: round_ % len(every)]
        for increments in order:
            started = time.process_time()
            for specimen, kinematics in runs:
                model = spec.model(specimen, kinematics)
                solve(model, increments, spec.arc_iterations, spec.arc_chords)
            sums[increments].append(time.process_time() - started)
    for increments in every:
        spent = ", ".join(f"{t:.2f}" for t in sums[increments])
        print(
            f"{name} {len(runs)} runs on {increments:3d} increments: best "
            f"{min(sums[increments]):.2f} s CPU ({spent})",
            flush=True,
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", default="bai-6.1.1,bai-6.2.1")
    parser.add_argument("--resolution", default="default")
    parser.add_argument("--increments", default="5")
    parser.add_argument(
        "--turns", type=int, default=0, help="the runs' sums per count, alternately, N rounds"
    )
    args = parser.parse_args()
    os.environ.setdefault("FIBRESHELL_PROGRESS", "0")
    counts = [int(n) for n in args.increments.split(",")]
    print(f"load before: {os.getloadavg()}")
    for name in args.cases.split(","):
        if args.turns:
            turns(name, args.resolution, counts, args.turns)
        else:
            measure(name, args.resolution, counts)
    print(f"load after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
