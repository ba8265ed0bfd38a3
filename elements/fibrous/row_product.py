"""Some rows of the fibrous membrane's J^T H J and of the bending patches added to them, with
the arithmetic of the whole product (docs/theory.md §2.6, §6.2).

``tangent_kernels.MembraneProduct`` forms every row of K = J^T H J on a pattern of node pairs
through P = H J. A row i of K needs only the rows k of P around i (the nodes of the cells
at i) and a row k of P only the rows of H at k and of J at k's neighbours; ``RowProduct``
forms the rows of K of a set of nodes from those alone. Both run the loops below
(``MembraneProduct`` over every row), so each row is the whole product's to the last bit
whatever rows are asked for at once. ``row_patches`` adds the bending patches' blocks to
those rows (cells in order).
elements/fibrous/tangent_pieces.py gives the rows a run of nodes at a time to the explicit
solver's stable-step bound.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from femcore.jit import AVAILABLE, serial

__all__ = ["AVAILABLE", "RowProduct", "row_patches"]


@serial
def _membrane_rows(
    indptr, indices, transposed, hessian, h_of, jacobian, p_rows, p_of, p_indptr, p_indices,
    k_rows, k_indptr, k_indices, product, out,
):  # fmt: skip
    """out (K's blocks of the rows k_rows, 6, 6) = J^T H J on (k_indptr, k_indices), through
    product (P's blocks of the rows p_rows, 9, 6) = H J on (p_indptr, p_indices), each
    product's rows in turn, a marker of the row's pattern giving each block's place. H's
    block of pair hb is hessian[h_of[hb]] (9, 9), J's S rows jacobian[hb] (3, 3) on the node
    pairs (indptr, indices), transposed[b] the pair (j, i) of pair b = (i, j), p_of[k] the
    row of P of node k (-1: not formed)."""
    n = indptr.size - 1
    marker = np.full(n, -1)
    for row in range(p_rows.size):  # P_kj = sum_l H_kl J_lj
        k = p_rows[row]
        for q in range(p_indptr[row], p_indptr[row + 1]):
            marker[p_indices[q]] = q
            product[q] = 0.0
        for hb in range(indptr[k], indptr[k + 1]):
            node = indices[hb]
            h = h_of[hb]
            q = marker[node]
            for r in range(9):
                for c in range(6):
                    product[q, r, c] += hessian[h, r, c]
            for jb in range(indptr[node], indptr[node + 1]):
                q = marker[indices[jb]]
                for r in range(9):
                    for c in range(3):
                        total = 0.0
                        for t in range(3):
                            total += hessian[h, r, 6 + t] * jacobian[jb, t, c]
                        product[q, r, c] += total
        for q in range(p_indptr[row], p_indptr[row + 1]):
            marker[p_indices[q]] = -1
    for row in range(k_rows.size):  # K_ij = sum_k J_ki^T P_kj
        i = k_rows[row]
        for t in range(k_indptr[row], k_indptr[row + 1]):
            marker[k_indices[t]] = t
            out[t] = 0.0
        for b in range(indptr[i], indptr[i + 1]):
            node = indices[b]
            jb = transposed[b]  # J_(node, i)
            p = p_of[node]
            for q in range(p_indptr[p], p_indptr[p + 1]):
                t = marker[p_indices[q]]
                if node == i:
                    for r in range(6):
                        for c in range(6):
                            out[t, r, c] += product[q, r, c]
                for r in range(3):
                    for c in range(6):
                        total = 0.0
                        for s in range(3):
                            total += jacobian[jb, s, r] * product[q, 6 + s, c]
                        out[t, r, c] += total
        for t in range(k_indptr[row], k_indptr[row + 1]):
            marker[k_indices[t]] = -1


@serial
def _row_patch_sums(k_of, k_indptr, k_indices, nodes, blocks, data):
    """data (K's blocks of some rows, 6, 6) += blocks (c, p, 3, p, 3): the translations of each
    cell's patch node pair (a, b) whose row node nodes[c, a] is one of the rows (its row
    k_of[node], -1 for the others), into the top left of the block of the row's column
    nodes[c, b] (each row's columns sorted), cells in order. False
    when a pair is not in the pattern (nothing more added)."""
    cells, p = nodes.shape
    for cell in range(cells):
        for a in range(p):
            row = k_of[nodes[cell, a]]
            if row < 0:
                continue
            for b in range(p):
                column = nodes[cell, b]
                low, high = k_indptr[row], k_indptr[row + 1]
                while low < high:  # the column among the row's, sorted
                    middle = (low + high) // 2
                    if k_indices[middle] < column:
                        low = middle + 1
                    else:
                        high = middle
                if low == k_indptr[row + 1] or k_indices[low] != column:
                    return False
                for r in range(3):
                    for c in range(3):
                        data[low, r, c] += blocks[cell, a, r, b, c]
    return True


class RowProduct:
    """The rows of J^T H J of the nodes ``run`` (sorted) on a pattern of node pairs (CornerPairs
    ``indptr``, ``indices``, symmetric, over n nodes): the patterns of the rows of P = H J
    around them (``p_rows``, the nodes paired with the run) and of the run's rows of K, found
    once from scipy's products of the patterns."""

    def __init__(self, indptr: np.ndarray, indices: np.ndarray, n_nodes: int, run: np.ndarray):
        self.indptr = np.asarray(indptr, dtype=np.int64)
        self.indices = np.asarray(indices, dtype=np.int64)
        self.run = np.asarray(run, dtype=np.int64)
        self.k_of = np.full(n_nodes, -1, dtype=np.int64)
        self.k_of[self.run] = np.arange(self.run.size)
        rows = np.repeat(np.arange(n_nodes), np.diff(self.indptr))
        keys = rows * n_nodes + self.indices
        self.transposed = np.searchsorted(keys, self.indices * n_nodes + rows).astype(np.int64)
        pattern = sp.csr_matrix(
            (np.ones(self.indices.size, dtype=np.int32), self.indices, self.indptr),
            shape=(n_nodes, n_nodes),
        )
        own = pattern[self.run]
        self.p_rows = np.unique(own.indices).astype(np.int64)
        p = pattern[self.p_rows] @ pattern
        p.sort_indices()
        k = own[:, self.p_rows] @ p
        k.sort_indices()
        self.p_of = np.full(n_nodes, -1, dtype=np.int64)
        self.p_of[self.p_rows] = np.arange(self.p_rows.size)
        self.p_indptr = p.indptr.astype(np.int64)
        self.p_indices = p.indices.astype(np.int64)
        self.k_indptr = k.indptr.astype(np.int64)
        self.k_indices = k.indices.astype(np.int64)

    def h_pairs(self) -> tuple[np.ndarray, np.ndarray]:
        """The node pairs (positions in ``indices``) whose H blocks the rows read: those of
        the rows ``p_rows``, in order; and the row (node) of each."""
        starts, stops = self.indptr[self.p_rows], self.indptr[self.p_rows + 1]
        counts = stops - starts
        positions = np.repeat(starts - np.cumsum(counts) + counts, counts)
        return positions + np.arange(counts.sum()), np.repeat(self.p_rows, counts)

    def __call__(self, hessian: np.ndarray, h_of: np.ndarray, jacobian: np.ndarray) -> np.ndarray:
        """K's blocks (the run's rows, on ``k_indptr``, ``k_indices``; 6, 6) from H's blocks
        hessian[h_of[pair]] (9, 9) and J's S rows jacobian (pairs, 3, 3)."""
        product = np.empty((self.p_indices.size, 9, 6))
        out = np.empty((self.k_indices.size, 6, 6))
        _membrane_rows(
            self.indptr,
            self.indices,
            self.transposed,
            np.ascontiguousarray(hessian, dtype=float),
            np.ascontiguousarray(h_of, dtype=np.int64),
            np.ascontiguousarray(jacobian, dtype=float),
            self.p_rows,
            self.p_of,
            self.p_indptr,
            self.p_indices,
            self.run,
            self.k_indptr,
            self.k_indices,
            product,
            out,
        )
        return out


def row_patches(
    product: RowProduct, data: np.ndarray, nodes: np.ndarray, blocks: np.ndarray
) -> None:
    """Add cell blocks (c, p, 3, p, 3) in translations over the nodes (c, p) of each cell to
    the rows of ``product``'s run in K's blocks ``data`` (in place, cells in order; the other
    rows' pairs left out); ValueError when a pair is outside the pattern."""
    if not _row_patch_sums(
        product.k_of,
        product.k_indptr,
        product.k_indices,
        np.ascontiguousarray(nodes, dtype=np.int64),
        np.ascontiguousarray(blocks, dtype=float),
        data,
    ):
        raise ValueError("a cell's node pair is outside the rows' pattern")
