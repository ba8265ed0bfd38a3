"""Each ply contact point's side of the lower face, kept from one accepted state to the next: a
point that comes to lie deep behind a triangle of the lower face without passing through its
front does not touch it (docs/theory.md §9.3a, "The side kept").

Why. A point faces the nearest triangle of the lower face (elements/ply_projection.py), a rule
of the state alone. Where the lower ply is folded, two of its sheets can lie on either side of
a point: the nearest changes from the sheet the point lies in front of (g > 0) to one it lies
behind (g < 0), and its gap jumps between them. Measured on the fibrous [0/90] two-ply
hemisphere at 24 cells (docs/hemisphere_plies.md, "The holder's bore"): points between the
sheets of the lower ply's fold passed from +1.94 to -1.25 mm and from +0.95-1.05 to
-0.73-0.83 mm within ten steps, their penalty energy (+1.8 to +4.0 N mm each) appearing with
no work, and the run stopped on its energy balance at 99.5 % of the stroke. The point did not
pass through the sheet it came to face; the fold's other sheet came to be nearer. So the
contact keeps, per point, what it was at the last accepted state (``CLEAR``: not touching,
``TOUCHING``, ``BEHIND``: kept off a face it lies behind), and a point that was clear touches
now only down to a gap of -depth (the two faces' half thicknesses, elements/ply_block.py): one
deeper came there from behind the face, not through it, and is ``BEHIND``. It stays off while
its gap is negative, whichever triangle faces it, and comes back when its gap is >= 0 (it lies
in front of the face it faces, W(g) = 0 there), so its energy neither appears nor vanishes at a
gap away from zero. A point that touched at the last accepted state keeps touching at any
depth (an explicit step moves a point by far less than the plies' thickness; a Newton iterate
may press one deep into the layer it touches, and is held from the last increment's sides).

Only a point that cannot have come through the face's front is kept off: one whose motion
against the face it faces since the last accepted state (its contact point's displacement
less that of the face's point under it, from the faces kept with the sides) is shorter than
its depth less the plies' half thicknesses. To pass from in front of a face (g >= 0) to a gap
g < 0 a point moves at least |g| against it. An explicit step moves a point by micrometres
and the rule keeps the fold's points off; a Newton iterate of a Static increment may push a
clear point millimetres through the ply below, and it touches there (kept off, an increment
converged with one ply pushed through the other: a clear point 1 mm above a clamped ply,
pushed by 30 N in one increment, ended 3.5 mm through it).

The history of the codes that track a contact: the node-to-segment search of Hallquist,
Goudreau and Benson (CMAME 51 (1985) 107) finds a slave node's segment from the last step's by
a walk over neighbours (its incremental search), and LS-DYNA releases a node whose
penetration passes a share of the shell's thickness (its PENMAX) instead of pushing it through;
here the side, not the segment, is kept, and the release holds until the point is back in
front of the face, where the release of LS-DYNA would find it again at full depth.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from elements import ply_side_masks

if TYPE_CHECKING:
    from elements.ply_block import PlyContactBlock
    from elements.ply_projection import Facing
    from femcore.state import State

__all__ = [
    "BEHIND",
    "CLEAR",
    "TOUCHING",
    "PlySides",
    "behind",
    "held",
    "held_facing",
    "accepted_sides",
    "initial_sides",
    "sides_at",
    "sides_of",
]

#: A point's side at an accepted state: not touching, touching, kept off a face it lies behind.
CLEAR, TOUCHING, BEHIND = 0, 1, 2


@dataclass(frozen=True)
class PlySides:
    """Each point's side (``CLEAR``, ``TOUCHING`` or ``BEHIND``) at the last accepted state
    and the faces there: the history of a frictionless ply contact, and a frictional one's
    ``sides``.

    sides : (P,) int8
    faces : (P, 3) float
        The contact points p at that state, mm.
    corners : (m, 3, 3) float
        The offset lower corners y at that state, mm.
    """

    sides: np.ndarray
    faces: np.ndarray
    corners: np.ndarray

    @property
    def dissipated(self) -> float:
        """No friction, no dissipation, N mm."""
        return 0.0


def initial_sides(block: PlyContactBlock) -> PlySides:
    """``TOUCHING`` where a point touches in the reference state, else ``CLEAR`` (a point laid
    deep in a face at the start touches it: the model put it there), with the reference's
    faces."""
    reference = block._reference
    touching = np.asarray(block.facing(reference).touching, dtype=bool)
    faces, corners = block._faces(reference)
    return PlySides(np.where(touching, TOUCHING, CLEAR).astype(np.int8), faces, corners)


def behind(block: PlyContactBlock, state: State, facing: Facing, last: PlySides) -> np.ndarray:
    """(P,) bool: the points kept off the face at ``state`` (``facing`` there), from their
    sides and faces ``last`` at the last accepted state (module docstring): clear then, deeper
    now than the block's depth (the plies' half thicknesses, mm) and moved against the face
    by less than that depth below the face, or kept off then and still behind a face."""
    gap = facing.gap
    depth = block.depth
    if ply_side_masks.COMPILED:  # one pass for the flags (elements/ply_side_masks.py)
        entered, off, count = ply_side_masks.entered_off(gap, last.sides, depth, CLEAR, BEHIND)
        if count == 0:  # (most steps: no point came deeper than the depth)
            return off
    else:
        entered = (last.sides == CLEAR) & (gap < -depth)
    rows = np.flatnonzero(entered)
    if len(rows):
        faces, corners = block._faces(state)
        triangle, weights = facing.triangle[rows], facing.weights[rows]
        under = np.einsum("rk,rki->ri", weights, corners[triangle] - last.corners[triangle])
        moved = np.linalg.norm(faces[rows] - last.faces[rows] - under, axis=1)
        entered[rows] = moved < -gap[rows] - depth
    return (gap < 0.0) & ((last.sides == BEHIND) | entered)


def sides_at(
    block: PlyContactBlock,
    state: State,
    facing: Facing,
    last: PlySides,
    off: np.ndarray | None = None,
) -> PlySides:
    """Each point's side at ``state`` (``facing`` there), accepted, from its sides ``last`` at
    the last accepted state, with the faces at ``state``; ``off`` the points ``behind`` keeps
    off there, where already known."""
    if off is None:
        off = behind(block, state, facing, last)
    sides = facing.touching.astype(np.int8)  # TOUCHING 1 where touching, else CLEAR 0
    sides[off] = BEHIND
    faces, corners = block._faces(state)
    return PlySides(sides, faces, corners)


def held(block: PlyContactBlock, state: State, facing: Facing, last: PlySides | None) -> Facing:
    """``facing`` with the points kept off (``behind``) not touching; ``facing`` itself where
    none of its touching points is kept off (or no side is known: ``last`` None)."""
    return _held_by(facing, None if last is None else behind(block, state, facing, last))


def held_facing(block: PlyContactBlock, state: State, history: Any, second: bool = False) -> Facing:
    """``block.facing(state, second)`` with the points that ``history``'s sides keep off their
    faces not touching (``held``); the same object where none is. Kept for the last facing
    and sides, so that a step's calls (loads, energy, friction, history) share one object, as
    they share the facing (the friction's kept return mapping is matched by identity)."""
    facing = block.facing(state, second)
    sides = sides_of(history)
    kept = block._held_at
    if kept is not None and kept[0] is facing and kept[1] is sides:
        return kept[2]
    off = None if sides is None else behind(block, state, facing, sides)
    found = _held_by(facing, off)
    # the flags ``behind`` gave, which ``accepted_sides`` takes at this facing and sides
    block._held_at = (facing, sides, found, off)
    return found


def _held_by(facing: Facing, off: np.ndarray | None) -> Facing:
    """``held``'s answer from the flags ``behind`` gave (None: no side known)."""
    if off is None:
        return facing
    off = off & facing.touching
    if not off.any():
        return facing
    touching = facing.touching & ~off
    touching.setflags(write=False)
    return replace(facing, touching=touching)


def accepted_sides(block: PlyContactBlock, state: State, history: Any) -> tuple[Facing, PlySides]:
    """(``held_facing(block, state, history)``, each point's side at ``state`` accepted:
    ``sides_at`` there from ``history``'s sides), the flags ``behind`` gave the held facing
    taken again. The held facing is kept for the new sides too: from sides accepted at this
    facing a point is kept off where it was (``BEHIND`` now where ``behind`` held it; a point
    clear now does not touch at this facing), so the next step's calls at this state find
    the same object (the friction's mapping made for it at the commit among them)."""
    facing = held_facing(block, state, history)
    last = sides_of(history)
    kept = block._held_at
    if last is None or kept is None:
        raise ValueError("accepted_sides: the history holds no sides (a PlySides expected)")
    # held_facing's flags at this facing and these sides (None where it found the facing
    # kept from a commit at this state: then made again)
    off = kept[3] if kept[3] is not None else behind(block, state, kept[0], last)
    # (the held facing's touching points are the raw facing's less those kept off: the sides
    # are the same from either)
    accepted = sides_at(block, state, facing, last, off)
    block._held_at = (kept[0], accepted, facing, None)
    return facing, accepted


def sides_of(history: Any) -> PlySides | None:
    """The sides a ply contact's history holds (a ``PlySides``, or a friction history's
    ``sides``); None for none (a caller that keeps no history)."""
    if isinstance(history, PlySides):
        return history
    return getattr(history, "sides", None)
