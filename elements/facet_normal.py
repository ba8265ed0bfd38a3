"""The turn of a meshed tool's closest-point normal as a point moves (elements/tools.py
``RigidSurface.normal_gradient``; docs/theory.md §9.3): the contact tangent's k p dn/dx round
the edges and vertices of the facets."""

from __future__ import annotations

import numpy as np

__all__ = ["turn_round_features"]


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
