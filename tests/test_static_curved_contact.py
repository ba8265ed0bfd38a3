"""Static's curved steps with the plies' contact (``Static(curved_with_contact=True)``,
solvers/newton.py; docs/theory.md §6.5, "Curved steps of a sliding stack")."""

import numpy as np
import pytest
from bent_deck import bent_deck

from solvers import Static
from validation.cases import plies_deck_of_cards as deck


@pytest.mark.parametrize("bad", [1, "yes", None])
def test_a_switch_that_is_not_true_or_false_is_refused(bad):
    with pytest.raises(ValueError, match="curved_with_contact"):
        Static(curved_with_contact=bad)


def test_curved_with_contact_without_curved_steps_is_refused():
    with pytest.raises(ValueError, match="curved=True"):
        Static(curved=False, curved_with_contact=True)


def _solve(curved: bool, correction: str = "fitted"):
    solver = Static(
        increments=4,
        seek_stable=False,
        max_iterations=deck.DECK_ITERATIONS,
        curved_with_contact=curved,
        correction=correction,
        progress=False,
    )
    return solver.solve(bent_deck(2, 10))


def test_curved_steps_bend_the_deck_in_fewer_iterations_to_the_same_equilibrium():
    # The deck of 2 plies on 10 cells bent onto the quarter circle in 4 increments. Straight
    # steps stretch each turning ply by theta^2 / 2 and press the plies into each other (the
    # offsets between them do not turn): 19-21-22-27 Newton iterations; curved, 9-8-6-42
    # (measured, the two solves of this test). The last increment
    # lands where the plies need no contact force (the ramp's double root, the module
    # docstring of validation/cases/plies_deck_of_cards.py) and is not compared. Bound: the
    # three increments before it in at most 2/3 of the straight iterations (measured 23 of
    # 62); the equilibria within 1e-6 mm (Static's tolerance 1e-8 of the forces on a 100 mm
    # strip, as tests/test_static_update_turn.py).
    straight, curved = _solve(False), _solve(True)
    assert straight.info["curved_steps"] == 0
    assert curved.info["curved_steps"] > 0
    before = {
        "straight": sum(straight.info["iterations_per_increment"][:-1]),
        "curved": sum(curved.info["iterations_per_increment"][:-1]),
    }
    assert 3 * before["curved"] <= 2 * before["straight"], before
    assert np.abs(curved.positions - straight.positions).max() <= 1e-6
    assert np.abs(curved.directors - straight.directors).max() <= 1e-8


def test_curved_steps_with_contact_take_the_whole_correction():
    """The fitted share of the curved correction (``Static(correction="fitted")``, the
    default) is not taken with interactions: on the plies of plies-deck-of-cards it cost
    iterations (924 against 882, solvers/newton_curvature.py; on this deck 9-8-8-78 against
    9-8-8-42). The default solve of the bent deck is the correction="whole" solve to the
    bit."""
    fitted, whole = _solve(True), _solve(True, correction="whole")
    assert fitted.info["curved_steps"] > 0
    assert fitted.info["iterations_per_increment"] == whole.info["iterations_per_increment"]
    assert np.array_equal(fitted.positions, whole.positions)
    assert np.array_equal(fitted.directors, whole.directors)


def test_frictional_plies_keep_straight_steps_with_the_flag():
    """With friction between the plies the forces are not the gaps' alone (stick anchors, a
    return mapping): the flag lets no curved step through, and the solve is the flag-off
    solve to the bit (curved, a frictional 2-ply deck on 6 cells took 302 iterations cut
    against 47, and moved the equilibrium by 6.3e-6 mm)."""

    def solve(curved):
        solver = Static(
            increments=2,
            seek_stable=False,
            max_iterations=150,
            curved_with_contact=curved,
            progress=False,
        )
        return solver.solve(bent_deck(2, 6, friction=0.2))

    plain, flagged = solve(False), solve(True)
    assert flagged.info["curved_steps"] == 0
    assert flagged.info["iterations_per_increment"] == plain.info["iterations_per_increment"]
    assert np.array_equal(flagged.positions, plain.positions)
