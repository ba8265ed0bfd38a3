"""The Mindlin triangle's compiled cell loops of another revision beside this tree's, in one
process, taken in turns: the elastic tangent (elements/mindlin_tangent.py) and the fabric
section's tangent, loads and section measures (elements/mindlin_fabric_tangent.py, _loads.py,
_measures.py), with the per-cell pieces they share (elements/mindlin_cell_terms.py).

The revision's files (``git show``, those it has) are written into a package of their own in a
temporary folder (benchmarks/revision_modules.py) and imported beside this
tree's; both are called on the same inputs, made once by this tree: the elastic and the
fabric (presets.g986_stack) block of a sheet, its nodes jittered and its directors turned.

Printed, a line a kernel and sheet: whether the two give the same numbers to the last bit
(np.array_equal; else the largest difference over the largest value), on one thread and, with
``--threads 2``, on two (the loop split in two parts); the best CPU time per cell of each over
``--rounds`` rounds (each round ``--calls`` calls of each, their order flipped every round),
and the median of new / old over the rounds with its quartiles; the machine's load (uptime)
before and after. ``--compile`` first times, in a fresh process on an empty numba cache
(NUMBA_CACHE_DIR) for each side, the CPU of each kernel's first call on a small sheet less
that of its second (numba's build of the loop, one thread).

Measured on the 2-core machine shared with other jobs, one numba thread, ``--ref 14e312d``
(the loops spelling their pieces out) beside the loops with elements/mindlin_cell_terms.py,
10,000-triangle sheets, best of 9 rounds (uptime before and after: load 8.65 and 11.51):

    kernel            old us/cell  new us/cell  new/old median (quartiles)  bits, 1 and 2 threads
    elastic tangent      2.434        2.133        0.865 (0.858-0.879)       the same
    fabric tangent       1.973        1.884        0.982 (0.968-0.985)       the same
    fabric loads         0.443        0.447        0.975 (0.972-0.984)       the same
    fabric measures      0.089        0.087        0.968 (0.951-0.995)       the same

(the elastic tangent's scratch allocated once a chunk of 64 cells instead of once a cell: the
most of its 14 %). On the way, at 2,500 triangles (load 5-10): the pieces spliced with loops
over the levels or the rows inside them (the arrays' reference counts kept in every cell),
elastic tangent 1.042, fabric tangent 1.002, loads 1.129, measures 1.614; the loops of fixed
length, 1.015, 0.977, 0.972, 1.034 (the elastic tangent's scratch still a cell's, freed inside
the cell: its counts kept); the loads' rows formed whole by ``measure_row`` and then summed,
1.051 (not kept).

Builds (``--compile``, fresh process, empty cache, one thread, CPU s of the first call less
the second's; load 11-13), before / after, four runs (the last two with ``measure_entries``
and ``clear_stress_terms``):

    elastic tangent   2.89 / 3.25   3.05 / 3.21   3.71 / 3.30   3.46 / 3.86
    fabric tangent    2.61 / 2.98   2.58 / 2.77   3.18 / 3.41   3.19 / 3.31
    fabric loads      0.86 / 1.25   0.85 / 1.17   1.30 / 1.36   1.36 / 1.39
    fabric measures   0.78 / 0.96   0.75 / 0.91   0.70 / 0.82   0.68 / 0.83
    the four          7.14 / 8.44   7.23 / 8.06   8.89 / 8.89   8.69 / 9.39

0 to 18 % longer (numba reads each spliced helper's bytecode again at each call site and
types the larger loop), within the spread of one side from run to run at this load.

The fabric section's response (elements/fabric_section_kernels.py ``section_response``: the
forces ask for it without the Hessian, the tangent with it) with each law function spliced
once, in a loop over the five laws, beside the loop that called them per law (11 spliced
copies), ``--ref 4cc9eb3 --cells 200,5000 --rounds 9 --compile``, load 8.3-14.4 (another
job's CI beside it):

    build (first call less second)   old 8.77 s  new 3.44 s (one build serves both calls)
    section forces    196 cells  old 0.133  new 0.105 us/cell  new/old 0.804 (0.802-0.821)
    section tangent   196 cells  old 0.247  new 0.220 us/cell  new/old 0.910 (0.902-0.912)
    section forces   4900 cells  old 0.120  new 0.098 us/cell  new/old 0.818 (0.815-0.820)
    section tangent  4900 cells  old 0.256  new 0.228 us/cell  new/old 0.895 (0.890-0.900)

the same bits (and on tests/test_fabric_section_kernels.py's linear and non-linear fabrics,
tables and tension-only laws included, with and without the Hessian); the other kernels
within 1 % of 1.000. The inputs of the tangents and loads take the numpy response, so that
the compiled response's build is among those timed.

Run from the project root (the other revision must be a git ref of this repository):

    python benchmarks/mindlin_kernel_pairs.py --ref main --cells 10000 --rounds 12 [--compile]
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # run from anywhere, no install

import numpy as np  # noqa: E402
from revision_modules import revision_modules  # noqa: E402

# The files taken from the other revision, and the name each is imported under there.
MODULES = {
    "elements/mindlin_tangent.py": "elements.mindlin_tangent",
    "elements/mindlin_fabric_tangent.py": "elements.mindlin_fabric_tangent",
    "elements/mindlin_fabric_loads.py": "elements.mindlin_fabric_loads",
    "elements/mindlin_fabric_measures.py": "elements.mindlin_fabric_measures",
    "elements/mindlin_cell_terms.py": "elements.mindlin_cell_terms",
    "elements/fabric_section_kernels.py": "elements.fabric_section_kernels",
}
KERNELS = (
    "elastic tangent",
    "fabric tangent",
    "fabric loads",
    "fabric measures",
    "section forces",
    "section tangent",
)


def sheet(cells: int, fabric: bool, seed: int = 3):
    """The block of a 2:1 rectangle (200 x 100 mm) of about ``cells`` triangles, elastic
    (h = 1 mm, steel) or of the g986 stack's fabric, and its corners x, v (m, 3, 3) stretched
    2 %, jittered by 0.1 mm, the directors turned by about 0.3 rad."""
    from elements import MindlinShell
    from femcore import Mesh, Model
    from materials import ElasticShell, presets
    from tests.test_mindlin_fabric_tangent import _bent_state

    ny = max(1, int(round(np.sqrt(cells / 4.0))))
    mesh = Mesh.rectangle(200.0, 100.0, nx=2 * ny, ny=ny)
    material = presets.g986_stack() if fabric else ElasticShell(210000.0, 0.3, 1.0, 7.8e-9)
    model = Model(mesh)
    model.add(MindlinShell(material, warp=(1.0, 0.3, 0.0)) if fabric else MindlinShell(material))
    compiled = model.compile()
    state = _bent_state(compiled, np.random.default_rng(seed))
    block = compiled.blocks[0]
    return block, state.positions[block.connectivity], state.directors[block.connectivity]


def calls(modules: dict, cells: int) -> dict:
    """Each kernel of ``modules`` (name: module, the four files) as a function of no arguments
    on inputs made once by this tree's blocks."""
    from elements.fabric_section import numpy_response
    from elements.mindlin_tables import _TYING_N

    elastic, x, v = sheet(cells, fabric=False)
    stiffness, products = elastic._level_stiffness(), elastic._products()
    fabric, xf, vf = sheet(cells, fabric=True)
    gradient, curvature = fabric._products()
    # the numpy path's measures and response (the compiled loops' own first builds are among
    # those timed)
    y = fabric.section_measures(fabric._vectors(xf, vf))
    answer = numpy_response(fabric.section, y, hessian=True)
    common = (xf, vf, fabric.zeta, fabric.h, _TYING_N)
    metric = fabric.reference_metric
    tangent = modules["mindlin_tangent"].mindlin_tangent_blocks
    fabric_tangent = modules["mindlin_fabric_tangent"].fabric_tangent_blocks
    loads = modules["mindlin_fabric_loads"].fabric_cell_loads
    measures = modules["mindlin_fabric_measures"].fabric_section_measures
    section = fabric.section
    # the section's response (elements/fabric_section.py ``response``) as the forces ask for
    # it (no Hessian) and as the tangent does
    laws = (*section.laws, section.area, section.warp_rows, section.weft_rows)
    tables = (section.shear_rows, section.half_thickness, section.twisting, section.transverse)
    bending = np.asarray(section.reference_bending)
    response_of = modules["fabric_section_kernels"].section_response
    return {
        "elastic tangent": (
            lambda: tangent(elastic, x, v, stiffness, *products),
            len(x),
        ),
        "fabric tangent": (
            lambda: fabric_tangent(
                *common, metric, answer.gradient, answer.hessian, gradient, curvature
            ),
            len(xf),
        ),
        "fabric loads": (lambda: loads(*common, answer.gradient, gradient), len(xf)),
        "fabric measures": (lambda: measures(*common, metric), len(xf)),
        "section forces": (lambda: response_of(*laws, *tables, bending, y, False), len(xf)),
        "section tangent": (lambda: response_of(*laws, *tables, bending, y, True), len(xf)),
    }


def flat(result) -> np.ndarray:
    parts = result if isinstance(result, tuple) else (result,)
    return np.concatenate([np.ravel(p) for p in parts if p is not None])


def same(a: np.ndarray, b: np.ndarray) -> str:
    if np.array_equal(a, b):
        return "same bits"
    return f"differ by {np.max(np.abs(a - b)) / np.max(np.abs(a)):.1e}"


def on_threads(run, threads: int):
    """``run()`` with numba's loops on ``threads`` threads (the load not followed)."""
    import numba

    from femcore import jit

    saved, follow = numba.get_num_threads(), jit.FOLLOW_LOAD
    numba.set_num_threads(threads)
    jit.FOLLOW_LOAD = False
    try:
        return run()
    finally:
        numba.set_num_threads(saved)
        jit.FOLLOW_LOAD = follow


def pair(
    name: str, old, new, cells: int, rounds: int, repeats: int, threads: int, unit: str = "cell"
) -> str:
    a, b = flat(old()), flat(new())
    bits = same(a, b)
    if threads > 1:
        bits += f", {threads} threads: " + same(a, flat(on_threads(new, threads)))
        bits += f" (old {same(a, flat(on_threads(old, threads)))})"
    times: dict = {old: [], new: []}
    ratios = []
    for r in range(rounds):
        for kernel in (old, new) if r % 2 == 0 else (new, old):
            started = time.process_time()
            for _ in range(repeats):
                kernel()
            times[kernel].append((time.process_time() - started) / repeats / cells * 1e6)
        ratios.append(times[new][-1] / times[old][-1])
    q1, median, q3 = np.percentile(ratios, [25, 50, 75])
    return (
        f"{name:16s} {cells:6d} {unit}s  old {min(times[old]):7.3f}  new {min(times[new]):7.3f} "
        f"us/{unit}  new/old {median:.3f} ({q1:.3f}-{q3:.3f})  {bits}"
    )


def uptime() -> str:
    return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()


def first_builds(package: str | None, folder: str | None) -> dict:
    """CPU s of each kernel's first call less its second (on an empty cache: numba's build),
    in this process: this tree's modules (``package`` None) or the package ``package`` in
    ``folder``."""
    if folder is not None:
        sys.path.insert(0, folder)
    prefix = "elements" if package is None else package
    modules = {n.rsplit(".", 1)[1]: importlib.import_module(f"{prefix}.{n.rsplit('.', 1)[1]}")
               for n in MODULES.values() if n != "elements.mindlin_cell_terms"}  # fmt: skip
    built = {}
    for name, (run, _) in calls(modules, 200).items():
        started = time.process_time()
        run()
        first = time.process_time() - started
        started = time.process_time()
        run()
        built[name] = first - (time.process_time() - started)
    return built


def compile_times(package: str, folder: str) -> dict:
    """``first_builds`` of each side in a fresh process on an empty numba cache."""
    found = {}
    for side, arguments in (("old", [package, folder]), ("new", [])):
        with tempfile.TemporaryDirectory() as cache:
            environment = dict(os.environ, NUMBA_CACHE_DIR=cache, NUMBA_NUM_THREADS="1")
            done = subprocess.run(
                [sys.executable, __file__, "--builds", *arguments],
                env=environment, capture_output=True, text=True, check=True,
            )  # fmt: skip
            found[side] = json.loads(done.stdout.strip().splitlines()[-1])
    return found


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ref", default="main", help="the other revision (a git ref)")
    parser.add_argument("--cells", default="10000", help="sheet sizes, triangles (a list)")
    parser.add_argument("--rounds", type=int, default=12)
    parser.add_argument("--calls", type=int, default=0, help="calls a turn (0: 200k cells')")
    parser.add_argument("--threads", type=int, default=1, help="threads of the bits check")
    parser.add_argument("--compile", action="store_true", help="time the builds first")
    parser.add_argument("--builds", nargs="*", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.builds is not None:  # the child of ``compile_times``
        package, folder = (args.builds + [None, None])[:2]
        print(json.dumps(first_builds(package, folder)))
        return
    import numba

    numba.set_num_threads(1)  # the timings' (``--threads`` is the bits check's)
    print(uptime(), flush=True)
    with tempfile.TemporaryDirectory() as folder:
        package, commit = revision_modules(args.ref, Path(folder), MODULES)
        print(f"{args.ref} ({commit}) beside this tree, one process, CPU time", flush=True)
        if args.compile:
            built = compile_times(package, folder)
            for name in KERNELS:
                print(f"build {name:16s} old {built['old'][name]:6.2f} s  new "
                      f"{built['new'][name]:6.2f} s", flush=True)  # fmt: skip
            print(uptime(), flush=True)
        names = [n.rsplit(".", 1)[1] for n in MODULES.values() if "cell_terms" not in n]
        old = {n: importlib.import_module(f"{package}.{n}") for n in names}
        new = {n: importlib.import_module(f"elements.{n}") for n in names}
        for size in [int(s) for s in args.cells.split(",")]:
            olds, news = calls(old, size), calls(new, size)
            for name in KERNELS:
                (run_old, cells), (run_new, _) = olds[name], news[name]
                repeats = args.calls or max(1, 200_000 // cells)
                run_old(), run_new()  # built (or loaded) before the clock
                print(pair(name, run_old, run_new, cells, args.rounds, repeats, args.threads),
                      flush=True)  # fmt: skip
    print(uptime(), flush=True)


if __name__ == "__main__":
    main()
