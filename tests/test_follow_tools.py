"""Static's tool-following predictor (``Static(follow_tools=True)``): an increment starts with
the nodes that touch a moving tool carried by the tool's prescribed translation over the
increment, instead of the tool standing inside them by its whole step. Reference: a cable
lying on a rigid plane lifted by 10 mm in two increments, under a dead load pressing it on;
each node rests where the plane is, less its load over the penalty (closed form)."""

import numpy as np
import pytest

from elements import Cable, RigidPlane
from elements.dashpot import Dashpot
from femcore import Mesh, Model
from solvers import ConvergenceError, Static

LIFT, LOAD, PENALTY = 10.0, 0.5, 1e3  # mm, N per node, N/mm


def lifted_cable(lift: float = LIFT) -> Model:
    """Five nodes along x on the plane z = 0, held along x and y, each pressed down by LOAD;
    the plane moves ``lift`` (mm) up."""
    points = np.column_stack([np.arange(5.0), np.zeros(5), np.zeros(5)])
    model = Model(Mesh(points, lines=np.column_stack([np.arange(4), np.arange(1, 5)])))
    model.add(Cable(1e3, 1e-9))
    model.fix(np.arange(5), ["ux", "uy"])
    model.force(np.arange(5), (0.0, 0.0, -LOAD))
    model.contact(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), motion=(0.0, 0.0, lift)),
                  penalty=PENALTY)  # fmt: skip
    return model


@pytest.mark.parametrize("follow", [False, True])
def test_nodes_on_a_moving_tool_end_where_it_carries_them(follow):
    """Either way each node ends at LIFT - LOAD / PENALTY (to 1e-9 mm). Followed, the first
    iterate of each increment has the nodes where the plane carried them, off their
    equilibrium only by the increment's load (LOAD / 2 per node, which the contact spring,
    linear on a plane, takes in one Newton iteration); not followed, the plane stands 5 mm
    inside the cable (5000 N per node at the first iterate) and each increment takes two."""
    solver = Static(increments=2, follow_tools=follow, progress=False)
    result = solver.solve(lifted_cable())
    assert result.converged
    assert np.abs(result.positions[:, 2] - (LIFT - LOAD / PENALTY)).max() < 1e-9
    assert result.info["iterations_per_increment"] == ([1, 1] if follow else [2, 2])


def test_follow_tools_is_a_flag():
    with pytest.raises(ValueError):
        Static(follow_tools="yes")


def test_following_passes_over_interactions_that_carry_nothing():
    """A dashpot beside the moving plane (an interaction with its own ``follow`` setting, which
    is not the protocol's ``carried_by_tool``) carries no node: the cable still ends where the
    plane carries it, to 1e-9 mm, in one iteration per increment."""
    model = lifted_cable()
    model.interact(Dashpot([0], 1e-9))
    result = Static(increments=2, follow_tools=True, progress=False).solve(model)
    assert result.converged
    assert np.abs(result.positions[:, 2] - (LIFT - LOAD / PENALTY)).max() < 1e-9


def test_an_increment_that_was_cut_is_retried_with_the_tools_followed():
    """``follow_tools_after_cut``: the plane lifts 40 mm in two increments, 10 times the
    cable's 4 mm extent, which caps each Newton update (solvers.line_search.step_cap), and only 2
    iterations are allowed. Not followed, each retry still starts with the plane inside the
    cable by its whole (halved) step, and the run stops after one cut. With the retries
    followed, each increment's first attempt fails as before, its two halves start where the
    plane carries the nodes and converge in one iteration each: two cuts in all, and each node
    rests at lift - LOAD / PENALTY (closed form, to 1e-9 mm)."""
    lift = 40.0
    with pytest.raises(ConvergenceError):
        Static(increments=2, max_iterations=2, max_cuts=1, progress=False).solve(lifted_cable(lift))
    solver = Static(
        increments=2, max_iterations=2, max_cuts=1, follow_tools_after_cut=True, progress=False
    )
    result = solver.solve(lifted_cable(lift))
    assert result.converged
    assert result.info["cuts"] == 2
    assert result.info["iterations_per_increment"] == [2, 2]  # 1 + 1 in the halves
    assert np.abs(result.positions[:, 2] - (lift - LOAD / PENALTY)).max() < 1e-9


def test_follow_tools_after_cut_is_a_flag():
    with pytest.raises(ValueError):
        Static(follow_tools_after_cut="yes")
