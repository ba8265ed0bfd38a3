"""The ten section measures y of the Mindlin triangle with a fabric section as one compiled loop
over the cells: the numbers of ``MindlinFabricBlock.section_measures`` (elements/mindlin_fabric.py,
the numpy reference; docs/theory.md §5.5, §5.7) from each cell's corners, without the batched
vectors and products of the numpy path (about 0.5 us a cell of Python and numpy overhead at a
few thousand cells, where the loop costs a tenth of it).

y = P e: the membrane strains and tying changes of the mid-surface level, and half the
difference of the outer levels' membrane strains (the bending strains); the dot products are
summed component by component (within 1e-12 of numpy's, tests/test_mindlin_fabric_tangent.py).
"""

from __future__ import annotations

import numpy as np

from elements.jit import AVAILABLE, jit, prange
from elements.kernel_inputs import read_only

# Cells per chunk of the loop (the scratch allocated once a chunk), passed to the kernel as an
# argument (numba would freeze a global into its cached build).
CELLS_PER_CHUNK = 64

__all__ = ["AVAILABLE", "fabric_section_measures"]


@jit
def _measures_cells(x, v, zeta, half, tying_n, ref11, ref22, ref12, ref_tying, y, size):
    """y (m, 10): the section measures of each cell; x, v (m, 3, 3) corner positions and unit
    directors; zeta (3,) the levels -1, 0, 1; ref* (m, 3) and (m, 3, 4) the reference metric."""
    m = x.shape[0]
    nz = zeta.shape[0]
    # Chunks of ``size`` cells: the scratch is allocated once a chunk (numba's
    # parallel build would share what is allocated before the loop; once a cell cost 30 %).
    for chunk in prange((m + size - 1) // size):
        # scratch of this chunk
        g3 = np.empty((3, 3))
        g1 = np.empty(3)
        g2 = np.empty(3)
        e = np.empty((nz, 7))
        for cell in range(chunk * size, min(m, (chunk + 1) * size)):
            for t in range(3):  # g3 at the tying points A, B, C
                for c in range(3):
                    total = 0.0
                    for node in range(3):
                        total += tying_n[t, node] * v[cell, node, c]
                    g3[t, c] = half * total
            for z in range(nz):
                for c in range(3):
                    g1[c] = (x[cell, 1, c] - x[cell, 0, c]) + zeta[z] * half * (
                        v[cell, 1, c] - v[cell, 0, c]
                    )
                    g2[c] = (x[cell, 2, c] - x[cell, 0, c]) + zeta[z] * half * (
                        v[cell, 2, c] - v[cell, 0, c]
                    )
                d11 = d22 = d12 = t0 = t1 = t2 = t3 = 0.0
                for c in range(3):
                    d11 += g1[c] * g1[c]
                    d22 += g2[c] * g2[c]
                    d12 += g1[c] * g2[c]
                    t0 += g1[c] * g3[0, c]
                    t1 += g1[c] * g3[2, c]
                    t2 += g2[c] * g3[1, c]
                    t3 += g2[c] * g3[2, c]
                e[z, 0] = 0.5 * (d11 - ref11[cell, z])
                e[z, 1] = 0.5 * (d22 - ref22[cell, z])
                e[z, 2] = d12 - ref12[cell, z]
                e[z, 3] = t0 - ref_tying[cell, z, 0]
                e[z, 4] = t1 - ref_tying[cell, z, 1]
                e[z, 5] = t2 - ref_tying[cell, z, 2]
                e[z, 6] = t3 - ref_tying[cell, z, 3]
            for r in range(3):
                y[cell, r] = e[1, r]
                y[cell, 3 + r] = 0.5 * e[2, r] - 0.5 * e[0, r]
            for r in range(4):
                y[cell, 6 + r] = e[1, 3 + r]


def fabric_section_measures(
    x: np.ndarray,
    v: np.ndarray,
    zeta: np.ndarray,
    thickness: float,
    tying_n: np.ndarray,
    reference_metric: dict,
) -> np.ndarray:
    """The section measures y (m, 10) of elements/fabric_section.py.

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
    """
    m = len(x)
    if len(zeta) != 3 or reference_metric["tying"].shape != (m, 3, 4):
        raise ValueError(
            f"the section measures take 3 levels and an (m, 3, 4) reference tying table for "
            f"m = {m} cells, got {len(zeta)} levels and {reference_metric['tying'].shape}"
        )
    y = np.empty((m, 10))
    _measures_cells(
        read_only(x),
        read_only(v),
        read_only(zeta),
        0.5 * float(thickness),
        read_only(tying_n),
        read_only(reference_metric["11"]),
        read_only(reference_metric["22"]),
        read_only(reference_metric["12"]),
        read_only(reference_metric["tying"]),
        y,
        CELLS_PER_CHUNK,
    )
    return y
