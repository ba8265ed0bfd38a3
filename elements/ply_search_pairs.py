"""The ply contact's facing search over every pair of a small face compiled
(elements/ply_search.py ``FacingSearch._search``, its branch within ``EVERY_PAIR``: a Static
solve's plies, searched again after most Newton iterates): the triangles' centroids and
spheres, the points' distances to the centroids, the pairs within the spheres' bound, the
bound U of the least distance and the pairs kept below U + s, then the lists of those within
the least distance plus s, in three passes around the grown and cut distances the search
measures as before (``pair_distances``, ``_distances``).

numpy's reference is the branch itself (``ply_projection.COMPILED`` False). Each float is made
by numpy's operations in its order (no fused multiply-add: numba builds without fastmath):
the centroid (y_1 + y_2) + y_3 over 3, a squared length (x^2 + y^2) + z^2 as numpy's
reduction of three sums it, the norm its square root; the pairs in np.nonzero's order (by
point, then triangle), which every filter keeps, so that the lists' lexsort is the order they
come in. The same lists to the bit (tests/test_ply_search.py); some forty numpy calls of a
search made three compiled ones (benchmarks/ply_static_parts.py).
"""

from __future__ import annotations

import numpy as np

from elements.kernel_inputs import read_only
from femcore.jit import serial

__all__ = ["bounded_pairs", "kept_pairs", "lists_of"]


@serial
def _spheres(here, y, corners, skin, centroids, radius, apart, loose, slack):  # pragma: no cover
    """The triangles' centroids and radii, the points' distances to the centroids, their
    nearest (``loose``) and its slack, in place; the number of pairs within the bound."""
    m = y.shape[0]
    for t in range(m):
        for i in range(3):
            centroids[t, i] = (y[t, 0, i] + y[t, 1, i] + y[t, 2, i]) / 3.0
        largest = -np.inf
        for k in range(3):
            dx = corners[t, k, 0] - centroids[t, 0]
            dy = corners[t, k, 1] - centroids[t, 1]
            dz = corners[t, k, 2] - centroids[t, 2]
            squared = dx * dx + dy * dy + dz * dz
            if squared > largest:
                largest = squared
        radius[t] = np.sqrt(largest)
    count = 0
    for p in range(here.shape[0]):
        least = np.inf
        for t in range(m):
            dx = here[p, 0] - centroids[t, 0]
            dy = here[p, 1] - centroids[t, 1]
            dz = here[p, 2] - centroids[t, 2]
            distance = np.sqrt(dx * dx + dy * dy + dz * dz)
            apart[p, t] = distance
            if distance < least:
                least = distance
        loose[p] = least
        slack[p] = (least + skin) * (1.0 + 1e-9) + 1e-9 * skin
        for t in range(m):
            if apart[p, t] - radius[t] <= slack[p]:
                count += 1
    return count


@serial
def _pairs(apart, radius, slack, point, triangle):  # pragma: no cover - compiled
    """The pairs within the spheres' bound, by point then triangle (np.nonzero's order)."""
    i = 0
    for p in range(apart.shape[0]):
        for t in range(apart.shape[1]):
            if apart[p, t] - radius[t] <= slack[p]:
                point[i] = p
                triangle[i] = t
                i += 1


def bounded_pairs(here: np.ndarray, y: np.ndarray, corners: np.ndarray, skin: float):
    """The pairs (point, triangle) (c,) int whose centroid's distance less the sphere's radius
    is within the nearest centroid's distance plus ``skin`` (and a rounding), in np.nonzero's
    order; with the points' nearest centroid's distance (P,), the distances (P, m) and the
    radii (m,), mm. here (P, 3) the points, y (m, 3, 3) the triangles' corners, corners
    (m, 3, 3) the grown ones."""
    here = np.ascontiguousarray(here, dtype=float)
    count, m = len(here), len(y)
    centroids, radius = np.empty((m, 3)), np.empty(m)
    apart, loose, slack = np.empty((count, m)), np.empty(count), np.empty(count)
    pairs = _spheres(
        here,
        read_only(y),  # as the block keeps them (a caller's own y too): one build
        np.ascontiguousarray(corners, dtype=float),
        float(skin),
        centroids,
        radius,
        apart,
        loose,
        slack,
    )
    point, triangle = np.empty(pairs, dtype=np.int64), np.empty(pairs, dtype=np.int64)
    _pairs(apart, radius, slack, point, triangle)
    return point, triangle, loose, apart, radius


@serial
def _kept(
    loose, point, triangle, grown, exact, apart, radius, skin, keep, reach
):  # pragma: no cover
    upper = loose.copy()
    for i in range(point.shape[0]):
        if exact[i] and grown[i] < upper[point[i]]:
            upper[point[i]] = grown[i]
    kept = 0
    for i in range(point.shape[0]):
        p, t = point[i], triangle[i]
        reach[i] = upper[p] + skin
        keep[i] = apart[p, t] - radius[t] <= reach[i]
        kept += keep[i]
    return kept


def kept_pairs(loose, point, triangle, grown, exact, apart, radius, skin: float):
    """The pairs whose spheres' bound is within U + s (U: the least of the nearest centroid's
    distance and the uncut pairs' grown distances, per point): their rows (k,) of the pairs
    and their U + s (k,), mm. grown (c,) the pairs' grown distances, exact (c,) bool the
    pairs whose triangle has no cut."""
    keep = np.empty(len(point), dtype=np.bool_)
    reach = np.empty(len(point))
    _kept(
        loose,
        point,
        triangle,
        np.ascontiguousarray(grown, dtype=float),
        np.ascontiguousarray(exact, dtype=np.bool_),
        apart,
        radius,
        float(skin),
        keep,
        reach,
    )
    rows = np.flatnonzero(keep)
    return rows, reach[rows]


@serial
def _lists(point, distance, skin, least, count):  # pragma: no cover - compiled
    """Each point's least distance (``least``, inf-filled) and count of the pairs within it
    plus ``skin`` (``count``, zero-filled), in place; the widest count (at least 1)."""
    for i in range(point.shape[0]):
        if distance[i] < least[point[i]]:
            least[point[i]] = distance[i]
    for i in range(point.shape[0]):
        if distance[i] <= least[point[i]] + skin:
            count[point[i]] += 1
    width = 1
    for p in range(count.shape[0]):
        if count[p] > width:
            width = count[p]
    return width


@serial
def _fill(point, triangle, distance, skin, least, near):  # pragma: no cover - compiled
    """The rows of ``near`` (points, K): each point's kept triangles in the pairs' order, the
    rest of the row its first (np.repeat's padding, then the scatter of the lists)."""
    filled = np.zeros(near.shape[0], dtype=np.int64)
    for i in range(point.shape[0]):
        p = point[i]
        if distance[i] <= least[p] + skin:
            if filled[p] == 0:
                for k in range(near.shape[1]):
                    near[p, k] = triangle[i]
            near[p, filled[p]] = triangle[i]
            filled[p] += 1


def lists_of(points: int, point, triangle, distance, skin: float):
    """Each point's list (points, K) int of the triangles within its least distance plus
    ``skin``, in their rows' order, padded with its first, and the counts (points,) int:
    from the pairs (point, triangle) (c,) in np.nonzero's order and their distances (c,);
    None where a point has no pair (never in a search: its nearest centroid's triangle is
    one)."""
    point = np.ascontiguousarray(point, dtype=np.int64)
    triangle = np.ascontiguousarray(triangle, dtype=np.int64)
    distance = np.ascontiguousarray(distance, dtype=float)
    count, least = np.zeros(points, dtype=np.int64), np.full(points, np.inf)
    width = _lists(point, distance, float(skin), least, count)
    if not count.all():  # a point without a pair: numpy's padding (the branch's reference)
        return None
    near = np.empty((points, width), dtype=np.int64)
    _fill(point, triangle, distance, float(skin), least, near)
    return near, count
