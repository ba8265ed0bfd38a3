"""The choice of each ply contact point's facing triangle among its candidates, compiled
(elements/ply_projection.py ``closest_facing``, "Search" and "The wedge cut"; docs/theory.md,
the ply contact section): from the candidates' planes (``ply_kernels.candidates_at``), the
cut growths' kept sides, the distance to each candidate (to its plane where its cut growth
holds the projection, else to its closest point on the grown triangle's edges or a cut,
computed only where it can beat the nearest plane), the nearest candidate with ties to the
lowest triangle row, and its closest point, in one pass over the points.

Its numpy reference is ``closest_facing``'s own expressions with ``ply_wedge.cut_keeps``,
``cut_overshoot`` and ``closest_on_cut``, taken with ``ply_projection.COMPILED = False``. The
pass does the same IEEE operations in the same order (numpy's sums of three terms: ``np.sum``,
``np.linalg.norm``, ``einsum("cj,cji->ci")`` and ``einsum("...kj,...ji->...ki")`` from the
first term, ``einsum("ci,ci->c")``, ``einsum("cki,ci->ck")`` and ``einsum("...kj,...j->...k")``
as (first + last) + middle; ``np.hypot`` is libm's ``hypot``, as numba's; no fused
multiply-add: numba builds without fastmath), so it chooses the same triangles and gives the
same closest points to the last bit (tests/test_ply_kernels.py). Each point is independent:
the same bits on any thread count.
"""

from __future__ import annotations

import math

import numpy as np

from elements.kernel_inputs import read_only
from elements.ply_kernels import closest_on_sides
from elements.ply_projection import closest_on_edges, grown_corners
from elements.ply_wedge import KEEP, closest_on_cut_numpy, cut_keeps, cut_overshoot
from femcore.jit import jit_lanes, lanes, prange

__all__ = ["choice_arrays", "choice_returned", "choose_facing", "choose_facing_numpy", "cut_arrays"]


@lanes
def _keeps(lines, t, w0, w1, w2):
    """Every cut of triangle ``t`` (``lines`` (m, 3, 3)) keeps the point of barycentric
    coordinates (w0, w1, w2) (``ply_wedge.cut_keeps``)."""
    for k in range(3):
        level = (lines[t, k, 0] * w0 + lines[t, k, 2] * w2) + lines[t, k, 1] * w1
        if not level >= -KEEP:
            return False
    return True


def _choose(
    p,
    y,
    near,
    n,
    gradients,
    gap,
    weights,
    reach,
    inside,
    past,
    has_cuts,
    cut,
    lines,
    ends,
    best,
    on_edge,
    closest,
    on_cut,
    segment,
    along,
    held_at,
    grown_held_at,
    distance_at,
    points_at,
    cutting_at,
    ends_at_at,
    parameter_at,
    grown_at,
    q_at,
):
    """For each point p[i] (P, 3) among its candidates near[i] (P, K) of the triangles y
    (m, 3, 3), from their planes (n (P, K, 3), gradients (P, K, 3, 3), gap (P, K), weights
    (P, K, 3)), reach (P, K, 3), whether the grown triangle holds the projection ``inside``
    (P, K) and its distance past the edge lines ``past`` (P, K), and the cuts (``has_cuts``;
    per triangle ``cut`` (m,) bool, ``lines`` and ``ends`` (m, 3, 3)): the chosen column
    ``best`` (P,), whether its closest point is off its plane's held part ``on_edge`` (P,),
    and there that point ``closest`` (P, 3), on a cut ``on_cut`` (P,), the cut's segment ends'
    coordinates ``segment`` (P, 2, 3) and its parameter ``along`` (P,) (0 elsewhere)."""
    count = near.shape[1]
    for i in prange(p.shape[0]):
        p0, p1, p2 = p[i, 0], p[i, 1], p[i, 2]
        # this point's rows of the scratch arrays (one allocation a call, not nine a point),
        # indexed in place: a row taken as an array of its own (held_at[i]) costs its
        # reference count's two atomic updates; with nine such rows a point the pass took
        # 41.1 us a call on the two-ply hemisphere's 384 points and 15.0 on its 81, indexed
        # 12.7 and 8.8 (best of 40 rounds, one thread, load 8)
        for k in range(count):
            cutting_at[i, k] = False
            parameter_at[i, k] = 0.0
            for c in range(3):
                points_at[i, k, c] = 0.0
                ends_at_at[i, k, 0, c] = 0.0
                ends_at_at[i, k, 1, c] = 0.0
        least_plane = np.inf
        for k in range(count):
            t = near[i, k]
            holds = inside[i, k]
            grown_held_at[i, k] = holds
            if has_cuts and cut[t] and holds:
                holds = _keeps(lines, t, weights[i, k, 0], weights[i, k, 1], weights[i, k, 2])
            held_at[i, k] = holds
            distance_at[i, k] = abs(gap[i, k]) if holds else np.inf
            if distance_at[i, k] < least_plane:
                least_plane = distance_at[i, k]
        for k in range(count):
            if held_at[i, k]:
                continue
            t = near[i, k]
            if k > 0 and t == near[i, 0]:
                # a kept list's padding (elements/ply_search.py: each row padded with its
                # first): the first's closest point, which the same operations would give
                # again (and the ties below keep the first)
                distance_at[i, k] = distance_at[i, 0]
                cutting_at[i, k] = cutting_at[i, 0]
                parameter_at[i, k] = parameter_at[i, 0]
                for c in range(3):
                    points_at[i, k, c] = points_at[i, 0, c]
                    ends_at_at[i, k, 0, c] = ends_at_at[i, 0, 0, c]
                    ends_at_at[i, k, 1, c] = ends_at_at[i, 0, 1, c]
                continue
            beyond = past[i, k]
            if has_cuts and cut[t]:  # the farthest cut the projection lies past
                w0, w1, w2 = weights[i, k, 0], weights[i, k, 1], weights[i, k, 2]
                farthest = -np.inf
                for c in range(3):
                    level = (lines[t, c, 0] * w0 + lines[t, c, 2] * w2) + lines[t, c, 1] * w1
                    slope = 0.0
                    for a in range(3):
                        g = (
                            lines[t, c, 0] * gradients[i, k, 0, a]
                            + lines[t, c, 1] * gradients[i, k, 1, a]
                        ) + lines[t, c, 2] * gradients[i, k, 2, a]
                        slope = slope + g * g if a > 0 else g * g
                    slope = np.sqrt(slope)
                    value = -level / slope if slope > 0.0 else -np.inf
                    if c == 0 or value > farthest:
                        farthest = value
                beyond = max(beyond, farthest)
            if not math.hypot(gap[i, k], max(beyond, 0.0)) < least_plane:
                continue
            # the grown triangle's closest point on its edges (ply_kernels._grown)
            r0, r1, r2 = reach[i, k, 0], reach[i, k, 1], reach[i, k, 2]
            whole = 1.0 + (r0 + r1 + r2)
            for a in range(3):
                g0 = (whole if a == 0 else 0.0) - r0
                g1 = (whole if a == 1 else 0.0) - r1
                g2 = (whole if a == 2 else 0.0) - r2
                for c in range(3):
                    grown_at[i, a, c] = g0 * y[t, 0, c] + g1 * y[t, 1, c] + g2 * y[t, 2, c]
            closest_on_sides(p0, p1, p2, grown_at[i], q_at[i])
            if has_cuts:
                if grown_held_at[i, k]:  # the projection, which the cut growth does not hold
                    h = gap[i, k]
                    q_at[i, 0] = p0 - h * n[i, k, 0]
                    q_at[i, 1] = p1 - h * n[i, k, 1]
                    q_at[i, 2] = p2 - h * n[i, k, 2]
                lined = False
                for c in range(3):
                    for a in range(3):
                        if lines[t, c, a] != 0.0:
                            lined = True
                if lined:  # ply_wedge.closest_on_cut
                    v0, v1, v2 = (
                        q_at[i, 0] - y[t, 0, 0],
                        q_at[i, 1] - y[t, 0, 1],
                        q_at[i, 2] - y[t, 0, 2],
                    )
                    l0 = (gradients[i, k, 0, 0] * v0 + gradients[i, k, 0, 2] * v2) + gradients[
                        i, k, 0, 1
                    ] * v1
                    l0 += 1.0
                    l1 = (gradients[i, k, 1, 0] * v0 + gradients[i, k, 1, 2] * v2) + gradients[
                        i, k, 1, 1
                    ] * v1
                    l2 = (gradients[i, k, 2, 0] * v0 + gradients[i, k, 2, 2] * v2) + gradients[
                        i, k, 2, 1
                    ] * v1
                    if not _keeps(lines, t, l0, l1, l2):
                        nearest = np.inf
                        for c in range(3):
                            present = False
                            for a in range(3):
                                if lines[t, c, a] != 0.0:
                                    present = True
                            if not present:
                                continue
                            s0, s1, s2 = y[t, c, 0], y[t, c, 1], y[t, c, 2]
                            f0, f1, f2 = ends[t, c, 0], ends[t, c, 1], ends[t, c, 2]
                            e0 = ((f0 * y[t, 0, 0] + f1 * y[t, 1, 0]) + f2 * y[t, 2, 0]) - s0
                            e1 = ((f0 * y[t, 0, 1] + f1 * y[t, 1, 1]) + f2 * y[t, 2, 1]) - s1
                            e2 = ((f0 * y[t, 0, 2] + f1 * y[t, 1, 2]) + f2 * y[t, 2, 2]) - s2
                            squared = (e0 * e0 + e2 * e2) + e1 * e1
                            u = ((p0 - s0) * e0 + (p2 - s2) * e2) + (p1 - s1) * e1
                            u = u / (squared if squared > 0 else 1.0)
                            u = min(max(u, 0.0), 1.0)
                            o0, o1, o2 = s0 + u * e0, s1 + u * e1, s2 + u * e2
                            d0, d1, d2 = p0 - o0, p1 - o1, p2 - o2
                            length = np.sqrt((d0 * d0 + d1 * d1) + d2 * d2)
                            if length < nearest:
                                nearest = length
                                q_at[i, 0], q_at[i, 1], q_at[i, 2] = o0, o1, o2
                                for a in range(3):
                                    ends_at_at[i, k, 0, a] = 1.0 if a == c else 0.0
                                    ends_at_at[i, k, 1, a] = ends[t, c, a]
                                parameter_at[i, k] = u
                        cutting_at[i, k] = nearest < np.inf
            d0, d1, d2 = p0 - q_at[i, 0], p1 - q_at[i, 1], p2 - q_at[i, 2]
            distance_at[i, k] = np.sqrt((d0 * d0 + d1 * d1) + d2 * d2)
            points_at[i, k, 0], points_at[i, k, 1], points_at[i, k, 2] = (
                q_at[i, 0],
                q_at[i, 1],
                q_at[i, 2],
            )
        # ties (a closest point several candidates share) to the lowest triangle row
        least = distance_at[i, 0]
        for k in range(1, count):
            if distance_at[i, k] < least:
                least = distance_at[i, k]
        chosen = 0
        lowest = np.iinfo(np.int64).max
        for k in range(count):
            if distance_at[i, k] <= least + 1e-9 * (1.0 + least) and near[i, k] < lowest:
                lowest = near[i, k]
                chosen = k
        best[i] = chosen
        on_edge[i] = not held_at[i, chosen]
        closest[i, 0], closest[i, 1], closest[i, 2] = (
            points_at[i, chosen, 0],
            points_at[i, chosen, 1],
            points_at[i, chosen, 2],
        )
        on_cut[i] = cutting_at[i, chosen]
        for a in range(2):
            for c in range(3):
                segment[i, a, c] = ends_at_at[i, chosen, a, c]
        along[i] = parameter_at[i, chosen]


_choose_compiled = jit_lanes(_choose)


def choose_facing(p, y, near, n, gradients, gap, weights, reach, inside, past, cuts):
    """Each point's facing candidate and closest point, compiled (module docstring).

    Parameters
    ----------
    p : (P, 3) float
        The contact points, mm.
    y : (m, 3, 3) float
        The lower face's triangles' corners, mm.
    near : (P, K) int
        Each point's candidates (rows of ``y``).
    n, gradients, gap, weights, reach, inside, past
        ``ply_kernels.candidates_at``'s arrays of the candidates.
    cuts : WedgeCuts or None
        The growths' cuts (elements/ply_wedge.py).

    Returns
    -------
    best : (P,) int
        The chosen candidate's column in ``near``.
    on_edge : (P,) bool
        Its closest point is not its plane's projection (held by its cut growth).
    closest : (P, 3) float
        There that closest point, mm.
    on_cut : (P,) bool
        It lies on a cut.
    segment : (P, 2, 3) float
        There the barycentric coordinates of the cut's ends (0 elsewhere).
    along : (P,) float
        There its parameter on the cut (0 elsewhere).
    """
    count = len(p)
    out = choice_arrays(count)
    _choose_compiled(
        read_only(p),  # read-only as the block keeps them: one build (kernel_inputs.py)
        read_only(y),
        np.ascontiguousarray(near, dtype=np.int64),
        n,
        gradients,
        gap,
        weights,
        reach,
        inside,
        past,
        *cut_arrays(cuts, len(y)),
        *out,
        *_scratch(count, near.shape[1]),
    )
    return choice_returned(out, cuts)


def choice_arrays(count: int) -> tuple[np.ndarray, ...]:
    """``_choose``'s outputs for ``count`` points: best, on_edge, closest, on_cut, segment,
    along (the last four zero where no cut holds the point)."""
    return (
        np.empty(count, dtype=np.int64),
        np.empty(count, dtype=np.bool_),
        np.zeros((count, 3)),
        np.zeros(count, dtype=np.bool_),
        np.zeros((count, 2, 3)),
        np.zeros(count),
    )


def cut_arrays(cuts, m: int) -> tuple:
    """``_choose``'s arguments of the growths' cuts ``cuts`` (WedgeCuts or None) over ``m``
    triangles: whether any, and the cut flags, lines and ends (zeros for none)."""
    has_cuts = cuts is not None and cuts.any
    return (
        has_cuts,
        cuts.cut if has_cuts else np.zeros(m, dtype=np.bool_),
        np.ascontiguousarray(cuts.lines if has_cuts else np.zeros((m, 3, 3)), dtype=float),
        np.ascontiguousarray(cuts.ends if has_cuts else np.zeros((m, 3, 3)), dtype=float),
    )


def choice_returned(out: tuple, cuts) -> tuple:
    """``choose_facing``'s returns from ``_choose``'s outputs ``out``: along None without
    cuts."""
    return (*out[:5], out[5] if cuts is not None and cuts.any else None)


def _scratch(count: int, k: int) -> tuple[np.ndarray, ...]:
    """``_choose``'s per-point working arrays, a row per point: each point's candidates'
    held flags, distances, closest points, cut flags, segments and parameters (count, k, ...),
    its grown corners (count, 3, 3) and closest point (count, 3). Allocated once a call, not
    nine times a point inside the pass: 55.8 -> 36.3 us a call on the 384 points of one
    candidate each of the two-ply hemisphere (benchmarks/forming_step_overhead.py)."""
    return (
        np.empty((count, k), dtype=np.bool_),
        np.empty((count, k), dtype=np.bool_),
        np.empty((count, k)),
        np.empty((count, k, 3)),
        np.empty((count, k), dtype=np.bool_),
        np.empty((count, k, 2, 3)),
        np.empty((count, k)),
        np.empty((count, 3, 3)),
        np.empty((count, 3)),
    )


def choose_facing_numpy(p, y, near, n, gradients, gap, weights, reach, inside, past, cuts):
    """``choose_facing``'s numpy reference: the same arrays (``along`` None without cuts)."""
    held_grown = inside
    # a cut growth holds what each of its cuts keeps (measured at the cut candidates alone)
    cut_at = np.nonzero(cuts.cut[near]) if cuts is not None and cuts.any else None
    if cut_at is not None and cuts is not None:
        inside = inside.copy()
        inside[cut_at] &= cut_keeps(weights[cut_at], cuts.lines[near[cut_at]])
    # The distance to each candidate (grown past the outline): to its plane where it holds
    # the projection, else to its closest point on an edge, computed only where it can beat
    # the nearest plane that holds one (the distance to a plane is at most that to the
    # triangle).
    distance = np.where(inside, np.abs(gap), np.inf)
    held = distance.min(axis=1)
    if cut_at is not None and cuts is not None:  # and to the farthest cut it lies past
        # (read only where the candidate does not hold the projection)
        cut_out = tuple(index[~inside[cut_at]] for index in cut_at)
        past[cut_out] = np.maximum(
            past[cut_out],
            cut_overshoot(weights[cut_out], cuts.lines[near[cut_out]], gradients[cut_out]),
        )
    outside = np.nonzero(~inside & (np.hypot(gap, np.maximum(past, 0.0)) < held[:, None]))
    corners = grown_corners(y[near[outside]], reach[outside])
    q = closest_on_edges(p[outside[0]], corners)
    on_cut, segment, along = np.zeros(len(q), dtype=bool), np.zeros((len(q), 2, 3)), None
    if cut_at is not None and cuts is not None:  # the cut growth's closest point
        projected = p[outside[0]] - gap[outside][:, None] * n[outside]
        q = np.where(held_grown[outside][:, None], projected, q)
        rows = near[outside]
        q, on_cut, segment, along = closest_on_cut_numpy(
            p[outside[0]], y[rows], q, cuts.lines[rows], cuts.ends[rows], gradients[outside]
        )
    distance[outside] = np.linalg.norm(p[outside[0]] - q, axis=1)
    # ties (a closest point on an edge or a vertex that several candidates share) go to the
    # lowest triangle row, whatever the round-off: the same choice in any frame
    least = distance.min(axis=1, keepdims=True)
    tied = distance <= least + 1e-9 * (1.0 + least)
    best = np.argmin(np.where(tied, near, np.iinfo(np.int64).max), axis=1)
    rows = np.arange(len(p))
    on_edge = ~inside[rows, best]
    # each point's closest point among the computed ones (where its chosen one is off its
    # plane's held part)
    where = np.full(inside.shape, -1)
    where[outside] = np.arange(len(q))
    pick = where[rows, best]
    found = pick >= 0
    closest, cutting = np.zeros((len(p), 3)), np.zeros(len(p), dtype=bool)
    ends_at, parameter = np.zeros((len(p), 2, 3)), np.zeros(len(p))
    closest[found], cutting[found] = q[pick[found]], on_cut[pick[found]]
    ends_at[found] = segment[pick[found]]
    if along is not None:
        parameter[found] = along[pick[found]]
    return best, on_edge, closest, cutting, ends_at, None if along is None else parameter
