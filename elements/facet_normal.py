"""The turn of a meshed tool's closest-point normal as a point moves (elements/rigid_surface.py
``RigidSurface.normal_gradient``; docs/theory.md §9.3): the contact tangent's k p dn/dx round
the edges and vertices of the facets."""

from __future__ import annotations

import numpy as np

__all__ = ["turn_on_patches", "turn_round_features"]


def turn_round_features(
    local: np.ndarray,
    d: np.ndarray,
    normal: np.ndarray,
    point: np.ndarray,
    corners: np.ndarray,
    facet_normal: np.ndarray,
    tiny: float,
) -> np.ndarray:
    """(k, 3, 3) dn/dx of the normals n (k, 3) at the points ``local`` (k, 3), mm, whose signed
    distances are d (k,), mm, and whose closest points ``point`` (k, 3) lie on the facets of
    ``corners`` (k, 3, 3), of unit normals ``facet_normal`` (k, 3).

    Inside a facet the normal is the facet's: 0; so too where the normal is the facet's on its
    boundary (a point right over an edge between coplanar facets, which does not turn). On
    an edge of direction e, n = (x - c) / d turns about the edge: (I - n n^T - e e^T) / d; on
    a vertex (I - n n^T) / d. A point whose normal is not the direction from that closest
    point (a smoothed normal, a closest point of another facet at a tie) gets 0. ``tiny``:
    how far (mm) a closest point may lie off an edge's line and still be on it, and off
    x - d n.
    """
    agrees = np.linalg.norm(local - d[:, None] * normal - point, axis=1) <= tiny
    along = np.roll(corners, -1, axis=1) - corners  # edge i from corner i to corner i + 1
    unit = along / np.linalg.norm(along, axis=2)[:, :, None]
    off_line = np.linalg.norm(np.cross(point[:, None, :] - corners, unit), axis=2)
    on_edge = off_line <= tiny  # (k, 3)
    count = on_edge.sum(axis=1)
    edge = unit[np.arange(len(local)), np.argmax(on_edge, axis=1)]
    across = np.eye(3) - normal[:, :, None] * normal[:, None, :]
    across = across - np.where(
        (count == 1)[:, None, None], edge[:, :, None] * edge[:, None, :], 0.0
    )
    along_facet = np.abs(np.sum(normal * facet_normal, axis=1)) >= 1.0 - 1e-12
    turns = agrees & (count >= 1) & ~along_facet
    return np.where(turns[:, None, None], across / d[:, None, None], 0.0)


def turn_on_patches(
    x: np.ndarray, corners: np.ndarray, corner_normals: np.ndarray, lam: np.ndarray
) -> np.ndarray:
    """(k, 3, 3) dnu/dx of the unit normal nu of the Phong patches (elements/tool_smoothing.py,
    elements/ply_surface.py ``surface_point``) at the closest points of x (k, 3), mm, whose
    barycentric coordinates are ``lam`` (k, 3), over ``corners`` (k, 3, 3), mm, with unit
    corner normals ``corner_normals`` (k, 3, 3) (fixed: the tool is rigid); nu with the
    winding of the corners (t_1 x t_2), 1/mm.

    The closest point y(lambda) keeps the residual r = x - y normal to the tangents t_a =
    dy/dlambda_a (lambda_3 = 1 - lambda_1 - lambda_2): t_a . r = 0. Its derivative gives the
    point's slide (G_ab - r . H_ab) dlambda_b = t_a . dx, G_ab = t_a . t_b, H_ab the patch's
    second derivatives (y is quadratic in lambda: constant H); and nu = t_1 x t_2 / |t_1 x t_2|
    turns by dnu/dlambda_b = (I - nu nu^T)(H_1b x t_2 + t_1 x H_2b) / |t_1 x t_2|. So dnu/dx =
    (dnu/dlambda) (G - r . H)^-1 T, T the tangents as rows (docs/theory.md §9.3): on a sphere of
    radius R with exact corners, (I - nu nu^T) / (R -/+ g) to the patch's accuracy.
    """
    q = np.einsum("pk,pki->pi", lam, corners)
    e = np.einsum("pki,pki->pk", q[:, None, :] - corners, corner_normals)
    point = q - 0.5 * np.einsum("pk,pk,pki->pi", lam, e, corner_normals)
    dots = np.einsum("pai,pki->pak", corners, corner_normals)  # y_a . n_k
    partial = (
        corners
        - 0.5 * e[:, :, None] * corner_normals
        - 0.5 * np.einsum("pk,pak,pki->pai", lam, dots, corner_normals)
    )  # dy/dlambda_a, the three barycentric coordinates taken apart
    tangents = partial[:, :2] - partial[:, 2:3]  # (k, 2, 3)
    # d2y/dlambda_a dlambda_b = -1/2 (y_b . n_a) n_a - 1/2 (y_a . n_b) n_b, then reduced
    half = -0.5 * dots.transpose(0, 2, 1)[:, :, :, None] * corner_normals[:, :, None, :]
    full = half + half.transpose(0, 2, 1, 3)  # (k, 3, 3, 3): [a, b, :]
    second = (
        full[:, :2, :2] - full[:, :2, 2:3] - full[:, 2:3, :2] + full[:, 2:3, 2:3]
    )  # (k, 2, 2, 3)
    residual = x - point
    slide = np.einsum("pai,pbi->pab", tangents, tangents) - np.einsum(
        "pabi,pi->pab", second, residual
    )
    cross = np.cross(tangents[:, 0], tangents[:, 1])
    size = np.linalg.norm(cross, axis=1)
    nu = cross / size[:, None]
    turn = np.cross(second[:, 0], tangents[:, 1, None, :]) + np.cross(
        tangents[:, 0, None, :], second[:, 1]
    )  # (k, 2 (b), 3): d(t_1 x t_2)/dlambda_b
    turn = (turn - np.einsum("pbi,pi->pb", turn, nu)[:, :, None] * nu[:, None, :]) / size[
        :, None, None
    ]
    dlam_dx = np.linalg.solve(slide, tangents)  # (k, 2, 3)
    return np.einsum("pbi,pbj->pij", turn, dlam_dx)
