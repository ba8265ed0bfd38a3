"""The ply springs' bound (elements/ply_springs.py ``reachable_springs``, asked every tenth
step by the explicit step's stable step through ``PlyContactBlock.springs_at``) and the
two-ply hemisphere's least-gap probe (validation/studies/hemisphere_plies_gaps.py
``least_gaps``), each beside the code of a reference tree in the same process, one thread,
CPU (``time.process_time``), best of ``--rounds``, the machine's load printed.

* the springs: the calls of a share ``--share`` of the hemisphere-plies run (validation/
  studies/hemisphere_plies_setup.py, 8 cells, ``--kinematics``, ``--layup``) captured (every
  fourth, at most 100), then replayed through this tree's ``reachable_springs`` and the
  reference tree's (its elements/ply_springs.py loaded beside this tree's modules), us a
  call, their answers compared bit for bit;
* the probe: each top-ply node's gap over the run's frames (``node_gaps``) by a probe of
  one point per node (rule "nodes", this tree) and of a point at each triangle corner
  ("vertices", the reference), s of CPU over the frames, the gaps compared bit for bit.

    python benchmarks/ply_springs_speed.py --reference /tmp/main

Measured (main cfaff59 as the reference, one thread, 2 cores shared with other jobs):

* the springs, fibrous [0/90], 100 calls of the first 0.6 of the run: 1035-1063 -> 334-338
  us a call (x 3.1, load 9.4; 927-940 -> 356-359 at load 4.3 before the weighted reach's
  pass); Mindlin [0/45] before that pass: 1210-1371 -> 432-453 (load 7.2); the same springs
  to the bit. Where it went before (a timer round each statement, load 3): the wedge
  corners' KD-tree asked of every point 388 us (now of the points near an outline edge
  alone), the outline's nearest edges by numpy's every pair 202 us (now
  ``ply_kernels.nearest_segments_at``), the nodes' weights and F_p 152 + 65 us (F_p now
  elements/ply_springs_kernels.py), the slide 116 us (now there too), the least height from
  every triangle's frame 77 us (now ``ply_kernels.largest_gradient``), the ring's transpose
  made twice a call as CSC (now kept as CSR: the same sums in the same order). What is left:
  the nodes' weights' numpy, the fade's factor and numpy's glue.
* the probe over the run's 101 frames: fibrous [0/90] 0.76 -> 0.28 s of CPU on the curved
  face, 0.16 -> 0.08 on the flat facets (load 4.4); Mindlin [0/45] 0.95 -> 0.35 and 0.23 ->
  0.11 (load 7.4); the same gaps to the bit.

Then (main fcee482 as the reference, one thread, load 3.3): the points near the outline,
their sizes and loads and the loads spread on the nodes in compiled passes
(elements/ply_springs_kernels.py ``near_outline``, ``held_points``, ``spread_loads``), the
outline's segments and wedge corners and the power iteration's first weights kept: Mindlin
[0/90], 100 calls of the first 0.6 of the run, 339-367 -> 161-186 us a call (x 2.0-2.1), the
same springs to the bit. Where the 480 us a call went before (a timer round each statement,
200 calls replayed, load 2.2): the points near the outline 154 us (the asked points'
gathers, the nearest edges' pass, numpy's distance and scatter; the wedges' KD-tree), the
nodes' weights 98 (their checks and first weights, three bincounts and scipy's product),
the slide 32, the fade's factor, the points counted and their sizes 52, F_p 21, the least
height 22. What is left: the KD-tree of the wedge corners (its build is most of the outline's
part), the slide's and F_p's passes, and numpy's glue of a dozen small arrays.

What they give the report's hemisphere-plies case: benchmarks/forming_step_overhead.py,
"Sixth round" and "Ninth round".
"""

from __future__ import annotations

import argparse
import copy
import importlib.util
import os
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(HERE))  # run from anywhere, no install


def captured_springs(kinematics: str, layup: str, share: float) -> list[tuple]:
    """Every fourth call of ``reachable_springs`` (at most 100) over the first ``share`` of
    the run: (block, state, facing, y, step, mass) each."""
    from elements import ply_springs
    from validation.studies import hemisphere_plies_setup as setup
    from validation.studies.hemisphere_plies_run import case_solver

    _, model = setup.model(8, setup.LAYUPS[layup], kinematics, 20.0)
    calls: list[tuple] = []
    original = ply_springs.reachable_springs

    def capture(block, state, facing, y, step=None, mass=None):
        if len(calls) < 400:
            held = None if mass is None else np.array(mass)
            calls.append((block, copy.deepcopy(state), facing, y.copy(), step, held))
        return original(block, state, facing, y, step, mass)

    ply_springs.reachable_springs = capture
    try:
        solver = case_solver(layup, kinematics, share, output_interval=None, kinetic_bound=None)
        solver.solve(model.compile())
    finally:
        ply_springs.reachable_springs = original
    return calls[::4]


def best_cpu(function, calls: list[tuple], rounds: int) -> float:
    """The best of ``rounds`` of the calls' CPU, us a call."""
    best = np.inf
    for _ in range(rounds):
        start = time.process_time()
        for call in calls:
            function(*call)
        best = min(best, time.process_time() - start)
    return best / max(len(calls), 1) * 1e6


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--reference", type=Path, required=True, help="a tree of the code before")
    parser.add_argument("--kinematics", default="fibrous", choices=("fibrous", "mindlin"))
    parser.add_argument("--layup", default="0/90", choices=("0/90", "0/45"))
    parser.add_argument("--share", type=float, default=0.6, help="of the run captured")
    parser.add_argument("--rounds", type=int, default=5)
    arguments = parser.parse_args()
    from elements import ply_springs
    from elements.layup import Layup
    from validation.studies import hemisphere_plies_gaps as gaps
    from validation.studies import hemisphere_plies_setup as setup
    from validation.studies.hemisphere_plies_run import case_solver

    spec = importlib.util.spec_from_file_location(
        "reference_ply_springs", arguments.reference / "elements" / "ply_springs.py"
    )
    assert spec is not None and spec.loader is not None
    reference = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(reference)
    calls = captured_springs(arguments.kinematics, arguments.layup, arguments.share)
    same = all(
        all(np.array_equal(a, b) for a, b in zip(reference.reachable_springs(*call),
                                                  ply_springs.reachable_springs(*call)))
        for call in calls
    )  # fmt: skip
    for _ in range(2):
        old = best_cpu(reference.reachable_springs, calls, arguments.rounds)
        new = best_cpu(ply_springs.reachable_springs, calls, arguments.rounds)
        print(f"springs, {arguments.kinematics} [{arguments.layup}], {len(calls)} calls: "
              f"reference {old:.0f} us a call, this {new:.0f} (x {old / new:.2f}); the same "
              f"bits: {same} (load {os.getloadavg()[0]:.1f})")  # fmt: skip

    layup, model = setup.model(8, setup.LAYUPS[arguments.layup], arguments.kinematics, 20.0)
    solver = case_solver(arguments.layup, arguments.kinematics, kinetic_bound=None)
    frames = [
        frame.positions[: layup.mesh.n_nodes] for frame in solver.solve(model.compile()).frames
    ]
    for surface in ("curved", "flat"):
        probes = {
            rule: Layup(setup.FABRIC, tuple(layup.angles), 2 * setup.HALF, cells=8, rule=rule,
                        surface=surface).model().compile().interactions[0]
            for rule in ("vertices", "nodes")
        }  # fmt: skip
        found, spent = {}, {}
        for rule, probe in probes.items():
            gaps.node_gaps(probe, layup, frames[0])  # kernels loaded
            start = time.process_time()
            found[rule] = [gaps.node_gaps(probe, layup, x) for x in frames]
            spent[rule] = time.process_time() - start
        same = all(
            np.array_equal(a, b, equal_nan=True) for a, b in zip(found["vertices"], found["nodes"])
        )
        print(f"probe, {surface} face, {len(frames)} frames: a point at each corner "
              f"{spent['vertices']:.3f} s, one per node {spent['nodes']:.3f} s; the same gaps "
              f"to the bit: {same} (load {os.getloadavg()[0]:.1f})")  # fmt: skip


if __name__ == "__main__":
    main()
