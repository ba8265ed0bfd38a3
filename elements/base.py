"""What an element writer needs: the protocol (``ElementType``, ``ElementBlock``,
``CellTangent``, defined in femcore.element so that the core and the solvers know it without
importing the element types), the ``Scatter`` of femcore.assembly, and helpers: ``local_tangent``
(a cell-local stiffness by central differences, all cells at once), ``stacked_local_tangent``
(the same differences with every perturbed copy of the cells in one call) and
``check_positive``.

A block may fuse its force and energy passes by overriding
``ElementBlock.internal_force_and_energy`` (the default calls ``internal_force`` and
``strain_energy``): the explicit solver asks for both on the steps that check the energy
balance.

A new element type is one class deriving from ``ElementType`` whose ``bind`` returns an
``ElementBlock``; it may live in the user's own module and works with every solver.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from femcore.assembly import CellTangent, Scatter, SparseTangent
from femcore.checks import check_positive
from femcore.element import ElementBlock, ElementType
from femcore.rotation import rotate_about

__all__ = [
    "STACKED_CELLS",
    "CellTangent",
    "SparseTangent",
    "ElementBlock",
    "ElementType",
    "Scatter",
    "check_positive",
    "local_tangent",
    "stacked_local_tangent",
]


# The most stacked cells a call of ``stacked_local_tangent`` takes: its arrays of positions,
# directors, forces, moments and their joined loads (9 x 8 bytes a cell each, the loads twice)
# hold some 110 MB at this size, some 150 MB at the peak with the force pass's own, whatever
# the block.
STACKED_CELLS = 2**18


def local_tangent(
    cell_force: Callable,
    x: np.ndarray,
    v: np.ndarray | None,
    step: float,
    rotation_step: float = 1e-6,
) -> np.ndarray:
    """Central-difference stiffness of a cell-local force, all cells at once.

    cell_force(x, v) -> (forces (m, k, 3), moments (m, k, 3) or None): the unscattered nodal
    loads of each cell from its own corner positions x (m, k, 3) and directors v (m, k, 3) (or
    None for translation-only elements). Each of the k x c local unknowns is perturbed in every
    cell at once (they do not interact before the scatter), so the cost is 2 k c evaluations of
    cell_force whatever the mesh size. Returns (m, k, c, k, c) as in CellTangent.blocks.

    step : translation perturbation (mm); rotation_step : rotation perturbation (rad).
    """
    m, k, _ = x.shape
    c = 3 if v is None else 6

    def loads(xx, vv):
        f, moment = cell_force(xx, vv)
        return f if v is None else np.concatenate([f, moment], axis=-1)

    blocks = np.empty((m, k, c, k, c))
    for node in range(k):
        for comp in range(c):
            if comp < 3:
                shift = np.zeros_like(x)
                shift[:, node, comp] = step
                difference = loads(x + shift, v) - loads(x - shift, v)
                blocks[:, :, :, node, comp] = difference / (2.0 * step)
            else:
                assert v is not None  # c = 6 only with directors
                psi = np.zeros((m, 3))
                psi[:, comp - 3] = rotation_step
                plus, minus = v.copy(), v.copy()
                plus[:, node] = rotate_about(v[:, node], psi)
                minus[:, node] = rotate_about(v[:, node], -psi)
                difference = loads(x, plus) - loads(x, minus)
                blocks[:, :, :, node, comp] = difference / (2.0 * rotation_step)
    return blocks


def stacked_local_tangent(
    stacked_force: Callable,
    x: np.ndarray,
    v: np.ndarray,
    step: float,
    rotation_step: float = 1e-6,
    cells_per_call: int = STACKED_CELLS,
) -> np.ndarray:
    """``local_tangent`` with directors, its 2 k c perturbed copies of the cells evaluated in
    few calls (the + and - copies of as many unknowns a call as hold at most
    ``cells_per_call`` cells, at least one): the same perturbations, differences and
    quotients, so the same numbers to the bit where
    ``stacked_force`` gives each copy's loads as ``local_tangent``'s ``cell_force`` gives
    them. For a compiled force, whose cost per call (the passes' set-up) is then paid once
    (for a block of up to 2^18 / 72 = 3640 cells) instead of 2 k c times; the calls' arrays
    stay within ``cells_per_call`` cells (about 150 MB at the peak at STACKED_CELLS).

    stacked_force(xs, vs) -> (forces, moments): the unscattered loads (p m, k, 3) each of p
    stacked copies of the m cells (copy after copy, each in the block's cell order) from
    their corner positions and directors xs, vs (p m, k, 3). x, v : (m, k, 3). Returns
    (m, k, 6, k, 6) as in CellTangent.blocks.
    """
    m, k, _ = x.shape
    c = 6
    unknowns = [(node, comp) for node in range(k) for comp in range(c)]
    # Each call: the + and the - copy of as many unknowns as fit.
    per_call = max(1, cells_per_call // max(2 * m, 1))
    blocks = np.empty((m, k, c, k, c))
    for first in range(0, len(unknowns), per_call):
        group = unknowns[first : first + per_call]
        xs = np.broadcast_to(x, (2, len(group), m, k, 3)).copy()
        vs = np.broadcast_to(v, (2, len(group), m, k, 3)).copy()
        for j, (node, comp) in enumerate(group):
            if comp < 3:
                # local_tangent's x + shift: its zeros turn a -0.0 coordinate into +0.0
                xs[0, j] = x + 0.0
                xs[0, j, :, node, comp] = x[:, node, comp] + step
                xs[1, j, :, node, comp] = x[:, node, comp] - step
            else:
                psi = np.zeros((m, 3))
                psi[:, comp - 3] = rotation_step
                vs[0, j, :, node] = rotate_about(v[:, node], psi)
                vs[1, j, :, node] = rotate_about(v[:, node], -psi)
        force, moment = stacked_force(xs.reshape(-1, k, 3), vs.reshape(-1, k, 3))
        loads = np.concatenate([force, moment], axis=-1).reshape(2, len(group), m, k, c)
        for j, (node, comp) in enumerate(group):
            h = step if comp < 3 else rotation_step
            blocks[:, :, :, node, comp] = (loads[0, j] - loads[1, j]) / (2.0 * h)
    return blocks
