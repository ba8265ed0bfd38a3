"""The same Static solve gives the same answer to the bit, whatever was solved before it in the
process: nothing a solve keeps (the ply facing's kept lists, the friction's kept return
mapping, the linear solver's plans and factors, the automatic penalty) may carry over into
the next solve of the same model or of another one.

Measured on these decks and the case's 4-ply deck and heavy stack (one thread): the ply
search's kept lists renewed at every call, the facing's kept state cleared before every call,
or every parallel loop forced onto 2 threads, give the same bits; the linear solver's kept
measurement of QDLDL's cost (solvers/linear.py, ``_choose_band``) taken anew at every new
pattern moves the 4-ply deck's positions by 1.5e-12 mm: that choice follows the patterns met
earlier in the same solve, and a solve's linear solver is its own, so it does not carry over."""

import numpy as np
from bent_deck import bent_deck

from solvers import Static
from validation.cases import plies_deck_of_cards as deck


def _bent(model):
    """The case's solver: 4 curved increments (its decks' Static)."""
    return Static(
        increments=4,
        seek_stable=False,
        max_iterations=deck.DECK_ITERATIONS,
        curved_with_contact=True,
        progress=False,
    ).solve(model)


def _frictional(model):
    """Straight steps in 2 increments: the plies' friction keeps its return mapping."""
    return Static(increments=2, seek_stable=False, max_iterations=150, progress=False).solve(model)


def _assert_same(first, again):
    assert again.info["iterations_per_increment"] == first.info["iterations_per_increment"]
    assert again.info["iterations_cut"] == first.info["iterations_cut"]
    assert again.info["cuts"] == first.info["cuts"]
    assert np.array_equal(again.positions, first.positions)
    assert np.array_equal(again.directors, first.directors)


def test_a_deck_solved_again_after_another_model_gives_the_same_bits():
    # A: the frictionless 2-ply deck on 10 cells (Newton iterations at ratio ~1 and a cut in
    # its last increment: a path that any carried-over state would move); B: a frictional
    # 2-ply deck on 6 cells, another pattern and number of unknowns. Each solved again after
    # the other, on a model built anew and on the same compiled model: the same iterations
    # and the same positions and directors to the bit.
    first = _bent(bent_deck(2, 10))
    assert first.converged
    frictional = _frictional(bent_deck(2, 6, friction=0.2))
    assert frictional.converged
    _assert_same(first, _bent(bent_deck(2, 10)))
    _assert_same(frictional, _frictional(bent_deck(2, 6, friction=0.2)))
    compiled = bent_deck(2, 10).compile()
    _assert_same(first, _bent(compiled))
    _frictional(bent_deck(2, 6, friction=0.2))
    _assert_same(first, _bent(compiled))  # the same compiled model, solved twice
