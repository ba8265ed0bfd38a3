"""A ply overhanging the outline edge of a ply held whole, against its twin over a rigid table's
edge and against the heavy strip over a rigid edge in closed form: where the support ends.

The model (tests/test_ply_overhang.py): an upper Mindlin ply (10 x 10 mm on 12 x 12 cells, h =
0.5 mm, bending D = 0.05 N mm per unit width, q = 9.81e-5 N/mm^2) clamped at its edge of
largest y, L = 4 mm past the lower ply's outline edge y = 0, under gravity, solved by Static
at its defaults with the automatic penalty; the ply contact's points at the upper ply's nodes
(``rule="nodes"``, the node-to-surface of the rigid table's contact) but in the last test.
The upper ply's node rows nearest the edge lie 0.667 mm past it and 0.167 mm behind it.

Reference: the heavy strip resting on a rigid flat and pivoting on its edge (Euler-Bernoulli,
derived in tests/test_table_contact.py): the tip droops (1/8 + sqrt(2)/12) q L^4 / D below
the face, L the overhang past the support's end, 0.122 mm at L = 4 mm; the droop grows as L^4,
so a support that ends past the edge lessens it and one that ends behind it adds to it.

The ply contact fades past the lower ply's outline: a point's energy w W(g), w = S(1 - d / D_f)
falling from 1 at the outline edge to 0 at D_f = 0.15 h_l past it (h_l the least height of the
lower ply's outline triangles over the outline; elements/ply_fade.py, docs/theory.md §9.3a),
so a point up to D_f past the edge still touches, held by the stiff automatic penalty even
where w is small. On 4 x 4 lower cells (h_l = 5 mm, D_f = 0.75 mm) the node row 0.667 mm past
the edge is held (w = 0.036); on 8 x 8 (D_f = 0.375 mm) no node lies in the band, and the ply
rests as on the rigid table (RigidSurface, the independent node-to-surface contact of
elements/contact.py). With the mirrored pass at the lower ply's nodes (the last test, the upper
ply's points at its centroids), the lower ply's outline nodes hold the upper ply at the edge
itself. benchmarks/ply_margin.py has the study (both rules, the twins as either ply is
refined, the fade's length and the growths' reach varied, the mirrored pass).
"""

import numpy as np
import pytest

from elements import RigidSurface
from elements.plies import mindlin_ply
from femcore import Mesh, Model
from solvers import Static
from validation.studies.ply_overhang_setup import HALF, PLY, two_plies, upper_ply

BENDING = 0.05  # D, N mm: PLY's linear bending law (validation/studies/ply_overhang_setup.py)
OVERHANG, CELLS = 4.0, 12
WEIGHT = PLY.areal_density * 9810.0  # q, N/mm^2


def droop(overhang: float) -> float:
    """The closed-form tip droop (mm) of the heavy strip overhanging a rigid edge by
    ``overhang`` mm (module docstring)."""
    return (1.0 / 8.0 + np.sqrt(2.0) / 12.0) * WEIGHT * overhang**4 / BENDING


def _upper() -> tuple[np.ndarray, np.ndarray]:
    upper = upper_ply(-OVERHANG, CELLS)
    return upper.points, upper.triangles


def _tip(positions: np.ndarray, up: np.ndarray) -> float:
    """The droop of the free edge's middle node below the upper ply's plane, mm."""
    free = np.flatnonzero(up[:, 1] <= -OVERHANG + 1e-9)
    return 2.0 * HALF - positions[free[np.argmin(np.abs(up[free, 0] - 7.5))], 2]


def _on_ply(
    lower_cells: int, rule: str = "nodes", lower_rule: str | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """The upper ply's final positions on the lower ply (20 x 20 mm on ``lower_cells``
    squared cells, held whole), and its reference nodes; the ply contact's points at the upper
    ply's ``rule``, with the mirrored pass at the lower ply's ``lower_rule`` if given."""
    model, first, up = two_plies(-OVERHANG, CELLS, lower_cells, lower_rule, rule=rule)
    result = Static(progress=False).solve(model)
    assert result.converged
    return result.positions[first:], up


def _on_table() -> np.ndarray:
    """The upper ply's final positions over the rigid table, the lower ply's upper face."""
    up, triangles = _upper()
    model = Model(Mesh(up, triangles=triangles))
    model.add(mindlin_ply(PLY))
    top = Mesh.rectangle(20.0, 20.0, nx=4, ny=4)
    model.contact(RigidSurface(Mesh(top.points + [0.0, 0.0, HALF], triangles=top.triangles)))
    model.fix(np.flatnonzero(up[:, 1] >= up[:, 1].max() - 1e-9))
    model.gravity((0.0, 0.0, -9810.0))
    result = Static(progress=False).solve(model)
    assert result.converged
    return result.positions


def test_a_ply_with_no_point_in_the_fade_rests_as_over_a_rigid_table_edge():
    """Lower ply on 8 x 8 cells (D_f = 0.375 mm, no upper node within it past the edge): the
    upper ply rests where its twin over the rigid table rests, every node within 1e-2 of the
    tip's droop (measured 5.8e-4 mm, 4e-3: the two contacts' penalty laws differ, the ply's
    ramped), and both droop as the closed form's strip whose support ends at the last node
    behind the edge (0.167 mm) within 3 % (measured 0.8 % on the table, 1.2 % on the ply;
    the table's droop changes by 0.2 % from 12 to 24 upper cells, which put that node at the
    same place): 1.18 times the droop over the edge itself, so the last node's place, not
    the contact, is the error of either twin at this mesh."""
    on_ply, up = _on_ply(8)
    on_table = _on_table()
    tip = _tip(on_table, up)
    assert np.abs(on_ply - on_table).max() <= 1e-2 * tip
    behind = 2.0 / CELLS  # the last node row before the edge, mm behind it
    expected = droop(OVERHANG + behind)
    assert abs(tip - expected) <= 3e-2 * expected
    assert abs(_tip(on_ply, up) - expected) <= 3e-2 * expected


def test_the_fade_holds_a_ply_up_to_its_length_past_the_outline():
    """Lower ply on 4 x 4 cells (D_f = 0.75 mm): the node row 0.667 mm past the outline edge,
    within the fade's band, carries the ply, which droops as the strip whose support ends
    there: less than over the edge itself, more than over a support D_f past it (measured
    0.060 mm, the closed form's 0.057 at 0.667 mm past and 0.122 at the edge)."""
    on_ply, up = _on_ply(4)
    tip = _tip(on_ply, up)
    fade = 0.15 * 5.0  # D_f: FADE times the outline triangles' height, mm
    assert droop(OVERHANG - fade) < tip < droop(OVERHANG - 0.5 * fade)


@pytest.mark.slow
def test_the_mirrored_pass_holds_a_ply_at_the_outline_edge_itself():
    """The ply contact at the upper ply's centroids with its mirrored pass at the lower ply's
    nodes, lower ply on 32 x 32 cells (D_f = 0.094 mm; no upper centroid within it past the
    edge): the lower ply's outline nodes, on the edge itself, hold the upper ply there, and it
    droops as the strip whose support ends between the edge and D_f past it, within 1 % (the
    table's twin's distance from its own closed form at these cells, 0.8 %): measured 0.1176
    mm, between 0.1109 (D_f past) and 0.1220 (the edge). Without the mirrored pass the
    support ends at the last centroid before the edge, 0.449 mm behind, and the tip droops
    0.1775 mm (benchmarks/ply_margin.py)."""
    on_ply, up = _on_ply(32, "centroid", "nodes")
    tip = _tip(on_ply, up)
    fade = 0.15 * 20.0 / 32  # D_f, mm
    assert 0.99 * droop(OVERHANG - fade) < tip < 1.01 * droop(OVERHANG)
