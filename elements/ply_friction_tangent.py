"""The exact tangent of the friction between two plies (``friction_tangent``, elements/
ply_friction.py's return mapping differentiated; docs/theory.md §9.3a): d(force, moment)/d(u,
psi) of the stuck and sliding points over their upper triangle's, facing triangle's and
anchor triangle's corners and the ends of the outline's edge nearest them, the stick
potential's derivative (``_potential_tangent``: its lift and stored terms) and the couple's
(``_couple_tangent``; ``edge_couple_tangent`` where a point faces an edge or a vertex). The
mechanics are elements/ply_friction.py's module docstring ("The stick potential"); that module
re-exports ``friction_tangent``, and this one calls the return mapping and the couples through
it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from elements import ply_landing_kept
from elements.ply_edge_couple import edge_couple, edge_couple_tangent
from elements.ply_fade_hessian import plane_hessian
from femcore.assembly import CellTangent
from femcore.rotation import cross_matrix
from femcore.state import State

if TYPE_CHECKING:
    from elements.ply_block import PlyContactBlock
    from elements.ply_friction import PlyFrictionHistory
    from elements.ply_projection import Facing

__all__ = ["friction_tangent"]


def friction_tangent(
    block: PlyContactBlock, state: State, history: PlyFrictionHistory, facing: Facing
) -> CellTangent:
    """The return mapping's exact d(force, moment)/d(u, psi), (t, 11, 6, 11, 6) over the
    upper triangle's, the facing triangle's and the anchor triangle's corners and the ends
    of the outline's edge nearest the point (its fade's, elements/ply_fade.py).

    Over z = (p, y_f1..3, y_a1..3) (f the facing triangle, a the anchor's): the force F on
    p (``Sliding.force``) and -Lambda_k F on y_ak, with ds/dp = P = I - n n^T, ds/dy_ak =
    -Lambda_k P, ds/dy_fm = ((n . r) grad phi_m + (r . grad phi_m) n) n^T (from dn/dy_fm =
    -grad phi_m n^T); dF = k_t ds + s dk_t in stick (k_t = w W'', dk_t = w W''' dg + W'' dw),
    mu s^ dN + mu N / |s| (I - s^ s^T) ds in slip, with dN = -W'' dg, dg/dz = (n,
    -lambda_k n, 0); and a stuck point's stick potential beyond F (``friction_loads``: lift
    dg/dz + stored dw/dz and the couple), its derivative from ``_potential_tangent``,
    ``_couple_tangent`` and ``edge_couple_tangent``. Carried to the nodes
    and turned with the directors as the normal part (``tangent``). A point landing in this
    step (elements/ply_landing.py) has its anchor on the facing triangle moving with z: its
    dLambda/dz adds -sum_k y_k dLambda_k/dz to dr/dz and -dLambda_k/dz F to the corners'."""
    # the return mapping's own functions by their module's names (tests and benchmarks
    # replace ply_friction.edge_features and ._couple_rows); that module imports this one
    from elements import ply_friction

    found, history = ply_landing_kept.kept_landing(block, state, history, facing)
    sliding = ply_friction.friction_state(block, state, history, facing)
    on = np.flatnonzero(sliding.stuck | sliding.sliding)
    t = len(on)
    n, lam, grad = facing.normal[on], facing.weights[on], facing.gradients[on]
    r, s, force = sliding.offset[on], sliding.slip[on], sliding.force[on]
    big = history.anchor[on]
    k = block.stiffness[on]
    eye = np.eye(3)
    across = eye - n[:, :, None] * n[:, None, :]
    # dn/dz over z = (p, y_f1..3): -grad phi_m n^T on the facing corners of a plane; a point
    # facing the closest point of an edge or a vertex (elements/ply_projection.py) turns its
    # n = dg/dp with p and the corners as the gap's Hessian says.
    turning = np.zeros((t, 4, 3, 3))
    for m in range(3):
        turning[:, 1 + m] = -grad[:, m, :, None] * n[:, None, :]
    if facing.hessian is not None:
        bent = np.any(facing.hessian[on] != 0.0, axis=(1, 2, 3, 4))
        turning[bent] = np.swapaxes(facing.hessian[on][bent][:, 0], 1, 2)
    # s = (I - n n^T) r: ds = (I - n n^T) dr - (n . r) dn - n (r . dn)
    ds = np.zeros((t, 3, 9, 3))  # z = (p, y_f1..3, y_a1..3, a, b): the fade's outline ends
    normal_r = np.sum(n * r, axis=1)
    for w in range(4):
        ds[:, :, w, :] = (
            -normal_r[:, None, None] * turning[:, w]
            - n[:, :, None] * np.einsum("ti,tij->tj", r, turning[:, w])[:, None, :]
        )
    ds[:, :, 0, :] += across
    for m in range(3):
        ds[:, :, 4 + m, :] = -big[:, m, None, None] * across
    length = np.linalg.norm(s, axis=1)
    unit = s / np.where(length > 0, length, 1.0)[:, None]
    gap_gradient = np.zeros((t, 9, 3))
    gap_gradient[:, 0] = n
    gap_gradient[:, 1:4] = -lam[:, :, None] * n[:, None, :]
    moving = None  # a landing anchor's dr/dz beyond -Lambda_k I on y_ak
    if found is not None:
        lands = np.searchsorted(on, found.rows)  # (every landing point touches: in ``on``)
        searched = None if facing.hessian is None else facing.hessian[found.rows]
        motion = found.anchor_motion(gap_gradient[lands, :4], searched)  # (r, 3, 4, 3)
        _, y = block._faces(state)
        moving = np.zeros((t, 3, 9, 3))
        moving[lands, :, :4] = -np.einsum("rki,rkzb->rizb", y[facing.triangle[found.rows]], motion)
        ds += np.einsum("tij,tjzb->tizb", across, moving)
    _, slope, curvature = block.normal_law(facing.gap[on], k)
    d_pressing = -curvature[:, None, None] * gap_gradient  # (t, 9, 3)
    unfaded, spring_slope = ply_friction._spring(block, facing.gap[on], k)
    d_spring = spring_slope[:, None, None] * gap_gradient
    if facing.fade is not None and facing.fade_gradient is not None:
        # N = -w W'(g) past the outline (elements/ply_fade.py): dN = -(w W'' dg + W' dw),
        # and k_t = w W'': dk_t = w W''' dg + W'' dw
        fade = facing.fade[on][:, None, None]
        d_pressing *= fade
        d_pressing[:, :4] -= slope[:, None, None] * facing.fade_gradient[on][:, :4]
        d_pressing[:, 7:] -= slope[:, None, None] * facing.fade_gradient[on][:, 4:]
        if block.stick != "penalty":
            d_spring *= fade
            d_spring[:, :4] += unfaded[:, None, None] * facing.fade_gradient[on][:, :4]
            d_spring[:, 7:] += unfaded[:, None, None] * facing.fade_gradient[on][:, 4:]
    stuck = sliding.stuck[on]
    mu, pressing = block.friction, sliding.pressing[on]
    ratio = mu * pressing / np.where(length > 0, length, 1.0)
    slip_part = mu * unit[:, :, None, None] * d_pressing[:, None] + ratio[
        :, None, None, None
    ] * np.einsum("tij,tjzb->tizb", eye - unit[:, :, None] * unit[:, None, :], ds)
    spring = sliding.spring[on]
    stick_part = spring[:, None, None, None] * ds + s[:, :, None, None] * d_spring[:, None]
    d_force = np.where(stuck[:, None, None, None], stick_part, slip_part)
    points = np.zeros((t, 9, 3, 9, 3))
    points[:, 0] = d_force
    for m in range(3):
        points[:, 4 + m] = -big[:, m, None, None, None] * d_force
        if found is not None:
            points[lands, 4 + m, :, :4] -= force[lands][:, :, None, None] * motion[:, m, None]
    fading = np.zeros((t, 9, 3))  # dw/dz over the 9 slots (0 without a fade)
    if facing.fade_gradient is not None:
        fading[:, :4] = facing.fade_gradient[on][:, :4]
        fading[:, 7:] = facing.fade_gradient[on][:, 4:]
    lift, stored = sliding.lift[on], sliding.stored[on]
    # the stuck points whose potential holds g or w: on the ramp (W''' != 0) or in the fade's
    # band (dw != 0); deeper and inside, every term below is 0
    held = np.flatnonzero(
        stuck
        & (block.stick != "penalty")
        & (not block.curved)
        & ((spring_slope != 0.0) | np.any(fading != 0.0, axis=(1, 2)))
    )
    if held.size:
        points[held] += _potential_tangent(
            block, state, facing, on[held], s[held], ds[held], gap_gradient[held],
            fading[held], unfaded[held], spring_slope[held], lift[held], stored[held],
        )  # fmt: skip
    couple = ply_friction.stick_couple(block, sliding, facing, on)
    turns = np.flatnonzero(ply_friction._couple_rows(block, sliding, facing, on))
    if turns.size:
        points[turns] += _couple_tangent(
            n[turns], r[turns], s[turns], grad[turns], big[turns], ds[turns],
            turning[turns], spring[turns], d_spring[turns], couple[turns],
            None if moving is None else moving[turns],
        )  # fmt: skip
    edges = np.flatnonzero(stuck & facing.on_edge[on]) if facing.on_edge is not None else on[:0]
    turned = np.zeros((t, 4, 3))
    if edges.size and not block.curved:  # the couple of points facing an edge or a vertex
        at = on[edges]
        _, y = block._faces(state)
        # the edge's features made once, for the couple's derivative and for the couple
        # itself (``edge_couples``' rows, its numpy path: the same bits as the compiled one)
        features = ply_friction.edge_features(facing, y, block.cuts, at)
        points[edges] += edge_couple_tangent(
            features, facing.gap[at], n[edges], r[edges],
            s[edges], big[edges], ds[edges], spring[edges], d_spring[edges],
            None if moving is None else moving[edges],
        )  # fmt: skip
        turned[edges] = edge_couple(features, facing.gap[at], n[edges], r[edges], force[edges])
    ends, ends_offset = block.fade_ends(facing, on)
    nodes = np.column_stack(
        [
            block.above[on],
            block.cells[facing.triangle[on]],
            block.cells[sliding.triangle[on]],
            ends,
        ]
    )
    offset = np.column_stack(
        [
            block.lever
            * np.column_stack(
                [
                    -block.upper_offset[on],
                    block.corner_offset[facing.triangle[on]],
                    block.corner_offset[sliding.triangle[on]],
                ]
            ),
            ends_offset,
        ]
    )
    d = block.offset_directions(state)[nodes]  # (t, 11, 3)
    own = np.zeros((t, 11, 3, 6))
    own[:, :, :, :3] = eye
    own[:, :, :, 3:] = -offset[:, :, None, None] * cross_matrix(d)
    maps = np.zeros((t, 9, 3, 11, 6))
    for j in range(3):
        maps[:, 0, :, j, :] = block.shape[on][:, j, None, None] * own[:, j]
    for z in range(1, 9):
        maps[:, z, :, 2 + z, :] = own[:, 2 + z]
    carried = np.einsum("tzisj,tsjcb->tzicb", points, maps)
    blocks = np.einsum("tzira,tzicb->tracb", maps, carried)
    on_face = force + (lift[:, None] * n + stored[:, None] * fading[:, 0]) + turned[:, 0]
    forces = np.concatenate(
        [
            block.shape[on][:, :, None] * on_face[:, None, :],
            (-lift[:, None] * lam + couple)[:, :, None] * n[:, None, :]
            + stored[:, None, None] * fading[:, 1:4]
            + turned[:, 1:],
            -big[:, :, None] * force[:, None, :],
            stored[:, None, None] * fading[:, 7:],
        ],
        axis=1,
    )
    geometric = offset[:, :, None, None] * (
        d[:, :, :, None] * forces[:, :, None, :]
        - np.sum(forces * d, axis=-1)[:, :, None, None] * eye
    )
    for row in range(11):
        blocks[:, row, 3:, row, 3:] += geometric[:, row]
    return CellTangent(nodes, blocks)


def _potential_tangent(
    block: PlyContactBlock,
    state: State,
    facing: Facing,
    rows: np.ndarray,
    s: np.ndarray,
    ds: np.ndarray,
    gap_gradient: np.ndarray,
    fading: np.ndarray,
    spring: np.ndarray,
    slope: np.ndarray,
    lift: np.ndarray,
    stored: np.ndarray,
) -> np.ndarray:
    """The derivative (h, 9, 3, 9, 3) of the stuck points' ``lift`` dg/dz + ``stored`` dw/dz
    (``friction_loads``) over z = (p, y_f1..3, y_a1..3, a, b), for the points ``rows`` (h,)
    of the facing (module docstring, "The stick potential").

    With E = w W'' |s|^2 / 2 at fixed s: lift = w W''' |s|^2 / 2, stored = W'' |s|^2 / 2,
    d(|s|^2 / 2) = s . ds, and W'''' = 0 (W''' is constant on the ramp and 0 past it), so
    d lift = W''' |s|^2 / 2 dw + w W''' s . ds and d stored = W''' |s|^2 / 2 dg + W'' s . ds;
    with the gap's Hessian (``plane_hessian``, or the search's where the point faces an edge
    or a vertex) times lift and the fade's (``PlyContactBlock.fade_hessian_at``) times stored.

    s (h, 3) mm, ds (h, 3, 9, 3) ds/dz, gap_gradient and fading (h, 9, 3) dg/dz and dw/dz
    (1/mm), spring W'' (h,) N/mm, slope W''' (h,) N/mm^2, lift (h,) N and stored (h,) N mm.
    """
    half = 0.5 * np.sum(s * s, axis=1)
    along = np.einsum("ti,tizb->tzb", s, ds)  # d(|s|^2 / 2)/dz, mm
    fade = np.ones(len(rows)) if facing.fade is None else facing.fade[rows]
    d_lift = (slope * half)[:, None, None] * fading + (fade * slope)[:, None, None] * along
    d_stored = (slope * half)[:, None, None] * gap_gradient + spring[:, None, None] * along
    points = (
        gap_gradient[:, :, :, None, None] * d_lift[:, None, None]
        + fading[:, :, :, None, None] * d_stored[:, None, None]
    )
    n, lam, grad = facing.normal[rows], facing.weights[rows], facing.gradients[rows]
    hessian = plane_hessian(facing.gap[rows], n, lam, grad)  # (h, 4, 3, 4, 3)
    if facing.hessian is not None:
        bent = np.any(facing.hessian[rows] != 0.0, axis=(1, 2, 3, 4))
        hessian[bent] = facing.hessian[rows][bent]
    points[:, :4, :, :4, :] += lift[:, None, None, None, None] * hessian
    faded = np.flatnonzero(np.any(fading != 0.0, axis=(1, 2)) & (stored != 0.0))
    if faded.size:
        fade_hessian = stored[faded, None, None, None, None] * block.fade_hessian_at(
            state, facing, rows[faded]
        )
        slots = (0, 1, 2, 3, 7, 8)  # z's of (p, y_1, y_2, y_3, a, b)
        for i, row in enumerate(slots):
            for j, column in enumerate(slots):
                points[faded, row, :, column, :] += fade_hessian[:, i, :, j, :]
    return points


def _couple_tangent(
    n: np.ndarray,
    r: np.ndarray,
    s: np.ndarray,
    grad: np.ndarray,
    big: np.ndarray,
    ds: np.ndarray,
    turning: np.ndarray,
    spring: np.ndarray,
    d_spring: np.ndarray,
    couple: np.ndarray,
    moving: np.ndarray | None = None,
) -> np.ndarray:
    """The derivative (h, 9, 3, 9, 3) of the stuck points' couple c_m n on the facing
    corners (``stick_couple``: c_m = k_t (n . r)(s . grad phi_m)) over z = (p, y_f1..3,
    y_a1..3, a, b), for points facing a plane (module docstring, "The stick potential").

    dc_m = dk_t (n . r)(s . g_m) + k_t (s . g_m)(r . dn + n . dr) + k_t (n . r)(g_m . ds +
    s . dg_m), with dn/dy_fk = -g_k n^T, dr/dp = I, dr/dy_ak = -Lambda_k I and, from
    sum_m y_m g_m^T = I - n n^T and g_m . n = 0, dg_m/dy_fk = -g_k g_m^T + (g_m . g_k) n n^T,
    so s . dg_m/dy_fk = -(s . g_k) g_m (s . n = 0); and d(c_m n) = n dc_m + c_m dn.

    n, r, s (h, 3): the facing normal, r = p - a and s, mm; grad (h, 3, 3) the facing
    triangle's gradients g_m, 1/mm; big (h, 3) the anchor's Lambda; ds (h, 3, 9, 3) ds/dz;
    turning (h, 4, 3, 3) dn/dz over (p, y_f1..3), 1/mm; spring k_t (h,) N/mm; d_spring
    (h, 9, 3) dk_t/dz, N/mm^2; couple c_m (h, 3), N; moving (h, 3, 9, 3) a landing
    anchor's dr/dz beyond -Lambda_k I on y_ak (elements/ply_landing.py), None: none.
    """
    count = len(n)
    along = np.sum(n * r, axis=1)  # n . r, mm
    across = np.sum(s[:, None, :] * grad, axis=2)  # s . g_m, (h, 3)
    d_along = np.zeros((count, 9, 3))
    d_along[:, 0] = n
    d_along[:, 1:4] = np.einsum("ti,twij->twj", r, turning[:, 1:4])
    d_along[:, 4:7] = -big[:, :, None] * n[:, None, :]
    if moving is not None:
        d_along += np.einsum("ti,tizb->tzb", n, moving)
    d_across = np.einsum("tmi,tizb->tmzb", grad, ds)
    for k in range(3):
        d_across[:, :, 1 + k, :] -= across[:, k, None, None] * grad
    d_couple = (
        (along[:, None] * across)[:, :, None, None] * d_spring[:, None]
        + (spring[:, None] * across)[:, :, None, None] * d_along[:, None]
        + (spring * along)[:, None, None, None] * d_across
    )  # (h, 3, 9, 3)
    turned = np.zeros((count, 3, 9, 3))  # dn/dz over the 9 slots
    turned[:, :, :4, :] = np.swapaxes(turning, 1, 2)
    points = np.zeros((count, 9, 3, 9, 3))
    for m in range(3):
        points[:, 1 + m] = (
            n[:, :, None, None] * d_couple[:, m, None] + couple[:, m, None, None, None] * turned
        )
    return points
