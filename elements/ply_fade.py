"""The ply contact's fade past the lower ply's outline (elements/ply_projection.py, "Past the
outline, faded"; docs/theory.md §9.3a): the weight w in [0, 1] that multiplies a contact
point's penalty energy, W_p = w W(g), and its exact gradient, so that the contact's force, w W'
dg/dz + W dw/dz, stays the gradient of its energy where the point leaves the lower ply's face.

Two factors, each a smoothstep of a quantity continuous in the point and the facing triangle's
corners z = (p, y_1, y_2, y_3):

- past the outline, w_e = prod_k S(1 + lambda_k / FADE) over the facing triangle's outline
  edges k (those its plane reaches ``MARGIN`` past), lambda the barycentric coordinates of the
  projection of p on its plane and S(u) = 3 u^2 - 2 u^3 on [0, 1] (0 below, 1 above): 1 over
  the triangle, 0 from ``FADE`` past the edge in barycentric units on, before the growth's far
  edge (``MARGIN``), where a point used to pass between touching and beside;
- beside the growth, where the point's closest point q lies on a growth's edge off the
  triangle (the wedge next to an outline vertex that no growth's plane holds) or at a vertex
  of the outline (the facing triangle's normal signing the gap there), w_a =
  S(|h| / (SIDEWAYS |p - q|)), h the gap to the triangle's plane: 1 where p - q lies within
  60 deg of the normal, 0 where p lies in the plane beside the growth, the one place where the
  sign of g = +-|p - q| flips at a distance from q.

Gradients: d lambda_k = grad phi_k . (dp - h dn - sum_m lambda_m dy_m) with dn/dy_m = -grad
phi_m n^T (elements/ply_block.py, ``tangent``); dh/dz = (n, -lambda_m n); dg/dz = (nu,
-lambda_m(q) nu), nu = (p - q) / g, lambda(q) the coordinates of q (the closest point's own
gradient, elements/ply_projection.py); d(h / g) = (dh - (h / g) dg) / g. The second
derivative of w, which only the tangent needs, is the central difference of this exact
gradient (``fade_hessian``).

Stiffness (``stiffness_factor``, for the explicit step's springs). The fade's energy w W(g)
is stiffer than the penalty k along some directions of p. Beside a growth, with r = |p - q|,
theta the angle of p - q to the normal and w_a(theta) = S(cos theta / SIDEWAYS), the energy
E = W(r) w_a has in the orthonormal (r, theta) directions the Hessian [[W'' w_a, (W'/r -
W/r^2) w_a'], [., (W'/r) w_a + (W/r^2) w_a'']] (the azimuth of a vertex adds (W'/r) w_a +
(W/r^2) cot(theta) w_a' <= k, w_a' <= 0). With W'' <= k, W'/r <= k, 0 <= W'/r - W/r^2 <= k/2
and W/r^2 <= k/2 (W convex from W(0) = W'(0) = 0, W'' <= k) its largest eigenvalue is at
most k max_theta lambda_max [[w_a, |w_a'| / 2], [|w_a'| / 2, w_a + max(w_a'', 0) / 2]] =
k S''(0) / (2 SIDEWAYS^2) = 12 k, reached at theta = 90 deg (p in the triangle's plane beside
q, w_a = w_a' = 0: E ~ 6 k h^2 for a gap h to the plane), whatever r. The past factor w_e is
a function of the coordinates lambda, linear in p: |grad w_e| <= 1.5 G / FADE and
||hess w_e|| <= 6 (G / FADE)^2, G = sum_k |grad phi_k| over the outline edges (1 / the
heights); with |grad (W w_a)| <= k r (1 + (0.75 / SIDEWAYS)^2)^(1/2) and W w_a <= k r^2 / 2,
the product's Hessian is at most k (12 + 3 A x + 3 x^2), x = r G / FADE, A = (1 + (0.75 /
SIDEWAYS)^2)^(1/2), r = |p - q| = |g|: at most the plies' half thicknesses a + b, or the
point's own depth where it lies deeper (past the outline the fade carries a point at any
depth, elements/ply_projection.py "Past the outline, deeper than the plies").
"""

from __future__ import annotations

import numpy as np

from elements.ply_projection import closest_on_edges, facets, grown_corners

__all__ = ["FADE", "SIDEWAYS", "fade_hessian", "outline_fade", "stiffness_factor"]

#: Barycentric units past an outline edge over which the contact fades out (< MARGIN = 0.5).
FADE = 0.15
#: |h| / |p - q| (the cosine of p - q's angle with the normal) from which a point beside a
#: growth's edge has its full weight.
SIDEWAYS = 0.5


#: The largest stiffness of the angle's fade beside a growth, in times the penalty k: S''(0) /
#: (2 SIDEWAYS^2) (module docstring, "Stiffness").
SIDEWAYS_STIFFNESS = 3.0 / SIDEWAYS**2


def _step(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """S(u) = 3 u^2 - 2 u^3 clamped to [0, 1], and dS/du."""
    u = np.clip(u, 0.0, 1.0)
    return u * u * (3.0 - 2.0 * u), 6.0 * u * (1.0 - u)


def outline_fade(
    p: np.ndarray, corners: np.ndarray, reach: np.ndarray, beside: np.ndarray
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

    Returns
    -------
    w : (c,) float
        The fade, in [0, 1].
    gradient : (c, 4, 3) float
        dw/dz over z = (p, y_1, y_2, y_3), 1/mm.
    """
    count = len(p)
    n, _, grad, plane, lam = (a[:, 0] for a in facets(p, corners[:, None]))
    # d lambda_k / dz, (c, 3, 4, 3)
    dlam = np.zeros((count, 3, 4, 3))
    dlam[:, :, 0, :] = grad
    dots = np.einsum("cki,cmi->ckm", grad, grad)
    dlam[:, :, 1:, :] = (
        -lam[:, None, :, None] * grad[:, :, None, :]
        + (plane[:, None, None] * dots)[..., None] * n[:, None, None, :]
    )
    outline = reach > 0.0
    factor, slope = _step(1.0 + lam / FADE)
    factor = np.where(outline, factor, 1.0)
    slope = np.where(outline, slope / FADE, 0.0)
    others = np.stack(
        [factor[:, 1] * factor[:, 2], factor[:, 0] * factor[:, 2], factor[:, 0] * factor[:, 1]],
        axis=1,
    )
    past = factor.prod(axis=1)
    past_gradient = np.einsum("ck,ckzi->czi", others * slope, dlam)
    side = np.ones(count)
    side_gradient = np.zeros((count, 4, 3))
    at = np.flatnonzero(beside)
    if at.size:
        c = corners[at]
        q = closest_on_edges(p[at], grown_corners(c, reach[at]))
        r = p[at] - q
        distance = np.linalg.norm(r, axis=1)
        sign = np.where(plane[at] < 0.0, -1.0, 1.0)
        gap = sign * distance
        safe = np.where(distance > 0.0, gap, 1.0)
        nu = r / safe[:, None]
        on_q = np.einsum("cki,ci->ck", grad[at], q - c[:, 0])
        on_q[:, 0] += 1.0
        ratio = np.where(distance > 0.0, plane[at] / safe, 1.0)
        d_plane = np.concatenate(
            [n[at][:, None, :], -lam[at][:, :, None] * n[at][:, None, :]], axis=1
        )
        d_gap = np.concatenate([nu[:, None, :], -on_q[:, :, None] * nu[:, None, :]], axis=1)
        d_ratio = (d_plane - ratio[:, None, None] * d_gap) / safe[:, None, None]
        value, rise = _step(ratio / SIDEWAYS)
        side[at] = value
        side_gradient[at] = np.where(
            (distance > 0.0)[:, None, None], (rise / SIDEWAYS)[:, None, None] * d_ratio, 0.0
        )
    weight = past * side
    gradient = side[:, None, None] * past_gradient + past[:, None, None] * side_gradient
    return weight, gradient


def fade_hessian(
    p: np.ndarray, corners: np.ndarray, reach: np.ndarray, beside: np.ndarray, step: float
) -> np.ndarray:
    """(c, 4, 3, 4, 3) d2w/dz2, 1/mm^2: the central difference of ``outline_fade``'s exact
    gradient by ``step`` (mm) in each of the 12 coordinates of z, made symmetric."""
    count = len(p)
    hessian = np.zeros((count, 4, 3, 4, 3))
    for node in range(4):
        for axis in range(3):
            moved = []
            for sign in (1.0, -1.0):
                q, c = p.copy(), corners.copy()
                if node == 0:
                    q[:, axis] += sign * step
                else:
                    c[:, node - 1, axis] += sign * step
                moved.append(outline_fade(q, c, reach, beside)[1])
            hessian[:, node, axis] = (moved[0] - moved[1]) / (2.0 * step)
    return 0.5 * (hessian + np.transpose(hessian, (0, 3, 4, 1, 2)))


def stiffness_factor(
    gradients: np.ndarray,
    reach: np.ndarray,
    band: np.ndarray,
    beside: np.ndarray,
    depth: float | np.ndarray,
) -> np.ndarray:
    """An upper bound c_p >= 1 of the stiffness of the faded energy w W(g) along any direction
    of the point p, in times the penalty k (module docstring, "Stiffness").

    Parameters
    ----------
    gradients : (c, 3, 3) float
        grad phi_k of the points' facing triangles, 1/mm (row k).
    reach : (c, 3) float
        How far each triangle reaches past the edge opposite corner k (> 0: an outline edge).
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

    Returns
    -------
    (c,) float
        (12 beside, else 1) + 3 A x + 3 x^2 in the band (x = depth G / FADE), 1 elsewhere.
    """
    spread = np.where(reach > 0.0, np.linalg.norm(gradients, axis=2), 0.0).sum(axis=1)
    x = depth * spread / FADE
    cross = np.sqrt(1.0 + (0.75 / SIDEWAYS) ** 2)
    angle = np.where(beside, max(1.0, SIDEWAYS_STIFFNESS), 1.0)
    return np.where(band | beside, angle + 3.0 * cross * x + 3.0 * x * x, 1.0)
