"""A model that its supports do not hold against its loads: the quasi-static solvers say so before
iterating, naming the rigid motion (CompiledModel.unheld_rigid_motions). A net force along a
free translation has no equilibrium at any shape; loaded free rotations make a mechanism at
the starting shape, which Static cannot start from but DynamicRelaxation swings down from.

Reference: statics. A free body is in equilibrium only if its loads do no work along any of
its six rigid motions; supports remove the motions whose restriction to the held DOFs is not
zero. A dead load's resultant does not turn with the body; its moment about a pin does."""

import numpy as np
import pytest

from elements import Cable, FibrousShell, MindlinShell, RigidPlane
from femcore import Mesh, Model
from femcore.diagnostics import unbalanced_turns
from materials import ElasticShell, presets
from solvers import DynamicRelaxation, Static


def strip(supports=None) -> Model:
    model = Model(Mesh.rectangle(100.0, 20.0, nx=4, ny=1))
    model.add(FibrousShell(presets.g986_stack()))
    if supports is not None:
        model.fix("left", dofs=supports)
    return model


@pytest.mark.parametrize("solver", [Static(), DynamicRelaxation()], ids=["static", "relaxation"])
def test_an_unsupported_strip_under_gravity_is_refused_with_its_free_motion(solver):
    model = strip()
    model.gravity((0.0, 0.0, -9810.0))
    with pytest.raises(ValueError, match="translation along z"):
        solver.solve(model)


@pytest.mark.parametrize("solver", [Static(), DynamicRelaxation()], ids=["static", "relaxation"])
def test_a_free_body_under_a_net_force_has_no_equilibrium_at_any_shape(solver):
    model = strip()
    model.gravity((0.0, 0.0, -9810.0))
    with pytest.raises(ValueError, match="net force.*no equilibrium exists at any shape"):
        solver.solve(model)


def test_a_load_that_a_user_amplitude_takes_off_again_is_checked_on_the_way():
    # 4 lambda (1 - lambda) is exactly 0 at lambda = 1, where the check looked alone: the
    # strip falls on the way there.
    model = strip()
    model.gravity((0.0, 0.0, -9810.0), amplitude=lambda lam: 4.0 * lam * (1.0 - lam))
    with pytest.raises(ValueError, match="translation along z.*no equilibrium exists"):
        Static(progress=False).solve(model)


def hinged_strip() -> Model:
    """A Mindlin strip held at x = 0 in translations only: a hinge about its left edge (y)."""
    model = Model(Mesh.rectangle(100.0, 20.0, nx=4, ny=1))
    model.add(MindlinShell(ElasticShell(1e4, 0.3, 1.0, 1e-9)))
    model.fix("left", ["ux", "uy", "uz"])
    return model


@pytest.mark.parametrize(
    "solver",
    [Static(progress=False), DynamicRelaxation(progress=False)],
    ids=["static", "relaxation"],
)
def test_a_dead_moment_about_a_free_hinge_with_no_force_across_it_has_no_equilibrium(solver):
    # A dead moment's part about the hinge is the same at every turn, and the hinge's
    # reactions act on its axis: nothing balances it (DynamicRelaxation ran 20000 iterations
    # into a stall before it was refused; Static pointed to DynamicRelaxation).
    model = hinged_strip()
    model.moment("right", (0.0, 1.0, 0.0))
    with pytest.raises(ValueError, match=r"\(rotation about y\), and no force can turn it back"):
        solver.solve(model)


def test_a_moment_about_a_hinge_that_a_force_across_it_may_balance_is_let_through_to_relaxation():
    # With the strip's weight across the hinge a finite turn may balance the moment (a
    # pendulum): not refused as having no equilibrium (Static still cannot start there).
    model = hinged_strip()
    model.moment("right", (0.0, 1e-3, 0.0))
    model.gravity((0.0, 0.0, -9810.0))
    from solvers.common import check_held

    check_held(model.compile(), swings=True)
    with pytest.raises(ValueError, match="mechanism there, and Static cannot start"):
        check_held(model.compile(), swings=False)


def test_a_force_driven_tool_pressing_across_the_hinge_may_balance_the_moment():
    # A holder free along z, pushed down by 1 N onto the flap, balances a lifting moment a
    # finite turn away: its force counts (before the mend it was dropped as another body's and
    # DynamicRelaxation refused a model it solved before).
    model = hinged_strip()
    model.moment("right", (0.0, -1.0, 0.0))
    holder = RigidPlane((0.0, 0.0, 0.5), (0.0, 0.0, -1.0), free="z", force=(0, 0, -1.0),
                        mass=1e-6, amplitude="step")  # fmt: skip
    model.contact(holder, penalty=100.0)
    assert unbalanced_turns(model.compile()) == []


def test_a_strip_hanging_from_its_edge_is_a_mechanism_static_cannot_start_from():
    # Held at x = 0 in translations only, it turns about that edge under its weight: no
    # equilibrium at the flat start, but one a quarter turn down (hanging).
    model = Model(Mesh.rectangle(100.0, 20.0, nx=4, ny=1))
    model.add(MindlinShell(ElasticShell(1e4, 0.3, 1.0, 1e-9)))
    model.fix("left", ["ux", "uy", "uz"])
    model.gravity((0.0, 0.0, -9810.0))
    with pytest.raises(ValueError, match="mechanism there, and Static cannot start") as refused:
        Static(progress=False).solve(model)
    assert "no equilibrium exists" not in str(refused.value)
    assert "DynamicRelaxation" in str(refused.value)


def test_dynamic_relaxation_lets_a_cable_pinned_at_one_end_hang_straight_down():
    # A horizontal cable pinned at x = 0 swings down under its weight W = m g L. Closed form of
    # the hanging cable: straight down, the pin's reaction W, its stretch W L / (2 EA) (the
    # tension falls linearly from W at the pin). EA / W = 1e3. Tolerances: the relaxation's
    # residual 1e-4 of W leaves the end within 1e-3 L of the vertical and the reaction within
    # 1e-3 of W; the stretch within 2 % (strain 1e-3, the cable's own geometric non-linearity).
    length, mass_per_length, stiffness, g = 100.0, 1e-9, 1.0, 9810.0
    model = Model(Mesh.line((0.0, 0.0, 0.0), (length, 0.0, 0.0), 4))
    model.add(Cable(stiffness, mass_per_length))
    model.fix([0])
    model.gravity((0.0, 0.0, -g))
    result = DynamicRelaxation(progress=False).solve(model)
    weight = mass_per_length * length * g
    end = result.frames[-1].positions[-1]
    assert abs(end[0]) <= 1e-3 * length and end[1] == 0.0
    stretch = -end[2] - length
    assert stretch == pytest.approx(weight * length / (2.0 * stiffness), rel=0.02)
    assert result.frames[-1].reactions[0] == pytest.approx([0.0, 0.0, weight], abs=1e-3 * weight)
    assert np.all(np.diff(result.frames[-1].positions[:, 2]) < 0.0)  # hangs in order


def test_the_held_motions_are_not_reported():
    clamped = strip(supports=None)
    clamped.fix("left")
    clamped.gravity((0.0, 0.0, -9810.0))
    assert clamped.compile().unheld_rigid_motions() == []
    # In-plane pins hold x and y but not z: gravity still pushes the strip down.
    pinned = strip(supports=("ux", "uy"))
    pinned.gravity((0.0, 0.0, -9810.0))
    assert pinned.compile().unheld_rigid_motions() == ["translation along z"]


def test_self_balanced_loads_need_no_support_but_a_couple_does():
    balanced = strip()
    balanced.force("left", (-1.0, 0.0, 0.0))
    balanced.force("right", (1.0, 0.0, 0.0))
    assert balanced.compile().unheld_rigid_motions() == []
    couple = strip()
    couple.force("left", (0.0, 0.0, -1.0))
    couple.force("right", (0.0, 0.0, 1.0))
    assert couple.compile().unheld_rigid_motions() == ["rotation about y"]


def test_every_free_rigid_motion_is_listed_loaded_or_not():
    # Without supports and without loads, all six motions are free; pins holding x and y at
    # the left edge leave z (and the rotations that move it) free.
    free = strip().compile().unheld_rigid_motions(loaded_only=False)
    assert free == [
        "translation along x",
        "translation along y",
        "translation along z",
        "rotation about x",
        "rotation about y",
        "rotation about z",
    ]
    pinned = strip(supports=("ux", "uy")).compile().unheld_rigid_motions(loaded_only=False)
    assert "translation along z" in pinned
    clamped = strip(supports=None)
    clamped.fix("left")
    assert clamped.compile().unheld_rigid_motions(loaded_only=False) == []


def test_a_motion_that_moves_no_free_dof_is_not_a_free_one():
    """A cable pinned at both ends on a frictionless plane: turning about its own line moves
    none of its (translational) DOFs, so nothing is free; unpinned at one end, the slide
    along the cable and the turn about the pinned end remain."""
    from elements import Cable, RigidPlane

    def cable(pins) -> Model:
        model = Model(Mesh.line((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), 4))
        model.add(Cable(1.0e3, 1.0e-9))
        model.fix(pins)
        model.contact(RigidPlane((0.0, 0.0, -1.0), (0.0, 0.0, 1.0)))
        return model

    assert cable([0, 4]).compile().unheld_rigid_motions(loaded_only=False) == []
    free = cable([0]).compile().unheld_rigid_motions(loaded_only=False)
    assert free == ["rotation about the axis along (0, 0, 1) through (0, 0, 0)"]


def test_a_stack_of_plies_on_a_frictionless_table_names_its_sliding_motions():
    """The contact between plies moves with the stack: it holds no rigid motion of the whole,
    so a stack that only lies on a frictionless table is free to slide and turn on it."""
    from elements import RigidPlane
    from elements.plies import PlyStack

    stack = PlyStack(Mesh.rectangle(10.0, 5.0, nx=2, ny=1), presets.g986_ply(), 2)
    model = stack.model()
    model.contact(RigidPlane((0.0, 0.0, -1.0), (0.0, 0.0, 1.0)), nodes=stack.ply_nodes[0])
    model.gravity((0.0, 0.0, -9810.0))
    with pytest.raises(ValueError, match="translation along x, translation along y and rotation"):
        DynamicRelaxation(progress=False).solve(model)
