"""The in-plane turning angle of a fibre between the two cells of a patch, and its gradient
(docs/theory.md §4.7).

Each cell of a patch has a unit normal n = (m x p) / |m x p| from its fibre segment m and its
other fibre edge p (p points along the other family's reference direction, so the normals of
a patch's two cells agree in sign). The first cell's segment m_c is unfolded into the second
cell's plane by the least rotation that takes n_c to n_f (about the line the two planes share,
by the fold between them; Rodrigues' formula, smooth through a flat patch):

    r = c m_c + k x m_c + (k . m_c) k / (1 + c),   c = n_c . n_f,  k = n_c x n_f,

and the patch's angle is the signed angle from r to m_f about n_f,

    theta = atan2(n_f . (r x m_f), r . m_f).

In one plane it is the angle between the two segments. A rigid motion, a shear of the net
(its segments stay parallel), a bend of the surface about a line across the fibre and a twist
about the fibre leave it zero, and a fold across the fibre leaves a turning in the fabric's
plane as it was: the angle is the discrete geodesic curvature of the fibre's chords.

The functions act on vectors given as tuples of three components, each a float or an array:
numpy evaluates them over all patches at once (real or complex: the tangent takes the gradient
at a complex step), and the compiled kernel (elements/fibre_bending_kernels.py) calls the same
functions, compiled, patch by patch.
"""

from __future__ import annotations

import numpy as np

try:  # the compiled kernel calls these helpers; without numba they stay plain Python
    from numba.extending import register_jitable
except ImportError:  # pragma: no cover - exercised only where numba is missing

    def register_jitable(function):  # type: ignore[no-redef]
        return function


__all__ = ["patch_angles", "patch_gradients", "turning", "vector_spring_bounds"]

#: Added to 1 + c before dividing by it: a patch whose cells face opposite ways (a fold of
#: 180 deg, or a cell turned inside out in a flat run, c = -1 and k = 0) has no unique
#: unfolding; the guard keeps the passes finite there (r = -m_c) and changes nothing else
#: (1e-150 against 1 + c; its square still a normal number).
FOLD_GUARD = 1e-150


@register_jitable
def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@register_jitable
def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@register_jitable
def _combine(s, a, t, b):
    """s a + t b."""
    return (s * a[0] + t * b[0], s * a[1] + t * b[1], s * a[2] + t * b[2])


@register_jitable
def _normal_back(m, p, n, length, g_n):
    """The gradients with respect to m and p of g_n . n, n = (m x p) / length the unit normal
    (length = |m x p|)."""
    g_u = _combine(1.0 / length, g_n, -_dot(n, g_n) / length, n)
    return _cross(p, g_u), _cross(g_u, m)


@register_jitable
def turning(m_c, p_c, m_f, p_f):
    """The sine and cosine parts S, C of the patch's angle theta = atan2(S, C) and its
    gradients with respect to the four vectors m_c, p_c, m_f, p_f (each a tuple of three
    components, mm): returns S, C, and the four gradients (tuples, 1/mm)."""
    u_c = _cross(m_c, p_c)
    u_f = _cross(m_f, p_f)
    l_c = np.sqrt(_dot(u_c, u_c))
    l_f = np.sqrt(_dot(u_f, u_f))
    n_c = _combine(1.0 / l_c, u_c, 0.0, u_c)
    n_f = _combine(1.0 / l_f, u_f, 0.0, u_f)
    c = _dot(n_c, n_f)
    k = _cross(n_c, n_f)
    w = 1.0 / (1.0 + c + FOLD_GUARD)
    q = _dot(k, m_c)
    r = _combine(1.0, _combine(c, m_c, q * w, k), 1.0, _cross(k, m_c))
    across = _cross(m_f, n_f)
    s = _dot(r, across)
    cos = _dot(r, m_f)
    d = s * s + cos * cos
    g_s, g_cos = cos / d, -s / d
    # back through S = r . (m_f x n_f) and C = r . m_f
    g_r = _combine(g_s, across, g_cos, m_f)
    g_mf = _combine(g_s, _cross(n_f, r), g_cos, r)
    g_nf = _combine(g_s, _cross(r, m_f), 0.0, r)
    # back through r = c m_c + k x m_c + q w k
    g_rk = _dot(g_r, k)
    g_mc = _combine(1.0, _combine(c, g_r, g_rk * w, k), 1.0, _cross(g_r, k))
    g_k = _combine(1.0, _combine(q * w, g_r, g_rk * w, m_c), 1.0, _cross(m_c, g_r))
    g_c = _dot(g_r, m_c) - q * g_rk * w * w
    # back through c = n_c . n_f and k = n_c x n_f
    g_nc = _combine(g_c, n_f, 1.0, _cross(n_f, g_k))
    g_nf = _combine(1.0, g_nf, 1.0, _combine(g_c, n_c, 1.0, _cross(g_k, n_c)))
    d_mc, d_pc = _normal_back(m_c, p_c, n_c, l_c, g_nc)
    d_mf, d_pf = _normal_back(m_f, p_f, n_f, l_f, g_nf)
    return (
        s,
        cos,
        _combine(1.0, g_mc, 1.0, d_mc),
        d_pc,
        _combine(1.0, g_mf, 1.0, d_mf),
        d_pf,
    )


def _vectors(x: np.ndarray, ends: np.ndarray) -> list[tuple]:
    """The four vectors m_c, p_c, m_f, p_f, each a tuple of three (P,) components, from the
    patches' corner positions x (P, 5, 3) and ``ends`` (P, 4, 2)."""
    rows = np.arange(len(x))
    out = []
    for k in range(4):
        v = x[rows, ends[:, k, 1]] - x[rows, ends[:, k, 0]]
        out.append((v[:, 0], v[:, 1], v[:, 2]))
    return out


def patch_angles(x: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """theta (P,), rad, of each patch from its corners' current positions x (P, 5, 3)."""
    s, c = turning(*_vectors(x, ends))[:2]
    return np.arctan2(s, c)


def patch_gradients(x: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """d theta / d x (P, 5, 3), 1/mm, at the corners' positions x (P, 5, 3), real or complex
    (no atan2 on the way: the gradient is algebraic in x)."""
    by_vector = turning(*_vectors(x, ends))[2:]
    grad = np.zeros(x.shape, dtype=np.result_type(x, float))
    rows = np.arange(len(x))
    for k, g in enumerate(by_vector):
        g = np.stack(g, axis=-1)
        grad[rows, ends[:, k, 1]] += g  # one entry per row: no repeated index
        grad[rows, ends[:, k, 0]] -= g
    return grad


def vector_spring_bounds(x: np.ndarray, ends: np.ndarray, stiffness: np.ndarray, step: np.ndarray):
    """Springs (P, 5), N/mm, at the corners of each patch that bound its stiffness
    K = k (g g^T + theta H): x^T K x <= sum_k e_k |v_k|^2 (block Gershgorin in the four
    vectors v_k: e_k = sum_l |K_kl|, the Frobenius norms of K's 3 x 3 blocks in them, K
    symmetric), and |v_k|^2 <= 2 (|x_head|^2 + |x_tail|^2), so vector k adds 2 e_k at its
    head and its tail. x (P, 5, 3) mm the corners; ``ends`` (P, 4, 2); ``stiffness`` k (P,)
    N mm; H the forward difference of the gradient over ``step`` (P,) mm (elements/
    fibre_bending.py SPRING_STEP)."""
    vectors = np.stack([np.stack(v, axis=-1) for v in _vectors(x, ends)], axis=1)  # (P, 4, 3)
    s, c, *grads = turning(*_vectors(x, ends))
    theta = np.arctan2(s, c)
    g = np.stack([np.stack(v, axis=-1) for v in grads], axis=1).reshape(len(x), 12)
    hessian = np.empty((len(x), 12, 12))
    for column in range(12):
        shifted = vectors.copy()
        shifted[:, column // 3, column % 3] += step
        parts = turning(*[(v[:, 0], v[:, 1], v[:, 2]) for v in np.moveaxis(shifted, 1, 0)])[2:]
        column_grad = np.stack([np.stack(v, axis=-1) for v in parts], axis=1)
        hessian[:, :, column] = (column_grad.reshape(len(x), 12) - g) / step[:, None]
    k = stiffness[:, None, None] * (g[:, :, None] * g[:, None, :] + theta[:, None, None] * hessian)
    blocks = k.reshape(len(x), 4, 3, 4, 3)
    sums = np.sqrt(np.sum(blocks * blocks, axis=(2, 4))).sum(axis=2)  # (P, 4): e_k
    springs = np.zeros((len(x), 5))
    rows = np.arange(len(x))
    for vector in range(4):
        springs[rows, ends[:, vector, 1]] += 2.0 * sums[:, vector]
        springs[rows, ends[:, vector, 0]] += 2.0 * sums[:, vector]
    return springs
