"""The analytic tangent of the elastic MITC3 Mindlin triangle as one compiled loop over the
cells: the numbers of ``MindlinShellBlock._cell_tangent`` (elements/mindlin.py, the numpy
reference; docs/theory.md §5.5), each cell's 18 x 18 formed in place from its corners, without
the batched temporaries (20 vectors, B^psi, D B^psi per level) that the numpy path writes and
reads back for every cell.

Per cell and thickness level z: the vectors (g1, g2, g3^A, g3^B, g3^C) and their turned
copies V_k x g_u, the seven level measures e_z and sigma_z = D^_z e_z, B^psi_z (7 x 18) from
the product coefficients; then K = sum_z B_z^T D^_z B_z, the geometric part G (x) P P^T, and
the spin term (V_a g_a^T - (g_a . V_a) I) on the director blocks. The pieces the fabric
section's loops share with this one are elements/mindlin_cell_terms.py's.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from elements.mindlin_cell_terms import (
    bending_spin_blocks,
    clear_stress_terms,
    level_measures,
    level_vectors,
    measure_row,
    stress_terms,
    turned_vectors,
    tying_vectors,
)
from femcore.jit import AVAILABLE, jit, prange

if TYPE_CHECKING:
    from elements.mindlin import MindlinShellBlock

# Cells per chunk of the loop (the scratch allocated once a chunk), passed to the kernel as an
# argument (numba would freeze a global into its cached build).
CELLS_PER_CHUNK = 64

__all__ = ["AVAILABLE", "mindlin_tangent_blocks"]


@jit
def _tangent_cells(
    x, v, zeta, half, tying_n, ref11, ref22, ref12, ref_tying, stiffness, gradient,
    curvature, out, size,
):  # fmt: skip
    """out (m, 18, 18): d(force, moment)/d(u, psi) of each cell, rows and columns
    (corner a, u | psi, component); x, v (m, 3, 3) corner positions and unit directors;
    ref* (m, Z) and (m, Z, 4) the reference metric; stiffness (m, Z, 7, 7) D^_z; gradient
    (Z, 7, 6, 5) and curvature (Z, 7, 6, 6) the product coefficients of elements/mindlin.py."""
    m = x.shape[0]
    nz = zeta.shape[0]
    # Chunks of ``size`` cells: the scratch is allocated once a chunk (numba's parallel
    # build would share what is allocated before the loop). Allocated a cell, the scratch
    # arrays were freed inside the cell, between the start and the end of the spliced
    # helpers, and numba then kept counting the references of the helpers' arrays.
    for chunk in prange((m + size - 1) // size):
        # scratch of this chunk
        g3 = np.empty((3, 3))
        vec = np.empty((nz, 5, 3))
        turned = np.empty((3, 5, 3))
        b_psi = np.empty((nz, 7, 18))
        sigma = np.empty((nz, 7))
        e = np.empty((nz, 7))
        k = np.empty((18, 18))
        stressed = np.empty((7, 18))
        director_gradient = np.empty((3, 3))
        geometric = np.empty((6, 6))
        arms = np.empty((3, 2, 3, 3))
        for cell in range(chunk * size, min(m, (chunk + 1) * size)):
            for row in range(18):
                for col in range(18):
                    k[row, col] = 0.0
            clear_stress_terms(director_gradient, geometric)
            tying_vectors(v, cell, half, tying_n, g3)
            for z in range(nz):
                level_vectors(x, v, cell, zeta, z, half, g3, vec)
                turned_vectors(v, cell, vec, z, turned)
                level_measures(vec, z, cell, ref11, ref22, ref12, ref_tying, e)
                for r in range(7):
                    total = 0.0
                    for q in range(7):
                        total += stiffness[cell, z, r, q] * e[z, q]
                    sigma[z, r] = total
                for r in range(7):
                    measure_row(gradient, vec, turned, z, r, b_psi)
                # K += B^T (D B)
                for r in range(7):
                    for col in range(18):
                        total = 0.0
                        for q in range(7):
                            total += stiffness[cell, z, r, q] * b_psi[z, q, col]
                        stressed[r, col] = total
                # symmetric (D^_z is): the upper triangle, mirrored below
                for row in range(18):
                    for col in range(row, 18):
                        total = 0.0
                        for r in range(7):
                            total += b_psi[z, r, row] * stressed[r, col]
                        k[row, col] += total
                for r in range(7):
                    stress_terms(
                        sigma, gradient, curvature, vec, z, r, director_gradient, geometric
                    )
            bending_spin_blocks(v, cell, geometric, director_gradient, arms, k)
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
        CELLS_PER_CHUNK,
    )
    return out.reshape(m, 3, 6, 3, 6)


def _tying_n() -> np.ndarray:
    from elements.mindlin import _TYING_N

    return np.ascontiguousarray(_TYING_N, dtype=float)
