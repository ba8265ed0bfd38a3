"""The text of an Abaqus deck Mesh.write writes, so that Abaqus, CalculiX and this reader read
the mesh back as it is.

meshio 5.3 writes node coordinates as ``%.16e`` (23 characters), which CalculiX (ccx 2.20)
refuses: it reads at most 20 characters per number (an F20.0 field) and stops at "*ERROR
reading *NODE". A coordinate is written here as the shortest decimal that reads back to the
same double (Python's repr), in a form that fits 20 characters: fixed or scientific notation,
a leading "0" and an exponent's "+" and leading zeros left out (".0123", "1.5e-5": Fortran's
F input and Python's float read both): every double between 0.01 and 1e17 in magnitude fits
(at most 19 characters, 20 below 0.1). Outside, a double may need 17 significant digits,
a sign, a point and an exponent, more than 20 characters, and then the closest decimal of
fewer digits that fits is written (14 to 16 digits: a relative change below 1e-13;
``node_block`` counts them for the writer's warning). meshio also writes a set name as is, and
Abaqus reads a name's blanks away unless it is quoted ("Input syntax rules"): a name with
blanks is written in double quotes (femcore.inp_sets reads a quoted name as written).
"""

from __future__ import annotations

import math
import re
from decimal import Decimal

import numpy as np

__all__ = ["FIELD_WIDTH", "node_block", "node_number", "quote_set_names"]

FIELD_WIDTH = 20
"""Characters CalculiX reads per number of a data line (ccx 2.20: an F20.0 field)."""


def _forms(text: str) -> list[str]:
    """The fixed and the scientific spelling of the decimal ``text``, without redundant
    characters (a leading 0 before the point, an exponent's + and leading zeros)."""
    sign, digits, exponent = Decimal(text).as_tuple()
    exponent = int(exponent)  # finite: a mesh's coordinates are (femcore.mesh_checks)
    minus = "-" if sign else ""
    body = "".join(map(str, digits)).rstrip("0") or "0"
    point = len(digits) + exponent  # digits before the decimal point
    if body == "0":
        return [minus + "0.0"]
    if point <= 0:
        fixed = "." + "0" * -point + body
    elif point >= len(body):
        fixed = body + "0" * (point - len(body)) + "."
    else:
        fixed = body[:point] + "." + body[point:]
    mantissa = body[0] + ("." + body[1:] if len(body) > 1 else "")
    return [minus + fixed, f"{minus}{mantissa}e{point - 1}"]


def node_number(value: float) -> tuple[str, bool]:
    """A coordinate as written in a *NODE line.

    Parameters
    ----------
    value : float
        A finite coordinate (length units).

    Returns
    -------
    text : str
        At most FIELD_WIDTH characters: the shortest decimal that reads back as ``value``
        (repr) when it fits, else the closest one of fewer digits that does.
    exact : bool
        Whether ``text`` reads back as ``value`` bit for bit.
    """
    shortest = repr(float(value))
    if len(shortest) <= FIELD_WIDTH:
        return shortest, True
    for digits in range(17, 0, -1):  # repr's digits first, then fewer (rounded)
        text = shortest if digits == 17 else f"{value:.{digits - 1}e}"
        fitting = [form for form in _forms(text) if len(form) <= FIELD_WIDTH]
        if not math.isfinite(float(text)):  # the largest doubles round up past the range
            continue
        if fitting:
            best = min(fitting, key=len)
            return best, float(best) == value
    raise AssertionError("a one-digit decimal always fits")  # pragma: no cover


def node_block(points: np.ndarray) -> tuple[str, int]:
    """The data lines of a *NODE block, ``label, x, y, z`` with labels from 1.

    Parameters
    ----------
    points : (n, 3) float ndarray
        Node coordinates (length units).

    Returns
    -------
    text : str
        n lines, each ending with a line break.
    inexact : int
        How many numbers are written a few units in the last place off (node_number).
    """
    lines = []
    inexact = 0
    for label, row in enumerate(np.asarray(points, dtype=float).tolist(), start=1):
        numbers = [node_number(value) for value in row]
        inexact += sum(not exact for _, exact in numbers)
        lines.append(f"{label}, " + ", ".join(text for text, _ in numbers) + "\n")
    return "".join(lines), inexact


_BLANK = re.compile(r"\s")
_SET_LINE = re.compile(r"^(\*(?:NSET, NSET|ELSET, ELSET)=)(.*)$", re.MULTILINE)


def quote_set_names(text: str) -> str:
    """``text`` with the name of each ``*NSET, NSET=`` / ``*ELSET, ELSET=`` line (as meshio
    writes them) in double quotes where it holds a blank, which Abaqus would read away."""
    return _SET_LINE.sub(
        lambda match: match[1] + (f'"{match[2]}"' if _BLANK.search(match[2]) else match[2]),
        text,
    )
