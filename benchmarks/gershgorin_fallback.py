"""The assembled stable step's bound (femcore/gershgorin.py) where it cannot stream: CPU and
peak beside the tangent's own formation (the floor the bound cannot go below).

Each case in a fresh process of its own (one numba thread), the sheet 40 x 30 mm jittered
(0.2 mm) and its directors tilted (0.2 rad), one warm call first:

* Mindlin strip 400 x 20 (16k cells, in rows): the cells' band (799) longer than the pieces
  would otherwise be (666): streamed in pieces of the band (``banded_piece``);
* Mindlin 320 x 313 (200k cells) with its nodes and cells shuffled: no banded order, every
  pair held;
* fibrous 160 x 140 (44.8k cells) as one block (streamed) and as two blocks split at
  x = 20 mm (their seam's nodes in both: held to the end, the rest streamed).

Printed per case: the bound's CPU seconds (best of ``--repeat``), whether it streamed (the
tangent formed once), the reference pass (the tangent's pieces formed and dropped, every
block, CPU best of ``--repeat``), their ratio, and the process's peak (MB, ru_maxrss).
The script measures the tree it lives in (it puts that tree first on the import path, before
PYTHONPATH): to compare two trees, run each tree's own copy from its root; a copy from before
this rule (142080a's) measures the tree named by PYTHONPATH.

Measured on the 2-core machine shared with other runs (load 3.1-3.4), this script on main
1606060 (every pair held by merging each piece into all the pairs so far; Mindlin pieces of
256 cells on the strip) -> now, the bound's CPU s (ratio to the tangent alone), peak MB, the
same step to the bit in each case:

    mindlin-strip      0.157 (2.01)  235 -> 0.114 (1.46)  201   (streamed now)
    mindlin-shuffled   4.532 (4.42)  707 -> 2.091 (2.07)  665
    fibrous-one        2.259 (1.07)  271 -> 2.100 (1.08)  272
    fibrous-two       11.492 (7.88)  553 -> 2.597 (1.71)  461

Before the pieces (main cfaff59: all pieces' sums concatenated, one sort), one process a
case and a script, load 4.5-6.0, CPU s and peak MB, cfaff59 / 1606060 / now: Mindlin
shuffled 200k 2.22-2.25 (871-904) / 4.83-4.86 (711) / 2.35-2.43 (668); fibrous two blocks
2.49 (610) / 12.32-12.33 (548-550) / 3.30-3.34 (458-462); the strip 0.17 (220) / 0.22 (221) /
0.14 (200). The fibrous two blocks' bound was its tangent formed twice: the streamed pass gave
up at the second block's first piece (its seam's nodes summed with the first block).

The seam's nodes (those of more than one block) held to the end in the hash table, the rest
streamed: main 142080a -> now, side by side (a ``git archive`` of 142080a, PYTHONPATH set to
each tree), the bound's CPU s (ratio to the tangent alone), peak MB, the same step to the bit:

    run 1, load 9.4-7.7, best of 2:
    fibrous-two        3.345 (1.81)  459 -> 1.990 (1.16)  267   (streamed now)
    fibrous-one        2.448 (1.15)  272 -> 2.490 (1.13)  270
    run 2, load 4.8-5.4, best of 3:
    fibrous-two        3.089 (1.78)  457 -> 1.972 (1.19)  268   (streamed now)
    mindlin-strip      0.131 (1.49)  201 -> 0.123 (1.43)  199
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import resource
import subprocess
import sys
import time

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

from pathlib import Path

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages


CASES = {
    "mindlin-strip": ("mindlin", 400, 20, False, False, 1),
    "mindlin-shuffled": ("mindlin", 320, 313, True, True, 1),
    "fibrous-one": ("fibrous", 160, 140, False, False, 1),
    "fibrous-two": ("fibrous", 160, 140, False, False, 2),
}


def build(kind, nx, ny, shuffle_nodes, shuffle_cells, blocks, seed=3):
    """The jittered sheet's compiled model and state."""
    from elements import FibrousShell, MindlinShell
    from femcore import Mesh, Model
    from femcore.rotation import rotate_about
    from materials import ElasticShell, presets

    mesh = Mesh.rectangle(40.0, 30.0, nx=nx, ny=ny)
    rng = np.random.default_rng(seed)
    points, cells = mesh.points.copy(), mesh.triangles.copy()
    if shuffle_nodes:
        new = rng.permutation(len(points))
        moved = np.empty_like(points)
        moved[new] = points
        points, cells = moved, new[cells]
    if shuffle_cells:
        cells = cells[rng.permutation(len(cells))]
    model = Model(Mesh(points, cells))

    def element():
        if kind == "mindlin":
            return MindlinShell(ElasticShell(70e3, 0.3, 1.0, 2.7e-9))
        return FibrousShell(presets.g986_stack())

    if blocks == 1:
        model.add(element())
    else:
        middle = points[cells].mean(axis=1)[:, 0]
        model.add(element(), np.flatnonzero(middle < 20.0))
        model.add(element(), np.flatnonzero(middle >= 20.0))
    model.fix(np.flatnonzero(points[:, 0] == 0.0))
    compiled = model.compile()
    state = compiled.initial_state()
    positions = state.positions + rng.normal(scale=0.2, size=state.positions.shape)
    turn = np.cross(state.directors, rng.normal(scale=0.2, size=state.positions.shape))
    state = dataclasses.replace(
        state, positions=positions, directors=rotate_about(state.directors, turn)
    )
    return compiled, state


def run_case(name: str, repeat: int) -> None:
    from femcore import gershgorin

    compiled, state = build(*CASES[name])
    mass, inertia = compiled.lumped_mass(state)
    streamed = []
    # (main 1606060 named it _summed, with stream=True or False: the same figures for it)
    name_of = "_streamed" if hasattr(gershgorin, "_streamed") else "_summed"
    stream = getattr(gershgorin, name_of)

    def watched(*args, **options):
        result = stream(*args, **options)
        if options.get("stream", True):
            streamed.append(result is not None)
        return result

    setattr(gershgorin, name_of, watched)
    compiled.assembled_stable_dt(state, mass, inertia)  # warm
    bound, formed = [], []
    for _ in range(repeat):
        start = time.process_time()
        step = compiled.assembled_stable_dt(state, mass, inertia)
        bound.append(time.process_time() - start)
        start = time.process_time()
        for block in compiled.blocks:
            for piece in block.tangent_pieces(state):
                del piece
        formed.append(time.process_time() - start)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(
        f"{name:18s} cells {2 * CASES[name][1] * CASES[name][2]:7d} "
        f"streamed {streamed[-1]!s:5s} bound {min(bound):6.3f} s  tangent alone "
        f"{min(formed):6.3f} s  ratio {min(bound) / min(formed):5.2f}  peak {peak:6.0f} MB  "
        f"dt {float(step).hex()}",
        flush=True,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", default=",".join(CASES))
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--case", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.case:
        run_case(args.case, args.repeat)
        return
    print("load:", os.getloadavg(), flush=True)
    for name in args.cases.split(","):
        command = [sys.executable, __file__, "--case", name, "--repeat", str(args.repeat)]
        subprocess.run(command, check=True)
    print("load:", os.getloadavg(), flush=True)


if __name__ == "__main__":
    main()
