"""Where neighbouring plies have passed through each other at a state: the nodes of a ply
past the mid-surface of the ply on the other side of their contact.

The ply contact (elements/ply_contact.py) pushes the points of one ply's face out of the
other's; a single pass holds the upper ply's points off the lower ply but not the lower ply's
nodes off the upper one (its mirrored pass, ``lower_rule``, does that: docs/theory.md §9.3a
"Both ways"), and a penalty gives way under a sharp tool. A node that ends past the other
ply's mid-surface has crossed it: the ply order there is lost, which no field of the contact
shows (its gap is the mean of the points around an upper node, which may stay positive while
the node itself is through). This module measures it from the positions alone, as a user
would from the frames: each node's closest point on the other ply's mid-surface triangles,
the signed distance along that triangle's normal (oriented, as in the reference, from the
lower ply towards the upper), judged only where the closest point lies inside a triangle
(beside the outline a node is off the ply, not through it).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from elements.facet_search import closest_on_triangles
from elements.ply_topology import open_edges

__all__ = ["CANDIDATES", "crossed_nodes"]

#: The triangles of the other ply, nearest by centroid, among which a node's closest point
#: is sought: enough for the fans round a vertex of a structured ply mesh (six) and a cell's
#: worth more.
CANDIDATES = 12


def crossed_nodes(
    reference: np.ndarray,
    positions: np.ndarray,
    nodes: np.ndarray,
    triangles: np.ndarray,
    side: float,
) -> tuple[np.ndarray, np.ndarray]:
    """The ``nodes`` of one ply that lie past the other ply's mid-surface at ``positions``.

    Parameters
    ----------
    reference : (n, 3) float, mm
        The reference positions: orient each triangle's normal (+z there: a layup's plies
        are stacked along z, bottom first).
    positions : (n, 3) float, mm
        The state judged.
    nodes : (s,) int
        The ply's nodes.
    triangles : (m, 3) int
        The other ply's triangles.
    side : +1.0 or -1.0
        Where the nodes belong: +1 above the other ply (they are the upper ply's), -1 below.

    Returns
    -------
    crossed : (c,) int
        The nodes whose signed distance to the other ply's mid-surface, along the normal of
        the triangle holding their closest point, has the wrong sign.
    depth : (c,) float, mm
        How far past that mid-surface each lies.
    """
    corners = positions[triangles]  # (m, 3, 3)
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    at_start = reference[triangles]
    upward = np.cross(at_start[:, 1] - at_start[:, 0], at_start[:, 2] - at_start[:, 0])[:, 2]
    normals *= np.where(upward < 0, -1.0, 1.0)[:, None]
    length = np.linalg.norm(normals, axis=1)
    normals /= np.where(length > 0, length, 1.0)[:, None]
    count = min(CANDIDATES, len(triangles))
    near = cKDTree(corners.mean(axis=1)).query(positions[nodes], k=count)[1]
    near = np.asarray(near).reshape(len(nodes), count)
    x = positions[nodes][:, None, :]  # (s, 1, 3)
    tri = corners[near]  # (s, k, 3, 3)
    closest = closest_on_triangles(
        np.broadcast_to(x, tri.shape[:2] + (3,)), tri[:, :, 0], tri[:, :, 1], tri[:, :, 2]
    )
    distance = np.linalg.norm(closest - x, axis=2)
    best = np.argmin(distance, axis=1)
    rows = np.arange(len(nodes))
    chosen = near[rows, best]
    offset = x[:, 0] - closest[rows, best]
    signed = np.einsum("ij,ij->i", offset, normals[chosen])
    # over the ply: the closest point inside a triangle, or on an inner edge or vertex (a
    # fold between two of its triangles), not on the outline (beside the ply)
    over = ~_on_outline(closest[rows, best], corners[chosen], open_edges(triangles)[chosen])
    through = over & (side * signed < 0.0)
    return nodes[through], np.abs(signed[through])


def _on_outline(point: np.ndarray, corners: np.ndarray, outline: np.ndarray) -> np.ndarray:
    """(s,) bool: whether each point (s, 3), on its triangle (s, 3, 3), lies on a side of
    it that ``outline`` (s, 3) marks (at a vertex, on either side through it)."""
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
    twice = np.linalg.norm(np.cross(b - a, c - a), axis=1)
    twice = np.where(twice > 0, twice, 1.0)
    # the barycentric coordinates, from the sub-triangles' areas (the point is on the
    # triangle, so each is >= 0)
    share = (
        np.stack(
            [
                np.linalg.norm(np.cross(b - point, c - point), axis=1),
                np.linalg.norm(np.cross(c - point, a - point), axis=1),
                np.linalg.norm(np.cross(a - point, b - point), axis=1),
            ],
            axis=1,
        )
        / twice[:, None]
    )
    return np.any((share <= 1e-9) & outline, axis=1)
