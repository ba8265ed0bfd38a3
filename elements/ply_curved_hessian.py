"""The gap of a point on the upper ply's curved face to the lower ply's curved face, its
gradient and its exact Hessian over the two patches' data (docs/theory.md §9.3a, "Curved
faces", "The exact tangent"): what the contact's tangent needs (elements/ply_curved.py).

Local data of one point, v (36,): the upper patch's offset corners z_1..3 and unit normals
N_1..3, then the lower patch's offset corners y_1..3 and unit normals n_1..3, each 3
components (slot s holds v[3 s : 3 s + 3]). The point is p = P(sigma; z, N) at the rule's
fixed coordinates sigma, its projection Y = P(lambda; y, n) on the lower patch, P the Phong
map of elements/ply_surface.py, lambda the projection's coordinates (two free, lambda_3 =
1 - lambda_1 - lambda_2), t_a = dY/dlambda_a its tangents, nu their unit normal and g =
(p - Y) . nu.

Gradient. With u = d(p - Y) at fixed lambda (U = d(p - Y)/dv, (3, 36)): dg = nu . u, since
p - Y = g nu is normal to the tangents and nu to its own change (G = nu^T U).

Hessian. The projection's stationarity R_a = t_a . (p - Y) = 0 gives dlambda implicitly:
A dlambda = alpha + g h, A = M - g B, M_ab = t_a . t_b, B_ab = nu . d t_a / dlambda_b, alpha =
T^T U and h_a = nu . dt_a/dv at fixed lambda; the normal turns as dnu = -t^a (nu . dt_a), t^a
= M^-1_ab t_b the dual tangents. Differentiating dg = nu . u once more, and with g M^-1 B A^-1
= A^-1 - M^-1 (from g B = M - A):

    d2g/dv2 = nu . d2(p - Y)/dv2 - h^T A^-1 alpha - alpha^T A^-1 h - g h^T A^-1 h
              - alpha^T M^-1 B A^-1 alpha,

symmetric (M^-1 B A^-1 = A^-1 B M^-1). On a flat facet (B = 0, the normals out of P) it is the
plane's Hessian of elements/ply_fade_hessian.py ``plane_hessian``.

P is polynomial in its data: with q = sum lambda_k y_k, d_i = q - y_i, e_i = d_i . n_i and
c_ik = lambda_k - delta_ik,

    dP/dy_k = lambda_k (I - 1/2 sum_i lambda_i n_i n_i^T + 1/2 n_k n_k^T),
    dP/dn_i = -1/2 lambda_i (n_i d_i^T + e_i I),
    d2(w . P)/dy_k dn_i = -1/2 lambda_i c_ik ((w . n_i) I + n_i w^T),
    d2(w . P)/dn_i dn_i = -1/2 lambda_i (d_i w^T + w d_i^T)   (the other pairs 0),

and its derivatives in lambda, Pi_k = dP/dlambda_k = y_k - 1/2 e_k n_k - 1/2 sum_i lambda_i
(y_k . n_i) n_i, D_kl = dPi_k/dlambda_l = -1/2 ((y_l . n_k) n_k + (y_k . n_l) n_l),
nu . dPi_k/dy_m = delta_km nu^T - 1/2 c_km (nu . n_k) n_k^T - 1/2 delta_km sum_i lambda_i
(nu . n_i) n_i^T, nu . dPi_k/dn_m = -1/2 delta_km ((nu . n_k) d_k^T + e_k nu^T) - 1/2 lambda_m
((nu . n_m) y_k^T + (y_k . n_m) nu^T); t_a = Pi_a - Pi_3.
"""

from __future__ import annotations

import numpy as np

__all__ = ["SIZE", "gap_derivatives", "gap_gradient_and_turning", "phong_hessian", "phong_jacobian"]

#: Local data of a point: 12 vectors (module docstring).
SIZE = 36


def phong_jacobian(y: np.ndarray, n: np.ndarray, lam: np.ndarray) -> np.ndarray:
    """dP/d(y_1..3, n_1..3) (t, 3, 18) of the Phong map at fixed coordinates ``lam`` (t, 3)
    over corners ``y`` and unit normals ``n`` (t, 3, 3), mm (module docstring)."""
    t = len(lam)
    q = np.einsum("tk,tki->ti", lam, y)
    d = q[:, None, :] - y  # (t, 3, 3): d_i = q - y_i
    e = np.sum(d * n, axis=2)  # (t, 3)
    eye = np.eye(3)
    outer = n[:, :, :, None] * n[:, :, None, :]  # n_i n_i^T
    mixed = np.einsum("ti,tiab->tab", lam, outer)
    out = np.zeros((t, 3, 18), dtype=np.result_type(y, n, lam))
    for k in range(3):
        out[:, :, 3 * k : 3 * k + 3] = lam[:, k, None, None] * (
            eye - 0.5 * mixed + 0.5 * outer[:, k]
        )
        out[:, :, 9 + 3 * k : 12 + 3 * k] = (
            -0.5
            * lam[:, k, None, None]
            * (n[:, k, :, None] * d[:, k, None, :] + e[:, k, None, None] * eye)
        )
    return out


def phong_hessian(y: np.ndarray, n: np.ndarray, lam: np.ndarray, w: np.ndarray) -> np.ndarray:
    """d2(w . P)/d(y, n)^2 (t, 18, 18) at fixed coordinates ``lam`` (t, 3), w (t, 3) a fixed
    vector (module docstring)."""
    t = len(lam)
    q = np.einsum("tk,tki->ti", lam, y)
    d = q[:, None, :] - y
    wn = np.sum(w[:, None, :] * n, axis=2)  # (t, 3): w . n_i
    eye = np.eye(3)
    out = np.zeros((t, 18, 18))
    for i in range(3):
        ni = slice(9 + 3 * i, 12 + 3 * i)
        both = wn[:, i, None, None] * eye + n[:, i, :, None] * w[:, None, :]
        for k in range(3):
            c = lam[:, k] - (1.0 if i == k else 0.0)
            block = (-0.5 * lam[:, i] * c)[:, None, None] * both
            out[:, 3 * k : 3 * k + 3, ni] = block
            out[:, ni, 3 * k : 3 * k + 3] = np.swapaxes(block, 1, 2)
        out[:, ni, ni] = (-0.5 * lam[:, i])[:, None, None] * (
            d[:, i, :, None] * w[:, None, :] + w[:, :, None] * d[:, i, None, :]
        )
    return out


def _lambda_terms(y: np.ndarray, n: np.ndarray, lam: np.ndarray, nu: np.ndarray):
    """The lower patch's tangents T (t, 2, 3), B (t, 2, 2) = nu . dt_a/dlambda_b and h
    (t, 2, 18) = nu . dt_a/d(y, n) at the projection (module docstring)."""
    t = len(lam)
    q = np.einsum("tk,tki->ti", lam, y)
    d = q[:, None, :] - y
    e = np.sum(d * n, axis=2)
    yn = np.einsum("tki,tli->tkl", y, n)  # (t, k, l): y_k . n_l
    nun = np.sum(nu[:, None, :] * n, axis=2)  # nu . n_i
    pi = (
        y - 0.5 * e[:, :, None] * n - 0.5 * np.einsum("tkl,tli->tki", lam[:, None, :] * yn, n)
    )  # (t, 3, 3): Pi_k
    tangents = pi[:, :2] - pi[:, 2:3]
    # nu . D_kl = -1/2 ((y_l . n_k)(nu . n_k) + (y_k . n_l)(nu . n_l))
    nud = -0.5 * (np.swapaxes(yn, 1, 2) * nun[:, :, None] + yn * nun[:, None, :])
    kind = np.result_type(y, n, lam, nu)
    b = np.zeros((t, 2, 2), dtype=kind)
    for a in range(2):
        for col in range(2):
            b[:, a, col] = nud[:, a, col] - nud[:, a, 2] - nud[:, 2, col] + nud[:, 2, 2]
    # nu . dPi_k/dv (t, 3, 18)
    dpi = np.zeros((t, 3, 18), dtype=kind)
    mixed = np.einsum("ti,tij->tj", lam * nun, n)  # sum_i lambda_i (nu . n_i) n_i
    for k in range(3):
        for m in range(3):
            c = lam[:, m] - (1.0 if k == m else 0.0)
            row = -0.5 * (c * nun[:, k])[:, None] * n[:, k]
            if k == m:
                row = row + nu - 0.5 * mixed
            dpi[:, k, 3 * m : 3 * m + 3] = row
            on_n = -0.5 * lam[:, m, None] * (nun[:, m, None] * y[:, k] + yn[:, k, m, None] * nu)
            if k == m:
                on_n = on_n - 0.5 * (nun[:, k, None] * d[:, k] + e[:, k, None] * nu)
            dpi[:, k, 9 + 3 * m : 12 + 3 * m] = on_n
    h = dpi[:, :2] - dpi[:, 2:3]
    return tangents, b, h


def gap_derivatives(
    z: np.ndarray,
    upper_normals: np.ndarray,
    sigma: np.ndarray,
    y: np.ndarray,
    n: np.ndarray,
    lam: np.ndarray,
    nu: np.ndarray,
    gap: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The gap's gradient (t, 36) and Hessian (t, 36, 36) over the point's local data
    (module docstring), at a converged projection.

    Parameters
    ----------
    z, upper_normals : (t, 3, 3) float
        The upper patch's offset corners, mm, and unit normals.
    sigma : (t, 3) float
        The point's coordinates on the upper patch.
    y, n : (t, 3, 3) float
        The lower patch's offset corners, mm, and unit normals.
    lam : (t, 3) float
        The projection's coordinates on the lower patch.
    nu : (t, 3) float
        The lower surface's unit normal there.
    gap : (t,) float
        g, mm.
    """
    t = len(lam)
    u = np.zeros((t, 3, SIZE))
    u[:, :, :18] = phong_jacobian(z, upper_normals, sigma)
    u[:, :, 18:] = -phong_jacobian(y, n, lam)
    gradient = np.einsum("ti,tiv->tv", nu, u)
    tangents, b, h18 = _lambda_terms(y, n, lam, nu)
    h = np.zeros((t, 2, SIZE))
    h[:, :, 18:] = h18
    alpha = np.einsum("tai,tiv->tav", tangents, u)
    metric = np.einsum("tai,tbi->tab", tangents, tangents)
    a = metric - gap[:, None, None] * b
    a_inv = np.linalg.inv(a)
    m_inv = np.linalg.inv(metric)
    hessian = np.zeros((t, SIZE, SIZE))
    hessian[:, :18, :18] = phong_hessian(z, upper_normals, sigma, nu)
    hessian[:, 18:, 18:] = -phong_hessian(y, n, lam, nu)
    cross = np.einsum("tav,tab,tbw->tvw", h, a_inv, alpha, optimize=True)
    hessian -= cross + np.swapaxes(cross, 1, 2)
    hessian -= gap[:, None, None] * np.einsum("tav,tab,tbw->tvw", h, a_inv, h, optimize=True)
    curving = np.einsum("tab,tbc,tcd->tad", m_inv, b, a_inv, optimize=True)
    hessian -= np.einsum("tav,tab,tbw->tvw", alpha, curving, alpha, optimize=True)
    return gradient, hessian


def gap_gradient_and_turning(
    z: np.ndarray,
    upper_normals: np.ndarray,
    sigma: np.ndarray,
    y: np.ndarray,
    n: np.ndarray,
    lam: np.ndarray,
    nu: np.ndarray,
    gap: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The gap's gradient (t, 36) and the normal's turn dnu/dv (t, 3, 36) over the point's
    local data (the arguments as ``gap_derivatives``'): dnu = -t^a (nu . dt_a) with
    dt_a = dt_a/dv + dt_a/dlambda_b dlambda_b and A dlambda = alpha + g h (module
    docstring), i.e. dnu/dv = -T^T M^-1 (h + B A^-1 (alpha + g h)). Plain arithmetic:
    complex data give the complex-step derivatives of elements/ply_curved_friction.py."""
    t = len(lam)
    u = np.zeros((t, 3, SIZE), dtype=np.result_type(z, y, nu))
    u[:, :, :18] = phong_jacobian(z, upper_normals, sigma)
    u[:, :, 18:] = -phong_jacobian(y, n, lam)
    gradient = np.einsum("ti,tiv->tv", nu, u)
    tangents, b, h18 = _lambda_terms(y, n, lam, nu)
    h = np.zeros((t, 2, SIZE), dtype=u.dtype)
    h[:, :, 18:] = h18
    alpha = np.einsum("tai,tiv->tav", tangents, u)
    metric = np.einsum("tai,tbi->tab", tangents, tangents)
    moved = np.linalg.solve(metric - gap[:, None, None] * b, alpha + gap[:, None, None] * h)
    dual = np.linalg.solve(metric, h + np.einsum("tab,tbv->tav", b, moved))
    return gradient, -np.einsum("tai,tav->tiv", tangents, dual)
