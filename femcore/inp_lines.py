"""The data lines of an Abaqus deck's *NODE and *ELEMENT blocks, read as Abaqus reads them.

A node line is ``label, x, y, z`` where a coordinate left out or left blank is 0, as Abaqus
reads an empty or missing numeric field (Analysis User's Guide, "Input syntax rules"), given
in the block's
SYSTEM: R (rectangular, the default) or C (cylindrical: r, theta in degrees, z). Three more
numbers, the direction cosines of a normal, may follow; the reader computes its shells'
normals from their elements (docs/theory.md), so it notes them and leaves them. An element
type is read only where it is a shell or a truss/beam of the project's cells; a rigid,
surface, membrane or continuum element is refused, naming its type and line, not turned into
a shell triangle.
"""

from __future__ import annotations

import math

__all__ = ["ELEMENT_NODES", "element_type_refusal", "node_line"]

ELEMENT_NODES = {
    **dict.fromkeys(("S3", "S3R", "S3RS", "STRI3"), 3),  # shell triangles
    **dict.fromkeys(("S4", "S4R", "S4RS", "S4RSW", "S4R5"), 4),  # shell quadrilaterals
    **dict.fromkeys(("T3D2", "T3D2H", "T2D2", "T2D2H", "B31", "B31H", "B21", "B21H"), 2),
}
"""Element types the .inp reader reads (upper case) -> nodes per element: shells (a
quadrilateral becomes two triangles) and two-node trusses and beams (line cells)."""

# Prefixes of the element families refused, with what they are and what to do instead.
_REFUSED_FAMILIES = (
    (
        ("R3D", "R2D", "RAX", "RB3D", "RB2D"),
        "a rigid element: the .inp reader reads the deformable body only; give the tool as "
        "a separate surface file (a [[tool]] of the case, elements.RigidSurface) and leave "
        "its elements out of the body's deck",
    ),
    (("SFM", "SFCAX", "SFMAX", "SFMGAX"), "a surface element (no stiffness of its own)"),
    (("M3D", "MAX", "MGAX"), "a membrane element (no bending)"),
    (("CPS", "CPE", "CPEG", "CAX", "CGAX"), "a plane or axisymmetric continuum element"),
    (("C3D", "SC6", "SC8", "CSS", "DC3D", "DCC3D"), "a continuum or continuum shell element"),
)


def element_type_refusal(element_type: str) -> str | None:
    """Why ``element_type`` (as the deck writes it) is not read, None when it is.

    Returns
    -------
    str or None
        "R3D4 is a rigid element: ..." for a refused type; None for a key of ELEMENT_NODES.
    """
    upper = element_type.strip().upper()
    if upper in ELEMENT_NODES:
        return None
    if not upper:
        return "no TYPE= (expected e.g. *ELEMENT, TYPE=S3)"
    accepted = ", ".join(ELEMENT_NODES)
    if upper == "R3D3":  # what meshio writes for every triangle, shells included
        return (
            f"TYPE={element_type} is {_REFUSED_FAMILIES[0][1]}; if they are the shell's own "
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
