"""The frozen contact set of a frictionless node-to-tool contact as a linear model, from which
the static solver predicts the next set on each Newton step (solvers/contact_sets.py;
elements/contact.py, "Active set"; docs/theory.md §9.3a, "An active set under Static").

Why. Chosen between Newton iterations on the iterates' gaps, the set of a stiff body lying on a
tool changes by about one node an iteration where it lifts off: a frozen node holds its
neighbours on the tool, so only the node next to those already lifted shows the pull (a strip
laid flat on a table with an overhang, tests/test_table_contact.py: its lift-off front moves
from the edge to sqrt(2) L behind it, 17 node columns of the 2.5 mm mesh, one to two columns a
Newton iteration, and at the automatic penalty the first of 10 increments did not converge in
50 iterations). On the step's linear model the same rule runs over back-substitutions with the
factors already made, and the step taken is one whose end agrees with its set.

The model. A node of the set adds k g n to the internal forces (g = d - h/2, its gap; n the
tool's normal at it, dg/dx), k n n^T (+ k g dn/dx) to the tangent: its row of dg/dq is n on its
three translations. The rule is the unilateral law's own: a node is in the set where the step's
linearised gap g + n . du is negative (no multiplier kept: pressure 0, so that the solver's
rule lambda - k (g + G dq) > 0 is g + G dq < 0 whatever ``ACTIVE_SET_HYSTERESIS`` says), the
rule by which ``ContactBlock.freeze(grow=True)`` takes in a node that penetrates and the
converged check accepts a set. Only the frictionless contact of a tool that no node drives
gives a model: with friction the stick and slip sets and directions are frozen with the
contact set, which the linear model does not choose.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING, Any

import numpy as np

from elements.contact_history import FrictionHistory
from femcore.dofs import N_COLUMNS

if TYPE_CHECKING:
    from elements.contact import ContactBlock
    from femcore.state import State

__all__ = ["set_model", "with_set"]


def set_model(
    block: ContactBlock, state: State, history: Any, frames: Any, dofs: Any
) -> dict | None:
    """The frozen set's linear model at ``state`` (``InteractionBlock.set_model``): None where
    no set is frozen, the contact has friction or a driven tool (module docstring); else
    {"points": (s,) every contact row, "slots": (s, 30) int (the node's three translations,
    then its first slot again with zero entries), "values": (s, 30) (n, then zeros), "gap":
    (s,) mm, "stiffness": (s,) N/mm, "active": (s,) bool, the frozen set, "pressure": (s,)
    N, zero}. ``frames`` is not read: the rows have no rotation entries."""
    del frames, dofs
    if not isinstance(history, FrictionHistory) or history.active is None:
        return None
    if block.friction != 0.0 or block.tool_node is not None:
        return None
    d, n = block.tool.distance(block._positions(state), state.load_factor)
    count = len(d)
    nodes = block.connectivity[:, 0]
    slots = np.repeat((nodes * N_COLUMNS)[:, None], 30, axis=1)
    slots[:, :3] += np.arange(3)
    values = np.zeros((count, 30))
    values[:, :3] = n
    return {
        "points": np.arange(count),
        "slots": slots,
        "values": values,
        "gap": np.asarray(d - block.surface_offset(history), dtype=float),
        "stiffness": np.asarray(block.stiffness, dtype=float),
        "active": np.asarray(history.active, dtype=bool),
        "pressure": np.zeros(count),
    }


def with_set(
    history: FrictionHistory, points: np.ndarray, active: np.ndarray, pressure: np.ndarray
) -> FrictionHistory:
    """``history`` with the set's members ``active`` (r,) bool at the rows ``points`` (r,) of
    ``set_model`` (the others as they were); ``pressure`` is not kept (the rule keeps no
    multiplier, module docstring)."""
    del pressure
    assert history.active is not None
    members = np.array(history.active, dtype=bool)
    members[points] = active
    return replace(history, active=members)
