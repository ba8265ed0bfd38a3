"""The cost of the departure's slip in a ply contact's accepted history (elements/
ply_departure.py; docs/theory.md §9.3a, "A point's departure step"): an upper ply of 40 x 40
cells (9600 Gauss points) pressed 0.05 mm into a lower ply of 50 x 50 cells with friction, its
history's update (``update_history``, the compiled pass) timed when no point leaves and when
the points around a node or of a band of its cells leave, beside the same update with the
departure giving no rows (the rule before it), alternating, best of 15; then the departure pass
alone, and the machine's load.

    python benchmarks/ply_departure_cost.py

Measured (one process, load 0.8): no point leaving 0.94 / 0.92 ms against 0.92 / 0.92 ms
without the departure (its masks 0.05 ms); the 3 points about a node leaving 1.12 ms against
0.92 (the pass 0.20 ms: its numpy calls' fixed cost); 400 points 1.41 against 0.96 ms (0.47).
On the hemisphere-plies case's fibrous [0/90] run (10 cells, 20 N) over half its stroke's time,
whose points leave the lower face thousands of times, the run took 8.45 against 7.99 s of CPU
(one process, alternating, best of 2, load 1.0): 6 %, the pass's fixed cost in the steps where
points leave; a compiled pass would take most of it back (not done).
"""

from __future__ import annotations

import dataclasses
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(HERE))  # run from anywhere, no install


def main() -> None:
    import numpy as np

    from elements import MindlinShell, ply_departure
    from elements.ply_contact import PlyContact
    from femcore import Mesh, Model
    from materials import ElasticShell

    half, pressed = 0.1, 0.05
    lower = Mesh.rectangle(60.0, 60.0, nx=50, ny=50)
    upper = Mesh.rectangle(40.0, 40.0, nx=40, ny=40, origin=(10.0, 10.0, 2 * half - pressed))
    count = len(lower.points)
    mesh = Mesh(
        np.vstack([lower.points, upper.points]),
        triangles=np.vstack([lower.triangles, upper.triangles + count]),
        element_sets={
            "lower": np.arange(len(lower.triangles)),
            "upper": np.arange(len(lower.triangles), len(lower.triangles) + len(upper.triangles)),
        },
    )
    model = Model(mesh)
    shell = ElasticShell(E=70e3, nu=0.3, thickness=2 * half, density=2.7e-9)
    for name in ("lower", "upper"):
        model.add(MindlinShell(shell), cells=name)
    model.interact(
        PlyContact("upper", "lower", half, half, penalty=50.0, rule="gauss", friction=0.3)
    )
    compiled = model.compile()
    block = compiled.interactions[0]
    state = compiled.initial_state()
    upper_nodes = np.arange(count, len(mesh.points))

    def moved(shift, lifted=None):
        positions = state.positions.copy()
        positions[upper_nodes] += shift
        if lifted is not None:
            positions[lifted, 2] += 0.2
        return dataclasses.replace(state, positions=positions)

    history = block.initial_history()
    history = block.update_history(moved([0.05, 0.0, 0.0]), history)  # sliding
    band = upper_nodes[mesh.points[upper_nodes, 1] < 12.0]  # the first two rows of nodes
    rule = ply_departure.departure

    def none(block, y, history, facing):
        return np.zeros(0, dtype=np.int64), np.zeros(0)

    load = os.getloadavg()[0]
    for name, at in (
        ("no point leaves", moved([0.1, 0.0, 0.0])),
        ("a node's points leave", moved([0.1, 0.0, 0.0], band[20:21])),
        ("a band leaves", moved([0.1, 0.0, 0.0], band)),
    ):
        now, then, alone = [], [], []
        facing = block.facing(at)
        _, y = block._faces(at)
        for _ in range(15):
            ply_departure.departure = rule
            start = time.perf_counter()
            block.update_history(at, history)
            now.append(time.perf_counter() - start)
            ply_departure.departure = none
            start = time.perf_counter()
            block.update_history(at, history)
            then.append(time.perf_counter() - start)
            ply_departure.departure = rule
            start = time.perf_counter()
            rows, _ = rule(block, y, history, facing)
            alone.append(time.perf_counter() - start)
        print(
            f"{name} ({len(rows)} of {len(block.above)} points): update_history "
            f"{1e3 * min(now):.2f} ms, without the departure {1e3 * min(then):.2f} ms, the "
            f"departure alone {1e3 * min(alone):.3f} ms"
        )
    print(f"load {load:.1f} -> {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
