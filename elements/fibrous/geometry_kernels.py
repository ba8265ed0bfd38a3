"""Compiled loops of the fibrous shell's geometry (numba): each cell's unit normal, double
area and corner angles, the nodal normal sums S_k and frames, the fold angle and curvature
scale of each side between two cells, and the bending geometry (fold angles, curvature
coefficients, fold gradient) of every cell: pass 1 of elements/fibrous/kernels.py and the
bending geometry the tangent reads, with geometry.py and bending.py as their numpy reference
(``kernel="numpy"``; the tests hold the two to the bit). The corner angles' and folds'
arctangents are taken a chunk of 32 cells (sides) at a time with
elements/lane_maths.py ``lane_arctan2`` (vectorised), as kernels.py's docstring explains;
a cell of no area raises ZeroDivisionError (docs/theory.md §1.4, §2.7, §4.1-4.2)."""

from __future__ import annotations

import numpy as np

from elements.fibrous import level_lanes as lane
from elements.fibrous.cell_terms import (
    cell_cross,
    corner_thickness,
    fold_gradient,
    side_coefficients,
    side_squares,
    side_terms,
    side_vector,
    unit_edge_squares,
    wall_fold,
)
from elements.lane_maths import lane_arctan2
from femcore.jit import jit, jit_lanes, prange
from femcore.workspace import Fresh

__all__ = ["bending_geometry", "loop_array", "normal_sums"]


def loop_array(array) -> np.ndarray:
    """``array`` as the loops take every array of floats they read: C-contiguous float64 and
    writable. numba types a read-only array apart from a writable one and builds a loop once
    for each type it meets; the mesh's points, which the build passes, are read-only, and
    are copied here (once per build), so that each loop has one signature."""
    return np.require(array, dtype=np.float64, requirements=("C", "W"))


# ---------------------------------------------------------------------- pass 1: normals
@jit_lanes
def _normals_pass(connectivity, positions, with_angles, normal, double_area, angles):
    """Unit normal (m, 3), double area (m,) and, ``with_angles``, the corner angles alpha_k
    (m, 3) of every cell, their arctangents across chunks of cells (elements/lane_maths.py
    ``lane_arctan2``, vectorised); a cell of no area raises ZeroDivisionError."""
    chunks = (connectivity.shape[0] + lane.CHUNK - 1) // lane.CHUNK
    for chunk in prange(chunks):
        start = chunk * lane.CHUNK
        count = min(lane.CHUNK, connectivity.shape[0] - start)
        rows = np.empty(3 * lane.CHUNK)  # |c|, then the angles' cosines times |c| and angles
        for i in range(count):
            c = start + i
            ax, ay, az, bx, by, bz, cx, cy, cz = cell_cross(
                positions, connectivity[c, 0], connectivity[c, 1], connectivity[c, 2]
            )
            size = np.sqrt(cx * cx + cy * cy + cz * cz)
            if size == 0.0:
                raise ZeroDivisionError("a fibrous cell has no area")
            normal[c, 0], normal[c, 1], normal[c, 2] = cx / size, cy / size, cz / size
            double_area[c] = size
            # |u x w| = |c| at every corner, and the three angles sum to pi; at corner 1
            # u = x2 - x1 = b - a and w = x0 - x1 = -a
            rows[i] = size
            rows[lane.CHUNK + i] = ax * bx + ay * by + az * bz
            rows[2 * lane.CHUNK + i] = (ax - bx) * ax + (ay - by) * ay + (az - bz) * az
        if with_angles:
            for i in range(count):
                size = rows[i]
                rows[lane.CHUNK + i] = lane_arctan2(size, rows[lane.CHUNK + i])
                rows[2 * lane.CHUNK + i] = lane_arctan2(size, rows[2 * lane.CHUNK + i])
            for i in range(count):
                c = start + i
                alpha0, alpha1 = rows[lane.CHUNK + i], rows[2 * lane.CHUNK + i]
                angles[c, 0], angles[c, 1], angles[c, 2] = alpha0, alpha1, np.pi - alpha0 - alpha1


@jit
def _normal_sums(offsets, corners, angles, normal, out):
    """out[node] (n, 3) = sum of alpha_k n over the node's corners c * 3 + k, in cell order."""
    for node in prange(out.shape[0]):
        sx = sy = sz = 0.0
        for j in range(offsets[node], offsets[node + 1]):
            corner = corners[j]
            c = corner // 3
            angle = angles[c, corner - 3 * c]
            sx += angle * normal[c, 0]
            sy += angle * normal[c, 1]
            sz += angle * normal[c, 2]
        out[node, 0], out[node, 1], out[node, 2] = sx, sy, sz


def _cell_normals(block, positions: np.ndarray, with_angles: bool, work=Fresh):
    """Pass 1 over the cells: (normal (m, 3), double_area (m,), angles (m, 3) or empty)."""
    m = len(block.connectivity)
    normal, double_area = work.empty("normal", (m, 3)), work.empty("double_area", (m,))
    angles = work.empty("angles", (m, 3) if with_angles else (0, 3))
    _normals_pass(block.connectivity, positions, with_angles, normal, double_area, angles)
    return normal, double_area, angles


@jit_lanes
def _side_folds(
    sides, sign, connectivity, across_cell, across_side, positions, normal, double_area, fold,
    scale,
):  # fmt: skip
    """The fold angle and the curvature scale (cell_terms.py ``side_angle``) of each side that
    couples two cells, once per side (supports.py ``shared_sides``: ``sides`` (e, 2) its cell
    c and side s there, ``sign`` (e,)), written for both its cells at (cell, side) in
    ``fold`` and ``scale`` (m, 3): the angle as c sees it (the side from its corner s + 1 to
    its corner s + 2), times ``sign`` for the cell across (``across_cell``, ``across_side``
    (m, 3); not written where ``sign`` is 0). Every slot is the one side's: no two
    iterations write the same place. The arctangents across chunks of sides
    (elements/lane_maths.py ``lane_arctan2``, vectorised)."""
    chunks = (sides.shape[0] + lane.CHUNK - 1) // lane.CHUNK
    for chunk in prange(chunks):
        start = chunk * lane.CHUNK
        count = min(lane.CHUNK, sides.shape[0] - start)
        rows = np.empty(2 * lane.CHUNK)  # atan2's y, then the angles; its x
        for i in range(count):
            e = start + i
            c, s = sides[e, 0], sides[e, 1]
            other, other_side = across_cell[c, s], across_side[c, s]
            p, q = connectivity[c, (s + 1) % 3], connectivity[c, (s + 2) % 3]
            y, x, k = side_terms(
                positions[q, 0] - positions[p, 0], positions[q, 1] - positions[p, 1],
                positions[q, 2] - positions[p, 2], normal[c, 0], normal[c, 1], normal[c, 2],
                normal[other, 0], normal[other, 1], normal[other, 2], double_area[c],
                double_area[other],
            )  # fmt: skip
            rows[i], rows[lane.CHUNK + i] = y, x
            scale[c, s] = k
            if sign[e] != 0:
                scale[other, other_side] = k
        for i in range(count):
            rows[i] = lane_arctan2(rows[i], rows[lane.CHUNK + i])
        for i in range(count):
            e = start + i
            c, s = sides[e, 0], sides[e, 1]
            fold[c, s] = rows[i]
            if sign[e] != 0:
                fold[across_cell[c, s], across_side[c, s]] = sign[e] * rows[i]


def _shared_folds(block, positions, normal, double_area, work=Fresh):
    """``_side_folds`` of the block: (fold, scale) (m, 3), set on the sides that couple two
    cells (``interior_side``) and unset elsewhere."""
    m = len(block.connectivity)
    fold, scale = work.empty("fold", (m, 3)), work.empty("scale", (m, 3))
    _side_folds(
        block.shared_sides, block.shared_sign, block.connectivity, block.across_cell,
        block.across_side, positions, normal, double_area, fold, scale,
    )  # fmt: skip
    return fold, scale


@jit
def _node_frames(sums, directors, in_block, thickness, guard, frame):
    """cell_terms.py ``corner_thickness`` at every node of the block with its nodal normal
    S / |S| (``sums`` (n, 3), the wall nodes' replaced): frame (n, 10) the director V,
    V . N, h_m, N, 1 / |S| and 1 / max(V . N, guard), once per node instead of once per
    corner; zeros at nodes outside the block (no normal there)."""
    for node in prange(sums.shape[0]):
        if not in_block[node]:
            for j in range(10):
                frame[node, j] = 0.0
            continue
        # ``nodal`` given as in_block[node] (True here), not the constant True: numba types a
        # constant argument as a literal and would build the helper once per constant
        vx, vy, vz, cos, h_m, nx, ny, nz, inverse, over = corner_thickness(
            directors, sums, node, in_block[node], 0.0, 0.0, 0.0, thickness, guard
        )
        frame[node, 0], frame[node, 1], frame[node, 2] = vx, vy, vz
        frame[node, 3], frame[node, 4] = cos, h_m
        frame[node, 5], frame[node, 6], frame[node, 7] = nx, ny, nz
        frame[node, 8], frame[node, 9] = inverse, over


def normal_sums(block, positions: np.ndarray) -> np.ndarray:
    """S_k (n, 3), the sums of alpha_k n over the block's cells around each node (0 at nodes
    outside the block; the wall nodes not replaced), by the compiled loops: the same numbers
    to the last bit as the scatter of geometry.py ``corner_normals``."""
    x = loop_array(positions)
    normal, _, angles = _cell_normals(block, x, True)
    sums = np.empty((block.n_nodes, 3))
    corners = block.node_corners
    _normal_sums(corners.offsets, corners.corners, angles, normal, sums)
    return sums


# ---------------------------------------------------------------------- bending geometry
@jit
def _bending_sides(
    connectivity, positions, normal, double_area, side_fold, side_scale, interior, clamped,
    wall, mirror, fold, coefficients, gradient,
):  # fmt: skip
    """bending.py ``geometry`` of every cell: fold angles (m, 3), curvature coefficients
    (m, 2, 3) and the gradient D[s, k] (m, 3, 3), the folds of the sides between two cells
    from ``side_fold`` and ``side_scale`` (m, 3) of ``_side_folds``, as the force takes them."""
    for c in prange(connectivity.shape[0]):
        n0, n1, n2 = connectivity[c, 0], connectivity[c, 1], connectivity[c, 2]
        x0x, x0y, x0z = positions[n0, 0], positions[n0, 1], positions[n0, 2]
        x1x, x1y, x1z = positions[n1, 0], positions[n1, 1], positions[n1, 2]
        x2x, x2y, x2z = positions[n2, 0], positions[n2, 1], positions[n2, 2]
        nx, ny, nz, size = normal[c, 0], normal[c, 1], normal[c, 2], double_area[c]
        t0x, t0y, t0z = x2x - x1x, x2y - x1y, x2z - x1z
        t1x, t1y, t1z = x0x - x2x, x0y - x2y, x0z - x2z
        t2x, t2y, t2z = x1x - x0x, x1y - x0y, x1z - x0z
        d00, d11, d22, i00, i11, i22 = side_squares(t0x, t0y, t0z, t1x, t1y, t1z, t2x, t2y, t2z)
        d = fold_gradient(
            t0x, t0y, t0z, t1x, t1y, t1z, t2x, t2y, t2z, d00, d11, d22, i00, i11, i22,
            1.0 / size,
        )  # fmt: skip
        gradient[c, 0, 0], gradient[c, 0, 1], gradient[c, 0, 2] = d[0], d[1], d[2]
        gradient[c, 1, 0], gradient[c, 1, 1], gradient[c, 1, 2] = d[3], d[4], d[5]
        gradient[c, 2, 0], gradient[c, 2, 1], gradient[c, 2, 2] = d[6], d[7], d[8]
        e1x, e1y, e1z, e2x, e2y, e2z, over1, over2 = unit_edge_squares(
            x0x, x0y, x0z, x1x, x1y, x1z, x2x, x2y, x2z
        )
        for s in range(3):
            if interior[c, s]:
                sx, sy, sz = side_vector(s, x0x, x0y, x0z, x1x, x1y, x1z, x2x, x2y, x2z)
                fold[c, s] = side_fold[c, s]
                coefficients[c, 0, s], coefficients[c, 1, s] = side_coefficients(
                    sx, sy, sz, nx, ny, nz, e1x, e1y, e1z, e2x, e2y, e2z, over1, over2,
                    side_scale[c, s],
                )  # fmt: skip
            elif clamped[c, s]:
                fold[c, s], coefficients[c, 0, s], coefficients[c, 1, s] = wall_fold(
                    c, s, x0x, x0y, x0z, x1x, x1y, x1z, x2x, x2y, x2z, nx, ny, nz, size,
                    e1x, e1y, e1z, e2x, e2y, e2z, over1, over2, wall, mirror,
                )  # fmt: skip
            else:
                fold[c, s], coefficients[c, 0, s], coefficients[c, 1, s] = 0.0, 0.0, 0.0


def bending_geometry(block, positions: np.ndarray) -> dict:
    """bending.py ``geometry`` by the compiled loops."""
    x = loop_array(positions)
    normal, double_area, _ = _cell_normals(block, x, False)
    side_fold, side_scale = _shared_folds(block, x, normal, double_area)
    m = len(normal)
    fold, coefficients, gradient = np.empty((m, 3)), np.empty((m, 2, 3)), np.empty((m, 3, 3))
    _bending_sides(
        block.connectivity, x, normal, double_area, side_fold, side_scale, block.interior_side,
        block.clamped_side, block.reference_normal, block.mirror_normal, fold, coefficients,
        gradient,
    )  # fmt: skip
    return {"fold": fold, "coefficients": coefficients, "gradient": gradient, "normal": normal}
