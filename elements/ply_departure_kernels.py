"""The ply contact's departure slip compiled (elements/ply_departure.py, docs/theory.md §9.3a,
"A point's departure step"): for the points the departure's rule selects (``ply_departure.
leaving``, numpy, kept in one place), each one's places on its anchor's triangle's plane then
and now, theta = pen_0 / (pen_0 + g), its offset from its anchor where it left (its part
across the gap's normal nu now for the points beside a growth's edge, ``ply_departure.
beside_growth``, numpy too) and that offset's length, written with its dissipation into the
accepted history's records: inside the fused history pass (elements/ply_friction_pass.py, the
kernel's plain build run after the anchors are moved), or by one call of its own
(``departed``) where the passes run apart.

The numpy geometry (``ply_departure.departure``) made some twenty numpy calls on a few rows,
at almost every step of a two-ply run whose flange points rest near zero gap and leave and
land in turn: their fixed cost, 0.20 ms of a 0.92-ms history update with 3 points leaving
(benchmarks/ply_departure_cost.py). The kernel does the same IEEE operations in the same
order as the numpy reference (``ply_landing.plane_places`` through ``triangle_frames``:
the cross products as femcore/rotation.py ``cross`` writes them, the norms' sums from the
first term, ``einsum("rki,rki->rk")`` and ``einsum("ri,ri->r")`` as (first + last) +
middle, ``einsum("rk,rki->ri")`` from the first term; no fused multiply-add: numba builds
without fastmath), so the records are the same to the last bit (tests/test_ply_departure_
kernels.py).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from elements import plane_place_kernels as plane
from elements import ply_departure
from elements.kernel_inputs import read_only, writable
from femcore.jit import jit_lanes, prange

if TYPE_CHECKING:
    from elements.ply_block import PlyContactBlock
    from elements.ply_friction import PlyFrictionHistory
    from elements.ply_projection import Facing

__all__ = ["COMPILED", "departed", "departure_slip"]

#: The history pass's departure records by this kernel; False: by the numpy reference
#: (``ply_departure.departure``; benchmarks/ply_departure_cost.py compares the two).
COMPILED = True


def _departure(
    rows,
    triangle,
    before,
    now,
    then,
    face,
    anchor,
    normal,
    aside,
    friction,
    pressing,
    last_pressing,
    last_slip,
    way,
    slipped,
    dissipation,
):
    """Each row's slip up to where it left, written into ``way`` (r,) mm (NaN where its gap
    to its anchor's triangle's plane now is not > 0: not lifted off it, no slip counted) and,
    where ``friction`` > 0, the accepted records of the points ``rows`` (r,) that left
    (``slipped`` last slip + way, mm; ``dissipation`` mu (N_0 + N) / 2 times way, N mm; rows
    not lifted untouched). ``triangle`` (P,) each point's anchor's lower triangle, ``before``
    and ``now`` (m, 3, 3) the lower corners at the last accepted state and now, ``then`` and
    ``face`` (P, 3) the points then and now, ``anchor`` (P, 3) their barycentric anchors,
    ``normal`` (P, 3) their gaps' normals nu now, ``aside`` (r,) bool the rows beside a
    growth's edge (``ply_departure.beside_growth``: their offset's part across nu counted),
    ``pressing`` and ``last_pressing`` (P,) N the normal forces now and then, ``last_slip``
    (P,) mm."""
    for j in prange(rows.shape[0]):
        i = rows[j]
        t = triangle[i]
        # the places of the point then (side 0) and now (side 1) on T's plane then and now:
        # ply_landing.plane_places through ply_projection.triangle_frames, operation by
        # operation (elements/plane_place_kernels.py)
        place0 = np.empty(3)
        place1 = np.empty(3)
        height0 = 0.0
        height1 = 0.0
        for side in range(2):
            corners = before[t] if side == 0 else now[t]
            point = then[i] if side == 0 else face[i]
            n0, n1, n2, _, g00, g01, g02, g10, g11, g12, _, _, _ = plane.frame(corners)
            w0, w1, w2, r0, r1, r2 = plane.place(corners, point, g00, g01, g02, g10, g11, g12)
            height = (n0 * r0 + n2 * r2) + n1 * r1
            if side == 0:
                place0[0], place0[1], place0[2] = w0, w1, w2
                height0 = height
            else:
                place1[0], place1[1], place1[2] = w0, w1, w2
                height1 = height
        gap = height1
        if not gap > 0.0:  # not lifted off T's plane (ply_departure.py's docstring)
            way[j] = np.nan
            continue
        pen0 = -height0
        if not (pen0 >= 0.0 or pen0 != pen0):  # numpy's maximum(-h, 0): NaN and -0.0 kept
            pen0 = 0.0
        theta = pen0 / (pen0 + gap)
        d0 = (place0[0] + theta * (place1[0] - place0[0])) - anchor[i, 0]
        d1 = (place0[1] + theta * (place1[1] - place0[1])) - anchor[i, 1]
        d2 = (place0[2] + theta * (place1[2] - place0[2])) - anchor[i, 2]
        o0 = 0.0
        o1 = 0.0
        o2 = 0.0
        for axis in range(3):
            y0 = before[t, 0, axis] + theta * (now[t, 0, axis] - before[t, 0, axis])
            y1 = before[t, 1, axis] + theta * (now[t, 1, axis] - before[t, 1, axis])
            y2 = before[t, 2, axis] + theta * (now[t, 2, axis] - before[t, 2, axis])
            sum_k = (d0 * y0 + d1 * y1) + d2 * y2
            if axis == 0:
                o0 = sum_k
            elif axis == 1:
                o1 = sum_k
            else:
                o2 = sum_k
        if aside[j]:  # the offset's part across nu (ply_departure.py's docstring)
            nu0, nu1, nu2 = normal[i, 0], normal[i, 1], normal[i, 2]
            along = (nu0 * o0 + nu2 * o2) + nu1 * o1
            o0 = o0 - along * nu0
            o1 = o1 - along * nu1
            o2 = o2 - along * nu2
        length = np.sqrt((o0 * o0 + o1 * o1) + o2 * o2)
        way[j] = length
        if friction > 0.0:
            slipped[i] = last_slip[i] + length
            dissipation[i] = friction * 0.5 * (pressing[i] + last_pressing[i]) * length


_departure_compiled = jit_lanes(_departure)


def _call(y, history, facing, rows, pressing, slipped, dissipation, friction) -> np.ndarray:
    """The kernel over ``rows`` (r,): the ways (r,), NaN where not lifted."""
    sides = history.sides
    way = np.empty(len(rows))
    # each input of the type the history pass's call hands it (one build whoever calls)
    _departure_compiled(
        writable(rows, np.int64),
        writable(history.triangle, np.int64),
        read_only(sides.corners),
        read_only(y),
        read_only(sides.faces),
        read_only(facing.face),
        writable(history.anchor),
        read_only(facing.normal),
        writable(ply_departure.beside_growth(facing, rows), np.bool_),
        float(friction),
        writable(pressing),
        writable(history.pressing),
        writable(history.slip),
        way,
        slipped,
        dissipation,
    )
    return way


def departure_slip(
    block: PlyContactBlock, y: np.ndarray, history: PlyFrictionHistory, facing: Facing
) -> tuple[np.ndarray, np.ndarray]:
    """``ply_departure.departure`` compiled: (rows (r,) int, slip (r,) mm), the same bits."""
    rows = ply_departure.leaving(block, history, facing)
    if len(rows) == 0:
        return rows, np.zeros(0)
    scratch = np.empty(0)
    way = _call(y, history, facing, rows, scratch, scratch, scratch, 0.0)
    lifted = way == way
    return rows[lifted], way[lifted]


def departed(
    block: PlyContactBlock,
    y: np.ndarray,
    history: PlyFrictionHistory,
    facing: Facing,
    pressing: np.ndarray,
    slipped: np.ndarray,
    dissipation: np.ndarray,
) -> None:
    """The accepted history's records of the points that left the lower face in the step
    from ``history`` to the state of ``facing`` (the lower corners ``y`` (m, 3, 3) there,
    mm), written in place: ``slipped`` (P,) mm their last slip plus their slip up to where
    they left, ``dissipation`` (P,) N mm mu (N_0 + N) / 2 times that slip, N = ``pressing``
    (P,) the normal forces now (elements/ply_departure.py; as
    elements/ply_friction_kernels.py wrote them from its numpy reference, the same bits)."""
    rows = ply_departure.leaving(block, history, facing)  # none without friction or sides
    if len(rows):
        _call(y, history, facing, rows, pressing, slipped, dissipation, block.friction)
