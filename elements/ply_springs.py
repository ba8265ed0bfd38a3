"""The ply contact's springs for the explicit step, per node and held until the step is next
evaluated (docs/theory.md §6.2, "The penalty springs"; ``PlyContactBlock.springs_at``).

The promise (femcore/interaction.py, ``springs``): at every state the contact can reach
before the step is evaluated again (``SPRINGS_HELD_STEPS`` steps later), its stiffness K
satisfies x^T K x <= sum_s k_s |u_s|^2, u_s the translation of spring s's node.

One point. A point p of penalty k_p whose faded energy's stiffness is at most c_p k_p along
any direction (elements/ply_fade.py, "Stiffness"; the friction's stick spring at most k_p
across the normal) adds at most c_p k_p |a . u|^2, a . u = sum_j N_j u_j - sum_k lambda_k
y_k, u the upper corners' and y the lower ones' translations, lambda the barycentric
coordinates of its projection on its facing triangle. By Cauchy-Schwarz |a . u|^2 <= (sum |a|)
sum |a_i| |u_i|^2 with sum |a| = s_p = 1 + sum_k |lambda_k| (2 inside the triangle, more past
its outline edge): upper node j gets c_p k_p s_p N_j, lower node k gets c_p k_p s_p
|lambda_k|, summed over every point, touching or not (a point not touching now may touch
before the next evaluation).

Weights. Cauchy-Schwarz with node weights v > 0 holds as well: |a . u|^2 <= (sum_i |a_i|
v_i) (sum_i |a_i| |u_i|^2 / v_i), so node i may take c_p k_p |a_i| F_p / v_i with F_p =
sum_j |a_j| v_j (equal weights: F_p = s_p, the springs above). The explicit step divides
each node's springs by its mass m_i, and the best weights are the largest mode of M^-1 |K|
(Collatz-Wielandt: max_i (M^-1 |K| v)_i / v_i >= lambda_max(M^-1 |K|) for every v > 0, with
equality at its Perron vector), |K| = sum_p c_p k_p |a_p| |a_p|^T: the weights start at v =
1 / m (exact for one spring, k (1 / m_1 + 1 / m_2) for a spring between two nodes, where
equal weights give 2 k / m_light) and take ``WEIGHT_ITERATIONS`` power iterations v <- M^-1
L(v), L_i(v) = sum_p c_p k_p |a_p,i| F_p(v). Whatever the iterations give, the springs bound
the stiffness: they only choose v. The masses are those the contact was calibrated with
(the explicit step's, mass scaling included: ``penalty_frequency_squared`` hands them down;
else those of ``PlyContactBlock.calibrate``); uncalibrated, or a mass not positive and
finite, equal weights.
F_p is bounded over every state the point reaches until then (below): sum_j N_j v_j plus the
least of sum over its facing triangle's corners of (|lambda_k| + delta) v_k with delta v_i
over the ring's nodes that may take it, and (s_p - 1) times the largest v of those nodes.

Until the next evaluation. The points slide on the lower face by at most ``slide`` (mm): the
fastest point's speed against the lower face's point it faces, over the held steps at the
step's largest value (which the solver gives: solvers/explicit_step_size.py ``_step_size``), times
``GROWTH`` for the speed's growth until then, and at least ``FLOOR`` of
the lower triangles' least height (plies at rest start to move: a floor, not a bound). Then:

- lambda: a lower node's hat function phi_k has a gradient of at most 1 / h on the face, h
  the least height of the lower triangles, so a point's lambda_k moves by at most delta = s /
  h: the point's own nodes take |lambda_k| + delta, and s_p takes 3 delta more.
- the points that may face a lower node's triangles (its star) by then: while s < h, the
  points facing a triangle that shares a vertex with the star (a triangle sharing none lies at
  least a height away on a planar face) and may enter it, with lambda_k at most delta there.
  The lower node gets delta c_p k_p s_p from each of them (``ring``: the triangles that share a
  vertex with the star but are not in it). A facing that jumps across a fold of the lower ply
  (between its sheets, not a slide on the face) is not covered.
- c_p: the fade's factor (12 + 3 A x + 3 x^2 beside a growth or an outline vertex, 1 + 3 A x
  + 3 x^2 past an outline edge, 1 elsewhere) is taken at the largest a point can reach: the
  beside figure for a point beside now or within s + r + 3 D of an outline vertex (r the
  deepest it touches, D the fade's length: beside a growth its energy is nonzero within r of
  its closest point and D of the outline, and a growth's side edge within 70 deg of the outline
  edge's normal puts that within 3 D of the vertex), the past figure for a point past an
  outline edge now or within delta of one (lambda_k < delta for an outline edge opposite k),
  depth x = r / D with r its own depth plus s where it touches deeper than the plies.
- s >= h: the ring no longer bounds the points' reach; every point takes the beside figure and
  every lower node the whole load sum_p c_p k_p s_p (safe, and as short a step as it gives;
  equal weights there).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

from elements import ply_kernels, ply_projection, ply_springs_kernels
from elements.kept_bits import same_bits
from elements.ply_fade import OutlineTree, nearest_segments, outline_segments, stiffness_factor
from elements.ply_projection import MARGIN, triangle_frames
from femcore.interaction import SPRINGS_HELD_STEPS

__all__ = ["FLOOR", "GROWTH", "STEP_GROWTH", "reachable_springs", "ring_matrix", "slide"]

#: How much the plies' relative speed may grow until the next evaluation.
GROWTH = 2.0
#: The step's largest value in times the critical step without contact that the contact was
#: calibrated with, where the caller does not give it (the cells' bound moves with the
#: geometry; the solver's safety is below 1).
STEP_GROWTH = 2.0
#: The least slide counted, in times the lower triangles' least height: plies at rest (the
#: start of a stroke) start to move before the next evaluation.
FLOOR = 0.01
#: A growth's side edge lies within 70 deg of its outline edge's normal: a point beside it
#: and within the fade's length D of the outline lies within D / cos(70 deg) < 3 D of the vertex.
BESIDE_REACH = 3.0


def slide(block, state, facing, step: float) -> float:
    """The largest move of a point against the lower face until the next evaluation, mm: the
    fastest point's speed against its facing triangle's point (sum_j N_j v_j - sum_k lambda_k
    v_k, plus the plies' depth times both sets' largest angular speed: the offsets along the
    directors turn with them) times ``GROWTH`` over ``SPRINGS_HELD_STEPS`` steps of ``step``
    s (0 for plies at rest: the step need not be known)."""
    v, spins = state.velocities, state.angular_velocities
    if not (np.any(v) or np.any(spins)):
        return 0.0
    if ply_projection.COMPILED:  # the same bits, one compiled pass (ply_springs_kernels.py)
        fastest = ply_springs_kernels.fastest_point(
            block.shape, block.above, facing.weights, block.cells, facing.triangle, v, spins,
            block.depth, MARGIN,
        )  # fmt: skip
        return GROWTH * fastest * SPRINGS_HELD_STEPS * step
    own = np.einsum("pj,pji->pi", block.shape, v[block.above])
    facing_corners = block.cells[facing.triangle]
    # (far past their triangle's reach the points carry nothing: their weights held there)
    weights = np.clip(facing.weights, -MARGIN, 1.0 + 2.0 * MARGIN)
    other = np.einsum("pk,pki->pi", weights, v[facing_corners])
    speed = np.sqrt(np.einsum("pi,pi->p", own - other, own - other))
    spin = np.sqrt(np.einsum("ij,ij->i", spins, spins))
    turning = block.depth * (spin[block.above].max(axis=1) + spin[facing_corners].max(axis=1))
    fastest = float(np.max(speed + turning)) if len(speed) else 0.0
    return GROWTH * fastest * SPRINGS_HELD_STEPS * step


def ring_matrix(cells: np.ndarray, lower_nodes: np.ndarray) -> sp.csr_matrix:
    """(l, m) 0/1: lower node i (a row of ``lower_nodes``) and triangle T of ``cells`` (m, 3)
    where T shares a vertex with a triangle of i's star but is not in it."""
    rows = np.searchsorted(lower_nodes, cells.ravel())
    m = len(cells)
    star = sp.csr_matrix(
        (np.ones(3 * m), (rows, np.repeat(np.arange(m), 3))), shape=(len(lower_nodes), m)
    )
    near = (star @ (star.T @ star)) > 0  # triangles sharing a vertex with the star, or in it
    return sp.csr_matrix(near.astype(float) - (star > 0).astype(float))


def reachable_springs(
    block, state, facing, y: np.ndarray, step: float | None = None, mass=None
) -> tuple[np.ndarray, np.ndarray]:
    """(nodes, stiffness N/mm) of ``block`` (a PlyContactBlock on flat faces with a fade)
    held until the next evaluation (module docstring).

    Parameters
    ----------
    block : PlyContactBlock
        Its points' penalties ``stiffness`` (P,), shapes, lower cells, outline, depth, fade
        length, calibrated step.
    state : State
        The state (its velocities and angular velocities).
    facing : Facing
        The points' facing at the state (elements/ply_projection.py).
    y : (m, 3, 3) float
        The lower face's corners at the state, mm.
    step : float, optional
        The largest step until the next evaluation, s (None: ``STEP_GROWTH`` times the
        critical step the contact was calibrated with).
    mass : (n,) float, optional
        The lumped masses the explicit step divides the springs by, t (mass scaling
        included): they weigh the nodes (None: those the block was calibrated with).
    """
    nodes = np.concatenate([block.upper, block.lower_nodes])
    step = STEP_GROWTH * block.calibrated_dt if step is None else step
    s = slide(block, state, facing, step)
    if ply_projection.COMPILED:  # the same bits, one compiled pass (ply_kernels.py)
        least = 1.0 / ply_kernels.largest_gradient(y)
    else:
        least = 1.0 / float(np.max(np.linalg.norm(triangle_frames(y)[2], axis=-1)))
    # plies at rest start to move before the next evaluation: at least FLOOR of a height
    s = max(s, FLOOR * least) if np.isfinite(s) else np.inf
    weights = facing.weights
    faded = block.fade_length
    if (
        not s < least
    ):  # the ring does not hold (or no calibrated step): every point beside, every lower node all
        factor = stiffness_factor(
            np.ones(len(weights), bool), np.ones(len(weights), bool), block.depth + s, faded
        )
        load = block.stiffness * factor * (1.0 + np.abs(weights).sum(axis=1) + 3.0)
        upper = block._lumped(load)[block.upper]
        lower = np.full(len(block.lower_nodes), float(load.sum()))
        return nodes, np.concatenate([upper, lower])
    delta = s / least
    # the fade's factor at the largest the point can reach until then
    reached = np.where(facing.touching, np.maximum(block.depth, -facing.gap + s), block.depth)
    past = np.any((facing.reach > 0.0) & (facing.weights < 0.0), axis=1)
    beside = facing.on_growth.copy()
    if facing.joined is not None:
        past |= facing.joined
        beside &= ~facing.joined
    rows, ends, wedges = _outline(block)
    if len(rows):
        # a point may pass the outline until then where its projection lies within s of it:
        # the point itself within s + |g| of it
        ends_at = y[rows[:, None], ends]  # (E, 2, 3)
        # only a point facing a triangle with a corner on the outline, or past its edge, lies
        # within s < h of the outline (any other triangle lies a height from it)
        rim = getattr(block, "_rim_triangles", None)
        if rim is None:
            on_outline = np.zeros(block.n_nodes, bool)
            on_outline[block.cells[rows[:, None], ends]] = True
            rim = block._rim_triangles = on_outline[block.cells].any(axis=1)
        if ply_projection.COMPILED:  # the same flags, one compiled pass (ply_springs_kernels.py)
            near_edge = ply_springs_kernels.near_outline(
                facing.face, facing.triangle, weights, rim, facing.gap, ends_at[:, 0],
                ends_at[:, 1], s,
            )  # fmt: skip
        else:
            tree = getattr(block, "_springs_tree", None)
            if tree is None:
                tree = block._springs_tree = OutlineTree()
            asked = np.flatnonzero(rim[facing.triangle] | np.any(weights < 0.0, axis=1))
            face = facing.face[asked]
            nearest = nearest_segments(face, ends_at[:, 0], ends_at[:, 1], tree)
            near_edge = np.zeros(len(weights), bool)
            near_edge[asked] = _distance(face, ends_at[nearest]) <= s + np.abs(facing.gap[asked])
        past |= near_edge
        # only a point near an edge can lie beside a wedge: the others are not asked (a
        # point's distance is the tree's whichever others are asked with it)
        edged = np.flatnonzero(near_edge)
        if len(wedges) and len(edged):
            radius = s + float(np.max(reached)) + BESIDE_REACH * faded
            distance = cKDTree(y[wedges[:, 0], wedges[:, 1]]).query(
                facing.face[edged], distance_upper_bound=radius
            )[0]
            beside[edged] |= distance <= radius
    if ply_projection.COMPILED:  # the same numbers, one compiled pass (ply_springs_kernels.py)
        size, held = ply_springs_kernels.held_points(
            past, beside, reached, faded, facing.gap, s, weights, facing.reach, delta,
            block.stiffness, MARGIN,
        )  # fmt: skip
    else:
        factor = stiffness_factor(past, beside, reached, faded)
        # the points that may touch until then: within s of the face, and not past their
        # facing triangle's reach by more than the slide (a point beside a growth is held)
        counted = (facing.gap < s) & (beside | ~np.any(weights < -(facing.reach + delta), axis=1))
        # beside a growth the gap's lower weights are its closest point's, within the reach
        weights = np.where(beside[:, None], np.clip(weights, -MARGIN, 1.0 + 2.0 * MARGIN), weights)
        size = np.abs(weights) + delta  # (P, 3): |lambda_k| and its move until then
        held = np.where(counted, block.stiffness * factor, 0.0)  # c_p k_p
    ring = getattr(block, "_ring", None)
    if ring is None:
        ring = block._ring = ring_matrix(block.cells, block.lower_nodes)
    mass = block.calibrated_mass if mass is None else mass
    v = None if mass is None else _node_weights(block, mass, held, size, facing.triangle, delta)
    if v is None:  # equal weights: sum_i |a_i| <= s_p
        spread = 1.0 + size.sum(axis=1)
    else:  # sum_i |a_i| v_i over the nodes the point may reach (module docstring, "Weights")
        spread = _weighted_reach(block, v, size, facing.triangle, delta)
    load = held * spread
    if ply_projection.COMPILED:  # the same sums, one compiled pass (ply_springs_kernels.py)
        lumped, cornered, ringed = _spread(block, load, size, facing.triangle)
        upper = lumped[block.upper]
        lower = cornered[block.lower_nodes] + delta * ringed
    else:
        corners = block.cells[facing.triangle]
        upper = block._lumped(load)[block.upper]
        at = np.bincount(corners.ravel(), (load[:, None] * size).ravel(), block.n_nodes)[
            block.lower_nodes
        ]
        on_triangles = np.bincount(facing.triangle, load, len(block.cells))
        lower = at + delta * (ring @ on_triangles)
    if v is not None:
        upper, lower = upper / v[block.upper], lower / v[block.lower_nodes]
    return nodes, np.concatenate([upper, lower])


#: Power iterations that set the nodes' weights v (module docstring, "Weights"): any v > 0
#: gives a bound; each iteration brings v nearer the largest mode of M^-1 |K|.
WEIGHT_ITERATIONS = 1
#: The least weight a power iteration gives a node a point reaches, in times the largest (any
#: weight > 0 gives a bound; a node's rounding-sized share would give it one near 0).
WEIGHT_FLOOR = 1e-12


def _weighted_reach(block, v, size, triangle, delta) -> np.ndarray:
    """(P,) an upper bound of sum_i |a_i| v_i at every state the point reaches until the next
    evaluation: sum_j N_j v_j over its upper corners plus the least of sum_k (|lambda_k| +
    delta) v_k over its facing triangle's corners and delta v_i over the lower nodes whose
    ring holds that triangle, and (sum_k |lambda_k| + 3 delta) times the largest v of them."""
    reach = getattr(block, "_reach_nodes", None)
    if reach is None:  # (m, w): the lower nodes a point facing triangle T may reach, padded
        reach = block._reach_nodes = _padded_rows(block._ring.T.tocsr())
    transposed = getattr(block, "_ring_transposed", None)
    if transposed is None:  # the ring's rows by triangle (the same sums in the same order)
        transposed = block._ring_transposed = block._ring.T.tocsr()
    if ply_projection.COMPILED:  # the same bits, one compiled pass (ply_springs_kernels.py)
        return ply_springs_kernels.weighted_reach(
            block.shape, block.above, v, size, block.cells, triangle, block.lower_nodes, reach,
            transposed, delta,
        )  # fmt: skip
    own = np.einsum("pj,pj->p", block.shape, v[block.above])
    lower_v = v[block.lower_nodes]
    largest = np.maximum(v[block.cells].max(axis=1), lower_v[reach].max(axis=1))
    along = np.einsum("pk,pk->p", size, v[block.cells[triangle]])
    along = along + delta * (transposed @ lower_v)[triangle]
    return own + np.minimum(along, size.sum(axis=1) * largest[triangle])


def _padded_rows(matrix: sp.csr_matrix) -> np.ndarray:
    """(m, w) int: the columns of each row of ``matrix`` (m, l), each row padded with its own
    first column (a row without columns with column 0: a larger maximum of what the columns
    index, never a smaller one)."""
    counts = np.diff(matrix.indptr)
    if not len(matrix.indices):
        return np.zeros((matrix.shape[0], 1), dtype=np.int64)
    rows = np.repeat(np.arange(matrix.shape[0]), counts)
    slot = np.arange(len(matrix.indices)) - np.repeat(matrix.indptr[:-1], counts)
    first = np.where(
        counts > 0, matrix.indices[np.minimum(matrix.indptr[:-1], len(matrix.indices) - 1)], 0
    )
    padded = np.repeat(first[:, None], int(counts.max()), axis=1)
    padded[rows, slot] = matrix.indices
    return padded


def _node_weights(block, mass, held, size, triangle, delta) -> np.ndarray | None:
    """(n,) the weights v > 0 of the block's nodes: 1 / m, then ``WEIGHT_ITERATIONS`` power
    iterations v <- M^-1 L(v), L(v) the nodes' loads sum_p c_p k_p |a_p,i| sum_j |a_p,j| v_j
    (module docstring, "Weights"); None where a node of the block has no positive finite
    mass (equal weights then)."""
    mass = np.asarray(mass, dtype=float)
    nodes = np.concatenate([block.upper, block.lower_nodes])
    v = _start_weights(block, mass, nodes)
    if v is None:
        return None
    for _ in range(WEIGHT_ITERATIONS):
        load = held * _weighted_reach(block, v, size, triangle, delta)
        if ply_projection.COMPILED:  # the same sums, one compiled pass (ply_springs_kernels.py)
            lumped, cornered, ringed = _spread(block, load, size, triangle)
            loads = lumped + cornered
            loads[block.lower_nodes] += delta * ringed
        else:
            loads = block._lumped(load)
            loads += np.bincount(
                block.cells[triangle].ravel(), (load[:, None] * size).ravel(), block.n_nodes
            )
            loads[block.lower_nodes] += delta * (
                block._ring @ np.bincount(triangle, load, len(block.cells))
            )
        ahead = loads[nodes] / mass[nodes]
        if not ahead.max() > 0.0:
            break
        # a node no point reaches keeps its weight (its load is 0 whatever its weight); a
        # weight under WEIGHT_FLOOR of the largest, raised to it, keeps k / v finite
        scale = ahead.max()
        v[nodes] = np.where(ahead > 0.0, np.maximum(ahead / scale, WEIGHT_FLOOR), v[nodes])
    return v


def _spread(block, load, size, triangle) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The points' loads ``load`` (P,) spread on the nodes (``ply_springs_kernels.
    spread_loads``): (n,) sum_p N_j load_p at the upper corners (``block._lumped``), (n,) sum_p
    load_p (|lambda_k| + delta) at the facing corners, (l,) the ring's sum of the loads on
    each lower node's ring of triangles (``block._ring`` times them per triangle); the ring's
    arrays kept with it."""
    ring = block._ring
    kept = getattr(block, "_ring_arrays", None)
    if kept is None or kept[0] is not ring:
        kept = block._ring_arrays = (
            ring, *(np.ascontiguousarray(a, dtype=np.int64) for a in (ring.indptr, ring.indices)),
            np.ascontiguousarray(ring.data, dtype=float),
        )  # fmt: skip
    return ply_springs_kernels.spread_loads(
        load, block.shape, block.above, size, block.cells, triangle, kept[1], kept[2], kept[3],
        block.n_nodes,
    )  # fmt: skip


def _start_weights(block, mass: np.ndarray, nodes: np.ndarray) -> np.ndarray | None:
    """(n,) the weights the power iterations start from, 1 / m at ``nodes`` scaled to a
    largest of 1 (1 elsewhere), or None where a node of the block has no positive finite
    mass. Kept with the masses' bits (the solver hands down the same masses every tenth
    step): a copy of the kept weights where ``mass`` is the same, the same numbers."""
    kept = getattr(block, "_kept_start_weights", None)
    if kept is not None and same_bits(kept[0], mass):
        return None if kept[1] is None else kept[1].copy()
    v = None
    if len(mass) == block.n_nodes and np.all(np.isfinite(mass[nodes]) & (mass[nodes] > 0.0)):
        v = np.ones(block.n_nodes)
        v[nodes] = 1.0 / mass[nodes]
        v /= v[nodes].max()
    block._kept_start_weights = (mass.copy(), v)
    return None if v is None else v.copy()


def _outline(block) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(rows (E,), ends (E, 2), wedges (w, 2)) of ``block``'s lower outline
    (``outline_segments``, ``_wedge_corners``): its cells and outline are fixed when it is
    bound, so they are found once and kept."""
    kept = getattr(block, "_springs_outline", None)
    if kept is None:
        rows, ends = outline_segments(block.outline)
        kept = block._springs_outline = (rows, ends, _wedge_corners(block.cells, rows, ends))
    return kept


def _distance(points: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """(c,) the distance of each of ``points`` (c, 3) from its segment (c, 2, 3), mm."""
    along = segments[:, 1] - segments[:, 0]
    relative = points - segments[:, 0]
    squared = np.maximum(np.einsum("ci,ci->c", along, along), np.finfo(float).tiny)
    t = np.clip(np.einsum("ci,ci->c", relative, along) / squared, 0.0, 1.0)
    return np.linalg.norm(relative - t[:, None] * along, axis=1)


def _wedge_corners(cells: np.ndarray, rows: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """(w, 2) int: (triangle row, corner) of each outline vertex beside which a point can lie
    off every growth (the angle's fade, elements/ply_fade.py): a vertex of one triangle (a
    corner of the ply) or of three and more (a cut's wedge, elements/ply_wedge.py), not one of
    two triangles, whose growths are joined along their shared edge's extension
    (elements/ply_projection.py, "Growths joined")."""
    count = np.bincount(cells.ravel(), minlength=int(cells.max()) + 1)
    pairs = np.column_stack([np.repeat(rows, 2), ends.ravel()])
    node = cells[pairs[:, 0], pairs[:, 1]]
    return pairs[count[node] != 2]
