"""Where two plies start against each other (``PlyContactBlock.check_start``): an upper ply
whose mid-surface starts past the lower ply's is refused, a visible overlap is reported, plies
laid on each other start silently. The plies' counterpart of elements/contact_start.py (a body
against a rigid tool).

A contact point on the upper ply's face, x - a d, at gap g from the lower ply's face, y + b d,
touches at g = 0; g < 0 is a penetration the penalty pushes out at the first load, with a force
the reactions carry. Past g = -(a + b) the upper ply's mid-surface lies beyond the lower one's:
the plies were given in the wrong order (``upper`` the ply below) or stacked closer than their
thicknesses, and the penalty would push them further through each other. Plies stacked by
elements.plies.PlyStack or elements.layup.Layup start within 2e-6 of a + b of each other on
curved mid-surfaces too (their faces along the nodal directors coincide to second order):
far below the report's share.
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from elements.contact_start import OVERCLOSURE_SHARE

__all__ = ["check_ply_start"]


def check_ply_start(block: Any, facing: Any, tolerance: float) -> None:
    """Refuse or report the start of a ply contact's points against the lower ply.

    Parameters
    ----------
    block : elements.ply_block.PlyContactBlock
        Its ``upper_offset`` (P, 3) and ``corner_offset`` (m, 3), mm, the half thicknesses a
        and b; ``above`` (P, 3) the points' upper triangles' corners and ``shape`` (P, 3) the
        points' barycentric coordinates there, for the messages (a point's nearest corner).
    facing : elements.ply_projection.Facing
        The points' facing at the reference state (``gap`` (P,) mm, ``touching`` (P,) bool,
        ``triangle`` (P,) int).
    tolerance : float, mm
        Round-off of the gaps (the plies' size times 1e-9).

    Raises
    ------
    ValueError
        Touching points past the lower ply's mid-surface too (g < -(a + b)): how many, the
        deepest, and the likely causes.

    Warns
    -----
    UserWarning
        Touching points overlapping the lower ply by more than OVERCLOSURE_SHARE of a + b: how
        many, the deepest and by how much, and what to move.
    """
    on = np.flatnonzero(facing.touching)
    if on.size == 0:
        return
    a = np.abs(block.upper_offset[on]).mean(axis=1)
    b = np.abs(block.corner_offset[facing.triangle[on]]).mean(axis=1)
    depth = -facing.gap[on]
    where = block.above[on, np.argmax(block.shape[on], axis=1)]
    through = np.flatnonzero(depth > a + b + tolerance)
    if through.size:
        deepest = through[np.argmax(depth[through])]
        raise ValueError(
            f"the plies start through each other: {through.size} of {len(facing.gap)} contact "
            f"points of the upper ply lie up to {float(depth[deepest]):.3g} mm into the lower "
            f"ply (nearest node {int(where[deepest])}), deeper than both half thicknesses a + b = "
            f"{float(a[deepest] + b[deepest]):.3g} mm: the upper ply's mid-surface starts "
            "beyond the lower ply's. Give the ply above as ``upper`` (the stack's order, "
            "along the directors), and lay the plies a + b apart"
        )
    over = np.flatnonzero(depth > OVERCLOSURE_SHARE * (a + b) + tolerance)
    if over.size:
        deepest = over[np.argmax(depth[over])]
        warnings.warn(
            f"the plies start overlapping: {over.size} of {len(facing.gap)} contact points of "
            f"the upper ply lie up to {float(depth[deepest]):.3g} mm into the lower ply ("
            f"nearest node {int(where[deepest])}; the faces are a + b = "
            f"{float(a[deepest] + b[deepest]):.3g} mm apart at touch): the penalty pushes them "
            "out at the first load, with forces the reactions carry. Lay the plies "
            f"{float(depth[deepest]):.3g} mm further apart to start touching",
            UserWarning,
            stacklevel=3,
        )
