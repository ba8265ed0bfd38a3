"""The cut of two growths past an outline vertex of three or more triangles (elements/
ply_projection.py, "The wedge cut"; docs/theory.md §9.3a).

At an outline vertex v whose fan holds more triangles than the two outline triangles A and B
(A with its outline edge v-x_A and its inner edge v-a, B with v-x_B and v-b), A's growth past
its outline edge reaches past v up to the line of its inner edge v-a, on its outline edge's
side, and so holds the whole wedge between the lines of v-a and v-b past v (the middle
triangles' angle mirrored through v); so does B's. Across a fold the two planes there sign a
point between them oppositely, and where the nearer changes the gap flipped from -|g| to
+|g| (tests/test_ply_wedge.py). Each growth is therefore cut by a ray from v fixed at bind in
its own triangle's barycentric coordinates. In A's plane it turns from the line of A's inner
edge past v towards A's outline edge by alpha / 2 + GAP alpha, alpha the wedge's angle (the
fan's angles at v less A's and B's: the middle triangles' mirrored through v), and B's
likewise: laid flat about v, the two cuts stand 2 GAP alpha apart about the wedge's bisector.
Where A's and B's planes already cross at bind (their normals more than FOLD apart; blended
below it, where the line is lost in the round-off of a flat fan's normals) the cut turns from
the line L where they meet past v (direction n_A x n_B) instead of the bisector, by the same
GAP alpha: there the growths' planes meet along L as the faces do along an edge. The wedge is
then held by at most one growth, with a thin gap between the two where a point beside a cut has
its closest point on the cut, signed by its triangle's normal and faded by the angle's fade
beside a growth's edge (elements/ply_fade.py), which is 0 where the point passes the growth's
plane there. The cut depends on its triangle's three corners alone: the force stays on them.
What it does not mend: the cuts are fixed at bind, and a fan that folds or shears after
moves the line where the planes meet away from them; across a fold a point between the
planes beside the gap can still have opposite signs by the two growths where the nearer
changes, the angle's fade w_a > 0 there (measured below in docs/hemisphere_plies.md).

The cut growth is the grown triangle T (elements/ply_projection.py ``grown_corners``) with
the half-plane l(lambda) = c . lambda >= 0 of each cut (c the line through the cut's ends in
homogeneous barycentric coordinates, e_v x E, positive on the triangle's side): a convex
polygon P inside T. Its closest point to p: the closest point q_T of T (the projection where
T holds it, else on T's edges) where every cut keeps q_T, else (P convex, T convex: a closest
point of P inside every half-plane would be T's) the nearest of the cuts' segments' closest
points, the segment from v (e_v) to where the ray leaves T (E). P lies inside T, so the
facing search's spheres about the triangles and their Lipschitz bounds (elements/
ply_search.py) hold P too; its exact distances to P are these.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

__all__ = ["GAP", "WedgeCuts", "closest_on_cut", "closest_on_cut_numpy", "cut_keeps"]

#: The share of the wedge's angle by which each growth's cut turns from the wedge's bisector
#: (or the line where the two planes meet) towards its own side: the gap between the two
#: growths is twice that (0: the cuts on one line; 0.5 about the bisector: the whole wedge a
#: gap).
GAP = 0.1
#: The angle between A's and B's normals at bind (rad) from which their cuts turn from the
#: line where their planes meet rather than from the wedge's bisector (blended below it).
FOLD = np.radians(10.0)
#: l(lambda) >= -KEEP counts as kept by a cut (barycentric units, as ``INSIDE``).
KEEP = 1e-9


@dataclass(frozen=True)
class WedgeCuts:
    """The cuts of the lower face's growths (module docstring).

    Attributes
    ----------
    lines : (m, 3, 3) float
        For each triangle and corner k, the coefficients c of the cut from that corner
        (l(lambda) = c . lambda >= 0 on the kept side, max |c| = 1), 0 where none.
    ends : (m, 3, 3) float
        The barycentric coordinates E of the cut's far end (where its ray leaves the grown
        triangle), e_k where none.
    """

    lines: np.ndarray
    ends: np.ndarray

    @cached_property
    def cut(self) -> np.ndarray:
        """(m,) bool: the triangle has a cut."""
        return np.any(self.lines != 0.0, axis=(1, 2))

    @cached_property
    def any(self) -> bool:
        """Some triangle has a cut."""
        return bool(self.cut.any())

    @classmethod
    def none(cls, count: int) -> WedgeCuts:
        """No cut on ``count`` triangles."""
        return cls(np.zeros((count, 3, 3)), np.tile(np.eye(3), (count, 1, 1)))

    @classmethod
    def of(cls, y: np.ndarray, nodes: np.ndarray, outline: np.ndarray, reach: np.ndarray):
        """The cuts of the triangles with corners y (m, 3, 3), mm (the reference state), node
        ids ``nodes`` (m, 3), ``open_edges`` ``outline`` (m, 3) and growths ``reach`` (m, 3)
        (barycentric units past the edge opposite corner k)."""
        from elements.ply_projection import triangle_frames
        from elements.ply_topology import padded_groups

        count = len(nodes)
        cuts = cls.none(count)
        if count == 0 or not outline.any():
            return cuts
        fans = padded_groups(nodes.ravel(), int(nodes.max()) + 1)  # (v, f) row * 3 + k
        valid = fans >= 0
        safe = np.where(valid, fans, 0)
        row, k = safe // 3, safe % 3
        # the outline edges at the corner k: opposite k + 1 (between k + 2 and k) and
        # opposite k + 2 (between k and k + 1)
        after = outline[row, (k + 1) % 3] & valid
        before = outline[row, (k + 2) % 3] & valid
        rim = after ^ before  # exactly one outline edge of the triangle ends at v
        wedge = (valid.sum(axis=1) >= 3) & (rim.sum(axis=1) == 2) & ~(after & before).any(axis=1)
        vertices = np.flatnonzero(wedge)
        if vertices.size == 0:
            return cuts
        order = np.argsort(~rim[vertices], axis=1, kind="stable")[:, :2]
        pair = np.take_along_axis(fans[vertices], order, axis=1)  # (w, 2) the two corners
        prow, pk = pair // 3, pair % 3
        pafter = np.take_along_axis(after[vertices], order, axis=1)
        # the inner edge's other end a: corner k + 1 when the outline edge is opposite k + 1
        # (it runs from k to k + 2), else k + 2
        inner = np.where(pafter, (pk + 1) % 3, (pk + 2) % 3)
        # the wedge's angle: the fan's angles at v less A's and B's (the middle triangles',
        # mirrored through v), measured in the triangles' own planes
        u_side = np.roll(y, -1, axis=1) - y  # from corner k to k + 1
        v_side = np.roll(y, -2, axis=1) - y  # to k + 2
        angles = np.arctan2(
            np.linalg.norm(np.cross(u_side, v_side), axis=-1),
            np.einsum("mki,mki->mk", u_side, v_side),
        )
        fan_angles = np.where(valid, angles[row, k], 0.0)[vertices].sum(axis=1)
        wedge_angle = fan_angles - angles[prow, pk].sum(axis=1)  # (w,)
        outer = np.where(pafter, (pk + 2) % 3, (pk + 1) % 3)  # the outline edge's other end
        v = y[prow, pk]  # (w, 2, 3)
        a = y[prow, inner]
        x = y[prow, outer]
        u = (v - a) / np.linalg.norm(v - a, axis=-1, keepdims=True)
        # in the triangle's own plane, from the line of its inner edge past v towards its
        # outline edge by (1/2 + GAP) of the wedge's angle
        across = (x - v) - np.einsum("wsi,wsi->ws", x - v, u)[..., None] * u
        across = across / np.linalg.norm(across, axis=-1, keepdims=True)
        # where A's and B's planes cross at bind (a fold already there), the growths meet
        # along that line L (direction n_A x n_B, towards the wedge): the cut turns from it,
        # not from the bisector, where the normals are FOLD or more apart, from a blend of the
        # two below (L is lost in the round-off of a flat fan's normals), and from the
        # bisector alone where L lies outside the growth's angle past v
        normals = triangle_frames(y[prow])[0]  # (w, 2, 3)
        meet = np.cross(normals[:, 0], normals[:, 1])
        sine = np.linalg.norm(meet, axis=-1)
        meet = meet / np.where(sine > 0.0, sine, 1.0)[:, None]
        towards = np.einsum("wi,wi->w", meet, u.sum(axis=1)) < 0.0
        meet = meet * np.where(towards, -1.0, 1.0)[:, None]
        # its angle in each plane from the line of the inner edge towards the outline edge
        meets = np.arctan2(np.einsum("wi,wsi->ws", meet, across), np.einsum("wi,wsi->ws", meet, u))
        room = np.pi - angles[prow, pk]  # the growth's angle past v
        fold = np.clip(np.arcsin(np.minimum(sine, 1.0)) / FOLD, 0.0, 1.0)[:, None]
        fold = np.where((meets > 0.0) & (meets < room), fold, 0.0)
        middle = (1.0 - fold) * 0.5 * wedge_angle[:, None] + fold * meets
        turn = middle + GAP * wedge_angle[:, None]
        direction = np.cos(turn)[..., None] * u + np.sin(turn)[..., None] * across
        gradients = triangle_frames(y[prow])[2]  # (w, 2, 3, 3)
        step = np.einsum("wski,wsi->wsk", gradients, direction)  # d lambda along the ray
        rows_reach = reach[prow]  # (w, 2, 3)
        start = np.eye(3)[pk]  # (w, 2, 3)
        # along the ray lambda = e_v + s step: it leaves the grown triangle where the first
        # lambda_j reaches -reach_j
        with np.errstate(divide="ignore", invalid="ignore"):
            limits = np.where(step < 0.0, (start + rows_reach) / -step, np.inf)
        length = limits.min(axis=-1)
        # the ray must enter the growth at v: every coordinate at 0 without a reach must not
        # fall, and the ray must leave within the growth
        scale = np.abs(step).max(axis=-1, keepdims=True)
        enters = np.all((start > 0.0) | (rows_reach > 0.0) | (step >= 1e-6 * scale), axis=-1)
        # and it must turn short of the outline edge: past it (a wedge wider than twice the
        # growth's angle past v, as at a re-entrant corner or a fan folded at bind) the ray
        # runs into the triangle itself and would cut part of its own face away, where the
        # growth lies on its own side of the bisector anyway: no cut there
        usable = enters & (turn < room) & np.isfinite(length) & (length > 0.0)
        length = np.where(usable, length, 1.0)
        end = start + length[..., None] * step
        line = np.cross(start, end)
        side = line.sum(axis=-1)  # at the centroid (times 3): the triangle's side
        line = line * np.where(side < 0.0, -1.0, 1.0)[..., None]
        largest = np.abs(line).max(axis=-1, keepdims=True)
        usable &= largest[..., 0] > 0.0
        line = line / np.where(largest > 0.0, largest, 1.0)
        lines, ends = cuts.lines.copy(), cuts.ends.copy()
        use = usable.ravel()
        lines[prow.ravel()[use], pk.ravel()[use]] = line.reshape(-1, 3)[use]
        ends[prow.ravel()[use], pk.ravel()[use]] = end.reshape(-1, 3)[use]
        return cls(lines, _trimmed(lines, ends))


def _trimmed(lines: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """The cuts' segments (m, 3, 3) ended where they cross a triangle's other cut: a triangle
    cut at two of its corners whose segments cross keeps, of each, only the part on the
    other's kept side (the cut growth's boundary), so that the nearest of the segments'
    closest points is a point of the cut growth (``closest_on_cut``)."""
    trimmed = ends.copy()
    eye = np.eye(3)
    for k in range(3):
        for j in range(3):
            both = np.any(lines[:, k] != 0.0, axis=1) & np.any(lines[:, j] != 0.0, axis=1)
            if j == k or not both.any():
                continue
            start = lines[:, j] @ eye[k]  # l_j at the segment's start e_k (>= 0: kept)
            end = np.einsum("mi,mi->m", lines[:, j], ends[:, k])
            crosses = both & (start >= 0.0) & (end < 0.0)
            t = np.where(crosses, start / np.where(crosses, start - end, 1.0), 1.0)
            ended = eye[k] + t[:, None] * (ends[:, k] - eye[k])
            trimmed[crosses, k] = ended[crosses]
    return trimmed


def cut_keeps(weights: np.ndarray, lines: np.ndarray) -> np.ndarray:
    """(...,) bool: every cut keeps the point of barycentric coordinates ``weights`` (..., 3);
    ``lines`` (..., 3, 3) the cuts' coefficients of its triangle."""
    return np.all(np.einsum("...kj,...j->...k", lines, weights) >= -KEEP, axis=-1)


def cut_overshoot(weights: np.ndarray, lines: np.ndarray, gradients: np.ndarray) -> np.ndarray:
    """(...,) mm: a lower bound of the in-plane distance of the point of barycentric
    coordinates ``weights`` (..., 3) past its triangle's cuts (``lines`` (..., 3, 3), the
    triangle's barycentric gradients ``gradients`` (..., 3, 3), 1/mm): -l / |grad l|, 0 or
    less where every cut keeps it."""
    level = np.einsum("...kj,...j->...k", lines, weights)
    slope = np.linalg.norm(np.einsum("...kj,...ji->...ki", lines, gradients), axis=-1)
    return np.max(np.where(slope > 0.0, -level / np.where(slope > 0.0, slope, 1.0), -np.inf), -1)


def closest_on_cut(
    p: np.ndarray,
    corners: np.ndarray,
    q: np.ndarray,
    lines: np.ndarray,
    ends: np.ndarray,
    gradients: np.ndarray | None = None,
):
    """The closest point of the cut growths (module docstring) to the points p (c, 3), from
    the grown triangles' closest points ``q`` (c, 3) (the projection where the grown triangle
    holds it, else on its edges).

    Parameters
    ----------
    corners : (c, 3, 3) float
        The triangles' corners y_k (not grown), mm.
    lines, ends : (c, 3, 3) float
        Their cuts (``WedgeCuts``).
    gradients : (c, 3, 3) float, optional
        The triangles' barycentric gradients, 1/mm, where the caller has them
        (``triangle_frames``); None: computed here. Given, and with
        ``ply_projection.COMPILED``, the compiled pass answers (elements/ply_cut_kernels.py,
        the same bits).

    Returns
    -------
    q : (c, 3) float
        The closest point of the cut growth, mm.
    cut : (c,) bool
        It lies on a cut (its segment from e_v to E, ends included).
    segment : (c, 2, 3) float
        There the barycentric coordinates of the segment's ends (e_v, E); elsewhere 0.
    along : (c,) float
        Its parameter on that segment, in [0, 1] (0 elsewhere).
    """
    from elements import ply_projection

    if ply_projection.COMPILED and gradients is not None:  # one pass, the same bits
        from elements import ply_cut_kernels

        return ply_cut_kernels.closest_on_cut(p, corners, q, lines, ends, gradients, KEEP)
    return closest_on_cut_numpy(p, corners, q, lines, ends, gradients)


def closest_on_cut_numpy(
    p: np.ndarray,
    corners: np.ndarray,
    q: np.ndarray,
    lines: np.ndarray,
    ends: np.ndarray,
    gradients: np.ndarray | None = None,
):
    """``closest_on_cut`` in numpy: the compiled pass's reference (the same arguments and
    results)."""
    from elements.ply_projection import triangle_frames

    count = len(p)
    segment = np.zeros((count, 2, 3))
    along = np.zeros(count)
    cut = np.zeros(count, dtype=bool)
    rows = np.flatnonzero(np.any(lines != 0.0, axis=(1, 2)))
    if rows.size == 0:
        return q, cut, segment, along
    c = corners[rows]
    gradients = triangle_frames(c)[2] if gradients is None else gradients[rows]
    on_q = np.einsum("cki,ci->ck", gradients, q[rows] - c[:, 0])
    on_q[:, 0] += 1.0
    kept = cut_keeps(on_q, lines[rows])
    open_ = rows[~kept]
    if open_.size == 0:
        return q, cut, segment, along
    c = corners[open_]
    best = np.full(open_.size, np.inf)
    chosen = q[open_].copy()
    start_rows = np.zeros((open_.size, 3))
    end_rows = np.zeros((open_.size, 3))
    parameter = np.zeros(open_.size)
    for k in range(3):  # the (at most two) cuts of each triangle
        present = np.any(lines[open_, k] != 0.0, axis=1)
        if not present.any():
            continue
        start = c[:, k]
        edge = np.einsum("cj,cji->ci", ends[open_, k], c) - start
        squared = np.einsum("ci,ci->c", edge, edge)
        t = np.clip(
            np.einsum("ci,ci->c", p[open_] - start, edge) / np.where(squared > 0, squared, 1.0),
            0.0,
            1.0,
        )
        point = start + t[:, None] * edge
        distance = np.linalg.norm(p[open_] - point, axis=1)
        nearer = present & (distance < best)
        best = np.where(nearer, distance, best)
        chosen[nearer] = point[nearer]
        start_rows[nearer] = np.eye(3)[k]
        end_rows[nearer] = ends[open_[nearer], k]
        parameter[nearer] = t[nearer]
    q = q.copy()
    q[open_] = chosen
    cut[open_] = np.isfinite(best)
    segment[open_, 0] = start_rows
    segment[open_, 1] = end_rows
    along[open_] = parameter
    return q, cut, segment, along


def closest_on_grown(
    p: np.ndarray,
    corners: np.ndarray,
    reach: np.ndarray,
    lines: np.ndarray | None = None,
    ends: np.ndarray | None = None,
):
    """``closest_on_cut`` from scratch: the closest point to p (c, 3) of the triangles with
    corners (c, 3, 3), mm, grown by ``reach`` (c, 3) and cut by ``lines``, ``ends``
    (c, 3, 3; None: no cut), where the plane's projection of p lies outside the cut growth.
    Without a cut, the grown triangle's closest point on its edges
    (elements/ply_projection.py ``closest_on_edges``), bit for bit."""
    from elements import ply_kernels, ply_projection
    from elements.ply_projection import INSIDE, closest_on_edges, facets, grown_corners

    # compiled, the same bits (elements/ply_kernels.py)
    edges = ply_kernels.edges_closest if ply_projection.COMPILED else closest_on_edges
    q = edges(p, grown_corners(corners, reach))
    count = len(p)
    if lines is None or ends is None or not np.any(lines != 0.0):
        return q, np.zeros(count, dtype=bool), np.zeros((count, 2, 3)), np.zeros(count)
    rows = np.flatnonzero(np.any(lines != 0.0, axis=(1, 2)))
    if ply_projection.COMPILED:
        planes = ply_kernels.facets_at(p[rows], corners[rows], np.arange(rows.size)[:, None])
    else:
        planes = facets(p[rows], corners[rows][:, None])
    n, _, gradients, gap, weights = (a[:, 0] for a in planes)
    held = (weights >= -reach[rows] - INSIDE).all(axis=-1)
    q = q.copy()
    q[rows[held]] = p[rows[held]] - gap[held, None] * n[held]
    # the cut rows' gradients, which closest_on_cut reads (only there), taken from the planes
    # (triangle_frames' to the bit) rather than computed again
    every = np.zeros((count, 3, 3))
    every[rows] = gradients
    return closest_on_cut(p, corners, q, lines, ends, every)
