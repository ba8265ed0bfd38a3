"""The active-set strategy of the quasi-static solvers (elements/contact.py, module docstring):
``freeze`` fixes which nodes touch, which of them stick and slide and the slip directions, so
that the contact force is smooth while Newton iterates; ``thaw`` gives the unilateral law back.
"""

import math

import numpy as np
import pytest
from test_contact import assert_tangent_is_the_force_derivative

from elements import RigidCylinder, RigidPlane, RigidSurface
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


def test_a_frozen_node_more_than_a_thickness_off_the_tool_leaves_the_set():
    """Offset 0.5 mm (a body 1 mm thick): of three frozen nodes lifted 0.99, 1.01 and 3 mm past the
    contact surface, the first keeps its bilateral spring (k x 0.99 pulling it back) and the other
    two leave the set while it grows (``release=1``, ``release_turn=0``: off the tool by more than
    the body's thickness, whatever the normal, they have left it), counted with the node that
    joins. Without thickness (offset 0, a cable) no node leaves; with ``release=math.inf``, and by
    default (the normal of a plane does not turn), none does."""
    tool = RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    points = np.array([[0.0, 0.0, 0.5], [1.0, 0.0, 0.5], [2.0, 0.0, 0.5], [3.0, 0.0, 0.9]])
    mesh = Mesh(points, lines=np.array([[0, 1], [1, 2], [2, 3]]))
    zero = np.zeros((4, 3))
    lifted = State(points + [[0, 0, 0.99], [0, 0, 1.01], [0, 0, 3.0], [0, 0, -0.5]], *[zero] * 3)
    nodes = [0, 1, 2, 3]
    block = Contact(tool, nodes, offset=0.5, penalty=100.0, release_turn=0.0).bind(Body.bare(mesh))
    frozen_thick, _ = block.freeze(State(points.copy(), zero, zero, zero), None)
    assert frozen_thick.active.tolist() == [True, True, True, False]
    grown, changed = block.freeze(lifted, frozen_thick, grow=True)
    assert grown.active.tolist() == [True, False, False, True] and changed == 3
    np.testing.assert_allclose(
        block.contact_forces(lifted, grown), [[0, 0, -99.0], [0, 0, 0], [0, 0, 0], [0, 0, 10.0]]
    )
    thin = Contact(tool, nodes, offset=0.0, penalty=100.0, release_turn=0.0).bind(Body.bare(mesh))
    on = State(points - [0.0, 0.0, 0.5], zero, zero, zero)
    frozen, _ = thin.freeze(on, None)
    grown, changed = thin.freeze(State(on.positions + [0.0, 0.0, 3.0], *[zero] * 3), frozen,
                                 grow=True)  # fmt: skip
    assert grown.active.tolist() == frozen.active.tolist() == [True, True, True, False]
    assert changed == 0
    for kept in (Contact(tool, nodes, offset=0.5, penalty=100.0, release=math.inf),
                 Contact(tool, nodes, offset=0.5, penalty=100.0)):  # fmt: skip
        grown, changed = kept.bind(Body.bare(mesh)).freeze(lifted, frozen_thick, grow=True)
        assert grown.active.tolist() == [True, True, True, True] and changed == 1


def rim_die() -> RigidSurface:
    """A die's rim, meshed: a flange z = 0, 0 <= x <= 10 (normal +z) meeting at the edge x = z
    = 0 a wall x = 0 going down to z = -10 (normal -x, towards the die's opening x < 0)."""
    points = np.array(
        [[0, -5, 0], [10, -5, 0], [10, 5, 0], [0, 5, 0], [0, 5, -10], [0, -5, -10]], dtype=float
    )
    return RigidSurface(
        Mesh(points, triangles=np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 5]]))
    )


def test_a_frozen_node_carried_over_a_rim_leaves_the_set_and_one_lifted_off_the_flange_stays():
    """Offset 0.5 mm (a body 1 mm thick), k = 100 N/mm, three nodes frozen on the flange of
    ``rim_die`` (normal +z), then moved by a Newton step:

    * node 0 carried over the rim into the opening, to (-2, 0, 1): its closest point of the die
      is the edge (0, 0, 0), d = sqrt(5) mm, normal (-2, 0, 1) / sqrt(5), turned 63.4 deg from
      +z; off the contact surface by sqrt(5) - 0.5 = 1.74 mm, more than the thickness: it has
      left the flange and leaves the set (force 0). Without the release its bilateral spring
      pulls it back towards the edge: k (0.5 - sqrt(5)) n = (155.3, 0, -77.6) N.
    * node 1 lifted straight off the flange to z = 2: off by 1.5 mm, but facing the flange
      still (normal +z, not turned): it keeps its spring, k (0.5 - 2) = -150 N along z (the
      node a Newton step threw off the tool comes back; the distance-only rule released it).
    * node 2 carried just over the rim, to (-0.3, 0, 0.6): normal turned 26.6 deg, off by
      sqrt(0.45) - 0.5 = 0.17 mm: kept, k (0.5 - sqrt(0.45)) n.
    """
    x0 = np.array([[2.0, 0.0, 0.5], [5.0, 0.0, 0.5], [1.0, 0.0, 0.5]])
    mesh = Mesh(x0, lines=np.array([[0, 1], [1, 2]]))
    zero = np.zeros((3, 3))
    moved = State(np.array([[-2.0, 0.0, 1.0], [5.0, 0.0, 2.0], [-0.3, 0.0, 0.6]]), *[zero] * 3)
    k = 100.0
    n2 = np.array([-0.3, 0.0, 0.6]) / np.sqrt(0.45)
    f2 = k * (0.5 - np.sqrt(0.45)) * n2
    n0 = np.array([-2.0, 0.0, 1.0]) / np.sqrt(5.0)
    f0_held = k * (0.5 - np.sqrt(5.0)) * n0
    np.testing.assert_allclose(f0_held, [155.28, 0.0, -77.64], atol=0.01)  # the docstring's
    expected = {
        "default": ([False, True, True], [[0, 0, 0], [0, 0, -150.0], f2]),
        "never": ([True, True, True], [f0_held, [0, 0, -150.0], f2]),
        "distance alone": ([False, False, True], [[0, 0, 0], [0, 0, 0], f2]),
    }
    options = {
        "default": {},
        "never": {"release": math.inf},
        "distance alone": {"release_turn": 0.0},
    }
    for name, option in options.items():
        block = Contact(rim_die(), [0, 1, 2], offset=0.5, penalty=k, **option).bind(Body.bare(mesh))
        frozen, _ = block.freeze(State(x0.copy(), *[zero] * 3), None)
        assert frozen.active.tolist() == [True, True, True]
        grown, changed = block.freeze(moved, frozen, grow=True)
        active, forces = expected[name]
        assert grown.active.tolist() == active, name
        assert changed == active.count(False), name
        # 1e-9 N: the closest point and normal are computed exactly up to rounding
        np.testing.assert_allclose(block.contact_forces(moved, grown), forces, atol=1e-9)


def test_release_parameters_are_checked():
    """A release band <= 0 or NaN and a turn outside [0, 180) deg are refused at the API."""
    tool = RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    for bad in ({"release": 0.0}, {"release": float("nan")}, {"release_turn": -1.0},
                {"release_turn": 180.0}, {"release": "1"}):  # fmt: skip
        with pytest.raises(ValueError, match="release"):
            Contact(tool, **bad)


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
