"""Connectivity of triangle meshes: edges, neighbours, apexes, sanity checks and normals.

Conventions (0-based local numbering):

* side ``s`` of a triangle is the side OPPOSITE its local node ``s``: side 0 joins local nodes
  1 -> 2, side 1 joins 2 -> 0 and side 2 joins 0 -> 1, each traversed in the triangle's own
  (counter-clockwise) direction;
* an edge is an undirected pair of node ids stored sorted as ``(lo, hi)``; the edge list is
  sorted lexicographically, so edge ids are reproducible.

Everything is vectorised with numpy; the only loops run over the (at most three) local sides
or over the few offending items used to build an error message.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.spatial import cKDTree

from femcore.orientation import facing_sides
from femcore.read_only_state import ReadOnlyState
from femcore.rotation import cross

__all__ = [
    "MeshTopologyError",
    "Topology",
    "build_topology",
    "check_duplicate_nodes",
    "opposed_neighbours",
    "check_orientation",
    "check_triangles",
    "check_zero_area",
    "nodal_normals",
    "validate_cells",
    "validate_points",
]

# Relative tolerances of the checks: two nodes closer than DUPLICATE_TOL * (bounding-box
# diagonal) are duplicates; a triangle with area <= ZERO_AREA_TOL * diagonal**2 is degenerate.
DUPLICATE_TOL = 1e-9
ZERO_AREA_TOL = 1e-12


class MeshTopologyError(ValueError):
    """A triangle mesh that no shell can use (an edge of three triangles, neighbours facing
    opposite ways, duplicate nodes, a triangle of no area): raised by the checks below, so
    that a case file's reader names the mesh it read (fibreshell/case_model.py)."""


# Local node pairs of sides 0, 1, 2 (side s is opposite local node s), in traversal order.
_SIDE_START = np.array([1, 2, 0])
_SIDE_END = np.array([2, 0, 1])


# --------------------------------------------------------------------------------------------
# Input validation (shared with femcore.mesh)
# --------------------------------------------------------------------------------------------


def validate_points(points: ArrayLike) -> np.ndarray:
    """Return ``points`` as a new float64 array of shape (n, 3), n >= 1.

    Parameters
    ----------
    points : array_like, shape (n, 3) or (n, 2)
        Node coordinates (length units); 2-D points get z = 0.

    Returns
    -------
    numpy.ndarray of float64, shape (n, 3)
        A new array (never a view of the input).

    Raises
    ------
    ValueError
        A wrong shape, n = 0, or a non-finite coordinate (naming the first bad node).
    """
    try:
        pts = np.array(points, dtype=np.float64)
    except (TypeError, ValueError) as err:
        raise ValueError(
            f"points must be a numeric array of shape (n, 3) or (n, 2): {err}"
        ) from err
    if pts.ndim != 2 or pts.shape[1] not in (2, 3) or pts.shape[0] == 0:
        raise ValueError(
            f"points must have shape (n, 3) or (n, 2) with n >= 1, got shape {pts.shape}"
        )
    if pts.shape[1] == 2:
        pts = np.column_stack((pts, np.zeros(len(pts))))
    bad = np.flatnonzero(~np.isfinite(pts).all(axis=1))
    if bad.size:
        node = int(bad[0])
        raise ValueError(
            f"node {node} has a non-finite coordinate {tuple(pts[node].tolist())}; "
            "all coordinates must be finite"
        )
    return pts


def validate_cells(
    cells: ArrayLike | None, nodes_per_cell: int, kind: str, n_nodes: int | None = None
) -> np.ndarray:
    """Return cell connectivity as a new int64 array of shape (k, nodes_per_cell).

    Parameters
    ----------
    cells : array_like of int, shape (k, nodes_per_cell), or None
        Node ids per cell; None or empty gives (0, nodes_per_cell).
    nodes_per_cell : int
        Expected number of nodes of each cell.
    kind : str
        Cell kind ("triangle", "line"), only used to name the cells in error messages.
    n_nodes : int, optional
        Number of nodes; ids must be in [0, n_nodes). Without it only negative ids are refused.

    Returns
    -------
    numpy.ndarray of int64, shape (k, nodes_per_cell)
        A new array.

    Raises
    ------
    ValueError
        A wrong shape or dtype, a node id out of range (naming the cell and the id), or a
        degenerate cell that repeats a node.
    """
    if cells is None:
        return np.zeros((0, nodes_per_cell), dtype=np.int64)
    arr = np.asarray(cells)
    if arr.size == 0:
        # An empty list has dtype float64 and no shape to speak of: treat as "no cells".
        return np.zeros((0, nodes_per_cell), dtype=np.int64)
    if arr.dtype.kind not in "iu":
        raise ValueError(f"{kind} cells must hold integer node ids, got dtype {arr.dtype}")
    if arr.ndim != 2 or arr.shape[1] != nodes_per_cell:
        raise ValueError(
            f"{kind} cells must have shape (k, {nodes_per_cell}), got shape {arr.shape}"
        )
    arr = arr.astype(np.int64)
    upper = np.iinfo(np.int64).max if n_nodes is None else n_nodes
    bad = (arr < 0) | (arr >= upper)
    if bad.any():
        cell, local = np.argwhere(bad)[0]
        valid = "non-negative" if n_nodes is None else f"in [0, {n_nodes})"
        raise ValueError(
            f"{kind} {cell} refers to node {arr[cell, local]}, but node ids must be {valid}"
        )
    # Each pair of columns compared (a cell has few nodes): no sort of the rows.
    same = np.zeros(len(arr), dtype=bool)
    for i in range(nodes_per_cell):
        for j in range(i + 1, nodes_per_cell):
            same |= arr[:, i] == arr[:, j]
    repeated = np.flatnonzero(same)
    if repeated.size:
        cell = int(repeated[0])
        raise ValueError(
            f"{kind} {cell} is degenerate: it repeats a node in {tuple(arr[cell].tolist())}"
        )
    return arr


def _points_and_triangles(points: ArrayLike, triangles: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    pts = validate_points(points)
    return pts, validate_cells(triangles, 3, "triangle", len(pts))


# --------------------------------------------------------------------------------------------
# Topology
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Topology(ReadOnlyState):
    """Edge-based connectivity of a manifold triangle mesh (all arrays int64, read-only).

    Build it with :func:`build_topology`.

    Attributes
    ----------
    edges : numpy.ndarray, shape (e, 2)
        Unique undirected edges ``(lo, hi)``, sorted lexicographically.
    triangle_edges : numpy.ndarray, shape (m, 3)
        Edge id of side s of each triangle (side s opposite local node s).
    edge_triangles : numpy.ndarray, shape (e, 2)
        The triangles sharing each edge; the second column is -1 for a boundary edge. For an
        interior edge the first triangle has the smaller id.
    neighbour : numpy.ndarray, shape (m, 3)
        Triangle across side s, -1 on the boundary.
    apex : numpy.ndarray, shape (m, 3)
        Node of ``neighbour[t, s]`` that is not on side s, -1 on the boundary.
    boundary_edges : numpy.ndarray, shape (b, 2)
        Rows of ``edges`` that belong to a single triangle, in edge order.
    """

    edges: np.ndarray
    triangle_edges: np.ndarray
    edge_triangles: np.ndarray
    neighbour: np.ndarray
    apex: np.ndarray
    boundary_edges: np.ndarray

    @property
    def n_edges(self) -> int:
        """Number of unique edges e."""
        return len(self.edges)


def _directed_sides(triangles: np.ndarray) -> np.ndarray:
    """(m, 3, 2) start and end node of side s of each triangle, in traversal order."""
    return np.stack((triangles[:, _SIDE_START], triangles[:, _SIDE_END]), axis=2)


def build_topology(triangles: ArrayLike) -> Topology:
    """Build the edge/neighbour structure of triangles.

    Orientation consistency is NOT required here; see :func:`check_orientation`.

    Parameters
    ----------
    triangles : array_like of int, shape (m, 3)
        Node ids per triangle.

    Returns
    -------
    Topology
        Edges, neighbours and apexes of the triangles.

    Raises
    ------
    ValueError
        Invalid connectivity (see :func:`validate_cells`), or a non-manifold edge shared by
        more than two triangles (naming its nodes and triangles).
    """
    tri = validate_cells(triangles, 3, "triangle")
    m = len(tri)
    groups = _half_edges(tri)
    unique_keys, edge_of_half, counts, first, second, base = groups
    interior = counts == 2
    edges = np.column_stack((unique_keys // base, unique_keys % base))

    edge_triangles = np.column_stack((first // 3, np.where(interior, second // 3, -1)))
    # mate[h] is the other half-edge of the same edge, -1 on the boundary.
    mate = np.full(3 * m, -1, dtype=np.int64)
    mate[first[interior]] = second[interior]
    mate[second[interior]] = first[interior]
    has_mate = mate >= 0
    neighbour = np.where(has_mate, mate // 3, -1).reshape(m, 3)
    # Side s' of the neighbour is opposite its local node s', which is therefore the apex.
    apex = np.full(3 * m, -1, dtype=np.int64)
    apex[has_mate] = tri.reshape(-1)[mate[has_mate]]

    return Topology(
        edges=_frozen(edges),
        triangle_edges=_frozen(edge_of_half.reshape(m, 3)),
        edge_triangles=_frozen(edge_triangles),
        neighbour=_frozen(neighbour),
        apex=_frozen(apex.reshape(m, 3)),
        boundary_edges=_frozen(edges[counts == 1]),
    )


def _half_edges(tri: np.ndarray, names: np.ndarray | None = None) -> tuple:
    """The half-edges h = 3 t + s (side s of triangle t) of valid triangles (m, 3) grouped by
    undirected edge: (the edges' keys lo * base + hi in increasing order, the edge of each
    half-edge (3m,), the half-edges of each edge, its first and second half-edges (-1 where
    it has one), base). ValueError for an edge of more than two triangles (named by
    ``names`` (m,), their ids in the mesh, when given)."""
    m = len(tri)
    start, end = tri[:, _SIDE_START].reshape(-1), tri[:, _SIDE_END].reshape(-1)  # h = 3 t + s
    # Encode each undirected edge as one integer so that one sort groups them; the key order
    # lo * base + hi is the lexicographic order of (lo, hi).
    base = int(tri.max()) + 1 if m else 1
    keys = np.minimum(start, end) * base + np.maximum(start, end)
    # One stable sort: the half-edges of an edge side by side, the smaller triangle id first.
    order = np.argsort(keys, kind="stable")
    ordered = keys[order]
    starts = np.flatnonzero(np.r_[True, ordered[1:] != ordered[:-1]]) if m else np.zeros(0, int)
    counts = np.diff(np.r_[starts, len(keys)])
    unique_keys = ordered[starts]
    edge_of_half = np.empty(len(keys), dtype=np.int64)
    edge_of_half[order] = np.repeat(np.arange(len(starts)), counts)
    _raise_if_non_manifold(unique_keys, counts, edge_of_half, base, names)
    first = order[starts]
    second = np.full(len(starts), -1, dtype=np.int64)
    interior = counts == 2
    second[interior] = order[starts[interior] + 1]
    return unique_keys, edge_of_half, counts, first, second, base


def _frozen(array: np.ndarray) -> np.ndarray:
    out = np.ascontiguousarray(array, dtype=np.int64)
    out.setflags(write=False)
    return out


def _raise_if_non_manifold(
    unique_keys: np.ndarray,
    counts: np.ndarray,
    edge_of_half: np.ndarray,
    base: int,
    names: np.ndarray | None = None,
) -> None:
    crowded = np.flatnonzero(counts > 2)
    if crowded.size == 0:
        return
    edge = int(crowded[0])
    lo, hi = divmod(int(unique_keys[edge]), base)
    owners = _named(np.unique(np.flatnonzero(edge_of_half == edge) // 3), names).tolist()
    raise MeshTopologyError(
        f"non-manifold edge ({lo}, {hi}) is shared by {counts[edge]} triangles {owners}; "
        "at most two triangles may share an edge (a fin or a T-junction: split the mesh into "
        "parts that each have at most two triangles on an edge). Triangle and node numbers "
        "are 0-based positions in the mesh's order"
    )


# --------------------------------------------------------------------------------------------
# Checks
# --------------------------------------------------------------------------------------------


def check_orientation(triangles: ArrayLike) -> None:
    """Check that neighbouring triangles traverse their shared edge in opposite directions.

    Consistently oriented neighbours traverse a shared edge in opposite directions, so their
    normals point to the same side of the surface.

    Parameters
    ----------
    triangles : array_like of int, shape (m, 3)
        Node ids per triangle.

    Raises
    ------
    ValueError
        Two neighbours traverse their shared edge the same way (naming both and the edge), a
        non-manifold edge, or invalid connectivity.
    """
    tri = validate_cells(triangles, 3, "triangle")
    _check_orientation(tri, _half_edges(tri))


def _check_orientation(tri: np.ndarray, groups: tuple, names: np.ndarray | None = None) -> None:
    """check_orientation on the half-edge groups of ``_half_edges``: the two half-edges of
    an interior edge start at different nodes (the triangles named by ``names``, their ids
    in the mesh, when given)."""
    _, _, counts, first, second, _ = groups
    interior = np.flatnonzero(counts == 2)
    h0, h1 = first[interior], second[interior]
    directed = _directed_sides(tri).reshape(-1, 2)  # (3m, 2): start and end of half-edge h
    inconsistent = directed[h0, 0] == directed[h1, 0]
    same = np.flatnonzero(inconsistent)
    if same.size:
        k = int(same[0])
        t0, t1 = _named(np.array([h0[k] // 3, h1[k] // 3]), names).tolist()
        start, end = directed[h0[k]].tolist()
        pairs = np.column_stack([h0 // 3, h1 // 3])
        sides = facing_sides(len(tri), pairs, inconsistent, int(h0[k] // 3))
        if sides.orientable:
            listed = _listed(_named(sides.other_way, names))
            count = (
                f"{len(sides.other_way)} of the {len(sides.surface)} triangles of their "
                f"connected surface {'faces' if len(sides.other_way) == 1 else 'face'} the "
                f"other way from the rest ({listed})"
            )
            remedy = (
                "reverse those triangles' node order (gmsh: gmsh.model.mesh.reverse on the "
                "surfaces they belong to before writing the mesh; an Abaqus deck: list their "
                "nodes in the other order), so that every normal points to the same side"
            )
        else:
            count = (
                f"their connected surface of {len(sides.surface)} triangles is not "
                "orientable (a Moebius band: no choice of sides makes it consistent)"
            )
            remedy = "cut the surface so that it has two sides"
        total = int(np.count_nonzero(inconsistent))
        raise MeshTopologyError(
            f"triangles {t0} and {t1} have inconsistent orientation: both traverse "
            f"edge {start} -> {end} in the same direction ({total} shared "
            f"edge{'s' if total != 1 else ''} so traversed in all); {count}: {remedy}. "
            "Triangle and node numbers are 0-based positions in the mesh's order"
        )


def opposed_neighbours(triangles: ArrayLike) -> np.ndarray:
    """The neighbours whose orientations disagree: pairs of triangles that share an edge of
    theirs alone (a manifold edge) and traverse it the same way, so that their normals point
    to opposite sides of the surface. An edge of three or more triangles is not judged.

    Parameters
    ----------
    triangles : array_like of int, shape (m, 3)
        Node ids per triangle.

    Returns
    -------
    numpy.ndarray of int64, shape (p, 4)
        Per opposed pair: the two triangles (the smaller id first), the start and end node
        of the edge both traverse; (0, 4) when every manifold edge is traversed both ways.
    """
    tri = validate_cells(triangles, 3, "triangle")
    directed = _directed_sides(tri).reshape(-1, 2)  # half-edge h = 3 t + s
    if not len(directed):
        return np.zeros((0, 4), dtype=np.int64)
    base = int(tri.max()) + 1
    keys = directed.min(axis=1) * base + directed.max(axis=1)
    order = np.argsort(keys, kind="stable")
    ordered = keys[order]
    starts = np.flatnonzero(np.r_[True, ordered[1:] != ordered[:-1]])
    counts = np.diff(np.r_[starts, len(keys)])
    pairs = starts[counts == 2]
    first, second = order[pairs], order[pairs + 1]
    same = directed[first, 0] == directed[second, 0]
    first, second = first[same], second[same]
    return np.column_stack([first // 3, second // 3, directed[first]]).astype(np.int64)


def _listed(ids: np.ndarray, shown: int = 10) -> str:
    """ "triangles 3, 4, 5" or "triangles 3, 4, ..., 40" (the first ``shown``)."""
    ids = np.asarray(ids).reshape(-1)
    word = "triangle" if len(ids) == 1 else "triangles"
    if len(ids) <= shown:
        return f"{word} " + ", ".join(str(int(i)) for i in ids)
    return f"{word} " + ", ".join(str(int(i)) for i in ids[: shown - 1]) + f", ..., {int(ids[-1])}"


def _length_scale(points: np.ndarray) -> float:
    """Bounding-box diagonal of points (n, 3), in length units."""
    return float(np.linalg.norm(points.max(axis=0) - points.min(axis=0)))


def check_duplicate_nodes(points: ArrayLike, triangles: ArrayLike | None = None) -> None:
    """Check that no two nodes are closer than 1e-9 x the bounding-box diagonal.

    Parameters
    ----------
    points : array_like, shape (n, 3) or (n, 2)
        Node coordinates (length units).
    triangles : array_like of int, shape (m, 3), optional
        If given, only the nodes they use are compared (and the bounding box is theirs),
        since unused or cable-only nodes may legitimately coincide with shell nodes.

    Raises
    ------
    ValueError
        Two duplicate nodes (the message names their ids and distance), or invalid input.
    """
    pts = validate_points(points)
    cells = None if triangles is None else validate_cells(triangles, 3, "triangle", len(pts))
    _check_duplicate_nodes(pts, cells)


def _check_duplicate_nodes(pts: np.ndarray, cells: np.ndarray | None) -> None:
    """check_duplicate_nodes on validated points (n, 3) and triangles (m, 3) or None."""
    if cells is None:
        used = np.arange(len(pts))
    else:
        used = np.flatnonzero(np.bincount(cells.ravel(), minlength=len(pts)))
    if used.size < 2:
        return
    sub = pts[used]
    tol = DUPLICATE_TOL * _length_scale(sub)
    if tol < np.finfo(np.float64).tiny:
        raise ValueError(
            f"the mesh is degenerate or too small: its {used.size} nodes span "
            f"{_length_scale(sub):.3g} (bounding-box diagonal), so the duplicate-node "
            f"tolerance ({DUPLICATE_TOL:g} x that) is {tol:.3g}; check the units"
        )
    pairs = cKDTree(sub).query_pairs(tol, output_type="ndarray")
    if len(pairs) == 0:
        return
    # Report the lexicographically smallest pair so the message is reproducible.
    ids = np.sort(used[pairs], axis=1)
    a, b = ids[np.lexsort((ids[:, 1], ids[:, 0]))[0]].tolist()
    distance = np.linalg.norm(pts[a] - pts[b])
    raise MeshTopologyError(
        f"duplicate nodes {a} and {b}: distance {distance:.3g} <= tolerance {tol:.3g} "
        f"({DUPLICATE_TOL:g} x bounding-box diagonal); {len(ids)} such pair"
        f"{'s' if len(ids) != 1 else ''} in all: merge coincident nodes (gmsh: "
        "gmsh.model.mesh.removeDuplicateNodes, or fragment the geometry so that the surfaces "
        "share their edges) so that the triangles around them are joined. Node numbers are "
        "0-based positions in the mesh's order"
    )


def _triangle_cross(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """(m, 3) cross product (x1 - x0) x (x2 - x0) = 2 x area x unit normal, per triangle."""
    x0, x1, x2 = (points[triangles[:, k]] for k in range(3))
    return cross(x1 - x0, x2 - x0)


def check_zero_area(points: ArrayLike, triangles: ArrayLike) -> None:
    """Check that every triangle has an area above 1e-12 x diagonal**2.

    The diagonal is that of the bounding box of all points, so the tolerance (area units) is
    scale-invariant.

    Parameters
    ----------
    points : array_like, shape (n, 3) or (n, 2)
        Node coordinates (length units).
    triangles : array_like of int, shape (m, 3)
        Node ids per triangle.

    Raises
    ------
    ValueError
        Naming the first triangle with area <= the tolerance, or invalid input.
    """
    _check_zero_area(*_points_and_triangles(points, triangles))


def _check_zero_area(pts: np.ndarray, tri: np.ndarray, names: np.ndarray | None = None) -> None:
    """check_zero_area on validated points (n, 3) and triangles (m, 3), the triangles named
    by ``names`` (m,), their ids in the mesh, when given."""
    if len(tri) == 0:
        return
    area = 0.5 * np.linalg.norm(_triangle_cross(pts, tri), axis=1)
    tol = ZERO_AREA_TOL * _length_scale(pts) ** 2
    flat = np.flatnonzero(area <= tol)
    if flat.size:
        t = int(flat[0])
        raise MeshTopologyError(
            f"triangle {int(_named(flat[:1], names)[0])} with nodes {tuple(tri[t].tolist())} "
            f"has zero area ({area[t]:.3g} <= tolerance {tol:.3g}); {flat.size} such "
            f"triangle{'s' if flat.size != 1 else ''} in all. Triangle and node numbers are "
            "0-based positions in the mesh's order"
        )


def _named(rows: np.ndarray, names: np.ndarray | None) -> np.ndarray:
    """The ids in the mesh of the checked triangles' ``rows``: ``names[rows]``, or the rows
    themselves when the triangles checked are the mesh's own."""
    return rows if names is None else np.asarray(names)[rows]


def check_triangles(
    points: ArrayLike, triangles: ArrayLike, names: ArrayLike | None = None
) -> None:
    """Run all triangle-mesh checks.

    Checks, in order: connectivity (shape, range, repeated nodes), non-manifold edges,
    inconsistent orientation, duplicate nodes and zero-area triangles.

    Parameters
    ----------
    points : array_like, shape (n, 3) or (n, 2)
        Node coordinates (length units).
    triangles : array_like of int, shape (m, 3)
        Node ids per triangle.
    names : array_like of int, shape (m,), optional
        The triangles' ids in the mesh, which the messages name (a model checks some of its
        mesh's triangles); None: their rows in ``triangles``.

    Raises
    ------
    ValueError
        Describing the first problem found.
    """
    pts, tri = _points_and_triangles(points, triangles)
    ids = None if names is None else np.asarray(names, dtype=np.int64).reshape(-1)
    if ids is not None and len(ids) != len(tri):
        raise ValueError(f"names must give one id per triangle ({len(tri)}), got {len(ids)}")
    # One grouping of the half-edges serves the manifold and the orientation checks.
    _check_orientation(tri, _half_edges(tri, ids), ids)
    # The points and triangles validated once for all the checks.
    _check_duplicate_nodes(pts, tri)
    _check_zero_area(pts, tri, ids)


# --------------------------------------------------------------------------------------------
# Geometry on the topology
# --------------------------------------------------------------------------------------------


def nodal_normals(points: ArrayLike, triangles: ArrayLike) -> np.ndarray:
    """Area-weighted unit normals at the nodes.

    Each triangle contributes its area times its unit normal (right-hand rule on its local
    node order) to its three nodes.

    Parameters
    ----------
    points : array_like, shape (n, 3) or (n, 2)
        Node coordinates (length units).
    triangles : array_like of int, shape (m, 3)
        Node ids per triangle.

    Returns
    -------
    numpy.ndarray, shape (n, 3)
        Unit normals (dimensionless); a zero vector at nodes touched by no triangle, or where
        the contributions cancel exactly.

    Raises
    ------
    ValueError
        Invalid points or connectivity.
    """
    pts, tri = _points_and_triangles(points, triangles)
    n = len(pts)
    # The cross product already carries the (doubled) area weight, so no division is needed.
    weighted = _triangle_cross(pts, tri)
    flat_nodes = tri.reshape(-1)
    summed = np.column_stack(  # one weight per (triangle, node), component by component
        [
            np.bincount(flat_nodes, weights=np.repeat(weighted[:, k], 3), minlength=n)
            for k in range(3)
        ]
    )
    norm = np.linalg.norm(summed, axis=1)
    out = np.zeros_like(summed)
    np.divide(summed, norm[:, None], out=out, where=norm[:, None] > 0)
    return out
