"""solvers.linear: the LDL^T of K_ff, its kept symbolic factorisation and the inertia from its
pivots.

Reference: Sylvester's law of inertia (a congruence L D L^T keeps the numbers of negative,
zero and positive eigenvalues) and the eigenvalues computed densely by numpy."""

import numpy as np
import pytest
import scipy.sparse as sp
from qdldl_count import counting_qdldl

from solvers.linear import LinearSolver


def symmetric(n=300, shift=0.0, seed=0, density=0.02):
    rng = np.random.default_rng(seed)
    a = sp.random(n, n, density=density, random_state=seed)
    return (a + a.T + sp.diags(rng.uniform(1.0, 5.0, n) - shift)).tocsc()


@pytest.mark.parametrize("shift", [0.0, 1.5, 3.0, 4.5])
def test_the_negative_pivots_count_the_negative_eigenvalues(shift):
    # Shifting the diagonal moves eigenvalues below zero in numbers that are odd or even;
    # det K only sees the parity, the pivots see the count.
    k = symmetric(shift=shift)
    expected = int(np.sum(np.linalg.eigvalsh(k.toarray()) < 0.0))
    factor = LinearSolver().factorise(k)
    assert factor.negative == expected
    rhs = np.arange(k.shape[0], dtype=float)
    x = factor.solve(rhs)
    assert np.linalg.norm(k @ x - rhs) <= 1e-8 * np.linalg.norm(rhs)


def test_the_symbolic_factorisation_is_kept_while_the_pattern_is():
    solver = LinearSolver()
    k = symmetric()
    for scale in (1.0, 2.0, 3.0):
        solver.factorise(k * scale)
    assert (solver.symbolic, solver.numeric) == (1, 3)
    solver.factorise(symmetric(seed=1))  # another pattern
    assert solver.symbolic == 2


def test_a_non_symmetric_matrix_is_solved_exactly_by_lu():
    k = symmetric().tolil()
    k[0, 1] += 0.5  # a non-symmetric entry far above the noise
    k = k.tocsc()
    factor = LinearSolver().factorise(k)
    assert factor.kind == "lu"
    rhs = np.ones(k.shape[0])
    assert np.linalg.norm(k @ factor.solve(rhs) - rhs) <= 1e-10 * np.linalg.norm(rhs)


def test_a_singular_matrix_gives_no_solution():
    k = sp.csc_matrix(np.array([[1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [0.0, 0.0, 2.0]]))
    assert LinearSolver().factorise(k).solve(np.ones(3)) is None


def test_the_kept_pattern_plan_gives_the_scipy_asymmetry_and_upper_triangle():
    # The plan of a structurally symmetric pattern replaces sparse transposes and sorts by two
    # gathers; it must give what they give, to the bit, on a matrix with a non-symmetric part.
    from solvers.linear import _upper, _UpperPlan

    k = symmetric()
    skew = sp.triu(k, k=1) * 1e-3
    k = (k + skew - skew.T).tocsc()
    k.sort_indices()
    plan = _UpperPlan.of(k)
    assert plan is not None
    asymmetry, upper = plan.split(k.data)
    assert asymmetry == np.abs((k - k.T).data).max()
    reference = _upper(0.5 * (k + k.T))
    assert np.array_equal(upper.indptr, reference.indptr)
    assert np.array_equal(upper.indices, reference.indices)
    assert np.array_equal(upper.data, reference.data)


def test_a_pattern_without_its_mirror_or_its_diagonal_gets_no_plan():
    from solvers.linear import _UpperPlan

    lower_only = sp.csc_matrix(np.tril(np.ones((4, 4))))
    assert _UpperPlan.of(lower_only) is None
    no_diagonal = sp.csc_matrix(np.ones((4, 4)) - np.eye(4))
    assert _UpperPlan.of(no_diagonal) is None
    # As many entries in each column and row as its transpose, but (1, 0), (2, 1), (0, 2)
    # mirrored nowhere.
    cyclic = sp.csc_matrix(np.eye(3) + np.eye(3, k=-1) + np.eye(3, k=2))
    assert _UpperPlan.of(cyclic) is None


def test_the_plan_maps_each_entry_to_its_mirror():
    """``_UpperPlan.transposed`` (K^T by scipy's counting transpose) against the mirrors found
    one by one in a dictionary of K's entries, on a scattered symmetric pattern."""
    from solvers.linear import _UpperPlan

    rng = np.random.default_rng(4)
    a = sp.random(60, 60, density=0.08, random_state=5, format="csc")
    k = (a + a.T + sp.identity(60)).tocsc()
    k.sort_indices()
    k.data = rng.normal(size=k.nnz)
    plan = _UpperPlan.of(k)
    assert plan is not None
    columns = np.repeat(np.arange(60), np.diff(k.indptr))
    place = {(int(i), int(j)): e for e, (i, j) in enumerate(zip(k.indices, columns))}
    expected = [place[(int(j), int(i))] for i, j in zip(k.indices, columns)]
    assert np.array_equal(plan.transposed, expected)


def test_a_non_symmetric_pattern_is_still_factorised_and_solved():
    k = symmetric().tolil()
    k[0, 5] = 0.3  # no (5, 0) entry: the pattern is not symmetric
    k = k.tocsc()
    rhs = np.ones(k.shape[0])
    x = LinearSolver().factorise(k).solve(rhs)
    assert np.linalg.norm(k @ x - rhs) <= 1e-8 * np.linalg.norm(rhs)


def strip_matrix(length=60, width=4, shift=0.0, seed=0):
    """A symmetric matrix on the node graph of a length x width grid of 5-unknown nodes (the
    pattern of a shell strip's tangent), shifted by -shift on the diagonal."""
    rng = np.random.default_rng(seed)
    nodes = np.arange(length * width).reshape(length, width)
    pairs = [(nodes[:-1, :], nodes[1:, :]), (nodes[:, :-1], nodes[:, 1:])]
    pairs.append((nodes[:-1, :-1], nodes[1:, 1:]))
    a = sp.lil_matrix((5 * nodes.size, 5 * nodes.size))
    for first, second in pairs:
        for i, j in zip(first.ravel(), second.ravel()):
            block = rng.uniform(-0.2, 0.2, (5, 5))
            a[5 * i : 5 * i + 5, 5 * j : 5 * j + 5] = block
            a[5 * j : 5 * j + 5, 5 * i : 5 * i + 5] = block.T
    diagonal = rng.uniform(2.0, 4.0, 5 * nodes.size) - shift
    return (a.tocsc() + sp.diags(diagonal)).tocsc()


@pytest.mark.parametrize("shift", [0.0, 2.5, 3.5])
def test_the_band_ldlt_counts_the_negative_eigenvalues_and_solves(shift):
    from solvers.band import BandPlan

    k = strip_matrix(shift=shift)
    upper = sp.triu(k, format="csc")
    upper.sort_indices()
    factor = BandPlan(upper).factorise(upper.data)
    assert factor is not None
    assert factor.negative == int(np.sum(np.linalg.eigvalsh(k.toarray()) < 0.0))
    rhs = np.random.default_rng(1).standard_normal(k.shape[0])
    x = factor.solve(rhs)
    assert np.allclose(x, np.linalg.solve(k.toarray(), rhs), rtol=1e-9, atol=1e-9)


def test_a_strip_pattern_takes_the_band_and_a_scattered_one_qdldl():
    # The band of a strip is a few nodes wide; a sparse random pattern's envelope holds 47
    # times QDLDL's operations (at 2 % of the entries, nearly dense, the two come within 3.5
    # and the band is as good a choice).
    on_strip, scattered = LinearSolver(), LinearSolver()
    on_strip.factorise(strip_matrix())
    scattered.factorise(symmetric(density=0.005))
    assert on_strip._band is not None
    assert scattered._band is None


def qdldl_factorisation(k):
    """``LinearSolver().factorise(k)`` with neither the band nor the supernodal LDL^T: QDLDL's
    factors."""
    from solvers import linear

    advantage, supernodal = linear.BAND_ADVANTAGE, linear.SUPERNODAL_AVAILABLE
    try:
        linear.BAND_ADVANTAGE, linear.SUPERNODAL_AVAILABLE = 0.0, False
        return LinearSolver().factorise(k)
    finally:
        linear.BAND_ADVANTAGE, linear.SUPERNODAL_AVAILABLE = advantage, supernodal


def test_the_band_and_qdldl_give_the_same_solution_and_inertia():

    k = strip_matrix(shift=2.5)
    rhs = np.arange(k.shape[0], dtype=float)
    band = LinearSolver().factorise(k)
    general = qdldl_factorisation(k)
    assert band.negative == general.negative > 0
    x, y = band.solve(rhs), general.solve(rhs)
    assert np.abs(x - y).max() <= 1e-9 * np.abs(y).max()


def corner_matrix(cells=20, dof=5, seed=0):
    """A symmetric, diagonally dominant matrix on the grid of a corner specimen's free
    triangle (the nodes (i, j) with i + j <= cells), each node joined to its eight
    neighbours, ``dof`` unknowns a node."""
    rng = np.random.default_rng(seed)
    index: dict[tuple[int, int], int] = {}
    for i in range(cells + 1):
        for j in range(cells + 1 - i):
            index[(i, j)] = len(index)
    a = sp.lil_matrix((dof * len(index), dof * len(index)))
    for (i, j), k in index.items():
        for di in (-1, 0, 1):
            for dj in (-1, 0, 1):
                other = index.get((i + di, j + dj))
                if other is not None and other > k:
                    block = rng.uniform(-0.1, 0.1, (dof, dof))
                    a[dof * k : dof * k + dof, dof * other : dof * other + dof] = block
                    a[dof * other : dof * other + dof, dof * k : dof * k + dof] = block.T
    return (a.tocsc() + sp.diags(np.asarray(abs(a).sum(axis=1)).ravel() + 1.0)).tocsc()


def test_a_corner_whose_envelope_fits_takes_the_band_and_gives_qdldls_solution(monkeypatch):
    # On the corner's triangle the ordered band holds 3.75 times QDLDL's operations counted
    # as n b^2 (QDLDL's choice before the envelope was counted), its envelope 1.9 times:
    # the band's choice against QDLDL, without the supernodal LDL^T.
    import qdldl

    from solvers import linear
    from solvers.band import BandPlan

    k = corner_matrix()
    upper = sp.triu(k, format="csc")
    upper.sort_indices()
    plan = BandPlan(upper)
    n = k.shape[0]
    counts = np.diff(qdldl.Solver(upper, upper=True).factors()[0].indptr).astype(float)
    qdldl_operations = float(np.sum(counts**2))
    assert n * plan.bandwidth**2 > linear.BAND_ADVANTAGE * qdldl_operations  # the whole band
    assert plan.operations < 2.0 * qdldl_operations  # the envelope
    monkeypatch.setattr(linear, "SUPERNODAL_AVAILABLE", False)
    solver = LinearSolver()
    band = solver.factorise(k)
    assert solver._band is not None
    general = qdldl_factorisation(k)
    rhs = np.linspace(-1.0, 1.0, n)
    x, y = band.solve(rhs), general.solve(rhs)
    assert band.negative == general.negative == 0
    assert np.abs(x - y).max() <= 1e-12 * np.abs(y).max()


def test_a_zero_pivot_of_the_band_falls_back_and_still_solves():
    # Zero diagonal everywhere: the band's first pivot is zero, QDLDL or the LU take over.
    k = strip_matrix()
    k = (k - sp.diags(k.diagonal())).tocsc()
    k = (k + sp.diags(np.zeros(k.shape[0]))).tocsc()
    rhs = np.ones(k.shape[0])
    x = LinearSolver().factorise(k).solve(rhs)
    assert x is not None
    assert np.linalg.norm(k @ x - rhs) <= 1e-8 * np.linalg.norm(rhs)


def test_the_shift_invert_with_the_kept_factors_finds_the_same_lowest_modes():
    from solvers.stability import lowest_modes

    k = strip_matrix(shift=2.1)
    factor = LinearSolver().factorise(k)
    assert factor.kind == "ldlt" and factor.negative
    values, vectors = lowest_modes(k, factor.negative, factor.inverse())
    expected, _ = lowest_modes(k, factor.negative)
    assert np.allclose(values, expected, rtol=1e-8, atol=1e-10)
    assert np.allclose(np.abs(vectors.T @ (k @ vectors)), np.diag(np.abs(values)), atol=1e-8)


def test_the_envelope_gives_the_whole_bands_factors_and_solution_to_the_bit():
    # Column j of L reaches to the last row whose first entry is at or before j; a reach
    # cut shorter would drop fill and change the factors. Nodes joined across the strip's
    # diagonal and a few far pairs make the envelope vary along the band.
    from solvers.band import BandPlan, _factorise, _solve

    k = strip_matrix(shift=2.5).tolil()
    for i, j in ((0, 37), (12, 90), (40, 61)):
        k[i, j] = k[j, i] = 0.3
    upper = sp.triu(k.tocsc(), format="csc")
    upper.sort_indices()
    plan = BandPlan(upper)
    n = upper.shape[0]
    whole = np.minimum(plan.bandwidth, n - 1 - np.arange(n)).astype(np.int64)
    assert plan.operations < 0.8 * n * plan.bandwidth**2  # the envelope is not the band

    def factors(reaches):
        flat = np.zeros(plan.fill)
        flat[plan.slots] = upper.data
        band = flat.reshape(n, plan.bandwidth + 1)
        return _factorise(band, reaches), band

    (negative, band), (negative_whole, band_whole) = factors(plan.reaches), factors(whole)
    assert negative == negative_whole > 0
    assert np.array_equal(band, band_whole)
    rhs = np.linspace(-1.0, 2.0, n)
    assert np.array_equal(_solve(band, plan.reaches, rhs), _solve(band_whole, whole, rhs))


def test_the_band_ordering_sees_stored_zeros_as_part_of_the_pattern():
    # A flat shell's tangent stores exact zeros (its membrane-bending couplings); an ordering
    # of the values alone would leave those couplings out of the band it plans.
    from solvers.band import BandPlan

    upper = sp.triu(strip_matrix(), format="csc")
    upper.sort_indices()
    zeros = upper.copy()
    columns = np.repeat(np.arange(upper.shape[0]), np.diff(upper.indptr))
    zeros.data[upper.indices // 5 != columns // 5] = 0.0  # every coupling of two nodes
    assert BandPlan(zeros).bandwidth == BandPlan(upper).bandwidth < 50


def test_the_plan_leaves_zero_couplings_out_and_keeps_every_diagonal_entry():
    # A flat sheet's tangent stores zero bending couplings; QDLDL needs the diagonal stored.
    from solvers.linear import _UpperPlan

    values = np.array([[0.0, 1.0, 0.0], [1.0, 3.0, 4.0], [0.0, 4.0, 5.0]])
    k = sp.csc_matrix(np.ones((3, 3)))  # every entry stored
    k.data = values.T.ravel().copy()  # CSC order: column by column
    plan = _UpperPlan.of(k)
    assert plan is not None
    _, upper = plan.split(k.data)
    stored = set(zip(np.repeat(np.arange(3), np.diff(upper.indptr)), upper.indices))
    assert stored == {(0, 0), (1, 0), (1, 1), (2, 1), (2, 2)}  # (column, row): no (2, 0)
    assert np.array_equal(upper.toarray(), np.triu(values))


def test_a_wide_band_is_not_tried_where_qdldl_fails():
    # A scattered pattern with a zero diagonal: QDLDL meets a zero pivot; its band would hold
    # as many entries as the dense matrix, so the LU solves, without a band.
    k = symmetric(n=1500, seed=3)
    k = (k - sp.diags(k.diagonal()) + sp.diags(np.zeros(k.shape[0]))).tocsc()
    solver = LinearSolver()
    factor = solver.factorise(k)
    assert solver._band is None and factor.kind == "lu"
    rhs = np.ones(k.shape[0])
    x = factor.solve(rhs)
    assert x is None or np.linalg.norm(k @ x - rhs) <= 1e-8 * np.linalg.norm(rhs)


def test_a_strip_whose_contact_pairs_change_keeps_the_band_without_measuring_qdldl(monkeypatch):
    # A contact pair that moves changes a few entries of the pattern: the new pattern takes
    # the band on the last QDLDL measurement of as many unknowns, and its solution is the
    # band's as from a fresh solver (backward error 1e-12 in solvers.linear; 1e-9 here as in
    # the band test above).
    made = counting_qdldl(monkeypatch)
    solver = LinearSolver()
    k = strip_matrix()
    solver.factorise(k)
    moved = k.tolil()
    for i, j in ((0, 12), (7, 28), (40, 61)):  # unknowns of nodes a cell or two apart
        moved[i, j] = moved[j, i] = 0.01
    moved = moved.tocsc()
    rhs = np.linspace(-1.0, 1.0, k.shape[0])
    x = solver.factorise(moved).solve(rhs)
    assert solver.symbolic == 2
    assert solver._band is not None
    assert len(made) == 1
    assert np.allclose(x, np.linalg.solve(moved.toarray(), rhs), rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("shift", [0.0, 2.5, 3.5])
@pytest.mark.parametrize("far_pairs", [False, True])
def test_the_band_by_panels_gives_the_column_by_column_factors_to_the_bit(shift, far_pairs):
    # The panels make every entry's updates in the column order of the reference; a skipped,
    # repeated or reordered update changes the last bits of the factors. The strip (103
    # unknowns: panels that do not divide it) with and without far pairs, definite and not;
    # the inertia against numpy's eigenvalues.
    from solvers.band import BandPlan, _factorise, _factorise_by_column

    k = strip_matrix(length=61, shift=shift).tolil()
    if far_pairs:
        for i, j in ((0, 37), (12, 90), (40, 61)):
            k[i, j] = k[j, i] = 0.3
    k = k.tocsc()
    upper = sp.triu(k, format="csc")
    upper.sort_indices()
    plan = BandPlan(upper)

    def factors(factorise):
        flat = np.zeros(plan.fill)
        flat[plan.slots] = upper.data
        band = flat.reshape(plan.n, plan.bandwidth + 1)
        return factorise(band, plan.reaches), band

    (negative, band), (reference_negative, reference) = (
        factors(_factorise),
        factors(_factorise_by_column),
    )
    assert negative == reference_negative == int(np.sum(np.linalg.eigvalsh(k.toarray()) < 0.0))
    assert np.array_equal(band.view(np.int64), reference.view(np.int64))


def test_the_band_by_panels_stops_at_a_zero_pivot_as_the_reference_does():
    from solvers.band import BandPlan, _factorise, _factorise_by_column

    k = strip_matrix().tolil()
    k[20, 20] = 0.0
    k[20, :] = 0.0
    k[:, 20] = 0.0
    k = k.tocsc()
    upper = sp.triu(k, format="csc")
    upper.sort_indices()
    plan = BandPlan(upper)
    for factorise in (_factorise, _factorise_by_column):
        flat = np.zeros(plan.fill)
        flat[plan.slots] = upper.data
        assert factorise(flat.reshape(plan.n, plan.bandwidth + 1), plan.reaches) == -1


def test_the_compiled_plan_is_numpys_to_the_bit():
    """``_UpperPlan.of`` (one compiled pass) against ``of_numpy`` (scipy's counting transpose
    and numpy's masks): every array and its dtype, on scattered symmetric patterns and on
    the patterns that get no plan (a mirror or a diagonal entry missing)."""
    from solvers.linear import _UpperPlan

    patterns = [sp.csc_matrix(np.tril(np.ones((4, 4)))), sp.csc_matrix(np.ones((4, 4)) - np.eye(4))]
    patterns.append(sp.csc_matrix(np.eye(3) + np.eye(3, k=-1) + np.eye(3, k=2)))
    for seed, size in enumerate((1, 7, 60, 200)):
        a = sp.random(size, size, density=0.05, random_state=seed, format="csc")
        patterns.append((a + a.T + sp.identity(size)).tocsc())
    for k in patterns:
        k.sort_indices()
        new, old = _UpperPlan.of(k), _UpperPlan.of_numpy(k)
        assert (new is None) == (old is None)
        if new is None or old is None:
            continue
        for name in ("transposed", "upper", "indptr", "indices", "columns", "diagonal"):
            a, b = getattr(new, name), getattr(old, name)
            assert a.dtype == b.dtype and np.array_equal(a, b), name
    assert sum(_UpperPlan.of(k) is None for k in patterns) == 3


def test_the_compiled_band_plan_is_numpys_to_the_bit():
    """BandPlan's ordering and layout (perm, bandwidth, slots, reaches) by its compiled passes
    against scipy's sums and numpy's scatters, on strips, a scattered pattern, a pattern with
    stored zeros and one of a single unknown."""
    from solvers.band import BandPlan
    from solvers.linear import _upper

    matrices = [strip_matrix(), strip_matrix(length=12, width=3, seed=2)]
    a = sp.random(80, 80, density=0.04, random_state=6, format="csc")
    matrices.append((a + a.T + sp.identity(80)).tocsc())
    zeros = strip_matrix(length=10, width=2).tocsc()
    zeros.data[::3] = 0.0  # stored zeros: the ordering sees them
    matrices += [zeros, sp.csc_matrix(np.ones((1, 1)))]
    for k in matrices:
        upper = _upper(k)
        assert upper.has_sorted_indices
        new, old = BandPlan(upper), BandPlan(upper, compiled=False)
        assert new.bandwidth == old.bandwidth
        for name in ("perm", "slots", "reaches"):
            x, y = getattr(new, name), getattr(old, name)
            assert x.dtype == y.dtype and np.array_equal(x, y), name


@pytest.mark.parametrize("shift", [0.0, 2.5])
def test_the_band_written_in_its_envelope_alone_gives_the_zeroed_bands_factors_to_the_bit(shift):
    # BandPlan.band_of writes the envelope only and leaves the rest of an uninitialised band
    # as it came: here NaN, so that any read outside the envelope by the factorisation (by
    # panels or column by column) or the solve would show in the factors or the solution.
    from solvers.band import BandPlan, _factorise, _factorise_by_column, _fill_envelope, _solve

    k = strip_matrix(length=61, shift=shift).tolil()
    for i, j in ((0, 37), (12, 90), (40, 61)):
        k[i, j] = k[j, i] = 0.3
    upper = sp.triu(k.tocsc(), format="csc")
    upper.sort_indices()
    plan = BandPlan(upper)
    assert plan.operations < 0.8 * plan.n * plan.bandwidth**2  # the envelope is not the band
    zeroed = np.zeros(plan.fill)
    zeroed[plan.slots] = upper.data
    zeroed = zeroed.reshape(plan.n, plan.bandwidth + 1)
    inside = np.arange(plan.bandwidth + 1) <= plan.reaches[:, None]
    written = plan.band_of(upper.data)
    assert np.array_equal(written[inside], zeroed[inside])
    rhs = np.linspace(-1.0, 2.0, plan.n)
    for factorise in (_factorise, _factorise_by_column):
        poisoned = np.full_like(zeroed, np.nan)
        _fill_envelope(poisoned, plan.reaches, plan.slots, upper.data)
        reference = zeroed.copy()
        negative = int(np.sum(np.linalg.eigvalsh(k.toarray()) < 0.0))
        assert factorise(poisoned, plan.reaches) == factorise(reference, plan.reaches) == negative
        assert np.array_equal(poisoned[inside].view(np.int64), reference[inside].view(np.int64))
        assert np.array_equal(
            _solve(poisoned, plan.reaches, rhs).view(np.int64),
            _solve(reference, plan.reaches, rhs).view(np.int64),
        )
    factor = plan.factorise(upper.data)
    assert factor is not None
    assert np.allclose(k.tocsc() @ factor.solve(rhs), rhs, atol=1e-10)


def test_the_compiled_infinity_norm_is_scipys_to_the_bit():
    # The accuracy check's ||K||_inf by one compiled pass against scipy's
    # np.abs(k).sum(axis=1).max(): entries of magnitudes 1e-8..1e8 so that a sum in another
    # order would differ in its last bits; a stored zero, a row of zeros, a nan, one unknown.
    from solvers.linear import _infinity_norm

    rng = np.random.default_rng(3)
    matrices = []
    for size, density in ((1, 1.0), (7, 0.5), (200, 0.05), (900, 0.01)):
        a = sp.random(size, size, density=density, random_state=size, format="csc")
        a.data = rng.choice([-1.0, 1.0], a.nnz) * 10.0 ** rng.uniform(-8, 8, a.nnz)
        a = (a + sp.identity(size)).tocsc()
        matrices.append(a)
    zeros = matrices[2].copy()
    zeros.data[::5] = 0.0
    empty_row = matrices[2].tolil()
    empty_row[4, :] = 0.0
    undefined = matrices[3].copy()
    undefined.data[17] = np.nan
    matrices += [zeros, empty_row.tocsc(), undefined, strip_matrix(length=8).tocsc()]
    for k in matrices:
        expected = float(np.abs(k).sum(axis=1).max())
        found = _infinity_norm(k)
        assert np.isnan(expected) == np.isnan(found)
        if not np.isnan(expected):
            assert np.float64(found).view(np.int64) == np.float64(expected).view(np.int64)
    assert _infinity_norm(sp.csc_matrix((0, 0))) == 0.0


@pytest.mark.parametrize("change", [-5, 7])
def test_the_band_refuses_values_not_one_per_entry_of_its_pattern(change):
    """The band's compiled fill reads the values by the plan's slots without a bounds check:
    a values array of another length is a ValueError, not a read past its end."""
    from solvers.band import BandPlan

    k = strip_matrix(shift=0.0)
    upper = sp.triu(k, format="csc")
    upper.sort_indices()
    values = np.resize(upper.data, upper.data.size + change)
    with pytest.raises(ValueError, match="one per entry of the plan's pattern"):
        BandPlan(upper).factorise(values)


def test_the_splits_infinity_norm_is_the_compiled_norms_and_scipys_to_the_bit():
    # The factorisation takes ||K||_inf from the pass that splits K's upper triangle: the
    # same bits as _infinity_norm's pass of its own and as scipy's (its reference, by
    # split_numpy_and_norm), on entries of magnitudes 1e-8..1e8 (a sum in another order
    # would differ in its last bits), with stored zeros and a nan.
    from solvers.linear import _infinity_norm, _UpperPlan

    rng = np.random.default_rng(5)
    matrices = []
    for size, density in ((1, 1.0), (7, 0.5), (200, 0.05), (900, 0.01)):
        a = sp.random(size, size, density=density, random_state=size, format="csc")
        a = (a + a.T + sp.identity(size)).tocsc()
        a.sort_indices()
        a.data = rng.choice([-1.0, 1.0], a.nnz) * 10.0 ** rng.uniform(-8, 8, a.nnz)
        matrices.append(a)
    zeros = matrices[2].copy()
    zeros.data[::5] = 0.0
    undefined = matrices[3].copy()
    undefined.data[17] = np.nan
    matrices += [zeros, undefined, strip_matrix(length=8).tocsc()]
    for k in matrices:
        plan = _UpperPlan.of(k)
        assert plan is not None
        asymmetry, upper, norm = plan.split_and_norm(k.data)
        expected_asymmetry, expected_upper, expected = plan.split_numpy_and_norm(k.data)
        for found, reference in ((norm, expected), (norm, _infinity_norm(k))):
            assert np.isnan(found) == np.isnan(reference)
            if not np.isnan(reference):
                assert np.float64(found).view(np.int64) == np.float64(reference).view(np.int64)
        assert np.array_equal(asymmetry, expected_asymmetry, equal_nan=True)
        assert np.array_equal(upper.indptr, expected_upper.indptr)
        assert np.array_equal(upper.data, expected_upper.data, equal_nan=True)
    factor = LinearSolver().factorise(matrices[-1])
    assert factor._norm is not None  # made by the split, not by a pass of its own
    assert factor.norm == _infinity_norm(matrices[-1])


def _strip_band():
    """(K, the band LDL^T of K) of a strip's stiffness shifted by 2.5 (``strip_matrix``)."""
    from solvers.band import BandPlan

    k = strip_matrix(shift=2.5)
    upper = sp.triu(k, format="csc")
    upper.sort_indices()
    factor = BandPlan(upper).factorise(upper.data)
    assert factor is not None
    return k, factor


@pytest.mark.parametrize("count", [1, 3, 4, 9])
def test_the_band_solves_many_columns_as_it_solves_each_to_the_bit(count):
    # Each column of the compiled pass takes the same operations in the same order as the
    # one-column solve (solvers.band ``_solve_columns``, without fastmath), on either side
    # of COLUMNS_TOGETHER; the kernel's Python text (its reference) the same bits too.
    from solvers import band

    k, factor = _strip_band()
    rhs = np.random.default_rng(count).standard_normal((k.shape[0], count))
    rhs[:, 0] *= 1e-12  # columns of very different sizes
    alone = np.column_stack([factor.solve(rhs[:, j]) for j in range(count)])
    assert np.array_equal(factor.solve_columns(rhs), alone)
    permuted = np.ascontiguousarray(rhs[factor.plan.perm])
    compiled = band._solve_columns(factor.band, factor.plan.reaches, permuted)
    plain = getattr(band._solve_columns, "py_func", band._solve_columns)
    assert np.array_equal(plain(factor.band, factor.plan.reaches, permuted), compiled)


def test_the_columns_without_the_accuracy_check_are_the_checked_solves():
    # Factorisation.solve_columns skips solve's backward-error check and refinement: on a
    # well-conditioned K_ff the check passes at once, so the two give the same bits.
    k = strip_matrix()
    factor = LinearSolver().factorise(k)
    rhs = np.random.default_rng(3).standard_normal((k.shape[0], 6))
    assert np.array_equal(factor.solve_columns(rhs), factor.solve(rhs))


@pytest.mark.parametrize("layout", ["C", "F", "strided", "none"])
def test_many_columns_in_any_layout_are_the_columns_solved_each(layout):
    # A predicted contact set's columns (solvers/contact_sets.py) come as slices and stacks:
    # C or Fortran order, every other column of a wider array, or none at all (an empty
    # (n, 0) answer, where np.column_stack refused an empty list), on the band's factors and
    # on a non-symmetric K_ff's LU.
    k, band = _strip_band()
    skewed = k + sp.diags(np.full(k.shape[0] - 1, 1e-2 * abs(k).max()), 1, format="csc")
    lu = LinearSolver().factorise(skewed.tocsc())
    assert lu.kind == "lu"
    wide = np.random.default_rng(5).standard_normal((k.shape[0], 18))
    rhs = {
        "C": wide[:, :9].copy(),
        "F": np.asfortranarray(wide[:, :9]),
        "strided": wide[:, ::2],
        "none": wide[:, :0],
    }[layout]
    for factor in (band, lu):
        found = factor.solve_columns(rhs)
        assert found.shape == rhs.shape
        alone = [
            np.asarray(factor.solve(np.ascontiguousarray(rhs[:, j]))) for j in range(rhs.shape[1])
        ]
        for j, column in enumerate(alone):
            assert np.array_equal(found[:, j], column)
