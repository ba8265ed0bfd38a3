"""A ply contact's landing points found once per state (elements/ply_landing_kernels.py
``landing``, compiled on the flat faces, numpy's elements/ply_landing.py ``landing`` on the
curved ones, and ``ply_landing.landed``; docs/theory.md §9.3a, "A point's landing step"), kept
on the block with the state's facing and the accepted history they were found from.

The loads, the energy, the tangent and the accepted history of a state each asked for the
landing points at it (one compiled call where points land on flat faces, about 30 numpy calls
on curved ones). Kept for the last (history, facing), the second and later asks from one
history take the first one's answer: the same objects, so the same bits. This serves the energy
beside the loads (an explicit solver's checking steps) and Static's loads, energy and tangent
at one iterate, all from the increment's history. An explicit step asks at one state from two
histories: its commit from the history before the step (where the landing points are found,
once), the next step's loads from the committed history, whose sides touch wherever the facing
touches, so that none lands (measured: none in 584 such asks of the hemisphere-plies Mindlin
[0/90] run at 6 cells, its masks alone). The facing is kept by the block for the bits of the
state's positions and directors (elements/ply_block.py ``facing``, elements/ply_sides.py
``held_facing``), so the same facing object is the same state; the history is matched by
identity and by the bytes of the arrays the landing reads (its anchors' triangles and places,
its points' sides: a caller that edits them in place is answered afresh), and mu by value."""

from __future__ import annotations

from typing import TYPE_CHECKING, overload

import numpy as np

from elements import ply_landing, ply_landing_kernels

if TYPE_CHECKING:
    from elements.ply_block import PlyContactBlock
    from elements.ply_friction import PlyFrictionHistory
    from elements.ply_landing import Landing
    from elements.ply_projection import Facing
    from femcore.state import State

__all__ = ["kept_landing", "landed_at"]


def _bits(history: PlyFrictionHistory) -> bytes:
    """The bytes of what of ``history`` the landing reads besides its sides' faces and
    corners (the block's read-only faces of the state they were accepted at)."""
    sides = history.sides
    kept = [np.asarray(history.triangle).tobytes(), np.asarray(history.anchor).tobytes()]
    if sides is not None:
        kept.append(np.asarray(sides.sides).tobytes())
    return b"".join(kept)


def kept_landing(
    block: PlyContactBlock, state: State, history: PlyFrictionHistory, facing: Facing
) -> tuple[Landing | None, PlyFrictionHistory]:
    """(``ply_landing_kernels.landing``: compiled on the flat faces, numpy's on the curved;
    ``ply_landing.landed`` with it) at ``state`` (``facing``
    there) from ``history``: found once, then kept for that history and facing (module
    docstring). Where no point lands (most steps) the answer is the history itself, found by
    ``landing_rows``' few masks: cheaper than the keep's own check, which copies the history's
    bytes (0.03 against 0.46 ms at 60k points)."""
    rows = ply_landing.landing_rows(block, history, facing)
    if len(rows) == 0:
        return None, history
    kept = getattr(block, "_landing_at", None)
    if (
        kept is not None
        and kept[0] is history
        and kept[1] is facing
        and kept[2] is history.sides
        and kept[3] == block.friction
        and kept[4] == _bits(history)
    ):
        return kept[5], kept[6]
    # compiled on the flat faces (elements/ply_landing_kernels.py: the same bits)
    found = ply_landing_kernels.landing(block, state, history, facing, rows)
    # (``landed`` without a landing found would look for one again)
    landed = history if found is None else ply_landing.landed(block, state, history, facing, found)
    # (on the block as its other per-state caches, elements/ply_block.py ``facing``)
    kept = (history, facing, history.sides, block.friction, _bits(history), found, landed)
    setattr(block, "_landing_at", kept)  # noqa: B010 (not an attribute the block declares)
    return found, landed


@overload
def landed_at(
    block: PlyContactBlock, state: State, history: PlyFrictionHistory, facing: Facing
) -> PlyFrictionHistory: ...


@overload
def landed_at(block: PlyContactBlock, state: State, history: None, facing: Facing) -> None: ...


def landed_at(
    block: PlyContactBlock, state: State, history: PlyFrictionHistory | None, facing: Facing
) -> PlyFrictionHistory | None:
    """``ply_landing.landed`` at ``state`` (``facing`` there), kept (``kept_landing``)."""
    if history is None:
        return None
    return kept_landing(block, state, history, facing)[1]
