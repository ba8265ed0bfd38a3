"""A cheap scan of an Abaqus deck's keyword lines, beside meshio's reading of its mesh.

meshio reads the nodes, the elements and the sets of an .inp file and skips every other
keyword without a word; a deck's *BOUNDARY, *MATERIAL, *SHELL SECTION or *STEP would vanish
silently. The scan looks only at the lines that start with one "*" (comments start with
"**"), so it costs one pass over the text, and tells the reader which keywords it does not
turn into the mesh, the *ELEMENT blocks in file order with the element set each names, and
the sets made of other sets.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

__all__ = ["MESH_KEYWORDS", "DeckScan", "scan_deck"]

MESH_KEYWORDS = frozenset({"NODE", "ELEMENT", "NSET", "ELSET", "INCLUDE"})
"""Keywords the mesh reader turns into the mesh: nodes, elements, node and element sets."""

# Keywords that carry nothing a mesh reader could lose: titles, the frame of parts,
# assemblies and steps.
_NEUTRAL_KEYWORDS = frozenset(
    {
        "HEADING",
        "PREPRINT",
        "PART",
        "END PART",
        "ASSEMBLY",
        "END ASSEMBLY",
        "INSTANCE",  # one, unmoved: checked by femcore.mesh_io (DeckScan.instances)
        "END INSTANCE",
        "END STEP",  # its *STEP is listed
    }
)


@dataclass
class DeckScan:
    """What the keyword lines of a deck say.

    Attributes
    ----------
    ignored : dict[str, list[int]]
        Keyword (upper case, e.g. "SHELL SECTION") -> the line numbers (1-based) where a
        keyword the mesh reader does not use appears, in order of first appearance.
    element_sets : list[str | None]
        For each *ELEMENT block in file order, the ELSET= it names (None if none).
    node_blocks : int
        Number of *NODE blocks.
    includes : int
        Number of *INCLUDE lines (their files are not scanned).
    set_unions : list[tuple[str, str, list[str]]]
        The *NSET and *ELSET made of other sets, in file order: ("NSET" or "ELSET", the
        set's name, the names of the sets it joins). meshio 5.3 reads only the first name
        of each line of such a set, and leaves an *NSET of sets empty.
    instances : list[tuple[int, str, list[list[float]]]]
        The *INSTANCE lines of an assembly: (line number, NAME=, the numbers of each data
        line before its *END INSTANCE: a translation, then a rotation). meshio reads a part's
        mesh once, at the part's own coordinates, whatever its instances say.
    """

    ignored: dict[str, list[int]] = field(default_factory=dict)
    element_sets: list[str | None] = field(default_factory=list)
    node_blocks: int = 0
    includes: int = 0
    set_unions: list[tuple[str, str, list[str]]] = field(default_factory=list)
    instances: list[tuple[int, str, list[list[float]]]] = field(default_factory=list)

    def ignored_summary(self) -> str:
        """ "*BOUNDARY (line 12), *STEP (lines 20, 31)", the ignored keywords as the deck
        writes them with where they are (at most three lines each)."""
        parts = []
        for keyword, lines in self.ignored.items():
            shown = ", ".join(str(n) for n in lines[:3]) + (", ..." if len(lines) > 3 else "")
            parts.append(f"*{keyword} (line{'s' if len(lines) > 1 else ''} {shown})")
        return ", ".join(parts)


def scan_deck(path: str | Path) -> DeckScan:
    """Scan the keyword lines of an Abaqus deck.

    Parameters
    ----------
    path : str or pathlib.Path
        The .inp file (text; undecodable bytes are replaced, meshio reports them).

    Returns
    -------
    DeckScan
    """
    scan = DeckScan()
    current_set: tuple[str, str, list[str]] | None = None  # the set whose lines follow
    instance: list[list[float]] | None = None  # the data lines of the open *INSTANCE
    with open(path, encoding="utf-8", errors="replace") as deck:
        for number, line in enumerate(deck, start=1):
            if line.startswith("**"):
                continue
            if not line.startswith("*"):
                if instance is not None and line.strip():
                    instance.append(_numbers(line))
                if current_set is None:  # a node's or an element's line: nothing to note
                    continue
                names = [item.strip() for item in line.split(",") if item.strip()]
                if names and not names[0][0].isdigit():
                    current_set[2].extend(names)
                continue
            if current_set is not None and current_set[2]:
                scan.set_unions.append(current_set)
            current_set = None
            instance = None
            head, _, parameters = line.partition(",")
            keyword = " ".join(head[1:].split()).upper()
            if keyword in ("NSET", "ELSET"):
                name = _parameter(parameters, keyword)
                if name is not None:
                    current_set = (keyword, name, [])
            elif keyword == "ELEMENT":
                scan.element_sets.append(_parameter(parameters, "ELSET"))
            elif keyword == "INSTANCE":
                instance = []
                scan.instances.append((number, _parameter(parameters, "NAME") or "?", instance))
            elif keyword == "NODE":
                scan.node_blocks += 1
            elif keyword == "INCLUDE":
                scan.includes += 1
            elif keyword not in MESH_KEYWORDS and keyword not in _NEUTRAL_KEYWORDS:
                scan.ignored.setdefault(keyword, []).append(number)
    if current_set is not None and current_set[2]:
        scan.set_unions.append(current_set)
    return scan


def _parameter(parameters: str, name: str) -> str | None:
    """The value of ``name=value`` among a keyword line's comma-separated parameters."""
    for item in parameters.split(","):
        key, equals, value = item.partition("=")
        if equals and key.strip().upper() == name:
            return value.strip()
    return None


def _numbers(line: str) -> list[float]:
    """The numbers of a data line (a word that is not one reads as NaN: not a zero move)."""
    values = []
    for item in line.split(","):
        if item.strip():
            try:
                values.append(float(item))
            except ValueError:
                values.append(float("nan"))
    return values
