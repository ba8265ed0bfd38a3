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
