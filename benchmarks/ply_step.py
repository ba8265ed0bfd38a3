"""The two-ply explicit step's own cost: CPU per step over a window of the hemisphere-plies
case's fibrous [0/90] run (8 cells, holder 20 N: validation/studies/hemisphere_plies_run.py's
model and solver, its history file written as the case writes it), this tree beside a
reference tree (``--reference PATH``, e.g. a ``git archive`` of main), each round a fresh
process per tree, alternating, best of ``--repeats``, one thread; the machine's load printed.
The run goes from the start; the steps ``--start`` to ``--stop`` are timed (the tools move
with t / duration, so a window of the stroke is taken by its steps, not by a shorter run),
and the state at ``--stop`` is compared bit for bit between the trees (positions,
directors, velocities).

    NUMBA_NUM_THREADS=1 nice -n 5 python benchmarks/ply_step.py --reference /tmp/main

Where a step's time goes (main 81b7828, the same window, each function's CPU summed with a
timer round it, so a little over the step's own 2.3-2.7 ms; load 7-12): the commit 0.94 ms
(the new state's facing, both passes, 0.64: ``closest_facing`` 0.49, of which the outline's
fade 0.11, the choice 0.11, the edges' sides 0.08, the candidates' planes 0.05, the chosen
arrays 0.03, its numpy glue 0.10; the kept lists and the faces 0.16; the friction's
accepted history 0.19 with its two return mappings; the sides 0.08), the step 0.93 (the
forces 0.49: the ply loads 0.22 with the return mapping the commit kept for them, the two
fibrous plies 0.17, the tools from their cache), the tools' forces for the history rows
0.23 (the next step's forces take them from a cache), the stable step every 10 steps 0.20
a step, the rest the march's own bookkeeping. Each state's facing is made once (at the
commit) and served from the block's cache to the next step's loads, energy and springs:
the cost is the facing itself, some twenty compiled calls and their numpy glue a pass.

Measured (this script, best of 2-3, one thread, nice 5):

* the sides accepted at a commit from the flags its held facing was made with, the held
  facing kept for the new sides (elements/ply_sides.py ``accepted_sides``), and the
  per-state caches tested by their arrays' bits (elements/kept_bits.py) against main
  81b7828, load 2.8-5.7: 1.844 against 1.981 ms a step (0.931), again at load 4.6-6.4
  1.913 against 1.996 (0.958), the state at step 2500 identical to the bit (positions,
  directors, velocities); the sides alone 2.109 against 2.154 (0.979, one round, load
  4.5-6.1);
* the whole case (``python -m validation --cases hemisphere-plies --jobs 1`` from each tree,
  one after the other, both warm, load 6-7): 80.4 s of CPU (main) against 81.3 s, its four
  runs 11.88 / 21.16 / 14.95 / 25.70 against 11.58 / 21.86 / 15.59 / 25.47 s: the 4-7 %
  of the step lie within the case's own spread at that load; every number of its
  results.json but the times identical.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def window(start: int, stop: int, out: str) -> None:
    """Run the case's fibrous [0/90] run to step ``stop``, print the CPU per step (ms) of the
    steps ``start`` .. ``stop`` and save the state there to ``out`` (.npz)."""
    from femcore.state import State
    from solvers import CentralDifference
    from solvers.common import SolverError
    from solvers.interrupts import STOP, interruptible
    from validation.studies import hemisphere_plies_setup as setup

    _, model = setup.model(8, setup.LAYUPS["0/90"], "fibrous", 20.0)
    compiled = model.compile()
    commit = type(compiled).commit
    marks: dict[str, float] = {}
    count = [0]

    def counted(state: State) -> State:
        count[0] += 1
        if count[0] == start:
            marks["start"] = time.process_time()
        accepted = commit(compiled, state)
        if count[0] == stop:
            marks["stop"] = time.process_time()
            np.savez(
                out,
                positions=state.positions,
                directors=state.directors,
                velocities=state.velocities,
                time=state.time,
            )
            STOP.signal = "SIGINT"  # stops the run at this step's end
        return accepted

    compiled.commit = counted  # type: ignore[method-assign]
    with tempfile.TemporaryDirectory() as folder, interruptible():
        solver = CentralDifference(
            duration=setup.DURATION,
            damping=setup.DAMPING,
            progress=False,
            output_interval=setup.DURATION / 100,
            history=Path(folder) / "history.csv",
        )
        try:
            solver.solve(compiled)
        except SolverError:
            pass
    print(f"{(marks['stop'] - marks['start']) / (stop - start) * 1e3:.4f}")


def timed(tree: Path, start: int, stop: int, out: Path) -> float:
    """CPU ms a step of the window in a fresh process run from ``tree``'s root."""
    # the tree's packages first on the path (before an installed copy), this script's code
    environment = dict(os.environ, NUMBA_NUM_THREADS="1", PYTHONPATH=str(tree))
    done = subprocess.run(
        [
            sys.executable,
            str(Path(__file__).resolve()),
            "--window",
            str(start),
            str(stop),
            str(out),
        ],
        cwd=tree,
        env=environment,
        capture_output=True,
        text=True,
        check=True,
    )
    return float(done.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--reference", type=Path, help="the tree to compare with")
    parser.add_argument("--start", type=int, default=1700, help="first step timed")
    parser.add_argument("--stop", type=int, default=2500, help="last step timed")
    parser.add_argument("--repeats", type=int, default=3, help="rounds (best CPU)")
    parser.add_argument("--window", nargs=3, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.window:
        window(int(args.window[0]), int(args.window[1]), args.window[2])
        return
    trees = {"this": ROOT} | ({"reference": args.reference.resolve()} if args.reference else {})
    best = {name: np.inf for name in trees}
    print(f"load {os.getloadavg()}")
    with tempfile.TemporaryDirectory() as folder:
        for _ in range(args.repeats):
            for name, tree in trees.items():
                best[name] = min(
                    best[name], timed(tree, args.start, args.stop, Path(folder) / f"{name}.npz")
                )
        states = {name: np.load(Path(folder) / f"{name}.npz") for name in trees}
    for name in trees:
        print(f"{name}: {best[name]:.3f} ms a step, steps {args.start}-{args.stop} (best CPU)")
    if "reference" in trees:
        same = all(
            np.array_equal(states["this"][key], states["reference"][key])
            for key in ("positions", "directors", "velocities", "time")
        )
        print(f"ratio this / reference {best['this'] / best['reference']:.3f}; state at step "
              f"{args.stop} {'identical' if same else 'DIFFERENT'} to the bit")  # fmt: skip
    print(f"load {os.getloadavg()}")


if __name__ == "__main__":
    main()
