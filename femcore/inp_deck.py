"""A cheap scan of an Abaqus deck's keyword lines, beside the reading of its mesh.

meshio reads the nodes and the elements of an .inp file and skips every other keyword without
a word; a deck's *BOUNDARY, *MATERIAL, *SHELL SECTION or *STEP would vanish silently. The scan
looks only at the lines that start with one "*" (comments start with "**"), of the main deck
and of the files it includes (femcore.inp_include), so it costs one pass over the text, and
tells the reader which keywords it does not turn into the mesh and the *INSTANCE lines of an
assembly, each where it stands (the file and its line); a keyword that makes or moves nodes
or elements (GEOMETRY_KEYWORDS) is refused there, since ignoring it gives another mesh.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from femcore.inp_include import deck_lines, located

__all__ = ["GEOMETRY_KEYWORDS", "MESH_KEYWORDS", "DeckScan", "scan_deck"]

MESH_KEYWORDS = frozenset({"NODE", "ELEMENT", "NSET", "ELSET"})
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


# Keywords that make, copy or move nodes or elements (Abaqus Keywords Reference): a deck
# read without them is another mesh than the one Abaqus builds, so it is refused, not
# read with a warning.
GEOMETRY_KEYWORDS = frozenset(
    {
        "NGEN",  # nodes generated along a line or an arc between two nodes
        "NFILL",  # nodes filling the region between two node sets
        "NCOPY",  # nodes copied, moved, rotated or reflected
        "NMAP",  # nodes mapped from another coordinate system, scaled or moved
        "ELGEN",  # elements repeated along node-label increments
        "ELCOPY",  # elements copied onto other nodes
        "SYSTEM",  # a local system the nodes that follow are given in
        "IMPERFECTION",  # the nodes moved by a buckling mode or a list of displacements
    }
)


@dataclass
class DeckScan:
    """What the keyword lines of a deck say. A place is ``"line 12"`` in the main deck,
    ``"mesh.inp line 3"`` in a file it includes (femcore.inp_include.located).

    Attributes
    ----------
    ignored : dict[str, list[str]]
        Keyword (upper case, e.g. "SHELL SECTION") -> the places where a keyword the mesh
        reader does not use appears, in order of first appearance.
    instances : list[tuple[str, str, list[list[float]]]]
        The *INSTANCE lines of an assembly: (place, NAME=, the numbers of each data line
        before its *END INSTANCE: a translation, then a rotation). meshio reads a part's mesh
        once, at the part's own coordinates, whatever its instances say.
    """

    ignored: dict[str, list[str]] = field(default_factory=dict)
    instances: list[tuple[str, str, list[list[float]]]] = field(default_factory=list)

    def ignored_summary(self) -> str:
        """ "*BOUNDARY (line 12), *STEP (lines 20, 31), *MATERIAL (mat.inp line 2)", the
        ignored keywords as the deck writes them with where they are (at most three places
        each)."""
        parts = []
        for keyword, places in self.ignored.items():
            shown = places[:3]
            if all(place.startswith("line ") for place in shown) and len(places) > 1:
                shown = ["lines " + ", ".join(place[5:] for place in shown)]
            more = ", ..." if len(places) > 3 else ""
            parts.append(f"*{keyword} ({', '.join(shown)}{more})")
        return ", ".join(parts)


def scan_deck(path: str | Path) -> DeckScan:
    """Scan the keyword lines of an Abaqus deck and of the files it includes.

    Parameters
    ----------
    path : str or pathlib.Path
        The .inp file (UTF-8 text).

    Returns
    -------
    DeckScan

    Raises
    ------
    ValueError
        An *INCLUDE that cannot be followed, or a file that is not text
        (femcore.inp_include.deck_lines); a keyword that makes or moves nodes or elements
        (GEOMETRY_KEYWORDS), naming it and its place.
    """
    path = Path(path)
    scan = DeckScan()
    instance: list[list[float]] | None = None  # the data lines of the open *INSTANCE
    for file, number, line in deck_lines(path):
        if line.startswith("**"):
            continue
        if not line.startswith("*"):
            if instance is not None and line.strip():
                instance.append(_numbers(line))
            continue
        instance = None
        head, _, parameters = line.partition(",")
        keyword = " ".join(head[1:].split()).upper()
        if keyword == "INSTANCE":
            instance = []
            place = located(file, number, path)
            scan.instances.append((place, _parameter(parameters, "NAME") or "?", instance))
        elif keyword in GEOMETRY_KEYWORDS:
            raise ValueError(
                f"{path}: {located(file, number, path)}: *{keyword} makes or moves nodes or "
                "elements, and the .inp reader does not: the mesh read would not be the one "
                "Abaqus builds; write every node and element out (*NODE, *ELEMENT lines, as "
                "a pre-processor's 'write input' does)"
            )
        elif keyword not in MESH_KEYWORDS and keyword not in _NEUTRAL_KEYWORDS:
            scan.ignored.setdefault(keyword, []).append(located(file, number, path))
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
