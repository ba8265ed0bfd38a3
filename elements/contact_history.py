"""The friction state a rigid tool's contact keeps from one accepted step to the next
(elements/contact.py, module docstring "Friction" and "Active set"; the augmented Lagrangian's
multipliers, elements/augmented_contact.py)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["FrictionHistory", "accepted", "initial_friction", "landing", "start_anchors"]


@dataclass(frozen=True)
class FrictionHistory:
    """The friction state of a contact block after an accepted step.

    anchor : (s, 3) float
        Each node's anchor in the tool's own frame (its position less the tool's translation),
        mm; NaN for a node without one (not touching).
    slip : (s,) float
        Slip length accumulated by each node, mm.
    penetration : (s,) float
        Each node's penetration p when the step was accepted, mm (the dissipation of the next
        step takes the friction limit at the mean of the two).
    dissipated : float
        Energy dissipated by friction so far, N mm.
    active : (s,) bool or None
        The frozen contact set (module docstring), None: decided by the gap.
    sliding : (s,) bool or None
        The frozen slip set, None: decided by the return mapping.
    direction : (s, 3) float or None
        The frozen unit slip direction of each sliding node (the friction opposes its
        projection on the tool's tangent plane).
    normal : (s, 3) float or None
        The tool's unit normal at each node where the frozen set took it in (the release,
        module docstring "Active set").
    multiplier : (s,) float or None
        The augmented Lagrangian's normal multiplier of each node, N (None: pure penalty;
        elements/augmented_contact.py).
    traction : (s, 3) float or None
        The augmented Lagrangian's tangential multiplier (the stick traction) of each node, N.
    approach : (s, 3) float or None
        Each node without an anchor: where it was, in the tool's own frame, when the step
        was accepted, mm (NaN for an anchored node). A node that touches in the next step
        takes it as its anchor for that step, so its tangential motion since then is
        friction's slip (elements/contact.py, "Friction"); None: not kept (the node is then
        frictionless for that step).
    """

    anchor: np.ndarray
    slip: np.ndarray
    penetration: np.ndarray
    dissipated: float
    active: np.ndarray | None = None
    sliding: np.ndarray | None = None
    direction: np.ndarray | None = None
    normal: np.ndarray | None = None
    multiplier: np.ndarray | None = None
    traction: np.ndarray | None = None
    approach: np.ndarray | None = None


def start_anchors(history: FrictionHistory) -> np.ndarray:
    """(s, 3) the anchors a step's return mapping starts from, in the tool's frame, mm: the
    history's, and for a node without one where it was when the step was accepted (its
    ``approach``); NaN where there is neither (a history without ``approach``)."""
    approach = getattr(history, "approach", None)  # (absent from an older pickle)
    if approach is None:
        return history.anchor
    return np.where(np.isfinite(history.anchor), history.anchor, approach)


def landing(history: FrictionHistory) -> np.ndarray:
    """(s,) bool: the nodes that had no anchor when ``history``'s step was accepted, their
    step's anchor their ``approach``: those whose approach is kept (an augmented Lagrangian's
    pass, elements/augmented_contact.py, gives them an anchor and keeps it); none for a
    history without ``approach``."""
    approach = getattr(history, "approach", None)  # (absent from an older pickle)
    if approach is None:
        return np.zeros(len(history.anchor), dtype=bool)
    return np.isfinite(approach[:, 0])


def initial_friction(block: Any) -> FrictionHistory:
    """The history of a frictional tool contact ``block`` (elements/contact.py) where it
    starts: the nodes that touch the tool there are anchored where they are (a fabric laid on
    a tool sticks from the first step), the others keep where they are as their approach."""
    d, _ = block.tool.distance(block._reference, 0.0)
    touching = d <= block.offset + block.tolerance
    where = block._reference - block.tool.offset(0.0)
    anchor = np.where(touching[:, None], where, np.nan)
    approach = np.where(touching[:, None], np.nan, where)
    penetration = np.maximum(block.offset - d, 0.0)
    return FrictionHistory(anchor, np.zeros(len(d)), penetration, 0.0, approach=approach)


def accepted(block: Any, state: Any, history: FrictionHistory) -> FrictionHistory:
    """The return mapping of a tool contact ``block`` (elements/contact.py, "Friction")
    accepted at ``state`` from ``history``: sliding anchors follow their nodes to the friction
    limit, new contacts are anchored where they are, lost ones forget their anchor; the slip
    and its dissipation added."""
    p, n, touching = block.touch(state, history)
    _, s, stuck, sliding = block.tangential(state, history, p, n, touching)
    p = np.maximum(p, 0.0)  # a frozen node pulled off the tool has no friction limit
    x = block._positions(state)
    length = np.linalg.norm(s, axis=1)
    limit = block.friction * p / block.stick_ratio  # the spring's length at the limit
    slid = np.where(sliding, length - limit, 0.0)
    unit = s / np.where(length > 0, length, 1.0)[:, None]
    origin = block.tool.offset(state.load_factor)
    anchors = start_anchors(history)
    anchor = np.where(touching[:, None], x - origin, np.nan)  # new contacts
    anchor = np.where(stuck[:, None], anchors, anchor)
    moved = anchors + slid[:, None] * unit
    anchor = np.where(sliding[:, None], moved, anchor)
    # A new contact's anchor came from its approach, off the tool (an augmented pass's
    # too): put it level with the node, where its spring (s stuck, at the limit) ends.
    spring = np.where(sliding[:, None], limit[:, None] * unit, s)
    new = (stuck | sliding) & landing(history)
    anchor = np.where(new[:, None], x - origin - spring, anchor)
    approach = np.where(np.isfinite(anchor), np.nan, x - origin)
    # The slip happened while p went from its last value to this one: the limit force
    # at their mean (the integrator's midpoint rule) keeps the energy balance O(dt^2).
    force = block.friction * block.stiffness * 0.5 * (p + history.penetration)
    dissipated = history.dissipated + float(np.sum(force * slid))
    return FrictionHistory(anchor, history.slip + slid, p, dissipated, approach=approach)
