"""The flat ply contact's facing at a new state begun in one compiled call
(``PlyContactBlock.facing``, elements/ply_block.py; docs/theory.md §9.3a): the faces' unit
directions (the plies' nodal normals with ``faces="normal"``, elements/ply_face_points.py
``offset_normals``), the contact points p and the offset lower corners y (``face_points``), each
point's direction toward its own ply (``offset_toward``) and the kept search lists' moves
(elements/ply_search.py ``_moves``), where the facing of a state not seen before made them in
four compiled calls (three with faces along the directors) with the block's caches, numpy's
conversions and the search's own glue between them.

Each stage is its kernel itself, called from the pass in the same order on the same values, so
the directions, faces, ``toward`` and moves are the same to the last bit as the four calls'
(tests/test_ply_facing_front.py); the search then decides from the moves as it did
(``FacingSearch.near``'s ``moves``). The block's kept directions and faces are set as
``offset_directions`` and ``_faces`` set them, so that the state's later calls find them.

``begun`` serves the block's facing at a state whose faces are not kept yet (an explicit
step's committed history, each step), on flat faces with the compiled kernels and the kept
search lists; elsewhere it answers None and the facing takes the four calls.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from elements import ply_face_points, ply_projection, ply_search
from elements.jit import lanes
from elements.kept_bits import same_bits
from elements.kernel_inputs import writable

if TYPE_CHECKING:
    from elements.ply_block import PlyContactBlock
    from femcore.state import State

__all__ = ["FUSED", "begun", "toward"]

#: The new state's directions, faces, ``toward`` and the lists' moves in one compiled call
#: (False: the four calls, the same bits).
FUSED = True

_normals = ply_face_points._normals
_points = ply_face_points._points
_toward = ply_face_points._toward
_moves = ply_search._moves_compiled


@lanes
def _front(
    x, normals, triangles, directions, above, upper_offset, shape, cells, corner_offset, p, y,
    toward, listed, epoch, reach, origin, shift_then, moved_then, shift, drift,
):  # fmt: skip
    """The directions (written where ``normals``, else given), p (P, 3), y (m, 3, 3),
    ``toward`` (P, 3) and, where ``listed`` and every coordinate is finite, the lists' moves
    (``shift`` (3,), ``drift`` (P,)); returns (whether p and y are finite, M: NaN where not
    measured)."""
    if normals:
        _normals(x, triangles, directions)
    finite = _points(x, directions, above, upper_offset, shape, cells, corner_offset, p, y)
    _toward(directions, above, upper_offset, shape, toward)
    moved = np.nan
    if listed and finite:
        moved = _moves(y, epoch, reach, p, origin, shift_then, moved_then, shift, drift)
    return finite, moved


# no kept lists: the moves' inputs of their types, unread
_NO_CORNERS, _NO_ROWS, _NO_POINTS = np.zeros((0, 3, 3)), np.zeros((0, 3)), np.zeros(0)


def toward(block: PlyContactBlock, state: State) -> np.ndarray:
    """(P, 3) each contact point's direction from the lower ply to its own at ``state``,
    sum_j N_j a_j d_j, mm (the facing's ``toward``; compiled, the same bits as numpy's
    einsum: elements/ply_face_points.py)."""
    d = block.offset_directions(state)
    if ply_projection.COMPILED:
        return ply_face_points.offset_toward(d, block.above, block.upper_offset, block.shape)
    return np.einsum("pj,pj,pji->pi", block.shape, block.upper_offset, d[block.above])


def begun(
    block: PlyContactBlock, state: State
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
    """(p (P, 3), near (P, K) int, y (m, 3, 3), toward (P, 3)) at ``state`` from one compiled
    call (module docstring), the block's kept directions and faces set; None where the
    facing takes the chained calls (not flat, not compiled, candidates by the centroids'
    tree, the faces kept already, or ``FUSED`` False). A ValueError where p or y are not
    finite, as ``_faces`` raises it."""
    if not (FUSED and ply_projection.COMPILED) or block.curved or block.candidates is not None:
        return None
    x, directors = state.positions, state.directors
    kept = getattr(block, "_faces_at", None)
    if kept is not None and same_bits(kept[0], x) and same_bits(kept[1], directors):
        return None
    normals = block.along_normals
    count, m = len(block.above), len(block.cells)
    directions = np.empty((block.n_nodes, 3)) if normals else writable(directors)
    p, y, ahead = np.empty((count, 3)), np.empty((m, 3, 3)), np.empty((count, 3))
    search = block.search
    lists = search.lists_for(count, m)
    shift, drift = np.empty(3), np.empty(count)
    if lists is None:
        listed = (_NO_CORNERS, _NO_ROWS, _NO_ROWS, _NO_POINTS)
    else:
        listed = (lists.epoch, lists.origin, lists.shift, lists.moved)
    ints, floats = np.int64, np.float64
    finite, moved = _front(
        writable(x), normals, np.ascontiguousarray(block._own_triangles, dtype=ints),
        directions, np.ascontiguousarray(block.above, dtype=ints),
        np.ascontiguousarray(block.upper_offset, dtype=floats),
        np.ascontiguousarray(block.shape, dtype=floats),
        np.ascontiguousarray(block.cells, dtype=ints),
        np.ascontiguousarray(block.corner_offset, dtype=floats), p, y, ahead,
        lists is not None, listed[0], search.reach, *listed[1:], shift, drift,
    )  # fmt: skip
    if normals:  # kept as ``offset_directions`` keeps them (read-only)
        directions.setflags(write=False)
        block._directions_at = (x.copy(), directions)
    p, y = block._kept_faces(state, p, y, bool(finite))
    moves = None if lists is None else (float(moved), shift, drift)
    return p, search.near(p, y, moves), y, ahead  # (read-only, as kept)
