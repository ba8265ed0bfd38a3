"""The flat ply contact's friction compiled (elements/ply_friction.py, docs/theory.md §9.3a):
the return mapping at a state (``friction_state``: each touching point's normal force and
stick spring, its anchor on the lower face, its tangential offset s, stick or slip and the
tangential force) and the history after an accepted step (``updated_history``: the sliding
anchors moved to the friction limit and re-expressed on the facing triangle, the slip and the
dissipation), each one pass over the points.

Their numpy reference is ``ply_friction.friction_state`` and ``ply_friction.updated_history``
(the same signatures), taken with ``ply_projection.COMPILED = False``. The passes do the same
IEEE operations in the same order (the penalty law's branches as ``penalty_law`` writes them,
numpy's sums of three terms in its order: ``np.sum`` and ``np.linalg.norm`` over a row from the
first term, ``einsum("pk,pki->pi")`` likewise, ``einsum("pki,pi->pk")`` as (first + last) +
middle; no fused multiply-add: numba builds without fastmath), so they give the same numbers
to the last bit (tests/test_ply_kernels.py). The stick spring before the fade's w and its slope
(``ply_friction.stick_spring`` for ``stick="normal law"``, k_p and 0 for "penalty") in the
same pass, from numpy's min(g, 0) (its signed zeros; tests/test_ply_stick_spring_pass.py):
before, numpy's ``stick_spring`` on the touching points' masked rows cost about 39 us of the
pass's 70 (benchmarks/forming_step_overhead.py); a stuck point's potential's ``lift`` and
``stored`` as ``ply_friction.stick_potential`` computes them (|s|^2 / 2 as 0.5 times numpy's
row sum), and the dissipation's sum over the points from ``np.sum`` (numpy's pairwise order).
Each point is independent: the same bits on any thread count.

A step maps twice at one state: the history committed after the step maps from the history
before it, the next step's loads from the new one, which differs where points slide, touch
anew or leave (not the same inputs: tests/test_ply_kernels.py). The history's update makes the
second mapping right after the new anchors (the return mapping's kernel on the new history),
and keeps it on the block; ``friction_state`` returns it where its history (unedited), facing
and penalties are those (a step's next loads), and maps afresh otherwise: the Python and
numpy glue of one call a step fewer per block (benchmarks/forming_step_overhead.py).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from elements import ply_departure, ply_departure_kernels, ply_friction, ply_landing
from elements.kept_bits import same_bits
from elements.kernel_inputs import read_only, writable
from elements.ply_friction import PlyFrictionHistory, Sliding
from elements.ply_sides import PlySides
from femcore.jit import jit_lanes, prange

if TYPE_CHECKING:
    from elements.ply_block import PlyContactBlock
    from elements.ply_projection import Facing
    from femcore.state import State

__all__ = ["friction_state", "updated_history"]

#: ``updated_history``'s mapping, moved anchors and next mapping in one compiled call
#: (elements/ply_friction_pass.py, the same bits), else three.
FUSED = True
#: That call chooses the points that left the face itself (``ply_departure.leaving``'s rows
#: and ``beside_growth``'s flags, the same), else numpy's masks hand it them.
SELECT_IN_PASS = True


def _return_mapping(
    touching,
    gap,
    stiffness,
    smoothing,
    fade,
    bounded,
    normal_law,
    potential,
    friction,
    anchor_triangle,
    anchor_weights,
    face,
    normal,
    y,
    force,
    slip,
    stuck,
    sliding,
    pressing,
    offset,
    triangle,
    spring,
    lift,
    stored,
):
    """``ply_friction.friction_state``'s arrays (``Sliding``) of the points, written into
    force, slip, offset (P, 3), stuck, sliding (P,) bool, pressing, spring, lift, stored (P,),
    triangle (P,) int: from their touching flags, gaps (mm), penalties k_p (N/mm), the fade w,
    ``bounded`` numpy's min(g, 0) of the gaps (P,) mm (its signed zeros), ``normal_law``
    whether the stick spring is the normal law's W''(g) (``ply_friction.stick_spring``, with
    its slope W'''(g), and times w in k_t; else k_p, slope 0, no w), ``potential`` whether a
    stuck point's spring derives from its potential (``ply_friction.stick_potential``), the
    history's anchors (``anchor_triangle`` (P,), -1: none; ``anchor_weights`` (P, 3)), the
    points p ``face`` (P, 3), their facing normals (P, 3) and the lower corners y (m, 3, 3);
    ``smoothing`` delta, mm, ``friction`` mu."""
    for i in prange(gap.shape[0]):
        on = touching[i]
        normal_force = 0.0
        k_t = 0.0
        unfaded = 0.0
        slope = 0.0
        if on:
            k = stiffness[i]
            g = gap[i] if (gap[i] < 0.0 or gap[i] != gap[i]) else 0.0
            if smoothing == 0.0:
                law = k * g
            elif g <= -smoothing:
                law = k * (g + 0.5 * smoothing)
            else:
                law = -k * (g * g) / (2.0 * smoothing)
            normal_force = -law * fade[i]
            # the stick spring before w and its slope, as ``ply_friction.stick_spring`` writes
            # them (``penalty_law``'s W'' from numpy's min(g, 0); the slope's -k_p / delta)
            unfaded = k
            if normal_law:
                if smoothing == 0.0:
                    unfaded = k if gap[i] <= 0.0 else 0.0
                else:
                    b = bounded[i]
                    unfaded = k if b <= -smoothing else (-k * b) / smoothing
                    if gap[i] < 0.0 and gap[i] > -smoothing:
                        slope = -k / smoothing
            k_t = unfaded * fade[i] if normal_law else unfaded
        pressing[i] = normal_force
        spring[i] = k_t
        anchored = on and anchor_triangle[i] >= 0
        t = anchor_triangle[i] if anchored else 0
        triangle[i] = t
        r0 = r1 = r2 = 0.0
        if anchored:
            w0, w1, w2 = anchor_weights[i, 0], anchor_weights[i, 1], anchor_weights[i, 2]
            a0 = (w0 * y[t, 0, 0] + w1 * y[t, 1, 0]) + w2 * y[t, 2, 0]
            a1 = (w0 * y[t, 0, 1] + w1 * y[t, 1, 1]) + w2 * y[t, 2, 1]
            a2 = (w0 * y[t, 0, 2] + w1 * y[t, 1, 2]) + w2 * y[t, 2, 2]
            r0, r1, r2 = face[i, 0] - a0, face[i, 1] - a1, face[i, 2] - a2
        n0, n1, n2 = normal[i, 0], normal[i, 1], normal[i, 2]
        along = (r0 * n0 + r1 * n1) + r2 * n2
        s0, s1, s2 = r0 - along * n0, r1 - along * n1, r2 - along * n2
        length = np.sqrt((s0 * s0 + s1 * s1) + s2 * s2)
        limit = friction * normal_force
        held = anchored and k_t * length <= limit
        slides = anchored and not held
        if held:
            scale = k_t
        elif slides:
            scale = limit / (length if length > 0 else 1.0)
        else:
            scale = 0.0
        force[i, 0], force[i, 1], force[i, 2] = scale * s0, scale * s1, scale * s2
        slip[i, 0], slip[i, 1], slip[i, 2] = s0, s1, s2
        offset[i, 0], offset[i, 1], offset[i, 2] = r0, r1, r2
        stuck[i] = held
        sliding[i] = slides
        if held and potential:
            half = 0.5 * ((s0 * s0 + s1 * s1) + s2 * s2)
            lift[i] = fade[i] * (slope * half)
            stored[i] = unfaded * half
        else:
            lift[i] = 0.0
            stored[i] = 0.0


_return_mapping_compiled = jit_lanes(_return_mapping)


def friction_state(
    block: PlyContactBlock,
    state: State,
    history: PlyFrictionHistory | None,
    facing: Facing | None = None,
) -> Sliding:
    """``ply_friction.friction_state`` compiled (module docstring) on flat faces with a
    history and friction; otherwise that numpy reference itself."""
    facing = block.facing(state) if facing is None else facing
    if history is None or block.friction <= 0.0 or block.curved or facing.fade is None:
        return ply_friction.friction_state(block, state, history, facing)
    kept = _kept_mapping(block, history, facing)
    if kept is not None:
        return kept
    _, y = block._faces(state)
    return _mapped(block, facing, y, history.triangle, history.anchor)


def _kept_mapping(block: PlyContactBlock, history: PlyFrictionHistory, facing: Facing):
    """The mapping ``updated_history`` kept for ``history`` (unedited since) at ``facing``
    and the block's penalties now, made with the history itself: the same bits; else None."""
    kept = getattr(block, "_next_sliding", None)
    if (
        kept is not None
        and kept[0] is history
        and kept[1] is facing
        and _same(kept[2], block)
        and kept[4] == _bits(history)  # not edited in place since
    ):
        return kept[3]
    return None


def _mapped(block: PlyContactBlock, facing: Facing, y, triangle, anchor) -> Sliding:
    """The return mapping's kernel at a facing (its lower corners y (m, 3, 3)) from anchors on
    the lower triangles ``triangle`` (P,) int (-1: none) at barycentric ``anchor`` (P, 3):
    ``friction_state``'s and the one ``updated_history`` keeps, the same inputs either way."""
    arrays = _sliding_arrays(len(block.above))
    # each input of the type the block's own call hands it (the facing and faces read-only,
    # as the block keeps them; the penalties and the history writable): one build whoever
    # calls, no copy or view on the block's path (kernel_inputs.py)
    _return_mapping_compiled(
        read_only(facing.touching, np.bool_),
        read_only(facing.gap),
        writable(block.stiffness),
        float(block.smoothing),
        read_only(facing.fade),
        np.minimum(facing.gap, 0.0),  # numpy's, for its signed zeros (ply_penalty.py)
        block.stick != "penalty",
        block.stick != "penalty",  # flat faces here (ply_friction.stick_potential)
        float(block.friction),
        writable(triangle, np.int64),
        writable(anchor),
        read_only(facing.face),
        read_only(facing.normal),
        read_only(y),
        *arrays,
    )
    return Sliding(*arrays)


def _sliding_arrays(count: int) -> tuple[np.ndarray, ...]:
    """``Sliding``'s arrays for ``count`` points, uninitialised: force, slip (P, 3), stuck,
    sliding (P,) bool, pressing (P,), offset (P, 3), triangle (P,) int, spring, lift, stored
    (P,)."""
    return (
        np.empty((count, 3)),
        np.empty((count, 3)),
        np.empty(count, dtype=np.bool_),
        np.empty(count, dtype=np.bool_),
        np.empty(count),
        np.empty((count, 3)),
        np.empty(count, dtype=np.int64),
        np.empty(count),
        np.empty(count),
        np.empty(count),
    )


def _moved(
    touching,
    facing_triangle,
    facing_weights,
    gradients,
    gap,
    normal,
    y,
    friction,
    tilt_floor,
    slip,
    stuck,
    sliding,
    pressing,
    offset,
    spring,
    last_triangle,
    last_anchor,
    last_slip,
    last_pressing,
    triangle,
    anchor,
    slipped,
    dissipation,
):
    """``ply_friction.updated_history``'s arrays, written into triangle (P,) int, anchor (P, 3),
    slipped (P,) mm and dissipation (P,), N mm (each point's mu N_mid times its slip, which
    numpy sums): from the facing's touching flags, triangles, weights (P, 3), gradients (P, 3,
    3), gaps and normals (P, 3), the lower corners y (m, 3, 3), mu ``friction``,
    ``tilt_floor`` (ply_landing.TILT: an argument, so that no cached build keeps it), the return
    mapping's slip, offset (P, 3), stuck, sliding, pressing and spring (P,), and the last
    history's triangle, anchor, slip and pressing."""
    for i in prange(gap.shape[0]):
        s0, s1, s2 = slip[i, 0], slip[i, 1], slip[i, 2]
        length = np.sqrt((s0 * s0 + s1 * s1) + s2 * s2)
        divisor = length if length > 0 else 1.0
        u0, u1, u2 = s0 / divisor, s1 / divisor, s2 / divisor
        k_t = spring[i] if spring[i] > 0 else 1.0
        held = friction * pressing[i] / k_t
        slid = length - held if sliding[i] else 0.0
        t0 = -offset[i, 0] + slid * u0
        t1 = -offset[i, 1] + slid * u1
        t2 = -offset[i, 2] + slid * u2
        # the facing triangle's unit normal (ply_projection.triangle_frames)
        t = facing_triangle[i]
        e0, e1, e2 = y[t, 1, 0] - y[t, 0, 0], y[t, 1, 1] - y[t, 0, 1], y[t, 1, 2] - y[t, 0, 2]
        f0, f1, f2 = y[t, 2, 0] - y[t, 0, 0], y[t, 2, 1] - y[t, 0, 1], y[t, 2, 2] - y[t, 0, 2]
        c0 = e1 * f2 - e2 * f1
        c1 = e2 * f0 - e0 * f2
        c2 = e0 * f1 - e1 * f0
        twice = np.sqrt((c0 * c0 + c1 * c1) + c2 * c2)
        m0, m1, m2 = c0 / twice, c1 / twice, c2 / twice
        n0, n1, n2 = normal[i, 0], normal[i, 1], normal[i, 2]
        g = gap[i]
        w0, w1, w2 = t0 + g * n0, t1 + g * n1, t2 + g * n2
        tilt = (m0 * n0 + m1 * n1) + m2 * n2
        # numpy's where(|tilt| > TILT, rise / tilt, rise * tilt / TILT**2)
        rise = (m0 * w0 + m1 * w1) + m2 * w2
        if abs(tilt) > tilt_floor:
            along = rise / tilt
        else:
            along = rise * tilt / (tilt_floor**2)
        w0, w1, w2 = w0 - along * n0, w1 - along * n1, w2 - along * n2
        if stuck[i]:
            triangle[i] = last_triangle[i]
            for k in range(3):
                anchor[i, k] = last_anchor[i, k]
        elif sliding[i]:
            triangle[i] = t if touching[i] else -1
            for k in range(3):
                d = gradients[i, k]
                anchor[i, k] = facing_weights[i, k] + ((d[0] * w0 + d[2] * w2) + d[1] * w1)
        elif touching[i]:
            triangle[i] = t
            for k in range(3):
                anchor[i, k] = facing_weights[i, k]
        else:
            triangle[i] = -1
            for k in range(3):
                anchor[i, k] = np.nan
        slipped[i] = last_slip[i] + slid
        dissipation[i] = friction * 0.5 * (pressing[i] + last_pressing[i]) * slid


_moved_compiled = jit_lanes(_moved)


def updated_history(
    block: PlyContactBlock,
    state: State,
    history: PlyFrictionHistory | None,
    facing: Facing | None = None,
    sides: PlySides | None = None,
) -> PlyFrictionHistory | None:
    """``ply_friction.updated_history`` compiled (module docstring) on flat faces with
    friction; otherwise that numpy reference itself (``facing`` and ``sides`` as there)."""
    if history is None or block.friction <= 0.0 or block.curved:
        return ply_friction.updated_history(block, state, history, facing, sides)
    facing = block.facing(state) if facing is None else facing
    if facing.fade is None:
        return ply_friction.updated_history(block, state, history, facing, sides)
    if FUSED:  # the three passes below in one compiled call (ply_friction_pass.py)
        from elements import ply_commit_pass, ply_projection
        from elements.ply_friction_pass import history_pass

        _, y = block._faces(state)
        last = (history.triangle, history.anchor, history.slip, history.pressing)
        kept = _kept_mapping(block, history, facing)
        # the departure's records in the pass, its rows chosen there too
        # (elements/ply_departure_kernels.py)
        compiled = ply_departure_kernels.COMPILED
        select = compiled and SELECT_IN_PASS
        leaving = ply_departure.leaving(block, history, facing) if compiled and not select else None
        # the next step's loads in the same call (elements/ply_commit_pass.py)
        bounded = np.minimum(facing.gap, 0.0)  # numpy's, for its signed zeros
        made = None
        if ply_commit_pass.LOADS_IN_PASS and ply_projection.COMPILED:
            made = ply_commit_pass.loads_inputs(block, state, facing, bounded)
        sliding, moved, following = history_pass(
            block, facing, y, last, kept, leaving, history.sides, select, bounded,
            None if made is None else made[0],
        )  # fmt: skip
        return _kept_history(
            block, history, facing, sides, sliding, moved, following, y, departed=compiled,
            loads=None if made is None else made[1:],
        )  # fmt: skip
    sliding = friction_state(block, state, history, facing)
    _, y = block._faces(state)
    count = len(block.above)
    triangle = np.empty(count, dtype=np.int64)
    anchor = np.empty((count, 3))
    slipped = np.empty(count)
    dissipation = np.empty(count)
    _moved_compiled(
        np.ascontiguousarray(facing.touching, dtype=np.bool_),
        np.ascontiguousarray(facing.triangle, dtype=np.int64),
        np.ascontiguousarray(facing.weights, dtype=float),
        np.ascontiguousarray(facing.gradients, dtype=float),
        np.ascontiguousarray(facing.gap, dtype=float),
        np.ascontiguousarray(facing.normal, dtype=float),
        np.ascontiguousarray(y, dtype=float),
        float(block.friction),
        ply_landing.TILT,
        sliding.slip,
        sliding.stuck,
        sliding.sliding,
        sliding.pressing,
        sliding.offset,
        sliding.spring,
        np.ascontiguousarray(history.triangle, dtype=np.int64),
        np.ascontiguousarray(history.anchor, dtype=float),
        np.ascontiguousarray(history.slip, dtype=float),
        np.ascontiguousarray(history.pressing, dtype=float),
        triangle,
        anchor,
        slipped,
        dissipation,
    )
    # the next step's loads ask for the return mapping at this state from the new history:
    # made here, as ``friction_state`` makes it (``_mapped``: the same bits); by the mapping's
    # own kernel, not a per-point helper both kernels call: numba's call of one with two
    # dozen array arguments, even spliced (inline="always"), took the mapping from 6.7 to 41
    # us on 384 points
    following = _mapped(block, facing, y, triangle, anchor)
    moved = (triangle, anchor, slipped, dissipation)
    return _kept_history(block, history, facing, sides, sliding, moved, following, y)


def _kept_history(
    block, history, facing, sides, sliding, moved, following, y, departed=False, loads=None
):
    """The new history from ``moved`` (triangle, anchor, slipped, dissipation) and the
    mapping ``sliding``'s pressing, the points that left the face (at the lower corners ``y``)
    given their slip up to where they left (elements/ply_departure.py), the dissipation
    summed by numpy (``departed``: those records already written by the pass);
    ``following``, the mapping from it, kept on the block for the next step's loads (module
    docstring), as long as the facing and the penalties are these; with it the next loads
    (force, moment) (n, 3) the pass made from it, where given (``loads``;
    elements/ply_commit_pass.py), or None."""
    triangle, anchor, slipped, dissipation = moved
    if not departed:
        _departures(block, y, history, facing, sliding.pressing, slipped, dissipation)
    dissipated = history.dissipated + float(np.sum(dissipation))
    updated = PlyFrictionHistory(triangle, anchor, slipped, sliding.pressing, dissipated, sides)
    block._next_sliding = (updated, facing, _law(block), following, _bits(updated))
    block._next_loads = None if loads is None else (updated, *loads)
    return updated


def _departures(block, y, history, facing, pressing, slipped, dissipation) -> None:
    """The departure's records written into ``slipped`` and ``dissipation`` (``_kept_history``)
    by its kernel (elements/ply_departure_kernels.py) or, with that module's ``COMPILED``
    False, from the numpy reference (ply_departure.py ``departure``), the same bits."""
    if ply_departure_kernels.COMPILED:
        ply_departure_kernels.departed(block, y, history, facing, pressing, slipped, dissipation)
        return
    rows, way = ply_departure.departure(block, y, history, facing)
    if len(rows):  # (slid 0 there before)
        slipped[rows] = history.slip[rows] + way
        force = block.friction * 0.5 * (pressing[rows] + history.pressing[rows])
        dissipation[rows] = force * way


def _bits(history: PlyFrictionHistory) -> bytes:
    """The bytes of a history's arrays: a kept mapping is served only to the history it was
    made with, unedited (matched by identity and these; its arrays stay writable, as the
    kernels' other inputs of their kind, so that each kernel keeps one build)."""
    # (``tobytes`` gives the C order's bytes of any layout; a list, not a generator: 6.2 ->
    # 3.3 us on 384 points, six a step)
    return b"".join(
        [
            np.asarray(history.triangle).tobytes(),
            np.asarray(history.anchor).tobytes(),
            np.asarray(history.slip).tobytes(),
            np.asarray(history.pressing).tobytes(),
        ]
    )


def _law(block: PlyContactBlock) -> tuple:
    """What of the block a return mapping reads besides its history and facing: the
    penalties (their values, a copy: the array may be edited in place), the smoothing, mu
    and the stick spring's law."""
    return (np.array(block.stiffness, dtype=float), block.smoothing, block.friction, block.stick)


def _same(kept: tuple, block: PlyContactBlock) -> bool:
    """``_law``'s of a kept mapping and the block's now agree: the penalties the same bits
    (``same_bits``, with no copy of them: 1-2 us a check against 11-13 for a copy compared by
    numpy on the hemisphere's 384 points, four checks a step; penalties held in another
    dtype than the copy's float64 are not the same, and the mapping is made again, the same
    numbers), the smoothing, mu and the stick spring's law equal."""
    return same_bits(kept[0], np.asarray(block.stiffness)) and kept[1:] == (
        block.smoothing,
        block.friction,
        block.stick,
    )
