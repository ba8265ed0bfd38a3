"""Why a Mindlin run of the hemisphere-plies case costs about twice a fibrous one: each run's
steps, CPU, CPU a step and its stable step's parts (the cells' critical step, the ply and
tool springs' omega^2 that lower it), and with ``--profile`` a second run under cProfile,
the step's parts as shares of the march (cumulative times of the entry points named in
``PARTS``: the parts nest, so they do not add up to one).

    python benchmarks/ply_run_split.py --runs mindlin:0/90,fibrous:0/90 --profile
    python benchmarks/ply_run_split.py --rotary --runs ""

One numba thread; run it beside a reference tree (``git archive`` of main) on the same load,
its own copy run from its root, and compare the steps and CPU a step.

The facing's choice made in the front's call (elements/ply_facing_front.py ``CHOSEN``), this
script's Mindlin [0/90] run from each tree alternately, three rounds (one thread, nice 5, load
1.7-2.3): 36.22 / 36.34 / 36.37 s of CPU against main 15bf388's 37.21 / 37.67 / 37.24 (best
0.973), 32225 steps each; again with the choice handed read-only views (its build shared),
as the load rose from 1.8 to 7.5: 39.31 / 40.26 / 40.33 against 37.82 / 40.23 / 41.01, round
by round 1.04 / 1.00 / 0.98 (the noise as large as the cut: benchmarks/ply_step.py
``--toggle`` measures it within one run, 1.5-3 %).

Measured (main 5e52abb, one thread, nice 5, 2 cores shared, load 10.0-13.2: the CPU a step
inflated by the load; the shares are of a profiled run's march):

* fibrous [0/90] 4131 steps, 6.65 s, 1.610 ms a step; Mindlin [0/90] 8429 steps (2.04 x),
  12.65 s, 1.501 ms a step. **A Mindlin run costs twice a fibrous one because it takes twice
  the steps; its step costs no more.** Its cells' critical step at the start is 2.241e-5 s
  against the fibrous cells' 4.228e-5 s (0.53 x: the Mindlin cells' bound, docs/theory.md
  §6.2); the contacts' springs lower both alike (x0.655 / x0.651 at the first evaluation: the
  penalty is calibrated as a share of m (2 / dt)^2 of each model's own critical step,
  elements/ply_contact.py "Penalty"). Fewer steps would move the results (not the same bits):
  not touched here. The Mindlin cells' step is their rotations' (the transverse shear
  against the scaled rotary inertia j, 16.3 mm^2 here): ``--rotary`` gives the first cell's
  critical step 2.266e-5 s at the model's j, 3.008e-5 / 3.823e-5 / 4.595e-5 / 4.869e-5 s at
  2 / 4 / 8 / 100 j. A larger j (B2's scaling, docs/theory.md §6.2) would take the Mindlin
  runs' steps to about 0.6 of today's at 4 j (some 9-10 s of the case's CPU), but it moves
  the results: the rotational kinetic energy the quasi-static check counts, and the
  contacts' penalties, then calibrated on the critical step, softer by its square (since
  sized on the step at the closed j whatever j, docs/theory.md §6.2 "The penalty's step";
  the element rule then did not pay, docs/hemisphere_forming.md). These figures are of the
  case's [0/90] Mindlin run at its pace before it was slowed x2.
* shares of the march, Mindlin [0/90] / fibrous [0/90]: the two ply blocks' committed history
  0.403 / 0.321, of it the facing (all calls) 0.297 / 0.224: the whole facing's compiled pair
  0.136 / 0.117, the search's candidates 0.117 / 0.068, of which the full re-searches 0.061 /
  0.021 (807 searches in the Mindlin run, 786 of them new epochs: ~1-3 ms each on the top
  ply's block, 384 points and 128 triangles), the friction's history pass 0.042 / 0.043; the
  tool contacts' forces 0.156 / 0.136; the ply loads 0.106 / 0.114; the stable step 0.064 /
  0.071 (the ply springs' bound 0.054 / 0.056, every tenth step); the Mindlin shell's force
  0.040; the per-state caches' kept-bits tests 0.025 / 0.024 (226k calls in the Mindlin run);
  the output frames 0.020 / 0.023. No single part's Python above a few per cent: the step is
  spread over some fifty compiled calls.
* Tried, not kept: the full re-search by the matrix of every centroid's distance
  (elements/ply_search.py ``EVERY_PAIR`` raised past the top ply's block; the same lists) took
  4.3-7.0 ms a search against 1.4-4.1 ms by the k-d trees on the four runs' top-ply blocks at
  the start and two jittered states (load 10-11): slower. The springs' bound's fixed tables
  (``outline_segments``, ``_wedge_corners``), rebuilt each call: 4.7 and 7.3-8.3 us a call on
  the Mindlin [0/90] blocks (32 outline edges), about 0.02 s a run: not worth a cache.
  The search's skin doubled (elements/ply_search.py ``SKIN`` 0.1 -> 0.2 of the mean edge, any
  skin giving the same lists' answer): the Mindlin [0/90] run the same to the bit (final
  positions and the energy and tool history), its searches 371 + 438 -> 177 + 218, but its CPU
  12.01 / 12.50 -> 12.13 / 12.30 s (two rounds each, back to back, load 8.0-10.1): the
  searches saved are paid back by more candidates in every facing. Not kept.
"""

from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(HERE))  # run from anywhere, no install

#: (label, file ending, function name): the entry points whose cumulative time is reported.
PARTS = (
    ("committed history (ply blocks)", "elements/ply_block.py", "update_history"),
    ("  the facing (all calls)", "elements/ply_block.py", "facing"),
    ("    front's call (faces, choice)", "elements/ply_facing_front.py", "begun"),
    ("    facing's second call", "elements/ply_facing_whole.py", "finished_facing"),
    ("    whole facing (compiled pair)", "elements/ply_facing_whole.py", "whole_facing"),
    ("    search's candidates", "elements/ply_block.py", "_candidates"),
    ("      full re-searches", "elements/ply_search.py", "_renew"),
    ("  friction history pass", "elements/ply_friction_pass.py", "history_pass"),
    ("tool contacts' forces", "femcore/compiled.py", "tool_forces"),
    ("ply loads", "elements/ply_block.py", "internal_force"),
    ("stable step", "solvers/explicit_step_size.py", "_step_size"),
    ("  ply springs' bound", "elements/ply_springs.py", "reachable_springs"),
    ("Mindlin shell force", "elements/mindlin.py", "internal_force"),
    ("kept-bits tests", "elements/kept_bits.py", "same_bits"),
    ("output frames", "solvers/output.py", "append"),
)


def run(kinematics: str, layup: str, cells: int, profile: bool) -> dict:
    """One run of the case's setup: steps, CPU (s), the first stable step's parts and, with
    ``profile``, the parts' shares of the march."""
    from solvers import CentralDifference
    from validation.studies import hemisphere_plies_setup as setup
    from validation.studies.hemisphere_plies_run import case_solver

    _, built = setup.model(cells, setup.LAYUPS[layup], kinematics, 20.0)
    compiled = built.compile()
    lowered: list[tuple[float, float]] = []
    original = CentralDifference._lowered

    def recording(self, critical, springs):
        lowered.append((critical, springs))
        return original(self, critical, springs)

    CentralDifference._lowered = recording  # type: ignore[method-assign]
    try:
        with tempfile.TemporaryDirectory() as folder:
            solver = case_solver(layup, kinematics, history=Path(folder) / "history.csv")
            profiler = cProfile.Profile() if profile else None
            start = time.process_time()
            if profiler is not None:
                profiler.enable()
            result = solver.solve(compiled)
            if profiler is not None:
                profiler.disable()
            cpu = time.process_time() - start
    finally:
        CentralDifference._lowered = original  # type: ignore[method-assign]
    steps = int(getattr(result, "steps", 0) or 0)
    critical, springs = lowered[0]
    bare = original(solver, critical, 0.0)
    out = {
        "steps": steps,
        "cpu": cpu,
        "cells dt": critical,
        "springs lower": original(solver, critical, springs) / bare,
    }
    if profiler is not None:
        stats = pstats.Stats(profiler).stats  # type: ignore[attr-defined]
        march = max(v[3] for k, v in stats.items() if k[2] == "_march")
        for label, ending, name in PARTS:
            found = [v[3] for k, v in stats.items() if k[0].endswith(ending) and k[2] == name]
            out[label] = sum(found) / march
    return out


def rotary_steps(cells: int, factors: tuple[float, ...]) -> list[tuple[float, float]]:
    """(factor, critical step s) of the Mindlin [0/90] plies' first cell (the mesh's cells
    are congruent) with its rotary inertia j times each of ``factors`` (1: the model's own,
    docs/theory.md §6.2 B2): which modes set the Mindlin plies' step."""
    from validation.studies import hemisphere_plies_setup as setup

    _, built = setup.model(cells, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled = built.compile()
    shell = next(part for part in compiled.parts if hasattr(part, "rotary_factor"))
    x0, v0 = shell._reference_cells()
    own = shell.rotary_factor.copy()
    found = []
    try:
        for factor in factors:
            shell.rotary_factor = own * factor
            omega2 = float(shell.element_omega2(x0[:1], v0[:1], np.arange(1))[0])
            found.append((factor, 2.0 / np.sqrt(omega2)))
    finally:
        shell.rotary_factor = own
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", default="mindlin:0/90,fibrous:0/90")
    parser.add_argument("--cells", type=int, default=8)
    parser.add_argument("--profile", action="store_true")
    parser.add_argument("--rotary", action="store_true", help="the Mindlin cells' step by j")
    args = parser.parse_args()
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")
    print(f"load {os.getloadavg()}")
    if args.rotary:
        for factor, step in rotary_steps(args.cells, (1.0, 2.0, 4.0, 8.0, 100.0)):
            print(f"Mindlin cell, rotary inertia x{factor:g}: critical step {step:.3e} s")
    for item in filter(None, args.runs.split(",")):
        kinematics, layup = item.split(":")
        timed = run(kinematics, layup, args.cells, False)
        line = f"{kinematics} [{layup}]: {timed['steps']} steps, {timed['cpu']:.2f} s CPU, "
        line += f"{1e3 * timed['cpu'] / max(timed['steps'], 1):.3f} ms a step, "
        line += f"cells dt {timed['cells dt']:.3e} s, springs lower x{timed['springs lower']:.3f}"
        print(line)
        if args.profile:
            shares = run(kinematics, layup, args.cells, True)
            for label, _, _ in PARTS:
                print(f"    {label:34s} {shares[label]:.3f}")
    print(f"load {os.getloadavg()}")


if __name__ == "__main__":
    main()
