"""The closest facet of a meshed rigid tool (elements.rigid_surface.RigidSurface), compiled (numba):
for each point, the closest point on each of its candidate facets, the nearest kept.

A forming blank asks this of its ten thousand nodes at every explicit step, each with about
eight candidate facets, so the loop is written for speed while giving the numbers of a plain
scan over the candidates in their order, to the last bit:

* the corners are read as scalars and the closest point returned as a tuple: no array views
  nor small arrays made per point (measured on the hemisphere forming die: 2.4 instead of
  4.0 ms a pass over 10k points, one thread);
* a candidate whose bounding sphere (its centroid, its circumradius about it) lies further
  than a known distance is skipped without its closest point: every point of that facet is
  further than the known one, so the facet cannot be the nearest nor tie with it. The known
  distance is that to the point's facet of the last call (``hint``: mostly its nearest
  again), widened by ``SLACK`` so that rounding cannot turn a skipped facet into a tie. If
  the facets kept find none as near as that (the hint's facet is not a candidate, or rounding
  at the margin), the point's candidates are scanned again without skipping. Measured: 1.5
  ms a pass on the die above.
* ``closest_facets_kept`` gives a point its last nearest facet alone, without a scan, while
  it has moved less than half the gap from that facet to the next candidate (docs/theory.md
  §9.3). On the forming die's 71k facets with a 20k-triangle blank (10k nodes, 10
  candidates each), one thread, load 14: 0.9 ms a pass where every node keeps its facet
  against 7.0 for the scan.

The numpy pieces of the same geometry, which the tool uses at its build and to check these
loops: the closest point on triangles (``closest_on_triangles``), a surface's boundary edges
(``open_edges``) and the index spans of a CSR-like list (``spans``).
"""

from __future__ import annotations

import numpy as np

from femcore.jit import jit, lane_rows, prange, serial

__all__ = [
    "SHORT",
    "SLACK",
    "candidate_rows",
    "closest_facets",
    "closest_facets_kept",
    "closest_facets_listed",
    "closest_of_nearest",
    "closest_on_triangles",
    "largest_drift",
    "open_edges",
    "signed_from_closest",
    "spans",
]

# The known distance is widened by this fraction of itself and of the tool's reach before a
# facet is skipped: far beyond the rounding of the distances compared (1e-16 relative).
SLACK = 1e-9


def _closest_on_triangle(p0, p1, p2, a0, a1, a2, b0, b1, b2, c0, c1, c2):
    """The closest point (3 floats) to p on the triangle (a, b, c): Ericson's Voronoi regions
    (the scalar form of closest_on_triangles below)."""
    ab0, ab1, ab2 = b0 - a0, b1 - a1, b2 - a2
    ac0, ac1, ac2 = c0 - a0, c1 - a1, c2 - a2
    ap0, ap1, ap2 = p0 - a0, p1 - a1, p2 - a2
    d1 = ab0 * ap0 + ab1 * ap1 + ab2 * ap2
    d2 = ac0 * ap0 + ac1 * ap1 + ac2 * ap2
    if d1 <= 0.0 and d2 <= 0.0:
        return a0, a1, a2
    bp0, bp1, bp2 = p0 - b0, p1 - b1, p2 - b2
    d3 = ab0 * bp0 + ab1 * bp1 + ab2 * bp2
    d4 = ac0 * bp0 + ac1 * bp1 + ac2 * bp2
    if d3 >= 0.0 and d4 <= d3:
        return b0, b1, b2
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        t = d1 / (d1 - d3)
        return a0 + t * ab0, a1 + t * ab1, a2 + t * ab2
    cp0, cp1, cp2 = p0 - c0, p1 - c1, p2 - c2
    d5 = ab0 * cp0 + ab1 * cp1 + ab2 * cp2
    d6 = ac0 * cp0 + ac1 * cp1 + ac2 * cp2
    if d6 >= 0.0 and d5 <= d6:
        return c0, c1, c2
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        t = d2 / (d2 - d6)
        return a0 + t * ac0, a1 + t * ac1, a2 + t * ac2
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and (d4 - d3) >= 0.0 and (d5 - d6) >= 0.0:
        t = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        return b0 + t * (c0 - b0), b1 + t * (c1 - b1), b2 + t * (c2 - b2)
    denominator = va + vb + vc
    v, w = vb / denominator, vc / denominator
    return a0 + v * ab0 + w * ac0, a1 + v * ab1 + w * ac1, a2 + v * ab2 + w * ac2


_closest_on_triangle = serial(_closest_on_triangle)


def _squared_gap(p0, p1, p2, corners, f):
    """The closest point on facet f of corners (f, 3, 3) to p and its squared distance."""
    q0, q1, q2 = _closest_on_triangle(
        p0, p1, p2,
        corners[f, 0, 0], corners[f, 0, 1], corners[f, 0, 2],
        corners[f, 1, 0], corners[f, 1, 1], corners[f, 1, 2],
        corners[f, 2, 0], corners[f, 2, 1], corners[f, 2, 2],
    )  # fmt: skip
    return q0, q1, q2, (q0 - p0) ** 2 + (q1 - p1) ** 2 + (q2 - p2) ** 2


# Without numba's reference counting (femcore/jit.py ``lane_rows``): called once or more a
# point with the corners array, whose incref and decref (atomic) at every call took half the
# kept facets' loop (38 -> 19 us a call on the hemisphere die's 441 points when every point
# keeps its facet, one thread; benchmarks/forming_one_ply_step.py). No division here: the
# numpy error model changes no number (_closest_on_triangle keeps its own).
_squared_gap = lane_rows(_squared_gap)


def _closest_facets(x, corners, centroids, radius, slack, start, facets, hint, point, facet, gap):
    """For each point x[i] (k, 3), the closest point on its candidate facets
    facets[start[i]:start[i + 1]] of corners (f, 3, 3) (the first of equals in that order):
    into point (k, 3), facet (k,) and gap (k,) (the distance; inf without candidates, point
    and facet then untouched). centroids (f, 3) and radius (f,) bound each facet; hint (k,)
    a facet per point (any, or -1 for none: every candidate examined); slack (mm) widens the
    hint's distance before a facet is skipped (module docstring)."""
    for i in prange(x.shape[0]):
        p0, p1, p2 = x[i, 0], x[i, 1], x[i, 2]
        known = np.inf
        if hint[i] >= 0:
            known = np.sqrt(_squared_gap(p0, p1, p2, corners, hint[i])[3]) * (1.0 + SLACK)
            known += slack
        best = np.inf
        for sweep in range(2):
            for j in range(start[i], start[i + 1]):
                f = facets[j]
                if sweep == 0:
                    reach = known + radius[f]
                    apart = (
                        (centroids[f, 0] - p0) ** 2
                        + (centroids[f, 1] - p1) ** 2
                        + (centroids[f, 2] - p2) ** 2
                    )
                    if apart > reach * reach:
                        continue  # every point of the facet is further than the known one
                q0, q1, q2, d = _squared_gap(p0, p1, p2, corners, f)
                if d < best:
                    best = d
                    facet[i] = f
                    point[i, 0], point[i, 1], point[i, 2] = q0, q1, q2
            if sweep == 1 or best <= known * known:
                break
            best = np.inf  # none kept as near as the hint's: scan them all
        gap[i] = np.sqrt(best)


closest_facets = jit(_closest_facets)


def _dot_as_numpy(u0, u1, u2, v0, v1, v2):
    """u . v summed in the order numpy's einsum sums three products on this machine (its
    two-lane loop: the first and the third, then the second; measured: the sequential order
    differed from it in 30 % of random products), so that ``closest_on_triangles`` is
    reproduced to the last bit (tests/test_facet_search.py holds the two to it)."""
    return (u0 * v0 + u2 * v2) + u1 * v1


_dot_as_numpy = serial(_dot_as_numpy)


def _closest_as_numpy(p0, p1, p2, a0, a1, a2, b0, b1, b2, c0, c1, c2):
    """``_closest_on_triangle`` with ``closest_on_triangles``' dot products
    (``_dot_as_numpy``): numpy's closest point to the last bit, its regions in its order."""
    ab0, ab1, ab2 = b0 - a0, b1 - a1, b2 - a2
    ac0, ac1, ac2 = c0 - a0, c1 - a1, c2 - a2
    ap0, ap1, ap2 = p0 - a0, p1 - a1, p2 - a2
    d1 = _dot_as_numpy(ab0, ab1, ab2, ap0, ap1, ap2)
    d2 = _dot_as_numpy(ac0, ac1, ac2, ap0, ap1, ap2)
    if d1 <= 0.0 and d2 <= 0.0:
        return a0, a1, a2
    bp0, bp1, bp2 = p0 - b0, p1 - b1, p2 - b2
    d3 = _dot_as_numpy(ab0, ab1, ab2, bp0, bp1, bp2)
    d4 = _dot_as_numpy(ac0, ac1, ac2, bp0, bp1, bp2)
    if d3 >= 0.0 and d4 <= d3:
        return b0, b1, b2
    cp0, cp1, cp2 = p0 - c0, p1 - c1, p2 - c2
    d5 = _dot_as_numpy(ab0, ab1, ab2, cp0, cp1, cp2)
    d6 = _dot_as_numpy(ac0, ac1, ac2, cp0, cp1, cp2)
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        t = d1 / (d1 - d3)
        return a0 + t * ab0, a1 + t * ab1, a2 + t * ab2
    if d6 >= 0.0 and d5 <= d6:
        return c0, c1, c2
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        t = d2 / (d2 - d6)
        return a0 + t * ac0, a1 + t * ac1, a2 + t * ac2
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and (d4 - d3) >= 0.0 and (d5 - d6) >= 0.0:
        t = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        return b0 + t * (c0 - b0), b1 + t * (c1 - b1), b2 + t * (c2 - b2)
    v, w = vb / (va + vb + vc), vc / (va + vb + vc)
    return a0 + v * ab0 + w * ac0, a1 + v * ab1 + w * ac1, a2 + v * ab2 + w * ac2


_closest_as_numpy = serial(_closest_as_numpy)


def _closest_of_nearest(x, corners, facets, point, facet, gap):
    """For each point x[i] (k, 3), mm, the closest point on the facets facets[i] (k, m) of
    corners (f, 3, 3), the first of equal distances in the row's order: into point (k, 3),
    facet (k,) and gap (k,), the distance, mm. The numpy formulas of the search's reference
    (``closest_on_triangles``, the norm of each point's offsets and numpy's argmin: the
    first of equal gaps) to the last bit, one point at a time, without the (k, m, 3, 3)
    gathers: the batched searches of a meshed tool's candidate lists
    (RigidSurface._closest)."""
    for i in prange(x.shape[0]):
        p0, p1, p2 = x[i, 0], x[i, 1], x[i, 2]
        best = np.inf
        for j in range(facets.shape[1]):
            f = facets[i, j]
            q0, q1, q2 = _closest_as_numpy(
                p0, p1, p2,
                corners[f, 0, 0], corners[f, 0, 1], corners[f, 0, 2],
                corners[f, 1, 0], corners[f, 1, 1], corners[f, 1, 2],
                corners[f, 2, 0], corners[f, 2, 1], corners[f, 2, 2],
            )  # fmt: skip
            g = np.sqrt((q0 - p0) ** 2 + (q1 - p1) ** 2 + (q2 - p2) ** 2)  # numpy's norm
            if j == 0 or g < best:
                best = g
                facet[i] = f
                point[i, 0], point[i, 1], point[i, 2] = q0, q1, q2
        gap[i] = best


closest_of_nearest = jit(_closest_of_nearest)


def _room(nearest, second, slack):
    """How far (mm) a point may move from where its nearest facet lay ``nearest`` away, the
    next one ``second`` away (or a lower bound of it), keeping that facet the nearest: half
    the gap between them less a rounding allowance of SLACK of the two and ``slack``; inf
    where nothing else is near (an only candidate, or a short list's every facet)."""
    if second == np.inf:
        return np.inf
    return 0.5 * (second - nearest) - SLACK * (second + nearest) - slack


_room = serial(_room)


def _kept_answers(i, p0, p1, p2, table, row, f, anchor, room, point, facet, gap):
    """Whether point i (at p) is answered by its kept facet ``f``: it lies less than
    ``room[i]`` from where that facet was found (``_closest_facets_kept``); if so the facet,
    its closest point and gap are written in row i. The facet's corners are
    ``table[row]`` (the tool's corners and f, or a copy of them kept per point)."""
    if f < 0 or not room[i] > 0.0:
        return False
    moved = np.sqrt((p0 - anchor[i, 0]) ** 2 + (p1 - anchor[i, 1]) ** 2 + (p2 - anchor[i, 2]) ** 2)
    if not moved < room[i]:
        return False
    q0, q1, q2, d = _squared_gap(p0, p1, p2, table, row)
    facet[i] = f
    point[i, 0], point[i, 1], point[i, 2] = q0, q1, q2
    gap[i] = np.sqrt(d)
    return True


_kept_answers = lane_rows(_kept_answers)  # (as _squared_gap: five arrays, no division)


def _closest_facets_kept(
    x, corners, centroids, radius, slack, start, facets, hint, anchor, room, point, facet, gap
):
    """``_closest_facets`` for points that mostly keep their closest facet: point i whose
    facet of the last call ``hint[i]`` was found where it stood then (``anchor[i]`` (k, 3))
    at least 2 ``room[i]`` (mm) nearer than any other of its candidates is given that facet
    alone while it lies less than ``room[i]`` from that place: its distance has grown by less
    than that, every other's shrunk by less, so it is still the nearest, the only one at its
    distance (docs/theory.md §9.3). Else its candidates are scanned as ``_closest_facets``
    does, and anchor and room set anew: half the gap between the nearest facet and the next
    (its closest point's distance, or the bounding sphere's for a facet skipped), less a
    rounding allowance of SLACK of the two and ``slack`` (mm). A room of -1 (or a hint of -1)
    asks for the scan. The same point, facet and gap as ``_closest_facets``, to the last bit."""
    for i in prange(x.shape[0]):
        p0, p1, p2 = x[i, 0], x[i, 1], x[i, 2]
        f = hint[i]
        if _kept_answers(i, p0, p1, p2, corners, f, f, anchor, room, point, facet, gap):
            continue
        known = np.inf
        if f >= 0:
            known = np.sqrt(_squared_gap(p0, p1, p2, corners, f)[3]) * (1.0 + SLACK)
            known += slack
        best = np.inf
        second = np.inf  # the next facet's distance, or a lower bound of it (mm)
        for sweep in range(2):
            for j in range(start[i], start[i + 1]):
                g = facets[j]
                if sweep == 0:
                    reach = known + radius[g]
                    apart = (
                        (centroids[g, 0] - p0) ** 2
                        + (centroids[g, 1] - p1) ** 2
                        + (centroids[g, 2] - p2) ** 2
                    )
                    if apart > reach * reach:
                        second = min(second, np.sqrt(apart) - radius[g])
                        continue
                q0, q1, q2, d = _squared_gap(p0, p1, p2, corners, g)
                if d < best:
                    second = min(second, np.sqrt(best))
                    best = d
                    facet[i] = g
                    point[i, 0], point[i, 1], point[i, 2] = q0, q1, q2
                else:
                    second = min(second, np.sqrt(d))
            if sweep == 1 or best <= known * known:
                break
            best = np.inf  # none kept as near as the hint's: scan them all
            second = np.inf
        nearest = np.sqrt(best)
        gap[i] = nearest
        anchor[i, 0], anchor[i, 1], anchor[i, 2] = p0, p1, p2
        if start[i] == start[i + 1]:
            room[i] = -1.0  # no candidates: nothing kept
        else:
            room[i] = _room(nearest, second, slack)


closest_facets_kept = jit(_closest_facets_kept)

# The most facets a point keeps in its short list (``closest_facets_listed``): eight, so
# that a point near a vertex of a structured face can hold the six facets that meet there
# (within micrometres of one another: a list of four had one of them for its bound and
# scanned at nearly every call; docs/theory.md §9.3). On the two-ply fibrous hemisphere's
# die and holder, steps 1700-2500: whole-list scans 15929 -> 6635, the same answers
# (benchmarks/tool_short_lists.py).
SHORT = 8
# The fewest it keeps where it cannot hold every candidate: lengthened up to SHORT only
# where that takes the room past half of SHORT's (the fan round a vertex), since a short
# pass costs a closest point a facet listed (eight everywhere: the slow Mindlin strokes,
# answered mostly from their lists, 1-8 % slower in their tools' calls).
SHORT_LEAST = 4


def _copy_row(table, source, to, row):
    """to[row] = table[source]: a facet's corners and normal (4, 3) from one table of them
    (``candidate_rows``) to another."""
    for a in range(4):
        for b in range(3):
            to[row, a, b] = table[source, a, b]


_copy_row = lane_rows(_copy_row)


def _closest_facets_listed(
    x, corners, slack, start, facets, rows, spheres, hint, anchor, room, kept_facet,
    near_anchor, near_room, near_cut, near, value, at, near_facets, point, facet, gap,
):  # fmt: skip
    """``_closest_facets_kept`` with a short list between the kept facet and the scan: at a
    scan of point i's candidates (at ``near_anchor[i]``), its nearest of them are kept in
    ``near[i]`` (k, SHORT) (in the candidates' order; -1 past the last: every candidate where
    they fit, else SHORT_LEAST, or more while that doubles the room), with ``near_cut[i]``
    the next one's distance (or a lower bound of it: the bounding sphere's for a facet
    skipped), and ``near_room[i]`` half the gap from the nearest to it, less the rounding
    allowance of ``_closest_facets_kept``'s room. While the point lies less than
    ``near_room[i]`` from that place, every facet off the list is still further than the
    nearest on it (each other's distance shrunk by less, the nearest's grown by less), so
    the list alone is scanned, in the candidates' order (the first of equal distances
    kept, as the scan keeps it), and anchor and room are set anew from it (the facets off
    the list then at least ``near_cut[i]`` less the move away). ``value`` and ``at`` (k,
    SHORT + 1) are scratch: the SHORT + 1 smallest distances of a scan and their places in
    ``facets``. A near_room of -1 asks for the scan. The same point, facet and gap as
    ``_closest_facets``, to the last bit (docs/theory.md §9.3).

    The facets are read from copies in the order they are used, not from the tool's arrays
    by facet (the die's 71k facets scattered over megabytes, which a step's other work
    evicts from the caches between calls; the same numbers: the same floats): each
    candidate's ``rows[j]`` (m, 4, 3), facet facets[j]'s corners (3, 3) and its normal in
    the last row, and ``spheres[j]`` (m, 4), its bounding sphere's centre and radius
    (``candidate_rows``), so that a scan reads its point's candidates in a row; and per
    point, ``kept_facet[i]`` (k, 4, 3) and ``near_facets[SHORT i + s]`` (k SHORT, 4, 3), the
    kept facet's and the short list's rows, written where ``room[i]`` and ``near_room[i]``
    are (read only while those are > 0), so that ``kept_facet[i]`` is always the rows of
    ``facet[i]`` for a point with candidates. Measured on the hemisphere die's 441 points,
    one thread: 36-53 us a call with the caches flushed against 10-16 with them warm
    (benchmarks/forming_one_ply_step.py)."""
    short = near.shape[1]
    for i in prange(x.shape[0]):
        p0, p1, p2 = x[i, 0], x[i, 1], x[i, 2]
        f = hint[i]
        if _kept_answers(i, p0, p1, p2, kept_facet, i, f, anchor, room, point, facet, gap):
            continue
        if near_room[i] > 0.0:
            moved = np.sqrt(
                (p0 - near_anchor[i, 0]) ** 2
                + (p1 - near_anchor[i, 1]) ** 2
                + (p2 - near_anchor[i, 2]) ** 2
            )
            if moved < near_room[i]:
                best = np.inf
                second = near_cut[i] - moved  # every facet off the list is further
                chosen = short * i  # the nearest's row of near_facets
                for s in range(short):
                    g = near[i, s]
                    if g < 0:
                        break
                    q0, q1, q2, d = _squared_gap(p0, p1, p2, near_facets, short * i + s)
                    if d < best:
                        second = min(second, np.sqrt(best))
                        best = d
                        chosen = short * i + s
                        facet[i] = g
                        point[i, 0], point[i, 1], point[i, 2] = q0, q1, q2
                    else:
                        second = min(second, np.sqrt(d))
                nearest = np.sqrt(best)
                gap[i] = nearest
                anchor[i, 0], anchor[i, 1], anchor[i, 2] = p0, p1, p2
                room[i] = _room(nearest, second, slack)
                _copy_row(near_facets, chosen, kept_facet, i)
                continue
        known = np.inf
        if f >= 0:
            known = np.sqrt(_squared_gap(p0, p1, p2, corners, f)[3]) * (1.0 + SLACK)
            known += slack
        best = np.inf
        second = np.inf  # the next facet's distance, or a lower bound of it (mm)
        kept = 0  # how many of value[i] hold the scan's smallest distances so far
        chosen = start[i]  # the nearest's row of rows
        for sweep in range(2):
            for j in range(start[i], start[i + 1]):
                g = facets[j]
                skipped = False
                if sweep == 0:
                    reach = known + spheres[j, 3]
                    apart = (
                        (spheres[j, 0] - p0) ** 2
                        + (spheres[j, 1] - p1) ** 2
                        + (spheres[j, 2] - p2) ** 2
                    )
                    if apart > reach * reach:
                        bound = np.sqrt(apart) - spheres[j, 3]
                        second = min(second, bound)
                        skipped = True
                if not skipped:
                    q0, q1, q2, d = _squared_gap(p0, p1, p2, rows, j)
                    if d < best:
                        second = min(second, np.sqrt(best))
                        best = d
                        chosen = j
                        facet[i] = g
                        point[i, 0], point[i, 1], point[i, 2] = q0, q1, q2
                    else:
                        second = min(second, np.sqrt(d))
                    bound = np.sqrt(d)
                # The smallest SHORT + 1 distances (or bounds) so far, in order.
                if kept < value.shape[1] or bound < value[i, kept - 1]:
                    slot = min(kept, value.shape[1] - 1)
                    while slot > 0 and value[i, slot - 1] > bound:
                        value[i, slot] = value[i, slot - 1]
                        at[i, slot] = at[i, slot - 1]
                        slot -= 1
                    value[i, slot] = bound
                    at[i, slot] = j
                    kept = min(kept + 1, value.shape[1])
            if sweep == 1 or best <= known * known:
                break
            best = np.inf  # none kept as near as the hint's: scan them all
            second = np.inf
            kept = 0
        nearest = np.sqrt(best)
        gap[i] = nearest
        anchor[i, 0], anchor[i, 1], anchor[i, 2] = p0, p1, p2
        near_anchor[i, 0], near_anchor[i, 1], near_anchor[i, 2] = p0, p1, p2
        if start[i] == start[i + 1]:
            room[i] = -1.0  # no candidates: nothing kept
            near_room[i] = -1.0
            continue
        room[i] = _room(nearest, second, slack)
        _copy_row(rows, chosen, kept_facet, i)
        # The short list: the nearest in the candidates' order (an insertion sort of their
        # places), and how far the point may go keeping the nearest on it. Every candidate
        # where they all fit (no cut); else the SHORT_LEAST nearest, or more while the next
        # one's distance is less than half way from the nearest to the (SHORT + 1)th: the
        # list of ``listed`` facets has the room of that next one, whatever ``listed`` is,
        # and a short pass costs a closest point a facet listed.
        listed = min(kept, short)
        if kept > short:
            listed = min(SHORT_LEAST, short)
            half = 0.5 * (value[i, short] - nearest)
            while listed < short and value[i, listed] - nearest < half:
                listed += 1
        for s in range(1, listed):
            place = at[i, s]
            slot = s
            while slot > 0 and at[i, slot - 1] > place:
                at[i, slot] = at[i, slot - 1]
                slot -= 1
            at[i, slot] = place
        for s in range(short):
            near[i, s] = facets[at[i, s]] if s < listed else -1
            if s < listed:
                _copy_row(rows, at[i, s], near_facets, short * i + s)
        cut = value[i, listed] if kept > short else np.inf
        near_cut[i] = cut
        near_room[i] = _room(nearest, cut, slack)


closest_facets_listed = jit(_closest_facets_listed)


def candidate_rows(
    facets: np.ndarray, corners: np.ndarray, normals: np.ndarray, centroids: np.ndarray,
    radius: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """The candidates' copies ``closest_facets_listed`` reads, in the order of ``facets``
    (m,): (rows (m, 4, 3), each facet's corners (f, 3, 3) and its normal (f, 3) in the last
    row; spheres (m, 4), its centroid (f, 3) and the radius (f,) of its bounding sphere)."""
    rows = np.empty((len(facets), 4, 3))
    spheres = np.empty((len(facets), 4))
    # One compiled pass of copies, the same floats as numpy's gathers: 0.45 against 1.29 ms
    # on the hemisphere die's 72001 facets and 8200 candidates (a default run's mean lists),
    # load 5.6 (1.46 against 6.43 at 8.7); made anew at each search, 280 and 518 times in
    # the forming case's fibrous and Mindlin runs (benchmarks/report_gc.py --rows).
    candidate_copies(facets, corners, normals, centroids, radius, rows, spheres)
    return rows, spheres


def _candidate_copies(facets, corners, normals, centroids, radius, rows, spheres):
    """rows[j] = (corners[facets[j]], normals[facets[j]]) (m, 4, 3) and spheres[j] =
    (centroids[facets[j]], radius[facets[j]]) (m, 4) for each candidate j of ``facets``
    (m,), indices into the tool's facets."""
    for j in prange(facets.shape[0]):
        g = facets[j]
        for a in range(3):
            for b in range(3):
                rows[j, a, b] = corners[g, a, b]
            rows[j, 3, a] = normals[g, a]
            spheres[j, a] = centroids[g, a]
        spheres[j, 3] = radius[g]


candidate_copies = jit(_candidate_copies)


def _signed_from_closest(local, point, facet, gap, normals, tiny, d, n):
    """The signed distance and normal of each point local[i] (k, 3) from its closest point
    point[i] on facet facet[i] at distance gap[i] (RigidSurface._signed's formulas, in their
    order of operations): the side (+1, or -1 behind the facet's normal ``normals`` (f, 3)),
    d = side x gap into d (k,), and into n (k, 3) side x (local - point) / gap, or the facet's
    normal where gap <= ``tiny``. The open-edge correction of the points behind (d < 0) is
    the caller's."""
    for i in prange(local.shape[0]):
        f = facet[i]
        t0 = local[i, 0] - point[i, 0]
        t1 = local[i, 1] - point[i, 1]
        t2 = local[i, 2] - point[i, 2]
        side = -1.0 if t0 * normals[f, 0] + t1 * normals[f, 1] + t2 * normals[f, 2] < 0.0 else 1.0
        g = gap[i]
        d[i] = side * g
        if g > tiny:
            n[i, 0] = side * t0 / g
            n[i, 1] = side * t1 / g
            n[i, 2] = side * t2 / g
        else:
            n[i, 0], n[i, 1], n[i, 2] = normals[f, 0], normals[f, 1], normals[f, 2]


signed_from_closest = jit(_signed_from_closest)


def _largest_drift(x, anchor):
    """max |x - anchor| over the points (k, 3) and their coordinates, mm (0 for none): what
    RigidSurface asks of its candidate lists at every call before it looks at which points
    have moved past the margin (the numpy passes of that question cost 0.6 ms a call on the
    20k-triangle forming blank's 10k nodes, a fifth of the die's contact)."""
    largest = 0.0
    for i in range(x.shape[0]):
        for j in range(3):
            moved = abs(x[i, j] - anchor[i, j])
            if moved > largest:
                largest = moved
    return largest


largest_drift = serial(_largest_drift)


def open_edges(triangles: np.ndarray, corners: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The boundary edges of a triangulated surface (the edges of one triangle only): (start
    (f, 3, 3), a point of each facet's edge k from node k to node k + 1, mm; out (f, 3, 3),
    its unit normal in the facet's plane pointing away from the facet for a boundary edge,
    zero for an edge two facets share)."""
    pairs = np.stack([triangles, np.roll(triangles, -1, axis=1)], axis=2)  # (f, 3, 2)
    _, inverse, counts = np.unique(
        np.sort(pairs.reshape(-1, 2), axis=1), axis=0, return_inverse=True, return_counts=True
    )
    boundary = (counts[inverse.ravel()] == 1).reshape(-1, 3)
    start = corners
    along = np.roll(corners, -1, axis=1) - corners
    along /= np.linalg.norm(along, axis=2, keepdims=True)
    away = corners - np.roll(corners, 1, axis=1)  # from the opposite node to the edge's start
    away -= np.sum(away * along, axis=2, keepdims=True) * along
    away /= np.linalg.norm(away, axis=2, keepdims=True)
    return start.copy(), np.where(boundary[..., None], away, 0.0)


def closest_on_triangles(x: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray):
    """The closest point to each x (..., 3) on the triangle (a, b, c) (..., 3) of the same
    index (Ericson, Real-Time Collision Detection, 2005, §5.1.5: the Voronoi regions of the
    vertices, the edges and the face, tested in barycentric terms)."""

    def dot(u, v):
        return np.einsum("...i,...i->...", u, v)

    ab, ac, ap = b - a, c - a, x - a
    d1, d2 = dot(ab, ap), dot(ac, ap)
    bp, cp = x - b, x - c
    d3, d4 = dot(ab, bp), dot(ac, bp)
    d5, d6 = dot(ab, cp), dot(ac, cp)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        face_v = vb / (va + vb + vc)
        face_w = vc / (va + vb + vc)
        on_ab = d1 / (d1 - d3)
        on_ac = d2 / (d2 - d6)
        on_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
    point = a + face_v[..., None] * ab + face_w[..., None] * ac
    # The regions, from the last to the first test of Ericson's order (each overwrites).
    bc_edge = (va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0)
    point = np.where(bc_edge[..., None], b + on_bc[..., None] * (c - b), point)
    ac_edge = (vb <= 0) & (d2 >= 0) & (d6 <= 0)
    point = np.where(ac_edge[..., None], a + on_ac[..., None] * ac, point)
    point = np.where(((d6 >= 0) & (d5 <= d6))[..., None], c, point)
    ab_edge = (vc <= 0) & (d1 >= 0) & (d3 <= 0)
    point = np.where(ab_edge[..., None], a + on_ab[..., None] * ab, point)
    point = np.where(((d3 >= 0) & (d4 <= d3))[..., None], b, point)
    point = np.where(((d1 <= 0) & (d2 <= 0))[..., None], a, point)
    return point


def spans(start: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """The indices start[i] .. start[i + 1] - 1 of each row i of ``rows``, row after row:
    where a CSR-like list (``start`` (k + 1,)) keeps those rows' entries."""
    counts = start[rows + 1] - start[rows]
    offsets = np.repeat(start[rows] - np.cumsum(counts) + counts, counts)
    return offsets + np.arange(counts.sum())
