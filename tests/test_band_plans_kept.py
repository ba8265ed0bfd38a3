"""Band plans kept over changing patterns (solvers/band.py ``BandPlan.for_pattern``,
solvers/linear.py ``LinearSolver`` with ``KEEP_BAND_PLANS``, ``BAND_UNION_GROWTH``).

References: the solution and the negative eigenvalues of each matrix computed densely by
numpy (``np.linalg.solve``, ``eigvalsh``; Sylvester's law of inertia for the pivots), and the
plan made afresh on the pattern (the ordering of a new plan at every pattern). Tolerances:
the backward error 1e-12 that solvers.linear accepts, 1e-9 relative on the solutions of
these matrices (condition numbers 2-2.4 unshifted, 1.6e3 shifted: round-off errors near
1e-13)."""

import numpy as np
import pytest
import scipy.sparse as sp

from solvers import linear
from solvers.band import BandPlan
from solvers.linear import LinearSolver


def strip(length=40, width=3, shift=0.0, seed=0, extra=(), drop=0.0):
    """A symmetric matrix on the node graph of a length x width grid of 5-unknown nodes (a
    shell strip's tangent pattern), its diagonal shifted by -shift, with 5 x 5 couplings
    between the node pairs ``extra`` (contact pairs) and a share ``drop`` of the grid's
    couplings left out."""
    rng = np.random.default_rng(seed)
    nodes = np.arange(length * width).reshape(length, width)
    pairs = [(nodes[:-1, :], nodes[1:, :]), (nodes[:, :-1], nodes[:, 1:])]
    pairs.append((nodes[:-1, :-1], nodes[1:, 1:]))
    couples = [(int(i), int(j)) for a, b in pairs for i, j in zip(a.ravel(), b.ravel())]
    kept = rng.random(len(couples)) >= drop
    couples = [c for c, k in zip(couples, kept) if k] + list(extra)
    a = sp.lil_matrix((5 * nodes.size, 5 * nodes.size))
    for i, j in couples:
        block = rng.uniform(-0.2, 0.2, (5, 5))
        a[5 * i : 5 * i + 5, 5 * j : 5 * j + 5] = block
        a[5 * j : 5 * j + 5, 5 * i : 5 * i + 5] = block.T
    diagonal = rng.uniform(3.0, 5.0, 5 * nodes.size) - shift
    return (a.tocsc() + sp.diags(diagonal)).tocsc()


def upper_of(k):
    upper = sp.triu(k, format="csc")
    upper.sort_indices()
    return upper


@pytest.mark.parametrize("shift", [0.0, 3.9])
def test_a_plan_kept_for_a_pattern_inside_its_own_solves_as_a_fresh_plan(shift):
    """A plan made on the whole strip, kept for the strip with a third of its couplings
    left out: the same solution as a fresh plan of that pattern and as numpy's, and the same
    negative pivots as the matrix's negative eigenvalues (shift 3.9: some)."""
    whole = upper_of(strip(shift=shift))
    k = strip(shift=shift, drop=0.3, seed=1)
    upper = upper_of(k)
    kept = BandPlan(whole).for_pattern(upper)
    assert kept is not None and kept.slots.size == upper.nnz
    fresh = BandPlan(upper)
    assert fresh.operations < kept.operations  # the kept envelope is the larger
    rhs = np.linspace(-1.0, 2.0, k.shape[0])
    expected = np.linalg.solve(k.toarray(), rhs)
    negative = int(np.sum(np.linalg.eigvalsh(k.toarray()) < 0.0))
    for plan in (kept, fresh):
        factor = plan.factorise(upper.data)
        assert factor is not None and factor.negative == negative
        x = factor.solve(rhs)
        assert np.max(np.abs(x - expected)) <= 1e-9 * np.max(np.abs(expected))
    assert (negative > 0) == (shift > 0.0)


def test_a_pattern_with_an_entry_outside_the_envelope_has_no_kept_plan():
    """A coupling between the strip's two ends lies far outside the strip's band."""
    plan = BandPlan(upper_of(strip()))
    far = upper_of(strip(extra=[(0, 119)]))
    assert plan.for_pattern(far) is None
    assert plan.for_pattern(upper_of(strip(length=20))) is None  # another size


def test_the_solver_keeps_its_plan_replans_outside_it_and_grows_it_to_the_union():
    """The solver on the strip, then on the strip with a few couplings gone (kept: no new
    ordering), then with a contact pair a few nodes apart outside the envelope (a new plan on
    the union), then on the first pattern again (inside the union's: kept); every solution
    numpy's."""
    solver = LinearSolver()
    patterns = [
        strip(),
        strip(drop=0.2, seed=2),
        strip(extra=[(3, 20), (10, 27)], seed=3),
        strip(seed=4),
    ]
    rhs = np.linspace(-1.0, 1.0, patterns[0].shape[0])
    symbolic = []
    for k in patterns:
        x = solver.factorise(k).solve(rhs)
        expected = np.linalg.solve(k.toarray(), rhs)
        assert np.max(np.abs(x - expected)) <= 1e-9 * np.max(np.abs(expected))
        assert solver._band is not None
        symbolic.append(solver.symbolic)
    assert symbolic == [1, 1, 2, 2]
    union = upper_of(patterns[0] + patterns[2])  # the pattern the third plan was made on
    assert np.array_equal(solver._band.perm, BandPlan(union).perm)


def test_the_union_plan_is_taken_only_within_its_operations_bound(monkeypatch):
    """With BAND_UNION_GROWTH 0 a pattern outside the kept envelope is planned on its own
    (a fresh plan's ordering); with a bound that the union's operations pass, on the union;
    the plan taken holds at most the bound times the operations of the plan the union
    started from."""
    first, second = strip(), strip(extra=[(3, 20), (10, 27)], seed=3)
    for growth in (0.0, 1.25, 1e9):
        monkeypatch.setattr(linear, "BAND_UNION_GROWTH", growth)
        solver = LinearSolver()
        solver.factorise(first)
        base = solver._band.operations
        solver.factorise(second)
        own = BandPlan(upper_of(second))
        union = BandPlan(upper_of(first + second))
        taken = solver._band
        if growth == 0.0 or union.operations > growth * base:
            assert np.array_equal(taken.perm, own.perm)
        else:
            assert np.array_equal(taken.perm, union.perm)
            assert taken.operations <= growth * base
    assert union.operations <= 1e9 * base  # the last bound took the union


def test_without_kept_plans_every_new_pattern_is_ordered_anew(monkeypatch):
    monkeypatch.setattr(linear, "KEEP_BAND_PLANS", False)
    solver = LinearSolver()
    for k in (strip(), strip(drop=0.2, seed=2)):
        solver.factorise(k)
    assert solver.symbolic == 2


def test_a_pattern_of_few_of_the_unions_entries_is_planned_on_its_own():
    """The strip, then the strip with most couplings gone (fewer than BAND_KEPT_SHARE of the
    union's entries: plies that part): planned afresh on its own pattern, though it lies
    within the kept envelope."""
    solver = LinearSolver()
    solver.factorise(strip())
    sparse = strip(drop=0.8, seed=5)
    upper = upper_of(sparse)
    assert upper.nnz < linear.BAND_KEPT_SHARE * upper_of(strip()).nnz
    assert solver._band.for_pattern(upper) is not None
    solver.factorise(sparse)
    assert solver.symbolic == 2
    assert np.array_equal(solver._band.perm, BandPlan(upper).perm)


def test_every_few_kept_patterns_a_fresh_plan_bounds_the_kept_ones_operations(monkeypatch):
    """A plan made on a strip with couplings three rows apart, kept for the plain strip's patterns
    (within its envelope, of enough of its entries), which a fresh plan orders in far fewer
    operations: at the BAND_CHECK_EVERY-th kept pattern the fresh plan is taken."""
    monkeypatch.setattr(linear, "BAND_KEPT_SHARE", 0.0)
    solver = LinearSolver()
    solver.factorise(strip(extra=[(30, 39), (60, 69), (90, 99)]))
    wide = solver._band.operations
    symbolic = []
    for seed in range(linear.BAND_CHECK_EVERY):
        k = strip(drop=0.05, seed=10 + seed)
        solver.factorise(k)
        symbolic.append(solver.symbolic)
    assert symbolic == [1] * (linear.BAND_CHECK_EVERY - 1) + [2]
    fresh = BandPlan(upper_of(k))
    assert wide > linear.BAND_UNION_GROWTH * fresh.operations
    assert np.array_equal(solver._band.perm, fresh.perm)


def test_the_union_grows_over_patterns_that_are_not_nested():
    """The strip, then the strip with a contact pair (3, 9) and 5 % of its couplings gone,
    then with another pair (40, 46) and another 5 % gone: neither pattern lies within
    another, each falls outside the kept envelope, and each union differs from the new
    pattern. Each plan is the union's of every pattern since the first (its reaches and
    ordering a fresh BandPlan's of that union; the union stored is that union), within
    BAND_UNION_GROWTH of the first plan's operations; the solutions numpy's."""
    patterns = [
        strip(),
        strip(extra=[(3, 9)], drop=0.05, seed=11),
        strip(extra=[(40, 46)], drop=0.05, seed=12),
    ]
    solver = LinearSolver()
    rhs = np.linspace(-1.0, 1.0, patterns[0].shape[0])
    union = None
    for step, k in enumerate(patterns):
        x = solver.factorise(k).solve(rhs)
        expected = np.linalg.solve(k.toarray(), rhs)
        assert np.max(np.abs(x - expected)) <= 1e-9 * np.max(np.abs(expected))
        assert solver.symbolic == step + 1  # each outside the last envelope
        union = k if union is None else union + k
        if step == 0:
            base = solver._band.operations
            continue
        own, of_union = BandPlan(upper_of(k)), BandPlan(upper_of(union))
        assert not np.array_equal(own.reaches, of_union.reaches)  # the union is not k's
        assert np.array_equal(solver._band.perm, of_union.perm)
        assert np.array_equal(solver._band.reaches, of_union.reaches)
        assert solver._band.operations <= linear.BAND_UNION_GROWTH * base
        stored = upper_of(union)
        assert np.array_equal(solver._union[0], stored.indptr)
        assert np.array_equal(solver._union[1], stored.indices)
    # the first union (without (40, 46)) and the union of the first and last alone are not
    # the last plan's: the stored union grew
    assert not np.array_equal(
        BandPlan(upper_of(patterns[0] + patterns[2])).reaches, solver._band.reaches
    )


def test_a_union_past_the_growth_bound_is_refused_for_the_patterns_own_plan():
    """The strip, then the strip with a pair (20, 26) and 5 % of its couplings gone (not
    nested): the union's plan holds 1.37 times the first plan's operations, past
    BAND_UNION_GROWTH (1.25), so the new pattern is planned on its own, whose plan differs
    from the union's; the union restarts from it."""
    first, second = strip(), strip(extra=[(20, 26)], drop=0.05, seed=11)
    solver = LinearSolver()
    solver.factorise(first)
    base = solver._band.operations
    of_union = BandPlan(upper_of(first + second))
    assert of_union.operations > linear.BAND_UNION_GROWTH * base
    x = solver.factorise(second).solve(np.ones(second.shape[0]))
    expected = np.linalg.solve(second.toarray(), np.ones(second.shape[0]))
    assert np.max(np.abs(x - expected)) <= 1e-9 * np.max(np.abs(expected))
    own = BandPlan(upper_of(second))
    assert not np.array_equal(own.reaches, of_union.reaches)
    assert np.array_equal(solver._band.perm, own.perm)
    assert np.array_equal(solver._band.reaches, own.reaches)
    assert np.array_equal(solver._union[1], upper_of(second).indices)


def test_a_kept_pattern_grown_past_the_measured_entries_is_measured_anew(monkeypatch):
    """The strip, then the strip with 20 % of its couplings gone (within the kept envelope:
    kept by default, the first test above); with REORDER_GROWTH 0.5 its entries pass that
    share of the pattern QDLDL measured, so it is not kept but measured anew (a new
    symbolic analysis; the measured entries are its own)."""
    if not linear.SUPERNODAL_AVAILABLE:
        pytest.skip("the measured ordering is kept with the supernodal LDL^T only")
    monkeypatch.setattr(linear, "REORDER_GROWTH", 0.5)
    first, second = strip(), strip(drop=0.2, seed=2)
    solver = LinearSolver()
    solver.factorise(first)
    upper = upper_of(second)
    assert solver._band.for_pattern(upper) is not None
    assert upper.nnz > 0.5 * upper_of(first).nnz
    solver.factorise(second)
    assert solver.symbolic == 2
    assert solver._ordering[2] == upper.nnz


def test_a_plan_kept_for_another_pattern_leaves_the_original_plans_slots():
    """BandPlan.for_pattern returns a copy: the plan it was taken from keeps its own slots
    and factorises its own matrix as before (the same bits)."""
    k = strip()
    whole = upper_of(k)
    plan = BandPlan(whole)
    slots = plan.slots.copy()
    before = plan.factorise(whole.data).solve(np.ones(k.shape[0]))
    kept = plan.for_pattern(upper_of(strip(drop=0.3, seed=1)))
    assert kept is not None and kept.slots.size != slots.size
    assert np.array_equal(plan.slots, slots)
    assert np.array_equal(plan.factorise(whole.data).solve(np.ones(k.shape[0])), before)


def test_a_pattern_shrunk_below_the_measured_entries_gets_a_fresh_solvers_choice(monkeypatch):
    """With REORDER_SHRINK 0.75 (off by default: solvers/linear.py says why), a 30 x 6
    strip, whose band QDLDL's measurement takes, then the strip with 30 % of its couplings
    gone (0.70 of the entries: within the kept envelope and above BAND_KEPT_SHARE of the
    union, below REORDER_SHRINK of the measured pattern): measured anew, it gets the choice a
    solver that never met the whole strip makes for it, the supernodal LDL^T (the band kept
    on the whole strip's measurement held 2.5 times its operations), and solves as numpy
    does. By default (and before the bound) the band is kept."""
    if not linear.SUPERNODAL_AVAILABLE:
        pytest.skip("the measured ordering is kept with the supernodal LDL^T only")
    default = LinearSolver()
    default.factorise(strip(length=30, width=6))
    default.factorise(strip(length=30, width=6, drop=0.3, seed=2))
    assert default.symbolic == 1 and default._band is not None
    monkeypatch.setattr(linear, "REORDER_SHRINK", 0.75)
    first = strip(length=30, width=6)
    second = strip(length=30, width=6, drop=0.3, seed=2)
    solver = LinearSolver()
    solver.factorise(first)
    assert solver._band is not None
    upper = upper_of(second)
    assert solver._band.for_pattern(upper) is not None
    entries = upper_of(first).nnz
    assert linear.BAND_KEPT_SHARE * entries < upper.nnz < linear.REORDER_SHRINK * entries
    fresh = LinearSolver()
    fresh.factorise(second)
    assert fresh._band is None and fresh._supernodal is not None
    factor = solver.factorise(second)
    assert solver.symbolic == 2 and solver._ordering[2] == upper.nnz
    assert solver._band is None and solver._supernodal is not None
    assert solver._supernodal.operations == fresh._supernodal.operations
    rhs = np.linspace(-1.0, 2.0, second.shape[0])
    expected = np.linalg.solve(second.toarray(), rhs)
    x = factor.solve(rhs)
    assert np.max(np.abs(x - expected)) <= 1e-9 * np.max(np.abs(expected))


def test_the_measured_entries_bound_both_ways(monkeypatch):
    """A pattern is measured anew past REORDER_GROWTH times the measured entries or below
    REORDER_SHRINK times them (0.75 here; by default 0: never), and not between."""
    measured = 1000
    assert not LinearSolver._moved(1, measured)
    monkeypatch.setattr(linear, "REORDER_SHRINK", 0.75)
    assert LinearSolver._moved(int(linear.REORDER_GROWTH * measured) + 1, measured)
    assert LinearSolver._moved(int(linear.REORDER_SHRINK * measured) - 1, measured)
    assert not LinearSolver._moved(measured, measured)
    assert not LinearSolver._moved(int(linear.REORDER_SHRINK * measured) + 1, measured)
