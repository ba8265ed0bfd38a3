"""Cost of the ply contact's facing call and internal force with the lower face's topology made
once at bind (elements/ply_topology.py: the half-edge neighbours, the pseudonormals summed at
the touched edges and vertices only) against the code before it (``BASE``'s
elements/ply_projection.py, loaded from git: the edge ids' argsort and the whole face's
pseudonormals at every call), side by side in one run, one thread, CPU time
(``time.process_time``), the machine's load printed.

The model: the two-ply Mindlin [0/90] hemisphere (validation/studies/hemisphere_plies_setup.py)
at 10, 40 and 100 cells (200, 3200 and 20000 triangles a ply), both ply contacts (the top
ply's Gauss points, the mirrored pass at the bottom ply's nodes). The nodes lie at noise of
``NOISE`` mm about the flat layup (points on edges and at vertices, growths past the
outline), and each call moves them as an explicit step does (all down by ``DENT``, noise of
``STEP``), the blocks' kept facing cleared; the old and new blocks are copies with their
own kept lists, called in turns (which goes first alternates). Each call's facing, forces and
energy are checked equal, bit for bit.

Measured (one thread, 20 calls, 1-minute load 3.0-3.6, other jobs on the 2 cores), ms per
call, CPU, both passes; the pieces: the whole face's pseudonormals and the edge ids' sort
(before) against the pseudonormals at the touched rows and the neighbour table's look-up
(after), at the last state, 20 repeats:

| cells (triangles a ply) | facing old / new | internal force old / new | pieces before / after |
|---|---|---|---|
| 10 (200) | 3.35 / 3.21 | 3.61 / 3.49 | 0.50 / 0.40 |
| 40 (3200) | 27.7 / 25.4 | 29.7 / 27.7 | 3.56 / 0.61 |
| 100 (20000) | 284 / 267 | 290 / 281 | 20.9 / 1.26 |

An earlier run (load 2.6-3.9): facing 3.19 / 3.18, 27.2 / 25.3, 287 / 280; force 3.58 / 3.48,
29.0 / 27.2, 316 / 290; a later one (load 4.5-8.0): facing 3.75 / 3.82, 29.0 / 26.9, 312 / 281;
force 4.17 / 4.36, 31.4 / 29.4, 303 / 297 (at 10 cells the two are within the noise). The
pieces per call went down 1.2 / 5.8 / 17 x, but they were 3-15 % of a call: the rest is the
candidates' planes and projections (``facets``, the reductions), the faces' offsets and the
fade, as before. The outline's nearest edge (``ply_fade.tree_segments``) of the points near
the outline, a tree built at the call against the kept tree (``ply_fade.OutlineTree``, built
once over the 2 x 20 calls of each pass, load 4.5-8.0): 1.19 / 0.97 ms at 40 cells, 2.41 /
2.07 ms at 100 cells; at 10 cells every pair is measured (below ``EVERY_PAIR``), no tree.

The coarse hemisphere-plies case (``python -m validation --cases hemisphere-plies --resolution
coarse``, one thread): its results.json the same as ``BASE``'s but for the times; its CPU 96.6
(``BASE``) and 126.6 s (this code, its compiled caches cold) run one after the other, 130.4
(``BASE``) and 100.3 s (this) run at once (load 3-8): within the machine's noise, the 0/90 run
alone going 39.6-71.9 s on the same code. Its plies are 10-16 cells: the contact's pieces
above are a few tenths of a ms a call there.

Run: python benchmarks/ply_topology.py [--calls 30] [--cells 10 40 100]
"""

from __future__ import annotations

import argparse
import copy
import os
import subprocess
import sys
import time
import types
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # run from anywhere

from elements import ply_block, ply_fade  # noqa: E402
from elements.ply_block import PlyContactBlock  # noqa: E402
from elements.ply_projection import pseudonormals, pseudonormals_at  # noqa: E402
from femcore.state import State  # noqa: E402

#: The commit whose elements/ply_projection.py is the reference pass.
BASE = "6a919d4"
#: The nodes' noise about the flat layup, mm.
NOISE = 0.05
#: Each call's own noise, mm, and the layup's fall a call, mm (explicit steps: the search's
#: kept lists serve).
STEP = 1e-4
DENT = 4e-3
#: Repeats of the pieces' own measure.
REPEATS = 20


def _old_projection() -> types.ModuleType:
    source = subprocess.run(
        ["git", "show", f"{BASE}:elements/ply_projection.py"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    module = types.ModuleType("ply_projection_base")
    exec(compile(source, "ply_projection_base.py", "exec"), module.__dict__)
    return module


def _equal(a, b) -> bool:
    return all(
        np.array_equal(x, y, equal_nan=True)
        for x, y in zip(vars(a).values(), vars(b).values())
        if isinstance(x, np.ndarray)
    )


def run(cells: int, calls: int, old_facing) -> None:
    from validation.studies import hemisphere_plies_setup as setup

    _, model = setup.model(cells, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled = model.compile()
    new = [b for b in compiled.interactions if isinstance(b, PlyContactBlock)]
    old = [copy.deepcopy(b) for b in new]
    n = compiled.mesh.n_nodes
    rng = np.random.default_rng(0)
    directors = np.tile([0.0, 0.0, 1.0], (n, 1))
    zero = np.zeros((n, 3))
    totals = {(code, what): 0.0 for code in ("old", "new") for what in ("facing", "force")}
    real = ply_block.closest_facing

    def before(*args, topology=None, outline_tree=None, **kwargs):
        return old_facing(*args, nodes=topology.nodes, edges=topology.edges, **kwargs)

    rough = compiled.mesh.points + rng.normal(0.0, NOISE, (n, 3))
    for call in range(calls):
        moved = rough + rng.normal(0.0, STEP, (n, 3))
        moved[:, 2] -= DENT * call
        state = State(moved, directors, zero, zero)
        kept = {}
        for code in ("old", "new") if call % 2 == 0 else ("new", "old"):
            blocks = old if code == "old" else new
            ply_block.closest_facing = before if code == "old" else real  # type: ignore[assignment]
            for what in ("facing", "force"):
                start = time.process_time()
                for block in blocks:
                    block._facing_at = None
                    if what == "facing":
                        kept[code, block.mirrored] = block.facing(state)
                    else:
                        kept[code, block.mirrored, "F"] = block.internal_force(state)
                totals[code, what] += time.process_time() - start
        ply_block.closest_facing = real
        for mirrored in (False, True):
            assert _equal(kept["old", mirrored], kept["new", mirrored])
            for a, b in zip(kept["old", mirrored, "F"], kept["new", mirrored, "F"]):
                assert np.array_equal(a, b)
    # the pieces themselves, at the last state: the whole face's pseudonormals and the edge
    # ids' sort (before) against the pseudonormals at the rows the off-triangle points touch
    pieces = {"before": 0.0, "after": 0.0, "tree built": 0.0, "tree kept": 0.0}
    for block in new:
        facing = block.facing(state)
        off = np.flatnonzero(np.any(facing.weights < -1e-9, axis=1))
        rows = facing.triangle[off]
        corner = np.argmin(facing.weights[off], axis=1)
        y = block._faces(state)[1]
        topology = block.topology
        for _ in range(REPEATS):
            start = time.process_time()
            pseudonormals(y, topology.nodes, topology.edges)
            flat = topology.edges.ravel()
            order = np.argsort(flat, kind="stable")
            np.searchsorted(flat[order], flat, side="left")
            np.searchsorted(flat[order], flat, side="right")
            middle = time.process_time()
            pseudonormals_at(y, topology, topology.nodes[rows, corner], rows * 3 + corner)
            topology.other[rows * 3 + corner]
            pieces["after"] += time.process_time() - middle
            pieces["before"] += middle - start
        # the outline's nearest edge of the points near it: a tree built, the kept tree
        near = np.flatnonzero(facing.fade_edge >= 0)
        starts = y[topology.segment_rows, topology.segment_ends[:, 0]]
        ends = y[topology.segment_rows, topology.segment_ends[:, 1]]
        if len(near) * len(starts) > ply_fade.EVERY_PAIR:
            for _ in range(REPEATS):
                start = time.process_time()
                built = ply_fade.tree_segments(facing.face[near], starts, ends)
                middle = time.process_time()
                kept_tree = ply_fade.tree_segments(
                    facing.face[near], starts, ends, block.outline_tree
                )
                pieces["tree kept"] += time.process_time() - middle
                pieces["tree built"] += middle - start
                assert np.array_equal(built, kept_tree)
    triangles = len(new[0].cells)
    points = sum(len(b.above) for b in new)
    print(f"{cells} cells: {triangles} triangles a ply, {points} points (both passes)")
    for what in ("facing", "force"):
        o, w = (1e3 * totals[c, what] / calls for c in ("old", "new"))
        print(f"  {what:>7}: old {o:8.3f}  new {w:8.3f} ms a call  ({o / w:.2f} x)")
    o, w = (1e3 * pieces[c] / REPEATS for c in ("before", "after"))
    print(f"  topology pieces (both passes): before {o:7.3f}  after {w:7.3f} ms a call")
    o, w = (1e3 * pieces[c] / REPEATS for c in ("tree built", "tree kept"))
    builds = [b.outline_tree.builds for b in new]
    print(
        f"  outline's nearest edge: tree built {o:7.3f}  kept {w:7.3f} ms a call; builds {builds}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calls", type=int, default=30)
    parser.add_argument("--cells", type=int, nargs="+", default=[10, 40, 100])
    args = parser.parse_args()
    old_facing = _old_projection().closest_facing
    print("load", os.getloadavg())
    for cells in args.cells:
        run(cells, args.calls, old_facing)
    print("load", os.getloadavg())


if __name__ == "__main__":
    main()
