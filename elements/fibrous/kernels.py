"""Compiled loops of the fibrous shell (numba), with the numpy functions of the package
(geometry.py, membrane.py, bending.py) as their vectorised reference (``kernel="numpy"``); the
tests hold the two to 1e-12.

``internal_force``, ``strain_energy_parts`` and ``internal_force_and_energy`` evaluate the
whole element, laws included (``law_value`` and ``law_energy`` of packed_laws.py on the tables
of ``pack_laws``), in three parallel passes over the cells and three over the nodes, because
two quantities couple a cell to its neighbours (docs/theory.md §1.4, §2.5, §4):

1. cells: each cell's unit normal, double area and corner angles; nodes: the nodal normal sums
   S_k, the sums of alpha_k n over the node's cells; sides: the fold angle of each side
   between two cells and the scale of its curvature coefficients, once per side for both
   cells (the angle is the same seen from either, cell_terms.py ``side_angle``: an arctan2
   and a square root per side instead of per side and cell); these geometry loops, and the
   bending geometry the tangent reads, are in geometry_kernels.py;
2. cells: each cell's tension and shear over its fibre levels (forces, director moments,
   dW/dS_k and, when asked, energies), then its curvatures from its sides' folds (a clamped
   side's against the wall), bending energy and its share of each side's moment;
   nodes: T_k, the sums of dW/dS_k over the cells around each node;
3. cells: the pulls of T_k and of the side moments on each cell's nodes; nodes: the nodal
   forces and director moments.

The cells (and the sides) are taken in chunks of 32 (level_lanes.py ``CHUNK``) where a loop
across them can run 8 cells at a time (AVX-512; 4 with AVX2): the fibre levels of pass 2
(level_lanes.py: the chunk's inputs gathered into the rows of one scratch array, each level's
strains, laws and loads as loops across the chunk, then the director moments and corner
forces from the levels' sums as one more such loop) and the arctangents of the corner angles
and the folds; their log, arcsine and arctangent are branch-free arithmetic
(elements/lane_maths.py, within 2 units in the last place of the library's), with which
LLVM vectorises those loops (the library's functions are called one value a call), and
``_cells_pass`` is built with numba's numpy error model (femcore/jit.py ``jit_lanes``: no
zero test before each division, which would keep a loop scalar; a fibre of no length in
its plane still raises ZeroDivisionError, a cell of no area in pass 1 too).

Outside the chunks' loops a cell pass reads the positions and directors at its nodes itself and
keeps every vector in scalars (x, y, z), with the corner and side loops written out: one
scratch array a chunk, none per cell, no modulo indexing, no array passed to a helper with
branches inside the hot loop (numba increfs and decrefs each array argument, atomic
operations that LLVM keeps where the helper branches: the corners' frames read by such a
helper were 40 % of the cells' pass, perf). Between two passes only what the next one reads
is kept (about 300 bytes per cell: normals, areas, angles, the corner forces, moments and
dW/dS_k, the side moments); the fold-angle gradient D[s, k] = t_s . t_k / (|t_s| 2A) (t_s
the side opposite corner s, the in-plane form of -grad N_k . n^c_s) is recomputed where it
is used. The scalar pieces (corner thickness, director moment, side terms, fold gradient,
angle pull) are in cell_terms.py, where quotients that share a denominator share one
reciprocal.

Every sum from cells to nodes is a loop over nodes that adds the corners of the node's cells
in cell order (elements/kernels.py ``NodeCorners``): parallel without races, the same sums in
the same order as ``numpy.bincount``, and the same numbers to the last bit on any number of
threads. The per-cell pieces of the bending geometry also serve ``bending_geometry``, the
compiled form of bending.py ``geometry`` (tangent, fields), and the strains of the fields
(``strains``) come from a pass that reads the nodes' frames of pass 1 and forms each level by
pass 2's own inlined helper (cell_terms.py ``level_strains``): the strains the force took.
"""

from __future__ import annotations

import numpy as np

from elements.fibrous import level_lanes as lane
from elements.fibrous.cell_terms import (
    angle_pull,
    cell_cross,
    cell_levers,
    corner_levers,
    element_corner,
    fold_gradient,
    level_strains,
    side_coefficients,
    side_squares,
    side_vector,
    unit_edge_squares,
    wall_fold,
)
from elements.fibrous.geometry_kernels import (
    _cell_normals,
    _node_frames,
    _normal_sums,
    _normals_pass,
    _shared_folds,
    loop_array,
)
from elements.fibrous.packed_laws import law_energy, law_value
from elements.shell_geometry import GUARD
from femcore.jit import jit, jit_lanes, prange
from femcore.workspace import Fresh, workspace_of

__all__ = [
    "cell_membrane_loads",
    "internal_force",
    "internal_force_and_energy",
    "normal_pulls",
    "strains",
    "strain_energy_parts",
]


# ---------------------------------------------------------------------- pass 2: the cells
@jit_lanes
def _cells_pass(
    connectivity, positions, directors, frame, normal, double_area, nodal, thickness, guard,
    zeta, weights, area, reference_length1, reference_length2, shear_sign, reference_shear,
    xi_is_warp, law_integers, law_reals, variation, side_fold, side_scale, interior, clamped,
    wall, mirror, reference_fold, reference_coefficients, use_reference_coefficients, with_forces,
    with_energy, force, moment, d_sums, own, energy,
):  # fmt: skip
    """Each cell's tension and shear (geometry.py ``cell_geometry``, membrane.py ``strains``,
    ``layer_loads``, ``layer_forces``; Eq. 8-10, 14, 24-33) and bending (bending.py
    ``geometry``, ``curvatures``, ``side_moments``; Eq. 34-37).

    Membrane: h_m = h / max(V . N, guard) at the corners (N = S_k / |S_k| from the nodes'
    ``frame`` (n, 10) of ``_node_frames`` when ``nodal``, else the element's normal), then
    at each fibre level the vectors g1, g2, the log strains and the shear angle, and the
    laws (packed laws 0, 1, 2: warp tension, weft tension, shear). Bending: the fold angle of
    each side against the neighbour's normal (``side_fold`` and ``side_scale`` (m, 3) of
    ``_side_folds``, once per side) or the wall of the reference plane on a clamped side
    (``wall`` (m, 3); on a symmetry plane's side the wall through the side perpendicular to
    the plane of normal ``mirror`` (m, 3, 3), cell_terms.py ``wall_fold``), the curvatures
    chi_a = -sum_s c_as (theta_s - theta_s0) and the bending laws (packed laws 3, 4: warp,
    weft).

    ``with_forces``: force, moment, d_sums (m, 3, 3) the corner forces, director moments and
    dW/dS_k (zero without nodal normals), own (m, 3) the cell's share of each side's moment,
    -A0 sum_a M_a c_as; ``with_energy``: energy (m, 3) tension, shear, bending, N mm.
    """
    levels = zeta.shape[0]
    chunks = (connectivity.shape[0] + lane.CHUNK - 1) // lane.CHUNK
    for chunk in prange(chunks):
        start = chunk * lane.CHUNK
        count = min(lane.CHUNK, connectivity.shape[0] - start)
        rows = np.empty(lane.ROWS * lane.CHUNK)  # a row a quantity, a column a cell
        for i in range(count):  # the cells' inputs to their levels, gathered
            c = start + i
            n0, n1, n2 = connectivity[c, 0], connectivity[c, 1], connectivity[c, 2]
            nx, ny, nz = normal[c, 0], normal[c, 1], normal[c, 2]
            # g_a = r_a + zeta_f l_a, V and h_m at the corners (Eq. 10, 14; cell_terms.py
            # ``cell_levers``), the corners' frames (``corner_frame``'s) kept for the moments
            for k in range(3):
                frame_row, node = lane.FRAME0 + 10 * lane.CHUNK * k, connectivity[c, k]
                if nodal:  # the frame's ten columns in the order of the rows VX ... OVER
                    for j in range(10):
                        rows[frame_row + j * lane.CHUNK + i] = frame[node, j]
                    continue
                (
                    rows[frame_row + lane.VX + i], rows[frame_row + lane.VY + i],
                    rows[frame_row + lane.VZ + i], rows[frame_row + lane.COSINE + i],
                    rows[frame_row + lane.HM + i], rows[frame_row + lane.WX + i],
                    rows[frame_row + lane.WY + i], rows[frame_row + lane.WZ + i],
                    rows[frame_row + lane.LENGTH + i], rows[frame_row + lane.OVER + i],
                ) = element_corner(
                    directors[node, 0], directors[node, 1], directors[node, 2], nx, ny, nz,
                    thickness, guard,
                )  # fmt: skip
            r1x, r1y, r1z, r2x, r2y, r2z, _, _, _ = cell_cross(positions, n0, n1, n2)
            l1x, l1y, l1z, l2x, l2y, l2z = corner_levers(
                rows[lane.FRAME0 + lane.HM + i], rows[lane.FRAME0 + lane.VX + i],
                rows[lane.FRAME0 + lane.VY + i], rows[lane.FRAME0 + lane.VZ + i],
                rows[lane.FRAME1 + lane.HM + i], rows[lane.FRAME1 + lane.VX + i],
                rows[lane.FRAME1 + lane.VY + i], rows[lane.FRAME1 + lane.VZ + i],
                rows[lane.FRAME2 + lane.HM + i], rows[lane.FRAME2 + lane.VX + i],
                rows[lane.FRAME2 + lane.VY + i], rows[lane.FRAME2 + lane.VZ + i],
            )  # fmt: skip
            rows[lane.DOUBLE_AREA + i] = double_area[c]
            rows[lane.R1X + i], rows[lane.R1Y + i], rows[lane.R1Z + i] = r1x, r1y, r1z
            rows[lane.R2X + i], rows[lane.R2Y + i], rows[lane.R2Z + i] = r2x, r2y, r2z
            rows[lane.L1X + i], rows[lane.L1Y + i], rows[lane.L1Z + i] = l1x, l1y, l1z
            rows[lane.L2X + i], rows[lane.L2Y + i], rows[lane.L2Z + i] = l2x, l2y, l2z
            rows[lane.NX + i], rows[lane.NY + i], rows[lane.NZ + i] = nx, ny, nz
            rows[lane.AREA + i], rows[lane.SIGN + i] = area[c], shear_sign[c]
            rows[lane.WARP_FIRST + i] = 1.0 if xi_is_warp[c] else 0.0
            for row in range(lane.S1X, lane.REFERENCE1, lane.CHUNK):  # the sums over levels
                rows[row + i] = 0.0
        zero = 0
        for f in range(levels):  # each level across the chunk's cells (level_lanes.py)
            zero += lane.level_lanes(
                rows, count, start, f, zeta[f], nodal, reference_length1, reference_length2,
                reference_shear,
            )  # fmt: skip
            lane.law_lanes(
                rows, count, weights[f], law_integers, law_reals, with_forces, with_energy
            )
            if with_forces:
                lane.load_lanes(rows, count, zeta[f], weights[f])
        if zero > 0:
            raise ZeroDivisionError("a fibre of a fibrous cell has no length in its plane")
        if with_forces:  # the director moments and corner forces across the chunk's cells
            lane.moment_lanes(rows, count, nodal, guard, variation)
        for i in range(count):
            c = start + i
            n0, n1, n2 = connectivity[c, 0], connectivity[c, 1], connectivity[c, 2]
            x0x, x0y, x0z = positions[n0, 0], positions[n0, 1], positions[n0, 2]
            x1x, x1y, x1z = positions[n1, 0], positions[n1, 1], positions[n1, 2]
            x2x, x2y, x2z = positions[n2, 0], positions[n2, 1], positions[n2, 2]
            nx, ny, nz, size = normal[c, 0], normal[c, 1], normal[c, 2], double_area[c]
            a0 = area[c]
            warp_first = xi_is_warp[c]
            if with_energy:
                energy[c, 0] = rows[lane.TENSION_ENERGY + i]
                energy[c, 1] = rows[lane.SHEAR_ENERGY + i]
            if with_forces:  # moment_lanes' rows, cell by cell
                for k in range(3):
                    for j in range(3):
                        moment[c, k, j] = rows[lane.MOMENT + (3 * k + j) * lane.CHUNK + i]
                if nodal:
                    for k in range(3):
                        for j in range(3):
                            d_sums[c, k, j] = rows[lane.D_SUM + (3 * k + j) * lane.CHUNK + i]
                f1x, f1y, f1z = rows[lane.F1X + i], rows[lane.F1Y + i], rows[lane.F1Z + i]
                f2x, f2y, f2z = rows[lane.F2X + i], rows[lane.F2Y + i], rows[lane.F2Z + i]
                force[c, 0, 0], force[c, 0, 1], force[c, 0, 2] = (
                    -(f1x + f2x),
                    -(f1y + f2y),
                    -(f1z + f2z),
                )
                force[c, 1, 0], force[c, 1, 1], force[c, 1, 2] = f1x, f1y, f1z
                force[c, 2, 0], force[c, 2, 1], force[c, 2, 2] = f2x, f2y, f2z

            # ------------------------------------------------------------ bending
            if not (interior[c, 0] or interior[c, 1] or interior[c, 2]) and not (
                clamped[c, 0] or clamped[c, 1] or clamped[c, 2]
            ):  # no side folds (a lone or a held cell)
                if with_energy:
                    energy[c, 2] = 0.0
                if with_forces:
                    own[c, 0] = own[c, 1] = own[c, 2] = 0.0
                continue
            e1x, e1y, e1z, e2x, e2y, e2z, over1, over2 = unit_edge_squares(
                x0x, x0y, x0z, x1x, x1y, x1z, x2x, x2y, x2z
            )
            c10 = c11 = c12 = c20 = c21 = c22 = 0.0  # c_as of the sides that fold
            chi1 = chi2 = 0.0
            for s in range(3):
                # side s runs from corner s + 1 to corner s + 2
                if interior[c, s]:  # its fold from the side's own pass
                    fold = side_fold[c, s]
                    sx, sy, sz = side_vector(s, x0x, x0y, x0z, x1x, x1y, x1z, x2x, x2y, x2z)
                    c1s, c2s = side_coefficients(
                        sx, sy, sz, nx, ny, nz, e1x, e1y, e1z, e2x, e2y, e2z, over1, over2,
                        side_scale[c, s],
                    )  # fmt: skip
                elif clamped[c, s]:
                    fold, c1s, c2s = wall_fold(
                        c, s, x0x, x0y, x0z, x1x, x1y, x1z, x2x, x2y, x2z, nx, ny, nz, size,
                        e1x, e1y, e1z, e2x, e2y, e2z, over1, over2, wall, mirror,
                    )  # fmt: skip
                else:
                    continue
                if use_reference_coefficients:
                    c1s, c2s = reference_coefficients[c, 0, s], reference_coefficients[c, 1, s]
                if s == 0:
                    c10, c20 = c1s, c2s
                elif s == 1:
                    c11, c21 = c1s, c2s
                else:
                    c12, c22 = c1s, c2s
                turn = fold - reference_fold[c, s]
                chi1 -= c1s * turn
                chi2 -= c2s * turn
            bend1, bend2 = (3, 4) if warp_first else (4, 3)
            if with_energy:
                energy[c, 2] = a0 * (
                    law_energy(law_integers, law_reals, bend1, chi1)
                    + law_energy(law_integers, law_reals, bend2, chi2)
                )
            if with_forces:
                moment1 = law_value(law_integers, law_reals, bend1, chi1)
                moment2 = law_value(law_integers, law_reals, bend2, chi2)
                own[c, 0] = -a0 * (moment1 * c10 + moment2 * c20)
                own[c, 1] = -a0 * (moment1 * c11 + moment2 * c21)
                own[c, 2] = -a0 * (moment1 * c12 + moment2 * c22)


# ---------------------------------------------------------------------- pass 3: the pulls
@jit
def _pulls_pass(
    connectivity, positions, normal, double_area, angles, pull, nodal, own, across_cell,
    across_side, interior, force,
):  # fmt: skip
    """force[c] += the pull of T_k (n, 3), the nodal sums of dW/dS_k, through alpha_k n at the
    cell's corners (nodal normals only; geometry.py ``corner_normal_pull``) and each side's
    moment (own plus the neighbour's across it) times D[s, k] n (Eq. 37): every cell pulls on
    its own three nodes only."""
    for c in prange(connectivity.shape[0]):
        n0, n1, n2 = connectivity[c, 0], connectivity[c, 1], connectivity[c, 2]
        x0x, x0y, x0z = positions[n0, 0], positions[n0, 1], positions[n0, 2]
        x1x, x1y, x1z = positions[n1, 0], positions[n1, 1], positions[n1, 2]
        x2x, x2y, x2z = positions[n2, 0], positions[n2, 1], positions[n2, 2]
        nx, ny, nz, size = normal[c, 0], normal[c, 1], normal[c, 2], double_area[c]
        # the sides opposite each corner: t0 = x2 - x1, t1 = x0 - x2, t2 = x1 - x0
        t0x, t0y, t0z = x2x - x1x, x2y - x1y, x2z - x1z
        t1x, t1y, t1z = x0x - x2x, x0y - x2y, x0z - x2z
        t2x, t2y, t2z = x1x - x0x, x1y - x0y, x1z - x0z
        d00, d11, d22, i00, i11, i22 = side_squares(t0x, t0y, t0z, t1x, t1y, t1z, t2x, t2y, t2z)
        over_size = 1.0 / size
        # bending: each side's moment times D[s, k] n
        side0, side1, side2 = own[c, 0], own[c, 1], own[c, 2]
        if interior[c, 0]:
            side0 += own[across_cell[c, 0], across_side[c, 0]]
        if interior[c, 1]:
            side1 += own[across_cell[c, 1], across_side[c, 1]]
        if interior[c, 2]:
            side2 += own[across_cell[c, 2], across_side[c, 2]]
        b0 = b1 = b2 = 0.0
        if side0 != 0.0 or side1 != 0.0 or side2 != 0.0:
            g00, g01, g02, g10, g11, g12, g20, g21, g22 = fold_gradient(
                t0x, t0y, t0z, t1x, t1y, t1z, t2x, t2y, t2z, d00, d11, d22, i00, i11, i22,
                over_size,
            )  # fmt: skip
            b0 = side0 * g00 + side1 * g10 + side2 * g20
            b1 = side0 * g01 + side1 * g11 + side2 * g21
            b2 = side0 * g02 + side1 * g12 + side2 * g22
        f0x, f0y, f0z = b0 * nx, b0 * ny, b0 * nz
        f1x, f1y, f1z = b1 * nx, b1 * ny, b1 * nz
        f2x, f2y, f2z = b2 * nx, b2 * ny, b2 * nz
        if nodal:
            # T_k . d(alpha_k n)/dx: through alpha_k (d alpha_k / dx in the plane) and
            # through n (the pull on c = a x b with g = P sum_k alpha_k T_k / |c|)
            p0x, p0y, p0z = pull[n0, 0], pull[n0, 1], pull[n0, 2]
            p1x, p1y, p1z = pull[n1, 0], pull[n1, 1], pull[n1, 2]
            p2x, p2y, p2z = pull[n2, 0], pull[n2, 1], pull[n2, 2]
            # corner 0: u = x1 - x0 = t2, w = x2 - x0 = -t1
            tx, ty, tz, vx, vy, vz = angle_pull(
                nx, ny, nz, t2x, t2y, t2z, -t1x, -t1y, -t1z, i22, i11,
                p0x * nx + p0y * ny + p0z * nz,
            )  # fmt: skip
            f1x, f1y, f1z = f1x + tx, f1y + ty, f1z + tz
            f2x, f2y, f2z = f2x + vx, f2y + vy, f2z + vz
            f0x, f0y, f0z = f0x - (tx + vx), f0y - (ty + vy), f0z - (tz + vz)
            # corner 1: u = x2 - x1 = t0, w = x0 - x1 = -t2
            tx, ty, tz, vx, vy, vz = angle_pull(
                nx, ny, nz, t0x, t0y, t0z, -t2x, -t2y, -t2z, i00, i22,
                p1x * nx + p1y * ny + p1z * nz,
            )  # fmt: skip
            f2x, f2y, f2z = f2x + tx, f2y + ty, f2z + tz
            f0x, f0y, f0z = f0x + vx, f0y + vy, f0z + vz
            f1x, f1y, f1z = f1x - (tx + vx), f1y - (ty + vy), f1z - (tz + vz)
            # corner 2: u = x0 - x2 = t1, w = x1 - x2 = -t0
            tx, ty, tz, vx, vy, vz = angle_pull(
                nx, ny, nz, t1x, t1y, t1z, -t0x, -t0y, -t0z, i11, i00,
                p2x * nx + p2y * ny + p2z * nz,
            )  # fmt: skip
            f0x, f0y, f0z = f0x + tx, f0y + ty, f0z + tz
            f1x, f1y, f1z = f1x + vx, f1y + vy, f1z + vz
            f2x, f2y, f2z = f2x - (tx + vx), f2y - (ty + vy), f2z - (tz + vz)
            alpha0, alpha1, alpha2 = angles[c, 0], angles[c, 1], angles[c, 2]
            gx = alpha0 * p0x + alpha1 * p1x + alpha2 * p2x
            gy = alpha0 * p0y + alpha1 * p1y + alpha2 * p2y
            gz = alpha0 * p0z + alpha1 * p1z + alpha2 * p2z
            along = gx * nx + gy * ny + gz * nz
            gx = (gx - along * nx) * over_size
            gy = (gy - along * ny) * over_size
            gz = (gz - along * nz) * over_size
            # b x g on x1, g x a on x2, minus their sum on x0 (a = x1 - x0 = t2, b = x2 - x0)
            ux, uy, uz = t2y * gz - t2z * gy, t2z * gx - t2x * gz, t2x * gy - t2y * gx  # a x g
            wx, wy, wz = -t1y * gz + t1z * gy, -t1z * gx + t1x * gz, -t1x * gy + t1y * gx  # b x g
            f1x, f1y, f1z = f1x + wx, f1y + wy, f1z + wz
            f2x, f2y, f2z = f2x - ux, f2y - uy, f2z - uz
            f0x, f0y, f0z = f0x - (wx - ux), f0y - (wy - uy), f0z - (wz - uz)
        force[c, 0, 0] += f0x
        force[c, 0, 1] += f0y
        force[c, 0, 2] += f0z
        force[c, 1, 0] += f1x
        force[c, 1, 1] += f1y
        force[c, 1, 2] += f1z
        force[c, 2, 0] += f2x
        force[c, 2, 1] += f2y
        force[c, 2, 2] += f2z


@jit
def _node_loads(offsets, corners, force, moment, out_force, out_moment):
    """out_force[node], out_moment[node] (n, 3): the sums of force and moment (m * 3, 3) over
    the node's corners, in cell order."""
    for node in prange(out_force.shape[0]):
        fx = fy = fz = mx = my = mz = 0.0
        for j in range(offsets[node], offsets[node + 1]):
            corner = corners[j]
            fx += force[corner, 0]
            fy += force[corner, 1]
            fz += force[corner, 2]
            mx += moment[corner, 0]
            my += moment[corner, 1]
            mz += moment[corner, 2]
        out_force[node, 0], out_force[node, 1], out_force[node, 2] = fx, fy, fz
        out_moment[node, 0], out_moment[node, 1], out_moment[node, 2] = mx, my, mz


# ---------------------------------------------------------------------- strains (fields)
@jit
def _strains_pass(
    connectivity, positions, directors, frame, normal, nodal, thickness, guard, zeta,
    reference_length1, reference_length2, shear_sign, reference_shear, eps1, eps2, gamma,
):  # fmt: skip
    """The log fibre strains eps1, eps2 along edges 0-1 and 0-2 and the shear angles (m, L)
    of every cell and level (membrane.py ``strains``) by the arithmetic of ``_cells_pass``:
    its corner terms (``corner_frame`` on the nodes' ``frame`` (n, 10) of ``_node_frames``
    when ``nodal``), edges (``cell_cross``) and levels (``level_strains``), so that the
    fields are the strains the force took, to the last bit."""
    for c in prange(connectivity.shape[0]):
        n0, n1, n2 = connectivity[c, 0], connectivity[c, 1], connectivity[c, 2]
        nx, ny, nz = normal[c, 0], normal[c, 1], normal[c, 2]
        r1x, r1y, r1z, r2x, r2y, r2z, l1x, l1y, l1z, l2x, l2y, l2z = cell_levers(
            frame, directors, positions, n0, n1, n2, nodal, nx, ny, nz, thickness, guard
        )
        sign = shear_sign[c]
        for f in range(zeta.shape[0]):
            level = level_strains(
                zeta[f], r1x, r1y, r1z, r2x, r2y, r2z, l1x, l1y, l1z, l2x, l2y, l2z, nodal,
                nx, ny, nz, reference_length1[c, f], reference_length2[c, f], sign,
                reference_shear[c, f],
            )  # fmt: skip
            eps1[c, f], eps2[c, f], gamma[c, f] = level[20], level[21], level[22]


def _frames(block, x, v, normal, angles, work=Fresh):
    """The nodes' frame table (n, 10) of ``_node_frames`` from the cells' normals and corner
    angles of pass 1 (the nodal normal sums, a wall node's the wall's), as both cell passes
    read it; (0, 10) without nodal normals."""
    if not block.nodal_normals:
        return np.zeros((0, 10))
    corners = block.node_corners
    sums = work.empty("sums", (block.n_nodes, 3))
    _normal_sums(corners.offsets, corners.corners, angles, normal, sums)
    if block.plane_node_ids.size:  # on a symmetry plane, the mirrored whole's (symmetry.py)
        sums[block.plane_node_ids] *= block.plane_keep
    sums[block.wall_node_ids] = block.wall_sums
    frame = work.empty("frame", (block.n_nodes, 10))
    _node_frames(sums, v, block.node_in_block, float(block.fabric.thickness), GUARD, frame)
    return frame


def strains(block, positions: np.ndarray, directors: np.ndarray) -> dict:
    """membrane.py ``strains`` by the compiled loops, for the fields: eps1, eps2 and gamma
    (m, L), without the level vectors and corners (m, L, 3) the numpy path keeps."""
    x = loop_array(positions)
    v = loop_array(directors)
    normal, _, angles = _cell_normals(block, x, block.nodal_normals)
    frame = _frames(block, x, v, normal, angles)
    shape = block.reference_length1.shape
    eps1, eps2, gamma = np.empty(shape), np.empty(shape), np.empty(shape)
    _strains_pass(
        block.connectivity, x, v, frame, normal, block.nodal_normals,
        float(block.fabric.thickness), GUARD, block.zeta, block.reference_length1,
        block.reference_length2, block.shear_sign, block.reference_shear, eps1, eps2, gamma,
    )  # fmt: skip
    return {"eps1": eps1, "eps2": eps2, "gamma": gamma}


# ---------------------------------------------------------------------- the internal force
def _passes(block, positions, directors, with_forces: bool, with_energy: bool):
    """The passes of the module docstring: energies (m, 3) per cell (tension, shear, bending;
    N mm; empty without ``with_energy``) and, ``with_forces``, the nodal forces and director
    moments (n, 3)."""
    conn = block.connectivity
    with workspace_of(block).lease() as work:  # the (m, 3, 3) arrays kept (femcore/workspace.py)
        x, energy, cells = _cell_passes(block, positions, directors, with_forces, with_energy, work)
        if not with_forces:
            return energy, None, None
        normal, double_area, angles, force, moment, pull, own = cells
        _pulls_pass(
            conn, x, normal, double_area, angles, pull, block.nodal_normals, own,
            block.across_cell, block.across_side, block.interior_side, force,
        )  # fmt: skip
        out_force, out_moment = np.empty((block.n_nodes, 3)), np.empty((block.n_nodes, 3))
        _node_loads(
            block.node_corners.offsets, block.node_corners.corners, force.reshape(-1, 3),
            moment.reshape(-1, 3), out_force, out_moment,
        )  # fmt: skip
    return energy, out_force, out_moment


def normal_pulls(block, positions: np.ndarray, directors: np.ndarray) -> np.ndarray:
    """T_k = dW/dS_k (n, 3), N mm, the nodal sums of the cells' tension + shear energy
    derivatives in the normal sums (nodal normals; zero at the wall nodes, whose S_k does
    not vary): the pull of ``_passes`` without the forces' other passes."""
    with workspace_of(block).lease() as work:
        return _cell_passes(block, positions, directors, True, False, work)[2][5].copy()


def _cell_passes(block, positions, directors, with_forces: bool, with_energy: bool, work):
    """Passes 1 and 2 of the module docstring: the positions as given to the loops, the
    energies (m, 3) and, ``with_forces``, (normal, double_area, angles, force, moment, pull,
    own) for pass 3 (else None); every per-cell and per-node array of the passes in ``work``'s
    arrays (a lease of femcore/workspace.py), the energies and the loads returned made afresh."""
    conn, m = block.connectivity, len(block.connectivity)
    nodal, corners = block.nodal_normals, block.node_corners
    x = loop_array(positions)
    v = loop_array(directors)
    normal, double_area, angles = _cell_normals(block, x, nodal, work)
    side_fold, side_scale = _shared_folds(block, x, normal, double_area, work)
    frame = _frames(block, x, v, normal, angles, work)
    shape = (m, 3, 3) if with_forces else (0, 3, 3)
    force, moment = work.empty("force", shape), work.empty("moment", shape)
    d_sums = work.empty("d_sums", shape if nodal else (0, 3, 3))
    own = work.empty("own", (m, 3) if with_forces else (0, 3))
    energy = np.empty((m, 3) if with_energy else (0, 3))
    _cells_pass(
        conn, x, v, frame, normal, double_area, nodal, float(block.fabric.thickness), GUARD,
        block.zeta, block.weights, block.reference_area, block.reference_length1,
        block.reference_length2, block.shear_sign, block.reference_shear, block.xi_is_warp,
        *block.packed_laws, block.thickness_variation, side_fold, side_scale,
        block.interior_side, block.clamped_side, block.reference_normal, block.mirror_normal,
        block.reference_fold,
        block.reference_coefficients, block.reference_curvature_coefficients, with_forces,
        with_energy, force, moment, d_sums, own, energy,
    )  # fmt: skip
    if not with_forces:
        return x, energy, None
    pull = np.zeros((0, 3))
    if nodal:  # T_k, the sums of dW/dS_k; a wall node's S_k does not vary
        pull = corners.sum(d_sums, work.empty("pull", (block.n_nodes, 3)))
        if block.plane_node_ids.size:  # S_k projected on a symmetry plane
            pull[block.plane_node_ids] *= block.plane_keep
        pull[block.wall_node_ids] = 0.0
    del d_sums
    return x, energy, (normal, double_area, angles, force, moment, pull, own)


def cell_membrane_loads(block, x: np.ndarray, v: np.ndarray):
    """tangent.py ``membrane_loads`` by the compiled passes, element normals only: the
    unscattered tension + shear corner forces (N) and director moments (N mm), (p m, 3, 3)
    each, of p stacked copies of the block's m cells (copy after copy, in cell order) from
    their corner positions and directors x, v (p m, 3, 3). Each corner is a node of its own
    and no side couples two cells, so the passes leave out the bending and the pulls, and
    the cell pass's forces are the membrane's (with the variation of h_m through the
    element normal): the central differences of the element-normal tangent
    (base.py ``stacked_local_tangent``) take all their copies in one call."""
    if block.nodal_normals:
        raise ValueError("cell_membrane_loads: element normals only (the nodal sums couple cells)")
    cells = len(x)
    copies, rest = divmod(cells, len(block.connectivity))
    if rest:
        raise ValueError(
            f"cell_membrane_loads: {cells} cells are not copies of the block's "
            f"{len(block.connectivity)}"
        )
    connectivity = np.arange(3 * cells, dtype=block.connectivity.dtype).reshape(cells, 3)
    positions = loop_array(x.reshape(-1, 3))
    directors = loop_array(v.reshape(-1, 3))
    normal, double_area = np.empty((cells, 3)), np.empty(cells)
    _normals_pass(connectivity, positions, False, normal, double_area, np.empty((0, 3)))

    def tiled(array: np.ndarray) -> np.ndarray:
        return np.tile(array, (copies,) + (1,) * (array.ndim - 1))

    force, moment = np.empty((cells, 3, 3)), np.empty((cells, 3, 3))
    unset = np.empty((cells, 3))  # the side folds: read only where a side couples two cells
    # No side shared or clamped, in the layouts of the block's own flags (the force pass's
    # compiled build serves: another layout would compile another)
    alone, unclamped = (
        np.zeros((cells, 3), dtype=flags.dtype, order="C" if flags.flags.c_contiguous else "F")
        for flags in (block.interior_side, block.clamped_side)
    )
    _cells_pass(
        connectivity, positions, directors, np.zeros((0, 10)), normal, double_area, False,
        float(block.fabric.thickness), GUARD, block.zeta, block.weights,
        tiled(block.reference_area), tiled(block.reference_length1),
        tiled(block.reference_length2), tiled(block.shear_sign), tiled(block.reference_shear),
        tiled(block.xi_is_warp), *block.packed_laws, block.thickness_variation, unset, unset,
        alone, unclamped, block.reference_normal, block.mirror_normal, unset,
        block.reference_coefficients, False, True, False, force, moment,
        np.empty((0, 3, 3)), np.empty((cells, 3)), np.empty((0, 3)),
    )  # fmt: skip
    return force, moment


def _energy_parts(energy: np.ndarray) -> dict:
    """{"tension", "shear", "bending"} (N mm) from the per-cell energies (m, 3)."""
    total = energy.sum(axis=0)
    return {"tension": float(total[0]), "shear": float(total[1]), "bending": float(total[2])}


def internal_force(block, positions: np.ndarray, directors: np.ndarray):
    """Nodal internal forces and director moments (n, 3) of a FibrousShellBlock: tension,
    shear and bending (block.py ``internal_force``)."""
    _, force, moment = _passes(block, positions, directors, True, False)
    return force, moment


def internal_force_and_energy(block, positions: np.ndarray, directors: np.ndarray):
    """``internal_force`` and ``strain_energy_parts`` in one pass over the cells: (force
    (n, 3) N, moment (n, 3) N mm, parts dict N mm), the energies the same to the last bit as
    ``strain_energy_parts`` gives."""
    energy, force, moment = _passes(block, positions, directors, True, True)
    return force, moment, _energy_parts(energy)


def strain_energy_parts(block, positions: np.ndarray, directors: np.ndarray) -> dict:
    """Strain energy (N mm) of a FibrousShellBlock by term: {"tension", "shear", "bending"}
    (block.py ``strain_energy_parts``)."""
    return _energy_parts(_passes(block, positions, directors, False, True)[0])
