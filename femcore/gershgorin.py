"""Gershgorin's bound on the largest eigenvalue of M^-1/2 K M^-1/2 from element tangent blocks,
without assembling K: the explicit solver's assembled stable step
(``CompiledModel.assembled_stable_dt``).

The bound is max_i s_i sum_j |K_ij| s_j over the slots of the DOF map (n nodes x 5), with
s = M^-1/2 on the free slots and 0 elsewhere, K in generalised coordinates (T^T K T per node
pair, T the node maps of ``DofManager.node_maps``). K_ij sums the blocks of every cell that
holds both nodes before the absolute value is taken, so the blocks are summed per node pair
first: a compiled loop over the cells in their order into the node pairs they make, a piece
of the tangent at a time as the blocks give them (``ElementBlock.tangent_pieces``: the
Mindlin block never holds all its cells' 18 x 18 matrices, 2.6 kB a triangle), then each
pair's pieces summed in their order (the same sums whatever the threads) and the row sums.
A SparseTangent given in BSR with 6 x 6 blocks (the fibrous membrane's) is read block by
block, each block a node pair: T_a^T K_ab T_b formed per block, without scipy's T^T K T, its
conversions and a sort of the entries (the bound of a 20k-triangle fibrous sheet
on one thread: 2.3-2.6 s CPU with the conversions, 0.76-0.98 s without, the same number, at a
load of 10 on 2 cores).
A sparse assembly of the same (``femcore.assembly.tangent_matrix``) cost three times the
time and twice the memory at 100k triangles, most of it in scipy's conversions.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

import numpy as np
import scipy.sparse as sp

from femcore import kernel_cache
from femcore.assembly import CellTangent, TangentPart, generalised_sparse

__all__ = ["gershgorin_largest"]


def _add_transformed(ta, k, tb, right, target):
    """target (5, 5) += T_a^T K T_b, K (6, 6) a node pair's block and T (6, 5) the nodes' maps:
    K T_b first into ``right`` (6, 5), then T_a^T (right)."""
    for i in range(6):
        for c in range(5):
            total = 0.0
            for j in range(6):
                total += k[i, j] * tb[j, c]
            right[i, c] = total
    for r in range(5):
        for c in range(5):
            total = 0.0
            for i in range(6):
                total += ta[i, r] * right[i, c]
            target[r, c] += total


def _pair_sums(nodes, pair_of, blocks, maps, components, out):
    """Add T_a^T K_ab T_b (5 x 5; K_ab itself, top left, for translations-only blocks) of
    each cell's node pair (a, b) into out[pair_of[cell, a, b]] (pairs, 5, 5)."""
    m, p = nodes.shape
    right = np.empty((6, 5))
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
                _add_transformed(ta, k, tb, right, target)


def _bsr_sums(indptr, indices, blocks, maps, out):
    """out[entry] (5 x 5) = T_a^T K_ab T_b of each stored 6 x 6 block of a BSR matrix (blocks
    (entries, 6, 6); a the block row, b = indices[entry]): K T_b first (6 x 5), then T_a^T."""
    n = indptr.shape[0] - 1
    right = np.empty((6, 5))
    for a in range(n):
        ta = maps[a]
        for entry in range(indptr[a], indptr[a + 1]):
            tb = maps[indices[entry]]
            _add_transformed(ta, blocks[entry], tb, right, out[entry])


def _row_bound(keys, order, sums, scale, n_nodes):
    """max over slots i of s_i sum_j |K_ij| s_j: the pieces' node-pair sums (entries, 5, 5)
    of node pairs keys (entries,), sorted by ``order``, summed per pair in the pieces'
    order, then taken absolutely into the rows."""
    rows = np.zeros(scale.shape[0])
    block = np.empty((5, 5))
    position = 0
    while position < order.shape[0]:
        key = keys[order[position]]
        block[:, :] = 0.0
        while position < order.shape[0] and keys[order[position]] == key:
            entry = order[position]
            for r in range(5):
                for c in range(5):
                    block[r, c] += sums[entry, r, c]
            position += 1
        _add_row(block, key // n_nodes, key % n_nodes, scale, rows)
    return _largest(rows, scale)


def _add_row(block, a, b, scale, rows):
    """rows[5 a + r] += sum_c |block[r, c]| s_(5 b + c): a node pair's share of node a's
    row sums."""
    for r in range(5):
        total = 0.0
        for c in range(5):
            total += abs(block[r, c]) * scale[5 * b + c]
        rows[5 * a + r] += total


def _largest(rows, scale):
    """max over slots i of rows[i] s_i."""
    largest = 0.0
    for i in range(rows.shape[0]):
        value = rows[i] * scale[i]
        if value > largest:
            largest = value
    return largest


def _merge(held_keys, held, keys, order, sums, out_keys, out):
    """The node pairs still open (held_keys (h,) sorted, their sums held (h, 5, 5)) with a
    piece's (keys (e,), its stable sort ``order``, sums (e, 5, 5)) into out_keys, out: every
    pair once, sorted, each piece entry added in its order after what was held (0 + s1 + s2
    ..., the sums of ``_row_bound``). Returns the number of pairs written."""
    i = j = k = 0
    while i < held_keys.shape[0] or j < order.shape[0]:
        if j >= order.shape[0] or (i < held_keys.shape[0] and held_keys[i] <= keys[order[j]]):
            key = held_keys[i]
            out[k] = held[i]
            i += 1
        else:
            key = keys[order[j]]
            out[k] = 0.0
        while j < order.shape[0] and keys[order[j]] == key:
            entry = order[j]
            for r in range(5):
                for c in range(5):
                    out[k, r, c] += sums[entry, r, c]
            j += 1
        out_keys[k] = key
        k += 1
    return k


def _close(keys, sums, count, open_nodes, closed, scale, n_nodes, rows):
    """Take the pairs (a, b) of keys[:count] whose node a is not in ``open_nodes`` (n,) bool
    into the row sums ``rows`` (their node a met by no later piece: its row is complete),
    marking a ``closed``; the others are moved to the front, in order. Returns their count."""
    kept = 0
    for e in range(count):
        a = keys[e] // n_nodes
        if open_nodes[a]:
            keys[kept] = keys[e]
            for r in range(5):
                for c in range(5):
                    sums[kept, r, c] = sums[e, r, c]
            kept += 1
        else:
            _add_row(sums[e], a, keys[e] % n_nodes, scale, rows)
            closed[a] = True
    return kept


if kernel_cache.AVAILABLE:
    # Spliced into both loops (numba's inlining): a call with array arguments per node pair
    # would cost their reference counting.
    _add_transformed = kernel_cache.njit(_add_transformed, inline="always")
    _add_row = kernel_cache.njit(_add_row, inline="always")
    _largest = kernel_cache.njit(_largest)
    _merge = kernel_cache.njit(_merge)
    _close = kernel_cache.njit(_close)
    _pair_sums = kernel_cache.njit(_pair_sums)
    _row_bound = kernel_cache.njit(_row_bound)
    _bsr_sums = kernel_cache.njit(_bsr_sums)


class _Sums:
    """The pieces' node-pair sums one after the other in one array, grown in place
    (``ndarray.resize``: the kernel moves the pages, nothing is copied, and only the rows
    written are ever in memory): a concatenation at the end would hold them twice."""

    def __init__(self) -> None:
        self.rows = np.empty((0, 5, 5))
        self.used = 0

    def region(self, count: int) -> np.ndarray:
        """The next ``count`` rows, zeroed, to sum a piece into."""
        needed = self.used + count
        if needed > len(self.rows):
            self.rows.resize((max(needed, 2 * len(self.rows)), 5, 5), refcheck=False)
        region = self.rows[self.used : needed]
        region[:] = 0.0
        self.used = needed
        return region


def _piece_sums(piece: TangentPart, maps: np.ndarray, n_nodes: int, sums: _Sums) -> np.ndarray:
    """The node-pair keys a n + b (pairs,) of one tangent piece, its summed generalised
    5 x 5 blocks added to ``sums`` in their order."""
    if isinstance(piece, CellTangent):
        nodes = np.ascontiguousarray(piece.nodes, dtype=np.int64)
        flat = (nodes[:, :, None] * n_nodes + nodes[:, None, :]).ravel()
        keys, pair_of = np.unique(flat, return_inverse=True)
        blocks = np.ascontiguousarray(piece.blocks, dtype=np.float64)
        where = pair_of.reshape(nodes.shape + nodes.shape[1:2])
        _pair_sums(nodes, where, blocks, maps, blocks.shape[2], sums.region(len(keys)))
        return keys
    given = piece.matrix
    if sp.issparse(given) and given.format == "bsr" and given.blocksize == (6, 6):
        if given.shape == (6 * n_nodes, 6 * n_nodes):  # else generalised_sparse's error
            # Its blocks are the node pairs: T_a^T K_ab T_b of each, no conversion (the
            # fibrous membrane's J^T H J, tangent_kernels.MembraneProduct, comes as one).
            indptr = np.asarray(given.indptr, dtype=np.int64)
            indices = np.asarray(given.indices, dtype=np.int64)
            rows = np.repeat(np.arange(n_nodes, dtype=np.int64), np.diff(indptr))
            data = np.ascontiguousarray(given.data, dtype=np.float64)
            _bsr_sums(indptr, indices, data, maps, sums.region(len(indices)))
            return rows * n_nodes + indices
    matrix = generalised_sparse(piece, maps).tocoo()
    row, col = matrix.row.astype(np.int64), matrix.col.astype(np.int64)
    keys, pair_of = np.unique((row // 5) * n_nodes + col // 5, return_inverse=True)
    np.add.at(sums.region(len(keys)), (pair_of.ravel(), row % 5, col % 5), matrix.data)
    return keys


def gershgorin_largest(
    pieces: Iterable[TangentPart],
    maps: np.ndarray,
    scale: np.ndarray,
    n_nodes: int,
    again: Callable[[], Iterable[TangentPart]] | None = None,
) -> float:
    """max_i s_i sum_j |K_ij| s_j (1/s^2 when s = M^-1/2) of the generalised tangent whose
    pieces (CellTangent blocks (m, p, c, p, c), c = 6 (u, psi) or 3 (u); SparseTangent
    matrices) are given, taken one at a time as they come.

    Parameters
    ----------
    pieces : the tangent's parts (``ElementBlock.tangent_pieces``).
    maps : (n, 6, 5) node maps (u, psi) = T q.
    scale : (5 n,) s per slot, 0 off the free slots.
    n_nodes : n.
    again : a function giving the same pieces afresh, or None. Given, a node's row is summed
        and its pairs dropped as soon as a piece does not hold it (``_streamed``: the pairs of
        a few pieces are held instead of all of them); should a later piece hold it after
        all, the bound is made again from ``again()`` with every pair held. None: every pair
        held. The same number to the last bit either way.
    """
    if again is not None:
        streamed = _streamed(pieces, maps, scale, n_nodes)
        if streamed is not None:
            return streamed
        pieces = again()
    sums = _Sums()
    keys = [_piece_sums(piece, maps, n_nodes, sums) for piece in pieces]
    if not keys:
        return 0.0
    all_keys = np.concatenate(keys)
    order = np.argsort(all_keys, kind="stable")  # a pair's pieces in their order
    rows = sums.rows[: sums.used]
    return float(_row_bound(all_keys, order, rows, np.ascontiguousarray(scale), n_nodes))


def _streamed(
    pieces: Iterable[TangentPart], maps: np.ndarray, scale: np.ndarray, n_nodes: int
) -> float | None:
    """``gershgorin_largest`` holding only the node pairs whose row may still grow: after each
    piece, the pairs (a, b) whose node a the piece does not hold are summed into a's rows and
    dropped (a cell-ordered mesh's pieces of consecutive cells share only the nodes along
    their borders). Each pair is summed in the pieces' order and each row over its pairs in
    the order of b, as ``_row_bound`` does: the same number to the last bit. None when a
    piece holds a node already summed (a mesh whose cells are not in a banded order)."""
    scale = np.ascontiguousarray(scale)
    rows = np.zeros(scale.shape[0])
    closed = np.zeros(n_nodes, dtype=bool)
    open_nodes = np.zeros(n_nodes, dtype=bool)
    held_keys, held = np.empty(0, dtype=np.int64), np.empty((0, 5, 5))
    for piece in pieces:
        sums = _Sums()
        keys = _piece_sums(piece, maps, n_nodes, sums)
        del piece  # read: not held while the next one is made
        first = keys // n_nodes
        if closed[first].any():
            return None
        order = np.argsort(keys, kind="stable")
        out_keys = np.empty(len(held_keys) + len(keys), dtype=np.int64)
        out = np.empty((len(out_keys), 5, 5))
        count = _merge(held_keys, held, keys, order, sums.rows[: sums.used], out_keys, out)
        del sums
        open_nodes[:] = False
        open_nodes[first] = True
        kept = _close(out_keys, out, count, open_nodes, closed, scale, n_nodes, rows)
        held_keys, held = out_keys[:kept].copy(), out[:kept].copy()
        del out_keys, out
    open_nodes[:] = False
    _close(held_keys, held, len(held_keys), open_nodes, closed, scale, n_nodes, rows)
    return float(_largest(rows, scale))
