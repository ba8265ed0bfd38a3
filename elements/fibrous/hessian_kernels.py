"""The compiled cell Hessians of the fibrous shell's tension + shear (docs/theory.md §2.6, §2.7),
one cell at a time: elements/fibrous/tangent.py keeps the numpy reference of each quantity
(``membrane_hessian``, ``corner_normals(x, jacobian=True)``, ``CornerPairs.hessian``) and the
tests compare them to 1e-12 of the largest entry.

``membrane_hessians``: d(dW_e/d(x, psi, S))/d(x, psi, S) of every cell (m, 3, 9, 3, 9) and
dW_e/dS (m, 3, 3), nodal normals. The numpy form makes well over a hundred array passes
over temporaries of up to (m, 15, 27) and (m, 6, 3, 6) numbers; the loop forms a cell's level
Hessians (81 numbers per level) and accumulates them into its 15 x 15 H_w, its 15 x 27
variable Jacobian A, and A^T H_w A over the nonzero rows of A only (at most 6 in a column:
A is +-1 on the edges, dD_k/d(psi_k, S_k) on the director offsets, dn/dx on the normal),
4662 products where the dense 27 x 15 x 27 one takes 17010.

Every array is filled by explicit loops, never by a slice assignment: with slice assignments
in the body of the parallel cell loop, numba 0.68 gave wrong Hessians (its serial build of
the same code gave the right ones).

``normal_share_jacobians``: ds_k/dx_j of the cells' shares s_k = alpha_k n of the normal
sums (m, 3, 3, 3, 3), the wall nodes' rows zeroed.

``pair_sums``: the cells' blocks summed on the node pairs of a CornerPairs pattern, in cell
order (the additions of numpy.bincount, in its order: the same numbers to the last bit);
``pair_hessians`` the cells' Hessians so summed, formed a chunk of cells at a time.
"""

from __future__ import annotations

import math

import numpy as np

from elements.fibrous.compression_floor import strain_floors
from elements.fibrous.packed_laws import law_slope, law_value
from elements.fibrous.tangent_kernels import cell_normal
from elements.shell_geometry import GUARD
from femcore.jit import AVAILABLE, jit, prange, serial

__all__ = [
    "AVAILABLE",
    "CHUNK",
    "membrane_hessians",
    "normal_share_jacobians",
    "pair_hessians",
    "pair_sums",
]

# Cells per chunk of ``pair_hessians`` (their Hessians: 48 MB).
CHUNK = 8192
# Cells per chunk of ``_hessian_cells``'s loop: its scratch (some fifty small arrays) is
# allocated once a chunk, where a cell's own allocations took about a tenth of the loop's
# time (7.0 against 6.3 us a cell on bai-6.1.1's, the same bits; the paper cases' CPU in
# benchmarks/paper_case_cost.py). Passed to the kernel as an argument (numba would freeze a
# global into its cached build).
CELLS_PER_CHUNK = 64

# Structure of A = dw/dq (15 rows w = (e_1, e_2, d_1, d_2, n), 27 columns q = (x, psi, S)
# per corner): the rows of column (corner k, variable j) that can be nonzero.
_COLUMN_ROWS = np.zeros((27, 6), dtype=np.int64)
_COLUMN_COUNT = np.zeros(27, dtype=np.int64)
for _k in range(3):
    for _j in range(9):
        _rows: list[int] = []
        if _j < 3:  # x_k: e_a = x_a - x_0, and n(x)
            _rows += [_j] if _k == 1 else [3 + _j] if _k == 2 else [_j, 3 + _j]
            _rows += [12, 13, 14]
        else:  # (psi_k, S_k): d_a = D_a - D_0
            _rows += [6, 7, 8] if _k == 1 else [9, 10, 11] if _k == 2 else [6, 7, 8, 9, 10, 11]
        _COLUMN_ROWS[9 * _k + _j, : len(_rows)] = _rows
        _COLUMN_COUNT[9 * _k + _j] = len(_rows)


@serial
def _tension_level(g, n, t, t_slope, fibre, scale, hz, edge):
    """hz (3, 3, 3, 3) += the tension part of one fibre's level Hessian in (g_1, g_2, n)
    (tangent.py ``_add_tension_hessians``): P = kappa r, dW/dn = -kappa s r with r = g - s n,
    s = g . n, kappa = A0 w T / l^2, beta = A0 w (T' - 2 T) / l^4."""
    s = g[0] * n[0] + g[1] * n[1] + g[2] * n[2]
    r0, r1, r2 = g[0] - s * n[0], g[1] - s * n[1], g[2] - s * n[2]
    kappa = scale * t / fibre**2
    beta = scale * (t_slope - 2.0 * t) / fibre**4
    r = (r0, r1, r2)
    for i in range(3):
        for j in range(3):
            rr = r[i] * r[j]
            eye = 1.0 if i == j else 0.0
            projector = eye - n[i] * n[j]
            ng = n[i] * g[j]
            hz[edge, i, edge, j] += beta * rr + kappa * projector
            hz[edge, i, 2, j] += -s * beta * rr - kappa * (ng + s * eye)
            hz[2, i, edge, j] += -s * beta * rr - kappa * (r[i] * n[j] + s * projector)
            hz[2, i, 2, j] += s**2 * beta * rr - kappa * (r[i] * g[j] - s * ng - s**2 * eye)


@serial
def _shear_level(g1, g2, len1, len2, moment, moment_slope, scale, hz, u1, u2, grads):
    """hz += the shear part of one level's Hessian (tangent.py ``_add_shear_hessians``):
    P_a = A0 w f(c) dc/dg_a, c = u1 . u2, f = M / s, s = sqrt(1 - c^2); u1, u2 (3,) and
    grads (2, 3) scratch."""
    for i in range(3):
        u1[i] = g1[i] / len1
        u2[i] = g2[i] / len2
    c = u1[0] * u2[0] + u1[1] * u2[1] + u1[2] * u2[2]
    sine2 = 1.0 - c**2
    s = math.sqrt(max(sine2, 1e-24))
    f = scale * moment / s
    f_slope = scale * (moment_slope / s**2 + (moment * c / s**3 if sine2 > 1e-24 else 0.0))
    for i in range(3):
        grads[0, i] = (u2[i] - c * u1[i]) / len1  # dc/dg1
        grads[1, i] = (u1[i] - c * u2[i]) / len2
    for i in range(3):
        for j in range(3):
            eye = 1.0 if i == j else 0.0
            q1 = (eye - u1[i] * u1[j]) / len1  # du1/dg1
            q2 = (eye - u2[i] * u2[j]) / len2
            second_11 = -(u1[i] * grads[0, j] + c * q1 + grads[0, i] * u1[j]) / len1
            second_12 = (q2 - u1[i] * grads[1, j]) / len1
            second_21 = (q1 - u2[i] * grads[0, j]) / len2
            second_22 = -(u2[i] * grads[1, j] + c * q2 + grads[1, i] * u2[j]) / len2
            hz[0, i, 0, j] += f_slope * grads[0, i] * grads[0, j] + f * second_11
            hz[0, i, 1, j] += f_slope * grads[0, i] * grads[1, j] + f * second_12
            hz[1, i, 0, j] += f_slope * grads[1, i] * grads[0, j] + f * second_21
            hz[1, i, 1, j] += f_slope * grads[1, i] * grads[1, j] + f * second_22


@serial
def _add_level(hz, half, h_w):
    """h_w (15, 15) += a level's hz with the weights (zeta_f / 2)^p, p the number of director
    offsets d among the row and the column (tangent.py ``_level_sums``)."""
    for a in range(3):
        for b in range(3):
            for i in range(3):
                for j in range(3):
                    value = hz[a, i, b, j]
                    if a < 2 and b < 2:
                        h_w[3 * a + i, 3 * b + j] += value
                        h_w[6 + 3 * a + i, 3 * b + j] += half * value
                        h_w[3 * a + i, 6 + 3 * b + j] += half * value
                        h_w[6 + 3 * a + i, 6 + 3 * b + j] += half * half * value
                    elif a < 2:
                        h_w[3 * a + i, 12 + j] += value
                        h_w[6 + 3 * a + i, 12 + j] += half * value
                    elif b < 2:
                        h_w[12 + i, 3 * b + j] += value
                        h_w[12 + i, 6 + 3 * b + j] += half * value
                    else:
                        h_w[12 + i, 12 + j] += value


@jit
def _hessian_cells(
    x, v, sums, thickness, guard, zeta, weights, reference_area, reference_length1,
    reference_length2, shear_sign, reference_shear, xi_is_warp, law_integers, law_reals,
    variation, compression_free, floor1, floor2, column_rows, column_count, out, d_sums, size,
):  # fmt: skip
    """out (m, 27, 27): each cell's Hessian in (x, psi, S) per corner (tangent.py
    ``membrane_hessian``), d_sums (m, 3, 3): dW/dS_k; x, v, sums (m, 3, 3) the corners,
    directors and nodal normal sums S_k. ``compression_free``: the tensions of the stress
    terms at the strains raised to at least floor1, floor2 (m, L) (tangent.py
    ``membrane_hessian``). The cells
    in chunks of ``size``, the scratch allocated once a chunk (each cell writes every entry
    it reads, and zeroes those it sums into, as the arrays allocated per cell were)."""
    m = x.shape[0]
    levels = zeta.shape[0]
    for chunk in prange((m + size - 1) // size):
        n = np.empty(3)
        a = np.empty(3)
        b = np.empty(3)
        node_normal = np.empty((3, 3))
        length = np.empty(3)
        cosine = np.empty(3)
        h_m = np.empty(3)
        guarded = np.empty(3, dtype=np.bool_)
        g1 = np.empty(3)
        g2 = np.empty(3)
        p1 = np.empty((levels, 3))
        p2 = np.empty((levels, 3))
        normal_load = np.empty(3)
        hz = np.empty((3, 3, 3, 3))
        h_w = np.empty((15, 15))
        u1 = np.empty(3)
        u2 = np.empty(3)
        shear_u1 = np.empty(3)
        shear_u2 = np.empty(3)
        grads = np.empty((2, 3))
        jac = np.empty((15, 27))
        jac_rows = np.empty((15, 27))
        product = np.empty((15, 27))
        lever = np.empty((3, 3))
        d_director = np.empty((3, 3, 6))
        d_rows = np.empty((3, 3, 6))
        dc = np.empty(3)
        dn = np.empty(3)
        omega = np.empty(3)
        d_omega = np.empty(3)
        da_vec = np.empty(3)
        db_vec = np.empty(3)
        dv = np.empty(3)
        ds = np.empty(3)
        d_nn = np.empty(3)
        # a level's three laws (law1 and law2 along the edges, the shear's 2): the arguments
        # of their values and slopes, the values and slopes. Each law function is spliced
        # once, in a loop over the three: written per law they were spliced 8 times, and
        # numba compiles each copy again (the loop's build 7.0 -> 5.2 s of CPU, as fast,
        # the same bits: benchmarks/hessian_pairs.py).
        at_value = np.empty(3)
        at_slope = np.empty(3)
        value = np.empty(3)
        slope = np.empty(3)
        for cell in range(chunk * size, min(m, (chunk + 1) * size)):
            for c in range(3):
                normal_load[c] = 0.0
            for r in range(15):
                for c in range(15):
                    h_w[r, c] = 0.0
            area2 = cell_normal(x, cell, a, b, n)
            for k in range(3):
                s0, s1, s2 = sums[cell, k, 0], sums[cell, k, 1], sums[cell, k, 2]
                length[k] = math.sqrt(s0 * s0 + s1 * s1 + s2 * s2)
                node_normal[k, 0] = s0 / length[k]
                node_normal[k, 1] = s1 / length[k]
                node_normal[k, 2] = s2 / length[k]
                cosine[k] = (
                    v[cell, k, 0] * node_normal[k, 0]
                    + v[cell, k, 1] * node_normal[k, 1]
                    + v[cell, k, 2] * node_normal[k, 2]
                )
                h_m[k] = thickness / max(cosine[k], guard)
                guarded[k] = cosine[k] < guard
            # The laws of the fibres along edges 0 -> 1 and 0 -> 2: warp (0) and weft (1).
            law1 = 0 if xi_is_warp[cell] else 1
            law2 = 1 - law1
            for f in range(levels):
                scale = reference_area[cell] * weights[f]
                half = 0.5 * zeta[f]
                for c in range(3):
                    layer0 = x[cell, 0, c] + half * h_m[0] * v[cell, 0, c]
                    g1[c] = x[cell, 1, c] + half * h_m[1] * v[cell, 1, c] - layer0
                    g2[c] = x[cell, 2, c] + half * h_m[2] * v[cell, 2, c] - layer0
                len1 = math.sqrt(g1[0] ** 2 + g1[1] ** 2 + g1[2] ** 2)
                len2 = math.sqrt(g2[0] ** 2 + g2[1] ** 2 + g2[2] ** 2)
                along1 = g1[0] * n[0] + g1[1] * n[1] + g1[2] * n[2]
                along2 = g2[0] * n[0] + g2[1] * n[1] + g2[2] * n[2]
                fibre1 = math.sqrt(
                    (g1[0] - along1 * n[0]) ** 2
                    + (g1[1] - along1 * n[1]) ** 2
                    + (g1[2] - along1 * n[2]) ** 2
                )
                fibre2 = math.sqrt(
                    (g2[0] - along2 * n[0]) ** 2
                    + (g2[1] - along2 * n[1]) ** 2
                    + (g2[2] - along2 * n[2]) ** 2
                )
                eps1 = math.log(fibre1 / reference_length1[cell, f])
                eps2 = math.log(fibre2 / reference_length2[cell, f])
                cos12 = (g1[0] * g2[0] + g1[1] * g2[1] + g1[2] * g2[2]) / (len1 * len2)
                gamma = (
                    shear_sign[cell] * math.asin(min(max(cos12, -1.0), 1.0))
                    - reference_shear[cell, f]
                )
                at_slope[0], at_slope[1], at_slope[2] = eps1, eps2, gamma
                if compression_free:  # the stress terms of a slack fibre (tangent.py)
                    at_value[0] = max(eps1, floor1[cell, f])
                    at_value[1] = max(eps2, floor2[cell, f])
                else:
                    at_value[0], at_value[1] = eps1, eps2
                at_value[2] = gamma
                for k in range(3):
                    i = law1 if k == 0 else (law2 if k == 1 else 2)
                    value[k] = law_value(law_integers, law_reals, i, at_value[k])
                    slope[k] = law_slope(law_integers, law_reals, i, at_slope[k])
                t1, t2 = value[0], value[1]
                moment = shear_sign[cell] * value[2]
                # The layer loads P_a = dW/dg_a and dW/dn (membrane.py ``layer_loads``).
                kappa1 = scale * t1 / fibre1**2
                kappa2 = scale * t2 / fibre2**2
                for c in range(3):
                    u1[c] = g1[c] / len1
                    u2[c] = g2[c] / len2
                cu = u1[0] * u2[0] + u1[1] * u2[1] + u1[2] * u2[2]
                sine = math.sqrt(max(1.0 - cu**2, 1e-24))
                shear1 = scale * moment / (len1 * sine)
                shear2 = scale * moment / (len2 * sine)
                for c in range(3):
                    r1 = g1[c] - along1 * n[c]
                    r2 = g2[c] - along2 * n[c]
                    p1[f, c] = kappa1 * r1 + shear1 * (u2[c] - cu * u1[c])
                    p2[f, c] = kappa2 * r2 + shear2 * (u1[c] - cu * u2[c])
                    normal_load[c] -= kappa1 * along1 * r1 + kappa2 * along2 * r2
                for i in range(3):  # (explicit loops: see the module's docstring)
                    for j in range(3):
                        for q in range(3):
                            for r in range(3):
                                hz[i, j, q, r] = 0.0
                # the edges as int64, not constants (numba types a constant argument as a
                # literal and would build the helper once for each)
                _tension_level(
                    g1, n, t1, slope[0], fibre1, scale,
                    hz, np.int64(0),
                )  # fmt: skip
                _tension_level(
                    g2, n, t2, slope[1], fibre2, scale,
                    hz, np.int64(1),
                )  # fmt: skip
                _shear_level(
                    g1, g2, len1, len2, moment, slope[2],
                    scale, hz, shear_u1, shear_u2, grads,
                )  # fmt: skip
                _add_level(hz, half, h_w)
            for r in range(15):
                for c in range(27):
                    jac[r, c] = 0.0
                    jac_rows[r, c] = 0.0
            _jacobians(
                v, cell, a, b, n, area2, node_normal, length, cosine, h_m, guarded, thickness,
                variation, jac, jac_rows, d_director, d_rows, dc, dn,
            )  # fmt: skip
            # A_rows^T H_w A over the nonzero rows of A's columns (A_rows has A's structure).
            for col in range(27):
                for r in range(15):
                    total = 0.0
                    for t in range(column_count[col]):
                        s = column_rows[col, t]
                        total += h_w[r, s] * jac[s, col]
                    product[r, col] = total
            for row in range(27):
                for col in range(27):
                    total = 0.0
                    for t in range(column_count[row]):
                        s = column_rows[row, t]
                        total += jac_rows[s, row] * product[s, col]
                    out[cell, row, col] = total
            _normal_second(
                a, b, n, area2, normal_load, out[cell], omega, dc, dn, d_omega, da_vec, db_vec
            )
            for r in range(3):
                for c in range(3):
                    lever[r, c] = 0.0
            for f in range(levels):
                for c in range(3):
                    lever[1, c] += zeta[f] * p1[f, c]
                    lever[2, c] += zeta[f] * p2[f, c]
            for c in range(3):
                lever[0, c] = -(lever[1, c] + lever[2, c])
            for k in range(3):
                _director_second(
                    v, cell, k, lever, node_normal, length, cosine, h_m, guarded, thickness,
                    variation, out[cell], d_sums[cell], dv, ds, d_nn,
                )  # fmt: skip


@serial
def _jacobians(
    v, cell, a, b, n, area2, node_normal, length, cosine, h_m, guarded, thickness, variation,
    jac, jac_rows, d_director, d_rows, dc, dn,
):  # fmt: skip
    """jac (15, 27) = A = dw/dq and jac_rows the A of the rows (tangent.py
    ``_variable_jacobians``), both zero on entry: +-1 on the edges e_a, dD_k/d(psi_k, S_k)
    on the director offsets d_a (without ``variation`` the rows' h_m [V]x alone), dn/dx_k on
    the normal. Scratch: d_director, d_rows (3, 3, 6) (dD_k/d(psi_k, S_k) and the rows'),
    dc, dn (3,)."""
    for k in range(3):
        vk = (v[cell, k, 0], v[cell, k, 1], v[cell, k, 2])
        nk = (node_normal[k, 0], node_normal[k, 1], node_normal[k, 2])
        v_cross_n = (
            vk[1] * nk[2] - vk[2] * nk[1],
            vk[2] * nk[0] - vk[0] * nk[2],
            vk[0] * nk[1] - vk[1] * nk[0],
        )
        dh_dc = 0.0 if guarded[k] else -thickness / cosine[k] ** 2
        for i in range(3):
            for j in range(3):
                # -h_m [V]x: dD = h_m dpsi x V
                i1, i2 = (i + 1) % 3, (i + 2) % 3
                skew = -vk[i2] if j == i1 else vk[i1] if j == i2 else 0.0
                spin = -h_m[k] * skew
                dc_ds = (vk[j] - cosine[k] * nk[j]) / length[k]
                d_director[k, i, j] = spin + dh_dc * vk[i] * v_cross_n[j]
                d_director[k, i, 3 + j] = dh_dc * vk[i] * dc_ds
                d_rows[k, i, j] = spin
                d_rows[k, i, 3 + j] = 0.0
    if variation:
        for k in range(3):
            for i in range(3):
                for j in range(6):
                    d_rows[k, i, j] = d_director[k, i, j]
    for edge in range(2):
        for i in range(3):
            jac[3 * edge + i, 9 * (edge + 1) + i] = 1.0
            jac[3 * edge + i, i] = -1.0
            jac_rows[3 * edge + i, 9 * (edge + 1) + i] = 1.0
            jac_rows[3 * edge + i, i] = -1.0
            for j in range(6):
                jac[6 + 3 * edge + i, 9 * (edge + 1) + 3 + j] = d_director[edge + 1, i, j]
                jac[6 + 3 * edge + i, 3 + j] = -d_director[0, i, j]
                jac_rows[6 + 3 * edge + i, 9 * (edge + 1) + 3 + j] = d_rows[edge + 1, i, j]
                jac_rows[6 + 3 * edge + i, 3 + j] = -d_rows[0, i, j]
    for k in range(3):
        for c in range(3):
            _normal_change(a, b, n, area2, k, c, dc, dn)
            for i in range(3):
                jac[12 + i, 9 * k + c] = dn[i]
                jac_rows[12 + i, 9 * k + c] = dn[i]


@serial
def _direction_cross(a, b, da, db, c, dc):
    """dc (3,) = (da e_c) x b + a x (db e_c): the change of a x b when a moves by da e_c
    and b by db e_c."""
    c1, c2 = (c + 1) % 3, (c + 2) % 3
    dc[c] = 0.0
    dc[c1] = -da * b[c2] + db * a[c2]
    dc[c2] = da * b[c1] - db * a[c1]


@serial
def _normal_change(a, b, n, area2, node, comp, dc, dn):
    """dc (3,) = d(a x b) and dn (3,) = dn/d(x_node)_comp = P dc / |c| of the cell's unit
    normal n = c / |c|, c = a x b (|c| = area2), for corner ``node`` moved along ``comp``;
    returns d|c| = n . dc."""
    da = (1.0 if node == 1 else 0.0) - (1.0 if node == 0 else 0.0)
    db = (1.0 if node == 2 else 0.0) - (1.0 if node == 0 else 0.0)
    _direction_cross(a, b, da, db, comp, dc)
    d_area2 = n[0] * dc[0] + n[1] * dc[1] + n[2] * dc[2]
    for c in range(3):
        dn[c] = (dc[c] - d_area2 * n[c]) / area2
    return d_area2


@serial
def _normal_second(a, b, n, area2, load, out, omega, dc, dn, d_omega, da_vec, db_vec):
    """out (27, 27) += the second derivatives of n(x) contracted with dW/dn = ``load`` (3,)
    held, on the translation blocks (tangent.py ``_normal_second_derivatives``); omega, dc,
    dn, d_omega, da_vec, db_vec (3,) scratch."""
    n_load = load[0] * n[0] + load[1] * n[1] + load[2] * n[2]
    for c in range(3):
        omega[c] = (load[c] - n_load * n[c]) / area2
    for node in range(3):
        da = (1.0 if node == 1 else 0.0) - (1.0 if node == 0 else 0.0)
        db = (1.0 if node == 2 else 0.0) - (1.0 if node == 0 else 0.0)
        for comp in range(3):
            d_area2 = _normal_change(a, b, n, area2, node, comp, dc, dn)
            load_dn = load[0] * dn[0] + load[1] * dn[1] + load[2] * dn[2]
            for c in range(3):
                d_omega[c] = (-load_dn * n[c] - n_load * dn[c] - omega[c] * d_area2) / area2
                da_vec[c] = da if c == comp else 0.0
                db_vec[c] = db if c == comp else 0.0
            for c in range(3):
                c1, c2 = (c + 1) % 3, (c + 2) % 3
                along_a = (db_vec[c1] * omega[c2] - db_vec[c2] * omega[c1]) + (
                    b[c1] * d_omega[c2] - b[c2] * d_omega[c1]
                )
                along_b = (d_omega[c1] * a[c2] - d_omega[c2] * a[c1]) + (
                    omega[c1] * da_vec[c2] - omega[c2] * da_vec[c1]
                )
                out[c, 9 * node + comp] -= along_a + along_b
                out[9 + c, 9 * node + comp] += along_a
                out[18 + c, 9 * node + comp] += along_b


@serial
def _director_second(
    v, cell, k, lever, node_normal, length, cosine, h_m, guarded, thickness, variation, out,
    d_sums, dv, ds, d_nn,
):  # fmt: skip
    """out (27, 27) += the second derivatives of D_k(psi_k, S_k) with dW/dD_k = lever_k / 2
    held, on corner k's (psi, S) block (tangent.py ``_director_second_derivatives``), and
    d_sums[k] = dW/dS_k (membrane.py ``layer_forces``); dv, ds, d_nn (3,) scratch."""
    vk = (v[cell, k, 0], v[cell, k, 1], v[cell, k, 2])
    nk = (node_normal[k, 0], node_normal[k, 1], node_normal[k, 2])
    lk = (lever[k, 0], lever[k, 1], lever[k, 2])
    cos = cosine[k]
    size = length[k]
    dw_dh = 0.5 * (lk[0] * vk[0] + lk[1] * vk[1] + lk[2] * vk[2])
    dw_dc = 0.0 if guarded[k] else -dw_dh * thickness / cos**2
    for c in range(3):
        d_sums[k, c] = (dw_dc / size) * (vk[c] - cos * nk[c]) if variation else 0.0
    for unit in range(6):
        for c in range(3):
            dv[c] = 0.0
            ds[c] = 0.0
        if unit < 3:  # dpsi = e_unit: dV = e_unit x V
            u1, u2 = (unit + 1) % 3, (unit + 2) % 3
            dv[u1] = -vk[u2]
            dv[u2] = vk[u1]
        else:
            ds[unit - 3] = 1.0
        d_length = nk[0] * ds[0] + nk[1] * ds[1] + nk[2] * ds[2]
        for c in range(3):
            d_nn[c] = (ds[c] - d_length * nk[c]) / size
        d_cos = 0.0
        for c in range(3):
            d_cos += dv[c] * nk[c] + vk[c] * d_nn[c]
        dh = 0.0 if guarded[k] else -thickness * d_cos / cos**2
        column = 9 * k + 3 + unit
        d_dw_dh = 0.5 * (lk[0] * dv[0] + lk[1] * dv[1] + lk[2] * dv[2])
        d_dw_dc = (
            0.0 if guarded[k] else -thickness * (d_dw_dh / cos**2 - 2.0 * dw_dh * d_cos / cos**3)
        )
        for c in range(3):
            c1, c2 = (c + 1) % 3, (c + 2) % 3
            d_moment = 0.5 * (
                dh * (vk[c1] * lk[c2] - vk[c2] * lk[c1])
                + h_m[k] * (dv[c1] * lk[c2] - dv[c2] * lk[c1])
            )
            d_dsums = 0.0
            if variation:
                d_moment += d_dw_dc * (vk[c1] * nk[c2] - vk[c2] * nk[c1]) + dw_dc * (
                    (dv[c1] * nk[c2] - dv[c2] * nk[c1]) + (vk[c1] * d_nn[c2] - vk[c2] * d_nn[c1])
                )
                d_dsums = (d_dw_dc / size - dw_dc * d_length / size**2) * (vk[c] - cos * nk[c]) + (
                    dw_dc / size
                ) * (dv[c] - d_cos * nk[c] - cos * d_nn[c])
            out[9 * k + 3 + c, column] += d_moment
            out[9 * k + 6 + c, column] += d_dsums


def membrane_hessians(
    block,
    x: np.ndarray,
    v: np.ndarray,
    sums: np.ndarray,
    cells: slice | np.ndarray = slice(None),
    compression_free: bool = False,
    floors: tuple[np.ndarray, np.ndarray] | None = None,
):
    """``tangent.membrane_hessian(block, x, v, sums, compression_free, floors)`` by the compiled
    loop: the cells' Hessians (m, 3, 9, 3, 9) in (x, psi, S) per corner (N/mm, N, N mm and per
    unit of S) and dW/dS_k (m, 3, 3), N mm; x, v, sums (m, 3, 3) the corners, directors and
    normal sums (nodal normals) of the block's ``cells`` (a slice or an index array of them,
    all by default)."""
    m = len(x)
    out = np.empty((m, 27, 27))
    d_sums = np.empty((m, 3, 3))
    integers, reals = block.packed_laws
    floor1, floor2 = strain_floors(floors, m, block.zeta.size, cells)
    _hessian_cells(
        np.ascontiguousarray(x, dtype=float),
        np.ascontiguousarray(v, dtype=float),
        np.ascontiguousarray(sums, dtype=float),
        float(block.fabric.thickness),
        GUARD,
        block.zeta,
        block.weights,
        block.reference_area[cells],
        block.reference_length1[cells],
        block.reference_length2[cells],
        block.shear_sign[cells].astype(float),
        block.reference_shear[cells],
        block.xi_is_warp[cells],
        integers,
        reals,
        bool(block.thickness_variation),
        bool(compression_free),
        floor1,
        floor2,
        _COLUMN_ROWS,
        _COLUMN_COUNT,
        out,
        d_sums,
        CELLS_PER_CHUNK,
    )
    return out.reshape(m, 3, 9, 3, 9), d_sums


def pair_hessians(
    block,
    x: np.ndarray,
    v: np.ndarray,
    sums: np.ndarray,
    pairs,
    chunk=CHUNK,
    compression_free: bool = False,
    floors: tuple[np.ndarray, np.ndarray] | None = None,
):
    """The cells' Hessians of ``membrane_hessians`` (with ``compression_free`` and
    ``floors``) summed on the
    node pairs of ``pairs`` (a CornerPairs pattern): (pairs, 9, 9), the numbers of
    ``pairs.hessian`` to the last bit, and dW/dS_k (m, 3, 3). The cells ``chunk`` at a time,
    each chunk's Hessians summed before the next is formed: 5.8 kB a cell of them held at
    once for a chunk, not for the block."""
    m = len(x)
    h_blocks = np.zeros((pairs.n_pairs, 9, 9))
    d_sums = np.empty((m, 3, 3))
    for start in range(0, m, chunk):
        cells = slice(start, min(start + chunk, m))
        hessian, d_sums[cells] = membrane_hessians(
            block, x[cells], v[cells], sums[cells], cells, compression_free, floors
        )
        pair_sums(pairs.slot[cells], hessian, pairs.n_pairs, h_blocks)
    return h_blocks, d_sums


@jit
def _share_jacobian_cells(x, held, out):
    """out (m, 3 k, 3 i, 3 j, 3 c): d(alpha_k n)_i/d(x_j)_c of each cell (geometry.py
    ``corner_normals``), zero on the rows of the corners whose ``held`` (m, 3) is True."""
    m = x.shape[0]
    for cell in prange(m):
        a = np.empty(3)
        b = np.empty(3)
        n = np.empty(3)
        dc = np.empty(3)
        dn = np.empty((3, 3, 3))  # dn_i/d(x_j)_c as (j, c, i)
        d_angle = np.empty((3, 3, 3))  # d alpha_k/d(x_j)_c as (k, j, c)
        angle = np.empty(3)
        u = np.empty(3)
        w = np.empty(3)
        size = cell_normal(x, cell, a, b, n)
        for k in range(3):
            for c in range(3):
                u[c] = x[cell, (k + 1) % 3, c] - x[cell, k, c]
                w[c] = x[cell, (k + 2) % 3, c] - x[cell, k, c]
            u_len = math.sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
            w_len = math.sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2])
            c0 = u[1] * w[2] - u[2] * w[1]
            c1 = u[2] * w[0] - u[0] * w[2]
            c2 = u[0] * w[1] - u[1] * w[0]
            angle[k] = math.atan2(
                math.sqrt(c0 * c0 + c1 * c1 + c2 * c2), u[0] * w[0] + u[1] * w[1] + u[2] * w[2]
            )
            for c in range(3):
                c1_, c2_ = (c + 1) % 3, (c + 2) % 3
                # d_next = -(n x u / |u|) / |u|, d_prev = -(w / |w| x n) / |w|
                d_next = -(n[c1_] * (u[c2_] / u_len) - n[c2_] * (u[c1_] / u_len)) / u_len
                d_prev = -((w[c1_] / w_len) * n[c2_] - (w[c2_] / w_len) * n[c1_]) / w_len
                d_angle[k, (k + 1) % 3, c] = d_next
                d_angle[k, (k + 2) % 3, c] = d_prev
                d_angle[k, k, c] = -(d_next + d_prev)
        for j in range(3):
            da = (1.0 if j == 1 else 0.0) - (1.0 if j == 0 else 0.0)
            db = (1.0 if j == 2 else 0.0) - (1.0 if j == 0 else 0.0)
            for c in range(3):
                _direction_cross(a, b, da, db, c, dc)
                along = n[0] * dc[0] + n[1] * dc[1] + n[2] * dc[2]
                for i in range(3):
                    dn[j, c, i] = (dc[i] - along * n[i]) / size
        for k in range(3):
            for i in range(3):
                for j in range(3):
                    for c in range(3):
                        value = n[i] * d_angle[k, j, c] + angle[k] * dn[j, c, i]
                        out[cell, k, i, j, c] = 0.0 if held[cell, k] else value


def normal_share_jacobians(x: np.ndarray, held: np.ndarray) -> np.ndarray:
    """ds_k/dx_j (m, 3 k, 3, 3 j, 3) of the shares s_k = alpha_k n of each cell's corners
    (``geometry.corner_normals(x, jacobian=True)``), times 0 on the rows of the corners where
    ``held`` (m, 3) bool (the wall nodes, whose sums do not vary); x (m, 3, 3), mm."""
    out = np.empty((len(x), 3, 3, 3, 3))
    _share_jacobian_cells(
        np.ascontiguousarray(x, dtype=float), np.ascontiguousarray(held, dtype=np.bool_), out
    )
    return out


@serial
def _pair_sums(slot, blocks, out):
    """out (pairs, r, c) += the blocks (m, 3, r, 3, c) of each cell's corner pair (k, l)
    at out[slot[cell, k, l]], cells in order."""
    m = slot.shape[0]
    rows, columns = blocks.shape[2], blocks.shape[4]
    for cell in range(m):
        for k in range(3):
            for corner in range(3):
                target = slot[cell, k, corner]
                for r in range(rows):
                    for c in range(columns):
                        out[target, r, c] += blocks[cell, k, r, corner, c]


def pair_sums(
    slot: np.ndarray, blocks: np.ndarray, n_pairs: int, out: np.ndarray | None = None
) -> np.ndarray:
    """The cells' blocks (m, 3, r, 3, c) summed on the node pairs slot (m, 3, 3) of a
    CornerPairs pattern: (n_pairs, r, c), the numbers of ``CornerPairs.hessian`` (its
    bincount adds the same terms in the same order); added to ``out`` when it is given."""
    if out is None:
        out = np.zeros((n_pairs, blocks.shape[2], blocks.shape[4]))
    _pair_sums(
        np.ascontiguousarray(slot, dtype=np.int64), np.ascontiguousarray(blocks, dtype=float), out
    )
    return out
