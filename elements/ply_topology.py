"""The lower face's topology that a ply contact's facing search reads at every call
(elements/ply_projection.py ``closest_facing``): made once from the triangles' node ids (and
the outline) when the contact is bound, so that a call does no sort or count over the face.

What it holds: each triangle edge's id and its neighbour across it (the half-edge table), the
half-edges of each edge and the corners round each vertex (padded tables, for the
pseudonormals of only the edges and vertices that closest points touch), the outline's
vertices and its edges' triangle rows and end corners. Each sum over a table adds its terms
in the order of the flat index row * 3 + k, from 0.0, as ``np.bincount`` adds them over the
whole face: the pseudonormals of a few rows have the bits of the whole face's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["FaceTopology", "padded_groups"]


def padded_groups(keys: np.ndarray, count: int) -> np.ndarray:
    """(count, w) int: for each key 0 .. count - 1 the positions i of ``keys`` (s,) int with
    keys[i] equal to it, ascending, padded with -1 (w the most positions of a key)."""
    order = np.argsort(keys, kind="stable")
    sizes = np.bincount(keys, minlength=count)
    width = int(sizes.max(initial=0))
    table = np.full((count, max(width, 1)), -1, dtype=np.int64)
    starts = np.cumsum(sizes) - sizes
    column = np.arange(len(keys)) - np.repeat(starts, sizes)
    table[keys[order], column] = order
    return table


@dataclass(frozen=True)
class FaceTopology:
    """The topology of a triangle mesh's face (module docstring).

    Attributes
    ----------
    nodes : (m, 3) int
        The triangles' node ids.
    edges : (m, 3) int
        An id for the edge opposite each corner k, shared by neighbours
        (``edge_ids`` below).
    other : (m * 3,) int
        For each half-edge row * 3 + k, the neighbour's across that edge (the first or last
        of the edge's half-edges by flat index that is not its own), its own on an open edge.
    edge_halves : (E, w) int
        Each edge's half-edges (row * 3 + k) ascending, padded with -1.
    fans : (v, f) int
        Each node's corners (row * 3 + k) ascending, padded with -1.
    outline : (m, 3) bool or None
        The outline's edges (``open_edges``), None without one.
    rim : (v,) bool
        The node is an end of an outline edge.
    segment_rows : (S,) int
        Each outline edge's triangle row (elements/ply_fade.py ``outline_segments``).
    segment_ends : (S, 2) int
        Its corners at its ends.
    """

    nodes: np.ndarray
    edges: np.ndarray
    other: np.ndarray
    edge_halves: np.ndarray
    fans: np.ndarray
    outline: np.ndarray | None
    rim: np.ndarray
    segment_rows: np.ndarray
    segment_ends: np.ndarray

    @classmethod
    def of(
        cls, nodes: np.ndarray, outline: np.ndarray | None = None, edges: np.ndarray | None = None
    ) -> FaceTopology:
        """The topology of the triangles ``nodes`` (m, 3) int, with the outline ``outline``
        (m, 3) bool or None and the edge ids ``edges`` (m, 3) int (computed when None)."""
        from elements.ply_fade import outline_segments

        nodes = np.asarray(nodes)
        edges = edge_ids(nodes) if edges is None else np.asarray(edges)
        flat = edges.ravel()
        order = np.argsort(flat, kind="stable")
        first = order[np.searchsorted(flat[order], flat, side="left")]
        last = order[np.searchsorted(flat[order], flat, side="right") - 1]
        own = np.arange(flat.size)
        other = np.where(first == own, last, first)
        vertices = int(nodes.max()) + 1 if nodes.size else 0
        rim = np.zeros(vertices, dtype=bool)
        if outline is not None:
            rim[nodes[:, [1, 2, 0]][outline]] = True
            rim[nodes[:, [2, 0, 1]][outline]] = True
            rows, ends = outline_segments(outline)
        else:
            rows, ends = np.zeros(0, dtype=np.int64), np.zeros((0, 2), dtype=np.int64)
        return cls(
            nodes=nodes,
            edges=edges,
            other=other,
            edge_halves=padded_groups(flat, int(flat.max(initial=-1)) + 1),
            fans=padded_groups(nodes.ravel(), vertices),
            outline=outline,
            rim=rim,
            segment_rows=rows,
            segment_ends=ends,
        )


def edge_ids(nodes: np.ndarray) -> np.ndarray:
    """(m, 3) int: an id for the edge of each triangle opposite its corner k, one per edge of
    the mesh (shared by the triangles on either side); nodes (m, 3) the triangles' node ids."""
    ends = np.stack([nodes[:, [1, 2]], nodes[:, [2, 0]], nodes[:, [0, 1]]], axis=1)  # (m, 3, 2)
    inverse = np.unique(np.sort(ends, axis=-1).reshape(-1, 2), axis=0, return_inverse=True)[1]
    return inverse.reshape(len(nodes), 3)


def open_edges(cells: np.ndarray) -> np.ndarray:
    """(m, 3) bool: the edge of each triangle opposite its corner k lies on the outline of the
    mesh ``cells`` (m, 3) (no other triangle of ``cells`` shares it)."""
    ids = edge_ids(np.asarray(cells))
    return np.bincount(ids.ravel())[ids] == 1
