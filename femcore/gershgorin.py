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
from femcore.assembly import CellTangent, TangentPart, generalised_sparse, kernel_nodes

__all__ = ["banded_piece", "gershgorin_largest"]

# 2^64 / golden ratio as an int64 (Fibonacci hashing: the top bits of key x _GOLDEN spread
# keys that differ in any bits over the table, ``_slots``).
_GOLDEN = 0x9E3779B97F4A7C15 - 2**64


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


def _band(connectivity, n_nodes):
    """The most cells from one cell at a node to the next cell at it, in the cells' order
    (connectivity (m, p)); 0 when no node is in two cells."""
    last = np.full(n_nodes, -1, dtype=np.int64)
    band = 0
    for cell in range(connectivity.shape[0]):
        for corner in range(connectivity.shape[1]):
            node = connectivity[cell, corner]
            if last[node] >= 0 and cell - last[node] > band:
                band = cell - last[node]
            last[node] = cell
    return band


def _slots(table, shift, slot_keys, count, keys, slots):
    """The slot of each of ``keys`` (e,) in slots (e,): the slot holding it, found through
    ``table`` (open addressing, a power of 2 long, -1 where free; a key's first probe the top
    bits of key x 2^64 / golden ratio, ``shift`` = 64 - log2(len(table))), or a new one,
    count, count + 1, ... whose key is written to slot_keys. Returns the count of slots."""
    mask = table.shape[0] - 1
    for e in range(keys.shape[0]):
        key = keys[e]
        # the product's bits 64 - log2(len) to 63: int64 arithmetic wraps, and Python's int
        # (no compiler) has the same low 64 bits
        probe = ((int(key) * _GOLDEN) >> shift) & mask
        while True:
            slot = table[probe]
            if slot < 0:
                table[probe] = count
                slot_keys[count] = key
                slots[e] = count
                count += 1
                break
            if slot_keys[slot] == key:
                slots[e] = slot
                break
            probe = (probe + 1) & mask
    return count


def _rows_in_order(order, keys, sums, scale, n_nodes, rows):
    """rows += each pair's share (``_add_row``) of keys[order] (pairs, sorted a n + b) with
    their sums (slots, 5, 5): each row over its pairs in the order of b."""
    for e in range(order.shape[0]):
        slot = order[e]
        _add_row(sums[slot], keys[slot] // n_nodes, keys[slot] % n_nodes, scale, rows)


if kernel_cache.AVAILABLE:
    # Spliced into both loops (numba's inlining): a call with array arguments per node pair
    # would cost their reference counting.
    _add_transformed = kernel_cache.njit(_add_transformed, inline="always")
    _add_row = kernel_cache.njit(_add_row, inline="always")
    _largest = kernel_cache.njit(_largest)
    _merge = kernel_cache.njit(_merge)
    _close = kernel_cache.njit(_close)
    _slots = kernel_cache.njit(_slots)
    _band = kernel_cache.njit(_band)
    _rows_in_order = kernel_cache.njit(_rows_in_order)
    _pair_sums = kernel_cache.njit(_pair_sums)
    _bsr_sums = kernel_cache.njit(_bsr_sums)


def banded_piece(connectivity: np.ndarray, cells: int) -> int:
    """The cells of a piece of an element block's ``tangent_pieces`` of consecutive cells:
    ``cells``, or the cells' band (``_band``) where that is longer and at most a quarter of
    the block. A piece at least the band long holds a node in a run of consecutive pieces,
    so the bound streams (``gershgorin_largest`` with ``again``): a node's next cell is at
    most a piece on, in the same piece or the next. A thin strip of cells in rows
    (Mesh.rectangle(nx=400, ny=20): a band of 2 nx - 1 cells) is streamed in pieces of its
    band where ``cells`` were shorter; a band past a quarter of the cells (cells in no banded
    order) leaves ``cells``: every pair is then held (memory ~ pairs) rather than pieces the
    size of the block.

    Parameters
    ----------
    connectivity : (m, p) int, the cells' nodes in the block's order.
    cells : the piece's cells otherwise (> 0).
    """
    conn = np.ascontiguousarray(connectivity, dtype=np.int64)
    if conn.size == 0:
        return cells
    band = int(_band(conn, int(conn.max()) + 1))
    return band if cells < band <= len(conn) // 4 else cells


class _Held:
    """The node pairs held while streaming: keys (h,) sorted and their sums (h, 5, 5)."""

    def __init__(self) -> None:
        self.keys, self.sums = np.empty(0, dtype=np.int64), np.empty((0, 5, 5))
        self.taken = np.empty(0, dtype=bool)

    def start(self, keys: np.ndarray) -> np.ndarray:
        """The sums (pairs, 5, 5) a piece of node pairs ``keys`` (sorted, each once) adds its
        blocks to: the held sums of the pairs held, 0 for the others; ``taken`` (h,) bool
        the held pairs they took."""
        sums = np.zeros((len(keys), 5, 5))
        self.taken = np.zeros(len(self.keys), dtype=bool)
        if len(self.keys) and len(keys):
            at = np.minimum(np.searchsorted(self.keys, keys), len(self.keys) - 1)
            found = self.keys[at] == keys
            sums[found] = self.sums[at[found]]
            self.taken[at[found]] = True
        return sums


class _Table:
    """Every node pair met so far, each in a slot of its own: keys (slots,) and sums
    (slots, 5, 5) in the order the pairs were first met, found by key through a hash table
    (``_slots``). A piece's pairs are looked up, their sums taken, added to and put back:
    work and memory linear in the pieces' pairs (a merge of the sorted pairs so far with
    each piece's cost pieces x pairs: 12 s against 2.7 for a 44.8k-cell fibrous sheet as
    two blocks, benchmarks/gershgorin_fallback.py)."""

    def __init__(self) -> None:
        self.table = np.full(16, -1, dtype=np.int64)
        self.keys = np.empty(8, dtype=np.int64)
        self.sums = np.empty((8, 5, 5))
        self.count = 0
        self.grown = 0  # times the slots were grown (tests/test_gershgorin.py)
        self.slots = np.empty(0, dtype=np.int64)

    def start(self, keys: np.ndarray) -> np.ndarray:
        """The sums (pairs, 5, 5) so far of a piece's node pairs ``keys`` (each once), 0
        for those met first here; their slots kept for ``put``."""
        needed = self.count + len(keys)
        if needed > len(self.keys):
            size = max(needed, 2 * len(self.keys))
            # in place (the kernel moves the pages), no second copy held
            self.keys.resize(size, refcheck=False)
            self.sums.resize((size, 5, 5), refcheck=False)
            self.grown += 1
        if 2 * needed > len(self.table):
            size = len(self.table)
            while 2 * needed > size:
                size *= 2
            self.table = np.full(size, -1, dtype=np.int64)
            _slots(
                self.table,
                self._shift(),
                self.keys,
                0,
                self.keys[: self.count].copy(),
                np.empty(self.count, dtype=np.int64),
            )
        self.slots = np.empty(len(keys), dtype=np.int64)
        before = self.count
        self.count = int(_slots(self.table, self._shift(), self.keys, before, keys, self.slots))
        self.sums[before : self.count] = 0.0
        return self.sums[self.slots]

    def put(self, sums: np.ndarray) -> None:
        """The piece's sums back to its pairs' slots."""
        self.sums[self.slots] = sums

    def _shift(self) -> int:
        return 64 - (len(self.table).bit_length() - 1)


def _piece_sums(
    piece: TangentPart, maps: np.ndarray, n_nodes: int, start: Callable[[np.ndarray], np.ndarray]
) -> tuple[np.ndarray, np.ndarray]:
    """The node-pair keys a n + b (pairs,) of one tangent piece, sorted, each once; their
    sums: ``start(keys)`` (the pairs' sums so far, 0 where none) plus the piece's generalised
    5 x 5 blocks in their order."""
    if isinstance(piece, CellTangent):
        nodes = kernel_nodes(piece.nodes)
        flat = (nodes[:, :, None] * n_nodes + nodes[:, None, :]).ravel()
        keys, pair_of = np.unique(flat, return_inverse=True)
        blocks = np.ascontiguousarray(piece.blocks, dtype=np.float64)
        where = pair_of.reshape(nodes.shape + nodes.shape[1:2])
        sums = start(keys)
        _pair_sums(nodes, where, blocks, maps, blocks.shape[2], sums)
        return keys, sums
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
            sums = start(keys)
            _bsr_sums(indptr, indices, data, maps, sums)
            return keys, sums
    matrix = generalised_sparse(piece, maps).tocoo()
    row, col = matrix.row.astype(np.int64), matrix.col.astype(np.int64)
    keys, pair_of = np.unique((row // 5) * n_nodes + col // 5, return_inverse=True)
    sums = start(keys)
    np.add.at(sums, (pair_of.ravel(), row % 5, col % 5), matrix.data)
    return keys, sums


def gershgorin_largest(
    pieces: Iterable[TangentPart],
    maps: np.ndarray,
    scale: np.ndarray,
    n_nodes: int,
    again: Callable[[], Iterable[TangentPart]] | None = None,
    shared: np.ndarray | None = None,
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
    shared : (n,) bool or None: the nodes whose rows are held to the end while streaming
        (their pairs found by key, ``_Table``), the others streamed: the nodes of more than
        one element block (a seam), which a later block's pieces meet again after the first
        block has left them. None: none.
    """
    if again is not None:
        streamed = _streamed(pieces, maps, scale, n_nodes, shared)
        if streamed is not None:
            return streamed
        pieces = again()
    return _held(pieces, maps, scale, n_nodes)


def _held(
    pieces: Iterable[TangentPart], maps: np.ndarray, scale: np.ndarray, n_nodes: int
) -> float:
    """``gershgorin_largest`` holding every node pair to the end (``_Table``): each piece's
    blocks added to its pairs' sums so far as it comes, so that a pair's sum is 0 + its
    blocks in the pieces' order and in each piece's own, however the blocks are parted into
    pieces; then each row summed over its pairs in the order of b (one sort of the pairs)."""
    scale = np.ascontiguousarray(scale)
    table = _Table()
    for piece in pieces:
        _, sums = _piece_sums(piece, maps, n_nodes, table.start)
        del piece  # read: not held while the next one is made
        table.put(sums)
        del sums
    keys = table.keys[: table.count]
    rows = np.zeros(scale.shape[0])
    _rows_in_order(np.argsort(keys), keys, table.sums, scale, n_nodes, rows)
    return float(_largest(rows, scale))


def _streamed(
    pieces: Iterable[TangentPart],
    maps: np.ndarray,
    scale: np.ndarray,
    n_nodes: int,
    shared: np.ndarray | None = None,
) -> float | None:
    """``_held``'s number (each pair's blocks summed in the same order, each row over its
    pairs in the order of b) holding only the node pairs whose row may still grow: after
    each piece, the pairs (a, b) whose node a the piece does not hold are summed into a's
    rows and dropped (a cell-ordered mesh's pieces of consecutive cells share only the nodes
    along their borders, ``banded_piece``). The pairs (a, b) of the ``shared`` nodes a (n,)
    bool are held to the end in a ``_Table`` (as ``_held`` holds every pair) and their rows
    summed last: blocks that share a seam stream each in turn. None when a piece holds a
    node already summed (a mesh whose cells are not in a banded order)."""
    scale = np.ascontiguousarray(scale)
    rows = np.zeros(scale.shape[0])
    closed = np.zeros(n_nodes, dtype=bool)
    open_nodes = np.zeros(n_nodes, dtype=bool)
    held = _Held()
    seams = _Table()
    split: list[np.ndarray] = []  # the piece's pairs of shared nodes, or empty

    def start(keys: np.ndarray) -> np.ndarray:
        if shared is None or not (at_seam := shared[keys // n_nodes]).any():
            split[:] = []
            return held.start(keys)
        split[:] = [at_seam]
        sums = np.empty((len(keys), 5, 5))
        sums[~at_seam] = held.start(keys[~at_seam])
        sums[at_seam] = seams.start(keys[at_seam])
        return sums

    for piece in pieces:
        keys, sums = _piece_sums(piece, maps, n_nodes, start)
        del piece  # read: not held while the next one is made
        if split:
            at_seam = split[0]
            seams.put(sums[at_seam])
            keys, sums = keys[~at_seam], sums[~at_seam]
        first = keys // n_nodes
        if closed[first].any():
            return None
        # The pairs of the piece (their sums go on from the held ones) among the others held.
        count = len(held.keys) - int(held.taken.sum()) + len(keys)
        out_keys = np.empty(count, dtype=np.int64)
        out = np.empty((count, 5, 5))
        _merge(held.keys, held.sums, held.taken, keys, sums, out_keys, out)
        del sums
        held.sums = np.empty((0, 5, 5))
        open_nodes[:] = False
        open_nodes[first] = True
        kept = _close(out_keys, out, count, open_nodes, closed, scale, n_nodes, rows)
        held.keys, held.sums = out_keys[:kept].copy(), out[:kept].copy()
        del out_keys, out
    open_nodes[:] = False
    _close(held.keys, held.sums, len(held.keys), open_nodes, closed, scale, n_nodes, rows)
    # the shared nodes' rows: none of their pairs was streamed (rows of 0 until here)
    keys = seams.keys[: seams.count]
    _rows_in_order(np.argsort(keys), keys, seams.sums, scale, n_nodes, rows)
    return float(_largest(rows, scale))
