"""The augmented Lagrangian's passes (elements/augmented_contact.py) with a node that comes onto
the tool in the increment: its anchor for the increment is where its way touched the tool
(docs/theory.md §9.2),
which each pass and the accepted step put level with the node, and the friction force it
landed with is carried as its traction, as on the penalty path
(tests/test_contact_new_anchor.py)."""

from dataclasses import replace

import numpy as np
import pytest

from elements import RigidCylinder, RigidPlane
from elements.contact import Contact
from femcore import Body, Mesh
from femcore.state import State

MU, PENALTY, OFFSET, RADIUS = 0.3, 100.0, 0.5, 10.0
FAR = [50.0, 0.0, 50.0]  # the line's other node, never near the tool


def bound(tool, augmented: bool, start):
    """The contact of node 0 of a line with ``tool``, bound, and its history where node 0 is
    at ``start`` (clear of the tool)."""
    mesh = Mesh(np.array([start, FAR], dtype=float), lines=np.array([[0, 1]]))
    contact = Contact(tool, [0], offset=OFFSET, penalty=PENALTY, friction=MU, augmented=augmented)
    block = contact.bind(Body.bare(mesh))
    return block, block.initial_history()


def at(position):
    points = np.array([position, FAR], dtype=float)
    zero = np.zeros((2, 3))
    return State(points, zero, zero.copy(), zero.copy())


def on_cylinder(angle: float, depth: float):
    """(position at ``depth`` inside the contact surface, at ``angle`` from +z about y; the
    outward normal there)."""
    normal = np.array([np.sin(angle), 0.0, np.cos(angle)])
    return (RADIUS + OFFSET - depth) * normal, normal


@pytest.mark.parametrize("augmented", [False, True])
def test_a_node_landing_on_a_cylinder_is_anchored_level_with_itself(augmented):
    """A node 1 mm clear of a cylinder (R = 10 mm) comes straight down 0.05 mm into its contact
    surface: its anchor, from its approach at radius 11.5 mm, is accepted at the node's radius
    R + h / 2 - 0.05 = 10.45 mm (after an Uzawa pass too), so that a move by the angle a
    afterwards loads the stick spring by k_t times the arc (R + h / 2 - 0.05) a, the node's own
    (to 1e-6: the chord's sin a / a = 1 - 1.7e-7 and the turn of the normal, O(a^2)). The pass
    left it at the approach's height, and the spring 11.5 / 10.45 too stiff."""
    cylinder = RigidCylinder((0, 0, 0), (0, 1, 0), RADIUS)
    block, history = bound(cylinder, augmented, (0.0, 0.0, RADIUS + OFFSET + 1.0))
    landed, _ = on_cylinder(0.0, 0.05)
    radius = RADIUS + OFFSET - 0.05
    if augmented:
        history, _ = block.augment(at(landed), history)
        assert np.hypot(history.anchor[0, 0], history.anchor[0, 2]) == pytest.approx(radius)
    accepted = block.update_history(at(landed), history)
    anchor = accepted.anchor[0]
    assert np.hypot(anchor[0], anchor[2]) == pytest.approx(radius, rel=1e-12)
    angle = 1e-3
    moved, normal = on_cylinder(angle, 0.05)
    force = block.contact_forces(at(moved), accepted)[0]
    tangential = np.linalg.norm(force - (force @ normal) * normal)
    assert tangential == pytest.approx(PENALTY * radius * angle, rel=1e-6)


@pytest.mark.parametrize("slide", [2.0, 0.01])
def test_a_node_landing_sideways_carries_its_friction_force_as_its_traction(slide):
    """A node 1 mm above a plane, carried ``slide`` along x while it comes down 0.55 mm onto it
    (p = 0.05 mm): it touched the contact surface 0.5 / 0.55 of the way down (the gap taken
    linear over the step), so it slid ``slide`` x 0.05 / 0.55 after it touched. Before any
    pass its friction is the return mapping's against that slide, mu k p = 1.5 N sliding
    (2 mm), k_t s = 0.09 N stuck (0.01 mm), as the penalty's. After an Uzawa pass that force
    is its traction lambda_T: put back over where it touched (zero elastic slip), the node is
    held by it, the same force against its slide (stuck: the pass's normal multiplier doubles
    the limit to 3 N). The pass measures the stuck node's elastic slip from where it touched:
    that slide (the only stuck node's, the largest)."""
    plane = RigidPlane((0, 0, 0), (0, 0, 1))
    block, history = bound(plane, True, (0.0, 0.0, 1.0))
    landed = (slide, 0.0, OFFSET - 0.05)
    normal = PENALTY * 0.05
    touched = slide * 0.5 / 0.55  # where it touched the contact surface, mm along x
    friction = min(MU * normal, PENALTY * (slide - touched))
    force = block.contact_forces(at(landed), history)[0]
    np.testing.assert_allclose(force, [-friction, 0.0, normal], rtol=1e-12, atol=1e-12)
    history, report = block.augment(at(landed), history)
    stuck = (slide - touched) * PENALTY < MU * normal
    assert report["slip"] == pytest.approx(slide - touched if stuck else 0.0, rel=1e-12)
    np.testing.assert_allclose(history.traction[0], [-friction, 0.0, 0.0], rtol=1e-12)
    back = block.contact_forces(at((touched, 0.0, OFFSET - 0.05)), history)[0]
    np.testing.assert_allclose(back, [-friction, 0.0, 2.0 * normal], rtol=1e-12, atol=1e-12)


def test_the_tangent_after_a_pass_is_the_derivative_of_the_forces():
    """Nodes landing on a cylinder sideways, some stuck and some sliding (mu = 0.3), after an
    Uzawa pass: the pass gave them anchors, so the tangent holds no term of the anchor where
    they touched (which moves with x only while they have none); it is the central difference
    of the contact forces (step 1e-6 mm) to 1e-6 k (the difference's round-off and
    truncation, as in tests/test_contact_new_anchor.py)."""
    cylinder = RigidCylinder((0, 0, 0), (0, 1, 0), RADIUS)
    points = np.array([[x, y, RADIUS + OFFSET + 1.0] for x in (-0.2, 0.0, 0.2) for y in (0, 1)])
    mesh = Mesh(np.vstack([points, FAR]), lines=np.array([[k, 6] for k in range(6)]))
    contact = Contact(
        cylinder, np.arange(6), offset=OFFSET, penalty=PENALTY, friction=MU, augmented=True
    )
    block = contact.bind(Body.bare(mesh))
    history = block.initial_history()
    slide = np.array([0.001, 0.5, 0.002, 0.8, 0.0005, 0.3])
    x = np.vstack([points + np.column_stack([slide, 0 * slide, -1.0 - 0.05 - slide / 10]), FAR])

    def state(where):
        zero = np.zeros_like(where)
        return State(where, zero, zero.copy(), zero.copy())

    history, _ = block.augment(state(x), history)
    assert np.isfinite(history.anchor).all()
    p, n, touching = block.touch(state(x), history)
    _, _, stuck, sliding = block.tangential(state(x), history, p, n, touching)
    assert touching.all() and stuck.any() and sliding.any()
    blocks = block.tangent(state(x), history)[0].blocks[:, 0, :, 0, :]
    step = 1e-6
    for node in range(6):
        for axis in range(3):
            ahead, behind = x.copy(), x.copy()
            ahead[node, axis] += step
            behind[node, axis] -= step
            change = block.contact_forces(state(behind), history)[node]
            change = change - block.contact_forces(state(ahead), history)[node]
            column = change / (2.0 * step)
            assert np.abs(blocks[node][:, axis] - column).max() <= 1e-6 * PENALTY


def test_a_node_landing_after_a_pass_reset_its_multiplier_touches_the_surface_it_lands_on():
    """A node that left the tool keeps its multiplier lambda = 2 N (its contact surface
    lambda / k = 0.02 mm further out) until a pass at a state where it is clear of the tool
    resets it (lambda + k p < 0). Its next step brings it 2 mm along and down to 0.05 mm into
    the surface h / 2 it then has: it touched that surface at theta = g / (g + p) = 5 / 5.05
    of its way (g from its approach 5.5 mm over the plane, to the same surface as p), so it
    slips 2 x 0.05 / 5.05 - mu 0.05 mm (k_t = k; to 1e-12 mm, rounding). A gap kept when the
    step before was accepted, to the surface lambda / k further out (4.98 mm), would make it
    2 x 0.05 / 5.03 - mu 0.05, 7.9e-5 mm more (fails there)."""
    block, history = bound(RigidPlane((0, 0, 0), (0, 0, 1)), True, [0.0, 0.0, 5.5])
    history = replace(history, multiplier=np.array([2.0]))  # (kept from its last contact)
    history = block.update_history(at([0.4, 0.3, 5.5]), history)
    history, _ = block.augment(at([0.4, 0.3, 5.5]), history)
    assert history.multiplier[0] == 0.0
    landed = block.update_history(at([2.4, 0.3, 0.45]), history)
    assert landed.slip[0] == pytest.approx(2.0 * 0.05 / 5.05 - MU * 0.05, abs=1e-12)
