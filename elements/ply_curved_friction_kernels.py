"""The curved faces' friction loads over each point's local data (elements/ply_curved_friction.py
``local_loads_numpy``) in one compiled pass, real or complex (the complex steps of its
tangent): the same formulas, point by point.

Why. The tangent evaluates the local loads at 54 complex steps of every frictional point;
in numpy that is a few hundred small array operations on 54 t rows, 0.34 s of a 0.44-s
tangent at 96 points (benchmarks/ply_curved_static.py). The pass differs from the reference
by the rounding of its sums and of the 2 x 2 solves (closed form here, LAPACK there):
tests/test_ply_curved_friction.py holds it to 1e-12 of the largest load, real and complex.
"""

from __future__ import annotations

import numpy as np

from femcore.jit import inline, jit, prange

__all__ = ["local_loads"]


@inline
def _flat_point(data, corners, normals, lam, zero, q, e):
    """Into q (3,) and e (3,): the flat point q = sum_k lam_k y_k of the barycentric
    coordinates lam (3,) on a patch's corners y = data[corners] (3, 3) and its offsets
    e_k = (q - y_k) . n_k along the corners' normals n = data[normals] (3, 3), real or complex
    (``zero`` the row's zero): the start of the patch's Phong point and of its Jacobian, in
    the pass's projections and in its maps of the point, the facing point and the anchor."""
    for i in range(3):
        q[i] = lam[0] * data[corners, 0, i]
        for k in range(1, 3):
            q[i] = q[i] + lam[k] * data[corners, k, i]
    for k in range(3):
        e[k] = zero
        for i in range(3):
            e[k] = e[k] + (q[i] - data[corners, k, i]) * data[normals, k, i]


@inline
def _plane_places(corners, point, direction, places):
    """Into places (3,): the barycentric places on the plane of the triangle ``corners``
    (3, 3) of ``point`` (3,) moved onto it along ``direction`` (3,), along its normal where
    that lies within 60 deg of the plane; returns the point's height over the plane
    (elements/ply_curved_friction.py ``_plane_places``), real or complex."""
    a0 = corners[1, 0] - corners[0, 0]
    a1 = corners[1, 1] - corners[0, 1]
    a2 = corners[1, 2] - corners[0, 2]
    b0 = corners[2, 0] - corners[0, 0]
    b1 = corners[2, 1] - corners[0, 1]
    b2 = corners[2, 2] - corners[0, 2]
    c0 = a1 * b2 - a2 * b1
    c1 = a2 * b0 - a0 * b2
    c2 = a0 * b1 - a1 * b0
    area2 = np.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
    n0, n1, n2 = c0 / area2, c1 / area2, c2 / area2
    height = (
        n0 * (point[0] - corners[0, 0])
        + n1 * (point[1] - corners[0, 1])
        + n2 * (point[2] - corners[0, 2])
    )
    slant = n0 * direction[0] + n1 * direction[1] + n2 * direction[2]
    d0, d1, d2 = direction[0], direction[1], direction[2]
    if not abs(slant.real) > 0.5:
        d0, d1, d2, slant = n0, n1, n2, slant * 0.0 + 1.0
    rise = height / slant
    m0, m1, m2 = point[0] - rise * d0, point[1] - rise * d1, point[2] - rise * d2
    # grad phi_1 = n x (y_3 - y_2) / |c| and grad phi_2 = n x (y_1 - y_3) / |c|
    e0 = corners[2, 0] - corners[1, 0]
    e1 = corners[2, 1] - corners[1, 1]
    e2 = corners[2, 2] - corners[1, 2]
    f0 = corners[0, 0] - corners[2, 0]
    f1 = corners[0, 1] - corners[2, 1]
    f2 = corners[0, 2] - corners[2, 2]
    places[0] = (
        (n1 * e2 - n2 * e1) * (m0 - corners[1, 0])
        + (n2 * e0 - n0 * e2) * (m1 - corners[1, 1])
        + (n0 * e1 - n1 * e0) * (m2 - corners[1, 2])
    ) / area2
    places[1] = (
        (n1 * f2 - n2 * f1) * (m0 - corners[0, 0])
        + (n2 * f0 - n0 * f2) * (m1 - corners[0, 1])
        + (n0 * f1 - n1 * f0) * (m2 - corners[0, 2])
    ) / area2
    places[2] = 1.0 - places[0] - places[1]
    return height


def _local_loads(
    v, sigma, anchor, start, stiffness, branch_gap, stuck, landing, then, smoothing, friction,
    penalty, steps, out,
):  # fmt: skip
    """Into out (t, 54): the local loads of the points' data v (t, 54), real or complex
    (elements/ply_curved_friction.py ``local_loads_numpy``, whose arguments these are)."""
    for row in prange(v.shape[0]):
        zero = v[row, 0] * 0.0
        data = np.empty((6, 3, 3), v.dtype)
        for slot in range(6):
            for k in range(3):
                for i in range(3):
                    data[slot, k, i] = v[row, 9 * slot + 3 * k + i]
        lam = np.empty(3, v.dtype)
        # p on the upper patch, a on the anchor's, then the projection on the facing patch
        p = np.empty(3, v.dtype)
        a = np.empty(3, v.dtype)
        point = np.empty(3, v.dtype)
        q = np.empty(3, v.dtype)
        e = np.empty(3, v.dtype)
        partial = np.empty((3, 3), v.dtype)
        tangents = np.empty((2, 3), v.dtype)
        facing_lam = np.empty(3, v.dtype)
        facing_q = np.empty(3, v.dtype)
        facing_e = np.empty(3, v.dtype)
        facing_point = np.empty(3, v.dtype)
        nu = np.empty(3, v.dtype)
        gap = zero
        anchored = np.empty(3, v.dtype)  # the anchor's Lambda, moving where it lands
        for k in range(3):
            anchored[k] = anchor[row, k] + zero
        for which in range(3):
            corners, normals = 2 * which, 2 * which + 1
            if which == 0:
                for k in range(3):
                    lam[k] = sigma[row, k] + zero
            elif which == 2:
                for k in range(3):
                    lam[k] = anchored[k]
            else:
                for k in range(3):
                    lam[k] = start[row, k] + zero
            for iteration in range(steps + 1 if which == 1 else 1):
                _flat_point(data, corners, normals, lam, zero, q, e)
                for i in range(3):
                    total = zero
                    for k in range(3):
                        total = total + lam[k] * e[k] * data[normals, k, i]
                    point[i] = q[i] - 0.5 * total
                if which != 1:
                    break
                for k in range(3):
                    for i in range(3):
                        total = zero
                        for m in range(3):
                            dot = zero
                            for j in range(3):
                                dot = dot + data[2, k, j] * data[3, m, j]
                            total = total + lam[m] * dot * data[3, m, i]
                        partial[k, i] = data[2, k, i] - 0.5 * e[k] * data[3, k, i] - 0.5 * total
                for side in range(2):
                    for i in range(3):
                        tangents[side, i] = partial[side, i] - partial[2, i]
                if iteration == steps:
                    break
                m00 = zero
                m01 = zero
                m11 = zero
                r0 = zero
                r1 = zero
                for i in range(3):
                    m00 = m00 + tangents[0, i] * tangents[0, i]
                    m01 = m01 + tangents[0, i] * tangents[1, i]
                    m11 = m11 + tangents[1, i] * tangents[1, i]
                    r0 = r0 + tangents[0, i] * (p[i] - point[i])
                    r1 = r1 + tangents[1, i] * (p[i] - point[i])
                det = m00 * m11 - m01 * m01
                lam[0] = lam[0] + (m11 * r0 - m01 * r1) / det
                lam[1] = lam[1] + (m00 * r1 - m01 * r0) / det
                lam[2] = 1.0 - lam[0] - lam[1]
            if which == 0:
                for i in range(3):
                    p[i] = point[i]
            elif which == 2:
                for i in range(3):
                    a[i] = point[i]
            else:
                for i in range(3):
                    facing_lam[i] = lam[i]
                    facing_q[i] = q[i]
                    facing_e[i] = e[i]
                    facing_point[i] = point[i]
                # the normal and the gap
                c0 = tangents[0, 1] * tangents[1, 2] - tangents[0, 2] * tangents[1, 1]
                c1 = tangents[0, 2] * tangents[1, 0] - tangents[0, 0] * tangents[1, 2]
                c2 = tangents[0, 0] * tangents[1, 1] - tangents[0, 1] * tangents[1, 0]
                size = np.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
                nu[0], nu[1], nu[2] = c0 / size, c1 / size, c2 / size
                for i in range(3):
                    gap = gap + (p[i] - facing_point[i]) * nu[i]
                if landing[row]:  # the landing anchor's motion (its value: ``anchor``)
                    earlier = np.empty((3, 3), v.dtype)  # T's corners then
                    at = np.empty(3, v.dtype)  # the face point then
                    for k in range(3):
                        at[k] = then[row, 3, k] + zero
                        for i in range(3):
                            earlier[k, i] = then[row, k, i] + zero
                    now = np.empty(3, v.dtype)
                    before = np.empty(3, v.dtype)
                    _plane_places(data[2], p, nu, now)
                    height = _plane_places(earlier, at, nu, before)
                    g0 = max(height.real, 0.0)
                    pen = -gap if gap.real < 0.0 else zero
                    way = g0 + pen
                    theta = g0 / way if way.real > 0.0 else 1.0 + zero
                    for k in range(3):
                        moving = lam[k] - (1.0 - theta) * (now[k] - before[k])
                        anchored[k] = anchored[k] + (moving - moving.real)
        # the law
        k_p = stiffness[row]
        if smoothing == 0.0:
            pressing, spring, slope = -k_p * gap, k_p + zero, zero
        elif branch_gap[row] <= -smoothing:
            pressing, spring, slope = -k_p * (gap + 0.5 * smoothing), k_p + zero, zero
        else:
            pressing = k_p * gap * gap / (2.0 * smoothing)
            spring = -k_p * gap / smoothing
            slope = -k_p / smoothing + zero
        if penalty:
            spring, slope = k_p + zero, zero
        r = np.empty(3, v.dtype)
        s = np.empty(3, v.dtype)
        along = zero
        for i in range(3):
            r[i] = p[i] - a[i]
            along = along + nu[i] * r[i]
        half = zero
        for i in range(3):
            s[i] = r[i] - along * nu[i]
            half = half + 0.5 * s[i] * s[i]
        length = np.sqrt(2.0 * half) if half != 0.0 else 1.0 + zero
        scale = spring if stuck[row] else friction * pressing / length
        force = np.empty(3, v.dtype)
        for i in range(3):
            force[i] = scale * s[i]
        # the Phong maps' Jacobians (3, 18) of p, of the facing point and of a
        u = np.zeros((3, 36), v.dtype)
        anchor_map = np.empty((3, 18), v.dtype)
        for which in range(3):
            corners, normals = 2 * which, 2 * which + 1
            for k in range(3):
                if which == 0:
                    lam[k] = sigma[row, k] + zero
                elif which == 1:
                    lam[k] = facing_lam[k]
                else:
                    lam[k] = anchored[k]
            _flat_point(data, corners, normals, lam, zero, q, e)
            sign = -1.0 if which == 1 else 1.0
            for i in range(3):
                for j in range(3):
                    mixed = zero
                    for m in range(3):
                        mixed = mixed + lam[m] * data[normals, m, i] * data[normals, m, j]
                    for k in range(3):
                        eye = 1.0 if i == j else 0.0
                        on_y = lam[k] * (
                            eye - 0.5 * mixed + 0.5 * data[normals, k, i] * data[normals, k, j]
                        )
                        on_n = (
                            -0.5
                            * lam[k]
                            * (data[normals, k, i] * (q[j] - data[corners, k, j]) + e[k] * eye)
                        )
                        if which == 2:
                            anchor_map[i, 3 * k + j] = on_y
                            anchor_map[i, 9 + 3 * k + j] = on_n
                        else:
                            u[i, 18 * which + 3 * k + j] = sign * on_y
                            u[i, 18 * which + 9 + 3 * k + j] = sign * on_n
        # the facing patch's B and h at the projection (elements/ply_curved_hessian.py)
        y, n = data[2], data[3]
        nun = np.empty(3, v.dtype)
        for k in range(3):
            nun[k] = nu[0] * n[k, 0] + nu[1] * n[k, 1] + nu[2] * n[k, 2]
        yn = np.empty((3, 3), v.dtype)
        for k in range(3):
            for m in range(3):
                yn[k, m] = y[k, 0] * n[m, 0] + y[k, 1] * n[m, 1] + y[k, 2] * n[m, 2]
        nud = np.empty((3, 3), v.dtype)
        for k in range(3):
            for m in range(3):
                nud[k, m] = -0.5 * (yn[m, k] * nun[k] + yn[k, m] * nun[m])
        b = np.empty((2, 2), v.dtype)
        for i in range(2):
            for j in range(2):
                b[i, j] = nud[i, j] - nud[i, 2] - nud[2, j] + nud[2, 2]
        mixed_n = np.empty(3, v.dtype)
        for j in range(3):
            mixed_n[j] = zero
            for i in range(3):
                mixed_n[j] = mixed_n[j] + facing_lam[i] * nun[i] * n[i, j]
        dpi = np.zeros((3, 36), v.dtype)
        for k in range(3):
            for m in range(3):
                c = facing_lam[m] - (1.0 if k == m else 0.0)
                for j in range(3):
                    on_y = -0.5 * c * nun[k] * n[k, j]
                    on_n = -0.5 * facing_lam[m] * (nun[m] * y[k, j] + yn[k, m] * nu[j])
                    if k == m:
                        on_y = on_y + nu[j] - 0.5 * mixed_n[j]
                        on_n = on_n - 0.5 * (nun[k] * (facing_q[j] - y[k, j]) + facing_e[k] * nu[j])
                    dpi[k, 18 + 3 * m + j] = on_y
                    dpi[k, 27 + 3 * m + j] = on_n
        # G, alpha, M, A; moved = A^-1 (alpha + g h), dual = M^-1 (h + B moved)
        m00 = zero
        m01 = zero
        m11 = zero
        for i in range(3):
            m00 = m00 + tangents[0, i] * tangents[0, i]
            m01 = m01 + tangents[0, i] * tangents[1, i]
            m11 = m11 + tangents[1, i] * tangents[1, i]
        a00, a01, a10, a11 = (
            m00 - gap * b[0, 0],
            m01 - gap * b[0, 1],
            m01 - gap * b[1, 0],
            m11 - gap * b[1, 1],
        )
        det_a = a00 * a11 - a01 * a10
        det_m = m00 * m11 - m01 * m01
        for w in range(54):
            out[row, w] = zero
        for col in range(36):
            g_col = zero
            al0 = zero
            al1 = zero
            for i in range(3):
                g_col = g_col + nu[i] * u[i, col]
                al0 = al0 + tangents[0, i] * u[i, col]
                al1 = al1 + tangents[1, i] * u[i, col]
            h0 = dpi[0, col] - dpi[2, col]
            h1 = dpi[1, col] - dpi[2, col]
            f0 = al0 + gap * h0
            f1 = al1 + gap * h1
            mv0 = (a11 * f0 - a01 * f1) / det_a
            mv1 = (a00 * f1 - a10 * f0) / det_a
            k0 = h0 + b[0, 0] * mv0 + b[0, 1] * mv1
            k1 = h1 + b[1, 0] * mv0 + b[1, 1] * mv1
            d0 = (m11 * k0 - m01 * k1) / det_m
            d1 = (m00 * k1 - m01 * k0) / det_m
            load = zero
            if col < 18:
                for i in range(3):
                    load = load + force[i] * u[i, col]
            if stuck[row]:
                turned = zero
                for i in range(3):
                    turned = turned - force[i] * (tangents[0, i] * d0 + tangents[1, i] * d1)
                load = load - along * turned + slope * half * g_col
            out[row, col] = load
        for col in range(18):
            load = zero
            for i in range(3):
                load = load - force[i] * anchor_map[i, col]
            out[row, 36 + col] = load


_compiled = jit(_local_loads)


def local_loads(
    v: np.ndarray,
    sigma: np.ndarray,
    anchor: np.ndarray,
    start: np.ndarray,
    stiffness: np.ndarray,
    branch_gap: np.ndarray,
    stuck: np.ndarray,
    landing: np.ndarray,
    then: np.ndarray,
    smoothing: float,
    friction: float,
    penalty: bool,
    steps: int,
) -> np.ndarray:
    """The local loads (t, 54) of elements/ply_curved_friction.py ``local_loads_numpy``,
    compiled; v real or complex (t, 54), the rest as there. Raises ValueError for other
    shapes (the pass would read past its arrays)."""
    count = len(v) if np.ndim(v) == 2 else -1
    given = (sigma, anchor, start, stiffness, branch_gap, stuck, landing, then)
    shapes = [np.shape(a) for a in given]
    expected = [(count, 3)] * 3 + [(count,)] * 4 + [(count, 4, 3)]
    if np.shape(v) != (count, 54) or shapes != expected:
        raise ValueError(
            f"local data {np.shape(v)} and per-point arrays {shapes} given: expected (t, 54), "
            "three (t, 3), four (t,) and one (t, 4, 3) with one t"
        )
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 0:
        # fewer than none would leave the pass's tangents unset (read from np.empty)
        raise ValueError(f"steps must be a whole number >= 0, got {steps!r}")
    v = np.ascontiguousarray(v)
    out = np.empty(v.shape, dtype=v.dtype)
    _compiled(
        v, np.ascontiguousarray(sigma, dtype=float), np.ascontiguousarray(anchor, dtype=float),
        np.ascontiguousarray(start, dtype=float), np.ascontiguousarray(stiffness, dtype=float),
        np.ascontiguousarray(branch_gap, dtype=float), np.ascontiguousarray(stuck, dtype=bool),
        np.ascontiguousarray(landing, dtype=bool), np.ascontiguousarray(then, dtype=float),
        float(smoothing), float(friction), bool(penalty), int(steps), out,
    )  # fmt: skip
    return out
