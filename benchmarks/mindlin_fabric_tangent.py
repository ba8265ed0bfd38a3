"""MindlinShell(fabric)'s analytic tangent: the compiled loop (elements/mindlin_fabric_tangent.py)
beside its numpy reference (MindlinFabricBlock.numpy_cell_tangent, the code before), on
bai-6.1.1's Mindlin corner (validation/cases/bai_6_1_1.py, the paper stack's fabric section).

Part 1: one tangent of the block on the case's default mesh and on its 40-cell one, jittered
(0.05 mm) with tilted directors (0.05 rad): CPU ms, best of ROUNDS, each pass beside the other,
and the largest difference over the largest entry.

Part 2: the case's Mindlin Static run on those meshes with the numpy tangent, then with the
compiled one, in this process: CPU s of the run and of its tangents, increments, Newton
iterations, cuts, and the largest difference of the final positions (mm).

Measured (one numba thread, CPU, 2 cores shared, load 3.5-3.8; best of 20):

  cells triangles  numpy ms  compiled ms   ratio  difference
     20       400      4.64         1.03     4.5    4.31e-16
     40      1600     11.07         3.95     2.8    6.04e-16

(before the loop formed only the rows the section reads: 1.19 and 4.81 ms at load 6). The
Static runs, the second pair of each (the first pays for building and compiling): 20 cells
0.62 -> 0.47 s, tangents 0.27 -> 0.12 s; 40 cells 2.59 -> 1.91 s, tangents 1.06 -> 0.45 s
(the tangents include their assembly); the same 20 increments, 73 and 74 iterations, no
cut, final positions within 2.8e-14 mm. Of the compiled 40-cell run (cProfile, 1.94 s):
the numpy forces 0.66 s (MindlinFabricBlock._cell_loads: _turned_gradients 0.48), the
factorisations 0.29, the tangent loop 0.19; of one compiled tangent at 1600 triangles (4.2
ms before the row cut) the numpy section measures 0.8 ms, the section response 0.26 ms, the
loop 2.7 ms.

Run from the project root (one numba thread):

    python benchmarks/mindlin_fabric_tangent.py [--rounds 10] [--cells 20,40]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from contextlib import contextmanager
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ["FIBRESHELL_PROGRESS"] = "0"
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

import numpy as np  # noqa: E402

import solvers.static as static  # noqa: E402
from benchmarks.paper_cases import best, build, spec_of  # noqa: E402
from elements.mindlin import MindlinShellBlock  # noqa: E402
from elements.mindlin_fabric import MindlinFabricBlock  # noqa: E402
from femcore.rotation import rotate_about  # noqa: E402
from validation.paper.case import solve  # noqa: E402

CASE = "bai-6.1.1"


@contextmanager
def numpy_tangent():
    """MindlinFabricBlock's tangent as before the compiled loop: the elastic block's slices of
    the numpy path through the fabric's level response."""
    saved = MindlinFabricBlock.tangent, MindlinFabricBlock._cell_tangent
    MindlinFabricBlock.tangent = MindlinShellBlock.tangent  # type: ignore[method-assign]
    MindlinFabricBlock._cell_tangent = MindlinFabricBlock.numpy_cell_tangent  # type: ignore[method-assign]
    try:
        yield
    finally:
        MindlinFabricBlock.tangent, MindlinFabricBlock._cell_tangent = saved  # type: ignore[method-assign]


def one_tangent(cells: int, rounds: int) -> str:
    """Part 1's line for the mesh of ``cells``."""
    compiled = build(spec_of(CASE), "mindlin", cells).compile()
    block = next(b for b in compiled.blocks if isinstance(b, MindlinFabricBlock))
    state = compiled.initial_state()
    rng = np.random.default_rng(0)
    positions = state.positions + rng.normal(scale=0.05, size=state.positions.shape)
    turn = np.cross(state.directors, rng.normal(scale=0.05, size=state.positions.shape))
    directors = rotate_about(state.directors, turn)
    moved = type(state)(**{**state.__dict__, "positions": positions, "directors": directors})

    def numpy_pass():
        with numpy_tangent():
            return block.tangent(moved)[0].blocks

    def compiled_pass():
        return block.tangent(moved)[0].blocks

    reference, fast = numpy_pass(), compiled_pass()
    difference = np.abs(fast - reference).max() / np.abs(reference).max()
    numpy_s, compiled_s = best(numpy_pass, rounds), best(compiled_pass, rounds)
    return (
        f"{cells:5d} {len(block.connectivity):9d} {1e3 * numpy_s:9.2f} {1e3 * compiled_s:12.2f}"
        f" {numpy_s / compiled_s:7.1f} {difference:11.2e}"
    )


def run(cells: int) -> tuple[str, np.ndarray]:
    """One Mindlin Static run of the case on ``cells``: its line and final positions."""
    spec = spec_of(CASE)
    spent = [0.0]
    original = static.StaticRun.tangent

    def timed(self, *args, **kwargs):
        started = time.process_time()
        try:
            return original(self, *args, **kwargs)
        finally:
            spent[0] += time.process_time() - started

    static.StaticRun.tangent = timed  # type: ignore[method-assign]
    try:
        model = build(spec, "mindlin", cells)
        started = time.process_time()
        result, _, _ = solve(model, spec.increments)
        cpu = time.process_time() - started
    finally:
        static.StaticRun.tangent = original  # type: ignore[method-assign]
    info = result.info
    line = (
        f"{cpu:6.2f} s, tangents {spent[0]:5.2f} s; {len(result.frames) - 1} increments, "
        f"{sum(info['iterations_per_increment'])} iterations, {info['cuts']} cuts, "
        f"{info['evaluations']['tangent']} tangents"
    )
    return line, result.positions


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=10)
    parser.add_argument("--cells", default="20,40", help="the meshes, comma list")
    parser.add_argument("--runs", type=int, default=1, help="Static runs of each pass")
    args = parser.parse_args(argv)
    meshes = [int(c) for c in args.cells.split(",")]
    print(f"load average before: {os.getloadavg()}")
    print(f"{'cells':>5s} {'triangles':>9s} {'numpy ms':>9s} {'compiled ms':>12s} {'ratio':>7s}"
          f" {'difference':>11s}")  # fmt: skip
    for cells in meshes:
        print(one_tangent(cells, args.rounds), flush=True)
    for cells in meshes:
        for _ in range(args.runs):
            with numpy_tangent():
                line, reference = run(cells)
            print(f"{CASE} Mindlin {cells} cells, numpy tangent:    {line}", flush=True)
            line, positions = run(cells)
            moved = np.abs(positions - reference).max()
            print(f"{CASE} Mindlin {cells} cells, compiled tangent: {line}; "
                  f"positions within {moved:.2e} mm of the numpy run's", flush=True)  # fmt: skip
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
