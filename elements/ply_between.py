"""The plies between a pair that are not neighbours (``PlyContact(between=...)``,
elements/ply_contact.py ``join_plies``; docs/theory.md §9.3b, "Plies that are not
neighbours"): a contact of ply k on ply j < k - 1 acts only at the points of ply k that face
none of the plies between them.

Why. The pair's faces start (k - j - 1) h apart, a gap the one-sided penalty was meant to keep
silent while the plies between are there. A penalty gives, though: pressed, each neighbour
pair sinks by the load over its springs, 0.84 h a pair under 0.1 MPa at the automatic penalty
on a [0/0/0] stack, so the 3-on-1 gap of h closed and the pair pushed beside ply 2, which then
carried 0.73 of the load, and the middle ply pulled out of that stack slid at 2 mu (0.73 P)
where Coulomb's 2 mu P holds it. Shielded, the pair's points facing ply 2 carry nothing: the
whole load goes through ply 2, whatever the penalty.

How. At bind the pair binds, for each ply i between, a probe: the same contact (its rule, its
faces and surface, its points' ply) with ply i in place of the other ply, frictionless and
never calibrated, whose facing alone is asked. At each state the pair's facing (every consumer
reads it: loads, energy, tangent, friction, sides, springs) counts a point as touching only
where no probe finds it facing its ply: its projection within the probe's margin of a triangle
(``MARGIN``, ``MARGIN_CURVED`` on curved faces) and, on flat faces, its fade past the outline
above ``HELD_FADE``: the between ply's own contact holds the point with more than half its
weight there. Not w = 1, the start check's test of a point beside the outline
(elements/ply_start.py): plies of one outline have points on it, the mirrored pass's at the
nodes, and a thousandth of a cell past it (w = 0.99986 on the pressed stack's 10-mm cells)
they lost the shield and the pair pushed them (8.1 N of 40 on ply 1's nodes at 5 N/mm). Past
the middle of the fade the pair holds the point, where the neighbour's contact has faded,
rather than leave a hole. The switch is not
smooth: a point passing a between ply's outline while already pressed into ply j takes its
force at once. Such a point has come through a ply's outline it was on, and the pair's force
there is what stops it falling through; a smooth hand-over would need the fade of the pair by
the between ply's, which no reference here measures.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from elements.ply_curved import MARGIN_CURVED
from elements.ply_projection import MARGIN, Facing
from femcore.state import State

__all__ = ["HELD_FADE", "faces_ply", "shielded"]

#: A point past a between ply's outline is shielded while that ply's contact holds it with
#: more than this share of its weight (its fade w, elements/ply_fade.py): the fade's middle.
HELD_FADE = 0.5


def faces_ply(facing: Facing, curved: bool) -> np.ndarray:
    """(P,) bool: the points whose projection lands on the facing ply: within the contact's
    margin of the facing triangle (``facing.weights`` (P, 3) its barycentric coordinates) and,
    on flat faces, short of the fade's middle past the outline (``facing.fade`` (P,) above
    ``HELD_FADE``)."""
    overshoot = np.maximum(0.0, -np.asarray(facing.weights).min(axis=1))
    faces = overshoot <= (MARGIN_CURVED if curved else MARGIN)
    if facing.fade is not None:
        faces &= np.asarray(facing.fade) > HELD_FADE
    return faces


def shielded(probes: tuple[Any, ...], state: State, facing: Facing, curved: bool) -> Facing:
    """``facing`` with its points that face one of the plies between (``probes``, bound
    ``PlyContactBlock``s of the same points on those plies) not touching; the same object where
    there are no probes or no touching point faces one.

    Parameters
    ----------
    probes : tuple of elements.ply_block.PlyContactBlock
        One per ply between, their points the pair's, in the same order.
    state : State
        The state of ``facing``.
    facing : Facing
        The pair's facing at ``state`` (``touching`` (P,) bool).
    curved : bool
        The contact's faces are curved (the margin of ``faces_ply``).
    """
    if not probes or not facing.touching.any():
        return facing
    covered = np.zeros(len(facing.touching), dtype=bool)
    for probe in probes:  # one per ply between: two at most on a four-ply stack
        covered |= faces_ply(probe.facing(state), curved)
    masked = facing.touching & covered
    if not masked.any():
        return facing
    touching = facing.touching & ~covered
    return replace(facing, touching=touching)
