"""What a tool contact (elements/contact.py) reports of a state at the end of a run: how deep
the body's contact surface has gone into the tool (solvers/tool_penetration.py warns past a
share of the thickness; docs/theory.md §9.1)."""

from __future__ import annotations

import numpy as np

__all__ = ["penetration_report"]


def penetration_report(
    nodes: np.ndarray,
    positions: np.ndarray,
    distance: np.ndarray,
    offset: float | np.ndarray,
    stiffness: np.ndarray,
    share: float,
) -> dict:
    """The depth of the body's contact surface (the mid-surface offset by h / 2) into a tool.

    Parameters
    ----------
    nodes : (s,) int, the contact's body nodes.
    positions : (n, 3) mm, the state's node positions.
    distance : (s,) mm, each contact node's distance to the tool (towards the body positive).
    offset : float or (s,) mm, the contact offset h / 2 of each node (0 for a cable).
    stiffness : (s,) N/mm, the penalty springs.
    share : the share of the thickness h past which a node is counted in ``past_share``.

    Returns
    -------
    dict
        deepest_mm (>= 0), node and at (its position), thickness_mm (its h), pressed (nodes
        with h / 2 - d > 0), past_share (pressed deeper than ``share`` h), force_N (the
        springs' normal force over the pressed nodes), mean_mm (their mean depth).
    """
    offset = np.broadcast_to(np.asarray(offset, dtype=float), distance.shape)
    depth = offset - distance
    deepest = int(np.argmax(depth))
    pressed = depth > 0.0
    return {
        "deepest_mm": max(float(depth[deepest]), 0.0),
        "node": int(nodes[deepest]),
        "at": positions[nodes[deepest]].copy(),
        "thickness_mm": 2.0 * float(offset[deepest]),
        "pressed": int(np.count_nonzero(pressed)),
        # a body without thickness (a cable, offset 0) has no share to pass
        "past_share": int(
            np.count_nonzero(pressed & (offset > 0.0) & (depth > share * 2.0 * offset))
        ),
        "force_N": float(np.sum(stiffness[pressed] * depth[pressed])),
        "mean_mm": float(np.mean(depth[pressed])) if pressed.any() else 0.0,
    }
