"""The entries of the level projection's J (solvers.newton_levels ``gradient``) summed from a
block's gradient pieces (elements/fibrous/level_jacobian.py) by one compiled pass.

Why: on Peirce's cantilever the numpy sums (the turns dotted with the frame vectors, the pull
on the normal sums by a batched 3 x 3 by 3 x 9 product per pair of corners, a concatenation,
a mask of the held unknowns and a bincount) took about 0.25 ms a sweep of 40 cells, about as
much as the pieces' own numpy; here each value is made and added at its place in the order
the numpy sums took (direct, turns about V2, turns about V1, pulls): the same places, each
J entry summed in the same order, run to run.
"""

from __future__ import annotations

import numpy as np

from femcore import kernel_cache

__all__ = ["gather"]


def gather(
    direct: np.ndarray,
    turns: np.ndarray,
    axes: np.ndarray,
    through_sums: np.ndarray,
    shares: np.ndarray,
    pairs: np.ndarray,
    place: np.ndarray,
    start: int,
    data: np.ndarray,
) -> int:
    """Add one block's values to J's entries ``data`` (nnz,).

    Parameters
    ----------
    direct, turns : (m, p, 3, 3) float, ds/dx_k and V_k x ds/dV_k at each corner k.
    axes : (2, m, 3, 3) float, the frame vectors V2 and V1 at each cell's corners; (0, ...)
        without rotations (no turns' columns).
    through_sums : (m, p, 3, 3) float, ds/dS_k; shares (m, 3, 3, 3, 3) float,
        d(alpha_k n)/dx_j; pairs (4, q) int, (cell, corner, other cell, its corner): (0, ...)
        with element normals.
    place : (values,) int, each value's entry in ``data``, -1 for a held unknown.
    start : this block's first value in ``place``.

    Returns the next block's ``start``.
    """
    m, p = direct.shape[0], direct.shape[1]
    i = start
    for c in range(m):
        for j in range(p):
            for k in range(3):
                for d in range(3):
                    if place[i] >= 0:
                        data[place[i]] += direct[c, j, k, d]
                    i += 1
    for a in range(axes.shape[0]):
        for c in range(m):
            for j in range(p):
                for k in range(3):
                    if place[i] >= 0:
                        data[place[i]] += (
                            turns[c, j, k, 0] * axes[a, c, k, 0]
                            + turns[c, j, k, 1] * axes[a, c, k, 1]
                            + turns[c, j, k, 2] * axes[a, c, k, 2]
                        )
                    i += 1
    for e in range(pairs.shape[1]):
        cell, corner, other, other_corner = pairs[0, e], pairs[1, e], pairs[2, e], pairs[3, e]
        for j in range(p):
            for node in range(3):
                for d in range(3):
                    if place[i] >= 0:
                        total = 0.0
                        for k in range(3):
                            total += (
                                through_sums[cell, j, corner, k]
                                * shares[other, other_corner, k, node, d]
                            )
                        data[place[i]] += total
                    i += 1
    return i


if kernel_cache.AVAILABLE:
    gather = kernel_cache.njit(gather)
