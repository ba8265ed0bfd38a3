"""The ply contact's facing choice in one compiled call (elements/ply_projection.py
``closest_facing``, "Search"; docs/theory.md, the ply contact section): each point's
candidates' planes (``ply_kernels.candidates_at``), the nearest candidate and its closest
point (``ply_choice.choose_facing``) and the chosen candidate's arrays
(``ply_chosen.chosen``), run back to back inside one compiled function that makes the
candidates' arrays itself, instead of three calls from Python with their conversions and
allocations.

Each stage is its kernel's own plain build, its whole loop on the calling thread
(femcore/jit.py ``plain_part``: one build for the kernel and this pass), so the arrays are the
same to the last bit as the three kernels' (tests/test_ply_facing_pass.py compares them on cut
strips and the two-ply hemisphere's states). For a loop of ``SMALL_LOOP`` points or more, which
the three kernels run on several threads, ``closest_facing`` calls them as before; without the
gap's Hessian (the explicit step's facings) it takes elements/ply_facing_whole.py, which runs
these stages and the sides and the fade in two calls.

On the report's two-ply hemisphere (384 and 81 points of some five candidates), the three
calls took 67-69 us a block-step, 46-47 of them their kernels'; the one call 46-47, 37 of
them its kernel's (benchmarks/ply_chain_parts.py).
"""

from __future__ import annotations

import numpy as np

from elements import ply_choice, ply_chosen, ply_kernels
from elements.kernel_inputs import read_only
from elements.ply_choice import choice_arrays, choice_returned, cut_arrays
from elements.ply_chosen import chosen_arrays
from femcore.jit import lanes, plain_part

__all__ = ["facing_choice"]

# the stages' loops on the calling thread: their kernels' own plain builds, each loop whole
# (part 0 of 1), so the same bits, and one build of each for this pass and the kernel
_facets_here = plain_part(ply_kernels._facets_at_compiled)
_choose_here = plain_part(ply_choice._choose_compiled)
_chosen_here = plain_part(ply_chosen._chosen_compiled)


def _facing(
    p, y, near, outline, margin, tolerance, has_cuts, cut, lines, ends, toward, has_toward,
    best, on_edge, closest, on_cut, segment, along, triangle, chosen_gap, normal, lam,
    chosen_gradients, chosen_reach, overshoot, reached, turned,
):  # fmt: skip
    """The three stages on (P, 3) points ``p`` and their (P, K) candidates ``near`` of the
    triangles ``y`` (m, 3, 3) (``facing_choice``'s parameters) into its Returns' arrays,
    given (an array returned from compiled code costs its boxing, about a microsecond each:
    15 of them made the call 47 us a block-step against the three kernels' 45,
    benchmarks/ply_chain_parts.py). The candidates' arrays are made here: none is returned."""
    count, k = near.shape
    n = np.empty((count, k, 3))
    gradients = np.empty((count, k, 3, 3))
    gap = np.empty((count, k))
    weights = np.empty((count, k, 3))
    reach = np.empty((count, k, 3))
    inside = np.empty((count, k), dtype=np.bool_)
    past = np.empty((count, k))
    _facets_here(
        p, y, near, outline, margin, tolerance, n, np.empty((count, k)), gradients, gap,
        weights, reach, inside, past, np.int64(0), np.int64(1),
    )  # fmt: skip
    _choose_here(
        p, y, near, n, gradients, gap, weights, reach, inside, past, has_cuts, cut, lines,
        ends, best, on_edge, closest, on_cut, segment, along,
        np.empty((count, k), dtype=np.bool_), np.empty((count, k), dtype=np.bool_),
        np.empty((count, k)), np.empty((count, k, 3)), np.empty((count, k), dtype=np.bool_),
        np.empty((count, k, 2, 3)), np.empty((count, k)), np.empty((count, 3, 3)),
        np.empty((count, 3)), np.int64(0), np.int64(1),
    )  # fmt: skip
    _chosen_here(
        best, near, n, gap, weights, gradients, reach, toward, has_toward, triangle,
        chosen_gap, normal, lam, chosen_gradients, chosen_reach, overshoot, reached, turned,
        np.int64(0), np.int64(1),
    )  # fmt: skip


_facing_compiled = lanes(_facing)


def facing_choice(p, y, near, outline, margin, tolerance, cuts, toward):
    """Each point's facing candidate, closest point and chosen arrays in one compiled call:
    ``ply_kernels.candidates_at``, ``ply_choice.choose_facing`` and ``ply_chosen.chosen``
    in turn, the same bits (module docstring).

    Parameters
    ----------
    p : (P, 3) float
        The contact points, mm.
    y : (m, 3, 3) float
        The lower face's triangles' corners, mm.
    near : (P, K) int
        Each point's candidates (rows of ``y``).
    outline : (m, 3) bool or None
        The lower face's edges on its outline (None: none).
    margin, tolerance : float
        The reach past the outline edges (mm) and the tolerance of a held projection
        (``candidates_at``).
    cuts : WedgeCuts or None
        The growths' cuts (elements/ply_wedge.py).
    toward : (P, 3) float or None
        Each point's direction from the lower ply to its own (None: no triangle is turned).

    Returns
    -------
    choice : tuple
        ``choose_facing``'s best, on_edge, closest, on_cut, segment and along (None without
        cuts).
    picked : tuple
        ``chosen``'s triangle, gap, normal, weights, gradients, reach, overshoot, reached
        and turned.
    """
    m = len(y)
    if outline is None:
        outline = np.zeros((m, 3), dtype=bool)
    has_toward = toward is not None
    choice, picked = choice_arrays(len(p)), chosen_arrays(len(p))
    _facing_compiled(
        read_only(p),  # read-only as the block keeps them: one build (kernel_inputs.py)
        read_only(y),
        np.ascontiguousarray(near, dtype=np.int64),
        np.ascontiguousarray(outline, dtype=np.bool_),
        float(margin),
        float(tolerance),
        *cut_arrays(cuts, m),
        np.ascontiguousarray(toward if has_toward else np.zeros((1, 3)), dtype=float),
        has_toward,
        *choice,
        *picked,
    )
    return choice_returned(choice, cuts), picked
