"""The ply contact's fade past the lower ply's outline (elements/ply_projection.py, "Past the
outline, faded"; docs/theory.md §9.3a): the weight w in [0, 1] that multiplies a contact
point's penalty energy, W_p = w W(g), and its exact gradient, so that the contact's force, w W'
dg/dz + W dw/dz, stays the gradient of its energy where the point leaves the lower ply's face.

Two factors, each a smoothstep S(u) = 3 u^2 - 2 u^3 on [0, 1] (0 below, 1 above) of a
quantity continuous in the point, its facing triangle's corners y_k and the ends a, b of the
lower ply's outline edge nearest it, z = (p, y_1, y_2, y_3, a, b):

- past the outline (the projection past an outline edge of the facing triangle, or the point
  beside its growth), w_e = S(1 - d / D), d the distance of the point's foot on the grown
  face from the outline: d^2 = |p - q_o|^2 - g^2, q_o the outline's closest point to p (on
  its nearest edge, ``nearest_segments``) and g the gap to the grown face, so d is the
  in-plane distance to the outline on a flat ply and 0 where the point crosses the outline
  edge; D (``fade_length``) FADE times the least height of the outline triangles over their
  outline edges in the reference state: 0 before the growths' far edges (``MARGIN``), where
  a point used to pass between touching and beside. d is one function of the point whatever
  triangle faces it: the fade of before, S(1 + lambda_k / FADE) by the barycentric
  overshoot lambda_k of the facing triangle's own edge, differed between neighbouring
  growths (0.08 and 0.04 of their heights at the same point), and a point passing from one
  to the next past the outline changed its energy by the difference times W with no work
  (tests/test_ply_outline_fade.py);
- beside the growth, where the point's closest point q lies on a growth's edge off the
  triangle (the wedge next to an outline vertex that no growth's plane holds) or at a vertex
  of the outline (the facing triangle's normal signing the gap there), w_a =
  S(|h| / (SIDEWAYS |p - q|)), h the gap to the triangle's plane: 1 where p - q lies along
  the normal (SIDEWAYS = 1: the cosine of its angle to the normal at least 1), 0 where p lies
  in the plane beside the growth, the one place where the sign of g = +-|p - q| flips at a
  distance from q. Not on an edge's extension that the
  neighbour's growth holds too (``joined``): there the edge's pseudonormal signs the gap, the
  face has a side and w_a = 1 (elements/ply_projection.py, "Growths joined").

Gradients: d(d^2) = 2 (p - q_o) . (dp - (1 - t) da - t db) - 2 g dg (t the parameter of q_o
on its edge; the envelope of its minimum); dg/dz = (n, -lambda_m n) on a plane, (nu,
-lambda_m(q) nu) at an edge or a vertex (nu = (p - q) / g, lambda(q) q's coordinates: the
closest point's own gradient, elements/ply_projection.py); dw_e = -3 (1 - d / D) / D^2
d(d^2), with no division by d; d lambda_k = grad phi_k . (dp - h dn - sum_m lambda_m dy_m)
with dn/dy_m = -grad phi_m n^T (elements/ply_block_tangent.py, ``tangent``), dh/dz = (n, -lambda_m
n), d(h / g) = (dh - (h / g) dg) / g. The second derivative of w, which only the tangent
needs, is in closed form in elements/ply_fade_hessian.py (``central_fade_hessian`` here, the
central difference of this exact gradient, is its reference pass). The distance to
the outline kinks where its nearest edge changes on the concave side of a bend (its gradient
jumps, the energy stays continuous).

Stiffness (``stiffness_factor``, for the explicit step's springs). The fade's energy w W(g)
is stiffer than the penalty k along some directions of p. Beside a growth, with r = |p - q|,
theta the angle of p - q to the normal and w_a(theta) = S(cos theta / SIDEWAYS), the energy
E = W(r) w_a has in the orthonormal (r, theta) directions the Hessian [[W'' w_a, (W'/r -
W/r^2) w_a'], [., (W'/r) w_a + (W/r^2) w_a'']] (the azimuth of a vertex adds (W'/r) w_a +
(W/r^2) cot(theta) w_a' <= k, w_a' <= 0). With W'' <= k, W'/r <= k, 0 <= W'/r - W/r^2 <= k/2
and W/r^2 <= k/2 (W convex from W(0) = W'(0) = 0, W'' <= k) its largest eigenvalue is at
most k max_theta lambda_max [[w_a, |w_a'| / 2], [|w_a'| / 2, w_a + max(w_a'', 0) / 2]] =
k S''(0) / (2 SIDEWAYS^2) = 3 k, reached at theta = 90 deg (p in the triangle's plane beside
q, w_a = w_a' = 0: E ~ 1.5 k h^2 for a gap h to the plane), whatever r. (SIDEWAYS = 0.5, full
weight within 60 deg of the normal, made it 12 k; the two-ply hemisphere's explicit step is set
by these springs at the outline, and the wider fade takes 1.26 times fewer steps there with its
checks unchanged: benchmarks/ply_step_bound.py.) The past factor w_e =
S(1 - d / D) with |grad d| = 1 (d the in-plane distance on a flat ply, to an edge or a
vertex) has |grad w_e| <= 1.5 / D (max S') and ||hess w_e|| <= 6 / D^2 (|S''| <= 6 along
grad d, S'(s) / (s D^2) = 6 (1 - s) / D^2 across it at a vertex); with |grad (W w_a)| <= k r
(1 + (0.75 / SIDEWAYS)^2)^(1/2) and W w_a <= k r^2 / 2, the product's Hessian is at most k
(3 + 3 A x + 3 x^2), x = r / D, A = (1 + (0.75 / SIDEWAYS)^2)^(1/2) = 1.25, r = |p - q| = |g|: at
most the plies' half thicknesses a + b, or the point's own depth where it lies deeper (past
the outline the fade carries a point at any depth, elements/ply_projection.py "Past the
outline, deeper than the plies"); checked against central differences of the exact force
(tests/test_ply_fade_stiffness.py).
"""

from __future__ import annotations

import numpy as np

from elements.ply_projection import Facing, facets, triangle_frames
from elements.ply_wedge import closest_on_grown

__all__ = [
    "EVERY_PAIR",
    "FADE",
    "SIDEWAYS",
    "every_segment",
    "central_fade_hessian",
    "fade_length",
    "nearest_segments",
    "OutlineTree",
    "TREE_MOVE",
    "outline_fade",
    "outline_segments",
    "point_fade",
    "stiffness_factor",
    "tree_segments",
]

#: The fade's length past the outline in times the least height of the outline triangles
#: (< MARGIN = 0.5, the growths' reach in the same units).
FADE = 0.15
#: |h| / |p - q| (the cosine of p - q's angle with the normal) from which a point beside a
#: growth's edge has its full weight.
SIDEWAYS = 1.0


#: The largest stiffness of the angle's fade beside a growth, in times the penalty k: S''(0) /
#: (2 SIDEWAYS^2) (module docstring, "Stiffness").
SIDEWAYS_STIFFNESS = 3.0 / SIDEWAYS**2


def _step(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """S(u) = 3 u^2 - 2 u^3 clamped to [0, 1], and dS/du."""
    u = np.clip(u, 0.0, 1.0)
    return u * u * (3.0 - 2.0 * u), 6.0 * u * (1.0 - u)


def fade_length(corners: np.ndarray, outline: np.ndarray) -> float:
    """The fade's length D, mm: ``FADE`` times the least height of the triangles with corners
    ``corners`` (m, 3, 3) over their outline edges (``outline`` (m, 3) bool, the edge opposite
    corner k), so that w = 0 before the growths' far edges (``MARGIN`` heights past the
    outline) while the triangles keep heights above FADE / MARGIN of the least; inf without
    an outline."""
    if not outline.any():
        return float(np.inf)
    gradients = triangle_frames(corners)[2]
    heights = 1.0 / np.linalg.norm(gradients, axis=-1)  # (m, 3): over the edge opposite k
    return float(FADE * heights[outline].min())


def outline_segments(outline: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The outline's edges as (rows (E,), corners (E, 2)): each edge's triangle row and the
    corners k + 1, k + 2 (mod 3) at its ends, over ``outline`` (m, 3) bool (the edge opposite
    corner k of each triangle)."""
    rows, k = np.nonzero(outline)
    ends = np.column_stack([(k + 1) % 3, (k + 2) % 3])
    return rows, ends


def _segment_squared(rel: np.ndarray, e: np.ndarray, squared: np.ndarray) -> np.ndarray:
    """(k,) squared distances of points from segments, pair by pair, from p - a ``rel``
    (k, 3), the segments' b - a ``e`` (k, 3) and |b - a|^2 ``squared`` (k,): the same
    operations, in the same order, for any pairing, so that a distance has the same bits
    whichever pairs are measured together."""
    t = np.clip(np.einsum("ki,ki->k", rel, e) / squared, 0.0, 1.0)
    r = rel - t[:, None] * e
    return np.einsum("ki,ki->k", r, r)


#: Below this many point-edge pairs the nearest edge measures every pair: a KD-tree's build
#: and queries cost more there (crossing at 5000-10000 pairs, benchmarks/ply_fade.py).
EVERY_PAIR = 8192


def nearest_segments(
    p: np.ndarray, starts: np.ndarray, ends: np.ndarray, kept: OutlineTree | None = None
) -> np.ndarray:
    """(c,) int: the segment (from ``starts`` (E, 3) to ``ends`` (E, 3)) nearest each point
    p (c, 3); ties to the lowest index. The same answer, bit for bit, by measuring every pair
    (up to ``EVERY_PAIR`` pairs, ``every_segment``) or the segments a KD-tree finds near the
    point (``tree_segments``, its tree kept in ``kept`` between calls where given;
    tests/test_ply_outline_nearest.py). Non-finite coordinates (a trial state that blew up)
    are measured pair by pair too, as before the tree: the tree refuses them, and the
    caller's own finiteness check decides what such a state is."""
    small = len(p) * len(starts) <= EVERY_PAIR
    if small or not (
        np.isfinite(p).all() and np.isfinite(starts).all() and np.isfinite(ends).all()
    ):
        return every_segment(p, starts, ends)
    return tree_segments(p, starts, ends, kept)


def every_segment(p: np.ndarray, starts: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """``nearest_segments`` by measuring every segment against every point (c E work, in
    blocks of about a million pairs)."""
    chosen = np.zeros(len(p), dtype=np.int64)
    if len(p) == 0 or len(starts) == 0:
        return chosen
    e = ends - starts
    squared = np.maximum(np.einsum("ei,ei->e", e, e), np.finfo(float).tiny)
    block = max(1, 2**20 // len(starts))
    for first in range(0, len(p), block):  # blocks of points, not a loop over points
        rel = p[first : first + block, None, :] - starts[None]
        t = np.clip(np.einsum("cei,ei->ce", rel, e) / squared, 0.0, 1.0)
        r = rel - t[..., None] * e
        chosen[first : first + block] = np.argmin(np.einsum("cei,cei->ce", r, r), axis=1)
    return chosen


#: How far the outline's edges' ends may move from where a kept tree sampled them, in times
#: the tree's bound ``half`` at its build, before the tree is built again (``OutlineTree``).
TREE_MOVE = 0.25


class OutlineTree:
    """The KD-tree of ``tree_segments`` kept between calls over the same outline: its
    samples' owners and each segment's count of them, the ends it sampled and its bound
    ``half`` there. A sample lies at a fixed place between its segment's ends, so it moves no
    more than the ends' largest move m since the build: a segment not measured is then no
    nearer than reach_k - m - half (half of the pieces' current lengths), and the search
    widens its bound by m; the answer is that of a fresh tree, bit for bit (the distances
    measured at the current ends). Built again when m passes ``TREE_MOVE`` of the build's
    half (a wider bound measures more pairs) or the outline's size changes."""

    def __init__(self) -> None:
        self.builds = 0
        self.tree = None  # the cKDTree over the samples; None before the first build
        self.starts = self.ends = np.zeros((0, 3))  # (E, 3) the ends it sampled, mm
        self.owner = np.zeros(0, dtype=np.int64)  # (s,) each sample's segment
        self.pieces = np.zeros(0, dtype=np.int64)  # (E,) each segment's samples
        self.half = 0.0  # its bound there, mm

    def moved(self, starts: np.ndarray, ends: np.ndarray) -> float:
        """The largest move of the outline's edges' ends (E, 3) since the build, mm (inf
        before the first build or where the outline's size changed; NaN passes through)."""
        if self.tree is None or self.starts.shape != starts.shape:
            return np.inf
        return float(
            np.sqrt(
                max(
                    np.einsum("ei,ei->e", starts - self.starts, starts - self.starts).max(),
                    np.einsum("ei,ei->e", ends - self.ends, ends - self.ends).max(),
                )
            )
        )


def _sampled(starts: np.ndarray, e: np.ndarray, lengths: np.ndarray):
    """The samples of segments from ``starts`` (E, 3) along ``e`` (E, 3) of ``lengths`` (E,)
    (``tree_segments``): owners (s,), places along their segments (s,), pieces (E,)."""
    edges = len(starts)
    spacing = max(float(np.median(lengths)), 0.25 * float(lengths.mean()), np.finfo(float).tiny)
    pieces = np.maximum(np.ceil(lengths / spacing), 1.0).astype(np.int64)
    owner = np.repeat(np.arange(edges), pieces)
    first_piece = np.cumsum(pieces) - pieces
    along = (np.arange(owner.size) - first_piece[owner] + 0.5) / pieces[owner]
    return owner, along, pieces


def tree_segments(
    p: np.ndarray, starts: np.ndarray, ends: np.ndarray, kept: OutlineTree | None = None
) -> np.ndarray:
    """``nearest_segments`` measuring only the segments that can be nearest, found with a
    KD-tree over samples of the segments: each segment's midpoint, a long one's pieces'
    midpoints (the pieces no longer than the larger of the median segment and a quarter of
    the mean), so that every point of a segment lies within ``half`` of one of its samples,
    and a segment is no nearer to p than |p - s| - half, s its nearest sample. The segments
    of the k nearest samples give a least distance delta; a segment not among them is
    nearer only if the k-th sample lies within delta + half: k doubles for those points (the
    bound padded by 1e-9 of the model's size, far above the round-off of the distances, and
    each pair's distance the same operations as in ``every_segment``, so that the least has
    the same bits). About c log E work against c E: 1200 outline edges against 5000 points
    20 ms against 223 ms (benchmarks/ply_fade.py). With ``kept`` the tree of an earlier call
    serves while the ends have moved little (``OutlineTree``)."""
    from scipy.spatial import cKDTree

    count, edges = len(p), len(starts)
    chosen = np.zeros(count, dtype=np.int64)
    if count == 0 or edges == 0:
        return chosen
    e = ends - starts
    squared = np.maximum(np.einsum("ei,ei->e", e, e), np.finfo(float).tiny)
    # each segment sampled at its midpoint, a long one at the midpoints of pieces no longer
    # than the median segment (nor than a quarter of the mean: at most 5 E samples): every
    # point of a segment within ``half`` of a sample of it
    lengths = np.sqrt(squared)
    moved = np.inf if kept is None else kept.moved(starts, ends)
    build = kept is None or not moved <= TREE_MOVE * kept.half  # (NaN too)
    if build:
        owner, along, pieces = _sampled(starts, e, lengths)
        tree = cKDTree(starts[owner] + along[:, None] * e[owner])
        moved = 0.0
    else:
        assert kept is not None  # (build is True without one)
        owner, pieces, tree = kept.owner, kept.pieces, kept.tree
    half = 0.5 * float(np.max(lengths / pieces))
    if build and kept is not None:
        kept.starts, kept.ends, kept.owner, kept.pieces = starts.copy(), ends.copy(), owner, pieces
        kept.tree, kept.half = tree, half
        kept.builds += 1
    pad = 1e-9 * (float(np.abs(p).max()) + float(np.abs(starts).max()) + float(lengths.max()))
    best = np.full(count, np.inf)
    todo = np.arange(count)
    k = min(8, owner.size)
    while todo.size:  # rounds over the points still open, at most log2(samples / 8) + 1
        reach, near = tree.query(p[todo], k=k)
        reach, near = reach.reshape(len(todo), k), owner[near.reshape(len(todo), k)]
        rel = (p[todo, None, :] - starts[near]).reshape(-1, 3)
        values = _segment_squared(rel, e[near.ravel()], squared[near.ravel()]).reshape(near.shape)
        # ties to the lowest index among the least distances
        least = values.min(axis=1)
        chosen[todo] = np.where(values == least[:, None], near, edges).min(axis=1)
        best[todo] = least
        # a segment not measured has every sample beyond the k-th: it is nearer than the
        # nearest measured only if that sample is within its distance plus ``half`` (plus
        # the samples' move since a kept tree sampled them)
        bound = np.sqrt(best[todo]) + half + moved + pad
        open_ = (reach[:, -1] <= bound) & (k < owner.size)
        todo = todo[open_]
        k = min(2 * k, owner.size)
    return chosen


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
    """The fade w and its gradient of points against their facing triangles (module docstring).

    Parameters
    ----------
    p : (c, 3) float
        The contact points, mm.
    corners : (c, 3, 3) float
        Their facing triangles' corners y_k, mm.
    reach : (c, 3) float
        How far each triangle's plane reaches past the edge opposite corner k (> 0: an outline
        edge; elements/ply_projection.py ``MARGIN``).
    beside : (c,) bool
        The point's closest point lies on the triangle's growth past the outline, off the
        triangle, or at a vertex of the outline, and its gap is +-|p - q| signed by the
        triangle's normal.
    ends : (c, 2, 3) float
        The ends a, b of the outline's edge nearest each point (``nearest_segments``), mm.
    length : float
        The fade's length D (``fade_length``), mm.
    joined : (c,) bool, optional
        Of the ``beside`` points, those whose closest point lies on an edge's extension that
        the neighbour's growth holds too (elements/ply_projection.py, "Growths joined"): the
        gap is the distance to q, signed by the edge's pseudonormal, and has no angle factor
        (w_a = 1). None: none.
    lines, ends_cut : (c, 3, 3) float, optional
        The facing triangles' cuts past outline vertices of three or more triangles
        (elements/ply_wedge.py ``WedgeCuts``): a ``beside`` point's closest point is the cut
        growth's. None: no cut.

    Returns
    -------
    w : (c,) float
        The fade, in [0, 1].
    gradient : (c, 6, 3) float
        dw/dz over z = (p, y_1, y_2, y_3, a, b), 1/mm.
    """
    count = len(p)
    n, _, grad, plane, lam = (a[:, 0] for a in facets(p, corners[:, None]))
    # the gap g to the grown face and dg/dz over (p, y_1..3): the plane's, or beside a
    # growth's edge or at an outline vertex the distance to its closest point q
    gap = plane.copy()
    d_gap = np.concatenate([n[:, None, :], -lam[:, :, None] * n[:, None, :]], axis=1)
    side = np.ones(count)
    side_gradient = np.zeros((count, 6, 3))
    at = np.flatnonzero(beside)
    if at.size:
        c = corners[at]
        q = closest_on_grown(
            p[at],
            c,
            reach[at],
            None if lines is None else lines[at],
            None if ends_cut is None else ends_cut[at],
        )[0]
        r = p[at] - q
        distance = np.linalg.norm(r, axis=1)
        sign = np.where(plane[at] < 0.0, -1.0, 1.0)
        safe = np.where(distance > 0.0, sign * distance, 1.0)
        nu = r / safe[:, None]
        on_q = np.einsum("cki,ci->ck", grad[at], q - c[:, 0])
        on_q[:, 0] += 1.0
        ratio = np.where(distance > 0.0, plane[at] / safe, 1.0)
        d_plane = d_gap[at]
        d_edge = np.concatenate([nu[:, None, :], -on_q[:, :, None] * nu[:, None, :]], axis=1)
        d_ratio = (d_plane - ratio[:, None, None] * d_edge) / safe[:, None, None]
        value, rise = _step(ratio / SIDEWAYS)
        # on a joined edge the face has a side (the edge's pseudonormal's): no angle factor
        sideways = np.ones(at.size, dtype=bool) if joined is None else ~joined[at]
        side[at] = np.where(sideways, value, 1.0)
        side_gradient[at, :4] = np.where(
            ((distance > 0.0) & sideways)[:, None, None],
            (rise / SIDEWAYS)[:, None, None] * d_ratio,
            0.0,
        )
        gap[at] = sign * distance
        d_gap[at] = np.where((distance > 0.0)[:, None, None], d_edge, 0.0)
    # past the outline: the distance d of the point's projection on the face from the
    # outline, d^2 = |p - q_o|^2 - g^2 (q_o the outline's closest point), continuous across
    # growths; w_e = S(1 - d / D), dw_e = -3 (1 - d / D) / D^2 d(d^2)
    past = beside | np.any((reach > 0.0) & (lam < 0.0), axis=1)
    a, b = ends[:, 0], ends[:, 1]
    e = b - a
    t = np.clip(
        np.einsum("ci,ci->c", p - a, e) / np.maximum(np.einsum("ci,ci->c", e, e), 1e-300),
        0.0,
        1.0,
    )
    r_o = p - a - t[:, None] * e
    raw = np.einsum("ci,ci->c", r_o, r_o) - gap * gap
    # where the nearest outline edge is nearer than the face's plane (a fold, a deep point on
    # a growth's plane) d^2 < 0 is clamped to 0: w = 1 there and flat, so no gradient either
    squared = np.maximum(raw, 0.0)
    d_squared = np.zeros((count, 6, 3))
    d_squared[:, 0] = 2.0 * r_o
    d_squared[:, :4] -= 2.0 * gap[:, None, None] * d_gap
    d_squared[:, 4] = -2.0 * (1.0 - t)[:, None] * r_o
    d_squared[:, 5] = -2.0 * t[:, None] * r_o
    s = np.sqrt(squared) / length
    within = past & (s < 1.0) & (raw > 0.0)
    factor = np.where(past, _step(1.0 - s)[0], 1.0)
    slope = np.where(within, -3.0 * (1.0 - s) / length**2, 0.0)
    past_gradient = slope[:, None, None] * d_squared
    weight = factor * side
    gradient = side[:, None, None] * past_gradient + factor[:, None, None] * side_gradient
    return weight, gradient


def central_fade_hessian(
    p: np.ndarray,
    corners: np.ndarray,
    reach: np.ndarray,
    beside: np.ndarray,
    ends: np.ndarray,
    length: float,
    step: float,
    joined: np.ndarray | None = None,
    lines: np.ndarray | None = None,
    ends_cut: np.ndarray | None = None,
) -> np.ndarray:
    """(c, 6, 3, 6, 3) d2w/dz2 over z = (p, y_1, y_2, y_3, a, b), 1/mm^2: the central
    difference of ``outline_fade``'s exact gradient by ``step`` (mm) in each of the 18
    coordinates of z, made symmetric (``joined``, ``lines`` and ``ends_cut`` as there). The
    reference pass of the closed form the tangent takes (elements/ply_fade_hessian.py
    ``fade_hessian``), which it took before with the step 1e-6 (1 + max |y|) mm: 17 % off
    the force's derivative 1e-3 mm from an outline vertex, where w varies over that length
    (tests/test_ply_fade_hessian.py)."""
    count = len(p)
    hessian = np.zeros((count, 6, 3, 6, 3))
    for node in range(6):
        for axis in range(3):
            moved = []
            for sign in (1.0, -1.0):
                q, c, o = p.copy(), corners.copy(), ends.copy()
                if node == 0:
                    q[:, axis] += sign * step
                elif node < 4:
                    c[:, node - 1, axis] += sign * step
                else:
                    o[:, node - 4, axis] += sign * step
                moved.append(
                    outline_fade(q, c, reach, beside, o, length, joined, lines, ends_cut)[1]
                )
            hessian[:, node, axis] = (moved[0] - moved[1]) / (2.0 * step)
    return 0.5 * (hessian + np.transpose(hessian, (0, 3, 4, 1, 2)))


def stiffness_factor(
    band: np.ndarray, beside: np.ndarray, depth: float | np.ndarray, length: float
) -> np.ndarray:
    """An upper bound c_p >= 1 of the stiffness of the faded energy w W(g) along any direction
    of the point p, in times the penalty k (module docstring, "Stiffness").

    Parameters
    ----------
    band : (c,) bool
        The point is in the fade's band: its projection lies past an outline edge of its
        facing triangle (lambda_k < 0), or it is ``beside`` (elsewhere w = 1: c_p = 1).
    beside : (c,) bool
        Its closest point lies on a growth's edge or at an outline vertex (the angle's fade).
    depth : float or (c,) float
        The deepest gap at which each point in the band touches, mm: the plies' half
        thicknesses a + b beside a growth's edge, and a point's own depth where a growth's
        plane holds it deeper (elements/ply_projection.py, "Past the outline, deeper than the
        plies").
    length : float
        The fade's length D (``fade_length``), mm.

    Returns
    -------
    (c,) float
        (``SIDEWAYS_STIFFNESS`` = 3 beside, else 1) + 3 A x + 3 x^2 in the band (x = depth /
        D, A = 1.25), 1 elsewhere.
    """
    # (written again, operation by operation, in ply_springs_kernels._held: change both)
    x = np.asarray(depth, dtype=float) / length
    cross = np.sqrt(1.0 + (0.75 / SIDEWAYS) ** 2)
    angle = np.where(beside, max(1.0, SIDEWAYS_STIFFNESS), 1.0)
    return np.where(band | beside, angle + 3.0 * cross * x + 3.0 * x * x, 1.0)


def point_fade(facing: Facing, on: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The fade w (t,) past the outline of the points ``on`` (t,) and dw/dz (t, 6, 3), 1/mm,
    over z = (p, y_1, y_2, y_3, a, b), a and b the ends of the outline's edge nearest the
    point, as ``outline_fade`` left them on ``facing`` (1 and 0 where the facing carries
    none: the curved faces); the ply contact's loads and tangent weigh the points by them."""
    if facing.fade is None or facing.fade_gradient is None:
        return np.ones(len(on)), np.zeros((len(on), 6, 3))
    return facing.fade[on], facing.fade_gradient[on]
