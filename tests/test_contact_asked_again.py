"""A contact asked again for the forces of the state it was last asked about answers from
memory (an explicit step asks for its forces, then for its moving tools' work): the same
numbers, and never a stale answer when anything that sets them has changed."""

from dataclasses import replace

import numpy as np

from elements import RigidSphere
from elements.contact import Contact, FrictionHistory
from femcore import Body, Mesh
from femcore.state import State


def pressed_nodes():
    """Three nodes pressed into a sphere moving down, with friction and anchors."""
    points = np.array([[0.0, 0.0, 10.2], [1.0, 0.5, 10.1], [-0.5, 1.0, 10.15]])
    mesh = Mesh(points, lines=np.array([[0, 1], [1, 2]]))
    tool = RigidSphere((0.0, 0.0, 0.0), 10.0, motion=(0.0, 0.0, 1.0))
    contact = Contact(tool, [0, 1, 2], offset=0.5, penalty=100.0, friction=0.3)
    block = contact.bind(Body.bare(mesh))
    zero = np.zeros((3, 3))
    state = State(points.copy(), zero, zero.copy(), zero.copy(), load_factor=0.1)
    anchor = points - [[0.01, 0.0, 0.0], [0.0, 0.02, 0.0], [0.5, 0.0, 0.0]]
    history = FrictionHistory(anchor, np.zeros(3), np.full(3, 0.3), 0.0)
    return block, state, history


def test_the_forces_asked_again_are_the_same_and_not_a_view_of_the_memory():
    block, state, history = pressed_nodes()
    first = block.contact_forces(state, history)
    expected = first.copy()
    first[:] = 0.0  # the caller's array is its own
    again = block.contact_forces(state, history)
    np.testing.assert_array_equal(again, expected)
    again[:] = 0.0  # that of an answer from memory too
    np.testing.assert_array_equal(block.contact_forces(state, history), expected)
    assert np.any(expected != 0.0)


def test_the_forces_follow_the_positions_the_load_factor_the_history_and_the_stiffness():
    """Each of them changed in turn (the positions in place too): the answer is that of a
    fresh block."""
    block, state, history = pressed_nodes()

    def fresh(state, history, stiffness=None):
        other, _, _ = pressed_nodes()
        if stiffness is not None:
            other.stiffness = stiffness
        return other.contact_forces(state, history)

    before = block.contact_forces(state, history)
    moved = replace(state, positions=state.positions + [0.0, 0.0, -0.05])
    np.testing.assert_array_equal(block.contact_forces(moved, history), fresh(moved, history))
    state.positions[1, 2] -= 0.03  # moved in place
    np.testing.assert_array_equal(block.contact_forces(state, history), fresh(state, history))
    later = replace(state, load_factor=0.12)
    np.testing.assert_array_equal(block.contact_forces(later, history), fresh(later, history))
    slid = replace(history, anchor=history.anchor + 0.01)
    np.testing.assert_array_equal(block.contact_forces(later, slid), fresh(later, slid))
    block.stiffness = 2.0 * block.stiffness
    np.testing.assert_array_equal(
        block.contact_forces(later, slid), fresh(later, slid, block.stiffness)
    )
    assert not np.array_equal(block.contact_forces(later, slid), before)
