"""Gershgorin's bound on the largest eigenvalue of M^-1/2 K M^-1/2 from element tangent blocks,
without assembling K: the explicit solver's assembled stable step
(``CompiledModel.assembled_stable_dt``).

The bound is max_i s_i sum_j |K_ij| s_j over the slots of the DOF map (n nodes x 5), with
s = M^-1/2 on the free slots and 0 elsewhere, K in generalised coordinates (T^T K T per node
pair, T the node maps of ``DofManager.node_maps``). K_ij sums the blocks of every cell that
holds both nodes before the absolute value is taken, so the blocks are summed per node pair
first: a compiled loop over the cells in their order into the node pairs they make, a piece
of the tangent at a time as the blocks give them (``ElementBlock.tangent_pieces``: the
Mindlin block never holds all its cells' 18 x 18 matrices, 2.6 kB a triangle), each piece's
blocks added onto the sums its pairs hold so far: a pair's sum is 0 plus its blocks in order,
the same bits however the blocks are parted into pieces (and whatever the threads); then the
row sums, each over its pairs in order.
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


def _merge(held_keys, held, taken, keys, sums, out_keys, out):
    """The pairs held and not ``taken`` (held_keys (h,) sorted, their sums held (h, 5, 5))
    and a piece's (keys (e,) sorted, each once, sums (e, 5, 5)) into out_keys, out, sorted:
    two sorted runs merged, nothing added."""
    i = j = k = 0
    while i < held_keys.shape[0] or j < keys.shape[0]:
        if i < held_keys.shape[0] and taken[i]:
            i += 1
            continue
        if j >= keys.shape[0] or (i < held_keys.shape[0] and held_keys[i] < keys[j]):
            out_keys[k] = held_keys[i]
            out[k] = held[i]
            i += 1
        else:
            out_keys[k] = keys[j]
            out[k] = sums[j]
            j += 1
        k += 1


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
    _bsr_sums = kernel_cache.njit(_bsr_sums)


def _started(
    keys: np.ndarray, held_keys: np.ndarray, held: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The sums (pairs, 5, 5) a piece of node pairs ``keys`` (sorted, each once) adds its
    blocks to: the held sums of the pairs held (held_keys sorted, held (h, 5, 5)), 0 for the
    others; and which held pairs (h,) bool they took."""
    sums = np.zeros((len(keys), 5, 5))
    taken = np.zeros(len(held_keys), dtype=bool)
    if len(held_keys) and len(keys):
        at = np.minimum(np.searchsorted(held_keys, keys), len(held_keys) - 1)
        found = held_keys[at] == keys
        sums[found] = held[at[found]]
        taken[at[found]] = True
    return sums, taken


def _piece_sums(
    piece: TangentPart, maps: np.ndarray, n_nodes: int, held_keys: np.ndarray, held: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The node-pair keys a n + b (pairs,) of one tangent piece, sorted, each once; their
    sums: the held sum of each pair (0 where none) plus the piece's generalised 5 x 5 blocks
    in their order; which held pairs they took (``_started``)."""
    if isinstance(piece, CellTangent):
        nodes = np.ascontiguousarray(piece.nodes, dtype=np.int64)
        flat = (nodes[:, :, None] * n_nodes + nodes[:, None, :]).ravel()
        keys, pair_of = np.unique(flat, return_inverse=True)
        blocks = np.ascontiguousarray(piece.blocks, dtype=np.float64)
        where = pair_of.reshape(nodes.shape + nodes.shape[1:2])
        sums, taken = _started(keys, held_keys, held)
        _pair_sums(nodes, where, blocks, maps, blocks.shape[2], sums)
        return keys, sums, taken
    given = piece.matrix
    if sp.issparse(given) and given.format == "bsr" and given.blocksize == (6, 6):
        # else generalised_sparse's error, or its sums of repeated blocks
        if given.shape == (6 * n_nodes, 6 * n_nodes) and given.has_canonical_format:
            # Its blocks are the node pairs, each once and sorted: T_a^T K_ab T_b of each, no
            # conversion (the fibrous membrane's J^T H J comes as one).
            matrix = given
            indptr = np.asarray(matrix.indptr, dtype=np.int64)
            indices = np.asarray(matrix.indices, dtype=np.int64)
            rows = np.repeat(np.arange(n_nodes, dtype=np.int64), np.diff(indptr))
            data = np.ascontiguousarray(matrix.data, dtype=np.float64)
            keys = rows * n_nodes + indices
            sums, taken = _started(keys, held_keys, held)
            _bsr_sums(indptr, indices, data, maps, sums)
            return keys, sums, taken
    matrix = generalised_sparse(piece, maps).tocoo()
    row, col = matrix.row.astype(np.int64), matrix.col.astype(np.int64)
    keys, pair_of = np.unique((row // 5) * n_nodes + col // 5, return_inverse=True)
    sums, taken = _started(keys, held_keys, held)
    np.add.at(sums, (pair_of.ravel(), row % 5, col % 5), matrix.data)
    return keys, sums, taken


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
        and its pairs dropped as soon as a piece does not hold it (the pairs of a few pieces
        are held instead of all of them); should a later piece hold it after all, the bound
        is made again from ``again()`` with every pair held. None: every pair held. The same
        number to the last bit either way.
    """
    if again is not None:
        streamed = _summed(pieces, maps, scale, n_nodes, stream=True)
        if streamed is not None:
            return streamed
        pieces = again()
    summed = _summed(pieces, maps, scale, n_nodes, stream=False)
    assert summed is not None  # nothing is summed before the end
    return summed


def _summed(
    pieces: Iterable[TangentPart], maps: np.ndarray, scale: np.ndarray, n_nodes: int, stream: bool
) -> float | None:
    """``gershgorin_largest``: each piece's blocks added to the sums of its node pairs as it
    comes, in its order, so that a pair's sum is 0 + its blocks in the pieces' order and in
    each piece's own, however the blocks are parted into pieces; each row then summed over its
    pairs in the order of b. ``stream``: after each piece, the pairs (a, b) whose node a the
    piece does not hold are summed into a's rows and dropped (a cell-ordered mesh's pieces of
    consecutive cells share only the nodes along their borders); None when a piece holds a
    node already summed (a mesh whose cells are not in a banded order). Else every pair is
    held to the end."""
    scale = np.ascontiguousarray(scale)
    rows = np.zeros(scale.shape[0])
    closed = np.zeros(n_nodes, dtype=bool)
    open_nodes = np.zeros(n_nodes, dtype=bool)
    held_keys, held = np.empty(0, dtype=np.int64), np.empty((0, 5, 5))
    for piece in pieces:
        keys, sums, taken = _piece_sums(piece, maps, n_nodes, held_keys, held)
        del piece  # read: not held while the next one is made
        first = keys // n_nodes
        if stream and closed[first].any():
            return None
        # The pairs of the piece (their sums go on from the held ones) among the others held.
        out_keys = np.empty(len(held_keys) - int(taken.sum()) + len(keys), dtype=np.int64)
        out = np.empty((len(out_keys), 5, 5))
        _merge(held_keys, held, taken, keys, sums, out_keys, out)
        del sums, held
        if stream:
            open_nodes[:] = False
            open_nodes[first] = True
            kept = _close(out_keys, out, len(out_keys), open_nodes, closed, scale, n_nodes, rows)
            held_keys, held = out_keys[:kept].copy(), out[:kept].copy()
        else:
            held_keys, held = out_keys, out
        del out_keys, out
    open_nodes[:] = False
    _close(held_keys, held, len(held_keys), open_nodes, closed, scale, n_nodes, rows)
    return float(_largest(rows, scale))
