"""Shared piece of the shell benchmarks: explicit steps on a pinned square sheet under gravity.

Imported by ``fibrous_shell.py`` and ``mindlin_shell.py`` (run from the project root or from
anywhere: the scripts put the project on ``sys.path`` first).
"""

from __future__ import annotations

import math
import time

from femcore import Mesh, Model
from solvers import CentralDifference

GRAVITY = (0.0, 0.0, -9810.0)  # mm/s^2


def explicit_sheet(element, triangles: int, steps: int) -> dict:
    """``CentralDifference`` on a square sheet of ``element`` with about ``triangles`` cells
    (5 mm cells), pinned on its boundary and loaded by gravity from rest, for ``steps`` steps
    at 0.9 x the stable step; compilation excluded, frames only at the start and the end.
    Returns elements, nodes, steps, wall time and microseconds per element-step."""
    n = max(2, round(math.sqrt(triangles / 2)))
    mesh = Mesh.rectangle(5.0 * n, 5.0 * n, nx=n, ny=n)
    model = Model(mesh)
    model.add(element)
    for edge in ("left", "right", "bottom", "top"):
        model.fix(edge, ["ux", "uy", "uz"])
    model.gravity(GRAVITY)
    compiled = model.compile()
    dt = 0.9 * compiled.stable_dt(compiled.initial_state())
    solver = CentralDifference(duration=steps * dt, dt=dt, output_interval=steps * dt)
    started = time.perf_counter()
    result = solver.solve(compiled)
    wall = time.perf_counter() - started
    elements = len(mesh.triangles)
    return {
        "elements": elements,
        "nodes": mesh.n_nodes,
        "steps": result.steps,
        "wall_s": wall,
        "us_per_element_step": 1e6 * wall / (elements * result.steps),
    }


def print_explicit_table(title: str, element_factory, sizes, steps: int) -> None:
    """Print the explicit-step table for each size (a fresh element per size)."""
    print(title)
    print(f"{'elements':>9} {'nodes':>8} {'steps':>6} {'wall s':>8} {'us/elem-step':>13}")
    for size in sizes:
        row = explicit_sheet(element_factory(), size, steps)
        print(
            f"{row['elements']:9d} {row['nodes']:8d} {row['steps']:6d} {row['wall_s']:8.2f} "
            f"{row['us_per_element_step']:13.3f}"
        )
