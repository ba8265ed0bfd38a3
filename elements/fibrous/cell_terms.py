"""Scalar pieces of the fibrous shell's compiled cell loops (elements/fibrous/kernels.py):
a cell's edges and normal (also the fibre frame's, fibre_kernels.py), the corner thickness,
the levers and a level's fibre vectors and strains (the force pass's and the strains
pass's one writing), the director moment, a side's fold angle and curvature coefficients,
the fold-angle gradient and the pull of a corner angle. Each returns scalars (x, y, z
components), so that the loops keep every vector in registers. Each is a compiled helper
(femcore/jit.py ``serial``) that LLVM inlines into its callers, but for ``level_strains``,
which LLVM leaves a call: spliced into its two callers (``inline``).

Divisions are the dearest of the loops' arithmetic after the transcendental functions (a
division or a square root costs several multiplications' time): where several quotients
share their denominators, one reciprocal serves them all, e.g. 1 / |a|^2 and 1 / |b|^2 as
|b|^2 / (|a|^2 |b|^2) and |a|^2 / (|a|^2 |b|^2). That rounds differently from the numpy
reference by a few units in the last place, well inside the 1e-12 the tests hold the two to.
"""

from __future__ import annotations

import numpy as np

from elements.lane_maths import lane_arcsin, lane_log
from femcore.jit import inline, serial

__all__ = [
    "angle_pull",
    "cell_cross",
    "cell_levers",
    "corner_frame",
    "corner_levers",
    "corner_thickness",
    "director_moment",
    "element_corner",
    "fold_gradient",
    "level_strains",
    "side_angle",
    "side_coefficients",
    "side_squares",
    "side_terms",
    "side_vector",
    "unit_edge_squares",
    "wall_fold",
]


@serial
def corner_thickness(directors, sums, node, nodal, nx, ny, nz, thickness, guard):
    """At the corner on ``node``: its director V, V . N, h_m = h / max(V . N, guard) and N
    (the nodal normal S / |S| from the node's normal sum S in ``sums`` (n, 3) when ``nodal``,
    else the element's n), 1 / |S| (1 without nodal normals) and 1 / max(V . N, guard):
    (Vx, Vy, Vz, cos, h_m, Nx, Ny, Nz, 1 / |S|, 1 / max(cos, guard))."""
    vx, vy, vz = directors[node, 0], directors[node, 1], directors[node, 2]
    if nodal:
        sx, sy, sz = sums[node, 0], sums[node, 1], sums[node, 2]
        inverse = 1.0 / np.sqrt(sx * sx + sy * sy + sz * sz)
        cos = (vx * sx + vy * sy + vz * sz) * inverse
        over = 1.0 / max(cos, guard)
        nx, ny, nz = sx * inverse, sy * inverse, sz * inverse
        return vx, vy, vz, cos, thickness * over, nx, ny, nz, inverse, over
    return element_corner(vx, vy, vz, nx, ny, nz, thickness, guard)


@serial
def element_corner(vx, vy, vz, nx, ny, nz, thickness, guard):
    """``corner_thickness`` of a corner whose director is V and whose normal is the element's
    n, from scalars only (no array passed: a helper given arrays increfs and decrefs each of
    them at every call, atomic operations that cost the cells' pass 40 % of its time when
    it took each corner's frame by ``corner_frame``): (Vx, Vy, Vz, cos, h_m, nx, ny, nz, 1,
    1 / max(cos, guard))."""
    cos = vx * nx + vy * ny + vz * nz
    over = 1.0 / max(cos, guard)
    return vx, vy, vz, cos, thickness * over, nx, ny, nz, 1.0, over


@serial
def corner_frame(frame, directors, node, nodal, nx, ny, nz, thickness, guard):
    """``corner_thickness`` at the corner on ``node``: with nodal normals read from ``frame``
    (n, 10), the same numbers formed once per node (geometry_kernels.py ``_node_frames``: a node is
    a corner of six cells on a regular mesh); with the element's normal n formed here."""
    if nodal:
        return (
            frame[node, 0], frame[node, 1], frame[node, 2], frame[node, 3], frame[node, 4],
            frame[node, 5], frame[node, 6], frame[node, 7], frame[node, 8], frame[node, 9],
        )  # fmt: skip
    # (``nodal``, False here, rather than the constant: one build of corner_thickness)
    return corner_thickness(directors, frame, node, nodal, nx, ny, nz, thickness, guard)


@serial
def corner_levers(h0, v0x, v0y, v0z, h1, v1x, v1y, v1z, h2, v2x, v2y, v2z):
    """The levers l_a = (h_m^a V_a - h_m^0 V_0) / 2 of a cell's fibre vectors (Eq. 5, 8-9:
    x_k^f = x_k + zeta_f / 2 h_m^k V_k, so g_a = x_a^f - x_0^f = r_a + zeta_f l_a with
    r_a = x_a - x_0) from the corners' h_m and V (``corner_frame``): (l1x, l1y, l1z, l2x,
    l2y, l2z), mm."""
    u0x, u0y, u0z = 0.5 * h0 * v0x, 0.5 * h0 * v0y, 0.5 * h0 * v0z
    return (
        0.5 * h1 * v1x - u0x, 0.5 * h1 * v1y - u0y, 0.5 * h1 * v1z - u0z,
        0.5 * h2 * v2x - u0x, 0.5 * h2 * v2y - u0y, 0.5 * h2 * v2z - u0z,
    )  # fmt: skip


@serial
def cell_levers(frame, directors, positions, n0, n1, n2, nodal, nx, ny, nz, thickness, guard):
    """A cell's edges r_a = x_a - x_0 (``cell_cross``) and levers l_a (``corner_levers``, from
    its corners' ``corner_frame``), what its fibre levels g_a = r_a + zeta_f l_a are made of
    (the force pass's and the strains pass's one writing): (r1x, r1y, r1z, r2x, r2y, r2z,
    l1x, l1y, l1z, l2x, l2y, l2z), mm."""
    v0x, v0y, v0z, _, h0, _, _, _, _, _ = corner_frame(
        frame, directors, n0, nodal, nx, ny, nz, thickness, guard
    )
    v1x, v1y, v1z, _, h1, _, _, _, _, _ = corner_frame(
        frame, directors, n1, nodal, nx, ny, nz, thickness, guard
    )
    v2x, v2y, v2z, _, h2, _, _, _, _, _ = corner_frame(
        frame, directors, n2, nodal, nx, ny, nz, thickness, guard
    )
    r1x, r1y, r1z, r2x, r2y, r2z, _, _, _ = cell_cross(positions, n0, n1, n2)
    l1x, l1y, l1z, l2x, l2y, l2z = corner_levers(
        h0, v0x, v0y, v0z, h1, v1x, v1y, v1z, h2, v2x, v2y, v2z
    )
    return r1x, r1y, r1z, r2x, r2y, r2z, l1x, l1y, l1z, l2x, l2y, l2z


@inline
def level_strains(
    z, r1x, r1y, r1z, r2x, r2y, r2z, l1x, l1y, l1z, l2x, l2y, l2z, nodal, nx, ny, nz,
    reference1, reference2, sign, reference_shear,
):  # fmt: skip
    """The fibre vectors, log strains and shear angle of one level zeta_f = ``z`` of a cell
    (membrane.py ``strains``; Eq. 8, 26, Fig. 4): g_a = r_a + z l_a (r_a the edges 0 -> 1, 0 -> 2,
    l_a of ``corner_levers``), the log strain of the fibre length l_a (|g_a|, or with
    ``nodal`` normals |P g_a|, P = I - n n^T with n the cell's unit normal, docs/theory.md
    §2.2) against the reference length L_a (``reference1``, ``reference2``), and gamma =
    sign asin(g1 . g2 / (|g1| |g2|)) - ``reference_shear``; the log and the arcsine
    branch-free (elements/lane_maths.py), so that a loop of levels across cells vectorises.

    The log strain is half the log of the squared-length ratio, and 1 / l_a^2 and
    1 / L_a^2 share one division; the shear needs 1 / (|g1| |g2|) only (one root instead of
    four). The one writing of a level's strains that the force pass and the strains pass
    (kernels.py ``_cells_pass``, ``_strains_pass``) share. Returns (g1 (3), g2 (3), |g1|^2,
    |g2|^2, q1, q2 (g_a . n, 0 without ``nodal``), e1 (3), e2 (3) (P g_a), 1 / l1^2,
    1 / l2^2, 1 / (|g1| |g2|), cos, eps1, eps2, gamma)."""
    g1x, g1y, g1z = r1x + z * l1x, r1y + z * l1y, r1z + z * l1z
    g2x, g2y, g2z = r2x + z * l2x, r2y + z * l2y, r2z + z * l2z
    square1 = g1x * g1x + g1y * g1y + g1z * g1z
    square2 = g2x * g2x + g2y * g2y + g2z * g2z
    if nodal:  # the lengths of g_a projected on the element's plane (theory §2.2)
        q1 = g1x * nx + g1y * ny + g1z * nz
        q2 = g2x * nx + g2y * ny + g2z * nz
        e1x, e1y, e1z = g1x - q1 * nx, g1y - q1 * ny, g1z - q1 * nz
        e2x, e2y, e2z = g2x - q2 * nx, g2y - q2 * ny, g2z - q2 * nz
        fibre1 = e1x * e1x + e1y * e1y + e1z * e1z
        fibre2 = e2x * e2x + e2y * e2y + e2z * e2z
    else:
        q1 = q2 = 0.0
        e1x, e1y, e1z, e2x, e2y, e2z = g1x, g1y, g1z, g2x, g2y, g2z
        fibre1, fibre2 = square1, square2
    # 1 / l_a^2 and 1 / L_a^2 by one division
    reference1, reference2 = reference1 * reference1, reference2 * reference2
    fibres, references = fibre1 * fibre2, reference1 * reference2
    over = 1.0 / (fibres * references)
    over_fibre1, over_fibre2 = fibre2 * references * over, fibre1 * references * over
    eps1 = 0.5 * lane_log(fibre1 * (fibres * reference2 * over))
    eps2 = 0.5 * lane_log(fibre2 * (fibres * reference1 * over))
    inverse = 1.0 / np.sqrt(square1 * square2)  # 1 / (|g1| |g2|)
    cos = (g1x * g2x + g1y * g2y + g1z * g2z) * inverse
    gamma = sign * lane_arcsin(min(max(cos, -1.0), 1.0)) - reference_shear
    return (
        g1x, g1y, g1z, g2x, g2y, g2z, square1, square2, q1, q2, e1x, e1y, e1z, e2x, e2y,
        e2z, over_fibre1, over_fibre2, inverse, cos, eps1, eps2, gamma,
    )  # fmt: skip


@serial
def director_moment(
    rx, ry, rz, vx, vy, vz, h_m, cos, wx, wy, wz, inverse_length, over, guard, variation
):  # fmt: skip
    """The director moment of one corner from r = sum_f zeta_f dW/dg at the corner (the lever
    arm zeta_f h_m / 2 along V, Eq. 28, Bai Fig. 3) and, with ``variation``, the work of
    h_m = h / c, c = V . N (docs/theory.md §2.5): dc/dpsi = V x N, dc/dS = (V - c N) / |S|;
    ``inverse_length`` 1 / |S|, ``over`` 1 / max(c, guard) (corner_thickness).
    Returns (m (3), dW/dc (V - c N) (3), with dW/dc divided by |S|): the second is dW/dS_k
    with nodal normals, and with the element's normal the corner's pull on n times |c|."""
    half_h = 0.5 * h_m
    mx = half_h * (vy * rz - vz * ry)
    my = half_h * (vz * rx - vx * rz)
    mz = half_h * (vx * ry - vy * rx)
    if not variation:
        return mx, my, mz, 0.0, 0.0, 0.0
    dw_dh = 0.5 * (rx * vx + ry * vy + rz * vz)
    dw_dc = 0.0 if cos < guard else -dw_dh * h_m * over  # dh_m/dc = -h / c^2 = -h_m / c
    mx += dw_dc * (vy * wz - vz * wy)
    my += dw_dc * (vz * wx - vx * wz)
    mz += dw_dc * (vx * wy - vy * wx)
    factor = dw_dc * inverse_length
    return mx, my, mz, factor * (vx - cos * wx), factor * (vy - cos * wy), factor * (vz - cos * wz)


@serial
def unit_edge_squares(x0x, x0y, x0z, x1x, x1y, x1z, x2x, x2y, x2z):
    """The edges e1 = x1 - x0 and e2 = x2 - x0 of a cell and 1 / |e1|^2, 1 / |e2|^2 (what
    the curvature coefficients need of the unit edges f_a = e_a / |e_a|): (e1x, e1y, e1z,
    e2x, e2y, e2z, 1 / |e1|^2, 1 / |e2|^2)."""
    e1x, e1y, e1z = x1x - x0x, x1y - x0y, x1z - x0z
    e2x, e2y, e2z = x2x - x0x, x2y - x0y, x2z - x0z
    square1 = e1x * e1x + e1y * e1y + e1z * e1z
    square2 = e2x * e2x + e2y * e2y + e2z * e2z
    over = 1.0 / (square1 * square2)
    return e1x, e1y, e1z, e2x, e2y, e2z, square2 * over, square1 * over


@serial
def cell_cross(points, i, j, k):
    """The edges a = x_j - x_i, b = x_k - x_i of the cell on nodes i, j, k of ``points``
    (n, 3) and c = a x b, whose length is twice the cell's area and whose direction is its
    normal: (ax, ay, az, bx, by, bz, cx, cy, cz). The one writing of the cell normal that the
    force passes and the fibre frame (fibre_kernels.py) share."""
    ax = points[j, 0] - points[i, 0]
    ay = points[j, 1] - points[i, 1]
    az = points[j, 2] - points[i, 2]
    bx = points[k, 0] - points[i, 0]
    by = points[k, 1] - points[i, 1]
    bz = points[k, 2] - points[i, 2]
    return ax, ay, az, bx, by, bz, ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx


@serial
def side_angle(sx, sy, sz, nx, ny, nz, mx, my, mz, area2, other_area2):
    """The fold angle of the side s = q - p of a cell of unit normal n and double area
    ``area2`` against the unit normal m across it, theta = atan2(-m . n^c, m . n), n^c = s x
    n / |s| the outward in-plane normal, and the scale 2 / (|s| (2A + 2A')) of its curvature
    coefficients (``side_coefficients``; 2A' = ``other_area2``, 0 for a wall). With w = s x n
    (|w| = |s|): theta = atan2(-m . w, |s| m . n). Returns (theta, scale).

    The fold of a side seen from the cell across it is the same angle (the side runs the
    other way there and the two normals swap: -n . ((p - q) x m) = -m . ((q - p) x n)), and
    so is the scale, to the last bit (|p - q| = |q - p| and 2A' + 2A = 2A + 2A'): one
    evaluation serves both cells (geometry_kernels.py ``_side_folds``)."""
    y, x, scale = side_terms(sx, sy, sz, nx, ny, nz, mx, my, mz, area2, other_area2)
    return np.arctan2(y, x), scale


@serial
def side_terms(sx, sy, sz, nx, ny, nz, mx, my, mz, area2, other_area2):
    """``side_angle`` but for its arctangent: (y, x, scale), the fold angle atan2(y, x) (the
    sides' pass, geometry_kernels.py ``_side_folds``, takes the arctangents of a chunk of sides at
    once)."""
    length = np.sqrt(sx * sx + sy * sy + sz * sz)
    wx = sy * nz - sz * ny
    wy = sz * nx - sx * nz
    wz = sx * ny - sy * nx
    y = -(mx * wx + my * wy + mz * wz)
    return y, length * (mx * nx + my * ny + mz * nz), 2.0 / (length * (area2 + other_area2))


@serial
def side_coefficients(sx, sy, sz, nx, ny, nz, e1x, e1y, e1z, e2x, e2y, e2z, over1, over2, scale):
    """The curvature coefficients c_as = 2 (f_a . n^c)^2 / (h + h') of the side s = q - p of a
    cell of unit normal n (docs/theory.md §4.2): h = 2A / |s| the cell's height over the side
    and h' = 2A' / |s| the neighbour's (0 for a wall), f_a = e_a / |e_a| the unit edges 0 -> 1,
    0 -> 2 (bending.py ``geometry``), ``over1``, ``over2`` = 1 / |e_a|^2 (unit_edge_squares),
    ``scale`` = 2 / (|s| (2A + 2A')) (``side_angle``). With w = s x n (|w| = |s|): c_as =
    2 (e_a . w)^2 / (|e_a|^2 |s| (2A + 2A')), one division for both. Returns (c_1s, c_2s)."""
    wx = sy * nz - sz * ny
    wy = sz * nx - sx * nz
    wz = sx * ny - sy * nx
    p1 = e1x * wx + e1y * wy + e1z * wz
    p2 = e2x * wx + e2y * wy + e2z * wz
    return p1 * p1 * (over1 * scale), p2 * p2 * (over2 * scale)


@serial
def side_vector(s, x0x, x0y, x0z, x1x, x1y, x1z, x2x, x2y, x2z):
    """Side s of a cell, from corner s + 1 to corner s + 2: q - p (3 scalars)."""
    if s == 0:
        return x2x - x1x, x2y - x1y, x2z - x1z
    if s == 1:
        return x0x - x2x, x0y - x2y, x0z - x2z
    return x1x - x0x, x1y - x0y, x1z - x0z


@serial
def wall_fold(
    c, s, x0x, x0y, x0z, x1x, x1y, x1z, x2x, x2y, x2z, nx, ny, nz, size, e1x, e1y, e1z,
    e2x, e2y, e2z, over1, over2, wall, mirror,
):  # fmt: skip
    """Side s of cell c (from corner s + 1 to corner s + 2) clamped: its fold against the wall
    of the reference plane (the unit normal ``wall`` (m, 3) of the cell at bind), or on a
    symmetry plane (``mirror`` (m, 3, 3) the plane's signed normal p, 0 elsewhere) against
    the wall (p x t) / |p x t| through the side t (elements/fibrous/symmetry.py), and its
    curvature coefficients (``side_angle``, ``side_coefficients``): (fold, c_1s, c_2s)."""
    sx, sy, sz = side_vector(s, x0x, x0y, x0z, x1x, x1y, x1z, x2x, x2y, x2z)
    wx, wy, wz = wall[c, 0], wall[c, 1], wall[c, 2]
    px, py, pz = mirror[c, s, 0], mirror[c, s, 1], mirror[c, s, 2]
    if px != 0.0 or py != 0.0 or pz != 0.0:
        wx, wy, wz = py * sz - pz * sy, pz * sx - px * sz, px * sy - py * sx
        over = 1.0 / np.sqrt(wx * wx + wy * wy + wz * wz)
        wx, wy, wz = wx * over, wy * over, wz * over
    fold, scale = side_angle(sx, sy, sz, nx, ny, nz, wx, wy, wz, size, 0.0)
    c1s, c2s = side_coefficients(
        sx, sy, sz, nx, ny, nz, e1x, e1y, e1z, e2x, e2y, e2z, over1, over2, scale
    )  # fmt: skip
    return fold, c1s, c2s


@serial
def side_squares(t0x, t0y, t0z, t1x, t1y, t1z, t2x, t2y, t2z):
    """|t_s|^2 of the sides t0, t1, t2 of a cell and their reciprocals by one division:
    (|t0|^2, |t1|^2, |t2|^2, 1 / |t0|^2, 1 / |t1|^2, 1 / |t2|^2)."""
    d00 = t0x * t0x + t0y * t0y + t0z * t0z
    d11 = t1x * t1x + t1y * t1y + t1z * t1z
    d22 = t2x * t2x + t2y * t2y + t2z * t2z
    d0011 = d00 * d11
    over = 1.0 / (d0011 * d22)
    return d00, d11, d22, d11 * d22 * over, d00 * d22 * over, d0011 * over


@serial
def fold_gradient(
    t0x, t0y, t0z, t1x, t1y, t1z, t2x, t2y, t2z, d00, d11, d22, i00, i11, i22, over_area2
):  # fmt: skip
    """D[s, k] = -grad N_k . n^c_s = t_s . t_k / (|t_s| 2A) of a cell whose sides (opposite
    corners 0, 1, 2) are t0 = x2 - x1, t1 = x0 - x2, t2 = x1 - x0, from their squares d_ss,
    the reciprocals i_ss (side_squares) and 1 / 2A: the share D[s, k] n of d theta_s / dx_k
    on the cell's own nodes (Eq. 36). Returns the 9 entries row by row."""
    d01 = t0x * t1x + t0y * t1y + t0z * t1z
    d02 = t0x * t2x + t0y * t2y + t0z * t2z
    d12 = t1x * t2x + t1y * t2y + t1z * t2z
    s0 = np.sqrt(i00) * over_area2
    s1 = np.sqrt(i11) * over_area2
    s2 = np.sqrt(i22) * over_area2
    return (
        d00 * s0, d01 * s0, d02 * s0,
        d01 * s1, d11 * s1, d12 * s1,
        d02 * s2, d12 * s2, d22 * s2,
    )  # fmt: skip


@serial
def angle_pull(nx, ny, nz, ux, uy, uz, wx, wy, wz, over_u, over_w, weight):
    """weight times d alpha / dx at the next corner (-(n x u) / |u|^2) and at the previous one
    (-(w x n) / |w|^2) of a corner with edges u and w (``over_u``, ``over_w``: 1 / |u|^2,
    1 / |w|^2): (tx, ty, tz, vx, vy, vz); the corner itself takes minus their sum."""
    to_u = -weight * over_u
    to_w = -weight * over_w
    return (
        to_u * (ny * uz - nz * uy),
        to_u * (nz * ux - nx * uz),
        to_u * (nx * uy - ny * ux),
        to_w * (wy * nz - wz * ny),
        to_w * (wz * nx - wx * nz),
        to_w * (wx * ny - wy * nx),
    )
