"""The analytic tangent stiffness of the fibrous shell (docs/theory.md §2.6, §4.4).

Tension + shear with nodal normals (``nodal_membrane_tangent``): the energy is a sum of cell
energies W_e(x_e, psi_e, S_e) whose third argument, the nodal normal sums S_k, reaches the
cells around each node, so K = J^T H J + sum_f sum_k T_k . d2(alpha_k^f n_f)/dx2 with H the
cells' Hessians in (x, psi, S) (``membrane_hessian``), J the map from (u, psi) to (u, psi, S)
and T_k = dW/dS_k (``corner_normal_pull_tangent``), assembled on the node pairs of the cells
(``CornerPairs``). With element normals each cell's 18 x 18 block by central differences of
its loads (``membrane_loads``). The bending stiffness is bending.py ``tangent``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from elements.base import CellTangent, SparseTangent, local_tangent, stacked_local_tangent
from elements.fibrous import bending, hessian_kernels, kernels, tangent_kernels
from elements.fibrous.compression_floor import strain_floors
from elements.fibrous.fibres import by_family
from elements.fibrous.geometry import (
    cell_geometry,
    corner_geometry,
    corner_normals,
    free_sums,
    normal_sums,
    skew,
)
from elements.fibrous.membrane import layer_forces, layer_loads, strains
from elements.fibrous.symmetry import on_planes
from femcore.assembly import TangentPart
from femcore.rotation import cross
from femcore.state import State

if TYPE_CHECKING:
    from elements.fibrous.block import FibrousShellBlock

__all__ = [
    "CornerPairs",
    "cell_gradient",
    "corner_normal_pull_tangent",
    "membrane_hessian",
    "membrane_loads",
    "nodal_membrane_tangent",
    "tangent",
]


def tangent(
    block: FibrousShellBlock,
    state: State,
    compression_free: bool = False,
    floors: tuple[np.ndarray, np.ndarray] | None = None,
) -> list[TangentPart]:
    """Stiffness of tension + shear and of bending (Eq. 37 differentiated, see bending.py
    ``tangent``). Tension + shear: with element normals each cell's own 18 x 18, by central
    differences of its loads, all cells at once; with nodal normals the sparse matrix of
    ``nodal_membrane_tangent`` (closed form, as the bending).

    compression_free : with nodal normals, the stress terms of the tension (those of T, not
    of T') with each fibre's strain raised to at least zero (``membrane_hessian``): the
    tangent of Newton's iterates far from equilibrium (solvers.newton, docs/theory.md §6.5).
    The material terms T'(eps) are kept; element normals ignore the flag. ``floors``: the
    strains it raises them to (compression_floor.py; None: zero)."""
    bend = bending.tangent(block, state.positions)
    if block.nodal_normals:
        sparse, second = nodal_membrane_tangent(block, state, compression_free, floors)
        # The cell-local translation blocks join the bending patch's (its first 3 nodes).
        bend.blocks[:, :3, :, :3] += second
        return [sparse, bend]
    x = state.positions[block.connectivity]
    v = state.directors[block.connectivity]
    step = 1e-6 * float(np.sqrt(np.median(block.reference_area)))
    if block.compiled and hessian_kernels.AVAILABLE:
        # The 36 perturbed copies of the cells through the compiled passes in one call
        # (kernels.py ``cell_membrane_loads``): the numpy loads cost 30 ms a tangent on 400
        # cells (benchmarks/paper_cases.py).
        membrane = stacked_local_tangent(
            lambda xs, vs: kernels.cell_membrane_loads(block, xs, vs), x, v, step
        )
    else:
        membrane = local_tangent(lambda xx, vv: membrane_loads(block, xx, vv), x, v, step)
    return [CellTangent(block.connectivity, membrane), bend]


def membrane_loads(block: FibrousShellBlock, x: np.ndarray, v: np.ndarray):
    """Unscattered tension + shear forces and director moments (m, 3, 3) of each cell from its
    corner positions x and directors v (m, 3, 3) (element normals: cell-local)."""
    geo = cell_geometry(block, x, v)
    loads = layer_loads(block, geo, strains(block, geo))
    force, moment, _ = layer_forces(block, geo, *loads)
    return force, moment


def cell_gradient(
    block: FibrousShellBlock, x: np.ndarray, v: np.ndarray, sums: np.ndarray
) -> np.ndarray:
    """The gradient of each cell's tension + shear energy W_e(x_e, V_e, S_e) with the
    nodal normal sums S_k of its corners (m, 3, 3) as independent variables: (m, 3, 9), per
    corner (dW/dx, dW/dpsi, dW/dS)."""
    geo = cell_geometry(block, x, v, True, sums)
    loads = layer_loads(block, geo, strains(block, geo))
    force, moment, d_sums = layer_forces(block, geo, *loads)
    return np.concatenate([force, moment, d_sums], axis=-1)


def nodal_membrane_tangent(
    block: FibrousShellBlock,
    state: State,
    compression_free: bool = False,
    floors: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[SparseTangent, np.ndarray]:
    """Exact stiffness of tension + shear with nodal normals (docs/theory.md §2.6): a sparse
    matrix over the nodes in 6 x 6 blocks and the cell-local translation blocks of the
    second derivatives of the normal sums (m, 3, 3, 3, 3), as in CellTangent.blocks.

    W = sum_e W_e(x_e, psi_e, S_e) with S_k = sum_(f around k) alpha_k^f n_f(x_f), so
    K = J^T H J + sum_f sum_k T_k . d2(alpha_k^f n_f)/dx2: H the cells' 27 x 27 Hessians in
    (x, psi, S) per corner (``membrane_hessian``), J the map from (u, psi) to (u, psi, S)
    (dS_k/dx_j, the sum of d(alpha_k^f n_f)/dx_j over the cells f around k holding j,
    exact), and T_k = dW/dS_k (the second term ``corner_normal_pull_tangent``, closed form).

    H and J are block sparse on the node pairs of the cells (``CornerPairs``, built once):
    their blocks are summed into that fixed pattern by one bincount each, and the product
    is a BSR matrix with 6 x 6 blocks. ``compression_free``, ``floors``: see
    ``membrane_hessian``.
    """
    conn = block.connectivity
    x = state.positions[conn]
    v = state.directors[conn]
    sums = normal_sums(block, state.positions)[conn]
    pairs = block.corner_pairs()
    if (
        block.compiled and hessian_kernels.AVAILABLE
    ):  # the same numbers by the compiled loops (hessian_kernels.py, tangent_kernels.py)
        h_blocks, d_sums = hessian_kernels.pair_hessians(
            block, x, v, sums, pairs, compression_free=compression_free, floors=floors
        )
        ds_dx = hessian_kernels.normal_share_jacobians(x, block.wall_nodes[conn])
        ds_dx = on_planes(block, conn, ds_dx)
        j_blocks = hessian_kernels.pair_sums(pairs.slot, ds_dx, pairs.n_pairs)
        pull = free_sums(block, block.scatter.vectors(d_sums))[conn]  # T_k (m, 3, 3)
        second = tangent_kernels.normal_pull_stiffness(x, pull)
        if pairs.product is None:
            pairs.product = tangent_kernels.MembraneProduct(
                pairs.indptr, pairs.indices, pairs.n_nodes
            )
        return SparseTangent(pairs.product(h_blocks, j_blocks)), second

    hessian, d_sums = membrane_hessian(block, x, v, sums, compression_free, floors)
    h_ext = pairs.hessian(hessian)
    # J: (u, psi) of node k -> rows 9k..9k+5; S_k <- d(alpha_k^f n_f)/dx_j for k, j
    # corners of f.
    _, ds_dx = corner_normals(x, jacobian=True)  # (m, corner k, S comp, node j, x comp)
    ds_dx = on_planes(block, conn, ds_dx * ~block.wall_nodes[conn][:, :, None, None, None])
    jac = pairs.jacobian(ds_dx)
    # sum_f sum_k T_k . d2(alpha_k^f n_f)/dx2, T held.
    pull = free_sums(block, block.scatter.vectors(d_sums))[conn]  # T_k (m, 3, 3)
    second = corner_normal_pull_tangent(x, pull)
    return SparseTangent(jac.T @ (h_ext @ jac)), second


# ---------------------------------------------------------------------- the cells' Hessians
def membrane_hessian(
    block: FibrousShellBlock,
    x: np.ndarray,
    v: np.ndarray,
    sums: np.ndarray,
    compression_free: bool = False,
    floors: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """d(``cell_gradient``)/d(x, psi, S) of every cell (m, 3, 9, 3, 9), with nodal normals:
    row (corner, dW/dx | dW/dpsi | dW/dS), column (corner, x | psi | S); N/mm, N, N mm and
    per unit of S (the sums are angle-weighted normals, rad). Also the gradient's dW/dS
    (m, 3, 3), N mm, from the same loads.

    The cell energy reaches the 27 unknowns q through w = (e_a, d_a, n), 15 numbers:
    g_a^f = e_a + zeta_f / 2 d_a at each level f, with the edges e_a = x_a - x_0, the
    director offsets d_a = D_a - D_0 (D_k = h_m^k V_k) and n the element normal. So the
    stiffness is A^T H_w A plus the terms of the second derivatives of w: H_w from the
    9 x 9 derivatives of each level's loads (P_1, P_2, dW/dn) in (g_1, g_2, n)
    (``level_hessians``), summed over the levels with weights 1, zeta_f / 2, (zeta_f / 2)^2;
    A = dw/dq (a director turns as dV = dpsi x V); the second derivatives of n(x) contracted
    with dW/dn and of D_k(psi_k, S_k) with dW/dD_k. Every term is the derivative of the
    gradient's own formulas (with ``thickness_variation=False``, of its moments without the
    h_m term), so this is what central differences of ``cell_gradient`` converge to, in a few
    batched products instead of 54 evaluations of it.

    compression_free : the tension's stress terms (every term of T itself: the loads P_a
    and dW/dn that the second derivatives of g, n and D are contracted with, and the -2 T of
    d(T / l^2)) with each fibre's strain raised to at least its floor (``floors``: (warp,
    weft) (m, L), the compression of the last converged state, compression_floor.py; None:
    zero); the material term T'(eps) at the strain itself. Not the Hessian of W then, but
    the tangent that Newton's iterates far from equilibrium use (docs/theory.md §6.5):
    there a step's remainder compresses fibres whose stiffness is thousands of times the
    bending's, and their compression's geometric stiffness makes the tangent indefinite.
    dW/dS (the second output) is then that of the raised strains too.
    """
    geo = cell_geometry(block, x, v, True, sums)
    strain = strains(block, geo)
    slack = strain
    if compression_free:
        floor1, floor2 = strain_floors(floors, len(x), block.zeta.size)
        slack = {
            **strain,
            "eps1": np.maximum(strain["eps1"], floor1),
            "eps2": np.maximum(strain["eps2"], floor2),
        }
    p1, p2, normal_load = layer_loads(block, geo, slack)
    m = len(x)
    h_w = _level_sums(block.zeta, level_hessians(block, geo, strain, slack))
    jac, jac_rows = _variable_jacobians(block, geo)
    hessian = np.matmul(np.swapaxes(jac_rows, 1, 2), np.matmul(h_w, jac))
    hessian = hessian.reshape(m, 3, 9, 3, 9)
    corners = np.arange(3)
    hessian[:, :, 0:3, :, 0:3] += _normal_second_derivatives(geo, normal_load)
    explicit = _director_second_derivatives(block, geo, p1, p2)
    hessian[:, corners, 3:, corners, 3:] += explicit.transpose(2, 0, 3, 1)
    _, _, d_sums_gradient = layer_forces(block, geo, p1, p2, normal_load)
    return hessian, d_sums_gradient


def level_hessians(
    block: FibrousShellBlock, geo: dict, strain: dict, slack: dict | None = None
) -> np.ndarray:
    """Each level's loads (P_1, P_2, dW/dn) of ``membrane.layer_loads`` differentiated in
    (g_1, g_2, n): hz[m, f, out, i, in, j] (m, L, 3, 3, 3, 3), tension then shear.
    ``slack``: the strains of the tensions T in the stress terms (``membrane_hessian``;
    default ``strain``)."""
    m, levels = len(geo["corners"]), block.zeta.size
    hz = np.zeros((m, levels, 3, 3, 3, 3))
    _add_tension_hessians(block, geo, strain, hz, strain if slack is None else slack)
    _add_shear_hessians(block, geo, strain, hz)
    return hz


def _outer(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a b^T over the last axis (..., 3, 3)."""
    return a[..., :, None] * b[..., None, :]


def _add_tension_hessians(
    block: FibrousShellBlock, geo: dict, strain: dict, hz: np.ndarray, slack: dict
):
    """hz += the tension part of ``level_hessians``: P_a = A0 w T_a P g_a / l^2 and
    dW/dn = -sum_a A0 w T_a (n . g_a) P g_a / l^2 (membrane.py ``layer_loads``); T_a at the
    strains of ``slack``, T'_a at those of ``strain``."""
    eye = np.eye(3)
    scale = block.reference_area[:, None] * block.weights[None, :]  # A0 w_f, (m, L)
    n = geo["normal"][:, None, :]  # (m, 1, 3)
    warp, weft = by_family(block.xi_is_warp, strain["eps1"], strain["eps2"])
    slack_warp, slack_weft = by_family(block.xi_is_warp, slack["eps1"], slack["eps2"])
    flag = block.xi_is_warp[:, None]
    fabric = block.fabric
    value = fabric.tension.value(slack_warp), fabric.tension_weft.value(slack_weft)
    slope = fabric.tension.slope(warp), fabric.tension_weft.slope(weft)
    tensions = (
        (np.where(flag, value[0], value[1]), np.where(flag, slope[0], slope[1])),
        (np.where(flag, value[1], value[0]), np.where(flag, slope[1], slope[0])),
    )
    projector = eye - n[..., :, None] * n[..., None, :]  # (m, 1, 3, 3)
    for edge, g, (t, t_slope), fibre in (
        (0, geo["g1"], tensions[0], strain["fibre1"]),
        (1, geo["g2"], tensions[1], strain["fibre2"]),
    ):
        # P = kappa r, dW/dn = -kappa s r: r = g - s n, s = g . n, kappa = A0 w T / l^2,
        # and d kappa = beta (r . dg - s r . dn), beta = A0 w (T' - 2 T) / l^4.
        s = np.sum(g * n, axis=-1)[..., None, None]  # (m, L, 1, 1)
        r = g - s[..., 0] * n
        kappa = (scale * t / fibre**2)[..., None, None]
        beta = (scale * (t_slope - 2.0 * t) / fibre**4)[..., None, None]
        rr = r[..., :, None] * r[..., None, :]
        ng = n[..., :, None] * g[..., None, :]
        hz[:, :, edge, :, edge, :] += beta * rr + kappa * projector
        hz[:, :, edge, :, 2, :] += -s * beta * rr - kappa * (ng + s * eye)
        hz[:, :, 2, :, edge, :] += -s * beta * rr - kappa * (
            r[..., :, None] * n[..., None, :] + s * projector
        )
        hz[:, :, 2, :, 2, :] += s**2 * beta * rr - kappa * (
            r[..., :, None] * g[..., None, :] - s * ng - s**2 * eye
        )


def _add_shear_hessians(block: FibrousShellBlock, geo: dict, strain: dict, hz: np.ndarray):
    """hz += the shear part of ``level_hessians``: P_a = A0 w f(c) dc/dg_a, c = u1 . u2,
    f = M / s, s = sqrt(1 - c^2) (membrane.py ``layer_loads``)."""
    eye = np.eye(3)
    scale = block.reference_area[:, None] * block.weights[None, :]  # A0 w_f, (m, L)
    len1, len2 = strain["length1"][..., None], strain["length2"][..., None]
    u1, u2 = geo["g1"] / len1, geo["g2"] / len2
    c = np.sum(u1 * u2, axis=-1)
    sine2 = 1.0 - c**2
    s = np.sqrt(np.maximum(sine2, 1e-24))
    gamma = strain["gamma"]
    moment = block.shear_sign[:, None] * block.fabric.shear.value(gamma)
    f = scale * moment / s
    # d(M / s)/dc: dM/dc = M'(gamma) / s (the sign enters M and gamma); ds/dc = -c / s.
    f_slope = scale * (
        block.fabric.shear.slope(gamma) / s**2 + np.where(sine2 > 1e-24, moment * c / s**3, 0.0)
    )
    c1 = (u2 - c[..., None] * u1) / len1  # dc/dg1
    c2 = (u1 - c[..., None] * u2) / len2
    q1 = (eye - u1[..., :, None] * u1[..., None, :]) / len1[..., None]  # du1/dg1
    q2 = (eye - u2[..., :, None] * u2[..., None, :]) / len2[..., None]
    cc = c[..., None, None]
    # d(dc/dg_a)/dg_b (Q_a = du_a/dg_a): -(u1 c1^T + c Q1 + c1 u1^T) / |g1| for a = b = 1,
    # (Q2 - u1 c2^T) / |g1| for a = 1, b = 2, and likewise for a = 2.
    second = (
        (
            -(_outer(u1, c1) + cc * q1 + _outer(c1, u1)) / len1[..., None],
            (q2 - _outer(u1, c2)) / len1[..., None],
        ),
        (
            (q1 - _outer(u2, c1)) / len2[..., None],
            -(_outer(u2, c2) + cc * q2 + _outer(c2, u2)) / len2[..., None],
        ),
    )
    grads = (c1, c2)
    for a in range(2):
        for b in range(2):
            hz[:, :, a, :, b, :] += f_slope[..., None, None] * _outer(grads[a], grads[b])
            hz[:, :, a, :, b, :] += f[..., None, None] * second[a][b]


def _level_sums(zeta: np.ndarray, hz: np.ndarray) -> np.ndarray:
    """H_w (m, 15, 15) over w = (e_1, e_2, d_1, d_2, n), e_a = x_a - x_0 and d_a = D_a - D_0,
    so that g_a = e_a + zeta_f / 2 d_a: the levels' blocks hz (``level_hessians``) summed
    with weights (zeta_f / 2)^p, p the number of d among the row and the column."""
    m = len(hz)
    half = 0.5 * zeta
    moments = [np.einsum("f,mfaibj->maibj", half**p, hz) for p in range(3)]
    h_w = np.empty((m, 15, 15))
    for rows, p_row in ((slice(0, 6), 0), (slice(6, 12), 1)):
        for cols, p_col in ((slice(0, 6), 0), (slice(6, 12), 1)):
            h_w[:, rows, cols] = moments[p_row + p_col][:, :2, :, :2].reshape(m, 6, 6)
        h_w[:, rows, 12:] = moments[p_row][:, :2, :, 2].reshape(m, 6, 3)
        h_w[:, 12:, rows] = moments[p_row][:, 2, :, :2].reshape(m, 3, 6)
    h_w[:, 12:, 12:] = moments[0][:, 2, :, 2]
    return h_w


def _variable_jacobians(block: FibrousShellBlock, geo: dict) -> tuple[np.ndarray, np.ndarray]:
    """A = dw/dq (m, 15, 27), q = (x, psi, S) per corner: +-1 for e_a, the blocks
    dD_k/d(psi_k, S_k) for d_a, dn/dx_k for n; and the A of the rows (the same, but with
    ``thickness_variation=False`` the moments are h_m V x dW/dD without the variation of h_m,
    and dW/dS = 0)."""
    eye = np.eye(3)
    h0 = block.fabric.thickness
    x, v = geo["corners"], geo["directors"]
    m = len(x)
    n = geo["normal"][:, None, :]  # (m, 1, 3)
    projector = eye - n[..., :, None] * n[..., None, :]  # (m, 1, 3, 3)
    v_cross_n = cross(v, geo["node_normal"])  # dc_k/dpsi_k, (m, 3, 3)
    node_normal, sum_length = geo["node_normal"], geo["normal_sum_length"]
    cosine, h_m = geo["cosine"], geo["thickness"]
    dh_dc = np.where(geo["guarded"], 0.0, -h0 / cosine**2)[..., None, None]  # (m, 3, 1, 1)
    dc_ds = (v - cosine[..., None] * node_normal) / sum_length[..., None]  # dc_k/dS_k
    spin = -h_m[..., None, None] * skew(v)  # h dpsi x V
    d_psi = spin + dh_dc * _outer(v, v_cross_n)  # dD_k/dpsi_k (m, 3, 3, 3)
    d_by_sums = dh_dc * _outer(v, dc_ds)  # dD_k/dS_k
    area2 = geo["double_area"][:, None, None]
    a_edge, b_edge = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]
    dc_dx = np.stack([skew(b_edge) - skew(a_edge), -skew(b_edge), skew(a_edge)], axis=1)
    dn_dx = np.matmul(projector, dc_dx) / area2[:, None]  # (m, k, 3, 3)
    d_director = np.concatenate([d_psi, d_by_sums], axis=-1)  # dD_k/d(psi_k, S_k), (m, 3, 3, 6)

    def dw_dq(d_director: np.ndarray) -> np.ndarray:
        jac = np.zeros((m, 15, 3, 9))
        for a in (1, 2):
            edge = slice(3 * a - 3, 3 * a)
            jac[:, edge, a, 0:3] = eye
            jac[:, edge, 0, 0:3] = -eye
            jac[:, 6 + edge.start : 6 + edge.stop, a, 3:] = d_director[:, a]
            jac[:, 6 + edge.start : 6 + edge.stop, 0, 3:] = -d_director[:, 0]
        jac[:, 12:, :, 0:3] = dn_dx.transpose(0, 2, 1, 3)
        return jac.reshape(m, 15, 27)

    jac = dw_dq(d_director)
    if block.thickness_variation:
        return jac, jac
    return jac, dw_dq(np.concatenate([spin, np.zeros_like(spin)], axis=-1))


def _normal_second_derivatives(geo: dict, normal_load: np.ndarray) -> np.ndarray:
    """The second derivatives of n(x) contracted with dW/dn (m, 3) held: C^T omega,
    omega = P dW/dn / |c|, differentiated in x; (m, 3, 3, 3, 3) as the translation blocks
    of ``membrane_hessian``."""
    x = geo["corners"]
    m = len(x)
    n = geo["normal"][:, None, :]  # (m, 1, 3)
    area2 = geo["double_area"][:, None, None]
    a_edge, b_edge = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]
    load = normal_load[:, None]
    n_load = np.sum(load * n, axis=-1)[..., None]
    omega = (load - n_load * n) / area2  # (m, 1, 3)
    basis = np.eye(9).reshape(9, 3, 3)  # x_k component i, all in one cell
    da, db = basis[:, 1] - basis[:, 0], basis[:, 2] - basis[:, 0]  # (9, 3)
    dc = cross(da, b_edge[:, None]) + cross(a_edge[:, None], db)  # (m, 9, 3)
    d_area2 = np.sum(n * dc, axis=-1)[..., None]
    dn = (dc - d_area2 * n) / area2
    d_omega = -np.sum(load * dn, axis=-1)[..., None] * n - n_load * dn - omega * d_area2
    d_omega = d_omega / area2
    d_along_a = cross(db, omega) + cross(b_edge[:, None], d_omega)
    d_along_b = cross(d_omega, a_edge[:, None]) + cross(omega, da)
    d_force = np.stack([-(d_along_a + d_along_b), d_along_a, d_along_b], axis=2)
    return d_force.reshape(m, 3, 3, 3, 3).transpose(0, 3, 4, 1, 2)


def _director_second_derivatives(
    block: FibrousShellBlock, geo: dict, p1: np.ndarray, p2: np.ndarray
) -> np.ndarray:
    """The second derivatives of D_k(psi_k, S_k), dW/dD_k = lever_k / 2 held, from the layer
    loads P_1, P_2 (m, L, 3): (m, 6 in, 3 corners, 6 out), the same unit direction in every
    corner at once, each corner's terms depending on its own."""
    h0 = block.fabric.thickness
    v, node_normal, sum_length = geo["directors"], geo["node_normal"], geo["normal_sum_length"]
    cosine, h_m = geo["cosine"], geo["thickness"]
    arm1, arm2 = np.matmul(block.zeta, p1), np.matmul(block.zeta, p2)
    lever = np.stack([-(arm1 + arm2), arm1, arm2], axis=1)[:, None]  # (m, 1, 3, 3)
    unit = np.eye(6)[:, None, :]  # (6, 1 (all corners), 6)
    dv = cross(unit[..., 0:3], v[:, None])  # (m, 6, 3, 3)
    ds_ = unit[..., 3:6]
    vv, nn = v[:, None], node_normal[:, None]
    length = sum_length[:, None, :, None]
    d_length = np.sum(nn * ds_, axis=-1)[..., None]
    d_nn = (ds_ - d_length * nn) / length
    cos4 = cosine[:, None, :, None]
    d_cos = np.sum(dv * nn + vv * d_nn, axis=-1)[..., None]
    guarded = geo["guarded"][:, None, :, None]
    dh = np.where(guarded, 0.0, -h0 * d_cos / cos4**2)
    hm = h_m[:, None, :, None]
    d_moment = 0.5 * (dh * cross(vv, lever) + hm * cross(dv, lever))
    d_dsums = np.zeros(d_moment.shape)
    if block.thickness_variation:
        dw_dh = 0.5 * np.sum(lever * vv, axis=-1)[..., None]
        d_dw_dh = 0.5 * np.sum(lever * dv, axis=-1)[..., None]
        dw_dc = np.where(guarded, 0.0, -dw_dh * h0 / cos4**2)
        d_dw_dc = np.where(guarded, 0.0, -h0 * (d_dw_dh / cos4**2 - 2.0 * dw_dh * d_cos / cos4**3))
        d_moment += d_dw_dc * cross(vv, nn) + dw_dc * (cross(dv, nn) + cross(vv, d_nn))
        d_dsums = (d_dw_dc / length - dw_dc * d_length / length**2) * (vv - cos4 * nn) + (
            dw_dc / length
        ) * (dv - d_cos * nn - cos4 * d_nn)
    return np.concatenate([d_moment, d_dsums], axis=-1)  # (m, 6 in, 3 corners, 6 out)


# ---------------------------------------------------------------------- normal sums
def corner_normal_pull_tangent(x: np.ndarray, pull: np.ndarray) -> np.ndarray:
    """d(geometry.py ``corner_normal_pull``(x, pull))/dx with ``pull`` (m, 3, 3) held: the
    stiffness (m, 3, 3, 3, 3) of the normal sums' second derivatives sum_k pull_k .
    d2(alpha_k n)/dx2, N (per unit of the sums). Its formulas differentiated in the 9 unit
    directions of the corners, all cells at once (directions on axis 1)."""
    geo = corner_geometry(x)
    n, size, angle = geo["normal"][:, None], geo["size"][:, None, None], geo["angle"][:, None]
    directions = np.eye(9).reshape(9, 3, 3)  # (direction, corner, component)
    a, b = x[:, None, 1] - x[:, None, 0], x[:, None, 2] - x[:, None, 0]  # (m, 1, 3)
    da, db = directions[:, 1] - directions[:, 0], directions[:, 2] - directions[:, 0]
    dc = cross(da, b) + cross(a, db)  # (m, 9, 3)
    d_size = np.sum(n * dc, axis=-1)[..., None]
    dn = (dc - d_size * n) / size
    u = (x[:, [1, 2, 0]] - x)[:, None]  # (m, 1, corner, 3)
    w = (x[:, [2, 0, 1]] - x)[:, None]
    du = directions[:, [1, 2, 0]] - directions  # (9, corner, 3)
    dw = directions[:, [2, 0, 1]] - directions
    d_next, d_prev = geo["d_next"][:, None], geo["d_prev"][:, None]
    d_angle = np.sum(d_next * du + d_prev * dw, axis=-1)  # (m, 9, corner)
    nn, dnn = n[:, :, None], dn[:, :, None]
    u2 = np.sum(u * u, axis=-1)[..., None]
    w2 = np.sum(w * w, axis=-1)[..., None]
    # d_next = -(n x u) / |u|^2 and d_prev = -(w x n) / |w|^2, differentiated.
    dd_next = (
        -(cross(dnn, u) + cross(nn, du)) / u2
        - 2.0 * d_next * np.sum(u * du, axis=-1)[..., None] / u2
    )
    dd_prev = (
        -(cross(dw, nn) + cross(w, dnn)) / w2
        - 2.0 * d_prev * np.sum(w * dw, axis=-1)[..., None] / w2
    )
    held = pull[:, None]  # (m, 1, corner, 3)
    weight = np.sum(held * nn, axis=-1)[..., None]
    d_weight = np.sum(held * dnn, axis=-1)[..., None]
    next_ = d_weight * d_next + weight * dd_next  # on node k + 1
    prev = d_weight * d_prev + weight * dd_prev  # on node k + 2
    force = -(next_ + prev) + np.roll(next_, 1, axis=2) + np.roll(prev, 2, axis=2)
    g0 = np.sum(angle[..., None] * held, axis=2)  # (m, 1, 3)
    dg0 = np.sum(d_angle[..., None] * held, axis=2)  # (m, 9, 3)
    along = np.sum(g0 * n, axis=-1)[..., None]
    g = (g0 - along * n) / size
    dg = (
        dg0
        - (np.sum(dg0 * n, axis=-1)[..., None] + np.sum(g0 * dn, axis=-1)[..., None]) * n
        - along * dn
    ) / size - g * d_size / size
    d_along_a = cross(db, g) + cross(b, dg)
    d_along_b = cross(dg, a) + cross(g, da)
    force = force + np.stack([-(d_along_a + d_along_b), d_along_a, d_along_b], axis=2)
    return force.reshape(len(x), 3, 3, 3, 3).transpose(0, 3, 4, 1, 2)


# ---------------------------------------------------------------------- the sparse pattern
class NodePairs:
    """The node pairs (i, j) that share a cell: their pattern, sorted by row then column
    (``indptr``, ``indices``; ``n_pairs``), and ``slot`` (m, 3, 3) int, the pair of (corner
    k, corner l) of each cell."""

    def __init__(self, connectivity: np.ndarray, n_nodes: int):
        m = len(connectivity)
        rows = np.broadcast_to(connectivity[:, :, None], (m, 3, 3)).ravel()
        cols = np.broadcast_to(connectivity[:, None, :], (m, 3, 3)).ravel()
        keys, slot = np.unique(rows * n_nodes + cols, return_inverse=True)
        self.n_nodes, self.n_pairs = n_nodes, keys.size
        self.slot = slot.reshape(m, 3, 3)
        pair_rows, self.indices = np.divmod(keys, n_nodes)
        self.indptr = np.searchsorted(pair_rows, np.arange(n_nodes + 1))


class CornerPairs(NodePairs):
    """The node pairs (i, j) that share a cell, as the block structure of sparse matrices
    over the nodes whose blocks are sums of per-cell blocks (a BSR pattern, built once).

    slot : (m, 3, 3) int, the pair of (corner k, corner l) of each cell.
    indptr, indices : the BSR structure, pairs sorted by row then column.
    first_cell, first_corner : (nodes of the block,) a cell holding each node and the corner
        there, so that a per-node block is added exactly once.
    hessian_index, jacobian_index, identity_index : positions in the BSR data of the entries
        of ``hessian`` and ``jacobian``.
    """

    def __init__(self, connectivity: np.ndarray, n_nodes: int):
        super().__init__(connectivity, n_nodes)
        _, first = np.unique(connectivity.ravel(), return_index=True)
        self.first_cell, self.first_corner = np.divmod(first, 3)

        # Where each entry of the per-cell arrays lands in the BSR data, in the layouts the
        # tangent forms them (so that a call is one bincount, with no transposed copy):
        # the Hessians (m, k, 9, l, 9) and the Jacobians dS_k/dx_j (m, k, 3, j, 3), whose
        # blocks (9 x 6) hold them in rows 6-8, columns 0-2.
        slot = self.slot[:, :, None, :, None]
        self.hessian_index = (slot * 81 + np.arange(9)[:, None, None] * 9 + np.arange(9)).ravel()
        rows = 6 + np.arange(3)[:, None, None]
        self.jacobian_index = (slot * 54 + rows * 6 + np.arange(3)).ravel()
        # The identity of (u, psi) on the diagonal blocks of J.
        diagonal = self.slot[self.first_cell, self.first_corner, self.first_corner]
        self.identity_index = (diagonal[:, None] * 54 + np.arange(6) * 7).ravel()
        # The compiled J^T H J on this pattern (tangent_kernels.MembraneProduct), at first use.
        self.product: tangent_kernels.MembraneProduct | None = None

    def _matrix(self, data: np.ndarray, r: int, c: int) -> sp.bsr_matrix:
        return sp.bsr_matrix(
            (data.reshape(-1, r, c), self.indices, self.indptr),
            shape=(r * self.n_nodes, c * self.n_nodes),
        )

    def hessian(self, hessian: np.ndarray) -> sp.bsr_matrix:
        """The (9 n, 9 n) BSR matrix of per-cell Hessians (m, 3, 9, 3, 9) in (x, psi, S) per
        corner, summed on the node pairs."""
        data = np.bincount(self.hessian_index, hessian.ravel(), minlength=self.n_pairs * 81)
        return self._matrix(data, 9, 9)

    def jacobian(self, ds_dx: np.ndarray) -> sp.bsr_matrix:
        """The (9 n, 6 n) BSR matrix J from (u, psi) to (u, psi, S): the identity, and the
        per-cell dS_k/dx_j (m, k, 3, j, 3) summed on the node pairs."""
        data = np.bincount(self.jacobian_index, ds_dx.ravel(), minlength=self.n_pairs * 54)
        data[self.identity_index] += 1.0
        return self._matrix(data, 9, 6)
