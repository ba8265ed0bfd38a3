"""The stick potential's couple (elements/ply_friction.py ``stick_couple``, docs/theory.md
"Friction between plies"): its cost in the ply contact's tangent, the couple carried against
left out (``_couple_rows`` made all False: the tangent before), side by side in one run.

The model: tests/test_ply_kernels.py's two-ply Mindlin [0/90] hemisphere blank (8 cells,
validation/studies/hemisphere_plies_setup.py) bent 5 then 5.2 mm, both ply contact passes with
friction, the history committed at 5 mm (stuck and sliding anchors at 5.2); ``stick="normal
law"``. Timed: ``tangent`` (numpy, both passes), the facing kept (its cost is the same with
or without the couple), best of 5 repeats of 20 calls, CPU. The compiled loads compute the
couple in their one pass over the stuck points (elements/ply_load_kernels.py), a few dozen
operations a point: ``internal_force`` of both passes, best of 7 x 200 calls, took 0.219,
0.241, 0.222 ms before the couple (2ea6490) and 0.227, 0.235, 0.229 ms with it, the two code
trees run in turn (load 4.8-5.1): not told apart. Again, each tree (git archives of 2ea6490 and
6f096ef) with its packages first on the import path, in turn three times, the same blank and
calls (load 7.0-7.4): 0.189, 0.186, 0.190 ms before and 0.193, 0.192, 0.190 with the couple.

Measured (one thread, 2 cores shared), left out | carried, 63 stuck points all facing a plane,
three runs: tangent 40.5 | 40.9, 40.0 | 40.6, 41.2 | 41.4 ms a call (load 3.1-4.4).

Run: python benchmarks/ply_stick_couple.py
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numpy as np

if __name__ == "__main__":  # imported (ply_edge_couple.py), the importer's tree
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

from elements import ply_friction
from elements.ply_block import PlyContactBlock
from femcore.state import State
from validation.studies import hemisphere_plies_setup as setup


def _bent(compiled, depth: float) -> State:
    """The blank pressed ``depth`` mm (times (1 - r / 60 mm)^1.5) into a bowl about its pole,
    jittered 2e-3 mm, its directors tilted about 0.01 rad (tests/test_ply_kernels.py)."""
    x0 = compiled.mesh.points
    n = len(x0)
    rng = np.random.default_rng(3)
    radius = np.linalg.norm(x0[:, :2], axis=1)
    x = x0 + rng.normal(0.0, 2e-3, x0.shape)
    x[:, 2] -= depth * np.maximum(0.0, 1.0 - radius / 60.0) ** 1.5
    d = np.tile([0.0, 0.0, 1.0], (n, 1)) + rng.normal(0.0, 0.01, (n, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    return State(x, d, np.zeros((n, 3)), np.zeros((n, 3)))


def _best(call, repeats: int = 5, calls: int = 20) -> float:
    """The least CPU time of one call over ``repeats`` runs of ``calls`` calls, s."""
    best = np.inf
    for _ in range(repeats):
        start = time.process_time()
        for _ in range(calls):
            call()
        best = min(best, (time.process_time() - start) / calls)
    return best


def main() -> None:
    print(f"load before {os.getloadavg()[0]:.1f}", flush=True)
    _, model = setup.model(8, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled = model.compile()
    blocks = [b for b in compiled.interactions if isinstance(b, PlyContactBlock)]
    first, second = _bent(compiled, 5.0), _bent(compiled, 5.2)
    histories = [b.update_history(first, b.initial_history()) for b in blocks]
    for block, history in zip(blocks, histories):  # the facing kept at ``second``, warmed up
        block.tangent(second, history)
        block.internal_force(second, history)
    stuck = plane = 0
    for block, history in zip(blocks, histories):
        facing = block.facing(second, second=True)
        sliding = block.friction_state(second, history)
        stuck += int(sliding.stuck.sum())
        plane += int(np.sum(sliding.stuck & ~facing.on_edge))
    print(f"{stuck} stuck points, {plane} of them facing a plane", flush=True)
    carried = ply_friction._couple_rows

    def nowhere(block, sliding, facing, rows):
        return np.zeros(len(rows), dtype=bool)

    figures = {}
    for label, rows in (("left out", nowhere), ("carried", carried)):
        ply_friction._couple_rows = rows
        figures[label] = _best(lambda: [b.tangent(second, h) for b, h in zip(blocks, histories)])
    ply_friction._couple_rows = carried
    old, new = figures["left out"], figures["carried"]
    print(f"tangent  {1e3 * old:.1f} | {1e3 * new:.1f} ms a call (left out | carried)")
    print(f"load after {os.getloadavg()[0]:.1f}", flush=True)


if __name__ == "__main__":
    main()
