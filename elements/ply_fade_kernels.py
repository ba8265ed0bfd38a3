"""The ply contact's fade past the outline compiled (elements/ply_fade.py ``outline_fade``;
elements/ply_projection.py, "Past the outline, faded"; docs/theory.md, the ply contact
section): w = w_e w_a of each point against its facing triangle and the outline's edge
nearest it, and its gradient dw/dz over z = (p, y_1, y_2, y_3, a, b), in one pass over the
points near the outline (``outline_fade_at``: the nearest edge, the closest point of the
grown and cut triangle beside a growth, then ``fade_at``).

Its numpy reference is ``ply_fade.outline_fade`` on ``ply_chosen.fade_inputs_numpy``'s
arrays with ``ply_fade.every_segment``'s edges, taken with ``ply_projection.COMPILED =
False``. The facing triangles' planes are ``ply_kernels.candidates_at``'s
(``ply_projection.facets``' bits) and the closest points of the points beside a growth are
found as ``ply_wedge.closest_on_grown`` finds them; the pass does the rest with the same IEEE
operations in the same order (numpy's sums of three terms, ``einsum("ci,ci->c")`` and
``einsum("cki,ci->ck")`` as (first + last) + middle, ``np.linalg.norm`` from the first term;
no fused multiply-add: numba builds without fastmath) and D^2 as Python squares the fade's
length, so it gives the same numbers to the last bit (tests/test_ply_kernels.py). Each point
is independent: the same bits on any thread count.
"""

from __future__ import annotations

import numpy as np

from elements.kernel_inputs import read_only, writable
from elements.ply_cut_kernels import closest_cut_at
from elements.ply_fade import SIDEWAYS
from elements.ply_kernels import closest_on_sides, nearest_segment, segment_lines
from elements.ply_projection import INSIDE
from elements.ply_wedge import KEEP, WedgeCuts
from femcore.jit import jit_lanes, lanes, prange

__all__ = ["fade_at", "outline_fade_at"]


@lanes
def fade_at(
    i, j, corner, s, p, y, n, grad, plane, lam, reach, beside, q, starts, ends, length,
    length_squared, sideways, fade_gradient, d_gap, d_edge, side_gradient,
):  # fmt: skip
    """w of point i (j its row among the points near the outline), returned, and dw/dz
    (6, 3) into ``fade_gradient[i]``, as ``ply_fade.outline_fade`` writes them, from the
    point p[i] (3,), its facing triangle's corners y[corner] (3, 3), unit normal n[i] (3,),
    barycentric gradients ``grad[i]`` (3, 3), gap to its plane ``plane[i]`` and projection's
    coordinates ``lam[i]`` (3,), the reach past its edges ``reach[i]`` (3,), ``beside[i]`` and
    there the closest point q[j] (3,) of the growth, the ends a ``starts[s]`` and b
    ``ends[s]`` (3,) of the outline's nearest edge s, D ``length`` and D^2
    ``length_squared`` (mm, mm^2), and ``sideways``, the angle's factor applies (not on a
    joined edge); d_gap, d_edge and side_gradient (c, 4, 3) working rows. Every array is read
    and written in place by its indices: a row taken as an array of its own costs its
    reference count's two atomic updates, and an array made here its allocation: with the
    fifteen rows and three arrays of a point the pass took 27.7 us a call on the two-ply
    hemisphere's 90 points near the outline and 12.3 on 34, in place 21.3 and 10.0 (best of
    40 rounds, one thread, load 8)."""
    p0, p1, p2 = p[i, 0], p[i, 1], p[i, 2]
    n0, n1, n2 = n[i, 0], n[i, 1], n[i, 2]
    # dg/dz over (p, y_1..3), rows of 3: the plane's (n, -lambda_m n)
    d_gap[j, 0, 0], d_gap[j, 0, 1], d_gap[j, 0, 2] = n0, n1, n2
    for k in range(3):
        m = -lam[i, k]
        d_gap[j, 1 + k, 0], d_gap[j, 1 + k, 1], d_gap[j, 1 + k, 2] = m * n0, m * n1, m * n2
    gap = plane[i]
    side = 1.0
    for a in range(4):
        for c in range(3):
            side_gradient[j, a, c] = 0.0
    if beside[i]:  # the distance to q, the angle's factor
        r0, r1, r2 = p0 - q[j, 0], p1 - q[j, 1], p2 - q[j, 2]
        distance = np.sqrt((r0 * r0 + r1 * r1) + r2 * r2)
        sign = -1.0 if plane[i] < 0.0 else 1.0
        safe = sign * distance if distance > 0.0 else 1.0
        nu0, nu1, nu2 = r0 / safe, r1 / safe, r2 / safe
        ratio = plane[i] / safe if distance > 0.0 else 1.0
        v0 = q[j, 0] - y[corner, 0, 0]
        v1 = q[j, 1] - y[corner, 0, 1]
        v2 = q[j, 2] - y[corner, 0, 2]
        d_edge[j, 0, 0], d_edge[j, 0, 1], d_edge[j, 0, 2] = nu0, nu1, nu2
        for k in range(3):
            on_q = (grad[i, k, 0] * v0 + grad[i, k, 2] * v2) + grad[i, k, 1] * v1
            if k == 0:
                on_q += 1.0
            m = -on_q
            d_edge[j, 1 + k, 0], d_edge[j, 1 + k, 1], d_edge[j, 1 + k, 2] = (
                m * nu0,
                m * nu1,
                m * nu2,
            )
        u = min(max(ratio / SIDEWAYS, 0.0), 1.0)
        value = u * u * (3.0 - 2.0 * u)
        rise = 6.0 * u * (1.0 - u)
        if sideways:
            side = value
            if distance > 0.0:
                scale = rise / SIDEWAYS
                for a in range(4):
                    for c in range(3):
                        d_ratio = (d_gap[j, a, c] - ratio * d_edge[j, a, c]) / safe
                        side_gradient[j, a, c] = scale * d_ratio
        gap = sign * distance
        for a in range(4):
            for c in range(3):
                d_gap[j, a, c] = d_edge[j, a, c] if distance > 0.0 else 0.0
    # past the outline: d^2 = |p - q_o|^2 - g^2, w_e = S(1 - d / D)
    past = beside[i]
    for k in range(3):
        if reach[i, k] > 0.0 and lam[i, k] < 0.0:
            past = True
    a0, a1, a2 = starts[s, 0], starts[s, 1], starts[s, 2]
    e0, e1, e2 = ends[s, 0] - a0, ends[s, 1] - a1, ends[s, 2] - a2
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
    weight = factor * side
    twice = 2.0 * gap
    start = -2.0 * (1.0 - t)
    end = -2.0 * t
    for c in range(3):
        o = o0 if c == 0 else (o1 if c == 1 else o2)
        d_squared = 2.0 * o - twice * d_gap[j, 0, c]
        fade_gradient[i, 0, c] = side * (slope * d_squared) + factor * side_gradient[j, 0, c]
        for a in range(1, 4):
            d_squared = 0.0 - twice * d_gap[j, a, c]
            fade_gradient[i, a, c] = side * (slope * d_squared) + factor * side_gradient[j, a, c]
        fade_gradient[i, 4, c] = side * (slope * (start * o)) + factor * 0.0
        fade_gradient[i, 5, c] = side * (slope * (end * o)) + factor * 0.0
    return weight


def _outline(
    at,
    p,
    y,
    triangle,
    n,
    grad,
    plane,
    lam,
    reach,
    beside,
    joined,
    find,
    segment,
    starts,
    e,
    squared,
    ends,
    has_cuts,
    lines,
    cut_ends,
    inside,
    keep,
    length,
    length_squared,
    fade,
    fade_gradient,
    fade_edge,
    q,
    grown,
    cut_q,
    cut_segment,
    d_gap,
    d_edge,
    side_gradient,
):
    """``outline_fade_at``'s pass: at each point i = at[j] its nearest outline edge (measured
    against every edge where ``find``, else ``segment[j]``) into fade_edge[i], w into fade[i]
    and dw/dz into fade_gradient[i] (6, 3), from its facing triangle's plane (n, grad, plane,
    lam: ``ply_kernels.candidates_at``'s rows of the chosen candidate), reach, ``beside`` and
    there the closest point of its grown (and cut) triangle; q, grown, cut_q and cut_segment
    (c, ...) working rows."""
    for j in prange(at.shape[0]):
        i = at[j]
        t = triangle[i]
        p0, p1, p2 = p[i, 0], p[i, 1], p[i, 2]
        s = nearest_segment(p0, p1, p2, starts, e, squared) if find else segment[j]
        fade_edge[i] = s
        if beside[i]:  # ply_wedge.closest_on_grown: the grown triangle's closest point
            r0, r1, r2 = reach[i, 0], reach[i, 1], reach[i, 2]
            whole = 1.0 + (r0 + r1 + r2)
            for a in range(3):  # ply_kernels._grown
                g0 = (whole if a == 0 else 0.0) - r0
                g1 = (whole if a == 1 else 0.0) - r1
                g2 = (whole if a == 2 else 0.0) - r2
                for c in range(3):
                    grown[j, a, c] = g0 * y[t, 0, c] + g1 * y[t, 1, c] + g2 * y[t, 2, c]
            closest_on_sides(p0, p1, p2, grown[j], q[j])
            lined = False
            if has_cuts:
                for k in range(3):
                    for c in range(3):
                        if lines[t, k, c] != 0.0:
                            lined = True
            if lined:  # the projection where the growth holds it, then the cuts
                held = True
                for k in range(3):
                    if not lam[i, k] >= -reach[i, k] - inside:
                        held = False
                if held:
                    h = plane[i]
                    q[j, 0], q[j, 1], q[j, 2] = p0 - h * n[i, 0], p1 - h * n[i, 1], p2 - h * n[i, 2]
                closest_cut_at(
                    p[i], y[t], q[j], lines[t], cut_ends[t], grad[i], keep, cut_q[j], cut_segment[j]
                )
                for c in range(3):
                    q[j, c] = cut_q[j, c]
        fade[i] = fade_at(
            i, j, t, s, p, y, n, grad, plane, lam, reach, beside, q, starts, ends, length,
            length_squared, not joined[i], fade_gradient, d_gap, d_edge, side_gradient,
        )  # fmt: skip


_outline_compiled = jit_lanes(_outline)


def outline_fade_at(
    at: np.ndarray,
    p: np.ndarray,
    y: np.ndarray,
    triangle: np.ndarray,
    planes: tuple,
    reach: np.ndarray,
    beside: np.ndarray,
    joined: np.ndarray,
    segment: np.ndarray | None,
    starts: np.ndarray,
    ends: np.ndarray,
    cuts: WedgeCuts | None,
    length: float,
    out: tuple[np.ndarray, np.ndarray, np.ndarray],
) -> None:
    """The fade at the points ``at`` near the outline in one pass (elements/ply_projection.py
    ``closest_facing``), where the outline's nearest edges, the fade's inputs, their
    triangles' planes, the grown triangles' closest points and the fade were five compiled
    calls chained by numpy's gathers: the same bits as ``ply_fade.outline_fade`` on
    ``ply_chosen.fade_inputs_numpy``'s arrays with ``ply_fade.every_segment``'s edges
    (tests/test_ply_kernels.py).

    Parameters
    ----------
    at : (c,) int
        The points near the outline (rows of the points' arrays).
    p : (P, 3) float
        The points, mm.
    y : (m, 3, 3) float
        The lower face's triangles' corners, mm.
    triangle : (P,) int
        Each point's facing triangle.
    planes : (n, gradients, gap, lam)
        Each point's facing triangle's plane: unit normal (P, 3), barycentric gradients
        (P, 3, 3) 1/mm, the point's gap to it (P,) mm and its projection's coordinates
        (P, 3) (``ply_kernels.candidates_at``'s rows of the chosen candidates).
    reach, beside, joined : (P, 3) float, (P,) bool, (P,) bool
        The facing triangle's reach past its edges, the point beside a growth's edge
        (``on_growth``), on a joined edge's extension.
    segment : (c,) int or None
        The outline's edge nearest each point ``at`` (``ply_fade.nearest_segments``); None:
        measured here against every edge.
    starts, ends : (E, 3) float
        The outline's edges' ends, mm.
    cuts : WedgeCuts or None
        The growths' cuts (elements/ply_wedge.py).
    length : float
        The fade's length D, mm.
    out : (fade (P,), fade_gradient (P, 6, 3), fade_edge (P,) int)
        Written at the rows ``at``.
    """
    count = len(at)
    n, grad, plane, lam = planes
    e, squared = segment_lines(starts, ends)
    empty = np.zeros((0, 3, 3))
    fade, fade_gradient, fade_edge = out
    _outline_compiled(
        np.ascontiguousarray(at, dtype=np.int64),
        read_only(p),  # read-only as the block keeps them: one build (kernel_inputs.py)
        read_only(y),
        np.ascontiguousarray(triangle, dtype=np.int64),
        n,
        writable(grad),  # as ply_cut_kernels.py hands closest_cut_at its gradients
        plane,
        lam,
        reach,
        np.ascontiguousarray(beside, dtype=np.bool_),
        np.ascontiguousarray(joined, dtype=np.bool_),
        segment is None,
        np.zeros(count, dtype=np.int64) if segment is None else segment.astype(np.int64),
        np.ascontiguousarray(starts, dtype=float),
        e,
        squared,
        np.ascontiguousarray(ends, dtype=float),
        cuts is not None,
        empty if cuts is None else writable(cuts.lines),  # as ply_cut_kernels.py hands them
        empty if cuts is None else writable(cuts.ends),
        INSIDE,
        KEEP,
        float(length),
        float(length**2),
        fade,
        fade_gradient,
        fade_edge,
        np.empty((count, 3)),
        np.empty((count, 3, 3)),
        np.empty((count, 3)),
        np.empty((count, 2, 3)),
        np.empty((count, 4, 3)),
        np.empty((count, 4, 3)),
        np.empty((count, 4, 3)),
    )
