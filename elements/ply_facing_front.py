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

The choice in the same call (``CHOSEN``): where the facing is asked without the gap's
Hessian and ``closest_facing`` would take elements/ply_facing_whole.py's two calls, the pass
goes on from the lists' moves to ``FacingSearch.near``'s own tests (M <= s EPOCH_SHARE, every
drift < (1 - ROUNDING) s / 2, in its comparisons, NaN failing them) and, where they keep the
lists as they are (the search's answer is then the kept candidates, with nothing of the
search changed), makes the whole facing's first call (``_choice``: the candidates' planes,
the choice, the chosen arrays, the closest points' fans) on them in the same call; the
facing is then finished as the two calls finish it (``finished_facing``: numpy's arctan2 of
the fans' angles, which stays numpy's for its bits, and the second call). Where the lists
do not serve (a refresh, a new epoch: about one facing in a hundred on the two-ply
hemisphere), the pass stops after the moves and the search decides from them as before. So
a made facing is two compiled calls with one numpy arctan2 between, where it was three, and
the glue between the front's call and the choice's (the moves handed to the search, the
search's tests, ``closest_facing``'s and ``whole_facing``'s checks and conversions) is gone;
the same bits (tests/test_ply_facing_front.py: the Facing, the kept faces and lists against
the chained calls, the choice made exactly where numpy's tests keep the lists, on and one
ulp off both bounds, for the first and the last point, and NaN).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from elements import ply_face_points, ply_projection, ply_search
from elements.kept_bits import same_bits
from elements.kernel_inputs import writable
from elements.ply_facing_whole import (
    _choice_compiled,
    _face_inputs,
    chosen_outputs,
    finished_facing,
)
from elements.ply_projection import INSIDE, MARGIN, Facing
from femcore.jit import SMALL_LOOP, lanes

if TYPE_CHECKING:
    from elements.ply_block import PlyContactBlock
    from femcore.state import State

__all__ = ["CHOSEN", "FUSED", "begun", "toward"]

#: The new state's directions, faces, ``toward`` and the lists' moves in one compiled call
#: (False: the four calls, the same bits).
FUSED = True
#: With ``FUSED``, the facing's first call (the choice, elements/ply_facing_whole.py) in that
#: same call where the kept lists serve (False: two calls, the same bits).
CHOSEN = True

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


# the pass's own name of ``_front`` (a patch of ``_front``, which counts its calls, is no
# compiled function)
_front_pass = _front


@lanes
def _front_chosen(
    x, normals, triangles, directions, above, upper_offset, shape, cells, corner_offset, p, y,
    toward, listed, epoch, reach, origin, shift_then, moved_then, shift, drift, epoch_bound,
    bound, faces, corners, near, outline, margin, inside, has_cuts, cut, lines, ends, nodes,
    fans, best, on_edge, closest, on_cut, segment, along, triangle, chosen_gap, normal, lam,
    chosen_gradients, chosen_reach, overshoot, reached, turned, on_q, rise, run, plane_normal,
    plane_gap, plane_lam,
):  # fmt: skip
    """``_front`` over kept lists (``listed`` True, ``epoch`` .. ``moved_then``) and, where they
    serve as they are (p and y finite, M <= ``epoch_bound``, every drift < ``bound``:
    ``FacingSearch.near``'s tests, which then hand back the kept candidates ``near``), the
    facing's first call (elements/ply_facing_whole.py ``_choice``, its outputs ``best`` ..
    ``plane_lam``) on them with ``toward``. ``faces`` and ``corners``: read-only views of
    ``p`` and ``y``, which the choice reads (the types ``whole_facing`` hands it, so that the
    choice's build and its stages' are the ones already made, not a second build of each for
    writable arrays: some 5 s of CPU on an empty cache; ``listed`` given, not the literal
    True, for the same reason). Returns (whether p and y are finite, M, whether the choice
    was made)."""
    finite, moved = _front_pass(
        x, normals, triangles, directions, above, upper_offset, shape, cells, corner_offset, p,
        y, toward, listed, epoch, reach, origin, shift_then, moved_then, shift, drift,
    )  # fmt: skip
    if not finite or not moved <= epoch_bound:  # (NaN too)
        return finite, moved, False
    for i in range(drift.shape[0]):
        if not drift[i] < bound:
            return finite, moved, False
    _choice_compiled(
        faces, corners, near, outline, margin, inside, has_cuts, cut, lines, ends, toward,
        listed, nodes, fans, best, on_edge, closest, on_cut, segment, along, triangle,
        chosen_gap, normal, lam, chosen_gradients, chosen_reach, overshoot, reached, turned,
        on_q, rise, run, plane_normal, plane_gap, plane_lam,
    )  # fmt: skip
    return finite, moved, True


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
    block: PlyContactBlock, state: State, choose: bool = False
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | Facing | None:
    """(p (P, 3), near (P, K) int, y (m, 3, 3), toward (P, 3)) at ``state`` from one compiled
    call (module docstring), the block's kept directions and faces set; None where the
    facing takes the chained calls (not flat, not compiled, candidates by the centroids'
    tree, the faces kept already, or ``FUSED`` False). With ``choose`` (a facing without the
    gap's Hessian), where the kept lists serve as they are and ``CHOSEN``, the facing's
    choice made in that same call and the Facing itself, finished as
    elements/ply_facing_whole.py finishes it (``choosing``). A ValueError where p or y are
    not finite, as ``_faces`` raises it."""
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
    front = (
        writable(x), normals, np.ascontiguousarray(block._own_triangles, dtype=ints),
        directions, np.ascontiguousarray(block.above, dtype=ints),
        np.ascontiguousarray(block.upper_offset, dtype=floats),
        np.ascontiguousarray(block.shape, dtype=floats),
        np.ascontiguousarray(block.cells, dtype=ints),
        np.ascontiguousarray(block.corner_offset, dtype=floats), p, y, ahead,
    )  # fmt: skip
    arrays = None
    if lists is not None and choose and choosing(block):
        face = _face_inputs(block.topology, block.outline, block.cuts, m)
        arrays = chosen_outputs(count, face.fans.shape[1])
        finite, moved, chosen = _front_chosen(
            *front, True, lists.epoch, search.reach, *listed[1:], shift, drift,
            ply_search.EPOCH_SHARE * search.skin,
            0.5 * (1.0 - ply_search.ROUNDING) * search.skin, _viewed(p), _viewed(y),
            np.ascontiguousarray(lists.near, dtype=ints), face.outline, MARGIN, INSIDE,
            face.has_cuts, face.cut, face.lines, face.cut_ends, face.nodes, face.fans, *arrays,
        )  # fmt: skip
        arrays = arrays if chosen else None
    else:
        finite, moved = _front(
            *front, lists is not None, listed[0], search.reach, *listed[1:], shift, drift
        )
    if normals:  # kept as ``offset_directions`` keeps them (read-only)
        directions.setflags(write=False)
        block._directions_at = (x.copy(), directions)
    p, y = block._kept_faces(state, p, y, bool(finite))
    if arrays is not None:  # the kept lists as they are: ``FacingSearch.near``'s answer
        given = (block.tolerance, block.outline, block.depth, block.fade_length)
        found = (block.topology, block.outline_tree, block.cuts)
        return finished_facing(p, y, *given, *found, arrays)
    moves = None if lists is None else (float(moved), shift, drift)
    return p, search.near(p, y, moves), y, ahead  # (read-only, as kept)


def _viewed(array: np.ndarray) -> np.ndarray:
    """A read-only view of ``array`` (the array keeps its own flag)."""
    view = array.view()
    view.flags.writeable = False
    return view


def choosing(block: PlyContactBlock) -> bool:
    """Whether ``closest_facing`` takes the block's facing (without the gap's Hessian) by
    elements/ply_facing_whole.py's two calls (``CHOSEN`` set): ``begun`` then makes the first
    in its own call."""
    return (
        CHOSEN
        and ply_projection.WHOLE
        and block.topology is not None
        and block.outline is not None
        and block.topology.outline is block.outline
        and len(block.above) < SMALL_LOOP
    )
