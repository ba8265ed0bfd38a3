"""Whether each force-driven tool's force points towards the body it is to press, checked
before a quasi-static solve (Static, DynamicRelaxation: solvers/common.py ``check_held``;
docs/theory.md §9.5).

A force-driven tool (a blank holder) stands, in a quasi-static solve, where its prescribed
force equals its contact forces. The contact pushes the tool only away from the body (its
normal force on a node is k p n, n the tool's normal towards the body, and the node pushes
the tool back along -n): a force whose component along every such normal is not positive is
never balanced, the tool flies off, and the solve stops on a singular tangent that does not
name it. The tool's normals towards the nodes it may touch come from its interaction
(``InteractionBlock.tool_facing``), the force from the model's loads on its node at the end
of the load path (its weight with it).
"""

from __future__ import annotations

import numpy as np

from femcore.entry_error import EntryError
from femcore.model import CompiledModel

__all__ = ["ForceAwayFromBody", "check_driven_tools_face_body"]


class ForceAwayFromBody(EntryError):
    """A force-driven tool's force that points away from the body (a ValueError): ``index``
    the first interaction the tool belongs to (in the model's interactions, which a ply
    stack's contacts may precede), ``key`` the setting at fault ("force"), so that
    a case file's error names the ``[[contact]]`` table and its key (fibreshell/case_model.py).
    """

    def __init__(
        self,
        kind: str,
        index: int,
        reason: str,
        prefix: str = "",
        key: str | None = "force",
        case_reason: str | None = None,
    ) -> None:
        super().__init__(kind, index, reason, prefix, key, case_reason)


def _vector(v: np.ndarray) -> str:
    return "(" + ", ".join(f"{c:.4g}" for c in v) + ")"


def check_driven_tools_face_body(model: CompiledModel) -> None:
    """Raise ForceAwayFromBody (a ValueError) when a force-driven tool's force (along its free
    axes, at load factor 1) points away from every node it may touch: its component along each
    normal from the tool towards them is <= 0. The message names the tool, its force and the
    way to the body."""
    tools = model.driven_tools
    if not len(tools):
        return
    facing = model.tool_facing(model.initial_state())
    loads = tools.loads(1.0) * tools.free
    names = tools.names()
    for k, rows in enumerate(tools.rows):
        force = loads[k]
        if not np.any(force):
            continue  # no force: held by its contacts alone, or a weightless mass
        given = [facing[row] for row in rows]
        normals = [np.asarray(n) for n in given if n is not None and len(n)]
        if len(normals) < len(given):
            continue  # a tool whose side its interaction does not say: not judged
        along = np.concatenate([np.asarray(n) @ force for n in normals])
        if along.max() > 0.0:
            continue
        towards = np.mean(np.concatenate(normals), axis=0) * tools.free[k]
        length = float(np.linalg.norm(towards))
        way = f" (the body lies along {_vector(towards / length)} from it)" if length else ""
        raise ForceAwayFromBody(
            "interaction",
            tools.interaction_of(k),
            f"{names[k]}'s force {_vector(force)} N points away from the body{way}: a "
            "force-driven tool presses the body only with a force towards it, and this one "
            "would leave it, where a quasi-static solver (Static, DynamicRelaxation) finds no "
            "position at which the contact forces balance it. Give the force towards the body "
            "(its sign turned, "
            f"{_vector(-force + 0.0)} N, for a tool whose face looks straight at the body)",
        )
