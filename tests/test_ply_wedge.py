"""A ply contact point going round an outline vertex of three triangles past the outline.

What was left at the outline of the two-ply Mindlin [0/90] hemisphere (validation/studies/
hemisphere_plies_jumps.py, 8 and 10 cells, 20 N; docs/hemisphere_plies.md, "Growths joined at
a fold"): every jump of the mirrored pass lay at an outline vertex whose fan holds three
triangles, the outline triangles A and B grown past their outline edges up to the lines of
their inner edges and the middle triangle M not grown, where the sign of the gap flipped at a
distance as the nearest feature changed.

The two growths do not leave the wedge past v between the lines of their inner edges (M's
angle mirrored through v) to no growth: A's grown triangle reaches past v up to the line of
its inner edge v-a, on the side of A's outline edge, which holds that whole wedge, and so does
B's, so the growths overlap there by M's angle alpha_M (A and its growth span pi at v, as B and
its growth, round a fan of alpha_A + alpha_M + alpha_B: the outside is covered 2 pi -
alpha_A - alpha_B = alpha_M twice). Across a fold the two planes there sign a point between
them oppositely, and where the nearest of the two changes, at equal distances, the gap flips
from -|g| to +|g|. A growth of M into the wedge (its plane, {lambda_a <= 0, lambda_b <= 0} by v,
met by A's and B's growths along the lines of M's edges and signed there by the edges'
pseudonormals) adds a third sheet over the same wedge and leaves the flip (measured: the same
1.01 of the largest energy in one step); what would join the growths is a cut of each along
the line where A's and B's planes meet past v, signed by n_A + n_B, whose gap moves the other
triangle's corners too (docs/hemisphere_plies.md, "The wedge is an overlap").

Reference: the contact is a potential, its force the gradient of its energy, so along any
path the work of the force equals the change of the energy (trapezoidal rule per step), and
around a closed path the work is nil. The lower ply: the vertex v = (0, 0) with the outline
edges to (-1, 0) (A's) and (1, 0) (B's), A, M, B round it down to a = (-0.5, -1) and
b = (0.5, -1), one row below so that v is the only outline vertex of the fan; folded along
v-a and v-b, the surface z = -SLOPE |x| on A and B and M a plane through v, a and b (A's and
B's normals 127 deg apart, M's between). Faces 0.1 mm from the mid-surfaces. One upper
triangle (its centroid the contact point, 0.02 mm across, moved rigidly, the directors held
along z) circles the point v + PAST y in the x-z plane at RADIUS.
"""

import functools

import numpy as np
import pytest
from ply_point_loops import point_round, walk

from elements.ply_projection import open_edges

STEPS = 1000
PENALTY = 100.0  # N/mm
SLOPE = 2.0  # mm a mm: A's and B's fall across the fold
RADIUS = 0.08  # mm
PAST = 0.05  # mm past the outline y = 0


def _fan():
    """(block, positions (STEPS + 1, n, 3), directors (n, 3)): the fan of the module docstring
    and the upper triangle's path round its vertex, bound as a ply contact of penalty
    PENALTY at the centroid."""
    plan = np.array(
        [
            [0.0, 0.0],  # 0 v
            [-1.0, 0.0],  # 1 x1
            [-0.5, -1.0],  # 2 a
            [0.5, -1.0],  # 3 b
            [1.0, 0.0],  # 4 x2
            [-1.0, -1.0],  # 5
            [0.0, -1.5],  # 6
            [1.0, -1.0],  # 7
        ]
    )
    low = np.column_stack([plan, -SLOPE * np.abs(plan[:, 0])])
    low[6, 2] = low[2, 2]  # the row below level with a and b
    # counter-clockwise about +z: A = (x1, a, v), M = (v, a, b), B = (v, b, x2)
    lower = np.array([[1, 2, 0], [0, 2, 3], [0, 3, 4], [1, 5, 2], [2, 6, 3], [3, 7, 4]])
    block, positions, directors = point_round(
        low, lower, steps=STEPS, penalty=PENALTY, radius=RADIUS, past=PAST
    )
    return block, positions, directors, lower


def test_the_fan_has_three_triangles_at_its_outline_vertex_and_two_outline_edges_there():
    """The premise of the path: v (node 0) is held by A, M and B, ends A's and B's outline
    edges, and M has none at v."""
    _, _, _, lower = _fan()
    outline = open_edges(lower)
    at_v = np.flatnonzero((lower == 0).any(axis=1))
    assert at_v.tolist() == [0, 1, 2]
    # the edge opposite corner k ends at v where v is another corner of the triangle
    ends_at_v = [
        bool(outline[row, k]) and 0 in np.delete(lower[row], k) for row in at_v for k in range(3)
    ]
    assert sum(ends_at_v[0:3]) == 1 and sum(ends_at_v[3:6]) == 0 and sum(ends_at_v[6:9]) == 1


@functools.cache
def _loop():
    """(energy (STEPS + 1,) N mm, work (STEPS,) N mm of each step by the trapezoidal rule,
    touching (STEPS + 1,) bool, fades (STEPS + 1,)) of the point round the vertex."""
    walked = walk(*_fan()[:3])
    return walked["energy"], walked["work"], walked["touching"], walked["fade"]


def test_the_point_round_the_vertex_touches_on_part_of_its_path_past_the_outline():
    """The premises of the energy's test below: the point touches on part of the loop and
    not on another, with a fade below 1 (past the outline) where it touches."""
    energy, _, touching, fades = _loop()
    assert energy.max() > 1e-3 and touching.any() and not touching.all()
    assert fades[touching].max() < 1.0 and fades[touching].min() > 0.0


@pytest.mark.xfail(
    strict=True,
    reason="A's and B's growths overlap past an outline vertex of three triangles: the gap "
    "flips where the nearest of their planes changes (module docstring)",
)
def test_a_point_round_an_outline_vertex_of_three_triangles_works_its_energy():
    """Per step |Delta E - work| within 0.05 of the largest energy on the path, and around
    the loop the work within 0.05 of it (the trapezoidal rule's error where the force turns
    by a fold's angle in one step, as in tests/test_ply_growth_sign.py). Measured on the code
    as it stands: 1.01 of the largest energy in the step where the point, outside the fold
    at x = +0.08 mm, passes from B's plane (+0.0716 mm) to A's (-0.0716 mm, A's growth
    holding its projection past v), and back at the loop's end."""
    energy, work, _, _ = _loop()
    largest = energy.max()
    assert np.abs(np.diff(energy) - work).max() <= 0.05 * largest
    assert abs(work.sum()) <= 0.05 * largest
