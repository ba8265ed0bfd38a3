"""The flat ply contact's nodal loads compiled (``PlyContactBlock.internal_force``,
elements/ply_block.py): each touching point's penalty force w W'(g) dg/dz + W dw/dz on its
upper triangle's corners and its facing triangle's corners, the fade's forces W dw/da,
W dw/db on the ends of the outline's edge nearest it, the friction's tangential force on the
upper corners and the anchor triangle's corners and a stuck point's stick potential's
normal and fade terms on the upper, facing and outline-end nodes and its couple on the facing
corners (elements/ply_friction.py ``friction_loads``, ``stick_couple``; facing an edge or a
vertex, on the point too: ``edge_couples``, computed before the pass (elements/
ply_edge_couple_kernels.py) and added in it), their moments
c d x F on the directors, and their sums at the nodes, in one serial pass per block and call
(docs/theory.md, the ply contact section).

Their numpy reference is ``PlyContactBlock._pair_loads``, ``_end_loads``,
``ply_friction.friction_loads`` and the ``np.bincount`` sums of ``internal_force``, taken
with ``ply_projection.COMPILED = False``. The pass does the same IEEE operations in the same
order (each product in numpy's order, the penalty law's branches as ``penalty_law`` writes
them, no fused multiply-add: numba builds without fastmath), and sums each node's terms in the
order ``np.bincount`` adds them, the outline's ends first, then the pairs' and the friction's
terms, each list point by point from 0.0: so it gives the same forces and moments to the last
bit (tests/test_ply_kernels.py). Two numbers come in from numpy: the cube g^3 of the ramp's
energy and delta^2 (numpy's power of an array uses its own vectorised pow, whose last bit
libm's ``pow`` does not always give), both as ``penalty_law`` computes them. The pass is
serial (a scatter over the few hundred touching points of a block, no race to guard, the same
bits on any thread count); numpy spent its time there in the per-call overhead of some sixty
calls on small arrays (benchmarks/ply_facing.py). The scatter's helpers (``_add``,
``_add_upper``, ``_add_ends``) are spliced into the pass (``jit.inline``): called, each call
took the reference counts of the arrays it is handed, some ten calls a point, and the pass
took 75-84 us a call on the two-ply hemisphere's blocks against 44-45 spliced (one thread,
load 7; the same forces and moments to the bit on 3000 of the run's states).
"""

from __future__ import annotations

import numpy as np

from elements import ply_edge_couple_kernels, ply_penalty
from elements.kernel_inputs import read_only
from femcore.jit import inline, lanes

__all__ = ["ply_loads"]


@lanes
def _law(gap, cube, stiffness, smoothing, smoothing_squared, bilateral):
    """``ply_projection.penalty_law``'s energy (N mm) and dW/dg (N) of one point, in its
    operations' order; ``cube`` numpy's min(gap, 0)^3; with ``bilateral`` (and smoothing 0)
    the frozen active set's k/2 g^2 at either sign of g (elements/ply_active_set.py
    ``bilateral_law``)."""
    g = gap if (bilateral or gap < 0.0 or gap != gap) else 0.0
    if smoothing == 0.0:
        return 0.5 * stiffness * (g * g), stiffness * g
    if g <= -smoothing:
        shifted = g + 0.5 * smoothing
        energy = 0.5 * stiffness * (shifted * shifted) + stiffness * smoothing_squared / 24.0
        return energy, stiffness * shifted
    return -stiffness * cube / (6.0 * smoothing), -stiffness * (g * g) / (2.0 * smoothing)


@inline
def _add(sums, moments, node, lever, direction, f0, f1, f2):
    """Add the force (f0, f1, f2) N and its moment ``lever`` d x f (d = ``direction`` (n, 3)
    at ``node``) to row ``node`` of ``sums`` and ``moments`` (n, 3)."""
    d0, d1, d2 = direction[node, 0], direction[node, 1], direction[node, 2]
    sums[node, 0] += f0
    sums[node, 1] += f1
    sums[node, 2] += f2
    moments[node, 0] += lever * (d1 * f2 - d2 * f1)
    moments[node, 1] += lever * (d2 * f0 - d0 * f2)
    moments[node, 2] += lever * (d0 * f1 - d1 * f0)


@inline
def _add_upper(sums, moments, r, shape, above, upper_offset, lever, direction, f0, f1, f2):
    """Add point ``r``'s force (f0, f1, f2) N on its upper triangle's corners ``above[r]``,
    each its shape function's share ``shape[r, j]``, with their moments (``_add``, the signed
    offset -``upper_offset``: the point lies at x - upper_offset d)."""
    for j in range(3):
        s = shape[r, j]
        _add(
            sums,
            moments,
            above[r, j],
            lever * -upper_offset[r, j],
            direction,
            s * f0,
            s * f1,
            s * f2,
        )


@inline
def _add_ends(
    sums, moments, r, t, scale, fade_gradient, fade_edge, outline_nodes, outline_offsets,
    cells, corner_offset, lever, direction,
):  # fmt: skip
    # point r's fade forces scale dw/da, scale dw/db on the ends of the outline's edge nearest
    # it, where its fade moves with them (PlyContactBlock.fade_ends), else on its facing
    # triangle t's first two corners (where the fade's gradient is zero)
    moving = False
    if outline_nodes.shape[0] > 0 and fade_edge[r] >= 0:
        for a in range(6):
            for c in range(3):
                if fade_gradient[r, a, c] != 0.0:
                    moving = True
    for e in range(2):
        if moving:
            node = outline_nodes[fade_edge[r], e]
            offset = lever * outline_offsets[fade_edge[r], e]
        else:
            node = cells[t, e]
            offset = lever * corner_offset[t, e]
        _add(
            sums,
            moments,
            node,
            offset,
            direction,
            scale * fade_gradient[r, 4 + e, 0],
            scale * fade_gradient[r, 4 + e, 1],
            scale * fade_gradient[r, 4 + e, 2],
        )


@lanes
def _loads(
    on,
    cube,
    gap,
    normal,
    weights,
    triangle,
    fade,
    fade_gradient,
    fade_edge,
    stiffness,
    smoothing,
    smoothing_squared,
    shape,
    above,
    cells,
    upper_offset,
    corner_offset,
    lever,
    direction,
    outline_nodes,
    outline_offsets,
    sliding,
    anchor_triangle,
    friction_force,
    anchor,
    lift,
    stored,
    plane,
    anchor_offset,
    gradients,
    turn,
    bilateral,
    force,
    moment,
):
    """Sum the loads (module docstring) into ``force`` and ``moment`` (n, 3), zero on entry.

    on (t,) the touching points' rows, cube (t,) their min(g, 0)^3; per point (P rows): gap,
    normal (3,), weights (3,), triangle, fade, fade_gradient (6, 3), fade_edge (-1: none),
    stiffness, shape (3,), above (3,), upper_offset (3,); per lower triangle: cells (3,),
    corner_offset (3,); direction (n, 3) the faces' unit directions; outline_nodes and
    outline_offsets (E, 2) the outline's edges' ends; sliding (f,) the stuck or sliding
    points' rows, anchor_triangle, friction_force (3,), anchor (3,), lift, stored and
    anchor_offset r (3,) per point (P rows: elements/ply_friction.py ``Sliding``), plane (P,)
    the stuck points facing a plane and gradients (P, 3, 3) the facing's for their couple
    (``ply_friction.stick_couple``), turn (P, 4, 3) the couple on (p, y_1, y_2, y_3) of the
    stuck points facing an edge or a vertex (``ply_friction.edge_couples``, 0 elsewhere;
    (0, 4, 3) where there are none); bilateral: the frozen set's law k/2 g^2 at either sign of
    g (``_law``; with smoothing 0)."""
    n = force.shape[0]
    turned = turn.shape[0] > 0  # no rows: no stuck point faces an edge or a vertex (adds 0)
    ends_force = np.zeros((n, 3))
    ends_moment = np.zeros((n, 3))
    pair_force = np.zeros((n, 3))
    pair_moment = np.zeros((n, 3))
    for i in range(on.shape[0]):
        r = on[i]
        t = triangle[r]
        energy, slope = _law(gap[r], cube[i], stiffness[r], smoothing, smoothing_squared, bilateral)
        _add_ends(
            ends_force, ends_moment, r, t, energy, fade_gradient, fade_edge, outline_nodes,
            outline_offsets, cells, corner_offset, lever, direction,
        )  # fmt: skip
        pressed = fade[r] * slope
        n0, n1, n2 = normal[r, 0], normal[r, 1], normal[r, 2]
        face0 = pressed * n0 + energy * fade_gradient[r, 0, 0]
        face1 = pressed * n1 + energy * fade_gradient[r, 0, 1]
        face2 = pressed * n2 + energy * fade_gradient[r, 0, 2]
        _add_upper(
            pair_force, pair_moment, r, shape, above, upper_offset, lever, direction,
            face0, face1, face2,
        )  # fmt: skip
        for k in range(3):
            scaled = -pressed * weights[r, k]
            _add(
                pair_force,
                pair_moment,
                cells[t, k],
                lever * corner_offset[t, k],
                direction,
                scaled * n0 + energy * fade_gradient[r, 1 + k, 0],
                scaled * n1 + energy * fade_gradient[r, 1 + k, 1],
                scaled * n2 + energy * fade_gradient[r, 1 + k, 2],
            )
    for i in range(sliding.shape[0]):
        r = sliding[i]
        t = anchor_triangle[r]
        f0, f1, f2 = friction_force[r, 0], friction_force[r, 1], friction_force[r, 2]
        # a stuck point's stick potential beyond F: lift dg/dz + stored dw/dz (0: sliding)
        up, kept = lift[r], stored[r]
        n0, n1, n2 = normal[r, 0], normal[r, 1], normal[r, 2]
        _add_upper(
            pair_force, pair_moment, r, shape, above, upper_offset, lever, direction,
            (f0 + (up * n0 + kept * fade_gradient[r, 0, 0])) + (turn[r, 0, 0] if turned else 0.0),
            (f1 + (up * n1 + kept * fade_gradient[r, 0, 1])) + (turn[r, 0, 1] if turned else 0.0),
            (f2 + (up * n2 + kept * fade_gradient[r, 0, 2])) + (turn[r, 0, 2] if turned else 0.0),
        )  # fmt: skip
        for k in range(3):
            a = -anchor[r, k]
            _add(
                pair_force,
                pair_moment,
                cells[t, k],
                lever * corner_offset[t, k],
                direction,
                a * f0,
                a * f1,
                a * f2,
            )
        facing = triangle[r]
        # the couple c_k = (n . r)(F . grad phi_k), F = k_t s, on a stuck point's facing corners
        along = (n0 * anchor_offset[r, 0] + n1 * anchor_offset[r, 1]) + n2 * anchor_offset[r, 2]
        for k in range(3):
            couple = 0.0
            if plane[r]:
                g0, g1, g2 = gradients[r, k, 0], gradients[r, k, 1], gradients[r, k, 2]
                couple = along * ((f0 * g0 + f1 * g1) + f2 * g2)
            scaled = -up * weights[r, k] + couple
            _add(
                pair_force,
                pair_moment,
                cells[facing, k],
                lever * corner_offset[facing, k],
                direction,
                (scaled * n0 + kept * fade_gradient[r, 1 + k, 0])
                + (turn[r, 1 + k, 0] if turned else 0.0),
                (scaled * n1 + kept * fade_gradient[r, 1 + k, 1])
                + (turn[r, 1 + k, 1] if turned else 0.0),
                (scaled * n2 + kept * fade_gradient[r, 1 + k, 2])
                + (turn[r, 1 + k, 2] if turned else 0.0),
            )
        _add_ends(
            pair_force, pair_moment, r, facing, kept, fade_gradient, fade_edge, outline_nodes,
            outline_offsets, cells, corner_offset, lever, direction,
        )  # fmt: skip
    for node in range(n):
        for c in range(3):
            force[node, c] = (0.0 + ends_force[node, c]) + pair_force[node, c]
            moment[node, c] = (0.0 + ends_moment[node, c]) + pair_moment[node, c]


#: ``turn`` where no stuck point faces an edge or a vertex: the pass adds 0.0 in its place
#: (x + 0.0 is x, and -0.0 + 0.0 adds to a node's sum as -0.0 does)
NO_TURN = np.zeros((0, 4, 3))


def _contiguous(array, dtype=float):
    return np.ascontiguousarray(array, dtype=dtype)


def ply_loads(
    block, state, facing, sliding=None, anchor=None, law: str = "ramp"
) -> tuple[np.ndarray, np.ndarray]:
    """The flat ply contact's nodal forces and moments at ``state``, compiled: the same bits
    as ``PlyContactBlock.internal_force``'s numpy reference (module docstring).

    Parameters
    ----------
    block : PlyContactBlock
        The bound contact (flat faces).
    state : State
        The state of the facing.
    facing : Facing
        ``block.facing(state)``.
    sliding : Sliding, optional
        The friction's return mapping at ``state`` (elements/ply_friction.py); None: no
        friction.
    anchor : (P, 3) float, optional
        The friction history's anchors' barycentric coordinates (with ``sliding``).
    law : str
        The touching points' normal law: "ramp", the block's smoothed penalty; "plain", k/2
        min(g, 0)^2; "bilateral", k/2 g^2 (the laws of elements/ply_active_set.py
        ``ReachFacing``, whose numpy reference is ``ActiveSetPlyContactBlock``'s
        ``_pair_loads``).

    Returns
    -------
    force : (n, 3) float
        N, on the block's body's nodes.
    moment : (n, 3) float
        N mm, on their directors (dW/dpsi).
    """
    on = np.flatnonzero(facing.touching)
    smoothing = block.smoothing if law == "ramp" else 0.0
    # as ply_projection.penalty_law computes them (numpy's vectorised power), at the points
    # the ramp's energy reads them (ply_penalty.ramp_cubes)
    cube = ply_penalty.ramp_cubes(np.minimum(facing.gap[on], 0.0), smoothing)
    count = len(block.above)
    if sliding is None or anchor is None:
        rows = np.zeros(0, dtype=np.int64)
        triangle, friction, anchors = np.zeros(count, dtype=np.int64), np.zeros((count, 3)), None
        lift = stored = np.zeros(count)
        plane = np.zeros(count, dtype=np.bool_)
        offset = np.zeros((count, 3))
        turn = NO_TURN
    else:
        rows = np.flatnonzero(sliding.stuck | sliding.sliding)
        triangle, friction, anchors = sliding.triangle, sliding.force, anchor
        lift, stored, offset = sliding.lift, sliding.stored, sliding.offset
        edge = None if facing.on_edge is None else sliding.stuck & facing.on_edge
        plane = sliding.stuck if edge is None else sliding.stuck ^ edge  # stuck, not on_edge
        # the couple of the stuck points facing an edge or a vertex, from numpy on the same
        # rows as ply_friction.friction_loads (the same bits); count_nonzero costs a quarter
        # of np.any on these few hundred flags
        turn = NO_TURN
        if edge is not None and np.count_nonzero(edge):
            # ply_friction.edge_couples' rows among ``rows`` are these stuck points (stuck
            # points are among ``rows``): their couples written once, in place
            turn = np.zeros((count, 4, 3))
            at = np.flatnonzero(edge)
            turn[at] = ply_edge_couple_kernels.edge_couples(
                facing, block._faces(state)[1], block.cuts, at, sliding.offset, sliding.force
            )
    force = np.empty((block.n_nodes, 3))
    moment = np.empty((block.n_nodes, 3))
    outline_nodes = block.outline_nodes.reshape(-1, 2)
    _loads(
        on,
        _contiguous(cube),
        _contiguous(facing.gap),
        _contiguous(facing.normal),
        _contiguous(facing.weights),
        _contiguous(facing.triangle, np.int64),
        _contiguous(facing.fade),
        _contiguous(facing.fade_gradient),
        _contiguous(facing.fade_edge, np.int64),
        _contiguous(block.stiffness),
        float(smoothing),
        float(smoothing**2),
        _contiguous(block.shape),
        _contiguous(block.above, np.int64),
        _contiguous(block.cells, np.int64),
        _contiguous(block.upper_offset),
        _contiguous(block.corner_offset),
        float(block.lever),
        read_only(block.offset_directions(state)),  # as kept: one build (kernel_inputs.py)
        _contiguous(outline_nodes, np.int64),
        _contiguous(block.outline_offsets.reshape(-1, 2)),
        rows,
        _contiguous(triangle, np.int64),
        _contiguous(friction),
        _contiguous(np.zeros((count, 3)) if anchors is None else anchors),
        _contiguous(lift),
        _contiguous(stored),
        _contiguous(plane, np.bool_),
        _contiguous(offset),
        _contiguous(facing.gradients),
        _contiguous(turn),
        law == "bilateral",
        force,
        moment,
    )
    return force, moment
