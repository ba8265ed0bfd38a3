"""The fibre frame of each cell (fibres.py ``fibre_ordering`` and ``shear_orientation``, Bai
Eq. 9) by one compiled loop over the cells each, for the build of large blocks: the numpy
functions of fibres.py are their reference (``kernel="numpy"``), and the two give the same
connectivity, warp flags and signs (tests/test_fibrous_frame.py).

At 400k triangles the numpy ordering forms some thirty (m, 3) temporaries and reduces each
over its short last axis; a loop holds a cell's vectors in scalars. The arithmetic follows the
numpy functions' operations one by one (no fused multiply-add), so that a corner's tests are
decided by the same numbers, the warp's projection aside (a matrix-vector product there, whose
order of sums the BLAS chooses): a cell whose edge lies within a rounding error of the angle
tolerance is the only one the two could order differently.
"""

from __future__ import annotations

import math

import numpy as np

from elements.fibrous.cell_terms import cell_cross
from elements.fibrous.geometry_kernels import loop_array
from femcore.jit import serial

__all__ = ["fibre_corners", "shear_signs"]

# Status of a cell in ``fibre_corners``: no corner matches, or the cell is normal to the warp.
NO_CORNER = -1
NORMAL_TO_WARP = -2


@serial
def _corners(points, triangles, warp, cos_tol, corner, xi_is_warp):  # pragma: no cover - numba
    w0, w1, w2 = warp[0], warp[1], warp[2]
    for t in range(triangles.shape[0]):
        _, _, _, _, _, _, n0, n1, n2 = cell_cross(
            points, triangles[t, 0], triangles[t, 1], triangles[t, 2]
        )
        size = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
        n0, n1, n2 = n0 / size, n1 / size, n2 / size
        along_n = n0 * w0 + n1 * w1 + n2 * w2
        p0, p1, p2 = w0 - along_n * n0, w1 - along_n * n1, w2 - along_n * n2
        size = math.sqrt(p0 * p0 + p1 * p1 + p2 * p2)
        if size < 1e-6:
            corner[t] = NORMAL_TO_WARP
            continue
        p0, p1, p2 = p0 / size, p1 / size, p2 / size
        # the weft n x warp_t
        q0 = n1 * p2 - n2 * p1
        q1 = n2 * p0 - n0 * p2
        q2 = n0 * p1 - n1 * p0
        corner[t] = NO_CORNER
        for c in range(3):  # the first matching corner, as the numpy loop's last overwrite
            here = triangles[t, c]
            after = triangles[t, (c + 1) % 3]
            before = triangles[t, (c + 2) % 3]
            # the edges from this corner: cell_cross's a and b with the corner first
            u0, u1, u2, v0, v1, v2, _, _, _ = cell_cross(points, here, after, before)
            length = math.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
            u0, u1, u2 = u0 / length, u1 / length, u2 / length
            length = math.sqrt(v0 * v0 + v1 * v1 + v2 * v2)
            v0, v1, v2 = v0 / length, v1 / length, v2 / length
            u_warp = abs(u0 * p0 + u1 * p1 + u2 * p2) >= cos_tol
            u_weft = abs(u0 * q0 + u1 * q1 + u2 * q2) >= cos_tol
            v_warp = abs(v0 * p0 + v1 * p1 + v2 * p2) >= cos_tol
            v_weft = abs(v0 * q0 + v1 * q1 + v2 * q2) >= cos_tol
            warp_first = u_warp and v_weft
            if warp_first or (u_weft and v_warp):
                corner[t] = c
                xi_is_warp[t] = warp_first
                break


@serial
def _signs(points, connectivity, xi_is_warp, warp, sign):  # pragma: no cover - numba
    w0, w1, w2 = warp[0], warp[1], warp[2]
    for t in range(connectivity.shape[0]):
        a0, a1, a2, b0, b1, b2, n0, n1, n2 = cell_cross(
            points, connectivity[t, 0], connectivity[t, 1], connectivity[t, 2]
        )
        q0 = n1 * w2 - n2 * w1  # n x warp, unnormalised
        q1 = n2 * w0 - n0 * w2
        q2 = n0 * w1 - n1 * w0
        if xi_is_warp[t]:
            along_warp = a0 * w0 + a1 * w1 + a2 * w2
            along_weft = b0 * q0 + b1 * q1 + b2 * q2
        else:
            along_warp = b0 * w0 + b1 * w1 + b2 * w2
            along_weft = a0 * q0 + a1 * q1 + a2 * q2
        sign[t] = np.sign(along_warp) * np.sign(along_weft)


def fibre_corners(
    points: np.ndarray, triangles: np.ndarray, warp: np.ndarray, tolerance_deg: float
) -> tuple[np.ndarray, np.ndarray]:
    """For each triangle (m, 3) of ``points`` (n, 3, mm) the first local corner (0, 1, 2)
    with one edge along the warp (3,) (projected on the triangle's plane, unit) and the other
    along the weft within ``tolerance_deg``, and whether its next edge is the warp: (corner
    (m,) int64, ``NO_CORNER`` or ``NORMAL_TO_WARP`` where there is none; xi_is_warp (m,)
    bool)."""
    m = len(triangles)
    corner = np.empty(m, dtype=np.int64)
    xi_is_warp = np.zeros(m, dtype=bool)
    _corners(
        loop_array(points),
        np.ascontiguousarray(triangles, dtype=np.int64),
        loop_array(warp),
        float(np.cos(np.radians(tolerance_deg))),
        corner,
        xi_is_warp,
    )
    return corner, xi_is_warp


def shear_signs(
    points: np.ndarray, connectivity: np.ndarray, xi_is_warp: np.ndarray, warp: np.ndarray
) -> np.ndarray:
    """fibres.py ``shear_orientation`` by one loop: +1 or -1 per cell (m,) (0 for an edge
    normal to its family's direction)."""
    sign = np.empty(len(connectivity))
    _signs(
        loop_array(points),
        np.ascontiguousarray(connectivity, dtype=np.int64),
        np.ascontiguousarray(xi_is_warp, dtype=bool),
        loop_array(warp),
        sign,
    )
    return sign
