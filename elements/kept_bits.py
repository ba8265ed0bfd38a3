"""Whether an array holds the bits of one kept: the test of the ply contact's per-state caches
(elements/ply_block.py: the faces, the facing and the offset directions, kept for the last
state a step asks about, some thirty times a step).

The same shape, dtype and bytes: a cache hit then gives what the computation would, bit for
bit (it is a function of those bytes). ``np.array_equal`` took 3.2 us on the (170, 3)
positions of the two-ply hemisphere, two arrays' ``tobytes`` and their comparison 0.5 us.
Above SMALL entries the two ``tobytes`` copies cost more than the comparison (37-264 us
against 11-13 us at (20000, 3), 1.8 ms against 0.19 at (100000, 3)): the arrays' numbers are
then compared as unsigned integers of their width, in place, the same bits without a copy.
It differs from value equality only where that would answer from a state that is not the
one kept: -0.0 against +0.0 (equal values, other bits: computed again here), NaN (never
equal by value; the faces refuse a state that is not finite before they keep it) and equal
values held in another dtype (float32 against float64: computed again).
"""

from __future__ import annotations

import numpy as np

__all__ = ["SMALL", "same_bits"]

#: Entries below which two arrays' bytes are copied and compared (faster there than numpy's
#: comparison's set-up; the hemisphere's ply blocks hold 163-4803 rows of 3).
SMALL = 6000
# The unsigned integer of each width, to compare numbers by their bits in place.
_WORDS = {1: np.uint8, 2: np.uint16, 4: np.uint32, 8: np.uint64}


def same_bits(kept: np.ndarray, now: np.ndarray) -> bool:
    """Whether ``now`` has ``kept``'s shape and dtype and its bytes (any arrays)."""
    if kept.shape != now.shape or kept.dtype != now.dtype:
        return False
    word = _WORDS.get(kept.dtype.itemsize)
    if kept.size < SMALL or word is None or kept.dtype.hasobject:
        return kept.tobytes() == now.tobytes()
    return bool(np.array_equal(kept.view(word), now.view(word)))
