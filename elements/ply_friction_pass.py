"""The flat ply contact's friction history after an accepted step in one compiled call
(elements/ply_friction_kernels.py ``updated_history``; elements/ply_friction.py, docs/theory.md
§9.3a): the return mapping at the new state from the history before it (unless a kept one
serves), the anchors moved and re-expressed (``_moved``), the records of the points that left
the face (elements/ply_departure_kernels.py, the points ``ply_departure.leaving`` selects)
and the next loads' return mapping from the new history, back to back on the calling thread,
where ``updated_history`` made three compiled calls (four with the departure's) with their
arguments' conversions and outputs between them.

Each stage runs its kernel's own plain build (femcore/jit.py ``plain_part``; IEEE, no
fastmath), so the history and both mappings are the same to the last bit as the three calls'
(tests/test_ply_friction_pass.py); the dissipation's sum stays numpy's (its pairwise order).
With ``select`` the pass also chooses the points that left the face (``_leaving``: the rows
and flags of ``ply_departure.leaving`` and ``beside_growth``, the same), where numpy's masks
chose them before each call (tests/test_ply_friction_pass.py, tests/test_ply_edge_crossing.py).
"""

from __future__ import annotations

from dataclasses import fields
from typing import TYPE_CHECKING

import numpy as np

from elements import ply_departure, ply_departure_kernels, ply_friction_kernels, ply_landing
from elements.kernel_inputs import read_only, writable
from elements.ply_friction import Sliding
from elements.ply_friction_kernels import _sliding_arrays
from elements.ply_sides import TOUCHING, PlySides
from femcore.jit import lanes, plain_part

if TYPE_CHECKING:
    from elements.ply_block import PlyContactBlock
    from elements.ply_projection import Facing

__all__ = ["history_pass"]

# the stages' loops on the calling thread: the kernels' own plain builds, each loop whole
# (part 0 of 1, ``plain_part``), so the same bits and one build each
_mapping_here = plain_part(ply_friction_kernels._return_mapping_compiled)
_moved_here = plain_part(ply_friction_kernels._moved_compiled)
_departure_here = plain_part(ply_departure_kernels._departure_compiled)


def _history(
    touching, gap, stiffness, smoothing, fade, bounded, normal_law, potential, friction,
    last_triangle, last_anchor, face, normal, y, fresh, facing_triangle, facing_weights,
    gradients, last_slip, last_pressing, force, slip, stuck, sliding, pressing, offset,
    mapped_triangle, spring, lift, stored, triangle, anchor, slipped, dissipation,
    next_force, next_slip, next_stuck, next_sliding, next_pressing, next_offset,
    next_triangle, next_spring, next_lift, next_stored, leaving, before, then, aside, way,
    tilt_floor, select, sides, flagged, on_edge, on_growth, joined,
):  # fmt: skip
    """The mapping from the last history (where ``fresh``; else its arrays given), the new
    history's triangle, anchor, slipped and dissipation with the departure's records of the
    points ``leaving`` (elements/ply_departure_kernels.py; the lower corners ``before`` and
    the points ``then`` at the last accepted state, ``aside`` those beside a growth's edge,
    ``way`` their slips; ``tilt_floor`` ply_landing.TILT), then the mapping from them (the
    ``next_`` arrays), each written in place (``history_pass``). Where ``select``, the rows
    ``leaving`` and ``aside`` are chosen here instead (``_leaving``, from the last ``sides``
    (P,) int8 and, where ``flagged``, the facing's ``on_edge``, ``on_growth`` and ``joined``
    (P,) bool)."""
    if select:
        leaving, aside, way = _leaving(
            last_triangle, touching, sides, face, flagged, on_edge, on_growth, joined
        )
    if fresh:
        _mapping_here(
            touching, gap, stiffness, smoothing, fade, bounded, normal_law, potential,
            friction, last_triangle, last_anchor, face, normal, y, force, slip, stuck,
            sliding, pressing, offset, mapped_triangle, spring, lift, stored, np.int64(0),
            np.int64(1),
        )  # fmt: skip
    _moved_here(
        touching, facing_triangle, facing_weights, gradients, gap, normal, y, friction,
        tilt_floor, slip, stuck, sliding, pressing, offset, spring, last_triangle, last_anchor,
        last_slip, last_pressing, triangle, anchor, slipped, dissipation, np.int64(0),
        np.int64(1),
    )  # fmt: skip
    if leaving.shape[0]:
        _departure_here(
            leaving, last_triangle, before, y, then, face, last_anchor, normal, aside, friction,
            pressing, last_pressing, last_slip, way, slipped, dissipation, np.int64(0), np.int64(1),
        )  # fmt: skip
    _mapping_here(
        touching, gap, stiffness, smoothing, fade, bounded, normal_law, potential, friction,
        triangle, anchor, face, normal, y, next_force, next_slip, next_stuck, next_sliding,
        next_pressing, next_offset, next_triangle, next_spring, next_lift, next_stored,
        np.int64(0), np.int64(1),
    )  # fmt: skip


@lanes
def _leaving(last_triangle, touching, sides, face, flagged, on_edge, on_growth, joined):
    """(rows (r,) int, aside (r,) bool, way (r,) scratch): ``ply_departure.leaving``'s rows in
    its order (anchored then, touching then by their side, not touching now, their point now
    finite) and ``ply_departure.beside_growth``'s flags of them (none where not
    ``flagged``). The test written in the loop, not a helper called per point: numba's call
    of a compiled helper with array arguments (their reference counts at each call) took
    this pass 41 us on 384 points, 2.4 written here."""
    count = touching.shape[0]
    leaves = np.empty(count, dtype=np.bool_)
    total = 0
    for i in range(count):
        leaves[i] = (
            last_triangle[i] >= 0
            and not touching[i]
            and sides[i] == TOUCHING
            and np.isfinite(face[i, 0])
            and np.isfinite(face[i, 1])
            and np.isfinite(face[i, 2])
        )
        total += leaves[i]
    rows = np.empty(total, dtype=np.int64)
    aside = np.zeros(total, dtype=np.bool_)
    j = 0
    for i in range(count):
        if leaves[i]:
            rows[j] = i
            if flagged:
                aside[j] = on_edge[i] and on_growth[i] and not joined[i]
            j += 1
    return rows, aside, np.empty(total)


_history_compiled = lanes(_history)
# no point leaving: the departure's inputs of their types, read-only
_NO_CORNERS, _NO_POINTS = np.zeros((0, 3, 3)), np.zeros((0, 3))
_NO_CORNERS.setflags(write=False)
_NO_POINTS.setflags(write=False)
_NO_SIDES, _NO_FLAGS = np.zeros(0, dtype=np.int8), np.zeros(0, dtype=np.bool_)
_NO_FLAGS.setflags(write=False)


def history_pass(
    block: PlyContactBlock,
    facing: Facing,
    y: np.ndarray,
    last: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    kept: Sliding | None,
    leaving: np.ndarray | None = None,
    sides: PlySides | None = None,
    select: bool = False,
    bounded: np.ndarray | None = None,
    loads: tuple | None = None,
) -> tuple[Sliding, tuple[np.ndarray, ...], Sliding]:
    """The friction's history pass of a flat ply contact block at a facing (module
    docstring).

    Parameters
    ----------
    block : PlyContactBlock
        Its penalties, smoothing, mu and stick law.
    facing : Facing
        The facing at the new state (with its fade).
    y : (m, 3, 3) float
        The lower corners at the new state, mm.
    last : (triangle (P,) int, anchor (P, 3), slip (P,) mm, pressing (P,) N)
        The history before the step.
    kept : Sliding or None
        The mapping at this facing from that history where one is kept (None: made here).
    leaving : (r,) int or None
        The points whose departure's records the pass writes (``ply_departure.leaving``;
        None: none), from the last history's ``sides`` (its faces and lower corners).
    select : bool
        The pass chooses those points itself (``ply_departure.leaving``'s rule and
        ``beside_growth``'s flags, the same rows), from ``sides``; ``leaving`` is then not
        read (a step where none leaves pays no numpy mask).
    bounded : (P,) float or None
        numpy's min(g, 0) of the facing's gaps, mm, where the caller has it (None: made here).
    loads : tuple or None
        The next step's loads' inputs and outputs (elements/ply_commit_pass.py
        ``loads_inputs``, made with ``bounded``): the loads are then written in the same call,
        from the mapping it makes for them (None: the history alone).

    Returns
    -------
    sliding : Sliding
        The mapping from the last history (``kept`` where given).
    moved : (triangle (P,) int, anchor (P, 3), slipped (P,) mm, dissipation (P,) N mm)
        The new history's arrays and each point's dissipation.
    following : Sliding
        The mapping from the new history (the next step's loads').
    """
    count = len(block.above)
    fresh = kept is None
    mapped = (
        _sliding_arrays(count)
        if kept is None
        else tuple(getattr(kept, field.name) for field in fields(kept))
    )
    following = _sliding_arrays(count)
    moved = (
        np.empty(count, dtype=np.int64),
        np.empty((count, 3)),
        np.empty(count),
        np.empty(count),
    )
    last_triangle, last_anchor, last_slip, last_pressing = last
    chosen = _NO_SIDES  # the last sides where the pass chooses the rows
    if block.friction <= 0.0:  # ply_departure.leaving's rule: none leaves without friction
        select, leaving = False, None
    if sides is not None and (select or (leaving is not None and len(leaving))):
        before, then = sides.corners, sides.faces
        chosen = writable(sides.sides, np.int8) if select else chosen
    else:
        before, then, select = _NO_CORNERS, _NO_POINTS, False
    if select or leaving is None:
        leaving = np.zeros(0, dtype=np.int64)
    edge_flags = (facing.on_edge, facing.on_growth, facing.joined)
    flagged = all(flag is not None for flag in edge_flags)
    # the rows beside a growth's edge: their slip across the gap's normal (ply_departure.py)
    aside = ply_departure.beside_growth(facing, leaving)
    flag = block.stick != "penalty"  # the normal law's spring and potential (flat faces)
    if bounded is None:  # numpy's, for its signed zeros (ply_penalty.py)
        bounded = np.minimum(facing.gap, 0.0)
    # each input of the type ``_mapped`` and ``updated_history`` hand their kernels
    arguments = (
        read_only(facing.touching, np.bool_), read_only(facing.gap), writable(block.stiffness),
        float(block.smoothing), read_only(facing.fade), bounded, flag, flag,
        float(block.friction), writable(last_triangle, np.int64), writable(last_anchor),
        read_only(facing.face), read_only(facing.normal), read_only(y), fresh,
        read_only(facing.triangle, np.int64), read_only(facing.weights),
        read_only(facing.gradients), writable(last_slip), writable(last_pressing), *mapped,
        *moved, *following, writable(leaving, np.int64), read_only(before), read_only(then),
        writable(aside, np.bool_), np.empty(len(leaving)), ply_landing.TILT, select, chosen,
        flagged, *(read_only(f, np.bool_) if flagged else _NO_FLAGS for f in edge_flags),
    )  # fmt: skip
    if loads is None:
        _history_compiled(*arguments)
    else:  # the next loads in the same call (elements/ply_commit_pass.py)
        from elements.ply_commit_pass import _history_loads

        _history_loads(arguments, loads)
    sliding = Sliding(*mapped) if kept is None else kept
    return sliding, moved, Sliding(*following)
