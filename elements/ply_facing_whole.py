"""The ply contact's whole facing in two compiled calls (elements/ply_projection.py
``closest_facing``, "Search" to "Past the outline, faded"; docs/theory.md, the ply contact
section): the candidates' planes, the choice and the chosen arrays
(elements/ply_facing_pass.py), the closest points' coordinates and fans' rise and run
(elements/ply_edge_kernels.py ``_parts_once``: ``_parts`` with each vertex's fan made once a
call) and the chosen planes' copies in the first; numpy's
``arctan2`` of the fans' angles between; the signs, gaps and flags (``_sides``), the
outline's edges and the fade at the points near it (elements/ply_fade_kernels.py
``_outline``) and the touching points' last flag in the second. Before, ``closest_facing``
made the same stages in four compiled calls (``facing_choice``, ``edge_sides``' two,
``outline_fade_at``) chained by Python: their arguments' conversions, the outline's edges'
gathers, the working arrays and the planes' copies, about half of its time on the two-ply
hemisphere (benchmarks/ply_chain_parts.py).

Each stage runs its kernel's own plain build on the calling thread (femcore/jit.py
``plain_part``; IEEE, no fastmath; the fans' stage its own serial loop of the same
operations, tests/test_ply_fan_parts_once.py), so every array of the facing is the same to
the last bit as the chained calls' (tests/test_ply_facing_whole.py); ``arctan2`` stays numpy's
(elements/ply_edge_kernels.py says why). The first call's stages also run at the end of the
front's call of a new state (elements/ply_facing_front.py ``CHOSEN``), which hands its outputs
(``chosen_outputs``) to the same finish (``finished_facing``). ``closest_facing`` takes this
path for fewer than ``SMALL_LOOP`` points without the gap's Hessian; where the outline's
nearest edges would be measured against more than ``ply_fade.EVERY_PAIR`` pairs, the second
call leaves the fade to ``outline_fade_at`` with the KD-tree's edges, as before.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from elements import ply_edge_kernels, ply_fade_kernels
from elements.kernel_inputs import read_only, writable
from elements.ply_choice import choice_arrays, cut_arrays
from elements.ply_chosen import chosen_arrays
from elements.ply_facing_pass import _facing
from elements.ply_fade import EVERY_PAIR, fade_length, nearest_segments
from elements.ply_fade_kernels import outline_fade_at
from elements.ply_projection import INSIDE, MARGIN, Facing
from elements.ply_topology import FaceTopology
from elements.ply_wedge import KEEP, WedgeCuts
from femcore.jit import lanes, plain_part

__all__ = ["chosen_outputs", "finished_facing", "whole_facing"]

# the stages' loops on the calling thread: ply_facing_pass's pass, and the kernels' own plain
# builds, each loop whole (part 0 of 1, ``plain_part``), so the same bits and one build each
# (its flags given as np.bool_, not the literal True, for which numba would build it again)
_facing_here = lanes(_facing)
_parts_once = ply_edge_kernels._parts_once
_sides_here = plain_part(ply_edge_kernels._sides_compiled)
_outline_here = plain_part(ply_fade_kernels._outline_compiled)
_TINY = float(np.finfo(float).tiny)  # ply_kernels.segment_lines' least |b - a|^2


def _choice(
    p, y, near, outline, margin, inside, has_cuts, cut, lines, ends, toward, has_toward,
    nodes, fans, best, on_edge, closest, on_cut, segment, along, triangle, chosen_gap,
    normal, lam, chosen_gradients, chosen_reach, overshoot, reached, turned, on_q, rise, run,
    plane_normal, plane_gap, plane_lam,
):  # fmt: skip
    """The first call: ``ply_facing_pass._facing`` (the three stages) into the choice's and the
    chosen arrays, then ``_parts``' coordinates ``on_q`` (P, 3) and fans' ``rise`` and
    ``run`` (P, f) of the points on an edge, and the chosen planes' normal, gap and
    coordinates copied (the fade reads them where the second call rewrites the chosen ones).
    Every output is given: none is returned (numba boxes a returned array)."""
    _facing_here(
        p, y, near, outline, margin, inside, has_cuts, cut, lines, ends, toward, has_toward,
        best, on_edge, closest, on_cut, segment, along, triangle, chosen_gap, normal, lam,
        chosen_gradients, chosen_reach, overshoot, reached, turned,
    )  # fmt: skip
    # each vertex's fan made once (the same bits as ``_parts``: ply_edge_kernels.py)
    _parts_once(
        on_edge, triangle, y, nodes, fans, chosen_gradients, closest, chosen_reach, inside,
        on_q, rise, run,
    )  # fmt: skip
    for i in range(near.shape[0]):
        plane_gap[i] = chosen_gap[i]
        for c in range(3):
            plane_normal[i, c] = normal[i, c]
            plane_lam[i, c] = lam[i, c]


_choice_compiled = lanes(_choice)


def _sides_fade(
    p, y, on_edge, closest, on_cut, triangle, gap, normal, lam, reach, reached, turned,
    overshoot, nodes, fans, edges, edge_halves, other, outline, rim, inside, angles, on_q,
    depth, tolerance, margin, joined, at_rim, tiny, on_growth, beside, near_outline,
    touching, plane_normal, gradients, plane_gap, plane_lam, segment_rows, segment_ends,
    has_cuts, lines, cut_ends, keep, length, length_squared, every_pair, fade,
    fade_gradient, fade_edge,
):  # fmt: skip
    """The second call: ``_sides`` (the gaps, normals and coordinates rewritten at the
    points on an edge, the flags written), then, where the points near the outline times
    its edges are at most ``every_pair``, ``_outline`` on them (each one's nearest edge
    measured against every edge) into ``fade``, ``fade_gradient`` and ``fade_edge`` (given
    as 1, 0 and -1) and ``touching`` where w > 0. Returns whether the fade was made (False:
    the caller's, with the KD-tree's edges; ``touching`` then left as the sides gave it)."""
    count = p.shape[0]
    _sides_here(
        p, y, on_edge, closest, on_cut, triangle, gap, normal, lam, reach, reached, turned,
        overshoot, nodes, fans, edges, edge_halves, other, outline, np.bool_(True), rim, inside,
        angles, on_q, depth, tolerance, margin, np.empty((count, 3)), joined, at_rim, tiny,
        on_growth, beside, near_outline, touching, np.int64(0), np.int64(1),
    )  # fmt: skip
    near = 0
    for i in range(count):
        if near_outline[i]:
            near += 1
    segments = segment_rows.shape[0]
    if near * segments > every_pair:
        return False
    if near == 0:
        return True
    at = np.empty(near, dtype=np.int64)
    j = 0
    for i in range(count):
        if near_outline[i]:
            at[j] = i
            j += 1
    starts = np.empty((segments, 3))
    ends = np.empty((segments, 3))
    e = np.empty((segments, 3))
    squared = np.empty(segments)
    for s in range(segments):
        row = segment_rows[s]
        for c in range(3):
            starts[s, c] = y[row, segment_ends[s, 0], c]
            ends[s, c] = y[row, segment_ends[s, 1], c]
            e[s, c] = ends[s, c] - starts[s, c]
        # ply_kernels.segment_lines' sum, in its order (x, z, y), its maximum passing NaN
        value = e[s, 0] * e[s, 0] + e[s, 2] * e[s, 2] + e[s, 1] * e[s, 1]
        squared[s] = value if (value != value or value > _TINY) else _TINY
    _outline_here(
        at, p, y, triangle, plane_normal, gradients, plane_gap, plane_lam, reach, on_growth,
        joined, np.bool_(True), np.zeros(near, dtype=np.int64), starts, e, squared, ends, has_cuts,
        lines, cut_ends, inside, keep, length, length_squared, fade, fade_gradient,
        fade_edge, np.empty((near, 3)), np.empty((near, 3, 3)), np.empty((near, 3)),
        np.empty((near, 2, 3)), np.empty((near, 4, 3)), np.empty((near, 4, 3)),
        np.empty((near, 4, 3)), np.int64(0), np.int64(1),
    )  # fmt: skip
    for i in range(count):
        touching[i] = touching[i] and fade[i] > 0.0
    return True


_sides_fade_compiled = lanes(_sides_fade)


def whole_facing(
    p: np.ndarray,
    y: np.ndarray,
    near: np.ndarray,
    tolerance: float,
    outline: np.ndarray,
    depth: float,
    toward: np.ndarray | None,
    length: float | None,
    topology: FaceTopology | None,
    outline_tree,
    cuts: WedgeCuts | None,
) -> Facing:
    """``closest_facing``'s Facing without the gap's Hessian in two compiled calls, the same
    bits (module docstring).

    Parameters
    ----------
    p : (P, 3) float
        The contact points, mm.
    y : (m, 3, 3) float
        The lower face's triangles' corners, mm.
    near : (P, K) int
        Each point's candidates (rows of ``y``).
    tolerance : float
        The touching gap, mm.
    outline : (m, 3) bool
        The lower face's outline edges (``topology.outline``).
    depth : float
        mm: ``closest_facing``'s.
    toward : (P, 3) float or None
        Each point's direction from the lower ply to its own (None: none turned).
    length : float or None
        The fade's length D past the outline, mm (None: ``ply_fade.fade_length``'s of y).
    topology : FaceTopology
        The lower face's (elements/ply_topology.py), with ``outline`` (None refused).
    outline_tree : OutlineTree or None
        The outline's KD-tree kept between calls (the fade's edges past ``EVERY_PAIR``).
    cuts : WedgeCuts or None
        The growths' cuts (elements/ply_wedge.py).

    Returns
    -------
    Facing
        As ``closest_facing`` gives it (``hessian`` None).
    """
    if topology is None:
        raise ValueError("whole_facing: the lower face's topology is needed, got None")
    p = read_only(p)  # read-only as the block keeps them: one build (kernel_inputs.py)
    y = read_only(y)
    face = _face_inputs(topology, outline, cuts, len(y))
    arrays = chosen_outputs(len(p), face.fans.shape[1])
    _choice_compiled(
        p, y, np.ascontiguousarray(near, dtype=np.int64), face.outline, MARGIN, INSIDE,
        face.has_cuts, face.cut, face.lines, face.cut_ends,
        np.ascontiguousarray(toward if toward is not None else np.zeros((1, 3)), dtype=float),
        toward is not None, face.nodes, face.fans, *arrays,
    )  # fmt: skip
    given = (tolerance, outline, depth, length, topology, outline_tree, cuts)
    return finished_facing(p, y, *given, arrays)


def chosen_outputs(count: int, width: int) -> tuple[np.ndarray, ...]:
    """The first call's outputs for ``count`` points and fans of ``width`` triangles, in its
    order (``_choice``): the choice's six (elements/ply_choice.py ``choice_arrays``), the
    chosen nine (elements/ply_chosen.py ``chosen_arrays``), ``on_q`` (P, 3), ``rise`` and
    ``run`` (P, f) and the chosen planes' normal (P, 3), gap (P,) and coordinates (P, 3)."""
    return (
        *choice_arrays(count),
        *chosen_arrays(count),
        np.empty((count, 3)),
        np.empty((count, width)),
        np.empty((count, width)),
        np.empty((count, 3)),
        np.empty(count),
        np.empty((count, 3)),
    )


def finished_facing(
    p: np.ndarray,
    y: np.ndarray,
    tolerance: float,
    outline: np.ndarray,
    depth: float,
    length: float | None,
    topology: FaceTopology,
    outline_tree,
    cuts: WedgeCuts | None,
    arrays: tuple[np.ndarray, ...],
) -> Facing:
    """The Facing from the first call's outputs ``arrays`` (``chosen_outputs``, written by
    ``_choice``, or by the same stages in elements/ply_facing_front.py's pass): numpy's
    ``arctan2`` of the fans' angles, the second call and, past ``EVERY_PAIR``, the fade by the
    KD-tree's edges (``whole_facing``'s arguments; ``p`` and ``y`` read-only)."""
    if length is None:
        length = fade_length(y, outline)
    face = _face_inputs(topology, outline, cuts, len(y))
    outline = face.outline
    count = len(p)
    best, on_edge, closest, on_cut, segment, along = arrays[:6]
    triangle, gap, normal, lam, gradients, reach, overshoot, reached, turned = arrays[6:15]
    on_q, rise, run = arrays[15:18]
    planes = arrays[18:21]
    # numpy's arctan2 (elements/ply_edge_kernels.py), read only at the points on an edge
    angles = np.arctan2(rise, run) if on_edge.any() else rise
    flags = tuple(np.empty((7, count), dtype=np.bool_))  # one allocation, C-contiguous rows
    joined, at_rim, _, on_growth, _, near_outline, touching = flags
    fade, fade_gradient = np.ones(count), np.zeros((count, 6, 3))
    fade_edge = np.full(count, -1)
    made = _sides_fade_compiled(
        p, y, on_edge, closest, on_cut, triangle, gap, normal, lam, reach, reached, turned,
        overshoot, face.nodes, face.fans, face.edges, face.edge_halves, face.other, outline,
        face.rim, INSIDE, angles, on_q, float(depth), float(tolerance), MARGIN, *flags,
        planes[0], writable(gradients), planes[1], planes[2], face.segment_rows,
        face.segment_ends, cuts is not None, face.fade_lines, face.fade_ends, KEEP,
        float(length), float(length**2), EVERY_PAIR, fade, fade_gradient, fade_edge,
    )  # fmt: skip
    if not made:  # the outline's nearest edges by the KD-tree (ply_fade.nearest_segments)
        at = np.flatnonzero(near_outline)
        starts = y[topology.segment_rows, topology.segment_ends[:, 0]]
        ends = y[topology.segment_rows, topology.segment_ends[:, 1]]
        chosen = nearest_segments(p[at], starts, ends, outline_tree)
        out = (fade, fade_gradient, fade_edge)
        outline_fade_at(
            at, p, y, triangle, (planes[0], gradients, planes[1], planes[2]), reach,
            on_growth, joined, chosen, starts, ends, cuts, length, out,
        )  # fmt: skip
        touching &= fade > 0.0
    return Facing(
        triangle=triangle,
        gap=gap,
        normal=normal,
        weights=lam,
        gradients=gradients,
        touching=touching,
        face=p,
        hessian=None,
        fade=fade,
        fade_gradient=fade_gradient,
        reach=reach,
        on_growth=on_growth,
        fade_edge=fade_edge,
        joined=joined,
        on_edge=on_edge,
    )


@dataclass(frozen=True)
class _FaceInputs:
    """The two calls' inputs that depend on the lower face alone (its topology, outline and
    growths' cuts), as the kernels take them (C-contiguous, their dtypes; the cut flags and
    the fade's copies of the cuts made)."""

    outline: np.ndarray
    nodes: np.ndarray
    fans: np.ndarray
    edges: np.ndarray
    edge_halves: np.ndarray
    other: np.ndarray
    rim: np.ndarray
    segment_rows: np.ndarray
    segment_ends: np.ndarray
    has_cuts: bool
    cut: np.ndarray
    lines: np.ndarray
    cut_ends: np.ndarray
    fade_lines: np.ndarray
    fade_ends: np.ndarray


# the faces' inputs kept by the identity of their topology, outline and cuts (a block's own,
# made at bind and never written): converted at each call before, about a tenth of a call's
# CPU on the two-ply hemisphere (benchmarks/forming_step_overhead.py). A few faces are kept
# (a model's ply passes), the oldest dropped past ``_FACES_KEPT``.
_FACES: dict[int, tuple] = {}
_FACES_KEPT = 16


def _face_inputs(
    topology: FaceTopology, outline: np.ndarray, cuts: WedgeCuts | None, m: int
) -> _FaceInputs:
    """``whole_facing``'s inputs of the face (``_FaceInputs``) with ``m`` triangles, kept."""
    kept = _FACES.get(id(topology))
    if (
        kept is not None
        and kept[0] is topology
        and kept[1] is outline
        and kept[2] is cuts
        and kept[3] == m
    ):
        return kept[4]
    has_cuts, cut, lines, cut_ends = cut_arrays(cuts, m)
    # as the fade's kernel is handed the cuts (elements/ply_fade_kernels.py)
    empty = np.zeros((0, 3, 3))
    made = _FaceInputs(
        outline=np.ascontiguousarray(outline, dtype=np.bool_),
        nodes=np.ascontiguousarray(topology.nodes, dtype=np.int64),
        fans=np.ascontiguousarray(topology.fans, dtype=np.int64),
        edges=np.ascontiguousarray(topology.edges, dtype=np.int64),
        edge_halves=np.ascontiguousarray(topology.edge_halves, dtype=np.int64),
        other=np.ascontiguousarray(topology.other, dtype=np.int64),
        rim=np.ascontiguousarray(topology.rim, dtype=np.bool_),
        segment_rows=np.ascontiguousarray(topology.segment_rows, dtype=np.int64),
        segment_ends=np.ascontiguousarray(topology.segment_ends, dtype=np.int64),
        has_cuts=has_cuts,
        cut=cut,
        lines=lines,
        cut_ends=cut_ends,
        fade_lines=empty if cuts is None else writable(cuts.lines),
        fade_ends=empty if cuts is None else writable(cuts.ends),
    )
    if len(_FACES) >= _FACES_KEPT:
        _FACES.pop(next(iter(_FACES)))
    _FACES[id(topology)] = (topology, outline, cuts, m, made)
    return made
