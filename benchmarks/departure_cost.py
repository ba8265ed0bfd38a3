"""The cost of the departure's slip in a tool contact's accepted step (elements/
contact_history.py ``departure``; docs/theory.md §9.2, "Leaving the tool"): a 100 x 100-cell
plate (10201 nodes) sliding on a 60 x 60 meshed table with friction, its history's update
(``accepted``) timed when no node leaves and when 100 leave, beside the same update from a
history without ``place`` (the departure then skipped: the rule before it), alternating, best
of 15; then the departure pass alone, and the machine's load.

    python benchmarks/departure_cost.py

Measured (one process, two runs, load 5.6): no node leaving 2.15 / 1.99 ms against 2.08 / 1.99
ms without the departure (its check 0.01 ms); 100 nodes leaving 2.88 / 2.62 against 2.23 / 2.06
ms, the pass alone 0.32 ms (the tool's exact distances at the 100 nodes' places, ends and
leaving points). A step where no node leaves costs what it did.
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import replace
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(HERE))  # run from anywhere, no install


def main() -> None:
    import numpy as np

    from elements import RigidSurface
    from elements.contact import Contact
    from elements.contact_history import accepted, departure
    from femcore import Body, Mesh
    from femcore.state import State

    plate = Mesh.rectangle(100.0, 100.0, nx=100, ny=100)
    points = plate.points + [0.0, 0.0, 0.45]  # 0.05 mm into the contact surface (h / 2 = 0.5)
    table = Mesh.rectangle(140.0, 140.0, nx=60, ny=60)
    tool = RigidSurface(table.with_points(table.points - [20.0, 20.0, 0.0]))
    contact = Contact(tool, offset=0.5, penalty=100.0, friction=0.2)
    block = contact.bind(Body.bare(Mesh(points, triangles=plate.triangles)))

    def at(x):
        zero = np.zeros_like(x)
        return State(x, zero, zero.copy(), zero.copy())

    history = block.update_history(at(points), block.initial_history())
    history = block.update_history(at(points + [0.01, 0.0, 0.0]), history)  # sliding
    before = replace(history, place=None)
    on = points + [0.02, 0.0, 0.0]
    off = on.copy()
    off[:100, 2] += 0.1  # 100 nodes leave the tool in the step
    load = os.getloadavg()[0]
    for name, x in (("no node leaves", on), ("100 nodes leave", off)):
        now, then = [], []
        for _ in range(15):
            start = time.perf_counter()
            accepted(block, at(x), history)
            now.append(time.perf_counter() - start)
            start = time.perf_counter()
            accepted(block, at(x), before)
            then.append(time.perf_counter() - start)
        where = block._positions(at(x)) - tool.offset(0.0)
        touching = block.touch(at(x), None)[2]
        alone = []
        for _ in range(15):
            start = time.perf_counter()
            departure(block, history, where, touching)
            alone.append(time.perf_counter() - start)
        print(
            f"{name}: accepted {1e3 * min(now):.2f} ms, without the departure "
            f"{1e3 * min(then):.2f} ms, the departure alone {1e3 * min(alone):.3f} ms "
            f"({len(points)} nodes)"
        )
    print(f"load {load:.1f} -> {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
