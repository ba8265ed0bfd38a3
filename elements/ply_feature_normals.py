"""The unit pseudonormal of the edge or vertex on which a ply contact point's closest point
lies, compiled for one point at a time (elements/ply_facets.py ``_feature_normals``;
elements/ply_projection.py, "The sign at an edge" and "Growths joined"; docs/theory.md, the
ply contact section): which edge or vertex holds the closest point, the sum of its
triangles' unit normals (weighted at a vertex by their angles there, over the face's
topology tables, elements/ply_topology.py), whether the point lies on an edge's extension
that two growths hold, and the facing triangle's normal where the face has no side there.
``closest_facing``'s two passes after the choice (elements/ply_edge_kernels.py) call these
helpers: ``fan_parts`` gives the parts of the fan's angles, whose ``arctan2`` numpy takes
between the passes, and ``signing_at`` the normal.

Their numpy reference is ``ply_facets._feature_normals`` (with ``pseudonormals_at`` and
``_joined_growth``), taken with ``ply_projection.COMPILED = False``. The helpers do the same
IEEE operations in the same order (each sum of the tables' terms from 0.0 in their order, as
``np.bincount`` adds them; numpy's sums of three terms: ``np.linalg.norm`` from the first
term, ``einsum("mki,mki->mk")`` as (first + last) + middle; no fused multiply-add: numba
builds without fastmath). The angles' ``arctan2`` stays numpy's: numpy evaluates it with its
own vectorised routine, whose last bit libm's ``atan2`` does not always give, and which gives
an element the same bits wherever it stands in the array. So the normals are the same to the
last bit (tests/test_ply_kernels.py, the passes against numpy's ``closest_facing``). Each
point is independent: the same bits on any thread count.
"""

from __future__ import annotations

import numpy as np

from femcore.jit import lanes

__all__ = ["fan_parts", "signing_at"]


@lanes
def _where(lam, reach, inside):
    """(count of the bounds the closest point lies on, the first corner off them, the first
    corner on one, on a growth off the triangle) of the coordinates ``lam`` (3,) with the
    triangle's ``reach`` (3,) (``_feature_normals``' bound, count, corner, side, grown)."""
    count = 0
    corner = -1
    side = -1
    grown = False
    for k in range(3):
        bound = lam[k] <= -reach[k] + 1e-9
        if bound:
            count += 1
            if side < 0:
                side = k
        elif corner < 0:
            corner = k
        if lam[k] < -inside and reach[k] > 0.0:
            grown = True
    return count, max(corner, 0), max(side, 0), grown


@lanes
def fan_parts(row, lam, reach, y, nodes, fans, inside, rise, run):
    """rise and run (f,): |u x v| and u . v of the angle at each corner of the fan of the
    vertex at which the closest point of coordinates ``lam`` (3,) on triangle ``row`` with
    ``reach`` (3,) lies (``pseudonormals``' angles, whose ``arctan2`` numpy takes), 0 where
    it is not at a vertex or the fan has no more corners; y (m, 3, 3) the corners, nodes
    (m, 3), fans (v, f)."""
    count, corner, _, _ = _where(lam, reach, inside)
    vertex = nodes[row, corner]
    for f in range(fans.shape[1]):
        rise[f] = 0.0
        run[f] = 0.0
        at = fans[vertex, f]
        if count != 2 or at < 0:
            continue
        t, k = at // 3, at % 3
        a, b = (k + 1) % 3, (k + 2) % 3
        u0, u1, u2 = y[t, a, 0] - y[t, k, 0], y[t, a, 1] - y[t, k, 1], y[t, a, 2] - y[t, k, 2]
        v0, v1, v2 = y[t, b, 0] - y[t, k, 0], y[t, b, 1] - y[t, k, 1], y[t, b, 2] - y[t, k, 2]
        c0 = u1 * v2 - u2 * v1
        c1 = u2 * v0 - u0 * v2
        c2 = u0 * v1 - u1 * v0
        rise[f] = np.sqrt((c0 * c0 + c1 * c1) + c2 * c2)
        run[f] = (u0 * v0 + u2 * v2) + u1 * v1


@lanes
def _unit_normal(y, t, out):
    """out (3,) the unit normal of triangle ``t`` of y (m, 3, 3) (``triangle_frames``)."""
    e0, e1, e2 = y[t, 1, 0] - y[t, 0, 0], y[t, 1, 1] - y[t, 0, 1], y[t, 1, 2] - y[t, 0, 2]
    f0, f1, f2 = y[t, 2, 0] - y[t, 0, 0], y[t, 2, 1] - y[t, 0, 1], y[t, 2, 2] - y[t, 0, 2]
    c0 = e1 * f2 - e2 * f1
    c1 = e2 * f0 - e0 * f2
    c2 = e0 * f1 - e1 * f0
    twice = np.sqrt((c0 * c0 + c1 * c1) + c2 * c2)
    out[0], out[1], out[2] = c0 / twice, c1 / twice, c2 / twice


@lanes
def signing_at(
    row,
    y,
    nodes,
    fans,
    edges,
    edge_halves,
    other,
    outline,
    has_outline,
    lam,
    reach,
    normal,
    inside,
    angles,
    signing,
):
    """signing (3,) as ``ply_projection._feature_normals`` gives it for one closest point of
    coordinates ``lam`` (3,) on triangle ``row`` with ``reach`` (3,) and normal (3,), from the
    face's tables (elements/ply_topology.py: nodes, fans, edges, edge_halves, other; its
    outline (m, 3) bool where ``has_outline``) and its fan's angles (f,) (``fan_parts``'
    arctan2); whether the point lies on a joined edge's extension, returned."""
    count, corner, side, grown = _where(lam, reach, inside)
    s0, s1, s2 = 0.0, 0.0, 0.0
    unit = np.empty(3)
    if count == 2:  # the vertex's angle-weighted sum, in its fan's order
        vertex = nodes[row, corner]
        for f in range(fans.shape[1]):
            at = fans[vertex, f]
            if at < 0:
                s0, s1, s2 = s0 + 0.0, s1 + 0.0, s2 + 0.0
                continue
            _unit_normal(y, at // 3, unit)
            w = angles[f]
            s0, s1, s2 = s0 + w * unit[0], s1 + w * unit[1], s2 + w * unit[2]
    else:  # the edge's sum over its half-edges
        edge = edges[row, side]
        for h in range(edge_halves.shape[1]):
            half = edge_halves[edge, h]
            if half < 0:
                s0, s1, s2 = s0 + 0.0, s1 + 0.0, s2 + 0.0
                continue
            _unit_normal(y, half // 3, unit)
            s0, s1, s2 = s0 + unit[0], s1 + unit[1], s2 + unit[2]
    on_joined = False
    if has_outline and grown and count == 1:  # ply_projection._joined_growth
        own = row * 3 + side
        across = other[own]
        past = -1
        least = np.inf
        for k in range(3):
            value = np.inf if k == side else lam[k]
            if past < 0 or value < least:
                past, least = k, value
        node = nodes[row, past]
        neighbour = across // 3
        at = 0
        for k in range(3):
            if nodes[neighbour, k] == node:
                at = k
                break
        on_joined = (
            across != own and outline[row, past] and outline[neighbour, at] and lam[past] < 0.0
        )
    length = np.sqrt((s0 * s0 + s1 * s1) + s2 * s2)
    keep = (grown and not on_joined) or count == 0 or count == 3 or length < 1e-6
    joined = on_joined and not keep
    if keep:
        signing[0], signing[1], signing[2] = normal[0], normal[1], normal[2]
    else:
        divisor = length if length > 0.0 else 1.0
        signing[0], signing[1], signing[2] = s0 / divisor, s1 / divisor, s2 / divisor
    return joined
