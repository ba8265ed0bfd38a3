"""The checks a :class:`femcore.mesh.Mesh` runs on its input at construction.

Coordinates in a range where lengths, areas and their products stay ordinary double-precision
numbers, a mesh extent from which the relative tolerances of the topology checks are not
zero, no cell given twice, and well-formed named sets. Every failure is a ValueError that
names the offending value and what was expected; the checks are vectorised (a sort of the
cells, one pass over the points), so they cost little next to building the mesh.
"""

from __future__ import annotations

import inspect
import warnings
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from femcore.set_names import abaqus_key

__all__ = [
    "COORDINATE_LIMIT",
    "MIN_EXTENT",
    "THICK_SHELL_CELLS",
    "add_set",
    "as_mapping",
    "check_coordinates",
    "check_distinct_cells",
    "check_thickness_scale",
    "read_only",
    "select_by_predicate",
    "sorted_unique",
]

COORDINATE_LIMIT = 1e60
"""Largest absolute coordinate accepted (length units). Beyond it, products of a few lengths
(squared distances, areas, second moments of area) overflow double precision: a coordinate
that large is a unit or input mistake, not a mesh."""

MIN_EXTENT = 1e-60
"""Smallest extent (bounding-box diagonal, length units) of a mesh of several nodes. Below
it the relative tolerances of the checks (1e-9 x the extent for duplicate nodes, 1e-12 x its
square for zero areas) and products of lengths underflow to zero or to denormal numbers."""

# Characters that would break the set syntax of .inp or .msh files.
_FORBIDDEN_NAME_CHARS = {",", "=", '"', "\n", "\r"}

# How many repeated cells an error message lists.
_LISTED = 5


def check_coordinates(points: np.ndarray) -> None:
    """Check that coordinates are in range and that the nodes span a usable extent.

    Parameters
    ----------
    points : numpy.ndarray of float64, shape (n, 3)
        Finite node coordinates (length units), as ``validate_points`` returns them.

    Raises
    ------
    ValueError
        A coordinate beyond +-COORDINATE_LIMIT (naming the node and the range), or several
        nodes whose extent is below MIN_EXTENT (the mesh is degenerate or far too small;
        naming the extent), including nodes that all coincide.
    """
    magnitude = np.abs(points).max(axis=1)
    far = np.flatnonzero(magnitude > COORDINATE_LIMIT)
    if far.size:
        node = int(far[0])
        raise ValueError(
            f"node {node} has coordinates {tuple(points[node].tolist())} outside the range "
            f"[-{COORDINATE_LIMIT:g}, {COORDINATE_LIMIT:g}] (length units) that products of "
            f"lengths keep in double precision ({far.size} such nodes); check the units"
        )
    if len(points) < 2:
        return
    span = points.max(axis=0) - points.min(axis=0)
    largest = float(span.max())
    # Scaled so that the squares of a span of 1e-200 do not underflow to an extent of 0.
    extent = largest * float(np.linalg.norm(span / largest)) if largest > 0.0 else 0.0
    if extent < MIN_EXTENT:
        what = "all its nodes coincide" if extent == 0.0 else f"its extent is {extent:.3g}"
        raise ValueError(
            f"the mesh is degenerate or too small: {what} (bounding-box diagonal of its "
            f"{len(points)} nodes), below {MIN_EXTENT:g} length units, where the tolerances "
            "of duplicate nodes and zero areas underflow; check the units"
        )


def check_distinct_cells(cells: np.ndarray, kind: str) -> None:
    """Check that no two cells of one kind join the same nodes, in any order.

    The same triangle given twice (e.g. (0, 1, 2) and (1, 2, 0) or (0, 2, 1)) would count its
    mass and stiffness twice, silently.

    Parameters
    ----------
    cells : numpy.ndarray of int64, shape (c, k)
        Node ids per cell.
    kind : str
        The cell kind, for the message ("triangle", "line").

    Raises
    ------
    ValueError
        Naming the first pairs of repeated cells, their nodes and how many there are.
    """
    if len(cells) < 2:
        return
    nodes = np.sort(cells, axis=1)
    base = int(nodes[:, -1].max()) + 1
    if base ** nodes.shape[1] < 2**62:
        # One int64 key per cell: a 1-D sort, several times faster than a lexsort of rows.
        key = nodes[:, 0].copy()
        for column in nodes.T[1:]:
            key *= base
            key += column
        key.sort()
        if not (key[1:] == key[:-1]).any():
            return
    order = np.lexsort(nodes.T[::-1])
    ordered = nodes[order]
    same = np.flatnonzero((ordered[1:] == ordered[:-1]).all(axis=1))
    if same.size == 0:
        return
    pairs = np.sort(np.column_stack((order[same], order[same + 1])), axis=1)
    pairs = pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]
    listed = "; ".join(
        f"{a} {tuple(cells[a].tolist())} and {b} {tuple(cells[b].tolist())}"
        for a, b in pairs[:_LISTED].tolist()
    )
    more = f" (and {len(pairs) - _LISTED} more pairs)" if len(pairs) > _LISTED else ""
    raise ValueError(
        f"the same {kind} is given twice: {kind}s {listed}{more} join the same nodes; a cell "
        "given twice would count its mass and stiffness twice (remove the copies)"
    )


def read_only(array: np.ndarray) -> np.ndarray:
    """``array`` itself, made read-only."""
    array.setflags(write=False)
    return array


def as_mapping(given: Mapping[str, ArrayLike] | None, what: str) -> Mapping[str, ArrayLike]:
    """``given`` (None: an empty mapping), or ValueError if it is not a mapping."""
    if given is None:
        return {}
    if not isinstance(given, Mapping):
        # Project convention: every kind of bad input raises ValueError.
        raise ValueError(  # noqa: TRY004
            f"{what} must be a mapping name -> ids, got {type(given).__name__}"
        )
    return given


def add_set(
    store: dict[str, np.ndarray],
    what: str,
    name: str,
    ids: ArrayLike,
    size: int,
    item: str,
    fold: bool = False,
) -> None:
    """Check a new set's name and ids and add it to ``store`` as sorted unique int64 ids.

    Parameters
    ----------
    store : dict
        The sets of one kind (name -> ids), extended in place.
    what : str
        How messages name such a set, e.g. "node set".
    name : str
        The new set's name.
    ids : array_like of int, or bool array of shape (size,)
        Ids in [0, size) or a mask.
    size : int
        Number of items (nodes or cells of the kind).
    item : str
        How messages name one item, e.g. "node" or "triangle".
    fold : bool
        The mesh finds its sets as Abaqus reads names (a deck's mesh, femcore.set_names):
        a name equal to a set's up to case and blanks is that set's, so it is used too.

    Raises
    ------
    ValueError
        An invalid or used name (up to case and blanks when ``fold``), ids out of range, or
        a mask of the wrong shape.
    """
    name = _check_set_name(name, what, store)
    same = [known for known in store if abaqus_key(known) == abaqus_key(name)] if fold else []
    if same:
        raise ValueError(
            f"{what} name {name!r} is already used, as {same[0]!r}: this mesh, read from an "
            "Abaqus deck, reads set names as Abaqus does, in any case and without blanks "
            f"(femcore.set_names), so {name!r} would name that set; choose another name"
        )
    store[name] = _set_ids(ids, size, item, f"{what} {name!r}")


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
    arr = sorted_unique(arr.astype(np.int64).reshape(-1))
    if arr.size and (arr[0] < 0 or arr[-1] >= size):
        bad = arr[0] if arr[0] < 0 else arr[-1]
        raise ValueError(f"{label} refers to {item} {bad}, but {item} ids must be in [0, {size})")
    return read_only(arr)


def sorted_unique(ids: ArrayLike) -> np.ndarray:
    """Sorted unique ids, shape (k,) int64, of any ids. A sort and a comparison: numpy 2's
    np.unique hashes, about 100 times slower on the millions of ids of a large mesh's sets."""
    ids = np.asarray(ids, dtype=np.int64).reshape(-1)
    if ids.size > 1 and not (ids[1:] > ids[:-1]).all():
        ids = np.sort(ids)
        ids = ids[np.concatenate(([True], ids[1:] != ids[:-1]))]
    return ids


_PREDICATE_FORM = (
    "a node predicate takes the (x, y, z) coordinate arrays and returns a bool array, "
    "one entry per node, e.g. lambda x, y, z: np.isclose(x, 0.0)"
)


def select_by_predicate(points: np.ndarray, predicate: Callable[..., Any]) -> np.ndarray:
    """Ids of the nodes a predicate selects, or ValueError saying what a predicate must be.

    Parameters
    ----------
    points : numpy.ndarray, shape (n, 3)
        Node coordinates (length units).
    predicate : callable
        Called once as ``predicate(x, y, z)`` with the (n,) coordinate arrays; must return an
        (n,) bool array.

    Returns
    -------
    numpy.ndarray of int64, shape (s,)
        Sorted ids of the nodes where the mask is True (possibly empty).

    Raises
    ------
    ValueError
        The predicate cannot be called with three arguments, or returns something else than
        an (n,) bool array.
    """
    label = f"predicate {getattr(predicate, '__qualname__', repr(predicate))}"
    # The arity is checked before the call: a TypeError raised inside a predicate of the right
    # arity is the predicate's own bug and is left to propagate with its traceback.
    try:
        signature = inspect.signature(predicate)
    except (TypeError, ValueError):
        signature = None
    if signature is not None:
        try:
            signature.bind(points[:, 0], points[:, 1], points[:, 2])
        except TypeError:
            raise ValueError(
                f"{label}{signature} cannot be called as predicate(x, y, z): {_PREDICATE_FORM}"
            ) from None
    mask = np.asarray(predicate(points[:, 0], points[:, 1], points[:, 2]))
    n = points.shape[0]
    if mask.shape != (n,):
        raise ValueError(
            f"{label} returned an array of shape {mask.shape}, expected ({n},): {_PREDICATE_FORM}"
        )
    if mask.dtype != np.bool_:
        raise ValueError(
            f"{label} returned an array of dtype {mask.dtype}, expected bool: {_PREDICATE_FORM}"
        )
    return np.flatnonzero(mask)


# A shell thicker than its block's span is a section and a mesh in two systems of units (a
# mesh in m beside a thickness in mm: 1000 x too thick); one thicker than twenty times its
# cells' median edge is almost always the same mistake on a mesh too large for the first
# test to see it (a 2 m part in m with 5 cm cells and a 1 mm sheet in mm), while the meshes
# of thin shells have cells longer than, or a few times shorter than, their thickness. Not
# ten: the fine meshes of a convergence study on a thick stack reach 10-12 (the G986 stack, 6
# mm, on 0.5 x 3 mm cells; the G1151 laminate, 15 mm, on 1.4 mm cells).
THICK_SHELL_CELLS = 20.0


def check_thickness_scale(points: np.ndarray, cells: np.ndarray, thickness: float, what: str):
    """Refuse a shell thicker than its cells' span; warn for one thicker than
    ``THICK_SHELL_CELLS`` times their median edge (the median of each cell's first edge, a
    third of the edges, 0.03 s at 400 000 triangles).

    Parameters
    ----------
    points : (n, 3) float
        The mesh's node coordinates (length units).
    cells : (c, k) int
        The block's cells.
    thickness : float
        The section's thickness, in the units of the material.
    what : str
        The element type, for the message.

    Raises
    ------
    ValueError
        ``thickness`` above the largest extent of the block's nodes along x, y or z: almost
        always a mesh in m with a material in mm (or the other way round).
    """
    if not len(cells):
        return
    used = np.zeros(len(points), dtype=bool)
    used[cells.ravel()] = True
    span = float(np.ptp(points[used], axis=0).max())
    # every cell's first edge: the median of a third of the edges, at a third of the cost
    first = points[cells[:, 1]] - points[cells[:, 0]]
    edge = float(np.median(np.sqrt(np.einsum("ij,ij->i", first, first))))
    way_out = (
        "is the mesh in m and the material in mm (or the other way round)? Give both in one "
        "system of units (mm, N, t, s or m, N, kg, s)"
    )
    if span > 0.0 and thickness > span:
        raise ValueError(
            f"{what} thickness {thickness:g} is {thickness / span:.3g} x the largest extent of "
            f"its cells ({span:g}): {way_out}"
        )
    if edge > 0.0 and thickness > THICK_SHELL_CELLS * edge:
        warnings.warn(
            f"{what} thickness {thickness:g} is {thickness / edge:.3g} x the median edge of its "
            f"cells ({edge:g}; a shell's cells are rarely more than a few times shorter than "
            f"its thickness): {way_out}",
            UserWarning,
            stacklevel=4,
        )


def known_kind(kind: str, kinds: Mapping[str, Any]) -> str:
    """``kind`` if it is a key of ``kinds`` (femcore.mesh.CELL_KINDS), else a ValueError."""
    if kind not in kinds:
        raise ValueError(f"unknown cell kind {kind!r}; known kinds: {list(kinds)}")
    return kind


def by_kind(
    kinds: Mapping[str, Any],
    generic: Mapping[str, Any] | None,
    what: str,
    legacy: dict[str, Any],
    legacy_names: dict[str, str],
) -> dict[str, Any]:
    """Merge a generic kind -> value mapping (keys of ``kinds``) with the legacy per-kind
    arguments (a Mesh's ``triangles=``, ``lines=``...), refusing a kind given both ways."""
    merged = dict(as_mapping(generic, what))
    for kind in merged:
        known_kind(kind, kinds)
    for kind, value in legacy.items():
        if value is None:
            continue
        if kind in merged:
            raise ValueError(
                f"{kind} data given twice: as {legacy_names[kind]} and in {what}[{kind!r}]"
            )
        merged[kind] = value
    return merged
