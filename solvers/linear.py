"""The linear solve of a Newton iteration: a sparse LDL^T factorisation of K_ff whose symbolic
part (ordering and elimination tree) is kept between iterations, and the inertia of K_ff from
its pivots.

Why LDL^T: the tangent of a conservative model in the generalised coordinates of femcore.dofs
is symmetric (to the finite-difference noise of the tangents that come from differences; a
dead moment with a component along the director is the one non-symmetric load, and it is
handled by the LU fallback). A symmetric factorisation halves the work of an LU, and its
pivots give the inertia of K_ff (Sylvester's law: D has as many negative entries as K_ff has
negative eigenvalues), which tells a stable equilibrium from a saddle whatever the number of
negative modes: the sign of det K only sees an odd number of them.

The factorisation is an LDL^T without pivoting: the compiled band LDL^T of solvers.band (after
a reverse Cuthill-McKee ordering) where the pattern's envelope costs at most
BAND_OVER_SUPERNODAL times the operations of the sparse factor (strips and small corners), else
the compiled supernodal LDL^T of solvers.supernodal on QDLDL's AMD ordering (the fibrous
shell's tangents, whose envelope holds three times the sparse factor: 1.7 times faster than
the band on the 40-cell fibrous corner, 3.5 times than QDLDL), QDLDL (the ``qdldl`` package)
where neither applies or the compiled one meets a zero pivot; the choice is made once per
sparsity pattern, or kept from an earlier one: a pattern inside the kept supernodal factor's
L keeps its whole analysis (``SupernodalPlan.for_pattern``), and another pattern of as many
unknowns keeps the last QDLDL measurement's ordering while its entries and fill stay within
REORDER_GROWTH of the measured ones (``LinearSolver._choose_band``); a band plan is kept for
a new pattern within its envelope, and a pattern outside it is planned on the union of the
patterns met while that stays within BAND_UNION_GROWTH of a plan of one pattern alone
(``LinearSolver._kept_band``, ``_band_plan``: contact pairs that come and go change the
pattern at most Newton iterations of a ply stack; a pattern shrunk below REORDER_SHRINK of the
measured one is not measured anew by default: measured, off). The pattern's analysis
(the orderings, the band layout, the supernodes, QDLDL's elimination tree) is kept while it
holds, and so is the map from K_ff's entries to its symmetrised upper triangle (split off by
one compiled pass). Without pivoting it can fail on an indefinite matrix (a zero pivot) or
lose accuracy; every solution is therefore checked by its backward error and refined with the same
factors (up to REFINEMENTS steps), and a failed or still inaccurate factorisation falls back
to scipy's pivoting LU (SuperLU), as does a non-symmetric K_ff.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
import qdldl
import scipy.sparse as sp
from scipy.sparse.linalg import LinearOperator, MatrixRankWarning, splu

from femcore import kernel_cache
from solvers.band import AVAILABLE as BAND_AVAILABLE
from solvers.band import BandPlan
from solvers.supernodal import AVAILABLE as SUPERNODAL_AVAILABLE
from solvers.supernodal import SupernodalPlan, factor_operations

__all__ = ["Factorisation", "LinearSolver"]

# Relative asymmetry (max |K - K^T| / max |K|) below which K_ff is treated as symmetric: the
# element tangents computed by central differences carry ~1e-9 of noise.
SYMMETRY_TOLERANCE = 1e-7
# Relative asymmetry above which K_ff is no potential's Hessian (Coulomb friction in slip: of
# the order of mu), and its inertia is not reported (Factorisation.negative is None).
NON_CONSERVATIVE = 1e-3
# Backward error accepted from the LDL^T solve before refining it or falling back to LU
# (a stable factorisation gives ~1e-16).
ACCURACY = 1e-12
# Steps of iterative refinement tried before the LU fallback.
REFINEMENTS = 3
# How many times more elimination operations the band LDL^T (solvers.band, within its
# envelope: the sum of its column reaches squared) may take than QDLDL's (the sum of its
# column counts squared) and still be chosen for a pattern: per operation it runs 3.5-4.5
# times faster on the paper cases' corners (benchmarks/band_envelope.py: the 40-cell fibrous
# corner 0.70e9 operations in 53 ms against QDLDL's 0.22e9 in 75 ms; the 40-cell Mindlin one
# 86 million in 8.4 ms against 29 million in 9.9 ms), 4-5 on the Mindlin cantilever of
# benchmarks/static_solver.py. It was 3.0 when the band's operations were counted as n b^2.
# Without the supernodal LDL^T only (``SUPERNODAL_AVAILABLE``): with it, BAND_OVER_SUPERNODAL.
BAND_ADVANTAGE = 3.5
# With the supernodal LDL^T (solvers.supernodal, on QDLDL's ordering and so its operations)
# the band is chosen where its envelope holds at most this many times the supernodal
# factor's operations: per operation the band runs 1.4-2.3 times faster, the most on narrow
# strips (CPU ms, band against supernodal, at the ratio of their operations; the last K_ff
# of each run): bai-5.1's strips, fibrous 60 cells 0.25 against 0.36 at 1.54, Mindlin 60
# cells 0.08 against 0.14 at 0.89, fibrous 30 cells 0.12 against 0.20 at 1.52; the corners,
# Mindlin 10 cells 0.050 against 0.061 at 1.74, fibrous 10 cells 0.18 against 0.23 at 1.78,
# Mindlin 20 cells 0.53 against 0.49 at 2.1, bai-6.2.2's Mindlin 24 cells 1.2 against 0.75
# at 2.3, bai-6.1.2's fibrous 24 cells 6.4 against 3.9 at 2.6, the fibrous 40 cells 40
# against 21 at 3.1 (benchmarks/supernodal.py).
BAND_OVER_SUPERNODAL = 2.0
# A new pattern of as many unknowns as the one whose ordering is kept takes that ordering
# (a contact pair or a bending coupling that appears changes a few entries) unless the
# supernodal factor then holds more than this many times the operations it held on the
# pattern the ordering was made for: then the pattern is ordered afresh.
REORDER_GROWTH = 1.2
# A new pattern of fewer than this share of the entries of the pattern QDLDL last measured is
# measured anew, as one grown past REORDER_GROWTH is; 0: never, the default. The measured
# factor's operations overstate a sparser pattern's (plies-bai-5.1's default stack measured
# pressed, 3.2e7, keeps its band, 6.0e7, as its plies hang apart: 6.6 ms a factorisation
# against a fresh supernodal one's 1.2), but measuring anew did not pay: at 0.75 the bai
# stack 10.04 -> 9.54 s, the heavy cantilever's 1.56 -> 1.62, the deck's 2.49 -> 3.66 (its
# path moved by the round-off), benchmarks/measured_shrink.py.
REORDER_SHRINK = 0.0
# A band plan is kept for a new pattern whose entries all lie within its envelope
# (``BandPlan.for_pattern``); a pattern with an entry outside is planned on the union of the
# patterns the kept plan was made for and its own (contact pairs that come and go then fit
# the next time), unless that plan's envelope holds more than this many times the operations
# of the plan the union started from (a plan of one pattern alone): then on its own pattern.
BAND_UNION_GROWTH = 1.25
# A kept band plan (and its union) serves patterns of at least this share of the union's
# entries; a pattern of fewer (plies that part, whose contact pairs all go) is planned on its
# own: on plies-deck-of-cards' deck, whose plies part in its last increments, a fresh plan
# of the pattern then held down to 1/65 of the union's operations.
BAND_KEPT_SHARE = 0.6
# Every this many patterns served by a kept band plan, a fresh plan of the pattern is made
# and taken (a new union) where the kept one holds more than BAND_UNION_GROWTH times its
# operations: the bound of the kept plans' cost against a new ordering at every pattern, at
# one ordering in this many.
BAND_CHECK_EVERY = 8
# Where QDLDL fails on a new pattern (a zero pivot), the band is tried only if it holds at most
# this many times the entries of K_ff's upper triangle (the cantilever's: 5.5), so that a wide
# band never takes the memory of a dense matrix.
BAND_FILL_WITHOUT_QDLDL = 20
# Whether band plans are kept over new patterns and made on their union (above); False: a
# new plan for every new pattern, the reference.
KEEP_BAND_PLANS = True


@dataclass
class Factorisation:
    """One factorised K_ff.

    negative : the number of negative eigenvalues of the symmetric part of K_ff (from the LDL^T
        pivots), or None when the LDL^T failed (then only the LU is available) or K_ff is far
        from symmetric (NON_CONSERVATIVE: no stability is read from it).
    kind : "ldlt" or "lu", the factorisation that solves.
    neutral : negative pivots within round-off of zero, not in ``negative`` (solvers.neutral_modes).
    """

    matrix: sp.csc_matrix
    negative: int | None
    kind: str
    _ldl: Any = None
    _lu: Any = None
    _norm: float | None = None  # ||K_ff||_inf, made at the first accuracy check
    neutral: int = 0

    def solve(self, rhs: np.ndarray) -> np.ndarray | None:
        """x with K_ff x = rhs (one or more columns), or None when K_ff is singular."""
        if self.kind == "ldlt":
            x = _columns(self._ldl, rhs)
            # Without pivoting the factors of an ill-conditioned K_ff lose digits; a few steps
            # of iterative refinement with the same factors (x += K^-1 (b - K x)) recover them
            # at the cost of a solve each, far below that of an LU.
            for _ in range(REFINEMENTS):
                if _accurate(self.matrix, x, rhs, self.norm):
                    return x
                x = x + _columns(self._ldl, rhs - self.matrix @ x)
            if _accurate(self.matrix, x, rhs, self.norm):
                return x
            self._lu = self._lu or _lu(self.matrix)
            self.kind = "lu"
        if self._lu is None:
            return None
        x = _columns(self._lu, rhs)
        return x if np.all(np.isfinite(x)) else None

    @property
    def norm(self) -> float:
        """||K_ff||_inf (the largest sum of |entries| of a row), computed once: a solve's
        accuracy check needs it, and an arc-length iteration solves twice with one K_ff (it
        took a fifth of a solve on the 40-cell fibrous corner of bai-6.1.1), by one compiled pass
        (``_infinity_norm``)."""
        if self._norm is None:
            self._norm = _infinity_norm(self.matrix)
        return self._norm

    def solve_columns(self, rhs: np.ndarray) -> np.ndarray | None:
        """X (n, m) with K_ff X = rhs (n, m) by the LDL^T's factors alone, without the accuracy
        checks and refinements of ``solve`` (a third of the columns' cost on plies-bai-5.1's
        stack: the products K X), or ``solve`` where only the LU solves. For the columns of
        a predicted contact set (solvers/contact_sets.py), whose errors cost a worse
        prediction, which the Newton iteration's own residual then sees, never a wrong
        equilibrium."""
        if self.kind != "ldlt":
            return self.solve(rhs)
        x = _columns(self._ldl, np.asarray(rhs, dtype=float))
        return x if np.all(np.isfinite(x)) else None

    def inverse(self) -> LinearOperator | None:
        """K^-1 as a LinearOperator from the LDL^T's factors (of K's symmetric part, without
        the accuracy checks of ``solve``: for the shift-invert of solvers.stability), or None
        when only the LU solves."""
        if self.kind != "ldlt":
            return None
        n = self.matrix.shape[0]
        return LinearOperator((n, n), matvec=self._ldl.solve, dtype=float)


class LinearSolver:
    """Factorises successive K_ff of one model, reusing the symbolic LDL^T while the sparsity
    pattern of K_ff stays the same (it does while the assembly pattern does).

    Attributes
    ----------
    symbolic : how many times the symbolic factorisation was computed.
    numeric : how many numeric factorisations followed.
    """

    def __init__(self) -> None:
        self._ldl: qdldl.Solver | None = None
        self._pattern: tuple[np.ndarray, np.ndarray] | None = None
        self._band: BandPlan | None = None
        # the union of the patterns (upper triangles' indptr, indices) the band plans have
        # been made on since the last plan of one pattern alone, and that plan's operations
        self._union: tuple[np.ndarray, np.ndarray] | None = None
        self._union_base = 0.0
        self._kept = 0  # the patterns served by kept band plans
        self._checked: BandPlan | None = None  # a fresh plan made by that check, to be taken
        self._supernodal: SupernodalPlan | None = None
        self._fresh = False  # whether self._ldl holds the factors of the last matrix given
        self._plan: _UpperPlan | None = None
        self._plan_pattern: tuple[np.ndarray, np.ndarray] | None = None
        # (n, QDLDL's elimination operations) of the last pattern QDLDL was measured on
        self._measured: tuple[int, float] | None = None
        # (QDLDL's ordering of the last pattern measured, the supernodal factor's operations
        # under it (L's column counts with the diagonal, squared), that pattern's entries)
        self._ordering: tuple[np.ndarray, float, int] | None = None
        self.symbolic = 0
        self.numeric = 0

    def factorise(self, k_ff: sp.spmatrix) -> Factorisation:
        """The factorisation of a square sparse K_ff."""
        k = k_ff if isinstance(k_ff, sp.csc_matrix) else sp.csc_matrix(k_ff)
        plan = self._plan_for(k)
        scale = float(np.abs(k.data).max(initial=0.0))
        norm = None  # ||K_ff||_inf, made by the split's pass where K_ff has a plan
        if plan is None:
            asymmetry = float(np.abs((k - k.T).data).max(initial=0.0))
            upper = _upper(0.5 * (k + k.T))
        else:
            asymmetry, upper, norm = plan.split_and_norm(k.data)
        ldl, negative = self._ldlt(upper)
        symmetric = scale > 0.0 and asymmetry <= SYMMETRY_TOLERANCE * scale
        if ldl is not None and symmetric:
            return Factorisation(k, negative, "ldlt", _ldl=ldl, _norm=norm)
        if asymmetry > NON_CONSERVATIVE * scale:
            # Friction in slip: the symmetric part of a stable frictional tangent is often
            # indefinite (the slip does not follow a potential), so its pivots say nothing
            # about stability.
            negative = None
        return Factorisation(k, negative, "lu", _lu=_lu(k))

    def _plan_for(self, k: sp.csc_matrix) -> _UpperPlan | None:
        """The upper-triangle plan of K_ff's sparsity pattern (kept while the pattern is the
        same), or None when the pattern is not structurally symmetric with its diagonal."""
        if self._plan_pattern is not None and (
            np.array_equal(self._plan_pattern[0], k.indptr)
            and np.array_equal(self._plan_pattern[1], k.indices)
        ):
            return self._plan
        self._plan_pattern = (k.indptr.copy(), k.indices.copy())
        self._plan = _UpperPlan.of(k)
        return self._plan

    def _ldlt(self, upper: sp.csc_matrix) -> tuple[Any, int | None]:
        """(the LDL^T of the symmetric matrix of this upper triangle, its negative pivots), or
        (None, None) when it failed: the band or the supernodal LDL^T where the pattern chose
        one, else (or where it met a zero pivot) QDLDL."""
        pattern = (upper.indptr, upper.indices)
        if not self._same(pattern):
            kept = self._supernodal.for_pattern(upper) if self._supernodal is not None else None
            band = self._kept_band(upper) if kept is None else None
            self._ldl, self._band, self._supernodal, self._fresh = None, band, kept, False
            self._pattern = (upper.indptr.copy(), upper.indices.copy())
            if kept is None and band is None:
                self.symbolic += 1
                self._band = self._choose_band(upper)
        else:
            self._fresh = False
        self.numeric += 1
        for plan in (self._band, self._supernodal):
            if plan is not None:
                factor = plan.factorise(upper.data)
                if factor is not None:
                    return factor, factor.negative
        return self._qdldl(upper)

    def _kept_band(self, upper: sp.csc_matrix) -> BandPlan | None:
        """The kept band plan for the new pattern ``upper`` where its entries all lie within
        that plan's envelope (``BandPlan.for_pattern``), have not grown past REORDER_GROWTH
        times those of the pattern QDLDL last measured (then it is measured anew,
        ``_choose_band``) and hold at least BAND_KEPT_SHARE of the entries of the union the
        plan was made on, else None. Only a plan that the choice took for the last pattern
        is kept."""
        if self._band is None or not KEEP_BAND_PLANS:
            return None
        if self._ordering is not None and self._moved(upper.nnz, self._ordering[2]):
            return None
        if self._shrunk(upper):
            return None
        kept = self._band.for_pattern(upper)
        if kept is None:
            return None
        self._kept += 1
        if self._kept % BAND_CHECK_EVERY == 0:
            fresh = BandPlan(upper)
            if kept.operations > BAND_UNION_GROWTH * fresh.operations:
                self._union, self._checked = None, fresh  # ``_band_plan`` takes it
                return None
        return kept

    @staticmethod
    def _moved(entries: int, measured: int) -> bool:
        """Whether a pattern of ``entries`` has grown past REORDER_GROWTH or shrunk below
        REORDER_SHRINK times the ``measured`` entries of the pattern QDLDL last measured (its
        measurement then says nothing of this one's supernodal factor)."""
        return entries > REORDER_GROWTH * measured or entries < REORDER_SHRINK * measured

    def _shrunk(self, upper: sp.csc_matrix) -> bool:
        """Whether ``upper`` holds fewer than BAND_KEPT_SHARE of the union's entries."""
        return self._union is None or upper.nnz < BAND_KEPT_SHARE * self._union[1].size

    def _band_plan(self, upper: sp.csc_matrix) -> BandPlan:
        """A band plan of the new pattern ``upper`` (n unknowns): made on the union of the
        patterns of the plans since the last plan of one pattern alone and ``upper``, while
        its envelope holds at most BAND_UNION_GROWTH times that plan's operations and
        ``upper`` holds at least BAND_KEPT_SHARE of the union's entries, else on ``upper``
        alone (which then starts a union)."""
        n = upper.shape[0]
        if (
            KEEP_BAND_PLANS
            and self._union is not None
            and self._union[0].size == n + 1
            and not self._shrunk(upper)
        ):
            union = _union_pattern(self._union, upper, n)
            plan = BandPlan(union)
            if plan.operations <= BAND_UNION_GROWTH * self._union_base:
                fitted = plan.for_pattern(upper)
                assert fitted is not None  # a pattern lies within its union's envelope
                self._union = (union.indptr, union.indices)
                return fitted
        checked, self._checked = self._checked, None
        plan = checked if checked is not None and checked.n == n else BandPlan(upper)
        self._union = (upper.indptr.copy(), upper.indices.copy())
        self._union_base = plan.operations
        return plan

    def _qdldl(self, upper: sp.csc_matrix) -> tuple[qdldl.Solver | None, int | None]:
        try:
            if self._ldl is not None and self._fresh:
                pass  # made from this very matrix when its pattern was chosen
            elif self._ldl is not None:
                self._ldl.update(upper, upper=True)
            else:
                self._ldl = qdldl.Solver(upper, upper=True)
            self._fresh = False
            pivots = np.asarray(self._ldl.factors()[1])
        except RuntimeError:  # a zero pivot: singular, or an unlucky indefinite ordering
            self._ldl = None
            return None, None
        if not np.all(np.isfinite(pivots)):
            return None, None
        return self._ldl, int(np.count_nonzero(pivots < 0.0))

    def _choose_band(self, upper: sp.csc_matrix) -> BandPlan | None:
        """The band plan of a new pattern when its elimination costs at most BAND_ADVANTAGE
        times QDLDL's in operations (the band's contiguous updates run that much faster per
        operation; solvers.band), from QDLDL's own factor of this matrix (kept for the
        fallback): the sum of the band's column reaches squared (its envelope,
        ``BandPlan.operations``) against the sum of QDLDL's column counts squared. With the
        supernodal LDL^T (``SUPERNODAL_AVAILABLE``) the pattern takes it on QDLDL's ordering
        (``self._supernodal``) unless the band holds at most BAND_OVER_SUPERNODAL times its
        operations.

        A new pattern of as many unknowns as the last one QDLDL was measured on (contact
        pairs that change from one iteration to the next change a few entries of a shell's
        tangent, and QDLDL's fill hardly) is not measured again while its entries stay within
        REORDER_GROWTH of the measured pattern's. With the supernodal LDL^T it then takes the
        band where its envelope holds at most BAND_OVER_SUPERNODAL times the measured
        factor's operations, else the supernodal LDL^T on the measured ordering while that
        factor's operations stay within REORDER_GROWTH of the measured ones (a flat sheet's
        tangent, whose zero couplings are left out, is ordered anew once it curves); grown
        entries or fill are measured anew. Without it the band is taken where it holds at
        most BAND_ADVANTAGE times the measured QDLDL operations, else QDLDL is measured anew.
        (A pattern inside the kept supernodal factor's L does not come here: ``_ldlt`` keeps
        that analysis whole, weighing neither its entries nor the band.)"""
        n = upper.shape[0]
        if not BAND_AVAILABLE or n == 0:
            return None
        plan = self._band_plan(upper)
        band_operations = plan.operations
        if self._measured is not None and self._measured[0] == n:
            if SUPERNODAL_AVAILABLE and self._ordering is not None:
                ordering, measured_operations, entries = self._ordering
                grown = self._moved(upper.nnz, entries)
                if not grown and band_operations <= BAND_OVER_SUPERNODAL * measured_operations:
                    self._ldl, self._fresh = None, False  # the band, as on that measurement
                    return plan
                if not grown:
                    supernodal = SupernodalPlan(upper, ordering)
                    if supernodal.operations <= REORDER_GROWTH * measured_operations:
                        self._ldl, self._fresh = None, False
                        return self._band_or_supernodal(plan, supernodal)
            elif band_operations <= BAND_ADVANTAGE * self._measured[1]:
                self._ldl, self._fresh = None, False  # QDLDL's factor made only if the band fails
                return plan
        try:
            self._ldl = qdldl.Solver(upper, upper=True)
            self._fresh = True
            lower, _, ordering = self._ldl.factors()
            counts = np.diff(lower.indptr).astype(float)
        except RuntimeError:  # QDLDL's ordering meets a zero pivot: the band, if it is narrow
            self._ldl, self._fresh = None, False
            return plan if plan.fill <= BAND_FILL_WITHOUT_QDLDL * max(upper.nnz, 1) else None
        self._measured = (n, float(np.sum(counts**2)))
        if SUPERNODAL_AVAILABLE:
            operations = factor_operations(counts)
            ordering = np.asarray(ordering, dtype=np.int64)
            self._ordering = (ordering, operations, upper.nnz)
            if band_operations <= BAND_OVER_SUPERNODAL * operations:
                return plan  # no supernodal analysis where the band is taken anyway
            return self._band_or_supernodal(plan, SupernodalPlan(upper, ordering))
        return plan if band_operations <= BAND_ADVANTAGE * self._measured[1] else None

    def _band_or_supernodal(self, band: BandPlan, supernodal: SupernodalPlan) -> BandPlan | None:
        """The band where it holds at most BAND_OVER_SUPERNODAL times the supernodal
        factor's operations, else None with ``self._supernodal`` set."""
        if band.operations <= BAND_OVER_SUPERNODAL * supernodal.operations:
            return band
        self._supernodal = supernodal
        return None

    def _same(self, pattern: tuple[np.ndarray, np.ndarray]) -> bool:
        return (
            self._pattern is not None
            and np.array_equal(self._pattern[0], pattern[0])
            and np.array_equal(self._pattern[1], pattern[1])
        )


@dataclass
class _UpperPlan:
    """Where the entries of a structurally symmetric CSC pattern with a full diagonal go:
    ``transposed`` (the position of entry (j, i) for each entry (i, j)), ``upper`` (the
    positions of the entries with row <= column, in CSC order of the upper triangle) and that
    triangle's ``indptr``, ``indices``, ``columns`` and ``diagonal`` (which of its entries are).
    With it the asymmetry and the symmetrised upper triangle of each new K_ff on the pattern
    are two gathers, where sparse transposes, sums and sorts cost as much as a tenth of the
    numeric factorisation."""

    transposed: np.ndarray
    upper: np.ndarray
    indptr: np.ndarray
    indices: np.ndarray
    columns: np.ndarray
    diagonal: np.ndarray
    shape: tuple[int, int]
    # K's own pattern (int64), whose rows the split's pass sums for ||K||_inf
    matrix_indptr: np.ndarray
    matrix_indices: np.ndarray

    @classmethod
    def of(cls, k: sp.csc_matrix) -> _UpperPlan | None:
        """The plan of K's pattern (None: indices not sorted, no entries, an entry without its
        mirror or a diagonal entry not stored), by one compiled pass (``_upper_plan``) or,
        without numba, numpy's (``of_numpy``): the same arrays."""
        if _upper_plan_compiled is None:  # pragma: no cover - numba is a dependency
            return cls.of_numpy(k)
        n = k.shape[0]
        if not k.has_sorted_indices or k.nnz == 0:
            return None
        matrix_indptr = np.array(k.indptr, dtype=np.int64)
        matrix_indices = np.array(k.indices, dtype=np.int64)
        found = _upper_plan_compiled(matrix_indptr, matrix_indices, n)
        has_plan, transposed, upper, indptr, kept_rows, kept_columns = found
        if not has_plan:
            return None
        kept_rows = kept_rows.astype(k.indices.dtype)
        diagonal = kept_rows == kept_columns
        return cls(
            transposed, upper, indptr, kept_rows, kept_columns, diagonal, (n, n),
            matrix_indptr, matrix_indices,
        )  # fmt: skip

    @classmethod
    def of_numpy(cls, k: sp.csc_matrix) -> _UpperPlan | None:
        """``of`` by numpy and scipy (the reference of the compiled pass)."""
        n = k.shape[0]
        if not k.has_sorted_indices:
            return None
        columns = np.repeat(np.arange(n), np.diff(k.indptr))
        rows = k.indices
        # K^T in CSC by scipy's counting transpose (linear in the entries, where a search of
        # each mirror among the sorted keys took a quarter of a new pattern's analysis), its
        # entries carrying their places in K: on K's own pattern, the place of each mirror.
        places = sp.csr_matrix(
            (np.arange(k.nnz, dtype=np.int64), rows, k.indptr), shape=(n, n)
        ).tocsc()  # K^T's pattern, entry (j, i) holding the place of (i, j) in K
        if (
            k.nnz == 0
            or not np.array_equal(places.indptr, k.indptr)
            or not np.array_equal(places.indices, rows)
        ):
            return None  # an entry without its mirror
        transposed = places.data
        upper = np.flatnonzero(rows <= columns)
        if np.count_nonzero(rows == columns) != n:
            return None  # QDLDL needs every diagonal entry stored
        indptr = np.concatenate([[0], np.cumsum(np.bincount(columns[upper], minlength=n))])
        kept_rows, kept_columns = rows[upper].copy(), columns[upper]
        diagonal = kept_rows == kept_columns
        return cls(
            transposed, upper, indptr, kept_rows, kept_columns, diagonal, (n, n),
            np.array(k.indptr, dtype=np.int64), np.array(k.indices, dtype=np.int64),
        )  # fmt: skip

    def split(self, data: np.ndarray) -> tuple[float, sp.csc_matrix]:
        """(max |K - K^T|, the upper triangle of (K + K^T) / 2) of K's CSC ``data``, without
        its off-diagonal zeros: the entries that are zero in this K (the bending couplings of
        a flat sheet: the pattern of the fibrous shell's nodal normals reaches two rings of
        cells, its values do only once the sheet curves) are left out of the factorisation,
        which then fills far less (10 times less on a flat 3200-triangle fibrous sheet).
        One compiled pass (``_split_upper``; 5 ms of numpy gathers and masks on the 40-cell
        fibrous corner of benchmarks/paper_cases.py), ``split_numpy`` without numba."""
        return self.split_and_norm(data)[:2]

    def split_and_norm(self, data: np.ndarray) -> tuple[float, sp.csc_matrix, float]:
        """``split`` and ||K||_inf (the largest sum of |entries| of a row; nan if an entry
        is) of K's CSC ``data`` in the same pass (``_split_upper`` sums each column's entries
        into their rows before splitting it, in ``_row_sums_largest``'s order: the same bits
        as ``_infinity_norm``), where a pass of its own read K again for each accuracy check's
        factorisation; ``split_numpy_and_norm`` without numba."""
        if _split_upper_compiled is None:  # pragma: no cover - numba is a dependency
            return self.split_numpy_and_norm(data)
        n = self.shape[0]
        values = np.empty(self.upper.size)
        indices = np.empty(self.upper.size, dtype=self.indices.dtype)
        indptr = np.empty(n + 1, dtype=self.indptr.dtype)
        asymmetry, kept, norm = _split_upper_compiled(
            np.ascontiguousarray(data, dtype=float),
            self.transposed,
            self.upper,
            self.indices,
            self.indptr,
            self.diagonal,
            values,
            indices,
            indptr,
            self.matrix_indptr,
            self.matrix_indices,
        )
        upper = sp.csc_matrix((values[:kept], indices[:kept], indptr), shape=self.shape)
        upper.has_sorted_indices = True
        return float(asymmetry), upper, float(norm)

    def split_numpy(self, data: np.ndarray) -> tuple[float, sp.csc_matrix]:
        """``split`` by numpy's gathers and masks (the reference of the compiled pass)."""
        mirror = data[self.transposed]
        asymmetry = float(np.abs(data - mirror).max(initial=0.0))
        values = 0.5 * (data[self.upper] + mirror[self.upper])
        keep = (values != 0.0) | self.diagonal
        if keep.all():
            indices, indptr = self.indices, self.indptr
        else:
            values, indices = values[keep], self.indices[keep]
            counts = np.bincount(self.columns[keep], minlength=self.shape[0])
            indptr = np.concatenate([[0], np.cumsum(counts)])
        upper = sp.csc_matrix((values, indices, indptr), shape=self.shape)
        upper.has_sorted_indices = True
        return asymmetry, upper

    def split_numpy_and_norm(self, data: np.ndarray) -> tuple[float, sp.csc_matrix, float]:
        """``split_and_norm`` by numpy and scipy (the reference of the compiled pass)."""
        asymmetry, upper = self.split_numpy(data)
        k = sp.csc_matrix((data, self.matrix_indices, self.matrix_indptr), shape=self.shape)
        norm = float(np.abs(k).sum(axis=1).max()) if self.shape[0] else 0.0
        return asymmetry, upper, norm


def _split_upper(
    data: np.ndarray,
    transposed: np.ndarray,
    upper: np.ndarray,
    upper_rows: np.ndarray,
    upper_indptr: np.ndarray,
    diagonal: np.ndarray,
    values: np.ndarray,
    indices: np.ndarray,
    indptr: np.ndarray,
    matrix_indptr: np.ndarray,
    matrix_indices: np.ndarray,
) -> tuple[float, int, float]:
    """``_UpperPlan.split_and_norm`` in one pass over K's columns: (max |K - K^T| (nan if
    any entry is), the count of the kept entries, ||K||_inf), the kept entries' values
    (data[e] + data[mirror]) x 0.5 (numpy's operations, the same bits), rows and column
    pointers written into ``values``, ``indices`` and ``indptr``. An entry below the diagonal
    and its mirror have the same |difference| (a - b = -(b - a) exactly), so the upper
    triangle's entries give the whole matrix's largest. ||K||_inf: each column's entries
    (K's pattern ``matrix_indptr``, ``matrix_indices``) summed into their rows as
    ``_row_sums_largest`` sums them (the same bits), while the column is in the cache.
    Compiled by numba (serial)."""
    n = upper_indptr.size - 1
    sums = np.zeros(n)
    asymmetry = 0.0
    undefined = False
    kept = 0
    indptr[0] = 0
    for column in range(n):
        for e in range(matrix_indptr[column], matrix_indptr[column + 1]):
            sums[matrix_indices[e]] += abs(data[e])
        for u in range(upper_indptr[column], upper_indptr[column + 1]):
            e = upper[u]
            here, mirror = data[e], data[transposed[e]]
            difference = abs(here - mirror)
            if difference > asymmetry:
                asymmetry = difference
            elif difference != difference:
                undefined = True
            value = 0.5 * (here + mirror)
            if value != 0.0 or diagonal[u]:
                values[kept] = value
                indices[kept] = upper_rows[u]
                kept += 1
        indptr[column + 1] = kept
    return (np.nan if undefined else asymmetry), kept, _largest(sums)


def _upper_plan(indptr: np.ndarray, indices: np.ndarray, n: int):
    """``_UpperPlan.of``'s arrays (transposed, upper, the upper triangle's indptr, rows and
    columns) of a CSC pattern with sorted indices and entries, after whether it has a plan
    (False, and empty arrays, where an entry has no mirror or a diagonal entry is not
    stored): K's transpose by the counting pass of scipy's
    ``tocsc`` (each entry's place carried to its mirror's), checked against K's pattern.
    Compiled by numba."""
    nnz = indptr[n]
    empty = np.zeros(0, dtype=np.int64)
    counts = np.zeros(n + 1, dtype=np.int64)
    for e in range(nnz):
        counts[indices[e] + 1] += 1
    for i in range(n):
        counts[i + 1] += counts[i]
        if counts[i + 1] != indptr[i + 1]:
            return False, empty, empty, empty, empty, empty  # an entry without its mirror
    fill = counts[:n].copy()
    transposed = np.empty(nnz, dtype=np.int64)
    diagonals = 0
    above = 0
    for j in range(n):
        for e in range(indptr[j], indptr[j + 1]):
            i = indices[e]
            place = fill[i]
            fill[i] += 1
            if indices[place] != j:
                return False, empty, empty, empty, empty, empty  # an entry without its mirror
            transposed[place] = e
            if i == j:
                diagonals += 1
            if i <= j:
                above += 1
    if diagonals != n:
        return False, empty, empty, empty, empty, empty  # QDLDL needs every diagonal stored
    upper = np.empty(above, dtype=np.int64)
    upper_indptr = np.zeros(n + 1, dtype=np.int64)
    kept_rows = np.empty(above, dtype=np.int64)
    kept_columns = np.empty(above, dtype=np.int64)
    u = 0
    for j in range(n):
        for e in range(indptr[j], indptr[j + 1]):
            if indices[e] <= j:
                upper[u] = e
                kept_rows[u] = indices[e]
                kept_columns[u] = j
                u += 1
        upper_indptr[j + 1] = u
    return True, transposed, upper, upper_indptr, kept_rows, kept_columns


_upper_plan_compiled: Any = None
# numba is a dependency; without it the plan is numpy's (``_UpperPlan.of_numpy``)
if kernel_cache.AVAILABLE:
    _upper_plan_compiled = kernel_cache.njit(_upper_plan)


_split_upper_compiled: Any = None
# numba is a dependency; without it the split is numpy's (``_UpperPlan.split_numpy``)
if kernel_cache.AVAILABLE:
    _split_upper_compiled = kernel_cache.njit(_split_upper)


def _row_sums_largest(indptr: np.ndarray, indices: np.ndarray, data: np.ndarray, n: int) -> float:
    """The largest sum of |entries| of a row of the n x n CSC matrix (indptr, indices,
    data): each row's sum accumulated over the columns in order and each column's entries in
    their stored order, as scipy's product of the matrix with a column of ones adds them (the
    same bits as ``np.abs(k).sum(axis=1).max()``); nan if an entry is. Compiled by numba."""
    sums = np.zeros(n)
    for j in range(n):
        for e in range(indptr[j], indptr[j + 1]):
            sums[indices[e]] += abs(data[e])
    return _largest(sums)


def _largest(sums: np.ndarray) -> float:
    """The largest of ``sums`` (n,) (0 for none), nan if one is. Compiled by numba."""
    largest = sums[0] if sums.size else 0.0
    for i in range(1, sums.size):
        value = sums[i]
        if value > largest or value != value:
            largest = value
            if value != value:
                break
    return largest


_row_sums_largest_compiled: Any = None
if kernel_cache.AVAILABLE:
    _largest = kernel_cache.njit(_largest)  # the compiled passes' helper, called by them
    _row_sums_largest_compiled = kernel_cache.njit(_row_sums_largest)


def _infinity_norm(k: sp.csc_matrix) -> float:
    """||K||_inf (the largest sum of |entries| of a row; 0 for an empty K): one compiled pass
    over K's CSC arrays (``_row_sums_largest``), where scipy's ``np.abs(k).sum(axis=1).max()``
    (its reference) built two matrices and took 0.6 ms a factorisation on the coarse
    plies-bai-5.1 stack (684 unknowns), more than its band factorisation (benchmarks/
    band_fill.py)."""
    n = k.shape[0]
    if n == 0:
        return 0.0
    if _row_sums_largest_compiled is None or not isinstance(k, sp.csc_matrix):
        return float(np.abs(k).sum(axis=1).max())
    return float(
        _row_sums_largest_compiled(
            k.indptr, k.indices, np.ascontiguousarray(k.data, dtype=float), n
        )
    )


def _upper(k: sp.spmatrix) -> sp.csc_matrix:
    """The upper triangle in CSC with every diagonal entry stored (QDLDL needs the diagonal in
    the pattern, also where it is zero)."""
    n = k.shape[0]
    coo = sp.triu(k, format="coo")
    diagonal = np.arange(n)
    upper = sp.csc_matrix(
        (
            np.concatenate([coo.data, np.zeros(n)]),
            (np.concatenate([coo.row, diagonal]), np.concatenate([coo.col, diagonal])),
        ),
        shape=(n, n),
    )
    upper.sum_duplicates()
    upper.sort_indices()
    return upper


def _union_pattern(
    pattern: tuple[np.ndarray, np.ndarray], upper: sp.csc_matrix, n: int
) -> sp.csc_matrix:
    """The pattern (values 1) of the entries of an upper triangle's pattern (indptr,
    indices) and of ``upper``'s, n x n, in CSC with sorted indices."""
    indptr, indices = pattern
    union = sp.csc_matrix((np.ones(indices.size), indices, indptr), shape=(n, n)) + sp.csc_matrix(
        (np.ones(upper.indices.size), upper.indices, upper.indptr), shape=(n, n)
    )
    union = sp.csc_matrix(union)
    union.sort_indices()
    return union


def _lu(k: sp.csc_matrix):
    """SuperLU of K, or None when it is exactly singular."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", MatrixRankWarning)
        try:
            return splu(k)
        except (RuntimeError, MatrixRankWarning):
            return None


def _columns(factors: Any, rhs: np.ndarray) -> np.ndarray:
    """``factors.solve`` of rhs (n,), or of each column of rhs (n, m): in one pass where the
    factors solve many columns at once (``solve_columns``, the band's: the same bits as
    column by column), else a solve a column."""
    if rhs.ndim == 1:
        return np.asarray(factors.solve(rhs))
    if rhs.shape[1] == 0:  # (np.column_stack refuses an empty list)
        return np.empty(rhs.shape)
    if hasattr(factors, "solve_columns"):
        return factors.solve_columns(rhs)
    return np.column_stack([factors.solve(np.ascontiguousarray(column)) for column in rhs.T])


def _accurate(k: sp.csc_matrix, x: np.ndarray, rhs: np.ndarray, norm_k: float) -> bool:
    """Whether x solves K x = rhs to a backward error ||K x - b|| / (||K|| ||x|| + ||b||)
    (infinity norms, ``norm_k`` = ||K||) of at most ACCURACY: what a stable factorisation
    achieves whatever the conditioning of K (the relative residual of an ill-conditioned K_ff
    is 1e-7 with any solver), and what an LDL^T without pivoting loses when its pivots grow."""
    if not np.all(np.isfinite(x)):
        return False
    scale = norm_k * float(np.abs(x).max(initial=0.0)) + float(np.abs(rhs).max(initial=0.0))
    return scale == 0.0 or float(np.abs(k @ x - rhs).max(initial=0.0)) <= ACCURACY * scale
