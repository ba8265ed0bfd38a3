"""The slip of a ply contact point that leaves the lower face within a step (PlyContact with
``friction`` > 0; docs/theory.md §9.2 and §9.3a, "Friction between plies").

A point anchored at the last accepted state (touching) and off the lower face now slid, in
that step, from its place then to where its way left the face, under a normal force falling
from N_0 to 0 (the tool contact's rule, elements/contact_history.py ``departure``). Its place
is relative to the lower ply (which moves too): on the plane of its anchor's triangle T, the
barycentric place of the point's projection at the last accepted state (its contact point
p_0 on T's corners then, the history's sides keep both, elements/ply_sides.py) and now (p on
T's corners now),

    Lambda_l = Lambda_0 + theta (Lambda - Lambda_0),   theta = pen_0 / (pen_0 + g),

pen_0 = max(-n_0 . (p_0 - y_0), 0) its penetration of T's plane then, g = n . (p - y) its gap
to T's plane now, the gap taken linear over the step. Its slip is its whole offset from its
anchor there, |sum_k (Lambda_l - Lambda_a)_k y_l,k| with T's corners y_l = y_0 + theta (y -
y_0) (the stick spring holds nothing at g = 0), at the step's mean limit force mu N_0 / 2 (the
record's midpoint rule: N = 0 now). Exact for a flat lower face, a way straight relative to it
and T's corners moved affinely. Elsewhere a rule: on a curved or folded face the places are
those of T's plane (off the surface by the facet's sagitta), pen_0 the distance to T's plane,
not the normal law's gap. A point with no gap to T's plane now (g <= 0: it left across the
lower ply's outline or is kept off a face it lies behind, not lifted off) has no slip counted
for the step, as before the rule; so has a history that keeps no sides.

A point whose gap now is to an edge or a vertex (``Facing.on_edge``) leaves by the same rule:
until it left it slid under the gap it touched with at the last accepted state, which its
anchor's triangle T keeps, not under the gap it has now. Exact where that was T's plane's
(a point pressed under a ridge of the lower face, lifted through the ridge's line, faces the
ridge's edge once off: tests/test_ply_edge_crossing.py; measured across the edge gap's normal
now, as a landing's slip, its slip was 6.5e-5 short there); where it touched by a gap to an
edge or a vertex, a rule. Beside a growth's edge, at an outline vertex or on a cut (T's normal
signs the gap: ``Facing.on_growth``, not ``joined``) that gap's zero is T's plane too, and the
point touched beside the feature, its spring holding the offset across the gap's normal nu
(nearly in T's plane; its side flips with the sign): its slip is the offset's part across nu
now (the whole offset in T's plane counted the part along nu, which the spring never held: up
to 0.26 mm in a step on the hemisphere-plies Mindlin [0/90] run). Before, such points had no
departure slip counted.

Only the records change (the slip and the dissipation): the forces, the anchors and the
tangent are those of a point off the face.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from elements.ply_landing import plane_places
from elements.ply_sides import TOUCHING

if TYPE_CHECKING:
    from elements.ply_block import PlyContactBlock
    from elements.ply_friction import PlyFrictionHistory
    from elements.ply_projection import Facing

__all__ = ["beside_growth", "departure", "leaving"]


def leaving(block: PlyContactBlock, history: PlyFrictionHistory, facing: Facing) -> np.ndarray:
    """(r,) int the rows of the points of the ply contact ``block`` whose departure's slip is
    counted in the step from the accepted ``history`` to the state of ``facing`` (the rule's
    selection, module docstring; the numpy ``departure`` and the compiled pass,
    elements/ply_departure_kernels.py, both take it): anchored then, touching then by their
    side and not now, their point now finite (their gap now to a plane, an edge or a vertex).
    The ones among them with no gap to their anchor's triangle's plane now are left out after
    (not lifted off it). None without friction or sides. (Written again, test by test, in
    the friction's history pass, elements/ply_friction_pass.py ``_leaving``: change both.)"""
    sides = history.sides
    if sides is None or block.friction <= 0.0:
        return np.zeros(0, dtype=np.int64)
    # (the anchored points are few to test further: a step where none leaves costs a mask)
    rows = np.flatnonzero((history.triangle >= 0) & ~np.asarray(facing.touching, dtype=bool))
    rows = rows[sides.sides[rows] == TOUCHING]
    return rows[np.all(np.isfinite(facing.face[rows]), axis=1)]


def beside_growth(facing: Facing, rows: np.ndarray) -> np.ndarray:
    """(r,) bool which of the points ``rows`` (r,) int face a growth's edge, an outline vertex
    or a cut at ``facing`` (their gap to an edge or a vertex, T's normal signing it:
    ``Facing.on_edge`` and ``on_growth``, not ``joined``), whose departure's slip is the
    offset's part across the gap's normal nu (module docstring; the numpy ``departure`` and
    the compiled pass both take it)."""
    if facing.on_growth is None or facing.joined is None or facing.on_edge is None:
        return np.zeros(len(rows), dtype=bool)
    return facing.on_edge[rows] & facing.on_growth[rows] & ~facing.joined[rows]


def departure(
    block: PlyContactBlock, y: np.ndarray, history: PlyFrictionHistory, facing: Facing
) -> tuple[np.ndarray, np.ndarray]:
    """(rows (r,) int, slip (r,) mm): the points of the ply contact ``block`` that left the
    lower face in the step from the accepted ``history`` to the state of ``facing`` (the
    sides held; the offset lower corners ``y`` (m, 3, 3) there, mm), and each one's slip in
    that step up to where it left (module docstring). No rows without friction or sides."""
    sides = history.sides
    rows = leaving(block, history, facing)
    if sides is None or len(rows) == 0:
        return rows, np.zeros(0)
    triangle = history.triangle[rows]
    before, now = sides.corners[triangle], y[triangle]
    then, p = sides.faces[rows], facing.face[rows]
    # the places then and now in one pass (one frame of the 2r triangles: a step leaves few)
    places, heights = plane_places(np.concatenate([before, now]), np.concatenate([then, p]))
    count = len(rows)
    old, weights = places[:count], places[count:]
    pen0, gap = np.maximum(-heights[:count], 0.0), heights[count:]
    lifted = gap > 0.0  # (g <= 0: not lifted off T's plane; module docstring)
    rows, pen0, gap = rows[lifted], pen0[lifted], gap[lifted]
    before, now, old, weights = before[lifted], now[lifted], old[lifted], weights[lifted]
    theta = pen0 / (pen0 + gap)
    place = old + theta[:, None] * (weights - old)
    corners = before + theta[:, None, None] * (now - before)
    offset = np.einsum("rk,rki->ri", place - history.anchor[rows], corners)
    # beside a growth's edge (T's normal signs the gap) the spring held the offset across the
    # edge gap's normal nu, nearly in T's plane (module docstring)
    aside = beside_growth(facing, rows)
    if aside.any():
        nu = facing.normal[rows[aside]]
        offset[aside] -= np.einsum("ri,ri->r", nu, offset[aside])[:, None] * nu
    return rows, np.linalg.norm(offset, axis=1)
