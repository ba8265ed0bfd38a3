"""Meshes of 3-node triangles (shells, membranes) and 2-node lines (cables, bars).

A :class:`Mesh` holds node coordinates (length units, always 3-D), triangle and line
connectivity, and named sets of nodes, triangles and lines. Coordinates and connectivity are
validated once at construction and stored as read-only arrays, so a mesh never changes shape
after it was checked; :meth:`Mesh.with_points` makes a moved copy instead. The only mutating
methods are :meth:`Mesh.add_node_set`, :meth:`Mesh.add_element_set` and
:meth:`Mesh.add_line_set`, which only add new named sets.

Fibre-aligned generators (:meth:`Mesh.rectangle`, :meth:`Mesh.quadrilateral`) split each grid
cell into two triangles whose first local node is the corner where the warp (first grid
direction) and weft (second grid direction) meet: with 0-based local numbering, edge 0 -> 1
runs along the warp and edge 0 -> 2 along the weft, in the positive or negative sense
("node 1 at the right angle, 1 -> 2 along warp, 1 -> 3 along weft" in 1-based terms).
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator, Mapping
from functools import cached_property
from pathlib import Path
from types import MappingProxyType, ModuleType
from typing import Any

import meshio
import numpy as np
from numpy.typing import ArrayLike

from femcore.topology import (
    Topology,
    build_topology,
    check_triangles,
    validate_cells,
    validate_points,
)

__all__ = ["Mesh", "NodePredicate"]

NodePredicate = Callable[[np.ndarray, np.ndarray, np.ndarray], ArrayLike]
"""Called once as ``predicate(x, y, z)`` with (n,) coordinate arrays; returns an (n,) bool mask."""

# Characters that would break the set syntax of .inp or .msh files.
_FORBIDDEN_NAME_CHARS = {",", "=", '"', "\n", "\r"}

# Formats whose meshio reader and writer keep named point/cell sets (Abaqus NSET/ELSET).
# Every other format gets the sets as 0/1 mask arrays named with these prefixes.
_NATIVE_SET_FORMATS = {"abaqus"}
_NODE_MASK, _TRIANGLE_MASK, _LINE_MASK = "nset:", "elset:", "lset:"

# Relative tolerances of the quadrilateral corner checks (times the corner diameter).
_PLANARITY_TOL = 1e-9
_CONVEXITY_TOL = 1e-12


class Mesh:
    """Triangles and lines on shared nodes, with named node, triangle and line sets.

    Args:
        points: (n, 3) or (n, 2) node coordinates (length units); 2-D points get z = 0.
        triangles: (m, 3) node ids per triangle, counter-clockwise about the intended normal.
        lines: (k, 2) node ids per line cell.
        node_sets: name -> node ids (or an (n,) bool mask).
        element_sets: name -> triangle ids (or an (m,) bool mask).
        line_sets: name -> line ids (or a (k,) bool mask).

    Raises:
        ValueError: wrong shapes, non-finite coordinates (naming the node), node ids out of
            range (naming the cell and the id), a cell repeating a node, or invalid sets.
            Duplicate nodes, zero areas and orientation are checked by :meth:`check`.
    """

    def __init__(
        self,
        points: ArrayLike,
        triangles: ArrayLike | None = None,
        lines: ArrayLike | None = None,
        node_sets: Mapping[str, ArrayLike] | None = None,
        element_sets: Mapping[str, ArrayLike] | None = None,
        line_sets: Mapping[str, ArrayLike] | None = None,
    ) -> None:
        self._points = _read_only(validate_points(points))
        n = len(self._points)
        self._triangles = _read_only(validate_cells(triangles, 3, "triangle", n))
        self._lines = _read_only(validate_cells(lines, 2, "line", n))
        self._node_sets: dict[str, np.ndarray] = {}
        self._element_sets: dict[str, np.ndarray] = {}
        self._line_sets: dict[str, np.ndarray] = {}
        for given, what, add in (
            (node_sets, "node_sets", self.add_node_set),
            (element_sets, "element_sets", self.add_element_set),
            (line_sets, "line_sets", self.add_line_set),
        ):
            for name, ids in _as_mapping(given, what).items():
                add(name, ids)

    # ----------------------------------------------------------------------------------------
    # Read-only data
    # ----------------------------------------------------------------------------------------

    @property
    def points(self) -> np.ndarray:
        """(n, 3) float64 node coordinates (length units), read-only."""
        return self._points

    @property
    def triangles(self) -> np.ndarray:
        """(m, 3) int64 node ids of the triangles, read-only; (0, 3) if there are none."""
        return self._triangles

    @property
    def lines(self) -> np.ndarray:
        """(k, 2) int64 node ids of the line cells, read-only; (0, 2) if there are none."""
        return self._lines

    @property
    def node_sets(self) -> Mapping[str, np.ndarray]:
        """Read-only view name -> sorted unique int64 node ids."""
        return MappingProxyType(self._node_sets)

    @property
    def element_sets(self) -> Mapping[str, np.ndarray]:
        """Read-only view name -> sorted unique int64 triangle ids."""
        return MappingProxyType(self._element_sets)

    @property
    def line_sets(self) -> Mapping[str, np.ndarray]:
        """Read-only view name -> sorted unique int64 line-cell ids."""
        return MappingProxyType(self._line_sets)

    @property
    def n_nodes(self) -> int:
        """Number of nodes n."""
        return len(self._points)

    @property
    def n_triangles(self) -> int:
        """Number of triangles m."""
        return len(self._triangles)

    @property
    def n_lines(self) -> int:
        """Number of line cells k."""
        return len(self._lines)

    @cached_property
    def topology(self) -> Topology:
        """Edge/neighbour structure of the triangles (computed once; cells never change)."""
        return build_topology(self._triangles)

    def __repr__(self) -> str:
        return (
            f"Mesh(n_nodes={self.n_nodes}, n_triangles={self.n_triangles}, "
            f"n_lines={self.n_lines}, node_sets={list(self._node_sets)}, "
            f"element_sets={list(self._element_sets)}, line_sets={list(self._line_sets)})"
        )

    # ----------------------------------------------------------------------------------------
    # Sets (the only mutating methods)
    # ----------------------------------------------------------------------------------------

    def add_node_set(self, name: str, ids: ArrayLike) -> None:
        """Add a new node set: node ids (any order, repeats allowed) or an (n,) bool mask."""
        _add_set(self._node_sets, "node set", name, ids, self.n_nodes, "node")

    def add_element_set(self, name: str, ids: ArrayLike) -> None:
        """Add a new triangle set: triangle ids or an (m,) bool mask."""
        _add_set(self._element_sets, "element set", name, ids, self.n_triangles, "triangle")

    def add_line_set(self, name: str, ids: ArrayLike) -> None:
        """Add a new line-cell set: line ids or a (k,) bool mask."""
        _add_set(self._line_sets, "line set", name, ids, self.n_lines, "line")

    # ----------------------------------------------------------------------------------------
    # Queries
    # ----------------------------------------------------------------------------------------

    def nodes(self, selection: str | NodePredicate) -> np.ndarray:
        """Sorted int64 ids of the nodes selected by a node-set name or a predicate.

        The predicate is called ONCE as ``predicate(x, y, z)`` with the (n,) coordinate arrays
        and must return an (n,) bool mask, e.g. ``lambda x, y, z: np.isclose(x, 0.0)``.

        Raises:
            ValueError: unknown set name, a mask of the wrong shape or dtype, or an empty
                selection (almost always a tolerance or coordinate mistake).
        """
        if isinstance(selection, str):
            if selection not in self._node_sets:
                raise ValueError(
                    f"unknown node set {selection!r}; known node sets: {sorted(self._node_sets)}"
                )
            ids, label = self._node_sets[selection], f"node set {selection!r}"
        elif callable(selection):
            ids, label = self._select_by_predicate(selection)
        else:
            # Project convention: every kind of bad input raises ValueError.
            raise ValueError(  # noqa: TRY004
                "selection must be a node-set name or a predicate(x, y, z) -> bool mask, "
                f"got {type(selection).__name__}"
            )
        if ids.size == 0:
            lo, hi = self.bounding_box()
            raise ValueError(
                f"selection {label} selected no node (mesh bounding box {lo.tolist()} to "
                f"{hi.tolist()})"
            )
        return np.array(ids, dtype=np.int64)

    def _select_by_predicate(self, predicate: NodePredicate) -> tuple[np.ndarray, str]:
        label = f"predicate {getattr(predicate, '__qualname__', repr(predicate))}"
        mask = np.asarray(predicate(*self._points.T))
        if mask.shape != (self.n_nodes,):
            raise ValueError(
                f"{label} must return a mask of shape ({self.n_nodes},), got shape {mask.shape}"
            )
        if mask.dtype != np.bool_:
            raise ValueError(f"{label} must return a bool mask, got dtype {mask.dtype}")
        return np.flatnonzero(mask), label

    def bounding_box(self) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper corners (3,) of the axis-aligned box around all nodes."""
        return self._points.min(axis=0), self._points.max(axis=0)

    def check(self) -> None:
        """Run the topology checks on the triangles; raise ValueError on the first problem.

        See :func:`femcore.topology.check_triangles`: non-manifold edges, inconsistent
        orientation, duplicate nodes and zero-area triangles.
        """
        if self.n_triangles:
            check_triangles(self._points, self._triangles)

    def with_points(self, points: ArrayLike) -> Mesh:
        """A new mesh with the same cells and sets but other coordinates (n, 3) or (n, 2)."""
        pts = validate_points(points)
        if len(pts) != self.n_nodes:
            raise ValueError(f"points must have {self.n_nodes} rows, got {len(pts)}")
        return Mesh(
            pts,
            self._triangles,
            self._lines,
            node_sets=self._node_sets,
            element_sets=self._element_sets,
            line_sets=self._line_sets,
        )

    # ----------------------------------------------------------------------------------------
    # Generators
    # ----------------------------------------------------------------------------------------

    @classmethod
    def rectangle(
        cls,
        lx: float,
        ly: float,
        nx: int,
        ny: int,
        origin: ArrayLike = (0.0, 0.0, 0.0),
    ) -> Mesh:
        """Fibre-aligned right-triangle mesh of an lx x ly rectangle (length units).

        Warp along x, weft along y, in the plane z = origin z. Node ``j * (nx + 1) + i`` sits
        at origin + (i lx / nx, j ly / ny, 0). Grid cell (i, j), in order "for j, for i", gives
        T_A = (P_ij, P_i+1,j, P_i,j+1) then T_B = (P_i+1,j+1, P_i,j+1, P_i+1,j): both
        counter-clockwise (normal +z), right-angled at local node 0, edge 0 -> 1 along +-x.

        Node sets "left", "right", "bottom", "top" (x min, x max, y min, y max); element set
        "all".
        """
        lx = _positive_length(lx, "lx")
        ly = _positive_length(ly, "ly")
        nx = _positive_int(nx, "nx")
        ny = _positive_int(ny, "ny")
        base = _point3(origin, "origin")
        # linspace hits the far edge exactly, unlike i * (lx / nx).
        x, y = np.meshgrid(np.linspace(0.0, lx, nx + 1), np.linspace(0.0, ly, ny + 1))
        points = base + np.column_stack((x.ravel(), y.ravel(), np.zeros(x.size)))
        triangles = _split_quads(_grid_quads(nx, ny))
        return cls(
            points,
            triangles,
            node_sets=_grid_node_sets(nx, ny),
            element_sets={"all": np.arange(len(triangles))},
        )

    @classmethod
    def line(cls, p0: ArrayLike, p1: ArrayLike, n: int) -> Mesh:
        """n equal 2-node line cells from p0 to p1 ((3,) or (2,), length units).

        Node k sits at p0 + (k / n)(p1 - p0); cell k joins nodes k and k + 1. Node sets
        "start" and "end"; line set "all".
        """
        a = _point3(p0, "p0")
        b = _point3(p1, "p1")
        n = _positive_int(n, "n")
        if np.array_equal(a, b):
            raise ValueError(f"p0 and p1 must differ, both are {a.tolist()}")
        t = np.linspace(0.0, 1.0, n + 1)[:, None]
        points = (1.0 - t) * a + t * b  # exact at both ends, unlike a + t * (b - a)
        lines = np.column_stack((np.arange(n), np.arange(1, n + 1)))
        return cls(
            points,
            lines=lines,
            node_sets={"start": [0], "end": [n]},
            line_sets={"all": np.arange(n)},
        )

    @classmethod
    def quadrilateral(cls, corners: ArrayLike, nx: int, ny: int) -> Mesh:
        """Fibre-aligned structured triangle mesh of a planar convex quadrilateral, via gmsh.

        Args:
            corners: (4, 3) or (4, 2) corners c0, c1, c2, c3 in cyclic order (length units).
                The warp runs along c0 -> c1 with nx divisions, the weft along c0 -> c3 with
                ny divisions. Triangle normals follow (c1 - c0) x (c3 - c0), i.e. +z for
                2-D corners listed counter-clockwise.
            nx, ny: positive numbers of divisions.

        gmsh builds a transfinite quad mesh (nodes at the bilinear map of the corners); each
        quad is rotated so that its first edge is the one most aligned with the local warp
        direction (1 - eta)(c1 - c0) + eta (c2 - c3) at its centroid, and split as in
        :meth:`rectangle`. Nodes and cells are numbered exactly as in :meth:`rectangle`
        (node j * (nx + 1) + i at bilinear parameters (i / nx, j / ny)), so for rectangular
        corners both generators agree. Node sets "bottom" (c0-c1), "right" (c1-c2), "top"
        (c2-c3), "left" (c3-c0); element set "all".

        Raises:
            ValueError: bad shapes or counts, non-coplanar corners, or a non-convex,
                self-intersecting or degenerate quadrilateral.
        """
        quad, normal = _validate_quadrilateral(corners)
        nx = _positive_int(nx, "nx")
        ny = _positive_int(ny, "ny")
        coords, quads = _gmsh_structured_quads(quad, nx, ny)
        if len(quads) != nx * ny:
            raise RuntimeError(f"gmsh returned {len(quads)} quadrangles, expected {nx * ny}")
        points, quads = _structured_numbering(quad, coords, quads, nx, ny)
        quads = _orient_quads(points, quads, normal)
        eta = (quads // (nx + 1)).min(axis=1) / ny + 0.5 / ny  # weft parameter of centroid
        warp = (1.0 - eta)[:, None] * (quad[1] - quad[0]) + eta[:, None] * (quad[2] - quad[3])
        triangles = _split_quads(_rotate_to_warp(points, quads, warp))
        return cls(
            points,
            triangles,
            node_sets=_grid_node_sets(nx, ny),
            element_sets={"all": np.arange(len(triangles))},
        )

    # ----------------------------------------------------------------------------------------
    # File I/O
    # ----------------------------------------------------------------------------------------

    @classmethod
    def read(cls, path: str | Path, file_format: str | None = None) -> Mesh:
        """Read a mesh file through meshio (.msh, .vtu, .inp, ...).

        Keeps "triangle" and "line" cells and ignores "vertex" cells. Named sets come back
        from Abaqus NSET/ELSET (.inp), from the "nset:/elset:/lset:" mask arrays that
        :meth:`write` stores in other formats, and from named gmsh physical groups (dimension
        0 -> node set, 1 -> line set, 2 -> element set).

        Raises:
            FileNotFoundError: the file does not exist.
            ValueError: unknown format, unreadable file, other cell types, or neither
                triangles nor lines.
        """
        path = Path(path)
        if not path.is_file():
            raise FileNotFoundError(f"mesh file {path} does not exist")
        fmt = _resolve_format(path, file_format, writing=False)
        try:
            raw = meshio.read(path, file_format=fmt)
        except meshio.ReadError as err:
            raise ValueError(f"cannot read {path} as {fmt!r}: {err}") from err
        return _mesh_from_meshio(raw, str(path))

    def write(self, path: str | Path, file_format: str | None = None) -> None:
        """Write the mesh through meshio; the format follows the suffix unless given.

        .msh is written as ASCII gmsh 2.2. Sets are kept as NSET/ELSET in .inp and as 0/1
        mask arrays "nset:<name>" (point data), "elset:<name>" and "lset:<name>" (cell data)
        elsewhere. Known losses: formats without point/cell data (e.g. .stl, .obj) drop all
        sets; .msh drops element and line sets of a mesh with both triangles and lines
        (meshio 5.3 cannot read such element data back); .inp drops empty element and line
        sets.

        Raises:
            ValueError: unknown format, a mesh without cells, or (for .inp) a name used by
                both an element set and a line set.
        """
        path = Path(path)
        fmt = _resolve_format(path, file_format, writing=True)
        blocks = [(kind, cells) for kind, cells in self._cell_blocks() if len(cells)]
        if not blocks:
            raise ValueError("cannot write a mesh that has neither triangles nor lines")
        kinds = [kind for kind, _ in blocks]
        if fmt in _NATIVE_SET_FORMATS:
            extra = self._native_sets(kinds)
        else:
            extra = self._set_masks(blocks)
        options: dict[str, Any] = {}
        if fmt.startswith("gmsh"):
            extra = _gmsh_ascii_data(extra, blocks)
            options["binary"] = False
        out = meshio.Mesh(self._points, blocks, **extra)
        try:
            meshio.write(path, out, file_format=fmt, **options)
        except meshio.WriteError as err:
            raise ValueError(f"cannot write {path} as {fmt!r}: {err}") from err

    def _cell_blocks(self) -> list[tuple[str, np.ndarray]]:
        return [("triangle", self._triangles), ("line", self._lines)]

    def _native_sets(self, kinds: list[str]) -> dict[str, Any]:
        shared = sorted(set(self._element_sets) & set(self._line_sets))
        if shared:
            raise ValueError(
                f"set names {shared} are used by both an element set and a line set; "
                "an .inp file cannot keep both under one name"
            )
        empty = np.zeros(0, dtype=np.int64)
        cell_sets = {}
        for kind, sets in (("triangle", self._element_sets), ("line", self._line_sets)):
            for name, ids in sets.items():
                cell_sets[name] = [ids if k == kind else empty for k in kinds]
        return {"point_sets": dict(self._node_sets), "cell_sets": cell_sets}

    def _set_masks(self, blocks: list[tuple[str, np.ndarray]]) -> dict[str, Any]:
        point_data = {
            _NODE_MASK + name: _mask(ids, self.n_nodes) for name, ids in self._node_sets.items()
        }
        cell_data = {}
        for kind, prefix, sets in (
            ("triangle", _TRIANGLE_MASK, self._element_sets),
            ("line", _LINE_MASK, self._line_sets),
        ):
            for name, ids in sets.items():
                cell_data[prefix + name] = [
                    _mask(ids if k == kind else [], len(c)) for k, c in blocks
                ]
        return {"point_data": point_data, "cell_data": cell_data}


# --------------------------------------------------------------------------------------------
# Validation helpers
# --------------------------------------------------------------------------------------------


def _read_only(array: np.ndarray) -> np.ndarray:
    array.setflags(write=False)
    return array


def _as_mapping(given: Mapping[str, ArrayLike] | None, what: str) -> Mapping[str, ArrayLike]:
    if given is None:
        return {}
    if not isinstance(given, Mapping):
        # Project convention: every kind of bad input raises ValueError.
        raise ValueError(  # noqa: TRY004
            f"{what} must be a mapping name -> ids, got {type(given).__name__}"
        )
    return given


def _positive_int(value: Any, name: str) -> int:
    # bool is an int subclass, but Mesh.rectangle(1, 1, True, 2) is certainly a mistake.
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise ValueError(f"{name} must be a positive integer, got {value!r}")
    return int(value)


def _positive_length(value: Any, name: str) -> float:
    try:
        length = float(value)
    except (TypeError, ValueError) as err:
        raise ValueError(f"{name} must be a positive finite number, got {value!r}") from err
    if not np.isfinite(length) or length <= 0.0:
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return length


def _point3(value: ArrayLike, name: str) -> np.ndarray:
    try:
        point = np.array(value, dtype=np.float64)
    except (TypeError, ValueError) as err:
        raise ValueError(f"{name} must be a point (x, y[, z]), got {value!r}") from err
    if point.shape not in ((2,), (3,)) or not np.isfinite(point).all():
        raise ValueError(f"{name} must be a finite point (x, y[, z]), got {value!r}")
    return np.append(point, 0.0) if point.size == 2 else point


def _check_set_name(name: Any, what: str, existing: Mapping[str, np.ndarray]) -> str:
    if not isinstance(name, str) or not name or name != name.strip():
        raise ValueError(
            f"{what} name must be a non-empty string without surrounding blanks, got {name!r}"
        )
    if _FORBIDDEN_NAME_CHARS & set(name):
        raise ValueError(
            f'{what} name {name!r} must not contain any of , = " or line breaks '
            "(they break .inp and .msh files)"
        )
    if name in existing:
        raise ValueError(f"{what} {name!r} already exists; sets are never overwritten")
    return name


def _set_ids(ids: ArrayLike, size: int, item: str, label: str) -> np.ndarray:
    """Sorted unique int64 ids in [0, size) from ids or a (size,) bool mask."""
    arr = np.asarray(ids)
    if arr.dtype == np.bool_:
        if arr.shape != (size,):
            raise ValueError(f"{label}: a bool mask must have shape ({size},), got {arr.shape}")
        arr = np.flatnonzero(arr)
    elif arr.size == 0:
        arr = np.zeros(0, dtype=np.int64)
    elif arr.dtype.kind not in "iu" or arr.ndim > 1:
        raise ValueError(
            f"{label} must be a 1-D array of integer {item} ids, got dtype {arr.dtype} "
            f"and shape {arr.shape}"
        )
    arr = np.unique(arr.astype(np.int64).reshape(-1))
    if arr.size and (arr[0] < 0 or arr[-1] >= size):
        bad = arr[0] if arr[0] < 0 else arr[-1]
        raise ValueError(f"{label} refers to {item} {bad}, but {item} ids must be in [0, {size})")
    return _read_only(arr)


def _add_set(
    store: dict[str, np.ndarray], what: str, name: str, ids: ArrayLike, size: int, item: str
) -> None:
    name = _check_set_name(name, what, store)
    store[name] = _set_ids(ids, size, item, f"{what} {name!r}")


def _mask(ids: ArrayLike, size: int) -> np.ndarray:
    out = np.zeros(size, dtype=np.uint8)
    out[np.asarray(ids, dtype=np.int64)] = 1
    return out


# --------------------------------------------------------------------------------------------
# Structured grids
# --------------------------------------------------------------------------------------------


def _grid_quads(nx: int, ny: int) -> np.ndarray:
    """(nx * ny, 4) counter-clockwise grid cells (a, b, c, d), a at (i, j), "for j, for i"."""
    j, i = np.divmod(np.arange(nx * ny), nx)
    a = j * (nx + 1) + i
    return np.column_stack((a, a + 1, a + nx + 2, a + nx + 1))


def _split_quads(quads: np.ndarray) -> np.ndarray:
    """(2q, 3) triangles T_A = (a, b, d), T_B = (c, d, b) of quads (q, 4), interleaved."""
    return np.stack((quads[:, [0, 1, 3]], quads[:, [2, 3, 1]]), axis=1).reshape(-1, 3)


def _grid_node_sets(nx: int, ny: int) -> dict[str, np.ndarray]:
    """Side node sets of a structured grid numbered j * (nx + 1) + i."""
    column = np.arange(ny + 1) * (nx + 1)
    row = np.arange(nx + 1)
    return {"left": column, "right": column + nx, "bottom": row, "top": row + ny * (nx + 1)}


# --------------------------------------------------------------------------------------------
# Quadrilateral generator (gmsh)
# --------------------------------------------------------------------------------------------


def _validate_quadrilateral(corners: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Corners (4, 3) of a planar convex quadrilateral and its unit normal (3,)."""
    try:
        quad = np.array(corners, dtype=np.float64)
    except (TypeError, ValueError) as err:
        raise ValueError(f"corners must be a (4, 3) or (4, 2) array: {err}") from err
    if quad.shape not in ((4, 2), (4, 3)):
        raise ValueError(f"corners must have shape (4, 3) or (4, 2), got {quad.shape}")
    if not np.isfinite(quad).all():
        raise ValueError("corners must have finite coordinates")
    if quad.shape[1] == 2:
        quad = np.column_stack((quad, np.zeros(4)))
    size = np.linalg.norm(quad[:, None] - quad[None], axis=2).max()
    # Newell's normal: twice the vector area; robust for slightly non-planar input.
    newell = np.cross(quad, np.roll(quad, -1, axis=0)).sum(axis=0)
    if size == 0.0 or np.linalg.norm(newell) <= _CONVEXITY_TOL * size**2:
        raise ValueError(
            "corners enclose no area: they coincide, are collinear, or form a "
            "self-intersecting quadrilateral"
        )
    normal = newell / np.linalg.norm(newell)
    offset = np.abs((quad - quad.mean(axis=0)) @ normal)
    if offset.max() > _PLANARITY_TOL * size:
        raise ValueError(
            f"corners must be coplanar: corner {int(offset.argmax())} is "
            f"{offset.max():.3g} off their mean plane"
        )
    # At a convex corner of a counter-clockwise polygon the boundary turns left.
    turns = np.cross(quad - np.roll(quad, 1, axis=0), np.roll(quad, -1, axis=0) - quad) @ normal
    bad = np.flatnonzero(turns <= _CONVEXITY_TOL * size**2)
    if bad.size:
        raise ValueError(
            "corners must form a convex, non-self-intersecting quadrilateral in cyclic "
            f"order; the boundary does not turn consistently at corner {int(bad[0])}"
        )
    return quad, normal


# Options forced while meshing (and restored afterwards if gmsh was already running).
_GMSH_OPTIONS = {"General.Terminal": 0.0, "Mesh.ElementOrder": 1.0}


@contextlib.contextmanager
def _gmsh_model(name: str) -> Iterator[ModuleType]:
    """A fresh, silent gmsh model that is removed afterwards.

    If gmsh is not running it is initialised and finalised here; if the caller already runs
    gmsh, its current model and the options we touch are restored instead.
    """
    # Imported here: gmsh loads a large native library that only this generator needs.
    import gmsh

    owner = not gmsh.isInitialized()
    if owner:
        try:
            # interruptible=False: do not install a SIGINT handler (breaks Ctrl-C / threads).
            gmsh.initialize(readConfigFiles=False, interruptible=False)
        except TypeError:  # gmsh < 4.11 has no `interruptible` keyword
            gmsh.initialize(readConfigFiles=False)
        previous_model, saved = "", {}
    else:
        previous_model = gmsh.model.getCurrent()
        saved = {key: gmsh.option.getNumber(key) for key in _GMSH_OPTIONS}
    try:
        for key, value in _GMSH_OPTIONS.items():
            gmsh.option.setNumber(key, value)
        gmsh.model.add(name)
        try:
            yield gmsh
        finally:
            gmsh.model.remove()
    finally:
        if owner:
            gmsh.finalize()
        else:
            for key, value in saved.items():
                gmsh.option.setNumber(key, value)
            gmsh.model.setCurrent(previous_model)


def _gmsh_structured_quads(quad: np.ndarray, nx: int, ny: int) -> tuple[np.ndarray, np.ndarray]:
    """Transfinite quad mesh of corners (4, 3): coordinates (p, 3) and quads (q, 4) in 0..p-1."""
    with _gmsh_model("femcore-quadrilateral") as gmsh:
        geo = gmsh.model.geo
        corner_tags = [geo.addPoint(*c) for c in quad.tolist()]
        curves = [geo.addLine(corner_tags[k], corner_tags[(k + 1) % 4]) for k in range(4)]
        surface = geo.addPlaneSurface([geo.addCurveLoop(curves)])
        for curve, divisions in zip(curves, (nx, ny, nx, ny), strict=True):
            geo.mesh.setTransfiniteCurve(curve, divisions + 1)
        geo.mesh.setTransfiniteSurface(surface, cornerTags=corner_tags)
        geo.mesh.setRecombine(2, surface)
        geo.synchronize()
        gmsh.model.mesh.generate(2)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        _, quad_tags = gmsh.model.mesh.getElementsByType(3)  # 3 = 4-node quadrangle
    tags = np.asarray(tags, dtype=np.int64)
    lookup = np.full(tags.max() + 1, -1, dtype=np.int64)
    lookup[tags] = np.arange(len(tags))
    quads = lookup[np.asarray(quad_tags, dtype=np.int64).reshape(-1, 4)]
    # Compact numbering: keep only nodes that some quad uses.
    used, compact = np.unique(quads, return_inverse=True)
    return np.asarray(coords).reshape(-1, 3)[used], compact.reshape(-1, 4)


def _bilinear_inverse(quad: np.ndarray, x: np.ndarray, tol: float = 1e-13) -> np.ndarray:
    """Parameters (k, 2) = (xi, eta) in [0, 1]^2 of points x (k, 3) under the bilinear map.

    x(xi, eta) = (1-xi)(1-eta) c0 + xi (1-eta) c1 + xi eta c2 + (1-xi) eta c3. Gauss-Newton
    on all points at once (the loop is over iterations only); it converges quadratically
    from the centre for convex quadrilaterals.
    """
    c0, c1, c2, c3 = quad
    uv = np.full((len(x), 2), 0.5)
    for _ in range(50):
        xi, eta = uv[:, :1], uv[:, 1:]
        residual = (
            (1 - xi) * (1 - eta) * c0 + xi * (1 - eta) * c1 + xi * eta * c2 + (1 - xi) * eta * c3
        ) - x
        d_xi = (1 - eta) * (c1 - c0) + eta * (c2 - c3)
        d_eta = (1 - xi) * (c3 - c0) + xi * (c2 - c1)
        jac = np.stack((d_xi, d_eta), axis=2)  # (k, 3, 2)
        jtj = np.einsum("kdi,kdj->kij", jac, jac)
        jtr = np.einsum("kdi,kd->ki", jac, residual)
        step = np.linalg.solve(jtj, jtr[..., None])[..., 0]
        uv -= step
        if np.abs(step).max() < tol:
            break
    return uv


def _structured_numbering(
    quad: np.ndarray, coords: np.ndarray, quads: np.ndarray, nx: int, ny: int
) -> tuple[np.ndarray, np.ndarray]:
    """Renumber gmsh nodes as j * (nx + 1) + i and sort quads "for j, for i".

    (i, j) come from the bilinear parameters of each node, which a transfinite mesh of a
    straight-sided quadrilateral places exactly at (i / nx, j / ny).
    """
    scaled = _bilinear_inverse(quad, coords) * (nx, ny)
    grid = np.rint(scaled).astype(np.int64)
    ids = grid[:, 1] * (nx + 1) + grid[:, 0]
    n_grid = (nx + 1) * (ny + 1)
    on_grid = np.abs(scaled - grid).max() < 1e-6 and len(ids) == n_grid
    if not on_grid or not np.array_equal(np.sort(ids), np.arange(n_grid)):
        raise RuntimeError("gmsh did not return the expected structured grid of nodes")
    points = np.empty_like(coords)
    points[ids] = coords
    quads = ids[quads]
    cell = (quads // (nx + 1)).min(axis=1) * nx + (quads % (nx + 1)).min(axis=1)
    return points, quads[np.argsort(cell)]


def _orient_quads(points: np.ndarray, quads: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Reverse the node order of quads (q, 4) whose normal opposes ``normal`` (3,)."""
    x = points[quads]
    flip = np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 1]) @ normal < 0.0
    out = quads.copy()
    out[flip] = out[flip, ::-1]
    return out


def _rotate_to_warp(points: np.ndarray, quads: np.ndarray, warp: np.ndarray) -> np.ndarray:
    """Cyclically rotate quads (q, 4) so edge 0 -> 1 is the one most aligned with warp (q, 3)."""
    x = points[quads]
    edges = np.roll(x, -1, axis=1) - x  # edge k runs from node k to node k + 1
    edges /= np.linalg.norm(edges, axis=2, keepdims=True)
    shift = np.argmax(np.einsum("qkd,qd->qk", edges, warp), axis=1)
    return np.take_along_axis(quads, (shift[:, None] + np.arange(4)) % 4, axis=1)


# --------------------------------------------------------------------------------------------
# meshio conversion
# --------------------------------------------------------------------------------------------


def _gmsh_ascii_data(extra: dict[str, Any], blocks: list[tuple[str, np.ndarray]]) -> dict[str, Any]:
    """Adapt set masks for meshio's ASCII gmsh writer and add the two gmsh cell tags.

    Element and line sets are dropped when the mesh has both triangles and lines: meshio
    5.3's gmsh reader splits $ElementData of several cell blocks at the wrong places (it
    measures the (type, data) tuples instead of the blocks), so such a file could not be
    read back.
    """
    # meshio 5.3 prints ASCII data values with repr(), which numpy >= 2 renders as
    # "np.uint8(1)"; object arrays of Python ints print as plain "1".
    point_data = {name: mask.astype(object) for name, mask in extra["point_data"].items()}
    cell_data = {}
    if len(blocks) == 1:
        cell_data = {
            name: [mask.astype(object) for mask in per_block]
            for name, per_block in extra["cell_data"].items()
        }
    # Supplying the physical and elementary tags stops meshio warning that it invents them.
    cell_data["gmsh:physical"] = [np.zeros(len(cells), np.int32) for _, cells in blocks]
    cell_data["gmsh:geometrical"] = [np.ones(len(cells), np.int32) for _, cells in blocks]
    return {"point_data": point_data, "cell_data": cell_data}


def _resolve_format(path: Path, file_format: str | None, writing: bool) -> str:
    """meshio format name for path: explicit, else from the (possibly compound) suffix."""
    if file_format is not None:
        return file_format
    suffixes = [s.lower() for s in path.suffixes]
    for k in range(len(suffixes)):
        ext = "".join(suffixes[k:])
        if ext == ".msh":
            # meshio would pick "ansys" first for .msh; gmsh 2.2 ASCII is the portable choice.
            return "gmsh22" if writing else "gmsh"
        if ext in meshio.extension_to_filetypes:
            return meshio.extension_to_filetypes[ext][0]
    raise ValueError(
        f"cannot tell the mesh format of {path}: use a known suffix (.msh, .vtu, .inp, ...) "
        "or pass file_format"
    )


def _kind_ids(
    local_ids: list[np.ndarray | None], kinds: list[str], sizes: list[int], kind: str
) -> np.ndarray:
    """Ids in the concatenated numbering of ``kind`` cells from per-block local ids."""
    parts, offset = [], 0
    for block_kind, size, ids in zip(kinds, sizes, local_ids, strict=True):  # over blocks
        if block_kind == kind:
            if ids is not None:
                parts.append(np.asarray(ids, dtype=np.int64).reshape(-1) + offset)
            offset += size
    return np.concatenate(parts) if parts else np.zeros(0, dtype=np.int64)


def _merge_set(store: dict[str, np.ndarray], name: str, ids: np.ndarray) -> None:
    store[name] = np.union1d(store[name], ids) if name in store else ids


def _mesh_from_meshio(raw: meshio.Mesh, source: str) -> Mesh:
    kinds = [block.type for block in raw.cells]
    sizes = [len(block.data) for block in raw.cells]
    unsupported = sorted(set(kinds) - {"triangle", "line", "vertex"})
    if unsupported:
        raise ValueError(
            f"{source} contains {unsupported} cells; only triangle, line and vertex cells "
            "are supported"
        )
    if "triangle" not in kinds and "line" not in kinds:
        raise ValueError(f"{source} contains neither triangle nor line cells")
    cells = {
        kind: _kind_ids([b.data for b in raw.cells], kinds, sizes, kind).reshape(-1, width)
        for kind, width in (("triangle", 3), ("line", 2))
    }
    sets: dict[str, dict[str, np.ndarray]] = {"node": {}, "triangle": {}, "line": {}}

    for name, ids in raw.point_sets.items():
        _merge_set(sets["node"], name, np.asarray(ids, dtype=np.int64))
    for name, per_block in raw.cell_sets.items():
        if name.startswith("gmsh:"):  # meshio bookkeeping such as gmsh:bounding_entities
            continue
        for kind in ("triangle", "line"):
            ids = _kind_ids(list(per_block), kinds, sizes, kind)
            if ids.size:  # a set of the other cell kind has no members here
                _merge_set(sets[kind], name, ids)
    for name, data in raw.point_data.items():
        if name.startswith(_NODE_MASK):
            _merge_set(sets["node"], name[len(_NODE_MASK) :], np.flatnonzero(np.ravel(data)))
    for prefix, kind in ((_TRIANGLE_MASK, "triangle"), (_LINE_MASK, "line")):
        for name, per_block in raw.cell_data.items():
            if name.startswith(prefix):
                local = [np.flatnonzero(np.ravel(mask)) for mask in per_block]
                _merge_set(sets[kind], name[len(prefix) :], _kind_ids(local, kinds, sizes, kind))
    _add_physical_groups(raw, kinds, sizes, sets)

    return Mesh(
        raw.points,
        cells["triangle"],
        cells["line"],
        node_sets=sets["node"],
        element_sets=sets["triangle"],
        line_sets=sets["line"],
    )


def _add_physical_groups(
    raw: meshio.Mesh, kinds: list[str], sizes: list[int], sets: dict[str, dict[str, np.ndarray]]
) -> None:
    """Named gmsh physical groups -> node (dim 0), line (dim 1) and element (dim 2) sets."""
    physical = raw.cell_data.get("gmsh:physical")
    if physical is None:
        return
    kind_of_dim = {0: "vertex", 1: "line", 2: "triangle"}
    for name, (tag, dim) in ((n, np.ravel(v)[:2]) for n, v in raw.field_data.items()):
        kind = kind_of_dim.get(int(dim))
        if kind is None:
            continue
        local = [np.flatnonzero(np.ravel(tags) == tag) for tags in physical]
        ids = _kind_ids(local, kinds, sizes, kind)
        if kind == "vertex":
            vertices = _kind_ids([b.data for b in raw.cells], kinds, sizes, "vertex")
            _merge_set(sets["node"], name, np.unique(vertices[ids]))
        else:
            _merge_set(sets[kind], name, ids)
