"""Whether a frozen contact attempt was wrong in its stick and slip states alone
(solvers/newton.py; docs/theory.md §9.2, "Stick and slip under Static").

Why. Under Static each increment freezes, with its contact set, the stick and slip states of
the frictional nodes and each sliding node's slip direction (elements/contact.py, "Active
set"); a converged state is accepted only under the return mapping. Where the frozen set
converges but the stick and slip states it shows differ, freezing them again is a fixed-point
iteration on the directions and the stick limit: with the automatic penalty the elastic slip
mu k p / k_t of a light strip is 1e-9 mm, so a node's slip direction is decided by its motion
at that scale, and each new frozen set was wrong again (the strip on a rough table of
tests/test_table_contact.py: three frozen attempts an increment, 19 Newton iterations, before
the return mapping itself finished in 2-3). From the converged frozen state, the nodes touching
where the set says, the return mapping's own Newton (its exact stick and slip tangent,
elements/contact_tangent.py) is near its solution: the increment goes on with it at once.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from femcore.model import CompiledModel
from femcore.state import State

__all__ = ["release_slips", "slips_alone"]


def slips_alone(model: CompiledModel, state: State, info: dict[str, Any]) -> bool:
    """Whether ``state``, converged with its contact sets frozen and refused under the
    unilateral law, touches every tool where its frozen sets say (``touch_changes`` of the
    frictional interactions 0, the others' ``freeze`` counting no change) and has a
    frictional set (module docstring); counted in ``info["slip_releases"]``."""
    first = len(model.parts) - len(model.interactions)
    told = False
    for i, part in enumerate(model.interactions):
        if not part.keeps_contact_sets:
            continue
        history = state.history[first + i]
        changes = part.touch_changes(state, history)
        if changes is None:  # no stick and slip state: its freeze count is all of it
            changes = part.freeze(state, history)[1]
        else:
            told = True
        if changes:
            return False
    if told:
        info["slip_releases"] = info.get("slip_releases", 0) + 1
    return told


def release_slips(model: CompiledModel, state: State) -> State:
    """``state`` with each interaction's frozen set kept and its stick and slip states left
    to the return mapping (``InteractionBlock.released_slip``)."""
    first = len(model.parts) - len(model.interactions)
    history = list(state.history)
    for i, part in enumerate(model.interactions):
        history[first + i] = part.released_slip(history[first + i])
    return replace(state, history=tuple(history))
