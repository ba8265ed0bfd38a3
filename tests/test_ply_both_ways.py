"""The ply contact both ways (elements/ply_contact.py, "Both ways"): the upper ply's points
against the lower ply's face, and the mirrored pass, the lower ply's points against the upper
ply's face, so that a node of the upper ply pressed by a tool between its own contact points
cannot pass through the ply below."""

from __future__ import annotations

import numpy as np
import pytest

from elements import RigidSphere
from elements.layup import Layup
from elements.ply_contact import PlyContact
from femcore.state import State
from materials import Fabric
from solvers import CentralDifference
from validation.studies.hemisphere_plies_gaps import node_gaps

PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)


def _node_gaps(layup: Layup, positions: np.ndarray) -> np.ndarray:
    """(s,) each upper-ply node's least gap to the lower ply's face, mm, through a
    node-to-surface contact (rule "vertices") on the same plies; NaN where no facet faces it."""
    probe = Layup(PLY, tuple(layup.angles), 40.0, cells=4, rule="vertices")
    return node_gaps(probe.model().compile().interactions[0], layup, positions)


def _pressed(angles: tuple[float, float], clearance: float = 0.0, safety: float = 0.9):
    """Two 40-mm plies (10-mm cells, both outlines pinned, the mirrored pass at the bottom
    ply's nodes), the top ply's centre node pressed 3 mm down by a rigid sphere of radius 5
    mm that starts ``clearance`` mm above it, at ``safety`` x the stable step: (layup, the
    centre node, the result)."""
    layup = Layup(PLY, angles, 40.0, cells=4, rule="gauss", lower_rule="vertices")
    model = layup.model()
    model.fix("outline", ["ux", "uy", "uz"])
    top = layup.ply_nodes[1]
    points = layup.mesh.points
    centre = top[np.argmin(np.linalg.norm(points[top, :2], axis=1))]
    radius, depth = 5.0, 3.0
    start = (0.0, 0.0, points[centre, 2] + 0.5 * PLY.thickness + radius + clearance)
    model.contact(
        RigidSphere(start, radius, motion=(0.0, 0.0, -depth), amplitude="smooth"), nodes="ply_2"
    )
    result = CentralDifference(
        duration=0.01, damping=20.0, progress=False, kinetic_bound=None, safety=safety
    ).solve(model)
    return layup, centre, result


@pytest.mark.parametrize("angles", [(0.0, 90.0), (0.0, 45.0)], ids=["0-90", "0-45"])
def test_a_node_pressed_by_a_sphere_stays_out_of_the_ply_below(angles):
    """Two 40-mm plies (10-mm cells, both outlines pinned), the top ply's centre node pressed
    3 mm down by a rigid sphere of radius 5 mm. With the upper ply's Gauss points alone, the
    node (no contact point of its ply) went 0.30 mm ([0/90]) and 0.40 mm ([0/45]) through
    the bottom ply's face, a ply thickness; with the mirrored pass at the bottom ply's nodes
    it stays within 0.07 mm (the penalty's give), here within half a ply thickness over the
    whole run."""
    layup, centre, result = _pressed(angles)
    points = layup.mesh.points
    assert result.positions[centre, 2] < points[centre, 2] - 2.5  # pressed
    n = layup.mesh.n_nodes
    least = min(np.nanmin(_node_gaps(layup, frame.positions[:n])) for frame in result.frames)
    assert least > -0.5 * PLY.thickness


def _sunk(layup: Layup, sink: float) -> tuple[list, State]:
    """The layup's compiled ply contacts and a state with the top ply ``sink`` mm into the
    bottom one, directors upright."""
    contacts = layup.model().compile().interactions
    x = layup.mesh.points.copy()
    x[layup.ply_nodes[1], 2] -= sink
    zero = np.zeros_like(x)
    directors = np.tile([0.0, 0.0, 1.0], (len(x), 1))
    return contacts, State(x, directors, zero, zero)


@pytest.mark.parametrize("faces", ["normal", "director"])
def test_the_mirrored_pass_pushes_the_lower_ply_down_and_the_upper_ply_up(faces):
    """Flat [0/45] plies sunk 0.1 mm into each other: every node of the bottom ply under the
    top one penetrates its face by 0.1 mm, and the pass pushes the plies apart along the
    normal, equal and opposite."""
    layup = Layup(PLY, (0.0, 45.0), 40.0, cells=4, lower_rule="vertices", faces=faces)
    contacts, state = _sunk(layup, 0.1)
    assert len(contacts) == 2 and contacts[1].mirrored and not contacts[0].mirrored
    mirrored = contacts[1]
    facing = mirrored.facing(state)
    assert facing.touching.sum() >= 9
    np.testing.assert_allclose(facing.gap[facing.touching], -0.1, atol=1e-12)
    force, moment = mirrored.internal_force(state)  # dW/dx: the push on the plies is -force
    bottom, top = layup.ply_nodes
    assert force[top, 2].sum() < 0.0 < force[bottom, 2].sum()
    assert np.all(force[top, 2] <= 0.0) and np.all(force[bottom, 2] >= 0.0)
    assert force[top, 2].sum() == pytest.approx(-force[bottom, 2].sum(), rel=1e-12)
    assert np.abs(force[:, :2]).max() <= 1e-9 * np.abs(force[:, 2]).max()
    np.testing.assert_allclose(moment, 0.0, atol=1e-9 * np.abs(force).max())
    assert mirrored.node_fields(state) == {}  # the upper ply's fields are the first pass's


def test_a_layup_without_a_lower_rule_keeps_one_pass_per_interface():
    # three pairs of plies: 2 on 1, 3 on 2, 3 on 1 (elements/ply_contact.py join_plies)
    layup = Layup(PLY, (0.0, 45.0, 90.0), 40.0, cells=2)
    assert len(layup.model().compile().interactions) == 3
    both = Layup(PLY, (0.0, 45.0, 90.0), 40.0, cells=2, lower_rule="centroid")
    assert [c.mirrored for c in both.model().compile().interactions] == [False, True] * 3


def test_unknown_points_and_lower_rules_are_refused_with_the_choices():
    with pytest.raises(ValueError, match="points must be one of .*'upper', 'lower'.*'middle'"):
        PlyContact("ply_2", "ply_1", points="middle")
    with pytest.raises(ValueError, match="lower_rule must be None or one of .*'edges'"):
        Layup(PLY, (0.0, 90.0), 40.0, cells=2, lower_rule="edges")


def test_curved_faces_apart_give_a_zero_float_force():
    """No point touching: the curved faces' loads are zeros (they were an integer array, on
    which the normals' pull-back could not be added)."""
    layup = Layup(PLY, (0.0, 45.0), 40.0, cells=2, surface="curved")
    contacts, state = _sunk(layup, -1.0)
    force, moment = contacts[0].internal_force(state)
    assert force.dtype == np.float64 and not force.any() and not moment.any()


@pytest.mark.parametrize("safety", [0.6, 0.7, 0.8, 0.85, 0.9, 0.95])
def test_a_sphere_starting_clear_of_touching_plies_is_no_divergence_at_rest(safety):
    """The sphere starts 0.1 mm above the top ply: before it touches, the plies' contact at
    zero gap moves the model at rest by round-off (kinetic energy ~4e-29 N mm against no
    external work). That is not a blow-up: the run starts, and the sphere presses the node.
    Its first touch is no divergence either, at any step: the sphere's work over the half
    step before the touch's check is counted from before its spring engaged, a deficit of
    (1 - sigma) of that work in the energy balance (sigma the share of the step it touched,
    docs/theory.md §6.1, "First touch"), 0.1 to 0.7 of the energy there; the check stopped
    the run at safety 0.7, 0.85, 0.9 and 0.95 on the code before."""
    layup, centre, result = _pressed((0.0, 45.0), clearance=0.1, safety=safety)
    points = layup.mesh.points
    assert result.positions[centre, 2] < points[centre, 2] - 2.5  # pressed


def _lower_node_gaps(layup: Layup, positions: np.ndarray) -> np.ndarray:
    """(p,) the least gaps, mm, of the lower ply's nodes to the upper ply's lower face: the
    mirrored pass at the "vertices" rule on the same plies (one point per corner of each
    lower triangle), over its points facing an upper triangle (NaN elsewhere)."""
    probe = Layup(PLY, tuple(layup.angles), 40.0, cells=4, lower_rule="vertices", faces="normal")
    mirrored = probe.model().compile().interactions[1]
    zero = np.zeros_like(positions)
    facing = mirrored.facing(State(positions, zero, zero, zero))
    inside = np.maximum(0.0, -facing.weights.min(axis=1)) <= 0.5
    return np.where(inside, facing.gap, np.nan)


def test_the_studys_plies_hold_a_bottom_node_pushed_up_off_the_top_ply():
    """The two-ply hemisphere's ply contact (its rule, mirrored pass and faces:
    validation/studies/hemisphere_plies_setup.py) on two 40-mm [0/90] plies (10-mm cells,
    both outlines pinned), the bottom ply's centre node pushed 3 mm up by a rigid sphere of
    radius 5 mm from below in 5 ms: a bottom-ply node driven into the top ply between its
    contact points, as the [0/45] study's bottom pole node was at 10 cells (its docstring).
    With the top ply's Gauss points alone the node went 0.33 mm through the top ply's face
    (0.27 at the end), more than a ply thickness's half; with the bottom ply's nodes held
    too (the mirrored pass) 0.07 mm, the penalty's give. ([0/45] plies of this size do not
    show it: a Gauss point of the 45-deg ply lies over the centre node, -0.06 mm with one
    pass.)"""
    from validation.studies.hemisphere_plies_setup import FACES, LOWER_RULE, RULE

    layup = Layup(PLY, (0.0, 90.0), 40.0, cells=4, rule=RULE, lower_rule=LOWER_RULE, faces=FACES)
    model = layup.model()
    model.fix("outline", ["ux", "uy", "uz"])
    bottom = layup.ply_nodes[0]
    points = layup.mesh.points
    centre = bottom[np.argmin(np.linalg.norm(points[bottom, :2], axis=1))]
    radius, lift = 5.0, 3.0
    start = (0.0, 0.0, points[centre, 2] - 0.5 * PLY.thickness - radius)
    model.contact(
        RigidSphere(start, radius, motion=(0.0, 0.0, lift), amplitude="smooth"), nodes="ply_1"
    )
    result = CentralDifference(
        duration=0.005, damping=20.0, progress=False, kinetic_bound=None
    ).solve(model)
    assert result.positions[centre, 2] > points[centre, 2] + 2.5  # pushed up
    n = layup.mesh.n_nodes
    least = min(np.nanmin(_lower_node_gaps(layup, frame.positions[:n])) for frame in result.frames)
    assert least > -0.5 * PLY.thickness


@pytest.mark.parametrize("faces", ["normal", "director"])
def test_one_point_per_node_loads_the_plies_as_a_point_per_triangle_corner(faces):
    """Rule "nodes" against "vertices" (a point at each corner of each triangle, all of a
    node's at the node): on [0/45] plies sunk 0.1 mm into each other and jittered, both ways,
    the same energy, forces and moments, to round-off (1e-12 of the largest: sums of six
    equal terms against one), for a sixth of the points on a large mesh."""
    loads = []
    for rule in ("vertices", "nodes"):
        layup = Layup(PLY, (0.0, 45.0), 40.0, cells=4, rule=rule, lower_rule=rule, faces=faces)
        contacts, state = _sunk(layup, 0.1)
        if not loads:
            jitter = 0.03 * np.random.default_rng(3).normal(size=state.positions.shape)
        state.positions += jitter
        for contact in contacts:
            force, moment = contact.internal_force(state)
            loads.append((len(contact.above), contact.strain_energy(state), force, moment))
    for before, after in zip(loads[:2], loads[2:]):
        assert after[0] * 3 < before[0]  # 25 points against 96 on these 4 x 4 cells
        assert after[1] == pytest.approx(before[1], rel=1e-12)
        scale = np.abs(before[2]).max()
        np.testing.assert_allclose(after[2], before[2], rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(after[3], before[3], rtol=0, atol=1e-12 * scale)
        assert before[1] > 0.0
