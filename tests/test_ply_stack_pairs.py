"""Every ply of a layup touches every ply below it, not its neighbours alone
(elements/ply_contact.py ``join_plies``, docs/theory.md §9.3b "Plies that are not
neighbours"): where a middle ply has left the stack, the plies on either side of it face each
other and must not pass through each other."""

from __future__ import annotations

import numpy as np
import pytest

from elements.layup import Layup
from elements.ply_contact import PlyContactBlock
from materials import Fabric
from solvers import Static

PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)
SIDE = 20.0  # mm
LOAD = 1.0  # N, pressing the top ply down


def _middle_out(kinematics, **options):
    """A [0/0/0] stack whose middle ply has been drawn 30 mm out along x and whose top ply has
    come down onto the bottom one (faces touching, laid a smoothing width into it): the state
    after a pull-out, as the reference. The bottom and the middle ply held, the top ply held
    in its plane and pressed by ``LOAD`` shared by area over its nodes; ``options`` of the
    Layup."""
    layup = Layup(PLY, (0.0, 0.0, 0.0), SIDE, cells=2, kinematics=kinematics, **options)
    bottom, middle, top = layup.ply_nodes
    moved = layup.mesh.points.copy()
    moved[middle, 0] += 30.0
    # laid into the bottom ply's face by a smoothing width (1e-3 of the faces' a + b), so
    # that the contact holds it from the first iterate (at a gap of exactly 0 it does not
    # count as touching yet)
    moved[top, 2] -= PLY.thickness * (1.0 + 1e-3)
    layup.mesh = layup.mesh.with_points(moved)
    model = layup.model()
    model.fix(bottom)
    model.fix(middle)  # held where it was drawn to
    model.fix(top, ["ux", "uy"])
    x = layup.mesh.points
    tri = layup.mesh.triangles[layup.ply_cells[2]]
    area = 0.5 * np.abs(np.cross(x[tri[:, 1]] - x[tri[:, 0]], x[tri[:, 2]] - x[tri[:, 0]])[:, 2])
    lumped = np.bincount(tri.ravel(), np.repeat(area / 3.0, 3), layup.mesh.n_nodes)
    share = lumped[top] / lumped[top].sum()
    for node, s in zip(top, share):
        model.force([int(node)], (0.0, 0.0, -LOAD * s), amplitude="step")
    return layup, model


# the middle ply lies beside the others: its pairs face nothing (elements/ply_start.py)
NONE_FACES = "ignore:.*no contact point of the upper ply faces"


@pytest.mark.filterwarnings(NONE_FACES)
@pytest.mark.parametrize("kinematics", ["fibrous", "mindlin"])
def test_the_top_ply_rests_on_the_bottom_one_where_the_middle_ply_has_left(kinematics):
    layup, model = _middle_out(kinematics)
    result = Static(increments=1, progress=False, seek_stable=False).solve(model)
    bottom, _, top = layup.ply_nodes
    # statics: the top ply's load goes through the bottom ply to its supports (the Newton
    # tolerance is far below the 1e-6 N asked)
    assert result.reactions[bottom, 2].sum() == pytest.approx(LOAD, abs=1e-6)
    # and the top ply rests on the bottom one's face, pressed into it by the penalty's give:
    # the load over the contact's springs in series, sum_p k_p of the ply 3 on ply 1 pair,
    # uniform under a uniform pressure on a rigidly held ply (the smoothing, 1e-3 of a ply,
    # adds its half); the plate's lumped loads and springs share one area weighting, so the
    # penetration is uniform to rounding (measured: 1e-10 of it)
    compiled = model.compile()
    pairs = [b for b in compiled.interactions if isinstance(b, PlyContactBlock)]
    on_bottom = pairs[-1]  # ply 3 on ply 1, after the neighbours (join_plies)
    give = LOAD / float(np.sum(on_bottom.stiffness)) + 0.5 * on_bottom.smoothing
    face = 1.5 * PLY.thickness  # the bottom ply's upper face plus the top ply's half thickness
    depth = face - result.positions[top, 2]
    assert depth.mean() == pytest.approx(give, rel=1e-6)
    assert np.all(depth > 0.0) and np.all(depth < 0.1 * PLY.thickness)


@pytest.mark.filterwarnings(NONE_FACES)
def test_the_neighbours_switch_joins_each_ply_with_the_one_below_alone():
    # the switch the benchmark takes: the neighbours' pairs alone, as before
    layup, model = _middle_out("fibrous", pairs="neighbours")
    assert len(model.compile().interactions) == 2
    layup, model = _middle_out("fibrous")
    assert len(model.compile().interactions) == 3


def test_a_two_ply_stack_is_joined_as_before():
    for pairs in ("all", "neighbours"):
        layup = Layup(PLY, (0.0, 90.0), SIDE, cells=2, pairs=pairs, lower_rule="nodes")
        assert len(layup.model().compile().interactions) == 2


def test_pairs_must_be_a_known_choice():
    with pytest.raises(ValueError, match="pairs must be one of"):
        Layup(PLY, (0.0, 90.0), SIDE, cells=2, pairs="some")
