"""The bound ply contact's tangent (``PlyContactBlock.tangent``, elements/ply_block.py): the
exact derivative of the touching points' normal loads on flat facets, the fade's part past
the lower ply's outline (elements/ply_fade.py, elements/ply_fade_hessian.py) and, with
friction, the friction's (elements/ply_friction.py); on curved faces the curved loads' own
(elements/ply_curved_tangent.py, elements/ply_curved_friction.py). The block's methods
``tangent``, ``_fade_tangent`` and ``fade_hessian_at`` call these functions with the block.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from elements import (
    ply_carry,
    ply_curved_friction,
    ply_curved_tangent,
    ply_friction,
    ply_point_tangent,
    ply_projection,
)
from elements.ply_fade import point_fade
from elements.ply_fade_hessian import fade_hessian
from elements.ply_projection import Facing
from femcore.assembly import CellTangent, TangentPart
from femcore.state import State

if TYPE_CHECKING:
    from elements.ply_block import PlyContactBlock

__all__ = ["CURVED_TANGENT", "fade_hessian_at", "fade_tangent", "tangent"]

#: The curved faces' tangent is their loads' exact derivative (elements/ply_curved_tangent.py,
#: elements/ply_curved_friction.py); False: the flat facet's at the curved projection, normal
#: and friction, the tangent before (benchmarks/ply_curved_static.py compares the two).
CURVED_TANGENT = True


def tangent(block: PlyContactBlock, state: State, history: Any = None) -> list[TangentPart]:
    """Exact d(force, moment)/d(u, psi) of the touching points, (t, 6, 6, 6, 6).

    Over z = (p, y_1, y_2, y_3): Hess W = W'' G G^T + W' H with G = (n, -lambda_k n) the
    gradient of g and H its Hessian, from dn/dy_m = -grad phi_m n^T and dlambda_k =
    grad phi_k . (dp - g dn - sum_m lambda_m dy_m): H_pp = 0, H_p,m = -grad phi_m n^T,
    H_k,m = -g (grad phi_k . grad phi_m) n n^T + lambda_m n grad phi_k^T + lambda_k
    grad phi_m n^T. Carried to the nodes by dp = sum_j N_j (du_j - c_j [d_j]x psi_j) and
    dy_k = du_k - c_k [d_k]x psi_k (c = -a for the upper corners, b for the lower ones,
    psi the director's rotation), with the geometric term of the turned offset,
    d(c d x F)/dpsi = c (d F^T - (F . d) I), on each node's psi-psi block. Where a point
    faces an edge or a vertex, H is the search's (elements/ply_projection.py). On the
    curved faces, sparse matrices over all the nodes: elements/ply_curved_tangent.py (the
    normal loads) and elements/ply_curved_friction.py (the friction's).
    """
    if block.curved and CURVED_TANGENT:  # the curved loads' exact derivative
        facing = block._held(state, history)
        curved: list[TangentPart] = [ply_curved_tangent.curved_tangent(block, state, facing)]
        if block._frictional(history):  # a landing anchor moving (ply_landing.py)
            curved.append(
                ply_curved_friction.curved_friction_tangent(block, state, history, facing)
            )
        return curved
    facing = block._held(state, history, second=True)
    if ply_projection.COMPILED:  # the forces made in the pass (ply_point_tangent.py)
        on, law, nodes, offset = block._pair_rows(facing)
    else:
        nodes, forces, _, on, offset, law = block._pair_loads(state, facing)
    g = facing.gap[on]
    n, lam, grad = facing.normal[on], facing.weights[on], facing.gradients[on]
    gradient = np.concatenate([n[:, None, :], -lam[:, :, None] * n[:, None, :]], axis=1)
    fade, fading = point_fade(facing, on)
    # Points facing the closest point q on an edge or at a vertex (ply_projection.py,
    # "Search"): g = +-|p - q|, its Hessian over z given by the search.
    searched = None if facing.hessian is None else facing.hessian[on]
    d = block.offset_directions(state)[nodes]  # (t, 6, 3)
    rows = (g, n, lam, grad, searched, fade, law, d, offset, block.shape[on])
    if ply_projection.COMPILED:
        blocks = ply_point_tangent.point_blocks(*rows, fading=fading)
    else:
        blocks = ply_point_tangent.point_blocks_reference(*rows, forces)
    parts: list[TangentPart] = [CellTangent(nodes, blocks)]
    faded = np.flatnonzero(np.any(fading != 0.0, axis=(1, 2)))
    if faded.size:
        parts.append(block._fade_tangent(state, facing, on[faded], gradient[faded], law, faded))
    if block._frictional(history):
        parts.append(ply_friction.friction_tangent(block, state, history, facing))
    return parts


def fade_tangent(
    block: PlyContactBlock,
    state: State,
    facing: Facing,
    rows: np.ndarray,
    gradient: np.ndarray,
    law: tuple,
    faded: np.ndarray,
) -> CellTangent:
    """The fade's part of the tangent of the points ``rows`` (f,) (elements/ply_fade.py):
    Hess (w W) - w Hess W = W' (dg dw^T + dw dg^T) + W Hess w over z = (p, y_1, y_2,
    y_3, a, b), Hess w in closed form (elements/ply_fade_hessian.py), dg/dz = ``gradient``
    (f, 4, 3); carried to the upper triangle's, the facing triangle's and the outline
    edge's nodes (f, 8), with the turned offsets of the ends' forces W dw/da, W dw/db
    (the other nodes' are in the main part, whose forces hold the fade's)."""
    f = len(rows)
    energy, slope = law[0][faded], law[1][faded]
    fading = point_fade(facing, rows)[1]
    g6 = np.zeros((f, 6, 3))
    g6[:, :4] = gradient
    cross = g6[:, :, :, None, None] * fading[:, None, None, :, :]
    points = slope[:, None, None, None, None] * (cross + np.transpose(cross, (0, 3, 4, 1, 2)))
    ends_nodes, ends_offset = block.fade_ends(facing, rows)
    points += energy[:, None, None, None, None] * block.fade_hessian_at(state, facing, rows)
    nodes = np.column_stack([block.above[rows], block.cells[facing.triangle[rows]], ends_nodes])
    offset = np.column_stack(
        [
            -block.lever * block.upper_offset[rows],
            block.lever * block.corner_offset[facing.triangle[rows]],
            ends_offset,
        ]
    )
    d = block.offset_directions(state)[nodes]  # (f, 8, 3)
    blocks = ply_carry.carry(points, ply_carry.own_maps(offset, d), block.shape[rows])
    forces = energy[:, None, None] * fading[:, 4:]  # on the ends
    ply_carry.add_turned_offsets(blocks, offset[:, 6:], d[:, 6:], forces, 6)
    return CellTangent(nodes, blocks)


def fade_hessian_at(
    block: PlyContactBlock, state: State, facing: Facing, rows: np.ndarray
) -> np.ndarray:
    """Hess w (f, 6, 3, 6, 3), 1/mm^2, of the fade of the points ``rows`` (f,) whose fade
    moves (dw/dz != 0) over z = (p, y_1, y_2, y_3, a, b) (elements/ply_fade_hessian.py)."""
    p, y = block._faces(state)
    assert facing.reach is not None and facing.on_growth is not None
    assert facing.fade_edge is not None
    ends_nodes = block.fade_ends(facing, rows)[0]
    segment = np.stack(
        [
            state.positions[ends_nodes[:, k]]
            + block.outline_offsets[np.maximum(facing.fade_edge[rows], 0), k, None]
            * block.offset_directions(state)[ends_nodes[:, k]]
            for k in range(2)
        ],
        axis=1,
    )
    return fade_hessian(
        p[rows],
        y[facing.triangle[rows]],
        facing.reach[rows],
        facing.on_growth[rows],
        segment,
        block.fade_length,
        None if facing.joined is None else facing.joined[rows],
        block.cuts.lines[facing.triangle[rows]],
        block.cuts.ends[facing.triangle[rows]],
    )
