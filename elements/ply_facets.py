"""The lower ply's face as triangles, for the ply contact's search (elements/ply_projection.py,
whose docstring states the rules): each triangle's frame (unit normal, twice its area, the
barycentric gradients), points against their candidate triangles' planes (``facets``), the
closest point on a triangle's edges (``closest_on_edges``), and the pseudonormals that sign a
gap to an edge or a vertex (``pseudonormals``, ``pseudonormals_at`` over the face's topology,
elements/ply_topology.py; ``_feature_normals`` picks a closest point's edge or vertex and the
growths joined past the outline: ply_projection's docstring, "The sign at an edge" and
"Growths joined"). ply_projection re-exports them; its compiled passes have the same bits
(elements/ply_kernels.py, elements/ply_feature_normals.py, elements/ply_edge_kernels.py).
"""

from __future__ import annotations

import numpy as np

from elements.ply_topology import FaceTopology, edge_ids
from femcore.rotation import cross

__all__ = [
    "INSIDE",
    "closest_on_edges",
    "facets",
    "pseudonormals",
    "pseudonormals_at",
    "triangle_frames",
]

#: Barycentric overshoot below which a projection counts as inside a triangle (round-off of
#: a point right above a vertex or an edge).
INSIDE = 1e-9


def triangle_frames(corners: np.ndarray):
    """Unit normals (..., 3), twice the areas (...,) and the barycentric gradients
    (..., 3, 3) of triangles with corners (..., 3, 3)."""
    y1, y2, y3 = corners[..., 0, :], corners[..., 1, :], corners[..., 2, :]
    c = cross(y2 - y1, y3 - y1)
    area2 = np.linalg.norm(c, axis=-1)
    n = c / area2[..., None]
    edges = np.stack([y3 - y2, y1 - y3, y2 - y1], axis=-2)  # opposite corner k, cyclic
    gradients = cross(n[..., None, :], edges) / area2[..., None, None]
    return n, area2, gradients


def facets(p: np.ndarray, corners: np.ndarray):
    """Each point against each of its candidate triangles' planes: unit normals (P, K, 3),
    twice the areas (P, K), barycentric gradients (P, K, 3, 3), gaps (P, K) mm and the
    barycentric coordinates (P, K, 3) of the projections; p (P, 3), corners (P, K, 3, 3)."""
    n, area2, gradients = triangle_frames(corners)
    relative = p[:, None, :] - corners[..., 0, :]
    gap = np.sum(relative * n, axis=-1)  # (P, K)
    weights = np.einsum("skij,skj->ski", gradients, p[:, None, :] - corners[..., 1, :])
    weights[..., 1] = np.einsum("ski,ski->sk", gradients[..., 1, :], relative)
    weights[..., 2] = 1.0 - weights[..., 0] - weights[..., 1]
    return n, area2, gradients, gap, weights


def closest_on_edges(p: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """(c, 3) the closest point to p (c, 3) on the edges of the triangle with corners
    (c, 3, 3), mm: the nearest of the three edges' closest points (each a segment clamped to
    its ends). It is the triangle's closest point where its plane's projection of p lies
    outside it."""
    best = np.zeros_like(p)
    distance = np.full(len(p), np.inf)
    for a, b in ((1, 2), (2, 0), (0, 1)):
        start, edge = corners[:, a, :], corners[:, b, :] - corners[:, a, :]
        t = np.einsum("ci,ci->c", p - start, edge) / np.einsum("ci,ci->c", edge, edge)
        on_edge = start + np.clip(t, 0.0, 1.0)[:, None] * edge
        r = p - on_edge
        length = np.einsum("ci,ci->c", r, r)
        nearer = length < distance
        best[nearer] = on_edge[nearer]
        distance[nearer] = length[nearer]
    return best


def pseudonormals(
    y: np.ndarray, nodes: np.ndarray, edges: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """The pseudonormals of a triangle mesh's vertices and edges (ply_projection's docstring,
    "The sign at an edge"): (v, 3) at each node id, the sum of its triangles' unit normals weighted
    by their angles there, and (m, 3, 3) at each triangle's edge opposite corner k, the sum of
    the unit normals of the (one or two) triangles sharing it; not normalised. y (m, 3, 3)
    the triangles' corners, mm; nodes (m, 3) their node ids; edges (m, 3) ``edge_ids(nodes)``
    (computed when None)."""
    edges = edge_ids(nodes) if edges is None else edges
    n, angles = _unit_normals_and_angles(y)  # (m, 3), (m, 3)
    count = int(nodes.max()) + 1
    flat = nodes.ravel()
    weighted = (angles[:, :, None] * n[:, None, :]).reshape(-1, 3)
    vertex = np.column_stack([np.bincount(flat, weighted[:, i], count) for i in range(3)])
    ids = edges.ravel()
    repeated = np.repeat(n, 3, axis=0)  # (3 m, 3): each edge's triangle normal
    summed = np.column_stack(
        [np.bincount(ids, repeated[:, i], int(ids.max()) + 1) for i in range(3)]
    )
    return vertex, summed[ids].reshape(len(nodes), 3, 3)


def _unit_normals_and_angles(corners: np.ndarray):
    """The unit normals (r, 3) of the triangles of ``corners`` (r, 3, 3), mm, and their
    angles (r, 3) at each corner, rad (row by row: a few rows' have the whole face's bits)."""
    n = triangle_frames(corners)[0]
    u = np.roll(corners, -1, axis=1) - corners  # from corner k to corner k + 1
    v = np.roll(corners, -2, axis=1) - corners  # to corner k + 2
    angles = np.arctan2(np.linalg.norm(cross(u, v), axis=-1), np.einsum("mki,mki->mk", u, v))
    return n, angles


def pseudonormals_at(
    y: np.ndarray, topology: FaceTopology, vertices: np.ndarray, halves: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """``pseudonormals`` at a few vertices and edges only, with the same bits: (c, 3) at the
    node ids ``vertices`` (c,) and (h, 3) at the edges of the half-edges ``halves`` (h,)
    (row * 3 + k: the edge of triangle row opposite corner k). y (m, 3, 3) the triangles'
    corners, mm; ``topology`` the face's (elements/ply_topology.py), whose tables give each
    sum's terms in the order ``np.bincount`` adds them over the whole face."""
    fan = topology.fans[vertices]  # (c, f) corners row * 3 + k
    sharing = topology.edge_halves[topology.edges.ravel()[halves]]  # (h, w)
    rows = np.unique(np.concatenate([fan[fan >= 0] // 3, sharing[sharing >= 0] // 3]))
    n, angles = _unit_normals_and_angles(y[rows])
    at = np.full(len(y), -1)
    at[rows] = np.arange(len(rows))
    vertex = np.zeros((len(vertices), 3))
    for column in range(fan.shape[1]):  # the fan's corners in bincount's order, from 0.0
        corner = fan[:, column]
        row = at[corner // 3]
        term = angles[row, corner % 3][:, None] * n[row]
        vertex = vertex + np.where((corner >= 0)[:, None], term, 0.0)
    edge = np.zeros((len(halves), 3))
    for column in range(sharing.shape[1]):
        half = sharing[:, column]
        edge = edge + np.where((half >= 0)[:, None], n[at[half // 3]], 0.0)
    return vertex, edge


def _feature_normals(y, topology, triangle, lam, reach, normal):
    """(c, 3) the unit pseudonormal (``pseudonormals``) of the edge or vertex of the mesh on
    which each closest point with barycentric coordinates ``lam`` (c, 3) on triangle row
    ``triangle`` (c,) lies; ``normal`` (c, 3), the triangle's, where it lies on a growth past
    the outline (``reach`` (c, 3) > 0 on that bound) off an edge joined to its neighbour's
    growth, or the pseudonormal nearly vanishes (a fold pressed flat, ply_projection's docstring "A
    layer turned away"); and (c,) bool, the closest point lies on such a joined edge's
    extension past the outline (ply_projection's docstring, "Growths joined"; none without the
    topology's outline). ``topology`` the face's (elements/ply_topology.py)."""
    nodes, outline = topology.nodes, topology.outline
    bound = lam <= -reach + 1e-9
    # anywhere on a growth past the outline, off the triangle (its far edge or an edge's
    # extension): the face has no side there but the triangle's own, unless the edge's
    # extension is also its neighbour's growth's
    grown = np.any((lam < -INSIDE) & (reach > 0.0), axis=1)
    count = bound.sum(axis=1)
    corner = np.argmin(bound, axis=1)  # at a vertex: the corner off both bounds
    side = np.argmax(bound, axis=1)  # on an edge: the corner it lies opposite
    vertex, edge = pseudonormals_at(y, topology, nodes[triangle, corner], triangle * 3 + side)
    joined = np.zeros(len(triangle), dtype=bool)
    if outline is not None:
        joined = grown & (count == 1) & _joined_growth(topology, triangle, side, lam)
    chosen = np.where((count == 2)[:, None], vertex, edge)
    length = np.linalg.norm(chosen, axis=1)
    keep = (grown & ~joined) | (count == 0) | (count == 3) | (length < 1e-6)
    joined &= ~keep
    unit = chosen / np.where(length > 0.0, length, 1.0)[:, None]
    return np.where(keep[:, None], normal, unit), joined


def _joined_growth(topology, triangle, side, lam):
    """(c,) bool: the edge opposite corner ``side`` (c,) of triangle row ``triangle`` (c,)
    is shared with a neighbour that grows past it as the triangle does: of the edge's two
    ends, the one whose coordinate lam_i (c, 3) is negative (the closest point lies on the
    edge's line past its other end, an outline vertex) is opposite an outline edge of the
    neighbour as of the triangle, so both growths hold that extension of the edge (ply_projection's
    docstring, "Growths joined"); ``topology`` the lower face's (elements/ply_topology.py,
    with its outline)."""
    nodes, outline = topology.nodes, topology.outline
    count = len(triangle)
    own = triangle * 3 + side
    other = topology.other[own]  # the neighbour's (row * 3 + k), own on an open edge
    shared = other != own
    rows = np.arange(count)
    ends = np.where(np.arange(3)[None, :] == side[:, None], np.inf, lam)
    past = np.argmin(ends, axis=1)  # the end whose coordinate is negative
    node = nodes[triangle, past]
    neighbour = other // 3
    at = np.argmax(nodes[neighbour] == node[:, None], axis=1)
    return shared & outline[triangle, past] & outline[neighbour, at] & (lam[rows, past] < 0.0)
