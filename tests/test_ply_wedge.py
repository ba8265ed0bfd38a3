"""A ply contact point going round an outline vertex of three triangles past the outline.

What was left at the outline of the two-ply Mindlin [0/90] hemisphere (validation/studies/
hemisphere_plies_jumps.py, 8 and 10 cells, 20 N; docs/hemisphere_plies.md, "Growths joined at
a fold"): every jump of the mirrored pass lay at an outline vertex whose fan holds three
triangles, the outline triangles A and B grown past their outline edges up to the lines of
their inner edges and the middle triangle M not grown, where the sign of the gap flipped at a
distance as the nearest feature changed.

The two growths overlapped: A's grown triangle reaches past v up to the line of its inner
edge v-a, on the side of A's outline edge, which holds the whole wedge past v between the lines
of v-a and v-b (M's angle mirrored through v), and so did B's (A and its growth span pi at v,
as B and its growth, round a fan of alpha_A + alpha_M + alpha_B: the outside was covered
alpha_M twice). Across a fold the two planes there sign a point between them oppositely, and
where the nearest of the two changed, at equal distances, the gap flipped from -|g| to +|g|:
1.01 of the largest energy in one step. Now each growth is cut by a ray from v fixed at bind
in its own triangle's barycentric coordinates (elements/ply_wedge.py): turned from the line
where A's and B's planes meet at bind (from the wedge's bisector on a flat fan) by GAP of the
wedge's angle towards its own side, leaving a thin gap between the two growths where a point
beside a cut is faded by the angle's fade (docs/hemisphere_plies.md, "The wedge is an
overlap").

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
from ply_point_loops import point_round, translational_tangent, walk

from elements.ply_projection import open_edges
from femcore.state import State

STEPS = 1000
PENALTY = 100.0  # N/mm
SLOPE = 2.0  # mm a mm: A's and B's fall across the fold
RADIUS = 0.08  # mm
PAST = 0.05  # mm past the outline y = 0


def _fan(flat_at_bind: bool = False):
    """(block, positions (STEPS + 1, n, 3), directors (n, 3)): the fan of the module docstring
    and the upper triangle's path round its vertex, bound as a ply contact of penalty
    PENALTY at the centroid; ``flat_at_bind``: bound with the lower ply laid flat (z = 0),
    folded after, as a flat blank folds in forming."""
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
    flat = np.column_stack([plan, np.zeros(len(plan))])
    block, positions, directors = point_round(
        low,
        lower,
        steps=STEPS,
        penalty=PENALTY,
        radius=RADIUS,
        past=PAST,
        bound_at=flat if flat_at_bind else None,
    )
    return block, positions, directors, lower


def test_the_fan_has_three_triangles_at_its_outline_vertex_and_two_outline_edges_there():
    """The premise of the path: v (node 0) is held by A, M and B, ends A's and B's outline
    edges, and M has none at v; A's and B's growths are cut there (A's from its corner 2, B's
    from its corner 0), M is not."""
    block, _, _, lower = _fan()
    cut = np.any(block.cuts.lines != 0.0, axis=2)
    assert cut[0, 2] and cut[2, 0] and not cut[0, :2].any() and not cut[1].any()
    outline = open_edges(lower)
    at_v = np.flatnonzero((lower == 0).any(axis=1))
    assert at_v.tolist() == [0, 1, 2]
    # the edge opposite corner k ends at v where v is another corner of the triangle
    ends_at_v = [
        bool(outline[row, k]) and 0 in np.delete(lower[row], k) for row in at_v for k in range(3)
    ]
    assert sum(ends_at_v[0:3]) == 1 and sum(ends_at_v[3:6]) == 0 and sum(ends_at_v[6:9]) == 1


@functools.cache
def _loop(flat_at_bind: bool = False):
    """(energy (STEPS + 1,) N mm, work (STEPS,) N mm of each step by the trapezoidal rule,
    touching (STEPS + 1,) bool, fades (STEPS + 1,)) of the point round the vertex."""
    walked = walk(*_fan(flat_at_bind)[:3])
    return walked["energy"], walked["work"], walked["touching"], walked["fade"]


@pytest.mark.parametrize("flat_at_bind", [False, True], ids=["folded at bind", "flat at bind"])
def test_the_point_round_the_vertex_touches_on_part_of_its_path_past_the_outline(flat_at_bind):
    """The premises of the energy's test below: the point touches on part of the loop and
    not on another, with a fade below 1 (past the outline) where it touches."""
    energy, _, touching, fades = _loop(flat_at_bind)
    assert energy.max() > 1e-3 and touching.any() and not touching.all()
    assert fades[touching].max() < 1.0 and fades[touching].min() > 0.0


@pytest.mark.parametrize("flat_at_bind", [False, True], ids=["folded at bind", "flat at bind"])
def test_a_point_round_an_outline_vertex_of_three_triangles_works_its_energy(flat_at_bind):
    """Per step |Delta E - work| within 0.05 of the largest energy on the path, and around
    the loop the work within 0.05 of it (the trapezoidal rule's error where the force turns
    by a fold's angle in one step, as in tests/test_ply_growth_sign.py). Measured: 0.025 of
    the largest energy (the step where the point, inside the fold below v, passes from A's
    plane to B's at x = 0); with the growths overlapping (the code before the cuts) 1.01 in
    the step where the point, outside the fold at x = +0.08 mm, passed from B's plane
    (+0.0716 mm) to A's (-0.0716 mm, A's growth holding its projection past v), and back at
    the loop's end. Bound flat and folded after (the cuts then turn from the bisector of the
    flat fan): 0.025 measured, 1.03 with the growths overlapping."""
    energy, work, _, _ = _loop(flat_at_bind)
    largest = energy.max()
    assert np.abs(np.diff(energy) - work).max() <= 0.05 * largest
    assert abs(work.sum()) <= 0.05 * largest


def _beside_the_cut(block, low, out, behind):
    """The face point 0.03 mm from v along A's cut (bound flat, walked folded), ``out`` mm
    across it in A's plane (> 0: out of A's cut growth, into the gap) and ``behind`` mm behind
    A's offset face (the lower face 0.1 mm above the mid-surface along z)."""
    row, corner = 0, 2  # A = (x1, a, v): v is its corner 2
    y = low[block.cells[row]] + [0.0, 0.0, 0.1]
    start = y[corner]
    along = block.cuts.ends[row, corner] @ y - start
    along /= np.linalg.norm(along)
    normal = np.cross(y[1] - y[0], y[2] - y[0])
    normal /= np.linalg.norm(normal)
    across = np.cross(normal, along)
    # out of the growth: where the cut's line l(lambda) falls
    gradients = np.linalg.pinv(np.column_stack([y[0] - y[2], y[1] - y[2]]))
    level = block.cuts.lines[row, corner][:2] - block.cuts.lines[row, corner][2]
    if level @ gradients @ across > 0.0:
        across = -across
    return start + 0.03 * along + out * across - behind * normal


@pytest.mark.parametrize(
    "out, behind, beside",
    [(0.001, 0.02, True), (0.001, 0.05, True), (-0.003, 0.02, False), (-0.003, 0.05, False)],
    ids=["gap-0.02", "gap-0.05", "growth-0.02", "growth-0.05"],
)
def test_the_force_beside_a_cut_is_the_energys_gradient_and_the_tangent_its_derivative(
    out, behind, beside
):
    """Near A's cut (the fan bound flat, folded into a valley of a tenth of the path's slope): a
    point 0.001 mm across the cut in the gap between the growths, its closest point on the cut
    (signed by A's normal, faded by the angle), and one 0.003 mm inside A's cut growth, held by its
    plane, both touching 0.02 and 0.05 mm behind the face. Reference: central differences of the
    energy over every node's coordinates (step 1e-7 mm: round-off ~1e-9 of the force, truncation
    ~1e-14 mm^2 times its third derivative) give the force within 1e-6 of its largest component;
    central differences of that force give the tangent's translational blocks within 1e-7 of its
    largest entry (their round-off, ~1e-16 of the force over the 1e-7 mm step, measured 0.9-5.9e-10
    here; the fade's own second derivative in the tangent in closed form,
    elements/ply_fade_hessian.py; tests/test_ply_fade_hessian.py holds it to the central
    differences' own error)."""
    block, positions, directors, _ = _fan(flat_at_bind=True)
    x = positions[0].copy()
    low = x[: len(x) - 3]
    low[:, 2] *= -0.1  # a gentle valley (A's and B's normals 23 deg apart): A faces the points
    face = _beside_the_cut(block, low, out, behind)
    tiny = x[-3:] - x[-3:].mean(axis=0)
    x[-3:] = tiny + face + [0.0, 0.0, 0.1]
    zero = np.zeros_like(x)

    def state(at):
        return State(at, directors, zero, zero)

    facing = block.facing(state(x))
    assert facing.triangle[0] == 0 and facing.touching[0]  # the premises: A faces it
    assert bool(facing.on_growth[0]) == beside and 0.0 < facing.fade[0] < 1.0
    force = block.internal_force(state(x))[0]
    step = 1e-7
    central = np.zeros_like(x)
    stiffness = np.zeros((x.size, x.size))
    for node in range(len(x)):
        for axis in range(3):
            plus, minus = x.copy(), x.copy()
            plus[node, axis] += step
            minus[node, axis] -= step
            central[node, axis] = (
                block.strain_energy(state(plus)) - block.strain_energy(state(minus))
            ) / (2.0 * step)
            stiffness[:, 3 * node + axis] = (
                block.internal_force(state(plus))[0] - block.internal_force(state(minus))[0]
            ).ravel() / (2.0 * step)
    assert np.abs(force).max() > 0.0
    assert np.abs(force - central).max() <= 1e-6 * np.abs(force).max()
    tangent = translational_tangent(block, state(x))
    assert np.abs(tangent - stiffness).max() <= 1e-7 * np.abs(stiffness).max()


@pytest.mark.parametrize(
    "angles_deg", [(120.0, 140.0, 10.0), (100.0, 60.0, 100.0), (60.0, 100.0, 110.0)]
)
def test_no_cut_takes_away_part_of_its_own_triangle(angles_deg):
    """A cut only shortens a growth past the outline: every corner of its own triangle stays
    on the kept side (l(e_j) >= 0). Fans flat round v with A, M, B of ``angles_deg`` (a
    re-entrant corner of 270 deg, a corner of 260 deg with a wide wedge, a convex one); in the
    first, A's half of the wedge with the gap (84 deg) is wider than its growth's angle past
    v (60 deg), where a ray turned that far ran into A and cut 29 % of it away."""
    from elements.ply_wedge import WedgeCuts

    turns = np.radians(180.0 + np.r_[0.0, np.cumsum(angles_deg)])
    plan = np.vstack([[0.0, 0.0], np.column_stack([np.cos(turns), np.sin(turns)])])
    y_nodes = np.column_stack([plan, np.zeros(len(plan))])
    nodes = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4]])
    y = y_nodes[nodes]
    outline = open_edges(nodes)
    cuts = WedgeCuts.of(y, nodes, outline, np.where(outline, 0.5, 0.0))
    assert cuts.lines.any()  # the fan is cut: the test reaches the rule
    own = np.einsum("mkj,jc->mkc", cuts.lines, np.eye(3))  # l at each own corner
    assert own.min() >= -1e-12


@pytest.mark.parametrize("height", [0.3, 1.0])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_triangle_cut_at_both_ends_gives_closest_points_of_its_cut_growth(height, seed):
    """Outline triangles of a short strip ``height`` mm high, its nodes jittered by 0.05 mm in
    its plane and 0.2 mm out of it (each with an outline edge between two outline vertices of
    three triangles), are cut at both ends; where the two cuts' segments cross, each is
    ended at the other's line, so that the closest point returned lies in the cut growth
    and no point of the growth is nearer. Reference: a dense sample of the cut growth
    (barycentric steps of 0.004) and its nearest point by a k-d tree; tolerance, the
    sample's spacing. Before the segments were ended, returned points lay outside the
    growth, up to 0.1 of the triangle's side nearer than any of its points."""
    from scipy.spatial import cKDTree

    from elements.ply_projection import MARGIN
    from elements.ply_wedge import closest_on_grown, cut_keeps

    rng = np.random.default_rng(seed)
    nodes, y, outline, cuts = cut_strip(rng, height)
    reach = np.where(outline, MARGIN, 0.0)
    twice = np.flatnonzero(np.any(cuts.lines != 0.0, axis=2).sum(axis=1) == 2)
    assert twice.size >= 1  # the premise: a triangle cut at both ends
    steps = np.linspace(-MARGIN, 1.0 + 2.0 * MARGIN, 301)
    a, b = np.meshgrid(steps, steps)
    grid = np.column_stack([a.ravel(), b.ravel(), 1.0 - a.ravel() - b.ravel()])
    for row in twice:
        inside = grid[(grid >= -reach[row] - 1e-12).all(axis=1)]
        kept = inside[cut_keeps(inside, np.broadcast_to(cuts.lines[row], (len(inside), 3, 3)))]
        sample = kept @ y[row]
        size = np.linalg.norm(y[row, 1] - y[row, 0])
        spacing = 2.0 * (steps[1] - steps[0]) * size
        p = y[row].mean(axis=0) + rng.normal(0.0, size, (200, 3))
        count = len(p)
        q = closest_on_grown(
            p,
            np.broadcast_to(y[row], (count, 3, 3)).copy(),
            np.broadcast_to(reach[row], (count, 3)).copy(),
            np.broadcast_to(cuts.lines[row], (count, 3, 3)).copy(),
            np.broadcast_to(cuts.ends[row], (count, 3, 3)).copy(),
        )[0]
        nearest = cKDTree(sample).query(p)[0]
        distance = np.linalg.norm(p - q, axis=1)
        assert (distance >= nearest - spacing).all(), row  # no nearer than the growth allows
        assert (distance <= nearest + spacing).all(), row


def cut_strip(rng: np.random.Generator, height: float, cells: int = 4):
    """A short strip of ``cells`` squares' width along x, ``height`` mm high, of outline
    triangles (each outline vertex of three triangles), its nodes jittered by 0.05 mm in its
    plane and 0.2 mm out of it, cut at both ends: (nodes (m, 3), corners y (m, 3, 3), outline
    (m, 3), WedgeCuts)."""
    from elements.ply_projection import MARGIN
    from elements.ply_wedge import WedgeCuts

    top = [(float(i), 0.0) for i in range(cells + 1)]
    bottom = [(0.5 * j, -height) for j in range(2 * cells + 1)]
    plan = np.array(top + bottom)
    off_plane = rng.normal(0.0, 0.2, len(plan))
    points = np.column_stack([plan + rng.normal(0.0, 0.05, plan.shape), off_plane])
    below = cells + 1
    nodes = [(i, below + 2 * i + 1, i + 1) for i in range(cells)]
    for i in range(cells + 1):
        if i > 0:
            nodes.append((i, below + 2 * i - 1, below + 2 * i))
        if i < cells:
            nodes.append((i, below + 2 * i, below + 2 * i + 1))
    nodes = np.array(nodes)
    y = points[nodes]
    flipped = np.cross(y[:, 1] - y[:, 0], y[:, 2] - y[:, 0])[:, 2] < 0.0
    nodes[flipped] = nodes[flipped][:, [0, 2, 1]]
    y = points[nodes]
    outline = open_edges(nodes)
    cuts = WedgeCuts.of(y, nodes, outline, np.where(outline, MARGIN, 0.0))
    return nodes, y, outline, cuts
