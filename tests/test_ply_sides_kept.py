"""The sides accepted at a commit and the held facing kept for them (elements/ply_sides.py
``accepted_sides``) against the reference they stand for: ``sides_at`` and ``held`` made
afresh at the same state.

A commit (``update_history``) holds the facing with the last sides, then accepts the new
sides from the same ``behind`` flags, and keeps the held facing for the new sides: the next
explicit step's loads come at the same state with the new history. The model: the Z-fold of
tests/test_ply_fold_sides.py, the point walked through the pocket between the fold's sheets
(kept off, ``BEHIND``, where the raw facing touches B from behind), on through B's face to
just in front of it, and pressed back in (touching again), each state committed.
"""

import numpy as np
import pytest

from elements.ply_sides import BEHIND, TOUCHING, held, sides_at, sides_of
from femcore.state import State
from tests.test_ply_fold_sides import STEP, _fold


@pytest.mark.parametrize("friction", [0.0, 0.3], ids=["frictionless", "friction"])
def test_the_sides_accepted_and_the_facing_kept_for_them_are_those_made_afresh(friction):
    """At every state: the accepted sides, faces and corners equal ``sides_at``'s to the bit;
    the held facing the next loads find with the new history touches where ``held`` made
    afresh from the new sides does; the loads and energy with the new history equal those of
    a block whose kept facings were dropped. The walk has points kept off while the raw
    facing touches (where the kept facing differs from the raw one) and points touching."""
    block, nodes, directors, first = _fold(friction)
    history = block.initial_history()
    zero = np.zeros_like(nodes)
    start = nodes[first:, 2].mean() - 0.1
    heights = np.concatenate([1.2 + 5 * STEP * np.arange(183), [2.09, 2.05]])
    kept_off_touching = touching = 0
    for z in heights:
        x = nodes.copy()
        x[first:, 2] += z - start
        state = State(x, directors, zero, zero)
        block.internal_force(state, history)
        last = sides_of(history)
        raw = block.facing(state)
        expected = sides_at(block, state, held(block, state, raw, last), last)
        history = block.update_history(state, history)
        accepted = sides_of(history)
        for name in ("sides", "faces", "corners"):
            assert np.array_equal(getattr(accepted, name), getattr(expected, name)), name
        fresh = held(block, state, raw, accepted)
        kept = block._held(state, history)
        assert np.array_equal(kept.touching, fresh.touching)
        force, moment = block.internal_force(state, history)
        energy = block.strain_energy(state, history)
        block._held_at = block._facing_at = block._faces_at = None
        block._next_sliding = None
        again = block.internal_force(state, history)
        assert np.array_equal(force, again[0]) and np.array_equal(moment, again[1])
        assert energy == block.strain_energy(state, history)
        kept_off_touching += int(accepted.sides[0] == BEHIND and raw.touching[0])
        touching += int(accepted.sides[0] == TOUCHING)
    # the premises: the walk holds both kinds of state
    assert kept_off_touching > 20 and touching >= 1
