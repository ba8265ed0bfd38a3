"""The friction state a rigid tool's contact keeps from one accepted step to the next
(elements/contact.py, module docstring "Friction" and "Active set"; the augmented Lagrangian's
multipliers, elements/augmented_contact.py)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from elements.kept_bits import same_bits

__all__ = [
    "FrictionHistory",
    "accepted",
    "departure",
    "initial_friction",
    "landing",
    "landing_terms",
    "start_anchors",
]


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
        takes as its anchor for that step the point of its way from there where it touched
        (``start_anchors``), so its tangential motion since it touched is friction's slip
        (elements/contact.py, "Friction"); None: not kept (the node is then frictionless for
        that step).
    place : (s, 3) float or None
        Each anchored node: where it was, in the tool's own frame, when the step was
        accepted, mm (NaN for a node without an anchor). A node that is off the tool at the
        end of the next step slipped, in that step, from there to the point of its way where
        it left the contact surface (``departure``); None: not kept (the dissipation of that
        step then leaves it out).
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
    place: np.ndarray | None = None


def _landing_rows(
    block: Any, history: FrictionHistory, penetration: np.ndarray, touching: np.ndarray
):
    """(rows, g, theta): the ``touching`` (s,) bool nodes without an anchor whose approach
    is kept, their gaps g to the contact surface at their approach, mm, and theta = g / (g +
    p) (p = ``penetration`` (s,) mm now, taken as 0 where it is not into the surface; theta
    1 where the node was and is on the surface, g = p = 0). g is the tool's exact distance
    at the approach (``exact_distance``: a meshed tool's ``distance`` is a lower bound past
    its search distance) less the contact ``block``'s surface offset now, the one p is
    measured from (an augmented contact's moved by its multipliers)."""
    approach = getattr(history, "approach", None)  # (absent from an older pickle)
    if approach is None:
        none = np.zeros(0)
        return np.zeros(0, dtype=np.int64), none, none
    rows = np.flatnonzero(touching)
    rows = rows[np.isfinite(approach[rows, 0]) & ~np.isfinite(history.anchor[rows, 0])]
    if len(rows) == 0:
        return rows, np.zeros(0), np.zeros(0)
    d = _approach_distances(block, history, rows)
    g = np.maximum(d - block.surface_offset(history)[rows], 0.0)
    way = g + np.maximum(penetration[rows], 0.0)
    return rows, g, np.where(way > 0.0, g / np.where(way > 0.0, way, 1.0), 1.0)


def _approach_distances(block: Any, history: FrictionHistory, rows: np.ndarray) -> np.ndarray:
    """(r,) the tool's exact distances, mm, at the approaches of ``history``'s ``rows`` (r,),
    kept on the contact ``block`` for the last history and rows asked: a landing step asks for
    them at its forces, its history's update and its acceptance (Static at each iteration's
    forces and tangent), and a meshed tool's exact distance far from it searches every facet
    near the way's end (a k-d query whose band widens with the distance)."""
    kept = block.__dict__.get("_approach_distances")
    if kept is not None and kept[0] is history and same_bits(kept[1], rows):
        return kept[2]
    assert history.approach is not None  # (rows only where it is kept)
    origin = block.tool.offset(0.0)  # (the approach is in the tool's frame)
    d, _ = block.tool.exact_distance(history.approach[rows] + origin, 0.0)
    d.setflags(write=False)
    block.__dict__["_approach_distances"] = (history, rows.copy(), d)
    return d


def landing_terms(
    block: Any,
    history: FrictionHistory,
    where: np.ndarray,
    penetration: np.ndarray,
    touching: np.ndarray,
    normal: np.ndarray,
) -> np.ndarray:
    """(s, 3, 3) what a landing node's anchor, where it touched (``start_anchors``), adds to
    ds/dx of a fixed anchor: with r = x - a = (1 - theta)(x - x_0) and theta = g / (g + p),
    dtheta/dx = g / (g + p)^2 n^T (dp/dx = -n^T), so P dr/dx = (1 - theta) P - P w n^T with
    w = g / (g + p)^2 (x - x_0): -theta P - P w n^T (P = I - n n^T, n = ``normal`` (s, 3);
    ``where`` (s, 3) the nodes in the tool's frame, mm; ``penetration`` (s,) p, mm; dtheta/dx
    0 where p <= 0; g as ``start_anchors`` takes it, of the contact ``block``, fixed: the
    approach is); zero for the other nodes and those not ``touching`` (s,) bool."""
    terms = np.zeros((len(history.anchor), 3, 3))
    rows, g, theta = _landing_rows(block, history, penetration, touching)
    if len(rows) == 0:
        return terms
    assert history.approach is not None  # (rows only where it is kept)
    n = normal[rows]
    projector = np.eye(3) - n[:, :, None] * n[:, None, :]
    pressed = penetration[rows] > 0.0
    rate = np.where(pressed, g / np.where(pressed, g + penetration[rows], 1.0) ** 2, 0.0)
    w = rate[:, None] * (where[rows] - history.approach[rows])
    along = np.einsum("sij,sj->si", projector, w)
    terms[rows] = -theta[:, None, None] * projector - along[:, :, None] * n[:, None, :]
    return terms


def start_anchors(
    history: FrictionHistory,
    where: np.ndarray,
    penetration: np.ndarray,
    touching: np.ndarray,
    block: Any,
) -> np.ndarray:
    """(s, 3) the anchors a step's return mapping starts from, in the tool's frame, mm: the
    history's, and for a node without one the point of its way over the step where it
    touched, a = x_0 + theta (x - x_0) (x_0 its ``approach``, x = ``where`` (s, 3) the nodes
    now in the tool's frame, mm, theta = g / (g + p): g its gap to the contact surface of
    ``block`` at x_0, p its ``penetration`` (s,) now, mm, for the ``touching`` (s,) bool
    nodes; docs/theory.md §9.2), so only its tangential motion since then is slip; for a
    node not touching, its approach itself. NaN where there is neither (a history without
    ``approach``)."""
    approach = getattr(history, "approach", None)  # (absent from an older pickle)
    if approach is None:
        return history.anchor
    anchors = np.where(np.isfinite(history.anchor), history.anchor, approach)
    rows, _, theta = _landing_rows(block, history, penetration, touching)
    anchors[rows] += theta[:, None] * (where[rows] - approach[rows])
    return anchors


def departure(
    block: Any, history: FrictionHistory, where: np.ndarray, touching: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(rows, p_0 (r,) mm, slip (r,) mm): the nodes of the contact ``block`` that had an
    anchor when ``history``'s step was accepted and are not ``touching`` (s,) bool now, at
    ``where`` (s, 3) in the tool's frame, mm: the step in which they left the tool. Each
    slid from its ``place`` x_0 to the point of its way where it left the contact surface,
    x_l = x_0 + theta (x - x_0), theta = p_0 / (p_0 + g) (p_0 its penetration at x_0, the
    history's, g its gap at x to the surface p_0 was measured from: an augmented contact's
    moved by the multipliers the step started with; the gap taken linear over the step, as a
    landing node's, ``start_anchors``), under a normal force falling from k p_0 to 0: its
    slip is its whole tangential offset from its anchor there, |(I - n n^T)(x_l - a)| (n the
    tool's normal at x_l), the stick spring holding nothing at p = 0 (docs/theory.md
    §9.2). The distances are the tool's exact ones (``exact_distance``: a meshed tool's
    ``distance`` is a lower bound past its search distance), asked for these nodes alone.
    No rows for a frictionless block or a history without ``place``."""
    place = getattr(history, "place", None)  # (absent from an older pickle)
    none = np.zeros(0)
    if place is None or block.friction == 0.0:
        return np.zeros(0, dtype=np.int64), none, none
    rows = np.flatnonzero(~touching & np.isfinite(history.anchor[:, 0]) & np.isfinite(place[:, 0]))
    if len(rows) == 0:
        return rows, none, none
    origin = block.tool.offset(0.0)  # (the places and ``where`` are in the tool's frame)
    start, end = place[rows], where[rows]
    d, _ = block.tool.exact_distance(np.concatenate([start, end]) + origin, 0.0)
    # p_0 is the penetration the step started with (its normal force over k): an augmented
    # contact's surface is where its multipliers put it then, which a Uzawa pass at the end
    # of the increment may since have moved back (a node off the tool loses its multiplier),
    # and the surface measured now would give p_0 = 0 there, its anchor's whole offset as
    # slip and no dissipation: a record depending on whether a pass ran.
    p0 = history.penetration[rows]
    gap = np.maximum(d[len(rows) :] - (d[: len(rows)] + p0), 0.0)
    way = p0 + gap
    theta = np.where(way > 0.0, p0 / np.where(way > 0.0, way, 1.0), 0.0)
    left = start + theta[:, None] * (end - start)
    _, n = block.tool.exact_distance(left + origin, 0.0)
    r = left - history.anchor[rows]
    s = r - np.sum(r * n, axis=1)[:, None] * n
    return rows, p0, np.linalg.norm(s, axis=1)


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
    return FrictionHistory(
        anchor, np.zeros(len(d)), penetration, 0.0, approach=approach, place=anchor.copy()
    )


def accepted(block: Any, state: Any, history: FrictionHistory) -> FrictionHistory:
    """The return mapping of a tool contact ``block`` (elements/contact.py, "Friction")
    accepted at ``state`` from ``history``: sliding anchors follow their nodes to the friction
    limit, new contacts are anchored where they are, lost ones forget their anchor; the slip
    and its dissipation added, a node that left the tool's up to where it left
    (``departure``)."""
    x = block._positions(state)
    d, n = block.tool.distance(x, state.load_factor)
    if history.active is None:
        p, n, touching = block._touching(d, n, history)
    else:  # a frozen set (elements/contact.py, "Active set")
        p, n, touching = block.touch(state, history)
    _, s, stuck, sliding = block.tangential(state, history, p, n, touching)
    p = np.maximum(p, 0.0)  # a frozen node pulled off the tool has no friction limit
    length = np.linalg.norm(s, axis=1)
    limit = block.friction * p / block.stick_ratio  # the spring's length at the limit
    slid = np.where(sliding, length - limit, 0.0)
    unit = s / np.where(length > 0, length, 1.0)[:, None]
    where = x - block.tool.offset(state.load_factor)  # in the tool's frame
    anchors = start_anchors(history, where, p, touching, block)
    anchor = np.where(touching[:, None], where, np.nan)  # new contacts
    anchor = np.where(stuck[:, None], anchors, anchor)
    moved = anchors + slid[:, None] * unit
    anchor = np.where(sliding[:, None], moved, anchor)
    # A new contact's anchor, where it touched (or an augmented pass's), may lie off the
    # tool: put it level with the node, where its spring (s stuck, at the limit) ends.
    spring = np.where(sliding[:, None], limit[:, None] * unit, s)
    new = (stuck | sliding) & landing(history)
    anchor = np.where(new[:, None], where - spring, anchor)
    anchored = np.isfinite(anchor[:, :1])
    approach = np.where(anchored, np.nan, where)
    place = np.where(anchored, where, np.nan)
    # The slip happened while p went from its last value to this one: the limit force
    # at their mean (the integrator's midpoint rule) keeps the energy balance O(dt^2).
    mean = 0.5 * (p + history.penetration)
    # A node that left slid until it left, while p fell from p_0 to 0 (``departure``).
    rows, start, way = departure(block, history, where, touching)
    slid[rows], mean[rows] = way, 0.5 * start
    force = block.friction * block.stiffness * mean
    dissipated = history.dissipated + float(np.sum(force * slid))
    return FrictionHistory(
        anchor, history.slip + slid, p, dissipated, approach=approach, place=place
    )
