"""The gap of a ply contact's point to its closest point q on an edge or at a vertex of its
facing triangle, grown past the outline (elements/ply_projection.py, "Search"): g = +-|p - q|,
its gradient nu = (p - q) / g and its Hessian over z = (p, y_1, y_2, y_3), which the tangent
takes (elements/ply_block.py), on the grown triangle's edges and at its corners, and on the
cuts of the growths past an outline vertex of three or more triangles (elements/ply_wedge.py).
"""

from __future__ import annotations

import numpy as np

__all__ = ["edge_hessian", "towards_closest"]


def towards_closest(p, q, normal, corners, gradients, reach, second, cut=None):
    """Gap, normal nu, barycentric coordinates of q and d2g/dz2 (``edge_hessian``) of points
    p (c, 3) against their closest points q (c, 3) on an edge or at a vertex of their
    triangles (corners (c, 3, 3), gradients (c, 3, 3), unit normals (c, 3), grown by
    ``reach`` (c, 3)); the Hessian None unless ``second``; ``cut``: (c,) bool, q lies on a
    cut's segment, (c, 2, 3) its ends' barycentric coordinates, (c,) q's parameter on it
    (elements/ply_wedge.py ``closest_on_cut``), or None."""
    r = p - q
    length = np.linalg.norm(r, axis=-1)
    sign = np.where(np.sum(r * normal, axis=-1) < 0.0, -1.0, 1.0)
    gap = sign * length
    tiny = length <= 1e-12 * (1.0 + np.linalg.norm(p, axis=-1))
    nu = np.where(tiny[:, None], normal, r / np.where(tiny, 1.0, gap)[:, None])
    weights = np.einsum("pki,pi->pk", gradients, q - corners[:, 0, :])
    weights[:, 0] += 1.0
    if not second:
        return gap, nu, weights, None
    return gap, nu, weights, edge_hessian(gap, nu, weights, corners, reach, tiny, cut)


def edge_hessian(gap, nu, weights, corners, reach, tiny, cut=None):
    """d2g/dz2 (c, 4, 3, 4, 3), 1/mm, over z = (p, y_1, y_2, y_3) of g = +-|p - q|, q the
    closest point at a corner G_i y of the grown triangle (``grown_corners``'s rows G) or on its
    edge from u = G_a y to v = G_b y. At a corner, a a^T (x) (I - nu nu^T) / g with
    a = (1, -lambda), lambda the barycentric coordinates of q; on an edge e = v - u (unit e^,
    length L) q slides along it, and minimising over its parameter gives, with
    m = (0, G_b - G_a),

        (1/g) a a^T (x) (I - nu nu^T - e^ e^T) - (1/L) (a m^T (x) e^ nu^T + m a^T (x) nu e^T)
        - (g / L^2) m m^T (x) nu nu^T.

    On a cut (``cut``, elements/ply_wedge.py) u and v are the cut's ends, inside it on_edge.
    """
    count = len(gap)
    at_bound = weights <= -reach + 1e-9
    on_edge = at_bound.sum(axis=1) == 1
    ends = np.argsort(at_bound, axis=1, kind="stable")[:, :2]  # the two corners off the bound
    grow = np.eye(3) * (1.0 + reach.sum(axis=-1))[:, None, None] - reach[:, None, :]
    rows = np.arange(count)
    a = np.concatenate([np.ones((count, 1)), -weights], axis=1)  # (c, 4)
    m = np.zeros((count, 4))
    m[:, 1:] = grow[rows, ends[:, 1]] - grow[rows, ends[:, 0]]
    if cut is not None and cut[2] is not None and cut[0].any():
        on_cut, segment, along = cut
        m[on_cut, 1:] = segment[on_cut, 1] - segment[on_cut, 0]
        on_edge = np.where(on_cut, (along > 0.0) & (along < 1.0), on_edge)
    e = np.einsum("ck,cki->ci", m[:, 1:], corners)
    length = np.linalg.norm(e, axis=1)
    unit = e / length[:, None]
    safe = np.where(tiny, 1.0, gap)
    nn = nu[:, :, None] * nu[:, None, :]
    across = (
        np.eye(3) - nn - np.where(on_edge[:, None, None], unit[:, :, None] * unit[:, None, :], 0.0)
    )

    def outer(left, right, block):  # (c, 4, 3, 4, 3): left_z right_w block_ij
        return (
            left[:, :, None, None, None]
            * right[:, None, None, :, None]
            * block[:, None, :, None, :]
        )

    hessian = outer(a, a, across / safe[:, None, None])
    slide = np.where(on_edge, 1.0, 0.0)
    en = unit[:, :, None] * nu[:, None, :]
    hessian -= (slide / length)[:, None, None, None, None] * (
        outer(a, m, en) + outer(m, a, np.swapaxes(en, 1, 2))
    )
    hessian -= (slide * gap / length**2)[:, None, None, None, None] * outer(m, m, nn)
    return np.where(tiny[:, None, None, None, None], 0.0, hessian)
