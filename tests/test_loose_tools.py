"""A force-driven tool whose force points away from the body (solvers/tool_force_watch.py,
solvers/driven_tool_checks.py): it never touches the body, and the run says so instead of
blaming the loading's pace or a ringing.

Reference, closed forms: a holder of mass m pushed away from a held plate by F, from where it
touches the plate's face, touches nothing and travels F t^2 / (2 m) (central differences
integrate a constant acceleration exactly: to rounding); the plate held still, the run's
kinetic energy is all the holder's. In statics no position balances it (the contact pushes a
tool only away from the body)."""

import warnings

import numpy as np
import pytest

from solvers import CentralDifference, DynamicRelaxation, Static
from tests.test_force_driven_tools import held_plate_and_holder, mindlin, pressed_plate

FORCE, MASS, DURATION = 1.0, 1e-3, 0.01  # N, t, s: 0.05 mm of travel


def test_a_holder_pushed_off_the_plate_is_said_to_never_touch_it_with_its_travel():
    """One warning naming the tool, its 0 N, its travel (F T^2 / 2m = 0.05 mm, to 1e-12
    in the report) and the force's way; no ringing advice; the KE / W warning says the
    kinetic energy is the tool's own (all of it: the plate is held)."""
    model = held_plate_and_holder(gap=0.0, force=-FORCE, mass=MASS, penalty=100.0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run = CentralDifference(duration=DURATION, dt=1e-4).solve(model)
    said = [str(w.message) for w in caught]
    (driven,) = run.info["quasi_static"]["driven_tools"]
    travel = FORCE * DURATION**2 / (2.0 * MASS)
    assert driven["travel"] == [pytest.approx(travel, abs=1e-12)]
    assert driven["force_min"] == driven["force_max"] == [0.0]
    loose = [s for s in said if "never touched the body" in s]
    assert len(loose) == 1
    assert "tool1 pressed it with 0 N along z against 1 N prescribed" in loose[0]
    assert f"travelled {travel:.4g} mm" in loose[0] and "towards the body" in loose[0]
    assert not any("ringing" in s for s in said)
    kinetic = [s for s in said if "not quasi-static" in s]
    assert len(kinetic) == 1
    assert "1 of the kinetic energy at the end is the force-driven tools' own" in kinetic[0]
    assert "slow the loading" not in kinetic[0]


def test_a_holder_pressed_onto_the_plate_is_not_said_to_be_loose():
    """The same holder pushed towards the plate lands and presses it: no loose warning."""
    model = held_plate_and_holder(gap=0.0, force=FORCE, mass=MASS, penalty=100.0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run = CentralDifference(duration=DURATION, dt=1e-4).solve(model)
    assert not any("never touched" in str(w.message) for w in caught)
    assert run.info["quasi_static"]["driven_tools"][0]["force_min"][0] < 0.0  # pressing down


@pytest.mark.parametrize("solver", [Static(increments=2), DynamicRelaxation(increments=2)],
                         ids=["static", "relaxation"])  # fmt: skip
def test_a_quasi_static_solver_refuses_a_holder_force_away_from_the_plate_up_front(solver):
    """F = 50 N up on the holder over the plate: a ValueError naming the tool, its force and
    the way to the body, before any increment."""
    model = pressed_plate(mindlin(), 1.0, -50.0)
    with pytest.raises(ValueError, match=r"tool2's force \(0, 0, 50\) N points away from the "
                       r"body \(the body lies along \(0, 0, -1\) from it\)"):  # fmt: skip
        solver.solve(model)


def test_static_takes_a_holder_force_towards_the_plate_across_a_gap():
    """Pressed towards the plate from 0.1 mm above it: not refused, and the die carries F."""
    model = pressed_plate(mindlin(), 1.0, 50.0, gap=0.1)
    run = Static(increments=2).solve(model)
    assert run.converged
    assert np.isclose(run.tool_forces[-1, 0, 2], -50.0, rtol=1e-6)
