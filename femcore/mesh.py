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

The generators (:meth:`Mesh.rectangle`, :meth:`Mesh.line`, :meth:`Mesh.quadrilateral`,
:meth:`Mesh.from_quads`, :meth:`Mesh.corner`) are implemented in
:mod:`femcore.mesh_generators`, which describes the fibre-aligned split of the grid cells;
reading and writing files (:meth:`Mesh.read`, :meth:`Mesh.write`) in :mod:`femcore.mesh_io`.
Both modules import this one, so the methods import them when called.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from types import MappingProxyType

import numpy as np
from numpy.typing import ArrayLike

from femcore.mesh_checks import (
    add_set,
    as_mapping,
    by_kind,
    check_coordinates,
    check_distinct_cells,
    known_kind,
    read_only,
    select_by_predicate,
)
from femcore.read_only_state import ReadOnlyState
from femcore.set_names import set_named
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


# The constructor arguments that predate the generic ``cells`` / ``cell_sets``.
_LEGACY_CELLS = {"triangle": "triangles", "line": "lines"}
_LEGACY_SETS = {"triangle": "element_sets", "line": "line_sets"}


class Mesh(ReadOnlyState):
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
    fold_set_names : bool, optional
        Find a set by any spelling Abaqus takes for its name (any case, blanks ignored) where
        the name asked is not one exactly (femcore.set_names); keyword only. True for the
        mesh of an Abaqus deck (:meth:`read`), False (names exact) otherwise.

    Raises
    ------
    ValueError
        Wrong shapes, non-finite coordinates or coordinates beyond +-1e60 (naming the node),
        nodes spanning less than 1e-60 (a degenerate or far too small mesh,
        femcore.mesh_checks), node ids out of range (naming the cell and the id), a cell
        repeating a node, two cells of a kind on the same nodes in any order (naming them),
        invalid sets, an unknown cell kind, or the same cells or sets given both by their
        legacy argument and in ``cells`` / ``cell_sets``. Duplicate nodes, zero areas and
        orientation are checked by :meth:`check`.
    """

    _fold_set_names = False  # a mesh pickled before the attribute existed: names exact

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
        fold_set_names: bool = False,
    ) -> None:
        given_cells = by_kind(
            CELL_KINDS, cells, "cells", {"triangle": triangles, "line": lines}, _LEGACY_CELLS
        )
        given_sets = by_kind(
            CELL_KINDS,
            cell_sets,
            "cell_sets",
            {"triangle": element_sets, "line": line_sets},
            _LEGACY_SETS,
        )
        self._points = read_only(validate_points(points))
        check_coordinates(self._points)
        n = len(self._points)
        self._cells: dict[str, np.ndarray] = {
            kind: read_only(validate_cells(given_cells.get(kind), spec.nodes_per_cell, kind, n))
            for kind, spec in CELL_KINDS.items()
        }
        for kind, kind_cells in self._cells.items():
            check_distinct_cells(kind_cells, kind)
        self._node_sets: dict[str, np.ndarray] = {}
        self._cell_sets: dict[str, dict[str, np.ndarray]] = {kind: {} for kind in CELL_KINDS}
        for name, ids in as_mapping(node_sets, "node_sets").items():
            self.add_node_set(name, ids)
        for kind in CELL_KINDS:
            what = _LEGACY_SETS.get(kind, f"cell_sets[{kind!r}]")
            for name, ids in as_mapping(given_sets.get(kind), what).items():
                self.add_cell_set(kind, name, ids)
        self._fold_set_names = bool(fold_set_names)  # after the given sets: a deck's own

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
        return self._cells[known_kind(kind, CELL_KINDS)]

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
        return MappingProxyType(self._cell_sets[known_kind(kind, CELL_KINDS)])

    @property
    def triangles(self) -> np.ndarray:
        """(m, 3) int64 node ids of the triangles, read-only; (0, 3) if there are none."""
        return self._cells["triangle"]

    @property
    def lines(self) -> np.ndarray:
        """(k, 2) int64 node ids of the line cells, read-only; (0, 2) if there are none."""
        return self._cells["line"]

    @property
    def fold_set_names(self) -> bool:
        """Whether a set is found by any spelling Abaqus takes for its name (a deck's mesh)."""
        return self._fold_set_names

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
            Invalid or used name (up to case and blanks on a deck's mesh), bad ids or mask.
        """
        add_set(self._node_sets, "node set", name, ids, self.n_nodes, "node", self.fold_set_names)

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
        kind = known_kind(kind, CELL_KINDS)
        store, label = self._cell_sets[kind], CELL_KINDS[kind].set_label
        add_set(store, label, name, ids, len(self._cells[kind]), kind, self.fold_set_names)

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
            selection = set_named(self._node_sets, selection, self.fold_set_names)
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
        return select_by_predicate(self._points, predicate), label

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
        return Mesh(
            pts,
            node_sets=self._node_sets,
            cells=self._cells,
            cell_sets=self._cell_sets,
            fold_set_names=self.fold_set_names,
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
        diagonals: str = "one-way",
    ) -> Mesh:
        """Fibre-aligned right-triangle mesh of an lx x ly rectangle.

        Warp along x, weft along y, in the plane z = origin z. Node ``j * (nx + 1) + i`` sits
        at origin + (i lx / nx, j ly / ny, 0). Grid cell (i, j), in order "for j, for i", gives
        T_A = (P_ij, P_i+1,j, P_i,j+1) then T_B = (P_i+1,j+1, P_i,j+1, P_i+1,j): both
        counter-clockwise (normal +z), right-angled at local node 0, edge 0 -> 1 along +-x.
        With ``diagonals="alternating"`` the cells with i + j odd are split along the other
        diagonal instead, into (P_i+1,j, P_i+1,j+1, P_ij) then (P_i,j+1, P_ij, P_i+1,j+1):
        counter-clockwise, right-angled at local node 0, edge 0 -> 1 along +-y.

        Parameters
        ----------
        lx, ly : float
            Side lengths along x and y (length units), positive.
        nx, ny : int
            Positive numbers of divisions along x and y.
        origin : array_like, shape (3,) or (2,)
            Corner of the rectangle with the smallest coordinates (length units).
        diagonals : {"one-way", "alternating"}
            Every cell split along one diagonal, or a checkerboard of both. A Mindlin plate
            in two-way bending needs "alternating": MITC3 on the one-way pattern locks when
            the plate is thin (a clamped square plate at a/h = 1000 on 16 x 16 cells: 0.24 of
            Kirchhoff's deflection, 0.95 alternating; docs/theory.md §5.3). The fibrous shell
            needs "one-way": its rotation-free bending on the alternating pattern is stiff in
            two-way bending (a pinned orthotropic plate 0.50 of its Navier deflection at 8 and
            16 cells, 0.81 and 0.89 one-way; a one-way strip alike on both).

        Returns
        -------
        Mesh
            (nx + 1)(ny + 1) nodes and 2 nx ny triangles, with node sets "left", "right",
            "bottom", "top" (x min, x max, y min, y max) and element set "all".

        Raises
        ------
        ValueError
            Non-positive or non-finite lengths, non-positive or non-integer counts, a bad
            origin, an unknown ``diagonals``, or more triangles than the memory available can
            hold (femcore.memory).
        """
        from femcore.mesh_generators import rectangle

        return rectangle(lx, ly, nx, ny, origin, diagonals)

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
            Bad or coincident end points, a non-positive count, or more cells than the
            memory available can hold.
        """
        from femcore.mesh_generators import line

        return line(p0, p1, n)

    @classmethod
    def quadrilateral(
        cls, corners: ArrayLike, nx: int, ny: int, diagonals: str = "one-way"
    ) -> Mesh:
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
        diagonals : {"one-way", "alternating"}
            As in :meth:`rectangle`.

        Returns
        -------
        Mesh
            (nx + 1)(ny + 1) nodes and 2 nx ny triangles, with node sets "bottom" (c0-c1),
            "right" (c1-c2), "top" (c2-c3), "left" (c3-c0) and element set "all".

        Raises
        ------
        ValueError
            Bad shapes or counts, non-coplanar corners, a non-convex, self-intersecting or
            degenerate quadrilateral, or more triangles than the memory available can hold.
        RuntimeError
            gmsh did not return the expected structured grid.
        """
        from femcore.mesh_generators import quadrilateral

        return quadrilateral(corners, nx, ny, diagonals)

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
            Quads not of shape (q, 4), node ids out of range, a quad set out of range, or
            more triangles than the memory available can hold.
        """
        from femcore.mesh_generators import from_quads

        return from_quads(points, quads, node_sets, quad_sets)

    @classmethod
    def corner(
        cls,
        lx: float,
        ly: float,
        n: int,
        grip: float | tuple[float, float] | None = None,
        diagonals: str = "one-way",
    ) -> Mesh:
        """The corner specimen of Bai et al. (2020) §6 (Fig. 8): the free triangle of an
        lx x ly rectangle beyond its diagonal.

        Of the rectangle, the triangle beyond the diagonal from (lx, 0) to (0, ly) is clamped
        (Bai §6.1-6.2), so only the free triangle with corners (0, 0) (the loaded corner),
        (lx, 0) and (0, ly) is meshed: the triangles of :meth:`rectangle` with n x n cells
        whose centroid lies before the diagonal, its nodes renumbered keeping their order; the
        clamp is a straight line of cell diagonals (``FibrousShell(clamped="clamp")``).

        Parameters
        ----------
        lx, ly : float
            Side lengths of the rectangle along x (warp) and y (weft) (length units), positive.
        n : int
            Positive number of cells of the rectangle along each side before the cut.
        grip : float, (a, b) or None
            The a x b patch at the free corner (one number: a square) that a gripper holds:
            its edges are grid lines at every n (a graded grid,
            femcore.mesh_generators.corner), its nodes the set "grip"; None: no patch.
        diagonals : {"one-way", "alternating"}
            As in :meth:`rectangle`; the cells the clamp cuts stay split along it.

        Returns
        -------
        Mesh
            (n + 1)(n + 2) / 2 nodes, n^2 triangles, node sets "clamp" (the diagonal),
            "corner" (the origin) and "grip"; without a grip, the grid of :meth:`rectangle`.

        Raises
        ------
        ValueError
            As :meth:`rectangle`; a grip not positive or reaching the diagonal, or an n that
            leaves no cell between the patch and the clamp.
        """
        from femcore.mesh_generators import corner

        return corner(lx, ly, n, grip, diagonals)

    # ----------------------------------------------------------------------------------------
    # File I/O
    # ----------------------------------------------------------------------------------------

    @classmethod
    def read(cls, path: str | Path, file_format: str | None = None) -> Mesh:
        """Read a mesh file through meshio (.msh, .vtu, .inp, ...).

        Keeps the cells of the kinds in CELL_KINDS ("triangle" and "line") of every block,
        in file order, with meshio's node ids (every point of the file is a node, used or
        not), and ignores "vertex" cells; quadrilaterals (gmsh quads, Abaqus S4/S4R) are
        split in two triangles each as :meth:`from_quads` does (fibre-aligned when their
        sides follow the fibres), their sets and cell data following them. Named sets come
        back from Abaqus NSET/ELSET (.inp, read by Abaqus's rules: NSET= of *NODE and ELSET=
        of *ELEMENT lines, sets made of other sets, GENERATE lines, the nodes of several
        *NODE blocks; the files of *INCLUDE lines read in place, nested, a relative INPUT=
        from the main deck's folder at every depth: femcore.inp_include), from the
        "nset:/elset:/lset:" mask arrays that :meth:`write` stores in other formats, and
        from named gmsh physical groups: every group is the node set of its cells' nodes (a
        physical curve "clamp" holds the nodes of its lines), and a group of dimension d is
        also a set of the cells of the kinds of dimension d (1 -> line set, 2 -> element
        set). An element that MSH 2.2 repeats for each physical group of its
        entity is kept once. Keywords of an Abaqus deck the reader does not turn into the
        mesh (*BOUNDARY, *MATERIAL, *SHELL SECTION, *STEP, ...) are listed in one
        UserWarning. A deck is read by Abaqus's syntax: a set name in any case and without
        its blanks is one set, named as the deck first writes it and found by any such
        spelling (``fold_set_names``); a coordinate left out or blank is 0, SYSTEM=C nodes
        (r, theta deg, z) are converted; data lines may stand in an INPUT= file; shells
        (S3, S4 families; gmsh's CPS3, S3T.. with a warning) and trusses/beams are read.

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
        ValueError
            A missing file or a directory, unknown format, unreadable file, other cell
            types, no cell of a known kind, an Abaqus deck's *INCLUDE file missing or
            including itself again (naming the including file and line), an
            assembly of several *INSTANCE entries or a moved one, a set naming a set, a
            node or an element the deck does not define, a GENERATE line that is not
            ``first, last[, increment]``, an element repeating a node, a rigid (a tool's:
            RigidSurface), membrane, continuum or second-order type, an empty *ELEMENT block,
            SYSTEM=S, a keyword making or moving nodes (*NGEN, *ELGEN, *SYSTEM, ...), a line that
            is not numbers (each naming the file and the line: femcore.inp_sets), two gmsh
            physical groups of one name or one whose name a set cannot take (naming the
            file and the groups), a mesh too large for the memory available
            (femcore.memory), or any check of the constructor (e.g. the same triangle
            twice; naming the file).
        """
        from femcore.mesh_io import read_mesh

        return read_mesh(path, file_format)

    def write(self, path: str | Path, file_format: str | None = None) -> None:
        """Write the mesh through meshio; the format follows the suffix unless given.

        .msh is written as ASCII gmsh 2.2, .inp with triangles as S3 shells and lines as
        T3D2 trusses. Sets are kept as NSET/ELSET in .inp and as 0/1
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
            two cell kinds (e.g. both an element set and a line set), or set names equal up
            to case and blanks (one set for Abaqus).
        """
        from femcore.mesh_io import write_mesh

        write_mesh(self, path, file_format)
