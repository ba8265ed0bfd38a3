"""A node that comes onto a tool in a step is anchored, for that step, at the point of its way
where it touched the contact surface (elements/contact.py, "Friction"; docs/theory.md §9.2):
its tangential motion since then is slip, and Coulomb's law holds at the end of the step in
which it arrived, as at any other."""

import numpy as np
import pytest

from elements import RigidCylinder, RigidPlane, RigidSphere
from elements.contact import Contact
from femcore import Body, Mesh
from femcore.state import State

MU, PENALTY, OFFSET = 0.3, 100.0, 0.5


def node_above_a_plane():
    """One node 1 mm above the plane z = 0, clear of it (half thickness 0.5 mm): (the bound
    contact, its history where the node starts)."""
    points = np.array([[0.0, 0.0, 1.0], [5.0, 0.0, 1.0]])
    mesh = Mesh(points, lines=np.array([[0, 1]]))
    plane = RigidPlane((0, 0, 0), (0, 0, 1))
    contact = Contact(plane, [0], offset=OFFSET, penalty=PENALTY, friction=MU)
    block = contact.bind(Body.bare(mesh))
    return block, block.initial_history()


def at(position):
    points = np.array([position, [5.0, 0.0, 1.0]], dtype=float)
    zero = np.zeros((2, 3))
    return State(points, zero, zero.copy(), zero.copy())


def test_a_node_that_lands_sliding_has_coulomb_friction_in_the_step_it_lands():
    """Carried 2 mm along x while it comes down 0.55 mm onto the plane (p = 0.05 mm): the
    friction is mu k p against its motion, |f_T| = mu f_N (Coulomb; frictionless, as a node
    with no anchor was, it was 0), and the accepted step leaves its anchor where the spring
    holds mu k p, mu p / 1 behind it. Its slip is counted from where it touched the
    surface, 0.5 / 0.55 of the way down (the gap taken linear over the step), so it slid
    2 x 0.05 / 0.55 - mu p after it touched (2 - mu p when its approach was its anchor: the
    way before it touched counted as slip)."""
    block, history = node_above_a_plane()
    assert not np.isfinite(history.anchor).any()
    state = at((2.0, 0.0, OFFSET - 0.05))
    force = block.contact_forces(state, history)[0]
    normal = PENALTY * 0.05
    assert force[2] == pytest.approx(normal, rel=1e-12)
    assert force[0] == pytest.approx(-MU * normal, rel=1e-12)
    assert force[1] == 0.0
    accepted = block.update_history(state, history)
    np.testing.assert_allclose(accepted.anchor[0], [2.0 - MU * 0.05, 0.0, OFFSET - 0.05])
    assert accepted.slip[0] == pytest.approx(2.0 * 0.05 / 0.55 - MU * 0.05, rel=1e-12)
    assert np.isnan(accepted.approach[0]).all()  # anchored now


def test_a_node_that_lands_straight_down_has_no_friction():
    """Straight down onto the plane: no tangential motion, no friction force, no slip; a
    node that leaves the tool forgets its anchor and keeps where it left from."""
    block, history = node_above_a_plane()
    state = at((0.0, 0.0, OFFSET - 0.05))
    force = block.contact_forces(state, history)[0]
    np.testing.assert_allclose(force, [0.0, 0.0, PENALTY * 0.05], atol=1e-12)
    accepted = block.update_history(state, history)
    assert accepted.slip[0] == 0.0
    off = at((1.0, 0.0, 2.0))
    left = block.update_history(off, accepted)
    assert np.isnan(left.anchor[0]).all()
    np.testing.assert_allclose(left.approach[0], [1.0, 0.0, 2.0])


def assembled(tangent, n_nodes: int) -> np.ndarray:
    """The (3 n, 3 n) matrix of a contact block's CellTangent list."""
    matrix = np.zeros((3 * n_nodes, 3 * n_nodes))
    for part in tangent:
        for nodes, block in zip(part.nodes, part.blocks):
            for a, node_a in enumerate(nodes):
                for b, node_b in enumerate(nodes):
                    matrix[3 * node_a : 3 * node_a + 3, 3 * node_b : 3 * node_b + 3] += block[
                        a, :, b, :
                    ]
    return matrix


@pytest.mark.parametrize(
    "tool",
    [RigidSphere((0, 0, -20), 20.0), RigidCylinder((0, 0, -20), (1, 0.2, 0), 20.0)],
    ids=["sphere", "cylinder"],
)
@pytest.mark.parametrize("stick", [1.0, 0.05])
def test_the_tangent_of_nodes_landing_on_a_round_tool_is_the_derivative_of_their_force(tool, stick):
    """16 nodes of a 4 x 4 mm patch 3 mm clear of the tool (no anchors) brought onto it in one
    step, each by its own random way (some stick, some slide, mu = 0.4): the tangent, whose
    friction part is that of the spring from where each node touched, is the central difference
    of the contact forces (step 1e-6 mm) to 1e-6 k (the difference's error: round-off ~1e-16
    |f| / 1e-6 and the truncation ~1e-12 of the springs' N/mm; measured 3e-9). Taken from
    the missing anchors instead, the landing nodes lose their friction part: 0.17 k off
    (0.009 k with the softer stick spring)."""
    rectangle = Mesh.rectangle(4.0, 4.0, nx=3, ny=3)
    start = rectangle.points + [-2.0, -2.0, 3.0]
    mesh = Mesh(start, triangles=rectangle.triangles)
    penalty = 100.0
    contact = Contact(
        tool,
        np.arange(mesh.n_nodes),
        offset=0.5,
        penalty=penalty,
        friction=0.4,
        stick_stiffness=stick,
    )
    block = contact.bind(Body.bare(mesh))
    history = block.initial_history()
    assert not np.isfinite(history.anchor).any()
    rng = np.random.default_rng(3)
    x = start + rng.normal(scale=0.3, size=start.shape) - [0.0, 0.0, 3.3]

    def state(points):
        zero = np.zeros_like(points)
        return State(points, zero, zero.copy(), zero.copy())

    p, n, touching = block.touch(state(x), history)
    _, _, stuck, sliding = block.tangential(state(x), history, p, n, touching)
    assert touching.all() and stuck.any()
    matrix = assembled(block.tangent(state(x), history), mesh.n_nodes)
    step = 1e-6
    difference = np.zeros_like(matrix)
    rows = block.connectivity[:, 0]
    for column in range(x.size):
        ahead, behind = x.copy(), x.copy()
        ahead.ravel()[column] += step
        behind.ravel()[column] -= step
        change = np.zeros_like(x)
        change[rows] = block.contact_forces(state(behind), history)
        change[rows] -= block.contact_forces(state(ahead), history)
        difference[:, column] = change.ravel() / (2.0 * step)
    assert np.abs(matrix - difference).max() <= 1e-6 * penalty
