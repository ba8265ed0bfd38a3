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

Measured (one thread, 30 calls, 1-minute load 2.0-3.2, other jobs on the 2 cores), ms per
call, CPU, both passes:

(figures below)

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

from elements import ply_block  # noqa: E402
from elements.ply_block import PlyContactBlock  # noqa: E402
from femcore.state import State  # noqa: E402

#: The commit whose elements/ply_projection.py is the reference pass.
BASE = "6a919d4"
#: The nodes' noise about the flat layup, mm.
NOISE = 0.05
#: Each call's own noise, mm, and the layup's fall a call, mm (explicit steps: the search's
#: kept lists serve).
STEP = 1e-4
DENT = 4e-3


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

    def before(*args, topology=None, **kwargs):
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
    triangles = len(new[0].cells)
    points = sum(len(b.above) for b in new)
    print(f"{cells} cells: {triangles} triangles a ply, {points} points (both passes)")
    for what in ("facing", "force"):
        o, w = (1e3 * totals[c, what] / calls for c in ("old", "new"))
        print(f"  {what:>7}: old {o:8.3f}  new {w:8.3f} ms a call  ({o / w:.2f} x)")


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
