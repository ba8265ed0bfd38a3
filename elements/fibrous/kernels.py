"""Compiled loops of the fibrous shell (numba), with the numpy functions of the package
(geometry.py, membrane.py, bending.py) as their vectorised reference (``kernel="numpy"``); the
tests hold the two to 1e-12.

``internal_force`` and ``strain_energy_parts`` evaluate the whole element, laws included
(``law_value`` and ``law_energy`` of packed_laws.py on the tables of ``pack_laws``), in four
parallel passes,
because two quantities couple a cell to its neighbours (docs/theory.md §1.4, §2.5, §4):

1. each cell's share of the nodal normal sums S_k, summed at the nodes;
2. each cell's tension and shear in one loop over its fibre levels (``_membrane_cell``: forces,
   director moments, dW/dS_k, energies), then its fold angles, which read the neighbours'
   normals, its bending energy and its share of each side's moment;
3. T_k, the sums of dW/dS_k over the cells around each node;
4. the pulls of T_k and of the side moments on each cell's nodes, summed at the nodes.

Every sum from cells to nodes is a loop over nodes that adds the corners of the node's cells
in cell order (elements/kernels.py ``NodeCorners``): parallel without races, and the same sums
in the same order as ``numpy.bincount``. The per-cell pieces of the bending geometry also serve
``bending_geometry``, the compiled form of bending.py ``geometry`` (tangent, fields).
"""

from __future__ import annotations

import numpy as np

from elements.fibrous.packed_laws import law_energy, law_value
from elements.jit import jit, prange, serial
from elements.shell_geometry import GUARD

__all__ = ["bending_geometry", "corner_shares", "internal_force", "strain_energy_parts"]


# ---------------------------------------------------------------------- one cell's geometry
@serial
def _edges(x, c):
    """The edges a = x1 - x0 and b = x2 - x0 of cell c with corners x (m, 3, 3)."""
    return (
        x[c, 1, 0] - x[c, 0, 0],
        x[c, 1, 1] - x[c, 0, 1],
        x[c, 1, 2] - x[c, 0, 2],
        x[c, 2, 0] - x[c, 0, 0],
        x[c, 2, 1] - x[c, 0, 1],
        x[c, 2, 2] - x[c, 0, 2],
    )


@serial
def _unit_normal(x, c):
    """(n_x, n_y, n_z, |c|) of cell c with corners x (m, 3, 3): c = (x1 - x0) x (x2 - x0)."""
    ax, ay, az, bx, by, bz = _edges(x, c)
    cx, cy, cz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
    size = np.sqrt(cx * cx + cy * cy + cz * cz)
    return cx / size, cy / size, cz / size, size


@serial
def _add_cross_pull(x, c, gx, gy, gz, force):
    """force[c] += d(g . c)/dx at the corners of cell c, g held: b x g on x1, g x a on x2
    (a = x1 - x0, b = x2 - x0), minus their sum on x0 (geometry.py ``cross_product_pull``)."""
    ax, ay, az, bx, by, bz = _edges(x, c)
    p1x, p1y, p1z = by * gz - bz * gy, bz * gx - bx * gz, bx * gy - by * gx
    p2x, p2y, p2z = gy * az - gz * ay, gz * ax - gx * az, gx * ay - gy * ax
    force[c, 0, 0] -= p1x + p2x
    force[c, 0, 1] -= p1y + p2y
    force[c, 0, 2] -= p1z + p2z
    force[c, 1, 0] += p1x
    force[c, 1, 1] += p1y
    force[c, 1, 2] += p1z
    force[c, 2, 0] += p2x
    force[c, 2, 1] += p2y
    force[c, 2, 2] += p2z


@serial
def _corner_edges(x, c, k):
    """The two edges of cell c at corner k, u = x_(k+1) - x_k and w = x_(k+2) - x_k:
    (ux, uy, uz, wx, wy, wz)."""
    q, r = (k + 1) % 3, (k + 2) % 3
    return (
        x[c, q, 0] - x[c, k, 0],
        x[c, q, 1] - x[c, k, 1],
        x[c, q, 2] - x[c, k, 2],
        x[c, r, 0] - x[c, k, 0],
        x[c, r, 1] - x[c, k, 1],
        x[c, r, 2] - x[c, k, 2],
    )


@serial
def _corner(x, c, k):
    """The angle alpha_k of cell c at corner k and its two edges (``_corner_edges``):
    (alpha, ux, uy, uz, wx, wy, wz)."""
    ux, uy, uz, wx, wy, wz = _corner_edges(x, c, k)
    sx, sy, sz = uy * wz - uz * wy, uz * wx - ux * wz, ux * wy - uy * wx
    angle = np.arctan2(np.sqrt(sx * sx + sy * sy + sz * sz), ux * wx + uy * wy + uz * wz)
    return angle, ux, uy, uz, wx, wy, wz


@serial
def _shares_cell(x, c, shares, normal, double_area, angles):
    """Cell c's unit normal and double area, its angles alpha_k and its share of the nodal
    normal sums, alpha_k n at each corner k (geometry.py ``corner_normals``)."""
    nx, ny, nz, size = _unit_normal(x, c)
    normal[c, 0], normal[c, 1], normal[c, 2], double_area[c] = nx, ny, nz, size
    for k in range(3):
        angle = _corner(x, c, k)[0]
        angles[c, k] = angle
        shares[c, k, 0] = angle * nx
        shares[c, k, 1] = angle * ny
        shares[c, k, 2] = angle * nz


@jit
def _corner_shares(x, shares, normal, double_area, angles):
    for c in prange(x.shape[0]):
        _shares_cell(x, c, shares, normal, double_area, angles)


def corner_shares(positions: np.ndarray, connectivity: np.ndarray) -> np.ndarray:
    """alpha_k n (m, 3, 3) of each cell by the compiled loop."""
    m = len(connectivity)
    shares = np.empty((m, 3, 3))
    x = np.ascontiguousarray(positions[connectivity], dtype=np.float64)
    _corner_shares(x, shares, np.empty((m, 3)), np.empty(m), np.empty((m, 3)))
    return shares


# ---------------------------------------------------------------------- one cell's membrane
@serial
def _membrane_cell(
    c, x, v, sums, connectivity, nodal, thickness, guard, zeta, weights, area,
    reference_length1, reference_length2, shear_sign, reference_shear, xi_is_warp,
    law_integers, law_reals, thickness_variation, with_forces, normal, double_area, cosine,
    h_m, node_normal, energy, force, moment, d_sums,
):  # fmt: skip
    """Tension and shear of cell c in one pass over its fibre levels (geometry.py
    ``cell_geometry``, membrane.py ``strains``, ``layer_loads`` and ``layer_forces``; Eq. 8-10, 14,
    24-33): the element normal and area, h_m = h / max(V . N, guard) at the corners (N the
    nodal normal S_k / |S_k|, S (n, 3) read at the cell's nodes, when ``nodal``; else the
    element's), then at each level the vectors g1, g2, the log strains and the shear angle,
    and the laws (packed laws 0, 1, 2: warp tension, weft tension, shear). ``with_forces``:
    the cell's forces, director moments and dW/dS_k (zero without nodal normals), (m, 3, 3)
    rows; else its energies (energy[c, 0] tension, energy[c, 1] shear, N mm).
    cosine, h_m (m, 3) and node_normal (m, 3, 3) are scratch rows of the cell."""
    nx, ny, nz, size = _unit_normal(x, c)
    normal[c, 0], normal[c, 1], normal[c, 2] = nx, ny, nz
    double_area[c] = size
    for k in range(3):
        if nodal:
            node = connectivity[c, k]
            sx, sy, sz = sums[node, 0], sums[node, 1], sums[node, 2]
            length = np.sqrt(sx * sx + sy * sy + sz * sz)
            node_normal[c, k, 0] = sx / length
            node_normal[c, k, 1] = sy / length
            node_normal[c, k, 2] = sz / length
            cos = (v[c, k, 0] * sx + v[c, k, 1] * sy + v[c, k, 2] * sz) / length
        else:
            cos = v[c, k, 0] * nx + v[c, k, 1] * ny + v[c, k, 2] * nz
        cosine[c, k] = cos
        h_m[c, k] = thickness / max(cos, guard)
    law1, law2 = (0, 1) if xi_is_warp[c] else (1, 0)  # the tension laws along 0-1 and 0-2
    tension_energy = shear_energy = 0.0
    s1x = s1y = s1z = s2x = s2y = s2z = 0.0  # sum_f P_a
    a1x = a1y = a1z = a2x = a2y = a2z = 0.0  # sum_f zeta_f P_a
    lx = ly = lz = 0.0  # dW/dn
    for f in range(zeta.shape[0]):
        # g_a = x_a^f - x_0^f, x_k^f = x_k + zeta_f / 2 h_m^k V_k (Eq. 8-9)
        half = 0.5 * zeta[f]
        o0, o1, o2 = half * h_m[c, 0], half * h_m[c, 1], half * h_m[c, 2]
        b = x[c, 0, 0] + o0 * v[c, 0, 0]
        g1x, g2x = x[c, 1, 0] + o1 * v[c, 1, 0] - b, x[c, 2, 0] + o2 * v[c, 2, 0] - b
        b = x[c, 0, 1] + o0 * v[c, 0, 1]
        g1y, g2y = x[c, 1, 1] + o1 * v[c, 1, 1] - b, x[c, 2, 1] + o2 * v[c, 2, 1] - b
        b = x[c, 0, 2] + o0 * v[c, 0, 2]
        g1z, g2z = x[c, 1, 2] + o1 * v[c, 1, 2] - b, x[c, 2, 2] + o2 * v[c, 2, 2] - b
        # squared lengths: the log strain is half the log of their ratio, and the shear needs
        # 1 / (|g1| |g2|) only (one root instead of four)
        square1 = g1x * g1x + g1y * g1y + g1z * g1z
        square2 = g2x * g2x + g2y * g2y + g2z * g2z
        if nodal:  # the lengths of g_a projected on the element's plane (docs/theory.md §2.2)
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
        reference1, reference2 = reference_length1[c, f], reference_length2[c, f]
        eps1 = 0.5 * np.log(fibre1 / (reference1 * reference1))
        eps2 = 0.5 * np.log(fibre2 / (reference2 * reference2))
        inverse = 1.0 / np.sqrt(square1 * square2)  # 1 / (|g1| |g2|)
        cos = (g1x * g2x + g1y * g2y + g1z * g2z) * inverse
        gamma = shear_sign[c] * np.arcsin(min(max(cos, -1.0), 1.0)) - reference_shear[c, f]
        w = area[c] * weights[f]  # A0 w_f
        if not with_forces:
            tension_energy += w * (
                law_energy(law_integers, law_reals, law1, eps1)
                + law_energy(law_integers, law_reals, law2, eps2)
            )
            shear_energy += w * law_energy(law_integers, law_reals, 2, gamma)
            continue
        # Tension (Eq. 24-27): dW/dg_a = A0 w_f T_a P g_a / l^2 (P g = g without nodal normals)
        k1 = w * law_value(law_integers, law_reals, law1, eps1) / fibre1
        k2 = w * law_value(law_integers, law_reals, law2, eps2) / fibre2
        p1x, p1y, p1z = k1 * e1x, k1 * e1y, k1 * e1z
        p2x, p2y, p2z = k2 * e2x, k2 * e2y, k2 * e2z
        lx -= k1 * q1 * e1x + k2 * q2 * e2x
        ly -= k1 * q1 * e1y + k2 * q2 * e2y
        lz -= k1 * q1 * e1z + k2 * q2 * e2z
        # Shear (Eq. 30-33): d gamma = sign (dg1 . t1 / |g1| + dg2 . t2 / |g2|), t1 / |g1| =
        # (g2 / (|g1| |g2|) - cos g1 / |g1|^2) / sin, and t2 / |g2| likewise
        sin = np.sqrt(max(1.0 - cos * cos, 1e-24))
        shear_moment = w * shear_sign[c] * law_value(law_integers, law_reals, 2, gamma) / sin
        c1, c2 = cos / square1, cos / square2
        p1x += shear_moment * (g2x * inverse - c1 * g1x)
        p1y += shear_moment * (g2y * inverse - c1 * g1y)
        p1z += shear_moment * (g2z * inverse - c1 * g1z)
        p2x += shear_moment * (g1x * inverse - c2 * g2x)
        p2y += shear_moment * (g1y * inverse - c2 * g2y)
        p2z += shear_moment * (g1z * inverse - c2 * g2z)
        s1x += p1x
        s1y += p1y
        s1z += p1z
        s2x += p2x
        s2y += p2y
        s2z += p2z
        a1x += zeta[f] * p1x
        a1y += zeta[f] * p1y
        a1z += zeta[f] * p1z
        a2x += zeta[f] * p2x
        a2y += zeta[f] * p2y
        a2z += zeta[f] * p2z
    if not with_forces:
        energy[c, 0], energy[c, 1] = tension_energy, shear_energy
        return
    # F_k = sum_a N_k,a P_a on the nodes (Eq. 24); the director takes the moment of the
    # lever arm zeta_f h_m / 2 along V (Eq. 28, Bai Fig. 3)
    force[c, 0, 0], force[c, 0, 1], force[c, 0, 2] = -(s1x + s2x), -(s1y + s2y), -(s1z + s2z)
    force[c, 1, 0], force[c, 1, 1], force[c, 1, 2] = s1x, s1y, s1z
    force[c, 2, 0], force[c, 2, 1], force[c, 2, 2] = s2x, s2y, s2z
    # n = c / |c| varies: the corners pull on c = a x b with g = P dW/dn / |c|
    gx = gy = gz = 0.0
    if nodal:
        along = lx * nx + ly * ny + lz * nz
        gx, gy, gz = (lx - along * nx) / size, (ly - along * ny) / size, (lz - along * nz) / size
    for k in range(3):
        if k == 0:
            rx, ry, rz = -(a1x + a2x), -(a1y + a2y), -(a1z + a2z)
        elif k == 1:
            rx, ry, rz = a1x, a1y, a1z
        else:
            rx, ry, rz = a2x, a2y, a2z
        vx, vy, vz = v[c, k, 0], v[c, k, 1], v[c, k, 2]
        half_h = 0.5 * h_m[c, k]
        mx = half_h * (vy * rz - vz * ry)
        my = half_h * (vz * rx - vx * rz)
        mz = half_h * (vx * ry - vy * rx)
        dsx = dsy = dsz = 0.0
        if thickness_variation:  # the work of h_m = h / c, c = V . N (docs/theory.md §2.5)
            dw_dh = 0.5 * (rx * vx + ry * vy + rz * vz)
            ck = cosine[c, k]
            dw_dc = 0.0 if ck < guard else -dw_dh * thickness / (ck * ck)
            if nodal:  # dc/dS_k = (V_k - c N_k) / |S_k|, dc/dpsi_k = V_k x N_k
                wx, wy, wz = node_normal[c, k, 0], node_normal[c, k, 1], node_normal[c, k, 2]
                node = connectivity[c, k]
                length = np.sqrt(
                    sums[node, 0] * sums[node, 0]
                    + sums[node, 1] * sums[node, 1]
                    + sums[node, 2] * sums[node, 2]
                )
                factor = dw_dc / length
                dsx = factor * (vx - ck * wx)
                dsy = factor * (vy - ck * wy)
                dsz = factor * (vz - ck * wz)
            else:  # through n = c / |c|: dc_k = (V_k - c_k n) . dc / |c|
                wx, wy, wz = nx, ny, nz
                gx += dw_dc * (vx - ck * nx) / size
                gy += dw_dc * (vy - ck * ny) / size
                gz += dw_dc * (vz - ck * nz) / size
            mx += dw_dc * (vy * wz - vz * wy)
            my += dw_dc * (vz * wx - vx * wz)
            mz += dw_dc * (vx * wy - vy * wx)
        moment[c, k, 0], moment[c, k, 1], moment[c, k, 2] = mx, my, mz
        d_sums[c, k, 0], d_sums[c, k, 1], d_sums[c, k, 2] = dsx, dsy, dsz
    _add_cross_pull(x, c, gx, gy, gz, force)


@serial
def _normal_pull_cell(x, c, pull, connectivity, angles, force):
    """force[c] += sum_k T_k . d(alpha_k n)/dx_j at the corners of cell c, T (n, 3) read at
    its nodes (geometry.py ``corner_normal_pull``); angles (m, 3) the alpha_k of
    pass 1."""
    nx, ny, nz, size = _unit_normal(x, c)
    gx = gy = gz = 0.0
    for k in range(3):
        q, r = (k + 1) % 3, (k + 2) % 3
        node = connectivity[c, k]
        px, py, pz = pull[node, 0], pull[node, 1], pull[node, 2]
        angle = angles[c, k]
        ux, uy, uz, wx, wy, wz = _corner_edges(x, c, k)
        u_len = np.sqrt(ux * ux + uy * uy + uz * uz)
        w_len = np.sqrt(wx * wx + wy * wy + wz * wz)
        # d alpha_k / dx at the next corner: -(n x u / |u|) / |u|; at the previous one:
        # -((w / |w|) x n) / |w|; at x_k minus their sum.
        tx = -(ny * uz - nz * uy) / (u_len * u_len)
        ty = -(nz * ux - nx * uz) / (u_len * u_len)
        tz = -(nx * uy - ny * ux) / (u_len * u_len)
        vx = -(wy * nz - wz * ny) / (w_len * w_len)
        vy = -(wz * nx - wx * nz) / (w_len * w_len)
        vz = -(wx * ny - wy * nx) / (w_len * w_len)
        weight = px * nx + py * ny + pz * nz
        force[c, q, 0] += weight * tx
        force[c, q, 1] += weight * ty
        force[c, q, 2] += weight * tz
        force[c, r, 0] += weight * vx
        force[c, r, 1] += weight * vy
        force[c, r, 2] += weight * vz
        force[c, k, 0] -= weight * (tx + vx)
        force[c, k, 1] -= weight * (ty + vy)
        force[c, k, 2] -= weight * (tz + vz)
        gx += angle * px
        gy += angle * py
        gz += angle * pz
    along = gx * nx + gy * ny + gz * nz
    gx, gy, gz = (gx - along * nx) / size, (gy - along * ny) / size, (gz - along * nz) / size
    _add_cross_pull(x, c, gx, gy, gz, force)


# ---------------------------------------------------------------------- one cell's bending
@serial
def _bending_sides_cell(
    x, c, normal, double_area, across_cell, interior, clamped, wall, fold, coefficients,
    gradient,
):  # fmt: skip
    """bending.py ``geometry`` of cell c: the fold angle theta_s of each
    side against the neighbour across it (or the wall of the reference plane on a clamped
    side), the curvature coefficients c_as (m, 2, 3) and the gradient D[s, k] (m, 3, 3).
    ``normal`` and ``double_area`` hold every cell's (the neighbours' are read)."""
    nx, ny, nz = normal[c, 0], normal[c, 1], normal[c, 2]
    area2 = double_area[c]
    f1x, f1y, f1z, f2x, f2y, f2z = _edges(x, c)
    l1 = np.sqrt(f1x * f1x + f1y * f1y + f1z * f1z)
    l2 = np.sqrt(f2x * f2x + f2y * f2y + f2z * f2z)
    f1x, f1y, f1z = f1x / l1, f1y / l1, f1z / l1
    f2x, f2y, f2z = f2x / l2, f2y / l2, f2z / l2
    for s in range(3):
        p, q = (s + 1) % 3, (s + 2) % 3  # side s runs from corner p to corner q
        sx = x[c, q, 0] - x[c, p, 0]
        sy = x[c, q, 1] - x[c, p, 1]
        sz = x[c, q, 2] - x[c, p, 2]
        length = np.sqrt(sx * sx + sy * sy + sz * sz)
        ox = (sy * nz - sz * ny) / length  # outward in-plane normal n^c_s
        oy = (sz * nx - sx * nz) / length
        oz = (sx * ny - sy * nx) / length
        for k in range(3):
            pk, qk = (k + 1) % 3, (k + 2) % 3
            tx = x[c, qk, 0] - x[c, pk, 0]
            ty = x[c, qk, 1] - x[c, pk, 1]
            tz = x[c, qk, 2] - x[c, pk, 2]
            gx = (ny * tz - nz * ty) / area2  # grad N_k
            gy = (nz * tx - nx * tz) / area2
            gz = (nx * ty - ny * tx) / area2
            gradient[c, s, k] = -(ox * gx + oy * gy + oz * gz)
        if not (interior[c, s] or clamped[c, s]):
            fold[c, s] = 0.0
            coefficients[c, 0, s] = 0.0
            coefficients[c, 1, s] = 0.0
            continue
        if clamped[c, s]:
            mx, my, mz = wall[c, 0], wall[c, 1], wall[c, 2]
            other_height = 0.0
        else:
            other = across_cell[c, s]
            mx, my, mz = normal[other, 0], normal[other, 1], normal[other, 2]
            other_height = double_area[other] / length
        if clamped[c, s] and interior[c, s]:
            other_height = double_area[across_cell[c, s]] / length
        fold[c, s] = np.arctan2(-(mx * ox + my * oy + mz * oz), mx * nx + my * ny + mz * nz)
        total = area2 / length + other_height
        p1 = f1x * ox + f1y * oy + f1z * oz
        p2 = f2x * ox + f2y * oy + f2z * oz
        coefficients[c, 0, s] = 2.0 * p1 * p1 / total
        coefficients[c, 1, s] = 2.0 * p2 * p2 / total


@jit
def _cell_normals(x, normal, double_area):
    """Unit normals (m, 3) and double areas (m,) of the cells with corners x (m, 3, 3)."""
    for c in prange(x.shape[0]):
        normal[c, 0], normal[c, 1], normal[c, 2], double_area[c] = _unit_normal(x, c)


@jit
def _bending_sides(
    x, normal, double_area, across_cell, interior, clamped, wall, fold, coefficients, gradient
):  # fmt: skip
    for c in prange(x.shape[0]):
        _bending_sides_cell(
            x, c, normal, double_area, across_cell, interior, clamped, wall, fold,
            coefficients, gradient,
        )  # fmt: skip


def bending_geometry(block, positions: np.ndarray) -> dict:
    """bending.py ``geometry`` by the compiled loops."""
    x = np.ascontiguousarray(positions[block.connectivity], dtype=np.float64)
    m = len(x)
    normal, double_area = np.empty((m, 3)), np.empty(m)
    _cell_normals(x, normal, double_area)
    fold, coefficients, gradient = np.empty((m, 3)), np.empty((m, 2, 3)), np.empty((m, 3, 3))
    _bending_sides(
        x, normal, double_area, block.across_cell, block.interior_side, block.clamped_side,
        block.reference_normal, fold, coefficients, gradient,
    )  # fmt: skip
    return {"fold": fold, "coefficients": coefficients, "gradient": gradient, "normal": normal}


@serial
def _side_moments_cell(
    c, fold, reference_fold, coefficients, area, xi_is_warp, law_integers, law_reals,
    with_forces, energy, own,
):  # fmt: skip
    """Cell c's share of its side moments (bending.py ``forces``): chi_a =
    -sum_s c_as (theta_s - theta_s0) (Eq. 35), M_a from the bending laws (packed laws 3, 4:
    warp, weft) and own_s = -A0 sum_a M_a c_as; without ``with_forces`` its bending energy
    energy[c, 2] = A0 sum_a Phi_a(chi_a) instead."""
    chi1 = chi2 = 0.0
    for s in range(3):
        turn = fold[c, s] - reference_fold[c, s]
        chi1 -= coefficients[c, 0, s] * turn
        chi2 -= coefficients[c, 1, s] * turn
    law1, law2 = (3, 4) if xi_is_warp[c] else (4, 3)
    if not with_forces:
        energy[c, 2] = area[c] * (
            law_energy(law_integers, law_reals, law1, chi1)
            + law_energy(law_integers, law_reals, law2, chi2)
        )
        return
    m1 = law_value(law_integers, law_reals, law1, chi1)
    m2 = law_value(law_integers, law_reals, law2, chi2)
    for s in range(3):
        own[c, s] = -area[c] * (m1 * coefficients[c, 0, s] + m2 * coefficients[c, 1, s])


@serial
def _bending_pull_cell(c, own, across_cell, across_side, interior, gradient, normal, force):
    """force[c] += each side's moment (own plus the neighbour's across it) times D[s, k] n
    (Eq. 37): every cell pulls on its own three nodes only."""
    w0 = w1 = w2 = 0.0
    for s in range(3):
        side = own[c, s]
        if interior[c, s]:
            side += own[across_cell[c, s], across_side[c, s]]
        w0 += side * gradient[c, s, 0]
        w1 += side * gradient[c, s, 1]
        w2 += side * gradient[c, s, 2]
    for i in range(3):
        force[c, 0, i] += w0 * normal[c, i]
        force[c, 1, i] += w1 * normal[c, i]
        force[c, 2, i] += w2 * normal[c, i]


# ---------------------------------------------------------------------- the internal force
@jit
def _gather_corners(positions, directors, connectivity, x, v):
    """x, v (m, 3, 3): the positions and directors at each cell's corners."""
    for c in prange(connectivity.shape[0]):
        for k in range(3):
            node = connectivity[c, k]
            for i in range(3):
                x[c, k, i] = positions[node, i]
                v[c, k, i] = directors[node, i]


@jit
def _cells_pass(
    x, v, sums, connectivity, nodal, thickness, guard, zeta, weights, area,
    reference_length1, reference_length2, shear_sign, reference_shear, xi_is_warp,
    law_integers, law_reals, thickness_variation, with_forces, across_cell, interior, clamped,
    wall, reference_fold, reference_coefficients, use_reference_coefficients, normal,
    double_area, cosine, h_m, node_normal, fold, coefficients, gradient, own, energy, force,
    moment, d_sums,
):  # fmt: skip
    """Pass 2: each cell's membrane forces, director moments and dW/dS_k (or energies)
    (``_membrane_cell``), then its side moments (or bending energy)."""
    for c in prange(x.shape[0]):
        _membrane_cell(
            c, x, v, sums, connectivity, nodal, thickness, guard, zeta, weights, area,
            reference_length1, reference_length2, shear_sign, reference_shear, xi_is_warp,
            law_integers, law_reals, thickness_variation, with_forces, normal, double_area,
            cosine, h_m, node_normal, energy, force, moment, d_sums,
        )  # fmt: skip
    # The fold angles read the neighbours' normals: written by every cell above.
    used = reference_coefficients if use_reference_coefficients else coefficients
    for c in prange(x.shape[0]):
        _bending_sides_cell(
            x, c, normal, double_area, across_cell, interior, clamped, wall, fold,
            coefficients, gradient,
        )  # fmt: skip
        _side_moments_cell(
            c, fold, reference_fold, used, area, xi_is_warp, law_integers, law_reals,
            with_forces, energy, own,
        )  # fmt: skip


@jit
def _pulls_pass(x, pull, connectivity, angles, nodal, own, across_cell, across_side, interior,
                gradient, normal, force):  # fmt: skip
    """Pass 4 of ``internal_force``: the pull of the nodal sums of dW/dS_k on each cell's
    nodes (nodal normals only) and the bending forces."""
    for c in prange(x.shape[0]):
        if nodal:
            _normal_pull_cell(x, c, pull, connectivity, angles, force)
        _bending_pull_cell(c, own, across_cell, across_side, interior, gradient, normal, force)


def _passes(block, positions: np.ndarray, directors: np.ndarray, with_forces: bool):
    """Passes 1 to 4 (see the module docstring): energies (m, 3) per cell (tension, shear,
    bending; N mm) and, ``with_forces``, the nodal forces and director moments (n, 3)."""
    conn, m = block.connectivity, len(block.connectivity)
    nodal, corners = block.nodal_normals, block.node_corners
    x, v = np.empty((m, 3, 3)), np.empty((m, 3, 3))
    _gather_corners(
        np.ascontiguousarray(positions, dtype=np.float64),
        np.ascontiguousarray(directors, dtype=np.float64),
        conn, x, v,
    )  # fmt: skip
    normal, double_area, angles = np.empty((m, 3)), np.empty(m), np.empty((m, 3))
    sums = np.zeros((0, 3))
    if nodal:  # pass 1: the nodal normal sums
        shares = np.empty((m, 3, 3))
        _corner_shares(x, shares, normal, double_area, angles)
        sums = corners.sum(shares)
        sums[block.wall_node_ids] = block.wall_sums
    cosine, h_m, node_normal = np.empty((m, 3)), np.empty((m, 3)), np.empty((m, 3, 3))
    fold, coefficients = np.empty((m, 3)), np.empty((m, 2, 3))
    gradient, own, energy = np.empty((m, 3, 3)), np.empty((m, 3)), np.empty((m, 3))
    shape = (m, 3, 3) if with_forces else (0, 3, 3)
    force, moment, d_sums = np.empty(shape), np.empty(shape), np.empty(shape)
    _cells_pass(
        x, v, sums, conn, nodal, float(block.fabric.thickness), GUARD, block.zeta,
        block.weights, block.reference_area, block.reference_length1, block.reference_length2,
        block.shear_sign, block.reference_shear, block.xi_is_warp, *block.packed_laws,
        block.thickness_variation, with_forces, block.across_cell, block.interior_side,
        block.clamped_side, block.reference_normal, block.reference_fold,
        block.reference_coefficients, block.reference_curvature_coefficients, normal,
        double_area, cosine, h_m, node_normal, fold, coefficients, gradient, own, energy,
        force, moment, d_sums,
    )  # fmt: skip
    if not with_forces:
        return energy, None, None
    pull = np.zeros((0, 3))
    if nodal:  # pass 3: T_k, the sums of dW/dS_k; a wall node's S_k does not vary
        pull = corners.sum(d_sums)
        pull[block.wall_node_ids] = 0.0
    _pulls_pass(
        x, pull, conn, angles, nodal, own, block.across_cell, block.across_side,
        block.interior_side, gradient, normal, force,
    )  # fmt: skip
    return energy, corners.sum(force), corners.sum(moment)


def internal_force(block, positions: np.ndarray, directors: np.ndarray):
    """Nodal internal forces and director moments (n, 3) of a FibrousShellBlock: tension,
    shear and bending (block.py ``internal_force``)."""
    _, force, moment = _passes(block, positions, directors, True)
    return force, moment


def strain_energy_parts(block, positions: np.ndarray, directors: np.ndarray) -> dict:
    """Strain energy (N mm) of a FibrousShellBlock by term: {"tension", "shear", "bending"}
    (block.py ``strain_energy_parts``)."""
    energy = _passes(block, positions, directors, False)[0].sum(axis=0)
    return {"tension": float(energy[0]), "shear": float(energy[1]), "bending": float(energy[2])}
