"""A layup's frames tell the plies apart: the cell field "part" holds each cell's ply number
(bottom 1), and "warp_direction" and "weft_direction" each cell's fibres in global axes, the
axes along which its "11" and "22" components are taken (README "Output fields",
docs/theory.md §9.3b).

References: a ply laid at angle a has its warp along (cos a, sin a, 0) and its weft along
(-sin a, cos a, 0) (the layup's definition); a fibre is a material line, so a rigid rotation R
of a cell turns its fibres by R, and a homogeneous deformation F takes a fibre of direction a
to F a / |F a| (continuum kinematics)."""

import math

import numpy as np
import pytest

from elements.layup import Layup
from femcore import Mesh
from materials import Fabric
from solvers.common import empty_result, make_frame

FABRIC = Fabric(thickness=0.5, areal_density=5e-10, tension=1200.0, shear=0.5, bending=1.0)


@pytest.mark.parametrize("kinematics", ["fibrous", "mindlin"])
def test_each_cell_of_a_0_90_layup_names_its_ply_and_its_fibres(kinematics):
    layup = Layup(FABRIC, (0.0, 90.0), lx=20.0, cells=2, kinematics=kinematics)
    compiled = layup.model().compile()
    mesh = empty_result(compiled, [make_frame(compiled, compiled.initial_state())]).to_meshio()
    part = mesh.cell_data["part"][0]
    warp, weft = mesh.cell_data["warp_direction"][0], mesh.cell_data["weft_direction"][0]
    for ply, angle in ((1, 0.0), (2, 90.0)):
        cells = layup.mesh.cell_sets("triangle")[f"ply_{ply}"]
        assert np.all(part[cells] == ply)
        a = math.radians(angle)
        along = np.ones((len(cells), 1))
        np.testing.assert_allclose(warp[cells], along * [math.cos(a), math.sin(a), 0], atol=1e-12)
        np.testing.assert_allclose(weft[cells], along * [-math.sin(a), math.cos(a), 0], atol=1e-12)
    assert np.all(np.isin(part, [1.0, 2.0]))


def test_one_block_has_no_part_field():
    layup = Layup(FABRIC, (0.0,), lx=20.0, cells=2)
    compiled = layup.model().compile()
    fields = compiled.fields(compiled.initial_state())
    assert "part" not in fields["triangle"] and "warp_direction" in fields["triangle"]


def test_the_fibres_follow_a_rigid_rotation_and_a_homogeneous_shear():
    from elements.fibre_directions import fibre_components, fibre_directions

    mesh = Mesh.rectangle(10.0, 10.0, nx=2, ny=2)
    warp = np.array([math.cos(0.3), math.sin(0.3), 0.0])  # any warp in the plane
    components = fibre_components(mesh.points, mesh.triangles, warp)
    turn = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])  # 90 deg about y
    shear = np.array([[1.0, 0.4, 0.0], [0.0, 1.2, 0.0], [0.0, 0.0, 1.0]])
    for F in (turn, shear):
        fibres = fibre_directions(mesh.points @ F.T, mesh.triangles, components)
        weft = np.array([-warp[1], warp[0], 0.0])
        for name, a in (("warp_direction", warp), ("weft_direction", weft)):
            expected = F @ a / np.linalg.norm(F @ a)
            np.testing.assert_allclose(fibres[name], np.tile(expected, (8, 1)), atol=1e-12)


@pytest.mark.parametrize("kinematics", ["fibrous", "mindlin"])
def test_a_block_pickled_before_the_directions_existed_writes_its_other_fields(kinematics):
    # a checkpoint's model written by an earlier run has blocks without fibre_components
    compiled = Layup(FABRIC, (0.0,), lx=20.0, cells=2, kinematics=kinematics).model().compile()
    del compiled.blocks[0].fibre_components
    fields = compiled.fields(compiled.initial_state())["triangle"]
    assert "membrane_force" in fields and "warp_direction" not in fields
