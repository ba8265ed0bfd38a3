"""Where a ply contact point that lands in a step is anchored for that step (PlyContact with
``friction`` > 0; docs/theory.md §9.2 and §9.3a, "Friction between plies").

A point that had no stick anchor at the last accepted state (it was not touching) and touches
now takes as its anchor, for this step, the place of the lower face where its way crossed it,
so that only its tangential motion since the touch is friction's slip (the tool contact's rule,
elements/contact_history.py ``start_anchors``). The place is relative to the lower ply (which
moves too): on the plane of the triangle T the point faces now, the barycentric place of the
point's projection at the last accepted state (its face point p_0 on T's corners then, the
history's sides keep both, elements/ply_sides.py) and now (p on T's corners now),

    Lambda_a = Lambda_0 + theta (Lambda - Lambda_0),   theta = g_0 / (g_0 + pen),

g_0 = max(n_0 . (p_0 - y_0), 0) the point's gap to T's plane then, pen = max(-g, 0) its
penetration now (the normal law's gap g), the gap taken linear over the step. Exact for a flat
lower face, a way straight relative to it and T's corners moved affinely (a fixed or
translated face; a way that crosses triangles of a flat face too: the places are those of its
plane). Elsewhere a rule: on a curved or folded face the places are the planes' of T then and
now (off them by the facet's sagitta; the curved faces put the anchor on T's Phong patch at
the point's projection now less (1 - theta) times its way, the places taken along the patch's
normal at that projection, so that a point coming in along it has no tangential way), g_0
is the distance to T's plane, not the normal law's gap there; a point already through the face
then (g_0 = 0) is anchored at its place then, one touching without
penetrating (g_0 = pen = 0) at its place now.

A point whose gap is to an edge or a vertex of the lower face (``Facing.on_edge``: its closest
point q there, g = +-|p - q| along nu = (p - q) / g, not T's normal) lands by that gap
(``edge_crossing``), its zero through q taken as a plane of normal m: m = nu where the feature's
pseudonormal signs g (g passes zero at q; the plane normal to nu is its zero to first order
about the state now), m = T's normal where T's normal signs it (beside a growth's edge, at an
outline vertex, on a cut: g = sign(h) |p - q| changes sign where p passes T's plane, h = 0, and
the fade's w starts from 0 there). So g_0 = max(m . (p_0 - q_0), 0), q_0 = sum_k lambda_k y_0,k
the same point of the same edge or vertex on T's corners then (lambda its barycentric
coordinates now), pen = max(-m . (p - q), 0), theta = g_0 / (g_0 + pen); the crossing's place is
interpolated between the places then and now on T's planes, heights included (p = sum Lambda_k
y_k + h n, the crossing's height rise = h_0 + theta (h - h_0)), and moved along nu onto T's
plane, where the anchor is kept: by rise / t along nu, t = nu . n, so that the slip, measured
across nu as the friction measures it, is the way's part across nu after the crossing. Where nu
lies within TILT = 0.1 of T's plane (|t| <= 0.1, 6 deg; the move along nu grows as 1 / t) it
moves rise t / TILT^2 along nu and drops the rest, (1 - t^2 / TILT^2) rise, along n, which counts
as slip across nu: continuous across TILT, at t = 0 the whole height (there no anchor on T's
plane is off the crossing along nu), where before the whole height dropped along n below TILT
(a jump of about |rise| there). Exact for a way straight relative to the lower face that
crosses the edge's line (the gap linear over the step) with T's corners moved affinely;
elsewhere a rule. Before it such a point did not land (anchored at its projection once the step
was accepted): with g_0 T's plane's against a penetration to the edge, the hemisphere-plies
Mindlin [0/90] run's slipped up to 0.090 mm against ways of at most 0.029 mm (docs/theory.md
§9.3a). Its anchor moves with the state in the tangent, through p, T's corners and the closest
point's lambda and nu (the gap's Hessian): elements/ply_edge_landing.py ``crossing_motion``.

A face point's anchor moves with the state: dLambda_a/dz = theta dLambda/dz + (Lambda -
Lambda_0) dtheta/dz over z = (p, y_1, y_2, y_3) (T's corners now), with dtheta/dz = g_0 / (g_0 +
pen)^2 dg/dz (where pen > 0) and, on T's plane (unit normal n, barycentric gradients grad
phi_k, p = sum Lambda_k y_k + h n), dLambda_k/dp = grad phi_k^T and dLambda_k/dy_m = -Lambda_m
grad phi_k^T + h (grad phi_k . grad phi_m) n^T. The flat faces' tangent carries it
(elements/ply_friction_tangent.py ``friction_tangent``); the curved faces' tangent makes the anchor
again from each point's local data in its complex steps (elements/ply_curved_friction.py
``landing_anchor``: the projection, its normal and theta moving, the places then held), so
its derivative there is exact as the rest of that tangent; it knows the face rule alone, the
curved faces' facing marking no point's gap to an edge or a vertex. The loads, the energy,
the tangent and the accepted history at a state take one ``landing`` (the edge rows' places
in it), found once (elements/ply_landing_kept.py).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, overload

import numpy as np

from elements import ply_side_masks
from elements.ply_edge_landing import Crossing, crossing_motion
from elements.ply_projection import triangle_frames
from elements.ply_sides import TOUCHING, PlySides

if TYPE_CHECKING:
    from elements.ply_block import PlyContactBlock
    from elements.ply_friction import PlyFrictionHistory
    from elements.ply_projection import Facing
    from femcore.state import State

__all__ = [
    "TILT",
    "Landing",
    "edge_crossing",
    "landed",
    "landing",
    "landing_rows",
    "plane_places",
]

#: |nu . n| below which an edge point's anchor is not moved along nu alone onto T's plane
#: (``edge_crossing``: a share (nu . n)^2 / TILT^2 of the height along nu, the rest along n).
TILT = 0.1


@dataclass(frozen=True)
class Landing:
    """The landing points of a step and their anchors' motion (module docstring).

    rows : (r,) int
        The points that had no anchor at the last accepted state and touch now.
    rate : (r, 3) float
        Lambda - Lambda_0, the barycentric way over the step on T.
    theta : (r,) float
        The share of the way before the touch.
    dtheta : (r,) float
        g_0 / (g_0 + pen)^2, 1/mm: dtheta/dz = dtheta dg/dz (0 where pen = 0).
    weights : (r, 3) float
        Lambda, the barycentric place of the point's projection on T's plane now.
    gradients : (r, 3, 3) float
        grad phi_k of T now, 1/mm.
    normal : (r, 3) float
        T's unit normal now.
    height : (r,) float
        h = n . (p - y_1), mm.
    edge : (r,) bool or None
        The rows whose gap is to an edge or a vertex (``edge_crossing``); None: none.
    place : (r, 3) float or None
        Their anchors' barycentric places Lambda_a on T (the other rows' not used); None:
        no such row.
    crossing : Crossing or None
        What their places were made from (elements/ply_edge_landing.py), for their motion;
        None: no such row.
    """

    rows: np.ndarray
    rate: np.ndarray
    theta: np.ndarray
    dtheta: np.ndarray
    weights: np.ndarray
    gradients: np.ndarray
    normal: np.ndarray
    height: np.ndarray
    edge: np.ndarray | None = None
    place: np.ndarray | None = None
    crossing: Crossing | None = None

    def anchor_motion(
        self, gap_gradient: np.ndarray, hessian: np.ndarray | None = None
    ) -> np.ndarray:
        """(r, 3, 4, 3) dLambda_a,k/dz over z = (p, y_1, y_2, y_3), 1/mm, given dg/dz
        ``gap_gradient`` (r, 4, 3) of the rows and, where a row's gap is to an edge or a
        vertex, its Hessian d2g/dz2 ``hessian`` (r, 4, 3, 4, 3), 1/mm (``Facing.hessian``'s
        rows; elements/ply_edge_landing.py)."""
        grad, lam, n, h = self.gradients, self.weights, self.normal, self.height
        motion = np.zeros((len(self.rows), 3, 4, 3))
        motion[:, :, 0] = grad
        for m in range(3):
            motion[:, :, 1 + m] = (
                -lam[:, m, None, None] * grad
                + (h[:, None, None] * np.einsum("tki,ti->tk", grad, grad[:, m])[:, :, None])
                * n[:, None, :]
            )
        motion *= self.theta[:, None, None, None]
        motion += (self.rate * self.dtheta[:, None])[:, :, None, None] * gap_gradient[:, None]
        if self.edge is not None:  # ``edge_crossing``'s anchor
            if hessian is None or self.crossing is None:
                raise ValueError(
                    "an edge point's landing anchor moves by its crossing (Landing.crossing) "
                    "and its gap's Hessian (Facing.hessian's rows, (r, 4, 3, 4, 3)); got "
                    f"crossing {'None' if self.crossing is None else 'given'}, hessian "
                    f"{'None' if hessian is None else 'given'}"
                )
            motion[self.edge] = crossing_motion(self.crossing, hessian[self.edge], TILT)
        return motion


def plane_places(corners: np.ndarray, point: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(weights (r, 3), height (r,) mm): the barycentric places of the projections of
    ``point`` (r, 3) on the planes of the triangles ``corners`` (r, 3, 3), from their
    gradients (as elements/ply_projection.py ``facets`` computes a projection's), and its
    signed distances to them along their normals; one frame of the triangles for both (the
    landing's and the departure's places, elements/ply_departure.py)."""
    normal, _, gradients = triangle_frames(corners)
    relative = point - corners[:, 0]
    weights = np.einsum("rki,rki->rk", gradients, point[:, None, :] - corners[:, 1, None, :])
    weights[:, 1] = np.einsum("ri,ri->r", gradients[:, 1], relative)
    weights[:, 2] = 1.0 - weights[:, 0] - weights[:, 1]
    return weights, np.einsum("ri,ri->r", normal, relative)


def landing_rows(block: PlyContactBlock, history: PlyFrictionHistory, facing: Facing) -> np.ndarray:
    """(r,) the rows of the points landing at the state ``facing`` is of from the accepted
    ``history`` (``landing``: touching now, without an anchor and not touching then); none
    without friction or where the history keeps no sides. A few masks: what a step where no
    point lands costs (elements/ply_landing_kept.py asks it before its keep)."""
    sides = history.sides
    if sides is None or block.friction <= 0.0:
        return np.empty(0, dtype=np.intp)
    # (points facing an edge or a vertex among them: they land by ``edge_crossing``)
    if ply_side_masks.COMPILED:  # one pass (elements/ply_side_masks.py), the same rows
        return ply_side_masks.landing_rows(facing.touching, history.triangle, sides.sides, TOUCHING)
    return np.flatnonzero(facing.touching & (history.triangle < 0) & (sides.sides != TOUCHING))


def landing(
    block: PlyContactBlock, state: State, history: PlyFrictionHistory, facing: Facing
) -> Landing | None:
    """The landing points at ``state`` (``facing`` there, the sides held) from the accepted
    ``history``: touching now, without an anchor and not touching then (their side; a history
    whose anchors a caller dropped from touching points leaves them without friction, as
    before); None where there are none (or the history keeps no sides: no place then)."""
    rows = landing_rows(block, history, facing)
    if len(rows) == 0:
        return None
    sides = history.sides
    assert sides is not None  # (landing_rows finds none without them)
    triangle = facing.triangle[rows]
    before = sides.corners[triangle]
    then = sides.faces[rows]
    _, y = block._faces(state)
    now = y[triangle]
    p = facing.face[rows]
    old = plane_places(before, then)[0]
    normal, _, gradients = triangle_frames(now)
    weights = plane_places(now, p)[0]
    height = np.sum(normal * (p - now[:, 0]), axis=1)
    g0 = np.maximum(np.sum(triangle_frames(before)[0] * (then - before[:, 0]), axis=1), 0.0)
    pen = np.maximum(-facing.gap[rows], 0.0)
    way = g0 + pen
    safe = np.where(way > 0.0, way, 1.0)
    theta = np.where(way > 0.0, g0 / safe, 1.0)
    dtheta = np.where(pen > 0.0, g0 / safe**2, 0.0)
    rate = weights - old
    if block.curved:
        # The way's tangential part is along the lower surface, whose normal at the point's
        # projection (the Phong patch's, facing.normal) is not T's: a point coming in along it
        # has no tangential way, though its places on T's plane (taken along T's normal) move.
        # Its places along that normal instead (the flat faces' rate is the same, n = nu).
        along = facing.normal[rows]
        rate = (
            plane_places(now, _onto_plane(now, p, along))[0]
            - plane_places(before, _onto_plane(before, then, along))[0]
        )
    edge, place, crossing = None, None, None
    if facing.on_edge is not None and facing.on_edge[rows].any():
        # gaps to an edge or a vertex: theta and the anchor by that gap (docstring)
        edge = facing.on_edge[rows]
        at = np.flatnonzero(edge)
        place = np.full((len(rows), 3), np.nan)
        crossing = edge_rows_crossing(facing, sides, y, rows[at])
        # the gap's zero through q: normal to nu, or T's plane where T's normal signs the gap
        # (beside a growth's edge, at an outline vertex, on a cut: docstring)
        zero = np.where(crossing.plane[:, None], normal[at], crossing.normal)
        theta[at], place[at] = edge_crossing(
            crossing.before, crossing.now, crossing.then, crossing.point, crossing.feature,
            crossing.normal, zero,
        )  # fmt: skip
        dtheta[at] = 0.0  # (their motion: ``crossing_motion``)
    return Landing(
        rows, rate, theta, dtheta, weights, gradients, normal, height, edge, place, crossing
    )


def edge_rows_crossing(
    facing: Facing, sides: PlySides, y: np.ndarray, points: np.ndarray
) -> Crossing:
    """What ``edge_crossing`` takes for the landing points ``points`` (e,) int whose gap is to
    an edge or a vertex (``Crossing``): their facing triangles' corners then (the history's
    ``sides``) and now (``y`` (m, 3, 3) mm), the points then and now, their closest points'
    coordinates and gap normals, and whether their gap's zero is T's plane (beside a growth's
    edge, not joined: module docstring)."""
    triangle = facing.triangle[points]
    plane = np.zeros(len(points), dtype=bool)
    if facing.on_growth is not None and facing.joined is not None:
        plane = facing.on_growth[points] & ~facing.joined[points]
    return Crossing(
        sides.corners[triangle], y[triangle], sides.faces[points], facing.face[points],
        facing.weights[points], facing.normal[points], plane,
    )  # fmt: skip


def edge_crossing(
    before: np.ndarray,
    now: np.ndarray,
    then: np.ndarray,
    point: np.ndarray,
    feature: np.ndarray,
    normal: np.ndarray,
    zero: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """(theta (r,), place (r, 3)): where the way of points landing on an edge or a vertex of
    their triangles T crossed their gap's zero (module docstring), and the barycentric place
    on T now of the anchor there.

    Parameters
    ----------
    before, now : (r, 3, 3) float
        T's corners at the last accepted state and now, mm.
    then, point : (r, 3) float
        The points' contact points then (p_0) and now (p), mm.
    feature : (r, 3) float
        The barycentric coordinates on T of the closest point q now (``Facing.weights``).
    normal : (r, 3) float
        nu = (p - q) / g now (``Facing.normal``), across which the slip is measured.
    zero : (r, 3) float
        The unit normal m of the gap's zero through q: nu, or T's normal where T's normal
        signs the gap (its zero T's plane).

    Returns
    -------
    theta = g_0 / (g_0 + pen), g_0 = max(m . (p_0 - q_0), 0), q_0 = sum_k lambda_k y_0,k the
    same point of T then, pen = max(-m . (p - q), 0) (1 where both vanish); and Lambda_a, the
    crossing's place (the places and heights then and now on T's planes, interpolated by
    theta) moved along nu onto T's plane (where |nu . n| <= TILT a share (nu . n)^2 / TILT^2 of
    that move, the rest of the height along T's normal).
    """
    q0 = np.einsum("rk,rki->ri", feature, before)
    q = np.einsum("rk,rki->ri", feature, now)
    g0 = np.maximum(np.einsum("ri,ri->r", zero, then - q0), 0.0)
    way = g0 + np.maximum(-np.einsum("ri,ri->r", zero, point - q), 0.0)
    theta = np.where(way > 0.0, g0 / np.where(way > 0.0, way, 1.0), 1.0)
    old, old_height = plane_places(before, then)
    new, height = plane_places(now, point)
    place = old + theta[:, None] * (new - old)
    rise = old_height + theta * (height - old_height)  # the crossing's height over T's plane
    plane, _, gradients = triangle_frames(now)
    tilt = np.einsum("ri,ri->r", plane, normal)
    # onto T's plane along nu (rise / tilt: the anchor off the crossing along nu alone); where
    # nu lies within TILT of the plane a share tilt^2 / TILT^2 of that, the rest of the height
    # dropped along n (counted as slip across nu: (1 - tilt^2 / TILT^2) |rise| at most),
    # continuous across TILT (module docstring)
    steep = np.abs(tilt) > TILT
    along = np.where(steep, rise / np.where(steep, tilt, 1.0), rise * tilt / TILT**2)
    place -= along[:, None] * np.einsum("rki,ri->rk", gradients, normal)
    return theta, place


def _onto_plane(corners: np.ndarray, point: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """(r, 3) ``point`` (r, 3) moved along ``direction`` (r, 3) onto the planes of the
    triangles ``corners`` (r, 3, 3); moved along the planes' normals where ``direction``
    lies (nearly) in them."""
    normal = triangle_frames(corners)[0]
    height = np.sum(normal * (point - corners[:, 0]), axis=1)
    slant = np.sum(normal * direction, axis=1)
    usable = np.abs(slant) > 0.5  # within 60 deg of the plane's normal
    direction = np.where(usable[:, None], direction, normal)
    slant = np.where(usable, slant, 1.0)
    return point - (height / slant)[:, None] * direction


@overload
def landed(
    block: PlyContactBlock,
    state: State,
    history: PlyFrictionHistory,
    facing: Facing,
    found: Landing | None = None,
) -> PlyFrictionHistory: ...


@overload
def landed(
    block: PlyContactBlock,
    state: State,
    history: None,
    facing: Facing,
    found: Landing | None = None,
) -> None: ...


def landed(
    block: PlyContactBlock,
    state: State,
    history: PlyFrictionHistory | None,
    facing: Facing,
    found: Landing | None = None,
) -> PlyFrictionHistory | None:
    """``history`` with its landing points (``landing``, or ``found``) anchored for this
    step on the triangle they face at Lambda_a = Lambda_0 + theta (Lambda - Lambda_0); the
    history itself (the same object) where no point lands."""
    if history is None:
        return None
    found = landing(block, state, history, facing) if found is None else found
    if found is None:
        return history
    triangle = np.array(history.triangle, copy=True)
    anchor = np.array(history.anchor, dtype=float, copy=True)
    triangle[found.rows] = facing.triangle[found.rows]
    # From the point's projection now, not its place on T's plane: the two are one on a flat
    # face; on a curved one (the anchor on T's Phong patch) the plane's place is off the
    # projection, and a point landing along the normal would slip by that difference.
    anchor[found.rows] = facing.weights[found.rows] - (1.0 - found.theta)[:, None] * found.rate
    if found.edge is not None and found.place is not None:  # at its crossing (``edge_crossing``)
        anchor[found.rows[found.edge]] = found.place[found.edge]
    return replace(history, triangle=triangle, anchor=anchor)
