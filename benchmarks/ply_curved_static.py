"""Static on a frictional two-ply stack with curved faces (``PlyContact(surface="curved")``):
the curved loads' exact tangent (elements/ply_curved_tangent.py) against the tangent before,
the flat facet's at the curved projection (``ply_block_tangent.CURVED_TANGENT = False``), side by
side in one process.

The model: a [0/45] Mindlin layup (40 mm square, ``CELLS`` cells, mu = 0.2, curved faces,
Gauss points) laid on a sphere cap of radius 50 mm (the plies' reference geometry, faces
touching), the bottom ply clamped, the top ply pressed onto it by a body force and its left
edge pulled along x (the plies stick and slip).

Measured (one thread, 2 cores shared), Newton iterations [per increment], CPU:

    the normal tangent exact, the friction's still the flat one (load 4.2-5.5):
      4 cells  flat 90 [30, 20, 20, 20] 2.2 s | exact 28 [10, 7, 6, 5] 1.3 s, 2.1e-3 mm apart
      6 cells  flat 101 [38, 21, 21, 21] 4.2 s | exact 24 [8, 6, 6, 4] 2.1 s, 3.2e-8 mm apart
    both exact, the stuck points' couple in the loads, the friction's complex steps in numpy
    (load 9-11):
      4 cells  flat 91 [31, 20, 20, 20] 2.5 s | exact 24 [8, 7, 5, 4] 4.2-4.5 s, 1.4e-8 mm apart
      6 cells  flat 101 [38, 21, 21, 21] 4.4 s | exact 21 [7, 6, 5, 3] 6.3 s, 8.4e-9 mm apart
    the same, the complex steps compiled (elements/ply_curved_friction_kernels.py; load 6.5-7.4):
      4 cells  flat 91 2.1 s | exact 24 1.6 s;  6 cells  flat 101 3.9 s | exact 21 2.7 s

In numpy the friction's complex steps cost 0.34 s of a 0.44-s tangent at 4 cells (profiled):
fewer iterations, more time, until they were compiled.

Run: python benchmarks/ply_curved_static.py [cells]
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from elements import ply_block_tangent
from elements.layup import Layup
from materials import Fabric
from solvers import Static

PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)
RADIUS = 50.0  # mm
CELLS = 4


def build(cells: int):
    layup = Layup(
        PLY, (0.0, 45.0), 40.0, cells=cells, kinematics="mindlin-elastic", friction=0.2,
        surface="curved", rule="gauss", penalty=100.0,
    )  # fmt: skip
    x = layup.mesh.points.copy()
    for k, nodes in enumerate(layup.ply_nodes):
        radius = RADIUS + k * PLY.thickness
        x[nodes, 2] = np.sqrt(radius**2 - np.sum(x[nodes, :2] ** 2, axis=1)) - RADIUS
    layup.mesh = layup.mesh.with_points(x)
    model = layup.model()
    bottom, top = layup.ply_nodes
    model.fix(bottom)
    left = top[np.isin(top, layup.mesh.node_sets["ply_2_left"])]
    model.displace(left, ux=0.4, uy=0.0)
    model.gravity((0.0, 0.0, -2.0e9))  # mm/s^2: ~2.3 N on the top ply
    return model


def main(argv: list[str]) -> None:
    cells = int(argv[0]) if argv else CELLS
    print(f"load {os.getloadavg()}", flush=True)
    finals = {}
    for label, exact in (("flat tangent (before)", False), ("exact tangent", True)):
        ply_block_tangent.CURVED_TANGENT = exact
        model = build(cells)
        start = time.process_time()
        try:
            result = Static(increments=4, seek_stable=False, progress=False).solve(model)
            stopped = "" if result.converged else "not converged"
        except Exception as error:  # a stalled solve is a figure too
            result, stopped = getattr(error, "result", None), f"stopped: {error}"[:160]
        cpu = time.process_time() - start
        if result is None:
            print(f"{label:24s} {stopped} CPU {cpu:.1f} s", flush=True)
            continue
        iterations = list(result.info["iterations_per_increment"])
        finals[label] = result.positions
        print(
            f"{label:24s} {sum(iterations):4d} iterations {iterations} cuts "
            f"{result.info['cuts']} CPU {cpu:6.1f} s {stopped}",
            flush=True,
        )
    if len(finals) == 2:
        a, b = finals.values()
        print(f"final positions apart by {float(np.abs(a - b).max()):.3g} mm", flush=True)
    print(f"load {os.getloadavg()}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
