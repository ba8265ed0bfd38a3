"""Newton on plies-deck-of-cards' bent deck with the decks' penalty
(validation/cases/plies_deck_of_cards.py ``DECK_PENALTY``; docs/theory.md §6.5, "The deck's
last increment"): the deck needs almost no contact force, and the automatic penalty, set for
the explicit step by the plies' membrane, makes the plies' gap mode 3e7 times softer than
the contact, so that Newton's last increment halves the gaps towards the ramp's double root
for tens of iterations."""

import numpy as np
from bent_deck import bent_deck

from elements.ply_contact import SMOOTHING
from solvers import Static
from validation.cases import plies_deck_of_cards as deck


def _bend(penalty):
    solver = Static(
        increments=deck.DECK_INCREMENTS,
        seek_stable=False,
        max_iterations=deck.DECK_ITERATIONS,
        curved_with_contact=deck.DECK_CURVED,
        progress=False,
    )
    return solver.solve(bent_deck(2, 10, penalty=penalty))


def test_the_decks_penalty_bends_the_deck_in_few_iterations_to_the_stiff_penaltys_equilibrium():
    # The deck of 2 plies on 10 cells in the case's 4 curved increments. Measured: the
    # automatic penalty 9-8-8-43 Newton iterations and 68 more in an attempt cut; 3 N/mm a
    # node 9-8-8-13, none cut. Bound: no cut, at most 20 in any increment. The equilibria:
    # measured within 5.1e-6 mm; bound a quarter of the ramp delta (1e-3 of the plies' two
    # half thicknesses, 5e-4 mm), the contact law's own resolution: the deck carries almost
    # no contact force, so a softer penalty only deepens its few touching points within the
    # ramp (-7e-6 mm at the deepest on 4 plies against -5e-7).
    soft, stiff = _bend(deck.DECK_PENALTY), _bend(None)
    assert soft.info["iterations_cut"] == 0
    assert max(soft.info["iterations_per_increment"]) <= 20, soft.info["iterations_per_increment"]
    delta = SMOOTHING * deck.THICKNESS / 2
    assert np.abs(soft.positions - stiff.positions).max() <= 0.25 * delta
