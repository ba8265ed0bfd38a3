"""The kinematics of the fibrous shell at the cells' corners (docs/theory.md §1): the element
normals and areas, the nodal normals (angle-weighted sums of the element normals, §1.4) and
their derivatives, the thickness along the directors h_m = h / (V . n) (Bai Eq. 10, 14, 15),
and the fibre vectors g_1, g_2 of each level through the thickness (Eq. 5, 8).

Local nodes 1, 2, 3 of the paper are columns 0, 1, 2 here; side s of a triangle is opposite
local node s and runs from corner ``SIDE_FROM[s]`` to ``SIDE_TO[s]`` (counter-clockwise).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from elements.fibrous import geometry_kernels
from elements.shell_geometry import guarded_thickness, nodal_thickness
from femcore.rotation import cross

if TYPE_CHECKING:
    from elements.fibrous.block import FibrousShellBlock

__all__ = [
    "SIDE_FROM",
    "SIDE_TO",
    "cell_geometry",
    "corner_geometry",
    "corner_normal_pull",
    "corner_normals",
    "cross_product_pull",
    "free_sums",
    "geometry",
    "node_thickness",
    "normal_sums",
    "row_dot",
    "row_norm",
    "skew",
]

# Side s of a triangle is opposite local node s and runs SIDE_FROM[s] -> SIDE_TO[s].
SIDE_FROM = np.array([1, 2, 0])
SIDE_TO = np.array([2, 0, 1])


def row_dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a . b over the last axis (length 3), shape (...): np.sum(a * b, axis=-1) to the last
    bit, its three products added in the same order, without a reduction over a short axis
    (twice as fast on (m, 3) arrays)."""
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2]


def row_norm(a: np.ndarray) -> np.ndarray:
    """|a| over the last axis (length 3), shape (...): np.linalg.norm(a, axis=-1) to the
    last bit (``row_dot``)."""
    return np.sqrt(row_dot(a, a))


def geometry(
    block: FibrousShellBlock, positions: np.ndarray, directors: np.ndarray, layers: bool = True
) -> dict:
    """Element normals, thickness along the directors, and the fibre vectors of each level.

    Returns arrays over cells: corners (m,3,3), directors (m,3,3), normal (m,3),
    double_area (m,), cosine V.n (m,3), thickness h_m (m,3), guarded (m,3) bool, and with
    ``layers`` g1, g2 (m,L,3): covariant vectors of Eq. 8 at each fibre level (warp or
    weft along edge 0 -> 1 and 0 -> 2). With nodal normals also node_normal (m,3,3) and
    normal_sum_length (m,3): N_k and |S_k| at the corners.
    """
    sums = normal_sums(block, positions)[block.connectivity] if block.nodal_normals else None
    return cell_geometry(
        block, positions[block.connectivity], directors[block.connectivity], layers, sums
    )


def normal_sums(block: FibrousShellBlock, positions: np.ndarray) -> np.ndarray:
    """S_k = sum over the block's cells e around node k of alpha_k^e n_e, (n, 3): the
    element normals weighted by the cells' angles at the node; S_k / |S_k| is the nodal
    normal (docs/theory.md §1.4)."""
    if block.compiled:
        sums = geometry_kernels.normal_sums(block, positions)
    else:
        sums = block.scatter.vectors(corner_normals(positions[block.connectivity])[0])
    if block.plane_node_ids.size:  # a symmetry plane's nodes: the mirrored whole's sums
        sums[block.plane_node_ids] *= block.plane_keep  # (symmetry.py)
    if block.wall_nodes.any():
        sums[block.wall_nodes] = block.reference_sums[block.wall_nodes]
    return sums


def free_sums(block: FibrousShellBlock, nodal: np.ndarray) -> np.ndarray:
    """``nodal`` (n, 3) with the rows of the wall nodes zeroed: their S_k does not vary; and
    those of a symmetry plane's nodes projected on it, as their S_k (symmetry.py)."""
    if block.plane_node_ids.size:
        nodal = nodal.copy()
        nodal[block.plane_node_ids] *= block.plane_keep
    return np.where(block.wall_nodes[:, None], 0.0, nodal) if block.wall_nodes.any() else nodal


def cell_geometry(
    block: FibrousShellBlock,
    x: np.ndarray,
    v: np.ndarray,
    layers: bool = True,
    sums: np.ndarray | None = None,
) -> dict:
    """``geometry`` from the corner positions x and directors v (m, 3, 3) of each cell and,
    with nodal normals, the normal sums S_k at its corners (m, 3, 3)."""
    normal = cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    double_area = row_norm(normal)
    normal /= double_area[:, None]
    extra = {}
    if sums is None:  # Eq. 15: each element's own normal
        cosine = np.matmul(v, normal[:, :, None])[..., 0]
    else:  # the nodal normals N_k = S_k / |S_k|
        length = row_norm(sums)
        node_normal = sums / length[..., None]
        cosine = row_dot(v, node_normal)
        extra = {"node_normal": node_normal, "normal_sum_length": length}
    h_m, guarded = guarded_thickness(block.fabric.thickness, cosine)  # Eq. 10 / 14
    geo = {
        "corners": x,
        "directors": v,
        "normal": normal,
        "double_area": double_area,
        "cosine": cosine,
        "thickness": h_m,
        "guarded": guarded,
        **extra,
    }
    if layers:
        # Fibre end points x_k^f = x_k + zeta_f/2 h_m^k V_k, (m, 3, L, 3).
        offset = 0.5 * block.zeta[None, None, :, None] * (h_m[:, :, None] * v)[:, :, None, :]
        layer = x[:, :, None, :] + offset
        geo["g1"] = layer[:, 1] - layer[:, 0]
        geo["g2"] = layer[:, 2] - layer[:, 0]
    return geo


def node_thickness(block: FibrousShellBlock, geo: dict) -> np.ndarray:
    """Thickness along the director at the nodes (n,), mm, from a ``geometry`` ``geo``: h_m
    from the nodal normal, or with element normals the area-weighted mean of the per-element
    h_m (docs/theory.md §1.4); 0 at nodes outside the block (the model's fields: NaN)."""
    if block.nodal_normals:  # every corner of a node holds the same h_m
        value = np.zeros(block.n_nodes)
        value[block.connectivity] = geo["thickness"]
        return value
    return nodal_thickness(
        geo["thickness"], 0.5 * geo["double_area"], block.connectivity, block.n_nodes
    )


def skew(w: np.ndarray) -> np.ndarray:
    """Cross-product matrices [w]x (..., 3, 3) with [w]x y = w x y."""
    zero = np.zeros(w.shape[:-1])
    return np.stack(
        [
            np.stack([zero, -w[..., 2], w[..., 1]], axis=-1),
            np.stack([w[..., 2], zero, -w[..., 0]], axis=-1),
            np.stack([-w[..., 1], w[..., 0], zero], axis=-1),
        ],
        axis=-2,
    )


def corner_geometry(x: np.ndarray) -> dict:
    """What the angle-weighted normal shares need of each cell (m cells, corners k): the unit
    normal n (m, 3) and |c| (m,), c = (x1 - x0) x (x2 - x0); the angle alpha_k (m, 3); and
    d alpha_k / dx at the next and previous corners, (m, 3, 3) each: -t_u / |u| for the edge
    u = x_(k+1) - x_k (t_u the in-plane unit vector normal to u towards the other edge), and
    likewise for w = x_(k+2) - x_k; at x_k itself minus their sum."""
    c = cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    size = np.linalg.norm(c, axis=1)
    n = c / size[:, None]
    u = x[:, [1, 2, 0]] - x
    w = x[:, [2, 0, 1]] - x
    u_len = np.linalg.norm(u, axis=-1, keepdims=True)
    w_len = np.linalg.norm(w, axis=-1, keepdims=True)
    return {
        "normal": n,
        "size": size,
        "angle": np.arctan2(np.linalg.norm(cross(u, w), axis=-1), np.sum(u * w, axis=-1)),
        "d_next": -cross(n[:, None, :], u / u_len) / u_len,
        "d_prev": -cross(w / w_len, n[:, None, :]) / w_len,
    }


def corner_normals(x: np.ndarray, jacobian: bool = False):
    """Each cell's share of the nodal normal sums: s_k = alpha_k n (m, 3, 3), the unit normal
    weighted by the cell's angle at corner k, and with ``jacobian`` ds_k/dx_j
    (m, 3 k, 3, 3 j, 3), exact: d alpha_k/dx from ``corner_geometry``, dn/dx_j =
    P dc/dx_j / |c| with P = I - n n^T."""
    geo = corner_geometry(x)
    n, angle = geo["normal"], geo["angle"]
    shares = angle[..., None] * n[:, None, :]
    if not jacobian:
        return shares, None
    d_angle = np.zeros((len(x), 3, 3, 3))  # (m, corner k, node j, x comp)
    rows = np.arange(3)
    d_angle[:, rows, (rows + 1) % 3] = geo["d_next"]
    d_angle[:, rows, (rows + 2) % 3] = geo["d_prev"]
    d_angle[:, rows, rows] = -(geo["d_next"] + geo["d_prev"])
    a = x[:, 1] - x[:, 0]
    b = x[:, 2] - x[:, 0]
    d1, d2 = -skew(b), skew(a)
    dc_dx = np.stack([-(d1 + d2), d1, d2], axis=1)  # (m, node j, 3, 3)
    projector = np.eye(3) - n[:, :, None] * n[:, None, :]
    dn_dx = np.matmul(projector[:, None], dc_dx) / geo["size"][:, None, None, None]
    ds = n[:, None, :, None, None] * d_angle[:, :, None, :, :]
    ds = ds + angle[:, :, None, None, None] * dn_dx.transpose(0, 2, 1, 3)[:, None]
    return shares, ds


def cross_product_pull(x: np.ndarray, g: np.ndarray) -> np.ndarray:
    """d(g . c)/dx at the corners (m, 3, 3) of c = (x1 - x0) x (x2 - x0), g (m, 3) held:
    b x g on x1, g x a on x2 (a = x1 - x0, b = x2 - x0), minus their sum on x0."""
    a = x[:, 1] - x[:, 0]
    b = x[:, 2] - x[:, 0]
    along_a, along_b = cross(b, g), cross(g, a)
    return np.stack([-(along_a + along_b), along_a, along_b], axis=1)


def corner_normal_pull(x: np.ndarray, pull: np.ndarray) -> np.ndarray:
    """sum_k pull_k . d(alpha_k n)/dx_j at the corners (m, 3, 3) of each cell, pull (m, 3, 3)
    held: the forces of the nodal normals' variation. The derivatives of
    ``corner_normals(x, jacobian=True)`` contracted as they are formed: (pull_k . n) times
    d alpha_k/dx, plus (dn/dx)^T sum_k alpha_k pull_k = (dc/dx)^T g, g = P sum_k alpha_k
    pull_k / |c|."""
    geo = corner_geometry(x)
    n = geo["normal"]
    weight = np.sum(pull * n[:, None, :], axis=-1)[..., None]  # pull_k . n, (m, 3, 1)
    d_next = weight * geo["d_next"]  # on node k + 1
    d_prev = weight * geo["d_prev"]  # on node k + 2
    force = -(d_next + d_prev) + np.roll(d_next, 1, axis=1) + np.roll(d_prev, 2, axis=1)
    g = np.sum(geo["angle"][..., None] * pull, axis=1)
    g = (g - np.sum(g * n, axis=1)[:, None] * n) / geo["size"][:, None]
    return force + cross_product_pull(x, g)
