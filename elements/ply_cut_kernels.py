"""The closest point of the cut growths (elements/ply_wedge.py ``closest_on_cut``, docs/
theory.md §9.3a) compiled: one pass over the points, where numpy made some forty calls on
arrays of a few rows (about 110 us a call, once or twice an explicit step of the two-ply
hemisphere; benchmarks/forming_step_overhead.py).

The same IEEE operations in the same order as numpy's expressions (its einsums' sums of three
terms in numpy's order, ``np.linalg.norm``'s, ``np.clip``'s comparisons; no fastmath), so the
same numbers to the last bit (tests/test_ply_cut_kernels.py against the numpy reference,
``ply_projection.COMPILED = False``).
"""

from __future__ import annotations

import numpy as np

from elements.kernel_inputs import read_only, writable
from femcore.jit import jit, prange, serial

__all__ = ["closest_cut_at", "closest_on_cut"]


@serial
def closest_cut_at(p, corners, q, lines, ends, gradients, keep, out, segment):
    """``closest_on_cut`` of one point p (3,): from its triangle's corners (3, 3), closest
    point q (3,) so far, cuts' ``lines`` and ``ends`` (3, 3) and barycentric gradients (3, 3),
    q into ``out`` (3,) and the segment's ends' coordinates into ``segment`` (2, 3); (whether
    q lies on a cut, its parameter there) returned. ``keep`` ply_wedge.KEEP."""
    for a in range(3):
        out[a] = q[a]
        segment[0, a] = 0.0
        segment[1, a] = 0.0
    present = np.zeros(3, dtype=np.bool_)
    any_line = False
    for k in range(3):
        for j in range(3):
            if lines[k, j] != 0.0:
                present[k] = True
                any_line = True
    if not any_line:
        return False, 0.0
    # q's barycentric coordinates on the triangle
    r0 = q[0] - corners[0, 0]
    r1 = q[1] - corners[0, 1]
    r2 = q[2] - corners[0, 2]
    on = np.empty(3)
    for k in range(3):
        g = gradients[k]
        on[k] = (g[0] * r0 + g[2] * r2) + g[1] * r1
    on[0] += 1.0
    kept = True
    for k in range(3):
        level = (lines[k, 0] * on[0] + lines[k, 2] * on[2]) + lines[k, 1] * on[1]
        if not level >= -keep:
            kept = False
    if kept:
        return False, 0.0
    best = np.inf
    c0, c1, c2 = q[0], q[1], q[2]
    start_row, end_row, parameter = -1, -1, 0.0
    for k in range(3):
        if not present[k]:
            continue
        s0, s1, s2 = corners[k, 0], corners[k, 1], corners[k, 2]
        e = ends[k]
        edge0 = ((e[0] * corners[0, 0] + e[1] * corners[1, 0]) + e[2] * corners[2, 0]) - s0
        edge1 = ((e[0] * corners[0, 1] + e[1] * corners[1, 1]) + e[2] * corners[2, 1]) - s1
        edge2 = ((e[0] * corners[0, 2] + e[1] * corners[1, 2]) + e[2] * corners[2, 2]) - s2
        squared = (edge0 * edge0 + edge2 * edge2) + edge1 * edge1
        w0, w1, w2 = p[0] - s0, p[1] - s1, p[2] - s2
        t = ((w0 * edge0 + w2 * edge2) + w1 * edge1) / (squared if squared > 0 else 1.0)
        if t < 0.0:
            t = 0.0
        elif t > 1.0:
            t = 1.0
        x0, x1, x2 = s0 + t * edge0, s1 + t * edge1, s2 + t * edge2
        d0, d1, d2 = p[0] - x0, p[1] - x1, p[2] - x2
        distance = np.sqrt((d0 * d0 + d1 * d1) + d2 * d2)
        if distance < best:
            best = distance
            c0, c1, c2 = x0, x1, x2
            start_row, end_row, parameter = k, k, t
    out[0], out[1], out[2] = c0, c1, c2
    if start_row < 0:
        return np.isfinite(best), 0.0
    segment[0, start_row] = 1.0
    for a in range(3):
        segment[1, a] = ends[end_row, a]
    return np.isfinite(best), parameter


def _closest(p, corners, q, lines, ends, gradients, keep, out, cut, segment, along):
    """``closest_on_cut``'s arrays of each point i (c,): q into ``out`` (c, 3), whether on a
    cut into ``cut``, the segment's ends' coordinates into ``segment`` (c, 2, 3) and the
    parameter into ``along`` (c,); ``keep`` ply_wedge.KEEP."""
    for i in prange(p.shape[0]):
        cut[i], along[i] = closest_cut_at(
            p[i], corners[i], q[i], lines[i], ends[i], gradients[i], keep, out[i], segment[i]
        )


_closest_compiled = jit(_closest)


def closest_on_cut(p, corners, q, lines, ends, gradients, keep: float):
    """``ply_wedge.closest_on_cut`` with the triangles' barycentric gradients given: (q (c,
    3), cut (c,), segment (c, 2, 3), along (c,)), the same bits."""
    count = len(p)
    out, cut = np.empty((count, 3)), np.empty(count, dtype=np.bool_)
    segment, along = np.empty((count, 2, 3)), np.empty(count)
    # the types the fade's pass hands ``closest_cut_at`` (elements/ply_fade_kernels.py): the
    # points and corners read-only (as the block keeps its faces), the rest writable (rows of
    # its own arrays); one build of the helper for both (kernel_inputs.py)
    _closest_compiled(
        read_only(p),
        read_only(corners),
        writable(q),
        writable(lines),
        writable(ends),
        writable(gradients),
        float(keep),
        out,
        cut,
        segment,
        along,
    )
    return out, cut, segment, along
