"""The sign of a ply contact point's gap where its closest point on the other ply's face lies
on an edge: a point outside a sharp ridge of that face stays outside, whichever of the
ridge's triangles the search hands it to (elements/ply_projection.py, "The sign at an edge").

What it guards: on the two-ply Mindlin [0/90] hemisphere (validation/studies/hemisphere_plies.py,
10 cells, 20 N), the bottom ply's nodes of the mirrored pass next to the flange's folded
wrinkles (closest points on an edge of the top ply's face, 0.2-0.3 mm away) had their gap
signed by the facing triangle's normal alone, which across a fold sharper than a right angle
points away from a point outside: gaps of +0.21 to -0.29 mm and back within a few steps, each
switch into contact 3-6 N mm of penalty energy made without work, +115 N mm over the run
against -50 N mm lost, until the run stopped on its energy balance at 98.5 % of the stroke.

Reference: the distance from a point to a straight edge (closed form) and the side of the
ridge the point lies on (outside: above both of its faces' planes' union, by construction).
"""

from __future__ import annotations

import numpy as np

from elements.layup import Layup
from femcore.state import State
from materials import Fabric

PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)
SLOPE = 2.0  # the ridge's faces z = -SLOPE |x|: their normals 2 atan(2) = 126.9 deg apart
RADIUS = 0.2  # mm, the point's distance from the ridge's edge


def _ridge_and_point():
    """Two 40-mm plies of 10-mm cells (faces along the directors, one contact point per
    node of the top ply), the bottom ply folded into a ridge along x = 0 (faces z = z_1 -
    SLOPE |x|), directors upright; the top ply's node at (0, -10) moved next to the ridge:
    (the ply contact block, a function of the angle phi (rad) from +z in the xz-plane giving
    the state with that node's face point at RADIUS from the ridge's face edge along phi, the
    node's contact point row)."""
    layup = Layup(PLY, (0.0, 0.0), 40.0, cells=4, rule="nodes", faces="director")
    block = layup.model().compile().interactions[0]
    x0 = layup.mesh.points.copy()
    bottom, top = layup.ply_nodes
    x0[bottom, 2] -= SLOPE * np.abs(x0[bottom, 0])
    node = top[np.argmin(np.linalg.norm(x0[top, :2] - [0.0, -10.0], axis=1))]
    half = 0.5 * PLY.thickness
    ridge = np.array([0.0, -4.0, layup.heights[0] + half])  # on the lower face's edge
    directors = np.tile([0.0, 0.0, 1.0], (len(x0), 1))
    zero = np.zeros_like(x0)
    point = np.flatnonzero(
        block.above[np.arange(len(block.above)), np.argmax(block.shape, 1)] == node
    )

    def state(phi: float) -> State:
        x = x0.copy()
        x[node] = ridge + RADIUS * np.array([np.sin(phi), 0.0, np.cos(phi)]) + [0.0, 0.0, half]
        return State(x, directors, zero, zero)

    return block, state, int(point[0])


def test_a_point_outside_a_sharp_ridge_keeps_a_positive_gap_around_it():
    """The point circles the ridge's edge at 0.2 mm, from -60 to +60 deg about the ridge's
    bisector (its faces' normals at +-63.4 deg): its closest point stays on the edge, and its
    gap is +0.2 mm all the way (to round-off, 1e-9 mm), it never touches and the contact
    stores no energy (1e-9 N mm: the other nodes rest on the bottom ply at g ~ 0). Before, signed by
    the facing triangle's normal, it read -0.2 mm past 26.6 deg on one side (the angle at
    which the point crosses that triangle's plane beside the ridge), where it touched with
    W(-0.2 mm) of energy from nothing."""
    block, state, point = _ridge_and_point()
    for phi in np.radians(np.linspace(-60.0, 60.0, 49)):
        facing = block.facing(state(phi))
        assert abs(facing.gap[point] - RADIUS) < 1e-9, (np.degrees(phi), facing.gap[point])
        assert not facing.touching[point]
        # the other points rest on the bottom ply at g ~ 0 (the ramp's W ~ g^3: round-off)
        assert block.strain_energy(state(phi)) < 1e-9


def test_a_point_outside_a_sharp_apex_keeps_a_positive_gap_around_it():
    """The vertex's pseudonormal (the angle-weighted normals of its triangles): a point 0.2
    mm from the apex of a steep four-sided pyramid (faces 63.4 deg off the horizontal, apex
    at the origin, base corners (+-1, 0, -2), (0, +-1, -2)), moved from -60 to +60 deg about
    the axis in the xz-plane (the apex is its closest point up to 63.4 deg), keeps a gap of
    +0.2 mm (1e-9 mm) and never touches; signed by the first triangle's normal (its normal
    (2, 2, 1) / 3), the gap reads -0.2 mm past -26.6 deg."""
    from elements.ply_projection import closest_facing

    base = np.array([[1.0, 0.0, -2.0], [0.0, 1.0, -2.0], [-1.0, 0.0, -2.0], [0.0, -1.0, -2.0]])
    points = np.vstack([np.zeros(3), base])  # node 0 the apex
    nodes = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1]])
    phi = np.radians(np.linspace(-60.0, 60.0, 49))
    path = RADIUS * np.column_stack([np.sin(phi), np.zeros_like(phi), np.cos(phi)])
    near = np.tile(np.arange(4), (len(path), 1))
    facing = closest_facing(path, points[nodes], near, 0.0, nodes=nodes)
    assert np.all(np.abs(facing.gap - RADIUS) < 1e-9)
    assert not facing.touching.any()
    # the premise: signed by the facing triangle's normal, the gap changes sign on the path
    alone = closest_facing(path, points[nodes], near, 0.0)
    assert (alone.gap < 0.0).any()
