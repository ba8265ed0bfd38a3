"""The analytic tangent of the Mindlin triangle with a fabric section as one compiled loop over
the cells: the numbers of ``MindlinShellBlock._cell_tangent`` with the fabric's level response
(elements/mindlin_fabric.py, the numpy reference; docs/theory.md §5.5, §5.7), each cell's
18 x 18 formed in place from its corners and the section's gradient and Hessian in the ten
section measures y (elements/fabric_section.py, itself compiled).

The section couples the three levels zeta = -1, 0, 1 through y = P e (P the constant
projection of elements/mindlin_fabric.py): the numpy path forms P^T H P (21 x 21) and
B^T (P^T H P) B; here B_y = P B (10 x 18) is formed from the level rows of B^psi and
K = B_y^T H B_y, the same sum with its zero terms left out (the rows of the outer levels P
does not read, on which sigma is zero, are not formed), in another order (within 1e-12 of
the reference, tests/test_mindlin_fabric_tangent.py). The geometric part
sigma . d2e/ds2, with sigma = P^T dW/dy, and the spin term are the elastic kernel's
(elements/mindlin_tangent.py): the per-cell pieces the two share are
elements/mindlin_cell_terms.py's.
"""

from __future__ import annotations

import numpy as np

from elements.kernel_inputs import read_only
from elements.mindlin_cell_terms import (
    bending_spin_blocks,
    clear_stress_terms,
    level_vectors,
    measure_row,
    section_stresses,
    stress_terms,
    turned_vectors,
    tying_vectors,
)
from femcore.jit import AVAILABLE, jit, prange

# Cells per chunk of the loop (the scratch allocated once a chunk), passed to the kernel as an
# argument (numba would freeze a global into its cached build).
CELLS_PER_CHUNK = 64

__all__ = ["AVAILABLE", "fabric_tangent_blocks"]


@jit
def _fabric_tangent_cells(
    x, v, zeta, half, tying_n, ref11, ref22, ref12, ref_tying, dw_dy, d2w_dy2, gradient,
    curvature, out, size,
):  # fmt: skip
    """out (m, 18, 18): d(force, moment)/d(u, psi) of each cell, rows and columns
    (corner a, u | psi, component); x, v (m, 3, 3) corner positions and unit directors;
    zeta (3,) the levels -1, 0, 1; ref* (m, 3) and (m, 3, 4) the reference metric;
    dw_dy (m, 10) and d2w_dy2 (m, 10, 10) the section's gradient and Hessian; gradient
    (3, 7, 6, 5) and curvature (3, 7, 6, 6) the product coefficients of elements/mindlin.py."""
    m = x.shape[0]
    nz = zeta.shape[0]
    # Chunks of ``size`` cells: the scratch is allocated once a chunk (numba's
    # parallel build would share what is allocated before the loop; once a cell cost 30 %).
    for chunk in prange((m + size - 1) // size):
        # scratch of this chunk
        g3 = np.empty((3, 3))
        vec = np.empty((nz, 5, 3))
        turned = np.empty((3, 5, 3))
        b_psi = np.empty((nz, 7, 18))
        b_y = np.empty((10, 18))
        stressed = np.empty((10, 18))
        sigma = np.empty((nz, 7))
        k = np.empty((18, 18))
        director_gradient = np.empty((3, 3))
        geometric = np.empty((6, 6))
        arms = np.empty((3, 2, 3, 3))
        for cell in range(chunk * size, min(m, (chunk + 1) * size)):
            section_stresses(dw_dy, cell, sigma)
            tying_vectors(v, cell, half, tying_n, g3)
            clear_stress_terms(director_gradient, geometric)
            for z in range(nz):
                level_vectors(x, v, cell, zeta, z, half, g3, vec)
                turned_vectors(v, cell, vec, z, turned)
                # P reads rows 0-2 of the outer levels and all 7 of the mid-surface: the others
                # have no part in B_y, and sigma is zero on them
                rows = 7 if z == 1 else 3
                for r in range(rows):
                    measure_row(gradient, vec, turned, z, r, b_psi)
                for r in range(rows):
                    stress_terms(
                        sigma, gradient, curvature, vec, z, r, director_gradient, geometric
                    )
            # B_y = P B^psi: the rows of the section measures y
            for col in range(18):
                for r in range(3):
                    b_y[r, col] = b_psi[1, r, col]
                    b_y[3 + r, col] = 0.5 * b_psi[2, r, col] - 0.5 * b_psi[0, r, col]
                for r in range(4):
                    b_y[6 + r, col] = b_psi[1, 3 + r, col]
            # K = B_y^T (H B_y), H symmetric: the upper triangle
            for r in range(10):
                for col in range(18):
                    total = 0.0
                    for q in range(10):
                        total += d2w_dy2[cell, r, q] * b_y[q, col]
                    stressed[r, col] = total
            for row in range(18):
                for col in range(row, 18):
                    total = 0.0
                    for r in range(10):
                        total += b_y[r, row] * stressed[r, col]
                    k[row, col] = total
            bending_spin_blocks(v, cell, geometric, director_gradient, arms, k)
            for row in range(18):
                for col in range(18):
                    out[cell, row, col] = k[row, col]


def fabric_tangent_blocks(
    x: np.ndarray,
    v: np.ndarray,
    zeta: np.ndarray,
    thickness: float,
    tying_n: np.ndarray,
    reference_metric: dict,
    dw_dy: np.ndarray,
    d2w_dy2: np.ndarray,
    gradient: np.ndarray,
    curvature: np.ndarray,
) -> np.ndarray:
    """The blocks (m, 3, 6, 3, 6) of ``MindlinFabricBlock.tangent`` (N/mm, N, N mm).

    Parameters
    ----------
    x, v : (m, 3, 3) float, mm and unit
        Corner positions and directors of the cells.
    zeta : (3,) float
        The measuring levels -1, 0, 1.
    thickness : float, mm
    tying_n : (3, 3) float
        The MITC3 tying points' shape functions (elements/mindlin_tables.py ``_TYING_N``).
    reference_metric : dict
        "11", "22", "12" (m, 3) and "tying" (m, 3, 4), mm^2: the cells' reference products.
    dw_dy, d2w_dy2 : (m, 10) and (m, 10, 10) float
        The section energy's gradient and Hessian in the section measures
        (elements/fabric_section.py ``response``).
    gradient, curvature : (3, 7, 6, 5) and (3, 7, 6, 6) float
        The product coefficients (elements/mindlin_tables.py ``_product_coefficients``).
    """
    m = len(x)
    if len(zeta) != 3 or dw_dy.shape != (m, 10) or d2w_dy2.shape != (m, 10, 10):
        raise ValueError(
            f"the fabric tangent takes 3 levels and (m, 10), (m, 10, 10) section derivatives "
            f"for m = {m} cells, got {len(zeta)} levels, {dw_dy.shape} and {d2w_dy2.shape}"
        )
    out = np.empty((m, 18, 18))
    _fabric_tangent_cells(
        read_only(x),
        read_only(v),
        read_only(zeta),
        0.5 * float(thickness),
        read_only(tying_n),
        read_only(reference_metric["11"]),
        read_only(reference_metric["22"]),
        read_only(reference_metric["12"]),
        read_only(reference_metric["tying"]),
        read_only(dw_dy),
        read_only(d2w_dy2),
        read_only(gradient),
        read_only(curvature),
        out,
        CELLS_PER_CHUNK,
    )
    return out.reshape(m, 3, 6, 3, 6)
