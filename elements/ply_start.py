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
curved mid-surfaces with flat faces (their faces along the nodal directors coincide to second
order): far below the report's share. Curved faces (Phong patches) bulge differently between
the nodes and overlap there by up to 1.1e-2 (a + b) on coarse meshes: reported above
CURVED_OVERCLOSURE_SHARE. Points past the lower ply's outline (where the contact fades them
out) are beside the ply, not in it, and are not judged. In the mirrored pass
(``points="lower"``) the points are the lower ply's, and the messages say so.
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from elements.contact_start import OVERCLOSURE_SHARE
from elements.ply_curved import MARGIN_CURVED
from elements.ply_projection import MARGIN

__all__ = ["CURVED_OVERCLOSURE_SHARE", "check_ply_start"]

#: The overlap reported on curved faces (``PlyContact(surface="curved")``), a share of a + b:
#: the two plies' Phong patches bulge differently between the nodes, so plies stacked to
#: touch at the nodes overlap between them by up to 1.1e-2 (a + b) on coarse curved meshes
#: (measured: a spherical cap and cylinders of radius 10-20 mm in 4-8 cells a side), which no
#: spacing of the nodes removes; a stack laid through by a visible share is still reported.
CURVED_OVERCLOSURE_SHARE = 0.05


def check_ply_start(block: Any, facing: Any, tolerance: float) -> None:
    """Refuse or report the start of a ply contact's points against the lower ply.

    Parameters
    ----------
    block : elements.ply_block.PlyContactBlock
        Its ``upper_offset`` (P, 3) and ``corner_offset`` (m, 3), mm, the half thicknesses a
        and b; ``curved`` and ``mirrored`` (its faces and its points' ply); ``above`` (P, 3)
        the points' upper triangles' corners and ``shape`` (P, 3) the points' barycentric
        coordinates there, for the messages (a point's nearest corner).
    facing : elements.ply_projection.Facing
        The points' facing at the reference state (``gap`` (P,) mm, ``touching`` (P,) bool,
        ``triangle`` (P,) int, ``fade`` (P,) float or None).
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
        No point facing the other ply at all (``_say_none_faces``). Touching points
        overlapping the lower ply by more than OVERCLOSURE_SHARE of a + b
        (CURVED_OVERCLOSURE_SHARE on curved faces): how
        many, the deepest and by how much, and what to move.
    """
    _say_none_faces(block, facing)
    on = facing.touching.copy()
    if facing.fade is not None:
        # a point past the lower ply's outline, where its weight w fades, is beside the ply,
        # not in it: its gap is to a growth's plane, deep on a coarse curved ply (0.395 mm at
        # w = 1.8e-3, a patch on a cylinder of radius 10 mm in 5-mm cells) and pushing w
        # times as little
        on &= facing.fade >= 1.0
    on = np.flatnonzero(on)
    if on.size == 0:
        return
    a = np.abs(block.upper_offset[on]).mean(axis=1)
    b = np.abs(block.corner_offset[facing.triangle[on]]).mean(axis=1)
    depth = -facing.gap[on]
    # the mirrored pass's points are the lower ply's, facing the upper one (ply_contact.py,
    # "Both ways")
    points, faced = ("lower", "upper") if block.mirrored else ("upper", "lower")
    where = block.above[on, np.argmax(block.shape[on], axis=1)]
    through = np.flatnonzero(depth > a + b + tolerance)
    if through.size:
        deepest = through[np.argmax(depth[through])]
        raise ValueError(
            f"the plies start through each other: {through.size} of {len(facing.gap)} contact "
            f"points of the {points} ply lie up to {float(depth[deepest]):.3g} mm into the "
            f"{faced} ply (nearest node {int(where[deepest])}), deeper than both half "
            f"thicknesses a + b = {float(a[deepest] + b[deepest]):.3g} mm: the {points} ply's "
            f"mid-surface starts beyond the {faced} ply's. Give the ply above as ``upper`` "
            "(the stack's order, along the directors), and lay the plies a + b apart"
        )
    share = CURVED_OVERCLOSURE_SHARE if block.curved else OVERCLOSURE_SHARE
    over = np.flatnonzero(depth > share * (a + b) + tolerance)
    if over.size:
        deepest = over[np.argmax(depth[over])]
        warnings.warn(
            f"the plies start overlapping: {over.size} of {len(facing.gap)} contact points of "
            f"the {points} ply lie up to {float(depth[deepest]):.3g} mm into the {faced} ply ("
            f"nearest node {int(where[deepest])}; the faces are a + b = "
            f"{float(a[deepest] + b[deepest]):.3g} mm apart at touch): the penalty pushes them "
            "out at the first load, with forces the reactions carry. Lay the plies "
            f"{float(depth[deepest]):.3g} mm further apart to start touching",
            UserWarning,
            stacklevel=3,
        )


def _say_none_faces(block: Any, facing: Any) -> None:
    """Warn where no contact point faces the other ply at the start: each point's projection
    lies past the other ply's outline by more than the contact's margin (``MARGIN``, or
    ``MARGIN_CURVED`` on curved faces; ``facing.weights`` (P, 3) its barycentric
    coordinates there) or where the fade past the outline has put it out (``facing.fade``
    0), so the contact acts only if the plies come to face each other (a ply laid beside the
    other, or shifted by a typo)."""
    overshoot = np.maximum(0.0, -facing.weights.min(axis=1))
    faces = overshoot <= (MARGIN_CURVED if block.curved else MARGIN)
    if facing.fade is not None:
        faces &= facing.fade > 0.0
    if faces.any():
        return
    points, faced = ("lower", "upper") if block.mirrored else ("upper", "lower")
    warnings.warn(
        f"no contact point of the {points} ply faces the {faced} ply at the start: all "
        f"{len(overshoot)} lie beside its outline, so the contact acts only where the plies "
        "come to face each other. Check where the plies are laid (a ply beside the other, or "
        "shifted)",
        UserWarning,
        stacklevel=4,
    )
