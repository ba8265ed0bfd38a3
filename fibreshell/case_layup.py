"""A case file's ``[layup]``: the part's fabric laid as plies at angles, each ply its own
mesh along its own fibres and its own shell, neighbours in contact with Coulomb friction
(elements.layup.Layup, docs/theory.md §9.3b); README "Case files", "A layup of plies".

```toml
[mesh]
rectangle = { lx = 40.0, ly = 40.0, nx = 4, ny = 4, origin = [-20.0, -20.0, 0.15] }
[[part]]                          # the plies' fabric, and their shell
element = "fibrous"
material = { thickness = 0.3, ... }
[layup]
angles = [0.0, 90.0]              # deg, each ply's warp from +x about +z, bottom ply first
friction = 0.2                    # ply on ply Coulomb coefficient (0)
# kinematics = "mindlin"          # the plies' shell (default: the part's element);
#                                 # "mindlin-elastic": the equivalent elastic section
# penalty, rule, smoothing, faces, surface, lower_rule: of every elements.PlyContact
```

The rectangle is the blank: its outline, and the bottom ply's mid-surface at the origin's
height (the plies above it one fabric thickness apart, their faces touching). Each ply is
``femcore.blank.ply_blank(lx, ly, nx, angle)``: square fibre cells of lx / nx, so ny must be
nx ly / lx rounded (the 0-degree ply's mesh is then the rectangle's). The case's mesh is the
layup's, every ply's nodes in one mesh: a node-set name ("left", ...) or a bounds table names
the nodes of every ply there, "ply_k" (1 = bottom) and "ply_k_left" ... one ply's. The ply's
shell is the part's element with the part's options and the ply's warp ("fibrous":
``FibrousShell(fabric, warp=w_k)``; "mindlin": ``MindlinShell(fabric, warp=w_k)``, the
fabric's own laws, as a Mindlin part of that fabric is built; "mindlin-elastic":
``MindlinShell(ElasticShell.equivalent(fabric, warp=w_k))``, the section of the laws'
initial slopes), each ``elements.layup.ply_element`` as a Python ``Layup`` builds it.
"""

from __future__ import annotations

import copy
import re
from dataclasses import dataclass, field
from typing import Any

from elements import FibrousShell, MindlinShell
from elements.layup import Layup, ply_element
from elements.ply_contact import RULES
from femcore.element import ElementType
from fibreshell.case_reading import _number, _table, _Where
from materials import Fabric

__all__ = ["LAYUP_KEYS", "Calibrated", "PlyShell", "layup_for", "read_layup"]

LAYUP_KEYS = ("angles", "kinematics", "friction", "penalty", "rule", "smoothing", "faces",
              "surface", "lower_rule")  # fmt: skip
PLY_SHELLS: dict[str, type] = {"fibrous": FibrousShell, "mindlin": MindlinShell}
# [layup] kinematics -> the part's element it may be given with options of (the same class)
PLY_KINDS = {"fibrous": "fibrous", "mindlin": "mindlin", "mindlin-elastic": "mindlin"}


@dataclass(frozen=True)
class PlyShell:
    """A ply's shell from (fabric, warp): ``elements.layup.ply_element(kind, fabric, warp,
    **options)``, as a Python ``Layup`` of that kinematics builds it (a class, not a closure:
    a case's layup is pickled with the case by the sweep's workers)."""

    kind: str
    options: dict = field(default_factory=dict)

    def __call__(self, fabric: Fabric, warp: Any) -> ElementType:
        return ply_element(self.kind, fabric, warp, **self.options)


@dataclass(frozen=True)
class Calibrated:
    """A fibrous ply's Mindlin shell by a calibration (``fibreshell.calibration``):
    ``rule.mindlin(FibrousShell(fabric, warp=warp))``, the same warp."""

    rule: Any

    def __call__(self, fabric: Fabric, warp: Any) -> ElementType:
        return self.rule.mindlin(FibrousShell(fabric, warp=warp))


def read_layup(top: _Where, data: dict, parts: list[dict]) -> Layup:
    """The ``[layup]`` of a case file's tables ``data``, its plies of the one part of
    ``parts`` (``fibreshell.case._part``'s records) on the ``[mesh]`` rectangle.

    Raises
    ------
    CaseError (a ValueError)
        An unknown key, a value of the wrong kind, not one fibrous or Mindlin part of a fabric,
        a part on a cell set or with its own warp, a mesh that is not a rectangle or whose ny
        is not nx ly / lx rounded, a Layup option Layup refuses: naming the file, the table
        and the key.
    """
    value = _table(top, data["layup"], "layup", LAYUP_KEYS, ("angles",))
    where = top.child("layup")
    if len(parts) != 1:
        raise where.error(
            None, f"a layup's plies are the one [[part]]'s fabric and shell; this case has "
            f"{len(parts)} parts",
        )  # fmt: skip
    part, at_part = parts[0], top.child("part[0]")
    if part["kind"] not in PLY_SHELLS or type(part["element"]) is not PLY_SHELLS[part["kind"]]:
        raise at_part.error(
            "element", f"a layup's plies are {' or '.join(PLY_SHELLS)} shells, got "
            f"{part['kind']!r}",
        )  # fmt: skip
    if part["cells"] is not None:
        raise at_part.error("cells", "a layup's plies cover every cell: give no cell set")
    element = part["element"]
    fabric = getattr(element, "fabric", None) or getattr(element, "material", None)
    if not isinstance(fabric, Fabric):
        raise at_part.error(
            "material", f"a layup's plies are a fabric (Fabric fields or a fabric preset), "
            f"got {type(fabric).__name__}",
        )  # fmt: skip
    options = dict(part["options"])
    if "warp" in options:
        raise at_part.child("options").error(
            "warp", "a layup gives each ply its warp ([layup] angles): give no warp"
        )
    kinematics = value.get("kinematics", part["kind"])
    if not isinstance(kinematics, str) or kinematics not in PLY_KINDS:
        raise where.error(
            "kinematics", f"expected one of {', '.join(PLY_KINDS)}, got {kinematics!r}"
        )
    if PLY_KINDS[kinematics] != part["kind"] and options:
        raise where.error(
            "kinematics", f"the part's options {sorted(options)} are those of its element "
            f"{part['kind']!r}, not of {kinematics!r}: write element = "
            f"{PLY_KINDS[kinematics]!r} in the part with its own options, or leave kinematics out",
        )  # fmt: skip
    lx, ly, nx, origin = _rectangle(top, data["mesh"])
    friction = _number(where, value.get("friction", 0.0), "friction")
    if friction < 0:
        raise where.error("friction", f"expected a Coulomb coefficient >= 0, got {friction!r}")
    if "penalty" in value and not _number(where, value["penalty"], "penalty") > 0:
        raise where.error("penalty", f"expected a positive number (N/mm), got {value['penalty']!r}")
    if "smoothing" in value:
        _number(where, value["smoothing"], "smoothing")
    for key in ("rule", "faces", "surface", "lower_rule"):
        if key in value and not isinstance(value[key], str):
            raise where.error(key, f"expected a name, got {value[key]!r}")
    if value.get("lower_rule", "centroid") not in RULES:  # Layup's message names "rule" alone
        raise where.error(
            "lower_rule", f"expected one of {', '.join(RULES)}, got {value['lower_rule']!r}"
        )
    angles = value["angles"]
    if not isinstance(angles, list) or not angles:
        raise where.error("angles", f"expected a list of ply angles in degrees, got {angles!r}")
    for angle in angles:
        _number(where, angle, "angles")
    h = fabric.thickness
    options_given = {k: value[k] for k in ("penalty", "rule", "smoothing", "surface") if k in value}
    try:
        return Layup(
            fabric,
            angles,
            lx,
            ly,
            cells=nx,
            kinematics=PlyShell(kinematics, options),
            friction=friction,
            bottom=origin[2] - 0.5 * h,
            centre=(origin[0] + 0.5 * lx, origin[1] + 0.5 * ly),
            faces=value.get("faces", "normal" if kinematics == "fibrous" else "director"),
            lower_rule=value.get("lower_rule"),
            **options_given,
        )
    except ValueError as error:
        text = str(error)
        raise where.error(_named(text, value), text) from None


def _rectangle(top: _Where, mesh: dict) -> tuple[float, float, int, tuple[float, ...]]:
    """lx, ly, nx and origin of the ``[mesh]`` rectangle (read and checked by
    ``fibreshell.case._mesh``), its ny that of the plies' square fibre cells."""
    if "rectangle" not in mesh:
        raise top.error(
            "mesh", "a layup meshes each ply along its own fibres over a rectangular blank: "
            "give [mesh] rectangle = { lx, ly, nx, ny, origin }",
        )  # fmt: skip
    rect = mesh["rectangle"]
    lx, ly, nx, ny = float(rect["lx"]), float(rect["ly"]), int(rect["nx"]), int(rect["ny"])
    cells = max(1, round(nx * ly / lx))
    if ny != cells:
        raise top.child("mesh.rectangle").error(
            "ny", f"a layup's plies are square fibre cells of lx / nx = {lx / nx:.6g}: ny must "
            f"be nx ly / lx rounded, {cells}, got {ny}",
        )  # fmt: skip
    origin = tuple(float(v) for v in rect.get("origin", (0.0, 0.0, 0.0)))
    return lx, ly, nx, origin


def _named(message: str, value: dict) -> str | None:
    """The ``[layup]`` key a Layup message is about (the first it names), None if none."""
    found = [(m.start(), key) for key in value
             if (m := re.search(rf"(?<![\w.]){re.escape(key)}(?!\w)", message))]  # fmt: skip
    if not found and "angle" in message:
        return "angles"
    return min(found)[1] if found else None


def layup_for(layup: Layup, kinematics: str | None, rule: Any) -> Layup:
    """``layup`` with its plies in ``kinematics``: "mindlin" turns fibrous plies into the
    Mindlin shells of calibration ``rule`` (``Calibrated``), as ``Case.model`` turns a
    fibrous part; None, "fibrous", or plies already Mindlin: ``layup`` as written. The
    plies' contact faces stay where the case put them (``faces``: along the nodal normals
    for fibrous plies by default), so that only the shells differ."""
    if kinematics != "mindlin" or not isinstance(layup.element(1), FibrousShell):
        return layup
    turned = copy.copy(layup)  # the same mesh (and the case's node sets on it)
    turned.kinematics = Calibrated(rule)
    return turned
