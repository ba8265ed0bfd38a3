"""What an element writer needs: the protocol (``ElementType``, ``ElementBlock``,
``CellTangent``, defined in femcore.element so that the core and the solvers know it without
importing the element types), the ``Scatter`` of femcore.assembly, and helpers: ``local_tangent``
(a cell-local stiffness by central differences, all cells at once) and ``check_positive``.

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
    "CellTangent",
    "SparseTangent",
    "ElementBlock",
    "ElementType",
    "Scatter",
    "check_positive",
    "local_tangent",
]


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
