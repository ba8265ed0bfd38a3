"""What a stopped Static solve suggests after its reason (solvers/stop_diagnosis.py
``stop_hint``): on a model with contacts, more increments or dynamic relaxation (a contact
closing, opening or sliding inside an increment stops Newton, and the arc length follows a
limit point, not a contact's events); on a model without, the arc length for a load path and
smaller increments for an arc-length one. A first increment's stop adds that a body held by
friction alone has no equilibrium past mu times its press (``FRICTION_AT_START``) only where
a body is so held: the loads push it along a translation no support holds."""

from types import SimpleNamespace

import numpy as np
import pytest

from elements import MindlinShell, RigidPlane
from elements.layup import Layup
from femcore import Mesh, Model
from femcore.interaction import InteractionBlock
from materials import ElasticShell, Fabric
from solvers import Static
from solvers.common import ConvergenceError
from solvers.stop_diagnosis import (
    FRICTION_AT_START,
    FRICTION_LATER,
    STEP_LOADS_RAMPED,
    held_by_friction_alone,
    steps_ramped_with_others,
    stop_hint,
)


class _Tie(InteractionBlock):
    """An interaction without a meshed tool (its ``facet_record`` the protocol's None)."""

    dofs = ("ux", "uy", "uz")
    connectivity = np.zeros((0, 2), dtype=np.int64)

    def internal_force(self, state, history=None):
        return np.zeros_like(state.positions), None

    def strain_energy(self, state, history=None):
        return 0.0


def test_a_model_with_contacts_is_sent_to_more_increments_not_to_the_arc_length():
    hint = stop_hint(SimpleNamespace(interactions=[_Tie()]), None, "load")
    assert "interactions (contacts" in hint and "more increments" in hint
    assert "try path='arc_length'" not in hint


def test_a_model_without_contacts_keeps_the_limit_points_hint():
    assert "try path='arc_length'" in stop_hint(SimpleNamespace(interactions=[]), None, "load")
    hint = stop_hint(SimpleNamespace(interactions=[]), None, "arc_length")
    assert "smaller increments" in hint


def _plate_on_a_rough_floor(clamped: bool) -> Model:
    """A 100 x 20 mm plate laid on the plane z = 0 (mu 0.3), pressed by its weight and
    pulled along x at its right end; its left end clamped or not."""
    thickness = 1.0
    flat = Mesh.rectangle(100.0, 20.0, nx=4, ny=1)
    model = Model(flat.with_points(flat.points + [0.0, 0.0, 0.5 * thickness]))
    model.add(MindlinShell(ElasticShell(E=70e3, nu=0.3, thickness=thickness, density=2.7e-9)))
    model.contact(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)), friction=0.3)
    model.gravity((0.0, 0.0, -9810.0))
    model.force(lambda x, y, z: x >= 100.0 - 1e-9, (0.01, 0.0, 0.0))
    if clamped:
        model.fix(lambda x, y, z: x <= 1e-9)
    return model


def test_a_clamped_body_under_a_rough_tool_is_not_said_to_be_held_by_friction_alone():
    # The review's case: any frictional interaction added the hint to any first-increment
    # stop, a clamped blank under a rough punch included, where the clamp holds the pull.
    model = _plate_on_a_rough_floor(clamped=True).compile()
    assert not held_by_friction_alone(model)
    hint = stop_hint(model, None, "load", at_start=True)
    assert "interactions (contacts" in hint and FRICTION_AT_START not in hint


def test_a_body_pulled_along_a_rough_tool_with_nothing_else_holding_it_gets_the_hint():
    model = _plate_on_a_rough_floor(clamped=False).compile()
    assert held_by_friction_alone(model)
    assert stop_hint(model, None, "load", at_start=True).endswith(FRICTION_AT_START)
    # not after a converged increment, nor where the loads are stepped in first already
    assert FRICTION_AT_START not in stop_hint(model, None, "load", at_start=False)
    assert FRICTION_AT_START not in stop_hint(
        model, None, "load", at_start=True, step_loads_first=True
    )


def test_a_ply_pulled_on_a_held_ply_is_held_by_friction_alone_unless_it_is_held_itself():
    ply = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)
    for held in (False, True):
        layup = Layup(ply, (0.0, 90.0), 20.0, cells=2, friction=0.3, kinematics="mindlin")
        model = layup.model()
        bottom, top = layup.ply_nodes
        model.fix(bottom)
        model.force([int(n) for n in top], (0.01, 0.0, -0.1))
        if held:
            model.fix([int(top[0])], ["ux", "uy", "uz"])
        assert held_by_friction_alone(model.compile()) is not held


def test_a_body_held_by_friction_alone_is_not_sent_to_a_quasi_static_solver():
    # A strip pulled past 2 mu F slides: no static state exists for DynamicRelaxation to find
    # either (the hint sent the user there); only an explicit run follows the slide.
    model = _plate_on_a_rough_floor(clamped=False).compile()
    hint = stop_hint(model, None, "load", at_start=True)
    assert "DynamicRelaxation (" not in hint and "or DynamicRelaxation" not in hint
    assert "only an explicit run (CentralDifference)" in hint


def _ply_pressed_and_pulled(press_amplitude) -> Model:
    """The review's ply: a Mindlin ply 20 x 10 mm (4 x 2 cells) laid on a floor of mu 0.3,
    pressed by dead forces totalling 1 N at ``press_amplitude``, its right edge pulled along
    x by 0.4 N ramped linearly, past mu times the press (0.3 N)."""
    thickness = 0.5
    mesh = Mesh.rectangle(20.0, 10.0, nx=4, ny=2, origin=(0.0, 0.0, 0.5 * thickness))
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(E=1e4, nu=0.3, thickness=thickness, density=1e-9)))
    model.contact(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)), friction=0.3)
    count = len(mesh.points)
    model.force(np.arange(count), (0.0, 0.0, -1.0 / count), amplitude=press_amplitude)
    right = np.flatnonzero(mesh.points[:, 0] > 20.0 - 1e-9)
    model.force(right, (0.4 / len(right), 0.0, 0.0), amplitude="linear")
    return model


def test_a_step_press_ramped_with_its_pull_is_said_to_keep_their_ratio():
    # The review's case: a press at amplitude "step" and a pull ramped linearly past mu times
    # it stopped Static at load factor 0 with the advice to press "at amplitude 'step'",
    # which the press was: Static ramps "step" loads too without step_loads_first, so the
    # pull passes mu times the press at every load factor.
    model = _ply_pressed_and_pulled("step").compile()
    assert steps_ramped_with_others(model)
    hint = stop_hint(model, None, "load", at_start=True)
    assert hint.endswith(FRICTION_AT_START + STEP_LOADS_RAMPED)
    assert "amplitude=lambda load_factor: 1.0" in hint
    # all loads at "step" (the plate under its weight, pulled at "step"): nothing to say
    plate = _plate_on_a_rough_floor(clamped=False).compile()
    assert not steps_ramped_with_others(plate)
    assert STEP_LOADS_RAMPED not in stop_hint(plate, None, "load", at_start=True)


def test_a_stop_after_converged_increments_of_a_body_held_by_friction_alone_says_it_slides():
    model = _ply_pressed_and_pulled("step").compile()
    hint = stop_hint(model, None, "load", at_start=False)
    assert hint.endswith(FRICTION_LATER) and FRICTION_AT_START not in hint
    assert "or DynamicRelaxation (" not in hint
    held = _plate_on_a_rough_floor(clamped=True).compile()
    assert FRICTION_LATER not in stop_hint(held, None, "load", at_start=False)


def test_the_press_held_whole_the_ply_slides_where_its_pull_reaches_mu_times_the_press():
    # Coulomb: the ply sticks while the pull 0.4 lambda N stays within mu N = 0.3 N, up to
    # lambda = 0.75, and has no static equilibrium past it (the load factor 1 increment and
    # its cuts fail; with max_cuts=1 the last converged is 0.75, where the pull is mu N).
    # The press at a callable amplitude of 1 is whole from the first increment; at "step"
    # it ramps with the pull and the stop comes at load factor 0 (both ratios 0.4 / 1 > mu).
    held_whole = _ply_pressed_and_pulled(lambda load_factor: 1.0)
    with pytest.raises(ConvergenceError) as stop:
        Static(increments=4, max_cuts=1, progress=False).solve(held_whole)
    frames = [frame.load_factor for frame in stop.value.result.frames]
    assert frames == pytest.approx([0.0, 0.25, 0.5, 0.75])
    assert str(stop.value).endswith(FRICTION_LATER + ".")
    ramped = _ply_pressed_and_pulled("step")
    with pytest.raises(ConvergenceError) as stop:
        Static(increments=4, max_cuts=1, progress=False).solve(ramped)
    assert [frame.load_factor for frame in stop.value.result.frames] == [0.0]
    assert str(stop.value).endswith(FRICTION_AT_START + STEP_LOADS_RAMPED + ".")
