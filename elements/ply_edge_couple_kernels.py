"""The stick couple of stuck points facing an edge or a vertex compiled (elements/
ply_edge_couple.py ``edge_features`` then ``edge_couple``, which are its numpy reference): one
serial pass over the points, the same IEEE operations in the same order (numpy's sums over
three terms as ((a + b) + c), its norms as the square root of such a sum, no fused
multiply-add: numba builds without fastmath), so the same couple to the last bit
(tests/test_ply_edge_couple.py). numpy spent its time in the per-call overhead of some fifty
calls on a few rows (benchmarks/ply_edge_couple.py)."""

from __future__ import annotations

import numpy as np

from elements.kernel_inputs import read_only, writable
from femcore.jit import lanes

__all__ = ["edge_couples"]


@lanes
def _couples(
    at, lam, reach, triangle, gap, normal, face, offset, force, y, lines, far, cut, keep, end,
    out,
):  # fmt: skip
    """C_w (e, 4, 3) into ``out`` for the points ``at`` (e,) (``edge_couple``'s arguments per
    point row, the lower face's corners y (m, 3, 3), its cuts' lines and far ends (m, 3, 3)
    and which triangles have one, ``cut`` (m,); keep, end: ``KEEP`` and ``END``)."""
    m = np.empty(4)
    e = np.empty(3)
    unit = np.empty(3)
    a = np.empty(4)
    for i in range(at.shape[0]):
        r = at[i]
        t = triangle[r]
        bound0 = lam[r, 0] <= -reach[r, 0] + 1e-9
        bound1 = lam[r, 1] <= -reach[r, 1] + 1e-9
        bound2 = lam[r, 2] <= -reach[r, 2] + 1e-9
        slide = (int(bound0) + int(bound1) + int(bound2)) == 1
        # the two corners off the bound, in order (numpy's stable argsort of the bounds)
        first, second = 0, 1
        if bound0:
            first, second = 1, 2
        elif bound1:
            first, second = 0, 2
        total = (reach[r, 0] + reach[r, 1]) + reach[r, 2]
        m[0] = 0.0
        for j in range(3):
            high = (1.0 + total if j == second else 0.0) - reach[r, j]
            low = (1.0 + total if j == first else 0.0) - reach[r, j]
            m[1 + j] = high - low
        if cut[t]:  # q on a cut's segment from e_k to E_k
            for k in range(3):
                present = lines[t, k, 0] != 0.0 or lines[t, k, 1] != 0.0 or lines[t, k, 2] != 0.0
                level = (lines[t, k, 0] * lam[r, 0] + lines[t, k, 1] * lam[r, 1]) + lines[
                    t, k, 2
                ] * lam[r, 2]
                d0 = far[t, k, 0] - (1.0 if k == 0 else 0.0)
                d1 = far[t, k, 1] - (1.0 if k == 1 else 0.0)
                d2 = far[t, k, 2] - (1.0 if k == 2 else 0.0)
                squared = (d0 * d0 + d1 * d1) + d2 * d2
                h0 = lam[r, 0] - (1.0 if k == 0 else 0.0)
                h1 = lam[r, 1] - (1.0 if k == 1 else 0.0)
                h2 = lam[r, 2] - (1.0 if k == 2 else 0.0)
                along = ((h0 * d0 + h1 * d1) + h2 * d2) / (squared if squared > 0.0 else 1.0)
                if present and abs(level) <= keep and along >= -end and along <= 1.0 + end:
                    m[1], m[2], m[3] = d0, d1, d2
                    slide = along > end and along < 1.0 - end
        if not slide:
            m[1] = m[2] = m[3] = 0.0
        for c in range(3):
            e[c] = (m[1] * y[t, 0, c] + m[2] * y[t, 1, c]) + m[3] * y[t, 2, c]
        length = np.sqrt((e[0] * e[0] + e[1] * e[1]) + e[2] * e[2])
        if not (slide and length > 0.0):
            length = 1.0
        for c in range(3):
            unit[c] = e[c] / length if slide else 0.0
        p0, p1, p2 = face[r, 0], face[r, 1], face[r, 2]
        live = abs(gap[r]) > 1e-12 * (1.0 + np.sqrt((p0 * p0 + p1 * p1) + p2 * p2))
        if not live:
            for w in range(4):
                for c in range(3):
                    out[i, w, c] = 0.0
            continue
        a[0] = 1.0
        a[1], a[2], a[3] = -lam[r, 0], -lam[r, 1], -lam[r, 2]
        n0, n1, n2 = normal[r, 0], normal[r, 1], normal[r, 2]
        along = (n0 * offset[r, 0] + n1 * offset[r, 1]) + n2 * offset[r, 2]
        f0, f1, f2 = force[r, 0], force[r, 1], force[r, 2]
        sigma = (f0 * unit[0] + f1 * unit[1]) + f2 * unit[2]
        slope = sigma / length
        safe = gap[r]
        for c in range(3):
            across = force[r, c] - sigma * unit[c]
            share = across / safe
            lifted = slope * normal[r, c]
            for w in range(4):
                out[i, w, c] = -along * (a[w] * share - m[w] * lifted)


def edge_couples(facing, y, cuts, rows, offset, force) -> np.ndarray:
    """``edge_couple(edge_features(facing, y, cuts, rows), ...)`` (elements/ply_edge_couple.py)
    compiled: (t, 4, 3) N for the points ``rows`` (t,) of ``facing``, offset r and force F
    (P, 3) of every point (``Sliding.offset``, ``Sliding.force``); the same bits."""
    from elements.ply_edge_couple import END
    from elements.ply_wedge import KEEP

    count = len(rows)
    reach = np.zeros((len(facing.gap), 3)) if facing.reach is None else facing.reach
    if cuts is None:
        lines = far = np.zeros((len(y), 3, 3))
        cut = np.zeros(len(y), dtype=np.bool_)
    else:
        lines, far, cut = cuts.lines, cuts.ends, cuts.cut
    out = np.empty((count, 4, 3))
    # each input of the type the block's own call hands it (the facing and faces read-only,
    # as the block keeps them; the mapping's offsets and forces and the cuts writable): one
    # build whoever calls, no copy or view on the block's path (kernel_inputs.py)
    _couples(
        writable(rows, np.int64),
        read_only(facing.weights),
        read_only(reach),
        read_only(facing.triangle, np.int64),
        read_only(facing.gap),
        read_only(facing.normal),
        read_only(facing.face),
        writable(offset),
        writable(force),
        read_only(y),
        writable(lines),
        writable(far),
        writable(cut, np.bool_),
        float(KEEP),
        float(END),
        out,
    )
    return out
