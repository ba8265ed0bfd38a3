"""Assembly: nodal vectors and the sparse tangent stiffness, for every solver.

- ``Scatter``: gather nodal arrays into per-cell arrays and scatter per-cell vectors back to the
  nodes. The index arrays are built once (when an element block is bound); a time step then
  costs one fancy-indexing gather and one ``np.bincount`` per scattered field, with no Python
  loop over cells or nodes.
- Tangent stiffness in generalised coordinates (femcore.dofs): ``tangent_matrix`` and
  ``FreeTangentAssembler`` (the cell blocks and the node blocks transformed and added into
  K_ff's fixed CSC structure by compiled passes, at positions found once per pattern) from
  the elements' own tangent parts, ``CellTangent`` (dense blocks
  per cell) or ``SparseTangent`` (a sparse matrix over all nodes, for couplings wider than a
  cell; best as BSR with 6 x 6 node blocks); the assembler caches the sparsity pattern of both
  and rebuilds it when the parts' structure changes (or, with ``superset``, when a node pair
  falls outside the structure kept); and ``finite_difference_tangent`` with its
  ``NodeGraph`` colouring for blocks without a tangent of their own
  (femcore/finite_difference.py, re-exported here).
"""

from __future__ import annotations

import functools
from typing import Any, NamedTuple

import numpy as np
import scipy.sparse as sp

from femcore import kernel_cache, tangent_pattern
from femcore.dofs import N_COLUMNS, DofManager, Frames
from femcore.finite_difference import (
    NodeGraph,
    finite_difference_tangent,
    greedy_colours,
    node_adjacency,
)

__all__ = [
    "CellTangent",
    "FreeTangentAssembler",
    "NodeGraph",
    "Scatter",
    "SparseTangent",
    "TangentPart",
    "entry_slots",
    "finite_difference_tangent",
    "generalised_blocks",
    "generalised_sparse",
    "greedy_colours",
    "node_adjacency",
    "tangent_matrix",
]


class CellTangent(NamedTuple):
    """Stiffness blocks of an element block, summed into the global tangent by the assembler.

    Attributes
    ----------
    nodes : (m, p) int
        Global node ids of each block (a node may appear twice: its entries add up).
    blocks : (m, p, c, p, c) float
        d(force, moment)_(node a, comp i) / d(u, psi)_(node b, comp j), with c = 3
        (translations only) or 6 (u then psi: a small rotation vector of the director in global
        components, V+ = V + psi x V). Units N/mm, N, N mm.
    """

    nodes: np.ndarray
    blocks: np.ndarray


class SparseTangent(NamedTuple):
    """A block's stiffness as one sparse matrix over all the nodes of the model.

    For couplings that dense per-cell blocks would store many times over: a force that depends
    on nodal quantities built from a whole node star (averaged normals) reaches two rings of
    cells, and its exact stiffness is a product of sparse Jacobians.

    Attributes
    ----------
    matrix : (6 n, 6 n) scipy.sparse matrix
        d(force, moment)/d(u, psi), row and column 6 node + component (u then psi, global
        components, the same convention as ``CellTangent.blocks`` with c = 6).
    """

    matrix: sp.spmatrix


#: A part of an element tangent: dense blocks per cell or one sparse matrix.
TangentPart = CellTangent | SparseTangent


class Scatter:
    """Precomputed scatter of per-cell nodal vectors to the global nodes.

    Parameters
    ----------
    connectivity : (m, k) int, the k nodes of each of the m cells (a cell may be a 2-node
        cable, a 3-node triangle, or a 6-node bending patch).
    n_nodes : number of global nodes.
    """

    def __init__(self, connectivity: np.ndarray, n_nodes: int):
        connectivity = np.asarray(connectivity, dtype=np.int64)
        if connectivity.ndim != 2:
            raise ValueError(f"connectivity must be (cells, nodes), got shape {connectivity.shape}")
        if connectivity.size and (connectivity.min() < 0 or connectivity.max() >= n_nodes):
            raise ValueError(f"connectivity refers to nodes outside 0..{n_nodes - 1}")
        self.connectivity = connectivity
        self.n_nodes = int(n_nodes)
        self._flat1 = connectivity.ravel()

    @functools.cached_property
    def _flat3(self) -> np.ndarray:
        """Flat index of (node, component) for 3-vectors: one bincount scatters all
        components. Built at the first scatter of vectors (m k 3 int64, 72 bytes per triangle
        that a compiled element summing at the nodes itself never needs)."""
        return (self.connectivity[:, :, None] * 3 + np.arange(3)).ravel()

    def gather(self, nodal: np.ndarray) -> np.ndarray:
        """Per-cell copy of a nodal array: (n, ...) -> (m, k, ...)."""
        return nodal[self.connectivity]

    def vectors(self, per_cell: np.ndarray) -> np.ndarray:
        """Sum per-cell nodal 3-vectors into nodes: (m, k, 3) -> (n, 3)."""
        return np.bincount(
            self._flat3, weights=per_cell.ravel(), minlength=3 * self.n_nodes
        ).reshape(self.n_nodes, 3)

    def scalars(self, per_cell: np.ndarray) -> np.ndarray:
        """Sum per-cell nodal scalars into nodes: (m, k) -> (n,)."""
        return np.bincount(self._flat1, weights=per_cell.ravel(), minlength=self.n_nodes)


# ---------------------------------------------------------------------- tangent stiffness
def generalised_blocks(part: CellTangent, maps: np.ndarray) -> np.ndarray:
    """The blocks of a CellTangent in generalised coordinates.

    Parameters
    ----------
    part : CellTangent
        Blocks (m, p, c, p, c) in (u, psi) per node (c = 6) or translations only (c = 3).
    maps : (n, 6, 5) float
        Per node T with (u, psi) = T q (``DofManager.node_maps``).

    Returns
    -------
    (m, p, c_q, p, c_q) float
        K_q = T^T K T per block, c_q = 5 (or the blocks unchanged when c = 3).
    """
    nodes, k = part.nodes, part.blocks
    if k.shape[2] == 3:
        return k
    t = maps[nodes]  # (m, p, 6, 5)
    m, p = nodes.shape
    # One block-diagonal T (6p x 5p) per cell, then T^T K T as two batched matmuls of whole
    # cell matrices: many tiny (6 x 6) @ (6 x 5) products cost numpy more in overhead than in
    # arithmetic.
    diagonal = np.zeros((m, p, 6, p, N_COLUMNS))
    corners = np.arange(p)
    diagonal[:, corners, :, corners, :] = np.swapaxes(t, 0, 1)
    block_t = diagonal.reshape(m, 6 * p, N_COLUMNS * p)
    right = np.matmul(k.reshape(m, 6 * p, 6 * p), block_t)
    left = np.matmul(np.swapaxes(block_t, 1, 2), right)
    return left.reshape(m, p, N_COLUMNS, p, N_COLUMNS)


def generalised_sparse(part: SparseTangent, maps: np.ndarray) -> sp.csr_matrix:
    """K_q = T^T K T (n_slots x n_slots) of a SparseTangent, T the block-diagonal node maps
    (n, 6, 5) of ``DofManager.node_maps``."""
    n = maps.shape[0]
    if part.matrix.shape != (6 * n, 6 * n):
        raise ValueError(
            f"SparseTangent.matrix must be (6 n, 6 n) = ({6 * n}, {6 * n}), got {part.matrix.shape}"
        )
    rows = np.broadcast_to((6 * np.arange(n))[:, None, None] + np.arange(6)[:, None], maps.shape)
    cols = np.broadcast_to(
        (N_COLUMNS * np.arange(n))[:, None, None] + np.arange(N_COLUMNS), maps.shape
    )
    t = sp.csr_matrix((maps.ravel(), (rows.ravel(), cols.ravel())), shape=(6 * n, N_COLUMNS * n))
    return (t.T @ sp.csr_matrix(part.matrix) @ t).tocsr()


def _add_cell_blocks(
    blocks: np.ndarray,
    nodes: np.ndarray,
    maps: np.ndarray,
    pairs: np.ndarray,
    ff_table: np.ndarray,
    fp_table: np.ndarray,
    ff: np.ndarray,
    fp: np.ndarray,
) -> None:
    """Adds T_a^T K_ab T_b of every block pair of a CellTangent into the CSC data of K_ff
    (``ff``) and K_fp (``fp``), in the order of the entries (cell, a, i, b, j) of the
    generalised blocks, at the positions ``*_table[pairs[cell, a, b], i, j]`` (-1: not in
    that matrix; femcore/tangent_pattern.py: pairs (m, p, p), the tables (pairs, 5, 5)).

    blocks (m, p, c, p, c), c = 6 (u, psi) or 3 (translations: no transformation); nodes
    (m, p); maps (n, 6, 5) of ``DofManager.node_maps``, whose T = [[I, 0], [0, R]] with
    R = [V2 V1] (3 x 2): the products use that shape (66 products per pair, not 900).
    Compiled by numba (one serial pass: the sums in a fixed order)."""
    m, p, c = blocks.shape[0], blocks.shape[1], blocks.shape[2]
    size = 5 if c == 6 else 3
    kq = np.empty((size, size))
    right = np.empty((3, 2))
    for cell in range(m):
        for a in range(p):
            node_a = nodes[cell, a]
            for b in range(p):
                node_b = nodes[cell, b]
                for i in range(3):
                    for j in range(3):
                        kq[i, j] = blocks[cell, a, i, b, j]
                if c == 6:
                    for i in range(3):
                        for q in range(2):
                            upper = 0.0
                            turned = 0.0
                            for r in range(3):
                                rb = maps[node_b, 3 + r, 3 + q]
                                upper += blocks[cell, a, i, b, 3 + r] * rb
                                turned += blocks[cell, a, 3 + i, b, 3 + r] * rb
                            kq[i, 3 + q] = upper
                            right[i, q] = turned
                    for q in range(2):
                        for j in range(3):
                            total = 0.0
                            for r in range(3):
                                total += maps[node_a, 3 + r, 3 + q] * blocks[cell, a, 3 + r, b, j]
                            kq[3 + q, j] = total
                        for t in range(2):
                            total = 0.0
                            for r in range(3):
                                total += maps[node_a, 3 + r, 3 + q] * right[r, t]
                            kq[3 + q, 3 + t] = total
                pair = pairs[cell, a, b]
                for i in range(size):
                    for j in range(size):
                        where = ff_table[pair, i, j]
                        if where >= 0:
                            ff[where] += kq[i, j]
                        else:
                            where = fp_table[pair, i, j]
                            if where >= 0:
                                fp[where] += kq[i, j]


def _add_node_blocks(
    block_rows: np.ndarray,
    indices: np.ndarray,
    data: np.ndarray,
    maps: np.ndarray,
    pairs: np.ndarray,
    ff_table: np.ndarray,
    fp_table: np.ndarray,
    ff: np.ndarray,
    fp: np.ndarray,
) -> None:
    """Adds T_I^T K_IJ T_J of every 6 x 6 node block of a SparseTangent's BSR matrix into the
    CSC data of K_ff (``ff``) and K_fp (``fp``), in the order of the entries (block, a, c) of
    the generalised blocks, at the positions ``*_table[pairs[block], a, c]`` (-1: not in that
    matrix; femcore/tangent_pattern.py).

    block_rows (count,) the row node I of each block, indices (count,) its column node J,
    data (count, 6, 6) the blocks; maps (n, 6, 5) of ``DofManager.node_maps`` (T = [[I, 0],
    [0, R]], R = [V2 V1]): the products of ``_add_cell_blocks``, K T_J first, then T_I^T
    of it (those of numpy's two matmuls, without the products by T's zeros and ones). A
    pattern's blocks are distinct node pairs, so each position receives at most one entry
    of a matrix. Compiled by numba (one serial pass)."""
    kq = np.empty((5, 5))
    right = np.empty((3, 2))
    for block in range(indices.size):
        node_a = block_rows[block]
        node_b = indices[block]
        for i in range(3):
            for j in range(3):
                kq[i, j] = data[block, i, j]
        for i in range(3):
            for q in range(2):
                upper = 0.0
                turned = 0.0
                for r in range(3):
                    rb = maps[node_b, 3 + r, 3 + q]
                    upper += data[block, i, 3 + r] * rb
                    turned += data[block, 3 + i, 3 + r] * rb
                kq[i, 3 + q] = upper
                right[i, q] = turned
        for q in range(2):
            for j in range(3):
                total = 0.0
                for r in range(3):
                    total += maps[node_a, 3 + r, 3 + q] * data[block, 3 + r, j]
                kq[3 + q, j] = total
            for t in range(2):
                total = 0.0
                for r in range(3):
                    total += maps[node_a, 3 + r, 3 + q] * right[r, t]
                kq[3 + q, 3 + t] = total
        pair = pairs[block]
        for i in range(5):
            for j in range(5):
                where = ff_table[pair, i, j]
                if where >= 0:
                    ff[where] += kq[i, j]
                else:
                    where = fp_table[pair, i, j]
                    if where >= 0:
                        fp[where] += kq[i, j]


_add_cell_blocks_compiled: Any = None
_add_node_blocks_compiled: Any = None
# numba is a dependency; without it the assembler sums the numpy blocks by bincount
if kernel_cache.AVAILABLE:
    _add_cell_blocks_compiled = kernel_cache.njit(_add_cell_blocks)
    _add_node_blocks_compiled = kernel_cache.njit(_add_node_blocks)
else:  # pragma: no cover - numba is a dependency
    _add_cell_blocks_compiled = None
    _add_node_blocks_compiled = None


def entry_slots(nodes: np.ndarray, components: int) -> tuple[np.ndarray, np.ndarray]:
    """Global slot row and column of every entry of (m, p, c_q, p, c_q) blocks, raveled."""
    index = DofManager.slots(nodes[:, :, None], np.arange(components))  # (m, p, c_q)
    shape = index.shape + index.shape[1:]
    rows = np.broadcast_to(index[:, :, :, None, None], shape).ravel()
    cols = np.broadcast_to(index[:, None, None, :, :], shape).ravel()
    return rows, cols


def _split(parts: list[TangentPart]) -> tuple[list[CellTangent], list[SparseTangent]]:
    cells = [p for p in parts if isinstance(p, CellTangent)]
    return cells, [p for p in parts if isinstance(p, SparseTangent)]


def _components(part: CellTangent) -> int:
    return 3 if part.blocks.shape[2] == 3 else N_COLUMNS


def tangent_matrix(dofs: DofManager, parts: list[TangentPart], frames: Frames) -> sp.csr_matrix:
    """Sparse K (n_slots x n_slots) in generalised coordinates from element tangent parts,
    with the nodal frames of the iteration (psi = alpha V2 + beta V1)."""
    size = dofs.n_slots
    if not parts:
        return sp.csr_matrix((size, size))
    maps = dofs.node_maps(frames)
    cell_parts, sparse_parts = _split(parts)
    rows, cols, values = [np.zeros(0, dtype=np.int64)], [np.zeros(0, dtype=np.int64)], [np.zeros(0)]
    for part in cell_parts:
        kq = generalised_blocks(part, maps)
        r, c = entry_slots(part.nodes, kq.shape[2])
        rows.append(r)
        cols.append(c)
        values.append(kq.ravel())
    k = sp.csr_matrix(
        (np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))), shape=(size, size)
    )
    for sparse_part in sparse_parts:
        k = k + generalised_sparse(sparse_part, maps)
    return k.tocsr()


def _node_blocks(part: SparseTangent, n_nodes: int) -> sp.bsr_matrix:
    """The matrix of a SparseTangent as 6 x 6 node blocks (converted unless it is already)."""
    matrix = part.matrix
    if matrix.shape != (6 * n_nodes, 6 * n_nodes):
        raise ValueError(
            f"SparseTangent.matrix must be (6 n, 6 n) = ({6 * n_nodes}, {6 * n_nodes}), got "
            f"{matrix.shape}"
        )
    if isinstance(matrix, sp.bsr_matrix) and matrix.blocksize == (6, 6):
        return matrix
    return sp.bsr_matrix(matrix, blocksize=(6, 6))


def kernel_nodes(nodes: np.ndarray) -> np.ndarray:
    """A tangent part's ``nodes`` (m, p) as the compiled passes take them: C-contiguous int64,
    read-only (a view where the caller's array is writable; no copy where it is C-contiguous
    int64). A block's connectivity is kept read-only, the nodes of a contact's or a patch's
    part are fresh, and numba builds a kernel once for each flag: one build for both."""
    nodes = np.ascontiguousarray(nodes, dtype=np.int64)
    if not nodes.flags.writeable:
        return nodes
    view = nodes.view()
    view.flags.writeable = False
    return view


def _check_nodes(parts: list[CellTangent], n_nodes: int) -> None:
    """Raises ValueError where a part's node array (m, p) holds an index outside
    [0, n_nodes): one min and one max per part."""
    for number, part in enumerate(parts):
        nodes = np.asarray(part.nodes)
        if nodes.size == 0:
            continue
        low, high = nodes.min(), nodes.max()
        if low < 0 or high >= n_nodes:
            bad = low if low < 0 else high
            raise ValueError(
                f"CellTangent part {number}: node index {bad} outside [0, {n_nodes}); "
                f"the parts' nodes must be the model's"
            )


# A kept structure (``FreeTangentAssembler(superset=True)``) serves parts whose node pairs
# reach at least 1 / SUPERSET_SLACK of its pairs (it holds at most SUPERSET_SLACK times the
# pairs they reach); below that share, it is built on theirs alone.
SUPERSET_SLACK = 1.5


class FreeTangentAssembler:
    """Sums element tangent parts straight into K_ff (free x free, CSC) and K_fp (free x
    prescribed, CSR).

    The map from the parts' entries to the sparse storage is built from their structure (the
    node arrays of the CellTangent parts, the 6 x 6 node-block pattern of the SparseTangent
    parts) and reused while it stays the same, so that each assembly is one compiled pass per
    part (the T^T K T of each block added at its positions: ``_add_cell_blocks``,
    ``_add_node_blocks``; numpy's matmuls and a bincount without numba); when it changes (a
    contact adds or drops pairs), the map is rebuilt at the next call: the distinct node
    pairs, K_ff's and K_fp's structure and a table of each pair's places (pairs, 5, 5) by one
    compiled pass (femcore/tangent_pattern.py, numpy's reference without numba), each part
    keeping the pair of each of its node pairs (m, p, p), through which the passes find an
    entry's place (2.5 ms against 28 ms for the build of a ply stack's 972 000 entries,
    benchmarks/tangent_pattern.py). A SparseTangent given
    as a BSR matrix with 6 x 6 blocks is used as it is; any other sparse format is converted
    to one at every call.

    With ``superset`` the structure is kept for parts whose node pairs all lie among its
    pairs (``tangent_pattern.pairs_within``: a bisection in each column node's pairs, where
    a build counts and places every entry) while they reach at least 1 / SUPERSET_SLACK of
    them, and built on the union of its pairs and theirs where one does not (on theirs alone
    where the union would be past that share): a ply contact's touching points change the
    pairs at most Newton iterations and come back to pairs met before. The pairs the parts
    leave out are stored zeros of K_ff and K_fp (the linear solver's split of K_ff's upper
    triangle leaves them out; docs/theory.md §6.5), the same matrices factorised to the bit.
    What it saves is the builds and the linear solver's plan of each new K_ff pattern's
    upper triangle (kept while the pattern is): with the kept band plans, 0.45 s against
    1.36 s of the default plies-bai-5.1 (42 structures against 304), 0.31 against 0.53 s of
    plies-deck-of-cards, 0.06 against 0.11 s of plies-heavy-cantilever
    (benchmarks/ply_kept_structure.py, one thread, load 7.6-14.2).

    The node blocks' compiled products are sums in a fixed order without fused
    multiply-adds, where numpy's matmuls (BLAS) round as the machine's kernel does: on the
    40-cell fibrous corner of benchmarks/paper_cases.py the two differ by at most 1.8e-16
    of K_ff's largest entry, on 4 % of its entries.
    """

    def __init__(self, dofs: DofManager, superset: bool = False):
        """``superset``: K_ff's and K_fp's structure kept for parts whose node pairs all lie
        among its own, and grown to the union when one does not (class docstring)."""
        self.dofs = dofs
        self.superset = superset
        self.n_free = dofs.free_slots.size
        self.n_moved = dofs.prescribed_slots.size
        self._position = np.full(dofs.n_slots, -1)
        self._position[dofs.free_slots] = np.arange(self.n_free)
        self._moved = np.full(dofs.n_slots, -1)
        self._moved[dofs.prescribed_slots] = np.arange(self.n_moved)
        self._pattern: list[tuple[np.ndarray, ...]] | None = None
        # the structure's distinct node pairs by column node (the superset's lookup)
        self._pair_start = np.zeros(0, dtype=np.int64)
        self._pair_rows = np.zeros(0, dtype=np.int64)
        self._pair_wide = np.zeros(0, dtype=bool)
        #: How many times the sparsity pattern was (re)built.
        self.builds = 0

    @staticmethod
    def _structure(parts: list[CellTangent], blocks: list[sp.bsr_matrix]) -> list:
        """What the map depends on: node arrays and components, block pointers and columns."""
        return [(part.nodes, np.array(_components(part))) for part in parts] + [
            (b.indptr, b.indices) for b in blocks
        ]

    def _node_pairs(
        self, parts: list[CellTangent], blocks: list[sp.bsr_matrix]
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The (row node, column node, width 5) of every node pair of the parts, in their
        order (a cell part of p nodes couples p^2 pairs where it holds (5 p)^2 entries);
        sets the node blocks' rows and columns."""
        rows, cols, wide = [np.zeros(0, dtype=np.int64)], [np.zeros(0, dtype=np.int64)], []
        wide.append(np.zeros(0, dtype=bool))
        for part in parts:
            nodes = np.asarray(part.nodes, dtype=np.int64)
            m, p = nodes.shape
            rows.append(np.broadcast_to(nodes[:, :, None], (m, p, p)).ravel())
            cols.append(np.broadcast_to(nodes[:, None, :], (m, p, p)).ravel())
            wide.append(np.full(m * p * p, _components(part) == N_COLUMNS))
        self._block_rows = [
            np.repeat(np.arange(len(b.indptr) - 1), np.diff(b.indptr)) for b in blocks
        ]
        self._block_columns = [np.asarray(b.indices, dtype=np.int64) for b in blocks]
        for block_rows, columns in zip(self._block_rows, self._block_columns):
            rows.append(block_rows)
            cols.append(columns)
            wide.append(np.ones(block_rows.size, dtype=bool))
        return np.concatenate(rows), np.concatenate(cols), np.concatenate(wide)

    def _restructure(self, parts: list[CellTangent], blocks: list[sp.bsr_matrix]) -> None:
        """The map for parts of a new structure: with ``superset``, the kept structure where
        every node pair of the parts is among its pairs and it holds at most SUPERSET_SLACK
        times the pairs they reach, else one built on the union of its pairs and theirs
        (within that bound; else on theirs alone); without, one built on theirs."""
        rows, cols, wide = self._node_pairs(parts, blocks)
        if not self.superset or self._pattern is None:
            self._build(parts, blocks, pairs=(rows, cols, wide))
            return
        inverse, distinct = tangent_pattern.pairs_within(
            rows, cols, wide, self._pair_start, self._pair_rows, self._pair_wide
        )
        if distinct >= 0 and self._pair_rows.size <= SUPERSET_SLACK * distinct:
            self._set_parts(parts, blocks, inverse)
            return
        if distinct < 0:  # a pair outside: the union, the kept pairs after the parts'
            kept_columns = np.repeat(np.arange(self.dofs.n_nodes), np.diff(self._pair_start))
            union = (
                np.concatenate([rows, self._pair_rows]),
                np.concatenate([cols, kept_columns]),
                np.concatenate([wide, self._pair_wide]),
            )
            reached = self._build(parts, blocks, pairs=union, given=rows.size)
            if self._pair_rows.size <= SUPERSET_SLACK * reached:
                return
        self._build(parts, blocks, pairs=(rows, cols, wide))

    def _build(
        self,
        parts: list[CellTangent],
        blocks: list[sp.bsr_matrix],
        compiled: bool = True,
        pairs: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
        given: int | None = None,
    ) -> int:
        """K_ff's and K_fp's structure of the node pairs ``pairs`` (row nodes, column nodes,
        width 5; None: the parts', ``_node_pairs``): the parts' first, ``given`` of them
        (None: all), then any others the structure is to hold; each entry's place counted
        per pair (femcore/tangent_pattern.py; ``compiled``: its numba pass, else numpy's).
        Returns how many distinct pairs the parts' node pairs reach."""
        rows, cols, wide = self._node_pairs(parts, blocks) if pairs is None else pairs
        n = self.dofs.n_nodes
        find = tangent_pattern.pattern if compiled else tangent_pattern.pattern_numpy
        found = find(
            rows,
            cols,
            wide,
            self._position.reshape(n, N_COLUMNS),
            self._moved.reshape(n, N_COLUMNS),
            self.n_free,
            self.n_moved,
        )
        # The structure of K_ff and K_fp in the index type scipy keeps for it (int32 where
        # every index fits, as scipy's get_index_dtype chooses): given int64, scipy's
        # constructors scan the indices and copy them to int32 at every assembly, 0.35 ms
        # for 320 000 entries against 0.01 (benchmarks/paper_case_cost.py). The matrices
        # are the same, their index arrays of the same type.
        largest = max(self.n_free, self.n_moved, found.ff_rows.size, found.fp_cols.size)
        index = np.int32 if largest < np.iinfo(np.int32).max else np.int64
        self.ff_indptr, self.ff_rows = found.ff_indptr.astype(index), found.ff_rows.astype(index)
        self.fp_indptr, self.fp_cols = found.fp_indptr.astype(index), found.fp_cols.astype(index)
        self.fp_rows = found.fp_rows
        # scipy keeps index arrays of its own type as given, without a copy: every K_ff and
        # K_fp returned shares them, so a caller's in-place change of a matrix's structure
        # (eliminate_zeros, prune) would corrupt every later assembly. Read-only, it raises.
        for shared in (self.ff_indptr, self.ff_rows, self.fp_indptr, self.fp_cols):
            shared.setflags(write=False)
        self._tables = (found.ff_table, found.fp_table)
        # the distinct pairs by column node, then row node (their order in the tables)
        count = found.ff_table.shape[0]
        pair_rows = np.empty(count, dtype=np.int64)
        pair_rows[found.inverse] = rows
        pair_columns = np.empty(count, dtype=np.int64)
        pair_columns[found.inverse] = cols
        self._pair_rows = pair_rows
        self._pair_start = np.concatenate(
            [[0], np.cumsum(np.bincount(pair_columns, minlength=n))]
        ).astype(np.int64)
        self._pair_wide = np.bincount(found.inverse, wide, count) > 0
        given = rows.size if given is None else given
        self._set_parts(parts, blocks, found.inverse[:given])
        self.builds += 1
        return int(np.count_nonzero(np.bincount(found.inverse[:given], minlength=count)))

    def _set_parts(
        self, parts: list[CellTangent], blocks: list[sp.bsr_matrix], inverse: np.ndarray
    ) -> None:
        """Per part, the distinct pair of each of its node pairs, (m, p, p) (a node block is
        a part of one node a cell and every component), from ``inverse`` (the parts' node
        pairs in order): the compiled passes find each entry's place in K_ff's or K_fp's
        data through the pairs' tables."""
        shapes = [(len(part.nodes), part.nodes.shape[1], _components(part)) for part in parts]
        shapes += [(block_rows.size, 1, N_COLUMNS) for block_rows in self._block_rows]
        self._shapes, self._pairs = shapes, []
        start = 0
        for m, p, _ in shapes:
            self._pairs.append(inverse[start : start + m * p * p].reshape(m, p, p))
            start += m * p * p
        self._n_cell_parts = len(parts)
        self.__dict__.pop("_destinations", None)
        self.__dict__.pop("_flat_map", None)
        self._pattern = [tuple(a.copy() for a in item) for item in self._structure(parts, blocks)]

    @functools.cached_property
    def _destinations(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """Per part, each entry's place in K_ff's and K_fp's data (-1: in neither), in the
        part's order (cell, row node, a, column node, c) of its raveled blocks; made at first
        use after each build (the numpy assembly's bincounts use them)."""
        return [
            tangent_pattern.part_destinations(pairs, *self._tables, c)
            for pairs, (_, _, c) in zip(self._pairs, self._shapes)
        ]

    @functools.cached_property
    def _flat_map(self) -> tuple[np.ndarray, ...]:
        """(ff_select, ff_map, fp_select, fp_map): the entries of the concatenated parts in
        K_ff's (K_fp's) data and their places there; made at first use after each build (the
        numpy assembly's bincounts use them, the compiled passes do not)."""
        ff_destination = np.concatenate(
            [np.zeros(0, dtype=np.int64)] + [d[0] for d in self._destinations]
        )
        fp_destination = np.concatenate(
            [np.zeros(0, dtype=np.int64)] + [d[1] for d in self._destinations]
        )
        ff_select = np.flatnonzero(ff_destination >= 0)
        fp_select = np.flatnonzero(fp_destination >= 0)
        return ff_select, ff_destination[ff_select], fp_select, fp_destination[fp_select]

    @property
    def ff_select(self) -> np.ndarray:
        """Which entries of the concatenated parts are in K_ff."""
        return self._flat_map[0]

    @property
    def ff_map(self) -> np.ndarray:
        """Their places in K_ff's data."""
        return self._flat_map[1]

    @property
    def fp_select(self) -> np.ndarray:
        """Which entries of the concatenated parts are in K_fp."""
        return self._flat_map[2]

    @property
    def fp_map(self) -> np.ndarray:
        """Their places in K_fp's data."""
        return self._flat_map[3]

    def _rest(self) -> tuple[np.ndarray, ...]:
        """The entries the compiled passes do not add (all of them without numba: the
        SparseTangent parts', summed by bincount): (ff places, their entries, fp places,
        theirs), the entries counted from the first such part's."""
        compiled = _add_cell_blocks_compiled is not None
        cells = self._shapes[: self._n_cell_parts]
        first = int(sum(m * (p * c) ** 2 for m, p, c in cells)) if compiled else 0
        ff_rest, fp_rest = self.ff_select >= first, self.fp_select >= first
        return (
            self.ff_map[ff_rest],
            self.ff_select[ff_rest] - first,
            self.fp_map[fp_rest],
            self.fp_select[fp_rest] - first,
        )

    def _same_pattern(self, parts: list[CellTangent], blocks: list[sp.bsr_matrix]) -> bool:
        structure = self._structure(parts, blocks)
        return (
            self._pattern is not None
            and len(self._pattern) == len(structure)
            and all(
                len(old) == len(new) and all(np.array_equal(a, b) for a, b in zip(old, new))
                for old, new in zip(self._pattern, structure)
            )
        )

    def __call__(
        self, all_parts: list[TangentPart], frames: Frames
    ) -> tuple[sp.csc_matrix, sp.csr_matrix]:
        """(K_ff, K_fp) of the parts in the iteration's frames.

        Raises
        ------
        ValueError
            Where a CellTangent part names a node outside [0, n_nodes) (the compiled
            passes index without bounds checks).
        """
        parts, sparse_parts = _split(all_parts)
        _check_nodes(parts, self.dofs.n_nodes)
        blocks = [_node_blocks(part, self.dofs.n_nodes) for part in sparse_parts]
        if not self._same_pattern(parts, blocks):
            self._restructure(parts, blocks)
        maps = self.dofs.node_maps(frames)
        ff = np.zeros(self.ff_rows.size)
        fp = np.zeros(self.fp_rows.size)
        compiled = _add_cell_blocks_compiled is not None
        values = []
        for part, pairs in zip(parts, self._pairs):
            if compiled:
                _add_cell_blocks_compiled(
                    np.ascontiguousarray(part.blocks, dtype=float),
                    kernel_nodes(part.nodes),
                    maps,
                    pairs,
                    *self._tables,
                    ff,
                    fp,
                )
            else:
                values.append(generalised_blocks(part, maps).ravel())
        if _add_node_blocks_compiled is not None and blocks:
            self._add_node_blocks(blocks, maps, ff, fp)
        else:
            for b, block_rows in zip(blocks, self._block_rows):
                # T_i^T K_ij T_j per node block, (count, 5, 5).
                right = np.matmul(b.data, maps[b.indices])
                values.append(np.matmul(np.swapaxes(maps[block_rows], 1, 2), right).ravel())
        if values:  # the parts the compiled passes did not add, by one bincount each
            flat = np.concatenate(values)
            ff_map, ff_select, fp_map, fp_select = self._rest()
            ff += np.bincount(ff_map, flat[ff_select], minlength=ff.size)
            fp += np.bincount(fp_map, flat[fp_select], minlength=fp.size)
        k_ff = sp.csc_matrix((ff, self.ff_rows, self.ff_indptr), shape=(self.n_free, self.n_free))
        k_ff.has_sorted_indices = True  # canonical by construction (unique sorted keys)
        k_fp = sp.csr_matrix((fp, self.fp_cols, self.fp_indptr), shape=(self.n_free, self.n_moved))
        k_fp.has_sorted_indices = True  # unique keys sorted by row, then column
        return k_ff, k_fp

    def _add_node_blocks(
        self, blocks: list[sp.bsr_matrix], maps: np.ndarray, ff: np.ndarray, fp: np.ndarray
    ) -> None:
        """Adds the SparseTangent parts' T^T K T into ``ff`` and ``fp`` by the compiled pass,
        the sums as the bincount's: a pattern's node blocks reach each position once, so one
        part is added in place (ff + v, as ff + bincount), several are summed apart first
        (ff + (v1 + v2), as the bincount sums them)."""
        node_pairs = self._pairs[self._n_cell_parts :]
        into = (ff, fp) if len(blocks) == 1 else (np.zeros(ff.size), np.zeros(fp.size))
        for b, block_rows, columns, pairs in zip(
            blocks, self._block_rows, self._block_columns, node_pairs
        ):
            _add_node_blocks_compiled(
                block_rows,
                columns,
                np.ascontiguousarray(b.data, dtype=float),
                maps,
                pairs.ravel(),
                *self._tables,
                *into,
            )
        if len(blocks) > 1:
            ff += into[0]
            fp += into[1]
