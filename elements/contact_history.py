"""The friction state a rigid tool's contact keeps from one accepted step to the next
(elements/contact.py, module docstring "Friction" and "Active set"; the augmented Lagrangian's
multipliers, elements/augmented_contact.py)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["FrictionHistory", "landing", "start_anchors"]


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
