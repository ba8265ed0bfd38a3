"""The analytic tangent of the elastic MITC3 Mindlin triangle as one compiled loop over the
cells: the numbers of ``MindlinShellBlock._cell_tangent`` (elements/mindlin.py, the numpy
reference; docs/theory.md §5.5), each cell's 18 x 18 formed in place from its corners, without
the batched temporaries (20 vectors, B^psi, D B^psi per level) that the numpy path writes and
reads back for every cell.

Per cell and thickness level z: the vectors (g1, g2, g3^A, g3^B, g3^C) and their turned
copies V_k x g_u, the seven level measures e_z and sigma_z = D^_z e_z, B^psi_z (7 x 18) from
the product coefficients; then K = sum_z B_z^T D^_z B_z, the geometric part G (x) P P^T, and
the spin term (V_a g_a^T - (g_a . V_a) I) on the director blocks.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from elements.jit import AVAILABLE, jit, prange

if TYPE_CHECKING:
    from elements.mindlin import MindlinShellBlock

__all__ = ["AVAILABLE", "mindlin_tangent_blocks"]


@jit
def _tangent_cells(
    x, v, zeta, half, tying_n, ref11, ref22, ref12, ref_tying, stiffness, gradient,
    curvature, out,
):  # fmt: skip
    """out (m, 18, 18): d(force, moment)/d(u, psi) of each cell, rows and columns
    (corner a, u | psi, component); x, v (m, 3, 3) corner positions and unit directors;
    ref* (m, Z) and (m, Z, 4) the reference metric; stiffness (m, Z, 7, 7) D^_z; gradient
    (Z, 7, 6, 5) and curvature (Z, 7, 6, 6) the product coefficients of elements/mindlin.py."""
    m = x.shape[0]
    nz = zeta.shape[0]
    for cell in prange(m):
        vec = np.empty((nz, 5, 3))
        turned = np.empty((nz, 3, 5, 3))
        b_psi = np.zeros((nz, 7, 18))
        sigma = np.zeros((nz, 7))
        e = np.empty(7)
        k = np.zeros((18, 18))
        stressed = np.empty((7, 18))
        director_gradient = np.zeros((3, 3))
        geometric = np.zeros((6, 6))
        arms = np.zeros((3, 2, 3, 3))
        for t in range(3):  # g3 at the tying points A, B, C
            for c in range(3):
                total = 0.0
                for node in range(3):
                    total += tying_n[t, node] * v[cell, node, c]
                for z in range(nz):
                    vec[z, 2 + t, c] = half * total
        for z in range(nz):
            for c in range(3):
                vec[z, 0, c] = (x[cell, 1, c] - x[cell, 0, c]) + zeta[z] * half * (
                    v[cell, 1, c] - v[cell, 0, c]
                )
                vec[z, 1, c] = (x[cell, 2, c] - x[cell, 0, c]) + zeta[z] * half * (
                    v[cell, 2, c] - v[cell, 0, c]
                )
            for a in range(3):
                for u in range(5):
                    turned[z, a, u, 0] = v[cell, a, 1] * vec[z, u, 2] - v[cell, a, 2] * vec[z, u, 1]
                    turned[z, a, u, 1] = v[cell, a, 2] * vec[z, u, 0] - v[cell, a, 0] * vec[z, u, 2]
                    turned[z, a, u, 2] = v[cell, a, 0] * vec[z, u, 1] - v[cell, a, 1] * vec[z, u, 0]
            d00 = d11 = d01 = d02 = d04 = d13 = d14 = 0.0
            for c in range(3):
                d00 += vec[z, 0, c] * vec[z, 0, c]
                d11 += vec[z, 1, c] * vec[z, 1, c]
                d01 += vec[z, 0, c] * vec[z, 1, c]
                d02 += vec[z, 0, c] * vec[z, 2, c]
                d04 += vec[z, 0, c] * vec[z, 4, c]
                d13 += vec[z, 1, c] * vec[z, 3, c]
                d14 += vec[z, 1, c] * vec[z, 4, c]
            e[0] = 0.5 * (d00 - ref11[cell, z])
            e[1] = 0.5 * (d11 - ref22[cell, z])
            e[2] = d01 - ref12[cell, z]
            e[3] = d02 - ref_tying[cell, z, 0]
            e[4] = d04 - ref_tying[cell, z, 1]
            e[5] = d13 - ref_tying[cell, z, 2]
            e[6] = d14 - ref_tying[cell, z, 3]
            for r in range(7):
                total = 0.0
                for q in range(7):
                    total += stiffness[cell, z, r, q] * e[q]
                sigma[z, r] = total
            for r in range(7):
                for a in range(3):
                    for c in range(3):
                        along = 0.0
                        turn = 0.0
                        for u in range(5):
                            along += gradient[z, r, a, u] * vec[z, u, c]
                            turn += gradient[z, r, 3 + a, u] * turned[z, a, u, c]
                        b_psi[z, r, 6 * a + c] = along
                        b_psi[z, r, 6 * a + 3 + c] = turn
            # K += B^T (D B)
            for r in range(7):
                for col in range(18):
                    total = 0.0
                    for q in range(7):
                        total += stiffness[cell, z, r, q] * b_psi[z, q, col]
                    stressed[r, col] = total
            for row in range(18):  # symmetric (D^_z is): the upper triangle, mirrored below
                for col in range(row, 18):
                    total = 0.0
                    for r in range(7):
                        total += b_psi[z, r, row] * stressed[r, col]
                    k[row, col] += total
            # dW/dV_a and the geometric coefficients G = sum_r sigma_r d2e_r/ds2
            for r in range(7):
                s = sigma[z, r]
                for a in range(3):
                    for u in range(5):
                        weight = s * gradient[z, r, 3 + a, u]
                        for c in range(3):
                            director_gradient[a, c] += weight * vec[z, u, c]
                for p in range(6):
                    for q in range(6):
                        geometric[p, q] += s * curvature[z, r, p, q]
        for row in range(18):
            for col in range(row):
                k[row, col] = k[col, row]
        # Geometric part: the block of slots (t, a), (t', b) is G P_at P_bt'^T, P_a0 = I and
        # P_a1 = [V_a]x.
        for a in range(3):
            for i in range(3):
                arms[a, 0, i, i] = 1.0
            arms[a, 1, 0, 1], arms[a, 1, 0, 2] = -v[cell, a, 2], v[cell, a, 1]
            arms[a, 1, 1, 0], arms[a, 1, 1, 2] = v[cell, a, 2], -v[cell, a, 0]
            arms[a, 1, 2, 0], arms[a, 1, 2, 1] = -v[cell, a, 1], v[cell, a, 0]
        for a in range(3):
            for t in range(2):
                for b in range(3):
                    for t2 in range(2):
                        coefficient = geometric[3 * t + a, 3 * t2 + b]
                        if coefficient == 0.0:
                            continue
                        for i in range(3):
                            for j in range(3):
                                product = 0.0
                                for c in range(3):
                                    product += arms[a, t, i, c] * arms[b, t2, j, c]
                                k[6 * a + 3 * t + i, 6 * b + 3 * t2 + j] += coefficient * product
        # Spin: turning V_a turns the arm of m_a = V_a x g_a (eq. 5.5.5).
        for a in range(3):
            along = 0.0
            for c in range(3):
                along += director_gradient[a, c] * v[cell, a, c]
            for i in range(3):
                for j in range(3):
                    k[6 * a + 3 + i, 6 * a + 3 + j] += v[cell, a, i] * director_gradient[a, j]
                k[6 * a + 3 + i, 6 * a + 3 + i] -= along
        for row in range(18):
            for col in range(18):
                out[cell, row, col] = k[row, col]


def mindlin_tangent_blocks(
    block: MindlinShellBlock,
    x: np.ndarray,
    v: np.ndarray,
    stiffness: np.ndarray,
    gradient: np.ndarray,
    curvature: np.ndarray,
) -> np.ndarray:
    """The blocks (m, 3, 6, 3, 6) of ``MindlinShellBlock.tangent`` (N/mm, N, N mm) from the
    corner positions x and unit directors v (m, 3, 3), the level stiffness D^_z (m, Z, 7, 7)
    and the product coefficients (gradient (Z, 7, 6, 5), curvature (Z, 7, 6, 6))."""
    m = len(x)
    out = np.empty((m, 18, 18))
    ref = block.reference_metric
    _tangent_cells(
        np.ascontiguousarray(x, dtype=float),
        np.ascontiguousarray(v, dtype=float),
        np.ascontiguousarray(block.zeta, dtype=float),
        0.5 * float(block.h),
        _tying_n(),
        np.ascontiguousarray(ref["11"]),
        np.ascontiguousarray(ref["22"]),
        np.ascontiguousarray(ref["12"]),
        np.ascontiguousarray(ref["tying"]),
        np.ascontiguousarray(stiffness),
        np.ascontiguousarray(gradient),
        np.ascontiguousarray(curvature),
        out,
    )
    return out.reshape(m, 3, 6, 3, 6)


def _tying_n() -> np.ndarray:
    from elements.mindlin import _TYING_N

    return np.ascontiguousarray(_TYING_N, dtype=float)
