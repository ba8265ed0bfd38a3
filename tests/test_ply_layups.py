"""Layups of plies at different angles (elements/layup.py): the fibre-aligned blanks of each
ply (femcore/blank.py), the shear angle of a ply, the net of a ply's own orientation
(validation/references/drape.py), the inter-ply slip field (elements/ply_slip.py) and a holder
pressing a layup onto a die."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from elements import FibrousShell, RigidPlane
from elements.layup import Layup, ply_shear
from elements.ply_contact import PlyContactBlock
from elements.ply_slip import slip_summary
from femcore import Model
from femcore.blank import ply_blank, ply_directions
from femcore.state import State
from materials import Fabric
from solvers import Static
from validation.references.drape import fishnet_on_sphere, net_coordinates

PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)


def _turn(rotation_vector):
    return Rotation.from_rotvec(rotation_vector).as_matrix()


def _areas(mesh):
    x = mesh.points[mesh.triangles]
    return 0.5 * np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])[:, 2]


@pytest.mark.parametrize("angle", [0.0, 90.0, 45.0, -45.0, 135.0])
def test_a_ply_blank_fills_the_square_with_fibre_aligned_right_triangles(angle):
    blank = ply_blank(200.0, 200.0, 10, angle, centre=(0.0, 0.0, 0.15))
    areas = _areas(blank)
    assert np.all(areas > 0.0)  # counter-clockwise about +z
    assert areas.sum() == pytest.approx(200.0 * 200.0, rel=1e-12)
    assert np.allclose(blank.points.min(axis=0), [-100.0, -100.0, 0.15])
    assert np.allclose(blank.points.max(axis=0), [100.0, 100.0, 0.15])
    outline = blank.points[blank.node_sets["outline"]]
    assert np.all(np.isclose(np.abs(outline[:, :2]), 100.0).any(axis=1))
    # every triangle has a corner with one leg along the warp and one along the weft
    warp, weft = ply_directions(angle)
    x = blank.points[blank.triangles]
    found = np.zeros(len(x), dtype=bool)
    for k in range(3):
        a = x[:, (k + 1) % 3] - x[:, k]
        b = x[:, (k + 2) % 3] - x[:, k]
        a /= np.linalg.norm(a, axis=1)[:, None]
        b /= np.linalg.norm(b, axis=1)[:, None]
        on = lambda u, d: np.isclose(np.abs(u @ d), 1.0, atol=1e-12)  # noqa: E731
        found |= (on(a, warp) & on(b, weft)) | (on(a, weft) & on(b, warp))
    assert found.all()
    model = Model(blank)
    model.add(FibrousShell(PLY, warp=warp, fibre_angle_tolerance=0.01))
    model.compile()  # the fibrous shell accepts the mesh along its warp


def test_a_45_degree_blank_has_the_fibre_segment_of_the_0_degree_one_to_rounding():
    square = ply_blank(200.0, 200.0, 20, 0.0)
    diamond = ply_blank(200.0, 200.0, 20, 45.0)
    assert len(diamond.triangles) == 784 and len(square.triangles) == 800
    assert np.sqrt(2.0 * _areas(diamond)[0]) == pytest.approx(10.1, abs=0.02)


def test_an_oblique_ply_warns_of_its_staircase_outline():
    with pytest.warns(UserWarning, match="staircase outline"):
        blank = ply_blank(200.0, 200.0, 10, 30.0)
    assert np.all(np.abs(blank.points[:, :2]) <= 100.0 + 1e-9)
    assert _areas(blank).sum() < 200.0 * 200.0


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: ply_blank(200.0, 200.0, 0), "cells must be an integer"),
        (lambda: ply_blank(-1.0, 200.0, 4), "finite sides"),
        (lambda: ply_blank(200.0, 200.0, 4, float("nan")), "finite number of degrees"),
        (lambda: ply_blank(200.0, 150.0, 10, 45.0), "not an even multiple"),
        (lambda: Layup(PLY, (), 200.0, cells=4), "1 to 200 plies"),
        (lambda: Layup(PLY, "0/90", 200.0, cells=4), "sequence of ply angles"),
        (
            lambda: Layup(PLY, (0.0, float("inf")), 200.0, cells=4),
            "ply 2: the angle must be finite",
        ),
        (lambda: Layup(PLY, (0.0, "45"), 200.0, cells=4), "ply 2: the angle must be a number"),
        (lambda: Layup(PLY, (0, 90), 200.0, cells=4, kinematics="abaqus"), "kinematics"),
        (lambda: Layup(PLY, (0, 90), 200.0, cells=4, friction=-0.1), "friction"),
        (lambda: Layup("G986", (0, 90), 200.0, cells=4), "materials.Fabric"),
    ],
)
def test_bad_layups_are_refused_with_what_was_expected(call, message):
    with pytest.raises(ValueError, match=message):
        call()


@pytest.mark.parametrize("kinematics", ["fibrous", "mindlin"])
def test_a_layup_is_one_model_with_a_shell_per_ply_at_its_own_warp(kinematics):
    layup = Layup(PLY, (0.0, 45.0, 90.0), 200.0, cells=6, kinematics=kinematics, friction=0.2)
    assert np.allclose(layup.heights, [0.15, 0.45, 0.75])
    assert np.allclose(layup.warps[1], [np.sqrt(0.5), np.sqrt(0.5), 0.0])
    compiled = layup.model().compile()
    # ply 2 on 1, ply 3 on 2, then ply 3 on 1 (every ply on every ply below it)
    assert len(compiled.blocks) == 3 and len(compiled.interactions) == 3
    assert all(isinstance(block, PlyContactBlock) for block in compiled.interactions)
    assert [b.friction for b in compiled.interactions] == [0.2, 0.2, 0.2]
    for k, nodes in enumerate(layup.ply_nodes):
        assert np.allclose(layup.mesh.points[nodes, 2], layup.heights[k])
    if kinematics == "fibrous":
        assert np.allclose(layup.element(2).warp, layup.warps[1])


def test_a_ply_shear_is_zero_in_a_rigid_motion_and_the_imposed_shear_of_its_fibres():
    blank = ply_blank(100.0, 100.0, 6, 45.0)
    warp, weft = ply_directions(45.0)
    turn = _turn(np.array([0.3, -0.2, 0.5]))
    moved = blank.points @ turn.T + [1.0, 2.0, 3.0]
    assert np.allclose(ply_shear(blank.points, moved, blank.triangles, warp), 0.0, atol=1e-12)
    # the weft leans towards the warp by gamma: the fibres close up, a positive shear
    gamma = 0.3
    shear_map = np.eye(3) + np.tan(gamma) * np.outer(warp, weft)
    sheared = blank.points @ shear_map.T
    assert np.allclose(ply_shear(blank.points, sheared, blank.triangles, warp), gamma)


def test_the_net_of_a_ply_at_an_angle_is_the_0_degree_net_turned_about_the_axis():
    straight = fishnet_on_sphere(50.0, 2.0, 30)
    turned = fishnet_on_sphere(50.0, 2.0, 30, angle=45.0)
    turn = _turn(np.array([0.0, 0.0, np.pi / 4]))
    assert np.allclose(turned["points"], straight["points"] @ turn.T, equal_nan=True, atol=1e-9)
    assert np.allclose(turned["shear"], straight["shear"], equal_nan=True, atol=1e-9)
    # the plane point along the ply's warp (weft) has arc length u (v) alone
    along = net_coordinates(np.array([[1.0, 1.0], [-1.0, 1.0]]), 45.0)
    assert np.allclose(along, [[np.sqrt(2.0), 0.0], [0.0, np.sqrt(2.0)]])


def _slip(layup, positions, directors):
    compiled = layup.model().compile()
    block = compiled.interactions[0]
    n = len(positions)
    state = State(positions, directors, np.zeros((n, 3)), np.zeros((n, 3)))
    fields = block.node_fields(state, None)
    return fields["ply_slip"], fields["ply_slip_vector"]


def test_the_inter_ply_slip_is_zero_in_a_rigid_motion_of_the_stack():
    layup = Layup(PLY, (0.0, 45.0), 100.0, cells=6)
    x0 = layup.mesh.points
    turn = _turn(np.array([0.4, 0.1, -0.7]))
    directors = np.tile(turn[:, 2], (len(x0), 1))
    slip, _ = _slip(layup, x0 @ turn.T + [5.0, -3.0, 2.0], directors)
    top = layup.ply_nodes[1]
    assert np.isnan(slip[layup.ply_nodes[0]]).all()  # no ply below the bottom one
    assert np.isfinite(slip[top]).all()
    assert np.allclose(slip[top], 0.0, atol=1e-10)


def test_the_inter_ply_slip_is_an_imposed_in_plane_shift_of_the_top_ply():
    layup = Layup(PLY, (0.0, 90.0), 100.0, cells=6)
    x = layup.mesh.points.copy()
    top = layup.ply_nodes[1]
    x[top] += [0.3, -0.4, 0.0]
    directors = np.tile([0.0, 0.0, 1.0], (len(x), 1))
    slip, vector = _slip(layup, x, directors)
    assert np.allclose(slip[top], 0.5, rtol=1e-12)
    assert np.allclose(vector[top], [0.3, -0.4, 0.0])
    summary = slip_summary(slip)
    assert summary["max_mm"] == pytest.approx(0.5) and summary["rms_mm"] == pytest.approx(0.5)
    assert summary["nodes"] == len(top)


def test_a_holder_presses_a_layup_onto_the_die_with_its_force():
    """Two plies [0/45] on a flat die, a flat holder free along z pushed by 2 N: the die and
    the holder carry 2 N (1e-6)."""
    layup = Layup(PLY, (0.0, 45.0), 40.0, cells=2, friction=0.2)
    model = layup.model()
    model.fix(lambda x, y, z: np.ones_like(x, dtype=bool), ["ux", "uy"])
    model.contact(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)), nodes="ply_1")
    holder = RigidPlane(
        (0.0, 0.0, 2 * PLY.thickness),
        (0.0, 0.0, -1.0),
        free="z",
        force=(0.0, 0.0, -2.0),
        amplitude="linear",
    )
    model.contact(holder, nodes="ply_2")
    run = Static(increments=2, seek_stable=False).solve(model)
    assert run.converged
    die, pressed = run.tool_forces[-1]
    assert die[2] == pytest.approx(-2.0, rel=1e-6)
    assert pressed[2] == pytest.approx(2.0, rel=1e-6)
    assert run.tool_displacements[-1, 1, 2] < 0.0


def test_the_plies_of_a_layup_give_one_field_of_each_name_with_each_plys_own_values():
    """Element blocks on disjoint nodes (the plies) write one node field of a name, not
    thickness, thickness_2, ...: each node's value is its own ply's."""
    layup = Layup(PLY, (0.0, 90.0), 40.0, cells=4)
    compiled = layup.model().compile()
    state = compiled.initial_state()
    fields = compiled.fields(state)["point"]
    own = [block.node_fields(state, None) for block in compiled.blocks[:2]]
    assert own[0], "a fibrous ply has node fields"
    for name in own[0]:
        assert f"{name}_2" not in fields
        for k, nodes in enumerate(layup.ply_nodes):
            np.testing.assert_array_equal(fields[name][nodes], np.asarray(own[k][name])[nodes])
