"""How the landing anchor of a ply contact point whose gap is to an edge or a vertex of the
lower face moves with the state (elements/ply_landing.py ``edge_crossing``; docs/theory.md
§9.3a, "A point's landing step"): its derivative dLambda_a/dz over z = (p, y_1, y_2, y_3), T's
corners now, which the friction's tangent carries as it carries a face point's
(elements/ply_friction_tangent.py ``friction_tangent``).

The crossing depends on z through p and T's corners directly and through the edge's closest
point: its barycentric coordinates lambda (q = sum_k lambda_k y_k, and q_0 = sum_k lambda_k
y_0,k on T's corners then) and the gap's normal nu = (p - q) / g. Both come from the gap's
Hessian d2g/dz2 the search gives (elements/ply_edge_gap.py ``edge_hessian``): dg/dp = nu and
dg/dy_k = -lambda_k nu, so dnu/dz is the Hessian's p rows and, |nu| being 1,

    dlambda_k/dz = -nu^T d2g/(dy_k dz).

With m the zero's normal (nu, or T's normal n where n signs the gap, dn/dy_m = -grad phi_m
n^T), g_0 = max(m . (p_0 - q_0), 0), pen = max(-m . (p - q), 0) and theta = g_0 / (g_0 + pen):

    dtheta = (pen dg_0 - g_0 dpen) / (g_0 + pen)^2,

the crossing's place and height Lambda_c = Lambda_0 + theta (Lambda - Lambda_0), rise = h_0 +
theta (h - h_0) (dLambda_k/dp = grad phi_k^T, dLambda_k/dy_m = -Lambda_m grad phi_k^T + h (grad
phi_k . grad phi_m) n^T, dh/dp = n^T, dh/dy_m = -Lambda_m n^T), and the move onto T's plane
Lambda_a = Lambda_c - a (grad phi_k . nu), a = rise t / max(t^2, TILT^2), t = n . nu (the
places then, p_0 and T's corners then, held), with d grad phi_k/dy_m = -grad phi_m grad
phi_k^T + (grad phi_k . grad phi_m) n n^T. A point at its edge (g = 0: the Hessian 0 there)
takes lambda and nu held.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from elements.ply_projection import triangle_frames

__all__ = ["Crossing", "crossing_motion"]


@dataclass(frozen=True)
class Crossing:
    """What ``edge_crossing`` made the edge rows' landing anchors from: its arguments, the
    zero's normal m given as the flag ``plane`` (m = n where set, else nu).

    before, now : (e, 3, 3) float
        T's corners at the last accepted state and now, mm.
    then, point : (e, 3) float
        The points' contact points then and now, mm.
    feature : (e, 3) float
        The barycentric coordinates on T of the closest point q now.
    normal : (e, 3) float
        nu, the gap's normal now.
    plane : (e,) bool
        The gap's zero is T's plane (m = n; else m = nu).
    """

    before: np.ndarray
    now: np.ndarray
    then: np.ndarray
    point: np.ndarray
    feature: np.ndarray
    normal: np.ndarray
    plane: np.ndarray


def crossing_motion(crossing: Crossing, hessian: np.ndarray, tilt_floor: float) -> np.ndarray:
    """(e, 3, 4, 3) dLambda_a,k/dz of the edge rows' landing anchors (module docstring), 1/mm,
    over z = (p, y_1, y_2, y_3); ``hessian`` (e, 4, 3, 4, 3) the rows' d2g/dz2, 1/mm
    (``Facing.hessian``), ``tilt_floor`` the rule's TILT (elements/ply_landing.py)."""
    c = crossing
    count = len(c.point)
    eye = np.eye(3)
    n, _, grad = triangle_frames(c.now)
    nu, lam = c.normal, c.feature
    # dp, dy_k over z (the slots' identities), and the closest point's motion from the Hessian
    d_point = np.zeros((count, 3, 4, 3))
    d_point[:, :, 0] = eye
    d_nu = hessian[:, 0]  # (e, 3, 4, 3)
    d_lam = -np.einsum("ei,ekizb->ekzb", nu, hessian[:, 1:])
    d_n = np.zeros((count, 3, 4, 3))  # dn/dy_m = -grad phi_m n^T
    d_grad = np.zeros((count, 3, 3, 4, 3))  # d grad phi_k / dy_m
    dots = np.einsum("eki,emi->ekm", grad, grad)
    for m in range(3):
        d_n[:, :, 1 + m] = -grad[:, m, :, None] * n[:, None, :]
        d_grad[:, :, :, 1 + m] = -grad[:, m][:, None, :, None] * grad[:, :, None, :] + (
            dots[:, :, m, None, None] * (n[:, :, None] * n[:, None, :])[:, None]
        )
    zero = np.where(c.plane[:, None], n, nu)
    d_zero = np.where(c.plane[:, None, None, None], d_n, d_nu)
    q0 = np.einsum("ek,eki->ei", lam, c.before)
    q = np.einsum("ek,eki->ei", lam, c.now)
    d_q0 = np.einsum("ekzb,eki->eizb", d_lam, c.before)
    d_q = np.einsum("ekzb,eki->eizb", d_lam, c.now)
    for k in range(3):
        d_q[:, :, 1 + k] += lam[:, k, None, None] * eye
    # g_0 and pen, each where it is positive
    ahead, inside = c.then - q0, c.point - q
    clear = np.einsum("ei,ei->e", zero, ahead)
    deep = -np.einsum("ei,ei->e", zero, inside)
    d_clear = np.einsum("eizb,ei->ezb", d_zero, ahead) - np.einsum("ei,eizb->ezb", zero, d_q0)
    d_deep = -np.einsum("eizb,ei->ezb", d_zero, inside) - np.einsum(
        "ei,eizb->ezb", zero, d_point - d_q
    )
    g0, pen = np.maximum(clear, 0.0), np.maximum(deep, 0.0)
    d_g0 = np.where((clear > 0.0)[:, None, None], d_clear, 0.0)
    d_pen = np.where((deep > 0.0)[:, None, None], d_deep, 0.0)
    way = g0 + pen
    safe = np.where(way > 0.0, way, 1.0)
    theta = np.where(way > 0.0, g0 / safe, 1.0)
    d_theta = (pen[:, None, None] * d_g0 - g0[:, None, None] * d_pen) / safe[:, None, None] ** 2
    # the places and heights on T's planes then (held) and now
    old, old_height = _plane_places(c.before, c.then)
    new, height = _plane_places(c.now, c.point)
    d_new = np.zeros((count, 3, 4, 3))
    d_new[:, :, 0] = grad
    d_height = np.zeros((count, 4, 3))
    d_height[:, 0] = n
    for m in range(3):
        d_new[:, :, 1 + m] = -new[:, m, None, None] * grad + (
            height[:, None, None] * dots[:, :, m, None] * n[:, None, :]
        )
        d_height[:, 1 + m] = -new[:, m, None] * n
    d_place = (new - old)[:, :, None, None] * d_theta[:, None] + theta[:, None, None, None] * d_new
    rise = old_height + theta * (height - old_height)
    d_rise = (height - old_height)[:, None, None] * d_theta + theta[:, None, None] * d_height
    # the move onto T's plane: a = rise t / max(t^2, TILT^2) along nu, t = n . nu
    tilt = np.einsum("ei,ei->e", n, nu)
    d_tilt = np.einsum("eizb,ei->ezb", d_n, nu) + np.einsum("ei,eizb->ezb", n, d_nu)
    steep = np.abs(tilt) > tilt_floor  # (as edge_crossing decides it)
    floor = np.where(steep, tilt**2, tilt_floor**2)
    along = rise * tilt / floor
    d_floor = np.where(steep[:, None, None], 2.0 * tilt[:, None, None] * d_tilt, 0.0)
    d_along = (d_rise * tilt[:, None, None] + rise[:, None, None] * d_tilt) / floor[
        :, None, None
    ] - (along / floor)[:, None, None] * d_floor
    share = np.einsum("eki,ei->ek", grad, nu)  # grad phi_k . nu
    d_share = np.einsum("ekizb,ei->ekzb", d_grad, nu) + np.einsum("eki,eizb->ekzb", grad, d_nu)
    return (
        d_place - share[:, :, None, None] * d_along[:, None] - along[:, None, None, None] * d_share
    )


def _plane_places(corners: np.ndarray, point: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(weights (e, 3), height (e,)): ``point``'s barycentric place on the planes of
    ``corners`` and its height over them (elements/ply_landing.py ``plane_places``)."""
    from elements.ply_landing import plane_places  # (ply_landing imports this module)

    return plane_places(corners, point)
