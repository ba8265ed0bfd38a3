"""Gershgorin's bound on the largest eigenvalue of M^-1/2 K M^-1/2 from element tangent blocks,
without assembling K: the explicit solver's assembled stable step
(``CompiledModel.assembled_stable_dt``).

The bound is max_i s_i sum_j |K_ij| s_j over the slots of the DOF map (n nodes x 5), with
s = M^-1/2 on the free slots and 0 elsewhere, K in generalised coordinates (T^T K T per node
pair, T the node maps of ``DofManager.node_maps``). K_ij sums the blocks of every cell that
holds both nodes before the absolute value is taken, so the blocks are summed per node pair
first: a compiled loop over the cells in their order (the same sums whatever the threads)
into the node pairs the cells make, then the row sums. A sparse assembly of the same
(``femcore.assembly.tangent_matrix``) costs six times as much at 100k triangles, most of it
in scipy's conversions.
"""

from __future__ import annotations

import numpy as np

from femcore.assembly import CellTangent

__all__ = ["gershgorin_largest"]


def _pair_sums(nodes, pair_of, blocks, maps, components, out):
    """Add T_a^T K_ab T_b (5 x 5; K_ab itself, top left, for translations-only blocks) of
    each cell's node pair (a, b) into out[pair_of[cell, a, b]] (pairs, 5, 5)."""
    m, p = nodes.shape
    for cell in range(m):
        for a in range(p):
            ta = maps[nodes[cell, a]]
            for b in range(p):
                tb = maps[nodes[cell, b]]
                target = out[pair_of[cell, a, b]]
                k = blocks[cell, a, :, b, :]
                if components == 3:
                    for r in range(3):
                        for c in range(3):
                            target[r, c] += k[r, c]
                    continue
                for r in range(5):
                    for c in range(5):
                        total = 0.0
                        for i in range(6):
                            row = 0.0
                            for j in range(6):
                                row += k[i, j] * tb[j, c]
                            total += ta[i, r] * row
                        target[r, c] += total


def _row_bound(first, second, sums, scale):
    """max over slots i of s_i sum_j |K_ij| s_j, K_ij of the node-pair sums (pairs, 5, 5)
    of node pairs (first, second)."""
    rows = np.zeros(scale.shape[0])
    for pair in range(first.shape[0]):
        a, b = first[pair], second[pair]
        for r in range(5):
            total = 0.0
            for c in range(5):
                total += abs(sums[pair, r, c]) * scale[5 * b + c]
            rows[5 * a + r] += total
    largest = 0.0
    for i in range(rows.shape[0]):
        value = rows[i] * scale[i]
        if value > largest:
            largest = value
    return largest


try:
    import numba

    _pair_sums = numba.njit(cache=True)(_pair_sums)
    _row_bound = numba.njit(cache=True)(_row_bound)
except ImportError:  # pragma: no cover - numba is a dependency
    pass


def gershgorin_largest(
    parts: list[CellTangent], maps: np.ndarray, scale: np.ndarray, n_nodes: int
) -> float:
    """max_i s_i sum_j |K_ij| s_j (1/s^2 when s = M^-1/2) of the generalised tangent of
    the CellTangent ``parts``.

    Parameters
    ----------
    parts : CellTangent parts, blocks (m, p, c, p, c) with c = 6 (u, psi) or 3 (u).
    maps : (n, 6, 5) node maps (u, psi) = T q.
    scale : (5 n,) s per slot, 0 off the free slots.
    n_nodes : n.
    """
    pairs = [(part.nodes[:, :, None] * n_nodes + part.nodes[:, None, :]).ravel() for part in parts]
    keys, pair_of = np.unique(np.concatenate(pairs), return_inverse=True)
    sums = np.zeros((len(keys), 5, 5))
    start = 0
    for part, flat in zip(parts, pairs):
        nodes = np.ascontiguousarray(part.nodes, dtype=np.int64)
        where = pair_of[start : start + flat.size].reshape(nodes.shape + nodes.shape[1:2])
        start += flat.size
        blocks = np.ascontiguousarray(part.blocks, dtype=np.float64)
        _pair_sums(nodes, where, blocks, maps, blocks.shape[2], sums)
    first, second = np.divmod(keys, n_nodes)
    return float(_row_bound(first, second, sums, np.ascontiguousarray(scale)))
