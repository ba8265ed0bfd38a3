"""The ply contact's facing compiled (elements/ply_kernels.py) against its numpy reference
(``ply_projection.COMPILED = False``), side by side in one process, CPU, one thread:

* the facing per state (both passes) of the two-ply Mindlin [0/90] hemisphere blank of
  validation/studies/hemisphere_plies_setup.py at ``--cells``, on ``--states`` states bent
  into a bowl and jittered (some points past the candidates' edges, as in a run), each
  block's facing computed afresh per state;
* CPU per explicit step over the first ``--steps`` steps of the hemisphere-plies case's run
  (fibrous [0/90] at the case's 8 cells, holder 20 N: validation/studies/
  hemisphere_plies_run.py's model and solver), stopped at a step boundary.

Both alternate, best of ``--repeats``; the machine's load is printed.

    python benchmarks/ply_facing.py

Where a step's time goes (the same stretch, fibrous [0/90], 8 cells, 1500 steps, one
thread, each function's CPU summed; load 9-10, main 5523c00): 6.0 ms a step, of which the
ply contact's facing 3.2 ms (53 %: the search's candidates 0.5, the candidates' planes
0.55, the closest points on edges and cuts 0.35, the feature normals' pseudonormals 0.3,
the outline's fade 0.65, the rest of ``closest_facing``'s numpy calls about 0.7), the ply
contact's loads and friction 1.2 ms (20 %), the elements' forces and the tools' contact
0.3 ms (5 %), the rest (the step, the checks, the records) 1.3 ms. With the kernels (same
stretch, load 6-7): the facing 49 % of the step, its planes and edges' closest points
under 0.5 % (0.03 ms), the fade 8 %, the feature normals 5 %, the cuts 4 %, the rest of
``closest_facing`` about 17 % (numpy calls on arrays of a few hundred rows); the loads and
friction 22 %. plies-bai-5.1 at coarse (Static, 4 plies; cProfile, so Python calls
over-counted): 79.6 s, of which the ply facing 42 s (53 %), its search re-listing the
candidates after Newton's jumps 19.5 s (the cut growths' closest points 9.6 s of it), the
ply tangent 17 s, the Mindlin tangent 6 s, the factorisations 4 s.

Measured (one thread, 2 cores shared with other work):

* this script, fcd7db7, load 5.0-7.3: the facing 9.57 -> 7.20 ms a state (x 1.33), the step
  5.84 -> 5.04 ms (x 1.16), numpy -> compiled (both sides with the faces kept per state and
  femcore.rotation's cross product, not switched by the flag); at 605fbac, load 9.2-6.7:
  11.03 -> 8.93 (x 1.23) and 6.20 -> 5.65 (x 1.10); at e5761d7 (the planes and the edges'
  closest points alone), load 10-12: 11.31 -> 10.05 and 6.33 -> 5.47;
* the step against main 5523c00 (the same stretch run from each tree, alternating, load
  6.7-7.0): 7.02 / 7.52 ms (main) against 5.22 / 5.28 ms (fcd7db7), x 1.33-1.42;
* the faces kept and the cross product alone (main beside e5761d7's parent, load 9-10):
  6.6-6.8 -> 5.8-5.9 ms.

The facing and the forces are the same to the bit on either side (tests/test_ply_kernels.py),
and the whole hemisphere-plies case at coarse gave the same results.json numbers to the bit
as main's (its times aside).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from elements import ply_projection  # noqa: E402
from elements.ply_block import PlyContactBlock  # noqa: E402
from femcore.state import State  # noqa: E402
from solvers import CentralDifference  # noqa: E402
from solvers.common import SolverError  # noqa: E402
from solvers.interrupts import STOP, interruptible  # noqa: E402
from validation.studies import hemisphere_plies_setup as setup  # noqa: E402


def bent_states(compiled, count: int) -> list[State]:
    """``count`` states of the blank pressed into a bowl (up to 10 mm deep at the pole) and
    jittered by up to 5e-3 mm, its directors tilted by about 0.01 rad."""
    x0 = compiled.mesh.points
    n = len(x0)
    rng = np.random.default_rng(0)
    radius = np.linalg.norm(x0[:, :2], axis=1)
    states = []
    for s in range(count):
        x = x0 + rng.normal(0.0, 1e-3 * (1 + s % 5), x0.shape)
        x[:, 2] -= 0.002 * (s % 6) * np.maximum(0.0, 60.0 - radius) ** 1.5
        d = np.tile([0.0, 0.0, 1.0], (n, 1)) + rng.normal(0.0, 0.01, (n, 3))
        d /= np.linalg.norm(d, axis=1)[:, None]
        states.append(State(x, d, np.zeros((n, 3)), np.zeros((n, 3))))
    return states


def facing_ms(blocks, states) -> float:
    """CPU ms a state of both passes' facing, computed afresh."""
    start = time.process_time()
    for state in states:
        for block in blocks:
            block._facing_at = None
            block._faces_at = None
            block.facing(state)
    return (time.process_time() - start) / len(states) * 1e3


def stretch_ms(compiled, steps: int) -> float:
    """CPU ms a step over the first ``steps`` explicit steps of the case's run."""
    commit = type(compiled).commit
    count = [0]

    def counted(state):
        count[0] += 1
        if count[0] >= steps:
            STOP.signal = "SIGINT"  # stops the run at this step's end, keeping its frames
        return commit(compiled, state)

    compiled.commit = counted
    solver = CentralDifference(
        duration=setup.DURATION,
        damping=setup.DAMPING,
        progress=False,
        output_interval=setup.DURATION / 100,
    )
    with interruptible():
        start = time.process_time()
        try:
            solver.solve(compiled)
        except SolverError:
            pass
        elapsed = time.process_time() - start
    del compiled.commit
    return elapsed / count[0] * 1e3


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cells", type=int, default=10, help="cells across the facing's blank")
    parser.add_argument("--states", type=int, default=30, help="states timed per round")
    parser.add_argument("--steps", type=int, default=300, help="explicit steps per round")
    parser.add_argument("--repeats", type=int, default=3, help="rounds (best CPU)")
    args = parser.parse_args()
    print(f"load {os.getloadavg()[0]:.2f}")
    _, model = setup.model(args.cells, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled = model.compile()
    blocks = [b for b in compiled.interactions if isinstance(b, PlyContactBlock)]
    states = bent_states(compiled, args.states)
    _, run_model = setup.model(8, setup.LAYUPS["0/90"], "fibrous", 20.0)
    run = run_model.compile()
    best = {(what, flag): np.inf for what in ("facing", "step") for flag in (False, True)}
    for flag in (False, True):  # compiled and warmed up before timing
        ply_projection.COMPILED = flag
        facing_ms(blocks, states[:2])
        stretch_ms(run, 5)
    for _ in range(args.repeats):
        for flag in (False, True):
            ply_projection.COMPILED = flag
            best["facing", flag] = min(best["facing", flag], facing_ms(blocks, states))
            best["step", flag] = min(best["step", flag], stretch_ms(run, args.steps))
    ply_projection.COMPILED = True
    print(f"facing, both passes, {args.cells} cells, ms a state (best of {args.repeats}, CPU): "
          f"numpy {best['facing', False]:.3f}, compiled {best['facing', True]:.3f} "
          f"(x {best['facing', False] / best['facing', True]:.2f})")  # fmt: skip
    print(f"explicit step, fibrous [0/90], 8 cells, first {args.steps} steps, ms (CPU): "
          f"numpy {best['step', False]:.3f}, compiled {best['step', True]:.3f} "
          f"(x {best['step', False] / best['step', True]:.2f})")  # fmt: skip
    print(f"load {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
