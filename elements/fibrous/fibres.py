"""The fibre frame of each triangle, fixed at bind (Bai Eq. 9): the local numbering that puts
one fibre family along edge 0 -> 1 and the other along 0 -> 2 (``fibre_ordering``), the sign
that gives the shear angle one convention in every cell (``shear_orientation``), and the
warp / weft values of quantities computed along the edges (``by_family``).
"""

from __future__ import annotations

import numpy as np

from elements.fibrous import fibre_kernels
from femcore.rotation import cross

__all__ = ["by_family", "fibre_ordering", "shear_orientation"]


def by_family(xi_is_warp: np.ndarray, along_xi, along_eta):
    """(warp, weft) values from (edge 0-1, edge 0-2) values, per cell (leading axis);
    ``xi_is_warp`` (m,) bool, True where edge 0 -> 1 is warp."""
    flag = xi_is_warp.reshape((-1,) + (1,) * (np.ndim(along_xi) - 1))
    return np.where(flag, along_xi, along_eta), np.where(flag, along_eta, along_xi)


def fibre_ordering(points, triangles, cell_ids, warp, tolerance_deg, compiled=False):
    """Rotate each triangle's local numbering (keeping it counter-clockwise) so that local
    node 0 is the corner where one edge runs along the warp and the other along the weft.

    The weft is the in-plane perpendicular of the warp projected on each triangle's plane.
    Returns the reordered (m, 3) connectivity and xi_is_warp (m,): True when edge 0 -> 1 is
    the warp edge (else it is the weft edge, and 0 -> 2 the warp). ``compiled``: the corners
    found by the loop of fibre_kernels.py (the same ones) instead of numpy.
    """
    if compiled:
        corner, xi_is_warp = fibre_kernels.fibre_corners(points, triangles, warp, tolerance_deg)
        flat = corner == fibre_kernels.NORMAL_TO_WARP
        if flat.any():
            bad = int(cell_ids[np.argmax(flat)])
            raise ValueError(f"triangle {bad} is normal to the warp direction {warp}")
    else:
        corner, xi_is_warp = _corners(points, triangles, cell_ids, warp, tolerance_deg)
    if np.any(corner < 0):
        bad = int(np.argmax(corner < 0))
        raise ValueError(
            f"triangle {int(cell_ids[bad])} (nodes {triangles[bad].tolist()}) has no corner "
            f"with one edge along the warp {warp.round(6).tolist()} and one along the weft "
            f"(within {tolerance_deg} deg): FibrousShell needs a fibre-aligned mesh (Bai "
            "Eq. 9), e.g. Mesh.rectangle or Mesh.quadrilateral split into right triangles"
        )
    order = (corner[:, None] + np.arange(3)[None, :]) % 3
    return np.take_along_axis(triangles, order, axis=1), xi_is_warp


def _corners(points, triangles, cell_ids, warp, tolerance_deg):
    """The numpy reference of fibre_kernels.py ``fibre_corners``: each triangle's first
    local corner with one edge along the warp and one along the weft (-1 where none), and
    whether its next edge is the warp (m,) each. ValueError for a triangle normal to the
    warp."""
    x = points[triangles]
    normal = cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    warp_t = warp - (normal @ warp)[:, None] * normal
    size = np.linalg.norm(warp_t, axis=1)
    if np.any(size < 1e-6):
        bad = int(cell_ids[np.argmax(size < 1e-6)])
        raise ValueError(f"triangle {bad} is normal to the warp direction {warp}")
    warp_t /= size[:, None]
    weft_t = cross(normal, warp_t)
    cos_tol = np.cos(np.radians(tolerance_deg))

    corner = np.full(len(triangles), -1)
    xi_is_warp = np.zeros(len(triangles), dtype=bool)
    for k in (2, 1, 0):  # the loop is over the three local corners, not over cells
        a = x[:, (k + 1) % 3] - x[:, k]
        b = x[:, (k + 2) % 3] - x[:, k]
        a /= np.linalg.norm(a, axis=1)[:, None]
        b /= np.linalg.norm(b, axis=1)[:, None]
        along = lambda u, d: np.abs(np.sum(u * d, axis=1)) >= cos_tol  # noqa: E731
        warp_first = along(a, warp_t) & along(b, weft_t)
        weft_first = along(a, weft_t) & along(b, warp_t)
        match = warp_first | weft_first
        corner = np.where(match, k, corner)
        xi_is_warp = np.where(match, warp_first, xi_is_warp)
    return corner, xi_is_warp


def shear_orientation(points, connectivity, xi_is_warp, warp, compiled=False) -> np.ndarray:
    """+1 where edges 0 -> 1 and 0 -> 2 of a cell point both along or both against the positive
    directions of their fibre families (warp, and weft = n x warp), else -1 (m,).

    The angle between the edges then equals the warp-weft angle or its supplement, and
    multiplying pi/2 - angle(g1, g2) by this sign gives the shear angle with one convention in
    every cell: positive when the warp-weft angle closes. ``compiled``: by the loop of
    fibre_kernels.py (the same signs).
    """
    if compiled:
        return fibre_kernels.shear_signs(points, connectivity, xi_is_warp, warp)
    x = points[connectivity]
    edge1, edge2 = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]
    normal = cross(edge1, edge2)
    weft = cross(normal, np.broadcast_to(warp, normal.shape))  # along n x warp (unnormalised)
    along_warp = np.where(xi_is_warp, np.sum(edge1 * warp, 1), np.sum(edge2 * warp, 1))
    along_weft = np.where(xi_is_warp, np.sum(edge2 * weft, 1), np.sum(edge1 * weft, 1))
    return np.sign(along_warp) * np.sign(along_weft)
