"""What a dynamic relaxation that ran out of iterations suggests: more increments only where a
load or prescribed displacement ramps with them (gravity and other "step" loads go in full
from the first increment, docs/theory.md §6.4: a strip over a cylinder under its weight alone
was told to use more increments, and increment 1 carried the whole weight at any count)."""

import pytest

from solvers import ConvergenceError, DynamicRelaxation
from solvers.relaxation_cuts import more_increments
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
