"""Where the plies of a layup have passed through each other (elements/ply_crossing.py,
fibreshell.layup_summary ``ply_crossings``): a node past the other ply's mid-surface, over
that ply, is counted with its depth; plies in their order, and a node beside the other ply's
outline, are not. A [0/90] layup of two 0.3-mm plies, 20 x 20 mm in 4 x 4 cells, laid flat
at z = 0.15 and 0.45 mm: the depths below are those of flat plies, exact."""

import warnings

import numpy as np
import pytest

from elements.layup import Layup
from elements.ply_crossing import crossed_nodes
from fibreshell.layup_summary import ply_crossings
from fibreshell.run import _say_crossings
from materials import presets

FABRIC = presets.g986_stack(2).plies(2)  # one 0.3-mm ply


@pytest.fixture(scope="module")
def layup() -> Layup:
    return Layup(FABRIC, (0.0, 90.0), 20.0, 20.0, cells=4)


def _moved(layup: Layup, node: int, to: tuple) -> np.ndarray:
    positions = layup.mesh.points.copy()
    positions[node] = to
    return positions


def _central(layup: Layup, ply: int) -> int:
    """The node of ``ply`` (0-based) nearest the blank's centre."""
    nodes = layup.ply_nodes[ply]
    return int(nodes[np.argmin(np.linalg.norm(layup.mesh.points[nodes, :2], axis=1))])


def test_plies_in_their_order_have_not_crossed(layup):
    reference = layup.mesh.points
    assert ply_crossings(layup, reference, reference) == {
        "ply_2": {"lower": "ply_1", "nodes": 0, "deepest_mm": 0.0, "first": []}
    }


def test_an_upper_node_below_the_lower_ply_is_counted_with_its_depth(layup):
    """Ply 2's central node moved to z = -0.05: 0.2 mm below ply 1's mid-surface, the
    deepest; ply 1's node under it is then above ply 2's dipped triangles (0.15 mm over
    -0.05: a crossing is mutual), the only other one."""
    node = _central(layup, 1)
    x, y, _ = layup.mesh.points[node]
    crossed = ply_crossings(layup, layup.mesh.points, _moved(layup, node, (x, y, -0.05)))
    assert crossed["ply_2"]["nodes"] == 2
    assert crossed["ply_2"]["first"] == [node, _central(layup, 0)]
    assert crossed["ply_2"]["deepest_mm"] == pytest.approx(0.2, rel=1e-12)


def test_a_lower_node_above_the_upper_ply_is_counted_too(layup):
    """Ply 1's central node moved to z = 0.55: 0.1 mm above ply 2's mid-surface (the one-way
    contact's blind side: its points are the upper ply's)."""
    node = _central(layup, 0)
    x, y, _ = layup.mesh.points[node]
    crossed = ply_crossings(layup, layup.mesh.points, _moved(layup, node, (x, y, 0.55)))
    assert crossed["ply_2"]["first"][0] == node
    assert crossed["ply_2"]["deepest_mm"] == pytest.approx(0.1, rel=1e-9)


def test_plies_that_are_not_neighbours_are_judged_too():
    """[0/0/0], the middle ply drawn 30 mm out along x and the top ply fallen 0.2 mm past the
    bottom ply's mid-surface (the middle-out stack without ply-on-ply contact between plies
    that are not neighbours): the top ply's central node is through the bottom ply by 0.2 mm
    and the bottom ply's central node above the top ply, a crossing being mutual; the nodes
    on the outline have their closest point on the other ply's outline, beside it and not
    through it (elements/ply_crossing.py), and the middle ply is beside both."""
    stack = Layup(FABRIC, (0.0, 0.0, 0.0), 20.0, 20.0, cells=2)
    bottom, middle, top = stack.ply_nodes
    positions = stack.mesh.points.copy()
    positions[middle, 0] += 30.0
    positions[top, 2] = stack.heights[0] - 0.2
    crossed = ply_crossings(stack, stack.mesh.points, positions)
    assert crossed["ply_3_on_ply_1"]["lower"] == "ply_1"
    # the inner node alone of each ply's 3 x 3 at 2 cells
    assert crossed["ply_3_on_ply_1"]["nodes"] == 2
    assert crossed["ply_3_on_ply_1"]["deepest_mm"] == pytest.approx(0.2, rel=1e-9)
    assert crossed["ply_2"]["nodes"] == 0 and crossed["ply_3"]["nodes"] == 0


def test_a_node_beside_the_other_plys_outline_is_off_it_not_through_it():
    """One triangle of the other ply, z = 0, normal +z: a node 1 mm below it over its
    inside is through (by 1 mm); the same node 1 mm past its outline is beside it."""
    reference = np.array([[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0], [1.0, 1.0, -1.0]])
    triangle = np.array([[0, 1, 2]])
    crossed, depth = crossed_nodes(reference, reference, np.array([3]), triangle, 1.0)
    assert crossed.tolist() == [3] and depth == pytest.approx([1.0], rel=1e-12)
    beside = reference.copy()
    beside[3] = (-1.0, 1.0, -1.0)
    crossed, _ = crossed_nodes(reference, beside, np.array([3]), triangle, 1.0)
    assert crossed.size == 0


def test_crossed_plies_are_said_with_the_remedy_of_their_contact():
    crossed = {"ply_2": {"nodes": 2, "deepest_mm": 0.99, "first": [70, 68]}}
    with pytest.warns(UserWarning, match=r"2 nodes of ply_2 .* by 0\.99 mm .*lower_rule"):
        _say_crossings(crossed, None)
    with pytest.warns(UserWarning, match=r"plies crossed.*a larger \[layup\] penalty"):
        _say_crossings(crossed, "nodes")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _say_crossings({"ply_2": {"nodes": 0, "deepest_mm": 0.0, "first": []}}, None)
