"""The node and element sets of an Abaqus deck, read by Abaqus's keyword rules.

meshio 5.3 reads an .inp file's sets with rules of its own: ``*NSET, GENERATE`` only with
the increment written and on one data line, an *ELSET listed for the *ELEMENT blocks read
before it only, an element label the deck does not define dropped, a node label it does not
define a KeyError, ``*NODE, NSET=`` ignored, and the *INCLUDE files each read as a mesh of its
own (their element sets dropped, their node sets unable to name the main deck's nodes). Here
the deck is read with its included files in place (femcore.inp_include) and the sets as
Abaqus reads them (a data line of labels or set names; GENERATE lines of ``first, last[,
increment]``, increment 1 by default, as many as given; NSET= and ELSET= of *NODE and
*ELEMENT; a name defined again adds to its set, in whichever file), and a label or a set name
the deck does not define is refused naming the file, the line and the set. meshio then reads
the nodes and elements from one text without the *NSET and *ELSET blocks or *INCLUDE lines,
its node lines written out in Cartesian coordinates (femcore.inp_lines). A set name is read as
Abaqus reads a label ("Input syntax rules"): without quotes, in any case and without blanks,
so ``Tip`` and ``TIP`` are one set, kept under the spelling the deck first writes (a mesh
written and read back keeps its names; femcore.set_names finds it by any spelling). An *NSET
with ELSET holds the nodes of the elements of the element sets it lists.
"""

from __future__ import annotations

from bisect import bisect_right
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from femcore.inp_include import deck_lines
from femcore.inp_lines import (
    element_type_refusal,
    meshio_element_type,
    node_line,
    nodes_per_element,
    read_as_note,
)
from femcore.inp_scope import DeckScopes

__all__ = ["DeckSets", "resolve_deck_sets", "scan_deck_sets"]


@dataclass
class DeckSets:
    """The sets of a deck as written, and the deck without them for meshio. A line's place
    is (index in ``files``, line number there): ``where`` words it.

    Attributes
    ----------
    files : list[pathlib.Path]
        The main deck, then each file it includes, in reading order.
    mesh_text : str
        The deck with its included files in place, without its *NSET and *ELSET blocks and
        *INCLUDE lines, every *NODE block's lines gathered in the first (meshio 5.3 keeps the
        last *NODE block alone), for meshio to read nodes and elements.
    node_labels : dict[int, int]
        Node label -> index (the order of the *NODE blocks' lines in the deck, meshio's; a
        label given again is the later line's node, as the deck's reading gives it).
    node_block_labels : list[list[int]]
        Per *NODE block, the labels of its lines (its NSET= holds the nodes they name: a label
        given again in a later line is that line's node, the one the elements use).
    node_count : int
        The node lines of every *NODE block (meshio's points).
    element_numbers : list[list[int]]
        Per *ELEMENT block, the integers of its data lines (label, nodes, label, ...).
    element_lines : list[list[tuple[int, int, int]]]
        Per *ELEMENT block, (index of a data line's first integer, its line number, its file).
    sets : list[tuple[str, str, str, tuple[int, int], list[tuple[tuple[int, int], list[str]]]]]
        (NSET or ELSET, name, how its data lines read: "GENERATE", "ELSET" (an *NSET of the
        nodes of element sets) or "", keyword line's place, [(place, items)]) in deck order.
    block_sets : list[tuple[str, str, int]]
        NSET= of *NODE and ELSET= of *ELEMENT: (NSET or ELSET, name, *NODE or *ELEMENT
        block).
    element_types : list[tuple[str, int, tuple[int, int]]]
        Per *ELEMENT block, (TYPE= as written, nodes per element, keyword line's place).
    spellings : dict[str, str]
        A set name's key (upper case without blanks; a quoted name as written) -> the name
        as the deck first writes it, which the mesh's set takes.
    normals_at : list[tuple[int, int]]
        The places of node lines giving the direction cosines of a normal (not read).
    read_as : list[str]
        "deck.inp: line 8: TYPE=CPS3 (...) is read as S3, by its nodes", per *ELEMENT block
        of a type read as another (femcore.inp_lines.read_as_note).
    scopes : femcore.inp_scope.DeckScopes
        The part and assembly scopes: the assembly's own nodes and sets left out.
    """

    files: list[Path] = field(default_factory=list)
    mesh_text: str = ""
    node_labels: dict[int, int] = field(default_factory=dict)
    node_block_labels: list[list[int]] = field(default_factory=list)
    node_count: int = 0
    element_numbers: list[list[int]] = field(default_factory=list)
    element_lines: list[list[tuple[int, int, int]]] = field(default_factory=list)
    sets: list[tuple[str, str, str, tuple[int, int], list[tuple[tuple[int, int], list[str]]]]] = (
        field(default_factory=list)
    )
    block_sets: list[tuple[str, str, int]] = field(default_factory=list)
    element_types: list[tuple[str, int, tuple[int, int]]] = field(default_factory=list)
    spellings: dict[str, str] = field(default_factory=dict)
    normals_at: list[tuple[int, int]] = field(default_factory=list)
    read_as: list[str] = field(default_factory=list)
    scopes: DeckScopes = field(default_factory=DeckScopes)

    def where(self, place: tuple[int, int]) -> str:
        """ "deck.inp: line 12", the file and the line of a place."""
        return f"{self.files[place[0]]}: line {place[1]}"

    def name(self, written: str, where: str = "") -> str:
        """The set a name written in the deck means, as the deck first writes it: Abaqus
        reads a label without quotes in any case and without its blanks ("Input syntax
        rules"), so ``Tip``, ``TIP`` and ``t ip`` are one set, named ``Tip`` if that comes
        first; a quoted label is read as written (``where``, the file and line, for the
        message refusing a quoted and an unquoted set of one spelling)."""
        written = written.strip()
        if len(written) > 1 and written[0] == written[-1] == '"':
            key = shown = written[1:-1]
        else:
            shown = "".join(written.split())
            key = shown.upper()
        if key not in self.spellings and shown in self.spellings.values():
            raise ValueError(
                f"{where}: the deck names two sets {shown!r}, one quoted (read as written) and one "
                "not (read in any case): the mesh cannot hold both under that name; rename one"
            )
        return self.spellings.setdefault(key, shown)


def _parameters(line: str) -> tuple[str, dict[str, str]]:
    head, *items = line.split(",")
    keyword = " ".join(head[1:].split()).upper()
    found = {}
    for item in items:
        key, _, value = item.partition("=")
        if key.strip():
            found[key.strip().upper()] = value.strip()
    return keyword, found


def scan_deck_sets(path: Path, tool: bool = False) -> DeckSets:
    """The sets of the deck at ``path`` and of the files it includes, as written, and its text
    without them, for meshio (its node lines as ``label, x, y, z`` in Cartesian coordinates,
    femcore.inp_lines). ``tool``: the deck is a rigid tool's, whose rigid and surface facets
    are read (femcore.inp_lines.element_type_refusal).

    Raises
    ------
    ValueError
        An *INCLUDE that cannot be followed, or a file that is not text
        (femcore.inp_include.deck_lines); naming the file and the line: a *NODE line that is
        not ``label, x, y, z`` (blank or missing coordinates are 0), a SYSTEM= other than R
        or C, an element type the reader does not take (femcore.inp_lines), an *ELEMENT line
        that is not integers, an *ELEMENT block with no element or whose integers are not a
        whole number of elements.
    """
    deck = DeckSets()
    file_ids: dict[Path, int] = {}
    keep: list[str] = []
    node_lines: list[str] = []  # every *NODE block's, for the first block's place in ``keep``
    node_at = -1
    mode, system = "", "R"
    current, file_id = None, 0
    for file, number, line in deck_lines(path):
        if line.startswith("**"):
            continue
        if file is not current:  # the file's index, looked up where the file changes only
            current, file_id = file, file_ids.setdefault(file, len(file_ids))
        if line.startswith("*"):
            at = (file_id, number)
            mode, parameters = _parameters(line)
            deck.scopes.enter(mode)
            if mode in ("NODE", "NSET", "ELSET") and deck.scopes.assembly_own(
                mode, parameters, deck_where(file, number)
            ):
                mode = "LEFT OUT"  # its data lines with it (femcore.inp_scope)
                continue
            if mode in ("NSET", "ELSET"):
                name = deck.name(parameters.get(mode, ""), deck_where(file, number))
                deck.scopes.check_set(mode, name, name, deck_where(file, number))
                if mode == "NSET" and parameters.get("ELSET"):
                    raise ValueError(
                        f"{deck_where(file, number)}: *NSET, ELSET={parameters['ELSET']}: "
                        "Abaqus's ELSET parameter of *NSET takes no value; the element sets "
                        "whose nodes the set holds stand on the data lines (*NSET, NSET=name, "
                        "ELSET, then a line 'B')"
                    )
                how = "GENERATE" if "GENERATE" in parameters else ""
                how = "ELSET" if mode == "NSET" and "ELSET" in parameters else how
                deck.sets.append((mode, name, how, at, []))
                continue  # not for meshio
            if mode == "NODE":
                system = parameters.get("SYSTEM", "R").upper() or "R"
                if system not in ("R", "C"):
                    raise ValueError(
                        f"{deck_where(file, number)}: *NODE, SYSTEM={parameters['SYSTEM']}: "
                        "the reader takes SYSTEM=R (x, y, z) and SYSTEM=C (r, theta in "
                        "degrees, z); give the nodes in one of these"
                    )
                deck.node_block_labels.append([])
                if parameters.get("NSET"):
                    block = len(deck.node_block_labels) - 1
                    named = deck.name(parameters["NSET"], deck_where(file, number))
                    deck.block_sets.append(("NSET", named, block))
                if node_at >= 0:
                    continue  # its lines join the first block's
                node_at = len(keep)
                line = "*NODE"  # its lines are Cartesian by now (SYSTEM= read)
            if mode == "ELEMENT" and deck.scopes.scope == "assembly":
                raise ValueError(
                    f"{deck_where(file, number)}: *ELEMENT in the assembly, outside its "
                    "instance: its node labels are the assembly's own (femcore.inp_scope), "
                    "not the part's; give the elements in the part, or the tool in a file "
                    'of its own ([[contact]] tool = "surface", file = ...)'
                )
            if mode == "ELEMENT":
                _start_element_block(deck, parameters, file, number, at, tool)
                line = f"*ELEMENT, TYPE={meshio_element_type(deck.element_types[-1][1])}"
            keep.append(line)
            continue
        if mode == "LEFT OUT":
            continue
        if mode in ("NSET", "ELSET"):
            items = [item.strip() for item in line.split(",") if item.strip()]
            if items:
                deck.sets[-1][4].append(((file_id, number), items))
            continue
        if mode == "NODE":
            if line.strip():  # meshio's point index: the count of node lines before
                fields = line.split(",")
                try:  # the common line, 'label, x, y, z' in x, y, z: given to meshio as is
                    if len(fields) != 4 or system != "R":
                        raise ValueError
                    label = int(fields[0])
                    _ = float(fields[1]), float(fields[2]), float(fields[3])
                except ValueError:  # the rest (blanks, no z, SYSTEM=C, errors): written out
                    label, (x, y, z), extra = node_line(line, system, deck_where(file, number))
                    if extra:
                        deck.normals_at.append((file_id, number))
                    line = f"{label}, {x!r}, {y!r}, {z!r}"
                deck.node_labels[label] = len(node_lines)
                deck.node_block_labels[-1].append(label)
                node_lines.append(line)
            continue
        keep.append(line)
        if mode == "ELEMENT" and line.strip():
            numbers = deck.element_numbers[-1]
            before = len(numbers)
            try:
                numbers.extend(map(int, line.replace(",", " ").split()))
            except ValueError:
                raise ValueError(
                    f"{deck_where(file, number)}: *ELEMENT line {line.strip()!r}: expected "
                    "integers 'label, node, node, ...'"
                ) from None
            if len(numbers) > before:
                deck.element_lines[-1].append((before, number, file_id))
    deck.files = list(file_ids) or [path]
    _check_element_blocks(deck)
    deck.node_count = len(node_lines)
    keep[node_at + 1 : node_at + 1] = node_lines if node_at >= 0 else []
    deck.mesh_text = "\n".join(keep) + "\n"
    return deck


def deck_where(file: Path, number: int) -> str:
    """ "deck.inp: line 12", for messages."""
    return f"{file}: line {number}"


def _start_element_block(
    deck: DeckSets,
    parameters: dict[str, str],
    file: Path,
    number: int,
    at: tuple[int, int],
    tool: bool,
) -> None:
    """Open an *ELEMENT block: its type checked (femcore.inp_lines; a tool's file takes rigid
    facets), its ELSET= noted."""
    written = parameters.get("TYPE", "")
    refusal = element_type_refusal(written, tool)
    if refusal:
        raise ValueError(f"{deck_where(file, number)}: *ELEMENT: {refusal}")
    note = read_as_note(written)
    if note:
        deck.read_as.append(f"{deck_where(file, number)}: {note}")
    deck.element_types.append((written, nodes_per_element(written, tool), at))
    deck.element_numbers.append([])
    deck.element_lines.append([])
    if parameters.get("ELSET"):
        block = len(deck.element_numbers) - 1
        deck.block_sets.append(
            ("ELSET", deck.name(parameters["ELSET"], deck_where(file, number)), block)
        )


def _check_element_blocks(deck: DeckSets) -> None:
    """ValueError naming the block for an *ELEMENT block with no element, or whose integers
    are not a whole number of (label, nodes...) elements."""
    for numbers, (written, per_cell, at) in zip(
        deck.element_numbers, deck.element_types, strict=True
    ):
        what = f"{deck.where(at)}: *ELEMENT, TYPE={written}"
        if not numbers:
            raise ValueError(
                f"{what}: the block has no element line; give its elements (label, then "
                f"{per_cell} node labels per line) or remove the keyword line"
            )
        if len(numbers) % (per_cell + 1):
            raise ValueError(
                f"{what}: its lines hold {len(numbers)} integers, not a whole number of "
                f"elements of {per_cell + 1} (label, then {per_cell} node labels)"
            )
    nodes = _Labels(np.fromiter(deck.node_labels, dtype=np.int64, count=len(deck.node_labels)))
    for block, numbers in enumerate(deck.element_numbers):
        per_cell = deck.element_types[block][1]
        rows = np.array(numbers, dtype=np.int64).reshape(-1, per_cell + 1)
        unknown = np.flatnonzero(
            (nodes.find(rows[:, 1:].reshape(-1)) < 0).reshape(rows[:, 1:].shape).any(axis=1)
        )
        if unknown.size:
            row = rows[unknown[0]]
            missing = [label for label in row[1:].tolist() if label not in deck.node_labels]
            raise ValueError(
                f"{_element_place(deck, block, int(unknown[0]))}: element {row[0]} names node "
                f"{missing[0]}, which the deck does not define (no *NODE line of that label)"
            )


def _element_place(deck: DeckSets, block: int, row: int) -> str:
    """ "deck.inp: line 12", where element ``row`` of *ELEMENT block ``block`` starts."""
    starts = deck.element_lines[block]
    first = row * (deck.element_types[block][1] + 1)
    _, line, file = starts[bisect_right(starts, (first, 1 << 62, 0)) - 1]
    return deck.where((file, line))


def resolve_deck_sets(deck: DeckSets) -> tuple[dict[str, np.ndarray], dict[str, list[np.ndarray]]]:
    """The sets of ``deck`` in meshio's numbering: (name -> node indices, name -> one array
    of local element indices per *ELEMENT block); an *NSET with ELSET holds the nodes of the
    elements of the element sets it lists.

    Raises
    ------
    ValueError
        Naming the file, the line and the set (or the element): a GENERATE line that is not
        ``first, last[, increment]`` with first <= last and a positive increment, a label of
        a node or an element the deck does not define, a set name no set before it defines,
        an element that repeats a node (a collapsed quadrilateral).
    """
    per_block_labels: list[np.ndarray] = []
    element_nodes: list[np.ndarray] = []  # per block, (elements, nodes per element) labels
    blocks: list[np.ndarray] = []
    locals_: list[np.ndarray] = []
    sizes: list[int] = []
    for block, (numbers, per_cell) in enumerate(
        zip(deck.element_numbers, [per_cell for _, per_cell, _ in deck.element_types], strict=True)
    ):
        rows = np.array(numbers, dtype=np.int64).reshape(-1, per_cell + 1)
        sizes.append(len(rows))
        ordered = np.sort(rows[:, 1:], axis=1)
        repeats = np.flatnonzero((ordered[:, 1:] == ordered[:, :-1]).any(axis=1))
        if repeats.size:
            row = rows[repeats[0]]
            raise ValueError(
                f"{_element_place(deck, block, int(repeats[0]))}: element {row[0]} repeats "
                f"a node in {tuple(row[1:].tolist())} (a collapsed element): write it as the "
                "element it is (an S3 triangle for a quadrilateral with one side collapsed)"
            )
        per_block_labels.append(rows[:, 0])
        element_nodes.append(rows[:, 1:])
        blocks.append(np.full(len(rows), block, dtype=np.int64))
        locals_.append(np.arange(len(rows), dtype=np.int64))
    elements = _Labels(np.concatenate(per_block_labels or [np.zeros(0, np.int64)]))
    element_block = np.concatenate(blocks or [np.zeros(0, np.int64)])
    element_local = np.concatenate(locals_ or [np.zeros(0, np.int64)])
    nodes = _Labels(np.fromiter(deck.node_labels, dtype=np.int64, count=len(deck.node_labels)))
    node_index = np.fromiter(deck.node_labels.values(), np.int64, len(deck.node_labels))
    point_sets: dict[str, np.ndarray] = {}
    cell_sets: dict[str, list[np.ndarray]] = {}
    # A name defined more than once (ELSET= on several *ELEMENT blocks, *NSET or *ELSET
    # repeated) is one set holding every definition's members, as Abaqus and CalculiX read it.
    for kind, name, block in deck.block_sets:
        if kind == "NSET":
            # By label, not by line: a label the deck gives again later is the later line's
            # node (the one the elements use, as Abaqus and CalculiX read it), and the block's
            # own line of it an orphan point no set should hold.
            nodes_of_block = node_index[nodes.find(deck.node_block_labels[block])]
            point_sets[name] = np.union1d(point_sets.get(name, nodes_of_block), nodes_of_block)
        else:
            before = cell_sets.get(name, [np.zeros(0, dtype=np.int64)] * len(sizes))
            cell_sets[name] = [
                np.arange(size, dtype=np.int64) if index == block else before[index]
                for index, size in enumerate(sizes)
            ]
    for kind, name, how, at, data in deck.sets:
        what = f"{deck.where(at)}: *{kind} {name!r}"
        if not name:
            raise ValueError(f"{what}: no {kind}= name")
        labels: list[int] = []
        members: list[str] = []
        for place, items in data:
            if how == "GENERATE":
                labels.extend(_generated(items, f"{deck.where(place)}: *{kind} {name!r}"))
                continue
            for item in items:
                if item.lstrip("+-").isdigit() and how != "ELSET":
                    labels.append(int(item))
                else:
                    members.append(deck.name(item, deck.where(place)))
        store: dict = point_sets if kind == "NSET" and how != "ELSET" else cell_sets
        unknown = [member for member in members if member not in store]
        if unknown:
            sets_of = "element sets" if how == "ELSET" else "sets"
            raise ValueError(
                f"{what} joins the {sets_of} {unknown}, which the deck does not define before "
                f"it (known: {sorted(store)})"
            )
        if how == "ELSET":  # the nodes of the elements of the element sets listed
            ids = [point_sets.get(name, np.zeros(0, dtype=np.int64))]
            for member in members:
                for block, local in enumerate(cell_sets[member]):
                    labels_of = element_nodes[block][local].reshape(-1).tolist()
                    ids.append(node_index[nodes.find(labels_of)])
            point_sets[name] = np.unique(np.concatenate(ids))
        elif kind == "NSET":
            found = nodes.defined(labels, f"{what} names node", _line_of(deck, how, data))
            ids = [node_index[found]]
            ids += [point_sets[member] for member in [*members, name] if member in point_sets]
            point_sets[name] = np.unique(np.concatenate(ids))
        else:
            found = elements.defined(labels, f"{what} names element", _line_of(deck, how, data))
            cell_sets[name] = [
                np.unique(
                    np.concatenate(
                        [element_local[found][element_block[found] == block]]
                        + [
                            cell_sets[member][block]
                            for member in [*members, name]
                            if member in cell_sets
                        ]
                    )
                )
                for block in range(len(sizes))
            ]
    return point_sets, cell_sets


class _Labels:
    """Labels (Abaqus's node or element numbers) found by binary search."""

    def __init__(self, labels: np.ndarray) -> None:
        self.order = np.argsort(labels, kind="stable")
        self.sorted = labels[self.order]

    def find(self, wanted: list[int] | np.ndarray) -> np.ndarray:
        """The index of each wanted label in the labels given, -1 where it is not one."""
        query = np.asarray(wanted, dtype=np.int64)
        at = np.minimum(np.searchsorted(self.sorted, query), max(len(self.sorted) - 1, 0))
        if not len(self.sorted):
            return np.full(len(query), -1, dtype=np.int64)
        return np.where(self.sorted[at] == query, self.order[at], -1)

    def defined(
        self, wanted: list[int], names: str, line_of: Callable[[int], str] | None = None
    ) -> np.ndarray:
        """``find``, or ValueError "<names> <label> (and k more), which the deck does not
        define (on <line_of(label)>)" for the first wanted label that is not one."""
        found = self.find(wanted)
        missing = np.asarray(wanted, dtype=np.int64)[found < 0].tolist()
        if missing:
            more = f" (and {len(missing) - 1} more)" if len(missing) > 1 else ""
            on = f" (its data line: {line_of(missing[0])})" if line_of else ""
            raise ValueError(f"{names} {missing[0]}{more}, which the deck does not define{on}")
        return found


def _line_of(deck: DeckSets, how: str, data: list) -> Callable[[int], str]:
    """The place of the first data line of a set that lists (or generates) a label, for the
    message refusing a label the deck does not define: the line may stand in another file
    than the keyword's (INPUT=)."""

    def line_of(label: int) -> str:
        for place, items in data:
            if how == "GENERATE":
                listed = label in _generated(items, deck.where(place))
            else:
                listed = any(item.lstrip("+-").isdigit() and int(item) == label for item in items)
            if listed:
                return deck.where(place)
        return "?"

    return line_of


def _generated(items: list[str], where: str) -> list[int]:
    """The labels of a GENERATE data line ``first, last[, increment]`` (increment 1 when
    omitted, as Abaqus reads it)."""
    try:
        values = [int(item) for item in items]
    except ValueError:
        values = []
    if (
        len(values) not in (2, 3)
        or (len(values) == 3 and values[2] <= 0)
        or (values[0] > values[1])
    ):
        raise ValueError(
            f"{where}, GENERATE: expected 'first, last[, increment]' with first <= last and "
            f"a positive increment (1 when omitted), got {', '.join(items)!r}"
        )
    step = values[2] if len(values) == 3 else 1
    return list(range(values[0], values[1] + 1, step))
