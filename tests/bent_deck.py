"""plies-deck-of-cards' deck of plies bent by end moments, small, for the tests of Static on
ply stacks (tests/test_static_curved_contact.py, tests/test_static_reproducible.py)."""

import numpy as np

from elements.plies import PlyStack
from femcore import Mesh
from validation.cases import plies_deck_of_cards as deck


def bent_deck(count: int, cells: int, friction: float = 0.0):
    """plies-deck-of-cards' deck of ``count`` plies on ``cells`` x 1 cells: each ply clamped
    at x = 0 and bent by the end moment that puts it alone on its arc concentric with the
    mid-surface's (validation/cases/plies_deck_of_cards.py, ``bend``), Coulomb ``friction``
    between the plies."""
    mid = Mesh.rectangle(deck.LENGTH, deck.WIDTH, nx=cells, ny=1)
    stack = PlyStack(mid, deck.DECK, count, friction=friction)
    model = stack.model()
    model.fix(stack.nodes("left"))
    radius = deck.LENGTH / deck.BEND
    ends = mid.nodes("right")
    for k, z in enumerate(stack.offsets):
        moment = float(stack.ply_fabric.bending.value(np.array(1.0 / (radius - z)))) * deck.WIDTH
        model.moment(stack.ply_nodes[k, ends], (0.0, -moment / len(ends), 0.0), amplitude="linear")
    return model
