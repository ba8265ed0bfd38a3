"""The ply contact's per-point masks of a state's sides and landing points, each one compiled
pass over the points (docs/theory.md §9.3a, "The side kept" and "A point's landing step").

An explicit step of a two-ply run asks for them some six times a block: the points a history's
sides keep off their faces (elements/ply_sides.py ``behind``: at the committed history's facing
of the new state, once a block) and the points landing at a state (elements/ply_landing.py
``landing_rows``: the committed history's and the next step's loads', twice a block). numpy made
each of them from three to five calls on the few hundred points (a comparison, a conjunction, a
``flatnonzero``), 7-9 us a mask on 384 points (one thread); one compiled pass takes a fraction
of it (benchmarks/forming_step_overhead.py). The masks are comparisons of the same numbers, so
the same flags and rows (tests/test_ply_side_masks.py); ``COMPILED`` False takes numpy's.
"""

from __future__ import annotations

import numpy as np

from femcore.jit import serial

__all__ = ["COMPILED", "entered_off", "landing_rows"]

#: The masks by the passes below; False: by numpy's calls (elements/ply_sides.py,
#: elements/ply_landing.py), the same flags.
COMPILED = True


def _landing_rows(touching, triangle, sides, touching_side):
    """(r,) int64 the rows of the points touching now (``touching`` (P,) bool), without an
    anchor (``triangle`` (P,) int < 0) and whose side (``sides`` (P,) int) is not
    ``touching_side``, ascending: numpy's ``flatnonzero`` of the three flags' conjunction."""
    count = 0
    for i in range(touching.shape[0]):
        if touching[i] and triangle[i] < 0 and sides[i] != touching_side:
            count += 1
    rows = np.empty(count, dtype=np.int64)
    at = 0
    for i in range(touching.shape[0]):
        if touching[i] and triangle[i] < 0 and sides[i] != touching_side:
            rows[at] = i
            at += 1
    return rows


def _entered_off(gap, sides, depth, clear, behind, entered, off):
    """Writes ``entered`` (P,) bool, the points clear (``sides`` == ``clear``) deeper than
    ``depth`` (gap < -depth, mm), and ``off`` (P,) bool, those with a negative gap kept off
    (side ``behind``) or entered; returns how many entered (numpy's comparisons: a NaN gap is
    neither)."""
    count = 0
    for i in range(gap.shape[0]):
        g = gap[i]
        came = sides[i] == clear and g < -depth
        entered[i] = came
        off[i] = g < 0.0 and (sides[i] == behind or came)
        if came:
            count += 1
    return count


_landing_rows_compiled = serial(_landing_rows)
_entered_off_compiled = serial(_entered_off)


def landing_rows(touching: np.ndarray, triangle: np.ndarray, sides: np.ndarray, side: int):
    """``_landing_rows`` (compiled): (r,) int64 rows, ascending."""
    return _landing_rows_compiled(touching, triangle, sides, side)


def entered_off(
    gap: np.ndarray, sides: np.ndarray, depth: float, clear: int, behind: int
) -> tuple[np.ndarray, np.ndarray, int]:
    """(entered (P,) bool, off (P,) bool, the count entered): ``_entered_off`` (compiled),
    ``off`` from the entered flags as they are (a caller that narrows them makes it again)."""
    entered = np.empty(len(gap), dtype=np.bool_)
    off = np.empty(len(gap), dtype=np.bool_)
    count = _entered_off_compiled(gap, sides, float(depth), clear, behind, entered, off)
    return entered, off, int(count)
