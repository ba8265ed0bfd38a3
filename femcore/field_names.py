"""The names of the components of output fields, which the VTU files carry.

A field with several components per node or cell (a vector, the three section forces, one
value per fibre level) is written with a name for each component, so that ParaView lists
"membrane_force 11" or "warp_strain top" instead of 0, 1, 2. The element types declare the
names of their own fields here when they are imported (:func:`name_components`); femcore
declares those of the fields every result holds (displacement, velocity, reaction, director,
reaction_moment). A field nobody declared is written without component names.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from typing import Any

__all__ = ["LEVELS", "component_names", "level_names", "name_components", "parts_fields"]

# Component names by level, bottom to top: the count is the element's, known only when written.
LEVELS = "levels"

_XYZ = ("x", "y", "z")
_declared: dict[str, tuple[str, ...] | str] = {
    name: _XYZ for name in ("displacement", "velocity", "reaction", "director", "reaction_moment")
}


def name_components(field: str, components: Sequence[str] | str) -> None:
    """Declare the component names of output field ``field``.

    Parameters
    ----------
    field : str
        The field's name, as the element's ``node_fields`` or ``cell_fields`` give it.
    components : sequence of str, or ``LEVELS``
        One name per component, in order (e.g. ``("11", "22", "12")``), or ``LEVELS``: one
        value per fibre level through the thickness, named by :func:`level_names`.

    Raises
    ------
    ValueError
        An empty or non-string name, or a field already declared with other components (two
        element types that write a field of one name must agree on what it holds).
    """
    if not isinstance(field, str) or not field:
        raise ValueError(f"field must be a non-empty string, got {field!r}")
    if isinstance(components, str):
        if components != LEVELS:
            raise ValueError(
                f"components of {field!r} must be a sequence of names or LEVELS, got {components!r}"
            )
        wanted: tuple[str, ...] | str = LEVELS
    else:
        wanted = tuple(components)
        if not wanted or not all(isinstance(c, str) and c for c in wanted):
            raise ValueError(
                f"components of {field!r} must be non-empty strings, got {components!r}"
            )
    before = _declared.get(field)
    if before is not None and before != wanted:
        raise ValueError(
            f"field {field!r} is already declared with components {before!r}, not {wanted!r}: "
            "every element type that writes a field of this name must give it the same "
            "components"
        )
    _declared[field] = wanted


def level_names(count: int) -> tuple[str, ...]:
    """Names of ``count`` fibre levels from the bottom (the director's tail) to the top:
    ``("middle",)``, ``("bottom", "top")``, ``("bottom", "middle", "top")``, and for more
    ``("bottom", "level_2", ..., "level_<count - 1>", "top")``."""
    if count == 1:
        return ("middle",)
    if count == 3:
        return ("bottom", "middle", "top")
    return ("bottom", *(f"level_{k}" for k in range(2, count)), "top")


def component_names(field: str, count: int) -> tuple[str, ...] | None:
    """The names of the ``count`` components of output field ``field``, or None when the
    field was not declared or was declared with another number of components. A second
    field of a name (``contact_gap_2``: two parts write ``contact_gap`` on shared nodes) has
    the components of the first."""
    declared = _declared.get(field)
    if declared is None:
        declared = _declared.get(re.sub(r"_\d+$", "", field))
    if declared is None:
        return None
    names = level_names(count) if declared == LEVELS else declared
    return tuple(names) if len(names) == count else None


def parts_fields(fields: Mapping[str, Any], name: str) -> list[Any]:
    """The fields ``name``, ``name_2``, ``name_3``, ... of ``fields`` (a frame's point or cell
    fields), one per part that writes ``name`` (femcore.compiled names a field of a name
    written again by a later part so), in the parts' order; [] when no part writes it."""
    found = [fields[name]] if name in fields else []
    while found and f"{name}_{len(found) + 1}" in fields:
        found.append(fields[f"{name}_{len(found) + 1}"])
    return found
