"""The interactions' automatic penalty is sized on the elements' critical step with their
rotations held (elements/contact_penalty.py; docs/theory.md §6.2, "The penalty's step"): a
property of the model's mass and stiffness, which the Mindlin shell's rotary inertia j (a
mass scaling of the rotations alone, B2) does not move.

References: the held step is the limit of the element's own eigenvalue problem (B4, all 18
degrees of freedom) as j grows without bound; the fibrous shell, whose step no rotary inertia
sets, keeps the rule it had (k = PENALTY_SHARE m (2 / dt)^2, dt its critical step).
"""

from __future__ import annotations

import numpy as np
import pytest

import elements.mindlin as mindlin
from elements import FibrousShell, MindlinShell, RigidPlane
from elements.contact import PENALTY_SHARE
from elements.layup import Layup
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
    # stays to the bit. Sized on the critical step (the code before), the closed form's
    # springs were 4.2 times the element rule's, the physical j's 7800 times.
    compiled = {s: _mindlin(s) for s in (False, True, "element")}
    steps = {s: c.stable_dt(c.initial_state()) for s, c in compiled.items()}
    assert steps["element"] > 1.8 * steps[True] > 9.0 * steps[False]
    stiffness = {s: c.interactions[0].stiffness for s, c in compiled.items()}
    assert np.array_equal(stiffness[False], stiffness[True])
    assert np.array_equal(stiffness["element"], stiffness[True])


def test_the_held_step_is_the_element_step_as_j_grows_without_bound():
    # The element's own eigenvalue problem (B4) with every cell's j times 1e6: its step is
    # the held step's to 1e-5 (the rotations' modes fall to zero frequency, the highest mode
    # is the translations' with the rotations standing still).
    block = next(p for p in _mindlin("element").parts if hasattr(p, "rotary_factor"))
    x0, v0 = block._reference_cells()
    held = block.held_rotation_stable_dt(_mindlin("element").initial_state())
    block.rotary_factor = block.rotary_factor * 1e6
    far = 2.0 / np.sqrt(block.element_omega2(x0, v0).max())
    assert held == pytest.approx(far, rel=1e-5)


def test_fibrous_and_mindlin_plies_share_the_rule():
    # k / m = PENALTY_SHARE (2 / dt_h)^2 on both shells, dt_h each one's critical step with
    # the rotations held: the fibrous shell's is its critical step (no rotary inertia sets
    # it), so its penalty is as it was; the Mindlin shell's is longer than its critical step,
    # so its springs add at most PENALTY_SHARE of the cells' omega^2 (here 0.02 of it).
    for compiled, fibrous in ((_plate(FibrousShell(PLY)), True), (_mindlin(True), False)):
        state = compiled.initial_state()
        held, step = compiled.held_rotation_stable_dt(state), compiled.stable_dt(state)
        contact = compiled.interactions[0]
        mass = compiled.mass0[contact.connectivity[:, 0]]
        np.testing.assert_allclose(contact.stiffness / mass, PENALTY_SHARE * (2.0 / held) ** 2)
        if fibrous:
            assert held == step
        else:
            assert held > 1.8 * step
        springs = compiled.penalty_frequency_squared(compiled.mass0)
        assert springs <= PENALTY_SHARE * (2.0 / step) ** 2 * (1 + 1e-12)


def test_the_plies_penalty_does_not_follow_the_rotary_inertia(monkeypatch):
    # Two Mindlin plies [0/90] on a die: their ply-on-ply springs (and the die's) the same to
    # the bit with the closed j and with the element rule's (every MindlinShell the layup
    # builds given it).
    def stiffness(mode):
        with monkeypatch.context() as patch:
            patch.setattr(mindlin, "rotary_mode", lambda value: mode)
            layup = Layup(PLY, (0.0, 90.0), 50.0, cells=2, kinematics="mindlin")
            model = layup.model()
            bottom = layup.heights[0] - 0.5 * PLY.thickness
            model.contact(RigidPlane((0, 0, bottom), (0, 0, 1.0)), "ply_1")
            compiled = model.compile()
        step = compiled.stable_dt(compiled.initial_state())
        return step, [
            np.asarray(getattr(i, "node_stiffness", i.stiffness)) for i in compiled.interactions
        ]

    closed_step, closed = stiffness("closed")
    element_step, element = stiffness("element")
    assert element_step > 1.5 * closed_step
    assert len(closed) == 2
    for a, b in zip(closed, element):
        assert np.array_equal(a, b)
