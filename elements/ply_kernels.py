"""The ply contact's facing, compiled where it is one pass over small arrays: each point's
candidate triangles' planes (``facets_at``: unit normal, twice the area, barycentric
gradients, the point's gap and its projection's barycentric coordinates; ``candidates_at``
with the reach past the outline, whether the grown triangle holds the projection and its
distance past the farthest edge line), the grown triangles' corners (``grown_corners``), the
closest points on their edges (``edges_closest``) and the helper measuring the outline's
nearest edge pair by pair (``nearest_segment``, which the fade's pass calls,
elements/ply_fade_kernels.py), for elements/ply_projection.py's ``closest_facing`` and the
facing search's distances (elements/ply_search.py, ply_wedge.py ``closest_on_grown``;
docs/theory.md, the ply contact section).

Their numpy references are ``ply_projection.facets``, ``closest_facing``'s own expressions,
``ply_projection.grown_corners`` and ``closest_on_edges``, and ``ply_fade.every_segment``,
taken with ``ply_projection.COMPILED = False``: the kernels do the same IEEE operations in
the same order (numpy's cross product, its sums of three terms in numpy's order, no fused
multiply-add: numba builds without fastmath), so they give the same numbers to the last bit,
and so the same facing (tests/test_ply_kernels.py compares both on random triangles, the
wedge test's fan folded at a cut outline vertex, strips cut at both ends and bent two-ply
hemisphere blanks at 8 and 10 cells, both passes). Each loop is over independent points:
the same bits on any thread count. Run one at a time on small arrays (a few hundred points
of some five candidates), numpy spent most of the time in its per-call overhead
(benchmarks/ply_facing.py).
"""

from __future__ import annotations

import numpy as np

from elements.kernel_inputs import read_only
from femcore.jit import jit_lanes, lanes, prange

__all__ = [
    "candidates_at",
    "edges_closest",
    "facets_at",
    "grown_corners",
    "largest_gradient",
    "nearest_segment",
    "nearest_segments_at",
    "segment_lines",
]


def _facets_at(
    p, y, near, outline, margin, tolerance, n, area2, gradients, gap, weights, reach, inside, past
):
    """For each point p[i] (P, 3) and candidate t = near[i, k] (P, K) of the triangles with
    corners y (m, 3, 3): n[i, k] (3,), area2[i, k], gradients[i, k] (3, 3), gap[i, k] and
    weights[i, k] (3,), as ``ply_projection.facets(p, y[near])`` writes them, and as
    ``ply_projection.closest_facing`` writes them from those: reach[i, k] (3,) (``margin``
    past the edges ``outline[t]`` (m, 3) bool marks), inside[i, k] (the projection within
    ``tolerance`` of the grown triangle) and past[i, k] (the projection's largest distance
    past the grown triangle's edge lines, mm; NaN as numpy's max passes it)."""
    for i in prange(p.shape[0]):
        p0, p1, p2 = p[i, 0], p[i, 1], p[i, 2]
        for k in range(near.shape[1]):
            t = near[i, k]
            if k > 0 and t == near[i, 0]:
                # a kept list's padding (elements/ply_search.py: each row padded with its
                # first, two thirds of the slots on the [0/45] hemisphere's upper pass): the
                # first's arrays, which the same operations would give again
                for a in range(3):
                    n[i, k, a] = n[i, 0, a]
                    weights[i, k, a] = weights[i, 0, a]
                    reach[i, k, a] = reach[i, 0, a]
                    for b in range(3):
                        gradients[i, k, a, b] = gradients[i, 0, a, b]
                area2[i, k] = area2[i, 0]
                gap[i, k] = gap[i, 0]
                inside[i, k] = inside[i, 0]
                past[i, k] = past[i, 0]
                continue
            a0, a1, a2 = y[t, 0, 0], y[t, 0, 1], y[t, 0, 2]
            b0, b1, b2 = y[t, 1, 0], y[t, 1, 1], y[t, 1, 2]
            c0, c1, c2 = y[t, 2, 0], y[t, 2, 1], y[t, 2, 2]
            u0, u1, u2 = b0 - a0, b1 - a1, b2 - a2  # y2 - y1
            v0, v1, v2 = c0 - a0, c1 - a1, c2 - a2  # y3 - y1
            s0 = u1 * v2 - u2 * v1
            s1 = u2 * v0 - u0 * v2
            s2 = u0 * v1 - u1 * v0
            twice = np.sqrt(s0 * s0 + s1 * s1 + s2 * s2)
            m0, m1, m2 = s0 / twice, s1 / twice, s2 / twice
            n[i, k, 0], n[i, k, 1], n[i, k, 2] = m0, m1, m2
            area2[i, k] = twice
            # the edges opposite corners 1, 2, 3 (cyclic): y3 - y2, y1 - y3, y2 - y1
            for e in range(3):
                if e == 0:
                    e0, e1, e2 = c0 - b0, c1 - b1, c2 - b2
                elif e == 1:
                    e0, e1, e2 = a0 - c0, a1 - c1, a2 - c2
                else:
                    e0, e1, e2 = u0, u1, u2
                gradients[i, k, e, 0] = (m1 * e2 - m2 * e1) / twice
                gradients[i, k, e, 1] = (m2 * e0 - m0 * e2) / twice
                gradients[i, k, e, 2] = (m0 * e1 - m1 * e0) / twice
            r0, r1, r2 = p0 - a0, p1 - a1, p2 - a2  # from corner 1
            q0, q1, q2 = p0 - b0, p1 - b1, p2 - b2  # from corner 2
            gap[i, k] = r0 * m0 + r1 * m1 + r2 * m2
            g = gradients[i, k]
            # numpy's einsum adds a sum of three products as (first + last) + middle
            w0 = (g[0, 0] * q0 + g[0, 2] * q2) + g[0, 1] * q1
            w1 = (g[1, 0] * r0 + g[1, 2] * r2) + g[1, 1] * r1
            w2 = 1.0 - w0 - w1
            weights[i, k, 0] = w0
            weights[i, k, 1] = w1
            weights[i, k, 2] = w2
            held = True
            farthest = 0.0
            for e in range(3):
                r = margin if outline[t, e] else 0.0
                reach[i, k, e] = r
                w = w0 if e == 0 else (w1 if e == 1 else w2)
                if not w >= -r - tolerance:
                    held = False
                length = np.sqrt(g[e, 0] * g[e, 0] + g[e, 1] * g[e, 1] + g[e, 2] * g[e, 2])
                beyond = -(w + r) / length
                if e == 0 or beyond != beyond or (farthest == farthest and beyond > farthest):
                    farthest = beyond  # numpy's max: the first NaN, else the largest
            inside[i, k] = held
            past[i, k] = farthest


_facets_at_compiled = jit_lanes(_facets_at)


def _planes(p, y, near, outline, margin, tolerance):
    """``_facets_at``'s arrays, each new."""
    count, k = near.shape
    arrays = (
        np.empty((count, k, 3)),
        np.empty((count, k)),
        np.empty((count, k, 3, 3)),
        np.empty((count, k)),
        np.empty((count, k, 3)),
        np.empty((count, k, 3)),
        np.empty((count, k), dtype=np.bool_),
        np.empty((count, k)),
    )
    _facets_at_compiled(
        read_only(p),  # read-only as the block keeps them: one build (kernel_inputs.py)
        read_only(y),
        np.ascontiguousarray(near, dtype=np.int64),
        np.ascontiguousarray(outline, dtype=np.bool_),
        float(margin),
        float(tolerance),
        *arrays,
    )
    return arrays


def facets_at(p: np.ndarray, y: np.ndarray, near: np.ndarray):
    """Each point against each of its candidate triangles' planes, compiled: the same arrays
    to the bit as ``ply_projection.facets(p, y[near])`` without gathering y[near].

    Parameters
    ----------
    p : (P, 3) float
        The points, mm.
    y : (m, 3, 3) float
        The triangles' corners, mm.
    near : (P, K) int
        Each point's candidates (rows of ``y``).

    Returns
    -------
    n : (P, K, 3) float
        The candidates' unit normals.
    area2 : (P, K) float
        Twice their areas, mm^2.
    gradients : (P, K, 3, 3) float
        Their barycentric gradients, 1/mm.
    gap : (P, K) float
        The points' gaps to their planes along n, mm.
    weights : (P, K, 3) float
        The barycentric coordinates of the points' projections on the planes.
    """
    return _planes(p, y, near, np.zeros((len(y), 3), dtype=bool), 0.0, 0.0)[:5]


def candidates_at(
    p: np.ndarray,
    y: np.ndarray,
    near: np.ndarray,
    outline: np.ndarray | None,
    margin: float,
    tolerance: float,
):
    """``facets_at``'s n, gradients, gap and weights, with what ``closest_facing`` reads of
    them first, in the same pass and with the same bits: reach (P, K, 3), ``margin`` past
    the candidates' edges on the outline (``outline`` (m, 3) bool, the edge opposite corner
    k; None: none), inside (P, K) bool, the projection within ``tolerance`` of the grown
    triangle, and past (P, K), mm, the projection's largest distance past the grown
    triangle's edge lines (negative inside)."""
    if outline is None:
        outline = np.zeros((len(y), 3), dtype=bool)
    n, _, gradients, gap, weights, reach, inside, past = _planes(
        p, y, near, outline, margin, tolerance
    )
    return n, gradients, gap, weights, reach, inside, past


@lanes
def closest_on_sides(p0, p1, p2, corners, out):
    """out (3,) the closest point to p on the edges of the triangle ``corners`` (3, 3), as
    ``ply_projection.closest_on_edges`` writes it (the first nearest of the edges opposite
    corners 1, 2, 3 in that order)."""
    distance = np.inf
    out[0], out[1], out[2] = 0.0, 0.0, 0.0
    for side in range(3):
        a, b = (1, 2) if side == 0 else ((2, 0) if side == 1 else (0, 1))
        s0, s1, s2 = corners[a, 0], corners[a, 1], corners[a, 2]
        e0 = corners[b, 0] - s0
        e1 = corners[b, 1] - s1
        e2 = corners[b, 2] - s2
        # numpy's einsum adds a sum of three products as (first + last) + middle
        t = ((p0 - s0) * e0 + (p2 - s2) * e2 + (p1 - s1) * e1) / (e0 * e0 + e2 * e2 + e1 * e1)
        t = min(max(t, 0.0), 1.0)
        o0, o1, o2 = s0 + t * e0, s1 + t * e1, s2 + t * e2
        r0, r1, r2 = p0 - o0, p1 - o1, p2 - o2
        length = r0 * r0 + r2 * r2 + r1 * r1
        if length < distance:
            out[0], out[1], out[2] = o0, o1, o2
            distance = length


def _edges_closest(p, corners, best):
    """best[i] (c, 3) the closest point to p[i] (c, 3) on the edges of the triangle with
    corners ``corners[i]`` (c, 3, 3) (``closest_on_sides``)."""
    for i in prange(p.shape[0]):
        closest_on_sides(p[i, 0], p[i, 1], p[i, 2], corners[i], best[i])


_edges_closest_compiled = jit_lanes(_edges_closest)


def edges_closest(p: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """(c, 3) the closest point to p (c, 3), mm, on the edges of the triangle with corners
    (c, 3, 3), mm, compiled: the same points to the bit as
    ``ply_projection.closest_on_edges``."""
    best = np.empty((len(p), 3))
    _edges_closest_compiled(
        np.ascontiguousarray(p, dtype=float), np.ascontiguousarray(corners, dtype=float), best
    )
    return best


@lanes
def nearest_segment(p0, p1, p2, starts, e, squared):
    """The segment from starts[j] (E, 3) along e[j] (E, 3), |e_j|^2 = squared[j], nearest the
    point (p0, p1, p2), as ``ply_fade.every_segment`` chooses it: the first of the least
    distances, or the first NaN one (numpy's argmin)."""
    best = np.inf
    found = 0
    held_nan = False
    for j in range(starts.shape[0]):
        r0 = p0 - starts[j, 0]
        r1 = p1 - starts[j, 1]
        r2 = p2 - starts[j, 2]
        # numpy's einsum adds a sum of three products as (first + last) + middle
        t = (r0 * e[j, 0] + r2 * e[j, 2] + r1 * e[j, 1]) / squared[j]
        if t < 0.0:
            t = 0.0
        elif t > 1.0:
            t = 1.0
        r0 -= t * e[j, 0]
        r1 -= t * e[j, 1]
        r2 -= t * e[j, 2]
        value = r0 * r0 + r2 * r2 + r1 * r1
        if value != value:
            if not held_nan:
                held_nan, found = True, j
        elif not held_nan and value < best:
            best, found = value, j
    return found


def segment_lines(starts: np.ndarray, ends: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The segments' b - a (E, 3) and |b - a|^2 (E,), at least the least positive float,
    from their ends a ``starts`` and b ``ends`` (E, 3), mm (``nearest_segment``'s)."""
    e = np.ascontiguousarray(ends - starts)
    e0, e1, e2 = e[:, 0], e[:, 1], e[:, 2]
    return e, np.maximum(e0 * e0 + e2 * e2 + e1 * e1, np.finfo(float).tiny)


def _gradient_norms(y, out):
    """out[t] the largest |grad phi_e| (1/mm) of triangle t of corners y (m, 3, 3), as
    ``np.linalg.norm(ply_projection.triangle_frames(y)[2], axis=-1).max(axis=1)`` gives it
    (``_facets_at``'s frames; numpy's max: the first NaN, else the largest)."""
    for t in prange(y.shape[0]):
        a0, a1, a2 = y[t, 0, 0], y[t, 0, 1], y[t, 0, 2]
        b0, b1, b2 = y[t, 1, 0], y[t, 1, 1], y[t, 1, 2]
        c0, c1, c2 = y[t, 2, 0], y[t, 2, 1], y[t, 2, 2]
        u0, u1, u2 = b0 - a0, b1 - a1, b2 - a2  # y2 - y1
        v0, v1, v2 = c0 - a0, c1 - a1, c2 - a2  # y3 - y1
        s0 = u1 * v2 - u2 * v1
        s1 = u2 * v0 - u0 * v2
        s2 = u0 * v1 - u1 * v0
        twice = np.sqrt(s0 * s0 + s1 * s1 + s2 * s2)
        m0, m1, m2 = s0 / twice, s1 / twice, s2 / twice
        largest = 0.0
        for e in range(3):  # the edges opposite corners 1, 2, 3 (cyclic)
            if e == 0:
                e0, e1, e2 = c0 - b0, c1 - b1, c2 - b2
            elif e == 1:
                e0, e1, e2 = a0 - c0, a1 - c1, a2 - c2
            else:
                e0, e1, e2 = u0, u1, u2
            g0 = (m1 * e2 - m2 * e1) / twice
            g1 = (m2 * e0 - m0 * e2) / twice
            g2 = (m0 * e1 - m1 * e0) / twice
            length = np.sqrt(g0 * g0 + g1 * g1 + g2 * g2)
            if e == 0 or length != length or (largest == largest and length > largest):
                largest = length
        out[t] = largest


_gradient_norms_compiled = jit_lanes(_gradient_norms)


def largest_gradient(y: np.ndarray) -> float:
    """The largest |grad phi| (1/mm) over the triangles of corners y (m, 3, 3), one over the
    least height, in one compiled pass: ``float(np.max(np.linalg.norm(
    ply_projection.triangle_frames(y)[2], axis=-1)))`` to the bit (NaN where that is)."""
    out = np.empty(len(y))
    # the corners read-only, as the block keeps the faces': one build (kernel_inputs.py)
    _gradient_norms_compiled(read_only(y), out)
    return float(np.max(out))


def _nearest_each(p, starts, e, squared, out):
    """out[i] the segment nearest each point p[i] (c, 3) (``nearest_segment``)."""
    for i in prange(p.shape[0]):
        out[i] = nearest_segment(p[i, 0], p[i, 1], p[i, 2], starts, e, squared)


_nearest_each_compiled = jit_lanes(_nearest_each)


def nearest_segments_at(p: np.ndarray, starts: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """(c,) int: the segment (from ``starts`` (E, 3) to ``ends`` (E, 3), mm) nearest each
    point p (c, 3) in one compiled pass, ``nearest_segment`` point by point: the answer of
    ``ply_fade.every_segment`` and ``ply_fade.nearest_segments`` (ties to the lowest index,
    the first NaN distance where some are NaN), without numpy's (c, E) arrays."""
    out = np.zeros(len(p), dtype=np.int64)
    if len(p) == 0 or len(starts) == 0:
        return out
    e, squared = segment_lines(starts, ends)
    _nearest_each_compiled(
        np.ascontiguousarray(p, dtype=float), np.ascontiguousarray(starts, dtype=float), e,
        squared, out,
    )  # fmt: skip
    return out


def _grown(corners, reach, out):
    """out[t] (m, 3, 3) the corners of triangle t of ``corners`` (m, 3, 3) grown by
    ``reach[t]`` (m, 3), as ``ply_projection.grown_corners`` writes them."""
    for t in prange(corners.shape[0]):
        r0, r1, r2 = reach[t, 0], reach[t, 1], reach[t, 2]
        whole = 1.0 + (r0 + r1 + r2)
        for i in range(3):
            g0 = (whole if i == 0 else 0.0) - r0
            g1 = (whole if i == 1 else 0.0) - r1
            g2 = (whole if i == 2 else 0.0) - r2
            for c in range(3):
                out[t, i, c] = g0 * corners[t, 0, c] + g1 * corners[t, 1, c] + g2 * corners[t, 2, c]


_grown_compiled = jit_lanes(_grown)


def grown_corners(corners: np.ndarray, reach: np.ndarray) -> np.ndarray:
    """Corners (m, 3, 3), mm, of the triangles with corners ``corners`` (m, 3, 3) grown by
    ``reach`` (m, 3) barycentric units past the edges opposite each corner, compiled: the
    same bits as ``ply_projection.grown_corners``."""
    out = np.empty((len(corners), 3, 3))
    # the corners read-only, as the block keeps the faces': one build (kernel_inputs.py)
    _grown_compiled(read_only(corners), np.ascontiguousarray(reach, dtype=float), out)
    return out
