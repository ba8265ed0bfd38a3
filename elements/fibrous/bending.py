"""Rotation-free bending from the neighbouring elements (Bai Eq. 20, 34-37; docs/theory.md §4), the
numpy reference of the compiled loops of kernels.py and geometry_kernels.py, and its stiffness.

The warp and weft curvatures of each element come from the fold angles theta_s with its three
neighbours (Eq. 35): chi_a = -sum_s c_as (theta_s - theta_s0), c_as = 2 (g_a . n^c_s)^2 /
(h_s + h_s'), the heights of the two cells over their common side; on a clamped side the
neighbour is the wall of the reference plane (§4.5). The virtual work (Eq. 20) is

    delta W_B = A0 sum_alpha M_alpha(chi_alpha) delta chi_alpha,

with delta chi_alpha = B delta u (Eq. 34) and the nodal forces of Eq. 37; since d theta_s/dx
has the share D[s, k] n on each element's own nodes (Eq. 36), every element scatters to its
own three nodes only, with each side's moment summed over its two elements.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from elements.base import CellTangent
from elements.fibrous import geometry_kernels, tangent_kernels
from elements.fibrous.fibres import by_family
from elements.fibrous.geometry import SIDE_FROM, SIDE_TO
from femcore.rotation import cross

if TYPE_CHECKING:
    from elements.fibrous.block import FibrousShellBlock

__all__ = [
    "curvatures",
    "energy",
    "forces",
    "geometry",
    "moments",
    "patch_nodes",
    "share_tangent",
    "side_geometry",
    "side_moments",
    "tangent",
]


def side_geometry(x: np.ndarray) -> dict:
    """Per-cell geometry of the sides from the corners x (m, 3, 3): unit normal n (m, 3),
    double_area (m,), side length (m, 3) and outward in-plane unit normal n^c_s (m, 3, 3), and
    gradient D (m, 3, 3), D[s, k] = -grad N_k . n^c_s: the element's share of the fold angle's
    gradient is d phi_s / d x_k = D[s, k] n (Eq. 36)."""
    normal = cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    double_area = np.linalg.norm(normal, axis=1)
    n = normal / double_area[:, None]
    side = x[:, SIDE_TO] - x[:, SIDE_FROM]  # (m, 3, 3): side s from p to q
    length = np.linalg.norm(side, axis=-1)
    outward = cross(side, n[:, None, :]) / length[..., None]  # n^c_s
    grad_n = cross(n[:, None, :], side) / double_area[:, None, None]  # grad N_k
    gradient = -np.matmul(outward, grad_n.transpose(0, 2, 1))  # D[s, k]
    return {
        "normal": n,
        "double_area": double_area,
        "length": length,
        "outward": outward,
        "gradient": gradient,
    }


def geometry(block: FibrousShellBlock, positions: np.ndarray, geo: dict | None = None) -> dict:
    """Fold angles, curvature coefficients and fold-angle gradients (docs/theory.md §4.1-4.3).

    fold : (m, 3) theta_s per side, atan2(-n'.n^c_s, n.n'); 0 on free sides and in held
        cells; against the element's reference plane on clamped sides, and against the wall
        through the side perpendicular to the plane on a symmetry plane's sides.
    coefficients : (m, 2, 3) c_as = 2 (g_a . n^c_s)^2 / (h_s + h_s') (0 on free sides and
        in held cells).
    gradient : (m, 3, 3) D[s, k] with d phi_s / d x_k = D[s, k] n (the element's share of
        d theta_s / dx, Eq. 36: D = -grad N_k . n^c_s).
    """
    if block.compiled:
        return geometry_kernels.bending_geometry(block, positions)
    x = positions[block.connectivity] if geo is None else geo["corners"]
    sides = side_geometry(x)
    n, double_area = sides["normal"], sides["double_area"]
    side_length, outward, gradient = sides["length"], sides["outward"], sides["gradient"]

    nb = block.across_cell
    n_other = np.where(block.interior_side[..., None], n[nb], 0.0)
    if block.clamped_side.any():
        wall = np.broadcast_to(block.reference_normal[:, None, :], n_other.shape)
        if block.mirror_normal.any():
            # On a symmetry plane the wall through the side perpendicular to the plane:
            # the fold against the mirrored cell is twice this one (symmetry.py).
            side = x[:, SIDE_TO] - x[:, SIDE_FROM]
            mirrored = cross(block.mirror_normal, side)
            norm = np.linalg.norm(mirrored, axis=-1, keepdims=True)
            mirrored = np.divide(mirrored, norm, out=np.zeros_like(mirrored), where=norm > 0)
            is_mirror = np.any(block.mirror_normal != 0.0, axis=-1)
            wall = np.where(is_mirror[..., None], mirrored, wall)
        n_other = np.where(block.clamped_side[..., None], wall, n_other)
    has_fold = block.interior_side | block.clamped_side
    fold = np.where(
        has_fold,
        np.arctan2(-np.sum(n_other * outward, axis=-1), np.matmul(n_other, n[:, :, None])[..., 0]),
        0.0,
    )
    heights = double_area[:, None] / side_length
    other_heights = np.where(block.interior_side, double_area[nb] / side_length, 0.0)
    fibre = np.stack([x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]], axis=1)
    fibre /= np.linalg.norm(fibre, axis=-1, keepdims=True)
    projection = np.matmul(fibre, outward.transpose(0, 2, 1))  # (m, a, s)
    coefficients = np.where(
        has_fold[:, None, :],
        2.0 * projection**2 / (heights + other_heights)[:, None, :],
        0.0,
    )
    return {"fold": fold, "coefficients": coefficients, "gradient": gradient, "normal": n}


def curvatures(block: FibrousShellBlock, bend: dict) -> tuple[np.ndarray, np.ndarray]:
    """chi (m, 2) along edges 0-1 and 0-2 (Eq. 35): chi_a = -sum_s c_as (theta_s - theta_s0),
    and the coefficients used."""
    coefficients = (
        block.reference_coefficients
        if block.reference_curvature_coefficients
        else bend["coefficients"]
    )
    chi = -np.matmul(coefficients, (bend["fold"] - block.reference_fold)[:, :, None])[..., 0]
    return chi, coefficients


def moments(block: FibrousShellBlock, chi: np.ndarray, slope: bool = False) -> np.ndarray:
    """M (m, 2) per unit width along edges 0-1 and 0-2 from the warp and weft laws (or,
    with ``slope``, dM/dchi)."""
    warp, weft = by_family(block.xi_is_warp, chi[:, 0], chi[:, 1])
    law = "slope" if slope else "value"
    m_warp = getattr(block.fabric.bending, law)(warp)
    m_weft = getattr(block.fabric.bending_weft, law)(weft)
    return np.stack(
        [np.where(block.xi_is_warp, m_warp, m_weft), np.where(block.xi_is_warp, m_weft, m_warp)],
        axis=1,
    )


def side_moments(block: FibrousShellBlock, moment: np.ndarray, coefficients: np.ndarray):
    """Each side's moment mu_s (m, 3), N mm: minus the sum over its two elements of
    A0 sum_a M_a c_as, from the moments M (m, 2) along edges 0-1 and 0-2 of every cell and the
    curvature coefficients c_as (m, 2, 3) used; 0 on free sides (c = 0 there)."""
    own = -block.reference_area[:, None] * np.matmul(moment[:, None, :], coefficients)[:, 0]
    across = np.where(block.interior_side, own[block.across_cell, block.across_side], 0.0)
    return own + across  # free sides: own = 0 since c = 0


def forces(block: FibrousShellBlock, positions: np.ndarray, geo: dict | None = None):
    """Nodal bending forces (m, 3, 3) (Eq. 37): the energy A0 sum_a Phi_a(chi_a) varies
    through the fold angles; each side's moment mu = -sum over its two elements of
    A0 sum_a M_a c_as multiplies d theta/dx, whose share on each element's own nodes is
    D[s, k] n, so every element scatters to its own three nodes only."""
    bend = geometry(block, positions, geo)
    chi, coefficients = curvatures(block, bend)
    side_moment = side_moments(block, moments(block, chi), coefficients)
    weights = np.matmul(side_moment[:, None, :], bend["gradient"])[:, 0]
    return weights[..., None] * bend["normal"][:, None, :]


def energy(block: FibrousShellBlock, positions: np.ndarray):
    """The bending energy of the block (N mm): A0 sum_a Phi_a(chi_a), Phi the laws'
    energies."""
    chi, _ = curvatures(block, geometry(block, positions))
    chi_warp, chi_weft = by_family(block.xi_is_warp, chi[:, 0], chi[:, 1])
    return np.sum(
        block.reference_area
        * (block.fabric.bending.energy(chi_warp) + block.fabric.bending_weft.energy(chi_weft))
    )


def tangent(block: FibrousShellBlock, positions: np.ndarray) -> CellTangent:
    """Stiffness of the bending forces F = sum_e A0 sum_a M_a(chi_a) dchi_a/dx (Eq. 37).

    Material part: sum_e A0 sum_a (dM_a/dchi) g_a g_a^T with g_a = dchi_a/dx = -sum_s c_as
    dtheta_s/dx over the element's patch: its own three nodes (the share D[s, k] n of
    every side) and the three nodes of each neighbour (the neighbour's share), two of
    which are its own: six nodes (``patch_nodes``), blocks (m, 6, 3, 6, 3).
    Geometric part: sum_s mu_s d2theta_s/dx2, i.e. each element's own share mu_s D[s, k] n
    differentiated (``share_tangent``, the side moments mu_s held). The coefficients c_as
    are held too, as in the force (exact with ``bending_geometry="reference"``; with
    "current" the neglected dc/dx terms are of the order of the fold-angle change over the
    increment).
    """
    terms = tangent_terms(block, positions)
    every = slice(None)
    return CellTangent(patch_nodes(block)[0], tangent_blocks(block, positions, terms, every))


def tangent_terms(block: FibrousShellBlock, positions: np.ndarray) -> dict:
    """What ``tangent_blocks`` needs of all cells (a few numbers a cell): the curvature
    coefficients (m, a, s), the sides' D[s, k] (m, s, k) and the normals (m, 3) (their shares
    D[s, k] n formed per slice), the moment slopes (m, a) and the side moments (m, s)."""
    bend = geometry(block, positions)
    chi, coefficients = curvatures(block, bend)
    return {
        "coefficients": coefficients,
        "gradient": bend["gradient"],
        "normal": bend["normal"],
        "slopes": moments(block, chi, slope=True),
        "side_moment": side_moments(block, moments(block, chi), coefficients),
    }


def tangent_blocks(
    block: FibrousShellBlock, positions: np.ndarray, terms: dict, cells: slice | np.ndarray
) -> np.ndarray:
    """The blocks (c, 6, 3, 6, 3), N/mm, of ``tangent`` for ``cells`` (c of them: a slice or
    an index array) from ``tangent_terms``: each cell's own, so that a slice's are those of
    the whole to round-off (numpy's batched products may round differently in batches of
    other sizes)."""
    coefficients = terms["coefficients"][cells]
    gradient, normal = terms["gradient"], terms["normal"]  # all cells: the neighbours' too
    share = gradient[cells][..., None] * normal[cells][:, None, None, :]  # D[s, k] n
    across_cell, across_side = block.across_cell[cells], block.across_side[cells]
    across = gradient[across_cell, across_side][..., None] * normal[across_cell][:, :, None, :]
    across_share = np.where(block.interior_side[cells][..., None, None], across, 0.0)
    m = len(coefficients)
    own = -np.einsum("mas,mskj->makj", coefficients, share)  # (m, a, 3, 3)
    across = -coefficients[..., None, None] * across_share[:, None]  # (m, a, s, 3, 3)
    # The patch has six nodes, not twelve: each neighbour shares the two nodes of its side,
    # so its share folds onto those and the node opposite (slot 3 + s); the blocks are then
    # a quarter of the size to form and to assemble.
    fold = _whole_patch(block)[2][cells]  # (m, s * 3 + j, 6)
    g = np.matmul(fold.transpose(0, 2, 1)[:, None], across.reshape(m, 2, 9, 3))
    g[:, :, :3] += own  # (m, a, 6, 3)
    weight = block.reference_area[cells][:, None] * terms["slopes"][cells]  # (m, a)
    flat = g.reshape(m, 2, 18)
    blocks = np.matmul(flat.transpose(0, 2, 1) * weight[:, None, :], flat)
    blocks = blocks.reshape(m, 6, 3, 6, 3)  # sum_a w_a g_a g_a^T

    side_moment = terms["side_moment"][cells]
    x = positions[block.connectivity[cells]]
    if block.compiled and tangent_kernels.AVAILABLE:
        blocks[:, :3, :, :3] += tangent_kernels.share_stiffness(x, side_moment)
    else:
        blocks[:, :3, :, :3] += share_tangent(x, side_moment)
    return blocks


def patch_nodes(
    block: FibrousShellBlock, cells: slice | np.ndarray = slice(None)
) -> tuple[np.ndarray, np.ndarray]:
    """The six nodes of each cell's bending patch (m, 6): its corners, then across each
    side s the neighbour's node opposite it (the cell's corner s where the side couples
    no neighbour: its blocks are zero there); and the patch slot (m, 9) of the
    neighbour's corner j across side s, at s * 3 + j; of the block's ``cells`` (a slice or an
    index array; all by default). Read-only: those of the whole block, made once."""
    nodes, slot, _ = _whole_patch(block)
    return nodes[cells], slot[cells]


def _whole_patch(block: FibrousShellBlock) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``patch_nodes`` of all the block's cells and the fold of each neighbour's corner onto
    the patch, (m, 9, 6) float, 1 at (s * 3 + j, slot): a function of the block's side tables
    alone, made at the first call and again when ``apply_supports`` has set new tables (the
    tables kept beside it are compared by identity). A static solve asks for it twice a
    tangent: 0.49 s of the paper cases' 29 s of solves when it was made at each call
    (benchmarks/paper_case_cost.py)."""
    tables = (block.connectivity, block.interior_side, block.across_cell)
    kept = block.bending_patch
    if kept is not None and all(a is b for a, b in zip(kept[0], tables)):
        return kept[1]
    nodes, slot = _patch_of(*tables)
    fold = (slot[..., None] == np.arange(6)).astype(float)
    for array in (nodes, slot, fold):
        array.setflags(write=False)
    block.bending_patch = (tables, (nodes, slot, fold))
    return nodes, slot, fold


def _patch_of(
    connectivity: np.ndarray, interior_side: np.ndarray, across_cell: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """``patch_nodes`` of every cell of these side tables (m, 6) and (m, 9), int."""
    conn = connectivity
    interior = interior_side
    other = connectivity[across_cell]  # (m, s, j)
    slot = np.broadcast_to(3 + np.arange(3)[None, :, None], other.shape).copy()
    for end in (SIDE_FROM, SIDE_TO):
        ends = conn[:, end]  # (m, s): the side's end node
        slot = np.where(other == ends[..., None], end[None, :, None], slot)
    slot = np.where(interior[..., None], slot, 3 + np.arange(3)[None, :, None])
    opposite = np.where(slot == 3 + np.arange(3)[None, :, None], other, 0).max(axis=2)
    opposite = np.where(interior, opposite, conn)
    return np.concatenate([conn, opposite], axis=1), slot.reshape(len(conn), 9)


def share_tangent(x: np.ndarray, side_moment: np.ndarray) -> np.ndarray:
    """d/dx of each element's own share of the bending forces, sum_s mu_s D[s, k] n (Eq. 37),
    with the side moments mu_s (m, 3) held: (m, 3, 3, 3, 3), N/mm. The formulas of
    ``side_geometry`` differentiated in the 9 unit directions of the corners, all cells at
    once (directions on axis 1)."""
    sides = side_geometry(x)
    n, area2 = sides["normal"][:, None], sides["double_area"][:, None, None]
    length, outward = sides["length"][:, None, :, None], sides["outward"][:, None]
    directions = np.eye(9).reshape(9, 3, 3)  # (direction, corner, component)
    a, b = x[:, None, 1] - x[:, None, 0], x[:, None, 2] - x[:, None, 0]
    da, db = directions[:, 1] - directions[:, 0], directions[:, 2] - directions[:, 0]
    dc = cross(da, b) + cross(a, db)  # (m, 9, 3)
    d_area2 = np.sum(n * dc, axis=-1)[..., None]
    dn = (dc - d_area2 * n) / area2
    nn, dnn = n[:, :, None], dn[:, :, None]
    side = (x[:, SIDE_TO] - x[:, SIDE_FROM])[:, None]  # (m, 1, s, 3)
    d_side = directions[:, SIDE_TO] - directions[:, SIDE_FROM]  # (9, s, 3)
    d_length = np.sum(side * d_side, axis=-1)[..., None] / length
    d_outward = (cross(d_side, nn) + cross(side, dnn)) / length - outward * d_length / length
    grad_n = cross(nn, side) / area2[..., None]  # grad N_k, (m, 1, k, 3)
    d_grad_n = (cross(dnn, side) + cross(nn, d_side)) / area2[..., None] - grad_n * (
        d_area2[..., None] / area2[..., None]
    )
    swap = (0, 1, 3, 2)
    d_gradient = -(
        np.matmul(d_outward, grad_n.transpose(swap)) + np.matmul(outward, d_grad_n.transpose(swap))
    )  # dD[s, k], (m, 9, s, k)
    w = np.matmul(side_moment[:, None, :], sides["gradient"])[:, 0][:, None, :, None]
    dw = np.matmul(side_moment[:, None, None, :], d_gradient)[:, :, 0][..., None]
    force = dw * nn + w * dnn  # (m, 9, k, 3)
    return force.reshape(len(x), 3, 3, 3, 3).transpose(0, 3, 4, 1, 2)
