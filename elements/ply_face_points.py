"""The flat ply contact's faces at a state compiled (``PlyContactBlock._faces`` and
``offset_directions``, elements/ply_block.py; docs/theory.md, the ply contact section): the
unit area-weighted nodal normals of the plies' triangles along which the faces lie
(``faces="normal"``), the contact points p = sum_j N_j (x_j - a_j d_j) and the lower
triangles' offset corners y_k = x_k + b_k d_k, and the points' directions toward their own ply
sum_j N_j a_j d_j (``PlyContactBlock.facing``'s ``toward``: numpy's three-operand einsum on
the gathered d cost about 48 and 12 us a facing on the hemisphere's two passes), each in one
serial pass.

Their numpy reference is the block's own expressions, taken with ``ply_projection.COMPILED =
False``. The passes do the same IEEE operations in the same order (the normals' sums node by
node in the order ``np.bincount`` adds them, from 0.0; ``einsum("pj,pji->pi")`` and
``np.linalg.norm`` from the first term, ``einsum("pj,pj,pji->pi")`` from 0.0 with the
products left to right; no fused multiply-add: numba builds without fastmath), so they give
the same numbers to the last bit (tests/test_ply_kernels.py); the same bits on any thread
count (serial).
"""

from __future__ import annotations

import numpy as np

from elements.kernel_inputs import read_only, writable
from femcore.jit import lanes

__all__ = ["face_points", "offset_normals", "offset_toward"]


@lanes
def _normals(x, triangles, directions):
    """directions (n, 3): the unit sums of the triangles' (t, 3) cross products at their
    corners (0 at a node of none), x (n, 3)."""
    n = directions.shape[0]
    summed = np.zeros((n, 3))
    for t in range(triangles.shape[0]):
        a, b, c = triangles[t, 0], triangles[t, 1], triangles[t, 2]
        u0, u1, u2 = x[b, 0] - x[a, 0], x[b, 1] - x[a, 1], x[b, 2] - x[a, 2]
        v0, v1, v2 = x[c, 0] - x[a, 0], x[c, 1] - x[a, 1], x[c, 2] - x[a, 2]
        s0 = u1 * v2 - u2 * v1
        s1 = u2 * v0 - u0 * v2
        s2 = u0 * v1 - u1 * v0
        for j in range(3):
            node = triangles[t, j]
            summed[node, 0] += s0
            summed[node, 1] += s1
            summed[node, 2] += s2
    for node in range(n):
        s0, s1, s2 = summed[node, 0], summed[node, 1], summed[node, 2]
        length = np.sqrt((s0 * s0 + s1 * s1) + s2 * s2)
        divisor = length if length > 0.0 else 1.0
        directions[node, 0] = s0 / divisor
        directions[node, 1] = s1 / divisor
        directions[node, 2] = s2 / divisor


def offset_normals(x: np.ndarray, triangles: np.ndarray, count: int) -> np.ndarray:
    """(count, 3) the unit area-weighted normals at the nodes of the triangles ``triangles``
    (t, 3) int at positions x (count, 3), mm (0 at a node of none), compiled: the same bits as
    ``PlyContactBlock.offset_directions``' numpy."""
    directions = np.empty((count, 3))
    _normals(
        np.ascontiguousarray(x, dtype=float),
        np.ascontiguousarray(triangles, dtype=np.int64),
        directions,
    )
    return directions


@lanes
def _points(x, d, above, upper_offset, shape, cells, corner_offset, p, y):
    """p (P, 3) and y (m, 3, 3) (module docstring); returns whether all are finite."""
    finite = True
    for i in range(above.shape[0]):
        for c in range(3):
            total = 0.0
            for j in range(3):
                node = above[i, j]
                corner = x[node, c] - upper_offset[i, j] * d[node, c]
                total = shape[i, j] * corner if j == 0 else total + shape[i, j] * corner
            p[i, c] = total
            finite = finite and np.isfinite(total)
    for t in range(cells.shape[0]):
        for k in range(3):
            node = cells[t, k]
            for c in range(3):
                value = x[node, c] + corner_offset[t, k] * d[node, c]
                y[t, k, c] = value
                finite = finite and np.isfinite(value)
    return finite


def face_points(
    x: np.ndarray,
    d: np.ndarray,
    above: np.ndarray,
    upper_offset: np.ndarray,
    shape: np.ndarray,
    cells: np.ndarray,
    corner_offset: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, bool]:
    """The contact points p (P, 3) and the lower corners y (m, 3, 3), mm, compiled (module
    docstring), and whether all their coordinates are finite: from the positions x (n, 3),
    mm, the faces' unit directions d (n, 3), the points' upper corners ``above`` (P, 3), their
    offsets a (P, 3), mm, and shape functions N (P, 3), and the lower triangles ``cells``
    (m, 3) and their offsets b (m, 3), mm."""
    p = np.empty((len(above), 3))
    y = np.empty((len(cells), 3, 3))
    finite = _points(
        read_only(x),  # as the block keeps its directions: one build (kernel_inputs.py)
        read_only(d),
        np.ascontiguousarray(above, dtype=np.int64),
        np.ascontiguousarray(upper_offset, dtype=float),
        np.ascontiguousarray(shape, dtype=float),
        np.ascontiguousarray(cells, dtype=np.int64),
        np.ascontiguousarray(corner_offset, dtype=float),
        p,
        y,
    )
    return p, y, bool(finite)


@lanes
def _toward(d, above, upper_offset, shape, toward):
    """toward (P, 3): sum_j (N_j a_j) d_j over each point's upper corners, as numpy's
    ``einsum("pj,pj,pji->pi")`` sums it (the products left to right, the terms from 0.0 in
    j's order)."""
    for i in range(above.shape[0]):
        for c in range(3):
            total = 0.0
            for j in range(3):
                total += (shape[i, j] * upper_offset[i, j]) * d[above[i, j], c]
            toward[i, c] = total


def offset_toward(
    d: np.ndarray, above: np.ndarray, upper_offset: np.ndarray, shape: np.ndarray
) -> np.ndarray:
    """(P, 3) each contact point's direction from the lower ply to its own, sum_j N_j a_j d_j
    (``PlyContactBlock.facing``'s ``toward``), mm, compiled: the same bits as numpy's
    ``einsum("pj,pj,pji->pi", shape, upper_offset, d[above])`` (module docstring), without
    the gather of d (n, 3) at the upper corners ``above`` (P, 3); a (P, 3) mm, N (P, 3)."""
    toward = np.empty((len(above), 3))
    _toward(  # the directions read-only as the block keeps them: one build (kernel_inputs.py)
        read_only(d),
        writable(above, np.int64),
        writable(upper_offset),
        writable(shape),
        toward,
    )
    return toward
