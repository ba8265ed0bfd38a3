"""The Mindlin shell's element eigenvalue bound of the critical step (docs/theory.md §6.2, B1,
B4 and B5) at a given rotary inertia j: the step the explicit solver takes (the block's own j,
``cell_stable_dt``, calibrated once on the cheap trace bound ``cheap_omega2`` and followed by
the stretch) and the step the interactions' automatic penalty is sized on (B2's closed-form j,
whatever rotary_scaling the shell was given: "The penalty's step"). ``MindlinShellBlock``'s
methods of the same names (elements/mindlin.py) call these with the block; the fabric block
overrides ``_cheap_omega2`` (elements/mindlin_fabric.py).
"""

from __future__ import annotations

from typing import cast

import numpy as np

from elements import kernels
from elements.mindlin_tables import _congruent_cells, inverse_metric, largest_stretch2
from femcore.memory import small_pages
from femcore.rotation import cross
from femcore.state import State

__all__ = [
    "cell_stable_dt",
    "cheap_omega2",
    "cheap_terms",
    "element_omega2",
    "penalty_stable_dt",
    "reference_steps",
]

_TANGENT_SLICE = 256  # cells a tangent slice holds (as elements/mindlin.py)


def element_omega2(
    block,
    x: np.ndarray,
    v: np.ndarray,
    cells: np.ndarray | None = None,
    rotary_factor: np.ndarray | None = None,
) -> np.ndarray:
    """Largest eigenvalue (c,), 1/s^2, of K_e phi = omega^2 M_e phi for each triangle of a
    bound MindlinShellBlock (or its fabric form) with corners x and directors v (c, 3, 3):
    K_e its 18 x 18 tangent in (u, psi) (symmetric part), M_e its lumped share rho h A / 3
    per translation and that times j per rotation (the drilling rotation too: a larger space
    only raises the maximum). ``cells`` (c,): the block's cells x and v belong to (default:
    all, in order); ``rotary_factor`` (m,), mm^2: j of every cell of the block (default: the
    block's own)."""
    cells = np.arange(len(x)) if cells is None else np.asarray(cells)
    j = block.rotary_factor if rotary_factor is None else rotary_factor
    share = block.material.areal_density * block.reference_area[cells] / 3.0
    node = np.stack([share] * 3 + [share * j[cells]] * 3, axis=1)
    scale = 1.0 / np.sqrt(np.tile(node, 3))  # (c, 18), M_e^-1/2
    omega2 = np.empty(len(x))
    for start in range(0, len(x), _TANGENT_SLICE):
        rows = slice(start, start + _TANGENT_SLICE)
        # An index array selects the cells' tables as the slices of ``tangent`` do.
        selected = cast(slice, cells[rows])
        k = block._cell_tangent(x[rows], v[rows], selected).reshape(-1, 18, 18)
        k = 0.5 * (k + np.swapaxes(k, 1, 2))
        k *= scale[rows, :, None] * scale[rows, None, :]
        omega2[rows] = np.linalg.eigvalsh(k)[:, -1]
    return omega2


def reference_steps(block, rotary_factor: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The cells' critical steps (m,), s, in the reference configuration with rotary inertia
    ``rotary_factor`` (m,), mm^2, and their calibration (m,), the element eigenvalue over the
    cheap bound ``_cheap_omega2`` (cells of the same reference shape share one eigenvalue
    problem). On (m, 3, 3) temporaries: the caller chooses the pages."""
    x0, v0 = block._reference_cells()
    first, shape_of = _congruent_cells(x0, v0)
    omega2 = element_omega2(block, x0[first], v0[first], first, rotary_factor)[shape_of]
    cheap = block._cheap_omega2(x0, rotary_factor)
    calibration = omega2 / cheap
    return 2.0 / np.sqrt(cheap * calibration), calibration


def penalty_stable_dt(block, state: State) -> float:
    """The block's critical step at ``state`` with B2's closed-form rotary inertia, s, whatever
    rotary_scaling the shell was given: its ``stable_dt`` where its j is the closed form's (the
    same bits), else the step its cells would have at the closed j (the same reference steps
    and the same stretch, B5). What the interactions' automatic penalty is sized on, so that
    no choice of j moves the contacts' stiffness (docs/theory.md §6.2, "The penalty's step")."""
    closed = block._closed_rotary_factor()
    if np.array_equal(closed, block.rotary_factor):
        return block.stable_dt(state)
    block.cell_stable_dt(state)  # the block's calibration: its inverse metric
    steps, _ = reference_steps(block, closed)
    if block.kernel == "compiled":
        cell_steps = kernels.mindlin_cell_steps(
            block, state.positions, steps, block._inverse_metric
        )
    else:
        positions = state.positions[block.connectivity]
        stretch2 = largest_stretch2(positions, block._inverse_metric)
        cell_steps = steps / np.sqrt(np.maximum(stretch2, 1.0))
    return float(np.min(cell_steps))


def cell_stable_dt(block, state: State) -> np.ndarray:
    """Critical step per cell, 2 / omega (docs/theory.md §6.2, B4): omega^2 the largest
    eigenvalue of each element's K_e phi = omega^2 M_e phi (its tangent and its share of
    the lumped masses and rotary inertias), which bounds that of the assembly (Irons:
    the Rayleigh quotient of a sum is at most the largest of the elements'). It is
    computed once, in the reference configuration (as a factor on the block's cheap bound
    ``_cheap_omega2``), and follows the deformation at each call as the element's
    Green-Lagrange strains do: omega^2 times the largest squared in-plane stretch, at
    least 1 (B5). Cells of the same reference shape (edges and directors equal to the
    bit: the cells of a structured mesh) share one eigenvalue problem.
    """
    if block._step_calibration is None:
        # once, on (m, 3, 3) temporaries: ordinary pages (femcore/memory.py)
        with small_pages():
            steps, block._step_calibration = reference_steps(block, block.rotary_factor)
            block._reference_steps = steps
            block._inverse_metric = inverse_metric(block._reference_cells()[0])
    if block.kernel == "compiled":  # the explicit solver asks every 10 steps: one loop
        return kernels.mindlin_cell_steps(
            block, state.positions, block._reference_steps, block._inverse_metric
        )
    stretch2 = largest_stretch2(state.positions[block.connectivity], block._inverse_metric)
    return block._reference_steps / np.sqrt(np.maximum(stretch2, 1.0))


def cheap_terms(block, rotary_factor: np.ndarray | None = None) -> tuple[float, np.ndarray]:
    """(a, b) of ``cheap_omega2`` = a sum_k 1 / h_k^2 + b: a = 3 / rho (max(Q11, Q22) +
    Q66 + kappa G), N/mm^2 / (t/mm^3); b (m,) = kappa G / (2 rho j), 1/s^2, j
    ``rotary_factor`` (m,), mm^2 (default: the block's)."""
    q = block.material.plane_stress
    shear = float(np.max(block.material.transverse))
    rho = block.material.density
    translational = 3.0 / rho * (max(q[0, 0], q[1, 1]) + q[2, 2] + shear)
    j = block.rotary_factor if rotary_factor is None else rotary_factor
    return translational, shear / (2.0 * rho * j)


def cheap_omega2(block, x: np.ndarray, rotary_factor: np.ndarray | None = None) -> np.ndarray:
    """omega^2 (m,) of docs/theory.md §6.2 B1-B2 from the corner positions x (m, 3, 3):
    the trace bound of M^-1 K for the translations of a linear triangle with lumped mass
    rho h A / 3, 3 / rho (max(Q11, Q22) + Q66 + kappa G) sum_k 1 / h_k^2 (h_k the
    altitudes), plus kappa G / (2 rho j) for the rotations (j the rotary factor). It
    follows the geometry, not the element's actual modes: on cells of aspect 10 it fell
    below the element eigenvalue (an unstable step), on regular cells it is above."""
    sides = np.linalg.norm(x[:, [2, 0, 1]] - x[:, [1, 2, 0]], axis=-1)  # opposite node k
    area2 = np.linalg.norm(cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), axis=1)
    inverse_heights2 = np.sum((sides / area2[:, None]) ** 2, axis=1)
    translational, rotational = cheap_terms(block, rotary_factor)
    return translational * inverse_heights2 + rotational
