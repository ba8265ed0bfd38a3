"""Reading and writing :class:`femcore.mesh.Mesh` files through meshio (and gmsh's format).

Users call :meth:`Mesh.read` and :meth:`Mesh.write`, which document the formats, the sets kept
and the known losses, and delegate to :func:`read_mesh` and :func:`write_mesh` here.
"""

from __future__ import annotations

import tempfile
import warnings
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

import meshio
import numpy as np
from numpy.typing import ArrayLike

from femcore.checks import as_path
from femcore.inp_deck import DeckScan, scan_deck
from femcore.inp_sets import resolve_deck_sets, scan_deck_sets
from femcore.inp_write import FIELD_WIDTH, node_block, quote_set_names
from femcore.memory import check_mesh_memory
from femcore.mesh import CELL_KINDS, Mesh
from femcore.mesh_checks import sorted_unique
from femcore.mesh_generators import split_quads
from femcore.set_names import abaqus_key
from femcore.writable import OutputError, check_folder

__all__ = ["read_mesh", "write_mesh"]

# Formats whose meshio reader and writer keep named point/cell sets (Abaqus NSET/ELSET).
# Every other format gets the sets as 0/1 mask arrays named with "nset:" (nodes) or the
# mask prefix of the cell kind.
_NATIVE_SET_FORMATS = {"abaqus"}
_NODE_MASK = "nset:"


def read_mesh(path: str | Path, file_format: str | None = None, tool: bool = False) -> Mesh:
    """Read a mesh file through meshio: the implementation of :meth:`Mesh.read`, which
    documents the formats, the sets read back and the errors. ``tool=True`` reads a rigid
    tool's file (elements.RigidSurface): an Abaqus deck's rigid and surface facets (R3D3,
    R3D4, SFM3D3, SFM3D4, SFM3D4R) are read as its triangles, where a body's deck refuses
    them (femcore.inp_lines)."""
    path = as_path(path, "Mesh.read path")
    if path.is_dir():
        raise ValueError(f"mesh file {path} is a directory; expected a mesh file in it")
    if not path.is_file():
        # Project convention: every kind of bad input raises ValueError.
        raise ValueError(f"mesh file {path} does not exist")
    fmt = _resolve_format(path, file_format, writing=False)
    deck = _checked_deck(path) if fmt == "abaqus" else DeckScan()
    if fmt == "gmsh":
        _check_physical_names(path)
    # A deck's sets are read here by Abaqus's rules, its *INCLUDE files in place
    # (femcore.inp_sets, femcore.inp_include), meshio reading its nodes and elements only.
    own_sets = scan_deck_sets(path, tool) if fmt == "abaqus" else None
    try:
        if own_sets is None:
            raw = meshio.read(path, file_format=fmt)
        else:
            with tempfile.TemporaryDirectory() as folder:
                bare = Path(folder) / path.name
                bare.write_text(own_sets.mesh_text, encoding="utf-8")
                raw = meshio.read(bare, file_format=fmt)
    except SystemExit as err:  # meshio's VTU reader ends the process on a corrupt file
        raise ValueError(f"cannot read {path} as {fmt!r}: not a valid {fmt} file") from err
    except UnicodeDecodeError as err:
        raise ValueError(
            f"cannot read {path} as {fmt!r}: not a text file ({err.reason} at byte {err.start})"
        ) from err
    except ModuleNotFoundError as err:  # e.g. .med files need h5py
        raise ValueError(
            f"cannot read {path} as {fmt!r}: meshio needs the package {err.name!r} for this "
            f"format (pip install {err.name})"
        ) from err
    except Exception as err:  # meshio's readers raise anything on a corrupt file
        hint = ""
        if "gmsh:physical" in str(err):
            hint = (
                " (a MSH 4.1 file written with gmsh's Mesh.SaveAll and physical groups, which "
                "meshio 5.3 cannot read: write it without SaveAll, or as MSH 2.2)"
            )
        raise ValueError(
            f"cannot read {path} as {fmt!r}: {type(err).__name__}: {err}{hint}"
        ) from err
    if own_sets is not None:  # meshio reads one block per *ELEMENT, as the scan does
        raw.point_sets, raw.cell_sets = resolve_deck_sets(own_sets)
    # Quads become two triangles each; the rest one cell each (vertex cells are dropped).
    n_cells = sum(len(block.data) * (2 if block.type == "quad" else 1) for block in raw.cells)
    check_mesh_memory(n_cells, len(raw.points), f"the mesh of {path}")
    mesh = _mesh_from_meshio(raw, str(path), fold_set_names=own_sets is not None)
    if own_sets is not None and own_sets.normals_at:
        more = len(own_sets.normals_at) - 1
        others = f" (and {more} more *NODE line{'s' if more > 1 else ''})" if more else ""
        warnings.warn(
            f"{own_sets.where(own_sets.normals_at[0])}{others} gives the direction cosines "
            "of a normal after the coordinates; the reader leaves them: a shell's normals "
            "come from its elements (docs/theory.md)",
            UserWarning,
            stacklevel=3,
        )
    left_out = own_sets.scopes.warning() if own_sets is not None else None
    if left_out:
        warnings.warn(left_out, UserWarning, stacklevel=3)
    for note in own_sets.read_as if own_sets is not None else []:
        warnings.warn(
            f"{note}: the deck's elements are read as the shell's (or the tool's) cells, and "
            "its sections never are; if the deck is a plane-stress or thermal model, it is "
            "not one here",
            UserWarning,
            stacklevel=3,
        )
    if deck.ignored:
        warnings.warn(
            f"{path}: the mesh reader keeps the nodes, elements and node/element sets of an "
            f"Abaqus deck and ignores {deck.ignored_summary()}; give supports, loads, "
            "materials, sections and steps in the model or the case file",
            UserWarning,
            stacklevel=3,
        )
    return mesh


def _checked_deck(path: Path) -> DeckScan:
    """The keyword scan of an Abaqus deck (its included files in place), or ValueError for an
    assembly the reader cannot place (several instances, or a moved one)."""
    deck = scan_deck(path)
    if len(deck.instances) > 1:
        listed = ", ".join(f"{name!r} ({line})" for line, name, _ in deck.instances)
        raise ValueError(
            f"{path} has {len(deck.instances)} *INSTANCE entries, {listed}; the .inp reader "
            "reads each part's mesh once, at the part's own coordinates, and the sets of "
            "every instance on that one copy: write the assembly as one flat mesh (one *NODE "
            "block, no *PART), or keep one instance"
        )
    for line, name, moves in deck.instances:
        # A translation line (3 numbers), then a rotation line (7, the angle last).
        moved = any(
            len(move) > 0 and not all(v == 0.0 for v in (move[-1:] if i else move))
            for i, move in enumerate(moves)
        )
        if moved:
            raise ValueError(
                f"{path}: *INSTANCE {name!r} ({line}) is moved or rotated, by "
                f"{'; '.join(', '.join(f'{v:g}' for v in m) for m in moves)}; the .inp reader "
                "reads the part's mesh at its own coordinates: write the mesh where it stands "
                "(no *PART), or the instance unmoved"
            )
    return deck


def write_mesh(mesh: Mesh, path: str | Path, file_format: str | None = None) -> None:
    """Write a mesh through meshio: the implementation of :meth:`Mesh.write`, which documents
    the formats, how the sets are kept, the known losses and the errors."""
    path = as_path(path, "Mesh.write path")
    fmt = _resolve_format(path, file_format, writing=True)
    check_folder(path.parent, "Mesh.write", create=False)
    blocks = [(kind, mesh.cells(kind)) for kind in mesh.cell_kinds]
    if not blocks:
        raise ValueError(
            f"cannot write a mesh that has {_neither(s.plural for s in CELL_KINDS.values())}"
        )
    kinds = [kind for kind, _ in blocks]
    if fmt in _NATIVE_SET_FORMATS:
        extra = _native_sets(mesh, kinds)
    else:
        extra = _set_masks(mesh, blocks)
    options: dict[str, Any] = {}
    if fmt.startswith("gmsh"):
        extra = _gmsh_ascii_data(extra, blocks)
        options["binary"] = False
    meshio_blocks = [(CELL_KINDS[kind].meshio_name, cells) for kind, cells in blocks]
    out = meshio.Mesh(mesh.points, meshio_blocks, **extra)
    try:
        meshio.write(path, out, file_format=fmt, **options)
        if fmt == "abaqus":
            _abaqus_element_types(path, mesh, kinds)
    except meshio.WriteError as err:
        raise ValueError(f"cannot write {path} as {fmt!r}: {err}") from err
    except OSError as err:
        raise OutputError.from_error(err, "nothing (the file may be incomplete)") from err


# The Abaqus type a meshio cell type is written as: a shell or a truss (meshio 5.3 writes
# R3D3, a rigid element, B31H, a beam, and CAX4P, an axisymmetric continuum, which Abaqus and
# CalculiX would read as such).
_ABAQUS_TYPES = {"triangle": "S3", "line": "T3D2", "quad": "S4"}


def _abaqus_element_types(path: Path, mesh: Mesh, kinds: list[str]) -> None:
    """Rewrite what meshio wrote at ``path`` so that Abaqus and CalculiX read the mesh as it
    is (femcore.inp_write): the *NODE lines with numbers of at most 20 characters, the
    *ELEMENT lines with the types of _ABAQUS_TYPES (meshio writes each block's keyword line
    as ``*ELEMENT, TYPE=<its type>`` alone), set names with blanks quoted."""
    text = path.read_text(encoding="utf-8")
    for kind in dict.fromkeys(kinds):
        name = CELL_KINDS[kind].meshio_name
        written = meshio.abaqus._abaqus.meshio_to_abaqus_type[name]
        text = text.replace(
            f"\n*ELEMENT, TYPE={written}\n", f"\n*ELEMENT, TYPE={_ABAQUS_TYPES[name]}\n"
        )
    head, _, rest = text.partition("\n*NODE\n")
    nodes, inexact = node_block(mesh.points)
    text = head + "\n*NODE\n" + nodes + rest[rest.index("*ELEMENT") :]
    path.write_text(quote_set_names(text), encoding="utf-8")
    if inexact:
        warnings.warn(
            f"{path}: {inexact} coordinate(s) need 17 significant digits and an exponent, "
            f"more than the {FIELD_WIDTH} characters CalculiX reads per number: written "
            "rounded to fewer digits (a few units in the last place)",
            UserWarning,
            stacklevel=4,
        )


def _native_sets(mesh: Mesh, kinds: list[str]) -> dict[str, Any]:
    """Node and cell sets as meshio point_sets / cell_sets (per block ids), for .inp."""
    names = list(CELL_KINDS)
    for i, first in enumerate(names):
        for second in names[i + 1 :]:
            shared = sorted(set(mesh.cell_sets(first)) & set(mesh.cell_sets(second)))
            if shared:
                raise ValueError(
                    f"set names {shared} are used by both "
                    f"{_article(CELL_KINDS[first].set_label)} and "
                    f"{_article(CELL_KINDS[second].set_label)}; "
                    "an .inp file cannot keep both under one name"
                )
    # NSET and ELSET names are apart in Abaqus: each checked among its own.
    clashes = []
    for names in (list(mesh.node_sets), [n for k in CELL_KINDS for n in mesh.cell_sets(k)]):
        spelled: dict[str, set[str]] = {}
        for name in names:
            spelled.setdefault(abaqus_key(name), set()).add(name)
        clashes += sorted(sorted(group) for group in spelled.values() if len(group) > 1)
    if clashes:
        raise ValueError(
            f"the set names {clashes[0]} differ in case or blanks only; Abaqus reads them as "
            "one set (femcore.set_names): rename them before writing an .inp file"
        )
    empty = np.zeros(0, dtype=np.int64)
    cell_sets = {}
    for kind in CELL_KINDS:
        for name, ids in mesh.cell_sets(kind).items():
            cell_sets[name] = [ids if k == kind else empty for k in kinds]
    return {"point_sets": dict(mesh.node_sets), "cell_sets": cell_sets}


def _set_masks(mesh: Mesh, blocks: list[tuple[str, np.ndarray]]) -> dict[str, Any]:
    """Node and cell sets as 0/1 point_data / cell_data mask arrays, for the other formats."""
    point_data = {
        _NODE_MASK + name: _mask(ids, mesh.n_nodes) for name, ids in mesh.node_sets.items()
    }
    cell_data = {}
    for kind in CELL_KINDS:
        prefix = CELL_KINDS[kind].mask_prefix
        for name, ids in mesh.cell_sets(kind).items():
            cell_data[prefix + name] = [_mask(ids if k == kind else [], len(c)) for k, c in blocks]
    return {"point_data": point_data, "cell_data": cell_data}


def _kind_of_meshio() -> dict[str, str]:
    """meshio cell type -> cell kind."""
    return {spec.meshio_name: kind for kind, spec in CELL_KINDS.items()}


def _neither(items: Iterator[str] | Sequence[str]) -> str:
    """ "neither a nor b nor c" """
    return "neither " + " nor ".join(items)


def _article(noun: str) -> str:
    return ("an " if noun[:1] in "aeiou" else "a ") + noun


def _mask(ids: ArrayLike, size: int) -> np.ndarray:
    out = np.zeros(size, dtype=np.uint8)
    out[np.asarray(ids, dtype=np.int64)] = 1
    return out


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
    """Ids in the concatenated numbering of ``kind`` cells from per-block local cell ids (a
    block's local cell i is cell offset + i of its kind, the offset counting the cells of that
    kind in the blocks before it). Cell ids only: node ids never get an offset."""
    parts, offset = [], 0
    for block_kind, size, ids in zip(kinds, sizes, local_ids, strict=True):  # over blocks
        if block_kind == kind:
            if ids is not None:
                parts.append(np.asarray(ids, dtype=np.int64).reshape(-1) + offset)
            offset += size
    return np.concatenate(parts) if parts else np.zeros(0, dtype=np.int64)


def _merge_set(store: dict[str, np.ndarray], name: str, ids: np.ndarray) -> None:
    store[name] = sorted_unique(np.concatenate([store[name], ids])) if name in store else ids


def _clean_cell_sets(raw: meshio.Mesh, source: str) -> dict[str, list[np.ndarray]]:
    """meshio's cell sets as one int64 array of local cell ids per block (None: empty; an
    Abaqus *ELSET with no element, which meshio reads as no block at all: empty in each), the
    gmsh bookkeeping ("gmsh:bounding_entities") left out; ValueError for a set whose shape
    does not follow the blocks (a file meshio reads wrong: an Abaqus deck's sets are read by
    femcore.inp_sets instead)."""
    empty = np.zeros(0, dtype=np.int64)
    out = {}
    for name, per_block in raw.cell_sets.items():
        if name.startswith("gmsh:"):
            continue
        if len(per_block) == 0:  # meshio's empty *ELSET: a set of no cell, in every block
            out[name] = [empty] * len(raw.cells)
            continue
        try:
            ids = [empty if b is None else np.asarray(b, dtype=np.int64) for b in per_block]
        except (TypeError, ValueError):
            ids = []
        if len(ids) != len(raw.cells) or any(b.ndim != 1 for b in ids):
            raise ValueError(
                f"{source}: cell set {name!r} cannot be read (meshio does not list its cells "
                "block by block): list its elements"
            )
        out[name] = ids
    return out


def _split_quad_blocks(raw: meshio.Mesh, cell_sets: dict[str, list[np.ndarray]]) -> meshio.Mesh:
    """``raw`` with ``cell_sets`` for its cell sets and each "quad" block replaced by its
    triangles (``split_quads``): quad i of a block is triangles 2 i and 2 i + 1 of it, in its
    cell sets and cell data too."""
    if "quad" in CELL_KINDS or not any(block.type == "quad" for block in raw.cells):
        return meshio.Mesh(
            raw.points,
            raw.cells,
            point_data=raw.point_data,
            cell_data=raw.cell_data,
            field_data=raw.field_data,
            point_sets=raw.point_sets,
            cell_sets=cell_sets,
        )
    quad = [block.type == "quad" for block in raw.cells]
    cells = [
        meshio.CellBlock("triangle", split_quads(np.asarray(block.data))) if is_quad else block
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
        field_data=raw.field_data,
        point_sets=raw.point_sets,
        cell_sets={name: doubled(v, True) for name, v in cell_sets.items()},
    )


class _Blocks:
    """The cells of each kind gathered from meshio's blocks (node ids as they are), and the
    map from per-block local cell ids to ids among the cells of a kind.

    With ``merge_copies`` a cell repeated with the same nodes in the same order is kept once
    and its ids map to the kept copy: gmsh's MSH 2.2 writes an element once per physical group
    of its entity (one tag each), so a surface in two groups comes back twice.
    """

    def __init__(self, raw: meshio.Mesh, kinds: list[str], merge_copies: bool):
        self.kinds = kinds
        self.sizes = [len(block.data) for block in raw.cells]
        self.connectivity: dict[str, np.ndarray] = {}
        self._kept: dict[str, np.ndarray | None] = {}
        for kind, spec in CELL_KINDS.items():
            width = spec.nodes_per_cell
            parts = [
                np.asarray(block.data, dtype=np.int64).reshape(-1, width)
                for block, block_kind in zip(raw.cells, kinds)
                if block_kind == kind
            ]
            cells = np.concatenate(parts) if parts else np.zeros((0, width), dtype=np.int64)
            kept = None
            if merge_copies and len(cells) > 1:
                _, first, inverse = np.unique(cells, axis=0, return_index=True, return_inverse=True)
                if len(first) < len(cells):
                    # Keep the first copy of each cell, in the order of the file.
                    rank = np.empty(len(first), dtype=np.int64)
                    rank[np.argsort(first)] = np.arange(len(first))
                    kept = rank[np.ravel(inverse)]
                    cells = cells[np.sort(first)]
            self.connectivity[kind] = cells
            self._kept[kind] = kept

    def ids(self, local_ids: Sequence[ArrayLike | None], kind: str) -> np.ndarray:
        """Sorted unique ids among the cells of ``kind`` of per-block local cell ids."""
        ids = _kind_ids(local_ids, self.kinds, self.sizes, kind)
        kept = self._kept[kind]
        return sorted_unique(ids if kept is None else kept[ids])


def _mesh_from_meshio(raw: meshio.Mesh, source: str, fold_set_names: bool = False) -> Mesh:
    """The Mesh of a meshio mesh: every block of every kind in file order (quads split in two
    triangles), node ids those of meshio's points, and every named set (found by any spelling
    Abaqus takes with ``fold_set_names``, for a deck's)."""
    raw = _split_quad_blocks(raw, _clean_cell_sets(raw, source))
    # Block kinds in our vocabulary ("vertex" and unknown meshio types keep their name).
    kind_of = _kind_of_meshio()
    kinds = [kind_of.get(block.type, block.type) for block in raw.cells]
    unsupported = sorted({block.type for block in raw.cells} - set(kind_of) - {"vertex"})
    if unsupported:
        names = ", ".join(kind_of)
        raise ValueError(
            f"{source} contains {unsupported} cells; only {names} and vertex cells are supported"
        )
    if not set(kinds) & set(CELL_KINDS):
        raise ValueError(f"{source} contains {_neither(list(CELL_KINDS))} cells")
    from_gmsh = "gmsh:physical" in raw.cell_data or "gmsh:geometrical" in raw.cell_data
    groups = _physical_groups(raw, kinds) if from_gmsh else {}
    blocks = _Blocks(raw, kinds, merge_copies=from_gmsh)
    sets: dict[str, dict[str, np.ndarray]] = {"node": {}, **{kind: {} for kind in CELL_KINDS}}

    for name, ids in raw.point_sets.items():
        _merge_set(sets["node"], name, np.asarray(ids, dtype=np.int64))
    for name, per_block in raw.cell_sets.items():
        if name in groups:  # gmsh 4.1 physical groups, read below with their dimension
            continue
        found = {kind: blocks.ids(per_block, kind) for kind in CELL_KINDS}
        for kind, ids in found.items():
            # a set of another cell kind has no members here; a set of no cell at all (an
            # empty *ELSET) is kept, empty, for each kind the file has: named by a part, it
            # is refused as empty, not as unknown
            if ids.size or (not any(i.size for i in found.values()) and kind in kinds):
                _merge_set(sets[kind], name, ids)
    for name, data in raw.point_data.items():
        if name.startswith(_NODE_MASK):
            _merge_set(sets["node"], name[len(_NODE_MASK) :], np.flatnonzero(np.ravel(data)))
    for kind, spec in CELL_KINDS.items():
        prefix = spec.mask_prefix
        for name, per_block in raw.cell_data.items():
            if name.startswith(prefix):
                local = [np.flatnonzero(np.ravel(mask)) for mask in per_block]
                _merge_set(sets[kind], name[len(prefix) :], blocks.ids(local, kind))
    for name, (dim, local) in groups.items():
        _add_physical_group(raw, blocks, sets, name, dim, local)
    empty = [name for name, (_, local) in groups.items() if not any(ids.size for ids in local)]
    if empty:
        warnings.warn(
            f"{source}: the physical groups {empty} hold no element of the file, so their "
            "sets are empty (gmsh's Mesh.SaveAll writes MSH 2.2 elements without their "
            "groups)",
            UserWarning,
            stacklevel=4,
        )

    try:
        return Mesh(
            raw.points,
            node_sets=sets["node"],
            cells=blocks.connectivity,
            cell_sets={kind: sets[kind] for kind in CELL_KINDS},
            fold_set_names=fold_set_names,
        )
    except ValueError as error:  # a degenerate cell, a set name .inp cannot hold: the file
        raise ValueError(f"{source}: {error}") from None


def _check_physical_names(path: Path) -> None:
    """ValueError naming the file and the groups for two gmsh physical groups of one name
    (meshio keeps one of them, and its sets alone: a curve "plate" beside a surface "plate"
    lost its line set) or a name a set cannot take (, = " or a line break: .inp and .msh
    files could not hold it)."""
    rows: list[str] = []
    with open(path, "rb") as handle:  # the section is text in binary files too, near the top
        inside = False
        for raw_line in handle:
            line = raw_line.decode("utf-8", errors="replace").strip()
            if line == "$PhysicalNames":
                inside = True
            elif line == "$EndPhysicalNames" or (not inside and line in ("$Nodes", "$Entities")):
                break
            elif inside:
                rows.append(line)
    seen: dict[str, tuple[str, str]] = {}
    for row in rows[1:]:  # after the count
        dim, tag, quoted = (row.split(maxsplit=2) + ["", "", ""])[:3]
        name = quoted.strip().strip('"')
        if name in seen:
            raise ValueError(
                f"{path}: the physical groups {name!r} of dimension {seen[name][0]} (tag "
                f"{seen[name][1]}) and of dimension {dim} (tag {tag}) share a name, and the "
                "reader would keep the sets of one of them only: give them distinct names"
            )
        seen[name] = (dim, tag)
        if set(name) & set(',="'):
            raise ValueError(
                f"{path}: the physical group {name!r} (dimension {dim}, tag {tag}) has a name "
                'a set cannot take (no , = or ", which .inp and .msh files use): rename it'
            )


def _physical_groups(raw: meshio.Mesh, kinds: list[str]) -> dict[str, tuple[int, list]]:
    """Named gmsh physical groups: name -> (dimension, local cell ids per block).

    A physical tag is unique within a dimension only (a curve and a surface may both be
    group 1), so the tags of a group are looked for in the blocks of its dimension. MSH 4.1
    files give meshio a cell set per group (every group of every entity); MSH 2.2 files one
    physical tag per element (the element repeated for each further group).
    """
    dims = [0 if kind == "vertex" else CELL_KINDS[kind].dimension for kind in kinds]
    tags = raw.cell_data.get("gmsh:physical")
    empty = np.zeros(0, dtype=np.int64)
    groups = {}
    for name, value in raw.field_data.items():
        value = np.ravel(value)
        if value.size < 2:
            continue
        tag, dim = int(value[0]), int(value[1])
        if name in raw.cell_sets:
            local = [np.asarray(ids, dtype=np.int64) for ids in raw.cell_sets[name]]
        elif tags is not None and len(tags) == len(kinds):
            local = [
                np.flatnonzero(np.ravel(t) == tag) if d == dim else empty
                for t, d in zip(tags, dims)
            ]
        else:
            local = [empty] * len(kinds)
        groups[name] = (dim, local)
    return groups


def _add_physical_group(
    raw: meshio.Mesh,
    blocks: _Blocks,
    sets: dict[str, dict[str, np.ndarray]],
    name: str,
    dim: int,
    local: list[np.ndarray],
) -> None:
    """A physical group as a node set (the nodes of its cells, any dimension: a physical
    curve "clamp" holds the nodes of its lines) and as a set of the cells of the kinds of its
    dimension (1 -> line set, 2 -> element set)."""
    nodes = [np.asarray(block.data)[ids].reshape(-1) for block, ids in zip(raw.cells, local)]
    _merge_set(sets["node"], name, sorted_unique(np.concatenate(nodes)))
    if dim == 0:
        return
    # The group goes to the kinds of its dimension that have members in it (to the first
    # such kind if none has: an empty set, as for a group on cells of an unused kind).
    candidates = [kind for kind, spec in CELL_KINDS.items() if spec.dimension == dim]
    found = {kind: blocks.ids(local, kind) for kind in candidates}
    targets = [kind for kind in candidates if found[kind].size] or candidates[:1]
    for kind in targets:
        _merge_set(sets[kind], name, found[kind])
