"""A contact asked again for the forces of the state it was last asked about answers from
memory (an explicit step asks for its forces, then for its moving tools' work): the same
numbers, and never a stale answer when anything that sets them has changed."""

import pickle
from dataclasses import replace

import numpy as np
import pytest

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


def _numbers(block, state, history):
    """(the nodes' rows added into zeros (3, 3), the tool's total force (1, 3), its work)."""
    force, moment = np.zeros((3, 3)), np.zeros((3, 3))
    block.add_internal_force(state, history, force, moment)
    return force, block.tool_forces(state, history), block.tool_work(state, history, 0.1, 0.2)


@pytest.mark.parametrize("friction", [0.3, 0.0])
def test_the_total_the_work_and_the_rows_follow_positions_moved_in_place(friction):
    """The tool's total force, its work and the nodes' rows are read from the kept forces
    without a copy, and the kept check compares the state's own rows (no copy either): a
    state whose positions are moved in place between two calls gets a fresh block's
    numbers, with friction (the numpy path) and without (the compiled pass)."""
    block, state, history = pressed_nodes()
    if friction == 0.0:
        tool = RigidSphere((0.0, 0.0, 0.0), 10.0, motion=(0.0, 0.0, 1.0))
        mesh = Mesh(state.positions.copy(), lines=np.array([[0, 1], [1, 2]]))
        block = Contact(tool, [0, 1, 2], offset=0.5, penalty=100.0).bind(Body.bare(mesh))
        history = None
    assert (block.compiled_forces is None) is (friction > 0.0)
    first = _numbers(block, state, history)
    assert np.any(first[0] != 0.0) and first[2] != 0.0
    for found, expected in zip(_numbers(block, state, history), first):  # from memory
        np.testing.assert_array_equal(found, expected)
    state.positions[1, 2] -= 0.03  # moved in place
    moved = _numbers(block, state, history)
    other = pickle.loads(pickle.dumps(block))
    other._last_forces = other._last_total = None
    for found, expected in zip(moved, _numbers(other, state, history)):
        np.testing.assert_array_equal(found, expected)
    assert not np.array_equal(moved[0], first[0])
    np.testing.assert_array_equal(moved[1], moved[0].sum(axis=0)[None, :])  # its reaction
