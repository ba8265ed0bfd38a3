"""The ten section measures y of the Mindlin triangle with a fabric section as one compiled loop
over the cells: the numbers of ``MindlinFabricBlock.section_measures`` (elements/mindlin_fabric.py,
the numpy reference; docs/theory.md §5.5, §5.7) from each cell's corners, without the batched
vectors and products of the numpy path (about 0.5 us a cell of Python and numpy overhead at a
few thousand cells, where the loop costs a tenth of it).

y = P e: the membrane strains and tying changes of the mid-surface level, and half the
difference of the outer levels' membrane strains (the bending strains); the dot products are
summed component by component (within 1e-12 of numpy's, tests/test_mindlin_fabric_tangent.py),
by the elastic tangent's pieces (elements/mindlin_cell_terms.py).
"""

from __future__ import annotations

import numpy as np

from elements.kernel_inputs import read_only
from elements.mindlin_cell_terms import level_measures, level_vectors, tying_vectors
from femcore.jit import AVAILABLE, jit, prange

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
        vec = np.empty((nz, 5, 3))
        e = np.empty((nz, 7))
        for cell in range(chunk * size, min(m, (chunk + 1) * size)):
            tying_vectors(v, cell, half, tying_n, g3)
            for z in range(nz):
                level_vectors(x, v, cell, zeta, z, half, g3, vec)
                level_measures(vec, z, cell, ref11, ref22, ref12, ref_tying, e)
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
