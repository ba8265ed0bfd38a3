"""The in-plane turning angle of a fibre between the two cells of a patch, and its gradient
(docs/theory.md §4.7): numpy over the patches, any real or complex dtype (the tangent takes
the gradient at a complex step), the reference of the compiled kernel
(elements/fibre_bending_kernels.py).

Each cell of a patch has a frame in its own plane: t = m / |m| along its fibre segment m, and
b the unit part of its other fibre edge p normal to t. The angle of the second cell's segment
m_f seen in the first cell's frame is phi_cf = atan2(m_f . b_c, m_f . t_c), and that of m_c in
the second's phi_fc; the patch's angle is theta = (phi_cf - phi_fc) / 2. In one plane it is
the angle between the two segments, signed; a rigid motion, a shear of the net (its segments
stay parallel), a bend or a twist of the surface about a line across or along the fibre leave
it zero (the frames turn with their cells; the two views cancel the rest to second order in
the fold).
"""

from __future__ import annotations

import numpy as np

__all__ = ["patch_angles", "patch_gradients"]


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2]


def _vectors(x: np.ndarray, ends: np.ndarray) -> list[np.ndarray]:
    """The four vectors m_c, p_c, m_f, p_f (P, 3) from the patches' corner positions x
    (P, 5, 3) and ``ends`` (P, 4, 2)."""
    rows = np.arange(len(x))
    return [x[rows, ends[:, k, 1]] - x[rows, ends[:, k, 0]] for k in range(4)]


def _view(m: np.ndarray, p: np.ndarray, seen: np.ndarray):
    """The angle of ``seen`` in the frame of (m, p): its sine and cosine parts S, C (P,) and
    the gradients of atan2(S, C) with respect to m, p and ``seen`` (P, 3) each."""
    length = np.sqrt(_dot(m, m))
    t = m / length[:, None]
    p_t = _dot(p, t)
    u = p - p_t[:, None] * t
    u_length = np.sqrt(_dot(u, u))
    b = u / u_length[:, None]
    s = _dot(seen, b)
    c = _dot(seen, t)
    d = s * s + c * c
    a_s, a_c = c / d, -s / d
    normal_part = seen - s[:, None] * b - c[:, None] * t  # the part of seen off the frame's plane
    d_seen = a_s[:, None] * b + a_c[:, None] * t
    d_m = (
        a_s[:, None] * (-c[:, None] * u - p_t[:, None] * normal_part) / (u_length * length)[:, None]
        + a_c[:, None] * (seen - c[:, None] * t) / length[:, None]
    )
    d_p = (a_s / u_length)[:, None] * normal_part
    return s, c, d_m, d_p, d_seen


def patch_angles(x: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """theta (P,), rad, of each patch from its corners' current positions x (P, 5, 3)."""
    m_c, p_c, m_f, p_f = _vectors(x, ends)
    s1, c1 = _view(m_c, p_c, m_f)[:2]
    s2, c2 = _view(m_f, p_f, m_c)[:2]
    return 0.5 * (np.arctan2(s1, c1) - np.arctan2(s2, c2))


def patch_gradients(x: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """d theta / d x (P, 5, 3), 1/mm, at the corners' positions x (P, 5, 3), real or complex
    (no atan2 on the way: the gradient is algebraic in x)."""
    m_c, p_c, m_f, p_f = _vectors(x, ends)
    _, _, c_m, c_p, c_seen = _view(m_c, p_c, m_f)  # phi_cf
    _, _, f_m, f_p, f_seen = _view(m_f, p_f, m_c)  # phi_fc
    by_vector = (
        0.5 * (c_m - f_seen),  # m_c
        0.5 * c_p,  # p_c
        0.5 * (c_seen - f_m),  # m_f
        -0.5 * f_p,  # p_f
    )
    grad = np.zeros(x.shape, dtype=np.result_type(x, float))
    rows = np.arange(len(x))
    for k, g in enumerate(by_vector):
        grad[rows, ends[:, k, 1]] += g  # one entry per row: no repeated index
        grad[rows, ends[:, k, 0]] -= g
    return grad
