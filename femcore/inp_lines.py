"""The data lines of an Abaqus deck's *NODE and *ELEMENT blocks, read as Abaqus reads them.

A node line is ``label, x, y, z`` where a coordinate left out or left blank is 0, as Abaqus
reads an empty or missing numeric field (Analysis User's Guide, "Input syntax rules"), given
in the block's
SYSTEM: R (rectangular, the default) or C (cylindrical: r, theta in degrees, z). Three more
numbers, the direction cosines of a normal, may follow; the reader computes its shells'
normals from their elements (docs/theory.md), so it notes them and leaves them. An element
type is read only where it is a shell or a truss/beam of the project's cells, or, in a rigid
tool's own file, a rigid or surface facet; any other (a membrane, a continuum, a second-order
element, a rigid facet in a body's deck) is refused, naming its type and line, not turned into
a shell triangle, but gmsh's plane-stress triangles and the coupled temperature shells, read
by their nodes with a note.
"""

from __future__ import annotations

import math

__all__ = [
    "ELEMENT_NODES",
    "TOOL_FACET_NODES",
    "element_type_refusal",
    "meshio_element_type",
    "node_line",
    "nodes_per_element",
    "read_as_note",
]

ELEMENT_NODES = {
    **dict.fromkeys(("S3", "S3R", "S3RS", "STRI3"), 3),  # shell triangles
    **dict.fromkeys(("S4", "S4R", "S4RS", "S4RSW", "S4R5"), 4),  # shell quadrilaterals
    **dict.fromkeys(("T3D2", "T3D2H", "T2D2", "T2D2H", "B31", "B31H", "B21", "B21H"), 2),
}
"""Element types the .inp reader reads (upper case) -> nodes per element: shells (a
quadrilateral becomes two triangles) and two-node trusses and beams (line cells)."""

TOOL_FACET_NODES = {
    **dict.fromkeys(("R3D3", "SFM3D3"), 3),
    **dict.fromkeys(("R3D4", "SFM3D4", "SFM3D4R"), 4),
}
"""Rigid and surface facets (upper case) -> nodes per element: what Abaqus meshes a rigid
tool with, read as the facets of a tool's file (elements.RigidSurface), refused in a body's
deck."""

# Types read as another with a note of what is left (upper case -> (read as, what it is)).
# gmsh writes every 2-D triangle of its .inp export as CPS3 (and quadrilateral as CPS4), with
# no option for another type: that file is a surface mesh, and a deck's section is never read
# (the case gives it), so its connectivity is read as the shell's; the note says so, for the
# rare deck that is a plane-stress model. A coupled temperature-displacement shell has the
# nodes of its mechanical twin; its temperature is not modelled here.
_READ_AS = {
    "CPS3": (
        "S3",
        "a plane-stress continuum triangle (gmsh's .inp export writes every 2-D triangle so)",
    ),
    "CPS4": (
        "S4",
        "a plane-stress continuum quadrilateral (gmsh's .inp export writes 2-D quadrilaterals so)",
    ),
    "S3T": ("S3", "a coupled temperature-displacement shell (its temperature is not modelled)"),
    "S3RT": ("S3R", "a coupled temperature-displacement shell (its temperature is not modelled)"),
    "S4T": ("S4", "a coupled temperature-displacement shell (its temperature is not modelled)"),
    "S4RT": ("S4R", "a coupled temperature-displacement shell (its temperature is not modelled)"),
}

_SECOND_ORDER = ("STRI65", "S8R", "S8R5", "S9R5", "S8RT", "M3D6", "M3D8", "M3D9", "CPS6", "CPS8")

_RIGID_IN_BODY = (
    "a rigid element: the body's deck holds the deformable shell only; give the tool in a "
    'file of its own, read as a rigid tool (a case\'s [[contact]] tool = "surface", file = '
    '"die.inp"; elements.RigidSurface("die.inp")), and leave its elements out of the body\'s '
    "deck"
)

# Prefixes of the element families refused, with what they are and what to do instead.
_REFUSED_FAMILIES = (
    (("R3D", "R2D", "RAX", "RB3D", "RB2D"), _RIGID_IN_BODY),
    (
        ("SFM", "SFCAX", "SFMAX", "SFMGAX"),
        "a surface element (no stiffness of its own); as a rigid tool's facets, give it in the "
        'tool\'s own file ([[contact]] tool = "surface", file = ...)',
    ),
    (("M3D", "MAX", "MGAX"), "a membrane element (no bending)"),
    (
        ("CPS", "CPE", "CPEG", "CAX", "CGAX"),
        "a plane or axisymmetric continuum element; for a surface mesh write TYPE=S3 (or S4), "
        "or read gmsh's .msh file instead of its .inp export",
    ),
    (("C3D", "SC6", "SC8", "CSS", "DC3D", "DCC3D"), "a continuum or continuum shell element"),
)


def _accepted(tool: bool) -> dict[str, int]:
    return {**ELEMENT_NODES, **TOOL_FACET_NODES} if tool else ELEMENT_NODES


def nodes_per_element(element_type: str, tool: bool = False) -> int:
    """Nodes per element of a type the reader takes (element_type_refusal gives None)."""
    upper = element_type.strip().upper()
    if upper in _READ_AS:
        upper = _READ_AS[upper][0]
    return _accepted(tool)[upper]


def meshio_element_type(nodes: int) -> str:
    """The type meshio 5.3 reads as the cell of ``nodes`` nodes the reader makes of it (a
    line, a triangle or a quadrilateral): the deck's own type may be one meshio does not
    know (R3D4, SFM3D3, S3T)."""
    return {2: "T3D2", 3: "S3", 4: "S4"}[nodes]


def read_as_note(element_type: str) -> str | None:
    """ "TYPE=CPS3 (a plane-stress ...) is read as S3", for a type read as another; else None."""
    upper = element_type.strip().upper()
    if upper not in _READ_AS:
        return None
    read_as, what = _READ_AS[upper]
    return f"TYPE={element_type.strip()} ({what}) is read as {read_as}, by its nodes"


def element_type_refusal(element_type: str, tool: bool = False) -> str | None:
    """Why ``element_type`` (as the deck writes it) is not read, None when it is.

    Parameters
    ----------
    element_type : str
        TYPE= of an *ELEMENT line.
    tool : bool
        True for a rigid tool's file (elements.RigidSurface), which takes rigid and surface
        facets (TOOL_FACET_NODES) besides the shells; False for a body's deck.

    Returns
    -------
    str or None
        "R3D4 is a rigid element: ..." for a refused type; None for a type read.
    """
    upper = element_type.strip().upper()
    if upper in _accepted(tool) or upper in _READ_AS:
        return None
    if not upper:
        return "no TYPE= (expected e.g. *ELEMENT, TYPE=S3)"
    accepted = ", ".join(_accepted(tool))
    if upper.startswith(_SECOND_ORDER):
        return (
            f"TYPE={element_type} is a second-order element (mid-side nodes), which the "
            "reader does not take: write the mesh with first-order elements (S3, S4)"
        )
    if upper == "R3D3":  # what meshio writes for every triangle, shells included
        return (
            f"TYPE={element_type} is {_RIGID_IN_BODY}; if they are the shell's own "
            "triangles (meshio, and Mesh.write before it wrote S3, write every triangle as "
            "R3D3), write TYPE=S3"
        )
    for prefixes, what in _REFUSED_FAMILIES:
        if upper.startswith(prefixes):
            return f"TYPE={element_type} is {what}; the reader takes {accepted}"
    return f"TYPE={element_type} is not a type the reader takes ({accepted})"


def node_line(line: str, system: str, where: str) -> tuple[int, tuple[float, float, float], int]:
    """The label and the Cartesian coordinates of a *NODE data line.

    Parameters
    ----------
    line : str
        ``label, x, y, z[, nx, ny, nz]`` (blank or missing coordinates are 0).
    system : str
        The block's SYSTEM=: "R" (x, y, z) or "C" (r, theta in degrees, z).
    where : str
        The file and line, for messages.

    Returns
    -------
    label : int
    coordinates : tuple of 3 float
        x, y, z (length units).
    extra : int
        How many numbers follow the coordinates (the direction cosines of a normal).

    Raises
    ------
    ValueError
        Naming ``where``: a label that is not an integer, a field that is not a number, more
        than 7 fields.
    """
    fields = [field.strip() for field in line.split(",")]
    while len(fields) > 1 and not fields[-1]:  # a trailing comma ends a line
        fields.pop()
    try:
        label = int(fields[0])
    except ValueError:
        raise ValueError(
            f"{where}: *NODE line {line.strip()!r}: the node label {fields[0]!r} is not an "
            "integer (expected 'label, x, y, z')"
        ) from None
    if len(fields) > 7:
        raise ValueError(
            f"{where}: *NODE line {line.strip()!r} has {len(fields)} fields; expected 'label, "
            "x, y, z' and at most the three direction cosines of a normal"
        )
    values = []
    for field in fields[1:]:
        try:
            values.append(float(field) if field else 0.0)
        except ValueError:
            raise ValueError(
                f"{where}: *NODE line {line.strip()!r}: {field!r} is not a number"
            ) from None
    first, second, third = (values[:3] + [0.0, 0.0, 0.0])[:3]
    if system == "C":  # r, theta (degrees), z: Abaqus Keywords Reference, *NODE, SYSTEM=C
        theta = math.radians(second)
        return label, (first * math.cos(theta), first * math.sin(theta), third), len(values[3:])
    return label, (first, second, third), len(values[3:])
