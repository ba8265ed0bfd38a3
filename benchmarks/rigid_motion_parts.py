"""What the rigid-motion check before a quasi-static solve costs (femcore/diagnostics.py, part
by part since femcore/connected_parts.py): ``unheld_rigid_motions`` on a body of ``--parts``
separate 2 x 2-cell Mindlin squares, every node clamped and one loaded, and on one
``--cells`` x ``--cells`` strip lying on a frictionless plane (the contact holds every node
along z), beside a reference pass over the same rows: the full singular value decomposition
the check took before (``full_matrices=True``, whose left vectors cost rows^2), timed on the
one strip's rows.

    NUMBA_NUM_THREADS=1 python benchmarks/rigid_motion_parts.py --parts 1000 --cells 60

Measured (2 cores shared with other jobs, load 11): 1000 parts of 9 nodes 0.46 s (each part's
arrays its own nodes': masked over the whole mesh, 100 parts took 188 s); the 60 x 60 strip on
the plane (3721 nodes) 0.021 s, the full decomposition of its 3843 rows alone, as the check
took it before, 1.75 s.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--parts", type=int, default=1000)
    parser.add_argument("--cells", type=int, default=60)
    options = parser.parse_args()

    from elements import MindlinShell, RigidPlane
    from femcore import Mesh, Model
    from materials import ElasticShell

    section = ElasticShell(E=1000.0, nu=0.3, thickness=1.0, density=1e-9)
    square = Mesh.rectangle(10.0, 10.0, nx=2, ny=2)
    k = options.parts
    points = np.vstack([square.points + [12.0 * i, 0.0, 0.0] for i in range(k)])
    cells = np.vstack([square.triangles + square.n_nodes * i for i in range(k)])
    parts = Model(Mesh(points, triangles=cells))
    parts.add(MindlinShell(section))
    parts.fix(np.arange(len(points)))
    parts.force([len(points) - 1], (0.0, 0.0, -1.0))
    compiled = parts.compile()
    start = time.perf_counter()
    compiled.unheld_rigid_motions()
    print(f"{k} parts of 9 nodes, every node clamped: check {time.perf_counter() - start:.3f} s")

    n = options.cells
    strip = Model(Mesh.rectangle(100.0, 100.0, nx=n, ny=n, origin=(0.0, 0.0, 0.5)))
    strip.add(MindlinShell(section))
    strip.contact(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)))
    strip.fix("left", ["ux", "uy"])
    strip.force("right", (0.0, 0.0, -1.0))
    compiled = strip.compile()
    start = time.perf_counter()
    compiled.unheld_rigid_motions(loaded_only=False)
    check = time.perf_counter() - start
    rows = np.random.default_rng(0).standard_normal((compiled.n_nodes + 2 * (n + 1), 6))
    start = time.perf_counter()
    np.linalg.svd(rows, full_matrices=True)  # the reference pass: the former decomposition
    reference = time.perf_counter() - start
    print(
        f"{n} x {n} strip on a plane ({compiled.n_nodes} nodes): check {check:.3f} s, "
        f"full decomposition of its {len(rows)} rows alone {reference:.3f} s"
    )


if __name__ == "__main__":
    main()
