"""The exact second derivative of the ply contact's fade w past the lower ply's outline
(elements/ply_fade.py, whose docstring gives w and its gradient), which the contact's tangent
takes in W Hess w (elements/ply_block_tangent.py, ``fade_tangent``).

Over z = (p, y_1, y_2, y_3, a, b), with the quantities of ``outline_fade``: h the gap to the
facing triangle's plane (unit normal n, barycentric gradients grad phi_k, coordinates
lambda of the projection), g the gap to the grown face (h on a plane; beside a growth's edge
or at an outline vertex g = +-|p - q|, q the cut growth's closest point), d^2 = Q = |r_o|^2 -
g^2 (r_o = p - a - t e, e = b - a, t the parameter of the outline's closest point),

    w = w_e w_a,   w_e = S(1 - s), s = sqrt(Q) / D,   w_a = S(rho / SIDEWAYS), rho = h / g,

    Hess w = w_a Hess w_e + w_e Hess w_a + grad w_a grad w_e^T + grad w_e grad w_a^T,
    Hess w_e = -3 (1 - s) / D^2 Hess Q + 3 / (2 D^3 sqrt(Q)) dQ dQ^T,
    Hess Q = Hess |r_o|^2 - 2 dg dg^T - 2 g Hess g,
    Hess w_a = S''(u) / SIDEWAYS^2 drho drho^T + S'(u) / SIDEWAYS Hess rho,  u = rho / SIDEWAYS,
    Hess rho = (Hess h - rho Hess g - drho dg^T - dg drho^T) / g,

(S'' = 6 - 12 u on (0, 1), 0 where S is clamped; sqrt(Q) dQ dQ^T / Q stays bounded, |dQ| ~ 2
sqrt(Q), so w_e is C1 and its Hessian finite at the outline edge). The parts:

- Hess h, the plane's gap (as the contact's own, elements/ply_block_tangent.py ``tangent``): H_pp =
  0, H_p,m = -grad phi_m n^T, H_k,m = -h (grad phi_k . grad phi_m) n n^T + lambda_m n grad
  phi_k^T + lambda_k grad phi_m n^T;
- Hess g: Hess h on a plane; beside, the distance's to its closest point on a grown edge, at
  a corner or on a cut (elements/ply_edge_gap.py ``edge_hessian``);
- Hess |r_o|^2 over (p, a, b): with dr_o/dz = B = (I, -(1 - t) I, -t I), 2 B^T B where t is
  clamped at an end of the edge; inside it the envelope of the minimum over t, 2 B^T B -
  (2 / |e|^2) v v^T, v = (-e, (1 - t) e + r_o, t e - r_o) (f_zz - f_zt f_zt^T / f_tt of f =
  |p - (1 - t) a - t b|^2).

Why closed form. The tangent took Hess w as the central difference of the exact gradient by a
step of 1e-6 (1 + max |y|) mm: 1e-4 mm on a blank 100 mm from the origin, where w_a varies
over h ~ SIDEWAYS |p - q|, which near an outline vertex is as small as the point's distance
from it: 1e-3 mm from a vertex the tangent was 17 % off central differences of the force
(tests/test_ply_fade_hessian.py). The closed form has no length of its own. It is the
derivative of w where w is smooth: where the facing feature (q's edge, corner or cut, the
outline's nearest edge, t's clamp) changes, w's gradient kinks, and a central difference
across the kink gave an average of the two sides that no side has.
"""

from __future__ import annotations

import numpy as np

from elements.ply_edge_gap import edge_hessian
from elements.ply_fade import SIDEWAYS
from elements.ply_projection import facets
from elements.ply_wedge import closest_on_grown

__all__ = ["fade_hessian", "plane_hessian"]


def plane_hessian(
    gap: np.ndarray, normal: np.ndarray, weights: np.ndarray, gradients: np.ndarray
) -> np.ndarray:
    """(c, 4, 3, 4, 3) d2h/dz2 over z = (p, y_1, y_2, y_3), 1/mm, of the signed distance h
    (c,) mm of points from their triangles' planes (unit normals (c, 3), the projections'
    barycentric coordinates (c, 3), barycentric gradients (c, 3, 3) 1/mm; module
    docstring)."""
    count = len(gap)
    hessian = np.zeros((count, 4, 3, 4, 3))
    nn = normal[:, :, None] * normal[:, None, :]
    dots = np.einsum("cki,cmi->ckm", gradients, gradients)
    for m in range(3):
        hessian[:, 0, :, 1 + m, :] = -gradients[:, m, :, None] * normal[:, None, :]
        hessian[:, 1 + m, :, 0, :] = -normal[:, :, None] * gradients[:, m, None, :]
        for k in range(3):
            hessian[:, 1 + k, :, 1 + m, :] = (
                -(gap * dots[:, k, m])[:, None, None] * nn
                + weights[:, m, None, None] * normal[:, :, None] * gradients[:, k, None, :]
                + weights[:, k, None, None] * gradients[:, m, :, None] * normal[:, None, :]
            )
    return hessian


def _outer(left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """(c, 6, 3, 6, 3) left right^T of two gradients (c, 6, 3)."""
    return left[:, :, :, None, None] * right[:, None, None, :, :]


def fade_hessian(
    p: np.ndarray,
    corners: np.ndarray,
    reach: np.ndarray,
    beside: np.ndarray,
    ends: np.ndarray,
    length: float,
    joined: np.ndarray | None = None,
    lines: np.ndarray | None = None,
    ends_cut: np.ndarray | None = None,
) -> np.ndarray:
    """(c, 6, 3, 6, 3) d2w/dz2 over z = (p, y_1, y_2, y_3, a, b), 1/mm^2, of the fade of
    ``outline_fade`` (elements/ply_fade.py; the same arguments), in closed form (module
    docstring); symmetric."""
    count = len(p)
    n, _, grad, plane, lam = (a[:, 0] for a in facets(p, corners[:, None]))
    d_plane = np.concatenate([n[:, None, :], -lam[:, :, None] * n[:, None, :]], axis=1)
    h_plane = plane_hessian(plane, n, lam, grad)  # (c, 4, 3, 4, 3)
    gap = plane.copy()
    d_gap = np.zeros((count, 6, 3))
    d_gap[:, :4] = d_plane
    h_gap = np.zeros((count, 6, 3, 6, 3))
    h_gap[:, :4, :, :4, :] = h_plane
    side = np.ones(count)
    side_gradient = np.zeros((count, 6, 3))
    side_hessian = np.zeros((count, 6, 3, 6, 3))
    at = np.flatnonzero(beside)
    if at.size:
        c = corners[at]
        q, on_cut, segment, along = closest_on_grown(
            p[at],
            c,
            reach[at],
            None if lines is None else lines[at],
            None if ends_cut is None else ends_cut[at],
        )
        r = p[at] - q
        distance = np.linalg.norm(r, axis=1)
        sign = np.where(plane[at] < 0.0, -1.0, 1.0)
        safe = np.where(distance > 0.0, sign * distance, 1.0)
        nu = r / safe[:, None]
        on_q = np.einsum("cki,ci->ck", grad[at], q - c[:, 0])
        on_q[:, 0] += 1.0
        ratio = np.where(distance > 0.0, plane[at] / safe, 1.0)
        d_edge = np.concatenate([nu[:, None, :], -on_q[:, :, None] * nu[:, None, :]], axis=1)
        tiny = distance <= 0.0
        h_edge = edge_hessian(
            safe, nu, on_q, c, reach[at], tiny, (on_cut, segment, along) if on_cut.any() else None
        )
        # rho = h / g: d rho = (dh - rho dg) / g, Hess rho = (Hess h - rho Hess g - d rho dg^T
        # - dg d rho^T) / g
        d_ratio = (d_plane[at] - ratio[:, None, None] * d_edge) / safe[:, None, None]
        cross = d_ratio[:, :, :, None, None] * d_edge[:, None, None, :, :]
        h_ratio = (h_plane[at] - ratio[:, None, None, None, None] * h_edge - cross) / safe[
            :, None, None, None, None
        ]
        h_ratio -= np.transpose(cross, (0, 3, 4, 1, 2)) / safe[:, None, None, None, None]
        u = ratio / SIDEWAYS
        clamped = np.clip(u, 0.0, 1.0)
        value = clamped * clamped * (3.0 - 2.0 * clamped)
        open_ = (u > 0.0) & (u < 1.0)
        rise = np.where(open_, 6.0 * clamped * (1.0 - clamped), 0.0)
        bend = np.where(open_, 6.0 - 12.0 * clamped, 0.0)
        # on a joined edge the face has a side (the edge's pseudonormal's): no angle factor
        sideways = np.ones(at.size, dtype=bool) if joined is None else ~joined[at]
        live = (distance > 0.0) & sideways
        side[at] = np.where(sideways, value, 1.0)
        side_gradient[at, :4] = np.where(
            live[:, None, None], (rise / SIDEWAYS)[:, None, None] * d_ratio, 0.0
        )
        side_hessian[at, :4, :, :4, :] = np.where(
            live[:, None, None, None, None],
            (bend / SIDEWAYS**2)[:, None, None, None, None]
            * d_ratio[:, :, :, None, None]
            * d_ratio[:, None, None, :, :]
            + (rise / SIDEWAYS)[:, None, None, None, None] * h_ratio,
            0.0,
        )
        gap[at] = sign * distance
        moving = (distance > 0.0)[:, None, None]
        d_gap[at, :4] = np.where(moving, d_edge, 0.0)
        h_gap[at] = 0.0
        h_gap[at, :4, :, :4, :] = np.where(moving[..., None, None], h_edge, 0.0)
    # past the outline: Q = d^2 = |r_o|^2 - g^2, w_e = S(1 - sqrt(Q) / D)
    past = beside | np.any((reach > 0.0) & (lam < 0.0), axis=1)
    a, b = ends[:, 0], ends[:, 1]
    e = b - a
    squared_e = np.maximum(np.einsum("ci,ci->c", e, e), 1e-300)
    raw_t = np.einsum("ci,ci->c", p - a, e) / squared_e
    t = np.clip(raw_t, 0.0, 1.0)
    r_o = p - a - t[:, None] * e
    raw = np.einsum("ci,ci->c", r_o, r_o) - gap * gap
    d_squared = np.zeros((count, 6, 3))
    d_squared[:, 0] = 2.0 * r_o
    d_squared -= 2.0 * gap[:, None, None] * d_gap
    d_squared[:, 4] = -2.0 * (1.0 - t)[:, None] * r_o
    d_squared[:, 5] = -2.0 * t[:, None] * r_o
    # Hess |r_o|^2 over (p, a, b) = (0, 4, 5): 2 B^T B, less the envelope's part inside
    coefficient = np.stack([np.ones(count), -(1.0 - t), -t], axis=1)  # (c, 3)
    h_squared = np.zeros((count, 6, 3, 6, 3))
    eye = np.eye(3)
    slide = (raw_t > 0.0) & (raw_t < 1.0)
    v = np.stack([-e, (1.0 - t)[:, None] * e + r_o, t[:, None] * e - r_o], axis=1)  # (c, 3, 3)
    envelope = np.where(slide, 2.0 / squared_e, 0.0)
    for i, zi in enumerate((0, 4, 5)):
        for j, zj in enumerate((0, 4, 5)):
            h_squared[:, zi, :, zj, :] = (
                2.0 * (coefficient[:, i] * coefficient[:, j])[:, None, None] * eye
                - envelope[:, None, None] * v[:, i, :, None] * v[:, j, None, :]
            )
    h_squared -= 2.0 * _outer(d_gap, d_gap) + 2.0 * gap[:, None, None, None, None] * h_gap
    squared = np.maximum(raw, 0.0)
    root = np.sqrt(squared)
    s = root / length
    within = past & (s < 1.0) & (raw > 0.0)
    factor = np.where(past, np.where(s < 1.0, (1.0 - s) ** 2 * (1.0 + 2.0 * s), 0.0), 1.0)
    slope = np.where(within, -3.0 * (1.0 - s) / length**2, 0.0)
    curl = np.where(within, 1.5 / (length**3 * np.where(within, root, 1.0)), 0.0)
    past_gradient = slope[:, None, None] * d_squared
    past_hessian = slope[:, None, None, None, None] * h_squared + curl[
        :, None, None, None, None
    ] * _outer(d_squared, d_squared)
    cross = _outer(side_gradient, past_gradient)
    hessian = (
        side[:, None, None, None, None] * past_hessian
        + factor[:, None, None, None, None] * side_hessian
        + cross
        + np.transpose(cross, (0, 3, 4, 1, 2))
    )
    return 0.5 * (hessian + np.transpose(hessian, (0, 3, 4, 1, 2)))
