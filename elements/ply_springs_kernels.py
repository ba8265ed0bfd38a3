"""The ply springs' passes compiled (elements/ply_springs.py; docs/theory.md §6.2, "The
penalty springs"): the slide (``fastest_point``: the fastest point's speed against its facing
triangle's point plus the plies' depth times both sets' largest angular speed), the points
within the slide of the outline's nearest edge and their gap (``near_outline``), the points'
sizes |lambda_k| + delta and held loads c_p k_p (``held_points``: the fade's factor, the
points that may touch, the weights clipped beside a growth), each point's bound F_p of
sum_i |a_i| v_i (``weighted_reach``) and the points' loads spread on the nodes
(``spread_loads``: the upper corners, the facing corners and the lower nodes' rings), each in
one serial pass over the points.

Their numpy references are ``ply_springs.slide``, ``reachable_springs`` (the outline's
reach, the held points and the spread), ``_weighted_reach`` and ``_node_weights`` with
``ply_projection.COMPILED = False``: the passes do the same IEEE
operations in the same order (numpy's ``einsum("pj,pji->pi")`` sums its three terms from the
first, ``einsum("pi,pi->p")`` as (first + last) + middle, a row's ``sum`` and
``np.linalg.norm(axis=1)``'s squares from the first, scipy's CSR product row by row from 0.0;
``np.clip``, the maxima and the minimum pass NaN as numpy's do; no fused multiply-add: numba
builds without fastmath), so they give the same numbers to the last bit
(tests/test_ply_springs.py, tests/test_ply_springs_kernels.py). Serial: a maximum, and a few
hundred points, every tenth step.
"""

from __future__ import annotations

import numpy as np

from elements.kernel_inputs import read_only
from elements.ply_fade import SIDEWAYS, SIDEWAYS_STIFFNESS
from elements.ply_kernels import nearest_segment, segment_lines
from femcore.jit import lanes

__all__ = ["fastest_point", "held_points", "near_outline", "spread_loads", "weighted_reach"]


@lanes
def _larger(a, b):
    """numpy's maximum of two: the first NaN, else the larger."""
    if a != a:
        return a
    if b != b or b > a:
        return b
    return a


@lanes
def _clipped(x, low, high):
    """``np.clip(x, low, high)`` of one number (NaN passes)."""
    if x < low:
        x = low
    if x > high:
        x = high
    return x


@lanes
def _spin(spins, node):
    """|omega| of ``node``, as ``np.sqrt(np.einsum("ij,ij->i", spins, spins))`` gives it."""
    s0, s1, s2 = spins[node, 0], spins[node, 1], spins[node, 2]
    return np.sqrt((s0 * s0 + s2 * s2) + s1 * s1)


@lanes
def _fastest(shape, above, weights, cells, triangle, v, spins, depth, low, high):
    """max over the points of |sum_j N_j v_j - sum_k clip(lambda_k) v_k| + depth (the largest
    |omega| of the upper corners + of the facing corners); NaN where numpy's max gives it."""
    fastest = 0.0
    for p in range(shape.shape[0]):
        t = triangle[p]
        a0, a1, a2 = above[p, 0], above[p, 1], above[p, 2]
        c0, c1, c2 = cells[t, 0], cells[t, 1], cells[t, 2]
        w0 = _clipped(weights[p, 0], low, high)
        w1 = _clipped(weights[p, 1], low, high)
        w2 = _clipped(weights[p, 2], low, high)
        s0, s1, s2 = shape[p, 0], shape[p, 1], shape[p, 2]
        d0 = ((s0 * v[a0, 0] + s1 * v[a1, 0]) + s2 * v[a2, 0]) - (
            (w0 * v[c0, 0] + w1 * v[c1, 0]) + w2 * v[c2, 0]
        )
        d1 = ((s0 * v[a0, 1] + s1 * v[a1, 1]) + s2 * v[a2, 1]) - (
            (w0 * v[c0, 1] + w1 * v[c1, 1]) + w2 * v[c2, 1]
        )
        d2 = ((s0 * v[a0, 2] + s1 * v[a1, 2]) + s2 * v[a2, 2]) - (
            (w0 * v[c0, 2] + w1 * v[c1, 2]) + w2 * v[c2, 2]
        )
        speed = np.sqrt((d0 * d0 + d2 * d2) + d1 * d1)
        upper = _larger(_larger(_spin(spins, a0), _spin(spins, a1)), _spin(spins, a2))
        lower = _larger(_larger(_spin(spins, c0), _spin(spins, c1)), _spin(spins, c2))
        total = speed + depth * (upper + lower)
        fastest = total if p == 0 else _larger(fastest, total)
    return fastest


def fastest_point(
    shape: np.ndarray,
    above: np.ndarray,
    weights: np.ndarray,
    cells: np.ndarray,
    triangle: np.ndarray,
    velocities: np.ndarray,
    spins: np.ndarray,
    depth: float,
    margin: float,
) -> float:
    """The fastest point's move rate against the lower face, mm/s: ``ply_springs.slide``'s
    ``fastest`` (0 for no points).

    Parameters
    ----------
    shape, above : (P, 3) float, (P, 3) int
        Each point's shape functions and upper triangle's corners.
    weights : (P, 3) float
        Its facing triangle's barycentric coordinates (clipped to [-margin, 1 + 2 margin]).
    cells : (m, 3) int
        The lower triangles' corners.
    triangle : (P,) int
        Each point's facing triangle.
    velocities, spins : (n, 3) float
        The nodes' velocities (mm/s) and angular velocities (rad/s).
    depth : float
        The plies' depth, mm (the offsets along the directors).
    margin : float
        ``ply_projection.MARGIN``.
    """
    if len(shape) == 0:
        return 0.0
    # the facing's arrays read-only, as the block keeps them: one build (kernel_inputs.py)
    return float(
        _fastest(
            np.ascontiguousarray(shape, dtype=float),
            np.ascontiguousarray(above, dtype=np.int64),
            read_only(weights),
            np.ascontiguousarray(cells, dtype=np.int64),
            read_only(triangle, np.int64),
            np.ascontiguousarray(velocities, dtype=float),
            np.ascontiguousarray(spins, dtype=float),
            float(depth),
            -float(margin),
            1.0 + 2.0 * float(margin),
        )
    )


@lanes
def _reach(
    shape, above, v, size, cells, triangle, lower_v, reach, indptr, indices, data, delta, out
):
    """out[p] the F_p bound of each point p (``weighted_reach``)."""
    for p in range(shape.shape[0]):
        t = triangle[p]
        a0, a1, a2 = above[p, 0], above[p, 1], above[p, 2]
        own = (shape[p, 0] * v[a0] + shape[p, 2] * v[a2]) + shape[p, 1] * v[a1]
        c0, c1, c2 = cells[t, 0], cells[t, 1], cells[t, 2]
        ring = lower_v[reach[t, 0]]
        for j in range(1, reach.shape[1]):
            ring = _larger(ring, lower_v[reach[t, j]])
        largest = _larger(_larger(_larger(v[c0], v[c1]), v[c2]), ring)
        along = (size[p, 0] * v[c0] + size[p, 2] * v[c2]) + size[p, 1] * v[c1]
        summed = 0.0
        for k in range(indptr[t], indptr[t + 1]):
            summed += data[k] * lower_v[indices[k]]
        along = along + delta * summed
        cap = ((size[p, 0] + size[p, 1]) + size[p, 2]) * largest
        # numpy's minimum: NaN where either is
        least = cap if (cap != cap or cap < along) else along
        out[p] = own + least


def weighted_reach(
    shape: np.ndarray,
    above: np.ndarray,
    v: np.ndarray,
    size: np.ndarray,
    cells: np.ndarray,
    triangle: np.ndarray,
    lower_nodes: np.ndarray,
    reach: np.ndarray,
    transposed,
    delta: float,
) -> np.ndarray:
    """(P,) ``ply_springs._weighted_reach`` in one pass, to the bit.

    Parameters
    ----------
    shape, above : (P, 3) float, (P, 3) int
        Each point's shape functions and upper triangle's corners.
    v : (n,) float
        The nodes' weights.
    size : (P, 3) float
        |lambda_k| + delta of each point's facing triangle's corners.
    cells, triangle : (m, 3) int, (P,) int
        The lower triangles' corners and each point's facing triangle.
    lower_nodes : (l,) int
        The lower nodes.
    reach : (m, w) int
        The rows of ``lower_nodes`` whose ring holds each triangle, padded.
    transposed : scipy.sparse.csr_matrix (m, l)
        The ring's matrix by triangle.
    delta : float
        The slide over the least height.
    """
    out = np.empty(len(shape))
    _reach(
        np.ascontiguousarray(shape, dtype=float), np.ascontiguousarray(above, dtype=np.int64),
        np.ascontiguousarray(v, dtype=float), np.ascontiguousarray(size, dtype=float),
        np.ascontiguousarray(cells, dtype=np.int64), read_only(triangle, np.int64),
        np.ascontiguousarray(v[lower_nodes], dtype=float),
        np.ascontiguousarray(reach, dtype=np.int64),
        np.ascontiguousarray(transposed.indptr, dtype=np.int64),
        np.ascontiguousarray(transposed.indices, dtype=np.int64),
        np.ascontiguousarray(transposed.data, dtype=float), float(delta), out,
    )  # fmt: skip
    return out


@lanes
def _near(face, triangle, weights, rim, gap, starts, e, squared, slide, out):
    """out[p] whether point p lies within ``slide`` + |gap[p]| of the outline's nearest edge,
    asked of the points facing a rim triangle or past an edge of theirs (else False)."""
    for p in range(face.shape[0]):
        out[p] = False
        if not (rim[triangle[p]] or weights[p, 0] < 0.0 or weights[p, 1] < 0.0
                or weights[p, 2] < 0.0):  # fmt: skip
            continue
        f0, f1, f2 = face[p, 0], face[p, 1], face[p, 2]
        j = nearest_segment(f0, f1, f2, starts, e, squared)
        r0, r1, r2 = f0 - starts[j, 0], f1 - starts[j, 1], f2 - starts[j, 2]
        # ply_springs._distance: einsum's (first + last) + middle, np.clip, then the norm's
        # squares summed from the first
        t = _clipped((r0 * e[j, 0] + r2 * e[j, 2] + r1 * e[j, 1]) / squared[j], 0.0, 1.0)
        d0, d1, d2 = r0 - t * e[j, 0], r1 - t * e[j, 1], r2 - t * e[j, 2]
        out[p] = np.sqrt((d0 * d0 + d1 * d1) + d2 * d2) <= slide + np.abs(gap[p])


def near_outline(
    face: np.ndarray,
    triangle: np.ndarray,
    weights: np.ndarray,
    rim: np.ndarray,
    gap: np.ndarray,
    starts: np.ndarray,
    ends: np.ndarray,
    slide: float,
) -> np.ndarray:
    """(P,) bool: the points that may pass the outline until the next evaluation,
    ``reachable_springs``' ``near_edge`` to the bit: those facing a triangle with a corner on
    the outline (``rim``) or past an edge of theirs (a weight below 0) whose face point lies
    within ``slide`` + |gap| of the outline's nearest edge (``ply_kernels.nearest_segment``:
    the first of the least distances, the first NaN one).

    Parameters
    ----------
    face : (P, 3) float
        The points on the upper face, mm.
    triangle : (P,) int
        Each point's facing triangle.
    weights : (P, 3) float
        Its barycentric coordinates on that triangle.
    rim : (m,) bool
        The lower triangles with a corner on the outline.
    gap : (P,) float
        The points' gaps, mm.
    starts, ends : (E, 3) float
        The outline edges' ends, mm (E > 0).
    slide : float
        The slide until the next evaluation, mm.
    """
    out = np.empty(len(face), dtype=np.bool_)
    e, squared = segment_lines(starts, ends)
    # the facing's arrays read-only, as the block keeps them: one build (kernel_inputs.py)
    _near(
        read_only(face), read_only(triangle, np.int64), read_only(weights),
        np.ascontiguousarray(rim, dtype=np.bool_), read_only(gap),
        np.ascontiguousarray(starts, dtype=float), e, squared, float(slide), out,
    )  # fmt: skip
    return out


@lanes
def _spread(load, shape, above, size, cells, triangle, indptr, indices, data, lumped, at, ring):
    """The three sums of ``spread_loads`` into ``lumped`` (n,), ``at`` (n,) and ``ring`` (l,),
    each in numpy's order: bincount adds its weights from zero in the points' order (a row's
    three after another), scipy's CSR product sums a row from 0.0 in its stored order."""
    for i in range(lumped.shape[0]):
        lumped[i] = 0.0
        at[i] = 0.0
    on = np.zeros(cells.shape[0])
    for p in range(load.shape[0]):
        share, t = load[p], triangle[p]
        for j in range(3):
            lumped[above[p, j]] += shape[p, j] * share
        for k in range(3):
            at[cells[t, k]] += share * size[p, k]
        on[t] += share
    for r in range(indptr.shape[0] - 1):
        summed = 0.0
        for k in range(indptr[r], indptr[r + 1]):
            summed += data[k] * on[indices[k]]
        ring[r] = summed


def spread_loads(
    load: np.ndarray,
    shape: np.ndarray,
    above: np.ndarray,
    size: np.ndarray,
    cells: np.ndarray,
    triangle: np.ndarray,
    indptr: np.ndarray,
    indices: np.ndarray,
    data: np.ndarray,
    nodes: int,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The points' loads spread on the nodes in one pass, as ``ply_springs``' numpy writes
    them (``block._lumped(load)``, ``np.bincount(cells[triangle].ravel(), (load[:, None] *
    size).ravel(), n)`` and ``ring @ np.bincount(triangle, load, m)``), to the bit.

    Parameters
    ----------
    load : (P,) float
        Each point's load c_p k_p F_p, N/mm.
    shape, above : (P, 3) float, (P, 3) int
        Each point's shape functions and upper triangle's corners.
    size : (P, 3) float
        |lambda_k| + delta of each point's facing triangle's corners.
    cells, triangle : (m, 3) int, (P,) int
        The lower triangles' corners and each point's facing triangle.
    indptr, indices, data : (l + 1,) int, (z,) int, (z,) float
        The ring's CSR matrix (l, m) (``ring_matrix``).
    nodes : int
        The body's nodes n.

    Returns
    -------
    lumped, at : (n,) float
        sum_p N_j load_p at the upper corners; sum_p load_p size_pk at the facing corners.
    ring : (l,) float
        The ring's matrix times the loads summed per triangle.
    """
    lumped, at, ring = np.empty(nodes), np.empty(nodes), np.empty(len(indptr) - 1)
    _spread(
        np.ascontiguousarray(load, dtype=float), np.ascontiguousarray(shape, dtype=float),
        np.ascontiguousarray(above, dtype=np.int64), np.ascontiguousarray(size, dtype=float),
        np.ascontiguousarray(cells, dtype=np.int64), read_only(triangle, np.int64), indptr,
        indices, data, lumped, at, ring,
    )  # fmt: skip
    return lumped, at, ring


@lanes
def _held(
    past, beside, reached, faded, cross, angle, gap, slide, weights, reach, delta, low, high,
    stiffness, size, held,
):  # fmt: skip
    """size[p] (3,) and held[p] of each point (``held_points``), numpy's operations in
    numpy's order: the fade's factor (ply_fade.stiffness_factor) (angle + (3 cross) x) + (3 x)
    x, x = reached / faded, in the band or beside, else 1; the weights clipped beside a
    growth (NaN passes)."""
    for p in range(weights.shape[0]):
        x = reached[p] / faded
        side = angle if beside[p] else 1.0
        factor = side + (3.0 * cross) * x + (3.0 * x) * x if (past[p] or beside[p]) else 1.0
        beyond = False
        for k in range(3):
            if weights[p, k] < -(reach[p, k] + delta):
                beyond = True
            w = _clipped(weights[p, k], low, high) if beside[p] else weights[p, k]
            size[p, k] = np.abs(w) + delta
        counted = gap[p] < slide and (beside[p] or not beyond)
        held[p] = stiffness[p] * factor if counted else 0.0


def held_points(
    past: np.ndarray,
    beside: np.ndarray,
    reached: np.ndarray,
    faded: float,
    gap: np.ndarray,
    slide: float,
    weights: np.ndarray,
    reach: np.ndarray,
    delta: float,
    stiffness: np.ndarray,
    margin: float,
) -> tuple[np.ndarray, np.ndarray]:
    """(size (P, 3), held (P,) N/mm) of ``reachable_springs`` in one pass, to the bit: each
    point's |lambda_k| + delta (its weights clipped to [-margin, 1 + 2 margin] beside a
    growth) and c_p k_p where it may touch until the next evaluation (its gap under the
    slide, and beside a growth or not past its facing triangle's reach by more than delta),
    else 0; c_p the fade's factor (``ply_fade.stiffness_factor``).

    Parameters
    ----------
    past, beside : (P,) bool
        The points in the fade's band past an outline edge, and beside a growth or a wedge.
    reached : (P,) float
        The deepest each point may touch until then, mm.
    faded : float
        The fade's length D, mm.
    gap : (P,) float
        The points' gaps, mm.
    slide : float
        The slide until then, mm.
    weights, reach : (P, 3) float
        The barycentric coordinates on the facing triangle and its reach past its edges.
    delta : float
        The slide over the least height.
    stiffness : (P,) float
        The points' penalties, N/mm.
    margin : float
        ``ply_projection.MARGIN``.
    """
    count = len(weights)
    size, held = np.empty((count, 3)), np.empty(count)
    # as stiffness_factor computes them: numpy's square root, Python's larger
    cross = float(np.sqrt(1.0 + (0.75 / SIDEWAYS) ** 2))
    angle = float(max(1.0, SIDEWAYS_STIFFNESS))
    _held(
        np.ascontiguousarray(past, dtype=np.bool_), np.ascontiguousarray(beside, dtype=np.bool_),
        np.ascontiguousarray(reached, dtype=float), float(faded), cross, angle, read_only(gap),
        float(slide), read_only(weights), read_only(reach), float(delta), -float(margin),
        1.0 + 2.0 * float(margin), np.ascontiguousarray(stiffness, dtype=float), size, held,
    )  # fmt: skip
    return size, held
