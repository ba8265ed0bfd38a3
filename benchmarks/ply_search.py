"""Cost of the ply contact's facing search (elements/ply_search.py) against the search before
it (the 6 nearest centroids from a k-d tree built at every call), side by side in one run, one
thread, CPU time (``time.process_time``), the machine's load printed.

Two cases, each over a sequence of calls that moves the plies as explicit steps do (a punch's
dent growing by 4e-3 mm a step at the centre and noise of 1e-4 mm at each node):

1. the two ply contacts of the two-ply hemisphere (validation/studies/hemisphere_plies.py,
   Mindlin [0/90], 10 cells: the top ply's Gauss points and the mirrored pass at the bottom
   ply's nodes): ``PlyContactBlock.facing`` per step (both passes), its cache cleared, with
   ``candidates=6`` (before) and the default (the kept lists);
2. a larger lower ply: a 100 x 100 sheet of 10-mm cells (20k triangles), wavy (3 mm
   amplitude, 60-mm wavelength), with 10k points within 1 mm above it: the candidates and
   ``closest_facing`` per call, the 6 nearest centroids against the kept lists.

Printed per case: ms per call before and after, the mean candidates per point, the full
searches over the calls, and the full search's own cost (every call searched, no list kept).

Measured (one thread, 200 calls per case, the machine's 1-minute load 4.4-5.5, other jobs on
the 2 cores), ms per call, CPU:

| case | before (6 centroids) | kept lists | searched every call | candidates |
|---|---|---|---|---|
| hemisphere, 10 cells, 721 points | 5.30 | 2.91 | 5.66 | 2.98 |
| wavy sheet, 20k triangles, 10k points | 62.8 | 49.6 | 92.5 | 2.15 |

(candidates: the mean per point, against 6; full searches: 3 per pass in the hemisphere's 200
steps, 5 in the sheet's 200 calls.) Each figure includes ``closest_facing`` over the
candidates (about 45 ms of the sheet's calls: its pseudonormals of the whole face, the fade):
the search's own share went from the k-d tree's build and query at every call (about 13 ms
on the sheet) to a check of the moves and a full search every few dozen steps, which alone
costs about 43 ms on the sheet and 2.8 ms on the hemisphere's two passes. A second run (60
calls, load 2.7-3.1): 4.96 / 2.85 / 5.86 and 60.4 / 47.5 / 91.3 ms. Grouping the sheet's
points by their count of candidates (two calls of ``closest_facing``) saved 10 % of its cost
(59.7 -> 54.2 ms), each triangle's frame computed once a call instead of once per listing
point 2-3 %: neither kept.

In a Static solve, whose iterates move the plies further than the skin, the lists are made
again more often: the 4-ply bai-5.1 strip (benchmarks/plies.py's solve, one thread, each code
in its own process, side by side, load 4.9-5.5) took 53.6 s of CPU on both codes, 418 Newton
iterations and 7 cuts on both.

With the lower face's topology made once (elements/ply_topology.py, the pseudonormals summed
at the touched rows only; benchmarks/ply_topology.py), 20 calls, load 2.4-2.5: 4.53 / 2.53 /
4.63 and 58.5 / 48.0 / 86.8 ms.

Run: python benchmarks/ply_search.py [--calls 200]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere

from elements.ply_block import PlyContactBlock  # noqa: E402
from elements.ply_projection import closest_facing, edge_ids, open_edges  # noqa: E402
from elements.ply_search import FacingSearch  # noqa: E402
from elements.ply_topology import FaceTopology  # noqa: E402
from femcore.state import State  # noqa: E402


def _steps(x0: np.ndarray, calls: int, rng: np.random.Generator):
    """Positions (n, 3) of ``calls`` explicit-like steps from x0: a dent growing at the centre
    of the sheet's bounding box by 4e-3 mm a step, noise of 1e-4 mm per node."""
    centre = 0.5 * (x0.min(axis=0) + x0.max(axis=0))
    radius = 0.25 * float(np.ptp(x0[:, :2], axis=0).max())
    dent = np.exp(-np.sum((x0[:, :2] - centre[:2]) ** 2, axis=1) / radius**2)
    for k in range(calls):
        x = x0.copy()
        x[:, 2] -= 4e-3 * k * dent
        yield x + rng.normal(0.0, 1e-4, x.shape)


def hemisphere(calls: int) -> None:
    from validation.studies import hemisphere_plies_setup as setup

    _, model = setup.model(10, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled = model.compile()
    blocks = [b for b in compiled.interactions if isinstance(b, PlyContactBlock)]
    n = compiled.mesh.n_nodes
    directors = np.tile([0.0, 0.0, 1.0], (n, 1))
    zero = np.zeros((n, 3))
    totals = {"before (6 centroids)": 0.0, "kept lists": 0.0, "searched every call": 0.0}
    states = [
        State(x, directors, zero, zero)
        for x in _steps(compiled.mesh.points, calls, np.random.default_rng(0))
    ]
    kept = [b.search for b in blocks]
    fresh = [FacingSearch(s.reach, s.skin) for s in kept]
    widths = []
    for state in states:
        for name in totals:
            start = time.process_time()
            for block, own, new in zip(blocks, kept, fresh):
                block.candidates = 6 if name.startswith("before") else None
                block.search = new if name.startswith("searched") else own
                new._lists = None
                block._facing_at = None
                block.facing(state)
            totals[name] += time.process_time() - start
        widths.append(np.mean([s._lists.count.mean() for s in kept]))
    points = sum(len(b.above) for b in blocks)
    print(f"hemisphere plies, Mindlin [0/90], 10 cells: {points} points, both passes")
    for name, total in totals.items():
        print(f"  {name:>22}: {1e3 * total / calls:7.3f} ms per step")
    print(
        f"  mean candidates per point {np.mean(widths):.2f} (before 6); full searches "
        f"{[s.searches for s in kept]}, points searched {[s.searched_points for s in kept]} "
        f"over {calls} steps"
    )


def sheet(calls: int, cells: int = 100, points: int = 10000) -> None:
    rng = np.random.default_rng(1)
    u = np.arange(cells + 1) * 10.0
    gx, gy = np.meshgrid(u, u, indexing="ij")
    nodes = np.column_stack(
        [
            gx.ravel(),
            gy.ravel(),
            3.0 * np.sin(gx.ravel() / 60.0 * 2 * np.pi) * np.cos(gy.ravel() / 60.0 * 2 * np.pi),
        ]
    )
    k = np.arange(cells) * (cells + 1)
    a = (k[:, None] + np.arange(cells)[None, :]).ravel()
    b, c, d = a + (cells + 1), a + (cells + 2), a + 1
    triangles = np.vstack([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    outline, edges = open_edges(triangles), edge_ids(triangles)
    topology = FaceTopology.of(triangles, outline, edges)  # made once, as a contact does
    # the points: above random places of the sheet, within 1 mm
    at = rng.integers(0, len(triangles), points)
    weights = rng.dirichlet(np.ones(3), points)
    p0 = np.einsum("pk,pki->pi", weights, nodes[triangles[at]]) + [0.0, 0.0, 0.0]
    p0[:, 2] += rng.uniform(-0.5, 1.0, points)
    search = FacingSearch.of(nodes[triangles], outline)
    fresh = FacingSearch(search.reach, search.skin)
    totals = {"before (6 centroids)": 0.0, "kept lists": 0.0, "searched every call": 0.0}
    moves = _steps(np.vstack([nodes, p0]), calls, np.random.default_rng(2))
    for x in moves:
        y, p = x[: len(nodes)][triangles], x[len(nodes) :]
        for name in totals:
            start = time.process_time()
            if name.startswith("before"):
                near = np.asarray(cKDTree(y.mean(axis=1)).query(p, k=6)[1])
            elif name.startswith("searched"):
                fresh._lists = None
                near = fresh.near(p, y)
            else:
                near = search.near(p, y)
            closest_facing(p, y, near, 0.0, outline, topology=topology)
            totals[name] += time.process_time() - start
    print(f"wavy sheet: {len(triangles)} triangles, {points} points")
    for name, total in totals.items():
        print(f"  {name:>22}: {1e3 * total / calls:7.3f} ms per call")
    assert search._lists is not None
    print(
        f"  mean candidates per point {search._lists.count.mean():.2f} (before 6); full "
        f"searches {search.searches}, points searched {search.searched_points} over {calls}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calls", type=int, default=200)
    args = parser.parse_args()
    print("load", os.getloadavg())
    hemisphere(args.calls)
    sheet(args.calls)
    print("load", os.getloadavg())


if __name__ == "__main__":
    main()
