"""Every ply of a layup touches every ply below it, not its neighbours alone
(elements/ply_contact.py ``join_plies``, docs/theory.md §9.3b "Plies that are not
neighbours"): where a middle ply has left the stack, the plies on either side of it face each
other and must not pass through each other."""

from __future__ import annotations

import numpy as np
import pytest

from elements.layup import Layup
from elements.ply_contact import PlyContact, PlyContactBlock
from femcore.state import State
from materials import Fabric
from solvers import CentralDifference, Static
from solvers.common import ConvergenceError

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


@pytest.mark.parametrize("between", ["ply_2", 2, None], ids=["name", "int", "none"])
def test_the_plies_between_must_be_a_tuple_of_selections(between):
    with pytest.raises(ValueError, match="between must be a tuple of the plies between"):
        PlyContact("ply_3", "ply_1", between=between)


# A consolidation pressure, 0.1 MPa on the 20 x 20 mm stack: under it, at the automatic
# penalty, each neighbour pair gives 0.84 h, so a pair that is not neighbours, h apart at
# the start, closes while the ply between is still there (elements/ply_between.py)
PRESSURE = 0.1  # MPa
PRESSED = PRESSURE * SIDE**2  # N


def _area_shares(layup, k):
    """Ply k's nodes (1 = bottom) and their shares of its area (lumped by triangle thirds)."""
    x = layup.mesh.points
    tri = layup.mesh.triangles[layup.ply_cells[k - 1]]
    area = 0.5 * np.abs(np.cross(x[tri[:, 1]] - x[tri[:, 0]], x[tri[:, 2]] - x[tri[:, 0]])[:, 2])
    lumped = np.bincount(tri.ravel(), np.repeat(area / 3.0, 3), layup.mesh.n_nodes)
    nodes = layup.ply_nodes[k - 1]
    return nodes, lumped[nodes] / lumped[nodes].sum()


def _pressed_stack(kinematics, middle_held=("ux", "uy"), laid_into=1.0, **options):
    """A [0/0/0] stack, every ply in place, laid ``laid_into`` smoothing widths into each
    other (so that the contacts hold from Static's first iterate; 0 for an explicit run,
    which an overlap would set moving with no work done), the bottom ply held, the top one
    held in its plane, the middle one along ``middle_held``; the automatic penalty."""
    layup = Layup(PLY, (0.0, 0.0, 0.0), SIDE, cells=2, kinematics=kinematics, **options)
    bottom, middle, top = layup.ply_nodes
    moved = layup.mesh.points.copy()
    moved[middle, 2] -= 2e-3 * PLY.thickness * laid_into
    moved[top, 2] -= 4e-3 * PLY.thickness * laid_into
    layup.mesh = layup.mesh.with_points(moved)
    model = layup.model()
    model.fix(bottom)
    model.fix(middle, list(middle_held))
    model.fix(top, ["ux", "uy"])
    return layup, model


def _pairs_at_end(layup, model, result):
    """The model's ply contacts (in join_plies' order) and the run's last state (positions,
    directors, at rest) to ask their forces at."""
    pairs = [b for b in model.compile().interactions if isinstance(b, PlyContactBlock)]
    state = State(
        result.positions,
        np.nan_to_num(result.directors),
        np.zeros((layup.mesh.n_nodes, 3)),
        np.zeros((layup.mesh.n_nodes, 3)),
    )
    return pairs, state


def _press(layup, model, amplitude):
    nodes, shares = _area_shares(layup, 3)
    for node, share in zip(nodes, shares):
        model.force([int(node)], (0.0, 0.0, -PRESSED * share), amplitude=amplitude)


# the fibrous plies at the automatic penalty (each pair gives 0.84 h under the load); the
# Mindlin plies' automatic penalty is stiffer (sized on their own step), so that the pairs give
# 0.5 h together, short of the gap: given, 15 N/mm a node, theirs gives 0.78 h a pair
# (faces along the normals: the same give, 0.84 h)
@pytest.mark.parametrize(
    "kinematics, penalty, faces",
    [("fibrous", None, None), ("fibrous", None, "normal"), ("mindlin", 15.0, None)],
    ids=["fibrous", "fibrous-normal-faces", "mindlin"],
)
def test_a_pressed_stack_carries_the_whole_load_through_the_middle_ply(kinematics, penalty, faces):
    # statics of a stack in place: ply 3 rests on ply 2 alone, which rests on ply 1, so ply 2
    # on ply 1 carries the whole load and ply 3 on ply 1 nothing, at any penalty; before, the
    # penalties' give closed the 3-on-1 gap and that pair pushed beside ply 2 (fibrous: 0.27
    # of the load)
    layup, model = _pressed_stack(kinematics, penalty=penalty, faces=faces)
    _press(layup, model, "linear")
    result = Static(increments=2, progress=False, seek_stable=False).solve(model)
    pairs, state = _pairs_at_end(layup, model, result)
    assert len(pairs) == 3  # 2 on 1, 3 on 2, then 3 on 1 (join_plies' order)
    bottom, middle, top = layup.ply_nodes
    # each pair's F_int = dW/dx on ply 1's nodes: the force ply 1 pushes up with, the load
    # the pair carries down onto it (the Newton tolerance is far below the 1e-6 asked)
    two_on_one = pairs[0].internal_force(state)[0][bottom, 2].sum()
    three_on_one = pairs[2].internal_force(state)[0]
    assert two_on_one == pytest.approx(PRESSED, rel=1e-6)
    assert np.abs(three_on_one).max() == 0.0  # no point of the pair acts
    assert result.reactions[bottom, 2].sum() == pytest.approx(PRESSED, rel=1e-6)
    # the pair's gap has closed indeed (its faces into each other): what made it act before
    assert np.mean(result.positions[top, 2] - result.positions[bottom, 2]) < PLY.thickness


def test_the_mirrored_passes_of_a_pressed_stack_go_through_the_middle_ply_too():
    # with the mirrored passes (points on the lower ply, at its nodes: on the plies' common
    # outline), soft enough (5 N/mm a node) that the 3-on-1 faces pass each other: the two
    # passes of ply 2 on ply 1 carry the whole load, those of ply 3 on ply 1 nothing (before:
    # no equilibrium from load factor 0.07; with the shield's w = 1 test the mirrored 3-on-1
    # pass took 8.1 N at the outline nodes)
    layup, model = _pressed_stack("fibrous", lower_rule="nodes", penalty=5.0)
    _press(layup, model, "linear")
    result = Static(increments=2, progress=False, seek_stable=False).solve(model)
    pairs, state = _pairs_at_end(layup, model, result)
    assert len(pairs) == 6  # (2 on 1, 3 on 2, 3 on 1), each with its mirrored pass
    bottom, _, top = layup.ply_nodes
    assert np.mean(result.positions[top, 2] - result.positions[bottom, 2]) < PLY.thickness
    carried = sum(p.internal_force(state)[0][bottom, 2].sum() for p in pairs[:2])
    assert carried == pytest.approx(PRESSED, rel=1e-6)
    for pair in pairs[4:]:
        assert np.abs(pair.internal_force(state)[0]).max() == 0.0


@pytest.mark.slow  # an explicit run of 400 steps: some 3 s
def test_an_explicit_press_goes_through_the_middle_ply_alone():
    # the explicit step reads the same facing: pressed smoothly to 0.1 MPa over 5 ms and at
    # rest there (fibrous plies, automatic penalty), ply 2 on ply 1 carries the load and ply
    # 3 on ply 1 nothing, though their faces have passed each other (before: 29.46 N and
    # 10.76 N); to 1e-3 of the load, the run's dynamic residue (2e-5 measured)
    layup, model = _pressed_stack("fibrous", laid_into=0.0)
    _press(layup, model, "smooth")
    result = CentralDifference(duration=0.005, progress=False, kinetic_bound=None).solve(model)
    pairs, state = _pairs_at_end(layup, model, result)
    bottom, _, top = layup.ply_nodes
    assert np.mean(result.positions[top, 2] - result.positions[bottom, 2]) < PLY.thickness
    assert pairs[0].internal_force(state)[0][bottom, 2].sum() == pytest.approx(PRESSED, rel=1e-3)
    assert np.abs(pairs[2].internal_force(state)[0]).max() == 0.0


def test_a_pressed_middle_ply_holds_below_coulombs_pull():
    # Coulomb's pull-out of the middle ply: both its faces carry P, so it sticks for a pull
    # T < 2 mu P (16 N here); pulled by 0.85 of that after the press, it holds, as it does
    # with the neighbours' pairs alone. Before, the 3-on-1 pair took 0.27 of P past ply 2,
    # which then slid at 2 mu (0.73 P) = 11.7 N: at 13.6 N the solve found no equilibrium
    mu = 0.2
    pull = 0.85 * 2 * mu * PRESSED
    layup, model = _pressed_stack("fibrous", middle_held=("uy",), friction=mu)
    _press(layup, model, "step")
    nodes, shares = _area_shares(layup, 2)
    for node, share in zip(nodes, shares):
        model.force([int(node)], (pull * share, 0.0, 0.0), amplitude="linear")
    result = Static(increments=4, progress=False, seek_stable=False, step_loads_first=True).solve(
        model
    )
    bottom, middle, top = layup.ply_nodes
    # stuck: each face's stick springs (k_t = W'' = k_p, pressed past the smoothing) carry
    # T / 2, so ply 2 moves by T / (2 sum k_p), the springs of one face's pair; to 1e-4 (the
    # ply's own stretch between its pull and its friction, both shared by area: 1e-6
    # measured)
    pairs = [b for b in model.compile().interactions if isinstance(b, PlyContactBlock)]
    give = pull / (2.0 * float(np.sum(pairs[0].stiffness)))
    assert result.displacements[middle, 0] == pytest.approx(np.full(len(middle), give), rel=1e-4)
    # equilibrium along x: the pull goes out through both faces' friction to the held plies
    # (symmetric: the same pressure on both faces)
    held = result.reactions[bottom, 0].sum() + result.reactions[top, 0].sum()
    assert held == pytest.approx(-pull, rel=1e-6)
    assert result.reactions[bottom, 0].sum() == pytest.approx(-pull / 2, rel=1e-3)


@pytest.mark.slow  # Newton cuts its last increment eight times before it stops: some 5 s
def test_a_pressed_middle_ply_slides_at_coulombs_pull():
    # past 2 mu P (16 N) no equilibrium holds the pulled middle ply: pulled towards 1.1 of
    # it, the static solve stops where the pull reaches 2 mu P, within two of the last
    # increment's smallest cuts (4.4 N / 2^8 = 0.017 N each) below it; 15.98 N measured.
    # Before, it stopped at 2 mu (0.73 P) = 11.7 N
    mu = 0.2
    limit = 2 * mu * PRESSED
    pull = 1.1 * limit
    layup, model = _pressed_stack("fibrous", middle_held=("uy",), friction=mu)
    _press(layup, model, "step")
    nodes, shares = _area_shares(layup, 2)
    for node, share in zip(nodes, shares):
        model.force([int(node)], (pull * share, 0.0, 0.0), amplitude="linear")
    solver = Static(increments=4, progress=False, seek_stable=False, step_loads_first=True)
    with pytest.raises(ConvergenceError) as stopped:
        solver.solve(model)
    reached = (stopped.value.load_factor - 1.0) * pull  # the press is the first unit
    assert limit - 2 * (0.25 * pull) / 2**8 <= reached <= limit
