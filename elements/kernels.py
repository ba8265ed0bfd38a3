"""Compiled per-element kernels (numba): fused loops over the cells of a block that gather the
nodal values, compute each cell's forces and scatter them, with no temporary arrays over all
cells. Each kernel has a numpy reference in its element class (the ``kernel="numpy"`` path),
and the tests hold the two to 1e-12 of the largest force.

The loops over cells run in parallel (numba's ``prange``, as many threads as
``numba.set_num_threads`` allows) into per-cell buffers; the scatter to the nodes is a serial
loop after them, so that no two threads add to the same node.
"""

from __future__ import annotations

import numpy as np

from elements.shell_geometry import GUARD

try:  # numba is a dependency; the numpy paths keep the package usable without it
    import numba

    AVAILABLE = True
except ImportError:  # pragma: no cover - exercised only where numba is missing
    numba = None  # type: ignore[assignment]
    AVAILABLE = False

__all__ = ["AVAILABLE", "cable_forces", "mindlin_energy", "mindlin_loads"]


def choose(kernel: str | None) -> str:
    """An element's ``kernel`` option checked: "compiled" (the default when numba is
    installed) or "numpy"."""
    if kernel is None:
        return "compiled" if AVAILABLE else "numpy"
    if kernel not in ("compiled", "numpy"):
        raise ValueError(f"kernel must be 'compiled' or 'numpy', got {kernel!r}")
    if kernel == "compiled" and not AVAILABLE:
        raise ValueError("kernel='compiled' needs numba: pip install numba, or use 'numpy'")
    return kernel


def _jit(function):
    if not AVAILABLE:
        return function
    return numba.njit(cache=True, parallel=True, fastmath=False)(function)


def _serial(function):
    if not AVAILABLE:
        return function
    return numba.njit(cache=True)(function)


def _prange(n):  # pragma: no cover - replaced by numba.prange inside compiled code
    return range(n)


prange = numba.prange if AVAILABLE else _prange


@_jit
def _mindlin_cells(
    positions, directors, connectivity, zeta, half, ref11, ref22, ref12, ref_tying,
    shear_a, shear_b, stiffness, tying_n, with_forces, force, moment, energy,
):  # fmt: skip
    """The strain energy (m,) of each MITC3 Mindlin triangle (elements/mindlin.py
    ``strain_energy``: 1/2 sum E . D E over its points) into ``energy`` and, ``with_forces``,
    its nodal forces and director moments (m, 3, 3) (``_cell_loads``, docs/theory.md
    §5.2-5.4) into ``force`` and ``moment``. stiffness: (m, P, Z, 5, 5) weighted lamina
    stiffness per point. Three-vectors are kept in scalars (x, y, z components): no array is
    allocated inside the loop."""
    m = connectivity.shape[0]
    nz = zeta.shape[0]
    npts = shear_a.shape[0]
    for c in prange(m):
        n0, n1, n2 = connectivity[c, 0], connectivity[c, 1], connectivity[c, 2]
        d1x = positions[n1, 0] - positions[n0, 0]
        d1y = positions[n1, 1] - positions[n0, 1]
        d1z = positions[n1, 2] - positions[n0, 2]
        d2x = positions[n2, 0] - positions[n0, 0]
        d2y = positions[n2, 1] - positions[n0, 1]
        d2z = positions[n2, 2] - positions[n0, 2]
        v0x, v0y, v0z = directors[n0, 0], directors[n0, 1], directors[n0, 2]
        v1x, v1y, v1z = directors[n1, 0], directors[n1, 1], directors[n1, 2]
        v2x, v2y, v2z = directors[n2, 0], directors[n2, 1], directors[n2, 2]
        w1x, w1y, w1z = half * (v1x - v0x), half * (v1y - v0y), half * (v1z - v0z)
        w2x, w2y, w2z = half * (v2x - v0x), half * (v2y - v0y), half * (v2z - v0z)
        # g3 at the tying points A, B, C: h/2 sum_k N_k(T) V_k
        ax = half * (tying_n[0, 0] * v0x + tying_n[0, 1] * v1x + tying_n[0, 2] * v2x)
        ay = half * (tying_n[0, 0] * v0y + tying_n[0, 1] * v1y + tying_n[0, 2] * v2y)
        az = half * (tying_n[0, 0] * v0z + tying_n[0, 1] * v1z + tying_n[0, 2] * v2z)
        bx = half * (tying_n[1, 0] * v0x + tying_n[1, 1] * v1x + tying_n[1, 2] * v2x)
        by = half * (tying_n[1, 0] * v0y + tying_n[1, 1] * v1y + tying_n[1, 2] * v2y)
        bz = half * (tying_n[1, 0] * v0z + tying_n[1, 1] * v1z + tying_n[1, 2] * v2z)
        cx = half * (tying_n[2, 0] * v0x + tying_n[2, 1] * v1x + tying_n[2, 2] * v2x)
        cy = half * (tying_n[2, 0] * v0y + tying_n[2, 1] * v1y + tying_n[2, 2] * v2y)
        cz = half * (tying_n[2, 0] * v0z + tying_n[2, 1] * v1z + tying_n[2, 2] * v2z)
        t1x = t1y = t1z = t2x = t2y = t2z = 0.0  # sums over z of p1, p2
        a1x = a1y = a1z = a2x = a2y = a2z = 0.0  # sums over z of zeta p1, zeta p2
        qax = qay = qaz = qbx = qby = qbz = qcx = qcy = qcz = 0.0  # dW/dg3 at A, B, C
        stored = 0.0  # 2 W
        for z in range(nz):
            zz = zeta[z]
            g1x, g1y, g1z = d1x + zz * w1x, d1y + zz * w1y, d1z + zz * w1z
            g2x, g2y, g2z = d2x + zz * w2x, d2y + zz * w2y, d2z + zz * w2z
            e11 = 0.5 * (g1x * g1x + g1y * g1y + g1z * g1z - ref11[c, z])
            e22 = 0.5 * (g2x * g2x + g2y * g2y + g2z * g2z - ref22[c, z])
            e12 = g1x * g2x + g1y * g2y + g1z * g2z - ref12[c, z]
            ta = 0.5 * (g1x * ax + g1y * ay + g1z * az - ref_tying[c, z, 0])
            tc1 = 0.5 * (g1x * cx + g1y * cy + g1z * cz - ref_tying[c, z, 1])
            tb = 0.5 * (g2x * bx + g2y * by + g2z * bz - ref_tying[c, z, 2])
            tc2 = 0.5 * (g2x * cx + g2y * cy + g2z * cz - ref_tying[c, z, 3])
            s11 = s22 = s12 = 0.0
            y0 = y1 = y2 = y3 = 0.0  # conjugates of the tying values, halved
            for p in range(npts):
                e13 = 2.0 * (
                    ta * shear_a[p, 0] + tc1 * shear_a[p, 1] + tb * shear_a[p, 2]
                    + tc2 * shear_a[p, 3]
                )  # fmt: skip
                e23 = 2.0 * (
                    ta * shear_b[p, 0] + tc1 * shear_b[p, 1] + tb * shear_b[p, 2]
                    + tc2 * shear_b[p, 3]
                )  # fmt: skip
                k = stiffness[c, p, z]
                r0 = k[0, 0] * e11 + k[0, 1] * e22 + k[0, 2] * e12 + k[0, 3] * e13 + k[0, 4] * e23
                r1 = k[1, 0] * e11 + k[1, 1] * e22 + k[1, 2] * e12 + k[1, 3] * e13 + k[1, 4] * e23
                r2 = k[2, 0] * e11 + k[2, 1] * e22 + k[2, 2] * e12 + k[2, 3] * e13 + k[2, 4] * e23
                r3 = k[3, 0] * e11 + k[3, 1] * e22 + k[3, 2] * e12 + k[3, 3] * e13 + k[3, 4] * e23
                r4 = k[4, 0] * e11 + k[4, 1] * e22 + k[4, 2] * e12 + k[4, 3] * e13 + k[4, 4] * e23
                stored += e11 * r0 + e22 * r1 + e12 * r2 + e13 * r3 + e23 * r4
                s11 += r0
                s22 += r1
                s12 += r2
                y0 += r3 * shear_a[p, 0] + r4 * shear_b[p, 0]
                y1 += r3 * shear_a[p, 1] + r4 * shear_b[p, 1]
                y2 += r3 * shear_a[p, 2] + r4 * shear_b[p, 2]
                y3 += r3 * shear_a[p, 3] + r4 * shear_b[p, 3]
            if not with_forces:
                continue
            p1x = s11 * g1x + s12 * g2x + y0 * ax + y1 * cx
            p1y = s11 * g1y + s12 * g2y + y0 * ay + y1 * cy
            p1z = s11 * g1z + s12 * g2z + y0 * az + y1 * cz
            p2x = s22 * g2x + s12 * g1x + y2 * bx + y3 * cx
            p2y = s22 * g2y + s12 * g1y + y2 * by + y3 * cy
            p2z = s22 * g2z + s12 * g1z + y2 * bz + y3 * cz
            t1x += p1x
            t1y += p1y
            t1z += p1z
            t2x += p2x
            t2y += p2y
            t2z += p2z
            a1x += zz * p1x
            a1y += zz * p1y
            a1z += zz * p1z
            a2x += zz * p2x
            a2y += zz * p2y
            a2z += zz * p2z
            qax += y0 * g1x
            qay += y0 * g1y
            qaz += y0 * g1z
            qbx += y2 * g2x
            qby += y2 * g2y
            qbz += y2 * g2z
            qcx += y1 * g1x + y3 * g2x
            qcy += y1 * g1y + y3 * g2y
            qcz += y1 * g1z + y3 * g2z
        energy[c] = 0.5 * stored
        if not with_forces:
            continue
        force[c, 0, 0] = -(t1x + t2x)
        force[c, 0, 1] = -(t1y + t2y)
        force[c, 0, 2] = -(t1z + t2z)
        force[c, 1, 0] = t1x
        force[c, 1, 1] = t1y
        force[c, 1, 2] = t1z
        force[c, 2, 0] = t2x
        force[c, 2, 1] = t2y
        force[c, 2, 2] = t2z
        for node_k in range(3):
            # dW/dV_k: the in-plane levels' part, then g3^T = h/2 sum_k N_k(T) V_k
            if node_k == 0:
                ux, uy, uz = -half * (a1x + a2x), -half * (a1y + a2y), -half * (a1z + a2z)
                vx, vy, vz = v0x, v0y, v0z
            elif node_k == 1:
                ux, uy, uz = half * a1x, half * a1y, half * a1z
                vx, vy, vz = v1x, v1y, v1z
            else:
                ux, uy, uz = half * a2x, half * a2y, half * a2z
                vx, vy, vz = v2x, v2y, v2z
            na, nb, nc = tying_n[0, node_k], tying_n[1, node_k], tying_n[2, node_k]
            ux += half * (na * qax + nb * qbx + nc * qcx)
            uy += half * (na * qay + nb * qby + nc * qcy)
            uz += half * (na * qaz + nb * qbz + nc * qcz)
            moment[c, node_k, 0] = vy * uz - vz * uy
            moment[c, node_k, 1] = vz * ux - vx * uz
            moment[c, node_k, 2] = vx * uy - vy * ux


@_serial
def _scatter(connectivity, per_cell, out):
    """out[node] += per_cell[c, k] for node = connectivity[c, k] (serial: no races)."""
    for c in range(connectivity.shape[0]):
        for k in range(connectivity.shape[1]):
            node = connectivity[c, k]
            for i in range(3):
                out[node, i] += per_cell[c, k, i]


def _run_mindlin(block, positions, directors, with_forces: bool):
    m = len(block.connectivity)
    shape = (m, 3, 3) if with_forces else (0, 3, 3)
    force, moment, energy = np.empty(shape), np.empty(shape), np.empty(m)
    ref = block.reference_metric
    _mindlin_cells(
        np.ascontiguousarray(positions, dtype=np.float64),
        np.ascontiguousarray(directors, dtype=np.float64),
        block.connectivity,
        block.zeta,
        0.5 * block.h,
        ref["11"],
        ref["22"],
        ref["12"],
        ref["tying"],
        block.shear_a,
        block.shear_b,
        block.weighted_stiffness,
        block.tying_n,
        with_forces,
        force,
        moment,
        energy,
    )
    return force, moment, energy


def mindlin_loads(block, positions: np.ndarray, directors: np.ndarray):
    """Nodal internal forces and director moments (n, 3) of a MindlinShellBlock by the
    compiled kernel."""
    force, moment, _ = _run_mindlin(block, positions, directors, True)
    nodal_force = np.zeros((block.n_nodes, 3))
    nodal_moment = np.zeros((block.n_nodes, 3))
    _scatter(block.connectivity, force, nodal_force)
    _scatter(block.connectivity, moment, nodal_moment)
    return nodal_force, nodal_moment


def mindlin_energy(block, positions: np.ndarray, directors: np.ndarray) -> float:
    """Strain energy (N mm) of a MindlinShellBlock by the compiled kernel."""
    return float(_run_mindlin(block, positions, directors, False)[2].sum())


@_serial
def _cable_forces(positions, connectivity, rest_length, axial_stiffness, tension_only, out):
    """Nodal forces (n, 3) of 2-node cables, N = EA (l / L0 - 1) along the chord (elements/
    cable.py), gathered, computed and scattered in one serial loop (a cell's work is too small
    to share between threads)."""
    for c in range(connectivity.shape[0]):
        a, b = connectivity[c, 0], connectivity[c, 1]
        dx = positions[b, 0] - positions[a, 0]
        dy = positions[b, 1] - positions[a, 1]
        dz = positions[b, 2] - positions[a, 2]
        length = np.sqrt(dx * dx + dy * dy + dz * dz)
        force = axial_stiffness * (length / rest_length[c] - 1.0)
        if tension_only and force < 0.0:
            force = 0.0
        scale = force / length
        out[a, 0] -= scale * dx
        out[a, 1] -= scale * dy
        out[a, 2] -= scale * dz
        out[b, 0] += scale * dx
        out[b, 1] += scale * dy
        out[b, 2] += scale * dz


def cable_forces(block, positions: np.ndarray) -> np.ndarray:
    """Nodal internal forces (n, 3) of a CableBlock by the compiled kernel."""
    out = np.zeros((block.scatter.n_nodes, 3))
    _cable_forces(
        np.ascontiguousarray(positions, dtype=np.float64),
        block.connectivity,
        block.rest_length,
        float(block.axial_stiffness),
        bool(block.tension_only),
        out,
    )
    return out


# ---------------------------------------------------------------------- fibrous shell pieces
@_serial
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


@_serial
def _unit_normal(x, c):
    """(n_x, n_y, n_z, |c|) of cell c with corners x (m, 3, 3): c = (x1 - x0) x (x2 - x0)."""
    ax, ay, az, bx, by, bz = _edges(x, c)
    cx, cy, cz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
    size = np.sqrt(cx * cx + cy * cy + cz * cz)
    return cx / size, cy / size, cz / size, size


@_serial
def _add_cross_pull(x, c, gx, gy, gz, force):
    """force[c] += d(g . c)/dx at the corners of cell c, g held: b x g on x1, g x a on x2
    (a = x1 - x0, b = x2 - x0), minus their sum on x0 (fibrous.py ``_cross_product_pull``)."""
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


@_serial
def _corner(x, c, k):
    """The angle alpha_k of cell c at corner k and its two edges u = x_(k+1) - x_k and
    w = x_(k+2) - x_k: (alpha, ux, uy, uz, wx, wy, wz)."""
    q, r = (k + 1) % 3, (k + 2) % 3
    ux = x[c, q, 0] - x[c, k, 0]
    uy = x[c, q, 1] - x[c, k, 1]
    uz = x[c, q, 2] - x[c, k, 2]
    wx = x[c, r, 0] - x[c, k, 0]
    wy = x[c, r, 1] - x[c, k, 1]
    wz = x[c, r, 2] - x[c, k, 2]
    sx, sy, sz = uy * wz - uz * wy, uz * wx - ux * wz, ux * wy - uy * wx
    angle = np.arctan2(np.sqrt(sx * sx + sy * sy + sz * sz), ux * wx + uy * wy + uz * wz)
    return angle, ux, uy, uz, wx, wy, wz


@_jit
def _corner_shares(x, shares):
    """Each cell's share of the nodal normal sums, alpha_k n (m, 3, 3): its unit normal
    weighted by its angle at corner k (elements/fibrous.py ``_corner_normals``)."""
    for c in prange(x.shape[0]):
        nx, ny, nz, _ = _unit_normal(x, c)
        for k in range(3):
            angle = _corner(x, c, k)[0]
            shares[c, k, 0] = angle * nx
            shares[c, k, 1] = angle * ny
            shares[c, k, 2] = angle * nz


def corner_shares(positions: np.ndarray, connectivity: np.ndarray) -> np.ndarray:
    """alpha_k n (m, 3, 3) of each cell by the compiled loop."""
    shares = np.empty((len(connectivity), 3, 3))
    _corner_shares(np.ascontiguousarray(positions[connectivity], dtype=np.float64), shares)
    return shares


@_jit
def _corner_normal_pull(x, pull, force):
    """sum_k pull_k . d(alpha_k n)/dx_j at the corners of each cell (elements/fibrous.py
    ``_corner_normal_pull``): x, pull (m, 3, 3) -> force (m, 3, 3)."""
    for c in prange(x.shape[0]):
        nx, ny, nz, size = _unit_normal(x, c)
        for j in range(3):
            force[c, j, 0] = 0.0
            force[c, j, 1] = 0.0
            force[c, j, 2] = 0.0
        gx = gy = gz = 0.0
        for k in range(3):
            q, r = (k + 1) % 3, (k + 2) % 3
            angle, ux, uy, uz, wx, wy, wz = _corner(x, c, k)
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
            weight = pull[c, k, 0] * nx + pull[c, k, 1] * ny + pull[c, k, 2] * nz
            force[c, q, 0] += weight * tx
            force[c, q, 1] += weight * ty
            force[c, q, 2] += weight * tz
            force[c, r, 0] += weight * vx
            force[c, r, 1] += weight * vy
            force[c, r, 2] += weight * vz
            force[c, k, 0] -= weight * (tx + vx)
            force[c, k, 1] -= weight * (ty + vy)
            force[c, k, 2] -= weight * (tz + vz)
            gx += angle * pull[c, k, 0]
            gy += angle * pull[c, k, 1]
            gz += angle * pull[c, k, 2]
        along = gx * nx + gy * ny + gz * nz
        gx, gy, gz = (gx - along * nx) / size, (gy - along * ny) / size, (gz - along * nz) / size
        _add_cross_pull(x, c, gx, gy, gz, force)


def corner_normal_pull(x: np.ndarray, pull: np.ndarray) -> np.ndarray:
    """The compiled ``_corner_normal_pull`` of elements/fibrous.py: (m, 3, 3)."""
    force = np.empty_like(x)
    _corner_normal_pull(
        np.ascontiguousarray(x, dtype=np.float64),
        np.ascontiguousarray(pull, dtype=np.float64),
        force,
    )
    return force


@_jit
def _fibrous_geometry(
    x, v, sums, nodal, thickness, guard, zeta, reference_length1, reference_length2,
    shear_sign, reference_shear, normal, double_area, node_normal, normal_sum_length, cosine,
    h_m, guarded, g1, g2, length1, length2, fibre1, fibre2, eps1, eps2, gamma,
):  # fmt: skip
    """elements/fibrous.py ``_cell_geometry`` and ``_strains`` in one loop per cell: the
    element normal and area, the cosine of each director with its normal (the nodal normal
    S_k / |S_k| when ``nodal``, else the element's), h_m = h / max(cos, guard), the level
    vectors g1, g2 (m, L, 3) and the log strains and shear angles (m, L). Every output array
    is written."""
    levels = zeta.shape[0]
    for c in prange(x.shape[0]):
        nx, ny, nz, size = _unit_normal(x, c)
        normal[c, 0], normal[c, 1], normal[c, 2] = nx, ny, nz
        double_area[c] = size
        for k in range(3):
            if nodal:
                sx, sy, sz = sums[c, k, 0], sums[c, k, 1], sums[c, k, 2]
                length = np.sqrt(sx * sx + sy * sy + sz * sz)
                node_normal[c, k, 0] = sx / length
                node_normal[c, k, 1] = sy / length
                node_normal[c, k, 2] = sz / length
                normal_sum_length[c, k] = length
                cos = (v[c, k, 0] * sx + v[c, k, 1] * sy + v[c, k, 2] * sz) / length
            else:
                cos = v[c, k, 0] * nx + v[c, k, 1] * ny + v[c, k, 2] * nz
            cosine[c, k] = cos
            h_m[c, k] = thickness / max(cos, guard)
            guarded[c, k] = cos < guard
        for f in range(levels):
            half = 0.5 * zeta[f]
            for i in range(3):
                base = x[c, 0, i] + half * h_m[c, 0] * v[c, 0, i]
                g1[c, f, i] = x[c, 1, i] + half * h_m[c, 1] * v[c, 1, i] - base
                g2[c, f, i] = x[c, 2, i] + half * h_m[c, 2] * v[c, 2, i] - base
            p1 = g1[c, f, 0] * g1[c, f, 0] + g1[c, f, 1] * g1[c, f, 1] + g1[c, f, 2] * g1[c, f, 2]
            p2 = g2[c, f, 0] * g2[c, f, 0] + g2[c, f, 1] * g2[c, f, 1] + g2[c, f, 2] * g2[c, f, 2]
            l1, l2 = np.sqrt(p1), np.sqrt(p2)
            length1[c, f], length2[c, f] = l1, l2
            if nodal:
                # the length of g_a projected on the element's plane (docs/theory.md §2.2)
                q1 = g1[c, f, 0] * nx + g1[c, f, 1] * ny + g1[c, f, 2] * nz
                q2 = g2[c, f, 0] * nx + g2[c, f, 1] * ny + g2[c, f, 2] * nz
                e1x, e1y, e1z = g1[c, f, 0] - q1 * nx, g1[c, f, 1] - q1 * ny, g1[c, f, 2] - q1 * nz
                e2x, e2y, e2z = g2[c, f, 0] - q2 * nx, g2[c, f, 1] - q2 * ny, g2[c, f, 2] - q2 * nz
                f1 = np.sqrt(e1x * e1x + e1y * e1y + e1z * e1z)
                f2 = np.sqrt(e2x * e2x + e2y * e2y + e2z * e2z)
            else:
                f1, f2 = l1, l2
            fibre1[c, f], fibre2[c, f] = f1, f2
            eps1[c, f] = np.log(f1 / reference_length1[c, f])
            eps2[c, f] = np.log(f2 / reference_length2[c, f])
            dot = g1[c, f, 0] * g2[c, f, 0] + g1[c, f, 1] * g2[c, f, 1] + g1[c, f, 2] * g2[c, f, 2]
            ratio = min(max(dot / (l1 * l2), -1.0), 1.0)
            gamma[c, f] = shear_sign[c] * np.arcsin(ratio) - reference_shear[c, f]


def fibrous_geometry(block, x: np.ndarray, v: np.ndarray, sums) -> tuple[dict, dict]:
    """(geometry, strains) of elements/fibrous.py ``_cell_geometry`` (with the level vectors)
    and ``_strains`` by the compiled loop; ``sums`` (m, 3, 3) the nodal normal sums at the
    corners, or None for the element normals."""
    m, levels = len(x), len(block.zeta)
    nodal = sums is not None
    out = {
        "normal": np.empty((m, 3)),
        "double_area": np.empty(m),
        "node_normal": np.empty((m, 3, 3) if nodal else (0, 3, 3)),
        "normal_sum_length": np.empty((m, 3) if nodal else (0, 3)),
        "cosine": np.empty((m, 3)),
        "thickness": np.empty((m, 3)),
        "guarded": np.empty((m, 3), dtype=np.bool_),
        "g1": np.empty((m, levels, 3)),
        "g2": np.empty((m, levels, 3)),
    }
    strain = {key: np.empty((m, levels)) for key in _STRAIN_KEYS}
    x = np.ascontiguousarray(x, dtype=np.float64)
    v = np.ascontiguousarray(v, dtype=np.float64)
    _fibrous_geometry(
        x, v, np.ascontiguousarray(sums) if nodal else np.zeros((0, 3, 3)), nodal,
        float(block.fabric.thickness), GUARD, block.zeta, block.reference_length1,
        block.reference_length2, block.shear_sign, block.reference_shear, *out.values(),
        *strain.values(),
    )  # fmt: skip
    geo = {"corners": x, "directors": v, **out}
    if not nodal:
        del geo["node_normal"], geo["normal_sum_length"]
    return geo, strain


_STRAIN_KEYS = ("length1", "length2", "fibre1", "fibre2", "eps1", "eps2", "gamma")


@_jit
def _fibrous_layer_forces(
    x, v, normal, double_area, node_normal, normal_sum_length, cosine, h_m, guarded, g1, g2,
    length1, length2, fibre1, fibre2, scale, t1, t2, shear_moment, zeta, nodal,
    thickness_variation, thickness, force, moment, d_sums,
):  # fmt: skip
    """elements/fibrous.py ``_layer_loads`` (tension and shear) and ``_layer_forces`` in one
    loop per cell, the law values given: t1, t2 (m, L) the tensions along edges 0-1 and 0-2,
    shear_moment (m, L) the shear moment times the cell's shear sign, scale (m, L) = A0 w_f.
    Writes force, moment and d_sums (dW/dS_k, zero without nodal normals), (m, 3, 3)."""
    levels = zeta.shape[0]
    for c in prange(x.shape[0]):
        nx, ny, nz = normal[c, 0], normal[c, 1], normal[c, 2]
        s1x = s1y = s1z = s2x = s2y = s2z = 0.0  # sum_f P_a
        a1x = a1y = a1z = a2x = a2y = a2z = 0.0  # sum_f zeta_f P_a
        lx = ly = lz = 0.0  # dW/dn
        for f in range(levels):
            g1x, g1y, g1z = g1[c, f, 0], g1[c, f, 1], g1[c, f, 2]
            g2x, g2y, g2z = g2[c, f, 0], g2[c, f, 1], g2[c, f, 2]
            w = scale[c, f]
            if nodal:
                q1 = g1x * nx + g1y * ny + g1z * nz
                q2 = g2x * nx + g2y * ny + g2z * nz
                k1 = w * t1[c, f] / (fibre1[c, f] * fibre1[c, f])
                k2 = w * t2[c, f] / (fibre2[c, f] * fibre2[c, f])
                e1x, e1y, e1z = g1x - q1 * nx, g1y - q1 * ny, g1z - q1 * nz
                e2x, e2y, e2z = g2x - q2 * nx, g2y - q2 * ny, g2z - q2 * nz
                p1x, p1y, p1z = k1 * e1x, k1 * e1y, k1 * e1z
                p2x, p2y, p2z = k2 * e2x, k2 * e2y, k2 * e2z
                lx -= k1 * q1 * e1x + k2 * q2 * e2x
                ly -= k1 * q1 * e1y + k2 * q2 * e2y
                lz -= k1 * q1 * e1z + k2 * q2 * e2z
            else:
                k1 = w * t1[c, f] / (fibre1[c, f] * fibre1[c, f])
                k2 = w * t2[c, f] / (fibre2[c, f] * fibre2[c, f])
                p1x, p1y, p1z = k1 * g1x, k1 * g1y, k1 * g1z
                p2x, p2y, p2z = k2 * g2x, k2 * g2y, k2 * g2z
            l1, l2 = length1[c, f], length2[c, f]
            u1x, u1y, u1z = g1x / l1, g1y / l1, g1z / l1
            u2x, u2y, u2z = g2x / l2, g2y / l2, g2z / l2
            cos = u1x * u2x + u1y * u2y + u1z * u2z
            sin = np.sqrt(max(1.0 - cos * cos, 1e-24))
            m1 = w * shear_moment[c, f] / (l1 * sin)
            m2 = w * shear_moment[c, f] / (l2 * sin)
            p1x += m1 * (u2x - cos * u1x)
            p1y += m1 * (u2y - cos * u1y)
            p1z += m1 * (u2z - cos * u1z)
            p2x += m2 * (u1x - cos * u2x)
            p2y += m2 * (u1y - cos * u2y)
            p2z += m2 * (u1z - cos * u2z)
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
        force[c, 0, 0], force[c, 0, 1], force[c, 0, 2] = -(s1x + s2x), -(s1y + s2y), -(s1z + s2z)
        force[c, 1, 0], force[c, 1, 1], force[c, 1, 2] = s1x, s1y, s1z
        force[c, 2, 0], force[c, 2, 1], force[c, 2, 2] = s2x, s2y, s2z
        # the corners pull on c = a x b with g: b x g on x1, g x a on x2, minus both on x0
        gx = gy = gz = 0.0
        if nodal:
            along = lx * nx + ly * ny + lz * nz
            gx = (lx - along * nx) / double_area[c]
            gy = (ly - along * ny) / double_area[c]
            gz = (lz - along * nz) / double_area[c]
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
            if thickness_variation:
                dw_dh = 0.5 * (rx * vx + ry * vy + rz * vz)
                ck = cosine[c, k]
                dw_dc = 0.0 if guarded[c, k] else -dw_dh * thickness / (ck * ck)
                if nodal:
                    wx, wy, wz = node_normal[c, k, 0], node_normal[c, k, 1], node_normal[c, k, 2]
                    factor = dw_dc / normal_sum_length[c, k]
                    dsx = factor * (vx - ck * wx)
                    dsy = factor * (vy - ck * wy)
                    dsz = factor * (vz - ck * wz)
                else:
                    wx, wy, wz = nx, ny, nz
                    gx += dw_dc * (vx - ck * nx) / double_area[c]
                    gy += dw_dc * (vy - ck * ny) / double_area[c]
                    gz += dw_dc * (vz - ck * nz) / double_area[c]
                mx += dw_dc * (vy * wz - vz * wy)
                my += dw_dc * (vz * wx - vx * wz)
                mz += dw_dc * (vx * wy - vy * wx)
            moment[c, k, 0], moment[c, k, 1], moment[c, k, 2] = mx, my, mz
            d_sums[c, k, 0], d_sums[c, k, 1], d_sums[c, k, 2] = dsx, dsy, dsz
        _add_cross_pull(x, c, gx, gy, gz, force)


def fibrous_layer_forces(block, geo: dict, strain: dict, tensions, shear_moment):
    """(force, moment, d_sums) (m, 3, 3) of ``_layer_forces(geo, *_layer_loads(geo,
    strain))`` by the compiled loop, with the laws' values ``tensions`` = (t1, t2) and the
    signed ``shear_moment`` (m, L) computed by the caller."""
    m = len(geo["corners"])
    nodal = "node_normal" in geo
    force, moment, d_sums = np.empty((m, 3, 3)), np.empty((m, 3, 3)), np.empty((m, 3, 3))
    empty = np.zeros((0, 3, 3))
    _fibrous_layer_forces(
        geo["corners"], geo["directors"], geo["normal"], geo["double_area"],
        geo["node_normal"] if nodal else empty,
        geo["normal_sum_length"] if nodal else np.zeros((0, 3)),
        geo["cosine"], geo["thickness"], geo["guarded"], geo["g1"], geo["g2"],
        strain["length1"], strain["length2"], strain["fibre1"], strain["fibre2"],
        block.reference_area[:, None] * block.weights[None, :], tensions[0], tensions[1],
        shear_moment, block.zeta, nodal, block.thickness_variation,
        float(block.fabric.thickness), force, moment, d_sums,
    )  # fmt: skip
    return force, moment, d_sums if nodal else None


@_jit
def _cell_normals(x, normal, double_area):
    """Unit normals (m, 3) and double areas (m,) of the cells with corners x (m, 3, 3)."""
    for c in prange(x.shape[0]):
        normal[c, 0], normal[c, 1], normal[c, 2], double_area[c] = _unit_normal(x, c)


@_jit
def _bending_sides(
    x, normal, double_area, across_cell, interior, clamped, wall, fold, coefficients, gradient
):  # fmt: skip
    """elements/fibrous.py ``_bending_geometry`` per cell: the fold angle theta_s of each side
    against the neighbour across it (or the wall of the reference plane on a clamped side),
    the curvature coefficients c_as (m, 2, 3) and the gradient D[s, k] (m, 3, 3)."""
    for c in prange(x.shape[0]):
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
            has_fold = interior[c, s] or clamped[c, s]
            if not has_fold:
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


def bending_geometry(block, positions: np.ndarray) -> dict:
    """elements/fibrous.py ``_bending_geometry`` by the compiled loops."""
    x = np.ascontiguousarray(positions[block.connectivity], dtype=np.float64)
    m = len(x)
    normal, double_area = np.empty((m, 3)), np.empty(m)
    _cell_normals(x, normal, double_area)
    fold, coefficients, gradient = np.empty((m, 3)), np.empty((m, 2, 3)), np.empty((m, 3, 3))
    _bending_sides(
        x, normal, double_area, block._across_cell, block.interior_side, block.clamped_side,
        block.reference_normal, fold, coefficients, gradient,
    )  # fmt: skip
    return {"fold": fold, "coefficients": coefficients, "gradient": gradient, "normal": normal}


@_jit
def _bending_pull(moments, coefficients, area, across_cell, across_side, interior, gradient,
                  normal, own, force):  # fmt: skip
    """elements/fibrous.py ``_bending_forces`` from the moments M (m, 2): each side's moment
    (this cell's -A0 sum_a M_a c_as plus the neighbour's across it) times D[s, k] n."""
    m = moments.shape[0]
    for c in prange(m):
        for s in range(3):
            own[c, s] = -area[c] * (
                moments[c, 0] * coefficients[c, 0, s] + moments[c, 1] * coefficients[c, 1, s]
            )
    for c in prange(m):
        w0 = w1 = w2 = 0.0
        for s in range(3):
            side = own[c, s]
            if interior[c, s]:
                side += own[across_cell[c, s], across_side[c, s]]
            w0 += side * gradient[c, s, 0]
            w1 += side * gradient[c, s, 1]
            w2 += side * gradient[c, s, 2]
        for i in range(3):
            force[c, 0, i] = w0 * normal[c, i]
            force[c, 1, i] = w1 * normal[c, i]
            force[c, 2, i] = w2 * normal[c, i]


def bending_forces(block, moments, coefficients, bend: dict) -> np.ndarray:
    """The compiled tail of elements/fibrous.py ``_bending_forces``: (m, 3, 3)."""
    m = len(moments)
    own, force = np.empty((m, 3)), np.empty((m, 3, 3))
    _bending_pull(
        np.ascontiguousarray(moments), np.ascontiguousarray(coefficients), block.reference_area,
        block._across_cell, block._across_side, block.interior_side, bend["gradient"],
        bend["normal"], own, force,
    )  # fmt: skip
    return force
