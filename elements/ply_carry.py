"""The flat ply contact's point Hessians carried to its nodes (``tangent`` and
``fade_tangent``, elements/ply_block_tangent.py): blocks = M^T P M, where P (t, Z, 3, Z, 3) is
each touching point's Hessian over z = (p, y_1, .., y_{Z-1}) and M (t, Z, 3, N, 6) the map of the
point's nodes' (u, psi) (N = Z + 2 nodes: the upper triangle's three corners, then one node per
lower z) onto z: dp = sum_j N_j (du_j - c_j [d_j]x psi_j), dy_k = du_k - c_k [d_k]x psi_k.

The reference, ``carry_reference``, builds M whole and takes the two contractions by
``np.einsum`` ("tzisj,tsjcb->tzicb", then "tzira,tzicb->tracb"), which sums each entry's
Z x 3 products in their index order from 0.0 (checked against a plain loop in that order:
tests/test_ply_carry.py). M is sparse: node c's columns reach z = 0 for the upper corners
(c < 3) and z = c - 2 for the others, and of those only the coordinates where its own map
``own`` (t, N, 3, 6) is not zero: one term for du (the identity), two for dpsi (a cross
product's matrix). ``carried_blocks`` takes those terms only, in the same order, from 0.0;
the terms it leaves out are products by an exact zero (+-0 added to a sum that is not -0:
the sum unchanged), so it gives the same blocks to the last bit with about a twelfth of the
products and none of M's or the intermediate's memory. numba builds without fastmath (no
fused multiply-add), so each product and sum is numpy's.
"""

from __future__ import annotations

import numpy as np

from femcore.jit import serial
from femcore.rotation import cross_matrix

__all__ = [
    "add_turned_offsets",
    "carried_blocks",
    "carry",
    "carry_point",
    "carry_reference",
    "own_maps",
    "point_maps",
]


def own_maps(offset: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """Each node's own map onto its z, dz = du - c [d]x psi, (t, N, 3, 6): from the nodes'
    signed offsets c (t, N), mm, and offset directions d (t, N, 3)."""
    own = np.zeros(offset.shape + (3, 6))
    own[:, :, :, :3] = np.eye(3)
    own[:, :, :, 3:] = -offset[:, :, None, None] * cross_matrix(directions)
    return own


def add_turned_offsets(
    blocks: np.ndarray, offset: np.ndarray, directions: np.ndarray, forces: np.ndarray, first: int
) -> None:
    """Add to ``blocks`` (t, N, 6, N, 6), in place, the turn of the moments c d x F of the
    nodes ``first``, ``first`` + 1, .. with the forces F (t, k, 3), N: with F held,
    d(c d x F)/dpsi = c (psi x d) x F = c (d F^T - (F . d) I) psi, on each node's own (psi,
    psi) block; offset c (t, k), mm, directions d (t, k, 3) those nodes'."""
    geometric = offset[:, :, None, None] * (
        directions[:, :, :, None] * forces[:, :, None, :]
        - np.sum(forces * directions, axis=-1)[:, :, None, None] * np.eye(3)
    )
    for row in range(forces.shape[1]):
        blocks[:, first + row, 3:, first + row, 3:] += geometric[:, row]


def point_maps(own: np.ndarray, shape: np.ndarray) -> np.ndarray:
    """M (t, Z, 3, N, 6) from each node's own map ``own`` (t, N, 3, 6) (dz = du - c [d]x psi)
    and the point's shape functions on its upper corners ``shape`` (t, 3), Z = N - 2."""
    t, nodes = own.shape[:2]
    maps = np.zeros((t, nodes - 2, 3, nodes, 6))
    for j in range(3):
        maps[:, 0, :, j, :] = shape[:, j, None, None] * own[:, j]
    for z in range(1, nodes - 2):
        maps[:, z, :, 2 + z, :] = own[:, 2 + z]
    return maps


def carry_reference(points: np.ndarray, own: np.ndarray, shape: np.ndarray) -> np.ndarray:
    """M^T P M (t, N, 6, N, 6) by numpy (module docstring): points P (t, Z, 3, Z, 3), own
    (t, N, 3, 6), shape (t, 3)."""
    maps = point_maps(own, shape)
    carried = np.einsum("tzisj,tsjcb->tzicb", points, maps)
    return np.einsum("tzira,tzicb->tracb", maps, carried)


@serial
def carry_point(points, own, shape, blocks, carried):  # pragma: no cover - compiled
    """M^T P M of one point into ``blocks`` (N, 6, N, 6): points (Z, 3, Z, 3), own
    (N, 3, 6), shape (3,), ``carried`` (Z, 3, N, 6) scratch (module docstring)."""
    nodes = own.shape[0]
    zs = nodes - 2
    # carried[z, i, c, b] = sum_{s, j} P[z, i, s, j] M[s, j, c, b]
    for z in range(zs):
        for i in range(3):
            for c in range(nodes):
                s = 0 if c < 3 else c - 2
                for b in range(6):
                    acc = 0.0
                    for j in range(3):
                        m = own[c, j, b]
                        if c < 3:
                            m = shape[c] * m
                        if m != 0.0:
                            acc += points[z, i, s, j] * m
                    carried[z, i, c, b] = acc
    # blocks[r, a, c, b] = sum_{z, i} M[z, i, r, a] carried[z, i, c, b]
    for r in range(nodes):
        z = 0 if r < 3 else r - 2
        for a in range(6):
            for c in range(nodes):
                for b in range(6):
                    acc = 0.0
                    for i in range(3):
                        m = own[r, i, a]
                        if r < 3:
                            m = shape[r] * m
                        if m != 0.0:
                            acc += m * carried[z, i, c, b]
                    blocks[r, a, c, b] = acc


@serial
def _carry(points, own, shape, blocks, carried):  # pragma: no cover - compiled
    """``carry_point`` of every point into ``blocks`` (t, N, 6, N, 6)."""
    for p in range(own.shape[0]):
        carry_point(points[p], own[p], shape[p], blocks[p], carried)


def carried_blocks(points: np.ndarray, own: np.ndarray, shape: np.ndarray) -> np.ndarray:
    """M^T P M (t, N, 6, N, 6), compiled, the same bits as ``carry_reference``: points P
    (t, Z, 3, Z, 3) 1/mm-weighted Hessians over z (N/mm), own (t, N, 3, 6) each node's map
    onto its z (dimensionless on du, mm on dpsi), shape (t, 3) the points' shape functions
    on their upper corners."""
    t, nodes = own.shape[:2]
    if points.shape != (t, nodes - 2, 3, nodes - 2, 3) or shape.shape != (t, 3):
        raise ValueError(
            f"points {points.shape} and shape {shape.shape} do not match own {own.shape}: "
            "expected (t, N - 2, 3, N - 2, 3) and (t, 3)"
        )
    blocks = np.empty((t, nodes, 6, nodes, 6))
    carried = np.empty((nodes - 2, 3, nodes, 6))
    _carry(
        np.ascontiguousarray(points, dtype=float),
        np.ascontiguousarray(own, dtype=float),
        np.ascontiguousarray(shape, dtype=float),
        blocks,
        carried,
    )
    return blocks


def carry(points: np.ndarray, own: np.ndarray, shape: np.ndarray) -> np.ndarray:
    """M^T P M: ``carried_blocks`` with ``ply_projection.COMPILED``, else ``carry_reference``
    (the same bits)."""
    from elements import ply_projection

    if ply_projection.COMPILED:
        return carried_blocks(points, own, shape)
    return carry_reference(points, own, shape)
