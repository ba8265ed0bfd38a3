"""A supernodal sparse LDL^T of K_ff after a fill-reducing ordering, compiled: solvers.linear's
factorisation where the band's envelope holds far more operations than the sparse factor.

Why: the band LDL^T of solvers.band runs its contiguous updates near the machine's speed, but
on the fibrous shell's tangent (whose nodal normals couple two rings of cells) the envelope of
the reverse Cuthill-McKee ordering holds three times the operations of the sparse factor after
an approximate minimum degree (AMD) ordering (the 40-cell fibrous corner of bai-6.2.1: 7.0e8
against 2.2e8). QDLDL works that sparse factor one scalar column at a time through index
lists, at a quarter of the band's speed. Here the columns of L that share their pattern below
the diagonal (supernodes: a node's unknowns, and the chains of separators AMD makes) are
stored as dense panels, so that the elimination is made of contiguous vector updates as in the
band, on the sparse factor's operations.

The ordering is QDLDL's AMD (the ``qdldl`` package's, computed with its factor; solvers.linear
gives a new pattern of as many unknowns an earlier pattern's ordering while its entries and
fill stay near that pattern's); the symbolic analysis (elimination tree, L's pattern, the
supernodes, where each entry of K_ff lands) is made once a pattern and kept, and kept whole
for a later pattern whose entries all lie in L (``SupernodalPlan.for_pattern``). LDL^T
without pivoting, as QDLDL's and the band's: D's negative entries count K's negative
eigenvalues (Sylvester's law), a zero or non-finite pivot says it failed. Every operation is
a compiled scalar loop without fastmath and without BLAS: the same factors, to the bit, on
every machine.

Layout: supernode s holds columns ``first[s]`` to ``first[s + 1] - 1`` of the ordered matrix
and the rows ``rows[row_start[s]:row_start[s + 1]]`` (its columns' diagonal rows, then the rows
below, ascending), column by column in ``values[value_start[s]:]`` (column-major: each
column's rows contiguous). After the factorisation each column holds D on its diagonal row
and L below it.
"""

from __future__ import annotations

import copy

import numpy as np
import scipy.sparse as sp

from femcore import kernel_cache

__all__ = ["SupernodalLDLT", "SupernodalPlan", "factor_operations"]

# Columns of a panel of a supernode's own elimination (as solvers.band.PANEL): each column
# after the panel takes the panel's updates four at a time in one pass.
PANEL = 8


def _elimination_tree(indptr: np.ndarray, indices: np.ndarray) -> np.ndarray:
    """The parent (n,) of each column of L (-1 at a root) from the upper triangle's CSC
    pattern (rows <= column) of the ordered matrix, by Liu's algorithm with path compression."""
    n = indptr.size - 1
    parent = np.full(n, -1, dtype=np.int64)
    ancestor = np.full(n, -1, dtype=np.int64)
    for k in range(n):
        for p in range(indptr[k], indptr[k + 1]):
            i = indices[p]
            while i != -1 and i < k:
                following = ancestor[i]
                ancestor[i] = k
                if following == -1:
                    parent[i] = k
                i = following
    return parent


def _column_patterns(
    indptr: np.ndarray, indices: np.ndarray, parent: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """L's pattern below the diagonal in CSC (column pointers (n + 1,), rows ascending): row k
    of L holds the columns met walking up the elimination tree from each entry (i, k), i < k,
    of the upper triangle (the row subtree), counted in a first pass and written in a second."""
    n = indptr.size - 1
    mark = np.full(n, -1, dtype=np.int64)
    counts = np.zeros(n, dtype=np.int64)
    for k in range(n):
        mark[k] = k
        for p in range(indptr[k], indptr[k + 1]):
            i = indices[p]
            while i < k and mark[i] != k:
                counts[i] += 1
                mark[i] = k
                i = parent[i]
    pointers = np.zeros(n + 1, dtype=np.int64)
    for j in range(n):
        pointers[j + 1] = pointers[j] + counts[j]
    rows = np.empty(pointers[n], dtype=np.int64)
    filled = pointers[:-1].copy()
    mark[:] = -1
    for k in range(n):  # k ascending: each column's rows come out ascending
        mark[k] = k
        for p in range(indptr[k], indptr[k + 1]):
            i = indices[p]
            while i < k and mark[i] != k:
                rows[filled[i]] = k
                filled[i] += 1
                mark[i] = k
                i = parent[i]
    return pointers, rows


def _slots(
    indptr: np.ndarray,
    indices: np.ndarray,
    position: np.ndarray,
    owner: np.ndarray,
    first: np.ndarray,
    row_start: np.ndarray,
    rows: np.ndarray,
    value_start: np.ndarray,
) -> tuple[np.ndarray, bool]:
    """(where each stored entry of the upper triangle (original numbering, CSC) lands in the
    supernodes' values: its ordered (row, column) taken below the diagonal, its supernode's
    column and the row's place among the supernode's rows (a binary search); -1 for an entry
    outside L's pattern (another pattern's entry), whether the pattern is a canonical upper
    triangle): at the first row out of order, repeated or below the diagonal it stops, False
    (the column pointers checked by the caller)."""
    n = indptr.size - 1
    slots = np.empty(indptr[n], dtype=np.int64)
    for column in range(n):
        previous = -1
        for p in range(indptr[column], indptr[column + 1]):
            if indices[p] <= previous or indices[p] > column:
                return slots, False
            previous = indices[p]
            a, b = position[indices[p]], position[column]
            row, col = max(a, b), min(a, b)
            s = owner[col]
            low, high = row_start[s], row_start[s + 1]
            while low < high:  # the first of the supernode's rows at or after ``row``
                middle = (low + high) // 2
                if rows[middle] < row:
                    low = middle + 1
                else:
                    high = middle
            if low == row_start[s + 1] or rows[low] != row:
                slots[p] = -1
                continue
            height = row_start[s + 1] - row_start[s]
            slots[p] = value_start[s] + (col - first[s]) * height + (low - row_start[s])
    return slots, True


def _factorise(
    values: np.ndarray,
    first: np.ndarray,
    row_start: np.ndarray,
    rows: np.ndarray,
    value_start: np.ndarray,
    owner: np.ndarray,
    widest: int,
    tallest: int,
) -> int:
    """In place: the supernodes' values of K become D (on each column's diagonal row) and L
    below it. Returns the number of negative pivots, or -1 at a zero or non-finite pivot.

    Right-looking by supernodes: each supernode factorises its panel (column by column, each
    column updating the panel's later ones by contiguous axpys), then sends its update
    L_B D L_B^T to the columns of its rows below (B): for each such column, the sum over the
    panel's columns (in column order) of the axpys of L's column with weight L D, then
    subtracted from the target supernode's entries at the places of B's rows among its rows
    (``where``, filled once a target supernode). ``widest``: the most columns of a supernode,
    ``tallest``: the most rows."""
    n = owner.size
    negative = 0
    weights = np.empty((widest, tallest))  # L D of the panel's columns (row k: column k)
    update = np.empty(tallest)
    where = np.empty(n, dtype=np.int64)
    for s in range(first.size - 1):
        width = first[s + 1] - first[s]
        base, height = value_start[s], row_start[s + 1] - row_start[s]
        own = rows[row_start[s] : row_start[s + 1]]
        for panel in range(0, width, PANEL):
            stop = min(panel + PANEL, width)
            for k in range(panel, stop):
                column = values[base + k * height : base + (k + 1) * height]
                pivot = column[k]
                if pivot == 0.0 or not np.isfinite(pivot):
                    return -1
                if pivot < 0.0:
                    negative += 1
                weight = weights[k]
                for i in range(k + 1, height):
                    weight[i] = column[i]
                    column[i] = column[i] / pivot
                for c in range(k + 1, stop):
                    w = weight[c]
                    if w == 0.0:
                        continue
                    # slices from row c: indices the compiler sees non-negative (it vectorises)
                    target = values[base + c * height + c : base + (c + 1) * height]
                    source = column[c:]
                    for t in range(height - c):
                        target[t] -= source[t] * w
            # the supernode's columns after the panel: the panel's updates four at a time,
            # each entry taking them in column order as the column-by-column elimination
            for c in range(stop, width):
                target = values[base + c * height + c : base + (c + 1) * height]
                length = height - c
                k = panel
                while k + 4 <= stop:
                    wa, wb = weights[k, c], weights[k + 1, c]
                    wc, wd = weights[k + 2, c], weights[k + 3, c]
                    la = values[base + k * height + c : base + (k + 1) * height]
                    lb = values[base + (k + 1) * height + c : base + (k + 2) * height]
                    lc = values[base + (k + 2) * height + c : base + (k + 3) * height]
                    ld = values[base + (k + 3) * height + c : base + (k + 4) * height]
                    for t in range(length):
                        target[t] = (((target[t] - la[t] * wa) - lb[t] * wb) - lc[t] * wc) - ld[
                            t
                        ] * wd
                    k += 4
                while k < stop:
                    w = weights[k, c]
                    la = values[base + k * height + c : base + (k + 1) * height]
                    for t in range(length):
                        target[t] -= la[t] * w
                    k += 1
        place = width
        while place < height:
            t_node = owner[own[place]]
            t_base, t_height = value_start[t_node], row_start[t_node + 1] - row_start[t_node]
            for index in range(row_start[t_node], row_start[t_node + 1]):
                where[rows[index]] = index - row_start[t_node]
            end = place
            while end < height and owner[own[end]] == t_node:
                end += 1
            for p in range(place, end):
                length = height - p
                summed = update[:length]
                for t in range(length):
                    summed[t] = 0.0
                k = 0
                while k + 4 <= width:  # four columns a pass, added in column order
                    wa, wb = weights[k, p], weights[k + 1, p]
                    wc, wd = weights[k + 2, p], weights[k + 3, p]
                    la = values[base + k * height + p : base + (k + 1) * height]
                    lb = values[base + (k + 1) * height + p : base + (k + 2) * height]
                    lc = values[base + (k + 2) * height + p : base + (k + 3) * height]
                    ld = values[base + (k + 3) * height + p : base + (k + 4) * height]
                    for t in range(length):
                        summed[t] = (((summed[t] + la[t] * wa) + lb[t] * wb) + lc[t] * wc) + ld[
                            t
                        ] * wd
                    k += 4
                while k < width:
                    w = weights[k, p]
                    la = values[base + k * height + p : base + (k + 1) * height]
                    for t in range(length):
                        summed[t] += la[t] * w
                    k += 1
                offset = t_base + (own[p] - first[t_node]) * t_height
                targets = own[p:]
                for t in range(length):
                    values[offset + where[targets[t]]] -= summed[t]
            place = end
    return negative


def _solve(
    values: np.ndarray,
    first: np.ndarray,
    row_start: np.ndarray,
    rows: np.ndarray,
    value_start: np.ndarray,
    rhs: np.ndarray,
    tallest: int,
) -> np.ndarray:
    """x with L D L^T x = rhs (the ordered unknowns), the factors in the supernodes' values.

    A supernode at a time: its own columns by the dense triangle, its rows below through a
    contiguous buffer (``below``), so that L's columns are read as contiguous vectors and x
    is gathered or scattered once a supernode, not once a column."""
    x = rhs.copy()
    below = np.empty(tallest)
    count = first.size - 1
    for s in range(count):  # L y = rhs
        start, width = first[s], first[s + 1] - first[s]
        base, height = value_start[s], row_start[s + 1] - row_start[s]
        for k in range(width):
            value = x[start + k]
            column = values[base + k * height : base + k * height + width]
            for i in range(k + 1, width):
                x[start + i] -= column[i] * value
        length = height - width
        summed = below[:length]
        for t in range(length):
            summed[t] = 0.0
        for k in range(width):
            value = x[start + k]
            column = values[base + k * height + width : base + (k + 1) * height]
            for t in range(length):
                summed[t] += column[t] * value
        targets = rows[row_start[s] + width : row_start[s + 1]]
        for t in range(length):
            x[targets[t]] -= summed[t]
    for s in range(count):  # D z = y
        start, width = first[s], first[s + 1] - first[s]
        base, height = value_start[s], row_start[s + 1] - row_start[s]
        for k in range(width):
            x[start + k] /= values[base + k * height + k]
    for s in range(count - 1, -1, -1):  # L^T x = z
        start, width = first[s], first[s + 1] - first[s]
        base, height = value_start[s], row_start[s + 1] - row_start[s]
        length = height - width
        gathered = below[:length]
        sources = rows[row_start[s] + width : row_start[s + 1]]
        for t in range(length):
            gathered[t] = x[sources[t]]
        for k in range(width - 1, -1, -1):
            total = x[start + k]
            column = values[base + k * height : base + (k + 1) * height]
            for i in range(k + 1, width):
                total -= column[i] * x[start + i]
            tail = column[width:]
            for t in range(length):
                total -= tail[t] * gathered[t]
            x[start + k] = total
    return x


def _checked_pattern(upper: sp.spmatrix, frame_only: bool = False) -> sp.csc_matrix:
    """``upper`` when it is an n x n upper triangle in canonical CSC (each column's rows
    ascending, none repeated, every row at most the column), else a ValueError saying what was
    wrong: ``_slots`` maps each stored entry to one place of L, so a repeated entry would
    overwrite where scipy adds, and an entry below the diagonal would land on its mirror's
    place. numpy's passes over the entries, once an analysis; ``frame_only``: the format, the
    shape and the column pointers alone (``_slots`` checks the rows as it maps them)."""
    if not sp.issparse(upper) or upper.format != "csc":
        raise ValueError(f"expected the upper triangle as a scipy CSC matrix, got {type(upper)}")
    rows, columns = upper.shape
    if rows != columns:
        raise ValueError(f"expected a square upper triangle (n x n), got {rows} x {columns}")
    indptr, indices = np.asarray(upper.indptr), np.asarray(upper.indices)
    if (
        indptr.shape != (rows + 1,)
        or indptr[0] != 0
        or indptr[-1] != indices.size
        or np.any(np.diff(indptr) < 0)
    ):
        raise ValueError("expected CSC column pointers (n + 1,) from 0 to nnz, non-decreasing")
    if frame_only or indices.size == 0:
        return upper
    column = np.repeat(np.arange(rows), np.diff(indptr))
    if int(indices.min()) < 0 or np.any(indices > column):
        raise ValueError(
            "expected an upper triangle: every stored row between 0 and its column (an entry "
            "below the diagonal, or out of range, was stored)"
        )
    same_column = column[1:] == column[:-1]
    if np.any(indices[1:][same_column] <= indices[:-1][same_column]):
        raise ValueError(
            "expected canonical CSC: each column's rows ascending and none stored twice "
            "(sum duplicates and sort the indices first)"
        )
    return upper


def _checked_perm(perm: np.ndarray, n: int) -> np.ndarray:
    """``perm`` as int64 when it is a permutation of 0..n-1, else a ValueError."""
    ordering = np.asarray(perm)
    if ordering.shape != (n,) or (n and not np.issubdtype(ordering.dtype, np.integer)):
        raise ValueError(f"expected the ordering as (n,) = ({n},) integers, got {ordering.shape}")
    ordering = ordering.astype(np.int64)
    if n and (
        int(ordering.min()) < 0
        or int(ordering.max()) >= n
        or np.any(np.bincount(ordering, minlength=n) != 1)
    ):
        raise ValueError(f"expected a permutation of 0..{n - 1}: an index repeated or missing")
    return ordering


# numba is a dependency; without it the supernodal path is not taken (``AVAILABLE``)
if kernel_cache.AVAILABLE:
    _elimination_tree = kernel_cache.njit(_elimination_tree)
    _column_patterns = kernel_cache.njit(_column_patterns)
    _slots = kernel_cache.njit(_slots)
    _factorise = kernel_cache.njit(_factorise)
    _solve = kernel_cache.njit(_solve)
    AVAILABLE = True
else:  # pragma: no cover - numba is a dependency
    AVAILABLE = False


def factor_operations(below: np.ndarray) -> float:
    """The operations of an LDL^T whose L holds ``below`` (n,) entries below the diagonal in
    each column: the sum of the column counts squared, diagonal included (QDLDL's measure, by
    which solvers.linear weighs an ordering, the band and the supernodal factor alike)."""
    return float(np.sum((np.asarray(below, dtype=float) + 1.0) ** 2))


class SupernodalPlan:
    """The symbolic analysis of one sparsity pattern (an upper triangle in CSC, every
    diagonal entry stored) under an ordering.

    perm : (n,) int, the ordering (position -> unknown).
    first : (S + 1,) int, the supernodes' first columns (and n).
    row_start, rows : each supernode's rows (ordered numbering, ascending).
    value_start : (S + 1,) int, where each supernode's values start.
    slots : (nnz,) int, where each stored entry of the upper triangle lands in the values.
    operations : the sum of L's column counts squared (diagonal included), QDLDL's measure.
    """

    def __init__(self, upper: sp.csc_matrix, perm: np.ndarray):
        upper = _checked_pattern(upper)
        n = upper.shape[0]
        self.n = n
        self.perm = _checked_perm(perm, n)
        position = np.empty(n, dtype=np.int64)
        position[self.perm] = np.arange(n)
        # The ordered matrix's upper triangle, pattern only (stored zeros included).
        ones = sp.csc_matrix((np.ones(upper.nnz), upper.indices, upper.indptr), shape=upper.shape)
        ordered = sp.triu((ones + ones.T)[self.perm][:, self.perm], format="csc")
        ordered.sort_indices()
        indptr = ordered.indptr.astype(np.int64)
        indices = ordered.indices.astype(np.int64)
        parent = _elimination_tree(indptr, indices)
        pointers, below = _column_patterns(indptr, indices, parent)
        counts = np.diff(pointers)  # below the diagonal
        self.operations = factor_operations(counts)
        # Column j joins j - 1's supernode where its pattern is j - 1's without j - 1's
        # first row below (j itself): parent[j - 1] == j and one entry fewer. (Relaxed
        # supernodes, storing up to 5-40 % more entries as zeros to join more columns, were
        # no faster: 20.8 ms at none, 21.3-24.2 ms at 0.1-0.4 on the 40-cell fibrous corner.)
        joins = np.zeros(n, dtype=bool)
        if n > 1:
            joins[1:] = (parent[:-1] == np.arange(1, n)) & (counts[:-1] == counts[1:] + 1)
        self.first = np.append(np.flatnonzero(~joins), n).astype(np.int64)
        starts = self.first[:-1]
        widths = np.diff(self.first)
        heights = widths + counts[self.first[1:] - 1]  # the last column's rows below, + width
        self.row_start = np.concatenate([[0], np.cumsum(heights)]).astype(np.int64)
        # A supernode's rows: its columns, then its last column's rows below.
        pieces = []
        for s in range(starts.size):
            last = self.first[s + 1] - 1
            pieces.append(np.arange(starts[s], last + 1))
            pieces.append(below[pointers[last] : pointers[last + 1]])
        self.rows = np.concatenate(pieces).astype(np.int64) if pieces else np.zeros(0, np.int64)
        self.value_start = np.concatenate([[0], np.cumsum(heights * widths)]).astype(np.int64)
        self.owner = np.repeat(np.arange(starts.size), widths).astype(np.int64)
        self.widest = int(widths.max(initial=1))
        self.tallest = int(heights.max(initial=1))
        self.position = position
        self.slots = self._slots_of(upper)

    def _slots_of(self, upper: sp.csc_matrix) -> np.ndarray:
        slots, canonical = _slots(
            upper.indptr.astype(np.int64),
            upper.indices.astype(np.int64),
            self.position,
            self.owner,
            self.first,
            self.row_start,
            self.rows,
            self.value_start,
        )
        if not canonical:
            _checked_pattern(upper)  # raises, saying what was wrong
            raise ValueError("expected an upper triangle in canonical CSC")  # pragma: no cover
        return slots

    def for_pattern(self, upper: sp.csc_matrix) -> SupernodalPlan | None:
        """This plan for another pattern of as many unknowns whose entries all lie in this
        plan's L (entries gone, or come within the fill), or None: one pass over the entries
        where a new analysis costs four times a numeric factorisation on a 1000-unknown
        tangent (the element-normal fibrous tangents by central differences, whose exact
        zeros come and go from one iteration to the next, changed pattern at every one)."""
        upper = _checked_pattern(upper, frame_only=True)
        if upper.shape[0] != self.n:
            return None
        slots = self._slots_of(upper)
        if slots.size and int(slots.min()) < 0:
            return None
        plan = copy.copy(self)
        plan.slots = slots
        return plan

    def factorise(self, upper_data: np.ndarray) -> SupernodalLDLT | None:
        """The LDL^T of the matrix whose upper triangle has these values (in the pattern's
        CSC order), or None at a zero or non-finite pivot."""
        if np.shape(upper_data) != self.slots.shape:
            raise ValueError(
                f"expected the values of the pattern's {self.slots.size} stored entries, "
                f"got shape {np.shape(upper_data)}"
            )
        values = np.zeros(int(self.value_start[-1]))
        values[self.slots] = upper_data
        negative = _factorise(
            values,
            self.first,
            self.row_start,
            self.rows,
            self.value_start,
            self.owner,
            self.widest,
            self.tallest,
        )
        if negative < 0:
            return None
        return SupernodalLDLT(self, values, negative)


class SupernodalLDLT:
    """A factorised K: ``solve(rhs)`` and ``negative`` (its negative eigenvalues)."""

    def __init__(self, plan: SupernodalPlan, values: np.ndarray, negative: int):
        self.plan, self.values, self.negative = plan, values, negative

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """x (n,) with K x = rhs, rhs (n,) or (n, 1)."""
        plan = self.plan
        if np.size(rhs) != plan.n or np.ndim(rhs) > 2:
            raise ValueError(f"expected rhs of length n = {plan.n}, got shape {np.shape(rhs)}")
        y = _solve(
            self.values,
            plan.first,
            plan.row_start,
            plan.rows,
            plan.value_start,
            np.ascontiguousarray(np.ravel(rhs)[plan.perm], dtype=float),
            plan.tallest,
        )
        x = np.empty_like(y)
        x[plan.perm] = y
        return x
