"""solvers.supernodal: the supernodal LDL^T against scipy's sparse LU solve, numpy's dense
eigenvalues (the inertia, by Sylvester's law) and QDLDL's factors on the same ordering (an
LDL^T without pivoting of a matrix under one ordering is unique: the same L and D up to
round-off), and its choice by solvers.linear."""

import hashlib
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import qdldl
import scipy.sparse as sp
from qdldl_count import counting_qdldl
from scipy.sparse.linalg import spsolve

from solvers.linear import LinearSolver
from solvers.supernodal import SupernodalPlan


def scattered(n=400, shift=0.0, density=0.01, seed=0):
    """A symmetric matrix with a random sparse pattern, its diagonal shifted by -shift: the
    elimination tree has long chains and many small branches."""
    rng = np.random.default_rng(seed)
    a = sp.random(n, n, density=density, random_state=seed)
    return (a + a.T + sp.diags(rng.uniform(1.0, 5.0, n) - shift)).tocsc()


def grid(nodes=12, dof=5, shift=0.0, seed=0):
    """A symmetric matrix on a nodes x nodes grid of ``dof``-unknown nodes joined to their
    eight neighbours (a shell's tangent pattern: supernodes of a node's unknowns and the
    separators of the minimum degree ordering), shifted by -shift on the diagonal."""
    rng = np.random.default_rng(seed)
    index = np.arange(nodes * nodes).reshape(nodes, nodes)
    a = sp.lil_matrix((dof * index.size, dof * index.size))
    for di, dj in ((0, 1), (1, 0), (1, 1), (1, -1)):
        for i in range(nodes - di):
            for j in range(max(0, -dj), nodes - max(0, dj)):
                p, q = index[i, j], index[i + di, j + dj]
                block = rng.uniform(-0.2, 0.2, (dof, dof))
                a[dof * p : dof * p + dof, dof * q : dof * q + dof] = block
                a[dof * q : dof * q + dof, dof * p : dof * p + dof] = block.T
    own = rng.uniform(-0.2, 0.2, (index.size, dof, dof))
    a = a.tocsc() + sp.block_diag(list(own + np.swapaxes(own, 1, 2)))
    diagonal = rng.uniform(3.0, 5.0, dof * index.size) - shift
    return (a + sp.diags(diagonal)).tocsc()


def plan_of(k):
    upper = sp.triu(k, format="csc")
    upper.sort_indices()
    ordering = qdldl.Solver(upper, upper=True)
    return upper, ordering, SupernodalPlan(upper, ordering.factors()[2])


@pytest.mark.parametrize(
    "k",
    [
        scattered(),
        scattered(shift=2.0),
        scattered(shift=4.0, density=0.03),
        grid(),
        grid(shift=3.0),
        grid(nodes=5, dof=6, shift=4.5),
    ],
    ids=["scattered", "scattered-2", "scattered-4", "grid", "grid-3", "small-grid-4.5"],
)
def test_the_supernodal_ldlt_solves_and_counts_the_negative_eigenvalues(k):
    # Tolerance: the backward error of an LDL^T without pivoting on these matrices (condition
    # numbers up to ~1e4) is ~1e-15; 1e-9 of the solution leaves room for the conditioning.
    upper, _, plan = plan_of(k)
    factor = plan.factorise(upper.data)
    assert factor is not None
    assert factor.negative == int(np.sum(np.linalg.eigvalsh(k.toarray()) < 0.0))
    rhs = np.random.default_rng(1).standard_normal(k.shape[0])
    x, expected = factor.solve(rhs), spsolve(k, rhs)
    assert np.abs(x - expected).max() <= 1e-9 * np.abs(expected).max()


@pytest.mark.parametrize("k", [scattered(shift=-6.0), grid()], ids=["scattered", "grid"])
def test_the_supernodal_factors_are_qdldls_on_the_same_ordering(k):
    # L's pattern: QDLDL's (its operations, the sum of the column counts squared, diagonal
    # included); L and D: QDLDL's to the round-off of two elimination orders (1e-12; these
    # definite matrices have condition numbers ~3, and the two agree within 2e-15: on the
    # indefinite ones the small pivots amplify the round-off to 1e-10, and the solve test
    # above holds them to scipy's solution instead).
    upper, ordering, plan = plan_of(k)
    lower, pivots, _ = ordering.factors()
    assert plan.operations == float(np.sum((np.diff(lower.indptr) + 1.0) ** 2))
    factor = plan.factorise(upper.data)
    assert factor is not None
    dense = np.zeros(k.shape)  # L below the diagonal, D on it, from the supernodes
    for s in range(plan.first.size - 1):
        rows = plan.rows[plan.row_start[s] : plan.row_start[s + 1]]
        width = plan.first[s + 1] - plan.first[s]
        block = factor.values[plan.value_start[s] : plan.value_start[s + 1]]
        for k_column in range(width):
            column = block[k_column * rows.size : (k_column + 1) * rows.size]
            dense[rows[k_column:], plan.first[s] + k_column] = column[k_column:]
    assert np.allclose(np.diag(dense), pivots, rtol=1e-12, atol=0.0)
    expected = lower.toarray()
    assert np.abs(np.tril(dense, -1) - expected).max() <= 1e-12 * np.abs(expected).max()


def test_a_zero_pivot_gives_no_factors():
    k = grid(nodes=4).tolil()
    k[7, :] = 0.0
    k[:, 7] = 0.0
    k = k.tocsc()
    upper = sp.triu(k, format="csc")
    upper.sort_indices()
    plan = SupernodalPlan(upper, np.arange(k.shape[0]))  # any ordering: row 7 stays empty
    assert plan.factorise(upper.data) is None


def test_the_factors_are_the_same_bits_from_one_factorisation_to_the_next():
    """Two factorisations of the same values in one process give the same bits: this catches
    a read of uninitialised memory (np.empty scratch) alone. It does not check the docstring's
    "the same factors on every machine", which rests on the kernels' having no fastmath, no
    BLAS and no fused multiply-add (checked by hand: the same factors compiled for a generic
    CPU and for haswell; the test below compares a generic build with this machine's)."""
    upper, _, plan = plan_of(grid(shift=3.0))
    first, second = plan.factorise(upper.data), plan.factorise(upper.data.copy())
    assert first is not None and second is not None
    assert np.array_equal(first.values.view(np.int64), second.values.view(np.int64))


def factor_digest():
    """The SHA-256 of a grid's supernodal factors and of one solution (hex)."""
    upper, _, plan = plan_of(grid(nodes=8, shift=3.0))
    factor = plan.factorise(upper.data)
    x = factor.solve(np.linspace(-1.0, 1.0, upper.shape[0]))
    return hashlib.sha256(factor.values.tobytes() + x.tobytes()).hexdigest()


def test_the_factors_compiled_for_a_generic_cpu_are_this_machines_bits(tmp_path):
    # The kernels are built without fastmath, so LLVM fuses no multiply-add: a build for a
    # generic x86-64 CPU (no FMA, no AVX) gives the bits of this machine's build (AVX-512 and
    # FMA where it was written). A fresh build in an empty cache folder: 4 s.
    root = Path(__file__).resolve().parents[1]
    environment = dict(os.environ, NUMBA_CPU_NAME="generic", NUMBA_CACHE_DIR=str(tmp_path))
    # (the tests' folder too: this module imports its sibling qdldl_count as pytest lets it)
    environment["PYTHONPATH"] = os.pathsep.join(
        [str(root), str(root / "tests"), environment.get("PYTHONPATH", "")]
    )
    script = "from tests.test_supernodal import factor_digest; print(factor_digest())"
    done = subprocess.run(
        [sys.executable, "-c", script],
        cwd=root,
        env=environment,
        capture_output=True,
        text=True,
        timeout=120,
        check=True,
    )
    assert done.stdout.split()[-1] == factor_digest()


def test_a_wide_pattern_takes_the_supernodal_ldlt_and_a_changed_one_keeps_its_ordering(
    monkeypatch,
):
    # The grid's envelope holds more than BAND_OVER_SUPERNODAL times the supernodal
    # operations; a few couplings added (contact pairs) keep QDLDL's ordering of the first
    # pattern (no second QDLDL) and still solve as scipy does.
    made = counting_qdldl(monkeypatch)
    k = grid(nodes=16, shift=3.0)
    solver = LinearSolver()
    factor = solver.factorise(k)
    assert solver._supernodal is not None and solver._band is None
    assert factor.negative == int(np.sum(np.linalg.eigvalsh(k.toarray()) < 0.0))
    moved = k.tolil()
    for i, j in ((0, 90), (33, 140), (400, 520)):
        moved[i, j] = moved[j, i] = 0.05
    moved = moved.tocsc()
    rhs = np.linspace(-1.0, 1.0, k.shape[0])
    x = solver.factorise(moved).solve(rhs)
    assert solver.symbolic == 2 and len(made) == 1
    assert solver._supernodal is not None
    expected = spsolve(moved, rhs)
    assert np.abs(x - expected).max() <= 1e-9 * np.abs(expected).max()


def test_a_strip_takes_the_band_where_the_supernodal_factor_saves_little():
    from tests.test_linear import strip_matrix

    solver = LinearSolver()
    solver.factorise(strip_matrix())
    assert solver._band is not None and solver._supernodal is None


def test_the_shift_invert_with_the_supernodal_factors_finds_the_same_lowest_modes():
    # solvers.stability's shift-invert by the kept factors (Factorisation.inverse) against
    # its own factorisation, as tests/test_linear.py does for the band.
    from solvers.stability import lowest_modes

    k = grid(nodes=16, shift=3.0)
    solver = LinearSolver()
    factor = solver.factorise(k)
    assert solver._supernodal is not None and factor.kind == "ldlt" and factor.negative
    values, vectors = lowest_modes(k, factor.negative, factor.inverse())
    expected, _ = lowest_modes(k, factor.negative)
    assert np.allclose(values, expected, rtol=1e-8, atol=1e-10)
    assert np.allclose(np.abs(vectors.T @ (k @ vectors)), np.diag(np.abs(values)), atol=1e-8)


def test_a_pattern_within_the_factors_pattern_keeps_the_analysis():
    # Entries that vanish (exact zeros of a tangent by differences, left out of the pattern)
    # leave a pattern inside L's: the plan is kept, no new analysis; the solution is the new
    # matrix's. An entry outside L's pattern asks for a new analysis.
    k = grid(nodes=16, shift=3.0)
    solver = LinearSolver()
    solver.factorise(k)
    assert solver._supernodal is not None and solver.symbolic == 1
    fewer = k.tolil()
    for i, j in ((0, 1), (33, 38), (400, 405)):  # couplings within a node's or a neighbour's
        fewer[i, j] = fewer[j, i] = 0.0
    fewer = fewer.tocsc()
    fewer.eliminate_zeros()
    assert fewer.nnz == k.nnz - 6
    rhs = np.linspace(-1.0, 1.0, k.shape[0])
    factor = solver.factorise(fewer)
    assert solver.symbolic == 1 and solver._supernodal is not None
    expected = spsolve(fewer, rhs)
    assert np.abs(factor.solve(rhs) - expected).max() <= 1e-9 * np.abs(expected).max()
    assert factor.negative == int(np.sum(np.linalg.eigvalsh(fewer.toarray()) < 0.0))
    far = k.tolil()
    far[0, k.shape[0] - 1] = far[k.shape[0] - 1, 0] = 0.05  # opposite corners of the grid
    solver.factorise(far.tocsc())
    assert solver.symbolic == 2


def test_a_pattern_whose_fill_grows_past_the_bound_is_ordered_anew(monkeypatch):
    # Four couplings across the grid (opposite corners, far nodes) add 0.015 % of the entries
    # but, under the first pattern's AMD ordering, 2.8 times its factor's operations: past
    # REORDER_GROWTH (1.2), so QDLDL orders the new pattern anew (a second measurement)
    # rather than factorising on the old ordering.
    from solvers.linear import REORDER_GROWTH

    made = counting_qdldl(monkeypatch)
    k = grid(nodes=16, shift=3.0)
    n = k.shape[0]
    solver = LinearSolver()
    solver.factorise(k)
    assert solver._supernodal is not None and len(made) == 1
    kept = solver._supernodal.operations
    linked = k.tolil()
    for i, j in ((0, n - 1), (4, n - 80), (n - 5, 75), (640, n - 1)):
        linked[i, j] = linked[j, i] = 0.05
    linked = linked.tocsc()
    upper = sp.triu(linked, format="csc")
    upper.sort_indices()
    assert upper.nnz <= REORDER_GROWTH * sp.triu(k).nnz  # the entries hardly grow
    assert SupernodalPlan(upper, solver._ordering[0]).operations > REORDER_GROWTH * kept
    rhs = np.linspace(-1.0, 1.0, n)
    x = solver.factorise(linked).solve(rhs)
    assert solver.symbolic == 2 and len(made) == 2
    assert solver._supernodal is not None
    assert solver._supernodal.operations <= REORDER_GROWTH * kept
    expected = spsolve(linked, rhs)
    assert np.abs(x - expected).max() <= 1e-9 * np.abs(expected).max()


def test_a_pattern_whose_entries_grow_past_the_bound_is_measured_anew(monkeypatch):
    # A strip first without its diagonal neighbours' couplings, then with them: 1.38 times
    # the entries (past REORDER_GROWTH), while the band of the whole strip is 1.05 times the
    # first factor's operations (within BAND_OVER_SUPERNODAL): the grown pattern is measured
    # by QDLDL anew all the same, and takes the band on that measurement.
    from solvers.linear import REORDER_GROWTH
    from tests.test_linear import strip_matrix

    made = counting_qdldl(monkeypatch)
    k = strip_matrix(length=60, width=4)
    nodes = np.arange(60 * 4).reshape(60, 4)
    thin = k.tolil()
    for i, j in zip(nodes[:-1, :-1].ravel(), nodes[1:, 1:].ravel()):
        thin[5 * i : 5 * i + 5, 5 * j : 5 * j + 5] = 0.0
        thin[5 * j : 5 * j + 5, 5 * i : 5 * i + 5] = 0.0
    thin = thin.tocsc()
    thin.eliminate_zeros()
    assert sp.triu(k).nnz > REORDER_GROWTH * sp.triu(thin).nnz
    solver = LinearSolver()
    solver.factorise(thin)
    assert solver._band is not None and len(made) == 1
    rhs = np.linspace(-1.0, 1.0, k.shape[0])
    x = solver.factorise(k).solve(rhs)
    assert solver.symbolic == 2 and len(made) == 2 and solver._band is not None
    assert solver._ordering[2] == sp.triu(k).nnz  # the measurement is the grown pattern's
    assert np.allclose(x, np.linalg.solve(k.toarray(), rhs), rtol=1e-9, atol=1e-9)


def test_an_ordering_that_is_no_permutation_is_refused():
    upper, ordering, _ = plan_of(grid(nodes=6))
    n = upper.shape[0]
    perm = np.asarray(ordering.factors()[2]).copy()
    repeated = perm.copy()
    repeated[5] = repeated[4]
    for bad in (repeated, perm[:-1], np.append(perm, n), perm + 1.0, -1 - perm):
        with pytest.raises(ValueError, match="permutation|ordering"):
            SupernodalPlan(upper, bad)


def test_a_pattern_that_is_no_canonical_upper_triangle_is_refused():
    k = grid(nodes=6)
    upper, _, plan = plan_of(k)
    full = k.tocsc()
    full.sort_indices()
    with pytest.raises(ValueError, match="upper triangle"):
        SupernodalPlan(full, plan.perm)  # (i, j) and (j, i) both stored
    with pytest.raises(ValueError, match="upper triangle"):
        plan.for_pattern(full)
    # a duplicate entry: scipy would add the two, a slot map would keep one
    indices = np.insert(upper.indices, upper.indptr[3], upper.indices[upper.indptr[3]])
    indptr = upper.indptr.copy()
    indptr[4:] += 1
    duplicated = sp.csc_matrix((np.ones(indices.size), indices, indptr), shape=upper.shape)
    for bad in (duplicated, upper[:, :-1], upper.tocsr()):
        with pytest.raises(ValueError, match="canonical|square|CSC"):
            SupernodalPlan(bad, plan.perm)
        with pytest.raises(ValueError, match="canonical|square|CSC"):
            plan.for_pattern(bad)
    unsorted = upper.copy()
    column = slice(unsorted.indptr[20], unsorted.indptr[21])
    unsorted.indices[column] = unsorted.indices[column][::-1].copy()
    unsorted.has_sorted_indices = False
    with pytest.raises(ValueError, match="canonical"):
        plan.for_pattern(unsorted)


def test_values_or_a_right_hand_side_of_the_wrong_length_are_refused():
    upper, _, plan = plan_of(grid(nodes=6))
    for values in (np.array([1.0]), upper.data[:-1], np.append(upper.data, 1.0)):
        with pytest.raises(ValueError, match="stored entries"):
            plan.factorise(values)
    factor = plan.factorise(upper.data)
    n = upper.shape[0]
    for rhs in (np.ones(n + 1), np.ones(n - 1), np.ones((n, 2))):
        with pytest.raises(ValueError, match="rhs"):
            factor.solve(rhs)
    assert factor.solve(np.ones((n, 1))).shape == (n,)
