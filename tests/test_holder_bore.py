"""The blank holder's bore (validation.specimens.holder_ring ``edge``, ``wall``; the two-ply
hemisphere's holder, validation/studies/hemisphere_plies_setup.py): a point that rises above
the holder's face in the free annulus and moves out under the ring must meet the holder's
surface, not find itself inside it at once (docs/hemisphere_plies.md, "The holder's bore").

Reference: a signed distance to a surface is 1-Lipschitz, |d(x) - d(x')| <= |x - x'| (closed
form; it holds through the surface, where d changes sign with the side), and so the contact's
energy k min(d, 0)^2 / 2 changes by no more than its force times the move. The flat ring's
open inner edge breaks it: past the edge's line a point behind the face is beside the tool
(elements/rigid_surface.py, open edges), d = +h, and one step out it is inside, d = -h, its
energy k h^2 / 2 at once (the 22-cell two-ply run stopped so on the energy balance, two
nodes 0.6 and 1.7 mm above the face taking 12 and 65 N mm).
"""

from __future__ import annotations

import numpy as np
import pytest

from elements import RigidSurface
from validation.specimens import holder_ring


def _holder() -> tuple[RigidSurface, float, float, float]:
    """The two-ply hemisphere's holder as its model builds it (8 cells: the mesh of the
    blank does not change the holder), the height of its face, its bore's radius and the
    bore's edge round, mm."""
    from validation.studies.hemisphere_plies_setup import (
        HOLDER_BORE,
        HOLDER_RING,
        PLIES,
        THICKNESS,
        model,
    )

    _, built = model(8, (0.0, 90.0), "fibrous", 20.0)
    (holder,) = [i.tool for i in built.interactions if getattr(i, "tool", None) is not None
                 and tuple(i.tool.free)]  # fmt: skip
    return holder, PLIES * THICKNESS, HOLDER_RING[0], HOLDER_BORE[0]


@pytest.mark.parametrize("rise", [0.3, 2.0, 5.0])
def test_a_point_moving_out_of_the_bore_above_the_face_meets_the_holder_continuously(rise):
    """Points ``rise`` mm above the face, from 3 mm inside the bore to 3 mm under the ring,
    0.01 mm apart: the signed distance changes by at most the step between neighbours
    (1-Lipschitz, to round-off 1e-9 mm); above the edge's round, past the bore's line the
    point is inside the holder by at most its distance to the bore's wall, and near the wall
    the contact pushes it back to the axis (the wall's normal)."""
    holder, face, bore, edge = _holder()
    radii = np.arange(bore - 3.0, bore + 3.0, 0.01)
    path = np.column_stack([radii, np.zeros_like(radii), np.full_like(radii, face + rise)])
    d, normal = holder.distance(path)
    steps = np.abs(np.diff(d))
    assert steps.max() <= 0.01 * (1.0 + 1e-6) + 1e-9, (
        f"the signed distance jumps by {steps.max():.3g} mm between points 0.01 mm apart "
        f"(at r = {radii[np.argmax(steps)]:.2f} mm)"
    )
    if rise > edge:  # above the edge's round: past the bore's line the point is inside
        inside = radii > bore + 1e-6
        assert (d[inside] < 0.0).all()
        assert (-d[inside] <= radii[inside] - bore + 1e-9).all()
        # just past the wall (nearer it than the face) the contact pushes the point back
        # towards the axis, horizontally
        near = (radii > bore + 0.05) & (radii < bore + 0.5 * (rise - edge))
        np.testing.assert_allclose(
            normal[near], np.tile([-1.0, 0.0, 0.0], (near.sum(), 1)), atol=1e-9
        )


def test_the_flat_ring_alone_puts_a_point_inside_at_once():
    """The flat ring's open edge (no ``edge``, ``wall``): the same path 2 mm above its face
    jumps from +2 to -2 mm at the edge's line: the mechanism the bore removes."""
    ring = holder_ring(60.9, 150.0, 10.0)
    holder = RigidSurface(ring)
    radii = np.arange(57.9, 63.9, 0.01)
    path = np.column_stack([radii, np.zeros_like(radii), np.full_like(radii, 2.0)])
    d, _ = holder.distance(path)
    assert np.abs(np.diff(d)).max() == pytest.approx(4.0, abs=0.02)


def test_the_bore_keeps_the_pressed_face_and_faces_the_axis():
    """The bore's mesh: the flat face from inner + edge to outer faces -z and covers its
    annulus (pi (R^2 - r^2) within the rings' polygon error, 1e-3), the wall's facets face the
    axis, and the wall reaches edge + wall above the face."""
    ring = holder_ring(60.9, 150.0, 10.0, 1.0, 20.0)
    corners = ring.points[ring.triangles]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    areas = 0.5 * np.linalg.norm(normals, axis=1)
    normals /= 2.0 * areas[:, None]
    centre = corners.mean(axis=1)
    flat = np.abs(corners[:, :, 2]).max(axis=1) < 1e-12
    np.testing.assert_allclose(normals[flat, 2], -1.0, rtol=1e-12)
    assert areas[flat].sum() == pytest.approx(np.pi * (150.0**2 - 61.9**2), rel=1e-3)
    wall = centre[:, 2] > 1.0 + 1e-9
    radial = np.sum(normals[wall, :2] * centre[wall, :2], axis=1) / np.hypot(*centre[wall, :2].T)
    assert radial.max() < -0.999
    assert ring.points[:, 2].max() == pytest.approx(21.0)


def test_the_bore_is_refused_half_given_or_out_of_range():
    """edge without wall, an edge wider than the ring, a wall of no height: ValueError."""
    with pytest.raises(ValueError, match="together"):
        holder_ring(60.9, 150.0, 10.0, edge=1.0)
    with pytest.raises(ValueError, match="0 < edge < outer - inner"):
        holder_ring(60.9, 70.0, 5.0, edge=10.0, wall=5.0)
    with pytest.raises(ValueError, match="wall > 0"):
        holder_ring(60.9, 150.0, 10.0, edge=1.0, wall=0.0)
