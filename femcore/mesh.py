"""Meshes of 3-node triangles (shells, membranes) and 2-node lines (cables, bars).

A :class:`Mesh` holds node coordinates (length units, always 3-D), the connectivity of each
kind of cell, and named sets of nodes and of cells of each kind. The kinds of cell a mesh can
hold are listed once, in :data:`CELL_KINDS` (today "triangle" and "line"); everything that
handles cells generically (:meth:`Mesh.cells`, :meth:`Mesh.cell_sets`, file I/O, result
export) loops over that table, so adding a kind is one entry there. The historical names
(:attr:`Mesh.triangles`, :attr:`Mesh.lines`, :attr:`Mesh.element_sets`,
:attr:`Mesh.line_sets`) are views of the triangle and line entries.

Coordinates and connectivity are validated once at construction and stored as read-only
arrays, so a mesh never changes shape after it was checked; :meth:`Mesh.with_points` makes a
moved copy instead. The only mutating methods are :meth:`Mesh.add_node_set`,
:meth:`Mesh.add_cell_set` and its shorthands :meth:`Mesh.add_element_set` and
:meth:`Mesh.add_line_set`, which only add new named sets.

Fibre-aligned generators (:meth:`Mesh.rectangle`, :meth:`Mesh.quadrilateral`) split each grid
cell into two triangles whose first local node is the corner where the warp (first grid
direction) and weft (second grid direction) meet: with 0-based local numbering, edge 0 -> 1
runs along the warp and edge 0 -> 2 along the weft, in the positive or negative sense
("node 1 at the right angle, 1 -> 2 along warp, 1 -> 3 along weft" in 1-based terms).
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
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

__all__ = ["CELL_KINDS", "CellKind", "Mesh", "NodePredicate"]

NodePredicate = Callable[[np.ndarray, np.ndarray, np.ndarray], ArrayLike]
"""Called once as ``predicate(x, y, z)`` with (n,) coordinate arrays; returns an (n,) bool mask."""


@dataclass(frozen=True)
class CellKind:
    """Description of one kind of cell a :class:`Mesh` can hold (an entry of CELL_KINDS).

    Parameters
    ----------
    nodes_per_cell : int
        Number of nodes of one cell (width of the (m, nodes_per_cell) connectivity).
    meshio_name : str
        meshio's name of the cell type, used for file I/O and result export.
    dimension : int
        Topological dimension (1 for curves, 2 for surfaces); a named gmsh physical group of
        this dimension becomes a set of cells of this kind.
    set_label : str
        How error messages name a set of these cells, e.g. "element set".
    mask_prefix : str
        Prefix of the 0/1 cell-data arrays that store these sets in formats without native
        sets, e.g. "elset:" (the array "elset:<name>").
    """

    nodes_per_cell: int
    meshio_name: str
    dimension: int
    set_label: str
    mask_prefix: str

    @property
    def plural(self) -> str:
        """Plural of the meshio name, for messages ("triangles", "lines")."""
        return self.meshio_name + "s"


# The one table of cell kinds; everything else reads it through CELL_KINDS at call time.
_CELL_KIND_TABLE: dict[str, CellKind] = {
    # Adding a kind (e.g. "quad": CellKind(4, "quad", 2, "quad set", "qset:")) is one entry.
    "triangle": CellKind(3, "triangle", 2, "element set", "elset:"),
    "line": CellKind(2, "line", 1, "line set", "lset:"),
}

CELL_KINDS: Mapping[str, CellKind] = MappingProxyType(_CELL_KIND_TABLE)
"""The known cell kinds, name -> :class:`CellKind`, in their canonical order (read-only)."""


def _kind_of_meshio() -> dict[str, str]:
    """meshio cell type -> cell kind."""
    return {spec.meshio_name: kind for kind, spec in CELL_KINDS.items()}


# The constructor arguments that predate the generic ``cells`` / ``cell_sets``.
_LEGACY_CELLS = {"triangle": "triangles", "line": "lines"}
_LEGACY_SETS = {"triangle": "element_sets", "line": "line_sets"}

# Characters that would break the set syntax of .inp or .msh files.
_FORBIDDEN_NAME_CHARS = {",", "=", '"', "\n", "\r"}

# Formats whose meshio reader and writer keep named point/cell sets (Abaqus NSET/ELSET).
# Every other format gets the sets as 0/1 mask arrays named with "nset:" (nodes) or the
# mask prefix of the cell kind.
_NATIVE_SET_FORMATS = {"abaqus"}
_NODE_MASK = "nset:"

# Relative tolerances of the quadrilateral corner checks (times the corner diameter).
_PLANARITY_TOL = 1e-9
_CONVEXITY_TOL = 1e-12


class Mesh:
    """Cells of the kinds in CELL_KINDS on shared nodes, with named node and cell sets.

    Parameters
    ----------
    points : array_like, shape (n, 3) or (n, 2)
        Node coordinates (length units); 2-D points get z = 0.
    triangles : array_like of int, shape (m, 3), optional
        Node ids per triangle, counter-clockwise about the intended normal. Same as
        ``cells={"triangle": ...}``.
    lines : array_like of int, shape (k, 2), optional
        Node ids per line cell. Same as ``cells={"line": ...}``.
    node_sets : Mapping[str, array_like], optional
        Name -> node ids (or an (n,) bool mask).
    element_sets : Mapping[str, array_like], optional
        Name -> triangle ids (or an (m,) bool mask). Same as ``cell_sets={"triangle": ...}``.
    line_sets : Mapping[str, array_like], optional
        Name -> line ids (or a (k,) bool mask). Same as ``cell_sets={"line": ...}``.
    cells : Mapping[str, array_like], optional
        Cell kind (a key of CELL_KINDS) -> (c, nodes_per_cell) node ids, keyword only.
    cell_sets : Mapping[str, Mapping[str, array_like]], optional
        Cell kind -> {name: cell ids or a (c,) bool mask}, keyword only.

    Raises
    ------
    ValueError
        Wrong shapes, non-finite coordinates (naming the node), node ids out of range (naming
        the cell and the id), a cell repeating a node, invalid sets, an unknown cell kind, or
        the same cells or sets given both by their legacy argument and in ``cells`` /
        ``cell_sets``. Duplicate nodes, zero areas and orientation are checked by
        :meth:`check`.
    """

    def __init__(
        self,
        points: ArrayLike,
        triangles: ArrayLike | None = None,
        lines: ArrayLike | None = None,
        node_sets: Mapping[str, ArrayLike] | None = None,
        element_sets: Mapping[str, ArrayLike] | None = None,
        line_sets: Mapping[str, ArrayLike] | None = None,
        *,
        cells: Mapping[str, ArrayLike | None] | None = None,
        cell_sets: Mapping[str, Mapping[str, ArrayLike] | None] | None = None,
    ) -> None:
        given_cells = _by_kind(
            cells, "cells", {"triangle": triangles, "line": lines}, _LEGACY_CELLS
        )
        given_sets = _by_kind(
            cell_sets, "cell_sets", {"triangle": element_sets, "line": line_sets}, _LEGACY_SETS
        )
        self._points = _read_only(validate_points(points))
        n = len(self._points)
        self._cells: dict[str, np.ndarray] = {
            kind: _read_only(validate_cells(given_cells.get(kind), spec.nodes_per_cell, kind, n))
            for kind, spec in CELL_KINDS.items()
        }
        self._node_sets: dict[str, np.ndarray] = {}
        self._cell_sets: dict[str, dict[str, np.ndarray]] = {kind: {} for kind in CELL_KINDS}
        for name, ids in _as_mapping(node_sets, "node_sets").items():
            self.add_node_set(name, ids)
        for kind in CELL_KINDS:
            what = _LEGACY_SETS.get(kind, f"cell_sets[{kind!r}]")
            for name, ids in _as_mapping(given_sets.get(kind), what).items():
                self.add_cell_set(kind, name, ids)

    # ----------------------------------------------------------------------------------------
    # Read-only data
    # ----------------------------------------------------------------------------------------

    @property
    def points(self) -> np.ndarray:
        """(n, 3) float64 node coordinates (length units), read-only."""
        return self._points

    @property
    def cell_kinds(self) -> tuple[str, ...]:
        """The cell kinds present (at least one cell), in CELL_KINDS order, e.g.
        ("triangle", "line")."""
        return tuple(kind for kind, cells in self._cells.items() if len(cells))

    def cells(self, kind: str) -> np.ndarray:
        """Connectivity of the cells of one kind.

        Parameters
        ----------
        kind : str
            A key of CELL_KINDS, e.g. "triangle" or "line".

        Returns
        -------
        numpy.ndarray of int64, shape (c, nodes_per_cell)
            Node ids per cell, read-only; (0, nodes_per_cell) if the mesh has none.

        Raises
        ------
        ValueError
            Unknown cell kind.
        """
        return self._cells[_known_kind(kind)]

    def cell_sets(self, kind: str) -> Mapping[str, np.ndarray]:
        """Named sets of the cells of one kind.

        Parameters
        ----------
        kind : str
            A key of CELL_KINDS, e.g. "triangle" or "line".

        Returns
        -------
        Mapping[str, numpy.ndarray]
            Read-only view name -> sorted unique int64 cell ids (indices into
            ``cells(kind)``).

        Raises
        ------
        ValueError
            Unknown cell kind.
        """
        return MappingProxyType(self._cell_sets[_known_kind(kind)])

    @property
    def triangles(self) -> np.ndarray:
        """(m, 3) int64 node ids of the triangles, read-only; (0, 3) if there are none."""
        return self._cells["triangle"]

    @property
    def lines(self) -> np.ndarray:
        """(k, 2) int64 node ids of the line cells, read-only; (0, 2) if there are none."""
        return self._cells["line"]

    @property
    def node_sets(self) -> Mapping[str, np.ndarray]:
        """Read-only view name -> sorted unique int64 node ids."""
        return MappingProxyType(self._node_sets)

    @property
    def element_sets(self) -> Mapping[str, np.ndarray]:
        """Read-only view name -> sorted unique int64 triangle ids (``cell_sets("triangle")``)."""
        return self.cell_sets("triangle")

    @property
    def line_sets(self) -> Mapping[str, np.ndarray]:
        """Read-only view name -> sorted unique int64 line-cell ids (``cell_sets("line")``)."""
        return self.cell_sets("line")

    @property
    def n_nodes(self) -> int:
        """Number of nodes n."""
        return len(self._points)

    @property
    def n_triangles(self) -> int:
        """Number of triangles m."""
        return len(self._cells["triangle"])

    @property
    def n_lines(self) -> int:
        """Number of line cells k."""
        return len(self._cells["line"])

    @cached_property
    def topology(self) -> Topology:
        """Edge/neighbour structure of the triangles (computed once; cells never change)."""
        return build_topology(self._cells["triangle"])

    def __repr__(self) -> str:
        return (
            f"Mesh(n_nodes={self.n_nodes}, n_triangles={self.n_triangles}, "
            f"n_lines={self.n_lines}, node_sets={list(self._node_sets)}, "
            f"element_sets={list(self.element_sets)}, line_sets={list(self.line_sets)})"
        )

    # ----------------------------------------------------------------------------------------
    # Sets (the only mutating methods)
    # ----------------------------------------------------------------------------------------

    def add_node_set(self, name: str, ids: ArrayLike) -> None:
        """Add a new node set.

        Parameters
        ----------
        name : str
            Non-empty name without surrounding blanks, commas, ``=``, quotes or line breaks.
        ids : array_like of int, or bool array of shape (n,)
            Node ids (any order, repeats allowed) or a bool mask over the nodes.

        Raises
        ------
        ValueError
            Invalid or already used name, ids out of range, or a mask of the wrong shape.
        """
        _add_set(self._node_sets, "node set", name, ids, self.n_nodes, "node")

    def add_cell_set(self, kind: str, name: str, ids: ArrayLike) -> None:
        """Add a new set of cells of one kind.

        Parameters
        ----------
        kind : str
            A key of CELL_KINDS, e.g. "triangle" or "line".
        name : str
            Non-empty name without surrounding blanks, commas, ``=``, quotes or line breaks;
            unique among the sets of this kind.
        ids : array_like of int, or bool array of shape (c,)
            Cell ids (indices into ``cells(kind)``) or a bool mask over those cells.

        Raises
        ------
        ValueError
            Unknown kind, invalid or already used name, ids out of range, or a mask of the
            wrong shape.
        """
        kind = _known_kind(kind)
        label = CELL_KINDS[kind].set_label
        _add_set(self._cell_sets[kind], label, name, ids, len(self._cells[kind]), kind)

    def add_element_set(self, name: str, ids: ArrayLike) -> None:
        """Add a new triangle set: ``add_cell_set("triangle", name, ids)``.

        Parameters
        ----------
        name : str
            Name of the new set (see :meth:`add_cell_set`).
        ids : array_like of int, or bool array of shape (m,)
            Triangle ids or a bool mask over the triangles.

        Raises
        ------
        ValueError
            As :meth:`add_cell_set`.
        """
        self.add_cell_set("triangle", name, ids)

    def add_line_set(self, name: str, ids: ArrayLike) -> None:
        """Add a new line-cell set: ``add_cell_set("line", name, ids)``.

        Parameters
        ----------
        name : str
            Name of the new set (see :meth:`add_cell_set`).
        ids : array_like of int, or bool array of shape (k,)
            Line ids or a bool mask over the line cells.

        Raises
        ------
        ValueError
            As :meth:`add_cell_set`.
        """
        self.add_cell_set("line", name, ids)

    # ----------------------------------------------------------------------------------------
    # Queries
    # ----------------------------------------------------------------------------------------

    def nodes(self, selection: str | NodePredicate) -> np.ndarray:
        """Ids of the nodes selected by a node-set name or a predicate.

        Parameters
        ----------
        selection : str or NodePredicate
            A node-set name, or a predicate called ONCE as ``predicate(x, y, z)`` with the
            (n,) coordinate arrays (length units) that must return an (n,) bool mask, e.g.
            ``lambda x, y, z: np.isclose(x, 0.0)``.

        Returns
        -------
        numpy.ndarray of int64, shape (s,)
            Sorted node ids, s >= 1.

        Raises
        ------
        ValueError
            Unknown set name, a mask of the wrong shape or dtype, or an empty selection
            (almost always a tolerance or coordinate mistake).
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
        """Corners of the axis-aligned box around all nodes.

        Returns
        -------
        lower, upper : numpy.ndarray, shape (3,)
            Smallest and largest coordinate along each axis (length units).
        """
        return self._points.min(axis=0), self._points.max(axis=0)

    def check(self) -> None:
        """Run the topology checks on the triangles.

        See :func:`femcore.topology.check_triangles`: non-manifold edges, inconsistent
        orientation, duplicate nodes and zero-area triangles.

        Raises
        ------
        ValueError
            Describing the first problem found.
        """
        if self.n_triangles:
            check_triangles(self._points, self.triangles)

    def with_points(self, points: ArrayLike) -> Mesh:
        """A new mesh with the same cells and sets but other coordinates.

        Parameters
        ----------
        points : array_like, shape (n, 3) or (n, 2)
            New node coordinates (length units), one row per existing node.

        Returns
        -------
        Mesh
            The moved copy; this mesh is unchanged.

        Raises
        ------
        ValueError
            Wrong number of rows, wrong shape or non-finite coordinates.
        """
        pts = validate_points(points)
        if len(pts) != self.n_nodes:
            raise ValueError(f"points must have {self.n_nodes} rows, got {len(pts)}")
        return Mesh(pts, node_sets=self._node_sets, cells=self._cells, cell_sets=self._cell_sets)

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
        """Fibre-aligned right-triangle mesh of an lx x ly rectangle.

        Warp along x, weft along y, in the plane z = origin z. Node ``j * (nx + 1) + i`` sits
        at origin + (i lx / nx, j ly / ny, 0). Grid cell (i, j), in order "for j, for i", gives
        T_A = (P_ij, P_i+1,j, P_i,j+1) then T_B = (P_i+1,j+1, P_i,j+1, P_i+1,j): both
        counter-clockwise (normal +z), right-angled at local node 0, edge 0 -> 1 along +-x.

        Parameters
        ----------
        lx, ly : float
            Side lengths along x and y (length units), positive.
        nx, ny : int
            Positive numbers of divisions along x and y.
        origin : array_like, shape (3,) or (2,)
            Corner of the rectangle with the smallest coordinates (length units).

        Returns
        -------
        Mesh
            (nx + 1)(ny + 1) nodes and 2 nx ny triangles, with node sets "left", "right",
            "bottom", "top" (x min, x max, y min, y max) and element set "all".

        Raises
        ------
        ValueError
            Non-positive or non-finite lengths, non-positive or non-integer counts, or a bad
            origin.
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
        """n equal 2-node line cells from p0 to p1.

        Node k sits at p0 + (k / n)(p1 - p0); cell k joins nodes k and k + 1.

        Parameters
        ----------
        p0, p1 : array_like, shape (3,) or (2,)
            End points (length units); they must differ.
        n : int
            Positive number of cells.

        Returns
        -------
        Mesh
            n + 1 nodes and n line cells, with node sets "start" and "end" and line set "all".

        Raises
        ------
        ValueError
            Bad or coincident end points, or a non-positive count.
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

        gmsh builds a transfinite quad mesh (nodes at the bilinear map of the corners); each
        quad is rotated so that its first edge is the one most aligned with the local warp
        direction (1 - eta)(c1 - c0) + eta (c2 - c3) at its centroid, and split as in
        :meth:`rectangle`. Nodes and cells are numbered exactly as in :meth:`rectangle`
        (node j * (nx + 1) + i at bilinear parameters (i / nx, j / ny)), so for rectangular
        corners both generators agree.

        Parameters
        ----------
        corners : array_like, shape (4, 3) or (4, 2)
            Corners c0, c1, c2, c3 in cyclic order (length units). The warp runs along
            c0 -> c1 with nx divisions, the weft along c0 -> c3 with ny divisions. Triangle
            normals follow (c1 - c0) x (c3 - c0), i.e. +z for 2-D corners listed
            counter-clockwise.
        nx, ny : int
            Positive numbers of divisions.

        Returns
        -------
        Mesh
            (nx + 1)(ny + 1) nodes and 2 nx ny triangles, with node sets "bottom" (c0-c1),
            "right" (c1-c2), "top" (c2-c3), "left" (c3-c0) and element set "all".

        Raises
        ------
        ValueError
            Bad shapes or counts, non-coplanar corners, or a non-convex, self-intersecting or
            degenerate quadrilateral.
        RuntimeError
            gmsh did not return the expected structured grid.
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
    def from_quads(
        cls,
        points: ArrayLike,
        quads: ArrayLike,
        node_sets: Mapping[str, ArrayLike] | None = None,
        quad_sets: Mapping[str, ArrayLike] | None = None,
    ) -> Mesh:
        """A triangle mesh from a quadrilateral one, each quad (a, b, c, d) split into
        (a, b, d) and (c, d, b): every triangle keeps two sides of its quad meeting at a
        corner, so a quad mesh whose sides follow the warp and the weft gives the
        fibre-aligned triangles the fibrous shell needs (one side along each family).

        Parameters
        ----------
        points : array_like, shape (n, 3) or (n, 2)
        quads : array_like of int, shape (q, 4)
            Node ids of each quad in cyclic order.
        node_sets : mapping name -> node ids, optional
        quad_sets : mapping name -> quad ids, optional
            Become triangle sets: quad i is triangles 2 i and 2 i + 1.

        Returns
        -------
        Mesh

        Raises
        ------
        ValueError
            Quads not of shape (q, 4), node ids out of range, or a quad set out of range.
        """
        quads = np.asarray(quads)
        if quads.ndim != 2 or quads.shape[1] != 4 or len(quads) == 0:
            raise ValueError(f"quads must have shape (q, 4) with q >= 1, got {quads.shape}")
        sets = {}
        for name, ids in (quad_sets or {}).items():
            ids = np.asarray(ids, dtype=np.int64).ravel()
            if ids.size and (ids.min() < 0 or ids.max() >= len(quads)):
                raise ValueError(f"quad set {name!r} refers to quads outside 0..{len(quads) - 1}")
            sets[name] = np.column_stack([2 * ids, 2 * ids + 1]).ravel()
        return cls(
            points,
            triangles=_split_quads(quads.astype(np.int64)),
            node_sets=node_sets,
            element_sets=sets,
        )

    @classmethod
    def read(cls, path: str | Path, file_format: str | None = None) -> Mesh:
        """Read a mesh file through meshio (.msh, .vtu, .inp, ...).

        Keeps the cells of the kinds in CELL_KINDS ("triangle" and "line") and ignores
        "vertex" cells; quadrilaterals (gmsh quads, Abaqus S4/S4R) are split in two triangles
        each as :meth:`from_quads` does (fibre-aligned when their sides follow the fibres),
        their sets and cell data following them. Named sets come back from Abaqus NSET/ELSET
        (.inp), from the "nset:/elset:/lset:" mask arrays that :meth:`write` stores in other
        formats, and from named gmsh physical groups (dimension 0 -> node set, 1 -> line set,
        2 -> element set; in general, dimension d -> a set of the cell kinds of dimension d).

        Parameters
        ----------
        path : str or pathlib.Path
            The file to read.
        file_format : str, optional
            meshio format name; by default it follows the suffix (.msh is read as gmsh).

        Returns
        -------
        Mesh
            The mesh with its cells and named sets.

        Raises
        ------
        FileNotFoundError
            The file does not exist.
        ValueError
            Unknown format, unreadable file, other cell types, or no cell of a known kind.
        """
        path = Path(path)
        if not path.is_file():
            raise FileNotFoundError(f"mesh file {path} does not exist")
        fmt = _resolve_format(path, file_format, writing=False)
        try:
            raw = meshio.read(path, file_format=fmt)
        except SystemExit as err:  # meshio's VTU reader ends the process on a corrupt file
            raise ValueError(f"cannot read {path} as {fmt!r}: not a valid {fmt} file") from err
        except UnicodeDecodeError as err:
            raise ValueError(
                f"cannot read {path} as {fmt!r}: not a text file ({err.reason} at byte {err.start})"
            ) from err
        except Exception as err:  # meshio's readers raise anything on a corrupt file
            raise ValueError(f"cannot read {path} as {fmt!r}: {type(err).__name__}: {err}") from err
        return _mesh_from_meshio(raw, str(path))

    def write(self, path: str | Path, file_format: str | None = None) -> None:
        """Write the mesh through meshio; the format follows the suffix unless given.

        .msh is written as ASCII gmsh 2.2. Sets are kept as NSET/ELSET in .inp and as 0/1
        mask arrays "nset:<name>" (point data), "elset:<name>" and "lset:<name>" (cell data;
        in general the mask prefix of the cell kind) elsewhere. Known losses: formats without
        point/cell data (e.g. .stl, .obj) drop all sets; .msh drops the cell sets of a mesh
        with cells of more than one kind, e.g. both triangles and lines (meshio 5.3 cannot
        read such element data back); .inp drops empty cell sets.

        Parameters
        ----------
        path : str or pathlib.Path
            The file to write.
        file_format : str, optional
            meshio format name; by default it follows the suffix.

        Raises
        ------
        ValueError
            Unknown format, a mesh without cells, or (for .inp) a name used by the sets of
            two cell kinds (e.g. both an element set and a line set).
        """
        path = Path(path)
        fmt = _resolve_format(path, file_format, writing=True)
        blocks = [(kind, self._cells[kind]) for kind in self.cell_kinds]
        if not blocks:
            raise ValueError(
                f"cannot write a mesh that has {_neither(s.plural for s in CELL_KINDS.values())}"
            )
        kinds = [kind for kind, _ in blocks]
        if fmt in _NATIVE_SET_FORMATS:
            extra = self._native_sets(kinds)
        else:
            extra = self._set_masks(blocks)
        options: dict[str, Any] = {}
        if fmt.startswith("gmsh"):
            extra = _gmsh_ascii_data(extra, blocks)
            options["binary"] = False
        meshio_blocks = [(CELL_KINDS[kind].meshio_name, cells) for kind, cells in blocks]
        out = meshio.Mesh(self._points, meshio_blocks, **extra)
        try:
            meshio.write(path, out, file_format=fmt, **options)
        except meshio.WriteError as err:
            raise ValueError(f"cannot write {path} as {fmt!r}: {err}") from err

    def _native_sets(self, kinds: list[str]) -> dict[str, Any]:
        names = list(CELL_KINDS)
        for i, first in enumerate(names):
            for second in names[i + 1 :]:
                shared = sorted(set(self._cell_sets[first]) & set(self._cell_sets[second]))
                if shared:
                    raise ValueError(
                        f"set names {shared} are used by both "
                        f"{_article(CELL_KINDS[first].set_label)} and "
                        f"{_article(CELL_KINDS[second].set_label)}; "
                        "an .inp file cannot keep both under one name"
                    )
        empty = np.zeros(0, dtype=np.int64)
        cell_sets = {}
        for kind, sets in self._cell_sets.items():
            for name, ids in sets.items():
                cell_sets[name] = [ids if k == kind else empty for k in kinds]
        return {"point_sets": dict(self._node_sets), "cell_sets": cell_sets}

    def _set_masks(self, blocks: list[tuple[str, np.ndarray]]) -> dict[str, Any]:
        point_data = {
            _NODE_MASK + name: _mask(ids, self.n_nodes) for name, ids in self._node_sets.items()
        }
        cell_data = {}
        for kind, sets in self._cell_sets.items():
            prefix = CELL_KINDS[kind].mask_prefix
            for name, ids in sets.items():
                cell_data[prefix + name] = [
                    _mask(ids if k == kind else [], len(c)) for k, c in blocks
                ]
        return {"point_data": point_data, "cell_data": cell_data}


# --------------------------------------------------------------------------------------------
# Validation helpers
# --------------------------------------------------------------------------------------------


def _known_kind(kind: str) -> str:
    if kind not in CELL_KINDS:
        raise ValueError(f"unknown cell kind {kind!r}; known kinds: {list(CELL_KINDS)}")
    return kind


def _by_kind(
    generic: Mapping[str, Any] | None,
    what: str,
    legacy: dict[str, Any],
    legacy_names: dict[str, str],
) -> dict[str, Any]:
    """Merge a generic kind -> value mapping with the legacy per-kind arguments."""
    merged = dict(_as_mapping(generic, what))
    for kind in merged:
        _known_kind(kind)
    for kind, value in legacy.items():
        if value is None:
            continue
        if kind in merged:
            raise ValueError(
                f"{kind} data given twice: as {legacy_names[kind]} and in {what}[{kind!r}]"
            )
        merged[kind] = value
    return merged


def _neither(items: Iterator[str] | Sequence[str]) -> str:
    """ "neither a nor b nor c" """
    return "neither " + " nor ".join(items)


def _article(noun: str) -> str:
    return ("an " if noun[:1] in "aeiou" else "a ") + noun


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

    Cell sets are dropped when the mesh has cells of more than one kind (e.g. both triangles
    and lines): meshio 5.3's gmsh reader splits $ElementData of several cell blocks at the
    wrong places (it measures the (type, data) tuples instead of the blocks), so such a file
    could not be read back.
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
            return str(meshio.extension_to_filetypes[ext][0])
    raise ValueError(
        f"cannot tell the mesh format of {path}: use a known suffix (.msh, .vtu, .inp, ...) "
        "or pass file_format"
    )


def _kind_ids(
    local_ids: Sequence[ArrayLike | None], kinds: Sequence[str], sizes: Sequence[int], kind: str
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


def _split_quad_blocks(raw: meshio.Mesh) -> meshio.Mesh:
    """``raw`` with each "quad" block replaced by its triangles (``_split_quads``): quad i of
    a block is triangles 2 i and 2 i + 1 of it, in its cell sets and cell data too."""
    if "quad" in CELL_KINDS or not any(block.type == "quad" for block in raw.cells):
        return raw  # no quads, or a registered quad kind that keeps them
    quad = [block.type == "quad" for block in raw.cells]
    cells = [
        meshio.CellBlock("triangle", _split_quads(np.asarray(block.data))) if is_quad else block
        for block, is_quad in zip(raw.cells, quad)
    ]

    def doubled(per_block, index_list: bool):
        out = []
        for data, is_quad in zip(per_block, quad):
            data = np.asarray(data)
            if is_quad and index_list:
                data = np.column_stack([2 * data, 2 * data + 1]).ravel()
            elif is_quad:
                data = np.repeat(data, 2, axis=0)
            out.append(data)
        return out

    return meshio.Mesh(
        raw.points,
        cells,
        point_data=raw.point_data,
        cell_data={name: doubled(v, False) for name, v in raw.cell_data.items()},
        point_sets=raw.point_sets,
        cell_sets={name: doubled(v, True) for name, v in raw.cell_sets.items()},
    )


def _mesh_from_meshio(raw: meshio.Mesh, source: str) -> Mesh:
    raw = _split_quad_blocks(raw)
    # Block kinds in our vocabulary ("vertex" and unknown meshio types keep their name).
    kind_of = _kind_of_meshio()
    kinds = [kind_of.get(block.type, block.type) for block in raw.cells]
    sizes = [len(block.data) for block in raw.cells]
    unsupported = sorted({block.type for block in raw.cells} - set(kind_of) - {"vertex"})
    if unsupported:
        names = ", ".join(kind_of)
        raise ValueError(
            f"{source} contains {unsupported} cells; only {names} and vertex cells are supported"
        )
    if not set(kinds) & set(CELL_KINDS):
        raise ValueError(f"{source} contains {_neither(list(CELL_KINDS))} cells")
    cells = {
        kind: _kind_ids([b.data for b in raw.cells], kinds, sizes, kind).reshape(
            -1, spec.nodes_per_cell
        )
        for kind, spec in CELL_KINDS.items()
    }
    sets: dict[str, dict[str, np.ndarray]] = {"node": {}, **{kind: {} for kind in CELL_KINDS}}

    for name, ids in raw.point_sets.items():
        _merge_set(sets["node"], name, np.asarray(ids, dtype=np.int64))
    for name, per_block in raw.cell_sets.items():
        if name.startswith("gmsh:"):  # meshio bookkeeping such as gmsh:bounding_entities
            continue
        for kind in CELL_KINDS:
            ids = _kind_ids(list(per_block), kinds, sizes, kind)
            if ids.size:  # a set of another cell kind has no members here
                _merge_set(sets[kind], name, ids)
    for name, data in raw.point_data.items():
        if name.startswith(_NODE_MASK):
            _merge_set(sets["node"], name[len(_NODE_MASK) :], np.flatnonzero(np.ravel(data)))
    for kind, spec in CELL_KINDS.items():
        prefix = spec.mask_prefix
        for name, per_block in raw.cell_data.items():
            if name.startswith(prefix):
                local = [np.flatnonzero(np.ravel(mask)) for mask in per_block]
                _merge_set(sets[kind], name[len(prefix) :], _kind_ids(local, kinds, sizes, kind))
    _add_physical_groups(raw, kinds, sizes, sets)

    return Mesh(
        raw.points,
        node_sets=sets["node"],
        cells=cells,
        cell_sets={kind: sets[kind] for kind in CELL_KINDS},
    )


def _add_physical_groups(
    raw: meshio.Mesh, kinds: list[str], sizes: list[int], sets: dict[str, dict[str, np.ndarray]]
) -> None:
    """Named gmsh physical groups -> node sets (dimension 0) and cell sets (dimension d: the
    cell kinds of that dimension, e.g. 1 -> line sets, 2 -> element sets)."""
    physical = raw.cell_data.get("gmsh:physical")
    if physical is None:
        return
    for name, (tag, dim) in ((n, np.ravel(v)[:2]) for n, v in raw.field_data.items()):
        local = [np.flatnonzero(np.ravel(tags) == tag) for tags in physical]
        if int(dim) == 0:
            ids = _kind_ids(local, kinds, sizes, "vertex")
            vertices = _kind_ids([b.data for b in raw.cells], kinds, sizes, "vertex")
            _merge_set(sets["node"], name, np.unique(vertices[ids]))
            continue
        # A group goes to the kinds of its dimension that have members in it (to the first
        # such kind if none has: an empty set, as for a group on cells of an unused kind).
        candidates = [kind for kind, spec in CELL_KINDS.items() if spec.dimension == int(dim)]
        found = {kind: _kind_ids(local, kinds, sizes, kind) for kind in candidates}
        targets = [kind for kind in candidates if found[kind].size] or candidates[:1]
        for kind in targets:
            _merge_set(sets[kind], name, found[kind])
