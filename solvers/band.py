"""A banded LDL^T of K_ff after a reverse Cuthill-McKee ordering, compiled: the fast path of
solvers.linear for the tangents of shells, strips and sheets.

Why: the general sparse LDL^T (QDLDL) works one scalar column at a time through index lists;
on a shell's tangent, whose nodes a reverse Cuthill-McKee ordering lines up along a band a few
nodes wide, the same elimination on the dense band is a sequence of contiguous vector updates
that the compiler vectorises. On the 2560-triangle Mindlin cantilever (6800 unknowns, band 94)
it takes about 10 ms where QDLDL takes about 35 (benchmarks/static_solver.py); where the band
would hold far more than QDLDL's factor (a wide square sheet), solvers.linear keeps QDLDL.

The factorisation is LDL^T without pivoting, as QDLDL's: D's negative entries count the
negative eigenvalues of K (Sylvester's law), a zero or non-finite pivot says it failed, and
solvers.linear checks every solution's backward error as it does for QDLDL.

Storage: the lower band of the permuted matrix column by column, ``band[j, r]`` = A[j + r, j]
for r = 0..b (b the bandwidth), C order so that each column's entries are contiguous.

The elimination runs within the envelope of the ordered matrix, not the whole band: column j
reaches down to the last row i whose first entry (its leftmost column) is at or before j
(``BandPlan.reaches``), and no fill falls outside (the envelope theorem: the L of a row starts
where the row's first entry does). The operations skipped are those on the band's entries
outside the envelope, zeros that stay zeros, so the factors and the solves are those of the
whole band to the bit: on the 40-cell fibrous corner of bai-6.2.1 (4025 unknowns, band 584)
the band held 1.37e9 operations (n b^2) where the envelope holds 0.70e9 (QDLDL's factor
0.22e9), 73 -> 52 ms a factorisation (QDLDL 75 ms; benchmarks/band_envelope.py).
"""

from __future__ import annotations

import copy
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import reverse_cuthill_mckee

from femcore import kernel_cache

__all__ = ["BandLDLT", "BandPlan"]

# Columns of a panel of ``_factorise``: on the 40-cell fibrous corner of bai-6.2.1 (4025
# unknowns, band 584) 4, 8, 12, 16, 32 and 64 took 44, 42, 44, 47, 52 and 53 ms, the column by
# column reference 59 (benchmarks/band_envelope.py).
PANEL = 8
# Bandwidth from which the panels are used: on narrower bands the column by column reference is
# faster (its axpys already in the cache; the panels' bookkeeping costs more than it saves):
# the Mindlin cantilever of benchmarks/kratos_cantilever.py (band 94) 5.6 against 6.7 ms, the
# paper cases' 10- and 20-cell Mindlin corners (54, 104) 0.05 / 0.53 against 0.07 / 0.65, the
# 10-cell fibrous one (123) 0.18 against 0.21; from 200 on the panels are as fast or faster
# (204: 8.8 against 9.0, 287: 3.2 against 3.7, 584: 40 against 54). The same bits either way.
PANEL_FROM = 200
# Columns from which ``BandLDLT.solve_columns`` solves them in one pass: below, its loop over
# the columns costs more than it saves (plies-bai-5.1's pressed default stack, 3528 unknowns,
# band 130: 1, 2, 3, 4, 8 columns 1.36, 1.53, 1.67, 1.44, 1.62 ms together against 0.53,
# 0.99, 1.49, 1.95, 4.21 one by one; timed once with the pass called directly, below this
# bound, where benchmarks/band_columns.py's own counts, 1 to 200 columns, take the loop).
COLUMNS_TOGETHER = 4


def _factorise_by_column(band: np.ndarray, reaches: np.ndarray) -> int:
    """In place: band (n, b + 1) of A becomes L (below the diagonal, unit diagonal implied)
    and D (column 0), column j's elimination reaching ``reaches[j]`` rows below the diagonal
    (its envelope, at most b). Returns the number of negative pivots, or -1 at a zero or
    non-finite pivot. Right-looking: each column scales, then updates the triangle of the
    columns below it (an axpy per column, contiguous). The reference of ``_factorise``, which
    makes the same updates in the same order by panels (the same bits)."""
    n, width = band.shape
    negative = 0
    column = np.empty(width)
    for j in range(n):
        pivot = band[j, 0]
        if pivot == 0.0 or not np.isfinite(pivot):
            return -1
        if pivot < 0.0:
            negative += 1
        reach = reaches[j]
        for r in range(1, reach + 1):
            column[r] = band[j, r]  # A[j + r, j], not yet divided
            band[j, r] = band[j, r] / pivot
        # A[j + s + t, j + s] -= L[j + s + t, j] A[j + s, j] for s = 1..reach, t = 0..reach - s
        for s in range(1, reach + 1):
            weight = column[s]
            if weight == 0.0:
                continue
            target = band[j + s]
            for t in range(reach - s + 1):
                target[t] -= band[j, s + t] * weight
    return negative


def _factorise(band: np.ndarray, reaches: np.ndarray) -> int:
    """``_factorise_by_column`` by panels of PANEL columns: the same factors to the bit, with
    a quarter of its loads and stores of the columns being updated.

    Each column of a panel is factorised and updates the panel's later columns as there; then
    each column c below the panel takes the updates of the panel's columns that reach it (the
    nonzero weights, in column order), four at a time in one pass down c: every entry gets the
    same products subtracted in the same order as by the column's axpys, one subtraction
    after the other (no fused multiply-add: numba compiles without fastmath), while c stays in
    the cache and is loaded and stored once for four updates. The reaches' ends j + reaches[j]
    do not decrease with j (``BandPlan``), so the columns reaching c are the panel's last ones
    and a column's update ends no lower than those before it."""
    n, width = band.shape
    negative = 0
    raw = np.empty((PANEL, width))  # each panel column's entries before its division
    active = np.empty(PANEL, dtype=np.int64)
    for start in range(0, n, PANEL):
        stop = min(start + PANEL, n)
        for j in range(start, stop):
            pivot = band[j, 0]
            if pivot == 0.0 or not np.isfinite(pivot):
                return -1
            if pivot < 0.0:
                negative += 1
            reach = reaches[j]
            column = raw[j - start]
            for r in range(1, reach + 1):
                column[r] = band[j, r]
                band[j, r] = band[j, r] / pivot
            for s in range(1, min(reach, stop - 1 - j) + 1):
                weight = column[s]
                if weight == 0.0:
                    continue
                target = band[j + s]
                for t in range(reach - s + 1):
                    target[t] -= band[j, s + t] * weight
        first = start
        for c in range(stop, stop + reaches[stop - 1]):
            while first + reaches[first] < c:
                first += 1
            count = 0
            for j in range(first, stop):
                if raw[j - start, c - j] != 0.0:
                    active[count] = j
                    count += 1
            target = band[c]
            k = 0
            while k + 4 <= count:
                ja, jb, jc, jd = active[k], active[k + 1], active[k + 2], active[k + 3]
                wa, wb = raw[ja - start, c - ja], raw[jb - start, c - jb]
                wc, wd = raw[jc - start, c - jc], raw[jd - start, c - jd]
                # each column's entries from row c down, sliced so that the compiler sees
                # non-negative indices and vectorises the pass
                la, lb = band[ja, c - ja :], band[jb, c - jb :]
                lc, ld = band[jc, c - jc :], band[jd, c - jd :]
                ea, eb = ja + reaches[ja] - c, jb + reaches[jb] - c
                ec, ed = jc + reaches[jc] - c, jd + reaches[jd] - c
                for t in range(ea + 1):
                    target[t] = (((target[t] - la[t] * wa) - lb[t] * wb) - lc[t] * wc) - ld[t] * wd
                for t in range(ea + 1, eb + 1):
                    target[t] = ((target[t] - lb[t] * wb) - lc[t] * wc) - ld[t] * wd
                for t in range(eb + 1, ec + 1):
                    target[t] = (target[t] - lc[t] * wc) - ld[t] * wd
                for t in range(ec + 1, ed + 1):
                    target[t] = target[t] - ld[t] * wd
                k += 4
            while k < count:
                ja = active[k]
                wa = raw[ja - start, c - ja]
                la = band[ja, c - ja :]
                for t in range(ja + reaches[ja] - c + 1):
                    target[t] -= la[t] * wa
                k += 1
    return negative


def _solve(band: np.ndarray, reaches: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """x with L D L^T x = rhs, the factors in ``band`` (n, b + 1), column j of L reaching
    ``reaches[j]`` rows below the diagonal."""
    n = band.shape[0]
    x = rhs.copy()
    for j in range(n):  # L y = rhs
        reach = reaches[j]
        value = x[j]
        for r in range(1, reach + 1):
            x[j + r] -= band[j, r] * value
    for j in range(n):
        x[j] /= band[j, 0]
    for j in range(n - 1, -1, -1):  # L^T x = y / D
        reach = reaches[j]
        total = x[j]
        for r in range(1, reach + 1):
            total -= band[j, r] * x[j + r]
        x[j] = total
    return x


def _solve_columns(band: np.ndarray, reaches: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """X (n, m) with L D L^T X = rhs (n, m), the factors as ``_solve``'s: each column the same
    operations in the same order as ``_solve`` on it alone (the same bits), the band read once
    for all the columns instead of once a column (solvers/contact_sets.py solves the switched
    points' columns together; benchmarks/band_columns.py)."""
    n = band.shape[0]
    m = rhs.shape[1]
    x = rhs.copy()
    for j in range(n):  # L Y = rhs
        reach = reaches[j]
        for r in range(1, reach + 1):
            weight = band[j, r]
            for c in range(m):
                x[j + r, c] -= weight * x[j, c]
    for j in range(n):
        pivot = band[j, 0]
        for c in range(m):
            x[j, c] /= pivot
    total = np.empty(m)
    for j in range(n - 1, -1, -1):  # L^T X = Y / D
        reach = reaches[j]
        for c in range(m):
            total[c] = x[j, c]
        for r in range(1, reach + 1):
            weight = band[j, r]
            for c in range(m):
                total[c] -= weight * x[j + r, c]
        for c in range(m):
            x[j, c] = total[c]
    return x


def _closure(indptr: np.ndarray, indices: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The CSR pattern (indptr, indices) of U + U^T for an upper triangle U in CSC with sorted
    indices (every row's columns come out sorted and once: row r takes column r's rows, then
    the later columns holding r, in order), the pattern of BandPlan's ``ones + ones.T``.
    Compiled by numba."""
    counts = np.zeros(n + 1, dtype=np.int64)
    for j in range(n):
        for e in range(indptr[j], indptr[j + 1]):
            i = indices[e]
            counts[i + 1] += 1
            if i != j:
                counts[j + 1] += 1
    for r in range(n):
        counts[r + 1] += counts[r]
    fill = counts[:n].copy()
    columns = np.empty(counts[n], dtype=np.int64)
    for j in range(n):
        for e in range(indptr[j], indptr[j + 1]):
            i = indices[e]
            if i != j:
                columns[fill[j]] = i
                fill[j] += 1
            columns[fill[i]] = j
            fill[i] += 1
    return counts, columns


def _layout(
    indptr: np.ndarray, indices: np.ndarray, perm: np.ndarray, n: int
) -> tuple[int, np.ndarray, np.ndarray]:
    """BandPlan's (bandwidth, slots, reaches) of an upper triangle's pattern in CSC ordered
    by ``perm``: the numpy scatters of ``BandPlan.__init__`` as loops (integers only, the
    same arrays). Compiled by numba."""
    position = np.empty(n, dtype=np.int64)
    for q in range(n):
        position[perm[q]] = q
    first = np.arange(n)  # each row's first entry (its diagonal at most)
    bandwidth = 0
    for j in range(n):
        b = position[j]
        for e in range(indptr[j], indptr[j + 1]):
            a = position[indices[e]]
            low, high = min(a, b), max(a, b)
            bandwidth = max(bandwidth, high - low)
            if low < first[high]:
                first[high] = low
    slots = np.empty(indptr[n], dtype=np.int64)
    for j in range(n):
        b = position[j]
        for e in range(indptr[j], indptr[j + 1]):
            a = position[indices[e]]
            low, high = min(a, b), max(a, b)
            slots[e] = low * (bandwidth + 1) + (high - low)
    last = np.full(n, -1, dtype=np.int64)  # the last row whose first entry is each column
    for i in range(n):
        if i > last[first[i]]:
            last[first[i]] = i
    reaches = np.empty(n, dtype=np.int64)
    reach = -1
    for j in range(n):
        reach = max(reach, last[j])
        reaches[j] = max(reach, j) - j
    return bandwidth, slots, reaches


def _fill_envelope(band: np.ndarray, reaches: np.ndarray, slots: np.ndarray, data: np.ndarray):
    """In place: the envelope of ``band`` (n, b + 1), ``band[j, 0..reaches[j]]``, set to the
    matrix whose upper triangle's values ``data`` (nnz,) land at ``slots`` (nnz,) of the flat
    band, zeros elsewhere in it; the entries outside the envelope are left as they are (no
    kernel reads them: the factorisation and the solves stop at each column's reach, and every
    stored entry lies within its row's first entry, so within the envelope). Compiled by
    numba."""
    flat = band.reshape(-1)
    for j in range(band.shape[0]):
        row = band[j]
        for r in range(reaches[j] + 1):
            row[r] = 0.0
    for e in range(slots.size):
        flat[slots[e]] = data[e]


def _slots_within(
    indptr: np.ndarray,
    indices: np.ndarray,
    position: np.ndarray,
    reaches: np.ndarray,
    bandwidth: int,
) -> np.ndarray:
    """The slots in a plan's flat band (``BandPlan.slots``) of the entries of an upper
    triangle's pattern in CSC (indptr, indices), ``position`` (n,) the plan's place of each
    unknown; or an empty array where an entry falls outside the plan's envelope (its row
    more than ``reaches`` of its column below the diagonal after the ordering). Compiled by
    numba."""
    n = indptr.size - 1
    slots = np.empty(indptr[n], dtype=np.int64)
    for j in range(n):
        b = position[j]
        for e in range(indptr[j], indptr[j + 1]):
            a = position[indices[e]]
            low, high = min(a, b), max(a, b)
            if high - low > reaches[low]:
                return np.empty(0, dtype=np.int64)
            slots[e] = low * (bandwidth + 1) + (high - low)
    return slots


_closure_compiled: Any = None
_layout_compiled: Any = None
_slots_within_compiled: Any = None
_fill_envelope_compiled: Any = None
# numba is a dependency; without it the band path is not taken (``AVAILABLE``)
if kernel_cache.AVAILABLE:
    _closure_compiled = kernel_cache.njit(_closure)
    _layout_compiled = kernel_cache.njit(_layout)
    _fill_envelope_compiled = kernel_cache.njit(_fill_envelope)
    _slots_within_compiled = kernel_cache.njit(_slots_within)
    _factorise_by_column = kernel_cache.njit(_factorise_by_column)
    _factorise = kernel_cache.njit(_factorise)
    # Compiled without fastmath: re-associating the back substitution's sums let the compiler
    # vectorise it (0.9-1.2 against 2.0-3.4 ms per solve alone, 3.0 against 3.4 ms within a
    # Static run, memory-bound there), but the sums then depend on the machine's vector width,
    # and Newton's path with them: the tip-loaded cantilever of tests/test_static.py took 7
    # iterations in an increment on a machine with 512-bit vectors, 6 with the solve as written.
    _solve = kernel_cache.njit(_solve)
    _solve_columns = kernel_cache.njit(_solve_columns)
    AVAILABLE = True
else:  # pragma: no cover - numba is a dependency
    AVAILABLE = False


class BandPlan:
    """The ordering and band layout of one sparsity pattern (an upper triangle in CSC).

    perm : (n,) int, the reverse Cuthill-McKee order (position -> unknown).
    bandwidth : b, the largest |i - j| of a stored entry after the ordering.
    slots : (nnz,) int, where each stored entry of the upper triangle lands in the flat band.
    reaches : (n,) int, how far below the diagonal column j of L may hold an entry: to the
        last row whose first entry is in column j or before (the envelope; at most b).
    """

    def __init__(self, upper: sp.csc_matrix, compiled: bool = True):
        """The plan of ``upper``'s pattern; ``compiled``: the symmetric pattern that the
        ordering sees and the band layout by compiled passes (``_closure``, ``_layout``,
        where the pattern's indices are sorted), else by scipy's sums and numpy's scatters
        (their reference): the same arrays."""
        n = upper.shape[0]
        self.n = n
        if compiled and _layout_compiled is not None and upper.has_sorted_indices:
            indptr = np.asarray(upper.indptr, dtype=np.int64)
            indices = np.asarray(upper.indices, dtype=np.int64)
            closure_indptr, closure_indices = _closure_compiled(indptr, indices, n)
            full = sp.csr_matrix(
                (np.ones(closure_indices.size), closure_indices, closure_indptr), shape=(n, n)
            )
            self.perm = np.asarray(reverse_cuthill_mckee(full, symmetric_mode=True), dtype=np.int64)
            bandwidth, self.slots, self.reaches = _layout_compiled(indptr, indices, self.perm, n)
            self.bandwidth = int(bandwidth)
            return
        # The ordering sees the pattern, stored zeros included (a flat shell's tangent stores
        # its zero membrane-bending couplings, and a sum of the values would drop them).
        ones = sp.csc_matrix((np.ones(upper.nnz), upper.indices, upper.indptr), shape=upper.shape)
        full = (ones + ones.T).tocsr()
        self.perm = np.asarray(reverse_cuthill_mckee(full, symmetric_mode=True), dtype=np.int64)
        position = np.empty(n, dtype=np.int64)
        position[self.perm] = np.arange(n)
        columns = np.repeat(np.arange(n), np.diff(upper.indptr))
        a, b = position[upper.indices], position[columns]
        low, high = np.minimum(a, b), np.maximum(a, b)  # (row, column) of the lower band
        self.bandwidth = int((high - low).max(initial=0))
        self.slots = low * (self.bandwidth + 1) + (high - low)
        # Row i's first entry (every diagonal is stored: at most i), then the last row whose
        # first entry is at or before column j, for each j.
        rows = np.arange(n, dtype=np.int64)
        first = rows.copy()
        np.minimum.at(first, high, low)
        last = np.full(n, -1, dtype=np.int64)
        np.maximum.at(last, first, rows)
        self.reaches = np.maximum(np.maximum.accumulate(last), rows) - rows if n else rows

    def for_pattern(self, upper: sp.csc_matrix) -> BandPlan | None:
        """This plan (its ordering, bandwidth and reaches) for another pattern of as many
        unknowns (an upper triangle in CSC) whose every entry lies within its envelope, or
        None where one falls outside. The elimination runs over the reaches' whole profile
        and the fill of any pattern inside it stays inside it (module docstring), so the
        factors are this pattern's under this ordering; the entries of the profile that this
        pattern leaves empty are zeros that stay zeros (an update of x by 0 w leaves x as it
        is). One pass over the entries (``_slots_within``; numpy's without numba), where a
        new plan orders the whole pattern anew (docs/theory.md §6.5, "Plans kept over
        changing contact pairs")."""
        if upper.shape != (self.n, self.n):
            return None
        position = np.empty(self.n, dtype=np.int64)
        position[self.perm] = np.arange(self.n)
        indptr = np.asarray(upper.indptr, dtype=np.int64)
        indices = np.asarray(upper.indices, dtype=np.int64)
        if _slots_within_compiled is not None:
            slots = _slots_within_compiled(indptr, indices, position, self.reaches, self.bandwidth)
            if slots.size != indices.size:
                return None
        else:  # pragma: no cover - numba is a dependency
            columns = np.repeat(np.arange(self.n), np.diff(indptr))
            a, b = position[indices], position[columns]
            low, high = np.minimum(a, b), np.maximum(a, b)
            if np.any(high - low > self.reaches[low]):
                return None
            slots = low * (self.bandwidth + 1) + (high - low)
        plan = copy.copy(self)
        plan.slots = slots
        return plan

    @property
    def operations(self) -> float:
        """The elimination's multiply-adds, twice over (the sum of the reaches squared), as
        QDLDL's are counted (the sum of its column counts squared): n b^2 for a full band."""
        return float(np.sum(self.reaches.astype(float) ** 2))

    @property
    def fill(self) -> int:
        """Entries of the band: n (b + 1)."""
        return self.n * (self.bandwidth + 1)

    def band_of(self, upper_data: np.ndarray) -> np.ndarray:
        """The band (n, b + 1) of the matrix whose upper triangle has these values (nnz,), in
        the pattern's CSC order: its envelope written by one compiled pass
        (``_fill_envelope``) into an uninitialised array, the rest of the band left as it
        came (the kernels never read it). A whole band zeroed and scattered took 1.95 s where
        this takes 1.08 s over the 1076 band factorisations of the default plies-bai-5.1
        stack solved without its stall rule (its band 1.75 times its envelope;
        benchmarks/band_fill.py). Without numba, the whole band zeroed, then scattered (the
        reference)."""
        upper_data = np.asarray(upper_data)
        if upper_data.shape != self.slots.shape:  # the compiled pass does not check bounds
            raise ValueError(
                f"BandPlan: the upper triangle's values must be one per entry of the plan's "
                f"pattern, shape {self.slots.shape}; got {upper_data.shape}"
            )
        if _fill_envelope_compiled is None:  # pragma: no cover - numba is a dependency
            flat = np.zeros(self.fill)
            flat[self.slots] = upper_data
            return flat.reshape(self.n, self.bandwidth + 1)
        band = np.empty((self.n, self.bandwidth + 1))
        _fill_envelope_compiled(
            band, self.reaches, self.slots, np.ascontiguousarray(upper_data, dtype=float)
        )
        return band

    def factorise(self, upper_data: np.ndarray) -> BandLDLT | None:
        """The LDL^T of the matrix whose upper triangle has these values (in the pattern's
        CSC order), or None at a zero or non-finite pivot."""
        band = self.band_of(upper_data)
        factorise = _factorise if self.bandwidth >= PANEL_FROM else _factorise_by_column
        negative = factorise(band, self.reaches)
        if negative < 0:
            return None
        return BandLDLT(self, band, negative)


class BandLDLT:
    """A factorised K: ``solve(rhs)`` and ``negative`` (its negative eigenvalues)."""

    def __init__(self, plan: BandPlan, band: np.ndarray, negative: int):
        self.plan, self.band, self.negative = plan, band, negative

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """x (n,) with K x = rhs, rhs (n,) or (n, 1)."""
        perm = self.plan.perm
        y = _solve(
            self.band, self.plan.reaches, np.ascontiguousarray(np.ravel(rhs)[perm], dtype=float)
        )
        x = np.empty_like(y)
        x[perm] = y
        return x

    def solve_columns(self, rhs: np.ndarray) -> np.ndarray:
        """X (n, m) with K X = rhs (n, m): ``solve`` on each column, to the bit, in one
        compiled pass (``_solve_columns``) from COLUMNS_TOGETHER columns on, a solve a column
        below."""
        if rhs.shape[1] == 0:
            return np.empty(rhs.shape)
        if rhs.shape[1] < COLUMNS_TOGETHER:
            return np.column_stack([self.solve(rhs[:, j]) for j in range(rhs.shape[1])])
        perm = self.plan.perm
        y = _solve_columns(
            self.band, self.plan.reaches, np.ascontiguousarray(rhs[perm], dtype=float)
        )
        x = np.empty_like(y)
        x[perm] = y
        return x
