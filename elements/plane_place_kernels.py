"""A point's place on a triangle's plane, compiled for one triangle at a time: the scalar
twins of elements/ply_projection.py ``triangle_frames`` and elements/ply_landing.py
``plane_places``, operation by operation (the cross products as femcore/rotation.py ``cross``
writes them, the norm's sum from the first term, ``einsum("rki,ri->rk")`` as (first + last) +
middle; no fused multiply-add: numba builds without fastmath), so that the compiled ply
landing and departure (elements/ply_landing_kernels.py, ply_departure_kernels.py), which
both place their points on the planes of their triangles then and now, give numpy's bits.

Built with numpy's error model (femcore/jit.py ``lanes``), as the kernels that call them:
a degenerate triangle gives inf or NaN, not an exception.
"""

from __future__ import annotations

import numpy as np

from femcore.jit import lanes

__all__ = ["frame", "place"]


@lanes
def frame(corners):
    """(n0, n1, n2, area2, g00, g01, g02, g10, g11, g12, g20, g21, g22) of the triangle
    ``corners`` (3, 3) mm: its unit normal, twice its area (mm^2) and the in-plane gradients
    grad phi_k (1/mm) of its three barycentric coordinates (``triangle_frames``)."""
    e0 = corners[1, 0] - corners[0, 0]
    e1 = corners[1, 1] - corners[0, 1]
    e2 = corners[1, 2] - corners[0, 2]
    f0 = corners[2, 0] - corners[0, 0]
    f1 = corners[2, 1] - corners[0, 1]
    f2 = corners[2, 2] - corners[0, 2]
    c0 = e1 * f2 - e2 * f1
    c1 = e2 * f0 - e0 * f2
    c2 = e0 * f1 - e1 * f0
    area2 = np.sqrt((c0 * c0 + c1 * c1) + c2 * c2)
    n0, n1, n2 = c0 / area2, c1 / area2, c2 / area2
    # the edges opposite corners 0, 1 and 2 (y3 - y2, y1 - y3, y2 - y1 = e), cyclic
    a0 = corners[2, 0] - corners[1, 0]
    a1 = corners[2, 1] - corners[1, 1]
    a2 = corners[2, 2] - corners[1, 2]
    b0 = corners[0, 0] - corners[2, 0]
    b1 = corners[0, 1] - corners[2, 1]
    b2 = corners[0, 2] - corners[2, 2]
    return (
        n0,
        n1,
        n2,
        area2,
        (n1 * a2 - n2 * a1) / area2,
        (n2 * a0 - n0 * a2) / area2,
        (n0 * a1 - n1 * a0) / area2,
        (n1 * b2 - n2 * b1) / area2,
        (n2 * b0 - n0 * b2) / area2,
        (n0 * b1 - n1 * b0) / area2,
        (n1 * e2 - n2 * e1) / area2,
        (n2 * e0 - n0 * e2) / area2,
        (n0 * e1 - n1 * e0) / area2,
    )


@lanes
def place(corners, point, g00, g01, g02, g10, g11, g12):
    """(w0, w1, w2, r0, r1, r2): the barycentric place of ``point`` (3,) mm on the plane of
    ``corners`` (3, 3) mm, given the first two coordinates' gradients (``frame``), and
    r = point - corners[0] (mm), from which its height over the plane is taken
    (``plane_places``)."""
    q0 = point[0] - corners[1, 0]
    q1 = point[1] - corners[1, 1]
    q2 = point[2] - corners[1, 2]
    r0 = point[0] - corners[0, 0]
    r1 = point[1] - corners[0, 1]
    r2 = point[2] - corners[0, 2]
    w0 = (g00 * q0 + g02 * q2) + g01 * q1
    w1 = (g10 * r0 + g12 * r2) + g11 * r1
    return w0, w1, 1.0 - w0 - w1, r0, r1, r2
