"""Case files: a model, its loads, its solver and its outputs in one TOML file.

A case file is read with the standard library (``tomllib``) and checked key by key: every
error is a ``CaseError`` (a ValueError) that names the file, the table and the key, and a key
the format does not know is an error, not ignored. The format (README "Case files"):

```toml
title = "G1151 strip under its own weight"     # optional
[mesh]
rectangle = { lx = 200.0, ly = 60.0, nx = 8, ny = 2 }   # or: file = "blank.msh" (meshio),
# or: corner = { lx = 200.0, ly = 150.0, n = 20 } (the corner specimen of Bai §6; grip =
# [20.0, 15.0] adds the node set "grip", the 20 x 15 mm patch at its corner)
[sets]                                   # optional named node sets, by bounds: mesh
tip = { x_min = "100%" }                 # units, or "P%" of the mesh's extent on that axis
[[part]]
element = "fibrous"                      # "fibrous" | "mindlin" | "cable" | a registered name
material = "g1151_laminate"              # a preset name (registered), or an inline table
options = { clamped = "left" }           # keyword options of the element class (symmetric =
                                         # "right" or ["right", "top"]: symmetry planes)
# [layup]                                # optional: the part's fabric as plies on the
# angles = [0.0, 90.0], friction = 0.2   # rectangle, each along its own fibres, in contact
#                                        # (fibreshell/case_layup.py); selectors then name
#                                        # every ply's nodes, "ply_k" one ply's
[[fix]]
nodes = "left"                           # a node-set name, or { x_max = 0.0 } style bounds
dofs = ["ux", "uy", "uz", "alpha", "beta"]   # optional: every DOF by default
[[displace]]                             # also [[force]] and [[moment]] with vector = [...]
nodes = "right"
uz = -10.0
[gravity]
acceleration = [0.0, 0.0, -9810.0]
[[contact]]                              # a rigid tool the shell may touch (elements.tools)
tool = "sphere"                          # "plane" | "annulus" | "sphere" | "cylinder" |
centre = [0.0, 0.0, -50.0]               # "surface"; plane: point, normal; annulus: point,
# normal, inner (the bore's radius: a holder's or a die flange's face); sphere: centre, radius;
radius = 50.0                            # cylinder: point, axis, radius; surface: file, flip,
side = "outside"                         # smooth (true: a normal continuous across facets);
# side (sphere and cylinder): "outside" | "inside"
motion = [0.0, 0.0, 20.0]                # optional translation at the end, with amplitude
# free = ["z"], force = [0.0, 0.0, -500.0], mass = 1e-3: free along z, pushed by 500 N (t);
# a "surface" tool may take pressure = 0.2 (N/mm^2 on its facets' area) instead of force
friction = 0.2                           # optional: Coulomb coefficient (0)
# nodes = "blank" (default: every node), penalty = N/mm per node (default: automatic),
# stick_stiffness = 0.01: the friction's stick spring over the penalty (default 1)
# augmented = true: Static's Uzawa passes (docs/theory.md §9.6), augmented_tolerance = mm
# damping = 0.2: normal contact damping, a fraction of critical (explicit; default 0)
[fibre_bending]                          # optional: the fibres' in-plane bending (fibrous
stiffness = 0.5                          # parts; elements.FibreBending), B_in in N mm,
# families = ["warp", "weft"]            # docs/theory.md §4.7; kinematics "mindlin": a warning
[[grip]]                                 # nodes that translate together (a gripper's jaws,
nodes = "grip"                           # elements.Grip): springs of stiffness N/mm from
stiffness = 23000.0                      # the first node to each other one
[solver]
kind = "static"                          # "static" | "relaxation" | "explicit"
increments = 3                           # any keyword option of that solver
# checkpoint = "checkpoint.pkl"          # explicit, relaxation: relative to the output folder
# checkpoint_interval = 60.0             # explicit: wall-clock s between saves
[output]
history = { reactions = ["left"], displacements = ["tip"] }
paths = { centre = { y_min = "50%", y_max = "50%" } }   # profiles along node paths
```

Node sets by bounds (``[sets]``, and wherever a table takes ``nodes`` or a path): each of
``x_min``, ``x_max``, ... is a number in mesh units or a string ``"P%"``, P from 0 to 100 of
the mesh's extent along that axis (fibreshell/case_sets.py), so that a sweep over the mesh's
size keeps the set; bounds that select no node are an error naming the set, each bound and
the mesh's extent.

Inline materials: for "fibrous" the fields of ``materials.Fabric`` (thickness, areal_density,
tension, shear, bending, tension_weft, bending_weft), each law a number (linear) or a table
``{ table = { x = [...], y = [...] } }``, ``{ bilinear = { initial, final, knee } }``,
``{ polynomial = { k1, k3, k5 } }``, with ``tension_only = true`` for a tension law; for
"mindlin" the same fabric fields (the Mindlin shell whose section is the fabric's laws,
docs/theory.md §5.7), or the arguments of ``materials.ElasticShell`` (E, nu, thickness,
density, G13, G23, shear_factor) or of ``ElasticShell.orthotropic`` (E1, E2, nu12, G12, G13,
G23, thickness, density, warp); for "cable" the arguments of ``elements.Cable`` (axial_stiffness,
mass_per_length, tension_only). A preset with some values changed:
``material = { preset = "paper_stack", sheets = 65, bending = 30.0 }`` (the preset's own
arguments, then fields of ``Fabric``). Units: mm, N, t, s.

Element and preset names: those of ``fibreshell.registry``, which holds the built-in elements,
the ``materials.presets`` and a user's own element types and materials, registered by a call or
found through Python entry points; the registry's docstring says how a part's ``material`` and
``options`` reach a user's element type.
"""

from __future__ import annotations

import inspect
import re
import tomllib
import warnings
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from elements import FibreBending, FibrousShell, Grip
from elements.layup import Layup
from elements.mindlin_fabric import NoDefaultStiffness
from femcore import Mesh, Model
from fibreshell import registry
from fibreshell.case_layup import layup_for, read_layup
from fibreshell.case_materials import _material, _user_element
from fibreshell.case_model import LocatedModel
from fibreshell.case_reading import (
    CaseError,
    _amplitude,
    _keywords,
    _number,
    _table,
    _vector,
    _Where,
)
from fibreshell.case_sets import (
    BOUND_KEYS,
    BoundsError,
    order_path,
    select_by_bounds,
    unused_in,
    used_nodes,
)
from fibreshell.case_tools import read_tool
from fibreshell.gravity_units import warn_gravity_units
from fibreshell.outputs import DEFAULT_CHECKPOINT, checkpoint_collision
from solvers import CentralDifference, DynamicRelaxation, Static
from solvers.driven_tool_checks import check_driven_tools_face_body

__all__ = ["Case", "CaseError", "case_from_data", "load_case", "read_case_data"]

SOLVERS = {"static": Static, "relaxation": DynamicRelaxation, "explicit": CentralDifference}
# Solver options the case file does not take: the outputs are the command's.
_SOLVER_RESERVED = {"self", "output", "history", "history_nodes", "progress"}
_TOP = ("title", "mesh", "sets", "part", "layup", "fix", "displace", "force", "moment",
        "gravity", "contact", "grip", "fibre_bending", "solver", "output")  # fmt: skip


@dataclass
class Case:
    """A case file read and checked: everything to build the model and run it.

    Attributes
    ----------
    path : pathlib.Path
        The case file.
    title : str
        Its title (the file name without suffix by default).
    mesh : femcore.Mesh
        With the ``[sets]`` node sets added; with a ``[layup]``, the layup's mesh (every ply).
    parts, fixes, displacements, forces, moments : list of dict
        The ``[[part]]`` ... tables, checked (node selections resolved to node ids).
    gravity : dict or None
        {"acceleration": (3,), "amplitude": str}.
    contacts : list of dict
        {"tool": RigidTool, "nodes": node ids or None, "friction": float, "penalty", ...} per
        ``[[contact]]``: the keyword arguments of ``Model.contact``.
    grips : list of dict
        {"nodes": node ids, "stiffness": N/mm} per ``[[grip]]`` (elements.Grip).
    fibre_bending : dict or None
        {"stiffness": N mm, "families": tuple of str} of ``[fibre_bending]``
        (elements.FibreBending), None without it.
    solver : dict
        {"kind": str, "options": dict, "checkpoint": str or None, "checkpoint_interval":
        float}: the checkpoint file (relative to the output folder; None: none) and the
        wall-clock seconds between saves of an explicit run.
    history : dict
        {"reactions": [set names], "displacements": [set names]}.
    paths : dict
        name -> node ids along the path, ordered along its longest extent.
    layup : elements.layup.Layup or None
        The ``[layup]``'s plies of the part's fabric (fibreshell/case_layup.py); the model is
        then its plies and their contacts in place of the parts, None without it.
    """

    path: Path
    title: str
    mesh: Mesh
    parts: list[dict] = field(default_factory=list)
    fixes: list[dict] = field(default_factory=list)
    displacements: list[dict] = field(default_factory=list)
    forces: list[dict] = field(default_factory=list)
    moments: list[dict] = field(default_factory=list)
    gravity: dict | None = None
    contacts: list[dict] = field(default_factory=list)
    grips: list[dict] = field(default_factory=list)
    fibre_bending: dict | None = None
    solver: dict = field(default_factory=dict)
    history: dict = field(default_factory=dict)
    paths: dict = field(default_factory=dict)
    node_sets: dict = field(default_factory=dict)
    layup: Layup | None = None
    mesh_file: str | None = None  # [mesh] file as written, which a mesh error names

    # ------------------------------------------------------------------ building
    def model(self, kinematics: str | None = None, calibration=None) -> Model:
        """The model of the case, compiled. ``kinematics="mindlin"`` replaces every fibrous part
        by the Mindlin shell of ``calibration`` (a ``fibreshell.calibration.Calibration`` or its
        name; None: "laws", the fabric's own laws) on the same cells; None or "fibrous" builds
        the case as written; a ``[layup]``'s fibrous plies so become Mindlin plies
        (fibreshell.case_layup.layup_for). Raises CaseError (a ValueError) naming the file,
        the table and the key of an entry that cannot be built or compiled (an unknown cell
        set, a part on cells another part covers, a moment on nodes only fibrous cells use,
        ...)."""
        from fibreshell.calibration import Calibration

        if kinematics not in (None, "fibrous", "mindlin"):
            raise ValueError(f"kinematics must be 'fibrous' or 'mindlin', got {kinematics!r}")
        rule = Calibration.from_options(calibration)
        top = _Where(self.path, "")
        if self.layup is not None:  # the plies' shells and contacts, written by [layup]
            with _raised_at(top.child("layup")):
                plies = layup_for(self.layup, kinematics, rule).model()
            located = LocatedModel(plies, top.child("layup"))
        else:
            located = LocatedModel(Model(self.mesh), None, top.child("mesh"), self.mesh_file)
        for i, part in enumerate(self.parts if self.layup is None else ()):
            element = part["element"]
            if kinematics == "mindlin" and isinstance(element, FibrousShell):
                element = rule.mindlin(element)
            with located.at(top.child(f"part[{i}]"), "cells" if part["cells"] else None) as m:
                m.add(element, part["cells"])
        for i, fix in enumerate(self.fixes):
            with located.at(top.child(f"fix[{i}]")) as m:
                m.fix(fix["nodes"], fix["dofs"])
        for i, item in enumerate(self.displacements):
            with located.at(top.child(f"displace[{i}]")) as m:
                m.displace(item["nodes"], **item["components"], amplitude=item["amplitude"])
        for kind, items in (("force", self.forces), ("moment", self.moments)):
            for i, item in enumerate(items):
                with located.at(top.child(f"{kind}[{i}]")) as m:
                    getattr(m, kind)(item["nodes"], item["vector"], amplitude=item["amplitude"])
        if self.gravity is not None:
            with located.at(top.child("gravity")) as m:
                m.gravity(self.gravity["acceleration"], amplitude=self.gravity["amplitude"])
        for i, contact in enumerate(self.contacts):
            with located.at(top.child(f"contact[{i}]")) as m:
                m.contact(**contact)
        for i, grip in enumerate(self.grips):
            with located.at(top.child(f"grip[{i}]")) as m:
                m.interact(Grip(grip["nodes"], grip["stiffness"]))
        if self.fibre_bending is not None:
            if kinematics == "mindlin":
                # The Mindlin shell has no fibres to bend: say so, so that a comparison of the
                # two kinematics on this case does not differ by the term silently.
                warnings.warn(
                    "[fibre_bending] acts on fibrous parts only: the Mindlin model of this case "
                    "has no in-plane fibre bending",
                    UserWarning,
                    stacklevel=2,
                )
            else:
                with located.at(top.child("fibre_bending")) as m:
                    m.interact(FibreBending(**self.fibre_bending))
        # Compiled here, where each entry's table is known (the solver reuses it): an error
        # of binding or applying one names the file, the table and the key.
        model = located.compile()
        if self.solver["kind"] != "explicit":
            # A holder whose force points away from the body has no quasi-static balance: the
            # solver refuses it as it starts (solvers/common.py check_held); checked here too,
            # where the [[contact]] that wrote it is known, so the error names it and its key.
            located.check(check_driven_tools_face_body)
        # A history set on nodes of cells that no part covers (a line of the mesh without a
        # cable part) would read 0 in every row: refused as one on nodes of no cell is.
        carried = np.any(model.compile().dofs.active, axis=1, keepdims=False).reshape(-1)
        inner = top.child("output").child("history")
        for key, names in self.history.items():
            for name in names:
                ids = self.mesh.nodes(name)
                bare = ids[~carried[ids]]
                if bare.size:
                    raise inner.error(
                        key,
                        f"node set {name!r} holds {bare.size} node(s) that no part's cells use "
                        f"(node {int(bare[0])}, at {self.mesh.points[bare[0]].tolist()}): they "
                        "carry no DOF; give a set of the nodes of the parts",
                    )
        return model

    def make_solver(self, **outputs):
        """The solver of ``[solver]`` with its options and ``outputs`` (progress, ...)."""
        return SOLVERS[self.solver["kind"]](**self.solver["options"], **outputs)

    @property
    def has_fibrous(self) -> bool:
        if self.layup is not None:
            return isinstance(self.layup.element(1), FibrousShell)
        return any(isinstance(part["element"], FibrousShell) for part in self.parts)


@contextmanager
def _raised_at(where: _Where):
    """A ValueError raised inside as a CaseError at ``where``."""
    try:
        yield
    except CaseError:
        raise
    except ValueError as error:
        raise where.error(None, str(error)) from None


# ---------------------------------------------------------------------- reading
def load_case(path: str | Path) -> Case:
    """Read and check a case file.

    Parameters
    ----------
    path : str or pathlib.Path
        A .toml case file; relative mesh paths are relative to its folder.

    Returns
    -------
    Case

    Raises
    ------
    CaseError (a ValueError)
        A missing or unreadable file, a TOML syntax error, an unknown table or key, a value of
        the wrong kind, an unknown preset, node set, element, solver or option: the message
        names the file, the table and the key.
    """
    path = Path(path)
    return case_from_data(read_case_data(path), path)


def read_case_data(path: str | Path) -> dict:
    """The tables of a case file as read by ``tomllib``, unchecked (``case_from_data`` checks
    them). Raises CaseError for a missing, unreadable or non-TOML file."""
    path = Path(path)
    if not path.is_file():
        raise CaseError(f"{path}: no such case file")
    try:
        return tomllib.loads(path.read_text(encoding="utf-8"))
    except UnicodeDecodeError as error:
        raise CaseError(f"{path}: not a text file ({error.reason})") from None
    except tomllib.TOMLDecodeError as error:
        raise CaseError(f"{path}: not valid TOML: {error}") from None


def case_from_data(data: dict, path: str | Path) -> Case:
    """A case from the tables of a case file (``read_case_data``, or built in Python), checked
    as ``load_case`` checks a file. ``path`` names the case in messages and its folder is where
    relative mesh files are looked for (it need not exist as a file)."""
    path = Path(path)
    top = _Where(path, "")
    _table(top, data, "", _TOP, required=("mesh", "part", "solver"))
    title = data.get("title", path.stem)
    if not isinstance(title, str):
        raise top.error("title", f"expected a string, got {title!r}")
    mesh = _mesh(top, data["mesh"], path.parent)
    case = Case(path=path, title=title, mesh=mesh, mesh_file=data["mesh"].get("file"))
    case.parts = [_part(top.child(f"part[{i}]"), p) for i, p in enumerate(_list(top, data, "part"))]
    if "layup" in data:  # the plies' mesh is the case's: every selector below names its nodes
        case.layup = read_layup(top, data, case.parts)
        mesh = case.mesh = case.layup.mesh
    for name, bounds in _table(
        top, data.get("sets", {}), "sets", tuple(data.get("sets", {}))
    ).items():
        ids = _select(top.child("sets"), mesh, bounds, name, named_only=False)
        case.node_sets[name] = ids
        try:
            mesh.add_node_set(name, ids)
        except ValueError as error:  # a name the mesh already has ("left", ...)
            raise top.child("sets").error(name, f"{error}: give this set another name") from None
    case.fixes = [
        _fix(top.child(f"fix[{i}]"), mesh, f) for i, f in enumerate(_list(top, data, "fix"))
    ]
    case.displacements = [
        _displace(top.child(f"displace[{i}]"), mesh, d)
        for i, d in enumerate(_list(top, data, "displace"))
    ]
    for kind, target in (("force", case.forces), ("moment", case.moments)):
        for i, item in enumerate(_list(top, data, kind)):
            where = top.child(f"{kind}[{i}]")
            _table(where, item, "", ("nodes", "vector", "amplitude"), ("nodes", "vector"))
            target.append(
                {
                    "nodes": _select(where, mesh, item["nodes"], "nodes"),
                    "vector": _vector(where, item["vector"], "vector"),
                    "amplitude": _amplitude(where, item.get("amplitude", "step")),
                }
            )
    if "gravity" in data:
        where = top.child("gravity")
        _table(top, data["gravity"], "gravity", ("acceleration", "amplitude"), ("acceleration",))
        case.gravity = {
            "acceleration": _vector(where, data["gravity"]["acceleration"], "acceleration"),
            "amplitude": _amplitude(where, data["gravity"].get("amplitude", "step")),
        }
        # in the materials' system of units (fibreshell/gravity_units.py)
        elements = [p["element"] for p in case.parts]
        warn_gravity_units(case.gravity["acceleration"], elements, f"{path}: [gravity]")
    case.contacts = [
        _contact(top.child(f"contact[{i}]"), mesh, c, path.parent)
        for i, c in enumerate(_list(top, data, "contact"))
    ]
    for i, item in enumerate(_list(top, data, "grip")):
        where = top.child(f"grip[{i}]")
        _table(where, item, "", ("nodes", "stiffness"), ("nodes", "stiffness"))
        stiffness = _number(where, item["stiffness"], "stiffness")
        if stiffness <= 0.0:
            raise where.error("stiffness", f"expected a positive stiffness, got {stiffness!r}")
        case.grips.append(
            {"nodes": _select(where, mesh, item["nodes"], "nodes"), "stiffness": stiffness}
        )
    if "fibre_bending" in data:
        case.fibre_bending = _fibre_bending(top, data["fibre_bending"])
    case.solver = _solver(top, data["solver"])
    explicit = case.solver["kind"] == "explicit"
    for i, item in enumerate(case.displacements if explicit else []):
        if item["amplitude"] == "step":  # a(0) = 1: a jump at t = 0
            raise top.child(f"displace[{i}]").error(
                "amplitude",
                'a displacement with amplitude "step" is prescribed already at t = 0, and an '
                "explicit run would make its nodes jump there in one step (an infinite "
                'velocity): give amplitude "smooth" or "linear" (a suddenly applied load is '
                'a [[force]] with amplitude "step")',
            )
    for i, contact in enumerate(case.contacts):
        tool = contact["tool"]
        if case.solver["kind"] == "explicit" and tool.driven and tool.mass is None:
            raise top.child(f"contact[{i}]").error(
                "mass",
                f"the tool is free along {', '.join(tool.free_names)} and the solver is "
                "explicit: give its mass (t), which m a = F - (contact forces) needs",
            )
    _output(top, data.get("output", {}), case)
    return case


def _fibre_bending(top: _Where, value: Any) -> dict:
    """``[fibre_bending]``: stiffness (N mm, > 0) and optionally families."""
    _table(top, value, "fibre_bending", ("stiffness", "families"), ("stiffness",))
    where = top.child("fibre_bending")
    options: dict[str, Any] = {"stiffness": _number(where, value["stiffness"], "stiffness")}
    if "families" in value:
        options["families"] = value["families"]
    try:
        bending = FibreBending(**options)
    except ValueError as error:
        raise where.error("stiffness" if "stiffness" in str(error) else "families",
                          str(error)) from None  # fmt: skip
    options["families"] = bending.families  # a tuple, whichever way the file gave it
    return options


def _list(where: _Where, data: dict, key: str) -> list:
    value = data.get(key, [])
    if isinstance(value, dict):  # [part] written once instead of [[part]]
        value = [value]
    if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
        raise where.error(key, f"expected [[{key}]] tables, got {value!r}")
    return value


def _mesh(top: _Where, value: Any, folder: Path) -> Mesh:
    table = _table(top, value, "mesh", ("rectangle", "corner", "file"))
    where = top.child("mesh")
    if len(table) != 1:
        raise where.error(
            None, 'give exactly one of rectangle = {...}, corner = {...} or file = "..."'
        )
    if "corner" in table:
        return _corner(where, table["corner"])
    if "file" in table:
        if not isinstance(table["file"], str):
            raise where.error("file", f"expected a path string, got {table['file']!r}")
        mesh_path = folder / table["file"]
        if not mesh_path.is_file():
            raise where.error("file", f"no such mesh file {str(mesh_path)!r}")
        try:
            return Mesh.read(mesh_path)
        except ValueError as error:
            raise where.error("file", str(error)) from None
    keys = ("lx", "ly", "nx", "ny", "origin", "diagonals")
    rect = _table(where, table["rectangle"], "rectangle", keys, ("lx", "ly", "nx", "ny"))
    inner = where.child("rectangle")
    for key in ("nx", "ny"):
        if isinstance(rect[key], bool) or not isinstance(rect[key], int) or rect[key] < 1:
            raise inner.error(key, f"expected a whole number of cells >= 1, got {rect[key]!r}")
    # read before the try: their own CaseErrors name their keys once
    lx, ly = _number(inner, rect["lx"], "lx"), _number(inner, rect["ly"], "ly")
    origin = _vector(inner, rect.get("origin", [0.0, 0.0, 0.0]), "origin")
    try:
        diagonals = rect.get("diagonals", "one-way")  # "alternating": docs/theory.md §5.3
        return Mesh.rectangle(lx, ly, rect["nx"], rect["ny"], origin, diagonals)
    except ValueError as error:
        raise inner.error(None, str(error)) from None


def _corner(where: _Where, value: Any) -> Mesh:
    """The corner specimen of Bai §6: the free triangle of an lx x ly rectangle beyond its
    diagonal, n x n cells before the cut, with node sets "clamp" (the diagonal) and "corner"
    (the free corner at the origin), and with ``grip = a`` or ``[a, b]`` (mm) the node set
    "grip" of the a x a (a x b) patch at the corner a gripper holds, on grid lines at every n;
    femcore.Mesh.corner."""
    keys = ("lx", "ly", "n", "grip", "diagonals")
    table = _table(where, value, "corner", keys, ("lx", "ly", "n"))
    inner = where.child("corner")
    if isinstance(table["n"], bool) or not isinstance(table["n"], int) or table["n"] < 2:
        raise inner.error("n", f"expected a whole number of cells >= 2, got {table['n']!r}")
    lx, ly = _number(inner, table["lx"], "lx"), _number(inner, table["ly"], "ly")
    grip = table.get("grip")
    if grip is not None:
        sizes = grip if isinstance(grip, list) and len(grip) == 2 else [grip]
        grip = tuple(_number(inner, size, "grip") for size in sizes)
    try:
        return Mesh.corner(lx, ly, table["n"], grip, table.get("diagonals", "one-way"))
    except ValueError as error:
        raise inner.error(None, str(error)) from None


def _select(where: _Where, mesh: Mesh, value: Any, key: str, named_only=False) -> np.ndarray:
    """Node ids of a node-set name or a bounds table {x_min, x_max, ..., tolerance}."""
    if isinstance(value, str):
        try:
            return mesh.nodes(value)
        except ValueError as error:
            raise where.error(key, str(error)) from None
    if named_only or not isinstance(value, dict):
        raise where.error(key, f"expected a node-set name or a bounds table, got {value!r}")
    try:
        bounds = _table(where, value, key, BOUND_KEYS)
        return select_by_bounds(mesh.points, bounds, used_nodes(mesh))
    except BoundsError as error:
        # a malformed bound at its own key ([sets.tip.x_min]), an empty set at the set's
        raise (where.child(key).error(error.key, str(error)) if error.key
               else where.error(key, str(error))) from None  # fmt: skip


def _part(where: _Where, value: dict) -> dict:
    _table(where, value, "", ("element", "material", "options", "cells"), ("element",))
    kind = value["element"]
    try:
        cls: Any = registry.element_type(kind)  # a built-in type, or a user's (any signature)
    except ValueError as error:
        raise where.error("element", str(error)) from None
    options = value.get("options", {})
    _table(where, options, "options", tuple(options))
    material = value.get("material")
    try:
        builtin = registry.BUILTIN_ELEMENTS.get(kind) is cls  # not replaced by a user's
        if not builtin:
            element = _user_element(where, kind, cls, material, options)
        elif kind == "cable":
            if not isinstance(material, dict):
                raise where.error("material", "a cable takes an inline table: axial_stiffness, "
                                              "mass_per_length, tension_only")  # fmt: skip
            arguments = {**_keywords(where.child("material"), cls, material), **options}
            _keywords(where.child("options"), cls, options)
            element = cls(**arguments)
        else:
            _keywords(
                where.child("options"), cls, options, frozenset({"self", "material", "fabric"})
            )
            element = cls(_material(where, kind, material), **options)
    except CaseError:
        raise
    except NoDefaultStiffness as error:  # a Mindlin part on a fabric whose bending has a toe
        route = "give both in the part's options = { transverse_shear = S, twisting = D }"
        raise where.error("options", f"{error}; {route}") from None
    except (ValueError, TypeError) as error:
        raise where.error(None, str(error)) from None
    cells = value.get("cells")
    if cells is not None and not isinstance(cells, str):
        raise where.error("cells", f"expected a cell-set name, got {cells!r}")
    return {"kind": kind, "element": element, "cells": cells, "options": dict(options)}


def _fix(where: _Where, mesh: Mesh, value: dict) -> dict:
    _table(where, value, "", ("nodes", "dofs"), ("nodes",))
    dofs = value.get("dofs")
    if dofs is not None and (
        not isinstance(dofs, list) or not all(isinstance(d, str) for d in dofs)
    ):
        raise where.error("dofs", f"expected a list of DOF names, got {dofs!r}")
    return {"nodes": _select(where, mesh, value["nodes"], "nodes"), "dofs": dofs}


def _displace(where: _Where, mesh: Mesh, value: dict) -> dict:
    _table(where, value, "", ("nodes", "ux", "uy", "uz", "amplitude"), ("nodes",))
    components = {k: _number(where, value[k], k) for k in ("ux", "uy", "uz") if k in value}
    if not components:
        raise where.error(None, "give at least one of ux, uy, uz")
    return {
        "nodes": _select(where, mesh, value["nodes"], "nodes"),
        "components": components,
        "amplitude": _amplitude(where, value.get("amplitude", "smooth")),
    }


def _contact(where: _Where, mesh: Mesh, value: dict, folder: Path) -> dict:
    """A ``[[contact]]`` table: its tool built, its nodes selected."""
    tool = read_tool(where, value, folder)
    friction = _number(where, value.get("friction", 0.0), "friction")
    if friction < 0:
        raise where.error("friction", f"expected a Coulomb coefficient >= 0, got {friction!r}")
    penalty = value.get("penalty")
    if penalty is not None and not _number(where, penalty, "penalty") > 0:
        raise where.error("penalty", f"expected a positive number (N/mm), got {penalty!r}")
    stick = value.get("stick_stiffness")
    if stick is not None and not 0.0 < _number(where, stick, "stick_stiffness") <= 1.0:
        raise where.error("stick_stiffness", f"expected a number in (0, 1], got {stick!r}")
    augmented, tol = value.get("augmented", False), value.get("augmented_tolerance")
    if not isinstance(augmented, bool):
        raise where.error("augmented", f"expected true or false, got {augmented!r}")
    if tol is not None and not (augmented and _number(where, tol, "augmented_tolerance") > 0):
        raise where.error("augmented_tolerance", "expected > 0 (mm) with augmented = true")
    damping = value.get("damping")
    if damping is not None and not 0.0 <= _number(where, damping, "damping") <= 1.0:
        raise where.error("damping", f"expected a fraction of critical in [0, 1], got {damping!r}")
    if augmented and damping:  # elements.contact.Contact refuses them together
        raise where.error(
            "damping", "the contact damping (explicit) is not taken with augmented = true (Static)"
        )
    nodes = _select(where, mesh, value["nodes"], "nodes") if "nodes" in value else None
    options = dict(tool=tool, nodes=nodes, friction=friction, penalty=penalty, augmented=augmented)
    return options | {"stick_stiffness": stick, "augmented_tolerance": tol, "damping": damping}


def _solver(top: _Where, value: Any) -> dict:
    if not isinstance(value, dict):
        raise top.error("solver", f"expected a table, got {value!r}")
    where = top.child("solver")
    kind = value.get("kind")
    if kind not in SOLVERS:
        raise where.error("kind", f"expected one of {', '.join(SOLVERS)}, got {kind!r}")
    options = {k: v for k, v in value.items() if k not in ("kind", *_CHECKPOINT_KEYS)}
    _keywords(where, SOLVERS[kind], options, frozenset(_SOLVER_RESERVED))
    needed = inspect.signature(SOLVERS[kind]).parameters.values()
    missing = [
        p.name for p in needed
        if p.default is p.empty and p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)
        and p.name not in options
    ]  # fmt: skip
    if missing:  # (the constructor's TypeError names neither the table nor the file)
        raise where.error(missing[0], f"missing: kind = {kind!r} needs {' and '.join(missing)}")
    try:
        SOLVERS[kind](**options)  # the solver's own checks, now, with the file named
    except (ValueError, TypeError) as error:
        raise where.error(_named_option(str(error), options), str(error)) from None
    return {"kind": kind, "options": options, **_checkpoint(where, kind, value)}


# The checkpoint options of [solver]: arguments of solve(), not of the solver's constructor.
_CHECKPOINT_KEYS = ("checkpoint", "checkpoint_interval")


def _checkpoint(where: _Where, kind: str, value: dict) -> dict:
    """``checkpoint`` (a file name relative to the output folder, or false for none; default
    DEFAULT_CHECKPOINT for explicit and relaxation runs; not the name of a file the run writes
    beside it, fibreshell.outputs.checkpoint_collision) and ``checkpoint_interval`` (explicit
    runs: wall-clock seconds between saves, default 60)."""
    checkpoint = value.get("checkpoint", DEFAULT_CHECKPOINT if kind != "static" else False)
    if kind == "static" and "checkpoint" in value:
        raise where.error(
            "checkpoint", "a static run has no checkpoint (its converged increments are "
            "written as they converge); checkpoints are for explicit and relaxation runs",
        )  # fmt: skip
    if checkpoint is True or not isinstance(checkpoint, str | bool) or checkpoint == "":
        raise where.error(
            "checkpoint", f"expected a file name (relative to the output folder) or false, "
            f"got {checkpoint!r}",
        )  # fmt: skip
    taken = checkpoint_collision(checkpoint) if isinstance(checkpoint, str) else None
    if taken is not None:
        raise where.error(
            "checkpoint", f"a checkpoint named {checkpoint!r} would overwrite {taken}; give "
            f"another name (default {DEFAULT_CHECKPOINT!r})",
        )  # fmt: skip
    interval = value.get("checkpoint_interval", 60.0)
    if "checkpoint_interval" in value and kind != "explicit":
        raise where.error(
            "checkpoint_interval", "an option of explicit runs (a relaxation saves after each "
            "converged increment)",
        )  # fmt: skip
    if (
        isinstance(interval, bool)
        or not isinstance(interval, int | float)
        or not (np.isfinite(interval) and interval >= 0)
    ):
        raise where.error(
            "checkpoint_interval", f"expected wall-clock seconds >= 0, got {interval!r}"
        )
    return {"checkpoint": checkpoint or None, "checkpoint_interval": float(interval)}


def _named_option(message: str, options: dict) -> str | None:
    """The option a solver's message is about (the one it names, the first named if
    several), so that the case error points at its key; None if it names none."""
    named = [(match.start(), key) for key in options if (match := _word(key).search(message))]
    return min(named)[1] if named else None


def _word(key: str) -> re.Pattern:
    return re.compile(rf"(?<![\w.]){re.escape(key)}(?!\w)")


def _output(top: _Where, value: Any, case: Case) -> None:
    table = _table(top, value, "output", ("history", "paths"))
    where = top.child("output")
    history = _table(where, table.get("history", {}), "history", ("reactions", "displacements"))
    inner = where.child("history")
    for key in ("reactions", "displacements"):
        names = history.get(key, [])
        if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
            raise inner.error(key, f"expected a list of node-set names, got {names!r}")
        for name in names:
            ids = _select(inner, case.mesh, name, key, named_only=True)
            stray = unused_in(case.mesh, ids)
            if stray.size:  # its displacement and reaction would read 0 in every row
                raise inner.error(
                    key,
                    f"node set {name!r} holds {stray.size} node(s) that no cell uses (node "
                    f"{int(stray[0])}, at {case.mesh.points[stray[0]].tolist()}): they carry "
                    "no DOF; give a set of the nodes of the cells",
                )
        case.history[key] = list(names)
    paths = table.get("paths", {})
    _table(where, paths, "paths", tuple(paths))
    for name, selection in paths.items():
        ids = _select(where.child("paths"), case.mesh, selection, name)
        if ids.size < 2:
            raise where.child("paths").error(name, "a path needs at least 2 nodes")
        try:  # a line of nodes, or the profiles zigzag across an area (the same order
            # reaches compare's figures, sweep.csv's path columns and identify --path)
            case.paths[name] = order_path(case.mesh.points, ids)
        except BoundsError as error:
            raise where.child("paths").error(name, str(error)) from None
