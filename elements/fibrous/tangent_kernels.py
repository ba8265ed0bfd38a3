"""Compiled loops of the fibrous shell's tangent (elements/fibrous/tangent.py keeps the numpy
reference of each and the tests compare them to 1e-12).

``normal_pull_stiffness``: ``tangent.corner_normal_pull_tangent``, the stiffness of the
nodal normals' second derivatives sum_k T_k . d2(alpha_k n)/dx2 with the pulls T held, one
cell at a time: its numpy form differentiates every formula in the 9 unit directions of the
corners at once, about 60 array passes over (m, 9, 3, 3) temporaries, where the loop forms
each cell's 81 numbers in registers.

``share_stiffness``: ``bending.share_tangent``, d/dx of each element's own share of the
bending forces sum_s mu_s D[s, k] n with the side moments mu_s held, the same way.

``MembraneProduct``: J^T H J of ``tangent.nodal_membrane_tangent`` with the shape of J used:
each of its 9 x 6 node blocks is the identity (u, psi) on the diagonal plus dS_k/dx_j in three
rows and three columns, so H J and J^T (H J) take a sixth of the products of general 9 x 9 by
9 x 6 block products (scipy's BSR product multiplies the stored zeros too). Its loops are
elements/fibrous/row_product.py's over every row (one kernel for the whole product and for
the stable-step bound's rows, so that each row is added up alike in both).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from elements.fibrous.row_product import RowProduct
from femcore.jit import AVAILABLE, jit, prange, serial

# Cells per chunk of the cell loops: their scratch allocated once a chunk, not once a cell,
# where the allocations took a third of the loops' time (the normal pulls 1.31 against 0.78
# us a cell, the shares 0.89 against 0.57, on bai-6.1.1's; the same bits). Passed to the
# kernels as an argument (numba would freeze a global into its cached build).
CELLS_PER_CHUNK = 64

__all__ = [
    "AVAILABLE",
    "MembraneProduct",
    "cell_normal",
    "normal_pull_stiffness",
    "share_stiffness",
]


@serial
def cell_normal(x, cell, a, b, n):
    """Fill a, b (3,) with the sides from corner 0 to corners 1 and 2 of ``cell`` of x
    (m, 3, 3) and n (3,) with the cell's unit normal a x b / |a x b|; return |a x b|, twice
    the cell's area (mm^2). Called from each cell loop (LLVM inlines it): the same operations
    in the same order as the loops wrote them out."""
    for c in range(3):
        a[c] = x[cell, 1, c] - x[cell, 0, c]
        b[c] = x[cell, 2, c] - x[cell, 0, c]
    n[0] = a[1] * b[2] - a[2] * b[1]
    n[1] = a[2] * b[0] - a[0] * b[2]
    n[2] = a[0] * b[1] - a[1] * b[0]
    size = math.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
    for c in range(3):
        n[c] /= size
    return size


@jit
def _normal_pull_cells(x, pull, out, per_chunk):
    """out (m, 3 k, 3 i, 3 j, 3 c): d(force_k,i)/d(x_j,c) of the corner-normal pulls of each
    cell, x (m, 3, 3) its corners, pull (m, 3, 3) the pulls T_k held; the cells in chunks of
    ``per_chunk``, the scratch allocated once a chunk."""
    m = x.shape[0]
    for chunk in prange((m + per_chunk - 1) // per_chunk):
        a = np.empty(3)
        b = np.empty(3)
        n = np.empty(3)
        u = np.empty((3, 3))
        w = np.empty((3, 3))
        d_next = np.empty((3, 3))
        d_prev = np.empty((3, 3))
        angle = np.empty(3)
        u2 = np.empty(3)
        w2 = np.empty(3)
        weight = np.empty(3)
        g0 = np.empty(3)
        g = np.empty(3)
        da = np.empty(3)
        db = np.empty(3)
        dc = np.empty(3)
        dn = np.empty(3)
        du = np.empty((3, 3))
        dw = np.empty((3, 3))
        nxt = np.empty((3, 3))
        prv = np.empty((3, 3))
        dg0 = np.empty(3)
        dg = np.empty(3)
        force = np.empty((3, 3))
        for cell in range(chunk * per_chunk, min(m, (chunk + 1) * per_chunk)):
            for c in range(3):
                g0[c] = 0.0
            size = cell_normal(x, cell, a, b, n)
            for k in range(3):
                for c in range(3):
                    u[k, c] = x[cell, (k + 1) % 3, c] - x[cell, k, c]
                    w[k, c] = x[cell, (k + 2) % 3, c] - x[cell, k, c]
                u2[k] = u[k, 0] * u[k, 0] + u[k, 1] * u[k, 1] + u[k, 2] * u[k, 2]
                w2[k] = w[k, 0] * w[k, 0] + w[k, 1] * w[k, 1] + w[k, 2] * w[k, 2]
                c0 = u[k, 1] * w[k, 2] - u[k, 2] * w[k, 1]
                c1 = u[k, 2] * w[k, 0] - u[k, 0] * w[k, 2]
                c2 = u[k, 0] * w[k, 1] - u[k, 1] * w[k, 0]
                dot = u[k, 0] * w[k, 0] + u[k, 1] * w[k, 1] + u[k, 2] * w[k, 2]
                angle[k] = math.atan2(math.sqrt(c0 * c0 + c1 * c1 + c2 * c2), dot)
                # d_next = -(n x u) / |u|^2, d_prev = -(w x n) / |w|^2
                d_next[k, 0] = -(n[1] * u[k, 2] - n[2] * u[k, 1]) / u2[k]
                d_next[k, 1] = -(n[2] * u[k, 0] - n[0] * u[k, 2]) / u2[k]
                d_next[k, 2] = -(n[0] * u[k, 1] - n[1] * u[k, 0]) / u2[k]
                d_prev[k, 0] = -(w[k, 1] * n[2] - w[k, 2] * n[1]) / w2[k]
                d_prev[k, 1] = -(w[k, 2] * n[0] - w[k, 0] * n[2]) / w2[k]
                d_prev[k, 2] = -(w[k, 0] * n[1] - w[k, 1] * n[0]) / w2[k]
                weight[k] = (
                    pull[cell, k, 0] * n[0] + pull[cell, k, 1] * n[1] + pull[cell, k, 2] * n[2]
                )
                for c in range(3):
                    g0[c] += angle[k] * pull[cell, k, c]
            along = g0[0] * n[0] + g0[1] * n[1] + g0[2] * n[2]
            for c in range(3):
                g[c] = (g0[c] - along * n[c]) / size
            for node in range(3):  # the direction: corner node moved along component comp
                for comp in range(3):
                    for c in range(3):
                        da[c] = 0.0
                        db[c] = 0.0
                    unit_a = (1.0 if node == 1 else 0.0) - (1.0 if node == 0 else 0.0)
                    unit_b = (1.0 if node == 2 else 0.0) - (1.0 if node == 0 else 0.0)
                    da[comp] = unit_a
                    db[comp] = unit_b
                    dc[0] = (da[1] * b[2] - da[2] * b[1]) + (a[1] * db[2] - a[2] * db[1])
                    dc[1] = (da[2] * b[0] - da[0] * b[2]) + (a[2] * db[0] - a[0] * db[2])
                    dc[2] = (da[0] * b[1] - da[1] * b[0]) + (a[0] * db[1] - a[1] * db[0])
                    d_size = n[0] * dc[0] + n[1] * dc[1] + n[2] * dc[2]
                    for c in range(3):
                        dn[c] = (dc[c] - d_size * n[c]) / size
                    for c in range(3):
                        dg0[c] = 0.0
                    for k in range(3):
                        for c in range(3):
                            du[k, c] = 0.0
                            dw[k, c] = 0.0
                        moved_next = (1.0 if node == (k + 1) % 3 else 0.0) - (
                            1.0 if node == k else 0.0
                        )
                        moved_prev = (1.0 if node == (k + 2) % 3 else 0.0) - (
                            1.0 if node == k else 0.0
                        )
                        du[k, comp] = moved_next
                        dw[k, comp] = moved_prev
                        d_angle = d_next[k, comp] * moved_next + d_prev[k, comp] * moved_prev
                        u_du = u[k, comp] * moved_next
                        w_dw = w[k, comp] * moved_prev
                        d_weight = pull[cell, k, 0] * dn[0] + pull[cell, k, 1] * dn[1]
                        d_weight += pull[cell, k, 2] * dn[2]
                        # dd_next = -(dn x u + n x du) / |u|^2 - 2 d_next (u . du) / |u|^2
                        # dd_prev = -(dw x n + w x dn) / |w|^2 - 2 d_prev (w . dw) / |w|^2
                        for c in range(3):
                            c1, c2 = (c + 1) % 3, (c + 2) % 3
                            dd_next = (
                                -(
                                    (dn[c1] * u[k, c2] - dn[c2] * u[k, c1])
                                    + (n[c1] * du[k, c2] - n[c2] * du[k, c1])
                                )
                                / u2[k]
                                - 2.0 * d_next[k, c] * u_du / u2[k]
                            )
                            dd_prev = (
                                -(
                                    (dw[k, c1] * n[c2] - dw[k, c2] * n[c1])
                                    + (w[k, c1] * dn[c2] - w[k, c2] * dn[c1])
                                )
                                / w2[k]
                                - 2.0 * d_prev[k, c] * w_dw / w2[k]
                            )
                            nxt[k, c] = d_weight * d_next[k, c] + weight[k] * dd_next
                            prv[k, c] = d_weight * d_prev[k, c] + weight[k] * dd_prev
                            dg0[c] += d_angle * pull[cell, k, c]
                    for k in range(3):
                        for c in range(3):
                            force[k, c] = (
                                -(nxt[k, c] + prv[k, c]) + nxt[(k + 2) % 3, c] + prv[(k + 1) % 3, c]
                            )
                    dg0_n = dg0[0] * n[0] + dg0[1] * n[1] + dg0[2] * n[2]
                    g0_dn = g0[0] * dn[0] + g0[1] * dn[1] + g0[2] * dn[2]
                    for c in range(3):
                        dg[c] = (dg0[c] - (dg0_n + g0_dn) * n[c] - along * dn[c]) / size
                        dg[c] -= g[c] * d_size / size
                    for c in range(3):
                        c1, c2 = (c + 1) % 3, (c + 2) % 3
                        along_a = (db[c1] * g[c2] - db[c2] * g[c1]) + (
                            b[c1] * dg[c2] - b[c2] * dg[c1]
                        )
                        along_b = (dg[c1] * a[c2] - dg[c2] * a[c1]) + (
                            g[c1] * da[c2] - g[c2] * da[c1]
                        )
                        force[0, c] -= along_a + along_b
                        force[1, c] += along_a
                        force[2, c] += along_b
                    for k in range(3):
                        for c in range(3):
                            out[cell, k, c, node, comp] = force[k, c]


def normal_pull_stiffness(x: np.ndarray, pull: np.ndarray) -> np.ndarray:
    """``tangent.corner_normal_pull_tangent(x, pull)`` (m, 3, 3, 3, 3), N per unit of the sums,
    by the compiled loop; x, pull (m, 3, 3)."""
    out = np.empty((len(x), 3, 3, 3, 3))
    _normal_pull_cells(
        np.ascontiguousarray(x, dtype=float),
        np.ascontiguousarray(pull, dtype=float),
        out,
        CELLS_PER_CHUNK,
    )
    return out


@jit
def _share_cells(x, side_moment, out, per_chunk):
    """out (m, 3 k, 3 i, 3 j, 3 c): d(sum_s mu_s D[s, k] n)_i / d(x_j)_c of each cell, x
    (m, 3, 3) its corners, side_moment (m, 3) mu_s held; side s runs from corner s + 1 to
    corner s + 2 (geometry.SIDE_FROM, SIDE_TO); the cells in chunks of ``per_chunk``, the
    scratch allocated once a chunk."""
    m = x.shape[0]
    for chunk in prange((m + per_chunk - 1) // per_chunk):
        a = np.empty(3)
        b = np.empty(3)
        n = np.empty(3)
        side = np.empty((3, 3))
        length = np.empty(3)
        outward = np.empty((3, 3))
        grad_n = np.empty((3, 3))
        w = np.empty(3)
        da = np.empty(3)
        db = np.empty(3)
        dc = np.empty(3)
        dn = np.empty(3)
        d_side = np.empty((3, 3))
        d_length = np.empty(3)
        d_outward = np.empty((3, 3))
        d_grad_n = np.empty((3, 3))
        dw = np.empty(3)
        for cell in range(chunk * per_chunk, min(m, (chunk + 1) * per_chunk)):
            for c in range(3):
                w[c] = 0.0
            area2 = cell_normal(x, cell, a, b, n)
            for s in range(3):
                for c in range(3):
                    side[s, c] = x[cell, (s + 2) % 3, c] - x[cell, (s + 1) % 3, c]
                length[s] = math.sqrt(side[s, 0] ** 2 + side[s, 1] ** 2 + side[s, 2] ** 2)
                for c in range(3):
                    c1, c2 = (c + 1) % 3, (c + 2) % 3
                    outward[s, c] = (side[s, c1] * n[c2] - side[s, c2] * n[c1]) / length[s]
                    grad_n[s, c] = (n[c1] * side[s, c2] - n[c2] * side[s, c1]) / area2
            for s in range(3):
                for k in range(3):
                    dot = outward[s, 0] * grad_n[k, 0] + outward[s, 1] * grad_n[k, 1]
                    dot += outward[s, 2] * grad_n[k, 2]
                    w[k] -= side_moment[cell, s] * dot
            for node in range(3):  # the direction: corner node moved along component comp
                for comp in range(3):
                    for c in range(3):
                        da[c] = 0.0
                        db[c] = 0.0
                    da[comp] = (1.0 if node == 1 else 0.0) - (1.0 if node == 0 else 0.0)
                    db[comp] = (1.0 if node == 2 else 0.0) - (1.0 if node == 0 else 0.0)
                    dc[0] = (da[1] * b[2] - da[2] * b[1]) + (a[1] * db[2] - a[2] * db[1])
                    dc[1] = (da[2] * b[0] - da[0] * b[2]) + (a[2] * db[0] - a[0] * db[2])
                    dc[2] = (da[0] * b[1] - da[1] * b[0]) + (a[0] * db[1] - a[1] * db[0])
                    d_area2 = n[0] * dc[0] + n[1] * dc[1] + n[2] * dc[2]
                    for c in range(3):
                        dn[c] = (dc[c] - d_area2 * n[c]) / area2
                    for s in range(3):
                        for c in range(3):
                            d_side[s, c] = 0.0
                        to_end = 1.0 if node == (s + 2) % 3 else 0.0
                        from_end = 1.0 if node == (s + 1) % 3 else 0.0
                        d_side[s, comp] = to_end - from_end
                        d_length[s] = side[s, comp] * d_side[s, comp] / length[s]
                    for s in range(3):
                        for c in range(3):
                            c1, c2 = (c + 1) % 3, (c + 2) % 3
                            d_outward[s, c] = (
                                (d_side[s, c1] * n[c2] - d_side[s, c2] * n[c1])
                                + (side[s, c1] * dn[c2] - side[s, c2] * dn[c1])
                            ) / length[s] - outward[s, c] * d_length[s] / length[s]
                            d_grad_n[s, c] = (
                                (dn[c1] * side[s, c2] - dn[c2] * side[s, c1])
                                + (n[c1] * d_side[s, c2] - n[c2] * d_side[s, c1])
                            ) / area2 - grad_n[s, c] * (d_area2 / area2)
                    for k in range(3):
                        total = 0.0
                        for s in range(3):
                            d_gradient = 0.0
                            for c in range(3):
                                d_gradient -= d_outward[s, c] * grad_n[k, c]
                                d_gradient -= outward[s, c] * d_grad_n[k, c]
                            total += side_moment[cell, s] * d_gradient
                        dw[k] = total
                    for k in range(3):
                        for c in range(3):
                            out[cell, k, c, node, comp] = dw[k] * n[c] + w[k] * dn[c]


def share_stiffness(x: np.ndarray, side_moment: np.ndarray) -> np.ndarray:
    """``bending.share_tangent(x, side_moment)`` (m, 3, 3, 3, 3), N/mm, by the compiled
    loop; x (m, 3, 3), side_moment (m, 3)."""
    out = np.empty((len(x), 3, 3, 3, 3))
    _share_cells(
        np.ascontiguousarray(x, dtype=float),
        np.ascontiguousarray(side_moment, dtype=float),
        out,
        CELLS_PER_CHUNK,
    )
    return out


class MembraneProduct(RowProduct):
    """J^T H J of the fibrous membrane tangent on the node pairs of the cells (a CornerPairs
    pattern: ``indptr``, ``indices``, symmetric): row_product's rows of every node, the
    patterns of H J and of the product found once (from scipy's product of the patterns)."""

    def __init__(self, indptr: np.ndarray, indices: np.ndarray, n_nodes: int):
        super().__init__(indptr, indices, n_nodes, np.arange(n_nodes))
        self.n = n_nodes
        self.pairs = np.arange(self.indices.size, dtype=np.int64)  # H's block of each pair

    def __call__(self, hessian: np.ndarray, jacobian: np.ndarray) -> sp.bsr_matrix:  # type: ignore[override]
        """J^T H J (6 n, 6 n) as BSR with 6 x 6 blocks, from H's blocks (pairs, 9, 9) and the
        S rows of J's blocks (pairs, 3, 3)."""
        out = super().__call__(hessian, self.pairs, jacobian)
        return sp.bsr_matrix((out, self.k_indices, self.k_indptr), shape=(6 * self.n, 6 * self.n))
