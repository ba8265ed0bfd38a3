"""The chosen facing candidate's arrays, compiled (elements/ply_projection.py
``closest_facing``, "Search"; docs/theory.md, the ply contact section): once each point's
candidate is chosen (elements/ply_choice.py), its triangle, plane's gap, normal,
projection's barycentric coordinates and their gradients, reach past its edges, the
projection's overshoot past the triangle, whether the triangle reaches past the outline at
all and whether its normal points against the point's ply, in one pass over the points
instead of a dozen numpy gathers and reductions on arrays of a few hundred rows (each a few
microseconds of call). At the points near the outline, the numpy path gathers the fade's
inputs from those (``fade_inputs_numpy``: the points, their facing triangles' corners and
cuts, the nearest outline edges' ends); the compiled fade's pass reads those rows in place
(elements/ply_fade_kernels.py ``outline_fade_at``).

Its numpy reference is ``chosen_numpy``, taken with ``ply_projection.COMPILED = False``. The
pass copies the chosen values and does the same IEEE operations in the same order (numpy's
``min`` taking the first NaN and the last of equal values, ``np.maximum(0.0, x)`` keeping a
NaN and -0.0, ``einsum("pi,pi->p")`` as (first + last) + middle; no fused multiply-add: numba
builds without fastmath), so it gives the same bits (tests/test_ply_kernels.py). Each point
is independent: the same bits on any thread count.
"""

from __future__ import annotations

import numpy as np

from femcore.jit import jit_lanes, prange

__all__ = ["chosen", "chosen_arrays", "chosen_numpy", "fade_inputs_numpy"]


def _chosen(
    best,
    near,
    n,
    gap,
    weights,
    gradients,
    reach,
    toward,
    has_toward,
    triangle,
    chosen_gap,
    normal,
    lam,
    chosen_gradients,
    chosen_reach,
    overshoot,
    reached,
    turned,
):
    """The chosen candidate ``best[i]``'s arrays into the outputs (``chosen``'s Returns)."""
    for i in prange(best.shape[0]):
        k = best[i]
        triangle[i] = near[i, k]
        chosen_gap[i] = gap[i, k]
        low = weights[i, k, 0]
        grown = False
        for c in range(3):
            normal[i, c] = n[i, k, c]
            w = weights[i, k, c]
            lam[i, c] = w
            # numpy's min: the first NaN, else the least (the later of equal ones: -0.0 or
            # 0.0, whichever comes last)
            if c > 0 and low == low and (w != w or not low < w):
                low = w
            chosen_reach[i, c] = reach[i, k, c]
            if reach[i, k, c] > 0.0:
                grown = True
            for d in range(3):
                chosen_gradients[i, c, d] = gradients[i, k, c, d]
        over = -low
        overshoot[i] = 0.0 if 0.0 > over else over  # np.maximum(0.0, over): -0.0 kept
        reached[i] = grown
        if has_toward:
            dot = (n[i, k, 0] * toward[i, 0] + n[i, k, 2] * toward[i, 2]) + n[i, k, 1] * toward[
                i, 1
            ]
            turned[i] = dot < 0.0
        else:
            turned[i] = False


_chosen_compiled = jit_lanes(_chosen)


def chosen(
    best: np.ndarray,
    near: np.ndarray,
    n: np.ndarray,
    gap: np.ndarray,
    weights: np.ndarray,
    gradients: np.ndarray,
    reach: np.ndarray,
    toward: np.ndarray | None,
) -> tuple[np.ndarray, ...]:
    """Each point's chosen candidate's arrays, compiled (module docstring).

    Parameters
    ----------
    best : (P,) int
        The chosen candidate's column in ``near`` (elements/ply_choice.py).
    near : (P, K) int
        Each point's candidate triangles.
    n, gap, weights, gradients, reach : (P, K, 3), (P, K), (P, K, 3), (P, K, 3, 3), (P, K, 3)
        The candidates' unit normals, plane gaps (mm), projections' barycentric coordinates,
        their gradients (1/mm) and reach past each edge (``ply_kernels.candidates_at``).
    toward : (P, 3) float or None
        Each point's direction from the lower ply to its own (None: no triangle is turned).

    Returns
    -------
    triangle : (P,) int
        The chosen triangle.
    gap, normal, weights, gradients, reach : (P,), (P, 3), (P, 3), (P, 3, 3), (P, 3)
        The chosen candidate's rows of the inputs (fresh arrays).
    overshoot : (P,) float
        max(0, -min_k lambda_k): how far the projection lies past the triangle.
    reached : (P,) bool
        The triangle reaches past some edge (on the outline).
    turned : (P,) bool
        Its normal points against ``toward`` (all False without it).
    """
    out = chosen_arrays(len(best))
    has_toward = toward is not None
    _chosen_compiled(
        np.ascontiguousarray(best, dtype=np.int64),
        np.ascontiguousarray(near, dtype=np.int64),
        np.ascontiguousarray(n, dtype=float),
        np.ascontiguousarray(gap, dtype=float),
        np.ascontiguousarray(weights, dtype=float),
        np.ascontiguousarray(gradients, dtype=float),
        np.ascontiguousarray(reach, dtype=float),
        np.ascontiguousarray(toward if has_toward else np.zeros((1, 3)), dtype=float),
        has_toward,
        *out,
    )
    return out


def chosen_arrays(count: int) -> tuple[np.ndarray, ...]:
    """``_chosen``'s outputs for ``count`` points: triangle, gap, normal, weights,
    gradients, reach, overshoot, reached, turned."""
    return (
        np.empty(count, dtype=np.int64),
        np.empty(count),
        np.empty((count, 3)),
        np.empty((count, 3)),
        np.empty((count, 3, 3)),
        np.empty((count, 3)),
        np.empty(count),
        np.empty(count, dtype=np.bool_),
        np.empty(count, dtype=np.bool_),
    )


def chosen_numpy(
    best: np.ndarray,
    near: np.ndarray,
    n: np.ndarray,
    gap: np.ndarray,
    weights: np.ndarray,
    gradients: np.ndarray,
    reach: np.ndarray,
    toward: np.ndarray | None,
) -> tuple[np.ndarray, ...]:
    """``chosen``'s numpy reference: the same arrays."""
    rows = np.arange(len(best))
    lam = weights[rows, best]
    normal = n[rows, best]
    chosen_reach = reach[rows, best]
    turned = (
        np.zeros(len(best), dtype=bool)
        if toward is None
        else np.einsum("pi,pi->p", normal, toward) < 0.0
    )
    return (
        near[rows, best],
        gap[rows, best],
        normal,
        lam,
        gradients[rows, best],
        chosen_reach,
        np.maximum(0.0, -lam.min(axis=-1)),
        (chosen_reach > 0.0).any(axis=-1),
        turned,
    )


def fade_inputs_numpy(at, p, y, triangle, reach, beside, joined, starts, ends, segment, cuts):
    """The fade's inputs (elements/ply_fade.py ``outline_fade``'s p, corners, reach, beside,
    ends, joined, lines and ends_cut) at the points ``at`` (c,) int near the outline, for
    ``closest_facing``'s numpy path (the compiled fade's pass reads those rows in place,
    elements/ply_fade_kernels.py ``outline_fade_at``).

    Parameters
    ----------
    at : (c,) int
        The points near the outline (rows of the points' arrays).
    p : (P, 3) float
        The points, mm.
    y : (m, 3, 3) float
        The lower face's triangles' corners, mm.
    triangle, reach, beside, joined : (P,) int, (P, 3) float, (P,) bool, (P,) bool
        Each point's facing triangle, its reach past its edges, whether the point is beside a
        growth's edge (``on_growth``) and on a joined edge.
    starts, ends : (E, 3) float
        The outline's edges' ends, mm.
    segment : (c,) int
        The outline's edge nearest each point ``at``.
    cuts : WedgeCuts or None
        The growths' cuts (elements/ply_wedge.py); None: lines and ends_cut None.

    Returns
    -------
    p (c, 3), corners (c, 3, 3), reach (c, 3), beside (c,), ends (c, 2, 3), joined (c,),
    lines (c, 3, 3) or None, ends_cut (c, 3, 3) or None
    """
    facing = triangle[at]
    return (
        p[at],
        y[facing],
        reach[at],
        beside[at],
        np.stack([starts[segment], ends[segment]], axis=1),
        joined[at],
        None if cuts is None else cuts.lines[facing],
        None if cuts is None else cuts.ends[facing],
    )
