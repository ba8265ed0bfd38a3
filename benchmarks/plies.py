"""The plies model of Bai §5.1 against one fibrous shell on the same mesh and load: wall time of
a full quasi-static solve, one thread and the default threads.

The strip of cases/bai-5.1.toml (150 x 30 mm, 30 x 2 cells, the 20-ply G986 stack h = 6 mm,
clamped at x = 0, the far end moved by (-30, 0, -50) mm, gravity) as N sliding plies
(elements/plies.py: N Mindlin shells, N - 1 PlyContact) and as one FibrousShell (the reference
pass), each solved to equilibrium with solvers.Static: gravity over load factor 0-1, then the
end's displacement over 1-2 (step_loads_first), 10 increments per phase. The fibrous shell
takes the same solver as the plies here (the report's bai-5.1 follows the arc length; the load
path converges on this strip too), so the two times differ by the model alone. Prints the
Newton iterations, cuts and wall time of each solve, and the machine's load (os.getloadavg)
before and after, as other jobs share the cores.

Measured (2 cores shared, load 3.9 before, 8.1 after): one thread, fibrous shell 21.2 s (222
Newton iterations, 4 cuts), 4 plies 166.6 s (394 iterations, 7 cuts); two threads 51.7 s and
222.6 s (the same iterations: the load, not the threads, set those times). 20 plies were run
apart (one thread): no convergence at the first displacement increment after 35 min.

Run: python benchmarks/plies.py [N ...] [--curved | --flat]   (default N = 4 20; the default
threads are NUMBA_NUM_THREADS or the core count, and each model also runs on one thread;
--help lists the options)

``--curved``: the curved faces' facing search (elements/ply_curved.py) of a [0/45] pair laid
on the hemisphere's 50-mm punch sphere, 0.1 mm into each other and jittered by 0.05 mm
(200-mm blanks at 8 and 14 cells), with every candidate's patch projected on (the reference
pass) and with only those ``NEAR`` their flat facets: CPU and wall per call, best of 3 of 20
calls each, and whether the two choose the same patches and gaps for the touching points.
Measured (one thread, load 10.9, the hemisphere run beside it): 8 cells, 432 points x 6
candidates, 41.4 -> 17.5 ms CPU per call; 14 cells, 1200 points, 121.2 -> 52.8 ms; the same
touching points, patches and gaps (another run: 39.9 -> 14.3 and 104.3 -> 46.6 ms); 4 points
not touching, at the sphere's rim where the blank turns flat and no patch holds their
projection, face none instead of a far one.

``--flat``: the flat faces' contact force (search and loads) of that pair, best of 3 of 20
calls. Measured (one thread, load 11-12), this search (the nearest candidate by its true
distance, edges searched where they can be nearer) against the one before it (the deepest
holding triangle, else the nearest's extended plane), the same script run on each: 8 cells,
432 points, 5.7 against 3.2 ms of CPU; 14 cells, 1200 points, 14.6 against 10.5 ms.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path
from typing import Any

import numba
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

from elements import FibrousShell
from elements.plies import PlyStack
from femcore import Mesh, Model
from materials.presets import g986_stack
from solvers import Static

INCREMENTS = 10  # per phase: the plies' 4- and 8-ply solves needed 7 cuts at 10


def _load(model: Model, far) -> Model:
    model.fix(far("left"))
    model.displace(far("right"), ux=-30.0, uz=-50.0)
    model.gravity((0.0, 0.0, -9810.0))
    return model


def solve(model: Model) -> tuple[float, int, int, bool]:
    """(wall time s, Newton iterations, cuts, converged) of one quasi-static solve."""
    solver = Static(increments=INCREMENTS, step_loads_first=True, progress=False)
    start = time.perf_counter()
    try:
        result = solver.solve(model)
        converged = bool(result.converged)
    except Exception as error:  # a stalled solve is a figure too: report where it stopped
        result, converged = error.result, False  # type: ignore[attr-defined]
    wall = time.perf_counter() - start
    return wall, int(sum(result.info["iterations_per_increment"])), result.info["cuts"], converged


def fibrous(mid: Mesh) -> Model:
    model = _load(Model(mid), mid.nodes)
    model.add(FibrousShell(g986_stack(), clamped="left"))
    return model


def plies(mid: Mesh, count: int) -> Model:
    stack = PlyStack(mid, g986_stack(), count)
    return _load(stack.model(), stack.nodes)


def main(counts: list[int]) -> None:
    default = numba.get_num_threads()
    print(f"threads: 1 and {default} (NUMBA_NUM_THREADS={os.environ.get('NUMBA_NUM_THREADS')})")
    print(f"load before (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")
    mid = Mesh.rectangle(150.0, 30.0, nx=30, ny=2)
    solve(fibrous(Mesh.rectangle(150.0, 30.0, nx=4, ny=1)))  # compile the kernels once
    for threads in sorted({1, default}):
        numba.set_num_threads(threads)
        for label, build in [("fibrous shell", fibrous)] + [
            (f"{count} plies", lambda m, c=count: plies(m, c)) for count in counts
        ]:
            wall, iterations, cuts, converged = solve(build(mid))
            print(
                f"{threads} thread(s) {label:14s}: {wall:8.1f} s, {iterations:4d} Newton "
                f"iterations, {cuts} cuts, {'converged' if converged else 'NOT converged'}",
                flush=True,
            )
    print(f"load after  (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")


def _jittered_pair(ply, cells: int, **faces: str) -> tuple[Any, Any]:
    """A [0/45] pair of ``cells`` x ``cells`` plies laid on spheres of radius 50 and 50 + h -
    0.1 mm (0.1 mm into each other), its nodes jittered by 0.05 mm (seeded): (the bound ply
    contact, the state)."""
    from elements.layup import Layup
    from femcore.state import State

    layup = Layup(ply, (0.0, 45.0), 200.0, cells=cells, rule="gauss", **faces)
    block: Any = layup.model().compile().interactions[0]
    x = layup.mesh.points.copy()
    for k, nodes in enumerate(layup.ply_nodes):
        radius = 50.0 + k * (ply.thickness - 0.1)
        x[nodes, 2] = np.sqrt(np.maximum(radius**2 - np.sum(x[nodes, :2] ** 2, axis=1), 0.0))
    x += 0.05 * np.random.default_rng(1).standard_normal(x.shape)
    zero = np.zeros_like(x)
    return block, State(x, x / np.linalg.norm(x, axis=1)[:, None], zero, zero)


def curved() -> None:
    from elements import ply_curved
    from materials import Fabric

    ply = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)
    print(f"load before (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")
    for cells in (8, 14):
        block, state = _jittered_pair(ply, cells, surface="curved")
        p, near, y = block._candidates(state)
        figures = {}
        for every in (True, False):
            best = (np.inf, np.inf)
            for _ in range(3):
                cpu, wall = time.process_time(), time.perf_counter()
                for _ in range(20):
                    facing = ply_curved.curved_facing(block, state, p, y, near, every=every)
                cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
                best = (min(best[0], cpu / 20), min(best[1], wall / 20))
            figures[every] = (best, facing)
        full, chosen = figures[True][1], figures[False][1]
        on = full.touching
        same = np.array_equal(on, chosen.touching) and np.array_equal(
            full.triangle[on], chosen.triangle[on]
        )
        gaps = float(np.max(np.abs(full.gap[on] - chosen.gap[on]), initial=0.0))
        apart = int(np.sum(full.triangle != chosen.triangle))
        for every, label in ((True, "every candidate"), (False, "near ones")):
            (cpu, wall), _ = figures[every]
            print(
                f"{cells:2d} cells, {len(p)} points x {near.shape[1]} candidates, {label:15s}: "
                f"{1e3 * cpu:7.2f} ms CPU, {1e3 * wall:7.2f} ms wall per call"
            )
        print(
            f"   same touching points and patches: {same} ({on.sum()} touching), largest gap "
            f"difference {gaps:.2e} mm; {apart} points not touching face other patches"
        )
    print(f"load after  (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")


def flat() -> None:
    """The flat faces' contact force (search and loads) of the same jittered [0/45] pair."""
    from materials import Fabric

    ply = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)
    print(f"load before (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")
    for cells in (8, 14):
        block, state = _jittered_pair(ply, cells, faces="normal")
        best = (np.inf, np.inf)
        for _ in range(3):
            cpu, wall = time.process_time(), time.perf_counter()
            for _ in range(20):
                block.internal_force(state)
            cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
            best = (min(best[0], cpu / 20), min(best[1], wall / 20))
        print(
            f"{cells:2d} cells, {len(block.above)} points, flat faces: {1e3 * best[0]:7.2f} ms "
            f"CPU, {1e3 * best[1]:7.2f} ms wall per contact force"
        )
    print(f"load after  (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "counts", nargs="*", type=int, default=[4, 20], metavar="N",
        help="ply counts of the stacks solved beside the fibrous shell (default: 4 20)",
    )  # fmt: skip
    study = parser.add_mutually_exclusive_group()
    study.add_argument("--curved", action="store_true", help="the curved faces' facing search")
    study.add_argument("--flat", action="store_true", help="the flat faces' contact force")
    arguments = parser.parse_args()
    if arguments.flat:
        flat()
    elif arguments.curved:
        curved()
    else:
        main(arguments.counts)
