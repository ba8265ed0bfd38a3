"""The exact first derivatives of the fibrous shell's level measures (``fibre_strains``: each
level's warp and weft strains and shear angle, per cell) with respect to the nodes' positions
and directors, which the static solver's level projection takes as its J (solvers/newton_levels.py,
docs/theory.md §6.5).

Each measure s of a cell is a function of the level vectors g_1, g_2 of its level (geometry.py,
Eq. 8), g_a = x_a - x_0 + zeta_f / 2 (h_a V_a - h_0 V_0), and, with nodal normals, of the cell's
normal n (the fibre length is |P g_a|, P = I - n n^T, membrane.py ``fibre_lengths``). So its
gradient is the "force" of membrane.py ``layer_forces`` with the loads P_a = ds/dg_a and
dW/dn = ds/dn in place of the energy's, each measure its own row:

- the log strain eps_a = log |P g_a| - log L_a: ds/dg_a = P g_a / l_a^2 and
  ds/dn = -(n . g_a) P g_a / l_a^2 (without nodal normals |g_a|, g_a / |g_a|^2);
- the shear angle gamma = sign asin(u_1 . u_2) - gamma_0: ds/dg_1 = sign (u_2 - c u_1) /
  (|g_1| sin), and likewise for g_2.

The variation of h_m = h / max(V . N, guard) is always counted (the measures depend on it
whatever the block's ``thickness_variation``, which concerns the forces): through the director
and, with nodal normals, through the normal sums S_k of the corners, S_k = sum over the cells
around node k of alpha_k n, whose derivative dS/dx reaches the nodes one cell from the corners
(assembled sparse here; the wall nodes' sums do not vary).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from elements.fibrous import hessian_kernels, level_kernels
from elements.fibrous.geometry import cell_geometry, corner_normals, normal_sums, row_dot
from elements.fibrous.symmetry import on_planes
from elements.shell_geometry import GUARD
from femcore.rotation import cross

if TYPE_CHECKING:
    from elements.fibrous.block import FibrousShellBlock

__all__ = ["level_strain_gradient", "sums_pairs"]


def _pull(x: np.ndarray, g: np.ndarray) -> np.ndarray:
    """d(g . c)/dx at the corners (m, p, 3, 3) of c = (x1 - x0) x (x2 - x0), g (m, p, 3)
    held (geometry.py ``cross_product_pull`` with an axis of measures)."""
    a = (x[:, 1] - x[:, 0])[:, None, :]
    b = (x[:, 2] - x[:, 0])[:, None, :]
    along_a, along_b = cross(b, g), cross(g, a)
    return np.stack([-(along_a + along_b), along_a, along_b], axis=2)


def level_strain_gradient(
    block: FibrousShellBlock,
    positions: np.ndarray,
    directors: np.ndarray,
    compiled: bool | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, np.ndarray | None]:
    """The derivatives of ``fibre_strains`` (row j of a cell: eps1 of each level, then eps2,
    then gamma; p = 3 L measures) at each cell's corners.

    Parameters
    ----------
    block : the fibrous block.
    positions, directors : (n, 3) float, mm and unit.
    compiled : None (the block's kernel: compiled where it is and numba is installed), True
        (level_kernels.py's cell loop, one cell at a time) or False (the numpy below, the
        reference of the compiled loop).

    Returns
    -------
    direct : (m, p, 3, 3) float, 1/mm (strains) and rad/mm (shear): ds/dx_k at corner k, the
        nodal normals held.
    turns : (m, p, 3, 3) float, per rad: V_k x ds/dV_k, so that a turn d psi of the
        director (dV = d psi x V) changes the measure by turns . d psi.
    through_sums : (m, p, 3, 3) float or None (element normals): ds/dS_k at corner k.
    shares : (m, 3, 3, 3, 3) float or None, 1/mm: d(alpha_k n)/dx_j of each cell (corner k,
        its component, corner j, x component), zero on the wall nodes' rows. A measure's
        derivative is direct plus, through the normal sums, sum over the cells e around its
        corner's node of through_sums . shares of e (``sums_pairs``).
    """
    conn = block.connectivity
    m, levels = conn.shape[0], block.zeta.size
    p = 3 * levels
    x, v = positions[conn], directors[conn]
    nodal = bool(block.nodal_normals)
    sums = normal_sums(block, positions)[conn] if nodal else None
    if compiled is None:
        compiled = block.compiled and level_kernels.AVAILABLE
    if compiled:
        direct, turns, through_sums = level_kernels.level_gradient_cells(
            x, v, sums, block.zeta, block.fabric.thickness, block.shear_sign, GUARD
        )
        if not nodal:
            return direct, turns, None, None
        return direct, turns, through_sums, _shares(block, x, conn)
    geo = cell_geometry(block, x, v, True, sums)
    g1, g2, n = geo["g1"], geo["g2"], geo["normal"]
    # The loads of each measure on g_1, g_2 (m, p, 3) and on n; each at its own level.
    p1, p2, normal_load = np.zeros((3, m, p, 3))
    if nodal:
        for g, load, rows in ((g1, p1, slice(0, levels)), (g2, p2, slice(levels, 2 * levels))):
            along = row_dot(g, n[:, None, :])
            in_plane = g - along[..., None] * n[:, None, :]
            coefficient = 1.0 / row_dot(in_plane, in_plane)
            load[:, rows] = coefficient[..., None] * in_plane
            normal_load[:, rows] = -(coefficient * along)[..., None] * in_plane
        # n = c / |c|: ds/dc = P ds/dn / |c|, pulled through the bilinear c.
        normal_load -= row_dot(normal_load, n[:, None, :])[..., None] * n[:, None, :]
        normal_load /= geo["double_area"][:, None, None]
    else:
        p1[:, :levels] = g1 / row_dot(g1, g1)[..., None]
        p2[:, levels : 2 * levels] = g2 / row_dot(g2, g2)[..., None]
    len1, len2 = np.sqrt(row_dot(g1, g1)), np.sqrt(row_dot(g2, g2))
    u1, u2 = g1 / len1[..., None], g2 / len2[..., None]
    c = row_dot(u1, u2)
    sine = np.sqrt(np.maximum(1.0 - c**2, 1e-24))
    sign = block.shear_sign[:, None]
    p1[:, 2 * levels :] = (sign / (len1 * sine))[..., None] * (u2 - c[..., None] * u1)
    p2[:, 2 * levels :] = (sign / (len2 * sine))[..., None] * (u1 - c[..., None] * u2)
    corner = np.stack([-(p1 + p2), p1, p2], axis=2)  # (m, p, 3 corners, 3)
    direct = corner + _pull(x, normal_load) if nodal else corner.copy()
    # The levels' end points x_k + zeta_f / 2 h_k V_k: ds/dV_k = h_k / 2 zeta_f F_k and
    # ds/dh_k = zeta_f / 2 F_k . V_k.
    lever = np.tile(block.zeta, 3)[None, :, None, None] * corner
    h_m, cosine = geo["thickness"], geo["cosine"]
    turns = 0.5 * h_m[:, None, :, None] * cross(v[:, None], lever)
    ds_dh = 0.5 * row_dot(lever, v[:, None])
    # h_m = h / (V . N): dh/dc = -h / c^2 where unguarded (the guard holds it constant).
    thickness = block.fabric.thickness
    ds_dc = np.where(geo["guarded"][:, None], 0.0, -ds_dh * thickness / cosine[:, None] ** 2)
    normal_of_corner = geo["node_normal"] if nodal else np.broadcast_to(n[:, None, :], v.shape)
    turns += ds_dc[..., None] * cross(v, normal_of_corner)[:, None]
    if not nodal:
        # c_k = V_k . n, n = c / |c|: dc_k = (V_k - c_k n) . dc / |c|.
        v_perp = v - cosine[..., None] * n[:, None, :]
        g = np.matmul(ds_dc, v_perp) / geo["double_area"][:, None, None]
        return direct + _pull(x, g), turns, None, None
    # c_k = V_k . S_k / |S_k|: dc/dS_k = (V_k - c N_k) / |S_k|.
    tilt = (v - cosine[..., None] * normal_of_corner) / geo["normal_sum_length"][..., None]
    through_sums = ds_dc[..., None] * tilt[:, None]
    return direct, turns, through_sums, _shares(block, x, conn)


def _shares(block: FibrousShellBlock, x: np.ndarray, conn: np.ndarray) -> np.ndarray:
    """d(alpha_k n)/dx_j of each cell (m, 3, 3, 3, 3), zero on the wall nodes' rows."""
    held = block.wall_nodes[conn]
    if block.compiled and hessian_kernels.AVAILABLE:
        return on_planes(block, conn, hessian_kernels.normal_share_jacobians(x, held))
    return on_planes(
        block, conn, corner_normals(x, jacobian=True)[1] * ~held[..., None, None, None]
    )


def sums_pairs(block: FibrousShellBlock) -> tuple[np.ndarray, ...]:
    """(cell c, corner k, cell e, corner k') of every pair of cell corners on a common node
    (conn[c, k] == conn[e, k']), (q,) each: the cells e whose shares make the normal sum S_k
    that cell c's measures see at its corner k."""
    conn = block.connectivity
    corners = conn.ravel()
    order = np.argsort(corners, kind="stable")
    counts = np.bincount(corners, minlength=block.n_nodes)
    starts = np.concatenate([[0], np.cumsum(counts)])
    # For each corner (c, k): every corner of its node, the node's run in ``order``.
    own = np.repeat(np.arange(corners.size), counts[corners])
    offset = np.arange(own.size) - np.repeat(
        np.cumsum(counts[corners]) - counts[corners], counts[corners]
    )
    other = order[starts[corners[own]] + offset]
    return own // 3, own % 3, other // 3, other % 3
