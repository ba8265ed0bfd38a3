"""Compiled per-element kernels (numba): fused loops over the cells of a block that gather the
nodal values, compute each cell's forces and scatter them, with no temporary arrays over all
cells. Each kernel has a numpy reference in its element class (the ``kernel="numpy"`` path),
and the tests hold the two to 1e-12 of the largest force.

The loops over cells run in parallel (numba's ``prange``, as many threads as
``numba.set_num_threads`` allows) into per-cell buffers; the sums to the nodes are a parallel
loop over nodes after them (``NodeCorners``), each node adding the corners of its cells in cell
order, so that no two threads add to the same node and the sums are those of numpy.bincount.
The fibrous shell's loops are in elements/fibrous/kernels.py; the compilation helpers
(``jit``, ``serial``, ``prange``) in elements/jit.py.
"""

from __future__ import annotations

import numpy as np

from elements.jit import AVAILABLE, jit, prange, serial

__all__ = ["AVAILABLE", "NodeCorners", "cable_forces", "mindlin_energy", "mindlin_loads"]


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


# ---------------------------------------------------------------------- nodes from corners
class NodeCorners:
    """The corners (cell c, local node k) of each node, in cell order: the pattern of the
    parallel passes from cells to nodes.

    Parameters
    ----------
    connectivity : (m, k) int, node ids of each cell.
    n_nodes : number of nodes.
    """

    def __init__(self, connectivity: np.ndarray, n_nodes: int):
        flat = np.asarray(connectivity, dtype=np.int64).ravel()
        self.corners = np.argsort(flat, kind="stable").astype(np.int64)  # c * 3 + k
        self.offsets = np.zeros(n_nodes + 1, dtype=np.int64)
        np.cumsum(np.bincount(flat, minlength=n_nodes), out=self.offsets[1:])

    def sum(self, per_corner: np.ndarray) -> np.ndarray:
        """sum over the corners of each node of per_corner (m, k, 3) -> (n, 3)."""
        out = np.empty((len(self.offsets) - 1, 3))
        _node_sums(self.offsets, self.corners, per_corner.reshape(-1, 3), out)
        return out


@jit
def _node_sums(offsets, corners, per_corner, out):
    """out[node] = sum of per_corner[j] (m * 3, 3) over the node's corners j."""
    for node in prange(out.shape[0]):
        sx = sy = sz = 0.0
        for j in range(offsets[node], offsets[node + 1]):
            corner = corners[j]
            sx += per_corner[corner, 0]
            sy += per_corner[corner, 1]
            sz += per_corner[corner, 2]
        out[node, 0], out[node, 1], out[node, 2] = sx, sy, sz


@jit
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
    return block.node_corners.sum(force), block.node_corners.sum(moment)


def mindlin_energy(block, positions: np.ndarray, directors: np.ndarray) -> float:
    """Strain energy (N mm) of a MindlinShellBlock by the compiled kernel."""
    return float(_run_mindlin(block, positions, directors, False)[2].sum())


@serial
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


# ---------------------------------------------------------------------- contact search
def _closest_on_triangle(p, a, b, c, out):
    """The closest point to p on the triangle (a, b, c), into out (3,): Ericson's Voronoi
    regions (the scalar form of elements.tools.closest_on_triangles)."""
    ab0, ab1, ab2 = b[0] - a[0], b[1] - a[1], b[2] - a[2]
    ac0, ac1, ac2 = c[0] - a[0], c[1] - a[1], c[2] - a[2]
    ap0, ap1, ap2 = p[0] - a[0], p[1] - a[1], p[2] - a[2]
    d1 = ab0 * ap0 + ab1 * ap1 + ab2 * ap2
    d2 = ac0 * ap0 + ac1 * ap1 + ac2 * ap2
    if d1 <= 0.0 and d2 <= 0.0:
        out[0], out[1], out[2] = a[0], a[1], a[2]
        return
    bp0, bp1, bp2 = p[0] - b[0], p[1] - b[1], p[2] - b[2]
    d3 = ab0 * bp0 + ab1 * bp1 + ab2 * bp2
    d4 = ac0 * bp0 + ac1 * bp1 + ac2 * bp2
    if d3 >= 0.0 and d4 <= d3:
        out[0], out[1], out[2] = b[0], b[1], b[2]
        return
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        t = d1 / (d1 - d3)
        out[0], out[1], out[2] = a[0] + t * ab0, a[1] + t * ab1, a[2] + t * ab2
        return
    cp0, cp1, cp2 = p[0] - c[0], p[1] - c[1], p[2] - c[2]
    d5 = ab0 * cp0 + ab1 * cp1 + ab2 * cp2
    d6 = ac0 * cp0 + ac1 * cp1 + ac2 * cp2
    if d6 >= 0.0 and d5 <= d6:
        out[0], out[1], out[2] = c[0], c[1], c[2]
        return
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        t = d2 / (d2 - d6)
        out[0], out[1], out[2] = a[0] + t * ac0, a[1] + t * ac1, a[2] + t * ac2
        return
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and (d4 - d3) >= 0.0 and (d5 - d6) >= 0.0:
        t = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        out[0] = b[0] + t * (c[0] - b[0])
        out[1] = b[1] + t * (c[1] - b[1])
        out[2] = b[2] + t * (c[2] - b[2])
        return
    denominator = va + vb + vc
    v, w = vb / denominator, vc / denominator
    out[0] = a[0] + v * ab0 + w * ac0
    out[1] = a[1] + v * ab1 + w * ac1
    out[2] = a[2] + v * ab2 + w * ac2


_closest_on_triangle = serial(_closest_on_triangle)


def _closest_facets(x, corners, start, facets, point, facet, gap):
    """For each point x[i] (k, 3), the closest point on its candidate facets
    facets[start[i]:start[i + 1]] of corners (f, 3, 3): into point (k, 3), facet (k,) and
    gap (k,) (the distance)."""
    for i in prange(x.shape[0]):
        trial = np.empty(3)
        best = np.inf
        for j in range(start[i], start[i + 1]):
            f = facets[j]
            _closest_on_triangle(x[i], corners[f, 0], corners[f, 1], corners[f, 2], trial)
            d = (trial[0] - x[i, 0]) ** 2 + (trial[1] - x[i, 1]) ** 2 + (trial[2] - x[i, 2]) ** 2
            if d < best:
                best = d
                facet[i] = f
                point[i, 0], point[i, 1], point[i, 2] = trial[0], trial[1], trial[2]
        gap[i] = np.sqrt(best)


closest_facets = jit(_closest_facets)
