"""The ply contact's fade past the outline compiled (elements/ply_fade.py ``outline_fade``;
elements/ply_projection.py, "Past the outline, faded"; docs/theory.md, the ply contact
section): w = w_e w_a of each point against its facing triangle and the outline's edge
nearest it, and its gradient dw/dz over z = (p, y_1, y_2, y_3, a, b), in one pass over the
points.

Its numpy reference is ``ply_fade.outline_fade`` (the same signature), taken with
``ply_projection.COMPILED = False``. The facing triangles' planes come from
``ply_kernels.facets_at`` (``ply_projection.facets``' bits) and the closest points of the
points beside a growth from ``ply_wedge.closest_on_grown`` (compiled where it is); the pass
does the rest with the same IEEE operations in the same order (numpy's sums of three terms,
``einsum("ci,ci->c")`` and ``einsum("cki,ci->ck")`` as (first + last) + middle, ``np.linalg
.norm`` from the first term; no fused multiply-add: numba builds without fastmath) and D^2 as
Python squares the fade's length, so it gives the same numbers to the last bit
(tests/test_ply_kernels.py). Each point is independent: the same bits on any thread count.
"""

from __future__ import annotations

import numpy as np

from elements import ply_kernels
from elements.jit import jit_lanes, prange
from elements.ply_fade import SIDEWAYS
from elements.ply_wedge import closest_on_grown

__all__ = ["outline_fade"]


def _fade(
    p,
    corners,
    n,
    grad,
    plane,
    lam,
    reach,
    beside,
    q,
    ends,
    length,
    length_squared,
    sideways,
    weight,
    gradient,
):
    """w (c,) into ``weight`` and dw/dz (c, 6, 3) into ``gradient``, as
    ``ply_fade.outline_fade`` writes them, from the points p (c, 3), their facing triangles'
    corners (c, 3, 3), unit normals n (c, 3), barycentric gradients ``grad`` (c, 3, 3), gaps
    to their planes ``plane`` (c,) and projections' coordinates ``lam`` (c, 3), the reach past
    their edges (c, 3), ``beside`` (c,) bool and there the closest points q (c, 3) of the
    growths, the ends a, b (c, 2, 3) of the outline's nearest edges, D ``length`` and D^2
    ``length_squared`` (mm, mm^2), and ``sideways`` (c,) bool, the angle's factor applies
    (not on a joined edge)."""
    for i in prange(p.shape[0]):
        p0, p1, p2 = p[i, 0], p[i, 1], p[i, 2]
        n0, n1, n2 = n[i, 0], n[i, 1], n[i, 2]
        # dg/dz over (p, y_1..3), rows of 3: the plane's (n, -lambda_m n)
        d_gap = np.empty((4, 3))
        d_gap[0, 0], d_gap[0, 1], d_gap[0, 2] = n0, n1, n2
        for k in range(3):
            m = -lam[i, k]
            d_gap[1 + k, 0], d_gap[1 + k, 1], d_gap[1 + k, 2] = m * n0, m * n1, m * n2
        gap = plane[i]
        side = 1.0
        side_gradient = np.zeros((4, 3))
        if beside[i]:  # the distance to q, the angle's factor
            r0, r1, r2 = p0 - q[i, 0], p1 - q[i, 1], p2 - q[i, 2]
            distance = np.sqrt((r0 * r0 + r1 * r1) + r2 * r2)
            sign = -1.0 if plane[i] < 0.0 else 1.0
            safe = sign * distance if distance > 0.0 else 1.0
            nu0, nu1, nu2 = r0 / safe, r1 / safe, r2 / safe
            ratio = plane[i] / safe if distance > 0.0 else 1.0
            v0 = q[i, 0] - corners[i, 0, 0]
            v1 = q[i, 1] - corners[i, 0, 1]
            v2 = q[i, 2] - corners[i, 0, 2]
            d_edge = np.empty((4, 3))
            d_edge[0, 0], d_edge[0, 1], d_edge[0, 2] = nu0, nu1, nu2
            for k in range(3):
                on_q = (grad[i, k, 0] * v0 + grad[i, k, 2] * v2) + grad[i, k, 1] * v1
                if k == 0:
                    on_q += 1.0
                m = -on_q
                d_edge[1 + k, 0], d_edge[1 + k, 1], d_edge[1 + k, 2] = m * nu0, m * nu1, m * nu2
            u = min(max(ratio / SIDEWAYS, 0.0), 1.0)
            value = u * u * (3.0 - 2.0 * u)
            rise = 6.0 * u * (1.0 - u)
            if sideways[i]:
                side = value
                if distance > 0.0:
                    scale = rise / SIDEWAYS
                    for a in range(4):
                        for c in range(3):
                            d_ratio = (d_gap[a, c] - ratio * d_edge[a, c]) / safe
                            side_gradient[a, c] = scale * d_ratio
            gap = sign * distance
            for a in range(4):
                for c in range(3):
                    d_gap[a, c] = d_edge[a, c] if distance > 0.0 else 0.0
        # past the outline: d^2 = |p - q_o|^2 - g^2, w_e = S(1 - d / D)
        past = beside[i]
        for k in range(3):
            if reach[i, k] > 0.0 and lam[i, k] < 0.0:
                past = True
        a0, a1, a2 = ends[i, 0, 0], ends[i, 0, 1], ends[i, 0, 2]
        e0, e1, e2 = ends[i, 1, 0] - a0, ends[i, 1, 1] - a1, ends[i, 1, 2] - a2
        w0, w1, w2 = p0 - a0, p1 - a1, p2 - a2
        t = ((w0 * e0 + w2 * e2) + w1 * e1) / max((e0 * e0 + e2 * e2) + e1 * e1, 1e-300)
        t = min(max(t, 0.0), 1.0)
        o0, o1, o2 = w0 - t * e0, w1 - t * e1, w2 - t * e2
        raw = ((o0 * o0 + o2 * o2) + o1 * o1) - gap * gap
        squared = raw if (raw > 0.0 or raw != raw) else 0.0
        s = np.sqrt(squared) / length
        within = past and s < 1.0 and raw > 0.0
        factor = 1.0
        if past:
            x = min(max(1.0 - s, 0.0), 1.0)
            factor = x * x * (3.0 - 2.0 * x)
        slope = -3.0 * (1.0 - s) / length_squared if within else 0.0
        weight[i] = factor * side
        twice = 2.0 * gap
        start = -2.0 * (1.0 - t)
        end = -2.0 * t
        for c in range(3):
            o = o0 if c == 0 else (o1 if c == 1 else o2)
            d_squared = 2.0 * o - twice * d_gap[0, c]
            gradient[i, 0, c] = side * (slope * d_squared) + factor * side_gradient[0, c]
            for a in range(1, 4):
                d_squared = 0.0 - twice * d_gap[a, c]
                gradient[i, a, c] = side * (slope * d_squared) + factor * side_gradient[a, c]
            gradient[i, 4, c] = side * (slope * (start * o)) + factor * 0.0
            gradient[i, 5, c] = side * (slope * (end * o)) + factor * 0.0


_fade_compiled = jit_lanes(_fade)


def outline_fade(
    p: np.ndarray,
    corners: np.ndarray,
    reach: np.ndarray,
    beside: np.ndarray,
    ends: np.ndarray,
    length: float,
    joined: np.ndarray | None = None,
    lines: np.ndarray | None = None,
    ends_cut: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """``ply_fade.outline_fade`` compiled: the same w (c,) and dw/dz (c, 6, 3), 1/mm, to the
    bit, from the same arguments (its docstring gives their shapes and units)."""
    count = len(p)
    p = np.ascontiguousarray(p, dtype=float)
    corners = np.ascontiguousarray(corners, dtype=float)
    n, _, grad, plane, lam = (
        np.ascontiguousarray(a[:, 0])
        for a in ply_kernels.facets_at(p, corners, np.arange(count)[:, None])
    )
    q = np.zeros((count, 3))
    at = np.flatnonzero(beside)
    if at.size:
        q[at] = closest_on_grown(
            p[at],
            corners[at],
            reach[at],
            None if lines is None else lines[at],
            None if ends_cut is None else ends_cut[at],
        )[0]
    sideways = np.ones(count, dtype=bool) if joined is None else ~np.asarray(joined, dtype=bool)
    weight = np.empty(count)
    gradient = np.empty((count, 6, 3))
    _fade_compiled(
        p,
        corners,
        n,
        grad,
        plane,
        lam,
        np.ascontiguousarray(reach, dtype=float),
        np.ascontiguousarray(beside, dtype=np.bool_),
        q,
        np.ascontiguousarray(ends, dtype=float),
        float(length),
        float(length**2),
        sideways,
        weight,
        gradient,
    )
    return weight, gradient
