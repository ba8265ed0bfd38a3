"""The ply contact's landing points compiled on the flat faces (elements/ply_landing.py
``landing``, docs/theory.md §9.3a, "A point's landing step"): for the points that land at a
state, their places on their facing triangle T's plane then and now, theta = g_0 / (g_0 +
pen) and its derivative's factor, T's frame now and the point's height over it, and, for the
points whose gap is to an edge or a vertex, theta and the anchor's place by that gap
(``ply_landing.edge_crossing``), in one compiled call.

The numpy reference made some thirty numpy calls and four of ``triangle_frames`` (seven with
edge rows) on a few rows, at almost every step of a two-ply run whose flange points rest near
zero gap and land and leave in turn: its fixed cost, about 220 us a call, 6.8-7.2 s of CPU over
the report's Mindlin [0/90] run (about 29k landings in 32242 steps), the largest ply cost left;
compiled, about 40 us a call (the kernel's call and its inputs' types), 0.8-1.3 s
(benchmarks/ply_landing_cost.py). The kernel does the same IEEE operations in the same order as
the numpy reference (as elements/ply_departure_kernels.py: the cross products as
femcore/rotation.py ``cross`` writes them, the norms' and ``np.sum(axis=1)``'s sums from the
first term, ``einsum("rki,rki->rk")``, ``einsum("ri,ri->r")`` and ``einsum("rki,ri->rk")`` as
(first + last) + middle, ``einsum("rk,rki->ri")`` from the first term, numpy's ``maximum``
keeping NaN and -0.0; no fused multiply-add: numba builds without fastmath), so that the
anchors, and the run, are the same to the last bit (tests/test_ply_landing_kernels.py). The
curved faces' landing (its places along the Phong patch's normal) stays numpy. The edge rows'
``Crossing`` (what the tangent moves their anchors by) is gathered after the call, by the same
helper as numpy's ``landing`` (``ply_landing.edge_rows_crossing``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from elements import plane_place_kernels as plane
from elements import ply_landing
from elements.kernel_inputs import read_only, writable
from femcore.jit import jit_lanes, prange

if TYPE_CHECKING:
    from elements.ply_block import PlyContactBlock
    from elements.ply_friction import PlyFrictionHistory
    from elements.ply_landing import Landing
    from elements.ply_projection import Facing
    from femcore.state import State

__all__ = ["COMPILED", "landing"]

#: The flat faces' landing by this kernel; False: by the numpy reference
#: (``ply_landing.landing``; benchmarks/ply_landing_cost.py compares the two).
COMPILED = True


def _landing(
    rows,
    triangle,
    before,
    now,
    then,
    face,
    gap,
    feature,
    nu,
    on_edge,
    plane_zero,
    tilt_floor,
    rate,
    theta,
    dtheta,
    weights,
    gradients,
    normal,
    height,
    edge,
    place,
):
    """``ply_landing.landing``'s arrays for the rows ``rows`` (r,) of the landing points,
    written into ``rate`` (r, 3), ``theta`` (r,), ``dtheta`` (r,) 1/mm, ``weights`` (r, 3),
    ``gradients`` (r, 3, 3) 1/mm, ``normal`` (r, 3), ``height`` (r,) mm, ``edge`` (r,) bool
    and, on the edge rows alone, ``place`` (r, 3). ``triangle`` (P,) each point's facing
    triangle now, ``before`` (m, 3, 3) the lower corners at the last accepted state (the
    history's sides) and ``now`` (m, 3, 3) now, mm; ``then`` and ``face`` (P, 3) the points
    then and now, mm; ``gap`` (P,) their gaps now, mm; ``feature`` (P, 3) the barycentric
    coordinates of their closest points now; ``nu`` (P, 3) their gaps' normals now;
    ``on_edge`` (P,) bool their gaps to an edge or a vertex (empty: none); ``plane_zero``
    (P,) bool their gaps' zero T's plane (on a growth and not joined; empty: none);
    ``tilt_floor`` ``ply_landing.TILT`` (an argument, not a global: a cached build would keep
    the value it was built with)."""
    for j in prange(rows.shape[0]):
        i = rows[j]
        t = triangle[i]
        # T's frames then (side 0) and now (side 1), the point's places on their planes and
        # heights over them: ply_projection.triangle_frames and ply_landing.plane_places,
        # operation by operation (elements/plane_place_kernels.py)
        g_then = 0.0  # np.sum(n_then * (then - y_1 then), axis=1): from the first term
        height_then = 0.0  # plane_places' height then (einsum: (first + last) + middle)
        height_plane = 0.0  # plane_places' height now
        old0 = 0.0
        old1 = 0.0
        old2 = 0.0
        for side in range(2):
            corners = before[t] if side == 0 else now[t]
            point = then[i] if side == 0 else face[i]
            n0, n1, n2, _, g00, g01, g02, g10, g11, g12, g20, g21, g22 = plane.frame(corners)
            w0, w1, w2, r0, r1, r2 = plane.place(corners, point, g00, g01, g02, g10, g11, g12)
            if side == 0:
                old0, old1, old2 = w0, w1, w2
                g_then = (n0 * r0 + n1 * r1) + n2 * r2
                height_then = (n0 * r0 + n2 * r2) + n1 * r1
            else:
                weights[j, 0], weights[j, 1], weights[j, 2] = w0, w1, w2
                normal[j, 0], normal[j, 1], normal[j, 2] = n0, n1, n2
                height[j] = (n0 * r0 + n1 * r1) + n2 * r2
                height_plane = (n0 * r0 + n2 * r2) + n1 * r1
                gradients[j, 0, 0], gradients[j, 0, 1], gradients[j, 0, 2] = g00, g01, g02
                gradients[j, 1, 0], gradients[j, 1, 1], gradients[j, 1, 2] = g10, g11, g12
                gradients[j, 2, 0], gradients[j, 2, 1], gradients[j, 2, 2] = g20, g21, g22
        # numpy's maximum(x, 0): NaN and -0.0 kept
        if not (g_then >= 0.0 or g_then != g_then):
            g_then = 0.0
        pen = -gap[i]
        if not (pen >= 0.0 or pen != pen):
            pen = 0.0
        way = g_then + pen
        safe = way if way > 0.0 else 1.0
        theta[j] = g_then / safe if way > 0.0 else 1.0
        dtheta[j] = g_then / (safe * safe) if pen > 0.0 else 0.0
        rate[j, 0] = weights[j, 0] - old0
        rate[j, 1] = weights[j, 1] - old1
        rate[j, 2] = weights[j, 2] - old2
        edge[j] = on_edge.shape[0] > 0 and on_edge[i]
        if not edge[j]:
            continue
        # ply_landing.edge_crossing: the gap's zero through q, normal to nu or T's plane
        m0, m1, m2 = nu[i, 0], nu[i, 1], nu[i, 2]
        if plane_zero.shape[0] > 0 and plane_zero[i]:
            m0, m1, m2 = normal[j, 0], normal[j, 1], normal[j, 2]
        lam0, lam1, lam2 = feature[i, 0], feature[i, 1], feature[i, 2]
        s0 = then[i, 0] - (
            (lam0 * before[t, 0, 0] + lam1 * before[t, 1, 0]) + lam2 * before[t, 2, 0]
        )
        s1 = then[i, 1] - (
            (lam0 * before[t, 0, 1] + lam1 * before[t, 1, 1]) + lam2 * before[t, 2, 1]
        )
        s2 = then[i, 2] - (
            (lam0 * before[t, 0, 2] + lam1 * before[t, 1, 2]) + lam2 * before[t, 2, 2]
        )
        u0 = face[i, 0] - ((lam0 * now[t, 0, 0] + lam1 * now[t, 1, 0]) + lam2 * now[t, 2, 0])
        u1 = face[i, 1] - ((lam0 * now[t, 0, 1] + lam1 * now[t, 1, 1]) + lam2 * now[t, 2, 1])
        u2 = face[i, 2] - ((lam0 * now[t, 0, 2] + lam1 * now[t, 1, 2]) + lam2 * now[t, 2, 2])
        g0e = (m0 * s0 + m2 * s2) + m1 * s1
        if not (g0e >= 0.0 or g0e != g0e):
            g0e = 0.0
        pene = -((m0 * u0 + m2 * u2) + m1 * u1)
        if not (pene >= 0.0 or pene != pene):
            pene = 0.0
        way_e = g0e + pene
        theta_e = g0e / (way_e if way_e > 0.0 else 1.0) if way_e > 0.0 else 1.0
        theta[j] = theta_e
        dtheta[j] = 0.0
        rise = height_then + theta_e * (height_plane - height_then)
        v0, v1, v2 = nu[i, 0], nu[i, 1], nu[i, 2]
        tilt = (normal[j, 0] * v0 + normal[j, 2] * v2) + normal[j, 1] * v1
        # numpy's where(steep, rise / tilt, rise * tilt / TILT**2)
        if abs(tilt) > tilt_floor:
            along = rise / tilt
        else:
            along = rise * tilt / (tilt_floor**2)
        olds = (old0, old1, old2)
        for k in range(3):
            across = (gradients[j, k, 0] * v0 + gradients[j, k, 2] * v2) + gradients[j, k, 1] * v1
            at = olds[k] + theta_e * (weights[j, k] - olds[k])
            place[j, k] = at - along * across


_landing_compiled = jit_lanes(_landing)


def landing(
    block: PlyContactBlock,
    state: State,
    history: PlyFrictionHistory,
    facing: Facing,
    rows: np.ndarray | None = None,
) -> Landing | None:
    """``ply_landing.landing`` at ``state`` (``facing`` there) from the accepted ``history``,
    compiled on the flat faces (the same bits); the curved faces', or with ``COMPILED``
    False, numpy's. ``rows`` the landing rows (``ply_landing.landing_rows``) where the caller
    has them."""
    if not COMPILED or block.curved:
        return ply_landing.landing(block, state, history, facing)
    if rows is None:
        rows = ply_landing.landing_rows(block, history, facing)
    if len(rows) == 0:
        return None
    sides = history.sides
    assert sides is not None  # (landing_rows finds none without them)
    _, y = block._faces(state)
    count = len(rows)
    none = np.zeros(0, dtype=np.bool_)
    on_edge = none if facing.on_edge is None else facing.on_edge
    plane_zero = none
    if facing.on_growth is not None and facing.joined is not None:
        plane_zero = facing.on_growth & ~facing.joined
    rate, weights, normal = np.empty((count, 3)), np.empty((count, 3)), np.empty((count, 3))
    theta, dtheta, height = np.empty(count), np.empty(count), np.empty(count)
    gradients = np.empty((count, 3, 3))
    edge = np.empty(count, dtype=np.bool_)
    place = np.full((count, 3), np.nan)
    _landing_compiled(
        writable(rows, np.int64),
        read_only(facing.triangle, np.int64),
        read_only(sides.corners),
        read_only(y),
        read_only(sides.faces),
        read_only(facing.face),
        read_only(facing.gap),
        read_only(facing.weights),
        read_only(facing.normal),
        read_only(on_edge, np.bool_),
        read_only(plane_zero, np.bool_),
        ply_landing.TILT,
        rate,
        theta,
        dtheta,
        weights,
        gradients,
        normal,
        height,
        edge,
        place,
    )
    if not edge.any():
        return ply_landing.Landing(rows, rate, theta, dtheta, weights, gradients, normal, height)
    # what the tangent moves the edge rows' anchors by (``ply_landing.landing``'s Crossing)
    crossing = ply_landing.edge_rows_crossing(facing, sides, y, rows[edge])
    return ply_landing.Landing(
        rows, rate, theta, dtheta, weights, gradients, normal, height, edge, place, crossing
    )
