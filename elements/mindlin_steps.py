"""The Mindlin shell's element eigenvalue bounds of the critical step (docs/theory.md §6.2, B1
and B4): each triangle's largest omega^2 of K_e phi = omega^2 M_e phi with its rotations free
(the step the explicit solver takes) and with its rotations held (the limit j -> infinity: the
translations alone, the step the interactions' automatic penalty is sized on, which no choice
of the rotary inertia j moves).
"""

from __future__ import annotations

from typing import cast

import numpy as np

from elements.mindlin_tables import _congruent_cells, inverse_metric, largest_stretch2
from femcore.state import State

__all__ = ["element_omega2", "held_rotation_stable_dt"]

_TANGENT_SLICE = 256  # cells a tangent slice holds (as elements/mindlin.py)
# the translations (u) among a triangle's 18 DOFs, node by node (u, psi)
_TRANSLATIONS = np.array([0, 1, 2, 6, 7, 8, 12, 13, 14])


def element_omega2(
    block, x: np.ndarray, v: np.ndarray, cells: np.ndarray | None = None, rotations: bool = True
) -> np.ndarray:
    """Largest eigenvalue (c,), 1/s^2, of K_e phi = omega^2 M_e phi for each triangle of a
    bound MindlinShellBlock (or its fabric form) with corners x and directors v (c, 3, 3):
    K_e its 18 x 18 tangent in (u, psi) (symmetric part), M_e its lumped share rho h A / 3
    per translation and that times j per rotation (the drilling rotation too: a larger space
    only raises the maximum). ``rotations`` False: the rotations held, the 9 x 9 block of the
    translations alone (K_tt phi = omega^2 M_t phi, j -> infinity). ``cells`` (c,): the
    block's cells x and v belong to (default: all, in order)."""
    cells = np.arange(len(x)) if cells is None else np.asarray(cells)
    share = block.material.areal_density * block.reference_area[cells] / 3.0
    node = np.stack([share] * 3 + [share * block.rotary_factor[cells]] * 3, axis=1)
    scale = 1.0 / np.sqrt(np.tile(node, 3))  # (c, 18), M_e^-1/2
    omega2 = np.empty(len(x))
    for start in range(0, len(x), _TANGENT_SLICE):
        rows = slice(start, start + _TANGENT_SLICE)
        # An index array selects the cells' tables as the slices of ``tangent`` do.
        selected = cast(slice, cells[rows])
        k = block._cell_tangent(x[rows], v[rows], selected).reshape(-1, 18, 18)
        k = 0.5 * (k + np.swapaxes(k, 1, 2))
        k *= scale[rows, :, None] * scale[rows, None, :]
        if not rotations:
            k = k[:, _TRANSLATIONS][:, :, _TRANSLATIONS]
        omega2[rows] = np.linalg.eigvalsh(k)[:, -1]
    return omega2


def held_rotation_stable_dt(block, state: State) -> float:
    """The block's critical step with the rotations held, s: 2 / sqrt(omega^2), omega^2 the
    largest over its cells of ``element_omega2`` with ``rotations=False`` in the reference
    configuration (cells of the same reference shape share one problem), times the largest
    squared in-plane stretch at ``state`` (at least 1), as ``cell_stable_dt`` follows the
    deformation (B5). It depends on the membrane and transverse shear stiffness and the mass,
    not on the rotary inertia j. Asked once, when a model is compiled."""
    x0, v0 = block._reference_cells()
    first, shape_of = _congruent_cells(x0, v0)
    held = element_omega2(block, x0[first], v0[first], first, rotations=False)[shape_of]
    stretch2 = largest_stretch2(state.positions[block.connectivity], inverse_metric(x0))
    return float(2.0 / np.sqrt(np.max(held * np.maximum(stretch2, 1.0))))
