"""The compiled first derivatives of the fibrous shell's level measures, one cell at a time:
level_jacobian.py ``level_strain_gradient`` keeps the numpy reference (its docstring derives
each term) and the tests compare the two to 1e-12 of the largest entry
(tests/test_level_kernels.py).

Why: on Peirce's cantilever (20 x 1 cells, 3 levels) the numpy form is about 60 array
operations on (m, 9, 3, 3) temporaries, 0.35-0.38 ms a sweep of the static solver's level
projection, the largest piece of its CPU (benchmarks/newton_iterations.py line 7); here a
cell's loads, pulls and turns are made in registers and small scratch arrays.

Every array is filled by explicit loops, never by a slice assignment (hessian_kernels.py: a
slice assignment in the body of a parallel cell loop gave wrong numbers with numba 0.68). Each
cell's numbers come from its own corners only, in a fixed order: the same bits on any number of
threads.
"""

from __future__ import annotations

import math

import numpy as np

from elements.fibrous.tangent_kernels import cell_normal
from femcore.jit import AVAILABLE, jit, prange

__all__ = ["AVAILABLE", "level_gradient_cells"]


@jit
def _gradient_cells(
    x, v, sums, nodal, zeta, thickness, shear_sign, guard, direct, turns, through_sums
):
    """Fill direct, turns (m, p, 3, 3) and, with ``nodal``, through_sums (m, p, 3, 3) of
    every cell (level_jacobian.py ``level_strain_gradient``); x, v, sums (m, 3, 3)."""
    m = x.shape[0]
    levels = zeta.shape[0]
    p = 3 * levels
    for cell in prange(m):
        a = np.empty(3)
        b = np.empty(3)
        n = np.empty(3)
        node_normal = np.empty((3, 3))  # N_k, or n at each corner with element normals
        sum_length = np.empty(3)
        cosine = np.empty(3)
        h_m = np.empty(3)
        guarded = np.empty(3, dtype=np.bool_)
        g1 = np.empty(3)
        g2 = np.empty(3)
        p1 = np.empty((p, 3))
        p2 = np.empty((p, 3))
        load = np.empty((p, 3))  # on the normal; with element normals on c (ds_dc pull)
        corner = np.empty((3, 3))
        ds_dc = np.empty(3)
        double_area = cell_normal(x, cell, a, b, n)
        for k in range(3):
            if nodal:
                s0, s1, s2 = sums[cell, k, 0], sums[cell, k, 1], sums[cell, k, 2]
                sum_length[k] = math.sqrt(s0 * s0 + s1 * s1 + s2 * s2)
                for c in range(3):
                    node_normal[k, c] = sums[cell, k, c] / sum_length[k]
            else:
                sum_length[k] = 1.0
                for c in range(3):
                    node_normal[k, c] = n[c]
            cosine[k] = (
                v[cell, k, 0] * node_normal[k, 0]
                + v[cell, k, 1] * node_normal[k, 1]
                + v[cell, k, 2] * node_normal[k, 2]
            )
            h_m[k] = thickness / max(cosine[k], guard)
            guarded[k] = cosine[k] < guard
        for j in range(p):
            for c in range(3):
                p1[j, c] = 0.0
                p2[j, c] = 0.0
                load[j, c] = 0.0
        # The loads of each measure on g_1, g_2 and on n, level by level.
        for level in range(levels):
            half = 0.5 * zeta[level]
            for c in range(3):
                base = x[cell, 0, c] + half * h_m[0] * v[cell, 0, c]
                g1[c] = x[cell, 1, c] + half * h_m[1] * v[cell, 1, c] - base
                g2[c] = x[cell, 2, c] + half * h_m[2] * v[cell, 2, c] - base
            for family in range(2):
                g = g1 if family == 0 else g2
                row = level + family * levels
                if nodal:
                    along = g[0] * n[0] + g[1] * n[1] + g[2] * n[2]
                    i0 = g[0] - along * n[0]
                    i1 = g[1] - along * n[1]
                    i2 = g[2] - along * n[2]
                    coefficient = 1.0 / (i0 * i0 + i1 * i1 + i2 * i2)
                    pulled = coefficient * along
                    target = p1 if family == 0 else p2
                    target[row, 0] = coefficient * i0
                    target[row, 1] = coefficient * i1
                    target[row, 2] = coefficient * i2
                    load[row, 0] = -pulled * i0
                    load[row, 1] = -pulled * i1
                    load[row, 2] = -pulled * i2
                else:
                    coefficient = 1.0 / (g[0] * g[0] + g[1] * g[1] + g[2] * g[2])
                    target = p1 if family == 0 else p2
                    for c in range(3):
                        target[row, c] = g[c] * coefficient
            len1 = math.sqrt(g1[0] * g1[0] + g1[1] * g1[1] + g1[2] * g1[2])
            len2 = math.sqrt(g2[0] * g2[0] + g2[1] * g2[1] + g2[2] * g2[2])
            cos12 = (g1[0] / len1) * (g2[0] / len2)
            cos12 += (g1[1] / len1) * (g2[1] / len2)
            cos12 += (g1[2] / len1) * (g2[2] / len2)
            sine = math.sqrt(max(1.0 - cos12 * cos12, 1e-24))
            row = 2 * levels + level
            f1 = shear_sign[cell] / (len1 * sine)
            f2 = shear_sign[cell] / (len2 * sine)
            for c in range(3):
                u1, u2 = g1[c] / len1, g2[c] / len2
                p1[row, c] = f1 * (u2 - cos12 * u1)
                p2[row, c] = f2 * (u1 - cos12 * u2)
        if nodal:  # n = c / |c|: ds/dc = P ds/dn / |c|
            for j in range(p):
                along = load[j, 0] * n[0] + load[j, 1] * n[1] + load[j, 2] * n[2]
                for c in range(3):
                    load[j, c] = (load[j, c] - along * n[c]) / double_area
        for j in range(p):
            lever = zeta[j % levels]
            for c in range(3):
                corner[0, c] = -(p1[j, c] + p2[j, c])
                corner[1, c] = p1[j, c]
                corner[2, c] = p2[j, c]
            for k in range(3):
                for c in range(3):
                    direct[cell, j, k, c] = corner[k, c]
                # ds/dV_k = h_k / 2 zeta_f F_k, ds/dh_k = zeta_f / 2 F_k . V_k
                l0, l1, l2 = lever * corner[k, 0], lever * corner[k, 1], lever * corner[k, 2]
                v0, v1, v2 = v[cell, k, 0], v[cell, k, 1], v[cell, k, 2]
                half_h = 0.5 * h_m[k]
                ds_dh = 0.5 * (l0 * v0 + l1 * v1 + l2 * v2)
                # h_m = h / (V . N): dh/dc = -h / c^2 where unguarded.
                ds_dc[k] = 0.0 if guarded[k] else -ds_dh * thickness / cosine[k] ** 2
                w0, w1, w2 = node_normal[k, 0], node_normal[k, 1], node_normal[k, 2]
                turns[cell, j, k, 0] = half_h * (v1 * l2 - v2 * l1) + ds_dc[k] * (v1 * w2 - v2 * w1)
                turns[cell, j, k, 1] = half_h * (v2 * l0 - v0 * l2) + ds_dc[k] * (v2 * w0 - v0 * w2)
                turns[cell, j, k, 2] = half_h * (v0 * l1 - v1 * l0) + ds_dc[k] * (v0 * w1 - v1 * w0)
                if nodal:  # c_k = V_k . S_k / |S_k|: dc/dS_k = (V_k - c N_k) / |S_k|
                    for c in range(3):
                        through_sums[cell, j, k, c] = (
                            ds_dc[k] * (v[cell, k, c] - cosine[k] * node_normal[k, c])
                        ) / sum_length[k]
            if not nodal:
                # c_k = V_k . n, n = c / |c|: dc_k = (V_k - c_k n) . dc / |c|.
                for c in range(3):
                    total = 0.0
                    for k in range(3):
                        total += ds_dc[k] * (v[cell, k, c] - cosine[k] * n[c])
                    load[j, c] = total / double_area
            # d(g . c)/dx at the corners of c = (x1 - x0) x (x2 - x0), g the load on c.
            q0, q1, q2 = load[j, 0], load[j, 1], load[j, 2]
            along_a0 = b[1] * q2 - b[2] * q1
            along_a1 = b[2] * q0 - b[0] * q2
            along_a2 = b[0] * q1 - b[1] * q0
            along_b0 = q1 * a[2] - q2 * a[1]
            along_b1 = q2 * a[0] - q0 * a[2]
            along_b2 = q0 * a[1] - q1 * a[0]
            direct[cell, j, 0, 0] += -(along_a0 + along_b0)
            direct[cell, j, 0, 1] += -(along_a1 + along_b1)
            direct[cell, j, 0, 2] += -(along_a2 + along_b2)
            direct[cell, j, 1, 0] += along_a0
            direct[cell, j, 1, 1] += along_a1
            direct[cell, j, 1, 2] += along_a2
            direct[cell, j, 2, 0] += along_b0
            direct[cell, j, 2, 1] += along_b1
            direct[cell, j, 2, 2] += along_b2


def level_gradient_cells(
    x: np.ndarray,
    v: np.ndarray,
    sums: np.ndarray | None,
    zeta: np.ndarray,
    thickness: float,
    shear_sign: np.ndarray,
    guard: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """direct, turns and through_sums of level_jacobian.py ``level_strain_gradient``.

    Parameters
    ----------
    x, v : (m, 3, 3) float, mm and unit: each cell's corner positions and directors.
    sums : (m, 3, 3) float or None: the normal sums S_k at the corners (None: element
        normals).
    zeta : (L,) float, the levels' places through the thickness (-1 to 1).
    thickness : float, mm; shear_sign (m,) float, +-1; guard : float, the least V . N.

    Returns
    -------
    direct, turns : (m, 3 L, 3, 3) float; through_sums (m, 3 L, 3, 3) float or None.
    """
    m, p = len(x), 3 * zeta.size
    nodal = sums is not None
    direct = np.empty((m, p, 3, 3))
    turns = np.empty((m, p, 3, 3))
    through_sums = np.empty((m, p, 3, 3) if nodal else (0, p, 3, 3))
    _gradient_cells(
        np.ascontiguousarray(x, dtype=float),
        np.ascontiguousarray(v, dtype=float),
        np.ascontiguousarray(sums if nodal else np.empty((0, 3, 3)), dtype=float),
        nodal,
        np.ascontiguousarray(zeta, dtype=float),
        float(thickness),
        np.ascontiguousarray(shear_sign, dtype=float),
        float(guard),
        direct,
        turns,
        through_sums,
    )
    return direct, turns, through_sums if nodal else None
