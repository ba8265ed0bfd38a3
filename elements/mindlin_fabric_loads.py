"""The element loads of the Mindlin triangle with a fabric section as one compiled loop over the
cells: the numbers of ``MindlinFabricBlock.numpy_cell_loads`` (elements/mindlin_fabric.py,
the numpy reference; docs/theory.md §5.5, §5.7), sigma . B^psi with sigma = P^T dW/dy, from
each cell's corners and the section's gradient dW/dy (elements/fabric_section.py, compiled),
without the batched B^psi (21 x 18 a cell) the numpy path writes and reads back.

The rows of B^psi are formed as elements/mindlin_fabric_tangent.py forms them (only those P
reads: rows 0-2 of the outer levels, all 7 of the mid-surface), from the per-cell pieces of
elements/mindlin_cell_terms.py, each entry of a row summed into the loads as it is formed
(``measure_entries``; the rows formed whole first, by the tangent's ``measure_row``, the loop
took 5 % longer); the sums run in another
order than numpy's matmul (within 1e-12 of the reference, tests/test_mindlin_fabric_tangent.py).
"""

from __future__ import annotations

import numpy as np

from elements.kernel_inputs import read_only
from elements.mindlin_cell_terms import (
    level_vectors,
    measure_entries,
    section_stresses,
    turned_vectors,
    tying_vectors,
)
from femcore.jit import AVAILABLE, jit, prange

# Cells per chunk of the loop (the scratch allocated once a chunk), passed to the kernel as an
# argument (numba would freeze a global into its cached build).
CELLS_PER_CHUNK = 64

__all__ = ["AVAILABLE", "fabric_cell_loads"]


@jit
def _fabric_loads_cells(x, v, zeta, half, tying_n, dw_dy, gradient, force, moment, size):
    """force, moment (m, 3, 3): dW/du and V x dW/dV at the corners of each cell; x, v (m, 3, 3)
    corner positions and unit directors; zeta (3,) the levels -1, 0, 1; dw_dy (m, 10) the
    section's gradient; gradient (3, 7, 6, 5) the product coefficients of
    elements/mindlin_tables.py."""
    m = x.shape[0]
    nz = zeta.shape[0]
    # Chunks of ``size`` cells: the scratch is allocated once a chunk (numba's
    # parallel build would share what is allocated before the loop; once a cell cost 30 %).
    for chunk in prange((m + size - 1) // size):
        # scratch of this chunk
        g3 = np.empty((3, 3))
        vec = np.empty((nz, 5, 3))
        turned = np.empty((3, 5, 3))
        sigma = np.empty((nz, 7))
        loads = np.empty(18)
        for cell in range(chunk * size, min(m, (chunk + 1) * size)):
            section_stresses(dw_dy, cell, sigma)
            for col in range(18):
                loads[col] = 0.0
            tying_vectors(v, cell, half, tying_n, g3)
            for z in range(nz):
                level_vectors(x, v, cell, zeta, z, half, g3, vec)
                turned_vectors(v, cell, vec, z, turned)
                rows = 7 if z == 1 else 3  # sigma is zero on the rows P does not read
                for r in range(rows):
                    s = sigma[z, r]
                    for a in range(3):
                        for c in range(3):
                            along, turn = measure_entries(gradient, vec, turned, z, r, a, c)
                            loads[6 * a + c] += s * along
                            loads[6 * a + 3 + c] += s * turn
            for a in range(3):
                for c in range(3):
                    force[cell, a, c] = loads[6 * a + c]
                    moment[cell, a, c] = loads[6 * a + 3 + c]


def fabric_cell_loads(
    x: np.ndarray,
    v: np.ndarray,
    zeta: np.ndarray,
    thickness: float,
    tying_n: np.ndarray,
    dw_dy: np.ndarray,
    gradient: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Unscattered nodal forces (m, 3, 3), N, and director moments (m, 3, 3), N mm.

    Parameters
    ----------
    x, v : (m, 3, 3) float, mm and unit
        Corner positions and directors of the cells.
    zeta : (3,) float
        The measuring levels -1, 0, 1.
    thickness : float, mm
    tying_n : (3, 3) float
        The MITC3 tying points' shape functions (elements/mindlin_tables.py ``_TYING_N``).
    dw_dy : (m, 10) float
        The section energy's gradient in the section measures (elements/fabric_section.py).
    gradient : (3, 7, 6, 5) float
        The product coefficients (elements/mindlin_tables.py ``_product_coefficients``).
    """
    m = len(x)
    if len(zeta) != 3 or dw_dy.shape != (m, 10):
        raise ValueError(
            f"the fabric loads take 3 levels and an (m, 10) section gradient for m = {m} "
            f"cells, got {len(zeta)} levels and {dw_dy.shape}"
        )
    force, moment = np.empty((m, 3, 3)), np.empty((m, 3, 3))
    _fabric_loads_cells(
        read_only(x),
        read_only(v),
        read_only(zeta),
        0.5 * float(thickness),
        read_only(tying_n),
        read_only(dw_dy),
        read_only(gradient),
        force,
        moment,
        CELLS_PER_CHUNK,
    )
    return force, moment
