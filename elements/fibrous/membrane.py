"""Tension and in-plane shear of the fibres at the levels through the thickness (Bai Eq. 19,
21, 24-33; docs/theory.md §2, §3), the numpy reference of the compiled loops of kernels.py.

At each level zeta_f the fibre vectors g_1, g_2 of geometry.py (Eq. 8) give the log strains
of the warp and weft (whose variation is Eq. 26) and the shear angle gamma = pi/2 -
angle(g_1, g_2) (the angle of Bai Fig. 4). The virtual work of the tension is (Eq. 19)

    delta W_T = A0 sum_f w_f sum_alpha T_alpha(eps_alpha) delta eps_alpha,

T per unit width from the fabric's laws, and that of the shear (Eq. 21)

    delta W_S = A0 sum_f w_f M_s(gamma) delta gamma.

``layer_loads`` gives dW/dg_a at each level (Eq. 24-27, 30-33), ``layer_forces`` the nodal
forces and director moments they make (Eq. 24, 28, and the variation of h_m of §2.5),
``forces`` those of a whole block with the variation of the nodal normals.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from elements.fibrous.fibres import by_family
from elements.fibrous.geometry import (
    corner_normal_pull,
    cross_product_pull,
    free_sums,
    row_dot,
    row_norm,
)
from femcore.rotation import cross

if TYPE_CHECKING:
    from elements.fibrous.block import FibrousShellBlock

__all__ = [
    "energies",
    "fibre_lengths",
    "forces",
    "layer_forces",
    "layer_loads",
    "shear_angle",
    "strains",
]


def shear_angle(g1: np.ndarray, g2: np.ndarray) -> np.ndarray:
    """gamma = pi/2 - angle(g1, g2) (Bai Fig. 4, the gamma of Eq. 21), rad; > 0 when the
    warp-weft angle closes."""
    c = row_dot(g1, g2) / (row_norm(g1) * row_norm(g2))
    return np.arcsin(np.clip(c, -1.0, 1.0))


def fibre_lengths(block: FibrousShellBlock, geo: dict) -> tuple[np.ndarray, np.ndarray]:
    """The lengths (m, L) whose log strain the tension law takes, along edges 0-1, 0-2.

    With element normals (Bai), |g_a| at each level. With nodal normals, the length of
    g_a projected on the element's plane, l = |P g_a|, P = I - n n^T (docs/theory.md §2.2).
    The component of g_a = e_a + zeta d_a along n is zeta d_a . n: straight directors make
    it (h / 2) theta kappa per unit length on a stack bent by theta with curvature kappa,
    and counting it would stretch both outer layers by (h theta kappa)^2 / 8, although the
    true material lines curve and the layers keep their length: it locks a thick stack's
    bending (+8% tip x on a heavy cantilever of h / L = 0.04). Components in the plane
    (in-plane shear of the levels) still count in full.
    """
    if not block.nodal_normals:
        return row_norm(geo["g1"]), row_norm(geo["g2"])
    n = geo["normal"][:, None, :]
    g1, g2 = geo["g1"], geo["g2"]
    return row_norm(g1 - row_dot(g1, n)[..., None] * n), row_norm(
        g2 - row_dot(g2, n)[..., None] * n
    )


def strains(block: FibrousShellBlock, geo: dict) -> dict:
    """Log fibre strains eps1, eps2 along edges 0-1 and 0-2 and shear angles (m, L), with
    the level vectors' lengths |g_a| (length1, length2) and the fibre lengths of
    ``fibre_lengths`` (fibre1, fibre2)."""
    fibre1, fibre2 = fibre_lengths(block, geo)
    return {
        "length1": np.linalg.norm(geo["g1"], axis=-1),
        "length2": np.linalg.norm(geo["g2"], axis=-1),
        "fibre1": fibre1,
        "fibre2": fibre2,
        "eps1": np.log(fibre1 / block.reference_length1),
        "eps2": np.log(fibre2 / block.reference_length2),
        "gamma": block.shear_sign[:, None] * shear_angle(geo["g1"], geo["g2"])
        - block.reference_shear,
    }


def layer_loads(block: FibrousShellBlock, geo: dict, strain: dict, tension=True, shear=True):
    """Derivatives P_a = dW/dg_a (m, L, 3) of the tension and/or shear energy, and with
    nodal normals the load on the element normal, dW/dn (m, 3) (else None).

    Tension (Eq. 24-27): dW/dg_a = A0 w_f T_a g_a / |g_a|^2 (d eps = g . dg / |g|^2). With
    the in-plane fibre length l = |P g| of ``fibre_lengths``, dW/dg_a = A0 w_f T_a P g_a /
    l^2 and, n varying, dW/dn = -sum_(f, a) A0 w_f T_a (n . g_a) P g_a / l^2.
    Shear (Eq. 30-33, §3): d gamma = sign (dg1 . t1 / |g1| + dg2 . t2 / |g2|), t1 the
    unit vector normal to g1 towards g2 in their plane (and t2 likewise), sign the cell's
    ``shear_sign``.
    """
    scale = block.reference_area[:, None] * block.weights[None, :]  # A0 w_f, (m, L)
    len1, len2 = strain["length1"], strain["length2"]
    fibre1, fibre2 = strain["fibre1"], strain["fibre2"]
    g1, g2 = geo["g1"], geo["g2"]
    p1 = np.zeros_like(g1)
    p2 = np.zeros_like(g2)
    normal_load = None
    if tension:
        warp, weft = by_family(block.xi_is_warp, strain["eps1"], strain["eps2"])
        t_warp = block.fabric.tension.value(warp)
        t_weft = block.fabric.tension_weft.value(weft)
        t1 = np.where(block.xi_is_warp[:, None], t_warp, t_weft)
        t2 = np.where(block.xi_is_warp[:, None], t_weft, t_warp)
        if block.nodal_normals:
            n = geo["normal"][:, None, :]
            normal_load = np.zeros_like(geo["normal"])
            for p, g, t, fibre in ((p1, g1, t1, fibre1), (p2, g2, t2, fibre2)):
                along = np.sum(g * n, axis=-1, keepdims=True)
                coefficient = (scale * t / fibre**2)[..., None]
                p += coefficient * (g - along * n)
                normal_load -= np.sum(coefficient * along * (g - along * n), axis=1)
        else:
            p1 += (scale * t1 / fibre1**2)[..., None] * g1
            p2 += (scale * t2 / fibre2**2)[..., None] * g2
    if shear:
        u1 = g1 / len1[..., None]
        u2 = g2 / len2[..., None]
        c = np.sum(u1 * u2, axis=-1)
        s = np.sqrt(np.maximum(1.0 - c**2, 1e-24))
        moment = block.shear_sign[:, None] * block.fabric.shear.value(strain["gamma"])
        p1 += (scale * moment / (len1 * s))[..., None] * (u2 - c[..., None] * u1)
        p2 += (scale * moment / (len2 * s))[..., None] * (u1 - c[..., None] * u2)
    return p1, p2, normal_load


def layer_forces(block: FibrousShellBlock, geo: dict, p1, p2, normal_load=None):
    """Nodal forces (m,3,3) and moment vectors (m,3,3) from the layer loads (Eq. 24, 28),
    and dW/dS_k (m,3,3) at the corners with nodal normals (else None).

    The force on fibre end point k of level f is F_k^f = sum_a N_k,a P_a (N_k,xi =
    (-1, 1, 0), N_k,eta = (-1, 0, 1)); the node takes sum_f F_k^f and the director the
    moment sum_f (zeta_f h_m^k / 2) V_k x F_k^f of the lever arm along V (Bai Fig. 3).
    With ``thickness_variation`` the work of h_m = h / (V . n) is added (docs/theory.md §2.5):
    through the director (moment), and through n: with the element normal as forces on the
    cell's nodes; with the nodal normals as dW/dS_k, which ``forces`` turns into
    forces on every cell around node k.
    """
    v, h_m = geo["directors"], geo["thickness"]
    # Sums over the levels first (F_k^f is linear in P_a): sum_f F_k^f and sum_f zeta_f F_k^f.
    total1, total2 = p1.sum(axis=1), p2.sum(axis=1)
    force = np.stack([-(total1 + total2), total1, total2], axis=1)
    if normal_load is not None:
        # n = c / |c|, c = a x b: dW/dc = P dW/dn / |c|, pulled through the bilinear c.
        n = geo["normal"]
        load = normal_load - np.sum(normal_load * n, axis=1)[:, None] * n
        force += cross_product_pull(geo["corners"], load / geo["double_area"][:, None])
    arm1, arm2 = np.matmul(block.zeta, p1), np.matmul(block.zeta, p2)
    lever = np.stack([-(arm1 + arm2), arm1, arm2], axis=1)
    moment = 0.5 * h_m[..., None] * cross(v, lever)
    d_sums = np.zeros_like(v) if block.nodal_normals else None
    if block.thickness_variation:
        # dW/dh_m^k = sum_f zeta_f / 2 F_k^f . V_k; h_m = h / c, c = V . n (unguarded only).
        dw_dh = 0.5 * np.sum(lever * v, axis=-1)
        c = geo["cosine"]
        dw_dc = np.where(geo["guarded"], 0.0, -dw_dh * block.fabric.thickness / c**2)
        if d_sums is not None:
            # c_k = V_k . S_k / |S_k|: dc/dpsi_k = V_k x N_k, dc/dS_k = (V_k - c N_k) / |S_k|.
            node_normal = geo["node_normal"]
            moment += dw_dc[..., None] * cross(v, node_normal)
            d_sums = (dw_dc / geo["normal_sum_length"])[..., None] * (
                v - c[..., None] * node_normal
            )
            return force, moment, d_sums
        n = geo["normal"]
        moment += dw_dc[..., None] * cross(v, n[:, None, :])  # dc/dpsi_k = V_k x n
        # dc_k/dx through n = c / |c|: dc_k = V_perp,k . dc / |c| (V_perp = V - c n), so
        # the corners pull as d(g . c)/dx with g = sum_k (dW/dc_k) V_perp,k / |c|.
        v_perp = v - c[..., None] * n[:, None, :]
        g = np.matmul(dw_dc[:, None, :], v_perp)[:, 0] / geo["double_area"][:, None]
        force += cross_product_pull(geo["corners"], g)
    return force, moment, d_sums


def forces(block: FibrousShellBlock, geo: dict, strain: dict, tension=True, shear=True):
    """Tension and/or shear forces and director moments per cell corner (m, 3, 3), the
    variation of the nodal normals included: dW/dS_k summed over the cells around node k
    (T_k), then d(S_k)/dx through every cell f around k: T_k . d(alpha_k^f n_f)/dx."""
    loads = layer_loads(block, geo, strain, tension, shear)
    force, moment, d_sums = layer_forces(block, geo, *loads)
    if d_sums is not None:
        pull = free_sums(block, block.scatter.vectors(d_sums))[block.connectivity]  # T_k
        force = force + corner_normal_pull(geo["corners"], pull)
    return force, moment


def energies(block: FibrousShellBlock, strain: dict):
    """The tension and shear energies of the block (N mm) from its ``strains``:
    A0 sum_f w_f (Phi_warp + Phi_weft) and A0 sum_f w_f Phi_s(gamma), Phi the laws' energies."""
    scale = block.reference_area[:, None] * block.weights[None, :]
    warp, weft = by_family(block.xi_is_warp, strain["eps1"], strain["eps2"])
    tension = np.sum(
        scale * (block.fabric.tension.energy(warp) + block.fabric.tension_weft.energy(weft))
    )
    shear = np.sum(scale * block.fabric.shear.energy(strain["gamma"]))
    return tension, shear
