"""A light ply laid on a ply held whole, clamped at one edge and pressed on it by its weight:
wholly on the lower ply, or overhanging its outline edge y = 0. The model of
tests/test_ply_overhang.py, tests/test_ply_margin.py and the benchmarks that study it
(benchmarks/ply_overhang.py, ply_margin.py, ply_friction_laid.py, ply_fade_hessian.py).

The lower ply: 20 x 20 mm, its mid-surface at z = 0, every node held. The upper ply: 10 x 10
mm, from x = 2.5 mm, its mid-surface at z = 2 HALF (laid on the lower ply's upper face, the
gap zero), clamped at its edge of largest y. Both Mindlin plies of PLY, joined by the ply
contact (elements/ply_contact.py ``join_neighbours``), under gravity.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from elements.plies import mindlin_ply
from elements.ply_contact import join_neighbours
from femcore import Mesh, Model
from materials import Fabric

__all__ = ["GRAVITY", "HALF", "PLY", "two_plies", "upper_ply"]

# A ply soft in bending (0.05 N mm): its free 10 mm cantilever sags 2.5 mm under its weight;
# the automatic penalty (100-600 N/mm per node) is some 1e4 times its bending stiffness per
# node.
PLY = Fabric(thickness=0.5, areal_density=1e-8, tension=1e3, shear=0.1, bending=0.05)
HALF = 0.5 * PLY.thickness  # mm
GRAVITY = 9810.0  # mm/s^2


def upper_ply(shift: float, cells: int = 6) -> Mesh:
    """The upper ply's mesh (``cells`` x ``cells``), placed: its edge of least y at ``shift``
    mm (-4: 4 mm past the lower ply's outline edge y = 0; 5: wholly on the lower ply)."""
    upper = Mesh.rectangle(10.0, 10.0, nx=cells, ny=cells)
    return Mesh(upper.points + [2.5, shift, 2.0 * HALF], triangles=upper.triangles)


def two_plies(
    shift: float,
    upper_cells: int = 6,
    lower_cells: int = 4,
    lower_rule: str | None = None,
    **contact: Any,
) -> tuple[Model, int, np.ndarray]:
    """The two plies (module docstring), the upper one of ``upper_ply(shift, upper_cells)``
    over a lower one of ``lower_cells`` squared cells; ``lower_rule`` and ``contact``
    (penalty, friction, stick, rule, ...) to ``join_neighbours`` (the automatic penalty by
    default). Returns the model, the upper ply's first node id and its reference nodes
    (m, 3), mm."""
    lower = Mesh.rectangle(20.0, 20.0, nx=lower_cells, ny=lower_cells)
    upper = upper_ply(shift, upper_cells)
    first, cells = len(lower.points), len(lower.triangles)
    points = np.vstack([lower.points, upper.points])
    mesh = Mesh(
        points,
        triangles=np.vstack([lower.triangles, upper.triangles + first]),
        node_sets={"ply_1": np.arange(first), "ply_2": np.arange(first, len(points))},
        element_sets={
            "ply_1": np.arange(cells),
            "ply_2": cells + np.arange(len(upper.triangles)),
        },
    )
    model = Model(mesh)
    model.add(mindlin_ply(PLY), cells="ply_1")
    model.add(mindlin_ply(PLY), cells="ply_2")
    join_neighbours(model, 2, HALF, lower_rule, **contact)
    model.fix(np.arange(first))
    up = upper.points
    model.fix(first + np.flatnonzero(up[:, 1] >= up[:, 1].max() - 1e-9))
    model.gravity((0.0, 0.0, -GRAVITY))
    return model, first, up
