"""Prescribed motion against stuck points (docs/theory.md §6.5): when the first iteration of
a Static increment applies the increment's prescribed motion alone, the free unknowns held,
instead of the linear step K_ff dq_f = r_f - K_fp dq_p that moves them with it.

In a model with a frictional interaction that keeps no contact set (the plies' friction,
elements/ply_contact.py; ``imposes_alone``), the converged state's tangent holds every
touching point by its stick spring, and its linear step may take the prescribed motion up
where the springs are softest: a pulled ply's faces stay on their anchors, its directors
turn and its faces lift off the points that press it. The motion is applied alone where that
step turns a director past the update cap, or lets go of a point that touches
(``opens_contact``); and an attempt that took the linear step and failed is tried once more
with the motion alone (solvers/newton.py ``_newton``).
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from femcore.interaction import InteractionBlock
from femcore.model import CompiledModel
from femcore.state import State

if TYPE_CHECKING:
    from solvers.static import StaticRun

__all__ = ["imposes_alone", "moves_prescribed", "opens_contact"]


def imposes_alone(model: CompiledModel) -> bool:
    """Whether the first iteration of an increment with prescribed motion may apply that
    motion alone, the free unknowns held: a model with a frictional interaction that keeps no
    contact set (the plies' friction, elements/ply_contact.py), whose converged state's
    tangent holds every touching point stuck. The tools' contact, which freezes its sets, is
    left as it was."""
    return any(_stuck_by_its_tangent(part) for part in model.interactions)


def _stuck_by_its_tangent(part: InteractionBlock) -> bool:
    return part.friction > 0.0 and not part.keeps_contact_sets


def moves_prescribed(run: StaticRun, state: State, load_factor: float) -> bool:
    """Whether the increment from ``state`` to ``load_factor`` moves a prescribed unknown."""
    moved = replace(state, load_factor=load_factor, time=load_factor)
    left = run.equilibrium(load_factor).remaining(moved)
    return bool(np.abs(left).max(initial=0.0) > 0.0)


def opens_contact(model: CompiledModel, state: State, trial: State) -> bool:
    """Whether a point that touches at ``state`` touches no more at ``trial`` (the end of the
    increment's first linear step) in an interaction of ``imposes_alone``'s kind that says
    which of its points touch (``InteractionBlock.touching``): the stick tangent's step has
    lifted the ply off a point that presses it (docs/theory.md §6.5)."""
    first = len(model.parts) - len(model.interactions)
    for i, part in enumerate(model.interactions):
        if not _stuck_by_its_tangent(part):
            continue
        history = state.history[first + i]
        before = part.touching(state, history)
        if before is None or not before.any():
            continue
        after = part.touching(trial, history)
        if after is not None and np.any(before & ~after):
            return True
    return False
