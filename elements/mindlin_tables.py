"""The tables of the Mindlin triangle (elements/mindlin.py) that depend on no cell: the
in-plane and tying points, the seven level measures as products of the covariant vectors and
their constant derivatives (docs/theory.md §5.5), the MITC3 assumed-shear rows (§5.3), the
packed 7 x 7 level stiffness, and the helpers of the bind (the volume check, the cells of
one reference shape).
"""

from __future__ import annotations

import numpy as np

from elements import kernels

__all__: list[str] = []  # the Mindlin modules' own tables

# In-plane 3-point rule (r, s), weight 1/6 each in the (r, s) triangle of area 1/2 (the
# compiled loops' one definition).
_IN_PLANE = kernels.IN_PLANE
# MITC3 tying points A (1/2, 0), B (0, 1/2), C (1/2, 1/2): shape functions N_k there.
_TYING_N = np.array([[0.5, 0.5, 0.0], [0.5, 0.0, 0.5], [0.0, 0.5, 0.5]])
# The seven strain measures of a thickness level (docs/theory.md §5.5), each a product
# f (g_a . g_b) of two of the vectors (g1, g2, g3^A, g3^B, g3^C) = indices 0-4: E11 = g1.g1/2,
# E22 = g2.g2/2, 2E12 = g1.g2 and the tying products g1.g3^A, g1.g3^C, g2.g3^B, g2.g3^C.
_PRODUCTS = (
    (0, 0, 0.5),
    (1, 1, 0.5),
    (0, 1, 1.0),
    (0, 2, 1.0),
    (0, 4, 1.0),
    (1, 3, 1.0),
    (1, 4, 1.0),
)
# The packed upper triangle of a symmetric 7 x 7 (MindlinShellBlock.level_stiffness).
_PACKED_ROWS, _PACKED_COLUMNS = kernels.PACKED_ROWS, kernels.PACKED_COLUMNS


def _level_stiffness_of(weighted: np.ndarray) -> np.ndarray:
    """D^_z = sum_p L_p^T D_pz L_p (m, Z, 7, 7) from the point-wise D_pz (m, P, Z, 5, 5)."""
    maps = _strain_maps(*_assumed_shear_coefficients())[None, :, None]  # (1, P, 1, 5, 7)
    return (np.swapaxes(maps, -1, -2) @ weighted @ maps).sum(axis=1)


def _packed(full: np.ndarray) -> np.ndarray:
    """The upper triangle (..., 28) of symmetric 7 x 7 matrices (..., 7, 7), symmetrised."""
    return 0.5 * (
        full[..., _PACKED_ROWS, _PACKED_COLUMNS] + full[..., _PACKED_COLUMNS, _PACKED_ROWS]
    )


def _congruent_cells(x0: np.ndarray, v0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The cells of the same reference shape: (the first cell of each shape (s,), the shape
    of each cell (m,)), the shape being the edges x1 - x0, x2 - x0 and the three directors
    equal to the bit (c, 3, 3 each). A cell's element eigenvalue depends on nothing else
    (its material, mass and rotary factor follow from it, the last to rounding)."""
    m = len(x0)
    key = np.empty((m, 15))
    key[:, :3], key[:, 3:6] = x0[:, 1] - x0[:, 0], x0[:, 2] - x0[:, 0]
    key[:, 6:] = v0.reshape(m, 9)
    key += 0.0  # -0.0 and 0.0 are one shape
    _, first, shape_of = np.unique(
        key.view(np.dtype((np.void, 15 * 8))).ravel(), return_index=True, return_inverse=True
    )
    return first, shape_of.ravel()


def _check_volume(smallest_det: np.ndarray, cell_ids: np.ndarray) -> None:
    """ValueError naming the first triangle whose reference det J (smallest over its points,
    (m,)) is not positive: its director field inverts the shell volume."""
    if np.any(~(smallest_det > 0)):
        bad = int(cell_ids[np.argmax(~(smallest_det > 0))])
        raise ValueError(f"triangle {bad}: the director field inverts the shell volume")


def _assumed_shear_coefficients() -> tuple[np.ndarray, np.ndarray]:
    """Rows a_p, b_p with e_rt(p) = a_p . t and e_st(p) = b_p . t, t = (e_rt^A, e_rt^C,
    e_st^B, e_st^C): e_rt = e_rt^A + c s, e_st = e_st^B - c r, c = (e_rt^C - e_rt^A) -
    (e_st^C - e_st^B) (docs/theory.md §5.3)."""
    r, s = _IN_PLANE[:, 0], _IN_PLANE[:, 1]
    a = np.column_stack([1 - s, s, s, -s])
    b = np.column_stack([r, -r, 1 - r, r])
    return a, b


def _strain_maps(shear_a: np.ndarray, shear_b: np.ndarray) -> np.ndarray:
    """L_p (P, 5, 7): the strain vector (E11, E22, 2E12, 2E13, 2E23) at in-plane point p from
    the level measures e = (E11, E22, 2E12, dt_A1, dt_C1, dt_B2, dt_C2) of docs/theory.md §5.5
    (dt: change of a tying product g_alpha . g3^T; 2E13 = a_p . dt, 2E23 = b_p . dt, §5.3)."""
    maps = np.zeros((len(_IN_PLANE), 5, 7))
    maps[:, :3, :3] = np.eye(3)
    maps[:, 3, 3:] = shear_a
    maps[:, 4, 3:] = shear_b
    return maps


def _product_coefficients(zeta: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
    """Constant tables of the level measures e_r = f_r g_a . g_b (docs/theory.md §5.5) over the
    18 cell numbers s = (x_1, x_2, x_3, V_1, V_2, V_3).

    Each vector is linear in s, g_u = sum_k c_uk s_k, with scalar c (Z, 5, 6): g1 and g2 at the
    level zeta, g3 at the tying points. Returns

    * ``gradient`` (Z, 7, 6, 5): de_r/ds_k = sum_u gradient[r, k, u] g_u (a 3-vector), i.e.
      f_r (c_ak g_b + c_bk g_a);
    * ``curvature`` (Z, 7, 6, 6): d2e_r/ds_k ds_l = curvature[r, k, l] I3, i.e.
      f_r (c_ak c_bl + c_bk c_al), constant (the measures are quadratic in s).
    """
    half = 0.5 * h
    nz = len(zeta)
    c = np.zeros((nz, 5, 6))
    d_xi, d_eta = np.array([-1.0, 1.0, 0.0]), np.array([-1.0, 0.0, 1.0])
    c[:, 0, :3], c[:, 1, :3] = d_xi, d_eta
    c[:, 0, 3:] = half * zeta[:, None] * d_xi
    c[:, 1, 3:] = half * zeta[:, None] * d_eta
    c[:, 2:, 3:] = half * _TYING_N  # g3^T = h/2 sum_k N_k(T) V_k
    gradient = np.zeros((nz, 7, 6, 5))
    curvature = np.zeros((nz, 7, 6, 6))
    for r, (a, b, f) in enumerate(_PRODUCTS):
        gradient[:, r, :, b] += f * c[:, a]
        gradient[:, r, :, a] += f * c[:, b]
        outer = c[:, a, :, None] * c[:, b, None, :]
        curvature[:, r] = f * (outer + np.swapaxes(outer, -1, -2))
    return gradient, curvature


def _turned_gradient_table(gradient: np.ndarray) -> np.ndarray:
    """(Z, 42, 20): row (r, k, t) of B^psi (docs/theory.md §5.5) from the 20 vectors
    (g_u, V_1 x g_u, V_2 x g_u, V_3 x g_u), u = 0-4: de_r/du_k (t = 0) = sum_u c g_u and
    de_r/dpsi_k (t = 1) = V_k x de_r/dV_k = sum_u c (V_k x g_u), with the c of ``gradient``
    (Z, 7, 6, 5) from _product_coefficients."""
    nz = len(gradient)
    table = np.zeros((nz, 7, 3, 2, 4, 5))
    for k in range(3):
        table[:, :, k, 0, 0] = gradient[:, :, k]
        table[:, :, k, 1, 1 + k] = gradient[:, :, 3 + k]
    return table.reshape(nz, 42, 20)


def inverse_metric(x0: np.ndarray) -> np.ndarray:
    """(m, 4) (G22, G12, G11, 1) / det G of the triangles with corners x0 (m, 3, 3), mm^-2
    (the last mm^-4): G the metric of the edges x1 - x0, x2 - x0 (G11 = |x1 - x0|^2, G12 their
    dot product), the reference that ``largest_stretch2`` measures a stretch against."""
    a, b = x0[:, 1] - x0[:, 0], x0[:, 2] - x0[:, 0]
    g11, g22, g12 = np.sum(a * a, axis=1), np.sum(b * b, axis=1), np.sum(a * b, axis=1)
    det = g11 * g22 - g12 * g12
    return np.column_stack([g22, g12, g11, np.ones_like(det)]) / det[:, None]


def largest_stretch2(x: np.ndarray, inverse: np.ndarray) -> np.ndarray:
    """(m,) the larger squared principal stretch of the triangles' mid-surfaces, the larger
    eigenvalue of G^-1 g (g the metric of the edges of the corners x (m, 3, 3) now, G^-1 from
    ``inverse_metric``): docs/theory.md §6.2 B5. The same arithmetic as the compiled loop
    (elements/kernels.py ``_cell_steps``)."""
    a, b = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]
    g11 = a[:, 0] * a[:, 0] + a[:, 1] * a[:, 1] + a[:, 2] * a[:, 2]
    g22 = b[:, 0] * b[:, 0] + b[:, 1] * b[:, 1] + b[:, 2] * b[:, 2]
    g12 = a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1] + a[:, 2] * b[:, 2]
    half = 0.5 * (inverse[:, 0] * g11 - 2.0 * inverse[:, 1] * g12 + inverse[:, 2] * g22)
    det = inverse[:, 3] * (g11 * g22 - g12 * g12)
    return half + np.sqrt(np.maximum(half * half - det, 0.0))
