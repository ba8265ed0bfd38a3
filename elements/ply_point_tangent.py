"""The flat ply contact's tangent of its touching points in one compiled pass
(``PlyContactBlock.tangent``, elements/ply_block.py, whose docstring gives the terms): per
point the gap's gradient G = (n, -lambda_k n) and Hessian H over z = (p, y_1, y_2, y_3) (the
plane's in closed form, ``plane_hessian`` of elements/ply_fade_hessian.py, or the search's
where the point faces an edge or a vertex), P = w (W'' G G^T + W' H), carried to the six
nodes by M^T P M (elements/ply_carry.py ``carry_point``) and the turned offsets' geometric
term c (d F^T - (F . d) I) added on each node's psi-psi block.

Its numpy reference is ``PlyContactBlock.tangent`` with ``ply_projection.COMPILED`` False.
The pass makes each product and sum in numpy's order (no fused multiply-add: numba builds
without fastmath), so it gives the same blocks to the last bit (tests/test_ply_carry.py); it
replaces some forty numpy calls on (t, 4, 3, 4, 3) and (t, 6, 3, 6) arrays a block and
tangent, and their memory.
"""

from __future__ import annotations

import numpy as np

from elements.ply_carry import add_turned_offsets, carry_point, carry_reference, own_maps
from elements.ply_fade_hessian import plane_hessian
from femcore.jit import serial

__all__ = ["point_blocks", "point_blocks_reference"]


@serial
def _blocks(
    gap,
    normal,
    weights,
    gradients,
    dots,
    searched,
    bent,
    fade,
    energy,
    slope,
    curvature,
    d,
    offset,
    shape,
    fading,
    forces,
    along,
    made,
    blocks,
):  # pragma: no cover - compiled
    """``point_blocks``' pass: each point's blocks into ``blocks`` (t, 6, 6, 6, 6), its forces
    and F . d into ``forces`` and ``along`` first where ``made``."""
    t = gap.shape[0]
    gradient = np.empty((4, 3))
    hessian = np.empty((4, 3, 4, 3))
    points = np.empty((4, 3, 4, 3))
    own = np.zeros((6, 3, 6))
    carried = np.empty((4, 3, 6, 6))
    for p in range(t):
        n = normal[p]
        lam = weights[p]
        grad = gradients[p]
        for i in range(3):
            gradient[0, i] = n[i]
        for k in range(3):
            for i in range(3):
                gradient[1 + k, i] = -lam[k] * n[i]
        if bent[p]:
            hessian[:] = searched[p]
        else:  # ply_fade_hessian.plane_hessian, its operations in its order
            hessian[:] = 0.0
            for m in range(3):
                for i in range(3):
                    for j in range(3):
                        hessian[0, i, 1 + m, j] = -grad[m, i] * n[j]
                        hessian[1 + m, i, 0, j] = -n[i] * grad[m, j]
                for k in range(3):
                    scaled = -(gap[p] * dots[p, k, m])
                    for i in range(3):
                        for j in range(3):
                            hessian[1 + k, i, 1 + m, j] = (
                                scaled * (n[i] * n[j])
                                + lam[m] * n[i] * grad[k, j]
                                + lam[k] * grad[m, i] * n[j]
                            )
        for z in range(4):
            for i in range(3):
                for s in range(4):
                    for j in range(3):
                        points[z, i, s, j] = fade[p] * (
                            curvature[p] * (gradient[z, i] * gradient[s, j])
                            + slope[p] * hessian[z, i, s, j]
                        )
        # each node's own map: the identity on du, -c [d]x on dpsi (femcore.rotation)
        for r in range(6):
            c = -offset[p, r]
            x, y, w = d[p, r, 0], d[p, r, 1], d[p, r, 2]
            for i in range(3):
                own[r, i, i] = 1.0
            own[r, 0, 3], own[r, 0, 4], own[r, 0, 5] = c * 0.0, c * -w, c * y
            own[r, 1, 3], own[r, 1, 4], own[r, 1, 5] = c * w, c * 0.0, c * -x
            own[r, 2, 3], own[r, 2, 4], own[r, 2, 5] = c * -y, c * x, c * 0.0
        carry_point(points, own, shape[p], blocks[p], carried)
        if made:  # the forces w W' dg/dz + W dw/dz on the nodes (PlyContactBlock._pair_loads)
            pressed = fade[p] * slope[p]
            for i in range(3):
                on_face = pressed * n[i] + energy[p] * fading[p, 0, i]
                for j in range(3):
                    forces[p, j, i] = shape[p, j] * on_face
                for k in range(3):
                    forces[p, 3 + k, i] = -pressed * lam[k] * n[i] + energy[p] * fading[p, 1 + k, i]
            for r in range(6):
                f = forces[p, r]
                e = d[p, r]
                along[p, r] = f[0] * e[0] + f[1] * e[1] + f[2] * e[2]  # np.sum's order
        # the moment c d x F turned with the director: c (d F^T - (F . d) I)
        for r in range(6):
            f = forces[p, r]
            e = d[p, r]
            for i in range(3):
                for j in range(3):
                    eye = 1.0 if i == j else 0.0
                    blocks[p, r, 3 + i, r, 3 + j] += offset[p, r] * (
                        e[i] * f[j] - along[p, r] * eye
                    )


def point_blocks(
    gap: np.ndarray,
    normal: np.ndarray,
    weights: np.ndarray,
    gradients: np.ndarray,
    searched: np.ndarray | None,
    fade: np.ndarray,
    law: tuple,
    directions: np.ndarray,
    offset: np.ndarray,
    shape: np.ndarray,
    forces: np.ndarray | None = None,
    fading: np.ndarray | None = None,
) -> np.ndarray:
    """The touching points' tangent blocks (t, 6, 6, 6, 6) over their nodes' (u, psi)
    (N/mm, N, N mm; module docstring).

    Parameters
    ----------
    gap : (t,) mm. normal : (t, 3) unit normals of the facing planes. weights : (t, 3) the
        projections' barycentric coordinates. gradients : (t, 3, 3) their gradients, 1/mm.
    searched : (t, 4, 3, 4, 3) 1/mm the search's Hessian of the gap (rows all zero: the
        plane's), or None (the plane's for every point).
    fade : (t,) the fade w. law : (energy, dW/dg, d2W/dg2), each (t,).
    directions : (t, 6, 3) the offset directions d at the nodes (upper corners, then the
        facing triangle's). offset : (t, 6) mm the signed offsets c (z = x + c d).
    shape : (t, 3) the points' shape functions on their upper corners.
    forces : (t, 6, 3) N the points' forces on the nodes, or None: made in the pass from
        ``fading`` (t, 6, 3) 1/mm, the fade's gradient over z = (p, y_1, y_2, y_3, a, b), as
        ``PlyContactBlock._pair_loads`` makes them (the same bits).

    Raises
    ------
    ValueError
        Neither the forces nor the fade's gradient given.
    """
    t = len(gap)
    if forces is None and fading is None:
        raise ValueError("point_blocks: give the points' forces or the fade's gradient")
    if searched is None:
        searched = np.zeros((t, 4, 3, 4, 3))
        bent = np.zeros(t, dtype=np.bool_)
    else:
        bent = np.any(searched != 0.0, axis=(1, 2, 3, 4))
    blocks = np.empty((t, 6, 6, 6, 6))
    # the two sums of three products that numpy groups by its own vector lanes (the gradients'
    # dot products by einsum as plane_hessian makes them, F . d by np.sum): taken from numpy
    dots = np.einsum("cki,cmi->ckm", gradients, gradients)
    made = forces is None  # then F . d summed in the pass in np.sum's order (left to right)
    if made:
        forces, along = np.empty((t, 6, 3)), np.empty((t, 6))
    else:
        along = np.sum(forces * directions, axis=-1)
    arrays = [gap, normal, weights, gradients, dots, searched]
    floats = [np.ascontiguousarray(a, dtype=float) for a in arrays]
    _blocks(
        *floats,
        bent,
        np.ascontiguousarray(fade, dtype=float),
        np.ascontiguousarray(law[0], dtype=float),
        np.ascontiguousarray(law[1], dtype=float),
        np.ascontiguousarray(law[2], dtype=float),
        np.ascontiguousarray(directions, dtype=float),
        np.ascontiguousarray(offset, dtype=float),
        np.ascontiguousarray(shape, dtype=float),
        np.ascontiguousarray(np.zeros((t, 6, 3)) if fading is None else fading, dtype=float),
        np.ascontiguousarray(forces, dtype=float),
        np.ascontiguousarray(along, dtype=float),
        made,
        blocks,
    )
    return blocks


def point_blocks_reference(
    gap: np.ndarray,
    normal: np.ndarray,
    weights: np.ndarray,
    gradients: np.ndarray,
    searched: np.ndarray | None,
    fade: np.ndarray,
    law: tuple,
    directions: np.ndarray,
    offset: np.ndarray,
    shape: np.ndarray,
    forces: np.ndarray | None = None,
    fading: np.ndarray | None = None,
) -> np.ndarray:
    """``point_blocks`` by numpy (its reference; the same arguments and blocks)."""
    n, lam = normal, weights
    if forces is None:  # PlyContactBlock._pair_loads' forces
        if fading is None:
            raise ValueError("point_blocks: give the points' forces or the fade's gradient")
        on_face = (fade * law[1])[:, None] * n + law[0][:, None] * fading[:, 0]
        forces = np.concatenate(
            [
                shape[:, :, None] * on_face[:, None, :],
                -(fade * law[1])[:, None, None] * lam[:, :, None] * n[:, None, :]
                + law[0][:, None, None] * fading[:, 1:4],
            ],
            axis=1,
        )
    gradient = np.concatenate([n[:, None, :], -lam[:, :, None] * n[:, None, :]], axis=1)
    hessian = plane_hessian(gap, n, lam, gradients)  # (t, 4, 3, 4, 3)
    if searched is not None:
        bent = np.flatnonzero(np.any(searched != 0.0, axis=(1, 2, 3, 4)))
        hessian[bent] = searched[bent]
    outer = gradient[:, :, :, None, None] * gradient[:, None, None, :, :]
    points = fade[:, None, None, None, None] * (
        law[2][:, None, None, None, None] * outer + law[1][:, None, None, None, None] * hessian
    )  # (t, 4, 3, 4, 3)
    # Each node's own map dz = du - c [d]x psi, (t, 6, 3, 6); the point p takes its
    # corners' maps times N_j, each lower corner its own.
    blocks = carry_reference(points, own_maps(offset, directions), shape)
    # The moment c d x F turns with the director (F held).
    add_turned_offsets(blocks, offset, directions, forces, 0)
    return blocks
