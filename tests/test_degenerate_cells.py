"""Triangles of no area (coincident or collinear corners) are refused where a model takes
its meshes, naming the cells by their ids in the mesh: the shells' own triangles when the
model is compiled, a ply contact's triangles when it is bound (they need not be a shell's),
a rigid surface's facets when it is made."""

from __future__ import annotations

import numpy as np
import pytest

from elements.layup import Layup
from elements.ply_contact import PlyContact
from elements.rigid_surface import RigidSurface
from femcore import Mesh, Model
from materials import Fabric

PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)


def _layup() -> Layup:
    return Layup(PLY, (0.0, 90.0), 40.0, cells=4)


def test_a_shells_triangle_of_no_area_is_named_by_its_id_in_the_mesh():
    """A shell on ply 2 alone (mesh triangles 32-63): its triangle 37 made flat (a corner
    moved to the middle of the opposite side) is named 37, not by its row among the shell's
    triangles (5, which the message gave before)."""
    layup = _layup()
    mesh = layup.mesh
    flat = int(mesh.cell_sets("triangle")["ply_2"][5])
    corners = mesh.triangles[flat]
    points = mesh.points.copy()
    points[corners[2]] = 0.5 * (points[corners[0]] + points[corners[1]])
    model = Model(mesh.with_points(points))
    model.add(layup.element(2), cells="ply_2")
    with pytest.raises(ValueError, match=rf"triangle {flat} with nodes .* has zero area"):
        model.compile()


def _with_flat_lower(layup: Layup) -> tuple[Mesh, int]:
    """The layup's mesh with one more triangle, on three collinear nodes of ply 1 (the
    first row's), in a set "lower" beside ply 1's triangles; no shell is bound to it, so the
    model's own check does not see it. Returns the mesh and the flat triangle's id."""
    mesh = layup.mesh
    bottom = layup.ply_nodes[0]
    row = bottom[np.lexsort(mesh.points[bottom, :2].T)][:3]
    assert np.allclose(mesh.points[row, 1], mesh.points[row[0], 1])  # one row: collinear
    flat = len(mesh.triangles)
    sets = dict(mesh.cell_sets("triangle"))
    sets["lower"] = np.append(sets["ply_1"], flat)
    triangles = np.vstack([mesh.triangles, row[None, :]])
    return Mesh(mesh.points, cells={"triangle": triangles}, cell_sets={"triangle": sets}), flat


@pytest.mark.parametrize("points", ["upper", "lower"])
def test_a_ply_contacts_triangle_of_no_area_is_refused_naming_it(points):
    """Before, such a triangle was bound and its normal, barycentric coordinates and
    penalty share were 0 / 0 (NaN with warnings) at every facing."""
    layup = _layup()
    mesh, flat = _with_flat_lower(layup)
    model = Model(mesh)
    for k in (1, 2):
        model.add(layup.element(k), cells=f"ply_{k}")
    model.interact(PlyContact("ply_2", "lower", 0.15, 0.15, faces="normal", points=points))
    with pytest.raises(ValueError, match=rf"1 lower triangle\(s\) of no area .*: {flat};"):
        model.compile()


def test_a_ply_contact_on_triangles_of_area_binds():
    layup = _layup()
    model = layup.model()
    assert len(model.compile().interactions) == 1


@pytest.mark.parametrize("how", ["coincident", "collinear"])
def test_a_rigid_surface_facet_of_no_area_is_refused_naming_it(how):
    mesh = Mesh.rectangle(2.0, 2.0, nx=2, ny=2)
    corners = mesh.triangles[3]
    points = mesh.points.copy()
    if how == "coincident":
        points[corners[1]] = points[corners[0]]
    else:
        points[corners[2]] = 0.5 * (points[corners[0]] + points[corners[1]])
    flat = np.flatnonzero(
        np.linalg.norm(
            np.cross(
                points[mesh.triangles[:, 1]] - points[mesh.triangles[:, 0]],
                points[mesh.triangles[:, 2]] - points[mesh.triangles[:, 0]],
            ),
            axis=1,
        )
        == 0.0
    )
    assert 3 in flat
    shown = ", ".join(str(t) for t in flat)
    with pytest.raises(
        ValueError, match=rf"RigidSurface: {flat.size} facet\(s\) of no area .*: {shown}$"
    ):
        RigidSurface(mesh.with_points(points))


@pytest.mark.parametrize("height, refused", [(1e-13, True), (1e-6, False)])
def test_a_rigid_surface_sliver_is_judged_on_the_meshs_tolerance(height, refused):
    """A facet whose third corner lies ``height`` (a share of the 2-mm plate's side) off its
    opposite side: refused below the mesh's tolerance (femcore.topology ZERO_AREA_TOL of the
    diagonal squared: a sliver of 1e-13 is round-off of a collinear corner), taken above it
    (a thin but real facet: a fine die's sliver must not be refused)."""
    mesh = Mesh.rectangle(2.0, 2.0, nx=2, ny=2)
    corners = mesh.triangles[3]
    points = mesh.points.copy()
    side = points[corners[1]] - points[corners[0]]
    normal_in_plane = np.cross([0.0, 0.0, 1.0], side) / np.linalg.norm(side)
    middle = 0.5 * (points[corners[0]] + points[corners[1]])
    points[corners[2]] = middle + height * 2.0 * normal_in_plane
    if refused:
        with pytest.raises(ValueError, match=r"RigidSurface: 1 facet\(s\) of no area .*: 3$"):
            RigidSurface(mesh.with_points(points))
    else:
        RigidSurface(mesh.with_points(points))


@pytest.mark.parametrize("height, refused", [(1e-13, True), (1e-6, False)])
def test_a_ply_contact_sliver_is_judged_on_the_meshs_tolerance(height, refused):
    """The lower set's extra triangle on three of ply 1's first-row nodes, the third moved
    ``height`` (a share of the row's spacing) off the others' line, in the plane (ply 1's
    own triangles barely change): refused as of no area below the tolerance, bound above it."""
    layup = _layup()
    mesh, flat = _with_flat_lower(layup)
    points = mesh.points.copy()
    a, b, c = mesh.triangles[flat]
    spacing = float(np.linalg.norm(points[b] - points[a]))
    points[c, 1] += height * spacing
    lifted = mesh.with_points(points)
    model = Model(lifted)
    for k in (1, 2):
        model.add(layup.element(k), cells=f"ply_{k}")
    model.interact(PlyContact("ply_2", "lower", 0.15, 0.15, faces="normal"))
    if refused:
        with pytest.raises(ValueError, match=rf"1 lower triangle\(s\) of no area .*: {flat};"):
            model.compile()
    else:
        assert len(model.compile().interactions) == 1
