"""What follows the choice of each ply contact point's facing triangle, compiled
(elements/ply_projection.py ``closest_facing``, "The sign at an edge", "Growths joined", "Past
the outline, faded" and "Deeper than the plies"; docs/theory.md, the ply contact section):
where the chosen candidate's closest point lies on an edge, at a vertex or on a cut, that
point's coordinates, the sign of its gap from the feature's pseudonormal (or the triangle's
normal at an outline vertex and on a cut), its gap, normal and coordinates
(elements/ply_edge_gap.py ``towards_closest``); then, at every point, whether it lies beside a
growth's edge or at an outline vertex, deeper than the plies, near the outline (where its fade
is computed) and touching but for the fade, in two passes over the points with numpy's
``arctan2`` of the fans' angles between (``edge_sides``).

Before, ``closest_facing`` chained the feature normals' two kernels, ``towards_closest`` and
the flags by numpy's gathers, stacks, masks and scatters on arrays of a few hundred rows:
67 + 20 + 10 us of a call on the two-ply hemisphere's 384 points (benchmarks/
forming_step_overhead.py). The numpy reference is ``closest_facing``'s own expressions with
``ply_facets._feature_normals`` and ``towards_closest``, taken with
``ply_projection.COMPILED = False``. The passes do the same IEEE operations in the same order
(the feature normals' helpers of elements/ply_feature_normals.py themselves; numpy's sums of
three terms: ``np.sum`` and ``np.linalg.norm`` from the first term, ``einsum("pki,pi->pk")``
as (first + last) + middle; numpy's ``min`` passing the first NaN; no fused multiply-add: numba
builds without fastmath), and the angles' ``arctan2`` stays numpy's, element by element the
same bits wherever an angle stands in its array, so the facing is the same to the last bit
(tests/test_ply_kernels.py). Each point is independent: the same bits on any thread count.
"""

from __future__ import annotations

import numpy as np

from elements.kernel_inputs import read_only
from elements.ply_edge_gap import edge_hessian
from elements.ply_feature_normals import _where, fan_parts, signing_at
from elements.ply_topology import FaceTopology
from femcore.jit import jit_lanes, lanes, prange

__all__ = ["edge_sides"]


def _parts(on_edge, triangle, y, nodes, fans, gradients, closest, reach, inside, on_q, rise, run):
    """At each point ``on_edge`` (P,) bool: its closest point's (P, 3) coordinates on_q (P, 3)
    on its triangle (rows ``triangle`` (P,) of y (m, 3, 3), barycentric gradients (P, 3, 3)),
    and the rise and run (P, f) of its vertex's fan's angles (``fan_parts``; 0 elsewhere)."""
    for i in prange(on_edge.shape[0]):
        if not on_edge[i]:
            for f in range(rise.shape[1]):
                rise[i, f] = 0.0
                run[i, f] = 0.0
            continue
        t = triangle[i]
        v0 = closest[i, 0] - y[t, 0, 0]
        v1 = closest[i, 1] - y[t, 0, 1]
        v2 = closest[i, 2] - y[t, 0, 2]
        for k in range(3):
            # numpy's einsum adds a sum of three products as (first + last) + middle
            on_q[i, k] = (gradients[i, k, 0] * v0 + gradients[i, k, 2] * v2) + gradients[
                i, k, 1
            ] * v1
        on_q[i, 0] += 1.0
        fan_parts(t, on_q[i], reach[i], y, nodes, fans, inside, rise[i], run[i])


_parts_compiled = jit_lanes(_parts)


@lanes
def _parts_once(
    on_edge, triangle, y, nodes, fans, gradients, closest, reach, inside, on_q, rise, run
):  # fmt: skip
    """``_parts`` on the calling thread, each vertex's fan's rise and run computed once a call
    and copied to every point at that vertex: they are of the vertex's fan alone (y, ``fans``:
    ``fan_parts``), not of the point, so the same operations on the same corners give the same
    bits, where ``_parts`` made them again at each point (on the two-ply hemisphere's upper
    pass some 290 of 384 points lie at some 76 vertices; docs/theory.md §9.3a)."""
    width = rise.shape[1]
    kept_rise = np.empty((fans.shape[0], width))
    kept_run = np.empty((fans.shape[0], width))
    made = np.zeros(fans.shape[0], dtype=np.bool_)
    for i in range(on_edge.shape[0]):
        if not on_edge[i]:
            for f in range(width):
                rise[i, f] = 0.0
                run[i, f] = 0.0
            continue
        t = triangle[i]
        v0 = closest[i, 0] - y[t, 0, 0]
        v1 = closest[i, 1] - y[t, 0, 1]
        v2 = closest[i, 2] - y[t, 0, 2]
        for k in range(3):
            # numpy's einsum adds a sum of three products as (first + last) + middle
            on_q[i, k] = (gradients[i, k, 0] * v0 + gradients[i, k, 2] * v2) + gradients[
                i, k, 1
            ] * v1
        on_q[i, 0] += 1.0
        count, corner, _, _ = _where(on_q[i], reach[i], inside)
        if count != 2:  # not at a vertex: fan_parts' zeros
            for f in range(width):
                rise[i, f] = 0.0
                run[i, f] = 0.0
            continue
        vertex = nodes[t, corner]
        if not made[vertex]:
            fan_parts(
                t, on_q[i], reach[i], y, nodes, fans, inside, kept_rise[vertex], kept_run[vertex]
            )
            made[vertex] = True
        for f in range(width):
            rise[i, f] = kept_rise[vertex, f]
            run[i, f] = kept_run[vertex, f]


def _sides(
    p,
    y,
    on_edge,
    closest,
    cutting,
    triangle,
    gap,
    normal,
    lam,
    reach,
    reached,
    turned,
    overshoot,
    nodes,
    fans,
    edges,
    edge_halves,
    other,
    outline,
    has_outline,
    rim,
    inside,
    angles,
    on_q,
    depth,
    tolerance,
    margin,
    signing,
    joined,
    at_rim,
    tiny,
    on_growth,
    beside,
    near_outline,
    touching,
):
    """``edge_sides``' pass after the angles: gap (P,), normal and lam (P, 3) rewritten in
    place at the points ``on_edge``, and the flags (P,) bool written (``edge_sides``' Returns);
    ``signing`` (P, 3) its working rows."""
    for i in prange(p.shape[0]):
        rim_i = False
        joined_i = False
        tiny_i = False
        edge_i = on_edge[i]
        if edge_i:
            t = triangle[i]
            # the sign by the feature's pseudonormal ("The sign at an edge")
            joined_i = signing_at(
                t,
                y,
                nodes,
                fans,
                edges,
                edge_halves,
                other,
                outline,
                has_outline,
                on_q[i],
                reach[i],
                normal[i],
                inside,
                angles[i],
                signing[i],
            )
            if has_outline:  # at a vertex of the outline the face has no side either
                count = 0
                corner = -1
                for k in range(3):
                    if on_q[i, k] <= -reach[i, k] + 1e-9:
                        count += 1
                    elif corner < 0:
                        corner = k
                rim_i = count == 2 and rim[nodes[t, max(corner, 0)]]
                joined_i = joined_i and not rim_i
            if rim_i or cutting[i]:  # the triangle's normal signs the gap ("The wedge cut")
                for c in range(3):
                    signing[i, c] = normal[i, c]
            if cutting[i]:
                joined_i = False
                rim_i = True
            # elements/ply_edge_gap.py ``towards_closest``
            p0, p1, p2 = p[i, 0], p[i, 1], p[i, 2]
            r0, r1, r2 = p0 - closest[i, 0], p1 - closest[i, 1], p2 - closest[i, 2]
            length = np.sqrt((r0 * r0 + r1 * r1) + r2 * r2)
            dot = (r0 * signing[i, 0] + r1 * signing[i, 1]) + r2 * signing[i, 2]
            g = (-1.0 if dot < 0.0 else 1.0) * length
            tiny_i = length <= 1e-12 * (1.0 + np.sqrt((p0 * p0 + p1 * p1) + p2 * p2))
            gap[i] = g
            if tiny_i:
                for c in range(3):
                    normal[i, c] = signing[i, c]
            else:
                normal[i, 0], normal[i, 1], normal[i, 2] = r0 / g, r1 / g, r2 / g
            for c in range(3):
                lam[i, c] = on_q[i, c]
        joined[i] = joined_i
        at_rim[i] = rim_i
        tiny[i] = tiny_i
        # numpy's min of the coordinates: the first NaN, else the least
        low = lam[i, 0]
        for c in range(1, 3):
            w = lam[i, c]
            if low == low and (w != w or w < low):
                low = w
        growth = (edge_i and low < -inside and reached[i]) or rim_i
        on_growth[i] = growth
        deep = gap[i] < -depth
        aside = (edge_i and deep) or (turned[i] and deep)
        beside[i] = aside
        near_outline[i] = growth or reached[i]
        touching[i] = gap[i] <= tolerance and overshoot[i] <= margin and not aside


_sides_compiled = jit_lanes(_sides)


def edge_sides(
    p: np.ndarray,
    y: np.ndarray,
    topology: FaceTopology,
    choice: tuple,
    triangle: np.ndarray,
    gap: np.ndarray,
    normal: np.ndarray,
    lam: np.ndarray,
    gradients: np.ndarray,
    reach: np.ndarray,
    reached: np.ndarray,
    turned: np.ndarray,
    overshoot: np.ndarray,
    bounds: tuple[float, float, float, float],
    hessian: np.ndarray | None = None,
) -> tuple[np.ndarray, ...]:
    """The chosen candidates' gaps, normals and coordinates where the closest point is off
    the plane, and the points' flags, compiled (module docstring).

    Parameters
    ----------
    p : (P, 3) float
        The contact points, mm.
    y : (m, 3, 3) float
        The lower face's triangles' corners, mm.
    topology : FaceTopology
        The lower face's (elements/ply_topology.py), its outline ``closest_facing``'s.
    choice : tuple
        ``ply_choice.choose_facing``'s on_edge (P,) bool, closest (P, 3) mm, on_cut (P,)
        bool, segment (P, 2, 3) and along (P,) or None: the closest point is off the plane's
        held part, that point, it lies on a cut, the cut's ends' coordinates and its
        parameter there.
    triangle, gap, normal, lam, gradients, reach, reached, turned, overshoot
        ``ply_chosen.chosen``'s arrays of the chosen candidates: (P,) int, (P,) mm, (P, 3),
        (P, 3), (P, 3, 3) 1/mm, (P, 3), (P,) bool, (P,) bool, (P,); ``gap``, ``normal`` and
        ``lam`` are rewritten in place at the points ``on_edge`` (the gap to the closest
        point, its gradient nu, the closest point's coordinates).
    bounds : (inside, depth, tolerance, margin) float
        ``ply_projection.INSIDE``; the depth (mm) below which a point facing an edge or a
        turned layer does not touch; the touching gap (mm); ``ply_projection.MARGIN``.
    hessian : (P, 4, 3, 4, 3) float, optional
        Zeros, given the gap's Hessian (elements/ply_edge_gap.py ``edge_hessian``) at the
        points ``on_edge`` in place; None: not asked for.

    Returns
    -------
    joined, at_rim : (P,) bool
        The closest point lies on a joined edge's extension; at an outline vertex or on a
        cut.
    on_growth, beside, near_outline, touching : (P,) bool
        Beside a growth's edge or at an outline vertex; deeper than the plies where it faces
        an edge or a turned layer; where the fade can differ from 1 (on a growth or a
        triangle reaching past the outline); touching but for the fade (w > 0 also needed).
    """
    on_edge, closest, cutting, segment, along = choice
    inside, depth, tolerance, margin = bounds
    count = len(p)
    y = read_only(y)  # read-only as the block keeps it: one build (kernel_inputs.py)
    nodes = np.ascontiguousarray(topology.nodes, dtype=np.int64)
    fans = np.ascontiguousarray(topology.fans, dtype=np.int64)
    triangle = np.ascontiguousarray(triangle, dtype=np.int64)
    on_edge = np.ascontiguousarray(on_edge, dtype=np.bool_)
    closest = np.ascontiguousarray(closest, dtype=float)
    gradients = np.ascontiguousarray(gradients, dtype=float)
    reach = np.ascontiguousarray(reach, dtype=float)
    on_q = np.empty((count, 3))
    width = fans.shape[1]
    if on_edge.any():
        rise, run = np.empty((count, width)), np.empty((count, width))
        _parts_compiled(
            on_edge, triangle, y, nodes, fans, gradients, closest, reach, float(inside), on_q,
            rise, run,
        )  # fmt: skip
        angles = np.arctan2(rise, run)  # numpy's, as pseudonormals' (module docstring)
    else:
        angles = np.zeros((count, width))
    outline = topology.outline
    # the seven flags the rows of one array: one allocation (2.8 -> 1.9 us at 384 points),
    # each row C-contiguous and writable as a fresh array (the same kernel build)
    flags = tuple(np.empty((7, count), dtype=np.bool_))
    _sides_compiled(
        read_only(p),
        y,
        on_edge,
        closest,
        np.ascontiguousarray(cutting, dtype=np.bool_),
        triangle,
        gap,
        normal,
        lam,
        reach,
        np.ascontiguousarray(reached, dtype=np.bool_),
        np.ascontiguousarray(turned, dtype=np.bool_),
        np.ascontiguousarray(overshoot, dtype=float),
        nodes,
        fans,
        np.ascontiguousarray(topology.edges, dtype=np.int64),
        np.ascontiguousarray(topology.edge_halves, dtype=np.int64),
        np.ascontiguousarray(topology.other, dtype=np.int64),
        np.zeros((1, 3), dtype=np.bool_) if outline is None else outline,
        outline is not None,
        np.ascontiguousarray(topology.rim, dtype=np.bool_),
        float(inside),
        angles,
        on_q,
        float(depth),
        float(tolerance),
        float(margin),
        np.empty((count, 3)),
        *flags,
    )
    joined, at_rim, tiny = flags[:3]
    edge = np.flatnonzero(on_edge)
    if hessian is not None and edge.size:  # at |p - q| within round-off (``tiny``) nu = n
        cut = (cutting[edge], segment[edge], None if along is None else along[edge])
        hessian[edge] = edge_hessian(
            gap[edge], normal[edge], lam[edge], y[triangle[edge]], reach[edge], tiny[edge], cut
        )
    return (joined, at_rim, *flags[3:])
