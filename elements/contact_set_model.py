"""The frozen contact set of a node-to-tool contact as a linear model, from which the static
solver predicts the next set on each Newton step (solvers/contact_sets.py; elements/contact.py,
"Active set"; docs/theory.md §9.1, "The set predicted on the step's linear model").

Why. Chosen between Newton iterations on the iterates' gaps, the set of a stiff body lying on a
tool changes by about one node an iteration where it lifts off: a frozen node holds its
neighbours on the tool, so only the node next to those already lifted shows the pull (a strip
laid flat on a table with an overhang, tests/test_table_contact.py: its lift-off front moves
from the edge to sqrt(2) L behind it, 17 node columns of the 2.5 mm mesh, one to two columns a
Newton iteration, and at the automatic penalty the first of 10 increments did not converge in
50 iterations, with friction or without). On the step's linear model the same rule runs over
back-substitutions with the factors already made, and the step taken is one whose end agrees
with its set.

The model. A node of the set adds k g n to the internal forces (g = d - h/2, its gap; n the
tool's normal at it, dg/dx), k n n^T (+ k g dn/dx) to the tangent: its row of dg/dq is n on its
three translations. The rule is the unilateral law's own: a node is in the set where the step's
linearised gap g + n . du is negative (no multiplier kept: pressure 0, so that the solver's
rule lambda - k (g + G dq) > 0 is g + G dq < 0 whatever ``ACTIVE_SET_HYSTERESIS`` says), the
rule by which ``ContactBlock.freeze(grow=True)`` takes in a node that penetrates and the
converged check accepts a set. With friction each node keeps its frozen friction with its row:
a sliding node's mu k p along -v follows its gap (force direction F = n - mu v where it
presses: k g F on the forces, k F n^T on the tangent), a stuck node's stick spring k_t s is two
more rows t_1, t_2 of its tangent plane (gap s . t_j, stiffness k_t) led by its gap's row; a
node the step lands slides without a direction, frictionless as its row (``with_set``). The
stick and slip states themselves are not chosen here (solvers/slip_sets.py). A tool that a
node drives, and an augmented contact with friction (its stick traction is no row's spring),
give no model.
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

__all__ = ["released_slip", "set_model", "touch_changes", "with_set"]


def set_model(
    block: ContactBlock, state: State, history: Any, frames: Any, dofs: Any
) -> dict | None:
    """The frozen set's linear model at ``state`` (``InteractionBlock.set_model``): None where
    no set is frozen, the tool is driven or the contact is augmented with friction (module
    docstring); else {"points": (r,) the contact row of each row, "slots": (r, 30) int (the
    node's three translations, then its first slot again with zero entries), "values": (r,
    30) the gradient G (n, or a tangent t_j), "forces": (r, 30) the force direction F (n - mu
    v at a sliding node), "gap": (r,) mm (g = d - h/2, or s . t_j), "stiffness": (r,) N/mm (k,
    or k_t), "active": (r,) bool, the frozen set, "pressure": (r,) N, zero, "leader": (r,) int,
    the row whose rule decides (a stick row's node's gap row)}: the gap rows first, one a
    contact node, then two stick rows a stuck node. A node none of whose translations is free
    or prescribed in ``dofs`` (None: every node counts) has no row: no step moves its gap,
    and the iterations' rule keeps its membership (a node clamped on the tool at a gap of
    round-off, which the model's g + G dq < 0 took out at every prediction and the converged
    check's d <= h/2 + tolerance put back). ``frames`` is not read: the rows have no rotation
    entries."""
    del frames
    if not isinstance(history, FrictionHistory) or history.active is None:
        return None
    if block.tool_node is not None:
        return None
    rough = block.friction != 0.0
    if rough and (history.sliding is None or history.traction is not None):
        return None  # (an augmented contact's stick traction is not a row's spring)
    d, n = block.tool.distance(block._positions(state), state.load_factor)
    count = len(d)
    kept = np.arange(count)
    if dofs is not None:
        moving = (dofs.free | dofs.prescribed).reshape(-1, N_COLUMNS)[:, :3].any(axis=1)
        kept = np.flatnonzero(moving[block.connectivity[:, 0]])
    active = np.asarray(history.active, dtype=bool)
    gap = np.asarray(d - block.surface_offset(history), dtype=float)
    values = n.copy()
    forces = n.copy()
    stiffness = np.asarray(block.stiffness, dtype=float)
    points, gaps, leader = kept, [gap[kept]], np.arange(len(kept))
    if rough:
        p, n, touching = block.touch(state, history)
        _, s, stuck, sliding = block.tangential(state, history, p, n, touching)
        # the sliding force mu k max(p, 0) along -v follows the gap while the node presses
        pressed = sliding & (p > 0.0)
        along = block._slip_direction(history, n)
        forces[pressed] -= block.friction * along[pressed]
        # a stuck node's spring k_t s in its tangent plane: two rows that follow its gap's
        row_of = np.full(count, -1)
        row_of[kept] = np.arange(len(kept))
        held = np.flatnonzero(stuck & (row_of >= 0))
        first, second = tangents(n[held])
        values = np.concatenate([values[kept], first, second])
        forces = np.concatenate([forces[kept], first, second])
        gaps += [np.sum(s[held] * first, axis=1), np.sum(s[held] * second, axis=1)]
        k_t = block.stiffness[held] * block.stick_ratio
        stiffness = np.concatenate([stiffness[kept], k_t, k_t])
        points = np.concatenate([kept, held, held])
        leader = np.concatenate([leader, row_of[held], row_of[held]])
    else:
        values, forces, stiffness = values[kept], forces[kept], stiffness[kept]
    rows = len(points)
    nodes = block.connectivity[points, 0]
    slots = np.repeat((nodes * N_COLUMNS)[:, None], 30, axis=1)
    slots[:, :3] += np.arange(3)
    wide, wide_forces = np.zeros((rows, 30)), np.zeros((rows, 30))
    wide[:, :3], wide_forces[:, :3] = values, forces
    return {
        "points": points,
        "slots": slots,
        "values": wide,
        "forces": wide_forces,
        "gap": np.concatenate(gaps),
        "stiffness": stiffness,
        "active": active[points],
        "pressure": np.zeros(rows),
        "leader": leader,
    }


def tangents(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors (m, 3) each, orthogonal to each other and to the unit normals n (m,
    3): the first across the axis along which n is smallest."""
    axis = np.zeros_like(n)
    axis[np.arange(len(n)), np.argmin(np.abs(n), axis=1)] = 1.0
    first = np.cross(n, axis)
    first /= np.linalg.norm(first, axis=1)[:, None]
    return first, np.cross(n, first)


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
    if history.sliding is None or history.direction is None:
        return replace(history, active=members)
    # a node the step lands slides without a direction, frictionless as on the linear model
    # (its rows hold no friction), until the set is frozen again at a converged state
    joined = members & ~history.active
    return replace(
        history,
        active=members,
        sliding=history.sliding | joined,
        direction=np.where(joined[:, None], 0.0, history.direction),
    )


def touch_changes(block: ContactBlock, state: State, history: Any) -> int | None:
    """With friction and a frozen set: the number of nodes whose touching at ``state``
    differs from the frozen set, their stick and slip states aside
    (``InteractionBlock.touch_changes``, solvers/slip_sets.py); else None."""
    if not isinstance(history, FrictionHistory) or history.active is None:
        return None
    if block.friction == 0.0:
        return None
    d, n = block.tool.distance(block._positions(state), state.load_factor)
    return int((block._touching(d, n, history)[2] != history.active).sum())


def released_slip(history: Any) -> Any:
    """``history`` with its frozen contact set kept and its stick and slip states and slip
    directions left to the return mapping (``InteractionBlock.released_slip``,
    solvers/slip_sets.py); as it is without a frozen frictional set."""
    if not isinstance(history, FrictionHistory) or history.active is None:
        return history
    return replace(history, sliding=None, direction=None)
