"""Cost of the ply contact's re-listing in a Static solve (elements/ply_search.py): the
report's plies-bai-5.1 at coarse (validation/cases/plies_bai_5_1.py: the 4-ply strip of 12
cells, 10 increments) solved with the search as it was (its pairs from k-d trees at every
search, every cut triangle's distance to its cut growth measured) and as it is (a search of
few points over a small face measures every centroid's distance in one matrix,
``EVERY_PAIR``, and takes its upper bound U from them and the grown distances of its pairs,
measured once; a cut triangle whose grown distance is already past U + s is not measured to
its cut growth), side by side in one process, alternating, one thread, CPU time
(``time.process_time``), the machine's load printed. The final positions and directors are
compared to the bit, and the Newton iterations.

Why the search runs so often: the Newton iterates move the plies by more than the lists'
skin. Measured on this solve: 7074 calls of ``FacingSearch.near`` over the three contacts,
2785 of them a full search (48 points each, a new epoch) and 3 a partial one; the
triangles' move M at the call, over the skin s, has quartiles 0 / 0.068 / 0.59, and 1937
of the calls had M > s / 2, past which no list can serve (2 delta >= 2 M >= s): those
searches are forced by the bound, so the search itself was made cheaper rather than rarer.
Of the 2.9 s CPU the searches took then (of 19.4 s for the case's three solves, one thread,
load 5-6), 1.2 s were the distances to the cut growths (``closest_on_grown``, numpy) and
0.6 s the k-d trees' pairs.

Measured (one thread, two rounds, the machine's 1-minute load printed, other jobs on the 2
cores), CPU s, the plies' solve alone:

| round | solve before | solve now | search before | search now | load |
|---|---|---|---|---|---|
| 0 | 19.61 | 17.10 | 3.12 | 1.32 | 4.1 |
| 1 | 18.76 | 15.48 | 2.98 | 1.17 | 4.0-4.2 |

358 Newton iterations on both; the final positions and directors the same to the bit. The
first step alone (the matrix's pairs and the skipped cut pairs, the upper bound still the
nearest centroid's triangle measured apart): search 2.85 / 3.34 -> 1.53 / 1.59 s.

The report's case (``python -m validation --cases plies-bai-5.1 --resolution coarse --jobs 1``,
the fibrous, Mindlin and plies solves, the code before and now alternating, load 3.9-4.3):
case_cpu_s before 18.8, 20.4, 20.6 s, now 18.8, 18.0, 18.1 s; the whole process (user +
system) before 22.1, 22.4 s, now 19.6, 19.8 s. The same results.json (but its times) and the
same three .vtu files, byte for byte.

What is left of the search (about 1.2 s): the cut growths' closest points of the pairs
within U + s (numpy, ``closest_on_grown``) and some twenty small numpy calls a search. The
rest of the solve (14-16 s) lies outside the search (the facing's own pass, the ply and
Mindlin tangents, the factorisations).

``EVERY_PAIR`` (--crossover: one search of every point of a crumpled sheet of 10-mm cells
cut at its outline vertices, nodes raised by N(0, 6 mm), the points within N(0, 3 mm) of
it, by the matrix and by the trees, 0.5 s of calls each; load 3.7), ms per search:

| points x triangles | matrix | trees |
|---|---|---|
| 48 x 72 = 3456 | 0.70 | 1.25 |
| 200 x 72 = 14400 | 1.63 | 2.19 |
| 128 x 128 = 16384 | 1.39 | 1.70 |
| 80 x 200 = 16000 | 1.28 | 1.61 |
| 160 x 200 = 32000 | 2.85 | 1.80 |
| 200 x 288 = 57600 | 4.51 | 2.08 |

Again with the matrix's passes compiled (elements/ply_search_pairs.py) and the cut flags read
from the cuts' own (``WedgeCuts.cut``), larger faces added (load 5.0-5.3), ms per search:

| points x triangles | matrix | trees |
|---|---|---|
| 48 x 72 = 3456 | 0.17 | 0.75 |
| 200 x 72 = 14400 | 0.45 | 1.71 |
| 128 x 128 = 16384 | 0.32 | 1.10 |
| 80 x 200 = 16000 | 0.26 | 1.02 |
| 160 x 200 = 32000 | 0.41 | 1.56 |
| 200 x 288 = 57600 | 0.51 | 1.86 |
| 384 x 128 = 49152 | 0.79 | 2.61 |
| 512 x 512 = 262144 | 1.45 | 3.74 |
| 1000 x 1152 = 1152000 | 4.26 | 8.03 |
| 2000 x 2048 = 4096000 | 16.46 | 16.21 |
| 4000 x 3200 = 12800000 | 59.21 | 35.53 |

So ``EVERY_PAIR`` is 2^21 (about two million pairs, a 16 MB matrix) where it was 16384: the
two-ply hemisphere's upper pass (384 x 128) now takes the matrix too.

Run: python benchmarks/ply_relist.py [--repeat 2] [--crossover]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere

from elements import ply_search  # noqa: E402
from fibreshell.plies import plies_solver, ply_stack, stack_model  # noqa: E402
from fibreshell.run import solve_keeping  # noqa: E402
from validation import ground_truth  # noqa: E402
from validation.cases import plies_bai_5_1 as bai  # noqa: E402

_DISTANCES = ply_search.FacingSearch._distances
_EVERY_PAIR = ply_search.EVERY_PAIR


def _as_before(self, x, y, corners, point, triangle, beyond=None, grown=None):
    """The search's distances as before: every cut pair measured to its cut growth."""
    return _DISTANCES(self, x, y, corners, point, triangle)


def _use(before: bool) -> None:
    ply_search.FacingSearch._distances = _as_before if before else _DISTANCES  # type: ignore[method-assign]
    ply_search.EVERY_PAIR = 0 if before else _EVERY_PAIR


def _solve(resolution: str):
    """The plies' solve of plies-bai-5.1 at ``resolution``: (result, CPU s, search CPU s)."""
    solver = {**bai.BEFORE_STALL_RULE, "increments": bai.INCREMENTS_BEFORE_FIRST_TURN[resolution]}
    case = ground_truth._case(bai.FILE, bai.CELLS[resolution], {"solver": solver})
    stack = ply_stack(case, bai.PLIES[resolution])
    model = stack_model(case, stack)
    search = ply_search.FacingSearch._search
    spent = [0.0]

    def timed(self, p, y, rows):
        start = time.process_time()
        try:
            return search(self, p, y, rows)
        finally:
            spent[0] += time.process_time() - start

    ply_search.FacingSearch._search = timed  # type: ignore[method-assign]
    try:
        start = time.process_time()
        result, error, _ = solve_keeping(plies_solver(case, False), model)
        total = time.process_time() - start
    finally:
        ply_search.FacingSearch._search = search  # type: ignore[method-assign]
    assert not error, error
    return result, total, spent[0]


def crossover() -> None:
    """ms per search of every point by the matrix and by the trees (``EVERY_PAIR``)."""
    from elements.ply_projection import MARGIN, open_edges
    from elements.ply_wedge import WedgeCuts

    rng = np.random.default_rng(0)
    sizes = [(6, 48), (6, 200), (8, 128), (10, 80), (10, 160), (12, 200), (8, 384)]
    sizes += [(16, 512), (24, 1000), (32, 2000), (40, 4000)]
    for cells, count in sizes:
        u = np.arange(cells + 1) * 10.0
        gx, gy = np.meshgrid(u, u, indexing="ij")
        nodes = np.column_stack([gx.ravel(), gy.ravel(), rng.normal(0.0, 6.0, gx.size)])
        k = np.arange(cells + 1) * (cells + 1)
        a = (k[:-1, None] + np.arange(cells)[None, :]).ravel()
        b, c, d = a + (cells + 1), a + (cells + 2), a + 1
        triangles = np.vstack([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
        outline = open_edges(triangles)
        y = nodes[triangles]
        cuts = WedgeCuts.of(y, triangles, outline, np.where(outline, MARGIN, 0.0))
        search = ply_search.FacingSearch.of(y, outline, cuts)
        side = 10.0 * cells
        p = np.column_stack(
            [
                rng.uniform(-5.0, side + 5.0, count),
                rng.uniform(-5.0, side + 5.0, count),
                rng.normal(0.0, 3.0, count),
            ]
        )
        rows = np.arange(count)
        cost = {}
        for name, limit in (("matrix", 1 << 62), ("trees", 0)):
            ply_search.EVERY_PAIR = limit
            search._search(p, y, rows)
            start, calls = time.process_time(), 0
            while time.process_time() - start < 0.5:
                search._search(p, y, rows)
                calls += 1
            cost[name] = 1e3 * (time.process_time() - start) / calls
        ply_search.EVERY_PAIR = _EVERY_PAIR
        print(
            f"  {count} x {len(triangles)} = {count * len(triangles)}: matrix "
            f"{cost['matrix']:.2f} ms, trees {cost['trees']:.2f} ms per search"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--resolution", default="coarse")
    parser.add_argument("--crossover", action="store_true")
    args = parser.parse_args()
    print("load", os.getloadavg())
    if args.crossover:
        crossover()
        print("load", os.getloadavg())
        return
    finals = {}
    for round_ in range(args.repeat):
        for name in ("before", "now"):
            _use(name == "before")
            result, total, search = _solve(args.resolution)
            final = result.frames[-1]
            finals[name] = (final.positions, final.directors, result.steps)
            print(
                f"  round {round_} {name:>6}: solve {total:6.2f} s CPU, search {search:5.2f} s, "
                f"steps {result.steps}, load {os.getloadavg()[0]:.1f}"
            )
        _use(False)
    same = all(np.array_equal(a, b) for a, b in zip(finals["before"][:2], finals["now"][:2]))
    print(f"final positions and directors the same to the bit: {same}")
    print("load", os.getloadavg())


if __name__ == "__main__":
    main()
