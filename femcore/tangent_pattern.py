"""The sparsity pattern of K_ff and K_fp from the node pairs the tangent parts couple, and each
part entry's place in their storage (femcore.assembly.FreeTangentAssembler).

A cell part of p nodes couples p^2 (row node I, column node J) pairs; a 6 x 6 node block of a
SparseTangent one. Each distinct pair holds the entries (5 I + a, 5 J + c) with a, c below
its widest part's components (3 for translation-only parts, else 5), those on free rows and
free columns in K_ff (CSC: by column, then row) and those on free rows and prescribed columns
in K_fp (CSR). Their places are counted per pair (the pairs sorted by column node, then row
node; a pair's rows follow those of the pairs of its column before it), never sorted out of
every entry.

Two ways to the same arrays, to the bit: ``pattern`` (numba: a counting sort of the pairs by
column node, each column's rows sorted alone, then one pass over the pairs) and
``pattern_numpy`` (np.unique over the pair keys and (pairs, 5, 5) tables), the reference the
compiled one is tested against, and the way without numba. The compiled assembly passes read
an entry's place from its pair's table; ``part_destinations`` lists them per entry for numpy's
bincounts. The ply contact's parts change
their pairs whenever a touching point changes its facing triangle, so a Static solve on ply
stacks builds this pattern at most Newton iterations (benchmarks/tangent_pattern.py).
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from femcore import kernel_cache
from femcore.dofs import N_COLUMNS

__all__ = ["Pattern", "pairs_within", "part_destinations", "pattern", "pattern_numpy"]


class Pattern(NamedTuple):
    """K_ff's and K_fp's structure and the place of each pair's entries in their data.

    Attributes
    ----------
    inverse : (k,) int
        The distinct pair (index into the tables) of each given pair.
    ff_indptr, ff_rows : (n_free + 1,), (nnz,) int
        K_ff in CSC: column pointers and the row of each stored entry.
    ff_table : (pairs, 5, 5) int
        Place in K_ff's data of entry (a, c) of each distinct pair (-1: not in K_ff).
    fp_indptr, fp_rows, fp_cols : (n_free + 1,), (nnz_fp,), (nnz_fp,) int
        K_fp in CSR: row pointers, the row and the column of each stored entry.
    fp_table : (pairs, 5, 5) int
        Place in K_fp's data of entry (a, c) of each distinct pair (-1: not in K_fp).
    """

    inverse: np.ndarray
    ff_indptr: np.ndarray
    ff_rows: np.ndarray
    ff_table: np.ndarray
    fp_indptr: np.ndarray
    fp_rows: np.ndarray
    fp_cols: np.ndarray
    fp_table: np.ndarray


def pattern_numpy(
    rows: np.ndarray,
    cols: np.ndarray,
    wide: np.ndarray,
    free: np.ndarray,
    moved: np.ndarray,
    n_free: int,
    n_moved: int,
) -> Pattern:
    """The pattern of the node pairs (``rows``, ``cols``) ((k,) int each), by numpy.

    ``wide`` (k,) bool: the pair's part has 5 components (else 3); ``free`` and ``moved``
    (n, 5) int: the place of each node's unknown among the free (prescribed) ones, -1 where it
    is not one; ``n_free``, ``n_moved`` their counts."""
    n = free.shape[0]
    pairs, inverse = np.unique(cols * n + rows, return_inverse=True)
    inverse = inverse.ravel()
    width = np.where(np.bincount(inverse, wide, pairs.size) > 0, N_COLUMNS, 3)
    column_node, row_node = np.divmod(pairs, n)
    components = np.arange(N_COLUMNS)
    inside = components[None, :] < width[:, None]  # (pairs, 5): a or c below the width
    row_free = free[row_node] >= 0  # (pairs, 5) over a
    ranks: np.ndarray = np.cumsum(row_free & inside, axis=1) - (row_free & inside)  # rank of a
    # K_ff (CSC: by column 5 J + c, then row 5 I + a): each pair holds rows_of[P] rows
    # of every free column c below its width, after the pairs of J before it.
    rows_of = np.count_nonzero(row_free & inside, axis=1)
    counts = np.where(inside & (free[column_node] >= 0), rows_of[:, None], 0)  # (P, c)
    before = np.cumsum(counts, axis=0) - counts
    group_start = np.searchsorted(column_node, column_node)  # each J's first pair
    before -= before[group_start]
    lengths = np.zeros(n_free, dtype=np.int64)
    column_free = free[column_node]
    np.add.at(lengths, column_free[counts > 0], counts[counts > 0])
    ff_indptr = np.concatenate([[0], np.cumsum(lengths)])
    entry = row_free[:, :, None] & inside[:, :, None] & (counts > 0)[:, None, :]  # (P, a, c)
    ff_table = np.where(
        entry,
        ff_indptr[np.maximum(column_free, 0)][:, None, :] + before[:, None, :] + ranks[:, :, None],
        -1,
    )
    ff_rows = np.empty(ff_indptr[-1], dtype=np.int64)
    where = np.nonzero(entry)
    ff_rows[ff_table[where]] = free[row_node[where[0]], where[1]]
    # K_fp (CSR through its sorted keys: row 5 I + a, then prescribed column 5 J + c).
    fp_entry = (
        row_free[:, :, None] & inside[:, :, None] & (inside & (moved[column_node] >= 0))[:, None, :]
    )
    where = np.nonzero(fp_entry)
    fp_keys = (
        free[row_node[where[0]], where[1]] * max(n_moved, 1)
        + moved[column_node[where[0]], where[2]]
    )
    keys, order = np.unique(fp_keys, return_inverse=True)
    fp_rows, fp_cols = np.divmod(keys, max(n_moved, 1))
    fp_indptr = np.searchsorted(fp_rows, np.arange(n_free + 1))
    fp_table = np.full(fp_entry.shape, -1, dtype=np.int64)
    fp_table[where] = order.ravel()
    return Pattern(inverse, ff_indptr, ff_rows, ff_table, fp_indptr, fp_rows, fp_cols, fp_table)


def _pattern_arrays(
    rows: np.ndarray,
    cols: np.ndarray,
    wide: np.ndarray,
    free: np.ndarray,
    moved: np.ndarray,
    n_free: int,
    n_moved: int,
) -> tuple[np.ndarray, ...]:
    """The arrays of ``Pattern`` in its order (pattern_numpy's arguments), by loops: compiled by
    numba. Integer counts only: any order of the sums gives the same arrays."""
    n = free.shape[0]
    k_count = rows.size
    # The pairs by column node (a counting sort), then each column's distinct row nodes.
    start = np.zeros(n + 1, dtype=np.int64)
    for k in range(k_count):
        start[cols[k] + 1] += 1
    for j in range(n):
        start[j + 1] += start[j]
    order = np.empty(k_count, dtype=np.int64)
    fill = start[:n].copy()
    for k in range(k_count):
        order[fill[cols[k]]] = k
        fill[cols[k]] += 1
    stamp = np.full(n, -1, dtype=np.int64)  # the column whose rows last met each node
    slot = np.zeros(n, dtype=np.int64)
    pair_row = np.empty(k_count, dtype=np.int64)
    pair_col = np.empty(k_count, dtype=np.int64)
    pair_wide = np.zeros(k_count, dtype=np.bool_)
    inverse = np.empty(k_count, dtype=np.int64)
    count = 0
    for j in range(n):
        first = count
        for t in range(start[j], start[j + 1]):
            i = rows[order[t]]
            if stamp[i] != j:
                stamp[i] = j
                pair_row[count] = i
                count += 1
        for q in range(first + 1, count):  # a column's few rows sorted in place
            row = pair_row[q]
            t = q - 1
            while t >= first and pair_row[t] > row:
                pair_row[t + 1] = pair_row[t]
                t -= 1
            pair_row[t + 1] = row
        for q in range(first, count):
            slot[pair_row[q]] = q
            pair_col[q] = j
        for t in range(start[j], start[j + 1]):
            k = order[t]
            q = slot[rows[k]]
            inverse[k] = q
            if wide[k]:
                pair_wide[q] = True
    # K_ff: each pair's stored rows (rank of a among them, -1: none) and, per column c, its
    # rows' count and the rows of the column's pairs before it.
    ranks = np.full((count, N_COLUMNS), -1, dtype=np.int64)
    counts = np.zeros((count, N_COLUMNS), dtype=np.int64)
    before = np.zeros((count, N_COLUMNS), dtype=np.int64)
    lengths = np.zeros(n_free, dtype=np.int64)
    running = np.zeros(N_COLUMNS, dtype=np.int64)
    for q in range(count):
        i, j = pair_row[q], pair_col[q]
        width = N_COLUMNS if pair_wide[q] else 3
        if q == 0 or pair_col[q - 1] != j:
            running[:] = 0
        stored = 0
        for a in range(width):
            if free[i, a] >= 0:
                ranks[q, a] = stored
                stored += 1
        if stored == 0:
            continue
        for c in range(width):
            if free[j, c] >= 0:
                counts[q, c] = stored
                before[q, c] = running[c]
                running[c] += stored
                lengths[free[j, c]] += stored
    ff_indptr = np.zeros(n_free + 1, dtype=np.int64)
    for column in range(n_free):
        ff_indptr[column + 1] = ff_indptr[column] + lengths[column]
    nnz = ff_indptr[n_free]
    ff_rows = np.empty(nnz, dtype=np.int64)
    ff_table = np.full((count, N_COLUMNS, N_COLUMNS), -1, dtype=np.int64)
    for q in range(count):
        i, j = pair_row[q], pair_col[q]
        for c in range(N_COLUMNS):
            if counts[q, c] == 0:
                continue
            base = ff_indptr[free[j, c]] + before[q, c]
            for a in range(N_COLUMNS):
                if ranks[q, a] >= 0:
                    place = base + ranks[q, a]
                    ff_table[q, a, c] = place
                    ff_rows[place] = free[i, a]
    # K_fp (CSR): each entry (free row 5 I + a, prescribed column 5 J + c) is one pair's, so
    # the keys are distinct; counted per row, and placed in the pairs' order (by J, then I) and
    # c's, which is each row's order of columns: no sort.
    fp_indptr = np.zeros(n_free + 1, dtype=np.int64)
    for q in range(count):
        i, j = pair_row[q], pair_col[q]
        width = N_COLUMNS if pair_wide[q] else 3
        columns_here = 0
        for c in range(width):
            if moved[j, c] >= 0:
                columns_here += 1
        if columns_here == 0:
            continue
        for a in range(width):
            if free[i, a] >= 0:
                fp_indptr[free[i, a] + 1] += columns_here
    for row in range(n_free):
        fp_indptr[row + 1] += fp_indptr[row]
    fp_rows = np.empty(fp_indptr[n_free], dtype=np.int64)
    fp_cols = np.empty(fp_indptr[n_free], dtype=np.int64)
    fp_table = np.full((count, N_COLUMNS, N_COLUMNS), -1, dtype=np.int64)
    fp_fill = fp_indptr[:n_free].copy()
    for q in range(count):
        i, j = pair_row[q], pair_col[q]
        width = N_COLUMNS if pair_wide[q] else 3
        for a in range(width):
            if free[i, a] < 0:
                continue
            for c in range(width):
                if moved[j, c] >= 0:
                    place = fp_fill[free[i, a]]
                    fp_fill[free[i, a]] += 1
                    fp_table[q, a, c] = place
                    fp_rows[place] = free[i, a]
                    fp_cols[place] = moved[j, c]
    return (
        inverse,
        ff_indptr,
        ff_rows,
        ff_table,
        fp_indptr,
        fp_rows,
        fp_cols,
        fp_table,
    )


_pattern_compiled: Any = None
# numba is a dependency; without it the pattern is numpy's
if kernel_cache.AVAILABLE:
    _pattern_compiled = kernel_cache.njit(_pattern_arrays)


def pattern(
    rows: np.ndarray,
    cols: np.ndarray,
    wide: np.ndarray,
    free: np.ndarray,
    moved: np.ndarray,
    n_free: int,
    n_moved: int,
) -> Pattern:
    """``pattern_numpy``'s arrays by the compiled pass (numpy's without numba)."""
    if _pattern_compiled is None:  # pragma: no cover - numba is a dependency
        return pattern_numpy(rows, cols, wide, free, moved, n_free, n_moved)
    arrays = _pattern_compiled(
        np.ascontiguousarray(rows, dtype=np.int64),
        np.ascontiguousarray(cols, dtype=np.int64),
        np.ascontiguousarray(wide, dtype=np.bool_),
        np.ascontiguousarray(free, dtype=np.int64),
        np.ascontiguousarray(moved, dtype=np.int64),
        int(n_free),
        int(n_moved),
    )
    return Pattern(*arrays)


def _pairs_within(
    rows: np.ndarray,
    cols: np.ndarray,
    wide: np.ndarray,
    pair_start: np.ndarray,
    pair_rows: np.ndarray,
    pair_wide: np.ndarray,
) -> tuple[np.ndarray, int]:
    """(the distinct pair of each node pair (``Pattern.inverse``), how many distinct pairs
    they reach) of the node pairs (``rows``, ``cols``, ``wide``: as ``pattern``'s) among a
    pattern's pairs, given by column node (``pair_start`` (n + 1,): each column node's
    first pair; ``pair_rows``: the pairs' row nodes, sorted within a column; ``pair_wide``:
    their parts' width is 5); (empty, -1) where a node pair is not among them, or is wide
    where its pair is not. A bisection within the column. Compiled by numba."""
    count = rows.size
    inverse = np.empty(count, dtype=np.int64)
    seen = np.zeros(pair_rows.size, dtype=np.bool_)
    distinct = 0
    for k in range(count):
        row = rows[k]
        low, high = pair_start[cols[k]], pair_start[cols[k] + 1]
        end = high
        while low < high:
            middle = (low + high) // 2
            if pair_rows[middle] < row:
                low = middle + 1
            else:
                high = middle
        if low == end or pair_rows[low] != row or (wide[k] and not pair_wide[low]):
            return np.empty(0, dtype=np.int64), -1
        inverse[k] = low
        if not seen[low]:
            seen[low] = True
            distinct += 1
    return inverse, distinct


_pairs_within_compiled: Any = None
if kernel_cache.AVAILABLE:
    _pairs_within_compiled = kernel_cache.njit(_pairs_within)


def pairs_within(
    rows: np.ndarray,
    cols: np.ndarray,
    wide: np.ndarray,
    pair_start: np.ndarray,
    pair_rows: np.ndarray,
    pair_wide: np.ndarray,
) -> tuple[np.ndarray, int]:
    """``_pairs_within`` by its compiled pass (by the same loops without numba)."""
    find = _pairs_within if _pairs_within_compiled is None else _pairs_within_compiled
    return find(
        np.ascontiguousarray(rows, dtype=np.int64),
        np.ascontiguousarray(cols, dtype=np.int64),
        np.ascontiguousarray(wide, dtype=np.bool_),
        pair_start,
        pair_rows,
        pair_wide,
    )


def part_destinations(
    pairs: np.ndarray, ff_table: np.ndarray, fp_table: np.ndarray, c: int
) -> tuple[np.ndarray, np.ndarray]:
    """Each entry's place in K_ff's and K_fp's data (-1: not in that matrix) of a part whose
    node pairs are ``pairs`` (m, p, p) (rows of ``Pattern.inverse``, in (cell, row node,
    column node) order) and whose blocks have ``c`` components, ``*_table`` the Pattern's;
    the entries in the order (cell, row node, a, column node, c) of the part's raveled blocks
    (the compiled assembly reads the tables through the pairs instead: femcore.assembly)."""
    m, p, _ = pairs.shape
    components = np.arange(c)
    at = pairs.reshape(m, p, 1, p, 1)
    a, b = components.reshape(1, 1, c, 1, 1), components.reshape(1, 1, 1, 1, c)
    flat = (at * N_COLUMNS**2 + (a * N_COLUMNS + b)).ravel()  # one index, two gathers
    return ff_table.take(flat), fp_table.take(flat)
