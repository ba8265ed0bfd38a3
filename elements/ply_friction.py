"""Coulomb friction between two plies (elements/ply_contact.py's PlyContact with
``friction`` > 0; docs/theory.md §9.3a): the stick anchors on the lower ply's face, the return
mapping, its loads, and the history after an accepted step; the loads' exact tangent is
elements/ply_friction_tangent.py's (``friction_tangent``, re-exported here).

Each touching contact point keeps an anchor on the lower face (a triangle and barycentric
coordinates, so it slides with the lower ply); the tangential offset of the point from it loads
a spring capped at mu times the point's normal force N. The spring's stiffness k_t is the
normal law's own (PlyContact's ``stick="normal law"``, the default), k_t = dN/d(-g) = W''(g)
(times the fade's w past the outline): k_p once the point is pressed deeper than the
smoothing delta, and k_p |g| / delta on the smoothed penalty's ramp, where N = k_p g^2 /
(2 delta); or the point's penalty k_p at any depth (``stick="penalty"``). The elastic slip at
the friction limit, mu N / k_t, is then mu |g| / 2 on the ramp (mu (|g| - delta / 2) deeper,
as with k_p): it vanishes with the penetration, where with k_t = k_p it vanishes with N, as
g^2.
Points laid on the face with nearly no normal force stick on a spring as soft as their
normal one instead of switching between stick and slip on a cone of radius mu N / k_p, far
below the slips a Newton iterate makes there (docs/theory.md §9.3a, "Friction between
plies"; benchmarks/ply_friction_laid.py).

The stick potential. A stuck point's energy is E = k_t |s|^2 / 2 = w W''(g) |s|^2 / 2 (its
record |F|^2 / (2 k_t)); with k_t = w W'' it depends on g and on the fade's w as well as on s,
so its gradient at fixed s is the tangential force k_t s plus a normal force dE/dg dg/dz =
w W'''(g) |s|^2 / 2 (n, -lambda_k n) (``Sliding.lift``: W''' = -k_p / delta on the ramp, so
it pushes the plies apart, by at most mu^2 N / 4 where |s| <= mu |g| / 2; 0 deeper) and, past
the outline, W'' |s|^2 / 2 dw/dz (``Sliding.stored``) on the point's, the facing triangle's and
the outline edge's nodes, as the normal law's own w W carries them. s is measured across the
facing normal n, which turns with the facing triangle's corners y_m, and dE/dy_m also holds
k_t s . ds/dy_m = -k_t (n . r) s . dn/dy_m, the couple of F and -F a distance n . r ~ g
apart: on a plane dn/dy_m = -grad phi_m n^T, so it is k_t (n . r)(s . grad phi_m) n on
corner m (``stick_couple``; a fraction ~ |g| / l of F, l the triangle's size). The loads
carry the three and the tangent their derivative (elements/ply_friction_tangent.py
``_potential_tangent``, ``_couple_tangent``). A point facing an edge or a vertex
(``Facing.on_edge``), whose n turns with p and the corners as the gap's Hessian says, carries
its couple C_w on p and the facing corners (``edge_couples``, elements/ply_edge_couple.py),
and the tangent its derivative
(``edge_couple_tangent``); E's gradient, and the loads, jump where the closest point passes
between a plane and an edge (the gap's Hessian does). With ``stick="penalty"`` E = k_p |s|^2
/ 2 holds no g: its gradient is F and the couple. A sliding point's force mu N s / |s| is no
gradient (friction dissipates); its energy record stays the spring's at the limit, |F|^2 / (2 k_t) =
(mu N)^2 / (2 k_t), the elastic part of its offset (what it gives back when unloaded,
continuous with E at the switch), with no normal force nor couple added: the normal force
jumps by the stuck point's lift as the point starts sliding.
On the curved faces the return mapping is this module's; the loads (the stuck points' whole
gradient of E, the couple across the curved face's turning normal included) and their tangent
are elements/ply_curved_friction.py's.
Used by ``PlyContactBlock``; the functions take the block as their first argument.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from elements import (
    ply_departure,
    ply_edge_couple_kernels,
    ply_landing,
    ply_projection,
    ply_surface,
)
from elements.ply_edge_couple import edge_couple, edge_features
from elements.ply_friction_tangent import friction_tangent
from elements.ply_projection import penalty_law, triangle_frames
from elements.ply_sides import PlySides, initial_sides
from femcore.rotation import cross
from femcore.state import State

if TYPE_CHECKING:
    from elements.ply_block import PlyContactBlock
    from elements.ply_projection import Facing

__all__ = [
    "PlyFrictionHistory",
    "Sliding",
    "friction_loads",
    "friction_state",
    "friction_tangent",
    "initial_history",
    "stick_spring",
    "updated_history",
]


@dataclass(frozen=True)
class PlyFrictionHistory:
    """The friction state of a ply contact after an accepted step (module docstring,
    "Friction"), one row per contact point.

    triangle : (P,) int
        Row of the block's lower triangles holding each point's stick anchor; -1 for a point
        without one (not touching).
    anchor : (P, 3) float
        The anchor's barycentric coordinates Lambda on that triangle (its point of the lower
        face, sum Lambda_k y_k, slides with the lower ply); NaN without an anchor.
    slip : (P,) float
        Slip length accumulated by each point, mm.
    pressing : (P,) float
        Each point's normal force N = -dW/dg when the step was accepted, N (the dissipation of
        the next step takes the friction limit at the mean of the two).
    dissipated : float
        Energy dissipated by friction so far, N mm.
    sides : PlySides or None
        Each point's side of the lower face at that state and the faces there
        (elements/ply_sides.py; None: not kept, every point may touch at any depth).
    """

    triangle: np.ndarray
    anchor: np.ndarray
    slip: np.ndarray
    pressing: np.ndarray
    dissipated: float
    sides: PlySides | None = None


@dataclass(frozen=True)
class Sliding:
    """The return mapping at a state (``PlyContactBlock.friction_state``), one row per point.

    force : (P, 3) float
        The tangential part of dW/dp, N: k_t s in stick, mu N s / |s| in slip, 0 elsewhere (the
        lower ply pulls the upper point by -force).
    slip : (P, 3) float
        s = (I - n n^T)(p - a), the tangential offset of the point from its anchor, mm.
    stuck, sliding : (P,) bool
        Anchored touching points within (k |s| <= mu N) and beyond the friction limit.
    pressing : (P,) float
        N = -dW/dg, the normal force of each touching point, N (0 elsewhere).
    offset : (P, 3) float
        r = p - a, mm (0 without an anchor).
    triangle : (P,) int
        The anchors' triangles (0 without an anchor).
    spring : (P,) float
        k_t, the stick spring of each touching point (module docstring: k_p, or w W''(g)),
        N/mm (0 elsewhere).
    lift : (P,) float
        dE/dg of each stuck point's stick potential E = w W''(g) |s|^2 / 2 at fixed s (module
        docstring, "The stick potential"): w W'''(g) |s|^2 / 2, N, the normal force it adds
        along dg/dz (0 elsewhere, with ``stick="penalty"`` and on the curved faces, whose
        stuck points' loads elements/ply_curved_friction.py makes whole).
    stored : (P,) float
        W''(g) |s|^2 / 2 of each stuck point, the potential before the fade's w, N mm: the
        factor of dw/dz in dE/dz past the outline (0 off the stuck points, with
        ``stick="penalty"`` and on curved faces; not 0 where ``lift`` is 0 deeper than the
        ramp).
    """

    force: np.ndarray
    slip: np.ndarray
    stuck: np.ndarray
    sliding: np.ndarray
    pressing: np.ndarray
    offset: np.ndarray
    triangle: np.ndarray
    spring: np.ndarray
    lift: np.ndarray
    stored: np.ndarray


def stick_spring(
    gap: np.ndarray, stiffness: np.ndarray, smoothing: float
) -> tuple[np.ndarray, np.ndarray]:
    """The stick spring k_t = W''(g) of touching points (module docstring) and its slope
    dk_t/dg = W'''(g), before the fade's w.

    Parameters
    ----------
    gap : (t,) float
        g, mm (< 0: penetration).
    stiffness : (t,) float
        The points' penalties k_p, N/mm.
    smoothing : float
        delta, mm: the penalty's ramp (elements/ply_projection.py's ``penalty_law``); 0: none.

    Returns
    -------
    spring (t,) N/mm, slope (t,) N/mm^2: k_p |g| / delta and -k_p / delta on the ramp
    (-delta < g < 0), k_p and 0 deeper (and at any g <= 0 without smoothing), 0 and 0 at g > 0.
    """
    spring = penalty_law(gap, stiffness, smoothing)[2]
    ramp = (gap < 0.0) & (gap > -smoothing)
    slope = np.where(ramp, -stiffness / (smoothing if smoothing > 0 else 1.0), 0.0)
    return spring, slope


def _spring(block: PlyContactBlock, gap: np.ndarray, stiffness: np.ndarray):
    """The block's stick spring and its slope (``stick_spring`` for ``stick="normal law"``;
    k_p and 0 for "penalty", the fade's w left out as before)."""
    if block.stick == "penalty":
        return np.array(stiffness, dtype=float), np.zeros(len(gap))
    return stick_spring(gap, stiffness, block.smoothing)


def friction_state(
    block: PlyContactBlock,
    state: State,
    history: PlyFrictionHistory | None,
    facing: Facing | None = None,
) -> Sliding:
    """The return mapping at ``state`` from the accepted ``history`` (module docstring,
    "Friction"): zero force, nothing stuck or sliding, without friction or anchors."""
    facing = block.facing(state) if facing is None else facing
    count = len(block.above)
    on = facing.touching
    pressing, spring, slope = np.zeros(count), np.zeros(count), np.zeros(count)
    pressing[on] = -block.normal_law(facing.gap[on], block.stiffness[on])[1]
    spring[on], slope[on] = _spring(block, facing.gap[on], block.stiffness[on])
    unfaded = spring.copy()
    fade = np.ones(count)
    if facing.fade is not None:  # N = -w W' past the outline (elements/ply_fade.py)
        fade = facing.fade
        pressing[on] *= facing.fade[on]
        if block.stick != "penalty":
            spring[on] *= facing.fade[on]
    zero = np.zeros((count, 3))
    if history is None or block.friction <= 0.0:
        none = np.zeros(count, dtype=bool)
        nowhere = np.zeros(count, dtype=np.int64)
        nothing = np.zeros(count)
        return Sliding(zero, zero, none, none, pressing, zero, nowhere, spring, nothing, nothing)
    anchored = on & (history.triangle >= 0)
    triangle = np.where(anchored, history.triangle, 0)
    _, y = block._faces(state)
    weights = np.where(anchored[:, None], history.anchor, 0.0)
    if block.curved:  # on the curved face, where the points are (elements/ply_surface.py)
        normals = block.surface_normals(state)[block.cells[triangle]]
        anchor = ply_surface.surface_point(y[triangle], normals, weights)[0]
    else:
        anchor = np.einsum("pk,pki->pi", weights, y[triangle])
    r = np.where(anchored[:, None], facing.face - anchor, 0.0)
    n = facing.normal
    s = r - np.sum(r * n, axis=1)[:, None] * n
    length = np.linalg.norm(s, axis=1)
    limit = block.friction * pressing
    stuck = anchored & (spring * length <= limit)
    sliding = anchored & ~stuck
    scale = np.where(
        stuck, spring, np.where(sliding, limit / np.where(length > 0, length, 1.0), 0.0)
    )
    lift, stored = stick_potential(block, stuck, s, fade, unfaded, slope)
    return Sliding(
        scale[:, None] * s, s, stuck, sliding, pressing, r, triangle, spring, lift, stored
    )


def stick_potential(
    block: PlyContactBlock,
    stuck: np.ndarray,
    slip: np.ndarray,
    fade: np.ndarray,
    spring: np.ndarray,
    slope: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The g- and w-derivatives of the stuck points' potential E = w W''(g) |s|^2 / 2 at
    fixed s (module docstring, "The stick potential"): ``Sliding.lift`` and
    ``Sliding.stored``, each (P,).

    Parameters
    ----------
    block : PlyContactBlock
    stuck : (P,) bool
    slip : (P, 3) float
        s, mm.
    fade : (P,) float
        w (1 without a fade).
    spring, slope : (P,) float
        W''(g), N/mm, and W'''(g), N/mm^2, before w (``stick_spring``; 0 where not touching).

    Returns
    -------
    lift (P,) N: w (W''' |s|^2 / 2); stored (P,) N mm: W'' |s|^2 / 2; both 0 off the stuck
    points, and everywhere with ``stick="penalty"`` (k_p |s|^2 / 2 holds no g) or on the
    curved faces (whose stuck points' loads, the lift among them, are
    elements/ply_curved_friction.py's).
    """
    potential = stuck & (block.stick != "penalty") & (not block.curved)
    half = 0.5 * np.sum(slip * slip, axis=1)
    lift = np.where(potential, fade * (slope * half), 0.0)
    stored = np.where(potential, spring * half, 0.0)
    return lift, stored


def stick_couple(
    block: PlyContactBlock, sliding: Sliding, facing: Facing, rows: np.ndarray
) -> np.ndarray:
    """The couple of the stuck points ``rows`` (t,): (t, 3) c_m = k_t (n . r)(s . grad phi_m)
    = (n . r)(F . grad phi_m), F = k_t s their force (``Sliding.force``), N, whose c_m n on
    the facing triangle's corners m is dE/dy_m of the stick potential E = k_t |s|^2 / 2
    beyond the normal and fade terms (module docstring, "The stick potential": dE/dy_m =
    k_t s . ds/dy_m = -k_t (n . r) s . dn/dy_m, with dn/dy_m = -grad phi_m n^T on a plane).
    0 for sliding points, on the curved faces and where the point faces an edge or a vertex
    (``Facing.on_edge``: their couple is ``edge_couples``')."""
    n, r, force = facing.normal[rows], sliding.offset[rows], sliding.force[rows]
    along = np.sum(n * r, axis=1)
    across = np.sum(force[:, None, :] * facing.gradients[rows], axis=2)
    plane = _couple_rows(block, sliding, facing, rows)
    return np.where(plane[:, None], along[:, None] * across, 0.0)


def edge_couples(
    block: PlyContactBlock, state: State, sliding: Sliding, facing: Facing, rows: np.ndarray
) -> np.ndarray:
    """The couple (t, 4, 3) C_w on z = (p, y_1, y_2, y_3), N, of the stuck points among
    ``rows`` (t,) whose closest point lies on an edge or at a vertex of the facing triangle
    (``Facing.on_edge``; elements/ply_edge_couple.py ``edge_couple``); 0 on the other rows
    and on the curved faces."""
    out = np.zeros((len(rows), 4, 3))
    if facing.on_edge is None or block.curved:
        return out
    pick = np.flatnonzero(sliding.stuck[rows] & facing.on_edge[rows])
    if pick.size:
        at = rows[pick]
        _, y = block._faces(state)
        if ply_projection.COMPILED:  # the same bits (elements/ply_edge_couple_kernels.py)
            out[pick] = ply_edge_couple_kernels.edge_couples(
                facing, y, block.cuts, at, sliding.offset, sliding.force
            )
            return out
        features = edge_features(facing, y, block.cuts, at)
        out[pick] = edge_couple(
            features, facing.gap[at], facing.normal[at], sliding.offset[at], sliding.force[at]
        )
    return out


def _couple_rows(
    block: PlyContactBlock, sliding: Sliding, facing: Facing, rows: np.ndarray
) -> np.ndarray:
    """(t,) bool: which of the points ``rows`` carry a couple (``stick_couple``): stuck, on
    the flat faces, facing a triangle's plane."""
    plane = sliding.stuck[rows] & (not block.curved)
    if facing.on_edge is not None:
        plane = plane & ~facing.on_edge[rows]
    return plane


def friction_loads(
    block: PlyContactBlock,
    state: State,
    sliding: Sliding,
    history: PlyFrictionHistory,
    facing: Facing,
):
    """Per stuck or sliding point: node rows (t, 11) (the upper triangle's corners, the
    anchor triangle's corners, the facing triangle's corners, the ends of the outline's edge
    nearest the point (``PlyContactBlock.fade_ends``)), forces (t, 11, 3) N and moments
    (t, 11, 3) N mm (c d x force): the tangential force F (N_j F on the upper corners,
    -Lambda_k F on the anchor's) and a stuck point's dE/dz of its stick potential beyond F
    (module docstring, "The stick potential"): ``lift`` dg/dz + ``stored`` dw/dz, with
    dg/dz = (n, -lambda_k n) over (p, y_1..3) and dw/dz over (p, y_1..3, a, b), and the
    couple c_m n on the facing corners (``stick_couple``), or C_w on p and the facing
    corners where the point faces an edge or a vertex (``edge_couples``) (0 for sliding
    points: their entries add zeros)."""
    on = np.flatnonzero(sliding.stuck | sliding.sliding)
    tri = sliding.triangle[on]
    facing_tri = facing.triangle[on]
    ends, ends_offset = block.fade_ends(facing, on)
    nodes = np.column_stack([block.above[on], block.cells[tri], block.cells[facing_tri], ends])
    force = sliding.force[on]
    # flat faces: the curved faces' loads are elements/ply_curved_friction.py's
    lower = -history.anchor[on][:, :, None] * force[:, None, :]
    lift, stored = sliding.lift[on], sliding.stored[on]
    n, lam = facing.normal[on], facing.weights[on]
    couple = stick_couple(block, sliding, facing, on)
    turned = edge_couples(block, state, sliding, facing, on)
    fading = np.zeros((len(on), 6, 3)) if facing.fade_gradient is None else facing.fade_gradient[on]
    on_face = force + (lift[:, None] * n + stored[:, None] * fading[:, 0]) + turned[:, 0]
    forces = np.concatenate(
        [
            block.shape[on][:, :, None] * on_face[:, None, :],
            lower,
            (-lift[:, None] * lam + couple)[:, :, None] * n[:, None, :]
            + stored[:, None, None] * fading[:, 1:4]
            + turned[:, 1:],
            stored[:, None, None] * fading[:, 4:],
        ],
        axis=1,
    )
    offset = np.column_stack(
        [
            block.lever
            * np.column_stack(
                [-block.upper_offset[on], block.corner_offset[tri], block.corner_offset[facing_tri]]
            ),
            ends_offset,
        ]
    )
    moments = offset[:, :, None] * cross(block.offset_directions(state)[nodes], forces)
    return nodes, forces, moments


def initial_history(block: PlyContactBlock) -> PlyFrictionHistory | None:
    """Frictionless: None. Otherwise the points that touch the lower ply in the reference
    state are anchored at their projections (plies laid on each other stick from the
    first step)."""
    if block.friction == 0.0:
        return None
    facing = block.facing(block._reference)
    sliding = friction_state(block, block._reference, None, facing)
    on = facing.touching
    count = len(block.above)
    return PlyFrictionHistory(
        np.where(on, facing.triangle, -1),
        np.where(on[:, None], facing.weights, np.nan),
        np.zeros(count),
        sliding.pressing,
        0.0,
        initial_sides(block),
    )


def updated_history(
    block: PlyContactBlock,
    state: State,
    history: PlyFrictionHistory | None,
    facing: Facing | None = None,
    sides: PlySides | None = None,
) -> PlyFrictionHistory | None:
    """The return mapping accepted (a new history; ``history`` is left as it was): stuck
    anchors stay, sliding ones move along s towards their points until the spring holds
    mu N and are re-expressed on the facing triangle, new contacts are anchored at their
    projections, lost ones forget their anchor, having slid up to where they left the face
    (elements/ply_departure.py); the dissipation adds mu N_mid times the slip, N_mid the mean
    of the last accepted and this normal force. ``facing`` the state's
    (with the points kept off their faces not touching, elements/ply_sides.py; the block's
    when None), ``sides`` the points' sides there, kept in the new history. The block hands
    it a history whose points landing in this step are anchored where their way crossed the
    face (elements/ply_landing.py ``landed``): they are stuck or sliding, not new contacts."""
    if history is None:
        return None
    facing = block.facing(state) if facing is None else facing
    sliding = friction_state(block, state, history, facing)
    on = facing.touching
    length = np.linalg.norm(sliding.slip, axis=1)
    unit = sliding.slip / np.where(length > 0, length, 1.0)[:, None]
    # k_t is 0 only where a point is stuck (k_t |s| <= mu N holds) or not touching: slid 0
    spring = np.where(sliding.spring > 0, sliding.spring, 1.0)
    held = block.friction * sliding.pressing / spring  # |s| at the limit, mm
    slid = np.where(sliding.sliding, length - held, 0.0)
    # a point that left the face slid until it left, N falling to 0 (elements/ply_departure.py)
    _, y = block._faces(state)
    rows, way = ply_departure.departure(block, y, history, facing)
    slid[rows] = way
    # The moved anchor q = a + slid s^, in the facing triangle's barycentric coordinates
    # (its in-plane gradients drop the normal part of q - p).
    target = -sliding.offset + slid[:, None] * unit  # q - p
    # Re-expressed from the facing triangle's closest point p - g n, and brought into its
    # plane along n, not along the plane's own normal m: a point facing an edge or a vertex
    # (elements/ply_projection.py) has n != m, and s, across n, must keep its new length
    # (on a plane n = m and the correction vanishes). That holds where |n . m| > TILT; below
    # it the landing's blend (next lines), which gives part of that length up.
    _, y = block._faces(state)
    plane = triangle_frames(y[facing.triangle])[0]
    # a point facing no patch (curved faces: gap inf, normal 0; elements/ply_curved.py)
    # touches nothing and keeps no anchor: its w is not used, kept finite
    gap = np.where(np.isfinite(facing.gap), facing.gap, 0.0)
    w = target + gap[:, None] * facing.normal
    tilt = np.sum(plane * facing.normal, axis=1)
    # where n lies within TILT of the plane a share tilt^2 / TILT^2 of that move, the rest of
    # the height along the plane's normal: the landing's rule (ply_landing.edge_crossing), so
    # that an anchor the landing placed is re-expressed where it is, continuous across TILT
    steep = np.abs(tilt) > ply_landing.TILT
    rise = np.sum(plane * w, axis=1)
    along = np.where(steep, rise / np.where(steep, tilt, 1.0), rise * tilt / ply_landing.TILT**2)
    w = w - along[:, None] * facing.normal
    moved = facing.weights + np.einsum("pki,pi->pk", facing.gradients, w)
    if block.curved:  # the moved anchor projected on the curved face, where it is measured
        _, y = block._faces(state)
        normals = block.surface_normals(state)[block.cells[facing.triangle]]
        moved = ply_surface.project(facing.face + target, y[facing.triangle], normals, moved)[0]
    triangle = np.where(on, facing.triangle, -1)
    anchor = np.where(on[:, None], facing.weights, np.nan)  # new contacts
    anchor = np.where(sliding.sliding[:, None], moved, anchor)
    triangle = np.where(sliding.stuck, history.triangle, triangle)
    anchor = np.where(sliding.stuck[:, None], history.anchor, anchor)
    force = block.friction * 0.5 * (sliding.pressing + history.pressing)
    dissipated = history.dissipated + float(np.sum(force * slid))
    return PlyFrictionHistory(
        triangle, anchor, history.slip + slid, sliding.pressing, dissipated, sides
    )
