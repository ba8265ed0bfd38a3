"""Where a body starts against a rigid tool (elements/contact.py ``check_start``): past the
tool's surface is refused, a visible overlap is reported, a body laid on it starts silently.

A node's mid-surface at signed distance d from the tool touches it at d = h / 2 (the contact
offset); d < h / 2 is a penetration p = h / 2 - d the penalty pushes out at the first load
with a force k p, which the reactions and the tool's force carry (a 15 mm laminate started
2.5 mm into a plane: 19 kN on the tool against a weight of 0.14 N). A mid-surface past the
surface (d < 0) is refused: the penalty would fling the node out or hold it on the wrong side.
"""

from __future__ import annotations

import warnings

import numpy as np

__all__ = ["OVERCLOSURE_SHARE", "check_start_gaps"]

#: An initial overlap deeper than this share of the contact offset h / 2 is reported: a blank
#: laid on a die to round-off is not, one started a visible fraction of its thickness into a
#: tool is (the commercial codes report initial overclosures too).
OVERCLOSURE_SHARE = 1e-3


def check_start_gaps(
    tool, distance: np.ndarray, offset, nodes: np.ndarray, tolerance: float
) -> None:
    """Refuse or report the start of the contact nodes against ``tool``.

    Parameters
    ----------
    tool : elements.tools.RigidTool
        Named in the messages (its ``side_hint`` too).
    distance : (s,) float, mm
        The signed distance of each contact node's mid-surface to the tool at the start.
    offset : float or (s,) float, mm
        The contact offset h / 2 of each node.
    nodes : (s,) int
        The contact nodes' ids, for the messages.
    tolerance : float, mm
        Round-off of the distances (the body's size times 1e-9).

    Raises
    ------
    ValueError
        A node whose mid-surface starts past the tool's surface (a penetration deeper than
        h / 2); the message states the depth past the surface and the penetration.

    Warns
    -----
    UserWarning
        Nodes that start overlapping the tool by more than OVERCLOSURE_SHARE of h / 2: how
        many, the deepest and by how much, and what to move.
    """
    offset = np.broadcast_to(np.asarray(offset, dtype=float), distance.shape)
    name = type(tool).__name__
    inside = np.flatnonzero(distance < -tolerance)
    if inside.size:
        ids = nodes[inside]
        first = ", ".join(str(int(n)) for n in ids[:5]) + (", ..." if ids.size > 5 else "")
        deepest = inside[np.argmin(distance[inside])]
        raise ValueError(
            f"the body starts inside the {name}: {ids.size} of {len(distance)} contact nodes "
            f"(nodes {first}) have their mid-surface up to {float(-distance[deepest]):.3g} mm "
            f"past its surface, a penetration of "
            f"{float(offset[deepest] - distance[deepest]):.3g} mm, deeper than the contact "
            f"offset h / 2 = {float(offset[deepest]):.3g} mm; {tool.side_hint()}"
        )
    depth = offset - distance
    over = np.flatnonzero(depth > OVERCLOSURE_SHARE * offset + tolerance)
    if over.size:
        deepest = over[np.argmax(depth[over])]
        warnings.warn(
            f"the body starts overlapping the {name}: {over.size} of {len(distance)} contact "
            f"nodes lie up to {float(depth[deepest]):.3g} mm into it (node "
            f"{int(nodes[deepest])}; their surface is h / 2 = {float(offset[deepest]):.3g} mm "
            "from the mid-surface): the penalty pushes them out at the first load, with "
            "forces the reactions and the tool's force carry. Move the tool or the blank "
            f"{float(depth[deepest]):.3g} mm apart to start touching",
            UserWarning,
            stacklevel=3,
        )
