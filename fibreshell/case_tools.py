"""A ``[[contact]]`` table's tool (fibreshell/case.py ``_contact`` reads the rest of the
table, the contact's own options): its kind, its geometry keys, a driven tool's free axes and
force, its motion, each checked as every key of a case file is (a ``CaseError`` naming the
file, the table and the key), then the ``elements`` tool built from them."""

from __future__ import annotations

import inspect
from pathlib import Path
from typing import Any

from elements import RigidAnnulus, RigidCylinder, RigidPlane, RigidSphere, RigidSurface
from fibreshell.case_reading import _amplitude, _number, _table, _vector, _Where

__all__ = ["CONTACT_KEYS", "DRIVE_KEYS", "TOOLS", "TOOL_KEYS", "read_tool"]

TOOLS = {"plane": RigidPlane, "annulus": RigidAnnulus, "sphere": RigidSphere,
         "cylinder": RigidCylinder, "surface": RigidSurface}  # fmt: skip
#: The geometry keys of each tool (its constructor's arguments, the mesh file for a surface;
#: ``smooth``: a meshed tool's normal interpolated over each facet's patch, continuous across
#: its edges, the remedy a Static stop in a crease gives, docs/theory.md §9.3).
TOOL_KEYS = {
    "plane": ("point", "normal"),
    "annulus": ("point", "normal", "inner"),
    "sphere": ("centre", "radius", "side"),
    "cylinder": ("point", "axis", "radius", "side"),
    "surface": ("file", "flip", "smooth", "search_distance"),
}
#: The contact's own keys (``Model.contact``'s options) and the tool's motion.
CONTACT_KEYS: tuple[str, ...] = ("tool", "nodes", "friction", "penalty", "stick_stiffness")
CONTACT_KEYS += ("augmented", "augmented_tolerance", "damping", "motion", "amplitude")
#: A tool driven by a force along its free axes (a blank holder): elements.tools.RigidTool.
DRIVE_KEYS = ("free", "force", "mass", "pressure")
_VECTORS = ("point", "normal", "centre", "axis", "motion", "force")
_NUMBERS = ("radius", "search_distance", "inner")
_FLAGS = ("flip", "smooth")


def read_tool(where: _Where, value: Any, folder: Path) -> Any:
    """The rigid tool of the ``[[contact]]`` table ``value`` (a dict), at ``where``; a
    ``"surface"`` tool's ``file`` relative to ``folder``. Every key of the table is checked
    against the contact's, the drive's and the tool kind's."""
    kind = value.get("tool") if isinstance(value, dict) else None
    if kind not in TOOLS:
        raise where.error("tool", f"expected one of {', '.join(TOOLS)}, got {kind!r}")
    _table(where, value, "", CONTACT_KEYS + DRIVE_KEYS + TOOL_KEYS[kind], ("tool",))
    options: dict[str, Any] = {}
    if "free" in value:
        free = value["free"]
        if isinstance(free, str):
            free = [free]
        if not isinstance(free, list) or not all(isinstance(a, str) for a in free):
            raise where.error("free", f'expected axis names such as ["z"], got {free!r}')
        options["free"] = tuple(free)
    for key in ("mass", "pressure"):
        if key in value:
            options[key] = _number(where, value[key], key)
    if "pressure" in value and kind != "surface":
        raise where.error(
            "pressure",
            'a pressure needs a meshed tool (tool = "surface"), whose facets have an area; '
            "an analytic tool has none: give force = [...]",
        )
    for key in TOOL_KEYS[kind] + ("motion", "force"):
        if key not in value:
            continue
        item = value[key]
        if key in _VECTORS:
            options[key] = _vector(where, item, key)
        elif key in _NUMBERS:
            options[key] = _number(where, item, key)
        elif key == "file":
            if not isinstance(item, str):
                raise where.error(key, f"expected a path string, got {item!r}")
            options["mesh"] = str(folder / item)
        elif key in _FLAGS:
            if not isinstance(item, bool):
                raise where.error(key, f"expected true or false, got {item!r}")
            options[key] = item
        else:  # side
            options[key] = item
    if "amplitude" in value:
        options["amplitude"] = _amplitude(where, value["amplitude"])
    # a key the tool cannot do without, named as the case file writes it (before the class's
    # own "missing 1 required positional argument")
    missing = [
        "file" if name == "mesh" else name
        for name, parameter in inspect.signature(TOOLS[kind]).parameters.items()
        if parameter.default is inspect.Parameter.empty
        and parameter.kind is not inspect.Parameter.VAR_KEYWORD
        and parameter.kind is not inspect.Parameter.VAR_POSITIONAL
        and name not in options
    ]
    if missing:
        raise where.error(missing[0], f'tool = "{kind}" needs {", ".join(missing)}: not given')
    try:
        return TOOLS[kind](**options)
    except (TypeError, ValueError) as error:
        text = str(error)
        key = next((k for k in DRIVE_KEYS + ("motion",) if text.startswith(k)), "tool")
        raise where.error(key, text) from None
