"""What a dynamic relaxation that ran out of iterations suggests: more increments only where a
load or prescribed displacement ramps with them (gravity and other "step" loads go in full
from the first increment, docs/theory.md §6.4: a strip over a cylinder under its weight alone
was told to use more increments, and increment 1 carried the whole weight at any count), and
where a tool's motion does (solvers/relaxation_cuts.py ``more_increments``)."""

import warnings

import pytest

from elements.tools import RigidPlane
from solvers import ConvergenceError, DivergenceError, DynamicRelaxation
from solvers.relaxation_cuts import CUTS, more_increments
from tests.test_relaxation_acceptance import strip_held_for_a_pull
from validation import specimens


def test_a_model_under_its_weight_alone_is_not_told_to_use_more_increments():
    model = specimens.hanging_chain(40, 5000.0)
    assert more_increments(model.compile()) == ""
    solver = DynamicRelaxation(increments=4, tol=1e-8, max_iterations=50, progress=False)
    with pytest.raises(ConvergenceError, match="Raise max_iterations, or try") as error:
        solver.solve(model)
    assert "increments" not in str(error.value).split("Raise")[1]


def test_a_prescribed_displacement_ramps_with_the_increments():
    model = specimens.hanging_chain(40, 5000.0)
    model.displace([20], uz=-1.0)  # a free node of the chain
    assert more_increments(model.compile()) == "use more increments, "


def pulled_by_a_plane(stretch):
    """A 40 x 10 mm fibrous strip (4 x 1 cells, linear tension 10 N/mm) whose right end a
    rigid plane behind it pushes out along x to ``stretch`` times its length: nothing but
    the tool's motion loads it."""
    _, model = strip_held_for_a_pull()
    plane = RigidPlane(
        point=(39.84, 0.0, 0.0), normal=(1.0, 0.0, 0.0), motion=((stretch - 1) * 40.0, 0.0, 0.0)
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the plane starts 0.01 mm into the strip's face
        model.contact(plane, nodes="right")
        return model.compile()


def test_a_moving_tool_ramps_with_the_increments():
    # Before: "" (the motion of a tool is neither a load nor a prescribed displacement).
    assert more_increments(pulled_by_a_plane(1.5)) == "use more increments, "


@pytest.mark.slow
def test_a_relaxation_driven_by_a_tool_halves_an_increment_that_fails():
    # Pulled to lambda = 3, past the linear law's peak at lambda = e: the fourth increment
    # (2.5 -> 3) fails acceptance and is halved CUTS times before the stop. Before: the
    # first failure stopped the run as one where "nothing in the model ramps".
    solver = DynamicRelaxation(increments=4, progress=False)
    with pytest.raises(DivergenceError, match=f"parts of 1/{2**CUTS} of the increment") as stop:
        solver.solve(pulled_by_a_plane(3.0))
    assert "'step' loads" not in str(stop.value) and "more increments" in str(stop.value)
    assert stop.value.result.info["cuts"] == CUTS
