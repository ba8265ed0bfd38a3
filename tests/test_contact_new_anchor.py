"""A node that comes onto a tool in a step is anchored, for that step, where it was when the
last step was accepted (elements/contact.py, "Friction"; docs/theory.md §9.2): its tangential
motion over the step is slip, and Coulomb's law holds at the end of the step in which it
arrived, as at any other."""

import numpy as np
import pytest

from elements import RigidPlane
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
    holds mu k p, mu p / 1 behind it, with 2 - mu p of slip."""
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
    assert accepted.slip[0] == pytest.approx(2.0 - MU * 0.05, rel=1e-12)
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
