"""MindlinShell(fabric)'s analytic tangent and forces: the compiled loops
(elements/mindlin_fabric_tangent.py, elements/mindlin_fabric_loads.py) beside their numpy
references (MindlinFabricBlock.numpy_cell_tangent and numpy_cell_loads, the code before), on
bai-6.1.1's Mindlin corner (validation/cases/bai_6_1_1.py, the paper stack's fabric section).

Part 1: one tangent and one internal force of the block on the case's default mesh and on
its 40-cell one, jittered (0.05 mm) with tilted directors (0.05 rad): CPU ms, best of ROUNDS,
each pass beside the other, and the largest difference over the largest entry.

Part 2: the case's Mindlin Static run on those meshes with the numpy tangent and forces, with
the numpy tangent alone, then with both compiled, in this process: CPU s of the run and of
its tangents, increments, Newton iterations, cuts, and the largest difference of the final
positions (mm).

Measured (one numba thread, CPU, 2 cores shared, load 2.1-2.5; best of 20), one tangent and
one internal force of the block, ms, the numpy passes beside the compiled ones (scratch per
chunk of 64 cells; per cell it took 3.73 and 1.29 ms at 1600 triangles, shared before the
loop, a race on threads, 2.81 and 0.98):

  cells triangles  numpy ms  compiled ms   ratio  difference
     20       400      3.89         0.67     5.8    4.31e-16   forces   1.07 ->   0.25 ms, 1.29e-16
     40      1600      9.89         2.75     3.6    6.04e-16   forces   4.18 ->   0.94 ms, 1.41e-16

The Static runs, the second set of each (the first pays for building and compiling), CPU s
of the run / of its tangents (with their assembly): 20 cells numpy tangent and forces 0.56 /
0.24, numpy tangent 0.45 / 0.24, compiled 0.29 / 0.09; 40 cells 2.57 / 1.05, 1.96 / 1.05,
1.21 / 0.37. The same 20 increments, 73 and 74 iterations, no cut; final positions within
1.4e-14 mm of the numpy run's.

The whole case (``python -m validation --cases bai-6.1.1 --jobs 1``, one thread, warm numba
caches, load 1.4-1.7), this tree beside a copy of the tree before, alternately: 13.6, 12.3,
12.4 s of CPU before, 11.6, 11.2, 11.1 after (the loops' scratch shared then); with the scratch
a chunk's, at load 3.6-5.1 (wall 20-22 s): 14.0, 14.2 before, 12.8, 12.3 after; 13/13 checks
pass, results.json within 5.5e-12 (deg) and 1.5e-11 relative of before's.

Along the way (load 2-6): the tangent loop before it formed only the rows the section reads,
1.19 and 4.81 ms; with numpy's section measures, 0.98 and 3.78 ms, forces 0.48 and 1.73 ms.
A cProfile of the 40-cell run with the compiled tangent and the numpy forces (1.94 s): the
forces 0.66 s (numpy's batched B^psi 0.48), the factorisations 0.29, the tangent loop 0.19;
with everything compiled (1.48 s, before the measures were): the factorisations 0.27, the
tangent loop 0.25, the numpy measures about 0.25, the loads loop 0.08.

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
def numpy_tangent(loads: bool = False):
    """MindlinFabricBlock's tangent as before the compiled loop: the elastic block's slices of
    the numpy path through the fabric's level response; with ``loads`` its forces and section
    measures (the strain energy's) too."""
    saved = (
        MindlinFabricBlock.tangent,
        MindlinFabricBlock._cell_tangent,
        MindlinFabricBlock._cell_loads,
        MindlinFabricBlock._measures,
    )
    MindlinFabricBlock.tangent = MindlinShellBlock.tangent  # type: ignore[method-assign]
    MindlinFabricBlock._cell_tangent = MindlinFabricBlock.numpy_cell_tangent  # type: ignore[method-assign]
    if loads:
        MindlinFabricBlock._cell_loads = MindlinFabricBlock.numpy_cell_loads  # type: ignore[method-assign]
        MindlinFabricBlock._measures = _numpy_measures  # type: ignore[method-assign]
    try:
        yield
    finally:
        (
            MindlinFabricBlock.tangent,
            MindlinFabricBlock._cell_tangent,
            MindlinFabricBlock._cell_loads,
            MindlinFabricBlock._measures,
        ) = saved  # type: ignore[method-assign]


def _numpy_measures(block, x, v, cells=slice(None)):
    """The section measures as before the compiled loop (the strain energy's)."""
    return block.section_measures(block._vectors(x, v), cells)


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

    def numpy_force():
        with numpy_tangent(loads=True):
            return block.internal_force(moved)[0]

    def compiled_force():
        return block.internal_force(moved)[0]

    reference, fast = numpy_pass(), compiled_pass()
    difference = np.abs(fast - reference).max() / np.abs(reference).max()
    numpy_s, compiled_s = best(numpy_pass, rounds), best(compiled_pass, rounds)
    force_reference, force = numpy_force(), compiled_force()
    force_difference = np.abs(force - force_reference).max() / np.abs(force_reference).max()
    numpy_f, compiled_f = best(numpy_force, rounds), best(compiled_force, rounds)
    return (
        f"{cells:5d} {len(block.connectivity):9d} {1e3 * numpy_s:9.2f} {1e3 * compiled_s:12.2f}"
        f" {numpy_s / compiled_s:7.1f} {difference:11.2e}   forces {1e3 * numpy_f:6.2f} ->"
        f" {1e3 * compiled_f:6.2f} ms, {force_difference:.2e}"
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
            with numpy_tangent(loads=True):
                line, reference = run(cells)
            print(f"{CASE} Mindlin {cells} cells, numpy tangent and forces: {line}", flush=True)
            with numpy_tangent():
                line, _ = run(cells)
            print(f"{CASE} Mindlin {cells} cells, numpy tangent:            {line}", flush=True)
            line, positions = run(cells)
            moved = np.abs(positions - reference).max()
            print(f"{CASE} Mindlin {cells} cells, compiled tangent and forces: {line}; "
                  f"positions within {moved:.2e} mm of the numpy run's", flush=True)  # fmt: skip
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
