"""The system K + rho J^T J of the level-strain projection's sweeps (solvers.newton_levels,
docs/theory.md §6.5) on a CSC pattern kept over the solve, its J^T J summed by a compiled
loop over J's rows.

Why: on Peirce's cantilever (200 unknowns, J of 360 rows and 9315 entries) the sweep's sparse
algebra (the held rows' diagonal times J, J^T J, K + rho J^T J and its placement on a pattern
kept for solvers.linear's symbolic analysis) took 1.1 ms a sweep, about as much as the rest of
the sweep, most of it scipy's object making on a small matrix. Here each product
J[r, i] J[r, j] of a held row r is added at its place in the system's pattern, found once per
pattern of J (``targets``), and K's entries are placed at theirs, found once per pattern of K:
a sweep then makes one CSC matrix. The sums run row by row in J's order: the same bits run to
run, and J^T J exactly symmetric (each product is made for (i, j) and (j, i) alike).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from femcore import kernel_cache

__all__ = ["PenaltySystem", "locate"]


def _normal(
    indptr: np.ndarray,
    data: np.ndarray,
    held: np.ndarray,
    groups: np.ndarray,
    target: np.ndarray,
    out: np.ndarray,
) -> None:
    """out (entries of the system's pattern) = J^T diag(held) J, J in CSR (indptr, data) whose
    rows groups[g]..groups[g + 1] share one column list; ``target`` the place of each product
    of a group's columns (group by group, a then b). Each product summed over the group's
    held rows in a dense block (its upper triangle), then added at its place and its
    mirror's: J^T J exactly symmetric."""
    out[:] = 0.0
    k = 0
    for g in range(groups.size - 1):
        first, last = groups[g], groups[g + 1]
        length = indptr[first + 1] - indptr[first]
        # the group's held rows, column by column: each product a sum along a short
        # contiguous run, in registers (updating a block row by row went through memory:
        # 1.6 against 0.9 ms a sweep on the force-pulled bias specimen)
        rows = np.empty((length, last - first))
        held_rows = 0
        for r in range(first, last):
            if held[r] == 0.0:
                continue
            for a in range(length):
                rows[a, held_rows] = data[indptr[r] + a]
            held_rows += 1
        block = np.empty((length, length))
        for a in range(length):
            for b in range(a, length):  # the upper triangle: J^T J is symmetric
                total = 0.0
                for r in range(held_rows):
                    total += rows[a, r] * rows[b, r]
                block[a, b] = total
        for a in range(length):
            for b in range(length):
                out[target[k]] += block[min(a, b), max(a, b)]
                k += 1


def _groups(indptr: np.ndarray, indices: np.ndarray) -> np.ndarray:
    """(groups + 1,) the first row of each run of consecutive rows with one column list (the
    measures of one cell), and the row count at the end (one more slot than rows: a J with no
    rows gives [0, 0], one empty run, rather than a write past the array's end)."""
    starts = np.empty(indptr.size + 1, dtype=np.int64)
    count = 1
    starts[0] = 0
    for r in range(1, indptr.size - 1):
        same = indptr[r + 1] - indptr[r] == indptr[r] - indptr[r - 1]
        if same:
            for i in range(indptr[r + 1] - indptr[r]):
                if indices[indptr[r] + i] != indices[indptr[r - 1] + i]:
                    same = False
                    break
        if not same:
            starts[count] = r
            count += 1
    starts[count] = indptr.size - 1
    return starts[: count + 1]


def locate(
    indptr: np.ndarray, indices: np.ndarray, rows: np.ndarray, columns: np.ndarray
) -> np.ndarray:
    """(entries,) the place of each (rows[t], columns[t]) in a CSC pattern (indptr, indices
    sorted within each column; of a CSR pattern with rows and columns swapped), -1 where it is
    not stored: a bisection within the column's few entries (numpy's searchsorted over the
    whole pattern's keys took 10 ms a solve on the bias specimen's 282 000 products)."""
    out = np.empty(rows.size, dtype=np.int64)
    for t in range(rows.size):
        low, high = indptr[columns[t]], indptr[columns[t] + 1]
        end = high
        while low < high:
            middle = (low + high) // 2
            if indices[middle] < rows[t]:
                low = middle + 1
            else:
                high = middle
        out[t] = low if low < end and indices[low] == rows[t] else -1
    return out


if kernel_cache.AVAILABLE:
    _normal = kernel_cache.njit(_normal)
    locate = kernel_cache.njit(locate)
    _groups = kernel_cache.njit(_groups)


class PenaltySystem:
    """K + rho J^T diag(held) J on the union of K's and J^T J's patterns (CSC over the free
    unknowns), and J^T diag(held) e; the patterns' maps made when J's or K's pattern is new."""

    def __init__(self, size: int):
        self.size = size  # free unknowns
        self._j: tuple[np.ndarray, np.ndarray] | None = None  # J's (indptr, indices)
        self._k: tuple[np.ndarray, np.ndarray] | None = None  # K's (indptr, indices)
        # (row, column) of each J^T J product, (products,) each
        self._pairs: tuple[np.ndarray, np.ndarray] | None = None
        self._rows: np.ndarray | None = None  # (J entries,) row of each entry
        self._groups: np.ndarray | None = None  # first rows of J's runs of one column list
        self._normal_pattern: sp.csc_matrix | None = None  # J^T J's structure
        self._size_pattern = 0  # entries of the system's pattern
        self._indices: np.ndarray | None = None
        self._indptr: np.ndarray | None = None
        self._target: np.ndarray | None = None  # (products,) place in the system's pattern
        self._place: np.ndarray | None = None  # (K entries,) place in the system's pattern
        self._diagonal: np.ndarray | None = None  # places of the diagonal

    def _same(self, kept, matrix) -> bool:
        return (
            kept is not None
            and np.array_equal(kept[0], matrix.indptr)
            and np.array_equal(kept[1], matrix.indices)
        )

    def _new_j(self, jacobian: sp.csr_matrix) -> None:
        indptr, indices = jacobian.indptr.astype(np.int64), jacobian.indices.astype(np.int64)
        groups = _groups(indptr, indices)
        lengths = indptr[groups[:-1] + 1] - indptr[groups[:-1]]  # columns of each group
        offsets = np.cumsum(lengths) - lengths  # each group's first column in ``columns``
        within = np.arange(lengths.sum()) - np.repeat(offsets, lengths)
        columns = indices[np.repeat(indptr[groups[:-1]], lengths) + within]
        # the products (a, b) of each group's columns, a then b
        reach = np.repeat(lengths, lengths)  # (group columns,) its group's length
        a = np.repeat(np.arange(columns.size), reach)
        b = np.repeat(np.repeat(offsets, lengths), reach)
        b += np.arange(a.size) - np.repeat(np.cumsum(reach) - reach, reach)
        # the product J[r, i] J[r, j] at (row i, column j)
        self._pairs = (columns[a], columns[b])
        ones = sp.csr_matrix((np.ones(indices.size), indices, indptr), shape=jacobian.shape)
        self._normal_pattern = (ones.T @ ones).tocsc()
        self._rows = np.repeat(np.arange(indptr.size - 1), np.diff(indptr))
        self._groups = groups
        self._j = (jacobian.indptr.copy(), jacobian.indices.copy())

    def _new_pattern(self, k: sp.csc_matrix) -> None:
        assert self._pairs is not None and self._normal_pattern is not None
        structure = sp.csc_matrix((np.ones(k.nnz), k.indices, k.indptr), shape=k.shape)
        union = (self._normal_pattern + structure).tocsc()  # no cancellation: all ones
        union.sort_indices()
        indptr, indices = union.indptr.astype(np.int64), union.indices.astype(np.int64)
        self._size_pattern = indices.size
        self._indices, self._indptr = indices, indptr
        self._target = locate(indptr, indices, *self._pairs)
        k_columns = np.repeat(np.arange(self.size), np.diff(k.indptr))
        self._place = locate(indptr, indices, k.indices.astype(np.int64), k_columns)
        diagonal = locate(indptr, indices, np.arange(self.size), np.arange(self.size))
        self._diagonal = diagonal[diagonal >= 0]
        self._k = (k.indptr.copy(), k.indices.copy())

    def assemble(
        self, k_ff: sp.csc_matrix, jacobian: sp.csr_matrix, held: np.ndarray, penalty: float
    ) -> tuple[sp.csc_matrix, float] | None:
        """(K + rho J^T diag(held) J, rho) with rho = penalty times the ratio of the largest
        diagonals of K and J^T diag(held) J; None when either is zero. k_ff (free, free)
        CSC; jacobian (rows, free) CSR; held (rows,) 0 or 1."""
        new_j = not self._same(self._j, jacobian)
        if new_j:
            self._new_j(jacobian)
        if not k_ff.has_canonical_format:  # sorted, no entry twice; the caller's left as is
            k_ff = k_ff.copy()
            k_ff.sum_duplicates()
        if new_j or not self._same(self._k, k_ff):
            self._new_pattern(k_ff)
        assert self._target is not None and self._groups is not None
        normal = np.empty(self._size_pattern)
        indptr = jacobian.indptr
        _normal(indptr, jacobian.data, held, self._groups, self._target, normal)
        k_scale = float(np.abs(k_ff.diagonal()).max(initial=0.0))
        j_scale = float(np.abs(normal[self._diagonal]).max(initial=0.0))
        if k_scale <= 0.0 or j_scale <= 0.0:
            return None
        rho = penalty * k_scale / j_scale
        data = rho * normal
        data[self._place] += k_ff.data
        shape = (self.size, self.size)
        return sp.csc_matrix((data, self._indices, self._indptr), shape=shape), rho

    def pull(self, jacobian: sp.csr_matrix, held: np.ndarray, error: np.ndarray) -> np.ndarray:
        """J^T diag(held) error (free,), error (rows,): summed entry by entry in J's order."""
        assert self._rows is not None
        weights = jacobian.data * (held * error)[self._rows]
        return np.bincount(jacobian.indices, weights=weights, minlength=self.size)
