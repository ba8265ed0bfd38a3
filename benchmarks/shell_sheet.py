"""Shared piece of the shell benchmarks: explicit steps on a pinned square sheet under gravity.

Imported by ``fibrous_shell.py`` and ``mindlin_shell.py`` (run from the project root or from
anywhere: the scripts put the project on ``sys.path`` first).
"""

from __future__ import annotations

import math
import resource
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

from femcore import Mesh, Model
from solvers import CentralDifference

GRAVITY = (0.0, 0.0, -9810.0)  # mm/s^2


def pinned_sheet(element, triangles: int) -> Model:
    """A square sheet of ``element`` with about ``triangles`` cells (5 mm cells), pinned on
    its boundary, under gravity."""
    n = max(2, round(math.sqrt(triangles / 2)))
    model = Model(Mesh.rectangle(5.0 * n, 5.0 * n, nx=n, ny=n))
    model.add(element)
    for edge in ("left", "right", "bottom", "top"):
        model.fix(edge, ["ux", "uy", "uz"])
    model.gravity(GRAVITY)
    return model


def explicit_sheet(element, triangles: int, steps: int) -> dict:
    """``CentralDifference`` on a square sheet of ``element`` with about ``triangles`` cells
    (5 mm cells), pinned on its boundary and loaded by gravity from rest, for ``steps`` steps
    at 0.9 x the stable step; compilation excluded, frames only at the start and the end.
    Returns elements, nodes, steps, wall time and microseconds per element-step."""
    model = pinned_sheet(element, triangles)
    mesh = model.mesh
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


def reference_pass(triangles: int, repeats: int = 20, clock=time.perf_counter) -> float:
    """Microseconds per element of a minimal numpy gather-compute-scatter pass over the same
    sheet: gather the corners, one cross product per triangle, scatter it to the nodes (the
    yardstick the explicit step is measured against, in the same run); the best of
    ``repeats`` by ``clock`` (wall time; ``time.process_time`` for CPU time)."""
    n = max(2, round(math.sqrt(triangles / 2)))
    mesh = Mesh.rectangle(5.0 * n, 5.0 * n, nx=n, ny=n)
    points, cells = mesh.points, mesh.triangles
    best = math.inf
    for _ in range(repeats):
        started = clock()
        x = points[cells]
        normal = np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
        out = np.zeros((mesh.n_nodes, 3))
        for axis in range(3):
            out[:, axis] = np.bincount(
                cells.ravel(), np.repeat(normal[:, axis], 3), minlength=mesh.n_nodes
            )
        best = min(best, clock() - started)
    return 1e6 * best / len(cells)


def kernel_rows(make) -> dict:
    """The table rows of one element: ``make(kernel)`` with the numpy path, and the compiled
    loops on one thread and on every core numba may use (label "compiled/<threads>")."""
    import numba

    rows = {"numpy": lambda: make("numpy")}
    for threads in sorted({1, numba.config.NUMBA_NUM_THREADS}):

        def compiled(threads=threads):
            numba.set_num_threads(threads)  # holds for the run that follows
            return make("compiled")

        rows[f"compiled/{threads}"] = compiled
    return rows


def peak_memory_mb() -> float:
    """Peak resident memory of this process so far (MB; Linux reports kB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def print_explicit_table(title: str, element_factory, sizes, steps: int) -> None:
    """Print the explicit-step table for each size (a fresh element per size) and each of the
    factories ``element_factory`` names (a callable, or a dict label -> callable), with the
    reference pass of the same size and the peak memory so far."""
    factories = element_factory if isinstance(element_factory, dict) else {"": element_factory}
    print(title)
    print(
        f"{'elements':>9} {'nodes':>8} {'kernel':>9} {'steps':>6} {'wall s':>8} "
        f"{'us/elem-step':>13} {'ref us/elem':>12} {'x ref':>6} {'peak MB':>8}"
    )
    for factory in factories.values():  # compile (or load the compiled loops) first
        explicit_sheet(factory(), 200, 2)
    for size in sizes:
        reference = reference_pass(size)
        for label, factory in factories.items():
            row = explicit_sheet(factory(), size, steps)
            print(
                f"{row['elements']:9d} {row['nodes']:8d} {label:>9} {row['steps']:6d} "
                f"{row['wall_s']:8.2f} {row['us_per_element_step']:13.3f} {reference:12.3f} "
                f"{row['us_per_element_step'] / reference:6.1f} {peak_memory_mb():8.0f}",
                flush=True,
            )
