"""The ply contact's facing, loads and friction compiled (elements/ply_kernels.py and the
kernels named below) against their numpy reference (``ply_projection.COMPILED = False``),
side by side in one process, CPU, one thread:

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
thread, each function's CPU summed with a timer round it, so a little over the step's own).
Before the kernels (load 9-10, main 5523c00): 6.0 ms a step, the ply contact's facing 53 %,
its loads and friction 20 %. With the candidates' planes and the edges' closest points
compiled (elements/ply_kernels.py, load 5.3-5.6, c0b0822): 4.75-4.94 ms, the facing 49 %
(``closest_facing`` 1.7 ms: the outline's fade 0.40, the feature normals' pseudonormals 0.28,
the rest of its numpy calls on arrays of a few hundred rows about 0.95; the search's kept
lists 0.46), the loads 0.5 ms and the friction's return mapping 0.55 ms (twice a step: the
loads' and the committed history's, from two different histories), the history's own
update 0.45 ms. Now, with the rest compiled (the loads and their sums at the nodes,
elements/ply_load_kernels.py; the friction's return mapping and history,
elements/ply_friction_kernels.py; the choice of the facing candidate with the cut growths'
closest points, elements/ply_choice.py; the fade, elements/ply_fade_kernels.py; the feature
pseudonormals, elements/ply_feature_normals.py; the faces' normals, points and corners,
elements/ply_face_points.py; load 12.9, 8b3c767): 3.1 ms timed so (2.3 ms untimed), the
facing 1.74 ms (56 %: ``closest_facing`` 1.14, of which its remaining numpy calls about
0.63, the choice 0.13, the fade 0.12, the outline's nearest edge 0.10, the planes 0.08, the
edge gaps 0.05, the pseudonormals 0.03; the search's kept lists 0.25, since compiled too,
the faces 0.15), the
loads 0.15 ms, the friction's two return mappings 0.18 ms: the rest of the step is Python
glue round some forty compiled calls and numpy calls on small arrays. plies-bai-5.1 at
coarse (Static, 4 plies; cProfile, so Python calls over-counted, before these kernels):
79.6 s, of which the ply facing 42 s (53 %), its search re-listing the candidates after
Newton's jumps 19.5 s (the cut growths' closest points 9.6 s of it), the ply tangent 17 s,
the Mindlin tangent 6 s, the factorisations 4 s.

Measured (one thread, 2 cores shared with other work):

* this script, numpy -> compiled (``ply_projection.COMPILED``, which now switches the loads,
  the friction, the faces and the search's kept lists' moves too): with the chosen
  candidate's arrays and the fade's inputs gathered compiled as well (elements/
  ply_chosen.py), load 4.6-4.8: the facing 7.68 -> 4.24 ms a state (x 1.81), the step 5.29
  -> 1.70 ms (x 3.12); main 9aed8a2's own script beside it (load 3.0): 7.65 -> 4.38 and
  5.15 -> 1.82 ms; with the kept lists' moves compiled as well (elements/ply_search.py
  ``_moves``), load 16.1-16.6: the facing
  9.07 -> 5.31 ms a state (x 1.71), the step 6.30 -> 2.11 ms (x 2.98); at 8b3c767 (all but
  the kept lists' moves), load 13.0-13.8: the
  facing 9.24 -> 5.43 ms a state (x 1.70), the step 6.07 -> 2.26 ms (x 2.69); at ab19c8b
  (all but the faces), load 10.2-11.4: 9.18 -> 5.72 (x 1.61) and 6.48 -> 2.55 (x 2.54); at
  13320b0 (the loads and the friction), load 9.0-9.1: 8.69 -> 5.98 and 5.53 -> 3.01; at
  11e605f (the loads alone), load 11.0-11.4: 8.80 -> 6.56 and 5.84 -> 4.28; at fcd7db7
  (the planes and the edges' closest points, the faces kept per state and femcore.rotation's
  cross product, not switched by the flag), load 5.0-7.3: 9.57 -> 7.20 ms and 5.84 -> 5.04;
* the step against main 9aed8a2 (``git archive`` into /tmp; each tree's ``stretch_ms`` in
  a process of its own, best of 3 rounds of 300 steps, alternating, load 3.8-4.0): main
  1.844 / 1.860 / 1.905 / 1.931 ms against 1.693 / 1.697 / 1.700 / 1.666 ms with
  elements/ply_chosen.py (x 1.09-1.16; its ``chosen`` alone, load 3.5-4.2: 2.114 / 1.859 /
  1.775 / 1.843 against 1.934 / 1.650 / 1.659 / 1.795); ``closest_facing`` alone, a call on
  60 of the step's calls (both passes, 384 points, one candidate each), best of 5 rounds
  of 10, load 4.0-4.6: 286-308 µs (main) against 196-198 µs (x 1.5). Its split now, a
  call, each piece timed with the CPU clock round it (load 5): the candidates' planes 24 µs,
  the choice 70, the chosen candidate's arrays with its overshoot, reach past the outline
  and turn 16 (numpy's gathers and reductions for them about 70 on main), the flags on the
  growths and deeper than the plies 22 (numpy), the outline's segments and their nearest
  28, the fade 40 (62 on main: its inputs' gathers about 40 then, 18 now; the fade's own
  call 21), the result 8;
* the step against main 5523c00 (the same stretch run from each tree, alternating, load
  6.7-7.0): 7.02 / 7.52 ms (main) against 5.22 / 5.28 ms (fcd7db7), x 1.33-1.42.

Not compiled, measured: the numpy ``arctan2`` of the pseudonormals' angles and ``np.power``
of the penalty's cube (numpy's vectorised routines differ from libm's ``atan2`` and ``pow``
in the last bit: 1345 of 1e6 cubes; the kernels take them from numpy); the rest of
``closest_facing``'s numpy calls after the choice: the edge gaps' signs
(elements/ply_edge_gap.py, a few points a call), the flags on the growths (about 20 µs a
call), the outline segments' ends and ``every_segment``'s glue (about 25 µs), each kernel's
call through numba's dispatch (10-20 µs with 15-20 arguments). The facing
and the forces are the same to the bit on either side (tests/test_ply_kernels.py), and the
whole hemisphere-plies case gave the same results.json numbers to the bit as main c0b0822's
(its times aside) at coarse (55.5 s CPU against 102.2 s) and at the default resolution
(148.7 s against 288.1 s; validation/report.py EXPECTED_CPU_S).
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
from solvers.common import SolverError  # noqa: E402
from solvers.interrupts import STOP, interruptible  # noqa: E402
from validation.studies import hemisphere_plies_setup as setup  # noqa: E402
from validation.studies.hemisphere_plies_run import case_solver  # noqa: E402


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
    solver = case_solver("0/90", "fibrous")  # the model ``main`` gives
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
