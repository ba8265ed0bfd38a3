"""Cost of the contact search against a meshed tool (elements.rigid_surface.RigidSurface).

A closed sphere of radius 100 mm meshed with about 1k, 10k and 100k triangles (the convex hull
of a Fibonacci lattice); 10k points scattered within +-2 mm of it (a blank lying on a tool).
Printed per size: the time to build the k-d tree, the microseconds per node for a full search
(the first query, or after a node moved more than the cache's margin), for a step answered from
the kept candidates (the points moved by a twentieth of a facet: what a contact block pays per node
and step in an explicit run), the same query against the analytic RigidSphere, and a reference
pass over the same points (one norm per point), side by side in one run, best of
``--repeats``.

Run from the project root:

    python benchmarks/contact_search.py
    python benchmarks/contact_search.py --sizes 1000,100000 --points 20000
"""

from __future__ import annotations

import argparse
import copy
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from elements import RigidSphere, RigidSurface  # noqa: E402
from validation.specimens import fibonacci_sphere  # noqa: E402


def best(function, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def time_surface(tool: RigidSurface, x: np.ndarray, repeats: int) -> tuple[float, float]:
    """(full search, step from the kept candidates), s; ``tool`` has not searched yet."""

    def search():
        # The full search, as after a long move: each run on a shallow copy of the tool as
        # built, which has kept no candidates (the copy shares the tree and the facets).
        copy.copy(tool).distance(x)

    full = best(search, repeats)
    tool.distance(x)
    # Points moving a twentieth of a facet per query, back and forth: every query differs
    # from the one before, so the tool's memory of its last answer never serves it.
    moves = [x + 0.05 * tool.reach, x]
    queries = iter(moves * (repeats + 1))
    return full, best(lambda: tool.distance(next(queries)), repeats)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="1000,10000,100000", help="facet counts")
    parser.add_argument("--points", type=int, default=10000, help="query points")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    radius = 100.0
    rng = np.random.default_rng(0)
    direction = rng.normal(size=(args.points, 3))
    direction /= np.linalg.norm(direction, axis=1)[:, None]
    x = direction * rng.uniform(radius - 2.0, radius + 2.0, size=(args.points, 1))
    sphere = RigidSphere((0.0, 0.0, 0.0), radius)
    print(f"{args.points} points within 2 mm of a sphere of radius {radius} mm")
    print(
        f"{'facets':>8} {'build s':>8} {'search us/node':>15} {'step us/node':>13} "
        f"{'sphere us/node':>15} {'ref us/node':>12}"
    )
    for size in (int(s) for s in args.sizes.split(",")):
        mesh = fibonacci_sphere(radius, size // 2 + 2)  # a closed hull: 2 (V - 2) facets
        start = time.perf_counter()
        tool = RigidSurface(mesh)
        build = time.perf_counter() - start
        meshed, stepped = time_surface(tool, x, args.repeats)
        analytic = best(lambda: sphere.distance(x), args.repeats)
        reference = best(lambda: np.linalg.norm(x, axis=1), args.repeats)
        per = 1e6 / args.points
        print(
            f"{mesh.n_triangles:>8} {build:>8.3f} {meshed * per:>15.3f} {stepped * per:>13.3f} "
            f"{analytic * per:>15.3f} "
            f"{reference * per:>12.4f}"
        )


if __name__ == "__main__":
    main()
