"""The gap of a ply contact point as it slides past a ridge of the lower ply's face.

What stopped the Mindlin [0/45] two-ply hemisphere (validation/studies/hemisphere_plies.py,
coarse, 10 N) at 91 % of the stroke on the explicit energy balance: one contact point of the
top ply, pressed into a wrinkle crest of the bottom ply under the holder and lying outside
both triangles of the crest (0.2 past their edges in barycentric units), was handed by the
search from one triangle's extended plane (gap -0.45 mm) to the other's (-2.24 mm) in one step:
+55.5 N mm of penalty energy made without work, 2.2 % of the run's largest energy at once.

Reference: the gap of a point to a surface is a distance, 1-Lipschitz in the point's position:
a point moved by s cannot change it by more than s. Two triangles folded 50 deg about their
shared edge (a ridge, as a wrinkle's crest); a point 0.2 mm below the flat one's plane moved
along a line in steps of 1e-3 mm past the ridge's end, where neither triangle holds its
projection.
"""

import numpy as np

from elements.ply_projection import closest_facing

STEP = 1e-3  # mm, between the points of the path


def _ridge_and_path():
    fold = np.radians(50.0)
    middle = np.array([0.5, 0.5, 0.0])
    across = np.array([1.0, 1.0, 0.0]) / np.sqrt(2.0)
    apex = middle + np.cos(fold) * across + np.array([0.0, 0.0, np.sin(fold)])
    triangles = np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[1, 0, 0], apex, [0, 1, 0]]], float)
    s = np.arange(-0.5, 1.5, STEP / np.sqrt(2.0))
    path = np.column_stack([s + 0.7, s - 0.7, np.full_like(s, -0.2)])
    return triangles, path


def test_the_path_crosses_a_change_of_facing_triangle_while_touching():
    # The premise of the test below: on this path the search changes its triangle next to
    # a touching point, past both triangles' edges.
    triangles, path = _ridge_and_path()
    facing = closest_facing(path, triangles, np.tile([0, 1], (len(path), 1)), 0.0)
    switch = np.flatnonzero(np.diff(facing.triangle) != 0)
    assert any(facing.touching[i] or facing.touching[i + 1] for i in switch)


def test_a_touching_points_gap_moves_no_more_than_the_point():
    triangles, path = _ridge_and_path()
    facing = closest_facing(path, triangles, np.tile([0, 1], (len(path), 1)), 0.0)
    either = facing.touching[1:] | facing.touching[:-1]
    jumps = np.abs(np.diff(facing.gap))[either]
    assert jumps.max() <= 1.01 * STEP


def _crumpled_sheet(rng, size=6, cell=1.0, amplitude=0.35):
    """A size x size grid of unit cells, two triangles each (counter-clockwise about +z),
    its nodes lifted by up to ``amplitude`` mm at random: ridges and valleys everywhere."""
    grid = np.arange(size + 1)
    x, y = np.meshgrid(grid * cell, grid * cell, indexing="ij")
    nodes = np.column_stack([x.ravel(), y.ravel(), amplitude * rng.uniform(-1, 1, x.size)])
    at = (grid[:-1, None] * (size + 1) + grid[None, :-1]).ravel()
    cells = np.vstack(
        [
            np.column_stack([at, at + size + 1, at + size + 2]),
            np.column_stack([at, at + size + 2, at + 1]),
        ]
    )
    return nodes, cells


def _height(x, cells, p):
    """(P,) the height of the sheet (nodes x, triangles ``cells``) above each point's (x, y)."""
    corners = x[cells][:, :, :2]  # (m, 3, 2)
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]

    def cross(u, v):
        return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]

    area = cross(b - a, c - a)
    q = p[:, None, :2]
    weights = np.stack([cross(c - b, q - b), cross(a - c, q - c), cross(b - a, q - a)], axis=-1)
    weights /= area[None, :, None]
    row = np.argmax(weights.min(axis=-1), axis=1)  # the triangle under the point
    at = np.arange(len(p))
    return np.einsum("pk,pk->p", weights[at, row], x[cells[row], 2])


def test_the_contact_energy_changes_by_minus_the_work_of_its_forces():
    """Points pressed 0.1-0.3 mm into a crumpled sheet of 1-mm cells (nodes lifted by up to
    0.35 mm: ridges and valleys, every point against every triangle) slide 3 mm across it
    while the sheet's nodes move too, in 600 steps: the change of sum W(g) equals the work
    of the contact forces (W' nu on each point, -lambda_k W' nu on the facing triangle's
    corners, trapezoidal rule) within 1e-2 of the energy's range over the path (measured
    6e-4 here, 1.5e-3 with other points: the rule's error where the force turns about a
    vertex). Before, with the nearest triangle's extended plane where no candidate held the
    projection and the deepest of those that held it, the gap jumped where the choice
    changed (-0.28 -> -0.45 mm in a step): 13.0 N mm off in 44 (0.29)."""
    from elements.ply_projection import closest_facing, open_edges, penalty_law

    rng = np.random.default_rng(7)
    nodes, cells = _crumpled_sheet(rng)
    outline = open_edges(cells)
    start = np.column_stack([rng.uniform(1.5, 3.0, 12), rng.uniform(1.5, 4.5, 12), np.zeros(12)])
    drift = np.array([3.0, 0.3, 0.0])
    wobble = 0.05 * rng.standard_normal(nodes.shape)  # the sheet's own motion over the path
    stiffness, smoothing = np.full(len(start), 100.0), 0.01
    everything = np.tile(np.arange(len(cells)), (len(start), 1))

    def loads(s):
        x = nodes + s * wobble
        p = start + s * drift
        p[:, 2] = _height(x, cells, p) - 0.1 - 0.2 * np.sin(np.pi * s)
        facing = closest_facing(p, x[cells], everything, 0.0, outline)
        on = facing.touching
        energy, slope, _ = penalty_law(facing.gap, stiffness, smoothing)
        energy, slope = np.where(on, energy, 0.0), np.where(on, slope, 0.0)
        on_point = slope[:, None] * facing.normal
        on_nodes = np.zeros_like(x)
        for k in range(3):
            np.add.at(on_nodes, cells[facing.triangle, k], -facing.weights[:, k, None] * on_point)
        return energy.sum(), on_point, on_nodes, p, x

    steps = np.linspace(0.0, 1.0, 601)
    records = [loads(s) for s in steps]
    energy = np.array([r[0] for r in records])
    work = 0.0
    for a, b in zip(records[:-1], records[1:]):
        work += 0.5 * np.sum((a[1] + b[1]) * (b[3] - a[3])) + 0.5 * np.sum(
            (a[2] + b[2]) * (b[4] - a[4])
        )
    assert energy.max() > 1.0  # the points press in all along
    assert abs(energy[-1] - energy[0] - work) <= 1e-2 * np.ptp(energy)


def _strip_beside_its_outline():
    """A 2 x 1 strip of four triangles (counter-clockwise about +z), its right half turned
    45 deg down about x = 1 (a wrinkle's flank), and a path 2e-3 mm long per step through the
    left triangle's plane at (1.3, -0.2): 0.2 past the outline y = 0 and 0.1 past the inner
    edge x + y = 1, beside the outline next to its vertex (1, 0)."""
    nodes = np.array(
        [[0, 0, 0], [1, 0, 0], [2, 0, -1], [0, 1, 0], [1, 1, 0], [2, 1, -1]], dtype=float
    )
    cells = np.array([[0, 1, 3], [1, 4, 3], [1, 2, 4], [2, 5, 4]])
    z = np.arange(0.05, -0.05, -2.0 * STEP)
    path = np.column_stack([np.full_like(z, 1.3), np.full_like(z, -0.2), z])
    return nodes[cells], cells, path


def test_a_point_beside_the_outline_does_not_touch_as_it_passes_the_plane():
    """The point is nearest to the left triangle's inner edge x + y = 1 extended past the
    outline (its growth by MARGIN), 0.07 mm away in the plane. Its gap, signed by the
    triangle's normal, flipped from +0.07 to -0.07 mm as the point passed the plane: a
    touching point whose gap moved 70 times as far as the point (the +92 N mm jump that
    stopped the Mindlin [0/45] hemisphere, elements/ply_projection.py "Beside the outline").
    The reference is the one of the test above, a touching point's gap moves no more than
    the point; and the point lies beside the lower ply, past its outline and off every
    triangle, so it does not touch at all."""
    from elements.ply_projection import open_edges

    triangles, cells, path = _strip_beside_its_outline()
    facing = closest_facing(path, triangles, np.tile(np.arange(4), (len(path), 1)), 0.0,
                            open_edges(cells))  # fmt: skip
    assert np.all(facing.triangle == 0)  # the premise: the inner edge's extension is nearest
    either = facing.touching[1:] | facing.touching[:-1]
    jumps = np.abs(np.diff(facing.gap))[either]
    assert jumps.max(initial=0.0) <= 1.01 * 2.0 * STEP
    assert not facing.touching.any()


def test_a_point_past_a_fold_pressed_flat_does_not_touch_deeper_than_the_plies():
    """A unit triangle and its neighbour folded back onto it about their shared edge (a
    wrinkle's flap laid flat: the same place, opposite normals), the folded one first in the
    rows; a point 0.3 mm beside the fold's edge, in their plane, moves 2 mm across it. Both
    triangles tie on the edge and give it opposite signs: the tie's choice handed it
    -|p - q| (the +9.67 to -9.56 mm flip that stopped the Mindlin [0/90] hemisphere at 92 %
    of the stroke). A point facing an edge deeper than both faces' half thicknesses (0.3 mm
    here) has gone past the ply's edge: it does not touch (elements/ply_projection.py
    "Deeper than the plies"), so along the path its energy is nil."""
    nodes = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 0]], dtype=float)
    cells = np.array([[1, 3, 2], [0, 1, 2]])  # the fold (normal -z) first, then the sheet (+z)
    s = np.linspace(-1.0, 1.0, 201)
    beside = np.array([0.5, 0.5, 0.0]) + 0.3 * np.array([1.0, 1.0, 0.0]) / np.sqrt(2.0)
    path = beside + s[:, None] * np.array([0.0, 0.0, 1.0])
    facing = closest_facing(path, nodes[cells], np.tile([0, 1], (len(path), 1)), 0.0, depth=0.3)
    np.testing.assert_allclose(np.abs(facing.gap), np.hypot(0.3, s), rtol=1e-12)
    assert not facing.touching[np.abs(s) > 1e-9].any()


def test_a_point_over_a_fold_pressed_flat_keeps_its_touching_gap_continuous():
    """A sheet triangle (normal +z) with its flap folded back and pressed flat over it (the
    same footprint, normal -z), the flap tilted 0.02 about x = 1 so that the two planes cross
    (a flap is never pressed exactly flat); a point 2 mm above them slides 1.4 mm along x in
    steps of 1e-3 mm. Both triangles hold its projection, at 2 mm from the one and, past
    x ~ 0.98, a little less from the other, which gives it the opposite sign: the nearest
    switched from +2.00 to -2.00 mm in one step, a touching point 2 mm deep (the +4.97 to
    -4.98 mm switch that stopped the Mindlin [0/90] hemisphere at 97.2 % of the stroke,
    elements/ply_projection.py "Deeper than the plies"). Reference as above: a touching
    point's gap moves no more than the point. A point 2 mm behind a face of plies 0.3 mm
    thick (``depth``) is on the lower ply's other side: it does not touch."""
    sheet = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]
    flap = [[0.0, 0.0, -0.02], [0.0, 2.0, -0.02], [2.0, 0.0, 0.02]]  # clockwise about +z
    triangles = np.array([sheet, flap])
    x = np.arange(0.3, 1.7, STEP)
    path = np.column_stack([x, np.full_like(x, 0.2), np.full_like(x, 2.0)])
    near, up = np.tile([0, 1], (len(path), 1)), np.tile([0.0, 0.0, 1.0], (len(path), 1))
    facing = closest_facing(path, triangles, near, 0.0, depth=0.3, toward=up)
    # the premise: the facing triangle switches along the path, with the gap's sign
    switch = np.flatnonzero(np.diff(facing.triangle) != 0)
    assert switch.size == 1 and facing.gap[switch[0]] * facing.gap[switch[0] + 1] < 0.0
    either = facing.touching[1:] | facing.touching[:-1]
    jumps = np.abs(np.diff(facing.gap))[either]
    assert jumps.max(initial=0.0) <= 1.01 * STEP
    assert not facing.touching.any()


def test_a_point_at_an_outline_vertex_touches_all_round_it():
    """The strip above with its right half turned 45 deg up about x = 1: at the outline vertex
    (1, 0) three triangles meet, the middle one there only, and past the outline the growths
    of the two outline triangles (by MARGIN) leave a thin wedge that neither holds. A point
    0.01 mm behind the face circles the vertex at 0.008 mm in 2000 steps of 2.5e-5 mm: the
    node of a ply meshed as the ply above it, sitting under that ply's outline node (the
    two-ply [0/90] hemisphere, whose bottom ply's outline nodes went in and out of contact at
    gaps of -0.01 to -0.02 mm and stopped the run at 22 % of the stroke on its energy
    balance, the penalty energy of the toggles). In the wedge its closest point lay on a
    growth's edge a few 1e-3 mm off its triangle, "beside the outline", and it did not touch:
    its energy jumped by W(-0.01) = 7.1e-3 N mm where it entered the wedge. Reference: a
    point whose gap is continuous (a distance) exchanges energy only as its force works
    (the test of the contact energy above): per step, the change of W within 1e-2 of the
    largest W along the path (measured 9.6e-4: the trapezoidal rule's error where the force
    turns about the vertex; 1.0 before, the jump), and the point touches all round (it is
    behind the face, within MARGIN of the outline)."""
    from elements.ply_projection import open_edges, penalty_law

    nodes = np.array(
        [[0, 0, 0], [1, 0, 0], [2, 0, 1], [0, 1, 0], [1, 1, 0], [2, 1, 1]], dtype=float
    )
    cells = np.array([[0, 1, 3], [1, 4, 3], [1, 2, 4], [2, 5, 4]])
    angle = np.linspace(0.0, 2.0 * np.pi, 2001)
    path = np.column_stack(
        [1.0 + 0.008 * np.cos(angle), 0.008 * np.sin(angle), np.full_like(angle, -0.01)]
    )
    near = np.tile(np.arange(4), (len(path), 1))
    facing = closest_facing(path, nodes[cells], near, 0.0, open_edges(cells), depth=0.3)
    energy, slope, _ = penalty_law(facing.gap, np.full(len(path), 100.0), 1e-3)
    energy = np.where(facing.touching, energy, 0.0)
    force = np.where(facing.touching, slope, 0.0)[:, None] * facing.normal
    work = np.sum(0.5 * (force[1:] + force[:-1]) * np.diff(path, axis=0), axis=1)
    assert facing.gap.max() < 0.0  # the premise: behind the face all round
    assert np.abs(np.diff(energy) - work).max() <= 1e-2 * energy.max()
    assert facing.touching.all()


def test_a_point_past_the_outline_deeper_than_the_plies_does_not_touch():
    """A lone triangle (every edge on the outline, grown by MARGIN = 0.5 past each) and a point
    1 mm behind its plane, 0.4 to 0.6 past its edge y = 0 in barycentric units, crossing the
    growth's far edge in steps of 1e-3. Inside the growth its plane held it at -1 mm and it
    touched; past the far edge its closest point lay on the growth's edge, beside the ply,
    and it did not: W(-1 mm) in one step (the bottom ply's corner node of the Mindlin [0/45]
    two-ply hemisphere, 3.35 mm deep, +146 N mm in a step, elements/ply_projection.py "Past
    the outline, deeper than the plies"). Reference as above: a touching point's gap moves
    no more than the point, and the energy only by the work of its force; a point past the
    outline deeper than both faces' half thicknesses (0.3 mm) lies beside the ply and does
    not touch, on either side."""
    from elements.ply_projection import open_edges

    triangle = np.array([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]])
    y = np.arange(-0.4, -0.6, -STEP)
    path = np.column_stack([np.full_like(y, 0.3), y, np.full_like(y, -1.0)])
    near = np.zeros((len(path), 1), dtype=int)
    facing = closest_facing(path, triangle, near, 0.0, open_edges(np.array([[0, 1, 2]])), depth=0.3)
    assert facing.gap.max() < -0.3  # the premise: deeper than the plies all along
    assert not facing.touching.any()
