"""The active-set strategy of the quasi-static solvers (elements/contact.py, module docstring):
``freeze`` fixes which nodes touch, which of them stick and slide and the slip directions, so
that the contact force is smooth while Newton iterates; ``thaw`` gives the unilateral law back.
"""

import numpy as np
import pytest
from test_contact import assert_tangent_is_the_force_derivative

from elements import RigidCylinder, RigidPlane
from elements import contact as contact_module
from elements.contact import Contact, FrictionHistory
from femcore import Mesh
from femcore.interaction import Body
from femcore.state import State
from solvers.linear import LinearSolver


def nodes_near(tool, mu, seed=5):
    """A 4 x 4 grid of nodes about the tool's top (some pressed in, some not), its contact
    block, the state and a history whose anchors lie a little off the nodes."""
    rng = np.random.default_rng(seed)
    mesh = Mesh.rectangle(4.0, 4.0, nx=3, ny=3)
    x = mesh.points + rng.normal(scale=0.2, size=mesh.points.shape) - [2.0, 2.0, -2.8]
    contact = Contact(tool, np.arange(mesh.n_nodes), offset=0.5, penalty=100.0, friction=mu)
    block = contact.bind(Body.bare(mesh))
    zero = np.zeros_like(x)
    state = State(positions=x, directors=zero, velocities=zero, angular_velocities=zero)
    state.load_factor = 0.5
    anchor = x - tool.offset(0.5) + rng.normal(scale=0.4, size=x.shape)
    history = FrictionHistory(anchor, np.zeros(len(x)), np.zeros(len(x)), 0.0)
    return block, state, history if mu > 0 else None


TOOLS = [
    RigidCylinder((0.0, 0.0, 0.0), (0.0, 1.0, 0.0), 3.0, motion=(0.1, 0.0, 0.2)),
    RigidPlane((0.0, 0.0, 3.0), (0.0, 0.0, 1.0), motion=(0.0, 0.0, -0.2)),
]


@pytest.mark.parametrize("tool", TOOLS, ids=["cylinder", "plane"])
def test_the_frozen_contact_tangent_is_the_derivative_of_the_frozen_force(tool):
    """Frozen at one state, the force at a state nearby (nodes moved 0.05 mm) is that of the
    frozen sets: its central differences match the tangent to 1e-6 of the penalty, sticking
    and sliding nodes alike (the projected frozen slip direction turns with the normal)."""
    block, state, history = nodes_near(tool, 0.4)
    frozen, _ = block.freeze(state, history)
    assert frozen.sliding.sum() >= 2 and (frozen.active & ~frozen.sliding).sum() >= 2
    rng = np.random.default_rng(7)
    moved = State(
        positions=state.positions + rng.normal(scale=0.05, size=state.positions.shape),
        directors=state.directors,
        velocities=state.velocities,
        angular_velocities=state.angular_velocities,
        load_factor=0.5,
    )
    assert_tangent_is_the_force_derivative(block, moved, frozen, tolerance=1e-6 * 100.0)


def test_a_frozen_node_lifted_off_the_tool_is_pulled_back_until_thawed():
    """A node of the frozen set lifted 0.1 mm clear of the tool feels a spring k x 0.1 pulling
    it back (the bilateral spring of the frozen set, no friction beyond the tool); thawed, it
    feels nothing; a node that was not touching stays free while frozen even if it moves in,
    until the set grows (what Newton does at each iteration: a set that only grows)."""
    tool = RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    mesh = Mesh(np.array([[0.0, 0.0, 0.4], [1.0, 0.0, 0.6]]), lines=np.array([[0, 1]]))
    block = Contact(tool, [0, 1], offset=0.5, penalty=100.0).bind(Body.bare(mesh))
    zero = np.zeros((2, 3))
    state = State(mesh.points.copy(), zero, zero, zero)
    frozen, changed = block.freeze(state, None)
    assert frozen.active.tolist() == [True, False] and changed == 1
    lifted = State(np.array([[0.0, 0.0, 0.6], [1.0, 0.0, 0.3]]), zero, zero, zero)
    np.testing.assert_allclose(block.contact_forces(lifted, frozen), [[0, 0, -10.0], [0, 0, 0]])
    assert block.freeze(lifted, frozen)[1] == 2  # both nodes changed their status
    grown, added = block.freeze(lifted, frozen, grow=True)  # the pressed node joins, none leaves
    assert grown.active.tolist() == [True, True] and added == 1
    assert block.thaw(frozen) is None  # frictionless: no history
    np.testing.assert_allclose(block.contact_forces(lifted, None), [[0, 0, 0], [0, 0, 20.0]])


def test_a_frozen_node_more_than_a_thickness_off_the_tool_leaves_the_set(monkeypatch):
    """Offset 0.5 mm (a body 1 mm thick): of three frozen nodes lifted 0.99, 1.01 and 3 mm past the
    contact surface, the first keeps its bilateral spring (k x 0.99 pulling it back) and the other
    two leave the set while it grows (RELEASE_THICKNESSES = 1, off by default: off the tool by more
    than the body's thickness, they have left it; the spring would pull them back over that
    distance onto whatever part of the tool is nearest), counted with the node that joins. Without
    thickness (offset 0, a cable) no node leaves; by default (RELEASE_THICKNESSES infinite) none
        does."""
    monkeypatch.setattr(contact_module, "RELEASE_THICKNESSES", 1.0)  # off by default
    tool = RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    points = np.array([[0.0, 0.0, 0.5], [1.0, 0.0, 0.5], [2.0, 0.0, 0.5], [3.0, 0.0, 0.9]])
    mesh = Mesh(points, lines=np.array([[0, 1], [1, 2], [2, 3]]))
    zero = np.zeros((4, 3))
    lifted = State(points + [[0, 0, 0.99], [0, 0, 1.01], [0, 0, 3.0], [0, 0, -0.5]], *[zero] * 3)
    block = Contact(tool, [0, 1, 2, 3], offset=0.5, penalty=100.0).bind(Body.bare(mesh))
    frozen_thick, _ = block.freeze(State(points.copy(), zero, zero, zero), None)
    assert frozen_thick.active.tolist() == [True, True, True, False]
    grown, changed = block.freeze(lifted, frozen_thick, grow=True)
    assert grown.active.tolist() == [True, False, False, True] and changed == 3
    np.testing.assert_allclose(
        block.contact_forces(lifted, grown), [[0, 0, -99.0], [0, 0, 0], [0, 0, 0], [0, 0, 10.0]]
    )
    thin = Contact(tool, [0, 1, 2, 3], offset=0.0, penalty=100.0).bind(Body.bare(mesh))
    on = State(points - [0.0, 0.0, 0.5], zero, zero, zero)
    frozen, _ = thin.freeze(on, None)
    grown, changed = thin.freeze(State(on.positions + [0.0, 0.0, 3.0], *[zero] * 3), frozen,
                                 grow=True)  # fmt: skip
    assert grown.active.tolist() == frozen.active.tolist() == [True, True, True, False]
    assert changed == 0
    monkeypatch.undo()  # the default: nothing leaves
    grown, changed = block.freeze(lifted, frozen_thick, grow=True)
    assert grown.active.tolist() == [True, True, True, True] and changed == 1


def test_a_frictional_tangent_reports_no_inertia():
    """A tangent far from symmetric (friction in slip: the symmetric part of a stable
    frictional tangent may be indefinite) is solved by LU and reports no count of negative
    eigenvalues, so that no stability search follows a mode it does not have."""
    import scipy.sparse as sp

    # eigenvalues 1 and 0.1, the symmetric part [[1, 1], [1, 0.1]] indefinite
    k = sp.csc_matrix(np.array([[1.0, 2.0], [0.0, 0.1]]))
    factor = LinearSolver().factorise(k)
    assert factor.kind == "lu" and factor.negative is None
    np.testing.assert_allclose(k @ factor.solve(np.array([1.0, 2.0])), [1.0, 2.0])
