"""The candidate triangles of a ply contact's facing search (elements/ply_block.py): for each
contact point, a list of lower triangles proven to hold the one nearest to it, kept between
calls while the points and the triangles have moved too little to change that.

What the list must hold. ``closest_facing`` (elements/ply_projection.py) takes the nearest of
a point's candidates by its distance to the triangle grown ``MARGIN`` past the outline edges
(to its plane where it holds the projection, else to its closest point on an edge or at a
vertex), ties to the lowest row. Its answer is the brute force's (every triangle a candidate)
exactly when the list holds every triangle within rounding of the least distance d*. The k
nearest centroids do not: the centroid of a large or stretched triangle, or of one across a
wrinkle's crest, can be further than k others' while its face is the nearest. Measured on the
two-ply Mindlin [0/90] hemisphere (10 cells, 20 N): with 6 centroids five steps flipped a
point's gap over a wrinkle, +0.13 to -0.16 mm, 1.0-1.9 N mm each; with 12 they went
(docs/hemisphere_plies.md).

The search. The centroid c_T of a triangle lies on it, and every point of the grown triangle
is within its radius r_T (the largest distance from c_T to a grown corner) of c_T, so

    |p - c_T| - r_T  <=  dist(p, T)  <=  |p - c_T|.

The nearest centroid's distance U bounds d* above; a ball query of radius U + s + max r_T
about p over a k-d tree of the centroids gives every triangle that can be within d* + s
(s the skin below); those whose bound |p - c_T| - r_T exceeds U + s are dropped unmeasured,
the rest measured exactly (Ericson's closest point on the grown triangle) and kept where
dist(p, T) <= d* + s. The list holds the nearest and every near tie: the brute force's
answer, bit for bit (the candidates' arithmetic does not depend on which others are listed).
A cut triangle (elements/ply_wedge.py) is measured to its cut growth, which lies inside its
grown triangle: where the grown distance is already past U + s >= d* + s, the cut one is too,
so that triangle is dropped, and leaves d* as it is, unmeasured (the cut growth's closest
point is numpy, the costliest part of a small search). Points over a face of up to some
two million pairs (points times triangles within ``EVERY_PAIR``: a Static solve's plies,
searched again after most Newton iterates, benchmarks/ply_relist.py; the two-ply hemisphere's
passes) take the nearest centroid and the pairs within the spheres' bound from one matrix of
the centroids' distances, in compiled passes, rather than from k-d trees, whose set-up costs
more there: the same lists (tests/test_ply_search.py).

Kept between calls (a Verlet list of skin s). The distance to a set is 1-Lipschitz in the
point, and moves by at most the largest move of a point of the set; a point of the grown
triangle at barycentric coordinates lambda moves by sum lambda_k dy_k, affine in lambda, so
its largest move is at one of the grown triangle's corners (``grown_moves``: (1 + sum_j
reach_j) dy_k - sum_j reach_j dy_j; the corner's own move dy_k on an inner triangle). The
bound before this, L_T max_k |dy_k| with L_T = 1 + 2 sum reach_T, is up to three times that
on an outline corner triangle whose far corner swings (the flange's corners of the Mindlin
hemisphere: a new epoch every 4-7 steps early in the run, 645 -> 459 epochs over its first
2623 steps, the same answers). Distances do not change when the point and the triangles
move by one translation, so the moves count less the corners' mean move t (a stack carried
down by a punch keeps its lists). With the point moved by m_p since its list was made and
every triangle's distance changed by at most M (max over T of its grown corners' largest
move), every distance moved by at most delta = m_p + M; a triangle left out was
further than d* + s then, so further than d*(now) + s - 2 delta now: while 2 delta < s (less a
thousandth of s for rounding) the list still holds the nearest and its ties. The triangles'
moves are measured from an epoch's start (the last full search); a point searched again since
then adds the move M_i they had at its search (their moves since then, less the change of t,
are at most M + M_i) and counts its own move less the change of t since its search. When a
point's delta reaches the bound, every point past ``REBUILD_SHARE`` of it is searched again
(one tree, one query for the batch); when M itself passes s / 4 (``EPOCH_SHARE``), all are
(a new epoch). An explicit step moves the plies by a small part of a cell, so a list serves
many steps; a Newton iterate that moves further is searched again: the answer is the same.

The curved faces (elements/ply_curved.py) read the whole list, not only its nearest: their
lists are made at each call (``FacingSearch.fresh``), so that the answer is the state's alone.

The skin s is ``SKIN`` times the lower face's mean edge length at bind: larger, a list serves
longer but holds more triangles, which every call's ``closest_facing`` measures.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from elements import ply_projection, ply_search_pairs
from elements.facet_search import _squared_gap, closest_on_triangles
from elements.kernel_inputs import read_only
from elements.ply_projection import MARGIN, grown_corners
from elements.ply_wedge import WedgeCuts, closest_on_grown
from femcore.jit import jit, lanes, prange

__all__ = ["REBUILD_SHARE", "SKIN", "FacingSearch", "grown_distance", "pair_distances"]

#: The skin s of the kept lists, a fraction of the lower face's mean edge length.
SKIN = 0.1
#: When a point's list must be made again, the points whose move has used this share of
#: their bound are searched with it (a batch, not a few points at every call).
REBUILD_SHARE = 0.5
#: A triangle's move M at which every list is made again (a new epoch), a share of the skin.
#: Any share below 1/2 gives the same lists' answer (module docstring); the cost is the
#: searches': at 1/8 the Mindlin [0/90] hemisphere's lists were all made again every 13
#: steps, at 1/4 every 25-29, with hardly a point searched alone (the bound's other half left
#: to each point's own move); at 5/16 the points' own searches outnumbered the epochs'
#: (benchmarks/ply_epoch.py).
EPOCH_SHARE = 0.25
#: The share of the skin that the bound 2 delta < s keeps for rounding.
ROUNDING = 1e-3
#: Points times triangles up to which a search measures every centroid's distance in one
#: matrix rather than through k-d trees (the same lists: tests/test_ply_search.py). Since the
#: matrix's passes are compiled (elements/ply_search_pairs.py) it is the faster up to about
#: four million pairs (benchmarks/ply_relist.py --crossover, one thread, load 5: 0.79 against
#: 2.61 ms at 384 x 128, the two-ply hemisphere's upper pass; 4.26 against 8.03 at 1000 x 1152;
#: 16.5 against 16.2 at 2000 x 2048); its matrix then holds 16 MB.
EVERY_PAIR = 1 << 21
#: The same for the numpy matrix (the fallback where the compiled one finds a point with no
#: pair, and the numpy path): its (r, m, 3) differences hold 134 MB at 2^21 pairs, against
#: 9.8 MB for the trees, and it takes 0.29 against 0.06 s at 1024 x 2048.
EVERY_PAIR_NUMPY = 16384


def grown_distance(p: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """(c,) the distance, mm, from each point p (c, 3) to the triangle with corners
    (c, 3, 3) (Ericson's closest point, ``closest_on_triangles``: the reference of
    ``pair_distances``)."""
    q = closest_on_triangles(p, corners[:, 0], corners[:, 1], corners[:, 2])
    return np.linalg.norm(p - q, axis=1)


def _pair_distances(x, corners, point, triangle, out):
    """out[i] (c,) = the distance, mm, from x[point[i]] (x (P, 3)) to the triangle
    ``triangle[i]`` of corners (m, 3, 3) (Ericson's closest point, compiled: the pairs of a
    search are some five per point)."""
    for i in prange(point.shape[0]):
        j = point[i]
        out[i] = np.sqrt(_squared_gap(x[j, 0], x[j, 1], x[j, 2], corners, triangle[i])[3])


_pair_distances_compiled = jit(_pair_distances)


def pair_distances(
    x: np.ndarray, corners: np.ndarray, point: np.ndarray, triangle: np.ndarray
) -> np.ndarray:
    """(c,) the distance, mm, from each point x[point] to its triangle ``triangle`` (rows of
    corners (m, 3, 3)); x (P, 3), point and triangle (c,) int."""
    out = np.empty(len(point))
    _pair_distances_compiled(
        np.ascontiguousarray(x, dtype=float),
        np.ascontiguousarray(corners, dtype=float),
        np.ascontiguousarray(point, dtype=np.int64),
        np.ascontiguousarray(triangle, dtype=np.int64),
        out,
    )
    return out


def _moves(y, epoch, reach, p, origin, shift_then, moved_then, shift, drift):
    """The kept lists' moves (``FacingSearch.near``), in the operations and order of
    ``grown_moves``: the corners' mean move t into ``shift`` (3,) (their sum row by row from
    0.0, over their count, as ``mean(axis=0)``), each point's drift |p - origin - (t -
    t_then)| + M + M_then into ``drift`` (P,), mm; returns M, the largest move off t of a
    triangle's grown corners (0 for none, NaN where a move is NaN, as ``np.max(...,
    initial=0.0)``). y, epoch (m, 3, 3) mm, reach (m, 3), p, origin (P, 3) mm, shift_then
    (P, 3), moved_then (P,)."""
    t0, t1, t2 = 0.0, 0.0, 0.0
    for t in range(y.shape[0]):
        for k in range(3):
            t0 += y[t, k, 0] - epoch[t, k, 0]
            t1 += y[t, k, 1] - epoch[t, k, 1]
            t2 += y[t, k, 2] - epoch[t, k, 2]
    count = float(3 * y.shape[0])
    t0, t1, t2 = t0 / count, t1 / count, t2 / count
    shift[0], shift[1], shift[2] = t0, t1, t2
    moved = 0.0
    for t in range(y.shape[0]):
        r0, r1, r2 = reach[t, 0], reach[t, 1], reach[t, 2]
        scale = 1.0 + ((r0 + r1) + r2)
        # sum_j reach_j (dy_j - t), each coordinate
        s0 = (
            r0 * ((y[t, 0, 0] - epoch[t, 0, 0]) - t0) + r1 * ((y[t, 1, 0] - epoch[t, 1, 0]) - t0)
        ) + r2 * ((y[t, 2, 0] - epoch[t, 2, 0]) - t0)
        s1 = (
            r0 * ((y[t, 0, 1] - epoch[t, 0, 1]) - t1) + r1 * ((y[t, 1, 1] - epoch[t, 1, 1]) - t1)
        ) + r2 * ((y[t, 2, 1] - epoch[t, 2, 1]) - t1)
        s2 = (
            r0 * ((y[t, 0, 2] - epoch[t, 0, 2]) - t2) + r1 * ((y[t, 1, 2] - epoch[t, 1, 2]) - t2)
        ) + r2 * ((y[t, 2, 2] - epoch[t, 2, 2]) - t2)
        largest = 0.0
        for k in range(3):
            d0 = scale * ((y[t, k, 0] - epoch[t, k, 0]) - t0) - s0
            d1 = scale * ((y[t, k, 1] - epoch[t, k, 1]) - t1) - s1
            d2 = scale * ((y[t, k, 2] - epoch[t, k, 2]) - t2) - s2
            squared = (d0 * d0 + d1 * d1) + d2 * d2
            if k == 0 or squared != squared or (largest == largest and squared > largest):
                largest = squared
        value = np.sqrt(largest)
        if moved == moved and (value != value or value > moved):
            moved = value
    for i in range(p.shape[0]):
        o0 = (p[i, 0] - origin[i, 0]) - (t0 - shift_then[i, 0])
        o1 = (p[i, 1] - origin[i, 1]) - (t1 - shift_then[i, 1])
        o2 = (p[i, 2] - origin[i, 2]) - (t2 - shift_then[i, 2])
        drift[i] = (np.sqrt((o0 * o0 + o1 * o1) + o2 * o2) + moved) + moved_then[i]
    return moved


_moves_compiled = lanes(_moves)


def grown_moves(move: np.ndarray, reach: np.ndarray) -> np.ndarray:
    """(m,) each triangle's largest grown-corner move, mm: the grown triangle's corners
    (``grown_corners``, affine in the corners with weights summing to one) moved by
    (1 + sum_j reach_j) dy_k - sum_j reach_j dy_j, dy (m, 3, 3) the corners' moves ``move``
    (less the common move t), reach (m, 3); the largest move of any point of the grown
    triangle, a vertex's (the move is affine over it). numpy's reference of ``_moves``."""
    r0, r1, r2 = reach[:, 0, None], reach[:, 1, None], reach[:, 2, None]
    scale = 1.0 + ((reach[:, 0] + reach[:, 1]) + reach[:, 2])
    weighted = (r0 * move[:, 0] + r1 * move[:, 1]) + r2 * move[:, 2]  # (m, 3)
    grown = scale[:, None, None] * move - weighted[:, None, :]
    squared = (grown[..., 0] * grown[..., 0] + grown[..., 1] * grown[..., 1]) + (
        grown[..., 2] * grown[..., 2]
    )
    return np.sqrt(np.max(squared, axis=1))


@dataclass(frozen=True)
class _Lists:
    """The kept lists: ``near`` (P, K) each point's candidates (padded with its first),
    ``count`` (P,) how many are its own, ``origin`` (P, 3) where it was searched, ``moved``
    (P,) the triangles' move M at its search and ``shift`` (P, 3) their mean move t then,
    ``epoch`` (m, 3, 3) the corners at the last full search."""

    near: np.ndarray
    count: np.ndarray
    origin: np.ndarray
    moved: np.ndarray
    shift: np.ndarray
    epoch: np.ndarray


class FacingSearch:
    """The candidate lists of a ply contact's points (module docstring).

    Parameters
    ----------
    reach : (m, 3) float
        How far (barycentric units) each lower triangle grows past its edge opposite corner k
        (``MARGIN`` on the outline edges, else 0).
    skin : float
        s, mm: a list holds the triangles within s of the nearest, and serves while every
        distance has moved less than s / 2.
    """

    def __init__(self, reach: np.ndarray, skin: float, cuts: WedgeCuts | None = None):
        if not skin > 0.0:
            raise ValueError(f"skin must be a positive length (mm), got {skin!r}")
        self.reach = np.ascontiguousarray(reach, dtype=float)
        self.skin = float(skin)
        # the growths' cuts (elements/ply_wedge.py): the distances to the cut triangles are
        # to their cut growths, which the facing measures
        self.cuts = cuts if cuts is not None and cuts.any else None
        grown = self.reach.sum(axis=1) > 0.0
        self._groups = (np.flatnonzero(~grown), np.flatnonzero(grown))
        self._lists: _Lists | None = None
        #: full searches and points searched since the start (for the benchmarks)
        self.searches = 0
        self.searched_points = 0

    @classmethod
    def of(cls, y: np.ndarray, outline: np.ndarray, cuts: WedgeCuts | None = None) -> FacingSearch:
        """The search of a lower face with triangles' corners y (m, 3, 3), mm, at bind and
        ``open_edges`` ``outline`` (m, 3): the skin ``SKIN`` times its mean edge length;
        ``cuts`` its growths' cuts (elements/ply_wedge.py), None: none."""
        edges = np.linalg.norm(y - np.roll(y, 1, axis=1), axis=-1)
        return cls(np.where(outline, MARGIN, 0.0), SKIN * float(edges.mean()), cuts)

    def _distances(self, x, y, corners, point, triangle, beyond=None, grown=None) -> np.ndarray:
        """``pair_distances`` to the grown triangles, to the cut growth where a triangle has
        a cut (elements/ply_wedge.py: P inside T, so the spheres still bound it). ``beyond``
        (c,) mm, None: every pair measured; else a pair whose grown distance exceeds it keeps
        that distance, a lower bound of its cut growth's (P inside T), unmeasured. ``grown``
        (c,) mm: the pairs' ``pair_distances`` where the caller has them (None: measured)."""
        distance = pair_distances(x, corners, point, triangle) if grown is None else grown.copy()
        if self.cuts is None:
            return distance
        cut = self._cut(triangle)
        if beyond is not None:
            cut &= ~(distance > beyond)
        cut = np.flatnonzero(cut)
        if cut.size:
            rows = triangle[cut]
            q = closest_on_grown(
                x[point[cut]],
                y[rows],
                self.reach[rows],
                self.cuts.lines[rows],
                self.cuts.ends[rows],
            )[0]
            distance[cut] = np.linalg.norm(x[point[cut]] - q, axis=1)
        return distance

    def _cut(self, triangle: np.ndarray) -> np.ndarray:
        """(c,) bool: the triangles ``triangle`` (c,) whose growth has a cut."""
        if self.cuts is None:
            return np.zeros(len(triangle), dtype=bool)
        # the cuts' own flags, made once (WedgeCuts.cut), where each search gathered its
        # pairs' lines twice and reduced them (about a fifth of a search of the two-ply
        # hemisphere's 384 points, benchmarks/ply_relist.py)
        return self.cuts.cut[triangle]

    def lists_for(self, count: int, m: int) -> _Lists | None:
        """The kept lists where they serve ``count`` points over ``m`` triangles (None: the
        next ``near`` makes them anew): the moves ``near`` measures are of these."""
        lists = self._lists
        if lists is None or lists.origin.shape != (count, 3) or lists.epoch.shape != (m, 3, 3):
            return None
        return lists

    def near(
        self,
        p: np.ndarray,
        y: np.ndarray,
        moves: tuple[float, np.ndarray, np.ndarray] | None = None,
    ) -> np.ndarray:
        """(P, K) int: each point's candidates (rows of y), holding its nearest grown triangle
        and every triangle within ``skin`` of it when the list was made; p (P, 3) the points,
        y (m, 3, 3) the lower triangles' corners, mm. ``moves``: ``_moves``' answer (M, t
        (3,), the drifts (P,)) at (p, y) from the lists ``lists_for`` gave, measured by the
        caller's pass (elements/ply_facing_front.py); None: measured here."""
        lists = self.lists_for(len(p), len(y))
        if lists is None:
            return self._renew(p, y)
        if moves is not None:
            moved, shift, drift = moves
        elif ply_projection.COMPILED:  # the same bits (_moves)
            shift, drift = np.empty(3), np.empty(len(p))
            moved = float(
                _moves_compiled(
                    read_only(y),  # as the block keeps them: one build (kernel_inputs.py)
                    lists.epoch,
                    self.reach,
                    read_only(p),
                    lists.origin,
                    lists.shift,
                    lists.moved,
                    shift,
                    drift,
                )
            )
        else:
            move = y - lists.epoch
            shift = move.reshape(-1, 3).mean(axis=0)  # the corners' mean move t
            moved = float(np.max(grown_moves(move - shift, self.reach), initial=0.0))
        if not moved <= EPOCH_SHARE * self.skin:  # NaN too
            return self._renew(p, y)
        if moves is None and not ply_projection.COMPILED:
            own = p - lists.origin - (shift - lists.shift)
            drift = np.linalg.norm(own, axis=1) + moved + lists.moved
        bound = 0.5 * (1.0 - ROUNDING) * self.skin
        if not np.all(drift < bound):
            rows = np.flatnonzero(~(drift < REBUILD_SHARE * bound))
            lists = self._refresh(lists, rows, p, y, moved, shift)
            self._lists = lists
        return lists.near

    def fresh(self, p: np.ndarray, y: np.ndarray) -> np.ndarray:
        """(P, K) int: the lists made at (p, y) alone, not kept. A choice that reads the whole
        list, not only its nearest (the curved faces' choice among the patches that hold the
        projection, elements/ply_curved.py), needs these: a kept list holds the triangles
        within s of the nearest when it was made, a set that depends on the calls before."""
        return self._search(p, y, np.arange(len(p)))[0]

    def _renew(self, p: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Every point searched at y: a new epoch."""
        near, count = self._search(p, y, np.arange(len(p)))
        zero = np.zeros(len(p))
        self._lists = _Lists(near, count, p.copy(), zero, np.zeros((len(p), 3)), y.copy())
        return near

    def _refresh(self, lists: _Lists, rows: np.ndarray, p, y, moved: float, shift) -> _Lists:
        """``lists`` with the points ``rows`` searched again at (p, y)."""
        near, count = self._search(p, y, rows)
        counts = lists.count.copy()
        counts[rows] = count
        width = int(counts.max())
        kept = _padded(lists.near, width)[:, :width].copy()
        kept[rows] = _padded(near, width)[:, :width]
        origin = lists.origin.copy()
        origin[rows] = p[rows]
        at_search = lists.moved.copy()
        at_search[rows] = moved
        shifts = lists.shift.copy()
        shifts[rows] = shift
        return _Lists(kept, counts, origin, at_search, shifts, lists.epoch)

    def _every_pair(self, here: np.ndarray, y: np.ndarray, corners: np.ndarray):
        """``_search``'s lists over every pair, by the compiled passes of
        elements/ply_search_pairs.py (the same lists), or None (numpy's then)."""
        point, triangle, loose, apart, radius = ply_search_pairs.bounded_pairs(
            here, y, corners, self.skin
        )
        grown = pair_distances(here, corners, point, triangle)
        exact = ~self._cut(triangle)
        rows, reach = ply_search_pairs.kept_pairs(
            loose, point, triangle, grown, exact, apart, radius, self.skin
        )
        point, triangle = point[rows], triangle[rows]
        distance = self._distances(here, y, corners, point, triangle, reach, grown[rows])
        return ply_search_pairs.lists_of(len(here), point, triangle, distance, self.skin)

    def _search(self, p: np.ndarray, y: np.ndarray, rows: np.ndarray):
        """The lists of the points ``rows`` at (p, y): (r, K) candidates padded with each
        point's first, and (r,) their counts."""
        self.searches += 1
        self.searched_points += len(rows)
        here = p[rows]
        corners = grown_corners(y, self.reach)
        if len(rows) * len(y) <= EVERY_PAIR and ply_projection.COMPILED:
            found = self._every_pair(here, y, corners)  # the same lists (ply_search_pairs.py)
            if found is not None:
                return found
        centroids = y.mean(axis=1)  # on the triangle, inside the grown one
        radius = np.sqrt(np.max(np.sum((corners - centroids[:, None]) ** 2, axis=-1), axis=1))
        if len(rows) * len(y) <= EVERY_PAIR_NUMPY:
            # a few points over a small face (a Static solve's plies, searched again after
            # most Newton iterates): one matrix of the centroids' distances costs less than
            # the trees' set-up
            apart = np.linalg.norm(here[:, None, :] - centroids[None], axis=-1)
            # the nearest centroid's distance bounds d* above (a centroid lies on its
            # triangle, which every cut keeps): the pairs within its spheres' bound, a
            # rounding looser (the spheres' test below decides), are measured to the grown
            # triangles in one compiled pass, and the least to an uncut one bounds d* closer
            loose = apart.min(axis=1)
            slack = (loose + self.skin) * (1.0 + 1e-9) + 1e-9 * self.skin
            point, triangle = np.nonzero(apart - radius[None] <= slack[:, None])
            grown = pair_distances(here, corners, point, triangle)
            exact = ~self._cut(triangle)
            upper = loose.copy()
            np.minimum.at(upper, point[exact], grown[exact])
        else:
            tree = cKDTree(centroids)
            nearest = np.asarray(tree.query(here, k=1)[1], dtype=np.int64)
            # >= the least distance d*
            upper = self._distances(here, y, corners, np.arange(len(rows)), nearest)
            # the inner triangles and the grown ones (larger spheres) queried apart, each
            # with its own largest radius: a ball query of the grown ones' radius over every
            # triangle would hand each point three times the pairs
            pairs = [
                _ball_pairs(centroids[group], here, upper + self.skin + radius[group].max(), group)
                for group in self._groups
                if group.size
            ]
            point = np.concatenate([pair[0] for pair in pairs])
            triangle = np.concatenate([pair[1] for pair in pairs])
            grown = None
        # the bounding spheres first: a triangle further than U + s cannot be within d* + s
        ahead = np.linalg.norm(here[point] - centroids[triangle], axis=1) - radius[triangle]
        reach = upper[point] + self.skin
        keep = ahead <= reach
        point, triangle, reach = point[keep], triangle[keep], reach[keep]
        # a cut triangle whose grown distance (a lower bound of its cut growth's) is past
        # U + s >= d* + s is dropped below whatever its cut distance, and leaves d* as it is
        distance = self._distances(
            here, y, corners, point, triangle, reach, None if grown is None else grown[keep]
        )
        least = np.full(len(rows), np.inf)
        np.minimum.at(least, point, distance)
        keep = distance <= least[point] + self.skin
        point, triangle = point[keep], triangle[keep]
        # each point's triangles in the order of their rows, padded with its first
        order = np.lexsort((triangle, point))
        point, triangle = point[order], triangle[order]
        count = np.bincount(point, minlength=len(rows))
        start = np.concatenate([[0], np.cumsum(count)[:-1]])
        width = int(count.max(initial=1))
        near = np.repeat(triangle[start][:, None], width, axis=1)
        near[point, np.arange(len(point)) - start[point]] = triangle
        return near, count


def _padded(near: np.ndarray, width: int) -> np.ndarray:
    """``near`` (P, K) with at least ``width`` columns, each row padded with its first."""
    if near.shape[1] >= width:
        return near
    return np.column_stack([near, np.repeat(near[:, :1], width - near.shape[1], axis=1)])


def _ball_pairs(
    centres: np.ndarray, points: np.ndarray, radii: np.ndarray, rows: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Every (point, row) pair with |points[i] - centres[j]| <= radii[i]: (point indices,
    rows[j]), int. The points within the common radius (twice the median) are matched by one
    ``sparse_distance_matrix`` of two trees (arrays out, no list per point), the few others
    by a ball query each."""
    tree = cKDTree(centres)
    common = min(float(radii.max()), 2.0 * float(np.median(radii)))
    within = np.flatnonzero(radii <= common)
    found = cKDTree(points[within]).sparse_distance_matrix(tree, common, output_type="ndarray")
    point, column = within[found["i"].astype(np.int64)], found["j"].astype(np.int64)
    wider = np.flatnonzero(radii > common)
    if wider.size:
        lists = tree.query_ball_point(points[wider], radii[wider])
        count = np.fromiter(map(len, lists), dtype=np.int64, count=len(lists))
        point = np.concatenate([point, np.repeat(wider, count)])
        column = np.concatenate([column, np.concatenate(lists).astype(np.int64)])
    return point, rows[column]
