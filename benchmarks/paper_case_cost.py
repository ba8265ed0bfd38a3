"""The paper cases' CPU, this tree beside a reference tree (the code before, from ``git
archive``), case by case, and whether their results.json numbers moved.

Each case runs as ``python -m validation --cases NAME --jobs 1`` in a fresh process of each
tree (its imports and numba's cached kernels loaded as a report worker's are; one numba
thread), the two trees in alternating order from one turn to the next, ``--turns`` turns
(best of them kept: the machine is shared). The figure is results.json's ``case_cpu_s``
(``Case.compute`` then ``Case.render``). Every number of the case's results.json but its
times (keys naming a time, CPU or wall) is compared between the trees: the largest relative
change is printed, 0 where they are the same bits; the texts are compared with their
seconds taken out (a note's "12.3 s elapsed").

Usage (from this tree's root; the reference tree's numba cache warmed first, ``--warm``)::

    git archive REF | tar -x -C /tmp/reference
    NUMBA_NUM_THREADS=1 python benchmarks/paper_case_cost.py --reference /tmp/reference \\
        [--cases paper|others|a,b] [--turns 2] [--warm] [--moved]

``--moved`` lists every number that moved (largest relative change first) and every text.

Measured (main ad9d75b from git archive beside this tree, one thread, best of 2
alternating turns, 2 cores shared with other jobs, load 5.2-8.5; case CPU s, reference ->
this): bai-5.1 5.75 -> 5.31, bai-6.1.1 8.93 -> 8.60, bai-6.1.2 6.82 -> 6.58, bai-6.2.1 7.65
-> 7.38, bai-6.2.2 6.39 -> 5.96, bai-6.1.1-sensitivity 3.83 -> 3.00: 39.37 -> 36.82 s (0.935);
every results.json number the same bits (5344 of them; the texts the same but their seconds).
The changes: the fibrous tangent kernels' scratch once a chunk of cells (hessian_kernels.py,
tangent_kernels.py), the bending patch made once a block (bending.py ``patch_nodes``), the
assembler's structure in scipy's index type (femcore/assembly.py), and the sensitivity sweep's
variants writing no frame series into the folders it throws away (fibreshell/run.py
``write_frames``). Before the assembler's change (load 9.2-9.8): 43.13 -> 41.00 s (0.951),
the sensitivity case 4.42 -> 3.44.

The nine static cases (``--cases`` with the three ply stacks; main 3228ca0 from git archive
beside the tree with ||K_ff||_inf summed in the split's pass, best of 2 alternating turns,
one thread, load 6.6-11.4; case CPU s): bai-5.1 6.47 -> 6.35, bai-6.1.1 9.57 -> 9.98,
bai-6.1.2 7.36 -> 7.45, bai-6.2.1 8.43 -> 8.30, bai-6.2.2 7.16 -> 7.13,
bai-6.1.1-sensitivity 3.75 -> 3.67, plies-bai-5.1 12.49 -> 12.74, plies-deck-of-cards 7.52
-> 7.42, plies-heavy-cantilever 2.94 -> 2.99: 65.69 -> 66.04 s (1.005, within the load's
spread); every results.json number the same bits (5496 of them).

Where the CPU of the report's static cases goes (main fcee482, each case computed and drawn
twice in one process, the second time kept: numba's cache loads and the imports, 0.9 s and
1.3 s a report worker, paid once; one thread, load 2.2-2.5; CPU s). Every case's computation
is its solves, but heavy-cantilever-nonlinear's: 1.70 s, of it 0.64 in its eight Static runs
and about 1.0 in the heavy elastica's references (scipy's solve_bvp, about 57 ms a solve of
the bilinear law; Peirce's test of it 0.85 s, of the linear law 0.06). The paper cases, 4.9
to 6.8 s each, seven Static arc-length runs: the fibrous run on the finest mesh of the orders
is the largest, 2.5-3.7 s (40-76 ms a Newton iteration: the supernodal LDL^T about half, the
fibrous Hessian kernels a quarter); their renders 1.2-1.8 s (four figures of 0.2-0.5 s each,
most of it the constrained layout's and the drawing's text; the three XDMF series 0.15 s).
plies-bai-5.1 10.8 s: the plies' Static 9.3 s (398 Newton iterations, 403 tangents: 23 ms
an iteration, of it the band LDL^T 10 ms, the tangent 10, the line search's forces 6; the
residual falls and rises again as contact points come and go, 15-34 iterations an increment
of the displacement), its fibrous and Mindlin runs 0.90 and 0.46 s, the very runs bai-5.1
makes (the same increments, iterations, cuts and tangents; the two cases run in separate
workers). plies-deck-of-cards 6.4 s in eight Static runs (the 8-ply deck 2.6 s: 174
iterations in 4 increments; the 8-ply stack's sag 1.9 s); plies-heavy-cantilever 1.6 s (the
plies 1.3 s); mindlin-pinched-cylinder 1.55 s (five meshes, two Newton iterations each, 0.85
s on 4225 nodes). The rest of the report's cases but the forming runs 0.1-0.8 s each. Inside a
case no model is built twice and no solve repeated, but Peirce's test's (below); no Python
glue of note round the kernels (femcore/jit.py's wrappers 0.2 s of plies-bai-5.1's 17 s
under cProfile).

References, and bai-6.2.2's orders (fcee482 from git archive beside this tree, ``--cases
bai-6.2.2,heavy-cantilever-nonlinear --warm``, best of 2 alternating turns, one thread,
load 3.2-4.6; case CPU s): heavy-cantilever-nonlinear 2.46 -> 2.25 (Peirce's test solving
each overhang it tries once, validation/references/elastica.py: 15 -> 11 solves of the
bilinear law, 9 -> 5 of the linear one), its 85 numbers the same bits; bai-6.2.2 7.51 -> 7.09
(7.02 -> 6.44 in a third turn, load 4.7; its orders' other meshes on 10 arc-length increments
a phase instead of 20, benchmarks/paper_refinement.py), 25 of its 866 numbers moved: the
Newton iterations in all (``steps``) 816 -> 725, the orders' values, orders and extrapolations
and their two checks' values by at most 1.4e-7 relative (a check's error 0.0026033160 ->
0.0026033157 against its tolerance 0.01), the texts the same.

The eleven cases (``--cases`` the six paper cases and ``others``, fcee482 beside this tree,
``--warm``, best of 2 alternating turns, one thread, load 2.8-4.5; case CPU s): bai-5.1 6.70
-> 6.97, bai-6.1.1 9.24 -> 9.74, bai-6.1.2 7.28 -> 7.53, bai-6.2.1 8.00 -> 7.85, bai-6.2.2
6.97 -> 6.47, bai-6.1.1-sensitivity 3.54 -> 3.43, plies-bai-5.1 11.52 -> 11.95,
plies-deck-of-cards 7.35 -> 7.11, plies-heavy-cantilever 2.86 -> 2.92,
heavy-cantilever-nonlinear 2.62 -> 2.41, mindlin-pinched-cylinder 1.67 -> 1.98: 67.74 ->
68.37 s (1.009): the two cuts, about 0.9 s, lie inside the spread of fresh processes on a
shared machine (the nine cases whose code did not change moved by -3 to +19 %). Every
results.json number of the ten other cases the same bits (4729 of them), bai-6.2.2's as above.

bai-5.1's orders' other meshes on 20 arc-length increments a phase instead of its own 10
(benchmarks/paper_refinement.py; fcee482 beside this tree, best of 2 alternating turns, one
thread, load 2.8-2.9): 6.82 -> 6.51 s (7.35 -> 6.77 in the first turn); 19 of its 965 numbers
moved: ``steps`` 963 -> 973, the orders' values, orders and extrapolations and their three
checks' values by at most 1.6e-8 relative (a check's error 0.00100953282 -> 0.00100953283
against its tolerance 0.01), the texts the same.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

CASES = (
    "bai-5.1",
    "bai-6.1.1",
    "bai-6.1.2",
    "bai-6.2.1",
    "bai-6.2.2",
    "bai-6.1.1-sensitivity",
)
# ``--cases others``: the report's other static cases of more than a second of CPU.
OTHERS = (
    "plies-bai-5.1",
    "plies-deck-of-cards",
    "plies-heavy-cantilever",
    "heavy-cantilever-nonlinear",
    "mindlin-pinched-cylinder",
)
# results.json keys that hold times (their values differ from run to run).
TIMED = re.compile(r"time|cpu|wall|elapsed")
# A duration in a text ("12.3 s", "0.4 s elapsed").
SECONDS = re.compile(r"\d+(\.\d+)? s\b")


def _load() -> str:
    """The machine's load averages (1, 5, 15 min)."""
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def run_case(tree: Path, name: str, resolution: str) -> dict[str, Any]:
    """The case's results.json entry from a fresh ``python -m validation`` in ``tree``."""
    env = dict(os.environ, NUMBA_NUM_THREADS="1", FIBRESHELL_PROGRESS="0", PYTHONPATH=str(tree))
    with tempfile.TemporaryDirectory() as out:
        subprocess.run(
            [sys.executable, "-m", "validation", "--cases", name, "--jobs", "1",
             "--resolution", resolution, "--out", out],
            cwd=tree, env=env, check=True, capture_output=True,
        )  # fmt: skip
        return json.loads((Path(out) / "results.json").read_text())["cases"][name]


def leaves(value: Any, path: str = "") -> dict[str, Any]:
    """The numbers and texts of a results.json entry by their path, times left out."""
    if isinstance(value, dict):
        found: dict[str, Any] = {}
        for key, item in value.items():
            if not TIMED.search(str(key)):
                found.update(leaves(item, f"{path}/{key}"))
        return found
    if isinstance(value, list):
        found = {}
        for i, item in enumerate(value):
            found.update(leaves(item, f"{path}/{i}"))
        return found
    if isinstance(value, str):
        return {path: SECONDS.sub("<s>", value)}
    return {path: value}


def compare(before: dict[str, Any], after: dict[str, Any]) -> tuple[float, int, int, int]:
    """(largest relative change of a number, numbers compared, numbers not the same bits,
    texts or structure that differ) between two results.json entries."""
    a, b = leaves(before), leaves(after)
    largest, numbers, moved, other = 0.0, 0, 0, len(set(a) ^ set(b))
    for key in set(a) & set(b):
        x, y = a[key], b[key]
        if (
            isinstance(x, bool)
            or isinstance(y, bool)
            or not (isinstance(x, int | float) and isinstance(y, int | float))
        ):
            other += x != y
            continue
        numbers += 1
        if x == y or (isinstance(x, float) and math.isnan(x) and math.isnan(y)):
            continue
        moved += 1
        largest = max(largest, abs(y - x) / max(abs(x), abs(y)))
    return largest, numbers, moved, other


def changes(before: dict[str, Any], after: dict[str, Any]) -> list[tuple[str, Any, Any]]:
    """The leaves (path, before, after) that differ between two results.json entries, the
    numbers by their relative change, largest first, then the texts (None: a leaf of one
    entry alone)."""
    a, b = leaves(before), leaves(after)
    found = [(key, a.get(key), b.get(key)) for key in sorted(set(a) | set(b))]
    nan = lambda v: isinstance(v, float) and math.isnan(v)  # noqa: E731
    found = [(key, x, y) for key, x, y in found if x != y and not (nan(x) and nan(y))]

    def size(item: tuple[str, Any, Any]) -> float:
        _, x, y = item
        if isinstance(x, int | float) and isinstance(y, int | float) and max(abs(x), abs(y)):
            return abs(y - x) / max(abs(x), abs(y))
        return math.inf

    return sorted(found, key=size, reverse=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reference", required=True, help="the reference tree's root")
    parser.add_argument(
        "--cases", default="paper", help='"paper" (CASES), "others" (OTHERS) or names a,b'
    )
    parser.add_argument("--resolution", default="default")
    parser.add_argument("--turns", type=int, default=2)
    parser.add_argument("--warm", action="store_true", help="run each case once first")
    parser.add_argument(
        "--moved", action="store_true", help="list each number and text that differs"
    )
    args = parser.parse_args()
    trees = {"reference": Path(args.reference).resolve(), "this": Path.cwd().resolve()}
    names = {"paper": list(CASES), "others": list(OTHERS)}.get(args.cases) or args.cases.split(",")
    print(f"reference {trees['reference']}, this {trees['this']}; load {_load()}", flush=True)
    if args.warm:
        for name in names:
            for tree in trees.values():
                run_case(tree, name, args.resolution)
    best: dict[tuple[str, str], float] = {}
    kept: dict[tuple[str, str], dict] = {}
    for turn in range(args.turns):
        order = list(trees) if turn % 2 == 0 else list(trees)[::-1]
        for name in names:
            for label in order:
                entry = run_case(trees[label], name, args.resolution)
                cpu = float(entry["case_cpu_s"])
                best[label, name] = min(best.get((label, name), math.inf), cpu)
                kept[label, name] = entry
                print(f"  turn {turn + 1} {name:24s} {label:9s} {cpu:6.2f} s", flush=True)
    print(f"load {_load()}")
    head = f"{'case':24s} {'reference':>9s} {'this':>7s} {'ratio':>6s}  results.json"
    print(head + "\n" + "-" * (len(head) + 40))
    totals = [0.0, 0.0]
    for name in names:
        before, after = best["reference", name], best["this", name]
        totals[0] += before
        totals[1] += after
        largest, numbers, moved, other = compare(kept["reference", name], kept["this", name])
        print(
            f"{name:24s} {before:9.2f} {after:7.2f} {after / before:6.3f}  {numbers} numbers, "
            f"{moved} moved (largest relative {largest:.1e}), {other} texts differ"
        )
        if args.moved:
            for key, x, y in changes(kept["reference", name], kept["this", name]):
                print(f"    {key}: {x!r} -> {y!r}")
    print(f"{'all':24s} {totals[0]:9.2f} {totals[1]:7.2f} {totals[1] / totals[0]:6.3f}")


if __name__ == "__main__":
    main()
