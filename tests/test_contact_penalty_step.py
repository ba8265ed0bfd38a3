"""The interactions' automatic penalty is sized on the elements' critical step with a Mindlin
shell's rotary inertia at B2's closed form, whatever rotary_scaling the shell was given
(elements/contact_penalty.py; docs/theory.md §6.2, "The penalty's step"): the rule the
penalty always had with the closed j (the same bits), which no other choice of j (the element
rule, a scaled j, the physical h^2 / 12) moves.

References: the closed-j shell's own critical step (the rule before, k = PENALTY_SHARE m (2 /
dt)^2); the element's own eigenvalue problem (B4, all 18 degrees of freedom) at the closed j;
the fibrous shell, whose step no rotary inertia sets, keeps its critical step.
"""

from __future__ import annotations

import numpy as np
import pytest

import elements.mindlin as mindlin
from elements import FibrousShell, MindlinShell, RigidPlane
from elements.contact import PENALTY_SHARE
from elements.layup import Layup
from elements.mindlin_steps import element_omega2
from femcore import Mesh, Model
from materials import ElasticShell, Fabric

# The two-ply hemisphere's ply (validation/studies/hemisphere_plies_setup.py) on 25-mm cells.
PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)


def _plate(element):
    """A 100 x 100 mm plate of 25-mm cells resting on the plane z = 0, compiled."""
    flat = Mesh.rectangle(100.0, 100.0, nx=4, ny=4)
    model = Model(flat.with_points(flat.points + [0.0, 0.0, 0.5 * PLY.thickness]))
    model.add(element)
    model.contact(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)))
    return model.compile()


def _mindlin(rotary_scaling):
    return _plate(MindlinShell(ElasticShell.equivalent(PLY), rotary_scaling=rotary_scaling))


def test_the_tools_penalty_does_not_follow_the_rotary_inertia():
    # j from h^2 / 12 (False) to the closed form (True) and the element rule (that held to
    # the membrane's step): the critical step grows 43 and 2.0 times, every contact spring
    # stays to the bit, and is the closed j's on its own critical step (the rule before the
    # rotary inertia could be chosen). Sized on each one's critical step, the closed form's
    # springs were 4.2 times the element rule's, the physical j's 1900 times the closed form's.
    compiled = {s: _mindlin(s) for s in (False, True, "element")}
    steps = {s: c.stable_dt(c.initial_state()) for s, c in compiled.items()}
    assert steps["element"] > 1.8 * steps[True] > 9.0 * steps[False]
    stiffness = {s: c.interactions[0].stiffness for s, c in compiled.items()}
    assert np.array_equal(stiffness[False], stiffness[True])
    assert np.array_equal(stiffness["element"], stiffness[True])
    closed = compiled[True]
    mass = closed.mass0[closed.interactions[0].connectivity[:, 0]]
    assert np.array_equal(stiffness[True], PENALTY_SHARE * mass * (2.0 / steps[True]) ** 2)


def test_the_penalty_step_is_the_closed_js_element_step():
    # The element rule's block: its penalty step is 2 / omega of the element eigenvalue
    # problem (B4) at the closed j in the reference configuration (to round-off: the
    # calibrated steps go through the cheap bound and back), and, stretched 1.2 times in x,
    # the closed-j shell's critical step at that state to the bit (the same stretch, B5).
    compiled = _mindlin("element")
    block = next(p for p in compiled.parts if hasattr(p, "rotary_factor"))
    x0, v0 = block._reference_cells()
    closed = block._closed_rotary_factor()
    assert block.rotary_factor.min() > 1.5 * closed.max()
    state = compiled.initial_state()
    eigen = 2.0 / np.sqrt(element_omega2(block, x0, v0, rotary_factor=closed).max())
    assert block.penalty_stable_dt(state) == pytest.approx(eigen, rel=1e-12)
    stretched = compiled.initial_state()
    stretched.positions[:, 0] *= 1.2
    closed_shell = _mindlin(True)
    assert compiled.penalty_stable_dt(stretched) == closed_shell.stable_dt(stretched)
    assert compiled.penalty_stable_dt(stretched) == pytest.approx(eigen / 1.2, rel=1e-12)


def test_fibrous_and_mindlin_plies_share_the_rule():
    # k / m = PENALTY_SHARE (2 / dt_p)^2 on both shells: the fibrous shell's dt_p is its
    # critical step (no rotary inertia sets it), the closed-j Mindlin shell's too, so their
    # springs add at most PENALTY_SHARE of the cells' omega^2; the element rule's shell
    # steps 2.0 times longer, and its springs weigh 4.2 times more against its cells' omega^2.
    for compiled, rule in (
        (_plate(FibrousShell(PLY)), "fibrous"),
        (_mindlin(True), "closed"),
        (_mindlin("element"), "element"),
    ):
        state = compiled.initial_state()
        penalty, step = compiled.penalty_stable_dt(state), compiled.stable_dt(state)
        contact = compiled.interactions[0]
        mass = compiled.mass0[contact.connectivity[:, 0]]
        np.testing.assert_allclose(contact.stiffness / mass, PENALTY_SHARE * (2.0 / penalty) ** 2)
        springs = compiled.penalty_frequency_squared(compiled.mass0)
        if rule == "element":
            assert 1.8 * penalty < step < 2.2 * penalty
            assert springs > 3.0 * PENALTY_SHARE * (2.0 / step) ** 2
        else:
            assert penalty == step
            assert springs <= PENALTY_SHARE * (2.0 / step) ** 2 * (1 + 1e-12)


def test_the_plies_penalty_does_not_follow_the_rotary_inertia(monkeypatch):
    # Two Mindlin plies [0/90] on a die: their ply-on-ply springs (and the die's) the same to
    # the bit with the closed j and with the element rule's (every MindlinShell the layup
    # builds given it).
    def stiffness(mode):
        with monkeypatch.context() as patch:
            patch.setattr(mindlin, "rotary_mode", lambda value: mode)
            layup = Layup(PLY, (0.0, 90.0), 50.0, cells=2, kinematics="mindlin-elastic")
            model = layup.model()
            bottom = layup.heights[0] - 0.5 * PLY.thickness
            model.contact(RigidPlane((0, 0, bottom), (0, 0, 1.0)), "ply_1")
            compiled = model.compile()
        step = compiled.stable_dt(compiled.initial_state())
        springs = [
            np.asarray(getattr(i, "node_stiffness", i.stiffness)) for i in compiled.interactions
        ]
        # the rule before j could be chosen: PENALTY_SHARE m (2 / dt)^2 at the critical step
        nodes = [getattr(i, "upper", None) for i in compiled.interactions]
        nodes = [
            i.connectivity[:, 0] if n is None else n for i, n in zip(compiled.interactions, nodes)
        ]
        before = [PENALTY_SHARE * compiled.mass0[n] * (2.0 / step) ** 2 for n in nodes]
        return step, springs, before

    closed_step, closed, before = stiffness("closed")
    element_step, element, _ = stiffness("element")
    assert element_step > 1.5 * closed_step
    assert len(closed) == 2
    for a, b, c in zip(closed, element, before):
        assert np.array_equal(a, b)
        assert np.array_equal(a, c)
