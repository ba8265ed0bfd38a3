"""The fibrous cells' critical steps (docs/theory.md §6.2) in one compiled pass over the cells
(numba), the formulas of ``FibrousShellBlock.cell_stable_dt_numpy`` in their order of operations:
the same steps to the last bit, on any number of threads (each cell its own output).

Why: the explicit solver asks for them every STABLE_DT_EVERY steps (solvers/explicit.py), and
the numpy formulas make some fifteen (cells,) arrays and a (cells, 3, 3) gather to do it, on
the main thread alone: 0.25 ms CPU a step of the 20k-triangle forming blank (2.5 ms an
evaluation, load 10), serial while the force passes run on two threads
(benchmarks/hemisphere_forming.py).
"""

from __future__ import annotations

import numpy as np

from elements.fibrous.cell_terms import cell_cross
from femcore.jit import jit_lanes, prange

__all__ = ["cell_steps"]


def _cell_steps(
    connectivity, positions, area, areal_density, tension, shear, coefficient, root, margin, out
):  # fmt: skip
    """Each cell's critical step (s) into out (cells,): connectivity (cells, 3) its nodes,
    positions (n, 3) mm, area (cells,) the reference areas A0, mm^2; areal_density t/mm^2;
    tension and shear the largest tangent stiffnesses, N/mm; the bending bound's step
    coefficient x L_min^2 x root, root = sqrt(areal_density / the largest bending
    stiffness); margin: the nodal normals' 10 % on omega^2."""
    for c in prange(connectivity.shape[0]):
        i0, i1, i2 = connectivity[c, 0], connectivity[c, 1], connectivity[c, 2]
        a0, a1, a2, b0, b1, b2, _, _, _ = cell_cross(positions, i0, i1, i2)
        # numpy's norm and sum of three components add them in order, from the first
        len1 = np.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
        len2 = np.sqrt(b0 * b0 + b1 * b1 + b2 * b2)
        cosine = abs(a0 * b0 + a1 * b1 + a2 * b2) / (len1 * len2)
        shortest = min(len1, len2)
        mass = areal_density * area[c] / 3.0
        omega2 = (2.0 + cosine) * tension * area[c] / (shortest * shortest * mass)
        omega2 += 2.0 * shear * area[c] * (1.0 / (len1 * len1) + 1.0 / (len2 * len2)) / mass
        rate = 2.0 / (coefficient * (shortest * shortest) * root)
        omega2 += rate * rate
        if margin:
            omega2 *= 1.1
        out[c] = 2.0 / np.sqrt(omega2)


# numpy's error model: a cell of no side length gives the numpy formulas' inf or nan
cell_steps = jit_lanes(_cell_steps)
