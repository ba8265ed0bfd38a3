"""A fixed alpha or beta names one rotation along its node set, or the model is refused
(femcore/frame_branches.py, docs/theory.md §1.2).

The pinched cylinder of MacNeal and Harder (Finite Elem. Anal. Des. 1 (1985) 3: R = 300,
L = 600, t = 3, E = 3e6, nu = 0.3, unit loads, rigid diaphragms), its octant modelled with the
cylinder's axis along x and again along z: the two meshes are the same triangles turned by
the cyclic permutation (x, y, z) -> (y, z, x), so the two octants must deflect alike to
rounding. Along z, the mid-length symmetry plane z = L/2 holds directors from e2 to e1, and the
nodes within 5.7 deg of +-e2 take the fallback frame, where alpha turns the director within
the plane: fixing alpha along the plane held the wrong rotation there and the octant deflected
0.784 of the reference where the x octant gives 0.951 (32 cells).
"""

import re
import warnings

import numpy as np
import pytest

from elements import MindlinShell
from femcore import Mesh, Model
from femcore.rotation import nodal_frames
from femcore.topology import nodal_normals
from materials import ElasticShell
from solvers import Static

RADIUS, LENGTH, THICKNESS, CELLS = 300.0, 600.0, 3.0, 16


def section():
    return MindlinShell(ElasticShell(3e6, 0.3, THICKNESS, 1e-9))


def octant_along_x():
    """The octant of tests/test_mindlin.py: axis x, the load at (L/2, 0, R) along -z."""
    flat = Mesh.rectangle(LENGTH / 2, RADIUS * np.pi / 2, nx=CELLS, ny=CELLS)
    x, s = flat.points[:, 0], flat.points[:, 1] / RADIUS
    mesh = flat.with_points(np.column_stack([x, RADIUS * np.sin(s), RADIUS * np.cos(s)]))
    model = Model(mesh)
    model.add(section())
    model.fix("left", ["uy", "uz"])  # the diaphragm x = 0
    model.fix("right", ["ux", "alpha"])  # the plane x = L/2: directors from e3 to e2
    model.fix("bottom", ["uy", "beta"])  # the plane y = 0
    model.fix("top", ["uz", "beta"])  # the plane z = 0
    load = mesh.nodes(lambda X, Y, Z: np.isclose(X, LENGTH / 2) & np.isclose(Y, 0.0))
    model.force(load, (0.0, 0.0, -0.25))
    return model, load[0], 2


def octant_along_z(hold: str):
    """The same octant turned: axis z, the load at (0, R, L/2) along -y. ``hold``: how the
    plane z = L/2 holds its directors' turn out of it: "alpha" along the whole plane,
    "per node" each node's DOF that turns its director towards z (by its frame, as the
    refusal says), "tilt" by Model.fix's ``tilt="z"``."""
    flat = Mesh.rectangle(LENGTH / 2, RADIUS * np.pi / 2, nx=CELLS, ny=CELLS)
    z, s = flat.points[:, 0], flat.points[:, 1] / RADIUS
    mesh = flat.with_points(np.column_stack([RADIUS * np.sin(s), RADIUS * np.cos(s), z]))
    model = Model(mesh)
    model.add(section())
    model.fix("left", ["ux", "uy"])  # the diaphragm z = 0
    model.fix("bottom", ["ux", "alpha"])  # the plane x = 0 (directors e2: the fallback frame)
    model.fix("top", ["uy", "beta"])  # the plane y = 0
    plane = mesh.nodes("right")  # z = L/2
    if hold == "tilt":
        model.fix(plane, ["uz"], tilt="z")
    elif hold == "per node":
        model.fix(plane, ["uz"])
        v1, v2 = nodal_frames(nodal_normals(mesh.points, mesh.triangles)[plane])
        alpha = np.abs(v1[:, 2]) > np.abs(v2[:, 2])  # alpha turns V towards V1
        model.fix(plane[alpha], ["alpha"])
        model.fix(plane[~alpha], ["beta"])
    else:
        model.fix(plane, ["uz", hold])
    load = mesh.nodes(lambda X, Y, Z: np.isclose(X, 0.0) & np.isclose(Z, LENGTH / 2))
    model.force(load, (0.0, -0.25, 0.0))
    return model, load[0], 1


def deflection(built):
    model, node, axis = built
    return -Static(increments=1).solve(model).displacements[node, axis]


def test_alpha_along_a_plane_whose_frames_change_branch_is_refused():
    model, _, _ = octant_along_z("alpha")
    with pytest.raises(ValueError) as caught:
        model.compile()
    message = str(caught.value)
    # the plane's nodes whose frame turns the director out of the plane by beta: those within
    # 5.7 deg of e2 (at 16 cells the node on the loaded line, V = e2, alone)
    plane = model.mesh.nodes("right")
    mesh = model.mesh  # the directors start at the nodal normals (docs/theory.md §1.1)
    v1, v2 = nodal_frames(nodal_normals(mesh.points, mesh.triangles)[plane])
    by_beta = plane[np.abs(v2[:, 2]) > np.abs(v1[:, 2])].tolist()
    assert by_beta == [CELLS]  # (CELLS, 0): the node (0, R, L/2)
    assert f"alpha means another rotation at nodes {by_beta}" in message
    assert f"fix beta instead of alpha at nodes {by_beta}" in message
    assert "docs/theory.md §1.2" in message


@pytest.mark.parametrize("hold", ["per node", "tilt"])
def test_the_octant_along_z_deflects_as_the_octant_along_x_when_each_node_holds_its_own(hold):
    # The same triangles turned: equal to rounding (1e-6 allows for the two Newton solves'
    # tolerance 1e-8 on the residual, not for a wrong support: the refused one gave -18 %).
    along_x = deflection(octant_along_x())  # compiles: alpha on x = L/2 names one rotation
    along_z = deflection(octant_along_z(hold))
    assert along_z == pytest.approx(along_x, rel=1e-6)
    # MacNeal and Harder's 1.8248e-5 as the 16-cell octant reaches it (0.80, as
    # tests/test_mindlin.py measures 3-node shells): the support holds the right rotation
    assert along_x == pytest.approx(0.80 * 1.8248e-5, rel=0.03)


def test_tilt_holds_the_turn_out_of_the_plane_by_alpha_or_beta_as_each_frame_has_it():
    model, _, _ = octant_along_z("tilt")
    compiled = model.compile()
    plane = model.mesh.nodes("right")  # (CELLS, j), j = 0 .. CELLS: phi = 0 .. 90 deg
    v1, v2 = nodal_frames(compiled.reference_directors[plane])
    held = compiled.dofs.fixed[plane]
    # within the plane (its ends are on the planes x = 0 and y = 0 too) one DOF at each node,
    # the one whose turn (towards V1 for alpha, -V2 for beta) is along z
    inner = slice(1, -1)
    along = np.where(held[inner, 3], np.abs(v1[inner, 2]), np.abs(v2[inner, 2]))
    assert (held[inner, 3] ^ held[inner, 4]).all() and np.allclose(along, 1.0)
    # at phi = 0 the director is e2, the fallback frame: beta turns it towards z, alpha
    # (held by the plane x = 0) out of that plane
    assert held[0, 4] and abs(v2[0, 2]) == pytest.approx(1.0)


def test_tilt_is_refused_where_the_directors_leave_its_plane_and_beside_alpha_or_beta():
    model, _, _ = octant_along_z("tilt")
    # the plane y = 0: its directors are e1 up to half a facet (2.8 deg), 87.2 deg off x = const
    model.fix("top", [], tilt="x")
    with pytest.raises(ValueError, match="the director lies 87.2 deg from that plane"):
        model.compile()
    with pytest.raises(ValueError, match="give the translations alone"):
        model.fix("right", ["uz", "alpha"], tilt="z")
    with pytest.raises(ValueError, match="tilt must be 'x', 'y' or 'z'"):
        model.fix("right", ["uz"], tilt="w")


def strip_facing_y():
    """A 100 x 10 strip in the plane y = 0 (directors -e2: the fallback frame), clamped at
    x = 0, alpha alone fixed at x = 100 (the turn towards V1 = e3 x V = e1 there)."""
    flat = Mesh.rectangle(100.0, 10.0, nx=4, ny=1)
    x, z = flat.points[:, 0], flat.points[:, 1]
    mesh = flat.with_points(np.column_stack([x, np.zeros_like(x), z]))
    model = Model(mesh)
    model.add(section())
    model.fix("left")
    model.fix("right", ["alpha"])
    return model.compile()


def turned(directors, axis, degrees):
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    k = np.array(axis, float)
    return directors * c + np.cross(k, directors) * s + np.outer(directors @ k, k) * (1 - c)


def test_a_director_turned_out_of_the_cone_warns_where_its_one_fixed_dof_changed_meaning():
    from dataclasses import replace

    from solvers.common import make_frame

    compiled = strip_facing_y()
    state = compiled.initial_state()
    right = compiled.mesh.nodes("right")
    # 10 deg about z: out of the 5.7-deg cone; the Eq. 7 frame's alpha turns the director
    # towards z there, the fallback's towards x, as at the start: another rotation
    about_z = replace(state, directors=turned(state.directors, (0, 0, 1), 10.0))
    with pytest.warns(UserWarning, match=re.escape(f"at nodes {right.tolist()} the director")):
        make_frame(compiled, about_z)
    # 10 deg about x: out of the cone too, but both frames' alpha turns it along x: no warning
    about_x = replace(state, directors=turned(state.directors, (1, 0, 0), 10.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        make_frame(compiled, about_x)
